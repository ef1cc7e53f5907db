//! Cunningham's slip correction: a gas-borne particle whose size approaches the gas's mean
//! free path feels less drag than Stokes' law says.
//!
//! # Physics (Cunningham 1910; Davies 1945; Hinds, *Aerosol Technology*, 2nd ed., §3.11)
//! The Stokes drag is divided by
//! ```math
//! C_c = 1 + \mathrm{Kn}\,\big(A_1 + A_2\, e^{-A_3/\mathrm{Kn}}\big),\qquad \mathrm{Kn} = \frac{2\lambda}{d},
//! ```
//! with Davies' (1945) coefficients A₁ = 1.257, A₂ = 0.400, A₃ = 1.10 (fitted to Millikan's
//! oil-drop data, all Kn; within about 2 % of later fits), λ the gas's mean free path (given
//! in the scene: 0.0665 µm for air at 20 °C and 1 atm, Hinds eq. 2.25) and d the particle's
//! diameter. For an ellipsoid d is the volume-equivalent diameter: the correction then acts
//! on Brenner's whole tensor as on a sphere's drag (exact in the continuum limit Kn → 0, and
//! the adjusted-sphere estimate of Dahneke 1973 otherwise: a shape-resolved slip correction
//! is not known to this code). +7 % settling speed at d = 2.5 µm in air, +16 % at 1 µm.

use super::{Contribution, ForceContext, ForceTerm, Registration};
use crate::error::{ParamError, positive};
use crate::tensor::Vec3;
use std::collections::BTreeMap;
use std::sync::Arc;

/// Davies (1945): A₁, A₂, A₃.
pub const DAVIES: [f64; 3] = [1.257, 0.400, 1.10];

/// Largest Knudsen number 2λ/d of a particle's rest shape the term admits. For Kn ≫ 1 the
/// correction is the free-molecular asymptote C_c → (A₁ + A₂) Kn = 1.657 Kn (Epstein's drag),
/// a finite factor at any finite Kn; but the carrier flow is a continuum field only on scales
/// L ≫ λ = Kn d/2, so at Kn = 10⁶ the flow would have to be smooth over 10⁶ particle
/// diameters around the particle (a 1 µm particle in a gas of λ = 0.5 m, about 10⁻⁷ atm),
/// which no continuum flow of a particle-laden scene is. Beyond it the factor only shrinks the
/// drag towards zero (to exactly 0 once 2λ/d overflows: λ = 10³⁰⁸ m was accepted), so the term
/// refuses such a particle instead.
pub const MAX_KNUDSEN: f64 = 1e6;

/// Cunningham's slip correction on the drag (module docs).
#[derive(Debug, Clone, Copy)]
pub struct Cunningham {
    mean_free_path: f64,
}

impl Cunningham {
    /// Name in scene files.
    pub const NAME: &'static str = "cunningham";

    /// Slip in a gas of mean free path λ > 0 (m), finite; a particle it is put on must have
    /// Kn = 2λ/d ≤ [`MAX_KNUDSEN`] ([`ForceTerm::admits`]).
    pub fn new(mean_free_path: f64) -> Result<Self, ParamError> {
        Ok(Self {
            mean_free_path: positive("cunningham.mean_free_path", mean_free_path)?,
        })
    }

    /// From scene parameters: `mean_free_path` (m), required and alone.
    pub fn from_parameters(parameters: &BTreeMap<String, f64>) -> Result<Self, ParamError> {
        if let Some(key) = parameters.keys().find(|k| *k != "mean_free_path") {
            return Err(ParamError::Unknown {
                kind: "force-term parameter",
                name: format!("{}.{key}", Self::NAME),
                known: vec!["mean_free_path"],
            });
        }
        let lambda = parameters.get("mean_free_path").copied().unwrap_or(f64::NAN);
        Self::new(lambda)
    }

    /// The gas's mean free path λ.
    pub fn mean_free_path(&self) -> f64 {
        self.mean_free_path
    }

    /// C_c for a particle of diameter d.
    pub fn correction(&self, d: f64) -> f64 {
        let kn = 2.0 * self.mean_free_path / d;
        let [a1, a2, a3] = DAVIES;
        1.0 + kn * (a1 + a2 * (-a3 / kn).exp())
    }
}

impl ForceTerm for Cunningham {
    fn name(&self) -> &'static str {
        Self::NAME
    }

    /// Refuse a rest shape whose Knudsen number 2λ/d exceeds [`MAX_KNUDSEN`] (d its
    /// volume-equivalent diameter 2 (r₁r₂r₃)^{1/3}).
    fn admits(&self, semi_axes: &Vec3) -> Result<(), ParamError> {
        let kn = self.mean_free_path / semi_axes.product().cbrt();
        if kn <= MAX_KNUDSEN {
            Ok(())
        } else {
            Err(ParamError::OutOfRange {
                name: "Knudsen number 2 cunningham.mean_free_path / d of the rest shape",
                value: kn,
                min: 0.0,
                max: MAX_KNUDSEN,
            })
        }
    }

    fn contribution(&self, ctx: &ForceContext) -> Contribution {
        Contribution {
            drag_factor: 1.0 / self.correction(ctx.volume_diameter()),
            ..Contribution::default()
        }
    }
}

fn build(parameters: &BTreeMap<String, f64>) -> Result<Arc<dyn ForceTerm>, ParamError> {
    Ok(Arc::new(Cunningham::from_parameters(parameters)?))
}

inventory::submit! {
    Registration {
        name: Cunningham::NAME,
        build,
    }
}

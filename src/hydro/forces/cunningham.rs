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

use super::{Contribution, ForceContext, ForceTerm, Omission, Registration, Rest, Size};
use crate::error::{ParamError, positive};
use crate::registry::Parameters;
use crate::tensor::Vec3;
use std::sync::Arc;

/// Davies (1945): A₁, A₂, A₃.
pub const DAVIES: [f64; 3] = [1.257, 0.400, 1.10];

/// Fluids lighter than this (kg/m³) are gases for the estimate of the slip left out: gases at
/// ordinary pressures are below 10, liquids above 500.
pub const GAS_DENSITY: f64 = 10.0;

/// Fluids more viscous than this (Pa s) are not gases for the estimate of the slip left out:
/// gases are 1–3·10⁻⁵ Pa s, liquids 2·10⁻⁴ and up, and a scene in nondimensional units (μ_f = 1
/// in the shear scenes) is not read as SI.
pub const GAS_VISCOSITY: f64 = 1e-4;

/// Mean molecular speed of air at 20 °C, c̄ = √(8RT/(πM)) (m/s), for the mean free path of a gas.
pub const AIR_MOLECULAR_SPEED: f64 = 463.0;

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
    pub fn from_parameters(p: &Parameters) -> Result<Self, ParamError> {
        p.only(&["mean_free_path"])?;
        Ok(Self {
            mean_free_path: p.positive("mean_free_path")?,
        })
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

    /// Its factor is a function of the particle's size and the gas's mean free path.
    fn orientation_free_on_spheres(&self) -> bool {
        true
    }

    fn contribution(&self, ctx: &ForceContext) -> Contribution {
        Contribution {
            drag_factor: 1.0 / self.correction(ctx.volume_diameter()),
            ..Contribution::default()
        }
    }
}

/// The slip's size where it is left out: C_c − 1 at d_eq for a gas in SI units (ρ_f <
/// [`GAS_DENSITY`] and μ_f < [`GAS_VISCOSITY`]; a scene in shear units is not read as a gas),
/// with the mean free path λ = μ_f/(0.499 ρ_f c̄) of kinetic theory and air's mean molecular
/// speed c̄ = [`AIR_MOLECULAR_SPEED`] (the gas is assumed to be air-like; 66 nm for air at
/// 1 atm); 0 in a liquid. Times |1 − ρ_f/ρ_p|: the correction scales the drag, so it moves a
/// particle by the share C_c − 1 of its slip, and the slip of a particle carried by the flow
/// (settling, inertial lag) is proportional to 1 − ρ_f/ρ_p to first order in its response
/// time: a tracer as dense as the gas has none to correct.
fn omitted(rest: &Rest) -> f64 {
    let gas = rest.rho_f > 0.0 && rest.rho_f < GAS_DENSITY && rest.mu_f < GAS_VISCOSITY;
    if !gas || !(rest.rho_p > 0.0) {
        return 0.0;
    }
    let lambda = rest.mu_f / (0.499 * rest.rho_f * AIR_MOLECULAR_SPEED);
    let buoyant = (1.0 - rest.rho_f / rest.rho_p).abs();
    Cunningham::new(lambda).map_or(0.0, |c| (c.correction(rest.d_eq) - 1.0) * buoyant)
}

inventory::submit! {
    Registration {
        name: Cunningham::NAME,
        build: |p| Ok(Arc::new(Cunningham::from_parameters(p)?)),
        omitted: Some(Omission {
            order: 50,
            carried_by: None,
            size: Size::Constant(omitted),
        }),
    }
}

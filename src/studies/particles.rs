//! What a scene builds its particles from: the shape family ([`Shape`], shared by every
//! scene), the softness of a release, the law family and drag model of the study, and one
//! default bulk ratio.
//!
//! A scene takes a [`ParticleModel`] so that a study with another hyperelastic law (any
//! [`LawFactory`]) or drag model (any [`DragModel`]) runs through the paper's scenes unchanged:
//! `Cavity::new(&field)?.with_model(ParticleModel::new(MooneyRivlinFactory { beta: 0.3 }, Brenner,
//! DEFAULT_BULK_RATIO)?)`.

use crate::ellipsoid::Ellipsoid;
use crate::error::{ParamError, positive};
use crate::hydro::{Brenner, DragModel};
use crate::material::{self, LawFactory, NeoHookeFactory};
use crate::particle::{Fluid, Particle};
use crate::tensor::Mat3;
use serde::{Deserialize, Serialize};

/// λ_s/μ_s of the scenes' soft particles: 10³ ("quasi-incompressible", paper §3; the paper
/// gives no value). The volume then changes by |J − 1| ≈ (shear stress)/λ_s ≲ 10⁻³ while the
/// bulk term stays far from stiffening the shape dynamics beyond what the integrators resolve
/// cheaply; the shape response does not depend on the value once |J − 1| ≪ 1 (the TU/TR
/// boundary moves by < 10⁻⁴ in Ca between 10³ and 10⁵).
pub const DEFAULT_BULK_RATIO: f64 = 1e3;

/// The shape families of every scene: a stress-free ellipsoid given by its semi-axis ratios in
/// the body frame (axes 1, 2, 3), without size, orientation or placement.
///
/// Spheroids carry the one aspect ratio λ the paper varies (Figs 7, 10–16, 18–23); the
/// triaxial family is kept in Sanagavarapu's ratios ω₁, ω₂ (paper Fig. 8), because those are
/// the numbers the paper quotes and sweeps: storing them as given makes the dataset columns and
/// the built semi-axes exactly those numbers, where a conversion to ratios over the smallest
/// axis, (1/ω₂, ω₁/ω₂, 1), would round. Size is a scene's choice ([`Shape::ellipsoid`] for a
/// given d_eq, [`Shape::volume_diameter`] for a given smallest semi-axis), and so is placement:
/// which body axis lies along the flow (e.g. [`crate::studies::shear_shape::ShearShape`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Shape {
    /// Semi-axes 1 : 1 : 1.
    Sphere,
    /// Semi-axes λ₁ : 1 : 1, the symmetry axis first. The real-flow scenes label λ₁ = 1 as
    /// `prolate_1`, the end of the prolate series the paper plots.
    Prolate(f64),
    /// Semi-axes λ₁ : λ₁ : 1, the symmetry axis last.
    Oblate(f64),
    /// Semi-axes 1 : ω₁ : ω₂ in Sanagavarapu's ratios: both relative to axis 1, which the shear
    /// scenes put along the flow, with axis 2 in the shear plane and axis 3 along the vorticity.
    Triaxial {
        /// ω₁ = r₂/r₁.
        omega1: f64,
        /// ω₂ = r₃/r₁.
        omega2: f64,
    },
}

impl Shape {
    /// Semi-axis ratios (r₁, r₂, r₃) in the body frame: sphere (1, 1, 1), prolate (λ₁, 1, 1),
    /// oblate (λ₁, λ₁, 1), triaxial (1, ω₁, ω₂).
    pub fn ratios(self) -> [f64; 3] {
        match self {
            Shape::Sphere => [1.0, 1.0, 1.0],
            Shape::Prolate(l) => [l, 1.0, 1.0],
            Shape::Oblate(l) => [l, l, 1.0],
            Shape::Triaxial { omega1, omega2 } => [1.0, omega1, omega2],
        }
    }

    /// Family name: `sphere`, `prolate`, `oblate` or `triaxial`.
    pub fn family(self) -> &'static str {
        match self {
            Shape::Sphere => "sphere",
            Shape::Prolate(_) => "prolate",
            Shape::Oblate(_) => "oblate",
            Shape::Triaxial { .. } => "triaxial",
        }
    }

    /// Label for datasets: the family and its parameters, e.g. `prolate_5`, `sphere`,
    /// `triaxial_0.5_0.2`.
    pub fn label(self) -> String {
        match self {
            Shape::Sphere => self.family().to_string(),
            Shape::Prolate(l) | Shape::Oblate(l) => format!("{}_{l}", self.family()),
            Shape::Triaxial { omega1, omega2 } => format!("{}_{omega1}_{omega2}", self.family()),
        }
    }

    /// The ellipsoid of this shape with volume-equivalent diameter `d_eq`
    /// (R₁R₂R₃ = (d_eq/2)³), body axis a along column a of `axes`.
    pub fn ellipsoid(self, d_eq: f64, axes: Mat3) -> Result<Ellipsoid, ParamError> {
        Ellipsoid::with_volume_diameter(self.ratios(), d_eq, axes)
    }

    /// Volume-equivalent diameter d_eq = 2 (R₁R₂R₃)^{1/3} of this shape when its smallest
    /// semi-axis is `smallest`: 2 r_min (ρ₁ρ₂ρ₃)^{1/3}/ρ_min for the ratios ρ_a.
    pub fn volume_diameter(self, smallest: f64) -> Result<f64, ParamError> {
        let ratios = self.ratios();
        for r in ratios {
            positive("axis ratio", r)?;
        }
        let smallest = positive("smallest semi-axis", smallest)?;
        let min = ratios.iter().copied().fold(f64::INFINITY, f64::min);
        // Cube roots first, as in `Ellipsoid::with_volume_diameter`: the product of the ratios
        // may overflow where its cube root does not.
        let d_eq = 2.0 * smallest * (ratios[0].cbrt() * ratios[1].cbrt() * ratios[2].cbrt()) / min;
        if d_eq.is_finite() && d_eq > 0.0 {
            Ok(d_eq)
        } else {
            Err(ParamError::Derived {
                name: "d_eq",
                value: d_eq,
                inputs: vec![smallest, ratios[0], ratios[1], ratios[2]],
            })
        }
    }
}

/// How a release deforms: the rigid limit Ca → 0, or an elastic solid with capillary number
/// Ca (the scene-level choice that [`ParticleModel::response`] turns into a particle's
/// [`material::Softness`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Deformability {
    /// The rigid limit Ca → 0: Jeffery spin and rigid-body drag, no elasticity.
    Rigid,
    /// Elastic solid with Ca = μ_f γ̇₀/μ_s at the scene's reference shear rate γ̇₀.
    Elastic {
        /// Capillary number.
        ca: f64,
    },
}

impl Deformability {
    /// Rigid for Ca = 0, elastic otherwise (Ca finite and > 0).
    pub fn from_ca(ca: f64) -> Result<Self, ParamError> {
        if ca == 0.0 {
            Ok(Deformability::Rigid)
        } else {
            Ok(Deformability::Elastic {
                ca: positive("Ca", ca)?,
            })
        }
    }

    /// Ca, with 0 for the rigid limit (how datasets label it).
    pub fn ca(&self) -> f64 {
        match self {
            Deformability::Rigid => 0.0,
            Deformability::Elastic { ca } => *ca,
        }
    }
}

/// The shape response ([`material::Response`]) of a scene's particles under a law family `L`:
/// rigid, or elastic with `L`'s law.
pub type StudyResponse<L> = material::Softness<<L as LawFactory>::Law>;

/// Law family, drag model and bulk ratio of a study's particles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParticleModel<L = NeoHookeFactory, D = Brenner> {
    law: L,
    drag: D,
    bulk_ratio: f64,
}

impl Default for ParticleModel {
    /// The paper's model: Neo-Hooke (eq. 9), Brenner drag, [`DEFAULT_BULK_RATIO`].
    fn default() -> Self {
        Self {
            law: NeoHookeFactory,
            drag: Brenner,
            bulk_ratio: DEFAULT_BULK_RATIO,
        }
    }
}

impl<L: LawFactory, D: DragModel + Clone> ParticleModel<L, D> {
    /// A model with its bulk ratio λ_s/μ_s (finite, > 0).
    pub fn new(law: L, drag: D, bulk_ratio: f64) -> Result<Self, ParamError> {
        Ok(Self {
            law,
            drag,
            bulk_ratio: positive("bulk ratio lambda_s/mu_s", bulk_ratio)?,
        })
    }

    /// The drag model.
    pub fn drag(&self) -> &D {
        &self.drag
    }

    /// λ_s/μ_s.
    pub fn bulk_ratio(&self) -> f64 {
        self.bulk_ratio
    }

    /// The shape response of `softness` when Ca is defined with the stress scale
    /// μ_f γ̇₀ = `stress_scale`: μ_s = μ_f γ̇₀/Ca, λ_s = bulk ratio · μ_s.
    pub fn response(&self, softness: Deformability, stress_scale: f64) -> Result<StudyResponse<L>, ParamError> {
        Ok(match softness {
            Deformability::Rigid => material::Softness::Rigid,
            Deformability::Elastic { ca } => {
                let mu_s = positive("stress scale", stress_scale)? / positive("Ca", ca)?;
                material::Softness::Elastic(self.law.law(mu_s, self.bulk_ratio * mu_s)?)
            }
        })
    }

    /// The particle of `shape` with `softness` (see [`Self::response`]) in `fluid`.
    pub fn particle(
        &self,
        shape: Ellipsoid,
        softness: Deformability,
        stress_scale: f64,
        fluid: Fluid,
        rho_solid: f64,
    ) -> Result<Particle<StudyResponse<L>, D>, ParamError> {
        Particle::with_drag(
            shape,
            self.response(softness, stress_scale)?,
            self.drag.clone(),
            fluid,
            rho_solid,
        )
    }
}

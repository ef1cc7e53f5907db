//! What a real-flow scene builds its particles from: the softness of a release, the law
//! family and drag model of the study, and one default bulk ratio.
//!
//! A scene takes a [`ParticleModel`] so that a study with another hyperelastic law (any
//! [`LawFactory`]) or drag model (any [`DragModel`]) runs through the paper's scenes unchanged:
//! `Cavity::new(&field)?.with_model(ParticleModel::new(MooneyRivlinLaw { beta: 0.3 }, Brenner,
//! DEFAULT_BULK_RATIO)?)`.

use crate::ellipsoid::Ellipsoid;
use crate::error::{ParamError, positive};
use crate::hydro::{Brenner, DragModel};
use crate::material::{self, LawFactory, NeoHookeLaw};
use crate::particle::{Fluid, Particle};
use serde::{Deserialize, Serialize};

/// λ_s/μ_s of the scenes' soft particles: 10³ ("quasi-incompressible", paper §3; the paper
/// gives no value). The volume then changes by |J − 1| ≈ (shear stress)/λ_s ≲ 10⁻³ while the
/// bulk term stays far from stiffening the shape dynamics beyond what the integrators resolve
/// cheaply; the shape response does not depend on the value once |J − 1| ≪ 1 (the TU/TR
/// boundary moves by < 10⁻⁴ in Ca between 10³ and 10⁵).
pub const DEFAULT_BULK_RATIO: f64 = 1e3;

/// Spheroidal shape families of the real-flow scenes, by their semi-axis ratios with the
/// symmetry axis first for prolates and last for oblates.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Shape {
    /// Semi-axes λ₁ : 1 : 1.
    Prolate(f64),
    /// Semi-axes λ₁ : λ₁ : 1.
    Oblate(f64),
}

impl Shape {
    /// Semi-axis ratios: prolate (λ₁, 1, 1), oblate (λ₁, λ₁, 1).
    pub fn ratios(self) -> [f64; 3] {
        match self {
            Shape::Prolate(l) => [l, 1.0, 1.0],
            Shape::Oblate(l) => [l, l, 1.0],
        }
    }
    /// Label for datasets, e.g. `prolate_5`.
    pub fn label(self) -> String {
        match self {
            Shape::Prolate(l) => format!("prolate_{l}"),
            Shape::Oblate(l) => format!("oblate_{l}"),
        }
    }
}

/// Softness of one release.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Softness {
    /// The rigid limit Ca → 0: Jeffery spin and rigid-body drag, no elasticity.
    Rigid,
    /// Elastic solid with Ca = μ_f γ̇₀/μ_s at the scene's reference shear rate γ̇₀.
    Elastic {
        /// Capillary number.
        ca: f64,
    },
}

impl Softness {
    /// Rigid for Ca = 0, elastic otherwise (Ca finite and > 0).
    pub fn from_ca(ca: f64) -> Result<Self, ParamError> {
        if ca == 0.0 {
            Ok(Softness::Rigid)
        } else {
            Ok(Softness::Elastic {
                ca: positive("Ca", ca)?,
            })
        }
    }

    /// Ca, with 0 for the rigid limit (how datasets label it).
    pub fn ca(&self) -> f64 {
        match self {
            Softness::Rigid => 0.0,
            Softness::Elastic { ca } => *ca,
        }
    }
}

/// The shape response of a scene's particles under a law family `L`.
pub type Response<L> = material::Softness<<L as LawFactory>::Law>;

/// Law family, drag model and bulk ratio of a study's particles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParticleModel<L = NeoHookeLaw, D = Brenner> {
    law: L,
    drag: D,
    bulk_ratio: f64,
}

impl Default for ParticleModel {
    /// The paper's model: Neo-Hooke (eq. 9), Brenner drag, [`DEFAULT_BULK_RATIO`].
    fn default() -> Self {
        Self {
            law: NeoHookeLaw,
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

    /// λ_s/μ_s.
    pub fn bulk_ratio(&self) -> f64 {
        self.bulk_ratio
    }

    /// The shape response of `softness` when Ca is defined with the stress scale
    /// μ_f γ̇₀ = `stress_scale`: μ_s = μ_f γ̇₀/Ca, λ_s = bulk ratio · μ_s.
    pub fn response(&self, softness: Softness, stress_scale: f64) -> Result<Response<L>, ParamError> {
        Ok(match softness {
            Softness::Rigid => material::Softness::Rigid,
            Softness::Elastic { ca } => {
                let mu_s = positive("stress scale", stress_scale)? / positive("Ca", ca)?;
                material::Softness::Elastic(self.law.law(mu_s, self.bulk_ratio * mu_s)?)
            }
        })
    }

    /// The particle of `shape` with `softness` (see [`Self::response`]) in `fluid`.
    pub fn particle(
        &self,
        shape: Ellipsoid,
        softness: Softness,
        stress_scale: f64,
        fluid: Fluid,
        rho_solid: f64,
    ) -> Result<Particle<Response<L>, D>, ParamError> {
        Particle::with_drag(
            shape,
            self.response(softness, stress_scale)?,
            self.drag.clone(),
            fluid,
            rho_solid,
        )
    }
}

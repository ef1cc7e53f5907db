//! Initial shapes for the shear-flow scenes, named by their semi-axes along the flow (x), the
//! gradient (y) and the vorticity (z) directions.
//!
//! # Conventions (paper §6.1, Fig. 3; Sanagavarapu et al.)
//! - oblate of aspect ratio λ: semi-axes (λ, 1, λ): r₁ along the flow, r₃ along the gradient,
//!   r₂ along the vorticity, so the in-plane ratio ω₁ = r_long/r_short = λ and the
//!   out-of-plane ratio ω₂ = r_vorticity/r_short = λ (the paper's ω₁(0) = ω₂(0) = 2.5 case);
//! - prolate of aspect ratio λ: (λ, 1, 1): the two largest axes in the shear plane, the
//!   longest along the flow;
//! - triaxial in Sanagavarapu's ratios ω₁ = r_short/r_long (in-plane) and
//!   ω₂ = r_vorticity/r_long: (1, ω₁, ω₂).
//!
//! The stress-free particle is scaled to d_eq = 1 (R₁R₂R₃ = 1/8).

use crate::error::ParamError;
use crate::material::{NeoHooke, Response};
use crate::particle::{Particle, ShearScaling};
use crate::tensor::Mat3;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Initial ellipsoid aligned with the shear axes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ShearShape {
    /// Family label used in datasets.
    pub family: &'static str,
    /// Semi-axis along the flow direction x (relative size).
    pub r_flow: f64,
    /// Semi-axis along the gradient direction y.
    pub r_gradient: f64,
    /// Semi-axis along the vorticity direction z.
    pub r_vorticity: f64,
}

impl ShearShape {
    /// Oblate (λ, 1, λ).
    pub fn oblate(aspect: f64) -> Self {
        Self {
            family: "oblate",
            r_flow: aspect,
            r_gradient: 1.0,
            r_vorticity: aspect,
        }
    }

    /// Sphere (1, 1, 1).
    pub fn sphere() -> Self {
        Self {
            family: "sphere",
            r_flow: 1.0,
            r_gradient: 1.0,
            r_vorticity: 1.0,
        }
    }

    /// Prolate (λ, 1, 1).
    pub fn prolate(aspect: f64) -> Self {
        Self {
            family: "prolate",
            r_flow: aspect,
            r_gradient: 1.0,
            r_vorticity: 1.0,
        }
    }

    /// Triaxial (1, ω₁, ω₂) in Sanagavarapu's ratios (both relative to the in-plane long axis).
    pub fn triaxial(family: &'static str, omega1: f64, omega2: f64) -> Self {
        Self {
            family,
            r_flow: 1.0,
            r_gradient: omega1,
            r_vorticity: omega2,
        }
    }

    /// Relative semi-axes in the order (flow, gradient, vorticity).
    pub fn ratios(&self) -> [f64; 3] {
        [self.r_flow, self.r_gradient, self.r_vorticity]
    }

    /// Indices (a, c) of the initial in-shear-plane semi-axes, a on the longer one (ties: flow).
    pub fn in_plane_axes(&self) -> (usize, usize) {
        if self.r_flow >= self.r_gradient { (0, 1) } else { (1, 0) }
    }

    /// In-plane aspect ratio r_long/r_short ≥ 1.
    pub fn in_plane_aspect(&self) -> f64 {
        self.r_flow.max(self.r_gradient) / self.r_flow.min(self.r_gradient)
    }

    /// Half of Jeffery's period π(r + 1/r) of a rigid spheroid with the in-plane aspect ratio:
    /// the time after which the rigid in-plane outline repeats. Soft particles are slower
    /// (≈ 10 vs 9.1 for the oblate 2.5 at Ca = 0.4), so this is a lower bound for the shape period.
    pub fn rigid_shape_period(&self) -> f64 {
        let r = self.in_plane_aspect();
        PI * (r + 1.0 / r)
    }

    /// The Neo-Hooke particle of this shape with the groups `scaling`, axes E′_a = e_a.
    pub fn particle(&self, scaling: &ShearScaling) -> Result<Particle<NeoHooke>, ParamError> {
        scaling.particle(self.ratios(), Mat3::identity())
    }

    /// The particle of this shape with another shape response (a law, or rigid).
    pub fn particle_with<M: Response>(&self, scaling: &ShearScaling, response: M) -> Result<Particle<M>, ParamError> {
        scaling.particle_with(self.ratios(), Mat3::identity(), response)
    }
}

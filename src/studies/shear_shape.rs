//! The placement of a [`Shape`] in the shear axes: which body axis starts along the flow (x),
//! the gradient (y) and the vorticity (z).
//!
//! # Conventions (paper §6.1, Fig. 3; Sanagavarapu et al.)
//! - oblate λ (body λ : λ : 1): the symmetry axis along the gradient, so the semi-axes along
//!   (flow, gradient, vorticity) are (λ, 1, λ): the in-plane ratio ω₁ = r_long/r_short = λ and
//!   the out-of-plane ratio ω₂ = r_vorticity/r_short = λ (the paper's ω₁(0) = ω₂(0) = 2.5 case);
//! - prolate λ (body λ : 1 : 1): the symmetry axis along the flow, (λ, 1, 1): the two largest
//!   axes in the shear plane, the longest along the flow;
//! - triaxial in Sanagavarapu's ratios (body 1 : ω₁ : ω₂, ω₁ = r_short/r_long in-plane,
//!   ω₂ = r_vorticity/r_long): body axes along (flow, gradient, vorticity), (1, ω₁, ω₂);
//! - sphere: (1, 1, 1).
//!
//! The semi-axis ratios are those of [`Shape::ratios`], reordered, never recomputed; the
//! stress-free particle is scaled to d_eq = 1 (R₁R₂R₃ = 1/8, [`ShearScaling`]).

use crate::error::ParamError;
use crate::material::{NeoHooke, Response};
use crate::particle::{Particle, ShearScaling};
use crate::studies::particles::Shape;
use crate::tensor::Mat3;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// A [`Shape`] placed in the shear axes by the paper's convention (module docs), its axes
/// E′_a = e_a.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ShearShape {
    /// The shape family.
    pub shape: Shape,
}

impl ShearShape {
    /// `shape` in the paper's placement.
    pub fn new(shape: Shape) -> Self {
        Self { shape }
    }

    /// Body axis (0, 1, 2) along the flow, the gradient and the vorticity.
    pub fn body_axes(&self) -> [usize; 3] {
        match self.shape {
            Shape::Oblate(_) => [0, 2, 1],
            Shape::Sphere | Shape::Prolate(_) | Shape::Triaxial { .. } => [0, 1, 2],
        }
    }

    /// Relative semi-axes in the order (flow, gradient, vorticity).
    pub fn ratios(&self) -> [f64; 3] {
        let body = self.shape.ratios();
        self.body_axes().map(|a| body[a])
    }

    /// Indices (a, c) of the initial in-shear-plane semi-axes, a on the longer one (ties: flow).
    pub fn in_plane_axes(&self) -> (usize, usize) {
        let [flow, gradient, _] = self.ratios();
        if flow >= gradient { (0, 1) } else { (1, 0) }
    }

    /// In-plane aspect ratio r_long/r_short ≥ 1.
    pub fn in_plane_aspect(&self) -> f64 {
        let [flow, gradient, _] = self.ratios();
        flow.max(gradient) / flow.min(gradient)
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

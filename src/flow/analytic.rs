//! Analytic linear and pipe flows.
//!
//! # Physics
//! - quiescent: u = 0;
//! - simple shear: u = γ̇ x₂ e₁, so l_f = γ̇ e₁⊗e₂ and the vorticity is −γ̇ e₃;
//! - planar extension: u = ε̇ (x₁, −x₂, 0);
//! - uniaxial extension: u = ε̇ (x₁, −x₂/2, −x₃/2);
//! - Poiseuille pipe along e₁ with radius R and mean velocity Ū:
//!   $u = 2Ū (1 − r²/R²) e_1$, r the distance from the axis; outside r > R is out of the domain.

use super::{FlowField, FlowSample, check_query};
use crate::error::{FlowError, ParamError, finite, positive};
use crate::tensor::{Mat3, Vec3};
use serde::{Deserialize, Serialize};

/// Fluid at rest.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize)]
pub struct Quiescent;

impl FlowField for Quiescent {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        check_query(x, t)?;
        Ok(FlowSample {
            u: Vec3::zeros(),
            grad_u: Mat3::zeros(),
        })
    }
}

/// Linear flow u = u₀ + L·x with a constant gradient L (shear, extensions, any combination).
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct LinearFlow {
    /// Velocity at the origin.
    pub u0: Vec3,
    /// Constant velocity gradient L.
    pub grad_u: Mat3,
}

impl LinearFlow {
    /// General linear flow; the gradient must be finite and traceless (incompressible).
    pub fn new(u0: Vec3, grad_u: Mat3) -> Result<Self, ParamError> {
        for c in u0.iter().chain(grad_u.iter()) {
            finite("linear flow coefficient", *c)?;
        }
        let scale = grad_u.abs().max().max(1.0);
        if grad_u.trace().abs() > 1e-12 * scale {
            return Err(ParamError::NonFinite {
                name: "tr grad_u (must be 0)",
                value: grad_u.trace(),
            });
        }
        Ok(Self { u0, grad_u })
    }

    /// Simple shear u = γ̇ x₂ e₁.
    pub fn simple_shear(shear_rate: f64) -> Result<Self, ParamError> {
        let mut l = Mat3::zeros();
        l[(0, 1)] = finite("shear rate", shear_rate)?;
        Self::new(Vec3::zeros(), l)
    }

    /// Planar extension u = ε̇ (x₁, −x₂, 0).
    pub fn planar_extension(rate: f64) -> Result<Self, ParamError> {
        let r = finite("extension rate", rate)?;
        Self::new(Vec3::zeros(), Mat3::from_diagonal(&Vec3::new(r, -r, 0.0)))
    }

    /// Uniaxial extension u = ε̇ (x₁, −x₂/2, −x₃/2).
    pub fn uniaxial_extension(rate: f64) -> Result<Self, ParamError> {
        let r = finite("extension rate", rate)?;
        Self::new(Vec3::zeros(), Mat3::from_diagonal(&Vec3::new(r, -0.5 * r, -0.5 * r)))
    }

    /// The same flow seen in a frame rotated by `q` (x' = q x): u' = q u₀, L' = q L qᵀ.
    pub fn rotated(&self, q: &Mat3) -> Self {
        Self {
            u0: q * self.u0,
            grad_u: q * self.grad_u * q.transpose(),
        }
    }
}

impl FlowField for LinearFlow {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        check_query(x, t)?;
        Ok(FlowSample {
            u: self.u0 + self.grad_u * x,
            grad_u: self.grad_u,
        })
    }
}

/// Hagen–Poiseuille flow in a straight circular pipe whose axis is the x₁ axis.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct Poiseuille {
    /// Pipe radius R.
    pub radius: f64,
    /// Mean (bulk) velocity Ū; the centreline velocity is 2Ū.
    pub mean_velocity: f64,
}

impl Poiseuille {
    /// Pipe of radius `radius` with bulk velocity `mean_velocity`.
    pub fn new(radius: f64, mean_velocity: f64) -> Result<Self, ParamError> {
        Ok(Self {
            radius: positive("pipe radius", radius)?,
            mean_velocity: finite("mean velocity", mean_velocity)?,
        })
    }

    /// Wall shear rate magnitude at distance `r` from the axis, |du/dr| = 4Ū r / R².
    pub fn shear_rate(&self, r: f64) -> f64 {
        4.0 * self.mean_velocity * r / (self.radius * self.radius)
    }
}

impl FlowField for Poiseuille {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        check_query(x, t)?;
        let r2 = x[1] * x[1] + x[2] * x[2];
        let rr = self.radius * self.radius;
        if r2 > rr {
            return Err(FlowError::outside(x));
        }
        let umax = 2.0 * self.mean_velocity;
        let mut grad_u = Mat3::zeros();
        grad_u[(0, 1)] = -2.0 * umax * x[1] / rr;
        grad_u[(0, 2)] = -2.0 * umax * x[2] / rr;
        Ok(FlowSample {
            u: Vec3::new(umax * (1.0 - r2 / rr), 0.0, 0.0),
            grad_u,
        })
    }
}

//! The pseudo-rigid particle: constant model data ([`Particle`]) and the evolving state
//! ([`State`]: barycentre x_c, v_c; deformation gradient F and its rate A = Ḟ).
//!
//! Particles are independent and `Send`, so a scene advances them in parallel.
//!
//! # Physics (paper §2, eqs. 1–8)
//! A pseudo-rigid body (Cohen & Muncaster 1988) moves affinely: x = x_c + F·Ξ with one
//! deformation gradient F for the whole particle (eqs. 1, 2), A = Ḟ (eq. 3), and the rest
//! shape Ξ = S·Ξ̄ of the unit sphere (eqs. 4, 5). Its motion is two Euler–Lagrange equations:
//! the barycentre's (eq. 6) and the shape's (eq. 7), with mass m and Euler tensor Θ (eq. 8).
//! [`State`] holds (x_c, v_c, F, A); [`Particle`] the constants; [`dynamics`] the loads of §3
//! inserted into eqs. 6, 7, which gives eqs. 17, 18; [`inertialess`] their limit Θ → 0 as a
//! right-hand side y′ = f(t, y) with its Jacobian; [`release`] the deformation measures a drug
//! release is triggered by (largest principal stretch, semi-axis ratio, energy density).

pub mod dynamics;
pub mod inertialess;
pub mod lines;
pub mod manifold;
pub mod model;
pub mod release;
pub mod scaling;

pub use dynamics::{Forcing, Geometry, Model, Work};
pub use model::{Fluid, Particle};
pub use scaling::ShearScaling;

use crate::error::StepError;
use crate::tensor::{Mat3, Vec3, all_finite};
use serde::{Deserialize, Serialize};

/// Evolving state of one particle at time t.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct State {
    /// Time t.
    pub t: f64,
    /// Barycentre x_c.
    pub x: Vec3,
    /// Barycentre velocity v_c.
    pub v: Vec3,
    /// Deformation gradient F (stress-free: F = 1).
    pub f: Mat3,
    /// Material velocity gradient A = Ḟ.
    pub a: Mat3,
}

impl State {
    /// Stress-free particle at rest at `x` at time 0 (the paper's initial increment).
    pub fn at_rest(x: Vec3) -> Self {
        Self {
            t: 0.0,
            x,
            v: Vec3::zeros(),
            f: Mat3::identity(),
            a: Mat3::zeros(),
        }
    }

    /// The state's image under an isometry of the flow (a cyclic pair, a symmetry plane, a
    /// wedge; [`crate::flow::image`]): $x_c^\prime = T(x_c)$, $v_c^\prime = Q v_c$, $F^\prime = Q F P$,
    /// $A^\prime = Q A P$, with P = 1 for a rotation and, for a reflection, the reflection
    /// $P = R_0 \operatorname{diag}(1, 1, −1) R_0^T$ through a principal plane of the rest ellipsoid
    /// (principal axes `rest_axes` $= R_0$, [`crate::ellipsoid::Ellipsoid::axes`]). P maps the
    /// rest ellipsoid, its inertia and an isotropic law onto themselves, so it relabels the
    /// mirrored body's reference configuration: the deformed ellipsoid $F^\prime B_0 = Q F B_0$
    /// is the mirror image of $F B_0$, and det F' > 0. (The reflection diag(1, 1, −1) of the
    /// reference coordinates alone maps a rest ellipsoid onto itself only where its axes are
    /// those coordinates' or e₃ is one of them.)
    pub fn mapped(&self, map: &crate::flow::Isometry, rest_axes: &Mat3) -> Self {
        let p = if map.q.determinant() < 0.0 {
            rest_axes * Mat3::from_diagonal(&Vec3::new(1.0, 1.0, -1.0)) * rest_axes.transpose()
        } else {
            Mat3::identity()
        };
        Self {
            t: self.t,
            x: map.point(&self.x),
            v: map.q * self.v,
            f: map.q * self.f * p,
            a: map.q * self.a * p,
        }
    }

    /// Spatial velocity gradient of the solid, l_s = A F⁻¹.
    pub fn l_s(&self) -> Mat3 {
        self.a * crate::tensor::inv_transpose(&self.f).transpose()
    }

    /// J = det F.
    pub fn det_f(&self) -> f64 {
        self.f.determinant()
    }

    /// Reject NaN/∞ anywhere in the state, det F ≤ 0, and an F whose stretches do not fit
    /// in f64: b = F Fᵀ (its eigenvalues are the squared stretches) must be finite and det F
    /// a normal number, else the principal frame of F is NaN.
    pub fn validate(&self) -> Result<(), StepError> {
        let finite = self.t.is_finite()
            && self.x.iter().chain(self.v.iter()).all(|c| c.is_finite())
            && all_finite(&self.f)
            && all_finite(&self.a);
        if !finite {
            return Err(StepError::NonFinite {
                what: "particle state",
                t: self.t,
            });
        }
        let det_f = self.det_f();
        if det_f <= 0.0 {
            return Err(StepError::Inverted { det_f, t: self.t });
        }
        if det_f < f64::MIN_POSITIVE || !det_f.is_finite() || !all_finite(&(self.f * self.f.transpose())) {
            return Err(StepError::NonFinite {
                what: "stretches of F (F Fᵀ or det F out of f64 range)",
                t: self.t,
            });
        }
        Ok(())
    }
}

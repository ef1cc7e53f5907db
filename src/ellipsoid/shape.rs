//! Stress-free ellipsoid B₀ and its shape tensor.
//!
//! # Physics (paper §2.1, eqs. 4, 8)
//! $S = \sum_a R_a\, E'_a \otimes \bar E_a$ maps the unit reference sphere onto B₀; R_a are the
//! semi-axes and E'_a the initial axes in global coordinates. Hence
//! vol(B₀) = det S · 4π/3 and, for a homogeneous solid ellipsoid of mass m,
//! the Euler tensor is Θ = (m/5) S Sᵀ.

use crate::error::{ParamError, positive};
use crate::tensor::{Mat3, Vec3};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// A stress-free ellipsoid: semi-axes R_a along the orthonormal initial axes E'_a.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Ellipsoid {
    semi_axes: Vec3,
    axes: Mat3,
}

impl Ellipsoid {
    /// Ellipsoid with semi-axes `semi_axes[a]` along column `a` of `axes` (E'_a).
    ///
    /// `axes` must be a rotation (orthonormal, det = +1) to 1e-10.
    pub fn new(semi_axes: [f64; 3], axes: Mat3) -> Result<Self, ParamError> {
        for r in semi_axes {
            positive("semi-axis", r)?;
        }
        let defect = (axes.transpose() * axes - Mat3::identity()).abs().max();
        let det = axes.determinant();
        if !(defect <= 1e-10 && (det - 1.0).abs() <= 1e-10) {
            return Err(ParamError::NotARotation {
                orthogonality_defect: defect,
                det,
            });
        }
        Ok(Self {
            semi_axes: Vec3::from(semi_axes),
            axes,
        })
    }

    /// Ellipsoid aligned with the global axes.
    pub fn aligned(semi_axes: [f64; 3]) -> Result<Self, ParamError> {
        Self::new(semi_axes, Mat3::identity())
    }

    /// Ellipsoid with axis ratios `ratios` scaled to the volume-equivalent diameter `d_eq`
    /// (R₁R₂R₃ = (d_eq/2)³), along `axes`.
    pub fn with_volume_diameter(ratios: [f64; 3], d_eq: f64, axes: Mat3) -> Result<Self, ParamError> {
        for r in ratios {
            positive("axis ratio", r)?;
        }
        let d_eq = positive("d_eq", d_eq)?;
        let scale = 0.5 * d_eq / (ratios[0] * ratios[1] * ratios[2]).cbrt();
        Self::new(ratios.map(|r| r * scale), axes)
    }

    /// Semi-axes R_a.
    pub fn semi_axes(&self) -> Vec3 {
        self.semi_axes
    }

    /// Initial axes E'_a as columns.
    pub fn axes(&self) -> Mat3 {
        self.axes
    }

    /// Shape and orientation tensor S = Σ_a R_a E'_a ⊗ Ē_a (eq. 4).
    pub fn shape_tensor(&self) -> Mat3 {
        self.axes * Mat3::from_diagonal(&self.semi_axes)
    }

    /// vol(B₀) = det S · 4π/3.
    pub fn volume(&self) -> f64 {
        4.0 / 3.0 * PI * self.semi_axes.product()
    }

    /// Volume-equivalent diameter d_eq = 2 (R₁R₂R₃)^{1/3}.
    pub fn volume_diameter(&self) -> f64 {
        2.0 * self.semi_axes.product().cbrt()
    }

    /// Euler tensor Θ = (m/5) S Sᵀ of a homogeneous ellipsoid of mass m (eq. 8).
    pub fn euler_tensor(&self, mass: f64) -> Mat3 {
        let s = self.shape_tensor();
        s * s.transpose() * (mass / 5.0)
    }

    /// Material position Ξ = R_a E'_a of the surface point on initial semi-axis `a`
    /// (the points A, B, C of paper Fig. 3).
    pub fn axis_point(&self, a: usize) -> Vec3 {
        self.axes.column(a) * self.semi_axes[a]
    }
}

//! Stress-free ellipsoid B₀ and its shape tensor.
//!
//! # Physics (paper §2.1, eqs. 4, 8)
//! $S = \sum_a R_a\\, E_a^{\prime} \otimes \bar E_a$ maps the unit reference sphere onto B₀; R_a are the
//! semi-axes and E′_a the initial axes in global coordinates. Hence
//! vol(B₀) = det S · 4π/3 and, for a homogeneous solid ellipsoid of mass m,
//! the Euler tensor is Θ = (m/5) S Sᵀ.

use crate::error::{ParamError, derived, positive};
use crate::tensor::{Mat3, Vec3};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// A stress-free ellipsoid: semi-axes R_a along the orthonormal initial axes E′_a.
///
/// Deserialisation goes through [`Ellipsoid::new`], so a file cannot bypass its checks.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "EllipsoidRaw", into = "EllipsoidRaw")]
pub struct Ellipsoid {
    semi_axes: Vec3,
    axes: Mat3,
}

/// The serialised form of an [`Ellipsoid`] (unchecked).
#[derive(Serialize, Deserialize)]
struct EllipsoidRaw {
    semi_axes: Vec3,
    axes: Mat3,
}

impl TryFrom<EllipsoidRaw> for Ellipsoid {
    type Error = ParamError;
    fn try_from(raw: EllipsoidRaw) -> Result<Self, ParamError> {
        Self::new(raw.semi_axes.into(), raw.axes)
    }
}

impl From<Ellipsoid> for EllipsoidRaw {
    fn from(e: Ellipsoid) -> Self {
        Self {
            semi_axes: e.semi_axes,
            axes: e.axes,
        }
    }
}

impl Ellipsoid {
    /// Ellipsoid with semi-axes `semi_axes[a]` along column `a` of `axes` (E′_a).
    ///
    /// `axes` must be a rotation (orthonormal, det = +1) to 1e-10. The squares R_a² (they
    /// enter S Sᵀ, Θ and Jeffery's integrals) and the volume must be finite and > 0.
    pub fn new(semi_axes: [f64; 3], axes: Mat3) -> Result<Self, ParamError> {
        for r in semi_axes {
            derived("semi-axis squared R²", positive("semi-axis", r)?.powi(2), &[r])?;
        }
        let product = semi_axes[0] * semi_axes[1] * semi_axes[2];
        derived("volume vol(B0)", 4.0 / 3.0 * PI * product, &semi_axes)?;
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
        // Cube roots first: the product of the ratios may overflow where its cube root does not.
        let scale = 0.5 * d_eq / (ratios[0].cbrt() * ratios[1].cbrt() * ratios[2].cbrt());
        Self::new(ratios.map(|r| r * scale), axes)
    }

    /// Semi-axes R_a.
    pub fn semi_axes(&self) -> Vec3 {
        self.semi_axes
    }

    /// Initial axes E′_a as columns.
    pub fn axes(&self) -> Mat3 {
        self.axes
    }

    /// Shape and orientation tensor S = Σ_a R_a E′_a ⊗ Ē_a (eq. 4).
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

    /// Θ⁻¹ = (5/m) S⁻ᵀ S⁻¹ = E′ diag(5/(m R_a²)) E′ᵀ in closed form (no matrix inversion), or
    /// an error when one of its principal values is not finite and > 0.
    pub fn euler_tensor_inverse(&self, mass: f64) -> Result<Mat3, ParamError> {
        let mut principal = Vec3::zeros();
        for a in 0..3 {
            let r = self.semi_axes[a];
            principal[a] = derived("principal value of Theta^-1", 5.0 / (mass * r * r), &[mass, r])?;
        }
        Ok(self.axes * Mat3::from_diagonal(&principal) * self.axes.transpose())
    }

    /// Material position Ξ = R_a E′_a of the surface point on initial semi-axis `a`
    /// (the points A, B, C of paper Fig. 3).
    pub fn axis_point(&self, a: usize) -> Vec3 {
        self.axes.column(a) * self.semi_axes[a]
    }
}

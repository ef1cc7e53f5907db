//! Current principal frame of the deformed ellipsoid.
//!
//! # Physics (paper §5 and eq. 20, corrected; eqs. A.1, A.2)
//! With F̄ = F·S the left Cauchy–Green tensor of the total distortion is
//! $\bar b = \bar F \bar F^T = \sum_a r_a^2\\, n_a \otimes n_a$, so the current semi-axes are
//! **r_a = sqrt(eig b̄)** (the paper's "r_a = λ_a" is a typo) and the rotation has rows n_a:
//! Q[a, B] = n_a · E_B. Principal components are X′ = Q X Qᵀ, global ones X = Qᵀ X′ Q (eq. A.2).
//! The misprint and its evidence: [`crate::theory::paper_errata`].
//!
//! Eigenvector sign, order and the choice inside a degenerate eigenspace do not matter for
//! σ̃ or k (tested); r is returned sorted descending only for the convenience of diagnostics.

use crate::error::{ParamError, derived};
use crate::tensor::{Mat3, Vec3};
use nalgebra::SymmetricEigen;

/// Semi-axes r_a (descending) and rotation Q (rows n_a) of the current ellipsoid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrincipalFrame {
    /// Current semi-axes r₁ ≥ r₂ ≥ r₃.
    pub r: Vec3,
    /// Rotation with rows n_a: X′ = Q X Qᵀ.
    pub q: Mat3,
}

impl PrincipalFrame {
    /// Frame of the total distortion F̄ = F·S.
    ///
    /// Precondition: F̄ finite and non-singular; otherwise the frame holds NaN or zero
    /// semi-axes, promptly (the hot path, [preconditions](crate::error#preconditions)).
    /// [`Self::try_from_total_distortion`] checks.
    pub fn from_total_distortion(f_bar: &Mat3) -> Self {
        let b = f_bar * f_bar.transpose();
        let eig = SymmetricEigen::new(b);
        let mut idx = [0usize, 1, 2];
        idx.sort_by(|&i, &j| eig.eigenvalues[j].total_cmp(&eig.eigenvalues[i]));
        let mut q = Mat3::zeros();
        let mut r = Vec3::zeros();
        for (a, &i) in idx.iter().enumerate() {
            r[a] = eig.eigenvalues[i].max(0.0).sqrt();
            q.set_row(a, &eig.eigenvectors.column(i).transpose());
        }
        if q.determinant() < 0.0 {
            q.row_mut(2).neg_mut();
        }
        Self { r, q }
    }

    /// Frame of the total distortion F̄ = F·S, or why it has none: an entry of F̄ that is not
    /// finite, or semi-axes that are not finite and > 0 (F̄ singular, or F̄F̄ᵀ overflowing).
    pub fn try_from_total_distortion(f_bar: &Mat3) -> Result<Self, ParamError> {
        if let Some(&value) = f_bar.iter().find(|v| !v.is_finite()) {
            return Err(ParamError::NonFinite {
                name: "total distortion F̄ = F·S",
                value,
            });
        }
        let frame = Self::from_total_distortion(f_bar);
        derived("largest semi-axis r₁", frame.r[0], frame.r.as_slice())?;
        derived("smallest semi-axis r₃", frame.r[2], frame.r.as_slice())?;
        Ok(frame)
    }

    /// The frame of the same ellipsoid turned by the rotation `rotation`: axes n_a ↦ R n_a, so
    /// Q ↦ Q Rᵀ, and the same semi-axes (F̄ ↦ R F̄ turns the eigenvectors of F̄F̄ᵀ by R).
    pub fn turned(&self, rotation: &Mat3) -> Self {
        Self {
            r: self.r,
            q: self.q * rotation.transpose(),
        }
    }

    /// Principal components X′ = Q X Qᵀ of a global tensor.
    pub fn to_principal(&self, x: &Mat3) -> Mat3 {
        self.q * x * self.q.transpose()
    }

    /// Global components X = Qᵀ X′ Q of a principal-frame tensor.
    pub fn to_global(&self, xp: &Mat3) -> Mat3 {
        self.q.transpose() * xp * self.q
    }

    /// Smallest semi-axis r_min.
    pub fn r_min(&self) -> f64 {
        self.r[2]
    }

    /// Extent of the ellipsoid from its centre along the unit vector `n` (support distance).
    pub fn support_distance(&self, n: &Vec3) -> f64 {
        support_distance(&self.r, &self.q, n)
    }

    /// Current volume 4π/3 r₁r₂r₃.
    pub fn volume(&self) -> f64 {
        4.0 / 3.0 * std::f64::consts::PI * self.r.product()
    }
}

/// Support distance $h(n) = \sqrt{\sum_a r_a^2 (n·n_a)^2} = \sqrt{n·\bar b\\,n}$ of an ellipsoid
/// with semi-axes `semi_axes` and rotation `q` (rows n_a) along the unit vector `n`: the
/// distance from its centre to its tangent plane with normal n (wall contact, deposition).
pub fn support_distance(semi_axes: &Vec3, q: &Mat3, n: &Vec3) -> f64 {
    (q * n).component_mul(semi_axes).norm()
}

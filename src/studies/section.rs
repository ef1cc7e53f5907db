//! The ellipse cut out of the current ellipsoid by the shear plane z = 0.
//!
//! # Geometry
//! The current ellipsoid is {ξ : ξᵀ b̄⁻¹ ξ ≤ 1} with b̄ = F̄F̄ᵀ (paper §2). Its section with
//! z = 0 is the ellipse with matrix M = [b̄⁻¹]_{xy}, semi-axes 1/√eig(M); the long axis is the
//! eigenvector of the smaller eigenvalue. Its angle from the flow direction is folded into
//! (−π/2, π/2] (eigenvector signs carry no meaning). The out-of-plane size is
//! the half-chord along the vorticity axis, 1/√(b̄⁻¹)_zz; for shapes with z as a symmetry
//! plane (all shapes of paper §6.1) z stays a principal axis and this is the principal r.

use crate::tensor::Mat3;
use nalgebra::{Matrix2, SymmetricEigen};
use std::f64::consts::PI;

/// In-plane ellipse of the current shape.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShearPlaneSection {
    /// Long semi-axis of the section.
    pub r_long: f64,
    /// Short semi-axis of the section.
    pub r_short: f64,
    /// Angle of the long axis from the flow direction x, in (−π/2, π/2].
    pub angle: f64,
    /// Half-chord along the vorticity axis z.
    pub r_out_of_plane: f64,
}

impl ShearPlaneSection {
    /// Section of the ellipsoid with total distortion F̄ = F·S.
    pub fn of(f_bar: &Mat3) -> Self {
        let b_inv = (f_bar * f_bar.transpose())
            .try_inverse()
            .expect("det F̄ > 0 is a state invariant");
        let m = Matrix2::new(b_inv[(0, 0)], b_inv[(0, 1)], b_inv[(1, 0)], b_inv[(1, 1)]);
        let eig = SymmetricEigen::new(m);
        let (long, short) = if eig.eigenvalues[0] <= eig.eigenvalues[1] {
            (0, 1)
        } else {
            (1, 0)
        };
        let dir = eig.eigenvectors.column(long);
        let mut angle = dir[1].atan2(dir[0]);
        if angle > PI / 2.0 {
            angle -= PI;
        } else if angle <= -PI / 2.0 {
            angle += PI;
        }
        Self {
            r_long: eig.eigenvalues[long].sqrt().recip(),
            r_short: eig.eigenvalues[short].sqrt().recip(),
            angle,
            r_out_of_plane: b_inv[(2, 2)].sqrt().recip(),
        }
    }

    /// In-plane aspect ratio ω₁ = r_long/r_short (oblate convention, ≥ 1).
    pub fn omega1(&self) -> f64 {
        self.r_long / self.r_short
    }

    /// Out-of-plane ratio ω₂ = r_out_of_plane/r_short (oblate convention).
    pub fn omega2(&self) -> f64 {
        self.r_out_of_plane / self.r_short
    }

    /// Taylor deformation D = (r_long − r_short)/(r_long + r_short).
    pub fn deformation(&self) -> f64 {
        (self.r_long - self.r_short) / (self.r_long + self.r_short)
    }

    /// End point of the long semi-axis (x, y).
    pub fn long_axis_tip(&self) -> (f64, f64) {
        (self.r_long * self.angle.cos(), self.r_long * self.angle.sin())
    }

    /// `n` points on the outline (closed: the first point is repeated at the end).
    pub fn outline(&self, n: usize) -> Vec<(f64, f64)> {
        let (c, s) = (self.angle.cos(), self.angle.sin());
        (0..=n)
            .map(|i| {
                let phi = 2.0 * PI * i as f64 / n as f64;
                let (u, v) = (self.r_long * phi.cos(), self.r_short * phi.sin());
                (c * u - s * v, s * u + c * v)
            })
            .collect()
    }
}

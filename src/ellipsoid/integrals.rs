//! Jeffery's ellipsoid integrals through Carlson's symmetric elliptic integrals.
//!
//! # Physics (Jeffery 1922; physics.md §4)
//! With x_i = r_i², Δ(λ) = √((x₁+λ)(x₂+λ)(x₃+λ)) and λ ∈ [0, ∞):
//! - $\chi_0 = \int d\lambda/\Delta = 2 R_F(x_1,x_2,x_3)$
//! - $\alpha_i = \int d\lambda/((x_i+\lambda)\Delta) = \tfrac23 R_D(x_j,x_k,x_i)$
//! - $\alpha'_k = \int d\lambda/((x_i+\lambda)(x_j+\lambda)\Delta)$ for the pair (i, j), k the third index
//! - $\alpha''_k = \int \lambda\, d\lambda/((x_i+\lambda)(x_j+\lambda)\Delta) = \alpha_i - x_j \alpha'_k$
//!
//! Checks: abc Σα_i = 2; a sphere of radius a has χ₀ = 2/a, α = 2/(3a³), α' = 2/(5a⁵),
//! α'' = 4/(15a³).
//!
//! # Degenerate pairs without a special branch
//! The textbook route α'_k = (α_j − α_i)/(x_i − x_j) cancels catastrophically when x_i ≈ x_j
//! (every sphere and spheroid). Instead we use ∂(1/Δ)/∂x_j = −1/(2(x_j+λ)Δ), which gives
//! $\alpha'_k = -2\,\partial\alpha_i/\partial x_j = -\tfrac43\,\partial_1 R_D(x_j,x_k,x_i)$,
//! and evaluate that derivative exactly with a dual number through Carlson's duplication
//! algorithm. There is no cancellation at any separation, so the near-degenerate branch of
//! physics.md §4 (O(δ²) error) is not needed; tests check 1e-12 against quadrature.

use crate::tensor::{Scalar, Vec3};
use num_dual::Dual64;

/// Relative spread of the duplication arguments at which the Taylor tail is used: the
/// neglected terms are O(δ⁶) ≈ 1e-20.
const DUPLICATION_SPREAD: f64 = 5e-4;

/// Carlson's R_F(x, y, z) = ½ ∫₀^∞ dt / √((t+x)(t+y)(t+z)) (Carlson 1995, duplication).
pub fn carlson_rf<S: Scalar>(x: S, y: S, z: S) -> S {
    let (mut x, mut y, mut z) = (x, y, z);
    loop {
        let a = (x + y + z) / 3.0;
        let spread = [x, y, z].iter().map(|v| (a.re() - v.re()).abs()).fold(0.0, f64::max);
        if spread <= DUPLICATION_SPREAD * a.re().abs() {
            let (dx, dy) = ((a - x) / a, (a - y) / a);
            let dz = -(dx + dy);
            let e2 = dx * dy - dz * dz;
            let e3 = dx * dy * dz;
            let series = S::one() - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - e2 * e3 * (3.0 / 44.0);
            return series / a.sqrt();
        }
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * sy + sy * sz + sz * sx;
        x = (x + lambda) * 0.25;
        y = (y + lambda) * 0.25;
        z = (z + lambda) * 0.25;
    }
}

/// Carlson's R_D(x, y, z) = (3/2) ∫₀^∞ dt / (√((t+x)(t+y)) (t+z)^{3/2}) (Carlson 1995).
pub fn carlson_rd<S: Scalar>(x: S, y: S, z: S) -> S {
    let (mut x, mut y, mut z) = (x, y, z);
    let mut sum = S::zero();
    let mut scale = 1.0;
    loop {
        let a = (x + y + z * 3.0) / 5.0;
        let spread = [x, y, z].iter().map(|v| (a.re() - v.re()).abs()).fold(0.0, f64::max);
        if spread <= DUPLICATION_SPREAD * a.re().abs() {
            let (dx, dy) = ((a - x) / a, (a - y) / a);
            let dz = -(dx + dy) / 3.0;
            let xy = dx * dy;
            let z2 = dz * dz;
            let e2 = xy - z2 * 6.0;
            let e3 = (xy * 3.0 - z2 * 8.0) * dz;
            let e4 = (xy - z2) * z2 * 3.0;
            let e5 = xy * z2 * dz;
            let series = S::one() - e2 * (3.0 / 14.0) + e3 / 6.0 + e2 * e2 * (9.0 / 88.0)
                - e4 * (3.0 / 22.0)
                - e2 * e3 * (9.0 / 52.0)
                + e5 * (3.0 / 26.0);
            return series * scale / (a * a.sqrt()) + sum * 3.0;
        }
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * sy + sy * sz + sz * sx;
        sum += (sz * (z + lambda)).recip() * scale;
        scale *= 0.25;
        x = (x + lambda) * 0.25;
        y = (y + lambda) * 0.25;
        z = (z + lambda) * 0.25;
    }
}

/// Jeffery's integrals of the current ellipsoid, indexed like its semi-axes.
///
/// `alpha_p[k]` and `alpha_pp[k]` belong to the pair (i, j) that excludes k.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EllipsoidIntegrals {
    /// x_i = r_i².
    pub x: Vec3,
    /// abc = r₁r₂r₃.
    pub abc: f64,
    /// χ₀.
    pub chi0: f64,
    /// α_i.
    pub alpha: Vec3,
    /// α'_k.
    pub alpha_p: Vec3,
    /// α''_k.
    pub alpha_pp: Vec3,
}

impl EllipsoidIntegrals {
    /// Integrals for semi-axes `r` (all finite and > 0; the frame guarantees this for det F > 0).
    pub fn new(r: &Vec3) -> Self {
        let x = r.component_mul(r);
        let mut alpha = Vec3::zeros();
        let mut alpha_p = Vec3::zeros();
        // α_i = (2/3) R_D(x_j, x_k, x_i); differentiating in x_j gives α' of the pair (i, j).
        for i in 0..3 {
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            let rd = carlson_rd(Dual64::new(x[j], 1.0), Dual64::from(x[k]), Dual64::from(x[i]));
            alpha[i] = 2.0 / 3.0 * rd.re;
            alpha_p[k] = -4.0 / 3.0 * rd.eps;
        }
        let mut alpha_pp = Vec3::zeros();
        for k in 0..3 {
            let (i, j) = ((k + 1) % 3, (k + 2) % 3);
            alpha_pp[k] = alpha[i] - x[j] * alpha_p[k];
        }
        Self {
            x,
            abc: r.product(),
            chi0: 2.0 * carlson_rf(x[0], x[1], x[2]),
            alpha,
            alpha_p,
            alpha_pp,
        }
    }
}

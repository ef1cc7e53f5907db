//! Jeffery's ellipsoid integrals through Carlson's symmetric elliptic integrals.
//!
//! # Physics (Jeffery 1922; Carlson 1995; the coefficients of paper eqs. 12 and 14)
//! With x_i = r_i², Δ(λ) = √((x₁+λ)(x₂+λ)(x₃+λ)) and λ ∈ [0, ∞):
//! - $\chi_0 = \int d\lambda/\Delta = 2 R_F(x_1,x_2,x_3)$
//! - $\alpha_i = \int d\lambda/((x_i+\lambda)\Delta) = \tfrac23 R_D(x_j,x_k,x_i)$
//! - $\alpha_k^{\prime} = \int d\lambda/((x_i+\lambda)(x_j+\lambda)\Delta)$ for the pair (i, j), k the third index
//! - $\alpha_k^{\prime\prime} = \int \lambda\\, d\lambda/((x_i+\lambda)(x_j+\lambda)\Delta) = \alpha_i - x_j \alpha_k^{\prime}$
//!
//! Checks: abc Σα_i = 2; a sphere of radius a has χ₀ = 2/a, α = 2/(3a³), α′ = 2/(5a⁵),
//! α″ = 4/(15a³).
//!
//! # Degenerate pairs without a special branch
//! The textbook route α′_k = (α_j − α_i)/(x_i − x_j) cancels catastrophically when x_i ≈ x_j
//! (every sphere and spheroid). Instead we use ∂(1/Δ)/∂x_j = −1/(2(x_j+λ)Δ), which gives
//! $\alpha_k^{\prime} = -2\\,\partial\alpha_i/\partial x_j = -\tfrac43\\,\partial_1 R_D(x_j,x_k,x_i)$,
//! and evaluate that derivative exactly by forward-mode AD through Carlson's duplication
//! algorithm. There is no cancellation at any separation, so the near-degenerate branch of
//! a series expansion (O(δ²) error) is not needed; tests check 1e-12 against quadrature.
//! R_F and the three R_D share one duplication sequence (`joint_duplication`), so one loop
//! yields all of them with their gradients.
//! The derivation, step by step: [`crate::theory::ellipsoid_integrals`].

use crate::error::ParamError;
use crate::tensor::{Scalar, Vec3, max_or_nan};
use num_dual::{Dual64, DualNum};

/// Relative spread of the duplication arguments at which the Taylor tail is used: the
/// neglected terms are O(δ⁶) ≈ 1e-20.
const DUPLICATION_SPREAD: f64 = 5e-4;

/// Cap on duplication steps. Each step divides the spread |A − x_i| by at least 4 (Carlson
/// 1995, eq. 2.4), and for admissible arguments the relative spread starts below 3 (all
/// x_i ≥ 0 gives |A − x_i| ≤ 2A for R_F, ≤ 4A for R_D), so 4⁻ⁿ·4 ≤ 5e-4 after n = 7 steps;
/// dynamic ranges of 1e600 between the arguments add log₄ of that ratio, under 500. The cap is
/// a guard, never reached by admissible input (the fuzz harness checks this).
const MAX_DUPLICATIONS: usize = 1000;

/// Arguments above this make the first mean (x + y + 3z)/5 overflow.
const MAX_ARGUMENT: f64 = f64::MAX / 8.0;

/// Domain check shared by R_F and R_D: finite, ≥ 0, not too large, and at most one zero among
/// the arguments that may vanish (two zeros make the integral diverge).
fn check_domain(function: &'static str, x: f64, y: f64, z: f64, z_may_vanish: bool) -> Result<(), ParamError> {
    let err = |reason| ParamError::OutOfDomain {
        function,
        x,
        y,
        z,
        reason,
    };
    if ![x, y, z]
        .iter()
        .all(|v| v.is_finite() && (0.0..=MAX_ARGUMENT).contains(v))
    {
        return Err(err("arguments must be finite, >= 0 and below f64::MAX/8"));
    }
    let zeros = [x, y].iter().filter(|&&v| v == 0.0).count() + usize::from(z == 0.0);
    if !z_may_vanish && z == 0.0 {
        return Err(err("the last argument must be > 0"));
    }
    if zeros > 1 {
        return Err(err("at most one argument may be zero"));
    }
    Ok(())
}

/// `Ok(value)` unless it overflowed (tiny arguments: R_D ~ z^{-3/2}).
fn finite_result<S: Scalar>(function: &'static str, value: S, [x, y, z]: [f64; 3]) -> Result<S, ParamError> {
    if value.re().is_finite() {
        Ok(value)
    } else {
        Err(ParamError::OutOfDomain {
            function,
            x,
            y,
            z,
            reason: "the value overflows f64",
        })
    }
}

/// Carlson's R_F(x, y, z) = ½ ∫₀^∞ dt / √((t+x)(t+y)(t+z)) (Carlson 1995, duplication).
///
/// Defined for finite x, y, z ≥ 0 with at most one zero; anything else (NaN, ∞, a negative
/// argument) is a [`ParamError::OutOfDomain`]. The duplication loop is capped.
pub fn carlson_rf<S: Scalar>(x: S, y: S, z: S) -> Result<S, ParamError> {
    let [x0, y0, z0] = [x.re(), y.re(), z.re()];
    check_domain("R_F", x0, y0, z0, true)?;
    let (mut x, mut y, mut z) = (x, y, z);
    for _ in 0..MAX_DUPLICATIONS {
        let a = (x + y + z) / 3.0;
        let spread = max_or_nan([x, y, z].iter().map(|v| (a.re() - v.re()).abs()));
        if spread <= DUPLICATION_SPREAD * a.re().abs() {
            return finite_result("R_F", rf_tail(x, y, z), [x0, y0, z0]);
        }
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * sy + sy * sz + sz * sx;
        x = (x + lambda) * 0.25;
        y = (y + lambda) * 0.25;
        z = (z + lambda) * 0.25;
    }
    Err(ParamError::OutOfDomain {
        function: "R_F",
        x: x.re(),
        y: y.re(),
        z: z.re(),
        reason: "duplication did not converge",
    })
}

/// Carlson's R_D(x, y, z) = (3/2) ∫₀^∞ dt / (√((t+x)(t+y)) (t+z)^{3/2}) (Carlson 1995).
///
/// Defined for finite x, y ≥ 0 (at most one zero) and z > 0; anything else is a
/// [`ParamError::OutOfDomain`]. The duplication loop is capped.
pub fn carlson_rd<S: Scalar>(x: S, y: S, z: S) -> Result<S, ParamError> {
    let [x0, y0, z0] = [x.re(), y.re(), z.re()];
    check_domain("R_D", x0, y0, z0, false)?;
    let (mut x, mut y, mut z) = (x, y, z);
    let mut sum = S::zero();
    let mut scale = 1.0;
    for _ in 0..MAX_DUPLICATIONS {
        let a = (x + y + z * 3.0) / 5.0;
        let spread = max_or_nan([x, y, z].iter().map(|v| (a.re() - v.re()).abs()));
        if spread <= DUPLICATION_SPREAD * a.re().abs() {
            return finite_result("R_D", rd_tail(x, y, z) * scale + sum * 3.0, [x0, y0, z0]);
        }
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * sy + sy * sz + sz * sx;
        sum += (sz * (z + lambda)).recip() * scale;
        scale *= 0.25;
        x = (x + lambda) * 0.25;
        y = (y + lambda) * 0.25;
        z = (z + lambda) * 0.25;
    }
    Err(ParamError::OutOfDomain {
        function: "R_D",
        x: x.re(),
        y: y.re(),
        z: z.re(),
        reason: "duplication did not converge",
    })
}

/// R_D(x_j, x_k, x_i) for i = 0, 1, 2 with their derivatives in x_j, j = i + 1 (mod 3), and
/// R_F(x₁, x₂, x₃), from one duplication sequence.
///
/// Duplication maps the argument set {x₁, x₂, x₃} to {(x_m + λ)/4} with
/// λ = √x₁√x₂ + √x₂√x₃ + √x₃√x₁, whatever the order of the arguments, so R_F and the three R_D
/// share one sequence; the R_D differ only in which member is their last argument z, which
/// enters the accumulated sum 3 Σ 4⁻ⁿ/(√z (z + λ)) (Carlson 1995, eqs. 2.2–2.5). The loop
/// carries the sequence's Jacobian ∂x_m⁽ⁿ⁾/∂x_p by the chain rule, and stops when
/// max − min ≤ 5·10⁻⁴ min over the set: then every mean the four Taylor tails expand about lies
/// within that spread, so each tail's truncation is O(δ⁶) ≈ 10⁻²⁰ as in [`carlson_rd`]. The
/// tails and the sums are dual numbers in the one direction each R_D needs.
fn joint_duplication(x0: [f64; 3]) -> Result<([Dual64; 3], f64), ParamError> {
    check_domain("R_D", x0[0], x0[1], x0[2], false)?;
    let mut x = x0;
    // jac[m][p] = ∂x_m/∂x_p at the start.
    let mut jac = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mut sums = [Dual64::from(0.0); 3];
    let mut scale = 1.0;
    let direction = |i: usize| (i + 1) % 3;
    for _ in 0..MAX_DUPLICATIONS {
        let lo = x[0].min(x[1]).min(x[2]);
        let hi = max_or_nan(x);
        if hi - lo <= DUPLICATION_SPREAD * lo {
            // x_m as a dual number in direction p.
            let dual = |m: usize, p: usize| Dual64::new(x[m], jac[m][p]);
            let rd = [0, 1, 2].map(|i| {
                let (j, k) = (direction(i), (i + 2) % 3);
                rd_tail(dual(j, j), dual(k, j), dual(i, j)) * scale + sums[i] * 3.0
            });
            let rf = rf_tail(x[0], x[1], x[2]);
            for v in rd.iter().map(|d| d.re).chain([rf]) {
                finite_result("R_D", v, x0)?;
            }
            return Ok((rd, rf));
        }
        let s = x.map(f64::sqrt);
        let lambda = s[0] * s[1] + s[1] * s[2] + s[2] * s[0];
        // ∂λ/∂x_m = (Σ_{n≠m} √x_n) / (2√x_m), chained through jac.
        let slope = [0, 1, 2].map(|m| (s[(m + 1) % 3] + s[(m + 2) % 3]) * 0.5 / s[m]);
        let d_lambda = [0, 1, 2].map(|p| (0..3).map(|m| slope[m] * jac[m][p]).sum::<f64>());
        for (i, sum) in sums.iter_mut().enumerate() {
            // 1/(√z (z + λ)) with z = x_i, differentiated in x_j.
            let j = direction(i);
            let z = Dual64::new(x[i], jac[i][j]);
            let root = Dual64::new(s[i], 0.5 * jac[i][j] / s[i]);
            *sum += (root * (z + Dual64::new(lambda, d_lambda[j]))).recip() * scale;
        }
        scale *= 0.25;
        for m in 0..3 {
            x[m] = (x[m] + lambda) * 0.25;
            jac[m] = [0, 1, 2].map(|p| (jac[m][p] + d_lambda[p]) * 0.25);
        }
    }
    Err(ParamError::OutOfDomain {
        function: "R_D",
        x: x[0],
        y: x[1],
        z: x[2],
        reason: "duplication did not converge",
    })
}

/// R_F(x, y, z) of nearly equal arguments: Carlson's Taylor series about the mean A,
/// truncated after the O(δ⁵) terms (δ the relative spread about A).
fn rf_tail<S: Scalar>(x: S, y: S, z: S) -> S {
    let a = (x + y + z) / 3.0;
    let (dx, dy) = ((a - x) / a, (a - y) / a);
    let dz = -(dx + dy);
    let e2 = dx * dy - dz * dz;
    let e3 = dx * dy * dz;
    let series = S::one() - e2 / 10.0 + e3 / 14.0 + e2 * e2 / 24.0 - e2 * e3 * (3.0 / 44.0);
    series / a.sqrt()
}

/// R_D(x, y, z) of nearly equal arguments: Carlson's Taylor series about A = (x + y + 3z)/5,
/// truncated after the O(δ⁵) terms.
fn rd_tail<S: Scalar>(x: S, y: S, z: S) -> S {
    let a = (x + y + z * 3.0) / 5.0;
    let (dx, dy) = ((a - x) / a, (a - y) / a);
    let dz = -(dx + dy) / 3.0;
    let xy = dx * dy;
    let z2 = dz * dz;
    let e2 = xy - z2 * 6.0;
    let e3 = (xy * 3.0 - z2 * 8.0) * dz;
    let e4 = (xy - z2) * z2 * 3.0;
    let e5 = xy * z2 * dz;
    let series =
        S::one() - e2 * (3.0 / 14.0) + e3 / 6.0 + e2 * e2 * (9.0 / 88.0) - e4 * (3.0 / 22.0) - e2 * e3 * (9.0 / 52.0)
            + e5 * (3.0 / 26.0);
    series / (a * a.sqrt())
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
    /// α′_k.
    pub alpha_p: Vec3,
    /// α″_k.
    pub alpha_pp: Vec3,
}

impl EllipsoidIntegrals {
    /// Integrals for semi-axes `r` (all finite and > 0; the frame guarantees this for det F > 0).
    ///
    /// Invalid semi-axes (NaN, ∞, ≤ 0, or squares that overflow or vanish) give integrals that
    /// are all NaN, promptly: this is the non-panicking path for hot loops whose input was
    /// validated upstream. Use [`EllipsoidIntegrals::try_new`] to get the typed error instead.
    pub fn new(r: &Vec3) -> Self {
        Self::try_new(r).unwrap_or(Self {
            x: r.component_mul(r),
            abc: r.product(),
            chi0: f64::NAN,
            alpha: Vec3::repeat(f64::NAN),
            alpha_p: Vec3::repeat(f64::NAN),
            alpha_pp: Vec3::repeat(f64::NAN),
        })
    }

    /// Integrals for semi-axes `r`, or the reason they do not exist in f64: a semi-axis that is
    /// not finite and > 0, a square r² that overflows or underflows, or a non-finite integral.
    pub fn try_new(r: &Vec3) -> Result<Self, ParamError> {
        for &ri in r.iter() {
            crate::error::derived("semi-axis squared r²", ri * ri, &[ri])?;
        }
        let x = r.component_mul(r);
        let (rd, rf) = joint_duplication(x.into())?;
        let mut alpha = Vec3::zeros();
        let mut alpha_p = Vec3::zeros();
        // α_i = (2/3) R_D(x_j, x_k, x_i) with j = i + 1, k = i + 2 (mod 3); its derivative in
        // x_j (the dual part) gives α' of the pair (i, j), which is α'_k.
        for (i, rd_i) in rd.iter().enumerate() {
            let k = (i + 2) % 3;
            alpha[i] = 2.0 / 3.0 * rd_i.re;
            alpha_p[k] = -4.0 / 3.0 * rd_i.eps;
        }
        let mut alpha_pp = Vec3::zeros();
        for k in 0..3 {
            let (i, j) = ((k + 1) % 3, (k + 2) % 3);
            alpha_pp[k] = alpha[i] - x[j] * alpha_p[k];
        }
        let ints = Self {
            x,
            abc: r.product(),
            chi0: 2.0 * rf,
            alpha,
            alpha_p,
            alpha_pp,
        };
        let values = [ints.abc, ints.chi0]
            .into_iter()
            .chain(alpha.iter().chain(&alpha_p).chain(&alpha_pp).copied());
        for v in values {
            if !v.is_finite() {
                return Err(ParamError::Derived {
                    name: "Jeffery integral",
                    value: v,
                    inputs: r.iter().copied().collect(),
                });
            }
        }
        Ok(ints)
    }
}

//! Plane stagnation-point flow against a wall (Hiemenz 1911): an exact solution of the steady
//! Navier–Stokes equations with a no-slip wall, the reference for near-wall interpolation.
//!
//! # Physics
//! The wall is the plane y = 0, the fluid y > 0, the outer flow u = a x, v = −a y. With
//! ℓ = √(ν/a) and η = y/ℓ,
//! ```math
//! u = a\,x\,f'(η),\qquad v = −\sqrt{aν}\,f(η),\qquad w = 0,
//! ```
//! ```math
//! f''' + f f'' − f'^2 + 1 = 0,\qquad f(0) = f'(0) = 0,\quad f'(∞) = 1
//! ```
//! (Schlichting & Gersten, *Boundary-Layer Theory*, 9th ed., §5.2.2; White, *Viscous Fluid Flow*,
//! 3rd ed., §3-8, whose table gives f''(0) = 1.2326). Near the wall
//! $v ≈ −\tfrac12 \sqrt{aν}\\, f^{\prime\prime}(0)\\,η^2$: the wall-normal velocity grows as the square of the wall
//! distance, with the coefficient continuity gives from the wall shear
//! γ = a x f''(0)/ℓ (∇ₛ·γ = a f''(0)/ℓ).
//!
//! # Numerics
//! f''(0) is found by shooting: f'(η_∞) − 1 at η_∞ = [`ETA_SHOOT`] changes sign once on
//! [1, 1.5] and is bisected to round-off; perturbations of the far-field solution grow
//! algebraically only (the linearised equation about f' = 1 has polynomial solutions), so the
//! shot is stable. f, f', f'' are tabulated by classical Runge–Kutta with step [`STEP`] and
//! interpolated by cubic Hermite polynomials (error O(STEP⁴) ≈ 10⁻¹²). Beyond the table,
//! f' = 1 to within its value at η_∞ (|f' − 1| < 10⁻¹² there, checked in the tests).

use super::{FlowField, FlowSample, check_query};
use crate::error::{FlowError, ParamError, positive};
use crate::tensor::{Mat3, Vec3};

/// Edge of the shooting interval in η: the boundary layer's f' − 1 is below 10⁻¹⁵ there.
pub const ETA_SHOOT: f64 = 8.0;
/// Runge–Kutta step of the table in η.
pub const STEP: f64 = 1e-3;
/// Bisection steps on f''(0): 60 halve the unit interval below f64's resolution.
const BISECTIONS: usize = 60;

/// The Hiemenz similarity function f on a table of η (module docs).
#[derive(Debug, Clone)]
pub struct Hiemenz {
    /// Strain rate a of the outer flow.
    a: f64,
    /// Kinematic viscosity ν.
    nu: f64,
    /// (f, f', f'') at η = k · STEP, k = 0..=ETA_SHOOT/STEP.
    table: Vec<[f64; 3]>,
}

/// Right-hand side of the Hiemenz equation as a first-order system in (f, f', f'').
fn rhs(y: [f64; 3]) -> [f64; 3] {
    [y[1], y[2], y[1] * y[1] - y[0] * y[2] - 1.0]
}

/// One classical Runge–Kutta step of size h.
fn rk4(y: [f64; 3], h: f64) -> [f64; 3] {
    let add = |y: [f64; 3], k: [f64; 3], s: f64| [y[0] + s * k[0], y[1] + s * k[1], y[2] + s * k[2]];
    let k1 = rhs(y);
    let k2 = rhs(add(y, k1, h / 2.0));
    let k3 = rhs(add(y, k2, h / 2.0));
    let k4 = rhs(add(y, k3, h));
    std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
}

/// The table from the wall to ETA_SHOOT for the wall curvature f''(0) = `curvature`; stops early
/// once f' leaves [−1, 2] (a shot far off, which can no longer reach f' = 1 by a sign change).
fn shoot(curvature: f64) -> Vec<[f64; 3]> {
    let steps = (ETA_SHOOT / STEP).round() as usize;
    let mut table = Vec::with_capacity(steps + 1);
    let mut y = [0.0, 0.0, curvature];
    table.push(y);
    for _ in 0..steps {
        y = rk4(y, STEP);
        table.push(y);
        if !(-1.0..=2.0).contains(&y[1]) {
            break;
        }
    }
    table
}

impl Hiemenz {
    /// Stagnation-point flow of strain rate `a` > 0 and kinematic viscosity `nu` > 0.
    pub fn new(a: f64, nu: f64) -> Result<Self, ParamError> {
        positive("Hiemenz strain rate a", a)?;
        positive("kinematic viscosity", nu)?;
        // f'(η_∞) − 1 > 0 when f''(0) is too large.
        let (mut lo, mut hi) = (1.0, 1.5);
        for _ in 0..BISECTIONS {
            let mid = 0.5 * (lo + hi);
            let table = shoot(mid);
            let end = table[table.len() - 1];
            if end[1] > 1.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        let table = shoot(0.5 * (lo + hi));
        Ok(Self { a, nu, table })
    }

    /// f''(0), the wall curvature of the similarity profile.
    pub fn wall_curvature(&self) -> f64 {
        self.table[0][2]
    }

    /// The boundary-layer length ℓ = √(ν/a).
    pub fn length(&self) -> f64 {
        (self.nu / self.a).sqrt()
    }

    /// (f, f', f'') at η ≥ 0: cubic Hermite in the table (f from f and f', f' from f' and f'',
    /// f'' from f'' and f'''), the outer flow beyond it.
    pub fn profile(&self, eta: f64) -> [f64; 3] {
        let last = self.table.len() - 1;
        let x = eta.max(0.0) / STEP;
        if x >= last as f64 {
            let end = self.table[last];
            return [end[0] + (eta - last as f64 * STEP) * end[1], end[1], end[2]];
        }
        let k = (x.floor() as usize).min(last - 1);
        let s = x - k as f64;
        let (p, q) = (self.table[k], self.table[k + 1]);
        let (dp, dq) = (rhs(p), rhs(q));
        let hermite = |y0: f64, y1: f64, d0: f64, d1: f64| {
            let (s2, s3) = (s * s, s * s * s);
            (2.0 * s3 - 3.0 * s2 + 1.0) * y0
                + (s3 - 2.0 * s2 + s) * STEP * d0
                + (-2.0 * s3 + 3.0 * s2) * y1
                + (s3 - s2) * STEP * d1
        };
        std::array::from_fn(|i| hermite(p[i], q[i], dp[i], dq[i]))
    }
}

impl FlowField for Hiemenz {
    /// u and ∇u at x = (x, y, z) with y ≥ 0; a point below the wall is outside the domain.
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        check_query(x, t)?;
        if x[1] < 0.0 {
            return Err(FlowError::outside(x));
        }
        let l = self.length();
        let [f, fp, fpp] = self.profile(x[1] / l);
        let a = self.a;
        let u = Vec3::new(a * x[0] * fp, -a * l * f, 0.0);
        let mut grad_u = Mat3::zeros();
        grad_u[(0, 0)] = a * fp;
        grad_u[(0, 1)] = a * x[0] * fpp / l;
        grad_u[(1, 1)] = -a * fp;
        Ok(FlowSample::steady(u, grad_u))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// f''(0) against White's table (1.2326, four digits) and the far field: f' → 1 and
    /// f − η → −0.6479 (the displacement thickness in units of ℓ, White Table 3-1).
    #[test]
    fn matches_the_tabulated_solution() {
        let h = Hiemenz::new(1.0, 1.0).unwrap();
        assert!((h.wall_curvature() - 1.2326).abs() < 5e-5, "{}", h.wall_curvature());
        let [f, fp, _] = h.profile(ETA_SHOOT);
        assert!((fp - 1.0).abs() < 1e-12, "f'(∞) = {fp}");
        assert!((f - ETA_SHOOT + 0.6479).abs() < 5e-5, "displacement {}", ETA_SHOOT - f);
    }

    /// The sampled field is divergence-free and its gradient is the derivative of u (central
    /// differences with step 10⁻⁵ ℓ: truncation ~10⁻¹⁰, round-off ~10⁻¹¹ relative).
    #[test]
    fn gradient_is_the_derivative_and_trace_free() {
        let h = Hiemenz::new(2.0, 0.01).unwrap();
        let e = 1e-5 * h.length();
        for x in [
            Vec3::new(0.3, 0.02, 0.0),
            Vec3::new(-1.0, 0.2, 1.0),
            Vec3::new(0.7, 1.5, 0.0),
        ] {
            let s = h.sample(&x, 0.0).unwrap();
            assert!(s.grad_u.trace().abs() < 1e-13);
            for j in 0..3 {
                let d = Vec3::ith(j, e);
                let du = (h.sample(&(x + d), 0.0).unwrap().u - h.sample(&(x - d), 0.0).unwrap().u) / (2.0 * e);
                for i in 0..3 {
                    assert!(
                        (du[i] - s.grad_u[(i, j)]).abs() < 1e-6 * (1.0 + s.grad_u.amax()),
                        "{x:?} {i}{j}"
                    );
                }
            }
        }
    }

    #[test]
    fn refuses_bad_parameters_and_points_below_the_wall() {
        assert!(Hiemenz::new(0.0, 1.0).is_err());
        assert!(Hiemenz::new(1.0, f64::NAN).is_err());
        let h = Hiemenz::new(1.0, 1.0).unwrap();
        assert!(h.sample(&Vec3::new(0.0, -1e-9, 0.0), 0.0).is_err());
    }
}

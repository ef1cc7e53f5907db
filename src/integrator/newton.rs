//! Newton's method on 9 unknowns (a flattened 3×3 tensor) with a caller-supplied Jacobian.
//!
//! # Physics
//! None of its own: it solves the implicit shape update of the paper's IMEX step, the residual
//! R(F) = F − Fⁿ − ΔtAⁿ − Δt² vol(B₀)[P̃*(F) − P(F)]Θ⁻¹ = 0 of eqs. 21, 22 (§5), for
//! [`super::imex`]; the paper reports quadratic convergence in about three iterations, which
//! needs the Jacobian of P̃* as well as the material tangent.

use super::control::JacobianReuse;
use crate::error::{ParamError, StepError, positive};
use crate::tensor::{Mat9, Vec9};
use nalgebra::{Const, LU};
use serde::{Deserialize, Serialize};

/// Largest iteration count [`NewtonOptions::new`] accepts: a Newton solve that needs more has
/// failed, and a bound keeps a mistyped setting from running for hours.
pub const MAX_NEWTON_ITERS: u32 = 100;

/// Convergence controls (validated: tol finite and > 0, 1 ≤ max_iters ≤ [`MAX_NEWTON_ITERS`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonOptions {
    tol: f64,
    max_iters: u32,
}

impl Default for NewtonOptions {
    /// |R|∞ ≤ 1e-12, at most 12 iterations.
    fn default() -> Self {
        Self {
            tol: 1e-12,
            max_iters: 12,
        }
    }
}

impl NewtonOptions {
    /// Absolute residual tolerance `tol` (max-norm) and an iteration limit.
    pub fn new(tol: f64, max_iters: u32) -> Result<Self, ParamError> {
        if !(1..=MAX_NEWTON_ITERS).contains(&max_iters) {
            return Err(ParamError::OutOfRange {
                name: "Newton max_iters",
                value: f64::from(max_iters),
                min: 1.0,
                max: f64::from(MAX_NEWTON_ITERS),
            });
        }
        Ok(Self {
            tol: positive("Newton tol", tol)?,
            max_iters,
        })
    }

    /// Residual tolerance.
    pub fn tol(&self) -> f64 {
        self.tol
    }

    /// Iteration limit.
    pub fn max_iters(&self) -> u32 {
        self.max_iters
    }
}

/// Result of a converged solve.
#[derive(Debug, Clone, Copy)]
pub struct NewtonResult {
    /// Solution.
    pub x: Vec9,
    /// Linear solves performed (= Jacobians built).
    pub iters: u32,
    /// Final residual (max-norm).
    pub residual: f64,
}

/// A Newton Jacobian kept from one solve to the next (a chord iteration across steps). Only the
/// matrix is serialised; its LU factors are a cache rebuilt from it, bitwise identically.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct JacobianCache {
    matrix: Option<Mat9>,
    #[serde(skip)]
    lu: Option<LU<f64, Const<9>, Const<9>>>,
    /// |J|∞ of the kept matrix, for the round-off floor (a cache of `matrix`).
    #[serde(skip)]
    norm: Option<f64>,
}

impl JacobianCache {
    fn set(&mut self, j: Mat9) {
        self.lu = Some(j.lu());
        self.norm = Some(j.amax());
        self.matrix = Some(j);
    }

    /// |J|∞ of the kept matrix (0 when there is none).
    fn norm(&mut self) -> f64 {
        if self.norm.is_none() {
            self.norm = self.matrix.as_ref().map(|m| m.amax());
        }
        self.norm.unwrap_or(0.0)
    }

    fn lu(&mut self) -> Option<&LU<f64, Const<9>, Const<9>>> {
        if self.lu.is_none() {
            self.lu = self.matrix.map(|m| m.lu());
        }
        self.lu.as_ref()
    }
}

/// Contraction a kept Jacobian must achieve per iteration (|R_{k+1}| ≤ |R_k|/20); a slower
/// iteration rebuilds the Jacobian at the current iterate. Measured on the paper's oblate
/// (Ca 0.4, ρ* 0.1, Δt = 5e-4, 20 000 steps): ¼ keeps one Jacobian for 1 500 steps but needs
/// 4.1 iterations per step, 1/20 builds 76 Jacobians at 2.8 iterations, 1/100 builds 318 at 2.1;
/// 1/20 was the fastest.
pub const JACOBIAN_REUSE: JacobianReuse = JacobianReuse { contraction: 0.05 };

/// Solve R(x) = 0 from `x0` with a Jacobian kept in `cache` across solves: the kept matrix is
/// used as long as it contracts the residual by 20× per iteration, and rebuilt at the current
/// iterate otherwise (or when there is none); the iterate converges to the same tolerance as
/// with fresh Jacobians, only the number of iterations can differ. `iters` counts linear solves.
///
/// `residual(x)` returns R(x) and its round-off floor: ε times the largest term that R sums
/// (for a stiff law the stress terms reach 1e9 while R is O(1e-12), so an absolute tolerance
/// alone can be below what floating point can resolve), and an update solved with J is exact
/// only to about ε‖J‖∞‖x‖∞ in R. Converged when |R|∞ ≤ max(tol, 64·floor, 8ε‖J‖∞‖x‖∞), or
/// when the update has reached round-off (|δ|∞ ≤ 8ε|x|∞) with |R|∞ ≤ 100× that.
pub fn solve_cached(
    x0: Vec9,
    opts: NewtonOptions,
    cache: &mut JacobianCache,
    mut residual: impl FnMut(&Vec9) -> Result<(Vec9, f64), StepError>,
    mut jacobian: impl FnMut(&Vec9) -> Mat9,
) -> Result<NewtonResult, StepError> {
    let mut x = x0;
    let mut fresh = false;
    let mut previous = f64::INFINITY;
    for iters in 0..=opts.max_iters {
        let (r, floor) = residual(&x)?;
        if r.iter().any(|c| !c.is_finite()) {
            return Err(StepError::NewtonNotConverged {
                iters,
                residual: f64::NAN,
            });
        }
        let res = r.amax();
        // Round-off floor of the iteration itself: a Newton update solved with J is exact only
        // to ~ε‖J‖‖x‖ in the residual (‖J‖ reaches 1e5 for a stiff law at large Δt).
        let conditioning = f64::EPSILON * cache.norm() * x.amax();
        let tol = opts.tol.max(64.0 * floor).max(8.0 * conditioning);
        if res <= tol {
            return Ok(NewtonResult {
                x,
                iters,
                residual: res,
            });
        }
        if iters == opts.max_iters {
            return Err(StepError::NewtonNotConverged { iters, residual: res });
        }
        // Rebuild when there is none or the iteration contracts too slowly: a kept matrix at
        // once, a fresh one only after several slow iterations (the problem is then too
        // nonlinear for the Jacobian of the first iterate).
        let slow = !JACOBIAN_REUSE.keeps(res, previous);
        if cache.matrix.is_none() || (slow && (!fresh || iters >= 3)) {
            cache.set(jacobian(&x));
            fresh = true;
        }
        let failed = StepError::NewtonNotConverged { iters, residual: res };
        let delta = cache.lu().ok_or(failed.clone())?.solve(&(-r)).ok_or(failed)?;
        x += delta;
        previous = res;
        if delta.amax() <= 8.0 * f64::EPSILON * x.amax() && res <= 100.0 * tol {
            return Ok(NewtonResult {
                x,
                iters: iters + 1,
                residual: res,
            });
        }
    }
    unreachable!("the loop returns at iters == max_iters")
}

//! Newton's method on 9 unknowns (a flattened 3×3 tensor) with a caller-supplied Jacobian.

use crate::error::StepError;
use crate::tensor::{Mat9, Vec9};

/// Convergence controls.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NewtonOptions {
    /// Absolute residual tolerance (max-norm).
    pub tol: f64,
    /// Maximum number of iterations.
    pub max_iters: u32,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        Self {
            tol: 1e-12,
            max_iters: 12,
        }
    }
}

/// Result of a converged solve.
#[derive(Debug, Clone, Copy)]
pub struct NewtonResult {
    /// Solution.
    pub x: Vec9,
    /// Linear solves performed.
    pub iters: u32,
    /// Final residual (max-norm).
    pub residual: f64,
}

/// Solve R(x) = 0 from `x0`. `eval(x)` returns the residual and its Jacobian, or an error
/// (e.g. an inverted iterate). Converged when |R|∞ ≤ tol, or when the update has reached
/// round-off (|δ|∞ ≤ 8ε|x|∞) with |R|∞ ≤ 100 tol.
pub fn solve<E>(x0: Vec9, opts: NewtonOptions, mut eval: E) -> Result<NewtonResult, StepError>
where
    E: FnMut(&Vec9, bool) -> Result<(Vec9, Option<Mat9>), StepError>,
{
    let mut x = x0;
    let mut iters = 0;
    loop {
        let want_jac = iters < opts.max_iters;
        let (r, jac) = eval(&x, want_jac)?;
        let residual = r.amax();
        if !residual.is_finite() {
            return Err(StepError::NewtonNotConverged { iters, residual });
        }
        if residual <= opts.tol {
            return Ok(NewtonResult { x, iters, residual });
        }
        let Some(jac) = jac else {
            return Err(StepError::NewtonNotConverged { iters, residual });
        };
        let delta = jac
            .lu()
            .solve(&(-r))
            .ok_or(StepError::NewtonNotConverged { iters, residual })?;
        x += delta;
        iters += 1;
        if delta.amax() <= 8.0 * f64::EPSILON * x.amax() && residual <= 100.0 * opts.tol {
            return Ok(NewtonResult { x, iters, residual });
        }
    }
}

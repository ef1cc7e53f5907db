//! Shampine's L-stable Rosenbrock(-W) pair of order 2(3) (the MATLAB `ode23s` formulas,
//! Shampine & Reichelt 1997), on a fixed-size state with a caller-supplied Jacobian.
//!
//! # Scheme
//! d = 1/(2 + √2), e₃₂ = 6 + √2, W = 1 − h d J:
//! k₁ = W⁻¹F₀, F₁ = f(t + h/2, y + h k₁/2), k₂ = W⁻¹(F₁ − k₁) + k₁, y₁ = y + h k₂,
//! F₂ = f(t + h, y₁), k₃ = W⁻¹[F₂ − e₃₂(k₂ − F₁) − 2(k₁ − F₀)], err = h(k₁ − 2k₂ + k₃)/6.
//! The second-order solution keeps its order for an approximate J (a W-method), which is what
//! lets the callers freeze slowly varying, non-stiff parts of the Jacobian.
//!
//! Hand-written rather than taken from an ODE crate because the callers need per-step control
//! (one accepted step per call with its work counts, stateless across particles, static sizes).

use crate::error::StepError;
use nalgebra::{Const, DimMin, SMatrix, SVector};

const D: f64 = 0.292_893_218_813_452_5; // 1/(2+√2)
const E32: f64 = 7.414_213_562_373_095; // 6+√2

/// Error-control settings of an adaptive integrator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
    /// Smallest step before giving up with [`StepError::StepSizeUnderflow`].
    pub h_min: f64,
}

impl Tolerances {
    /// rtol = atol = `tol`, h_min = 1e-12.
    pub fn uniform(tol: f64) -> Self {
        Self {
            rtol: tol,
            atol: tol,
            h_min: 1e-12,
        }
    }
}

/// Outcome of one accepted adaptive step.
pub struct Accepted<const N: usize> {
    /// New state.
    pub y: SVector<f64, N>,
    /// Step taken.
    pub h: f64,
    /// Proposed next step.
    pub h_next: f64,
    /// f(t + h, y) at the new state (first-same-as-last data for the caller).
    pub f_new: SVector<f64, N>,
    /// Right-hand-side evaluations.
    pub rhs_evals: u32,
    /// Jacobian evaluations.
    pub jac_evals: u32,
    /// Rejected attempts.
    pub rejected: u32,
}

/// Take one accepted step from (t, y) trying `h` first.
///
/// `rhs(t, y)` returns f or an error; an error (e.g. an inverted trial state) rejects the
/// attempt and halves h. `jac(t, y)` returns the (approximate) Jacobian at the step start.
pub fn step<const N: usize>(
    t: f64,
    y: &SVector<f64, N>,
    h: f64,
    tol: Tolerances,
    mut rhs: impl FnMut(f64, &SVector<f64, N>) -> Result<SVector<f64, N>, StepError>,
    jac: impl FnOnce(f64, &SVector<f64, N>) -> Result<SMatrix<f64, N, N>, StepError>,
) -> Result<Accepted<N>, StepError>
where
    Const<N>: DimMin<Const<N>, Output = Const<N>>,
{
    let f0 = rhs(t, y)?;
    let j = jac(t, y)?;
    let mut h = h;
    let mut rhs_evals = 1;
    let mut rejected = 0;
    loop {
        if h < tol.h_min {
            return Err(StepError::StepSizeUnderflow {
                dt: h,
                t,
                error: f64::NAN,
            });
        }
        let attempt = (|| {
            let w = (SMatrix::<f64, N, N>::identity() - j * (h * D)).lu();
            let solve = |b: SVector<f64, N>| {
                w.solve(&b).ok_or(StepError::NonFinite {
                    what: "Rosenbrock matrix",
                    t,
                })
            };
            let k1 = solve(f0)?;
            let f1 = rhs(t + 0.5 * h, &(y + k1 * (0.5 * h)))?;
            let k2 = solve(f1 - k1)? + k1;
            let y1 = y + k2 * h;
            let f2 = rhs(t + h, &y1)?;
            let k3 = solve(f2 - (k2 - f1) * E32 - (k1 - f0) * 2.0)?;
            let err = (k1 - k2 * 2.0 + k3) * (h / 6.0);
            let scaled = err
                .iter()
                .zip(y.iter().zip(y1.iter()))
                .map(|(e, (a, b))| e.abs() / (tol.atol + tol.rtol * a.abs().max(b.abs())))
                .fold(0.0, f64::max);
            Ok::<_, StepError>((y1, f2, scaled))
        })();
        match attempt {
            Ok((y1, f_new, err)) if err <= 1.0 => {
                rhs_evals += 2;
                let grow: f64 = if err == 0.0 {
                    5.0
                } else {
                    (0.8 * err.powf(-1.0 / 3.0)).clamp(0.2, 5.0)
                };
                return Ok(Accepted {
                    y: y1,
                    h,
                    h_next: h * grow,
                    f_new,
                    rhs_evals,
                    jac_evals: 1,
                    rejected,
                });
            }
            Ok((_, _, err)) if err.is_finite() => {
                rhs_evals += 2;
                h *= (0.8 * err.powf(-1.0 / 3.0_f64)).clamp(0.1, 0.5);
            }
            Ok(_) | Err(StepError::Inverted { .. }) | Err(StepError::NonFinite { .. }) => {
                rhs_evals += 2;
                h *= 0.25;
            }
            Err(e) => return Err(e),
        }
        rejected += 1;
    }
}

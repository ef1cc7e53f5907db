//! Typed errors. Each variant carries the numbers that explain the failure.

use crate::tensor::Vec3;
use thiserror::Error;

/// Invalid model parameters (shape, material, fluid, scaling).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ParamError {
    /// A parameter that must be finite and strictly positive is not.
    #[error("parameter `{name}` must be finite and > 0, got {value}")]
    NotPositive {
        /// Parameter name as in the docs.
        name: &'static str,
        /// Offending value.
        value: f64,
    },
    /// A parameter that must be finite is NaN or infinite.
    #[error("parameter `{name}` must be finite, got {value}")]
    NonFinite {
        /// Parameter name.
        name: &'static str,
        /// Offending value.
        value: f64,
    },
    /// A parameter lies outside its allowed interval.
    #[error("parameter `{name}` must lie in [{min}, {max}], got {value}")]
    OutOfRange {
        /// Parameter name.
        name: &'static str,
        /// Offending value.
        value: f64,
        /// Smallest allowed value.
        min: f64,
        /// Largest allowed value.
        max: f64,
    },
    /// The initial axes are not a right-handed orthonormal triad.
    #[error("initial axes are not a rotation: |QᵀQ − 1| = {orthogonality_defect:.3e}, det = {det}")]
    NotARotation {
        /// Max-norm of QᵀQ − 1.
        orthogonality_defect: f64,
        /// Determinant of the axes matrix.
        det: f64,
    },
}

/// Failures of the flow field at a query point.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FlowError {
    /// The point lies outside the flow domain.
    #[error("point {x:?} is outside the flow domain")]
    OutsideDomain {
        /// Query point.
        x: [f64; 3],
    },
    /// The query itself is not finite.
    #[error("non-finite query point {x:?} at t = {t}")]
    NonFiniteQuery {
        /// Query point.
        x: [f64; 3],
        /// Query time.
        t: f64,
    },
}

impl FlowError {
    /// Outside-domain error for a point.
    pub fn outside(x: &Vec3) -> Self {
        FlowError::OutsideDomain { x: [x[0], x[1], x[2]] }
    }
}

/// Failures of one time step of a particle.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum StepError {
    /// Newton's method did not reach the tolerance.
    #[error("Newton did not converge: {iters} iterations, residual {residual:.3e}")]
    NewtonNotConverged {
        /// Iterations performed.
        iters: u32,
        /// Final residual (max-norm).
        residual: f64,
    },
    /// The deformation gradient lost orientation (det F ≤ 0): the particle inverted.
    #[error("particle inverted: det F = {det_f:.6e} at t = {t}")]
    Inverted {
        /// det F of the offending iterate.
        det_f: f64,
        /// Time at which it happened.
        t: f64,
    },
    /// A state or input quantity is NaN or infinite.
    #[error("non-finite {what} at t = {t}")]
    NonFinite {
        /// Which quantity.
        what: &'static str,
        /// Time.
        t: f64,
    },
    /// The time step exceeds the stability limit of an explicit part of the scheme.
    #[error("time step {dt:.3e} exceeds the stability limit {limit:.3e} ({reason})")]
    Unstable {
        /// Requested step.
        dt: f64,
        /// Estimated stability limit.
        limit: f64,
        /// Which term limits the step.
        reason: &'static str,
    },
    /// The eigenvalues behind the explicit stability limit could not be computed (the bounded
    /// Schur iteration did not converge), so the step cannot be certified stable.
    #[error("stability limit unknown at t = {t}: the 9×9 eigenproblem did not converge")]
    StabilityUnknown {
        /// Time.
        t: f64,
    },
    /// An adaptive integrator shrank the step below its floor.
    #[error("step size underflow: dt = {dt:.3e} at t = {t} (error estimate {error:.3e})")]
    StepSizeUnderflow {
        /// Step size reached.
        dt: f64,
        /// Time.
        t: f64,
        /// Last scaled error estimate.
        error: f64,
    },
    /// A run used up its step or wall-time budget.
    #[error("budget exceeded after {steps} steps ({wall_s:.1} s) at t = {t}")]
    BudgetExceeded {
        /// Accepted steps taken.
        steps: u64,
        /// Time reached.
        t: f64,
        /// Wall-clock seconds used.
        wall_s: f64,
    },
    /// A step would not advance time in floating point (t + dt == t).
    #[error("step dt = {dt:.3e} does not advance t = {t}")]
    NoProgress {
        /// Time.
        t: f64,
        /// Step that vanished against t.
        dt: f64,
    },
    /// An event's zero crossing was not located on the dense output.
    #[error("event not located: gap {gap:.3e} at t = {t}")]
    EventNotLocated {
        /// Best estimate of the event time.
        t: f64,
        /// Gap there.
        gap: f64,
    },
    /// The flow field could not be sampled.
    #[error(transparent)]
    Flow(#[from] FlowError),
    /// Invalid parameters were passed to the step.
    #[error(transparent)]
    Param(#[from] ParamError),
}

/// Check that `value` is finite and strictly positive.
pub fn positive(name: &'static str, value: f64) -> Result<f64, ParamError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(ParamError::NotPositive { name, value })
    }
}

/// Check that `value` is finite.
pub fn finite(name: &'static str, value: f64) -> Result<f64, ParamError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ParamError::NonFinite { name, value })
    }
}

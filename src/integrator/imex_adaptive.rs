//! The paper's IMEX step with step-size control (an option; [`super::ImexPaper`] stays the
//! faithful fixed-step reference).
//!
//! # Scheme
//! Each attempt is one paper step of size h, capped at 0.9× the explicit viscous stability
//! limit ([`super::imex::stability_limit`]). A step is rejected when Newton fails or the
//! particle inverts, or when the local error estimate of the first-order scheme,
//! $e = \tfrac12 \lVert F^{n+1} - F^n - h A^n\rVert_\infty = \tfrac h2 \lVert A^{n+1} - A^n\rVert_\infty$
//! (the difference to the explicit predictor, ≈ ½h²|Ȧ|), exceeds tol·(1 + |Fⁿ|∞).
//! The next step is h·clamp(0.9 (tol/e)^{1/2}, 0.2, 2).

use super::{ImexPaper, StepInfo, TimeIntegrator, imex::stability_limit};
use crate::error::StepError;
use crate::flow::FlowField;
use crate::hydro::DragModel;
use crate::material::Hyperelastic;
use crate::particle::{Particle, State};

/// Adaptive IMEX integrator.
#[derive(Debug, Clone, Copy)]
pub struct ImexAdaptive {
    /// Local error tolerance (relative to 1 + |F|).
    pub tol: f64,
    /// Smallest step before giving up.
    pub h_min: f64,
}

impl ImexAdaptive {
    /// Adaptive IMEX with local tolerance `tol`.
    pub fn new(tol: f64) -> Self {
        Self { tol, h_min: 1e-14 }
    }
}

impl TimeIntegrator for ImexAdaptive {
    fn name(&self) -> &'static str {
        "imex_adaptive"
    }

    fn step<M: Hyperelastic, D: DragModel, F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        state: &State,
        flow: &F,
        dt: f64,
    ) -> Result<(State, StepInfo), StepError> {
        crate::error::positive("dt", dt)?;
        crate::error::positive("tol", self.tol)?;
        state.validate()?;
        let inner = ImexPaper {
            check_stability: false,
            ..ImexPaper::default()
        };
        let limit = 0.9 * stability_limit(particle, state);
        let mut h = dt.min(limit);
        let mut rejected = 0;
        let mut work = StepInfo::default();
        loop {
            if h < self.h_min {
                return Err(StepError::StepSizeUnderflow {
                    dt: h,
                    t: state.t,
                    error: f64::NAN,
                });
            }
            match inner.step(particle, state, flow, h) {
                Ok((next, info)) => {
                    work.rhs_evals += info.rhs_evals;
                    work.jac_evals += info.jac_evals;
                    work.newton_iters += info.newton_iters;
                    let e = 0.5 * (next.f - state.f - state.a * h).amax();
                    let err = e / (self.tol * (1.0 + state.f.amax()));
                    if err <= 1.0 {
                        let grow = if err == 0.0 {
                            2.0
                        } else {
                            (0.9 / err.sqrt()).clamp(0.2, 2.0)
                        };
                        let info = StepInfo {
                            dt: h,
                            dt_next: h * grow,
                            residual: info.residual,
                            rejected,
                            ..work
                        };
                        return Ok((next, info));
                    }
                    h *= (0.9 / err.sqrt()).clamp(0.1, 0.5);
                }
                Err(
                    StepError::NewtonNotConverged { .. } | StepError::Inverted { .. } | StepError::NonFinite { .. },
                ) => {
                    h *= 0.25;
                }
                Err(e) => return Err(e),
            }
            rejected += 1;
        }
    }
}

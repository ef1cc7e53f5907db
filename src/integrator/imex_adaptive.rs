//! The paper's IMEX step with step-size control (an option; [`super::ImexPaper`] stays the
//! faithful fixed-step reference).
//!
//! # Physics (paper eqs. 17–22)
//! The same equations and the same step as [`super::imex`] (eqs. 17, 18 discretised by
//! eqs. 19–22); only the step size changes, so the model and its stability conditions
//! ([`crate::theory::stability`]) are those of the paper.
//!
//! # Scheme
//! Each attempt is one paper step of size h, capped at 0.9× the explicit viscous stability
//! limit ([`super::imex::stability_limit`], cached as in [`super::imex::StabilityGuard`]).
//! A step is rejected when Newton fails or the particle inverts, or when the local error
//! estimate of the first-order scheme,
//! $e = \tfrac12 \lVert F^{n+1} - F^n - h A^n\rVert_\infty = \tfrac h2 \lVert A^{n+1} - A^n\rVert_\infty$
//! (the difference to the explicit predictor, ≈ ½h²|Ȧ|), exceeds tol·(1 + |Fⁿ|∞).
//! The next step is h·clamp(0.9 (tol/e)^{1/2}, 0.2, 2) ([`CONTROL`], the elementary controller
//! of [`super::control`]).
//!
//! # Volume-mode floor
//! With the literal eq. 12 traction ([`VolumetricTraction::Paper`]) the model's volume mode is
//! anti-damped, and the scheme is stable only above the floor Δt > a/ω²
//! ([`super::imex::volume_mode_floor`]): the backward-Euler damping of the stiff bulk term
//! then out-weighs the anti-damping. A tolerance tight enough to resolve the mode would
//! integrate the growth faithfully (J − 1 from 3·10⁻⁵ to 1.6 in a cavity run at tol 10⁻⁷). So
//! the controller never proposes a step below the floor, and when the error estimate demands
//! one it stops with [`StepError::VolumeModeUnresolvable`] instead of integrating an unphysical
//! dilation. Steps the caller shortens (to land on an output time) are taken as asked: one
//! short step grows the mode by at most a factor 1 + aΔt.
//!
//! [`VolumetricTraction::Paper`]: crate::hydro::VolumetricTraction::Paper

use super::control::{ErrorOrder, StepControl, Tolerances};
use super::dense::{Dense, Knot};
use super::imex::ImexMemory;
use super::imex::stability::{StabilityGuard, StepWindow};
use super::{ImexPaper, Step, StepInfo, TimeIntegrator};
use crate::error::{ParamError, StepError, positive};
use crate::flow::FlowField;
use crate::hydro::DragModel;
use crate::material::Response;
use crate::particle::{Model, Particle, State};

/// The step controller (err ∝ h²): h·clamp(0.9 err^{−1/2}, 0.2, 2) after an accepted step,
/// h·clamp(0.9 err^{−1/2}, 0.1, 0.5) after a rejected one, h/4 after a failed attempt, and 60
/// rejected attempts (each at least halves h: 18 decades).
pub const CONTROL: StepControl = StepControl {
    safety: 0.9,
    accept: (0.2, 2.0),
    reject: (0.1, 0.5),
    failure_shrink: 0.25,
    max_rejections: 60,
};

/// Smallest step of [`ImexAdaptive`].
const H_MIN: f64 = 1e-14;

/// Adaptive IMEX integrator.
#[derive(Debug, Clone, Copy)]
pub struct ImexAdaptive {
    /// rtol = atol = tol, applied as tol·(1 + |Fⁿ|∞) (module docs): the error test measures F
    /// alone, so the steps do not depend on the position (nor on the origin).
    tol: Tolerances,
}

impl ImexAdaptive {
    /// Adaptive IMEX with local tolerance `tol` (finite, > 0) and h_min = 1e-14.
    pub fn new(tol: f64) -> Result<Self, ParamError> {
        let tol = positive("imex_adaptive tol", tol)?;
        Ok(Self {
            tol: Tolerances::new(tol, tol, H_MIN)?,
        })
    }

    /// Local tolerance.
    pub fn tol(&self) -> f64 {
        self.tol.rtol()
    }
}

impl TimeIntegrator for ImexAdaptive {
    type Memory = ImexMemory;

    fn name(&self) -> &'static str {
        "imex_adaptive"
    }

    fn step_with<M: Response, D: DragModel, F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        state: &State,
        memory: &mut ImexMemory,
        flow: &F,
        dt: f64,
    ) -> Result<Step, StepError> {
        super::check_step(state, dt)?;
        let inner = ImexPaper::unguarded();
        let model = Model::new(particle, flow);
        let geo = memory.geometry(&model, &state.f, state.t)?;
        let window = memory
            .window(StabilityGuard::default(), particle, &state.f, &geo, state.t)?
            .unwrap_or(StepWindow::UNBOUNDED);
        let mut h = dt.min(window.max);
        let mut newton_iters = 0;
        for rejected in 0..=CONTROL.max_rejections {
            if h < self.tol.h_min() || state.t + h <= state.t {
                break;
            }
            match inner.unguarded_step(&model, state, &geo, memory, h) {
                Ok((next, sol)) => {
                    newton_iters += sol.iters;
                    let e = 0.5 * (next.f - state.f - state.a * h).amax();
                    let err = e / (self.tol.rtol() * (1.0 + state.f.amax()));
                    if err <= 1.0 {
                        let grow = CONTROL.grow(ErrorOrder::Two, err);
                        // Never propose a step below the volume-mode floor: a step there that
                        // meets the tolerance is accepted, one that does not is refused below.
                        let next_h = (h * grow).max(window.min.min(window.max));
                        let info = StepInfo {
                            newton_iters,
                            residual: sol.residual,
                            rejected,
                            ..StepInfo::from_work(model.work(), h, next_h)
                        };
                        return Ok(Step {
                            dense: Dense::new(state.t, h, Knot::of_state(state), Knot::of_state(&next)),
                            end: memory.end(&next.f),
                            state: next,
                            info,
                        });
                    }
                    // A NaN error is not ≤ 1 and lands here: shrink as for a failure.
                    let shrunk = h * CONTROL.shrink(ErrorOrder::Two, err);
                    if shrunk < window.min && h >= window.min {
                        return Err(StepError::VolumeModeUnresolvable {
                            dt: shrunk,
                            floor: window.min,
                            t: state.t,
                        });
                    }
                    h = shrunk;
                }
                Err(
                    StepError::NewtonNotConverged { .. } | StepError::Inverted { .. } | StepError::NonFinite { .. },
                ) => {
                    h *= CONTROL.failure_shrink;
                }
                Err(e) => return Err(e),
            }
        }
        Err(StepError::StepSizeUnderflow {
            dt: h,
            t: state.t,
            error: f64::NAN,
        })
    }
}

// Selectable by name: `[integrator] type = "imex_adaptive"`, `tol` (inertial barycentre only).
inventory::submit! {
    super::IntegratorRegistration {
        name: "imex_adaptive",
        aliases: &[],
        build: |p| {
            p.only(&["tol", "overdamped"])?;
            super::registry::inertial_only(p)?;
            Ok(super::SceneIntegrator::new(ImexAdaptive::new(p.positive("tol")?)?))
        },
    }
}

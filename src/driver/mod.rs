//! The driver owns the time loop: it calls an integrator step by step with the particle's step
//! memory, honours the step sizes the integrator proposes, lands exactly on requested output
//! times, locates terminal events on each step's dense output, enforces a step and wall-time
//! budget, and accumulates the work statistics used in work-precision studies.
//!
//! # Arguments
//! Every entry point takes the [`Problem`] (integrator, particle, flow) and the start state
//! first, then what to integrate to (a [`Plan`] and events, or a first step and output times),
//! and the [`Observers`] last: [`integrate`], [`resume`] (from a [`RunEnd`]), [`run`],
//! [`advance`], [`until_event`].
//!
//! # Events
//! An [`Event`] is a signed gap g(state), positive while nothing happens (a wall gap, the
//! distance to an outlet plane). When an accepted step ends with g ≤ 0 the driver solves
//! g(state(t)) = 0 on the step's [`Dense`] interpolant by the Illinois variant of regula falsi
//! until |g| ≤ 10⁻⁹ · [`Event::scale`], and stops there. An event may cap the step
//! ([`Event::max_step`]) so that a tumbling tip cannot touch and leave a wall within one step,
//! which no end-point test can see.
//!
//! # Accepted steps
//! Every accepted step is shown to `on_step` as an [`AcceptedStep`] ([`accepted`]): the step,
//! and its end state's principal frame and flow sample, carried from the scheme where it
//! computed them and otherwise computed once, on first demand, for every reader.
//!
//! # Held planes (2-D cases)
//! A [`Plan::with_hold`] keeps the barycentre in the plane normal to one axis, as OpenFOAM's
//! tracker keeps particles in a 2-D case's slab (it zeroes the displacement along the `empty`
//! direction): the start's velocity along the axis is set to zero, and every accepted step's
//! end state (and an event's located state) gets the start's coordinate and zero velocity along
//! it. The axis's force is taken up by the slab, as a constraint force; the shape's F and A are
//! not touched, so a shape tilted out of the plane keeps turning and stretching in 3-D (its
//! Jeffery orbit) while its barycentre stays in the plane, moved by the in-plane part of its
//! drag. Within a step the trial stages and the dense output may leave the plane by what the
//! out-of-plane force moves the barycentre in one step; the next accepted state is back on it.
//!
//! # Patches the particle passes through
//! Where a step ends outside the domain beyond a patch the particle passes through (a cyclic
//! patch, a symmetry plane, a wedge: [`FlowField::image`]), the step is cut where the
//! barycentre crossed the patch's plane, located on the dense output as events are (to 10⁻⁹ of
//! the step's travel), and the particle continues from the image of that state; the integrator
//! is told ([`Stepper::particle_mapped`]). The map is a symmetry of the flow, so the image
//! moves on as the particle would have: across a cyclic pair it is the same particle one
//! period on; at a symmetry plane it is the mirrored partner of the full domain, which the
//! half domain shows in its place (where a body force is not mirror-symmetric, gravity normal
//! to the plane, the plane reflects the particle as a frictionless, elastic wall would). Events are
//! located on the step up to the crossing; an event whose gap is already closed at the image
//! (a wall that continues across a cyclic pair) fires there.
//!
//! # Failures
//! A run that fails keeps its record: [`integrate`] returns a [`RunFailure`] with the error, the
//! state after the last accepted step and the [`RunStats`] of the steps taken up to the failure.
//!
//! [`Dense`]: crate::integrator::Dense

use crate::error::{FlowError, ParamError, StepError};
use crate::flow::{Crossing, FlowField};
use crate::hydro::DragModel;
use crate::integrator::{Dense, StepInfo, Stepper};
use crate::material::Response;
use crate::particle::{Particle, State};
use serde::{Deserialize, Serialize};
use std::time::{Duration, Instant};

pub mod accepted;

pub use accepted::{AcceptedStep, StepContext};

/// Accumulated work of a run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct RunStats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected step attempts.
    pub rejected: u64,
    /// Model evaluations.
    pub rhs_evals: u64,
    /// Jacobian evaluations.
    pub jac_evals: u64,
    /// Newton iterations, summed.
    pub newton_iters: u64,
    /// Largest Newton iteration count of any step.
    pub max_newton_iters: u32,
}

impl RunStats {
    /// Add one accepted step: its count, its rejected attempts and its work.
    pub fn record(&mut self, info: &StepInfo) {
        self.steps += 1;
        self.rejected += u64::from(info.rejected);
        self.rhs_evals += u64::from(info.rhs_evals);
        self.jac_evals += u64::from(info.jac_evals);
        self.newton_iters += u64::from(info.newton_iters);
        self.max_newton_iters = self.max_newton_iters.max(info.newton_iters);
    }
}

/// Limits on one run; exceeding one is a [`StepError::BudgetExceeded`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Budget {
    /// Largest number of accepted steps (default 10⁹: hours of work for one particle).
    pub max_steps: u64,
    /// Wall-clock limit, if any.
    pub wall_time: Option<Duration>,
}

impl Default for Budget {
    fn default() -> Self {
        Self {
            max_steps: 1_000_000_000,
            wall_time: None,
        }
    }
}

/// A terminal event: fires when the signed gap g(state) crosses from > 0 to ≤ 0.
pub trait Event {
    /// Signed gap, positive before the event.
    fn gap(&self, state: &State) -> f64;

    /// Scale of g: the event is located to |g| ≤ 10⁻⁹ · scale (default 1).
    fn scale(&self, _state: &State) -> f64 {
        1.0
    }

    /// Largest step the driver may take from `state` (default unbounded).
    fn max_step(&self, _state: &State) -> f64 {
        f64::INFINITY
    }
}

/// Relative tolerance of event location on the dense output.
pub const EVENT_TOL: f64 = 1e-9;
/// Iterations allowed to locate one event (Illinois converges superlinearly; 200 is a bound
/// that only a discontinuous gap function can reach).
const MAX_EVENT_ITERS: u32 = 200;

/// Why [`integrate`] returned.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Stop {
    /// The end time was reached.
    EndTime,
    /// Event number `index` (position in the events slice) fired.
    Event {
        /// Which event.
        index: usize,
    },
}

/// The end of a run.
#[derive(Debug, Clone)]
pub struct RunEnd {
    /// Final state (at t_end, or at the located event).
    pub state: State,
    /// Work statistics.
    pub stats: RunStats,
    /// Why the run ended.
    pub stop: Stop,
    /// The step the driver would have tried next: its proposal, not shortened to land on the
    /// end time. [`resume`] starts with it.
    pub dt_next: f64,
}

/// A run that stopped on an error: the error and what the run had done until then.
///
/// Its message is the error's followed by the accepted steps and the time reached; `?` turns
/// it into the bare [`StepError`] where only the cause matters.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{error} (after {} accepted steps, at t = {})", .stats.steps, .state.t)]
pub struct RunFailure {
    /// Why the run stopped.
    #[source]
    pub error: StepError,
    /// State after the last accepted step (the start state when no step was accepted).
    pub state: State,
    /// Work of the accepted steps and of their rejected attempts; the failed step's own work
    /// is not included (an integrator that fails reports no [`StepInfo`]).
    pub stats: RunStats,
}

impl From<RunFailure> for StepError {
    fn from(failure: RunFailure) -> Self {
        failure.error
    }
}

/// What to integrate to and how: end time, output times, first step, step cap and budget.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    t_end: f64,
    outputs: Vec<f64>,
    dt0: f64,
    dt_max: f64,
    budget: Budget,
    hold: Option<usize>,
}

impl Plan {
    /// Integrate to `t_end` starting with step `dt0` (fixed-step integrators keep it).
    /// Both must be finite, dt0 > 0.
    pub fn new(t_end: f64, dt0: f64) -> Result<Self, ParamError> {
        Ok(Self {
            t_end: crate::error::finite("t_end", t_end)?,
            outputs: Vec::new(),
            dt0: crate::error::positive("dt", dt0)?,
            dt_max: f64::INFINITY,
            budget: Budget::default(),
            hold: None,
        })
    }

    /// Keep the barycentre in the plane through its start normal to `axis` (0, 1 or 2): its
    /// coordinate and velocity along `axis` held (module docs, *Held planes*).
    pub fn with_hold(mut self, axis: usize) -> Result<Self, ParamError> {
        if axis > 2 {
            return Err(ParamError::OutOfRange {
                name: "held axis",
                value: axis as f64,
                min: 0.0,
                max: 2.0,
            });
        }
        self.hold = Some(axis);
        Ok(self)
    }

    /// The axis along which the barycentre is held, if any ([`Plan::with_hold`]).
    pub fn hold(&self) -> Option<usize> {
        self.hold
    }

    /// Stop exactly at these times (ascending, finite, ≤ t_end) and observe the state there.
    pub fn with_outputs(mut self, outputs: &[f64]) -> Result<Self, ParamError> {
        let mut last = f64::NEG_INFINITY;
        for &t in outputs {
            if !(t.is_finite() && t > last && t <= self.t_end) {
                return Err(ParamError::OutOfRange {
                    name: "output time (ascending, ≤ t_end)",
                    value: t,
                    min: last,
                    max: self.t_end,
                });
            }
            last = t;
        }
        self.outputs = outputs.to_vec();
        Ok(self)
    }

    /// Never step further than `dt_max` (> 0).
    pub fn with_dt_max(mut self, dt_max: f64) -> Result<Self, ParamError> {
        self.dt_max = crate::error::positive("dt_max", dt_max)?;
        Ok(self)
    }

    /// Limit the run.
    pub fn with_budget(mut self, budget: Budget) -> Self {
        self.budget = budget;
        self
    }

    /// The run's limits.
    pub fn budget(&self) -> Budget {
        self.budget
    }

    /// End time.
    pub fn t_end(&self) -> f64 {
        self.t_end
    }

    /// This plan ending at `t_end` if that is earlier: the output times up to it kept, the
    /// rest dropped (a segment of a run that [`resume`] continues).
    pub fn until(&self, t_end: f64) -> Self {
        let t_end = self.t_end.min(t_end);
        Self {
            t_end,
            outputs: self.outputs.iter().copied().filter(|&t| t <= t_end).collect(),
            ..self.clone()
        }
    }
}

/// Consecutive retries of a step whose trial state left the flow's domain, each with the step
/// shortened by [`OUTSIDE_SHRINK`]: 30 shrink it by 4³⁰ ≈ 10¹⁸, below any step that could still
/// reach the boundary from inside.
pub const MAX_OUTSIDE_RETRIES: u32 = 30;
/// Factor of the step after a trial state left the flow's domain.
pub const OUTSIDE_SHRINK: f64 = 0.25;

/// Times closer than this (relative to max(|t|, 1)) count as equal when landing on an output.
const LANDING_TOL: f64 = 1e-12;

/// The problem a run solves: the time integrator that takes its steps (the paper's IMEX
/// scheme, §5, or any other [`Stepper`]), the pseudo-rigid particle it moves (material law
/// W(F), drag K̂: [`Particle`]) and the carrier flow that supplies u and l_f = ∇u at the
/// barycentre x_c (Fig. 1, [`FlowField`]).
///
/// Every entry point of the driver takes it first, then the start state: [`integrate`],
/// [`resume`], [`run`], [`advance`], [`until_event`]. It only borrows, so it is `Copy`.
pub struct Problem<'a, I, M, D, F: ?Sized> {
    /// The time integrator.
    pub integrator: &'a I,
    /// The particle.
    pub particle: &'a Particle<M, D>,
    /// The carrier flow.
    pub flow: &'a F,
}

impl<'a, I, M, D, F: ?Sized> Problem<'a, I, M, D, F> {
    /// `particle` in `flow`, stepped by `integrator`.
    pub fn new(integrator: &'a I, particle: &'a Particle<M, D>, flow: &'a F) -> Self {
        Self {
            integrator,
            particle,
            flow,
        }
    }
}

impl<I, M, D, F: ?Sized> Clone for Problem<'_, I, M, D, F> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<I, M, D, F: ?Sized> Copy for Problem<'_, I, M, D, F> {}

/// What a run shows its caller: `observe` sees the state x_c, F, … at the start, at every
/// output time and at a located event ([`run`] shows the start only if it is an output time,
/// [`resume`] not again); `on_step` every accepted step, with its end state's principal frame
/// (r_a, Q) and flow sample (u, ∇u) ([`AcceptedStep`]).
///
/// [`Observers::none`] (the [`Default`]) shows nothing; `with_observe` and `with_on_step` add
/// one observer each.
pub struct Observers<O, S> {
    /// Called with the state at the start, at output times and at the event.
    pub observe: O,
    /// Called after every accepted step.
    pub on_step: S,
}

/// The observers that observe nothing ([`Observers::none`]).
pub type NoObservers = Observers<fn(&State), fn(&AcceptedStep<'_>)>;

impl NoObservers {
    /// No observer.
    pub fn none() -> Self {
        Self {
            observe: |_| {},
            on_step: |_| {},
        }
    }
}

impl Default for NoObservers {
    fn default() -> Self {
        Self::none()
    }
}

impl<O: FnMut(&State), S: FnMut(&AcceptedStep<'_>)> Observers<O, S> {
    /// `observe` at the start, the output times and the event, `on_step` after every step.
    pub fn new(observe: O, on_step: S) -> Self {
        Self { observe, on_step }
    }

    /// These observers with `observe` in place of theirs.
    pub fn with_observe<O2: FnMut(&State)>(self, observe: O2) -> Observers<O2, S> {
        Observers {
            observe,
            on_step: self.on_step,
        }
    }

    /// These observers with `on_step` in place of theirs.
    pub fn with_on_step<S2: FnMut(&AcceptedStep<'_>)>(self, on_step: S2) -> Observers<O, S2> {
        Observers {
            observe: self.observe,
            on_step,
        }
    }
}

/// Advance `state` with `memory` as `plan` says, stopping at the first event that fires.
/// `observers.observe` sees the start, every output time and the event state;
/// `observers.on_step` every accepted step, with its end state's frame and flow sample
/// ([`AcceptedStep`]). Refuses a start state already past t_end.
///
/// # Errors
/// A [`RunFailure`]: the [`StepError`] that stopped the run, with the state and the
/// [`RunStats`] of the accepted steps before it.
// A failure carries a State like the RunEnd does: the Err variant is no larger than Ok's.
#[allow(clippy::result_large_err)]
pub fn integrate<I, M, D, F, O, S>(
    problem: Problem<'_, I, M, D, F>,
    state: State,
    memory: &mut I::Memory,
    plan: &Plan,
    events: &[&dyn Event],
    observers: Observers<O, S>,
) -> Result<RunEnd, RunFailure>
where
    I: Stepper<M, D>,
    M: Response,
    D: DragModel,
    F: FlowField + ?Sized,
    O: FnMut(&State),
    S: FnMut(&AcceptedStep<'_>),
{
    let fresh = Progress {
        stats: RunStats::default(),
        last: state,
    };
    run_from(problem, memory, plan, events, observers, fresh, None)
}

/// Continue a run that stopped at its plan's end time (`from`, a [`Stop::EndTime`] outcome) as
/// `plan` says (a later end time: [`Plan::until`]), as if it had not stopped: from its state,
/// with its step proposal ([`RunEnd::dt_next`], not `plan`'s first step) and `memory`, its
/// statistics counted on (the step budget is the whole run's) and its last state not observed
/// again. The run differs from an uninterrupted one only in the step that landed on the
/// stop's time.
///
/// # Errors
/// As [`integrate`].
#[allow(clippy::result_large_err)]
pub fn resume<I, M, D, F, O, S>(
    problem: Problem<'_, I, M, D, F>,
    from: &RunEnd,
    memory: &mut I::Memory,
    plan: &Plan,
    events: &[&dyn Event],
    observers: Observers<O, S>,
) -> Result<RunEnd, RunFailure>
where
    I: Stepper<M, D>,
    M: Response,
    D: DragModel,
    F: FlowField + ?Sized,
    O: FnMut(&State),
    S: FnMut(&AcceptedStep<'_>),
{
    let stopped = Progress {
        stats: from.stats,
        last: from.state,
    };
    run_from(problem, memory, plan, events, observers, stopped, Some(from.dt_next))
}

/// What a run has done so far, kept outside it so that a failure still reports it: the
/// statistics of its accepted steps and the state after the last of them (the start state
/// before the first).
struct Progress {
    stats: RunStats,
    last: State,
}

/// The run [`integrate`] and [`resume`] both are: [`integrate_recorded`] from `progress`, a
/// failure reported with the state and statistics it had reached.
#[allow(clippy::result_large_err)]
fn run_from<I, M, D, F, O, S>(
    problem: Problem<'_, I, M, D, F>,
    memory: &mut I::Memory,
    plan: &Plan,
    events: &[&dyn Event],
    observers: Observers<O, S>,
    mut progress: Progress,
    resumed: Option<f64>,
) -> Result<RunEnd, RunFailure>
where
    I: Stepper<M, D>,
    M: Response,
    D: DragModel,
    F: FlowField + ?Sized,
    O: FnMut(&State),
    S: FnMut(&AcceptedStep<'_>),
{
    integrate_recorded(problem, memory, plan, events, observers, &mut progress, resumed).map_err(|error| RunFailure {
        error,
        state: progress.last,
        stats: progress.stats,
    })
}

/// [`integrate`] from `progress.last`, accumulating into `progress`; `resumed`: the first step
/// of a [`resume`]d run, whose start was the last run's end (and observed then).
fn integrate_recorded<I, M, D, F, O, S>(
    problem: Problem<'_, I, M, D, F>,
    memory: &mut I::Memory,
    plan: &Plan,
    events: &[&dyn Event],
    observers: Observers<O, S>,
    progress: &mut Progress,
    resumed: Option<f64>,
) -> Result<RunEnd, StepError>
where
    I: Stepper<M, D>,
    M: Response,
    D: DragModel,
    F: FlowField + ?Sized,
    O: FnMut(&State),
    S: FnMut(&AcceptedStep<'_>),
{
    let Problem {
        integrator,
        particle,
        flow,
    } = problem;
    let Observers {
        mut observe,
        mut on_step,
    } = observers;
    let Progress { stats, last } = progress;
    let state = *last;
    state.validate()?;
    if state.t > plan.t_end {
        return Err(ParamError::OutOfRange {
            name: "t_end (must not lie before the start time)",
            value: plan.t_end,
            min: state.t,
            max: f64::INFINITY,
        }
        .into());
    }
    let started = Instant::now();
    let mut s = state;
    // The held plane: the start's coordinate along the axis (a resumed run's start is on it).
    let hold = plan.hold.map(|k| (k, s.x[k]));
    let held = |state: &mut State| {
        if let Some((k, at)) = hold {
            state.x[k] = at;
            state.v[k] = 0.0;
        }
    };
    held(&mut s);
    let mut h = resumed.unwrap_or(plan.dt0).min(plan.dt_max);
    let mut outside_retries = 0;
    if resumed.is_none() {
        observe(&s);
    }
    for (index, e) in events.iter().enumerate() {
        if e.gap(&s) <= 0.0 {
            return Ok(RunEnd {
                state: s,
                stats: *stats,
                stop: Stop::Event { index },
                dt_next: h,
            });
        }
    }
    let context = StepContext::new(particle, flow);
    let t_start = s.t;
    let mut outputs = plan.outputs.iter().copied().filter(|&t| t > t_start).peekable();
    loop {
        let target = outputs.peek().copied().unwrap_or(plan.t_end);
        let remaining = target - s.t;
        if remaining <= LANDING_TOL * target.abs().max(1.0) {
            s.t = target;
            if outputs.next().is_some() {
                observe(&s);
                continue;
            }
            return Ok(RunEnd {
                state: s,
                stats: *stats,
                stop: Stop::EndTime,
                dt_next: h,
            });
        }
        if stats.steps >= plan.budget.max_steps {
            return Err(StepError::BudgetExceeded {
                steps: stats.steps,
                t: s.t,
                wall_s: started.elapsed().as_secs_f64(),
            });
        }
        if let Some(limit) = plan.budget.wall_time
            && started.elapsed() > limit
        {
            return Err(StepError::BudgetExceeded {
                steps: stats.steps,
                t: s.t,
                wall_s: started.elapsed().as_secs_f64(),
            });
        }
        let cap = events.iter().map(|e| e.max_step(&s)).fold(plan.dt_max, f64::min);
        let cap = if cap.is_nan() { plan.dt_max } else { cap };
        // Land on the target; never leave a sliver step (< 1 % of h) before it.
        let want = h.min(cap);
        let clamped = want >= 0.99 * remaining;
        let try_h = if clamped { remaining } else { want };
        if s.t + try_h <= s.t || try_h.is_nan() {
            return Err(StepError::NoProgress { t: s.t, dt: try_h });
        }
        let mut step = match integrator.step_particle(particle, &s, memory, flow, try_h) {
            Ok(step) => step,
            // A trial state beyond the domain: the step overshot a boundary the events have not
            // seen yet (a point particle crossing an exit, a stage past the wall). Retry shorter,
            // so the event can fire inside; a particle that really left fails after the retries.
            Err(StepError::Flow(FlowError::OutsideMesh { .. } | FlowError::OutsideDomain { .. }))
                if outside_retries < MAX_OUTSIDE_RETRIES =>
            {
                outside_retries += 1;
                h = try_h * OUTSIDE_SHRINK;
                continue;
            }
            Err(e) => return Err(e),
        };
        outside_retries = 0;
        held(&mut step.state);
        stats.record(&step.info);
        *last = step.state;
        // A step shortened to hit a target or a cap says nothing about the next step size.
        h = if clamped || want < h {
            h.max(step.info.dt_next)
        } else {
            step.info.dt_next
        };
        on_step(&AcceptedStep::new(&step, &context));
        // Past a patch the particle passes through: the step ends where the barycentre crossed
        // its plane, and the particle continues from the image of that state.
        let crossing = flow.image(&step.state.x, step.state.t);
        let mut end = match &crossing {
            Some(c) => crossed(c, &s, &step.dense, &step.state)?,
            None => step.state,
        };
        held(&mut end);
        if let Some((index, mut at)) = first_event(events, &s, &step.dense, &end)? {
            held(&mut at);
            observe(&at);
            return Ok(RunEnd {
                state: at,
                stats: *stats,
                stop: Stop::Event { index },
                dt_next: h,
            });
        }
        s = end;
        if let Some(c) = crossing {
            s = end.mapped(&c.map, &particle.shape().axes());
            held(&mut s);
            *last = s;
            integrator.particle_mapped(memory);
            // A wall that continues across a cyclic pair may already be touched there.
            if let Some(index) = events.iter().position(|e| e.gap(&s) <= 0.0) {
                observe(&s);
                return Ok(RunEnd {
                    state: s,
                    stats: *stats,
                    stop: Stop::Event { index },
                    dt_next: h,
                });
            }
        }
    }
}

/// The state on the step from `before` to `after` (interpolant `dense`) where the barycentre
/// crossed the plane of `crossing`, located as events are, to 10⁻⁹ of the step's travel; the
/// step's end if it started beyond the plane already.
fn crossed(crossing: &Crossing, before: &State, dense: &Dense, after: &State) -> Result<State, StepError> {
    let (g0, g1) = (crossing.gap(&before.x), crossing.gap(&after.x));
    if !(g0 > 0.0 && g1 <= 0.0) {
        return Ok(*after);
    }
    let travel = (after.x - before.x).norm();
    let mut at = locate_root(&|s| crossing.gap(&s.x), dense, (before.t, g0), (after.t, g1), travel)?;
    // Mapped from the domain's side the image would lie beyond the partner patch.
    if crossing.gap(&at.x) > 0.0 {
        at.x -= crossing.normal * crossing.gap(&at.x);
    }
    Ok(at)
}

/// The earliest event that fires within the step from `before` to `after`, located on `dense`.
fn first_event(
    events: &[&dyn Event],
    before: &State,
    dense: &Dense,
    after: &State,
) -> Result<Option<(usize, State)>, StepError> {
    let mut first: Option<(usize, State)> = None;
    for (index, e) in events.iter().enumerate() {
        // g at the step's start is needed only when the event fires at its end.
        let g1 = e.gap(after);
        if g1 > 0.0 {
            continue;
        }
        let g0 = e.gap(before);
        if g1.is_nan() || g0.is_nan() {
            return Err(StepError::NonFinite {
                what: "event gap",
                t: after.t,
            });
        }
        let at = locate(*e, dense, (before.t, g0), (after.t, g1), e.scale(after))?;
        if first.as_ref().is_none_or(|(_, s)| at.t < s.t) {
            first = Some((index, at));
        }
    }
    Ok(first)
}

/// Illinois regula falsi for g(state(t)) = 0 on `dense` between a (g > 0) and b (g ≤ 0).
fn locate(e: &dyn Event, dense: &Dense, a: (f64, f64), b: (f64, f64), scale: f64) -> Result<State, StepError> {
    locate_root(&|s| e.gap(s), dense, a, b, scale)
}

/// The state where `gap`(state(t)) = 0 on the step's interpolant `dense`, between
/// a = (t_a, g_a) with g_a > 0 and b = (t_b, g_b) with g_b ≤ 0: the driver's event location
/// (Illinois regula falsi until |g| ≤ 10⁻⁹ · `scale`, [`EVENT_TOL`]), for watches that locate
/// non-terminal crossings on the same interpolant (the release watch, `population::release`).
pub fn locate_root(
    gap: &dyn Fn(&State) -> f64,
    dense: &Dense,
    a: (f64, f64),
    b: (f64, f64),
    scale: f64,
) -> Result<State, StepError> {
    let ((mut ta, mut ga), (mut tb, mut gb)) = (a, b);
    let tol = EVENT_TOL * scale.abs().max(f64::MIN_POSITIVE);
    if -gb <= tol {
        return Ok(dense.state_at(tb));
    }
    let mut side = 0i8;
    for _ in 0..MAX_EVENT_ITERS {
        let tc = ta + ga / (ga - gb) * (tb - ta);
        let sc = dense.state_at(tc);
        let gc = gap(&sc);
        if gc.is_nan() {
            return Err(StepError::NonFinite {
                what: "event gap",
                t: tc,
            });
        }
        if gc.abs() <= tol || tb - ta <= 4.0 * f64::EPSILON * tb.abs().max(1.0) {
            return Ok(sc);
        }
        if gc > 0.0 {
            (ta, ga) = (tc, gc);
            if side == 1 {
                gb *= 0.5;
            }
            side = 1;
        } else {
            (tb, gb) = (tc, gc);
            if side == -1 {
                ga *= 0.5;
            }
            side = -1;
        }
    }
    Err(StepError::EventNotLocated { t: tb, gap: gb })
}

/// Advance from `state` to the last of `outputs` (ascending), starting with step `dt`,
/// calling `observers.observe` at every output time and `observers.on_step` after every
/// accepted step.
///
/// A failure is the bare [`StepError`]; [`integrate`] reports the statistics and the last
/// state of a failed run too ([`RunFailure`]).
pub fn run<I, M, D, F, O, S>(
    problem: Problem<'_, I, M, D, F>,
    state: State,
    dt: f64,
    outputs: &[f64],
    observers: Observers<O, S>,
) -> Result<(State, RunStats), StepError>
where
    I: Stepper<M, D>,
    M: Response,
    D: DragModel,
    F: FlowField + ?Sized,
    O: FnMut(&State),
    S: FnMut(&AcceptedStep<'_>),
{
    let t_end = outputs.last().copied().unwrap_or(state.t);
    let plan = Plan::new(t_end, dt)?.with_outputs(outputs)?;
    // `integrate` shows the start state first; `run` shows it only if it is an output time.
    let mut show_start = outputs.first().is_some_and(|&t| t <= state.t);
    let mut started = false;
    let mut memory = I::Memory::default();
    let Observers { mut observe, on_step } = observers;
    let observers = Observers::new(
        |s: &State| {
            if started || std::mem::take(&mut show_start) {
                observe(s);
            }
            started = true;
        },
        on_step,
    );
    let out = integrate(problem, state, &mut memory, &plan, &[], observers)?;
    Ok((out.state, out.stats))
}

/// Convenience: advance to `t_end` without observers.
pub fn advance<I, M, D, F>(
    problem: Problem<'_, I, M, D, F>,
    state: State,
    dt: f64,
    t_end: f64,
) -> Result<(State, RunStats), StepError>
where
    I: Stepper<M, D>,
    M: Response,
    D: DragModel,
    F: FlowField + ?Sized,
{
    run(problem, state, dt, &[t_end], Observers::none())
}

/// Convenience: [`integrate`] with fresh step memory and no observers, to the end of `plan` or
/// the first of `events` that fires.
#[allow(clippy::result_large_err)] // as `integrate`
pub fn until_event<I, M, D, F>(
    problem: Problem<'_, I, M, D, F>,
    state: State,
    plan: &Plan,
    events: &[&dyn Event],
) -> Result<RunEnd, RunFailure>
where
    I: Stepper<M, D>,
    M: Response,
    D: DragModel,
    F: FlowField + ?Sized,
{
    let mut memory = I::Memory::default();
    integrate(problem, state, &mut memory, plan, events, Observers::none())
}

/// Evenly spaced output times n·Δ for n = 1..=N with NΔ = t_end.
pub fn output_times(t_end: f64, count: usize) -> Vec<f64> {
    (1..=count).map(|n| t_end * n as f64 / count as f64).collect()
}

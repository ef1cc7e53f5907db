//! The driver owns the time loop: it calls an integrator step by step, honours the step sizes
//! the integrator proposes, lands exactly on requested output times, and accumulates the work
//! statistics used in work-precision studies.

use crate::error::StepError;
use crate::flow::FlowField;
use crate::hydro::DragModel;
use crate::integrator::{StepInfo, TimeIntegrator};
use crate::material::Hyperelastic;
use crate::particle::{Particle, State};
use serde::{Deserialize, Serialize};

/// Accumulated work of a run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct RunStats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected step attempts.
    pub rejected: u64,
    /// Hydrodynamic model evaluations.
    pub rhs_evals: u64,
    /// Jacobian evaluations.
    pub jac_evals: u64,
    /// Newton iterations, summed.
    pub newton_iters: u64,
    /// Largest Newton iteration count of any step.
    pub max_newton_iters: u32,
}

impl RunStats {
    fn record(&mut self, info: &StepInfo) {
        self.steps += 1;
        self.rejected += u64::from(info.rejected);
        self.rhs_evals += u64::from(info.rhs_evals);
        self.jac_evals += u64::from(info.jac_evals);
        self.newton_iters += u64::from(info.newton_iters);
        self.max_newton_iters = self.max_newton_iters.max(info.newton_iters);
    }
}

/// Advance from `state` to `t_end`, starting with step `dt` (fixed-step integrators keep it),
/// stopping exactly at every time in `outputs` (ascending) and calling `observe` there.
/// `observe` also sees every accepted step through `on_step`.
pub fn run<I, M, D, F>(
    integrator: &I,
    particle: &Particle<M, D>,
    state: State,
    flow: &F,
    dt: f64,
    outputs: &[f64],
    mut observe: impl FnMut(&State),
    mut on_step: impl FnMut(&State, &StepInfo),
) -> Result<(State, RunStats), StepError>
where
    I: TimeIntegrator,
    M: Hyperelastic,
    D: DragModel,
    F: FlowField + ?Sized,
{
    crate::error::positive("dt", dt)?;
    let mut s = state;
    let mut stats = RunStats::default();
    let mut h = dt;
    for &t_out in outputs {
        while t_out - s.t > 1e-12 * t_out.abs().max(1.0) {
            let remaining = t_out - s.t;
            // Land on t_out; never leave a sliver step (< 1 % of h) before it.
            let clamped = h >= 0.99 * remaining;
            let try_h = if clamped { remaining } else { h };
            let (next, info) = integrator.step(particle, &s, flow, try_h)?;
            stats.record(&info);
            // A step shortened to hit t_out says nothing about the next step size.
            h = if clamped { h.max(info.dt_next) } else { info.dt_next };
            s = next;
            on_step(&s, &info);
        }
        s.t = t_out;
        observe(&s);
    }
    Ok((s, stats))
}

/// Convenience: advance to `t_end` without observers.
pub fn advance<I, M, D, F>(
    integrator: &I,
    particle: &Particle<M, D>,
    state: State,
    flow: &F,
    dt: f64,
    t_end: f64,
) -> Result<(State, RunStats), StepError>
where
    I: TimeIntegrator,
    M: Hyperelastic,
    D: DragModel,
    F: FlowField + ?Sized,
{
    run(integrator, particle, state, flow, dt, &[t_end], |_| {}, |_, _| {})
}

/// Evenly spaced output times n·Δ for n = 1..=N with NΔ = t_end.
pub fn output_times(t_end: f64, count: usize) -> Vec<f64> {
    (1..=count).map(|n| t_end * n as f64 / count as f64).collect()
}

//! Runs in the pipe: orientation histories at fixed output times (paper Fig. 10) and tracking
//! until the particle touches the wall (Figs 11, 12).
//!
//! # Deposition event
//! Wall contact is a [`ContactEvent`] of the driver on the [`PipeWall`]: the gap
//! g = R − |x_⊥| − h(n) of the particle's extent ([`crate::contact::pipe`]) is located on each
//! step's dense output to |g| ≤ 10⁻⁹ d_eq, and the event caps each step so that a tumbling tip
//! cannot touch and leave the wall unseen ([`crate::contact`]).

use super::setup::PipeSetup;
use crate::contact::{ContactEvent, ContactModel, PipeWall};
use crate::diagnostics::{Monitor, Validity};
use crate::driver::{Event, Observers, Plan, Problem, Stop, integrate, run};
use crate::ellipsoid::PrincipalFrame;
use crate::hydro::DragModel;
use crate::integrator::TimeIntegrator;
use crate::material::{Hyperelastic, Softness};
use crate::particle::State;
use crate::particle::lines::material_line;
use crate::studies::StudyError;
use crate::tensor::Vec3;

/// The observed quantities of one state (units d_eq and 1/γ̇₀).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PipeSample {
    /// Time t̂ = γ̇₀ t.
    pub t: f64,
    /// Barycentre x_c.
    pub x: Vec3,
    /// Material line ξ_a = F·Ξ_A to the point A initially at r₁e₁ (Fig. 9).
    pub xi_a: Vec3,
    /// Wall gap g = R − |x_⊥| − h(n).
    pub gap: f64,
}

impl PipeSample {
    /// Direction cosines of l_a, ξ_a/|ξ_a| (paper Figs 10, 12).
    pub fn direction_cosines(&self) -> Vec3 {
        self.xi_a / self.xi_a.norm()
    }
}

impl<M: Hyperelastic, D: DragModel> PipeSetup<M, D> {
    /// Contact of the particle's extent with the pipe wall.
    pub fn contact(&self) -> ContactEvent<'_, PipeWall, Softness<M>, D, crate::flow::analytic::Poiseuille> {
        ContactEvent::new(&self.wall, &self.particle, &self.flow, ContactModel::Extent)
    }

    /// Observe a state.
    pub fn observe(&self, state: &State) -> PipeSample {
        PipeSample {
            t: state.t,
            x: state.x,
            xi_a: material_line(self.particle.shape(), &state.f, 0),
            gap: self.contact().gap(state),
        }
    }
}

/// Run from the release state and sample at `times` (ascending, > 0) with the driver; the first
/// sample is the release state.
pub fn sample_orientation<I: TimeIntegrator, M: Hyperelastic, D: DragModel>(
    setup: &PipeSetup<M, D>,
    integrator: &I,
    times: &[f64],
    dt0: f64,
) -> Result<Vec<PipeSample>, StudyError> {
    let start = setup.initial_state().map_err(crate::error::StepError::from)?;
    let mut out = vec![setup.observe(&start)];
    run(
        Problem::new(integrator, &setup.particle, &setup.flow),
        start,
        dt0,
        times,
        Observers::none().with_observe(|s| out.push(setup.observe(s))),
    )?;
    Ok(out)
}

/// Time averages over a run of the shape quantities that set the settling mobility
/// (stretching, not alignment, dominates the soft particles' extra travel), by the trapezoidal
/// rule over accepted steps.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ShapeStats {
    /// ∫(p·e₂)² dt.
    alignment_integral: f64,
    /// ∫r₁/r₃ dt.
    aspect_integral: f64,
    duration: f64,
    max_aspect: f64,
    /// (t, (p·e₂)², r₁/r₃) of the last state added.
    last: Option<(f64, f64, f64)>,
}

impl ShapeStats {
    /// Add the current ellipsoid `frame` at time `t` (after the previous one).
    pub fn add(&mut self, frame: &PrincipalFrame, t: f64) {
        let p = frame.q.row(0);
        let (align, aspect) = (p[1] * p[1], frame.r[0] / frame.r[2]);
        if let Some((t0, a0, r0)) = self.last {
            let dt = t - t0;
            self.alignment_integral += 0.5 * dt * (a0 + align);
            self.aspect_integral += 0.5 * dt * (r0 + aspect);
            self.duration += dt;
        }
        self.max_aspect = self.max_aspect.max(aspect);
        self.last = Some((t, align, aspect));
    }

    /// ⟨(p·e₂)²⟩, p the long axis: the rigid Jeffery value is 1/(1 + λ₁)
    /// ([`crate::reference::jeffery_mean_gradient_alignment`]). `None` before time has passed.
    pub fn mean_gradient_alignment(&self) -> Option<f64> {
        (self.duration > 0.0).then(|| self.alignment_integral / self.duration)
    }

    /// ⟨r₁/r₃⟩ of the current ellipsoid. `None` before time has passed.
    pub fn mean_aspect(&self) -> Option<f64> {
        (self.duration > 0.0).then(|| self.aspect_integral / self.duration)
    }

    /// max r₁/r₃ over the states added.
    pub fn max_aspect(&self) -> f64 {
        self.max_aspect
    }
}

/// A run from release to wall contact.
#[derive(Debug, Clone, PartialEq)]
pub struct Deposition {
    /// The release state, the first accepted step at or after each multiple of the recording
    /// interval, and the contact state.
    pub samples: Vec<PipeSample>,
    /// Accepted steps.
    pub steps: u64,
    /// Rejected step attempts.
    pub rejected: u64,
    /// Time-averaged shape and alignment.
    pub shape: ShapeStats,
    /// Validity diagnostics over the accepted steps.
    pub validity: Validity,
}

impl Deposition {
    /// The state at contact (g ≈ 0).
    pub fn contact(&self) -> &PipeSample {
        self.samples
            .last()
            .expect("a deposition holds the release and contact samples")
    }

    /// Streamwise deposition distance x₁(contact) − x₁(release) (d_eq).
    pub fn distance(&self) -> f64 {
        self.contact().x[0] - self.samples[0].x[0]
    }
}

/// Track the released particle until it touches the wall, starting with step `dt0` and
/// recording a sample about every `record_dt` (∞: release and contact only); fail with
/// [`StudyError::NotDeposited`] if it is still free at `t_max` (units 1/γ̇₀).
pub fn track_to_deposition<I: TimeIntegrator, M: Hyperelastic, D: DragModel>(
    setup: &PipeSetup<M, D>,
    integrator: &I,
    dt0: f64,
    t_max: f64,
    record_dt: f64,
) -> Result<Deposition, StudyError> {
    let state = setup.initial_state().map_err(crate::error::StepError::from)?;
    let release = setup.observe(&state);
    if release.gap <= 0.0 {
        return Err(StudyError::ReleasedInWall { gap: release.gap });
    }
    let contact = setup.contact();
    let mut samples = vec![release];
    let mut shape = ShapeStats::default();
    shape.add(&setup.particle.frame(&state.f), state.t);
    let mut monitor = Monitor::new(&setup.particle, &setup.flow, &setup.wall);
    monitor.observe(&state);
    let mut next_record = record_dt;
    let mut memory = I::Memory::default();
    let plan = Plan::new(t_max, dt0)?;
    let end = integrate(
        Problem::new(integrator, &setup.particle, &setup.flow),
        state,
        &mut memory,
        &plan,
        &[&contact],
        Observers::none().with_on_step(|step| {
            let state = step.state();
            shape.add(step.frame(), state.t);
            monitor.observe_step(step);
            if state.t >= next_record {
                samples.push(setup.observe(state));
                next_record = state.t + record_dt;
            }
        }),
    )?;
    match end.stop {
        Stop::Event { .. } => {
            samples.push(setup.observe(&end.state));
            Ok(Deposition {
                samples,
                steps: end.stats.steps,
                rejected: end.stats.rejected,
                shape,
                validity: monitor.validity(),
            })
        }
        Stop::EndTime => Err(StudyError::NotDeposited {
            t_max,
            gap: setup.observe(&end.state).gap,
        }),
    }
}

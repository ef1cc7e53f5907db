//! Runs in the pipe: orientation histories at fixed output times (paper Fig. 10) and tracking
//! until the particle touches the wall (Figs 11, 12).
//!
//! # Deposition event
//! The driver loop has no events, so [`track_to_deposition`] steps the integrator itself. It
//! caps each step so that the wall gap g (see [`super::wall`]) can close by at most
//! g + r₃/2 at the current rates, (|v_⊥| + r₁|∇u|) Δt ≤ g + r₃/2: translation by v_⊥ and a tip
//! sweeping at ≤ r₁|∇u|. This keeps the trial barycentre inside the pipe (where the flow is
//! defined) and prevents a tumbling tip from touching and leaving the wall within one step.
//! The step that closes the gap is then refined by regula falsi (Illinois) on g, re-stepping
//! from the last state before contact, until |g| ≤ 10⁻⁹ d_eq.

use super::setup::PipeScene;
use super::wall::wall_gap;
use crate::driver::run;
use crate::flow::FlowField;
use crate::integrator::TimeIntegrator;
use crate::particle::State;
use crate::particle::lines::material_line;
use crate::scenes::SceneError;
use crate::tensor::Vec3;

/// |g| at which the contact time counts as located (d_eq).
const CONTACT_GAP_TOL: f64 = 1e-9;
/// Regula-falsi iterations allowed for the contact time.
const MAX_CONTACT_ITERS: u32 = 100;

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

impl PipeScene {
    /// Observe a state.
    pub fn observe(&self, state: &State) -> PipeSample {
        let frame = self.particle.geometry(state).frame;
        PipeSample {
            t: state.t,
            x: state.x,
            xi_a: material_line(self.particle.shape(), &state.f, 0),
            gap: wall_gap(self.flow.radius, &state.x, &frame),
        }
    }
}

/// Run from the release state and sample at `times` (ascending, > 0) with the driver; the first
/// sample is the release state.
pub fn sample_orientation<I: TimeIntegrator>(
    scene: &PipeScene,
    integrator: &I,
    times: &[f64],
    dt0: f64,
) -> Result<Vec<PipeSample>, SceneError> {
    let start = scene.initial_state().map_err(crate::error::StepError::from)?;
    let mut out = vec![scene.observe(&start)];
    run(
        integrator,
        &scene.particle,
        start,
        &scene.flow,
        dt0,
        times,
        |s| out.push(scene.observe(s)),
        |_, _| {},
    )?;
    Ok(out)
}

/// A run from release to wall contact.
#[derive(Debug, Clone, PartialEq)]
pub struct Deposition {
    /// The release state, the first accepted step at or after each multiple of the recording
    /// interval, and the contact state.
    pub samples: Vec<PipeSample>,
    /// Accepted steps, including the contact refinement.
    pub steps: u64,
    /// Rejected step attempts.
    pub rejected: u64,
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
/// [`SceneError::NotDeposited`] if it is still free at `t_max` (units 1/γ̇₀).
pub fn track_to_deposition<I: TimeIntegrator>(
    scene: &PipeScene,
    integrator: &I,
    dt0: f64,
    t_max: f64,
    record_dt: f64,
) -> Result<Deposition, SceneError> {
    let mut state = scene.initial_state().map_err(crate::error::StepError::from)?;
    let mut now = scene.observe(&state);
    if now.gap <= 0.0 {
        return Err(SceneError::ReleasedInWall { gap: now.gap });
    }
    let mut run = Deposition {
        samples: vec![now],
        steps: 0,
        rejected: 0,
    };
    let mut h = dt0;
    let mut next_record = record_dt;
    while state.t < t_max {
        let cap = approach_cap(scene, &state, now.gap)?;
        let clamped = h > cap;
        let (next, info) = integrator.step(&scene.particle, &state, &scene.flow, h.min(cap))?;
        // t + h == t (a step below the float spacing of t) would loop forever.
        if next.t <= state.t {
            return Err(crate::error::StepError::StepSizeUnderflow {
                dt: info.dt,
                t: state.t,
                error: f64::NAN,
            }
            .into());
        }
        run.steps += 1;
        run.rejected += u64::from(info.rejected);
        h = if clamped { h.max(info.dt_next) } else { info.dt_next };
        let seen = scene.observe(&next);
        if seen.gap <= 0.0 {
            let contact = locate_contact(scene, integrator, (state, now.gap), (next, seen.gap), &mut run)?;
            run.samples.push(scene.observe(&contact));
            return Ok(run);
        }
        if seen.t >= next_record {
            run.samples.push(seen);
            next_record = seen.t + record_dt;
        }
        (state, now) = (next, seen);
    }
    Err(SceneError::NotDeposited { t_max, gap: now.gap })
}

/// Largest step that lets the gap close by at most g + r₃/2 at the current rates.
fn approach_cap(scene: &PipeScene, state: &State, gap: f64) -> Result<f64, SceneError> {
    let r = scene.particle.geometry(state).frame.r;
    let grad_u = scene
        .flow
        .sample(&state.x, state.t)
        .map_err(crate::error::StepError::from)?
        .grad_u;
    let rate = Vec3::new(0.0, state.v[1], state.v[2]).norm() + r[0] * grad_u.norm();
    Ok((gap + 0.5 * r[2]) / rate.max(f64::MIN_POSITIVE))
}

/// Regula falsi (Illinois) on the gap between `before` (g > 0) and `after` (g ≤ 0).
fn locate_contact<I: TimeIntegrator>(
    scene: &PipeScene,
    integrator: &I,
    before: (State, f64),
    after: (State, f64),
    run: &mut Deposition,
) -> Result<State, SceneError> {
    let ((mut a, mut ga), (mut b, mut gb)) = (before, after);
    if -gb <= CONTACT_GAP_TOL {
        return Ok(b);
    }
    let mut last_replaced_a = None;
    for _ in 0..MAX_CONTACT_ITERS {
        let h = ga / (ga - gb) * (b.t - a.t);
        let (c, info) = integrator.step(&scene.particle, &a, &scene.flow, h)?;
        run.steps += 1;
        run.rejected += u64::from(info.rejected);
        let gc = scene.observe(&c).gap;
        if gc.abs() <= CONTACT_GAP_TOL {
            return Ok(c);
        }
        let replaced_a = gc > 0.0;
        if replaced_a {
            (a, ga) = (c, gc);
        } else {
            (b, gb) = (c, gc);
        }
        // Illinois: an end point kept twice in a row gets half its weight, so that the bracket
        // shrinks from both sides.
        if last_replaced_a == Some(replaced_a) {
            if replaced_a {
                gb *= 0.5;
            } else {
                ga *= 0.5;
            }
        }
        last_replaced_a = Some(replaced_a);
    }
    Err(SceneError::ContactNotLocated { t: b.t, gap: gb })
}

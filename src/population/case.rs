//! One particle of a population, from its seed to its fate.

use super::observe::{Observer, Watch};
use super::record::{Fate, ParticleRecord};
use super::spec::{Injector, particle_rng};
use crate::contact::{Boundary, ContactEvent, ContactModel, PatchRule};
use crate::driver::{Event, Observers, Plan, Problem, RunEnd, RunFailure, RunStats, Stop, integrate, resume};
use crate::error::StepError;
use crate::flow::FlowField;
use crate::integrator::{IntegratorReport, Stepper};
use crate::material::Softness;
use crate::particle::{Particle, State};
use std::cell::RefCell;
use std::hash::Hasher;

/// Moves off the walls a particle born overlapping them may take ([`Case`], Birth).
pub const BIRTH_MOVES: usize = 8;

/// The observer of a case's particles ([`Case::with_observer`]).
pub type CaseObserver<'a, J, F, B> =
    dyn Observer<Particle<Softness<<J as Injector>::Law>, <J as Injector>::Drag>, F, B> + 'a;

/// What every particle of a population shares: integrator, flow, boundary, injection rule,
/// contact model, the driver's plan (end time, first step, step cap, step budget) and what is
/// observed of each run.
///
/// # Birth
/// A particle whose extent overlaps a wall where it is injected (near the rim of an inlet,
/// where the walls meet it) is moved off it along the wall's normal before its first step,
/// not deposited at birth; one that cannot be moved off in [`BIRTH_MOVES`] moves is refused and
/// counted as failed.
///
/// The plan's end time is each particle's time limit (it starts at its injection time,
/// [`Injector::injection`], usually 0), unless the injector gives a particle its own plan
/// ([`Injector::plan`]). Give the plan a step
/// budget ([`crate::driver::Budget::max_steps`]) but no wall-time limit: a wall-time limit
/// makes a particle's fate depend on the machine's load, and the run is then no longer the
/// same whatever its layout.
pub struct Case<'a, I, F: ?Sized, B: ?Sized, J: Injector> {
    integrator: &'a I,
    flow: &'a F,
    boundary: &'a B,
    injector: &'a J,
    contact: ContactModel,
    plan: Plan,
    samples: bool,
    observer: Option<&'a CaseObserver<'a, J, F, B>>,
}

impl<'a, I, F, B, J> Case<'a, I, F, B, J>
where
    I: Stepper<Softness<J::Law>, J::Drag> + std::fmt::Debug,
    F: FlowField + ?Sized,
    B: Boundary + ?Sized,
    J: Injector,
{
    /// Particles drawn by `injector`, advanced by `integrator` in `flow` as `plan` says, until
    /// their extent touches a patch of `boundary` ([`ContactModel::Extent`]).
    pub fn new(integrator: &'a I, flow: &'a F, boundary: &'a B, injector: &'a J, plan: Plan) -> Self {
        Self {
            integrator,
            flow,
            boundary,
            injector,
            contact: ContactModel::Extent,
            plan,
            samples: false,
            observer: None,
        }
    }

    /// Watch each particle's run with `observer` and keep its summary in the record
    /// ([`ParticleRecord::observed`]): the per-run columns of a scene.
    pub fn with_observer(mut self, observer: &'a CaseObserver<'a, J, F, B>) -> Self {
        self.observer = Some(observer);
        self
    }

    /// Keep each particle's states at the start, the plan's output times and its event in its
    /// record ([`ParticleRecord::samples`]): trajectories and time series for output files.
    pub fn with_samples(mut self) -> Self {
        self.samples = true;
        self
    }

    /// Use `contact` instead of the particle's extent.
    pub fn with_contact(mut self, contact: ContactModel) -> Self {
        self.contact = contact;
        self
    }

    /// The driver's plan every particle shares (unless the injector gives it its own).
    pub fn plan(&self) -> &Plan {
        &self.plan
    }

    /// The same particles on `flow` with `plan`: the same integrator, boundary, injection and
    /// contact model, without observer or kept samples (a re-track on another reconstruction
    /// of the field, `super::adequacy`).
    pub fn on<'b, G: FlowField + ?Sized>(&'b self, flow: &'b G, plan: Plan) -> Case<'b, I, G, B, J> {
        Case {
            integrator: self.integrator,
            flow,
            boundary: self.boundary,
            injector: self.injector,
            contact: self.contact,
            plan,
            samples: false,
            observer: None,
        }
    }

    /// The boundary (for patch names).
    pub fn boundary(&self) -> &B {
        self.boundary
    }

    /// The injection rule.
    pub fn injector(&self) -> &J {
        self.injector
    }

    /// Particle `index` of a run with seed `seed`: drawn from its own generator, then advanced
    /// until a patch is touched, the end time is reached, or something fails. A pure function
    /// of (case, seed, index): this is what makes the population's results independent of
    /// threads, shards and restarts.
    pub fn run_particle(&self, seed: u64, index: u64) -> ParticleRecord<J::Law> {
        let mut rng = particle_rng(seed, index);
        let spec = match self.injector.draw(index, &mut rng) {
            Ok(spec) => spec,
            Err(e) => {
                return ParticleRecord::not_started(index, None, None, &e);
            }
        };
        let start = match self.injector.injection(index, &spec, &mut rng) {
            Ok(start) => start,
            Err(e) => {
                return ParticleRecord::not_started(index, Some(spec), None, &e);
            }
        };
        let particle = match self.injector.particle(&spec) {
            Ok(p) => p,
            Err(e) => {
                return ParticleRecord::not_started(index, Some(spec), Some(start), &e);
            }
        };
        let plan = match self.injector.plan(index, &spec, &self.plan) {
            Ok(plan) => plan,
            Err(e) => {
                return ParticleRecord::not_started(index, Some(spec), Some(start), &e);
            }
        };
        let contact = ContactEvent::new(self.boundary, &particle, self.flow, self.contact);
        let start = match self.off_walls(&contact, start) {
            Ok(start) => start,
            Err(e) => return ParticleRecord::not_started(index, Some(spec), Some(start), &e),
        };
        let mut memory = I::Memory::default();
        let mut samples = Vec::new();
        // Both callbacks of the driver feed the one watch.
        let watch: RefCell<Option<Box<dyn Watch + '_>>> = RefCell::new(
            self.observer
                .map(|o| o.watch(&particle, self.flow, self.boundary, &start)),
        );
        let result = integrate(
            Problem::new(self.integrator, &particle, self.flow),
            start,
            &mut memory,
            &plan,
            &[&contact],
            Observers::new(
                |s| {
                    if self.samples {
                        samples.push(*s);
                    }
                    if let Some(w) = watch.borrow_mut().as_mut() {
                        w.output(s);
                    }
                },
                |step| {
                    if let Some(w) = watch.borrow_mut().as_mut() {
                        w.step(step);
                    }
                },
            ),
        );
        let (fate, end, stats) = self.fate(&contact, result);
        let observed = watch
            .into_inner()
            .map_or(serde_json::Value::Null, |w| w.finish(&fate, &end));
        ParticleRecord {
            index,
            spec: Some(spec),
            fate,
            end: Some(end),
            stats,
            integrator: self.integrator.particle_report(&memory),
            samples,
            observed,
        }
    }

    /// `start` moved off every wall its extent overlaps at birth: along the nearest wall's
    /// normal by its overlap and 10⁻⁶ of the particle's equivalent diameter, at most
    /// [`BIRTH_MOVES`] times (a particle wedged in a corner meets the other wall after the
    /// first move). A particle born on an exit patch is left as it is: it escapes at its first
    /// step. One still overlapping a wall after the last move is refused, with the wall and the
    /// depth, and counted as failed, apart from the deposited.
    fn off_walls(
        &self,
        contact: &ContactEvent<'_, B, Softness<J::Law>, J::Drag, F>,
        start: State,
    ) -> Result<State, String> {
        let mut state = start;
        let margin = 1e-6 * contact.scale(&state);
        for _ in 0..BIRTH_MOVES {
            let near = contact.nearest(&state);
            if !(near.gap <= 0.0) || self.boundary.rule(near.patch) == PatchRule::Exit {
                return Ok(state);
            }
            state.x -= near.normal * (margin - near.gap);
        }
        let near = contact.nearest(&state);
        if !(near.gap <= 0.0) || self.boundary.rule(near.patch) == PatchRule::Exit {
            return Ok(state);
        }
        Err(format!(
            "injected overlapping wall `{}`: still {:.3e} m deep after {BIRTH_MOVES} moves off along the wall normals \
             (from {:?})",
            self.boundary.patch_name(near.patch),
            -near.gap,
            start.x.as_slice()
        ))
    }

    /// The fate of a run's `result`, its end state and work.
    fn fate(
        &self,
        contact: &ContactEvent<'_, B, Softness<J::Law>, J::Drag, F>,
        result: Result<RunEnd, RunFailure>,
    ) -> (Fate, State, RunStats) {
        match result {
            Ok(out) => {
                let fate = match out.stop {
                    Stop::EndTime => Fate::Suspended,
                    Stop::Event { .. } => {
                        let patch = contact.nearest(&out.state).patch;
                        match self.boundary.rule(patch) {
                            PatchRule::Stick => Fate::Deposited {
                                patch,
                                position: out.state.x,
                                time: out.state.t,
                            },
                            PatchRule::Exit => Fate::Escaped {
                                patch,
                                time: out.state.t,
                            },
                        }
                    }
                };
                (fate, out.state, out.stats)
            }
            Err(failure) => (
                Fate::Failed {
                    error: failure_text(&failure.error),
                },
                failure.state,
                failure.stats,
            ),
        }
    }

    /// Particle `index` of a run with seed `seed` drawn, built and planned, ready for
    /// [`Case::advance`]; a particle that cannot be is its record, as in
    /// [`Case::run_particle`].
    // The in-flight particle (the Ok variant) is as large as its record: boxing saves nothing.
    #[allow(clippy::result_large_err)]
    pub fn launch(&self, seed: u64, index: u64) -> Result<InFlight<J, I::Memory>, ParticleRecord<J::Law>> {
        let mut rng = particle_rng(seed, index);
        let spec = self
            .injector
            .draw(index, &mut rng)
            .map_err(|e| ParticleRecord::not_started(index, None, None, &e))?;
        let start = self
            .injector
            .injection(index, &spec, &mut rng)
            .map_err(|e| ParticleRecord::not_started(index, Some(spec.clone()), None, &e))?;
        let not_started =
            |e: &dyn std::fmt::Display| ParticleRecord::not_started(index, Some(spec.clone()), Some(start), e);
        let particle = self.injector.particle(&spec).map_err(|e| not_started(&e))?;
        let plan = self
            .injector
            .plan(index, &spec, &self.plan)
            .map_err(|e| not_started(&e))?;
        let contact = ContactEvent::new(self.boundary, &particle, self.flow, self.contact);
        let start = self.off_walls(&contact, start).map_err(|e| not_started(&e))?;
        Ok(InFlight {
            index,
            spec,
            particle,
            plan,
            memory: I::Memory::default(),
            start,
            last: None,
            samples: Vec::new(),
        })
    }

    /// Advance `particle` to `until` (or its plan's end time, if earlier): `None` while it is
    /// still in flight, its record once it has its fate. The run is [`Case::run_particle`]'s
    /// cut at `until`: [`crate::driver::resume`] continues it with its step proposal and
    /// memory, and only the step that lands on `until` differs. Observers are not supported
    /// (a watch would hold the flow across the cut); samples are.
    pub fn advance(&self, particle: &mut InFlight<J, I::Memory>, until: f64) -> Option<ParticleRecord<J::Law>> {
        let own_end = particle.plan.t_end();
        let plan = particle.plan.until(until);
        if particle.last.is_none() && particle.start.t > plan.t_end() && plan.t_end() < own_end {
            // Released after `until`: nothing to do yet.
            return None;
        }
        let contact = ContactEvent::new(self.boundary, &particle.particle, self.flow, self.contact);
        let keep = self.samples;
        let samples = &mut particle.samples;
        let observe = |s: &State| {
            if keep {
                samples.push(*s);
            }
        };
        let result = match &particle.last {
            None => integrate(
                Problem::new(self.integrator, &particle.particle, self.flow),
                particle.start,
                &mut particle.memory,
                &plan,
                &[&contact],
                Observers::none().with_observe(observe),
            ),
            Some(last) => resume(
                Problem::new(self.integrator, &particle.particle, self.flow),
                last,
                &mut particle.memory,
                &plan,
                &[&contact],
                Observers::none().with_observe(observe),
            ),
        };
        match result {
            Ok(out) if out.stop == Stop::EndTime && plan.t_end() < own_end => {
                particle.last = Some(out);
                None
            }
            result => {
                let (fate, end, stats) = self.fate(&contact, result);
                Some(ParticleRecord {
                    index: particle.index,
                    spec: Some(particle.spec.clone()),
                    fate,
                    end: Some(end),
                    stats,
                    integrator: self.integrator.particle_report(&particle.memory),
                    samples: std::mem::take(&mut particle.samples),
                    observed: serde_json::Value::Null,
                })
            }
        }
    }

    /// The record of `particle` suspended where its last segment ended (its start, if it has
    /// not started): the end of a batch run cut before the particle's end time.
    pub fn suspend(&self, particle: &mut InFlight<J, I::Memory>) -> ParticleRecord<J::Law> {
        let (end, stats) = particle
            .last
            .as_ref()
            .map_or((particle.start, RunStats::default()), |o| (o.state, o.stats));
        ParticleRecord {
            index: particle.index,
            spec: Some(particle.spec.clone()),
            fate: Fate::Suspended,
            end: Some(end),
            stats,
            integrator: self.integrator.particle_report(&particle.memory),
            samples: std::mem::take(&mut particle.samples),
            observed: serde_json::Value::Null,
        }
    }

    /// Whether the case has an observer ([`Case::with_observer`]).
    pub fn observed(&self) -> bool {
        self.observer.is_some()
    }

    /// A hash (16 hex digits) of what determines the results of a run with `config`: the code
    /// version ([`super::seal::VERSION`]), the seed, the number of particles, the caller's
    /// fingerprint, the integrator (its settings), the
    /// plan and the contact model (their `Debug` forms print every f64 exactly). A checkpoint or shard
    /// file carries it, so a resumed run or a merge refuses files of a different run.
    ///
    /// FNV-1a (64 bit, the `fnv` crate) over a fixed byte layout: stable across Rust releases,
    /// unlike `std`'s `DefaultHasher`; it guards against mistakes, not against forgery.
    pub fn config_hash(&self, config: &RunConfig) -> String {
        let mut h = fnv::FnvHasher::default();
        for part in [
            "pseudorigid population v1",
            // Another version of the code may give other records: its checkpoints, shards and
            // caches are not this run's.
            super::seal::VERSION,
            &config.seed.to_string(),
            &config.particles.to_string(),
            &config.fingerprint,
            &format!("{:?}", self.integrator),
            &format!("{:?}", self.plan),
            &format!("{:?}", self.contact),
        ] {
            h.write(&(part.len() as u64).to_le_bytes());
            h.write(part.as_bytes());
        }
        // Records with and without samples differ; the hash of a run without them is unchanged.
        if self.samples {
            h.write(b"samples");
        }
        // Likewise with and without observations.
        if let Some(observer) = self.observer {
            let text = observer.fingerprint();
            h.write(b"observed");
            h.write(&(text.len() as u64).to_le_bytes());
            h.write(text.as_bytes());
        }
        format!("{:016x}", h.finish())
    }
}

impl<L> ParticleRecord<L> {
    /// A particle that failed before its first step (it could not be drawn, built or planned):
    /// no work, no samples.
    fn not_started(
        index: u64,
        spec: Option<super::ParticleSpec<L>>,
        end: Option<crate::particle::State>,
        error: &dyn std::fmt::Display,
    ) -> Self {
        ParticleRecord {
            index,
            spec,
            fate: Fate::Failed {
                error: error.to_string(),
            },
            end,
            stats: RunStats::default(),
            integrator: IntegratorReport::default(),
            samples: Vec::new(),
            observed: serde_json::Value::Null,
        }
    }
}

/// The text of a failed particle's error. Every error displays only numbers of the model,
/// except the step budget's, which also shows the wall time spent: the record keeps the
/// steps and the time reached, so that it stays the same on any machine and any load.
fn failure_text(error: &StepError) -> String {
    match error {
        StepError::BudgetExceeded { steps, t, .. } => format!("step budget exceeded after {steps} steps at t = {t}"),
        other => other.to_string(),
    }
}

/// A particle between two cuts of its run ([`Case::launch`], [`Case::advance`]): drawn, built
/// and planned, with its integrator memory and where its last segment ended.
pub struct InFlight<J: Injector, M> {
    index: u64,
    spec: super::ParticleSpec<J::Law>,
    particle: Particle<Softness<J::Law>, J::Drag>,
    plan: Plan,
    memory: M,
    start: State,
    last: Option<RunEnd>,
    samples: Vec<State>,
}

impl<J: Injector, M> InFlight<J, M> {
    /// The particle's index.
    pub fn index(&self) -> u64 {
        self.index
    }

    /// Accepted steps so far.
    pub fn steps(&self) -> u64 {
        self.last.as_ref().map_or(0, |o| o.stats.steps)
    }
}

/// What identifies a run: its seed, its number of particles and a fingerprint of everything
/// else that determines the results. Built by [`super::Fingerprint`] from typed parts.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RunConfig {
    /// Run seed s; particle k draws from [`super::particle_rng`]`(s, k)`.
    pub seed: u64,
    /// Number of particles N (indices 0..N).
    pub particles: u64,
    /// Text that determines the case beyond the integrator, the plan and the contact model:
    /// the flow field's identity, the boundary and the injector's parameters (e.g. the scene
    /// file and the mesh's time directory). The runner cannot see these itself: a mesh's
    /// `Debug` text would be as large as the mesh. Resuming or merging checks it through [`Case::config_hash`].
    pub fingerprint: String,
}

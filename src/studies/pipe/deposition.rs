//! Deposition studies: the cases of one aspect ratio as one population of the runner
//! ([`crate::population`]), each particle tracked until it touches the wall.

use super::orbit::jeffery_period;
use super::setup::PipeSetup;
use super::study::{DT0, PipeCase, SETTLING_TIMES};
#[cfg(doc)]
use super::tracking::track_to_deposition;
use super::tracking::{Deposition, ShapeStats};
use crate::contact::PipeWall;
use crate::diagnostics::{Monitor, Validity};
use crate::driver::AcceptedStep;
use crate::driver::Plan;
use crate::error::{ParamError, StepError};
use crate::flow::analytic::Poiseuille;
use crate::hydro::Brenner;
use crate::material::{NeoHooke, Softness};
use crate::particle::{Particle, State};
use crate::population::{
    Case, Fate, Fingerprint, Injector, Observer, ParticleRecord, ParticleRng, ParticleSpec, ParticleTemplate,
    RunOptions, Shard, Watch,
};
use crate::studies::StudyError;

/// Deposition runs at rtol = atol = `tol`, recording `per_orbit` samples per Jeffery period
/// at the release point (0: release and contact only), as [`track_to_deposition`] does. The
/// cases of one aspect ratio share their nondimensional flow, wall and fluid, and run as one
/// population ([`crate::population`]; particle k is the k-th case of that λ₁, in the order
/// given); a particle still free at its time limit is [`StudyError::NotDeposited`], one that
/// failed [`StudyError::ParticleFailed`].
pub fn deposition_study(
    cases: &[PipeCase],
    tol: f64,
    per_orbit: f64,
) -> Result<Vec<(PipeSetup, Deposition)>, StudyError> {
    let setups = cases.iter().map(PipeCase::setup).collect::<Result<Vec<_>, _>>()?;
    for setup in &setups {
        let gap = setup
            .observe(&setup.initial_state().map_err(crate::error::StepError::from)?)
            .gap;
        if gap <= 0.0 {
            return Err(StudyError::ReleasedInWall { gap });
        }
    }
    let mut runs: Vec<Option<Deposition>> = vec![None; cases.len()];
    let mut lambdas: Vec<f64> = Vec::new();
    for case in cases {
        if !lambdas.iter().any(|l| l.to_bits() == case.lambda1.to_bits()) {
            lambdas.push(case.lambda1);
        }
    }
    for lambda1 in lambdas {
        let mine: Vec<usize> = (0..cases.len())
            .filter(|&j| cases[j].lambda1.to_bits() == lambda1.to_bits())
            .collect();
        let group: Vec<&PipeSetup> = mine.iter().map(|&j| &setups[j]).collect();
        let first = group[0];
        let injection = CaseInjector { setups: &group };
        let observer = Observe {
            record_dt: jeffery_period(lambda1, 1.0) / per_orbit,
        };
        let integrator = first.integrator(tol)?;
        // Each particle's time limit is its own ([`CaseInjector::plan`]).
        let plan = Plan::new(1.0, DT0)?;
        let case = Case::new(&integrator, &first.flow, &first.wall, &injection, plan).with_observer(&observer);
        let config = Fingerprint::new("pipe deposition")
            .particles(&mine.iter().map(|&j| cases[j]).collect::<Vec<_>>())
            .config(0, group.len() as u64);
        let output = crate::population::run(&case, &config, Shard::ALL, &RunOptions::default().quiet())?;
        for record in output.records {
            let j = mine[record.index as usize];
            runs[j] = Some(deposition(&setups[j], record)?);
        }
    }
    Ok(setups
        .into_iter()
        .zip(runs)
        .map(|(setup, run)| (setup, run.expect("every case is run")))
        .collect())
}

/// The setup's reading of a population record: a deposit is the run to the wall, anything
/// else an error.
fn deposition(setup: &PipeSetup, record: ParticleRecord<NeoHooke>) -> Result<Deposition, StudyError> {
    let end = match (&record.fate, record.end) {
        (Fate::Deposited { .. }, Some(end)) => end,
        (Fate::Suspended, Some(end)) => {
            return Err(StudyError::NotDeposited {
                t_max: end.t,
                gap: setup.observe(&end).gap,
            });
        }
        (Fate::Failed { error }, _) => return Err(StudyError::ParticleFailed { error: error.clone() }),
        (fate, _) => {
            return Err(StudyError::Population(format!(
                "a pipe particle cannot be {}",
                fate.label()
            )));
        }
    };
    let log: Log = record.summary()?;
    let start = setup.initial_state().map_err(crate::error::StepError::from)?;
    let samples = std::iter::once(&start)
        .chain(&log.states)
        .chain(std::iter::once(&end))
        .map(|s| setup.observe(s))
        .collect();
    Ok(Deposition {
        samples,
        steps: record.stats.steps,
        rejected: record.stats.rejected,
        shape: log.shape,
        validity: log.validity,
    })
}

/// The released particles of cases that share their flow: particle k is the k-th setup's,
/// released stress-free at x₀ with the fluid's velocity, until 50 settling times of the
/// volume-equivalent sphere.
struct CaseInjector<'s> {
    setups: &'s [&'s PipeSetup],
}

impl Injector for CaseInjector<'_> {
    type Law = NeoHooke;
    type Drag = Brenner;

    fn draw(&self, index: u64, _rng: &mut ParticleRng) -> Result<ParticleSpec<NeoHooke>, StepError> {
        let setup = self.setups[index as usize];
        let start = setup.initial_state()?;
        Ok(ParticleSpec {
            shape: *setup.particle.shape(),
            softness: *setup.particle.material(),
            density: setup.particle.rho_solid(),
            position: start.x,
            velocity: start.v,
        })
    }

    fn particle(&self, spec: &ParticleSpec<NeoHooke>) -> Result<Particle<Softness<NeoHooke>, Brenner>, ParamError> {
        let p = &self.setups[0].particle;
        ParticleTemplate::new(*p.drag(), *p.fluid(), *p.gravity())?
            .with_volumetric(p.volumetric())
            .with_forces(p.forces().clone())
            .build(spec)
    }

    fn plan(&self, index: u64, _spec: &ParticleSpec<NeoHooke>, _plan: &Plan) -> Result<Plan, ParamError> {
        let t_max = SETTLING_TIMES * self.setups[index as usize].sphere_settling_time();
        Plan::new(t_max, DT0)
    }
}

/// What a deposition run keeps besides its fate: the recorded states (between release and
/// contact), the shape averages and the validity maxima.
#[derive(serde::Serialize, serde::Deserialize)]
struct Log {
    states: Vec<State>,
    shape: ShapeStats,
    validity: Validity,
}

/// Records the first accepted step at or after each multiple of `record_dt` (∞: none).
struct Observe {
    record_dt: f64,
}

impl Observer<Particle<Softness<NeoHooke>, Brenner>, Poiseuille, PipeWall> for Observe {
    fn fingerprint(&self) -> String {
        format!("pipe states every {:?}, shape averages, validity", self.record_dt)
    }

    fn watch<'w>(
        &'w self,
        particle: &'w Particle<Softness<NeoHooke>, Brenner>,
        flow: &'w Poiseuille,
        boundary: &'w PipeWall,
        start: &State,
    ) -> Box<dyn Watch + 'w> {
        let mut watching = Watching {
            particle,
            monitor: Monitor::new(particle, flow, boundary),
            shape: ShapeStats::default(),
            states: Vec::new(),
            record_dt: self.record_dt,
            next_record: self.record_dt,
        };
        watching.see(start);
        Box::new(watching)
    }
}

struct Watching<'w> {
    particle: &'w Particle<Softness<NeoHooke>, Brenner>,
    monitor: Monitor<'w, Softness<NeoHooke>, Brenner, Poiseuille, PipeWall>,
    shape: ShapeStats,
    states: Vec<State>,
    record_dt: f64,
    next_record: f64,
}

impl Watching<'_> {
    fn see(&mut self, state: &State) {
        let frame = self.particle.frame(&state.f);
        self.shape.add(&frame, state.t);
        self.monitor.observe(state);
    }
}

impl Watch for Watching<'_> {
    fn step(&mut self, step: &AcceptedStep) {
        let state = *step.state();
        self.shape.add(step.frame(), state.t);
        self.monitor.observe_step(step);
        if state.t >= self.next_record {
            self.states.push(state);
            self.next_record = state.t + self.record_dt;
        }
    }

    fn finish(mut self: Box<Self>, _fate: &Fate, _end: &State) -> serde_json::Value {
        let log = Log {
            states: std::mem::take(&mut self.states),
            shape: self.shape,
            validity: self.monitor.validity(),
        };
        serde_json::to_value(&log).expect("a pipe log is plain data")
    }
}

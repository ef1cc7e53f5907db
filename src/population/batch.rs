//! The time-synchronous batch runner: every live particle advanced through one time window,
//! then the flow's window slides ([`crate::flow::openfoam::TransientFlow`]), so a transient
//! field holds two or three levels whatever the number of its levels, where the
//! particle-major runner ([`super::run`]) would need all of them.
//!
//! # Same fates, not the same bits
//! A particle's run is [`Case::run_particle`]'s cut at the window ends ([`Case::advance`]):
//! the driver lands a step on each end and [`crate::driver::resume`] continues with the step
//! size it proposed and the integrator's memory. Only the landing steps differ from an uncut
//! run, by the truncation error of a step (the step control's tolerance), so on a steady field
//! the fates are those of [`super::run`] (tested), and positions and times agree to the
//! tolerance, not bit for bit.
//!
//! # Reproducible for any thread count, shard layout and restart
//! Within a window each particle's segment is a pure function of its state, memory and step at
//! the window's start, which are functions of (case, seed, index, windows): the records are the
//! same bit for bit on any number of threads and for any sharding ([`super::Shard`], merged by
//! [`super::RunOutput::merge`]). Finished records are checkpointed at every window end
//! ([`super::checkpoint`], atomic chunks). A resumed run skips them and runs the others from
//! their seeds through the windows again: the records of a killed and resumed run are those
//! of an uninterrupted one, and a kill costs the work on the particles in flight (their
//! integrator memories are not written: see [`super::checkpoint`] for why).
//!
//! # Work
//! The cuts add the landing steps (4 % more steps with 15 windows on the settling pipe), and
//! each particle's segment starts a contact event anew; the particle-steps per second were
//! 1.08 and 1.19 of the particle-major runner's in two runs on one thread (the test
//! `batch_fates_are_the_runners_on_a_steady_field` prints them).

use super::case::{Case, InFlight, RunConfig};
use super::checkpoint::Checkpoint;
use super::output::RunOutput;
use super::progress::Reporter;
use super::record::ParticleRecord;
use super::runner::{RunOptions, patch_names};
use super::shard::Shard;
use super::spec::Injector;
use super::{FORMAT, Fingerprint, PopulationError};
use crate::contact::{Boundary, ContactModel};
use crate::driver::Plan;
use crate::error::FlowError;
use crate::flow::{FlowField, FlowSample};
use crate::integrator::Stepper;
use crate::material::Softness;
use crate::tensor::Vec3;
use rayon::prelude::*;
use std::collections::BTreeMap;

/// A flow whose time window can slide: a transient field held window by window, or a steady
/// field ([`Steady`]).
pub trait Sliding: FlowField {
    /// Why a window cannot be held ([`std::convert::Infallible`] for a field that always can;
    /// [`crate::flow::openfoam::FoamError`] for a transient OpenFOAM field). A batch run returns
    /// it as the source of [`PopulationError::Slide`].
    type Error: std::error::Error + Send + Sync + 'static;

    /// Hold the field for the times of [start, end].
    fn slide(&mut self, start: f64, end: f64) -> Result<(), Self::Error>;
}

/// A steady field: every window is the same.
#[derive(Debug, Clone, Copy)]
pub struct Steady<'f, F: ?Sized>(pub &'f F);

impl<F: FlowField + ?Sized> FlowField for Steady<'_, F> {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        self.0.sample(x, t)
    }

    fn strain_rate(&self) -> Option<f64> {
        self.0.strain_rate()
    }

    fn image(&self, x: &Vec3, t: f64) -> Option<crate::flow::Crossing> {
        self.0.image(x, t)
    }
}

impl<F: FlowField + ?Sized> Sliding for Steady<'_, F> {
    type Error = std::convert::Infallible;

    fn slide(&mut self, _start: f64, _end: f64) -> Result<(), Self::Error> {
        Ok(())
    }
}

#[cfg(feature = "mesh")]
impl<F: crate::flow::openfoam::Windowed> Sliding for crate::flow::openfoam::TransientFlow<F> {
    type Error = crate::flow::openfoam::FoamError;

    fn slide(&mut self, start: f64, end: f64) -> Result<(), Self::Error> {
        crate::flow::openfoam::TransientFlow::slide(self, start, end)
    }
}

/// What every particle of a batch run shares ([`Case`] without the flow, which slides between
/// windows).
#[derive(Debug)]
pub struct Batch<'a, I, B: ?Sized, J> {
    integrator: &'a I,
    boundary: &'a B,
    injector: &'a J,
    plan: Plan,
    contact: ContactModel,
    samples: bool,
}

impl<'a, I, B, J> Batch<'a, I, B, J>
where
    I: Stepper<Softness<J::Law>, J::Drag> + std::fmt::Debug,
    B: Boundary + ?Sized,
    J: Injector,
{
    /// As [`Case::new`], without the flow.
    pub fn new(integrator: &'a I, boundary: &'a B, injector: &'a J, plan: Plan) -> Self {
        Self {
            integrator,
            boundary,
            injector,
            plan,
            contact: ContactModel::Extent,
            samples: false,
        }
    }

    /// As [`Case::with_contact`].
    pub fn with_contact(mut self, contact: ContactModel) -> Self {
        self.contact = contact;
        self
    }

    /// As [`Case::with_samples`].
    pub fn with_samples(mut self) -> Self {
        self.samples = true;
        self
    }

    /// The case of one window, over `flow`.
    pub fn case<'f, F: FlowField + ?Sized>(&'f self, flow: &'f F) -> Case<'f, I, F, B, J> {
        let case = Case::new(self.integrator, flow, self.boundary, self.injector, self.plan.clone())
            .with_contact(self.contact);
        if self.samples { case.with_samples() } else { case }
    }
}

/// The configuration of a batch run of `config` with window ends `windows`, whose hash its
/// checkpoints carry: the cuts change the landing steps, so the windows are part of what
/// determines the records (a merge of a batch run's shards checks against it).
pub fn batch_config(config: &RunConfig, windows: &[f64]) -> RunConfig {
    Fingerprint::of(config)
        .with("batch windows", windows)
        .config(config.seed, config.particles)
}

/// A particle launched ([`Case::launch`]), or its record if it could not be.
type Launched<J, M> = Result<InFlight<J, M>, ParticleRecord<<J as Injector>::Law>>;

/// Run shard `shard` of the population `config` window by window: `windows` = [t₀, t₁, ...,
/// t_n] (ascending, finite) are the window ends; every live particle is advanced to t₁, the
/// flow slides to [t₁, t₂], and so on. Particles still in flight at t_n are suspended there.
/// The first slide is to [t₀, t₁]; particles start at their own start times (usually t₀).
/// Checkpoints and resumption as in [`super::run`] (module docs); the checkpoint interval of
/// `options` is not used (every window end is a checkpoint); a stop request takes effect at
/// the next window end. Progress is reported as `options` says at every window end, in
/// particles: those finished, plus those in flight weighted by the share of the run's time
/// the windows have covered (most particles of a transient run may live to its end, and a
/// count of fates alone would stand still until then).
///
/// Records are returned by ascending index.
// As Case::launch: the in-flight particle is as large as the record.
#[allow(clippy::result_large_err)]
pub fn run_batch<I, W, B, J>(
    batch: &Batch<'_, I, B, J>,
    flow: &mut W,
    windows: &[f64],
    config: &RunConfig,
    shard: Shard,
    options: &RunOptions,
) -> Result<RunOutput<J::Law>, PopulationError>
where
    I: Stepper<Softness<J::Law>, J::Drag> + std::fmt::Debug,
    I::Memory: Send,
    W: Sliding,
    B: Boundary + ?Sized,
    J: Injector,
{
    if let Some(w) = windows
        .windows(2)
        .find(|w| !(w[0].is_finite() && w[1].is_finite() && w[0] < w[1]))
    {
        return Err(PopulationError::Window {
            start: w[0],
            end: w[1],
            reason: "window ends must be finite and ascending".into(),
        });
    }
    if windows.len() < 2 {
        return Err(PopulationError::Window {
            start: windows.first().copied().unwrap_or(f64::NAN),
            end: f64::NAN,
            reason: "at least two window ends are needed".into(),
        });
    }
    let config = batch_config(config, windows);
    let hash = batch.case(&*flow).config_hash(&config);
    let (mut checkpoint, done) = match &options.checkpoint {
        Some((dir, _)) => {
            let (cp, done) = Checkpoint::open(dir, &hash, (config.seed, config.particles), shard, options.resume)?;
            (Some(cp), done)
        }
        None => (None, BTreeMap::new()),
    };
    let mut records: BTreeMap<u64, ParticleRecord<J::Law>> = done;
    let total = shard.len(config.particles);
    let mut reporter = Reporter::start(
        options.progress,
        &format!("batch shard {shard}"),
        total,
        records.len() as u64,
    );
    let (first, last) = (windows[0], windows[windows.len() - 1]);
    let report = |reporter: &mut Reporter, finished: usize, live: usize, at: f64| {
        let done = finished as u64 + (live as f64 * (at - first) / (last - first)) as u64;
        reporter.update(done);
        if let Some(c) = &options.control {
            c.report(done, total);
        }
    };
    let indices: Vec<u64> = (0..total)
        .map(|j| shard.index() + j * shard.count())
        .filter(|k| !records.contains_key(k))
        .collect();
    let launch = |k: &u64| batch.case(&*flow).launch(config.seed, *k);
    let launched: Vec<Launched<J, I::Memory>> = if options.parallel {
        indices.par_iter().map(launch).collect()
    } else {
        indices.iter().map(launch).collect()
    };
    let mut live = Vec::with_capacity(launched.len());
    let mut finished = Vec::new();
    for l in launched {
        match l {
            Ok(p) => live.push(p),
            Err(record) => finished.push(record),
        }
    }
    let names = |r: &[ParticleRecord<J::Law>]| patch_names(batch.boundary, r);
    for w in windows.windows(2) {
        let (start, end) = (w[0], w[1]);
        flow.slide(start, end)
            .map_err(|e| PopulationError::slide(start, end, e))?;
        let case = batch.case(&*flow);
        let advance = |p: &mut InFlight<J, I::Memory>| case.advance(p, end);
        let outcomes: Vec<Option<ParticleRecord<J::Law>>> = if options.parallel {
            live.par_iter_mut().map(advance).collect()
        } else {
            live.iter_mut().map(advance).collect()
        };
        let mut still = outcomes.iter().map(Option::is_none);
        live.retain(|_| still.next().unwrap_or(true));
        finished.extend(outcomes.into_iter().flatten());
        if let Some(cp) = &mut checkpoint
            && (!finished.is_empty() || cp.is_empty())
        {
            cp.write(&finished, &names(&finished))?;
        }
        records.extend(finished.drain(..).map(|r| (r.index, r)));
        report(&mut reporter, records.len(), live.len(), end);
        if options.control.as_ref().is_some_and(|c| c.stopped()) && end < windows[windows.len() - 1] {
            return Err(PopulationError::Interrupted {
                done: records.len() as u64,
                total,
            });
        }
    }
    // Still in flight at the last window end: suspended there.
    let case = batch.case(&*flow);
    let rest: Vec<ParticleRecord<J::Law>> = live.iter_mut().map(|p| case.suspend(p)).collect();
    if let Some(cp) = &mut checkpoint
        && !rest.is_empty()
    {
        cp.write(&rest, &names(&rest))?;
    }
    records.extend(rest.into_iter().map(|r| (r.index, r)));
    report(&mut reporter, records.len(), 0, last);
    reporter.finish(records.len() as u64);
    let records: Vec<_> = records.into_values().collect();
    Ok(RunOutput {
        format: FORMAT,
        config_hash: hash,
        seed: config.seed,
        particles: config.particles,
        shard,
        patches: names(&records),
        records,
    })
}

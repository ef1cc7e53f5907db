//! Running a population (or one shard of it): particles in parallel, results collected,
//! checkpointed and reported by one collector thread.

use super::FORMAT;
use super::PopulationError;
use super::case::{Case, RunConfig};
use super::checkpoint::Checkpoint;
use super::output::{RunOutput, checkpoint_dir};
use super::progress::{Progress, Reporter};
use super::record::ParticleRecord;
use super::shard::Shard;
use super::spec::Injector;
use crate::contact::Boundary;
use crate::flow::FlowField;
use crate::integrator::Stepper;
use crate::material::Softness;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, mpsc};
use std::time::{Duration, Instant};

/// How to run: in parallel or serially, with which progress report, with or without
/// checkpoints.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOptions {
    pub(super) parallel: bool,
    pub(super) progress: Progress,
    pub(super) checkpoint: Option<(PathBuf, Duration)>,
    pub(super) resume: bool,
    pub(super) control: Option<Arc<RunControl>>,
}

/// A handle on a running population from another thread: how far it is, and a request to
/// stop (a caller's Ctrl-C). A stopped run starts no new particle, checkpoints the finished
/// ones and returns [`PopulationError::Interrupted`]; `resume` continues it.
#[derive(Debug, Default)]
pub struct RunControl {
    done: AtomicU64,
    total: AtomicU64,
    stop: AtomicBool,
}

impl RunControl {
    /// Particles of the run's shard finished so far (resumed ones included), and its total.
    pub fn progress(&self) -> (u64, u64) {
        (self.done.load(Ordering::Relaxed), self.total.load(Ordering::Relaxed))
    }

    /// Ask the run to stop after the particles in flight.
    pub fn stop(&self) {
        self.stop.store(true, Ordering::Relaxed);
    }

    /// Whether a stop was asked for.
    pub fn stopped(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    /// `done` of `total` particles are finished (the batch runner's report at a window end).
    pub(super) fn report(&self, done: u64, total: u64) {
        self.total.store(total, Ordering::Relaxed);
        self.done.store(done, Ordering::Relaxed);
    }
}

/// Two handles are equal when they are the same handle.
impl PartialEq for RunControl {
    fn eq(&self, other: &Self) -> bool {
        std::ptr::eq(self, other)
    }
}

impl Default for RunOptions {
    /// Parallel (rayon's current pool), [`Progress::Auto`], no checkpoints.
    fn default() -> Self {
        Self {
            parallel: true,
            progress: Progress::Auto,
            checkpoint: None,
            resume: false,
            control: None,
        }
    }
}

/// Checkpoint interval of [`RunOptions::with_checkpoints`] callers that have no better idea:
/// a minute of work at most is lost to a kill.
pub const CHECKPOINT_INTERVAL: Duration = Duration::from_secs(60);

impl RunOptions {
    /// Run the particles one after the other on the calling thread.
    pub fn serial(mut self) -> Self {
        self.parallel = false;
        self
    }

    /// Report progress as `progress` says.
    pub fn with_progress(mut self, progress: Progress) -> Self {
        self.progress = progress;
        self
    }

    /// No progress report.
    pub fn quiet(self) -> Self {
        self.with_progress(Progress::Quiet)
    }

    /// Write the finished records into `dir` every `interval` and at the end
    /// ([`super::checkpoint`]). An existing non-empty checkpoint there is an error unless
    /// [`RunOptions::resume`] is set.
    pub fn with_checkpoints(mut self, dir: impl AsRef<Path>, interval: Duration) -> Self {
        self.checkpoint = Some((dir.as_ref().to_path_buf(), interval));
        self
    }

    /// Continue from the checkpoint folder's records (a missing or empty folder starts afresh).
    /// Without checkpoints there is nothing to resume from, and this does nothing.
    pub fn resume(mut self, resume: bool) -> Self {
        self.resume = resume;
        self
    }

    /// Report progress to, and take stop requests from, `control` (besides [`Progress`]).
    pub fn with_control(mut self, control: Arc<RunControl>) -> Self {
        self.control = Some(control);
        self
    }
}

/// Run shard `shard` of the population `config` of `case` and return its records by
/// ascending index. Each particle is [`Case::run_particle`]; a particle that fails is recorded
/// as [`super::Fate::Failed`] and the run goes on. With checkpoints, finished records go to
/// disk as the run proceeds and a resumed run skips them; the results are bitwise the same
/// for any number of threads, serial or parallel, with or without restarts, and for the
/// merge of any sharding ([`RunOutput::merge`]).
///
/// Parallel runs use the current rayon pool: call inside `pool.install(..)` to choose one.
pub fn run<I, F, B, J>(
    case: &Case<'_, I, F, B, J>,
    config: &RunConfig,
    shard: Shard,
    options: &RunOptions,
) -> Result<RunOutput<J::Law>, PopulationError>
where
    I: Stepper<Softness<J::Law>, J::Drag> + std::fmt::Debug,
    F: FlowField + ?Sized,
    B: Boundary + ?Sized,
    J: Injector,
{
    let hash = case.config_hash(config);
    let (checkpoint, done) = match &options.checkpoint {
        Some((dir, interval)) => {
            let (cp, done) = Checkpoint::open(dir, &hash, (config.seed, config.particles), shard, options.resume)?;
            (Some((cp, *interval)), done)
        }
        None => (None, BTreeMap::new()),
    };
    let total = shard.len(config.particles);
    // The j-th particle of the shard; those in the checkpoint are skipped by the workers, so
    // nothing of size N is allocated up front.
    let (first, stride) = (shard.index(), shard.count());
    let finished: std::collections::BTreeSet<u64> = done.keys().copied().collect();
    let label = format!("population shard {shard}");
    let reporter = Reporter::start(options.progress, &label, total, done.len() as u64);
    let abort = AtomicBool::new(false);
    let control = options.control.as_deref();
    if let Some(c) = control {
        c.total.store(total, Ordering::Relaxed);
        c.done.store(done.len() as u64, Ordering::Relaxed);
    }
    let stopped = || control.is_some_and(RunControl::stopped);
    let (tx, rx) = mpsc::channel::<ParticleRecord<J::Law>>();
    let names = |records: &[ParticleRecord<J::Law>]| patch_names(case.boundary(), records);
    let collected = std::thread::scope(|scope| {
        let collector = scope.spawn(|| collect(rx, done, checkpoint, &names, reporter, &abort, control));
        let work = |tx: &mut mpsc::Sender<ParticleRecord<J::Law>>, j: u64| {
            let k = first + j * stride;
            if abort.load(Ordering::Relaxed) || stopped() || finished.contains(&k) {
                return;
            }
            // A closed channel means the collector failed; its error is reported below.
            let _ = tx.send(case.run_particle(config.seed, k));
        };
        if options.parallel {
            (0..total).into_par_iter().for_each_with(tx, |tx, j| work(tx, j));
        } else {
            let mut tx = tx;
            (0..total).for_each(|j| work(&mut tx, j));
        }
        collector.join()
    });
    let records = match collected {
        Ok(result) => result?,
        Err(panic) => std::panic::resume_unwind(panic),
    };
    if (records.len() as u64) < total && stopped() {
        return Err(PopulationError::Interrupted {
            done: records.len() as u64,
            total,
        });
    }
    let patches = names(&records);
    Ok(RunOutput {
        format: FORMAT,
        config_hash: hash,
        seed: config.seed,
        particles: config.particles,
        shard,
        patches,
        records,
    })
}

/// Names of patches 0..=p, p the largest patch index of `records` (none: empty).
pub(super) fn patch_names<B: Boundary + ?Sized, L>(boundary: &B, records: &[ParticleRecord<L>]) -> Vec<String> {
    match records.iter().filter_map(|r| r.fate.patch()).max() {
        Some(max) => (0..=max).map(|p| boundary.patch_name(p).to_string()).collect(),
        None => Vec::new(),
    }
}

/// [`run`] in the standard layout of an output folder `dir`: checkpoints in
/// [`checkpoint_dir`]`(dir, shard)` (every [`CHECKPOINT_INTERVAL`], or the interval `options`
/// set; resumed if `options` say so). The checkpoint is the shard's only record file: a
/// finished shard's folder holds every record ([`RunOutput::read_checkpoint`]), and
/// [`RunOutput::merge_dir`] merges the shards of `dir`. Tables are the caller's
/// ([`RunOutput::table`], the command's Parquet files).
pub fn run_in_dir<I, F, B, J>(
    case: &Case<'_, I, F, B, J>,
    config: &RunConfig,
    shard: Shard,
    dir: impl AsRef<Path>,
    options: &RunOptions,
) -> Result<RunOutput<J::Law>, PopulationError>
where
    I: Stepper<Softness<J::Law>, J::Drag> + std::fmt::Debug,
    F: FlowField + ?Sized,
    B: Boundary + ?Sized,
    J: Injector,
{
    let dir = dir.as_ref();
    let interval = options.checkpoint.as_ref().map_or(CHECKPOINT_INTERVAL, |(_, i)| *i);
    let options = options.clone().with_checkpoints(checkpoint_dir(dir, shard), interval);
    run(case, config, shard, &options)
}

/// Receive records until every worker is done: report progress, write a checkpoint chunk
/// every interval and at the end (an empty one if the folder has none yet: a finished shard
/// always leaves a chunk naming its run), and return all records by index. On a write error,
/// ask the workers to stop and return the error.
fn collect<L: serde::Serialize>(
    rx: mpsc::Receiver<ParticleRecord<L>>,
    mut done: BTreeMap<u64, ParticleRecord<L>>,
    mut checkpoint: Option<(Checkpoint, Duration)>,
    names: &(dyn Fn(&[ParticleRecord<L>]) -> Vec<String> + Sync),
    mut reporter: Reporter,
    abort: &AtomicBool,
    control: Option<&RunControl>,
) -> Result<Vec<ParticleRecord<L>>, PopulationError> {
    let mut pending: Vec<ParticleRecord<L>> = Vec::new();
    let mut next_flush = checkpoint.as_ref().map(|(_, interval)| Instant::now() + *interval);
    let flush = |pending: &mut Vec<ParticleRecord<L>>,
                 done: &mut BTreeMap<u64, ParticleRecord<L>>,
                 checkpoint: &mut Option<(Checkpoint, Duration)>,
                 last: bool|
     -> Result<(), PopulationError> {
        if let Some((cp, _)) = checkpoint
            && (!pending.is_empty() || (last && cp.is_empty()))
        {
            cp.write(pending, &names(pending))?;
        }
        done.extend(pending.drain(..).map(|r| (r.index, r)));
        Ok(())
    };
    let result = loop {
        let now = Instant::now();
        // With nothing to flush, only a record (or a log line) is worth waking up for.
        let flush_due = next_flush.filter(|_| !pending.is_empty());
        let wait = [
            flush_due.map(|t| t.saturating_duration_since(now)),
            reporter.until_due(),
        ]
        .into_iter()
        .flatten()
        .min();
        let received = match wait {
            Some(w) => rx.recv_timeout(w),
            None => rx.recv().map_err(|_| mpsc::RecvTimeoutError::Disconnected),
        };
        match received {
            Ok(record) => pending.push(record),
            Err(mpsc::RecvTimeoutError::Timeout) => {}
            Err(mpsc::RecvTimeoutError::Disconnected) => break flush(&mut pending, &mut done, &mut checkpoint, true),
        }
        if let Some(t) = next_flush
            && Instant::now() >= t
        {
            if let Err(e) = flush(&mut pending, &mut done, &mut checkpoint, false) {
                break Err(e);
            }
            next_flush = checkpoint.as_ref().map(|(_, interval)| Instant::now() + *interval);
        }
        let finished = (done.len() + pending.len()) as u64;
        reporter.update(finished);
        if let Some(c) = control {
            c.done.store(finished, Ordering::Relaxed);
        }
    };
    if result.is_err() {
        abort.store(true, Ordering::Relaxed);
    }
    reporter.finish(done.len() as u64);
    result.map(|()| done.into_values().collect())
}

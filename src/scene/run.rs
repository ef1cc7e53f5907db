//! `run` and `merge`: a scene's particles through the population runner (parallel,
//! checkpointed, resumable, shardable), then its files.

use crate::material::NamedLaw;
use crate::population::batch::{Batch, Sliding, batch_config, run_batch};
use crate::population::{
    CHECKPOINT_INTERVAL, Fingerprint, PopulationError, Progress, RunConfig, RunOptions, RunOutput, Shard,
    checkpoint_dir, run_in_dir,
};
use crate::scene::Scene;
use crate::scene::adequacy::{Adequacy, adequacy};
use crate::scene::error::SceneError;
use crate::scene::frames::{csv_tables, write_run};
use crate::scene::models::{SceneFlow, SceneTransient, Windows};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// What to do with a scene's population.
#[derive(Debug, Clone)]
pub enum Job {
    /// Run shard `shard` with `options` in `dir` (the population runner's layout: result file
    /// and checkpoint folder of the shard).
    Run {
        /// The shard ([`Shard::ALL`]: the whole run).
        shard: Shard,
        /// Parallelism, progress, checkpoint interval and resume.
        options: RunOptions,
        /// Output folder.
        dir: PathBuf,
    },
    /// Run shard `shard` with `options` in memory: no files (a notebook's small runs).
    Memory {
        /// The shard ([`Shard::ALL`]: the whole run).
        shard: Shard,
        /// Parallelism and progress (checkpoints are not used).
        options: RunOptions,
    },
    /// Merge the shard checkpoints in `dir`.
    Merge {
        /// Output folder of the shards.
        dir: PathBuf,
    },
}

impl Scene {
    /// The population's identity: seed, size, the scene text and the fingerprints of the flow
    /// and the boundary as loaded ([`crate::scene::models::SceneFlow::fingerprint`], [`crate::scene::models::SceneBoundary::fingerprint`]):
    /// the scene text names an OpenFOAM case by path and time, which may hold another field
    /// by the next run; the fingerprints say what was read.
    pub fn config(&self) -> RunConfig {
        Fingerprint::new(self.text.as_str())
            .flow(&self.flow)
            .boundary(&self.boundary)
            .config(self.seed, self.count())
    }

    /// Output times of the frames: the start and every output time.
    pub fn frame_times(&self) -> Vec<f64> {
        std::iter::once(0.0).chain(self.outputs.iter().copied()).collect()
    }

    /// Do `job` with this scene's integrator: on a steady flow with the particle-major
    /// runner ([`crate::population::run`]), on a transient OpenFOAM field with the batch
    /// runner ([`run_batch`]) over the windows of [`Scene::windows`].
    pub fn population(&self, job: &Job) -> Result<RunOutput<NamedLaw>, SceneError> {
        if let SceneFlow::Transient(field) = &self.flow {
            return self.batch_population(field, job);
        }
        let injector = self.injector();
        let case = self.case(&injector).with_samples();
        let config = self.config();
        match job {
            Job::Run { shard, options, dir } => Ok(run_in_dir(&case, &config, *shard, dir, options)?),
            Job::Memory { shard, options } => Ok(crate::population::run(&case, &config, *shard, options)?),
            Job::Merge { dir } => merged(dir, case.config_hash(&config)),
        }
    }
}

impl Scene {
    /// The window ends of a run on a transient field, from 0 to `end.t_end`
    /// ([`SceneTransient::window_ends`]); `None` on a steady flow.
    pub fn windows(&self) -> Option<Vec<f64>> {
        match &self.flow {
            SceneFlow::Transient(field) => Some(field.window_ends(self.plan.t_end())),
            _ => None,
        }
    }

    /// What a run on a transient field reads and how it cuts time, for the run log: the
    /// levels, their cycle and storage, and the windows. `None` on a steady flow.
    pub fn flow_log(&self) -> Option<String> {
        let SceneFlow::Transient(field) = &self.flow else {
            return None;
        };
        let windows = field.window_ends(self.plan.t_end()).len() - 1;
        Some(field.with_field(|f| {
            let levels = f.levels();
            format!(
                "flow.time: transient field, {} levels from t = {} to {}{}; {windows} windows of {:.6} to t_end = {}",
                levels.len(),
                levels[0],
                levels[levels.len() - 1],
                match f.cycle() {
                    crate::flow::openfoam::Cycle::Once => String::new(),
                    crate::flow::openfoam::Cycle::Periodic { period } => format!(", repeated with period {period}"),
                },
                field.window(),
                self.plan.t_end()
            )
        }))
    }

    /// [`Scene::population`] on the transient `field`, window by window.
    fn batch_population(&self, field: &SceneTransient, job: &Job) -> Result<RunOutput<NamedLaw>, SceneError> {
        let _exclusive = field.run();
        let injector = self.injector();
        let batch = Batch::new(&self.integrator, &self.boundary, &injector, self.plan.clone())
            .with_contact(self.contact)
            .with_samples();
        let windows = field.window_ends(self.plan.t_end());
        let config = self.config();
        let run = |shard: Shard, options: &RunOptions| -> Result<RunOutput<NamedLaw>, SceneError> {
            let mut flow = Windows(field);
            // The first window before any particle is launched (its fluid velocity is sampled
            // at t = 0); the runner's own first slide then keeps these levels. A run before
            // this one may have left the field at its last window.
            flow.slide(windows[0], windows[1])
                .map_err(|e| PopulationError::slide(windows[0], windows[1], e))?;
            Ok(run_batch(&batch, &mut flow, &windows, &config, shard, options)?)
        };
        match job {
            Job::Run { shard, options, dir } => run(
                *shard,
                &options
                    .clone()
                    .with_checkpoints(checkpoint_dir(dir, *shard), CHECKPOINT_INTERVAL),
            ),
            Job::Memory { shard, options } => run(*shard, options),
            Job::Merge { dir } => merged(
                dir,
                batch
                    .case(&Windows(field))
                    .config_hash(&batch_config(&config, &windows)),
            ),
        }
    }
}

/// The shards' outputs in `dir` merged ([`RunOutput::merge_dir`]), refused unless they are of
/// the run whose configuration hash is `expected`.
fn merged(dir: &Path, expected: String) -> Result<RunOutput<NamedLaw>, SceneError> {
    let merged = RunOutput::merge_dir(dir)?;
    if merged.config_hash != expected {
        return Err(PopulationError::ConfigMismatch {
            path: Some(dir.to_path_buf()),
            expected,
            found: merged.config_hash,
        }
        .into());
    }
    Ok(merged)
}

/// The options of the command's `run`: checkpoints in `out` every `checkpoint_every` seconds
/// (> 0), resumed if `resume`, progress as `progress` says.
pub fn run_options(
    out: &Path,
    checkpoint_every: f64,
    resume: bool,
    progress: Progress,
) -> Result<RunOptions, SceneError> {
    let interval = Duration::try_from_secs_f64(checkpoint_every)
        .ok()
        .filter(|d| !d.is_zero())
        .ok_or_else(|| SceneError::Input(format!("--checkpoint-every {checkpoint_every}: need seconds > 0")))?;
    Ok(RunOptions::default()
        .with_progress(progress)
        // The folder is the runner's own (`checkpoint-<k>-of-<N>` in `out`).
        .with_checkpoints(out, interval)
        .resume(resume))
}

/// A finished [`run`]: the command's one-line summary, the records it wrote (which a
/// caller such as the Python package hands on without reading the files back) and the
/// mesh-adequacy diagnostic of a run on an OpenFOAM field.
#[derive(Debug)]
pub struct Finished {
    /// The summary line.
    pub summary: String,
    /// The run's (or shard's) records, as its checkpoint holds them.
    pub output: RunOutput<NamedLaw>,
    /// The mesh-adequacy diagnostic ([`crate::scene::adequacy`]; `None` on an analytic flow): of a
    /// whole run also in `adequacy.json`; a shard's has no re-track (`merge` does it).
    pub adequacy: Option<Adequacy>,
}

/// [`run`] on `threads` worker threads (`None`: rayon's global pool, all cores).
pub fn run_on(
    scene: &Scene,
    out: &Path,
    shard: Shard,
    options: RunOptions,
    threads: Option<usize>,
    csv: bool,
) -> Result<Finished, SceneError> {
    match threads {
        None => run(scene, out, shard, options, csv),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| SceneError::Input(format!("--threads {n}: {e}")))?
            .install(|| run(scene, out, shard, options, csv)),
    }
}

/// Run `scene` (or one shard of it) into `out`: the shard's checkpoint
/// ([`crate::population::checkpoint_dir`]: the only file of its records) and tables. A whole
/// run writes its tables and frames ([`write_run`]). Shard k of N writes, with the feature
/// `parquet`, `records/part-k-of-N.parquet` and `frames/part-k-of-N.parquet`, and with CSV
/// ([`csv_tables`]) `results-k-of-N.csv`. Returns a one-line summary, the records and, on an
/// OpenFOAM field, the mesh-adequacy diagnostic ([`adequacy`], computed after the run from its
/// records: the run's files are those of a run without it; a whole run writes it to
/// `adequacy.json`, a shard leaves the re-track to [`merge`]).
pub fn run(scene: &Scene, out: &Path, shard: Shard, options: RunOptions, csv: bool) -> Result<Finished, SceneError> {
    let output = scene.population(&Job::Run {
        shard,
        options,
        dir: out.to_path_buf(),
    })?;
    let counts = output.counts();
    let steps = output.records.iter().map(|r| r.stats.steps).sum();
    let what = format!(
        "{} particles: {} deposited, {} escaped, {} suspended, {} failed{}",
        counts.total(),
        counts.deposited,
        counts.escaped,
        counts.suspended,
        counts.failed,
        output.integrator().summary(steps)
    );
    let whole = shard == Shard::ALL;
    let adequacy = adequacy(scene, &output.records, !whole)?;
    let summary = if whole {
        let frames = write_run(&output, &scene.frame_times(), scene.vtk, csv, out)?;
        match &adequacy {
            Some(a) => a.write(out)?,
            // A diagnostic of an earlier run into the same folder would speak for this one.
            None => crate::scene::adequacy::remove(out)?,
        }
        format!("{what}; {frames} frames in {}", out.display())
    } else {
        // A shard's tables go into `records/` and `frames/`: each folder reads as one dataset
        // (pyarrow, polars, pandas) over all shards without a merge.
        #[cfg(feature = "parquet")]
        {
            let name = format!("part-{:04}-of-{:04}.parquet", shard.index(), shard.count());
            crate::scene::parquet::write_records(&output, &out.join("records").join(&name))?;
            crate::scene::parquet::write_frames(&output, &scene.frame_times(), &out.join("frames").join(&name))?;
        }
        if csv_tables(csv) {
            let name = format!("results-{:04}-of-{:04}.csv", shard.index(), shard.count());
            output.table()?.write(out.join(name))?;
        }
        format!(
            "shard {shard}: {what}; records in {}",
            checkpoint_dir(out, shard).display()
        )
    };
    Ok(Finished {
        summary,
        output,
        adequacy,
    })
}

/// Merge the shard checkpoints in `out` into the whole run's tables and frames, and on an
/// OpenFOAM field the whole run's mesh-adequacy diagnostic (`adequacy.json`, with the re-track
/// the shards left out). Returns the lines to print: the diagnostic's, then a summary.
pub fn merge(scene: &Scene, out: &Path, csv: bool) -> Result<String, SceneError> {
    let output = scene.population(&Job::Merge { dir: out.to_path_buf() })?;
    let frames = write_run(&output, &scene.frame_times(), scene.vtk, csv, out)?;
    let adequacy = adequacy(scene, &output.records, false)?;
    match &adequacy {
        Some(a) => a.write(out)?,
        None => crate::scene::adequacy::remove(out)?,
    }
    Ok(format!(
        "{}merged {} particles; {frames} frames in {}",
        adequacy.as_ref().map_or(String::new(), Adequacy::log),
        output.records.len(),
        out.display()
    ))
}

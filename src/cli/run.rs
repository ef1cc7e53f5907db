//! `run` and `merge`: a scene's particles through the population runner (parallel,
//! checkpointed, resumable, shardable), then its files.

use super::error::CliError;
use super::frames::write_run;
use super::models::SceneLaw;
use super::scene::{Scene, SceneIntegrator};
use crate::integrator::TimeIntegrator;
use crate::population::{Case, PopulationError, RunConfig, RunOptions, RunOutput, Shard, result_path, run_in_dir};
use std::path::{Path, PathBuf};

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
    /// Merge the shard result files in `dir`.
    Merge {
        /// Output folder of the shards.
        dir: PathBuf,
    },
}

impl Scene {
    /// The population's identity: seed, size and the scene text.
    pub fn config(&self) -> RunConfig {
        RunConfig {
            seed: self.seed,
            particles: self.count(),
            fingerprint: self.text.clone(),
        }
    }

    /// Output times of the frames: the start and every output time.
    pub fn frame_times(&self) -> Vec<f64> {
        std::iter::once(0.0).chain(self.outputs.iter().copied()).collect()
    }

    /// Do `job` with this scene's integrator.
    pub fn population(&self, job: &Job) -> Result<RunOutput<SceneLaw>, CliError> {
        match &self.integrator {
            SceneIntegrator::Imex(i) => self.population_with(i, job),
            SceneIntegrator::ImexAdaptive(i) => self.population_with(i, job),
            SceneIntegrator::Stokesian(i) => self.population_with(i, job),
        }
    }

    fn population_with<I: TimeIntegrator + std::fmt::Debug>(
        &self,
        integrator: &I,
        job: &Job,
    ) -> Result<RunOutput<SceneLaw>, CliError> {
        let injector = self.injector();
        let case = Case::new(integrator, &self.flow, &self.boundary, &injector, self.plan.clone())
            .with_contact(self.contact)
            .with_samples();
        let config = self.config();
        match job {
            Job::Run { shard, options, dir } => Ok(run_in_dir(&case, &config, *shard, dir, options)?),
            Job::Merge { dir } => {
                let merged = RunOutput::merge_dir(dir)?;
                let expected = case.config_hash(&config);
                if merged.config_hash != expected {
                    return Err(PopulationError::ConfigMismatch {
                        path: Some(dir.clone()),
                        expected,
                        found: merged.config_hash,
                    }
                    .into());
                }
                Ok(merged)
            }
        }
    }
}

/// Run `scene` (or one shard of it) into `out`: the shard's result file and checkpoint
/// ([`crate::population::result_path`], [`crate::population::checkpoint_dir`]); a whole run
/// also writes `results.json`, `results.csv` and its frames. Returns a one-line summary.
pub fn run(scene: &Scene, out: &Path, shard: Shard, options: RunOptions) -> Result<String, CliError> {
    let output = scene.population(&Job::Run {
        shard,
        options,
        dir: out.to_path_buf(),
    })?;
    let counts = output.counts();
    let what = format!(
        "{} particles: {} deposited, {} escaped, {} suspended, {} failed",
        counts.total(),
        counts.deposited,
        counts.escaped,
        counts.suspended,
        counts.failed
    );
    if shard == Shard::ALL {
        let frames = write_run(&output, &scene.frame_times(), scene.vtk, out)?;
        Ok(format!("{what}; {frames} frames in {}", out.display()))
    } else {
        Ok(format!(
            "shard {shard}: {what}; written to {}",
            result_path(out, shard).display()
        ))
    }
}

/// Merge the shard result files in `out` into the whole run's files and frames.
pub fn merge(scene: &Scene, out: &Path) -> Result<String, CliError> {
    let output = scene.population(&Job::Merge { dir: out.to_path_buf() })?;
    let frames = write_run(&output, &scene.frame_times(), scene.vtk, out)?;
    Ok(format!(
        "merged {} particles; {frames} frames in {}",
        output.records.len(),
        out.display()
    ))
}

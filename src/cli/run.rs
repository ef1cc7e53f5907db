//! `run` and `merge`: a scene's particles through the population runner (parallel,
//! checkpointed, resumable, shardable), then its files.

use super::error::CliError;
use super::frames::write_run;
use super::models::SceneLaw;
use super::scene::{Scene, SceneIntegrator};
use crate::integrator::TimeIntegrator;
use crate::population::{Case, PopulationError, RunConfig, RunOptions, RunOutput, Shard};
use std::path::{Path, PathBuf};

/// What to do with a scene's population.
#[derive(Debug, Clone)]
pub enum Job {
    /// Run shard `shard` with `options`.
    Run {
        /// The shard ([`Shard::ALL`]: the whole run).
        shard: Shard,
        /// Parallelism, progress and checkpoints.
        options: RunOptions,
    },
    /// Merge these shard files.
    Merge {
        /// Shard result files.
        paths: Vec<PathBuf>,
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
            Job::Run { shard, options } => Ok(crate::population::run(&case, &config, *shard, options)?),
            Job::Merge { paths } => {
                let merged = RunOutput::merge_files(paths)?;
                let expected = case.config_hash(&config);
                if merged.config_hash != expected {
                    return Err(PopulationError::ConfigMismatch {
                        path: paths.first().cloned(),
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

/// `shard-<k>-of-<N>.json`.
pub fn shard_file(shard: Shard) -> String {
    format!("shard-{}-of-{}.json", shard.index(), shard.count())
}

/// Checkpoint folder of `shard` in `out`.
pub fn checkpoint_dir(out: &Path, shard: Shard) -> PathBuf {
    if shard == Shard::ALL {
        out.join("checkpoint")
    } else {
        out.join(format!("checkpoint-{}-of-{}", shard.index(), shard.count()))
    }
}

/// Run `scene` (or one shard of it) into `out`. A whole run writes its results and frames; a
/// shard writes its result file for [`merge`]. Returns a one-line summary.
pub fn run(scene: &Scene, out: &Path, shard: Shard, options: RunOptions) -> Result<String, CliError> {
    let output = scene.population(&Job::Run { shard, options })?;
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
        let file = out.join(shard_file(shard));
        output.write_json(&file)?;
        Ok(format!("shard {shard}: {what}; written to {}", file.display()))
    }
}

/// Merge the shard files `shard-*-of-*.json` in `out` into the whole run's files.
pub fn merge(scene: &Scene, out: &Path) -> Result<String, CliError> {
    let entries = std::fs::read_dir(out).map_err(|source| CliError::Read {
        path: out.to_path_buf(),
        source,
    })?;
    let mut paths: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("shard-") && n.ends_with(".json"))
        })
        .collect();
    paths.sort();
    if paths.is_empty() {
        return Err(CliError::Input(format!(
            "no shard-*-of-*.json files in {}",
            out.display()
        )));
    }
    let output = scene.population(&Job::Merge { paths: paths.clone() })?;
    let frames = write_run(&output, &scene.frame_times(), scene.vtk, out)?;
    Ok(format!(
        "merged {} shards ({} particles); {frames} frames in {}",
        paths.len(),
        output.records.len(),
        out.display()
    ))
}

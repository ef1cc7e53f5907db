//! Running a scene: `run` (the command's files), `run_in_memory`, and `load_results` (a run's
//! records read back from its output folder).

use crate::drive::drive;
use crate::errors::{population_error, scene_error};
use crate::results::Results;
use crate::scene::PyScene;
use pseudorigid::material::NamedLaw;
use pseudorigid::population::{Progress, RunControl, RunOptions, RunOutput, Shard, checkpoint_dir};
use pseudorigid::scene::SceneError;
use pseudorigid::scene::run::{Job, run_on, run_options};
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;

fn shard_of(py: Python<'_>, shard: Option<(u64, u64)>) -> PyResult<Shard> {
    match shard {
        None => Ok(Shard::ALL),
        Some((k, n)) => Shard::new(k, n).map_err(|e| population_error(py, &e)),
    }
}

/// The command's `run` of `scene` into `out` (`csv`: as `--csv`): the same files, bitwise.
/// Returns the command's summary line and the records the run wrote (not read back).
#[pyfunction]
#[pyo3(signature = (scene, out, *, threads = None, shard = None, resume = false, checkpoint_every = 60.0, progress = None, csv = false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn run(
    py: Python<'_>,
    scene: &Bound<'_, PyScene>,
    out: PathBuf,
    threads: Option<usize>,
    shard: Option<(u64, u64)>,
    resume: bool,
    checkpoint_every: f64,
    progress: Option<Bound<'_, PyAny>>,
    csv: bool,
) -> PyResult<(String, Results)> {
    let shard = shard_of(py, shard)?;
    let control = Arc::new(RunControl::default());
    let options = run_options(&out, checkpoint_every, resume, Progress::Quiet)
        .map_err(|e| scene_error(py, &e))?
        .with_control(control.clone());
    let scene = &scene.get().inner;
    let done = drive(py, &control, progress.as_ref(), || {
        run_on(scene, &out, shard, options, threads, csv)
    })?
    .map_err(|e| scene_error(py, &e))?;
    let results = Results {
        output: done.output,
        times: Some(scene.frame_times()),
    };
    Ok((done.summary, results))
}

/// Run `scene` in memory (no files): its results.
#[pyfunction]
#[pyo3(signature = (scene, *, threads = None, shard = None, progress = None))]
pub(crate) fn run_in_memory(
    py: Python<'_>,
    scene: &Bound<'_, PyScene>,
    threads: Option<usize>,
    shard: Option<(u64, u64)>,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<Results> {
    let shard = shard_of(py, shard)?;
    let control = Arc::new(RunControl::default());
    let options = RunOptions::default().quiet().with_control(control.clone());
    let scene = &scene.get().inner;
    let job = Job::Memory { shard, options };
    let work = || -> Result<RunOutput<NamedLaw>, SceneError> {
        match threads {
            None => scene.population(&job),
            Some(n) => rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| SceneError::Input(format!("threads = {n}: {e}")))?
                .install(|| scene.population(&job)),
        }
    };
    let output = drive(py, &control, progress.as_ref(), work)?.map_err(|e| scene_error(py, &e))?;
    Ok(Results {
        output,
        times: Some(scene.frame_times()),
    })
}

/// `scene`'s results from its output folder `out`: the checkpoint of shard `shard`, or without
/// `shard` the whole run's (`checkpoint-0000-of-0001`) or else the merge of the shards'.
#[pyfunction]
#[pyo3(signature = (out, scene = None, shard = None))]
pub(crate) fn load_results(
    py: Python<'_>,
    out: PathBuf,
    scene: Option<Bound<'_, PyScene>>,
    shard: Option<(u64, u64)>,
) -> PyResult<Results> {
    let shard = shard_of(py, shard)?;
    let output = py
        .detach(|| {
            if shard != Shard::ALL || checkpoint_dir(&out, Shard::ALL).is_dir() {
                RunOutput::<NamedLaw>::read_checkpoint(&out, shard)
            } else {
                RunOutput::<NamedLaw>::merge_dir(&out)
            }
        })
        .map_err(|e| population_error(py, &e))?;
    Ok(Results {
        output,
        times: scene.map(|s| s.get().inner.frame_times()),
    })
}

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
use pyo3::conversion::FromPyObjectOwned;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;
use std::sync::Arc;

fn shard_of(py: Python<'_>, shard: Option<(u64, u64)>) -> PyResult<Shard> {
    match shard {
        None => Ok(Shard::ALL),
        Some((k, n)) => Shard::new(k, n).map_err(|e| population_error(py, &e)),
    }
}

/// The keyword-only arguments of [`run`], which takes them as `**options`: its text signature
/// names them with their defaults, and [`RunArgs::new`] reads them as pyo3 reads declared
/// arguments (the same errors), so Python sees the signature of the stub.
struct RunArgs<'py> {
    threads: Option<usize>,
    shard: Option<(u64, u64)>,
    resume: bool,
    checkpoint_every: f64,
    progress: Option<Bound<'py, PyAny>>,
    csv: bool,
}

impl<'py> RunArgs<'py> {
    const NAMES: [&'static str; 6] = ["threads", "shard", "resume", "checkpoint_every", "progress", "csv"];

    /// The arguments in `options` (keyword to value), the defaults for those not given.
    fn new(options: Option<&Bound<'py, PyDict>>) -> PyResult<Self> {
        let mut args = Self {
            threads: None,
            shard: None,
            resume: false,
            checkpoint_every: 60.0,
            progress: None,
            csv: false,
        };
        let Some(options) = options else {
            return Ok(args);
        };
        // As pyo3: an unknown keyword first, then each argument in the signature's order.
        for key in options.keys() {
            if !Self::NAMES.contains(&key.to_string().as_str()) {
                return Err(PyTypeError::new_err(format!(
                    "run() got an unexpected keyword argument '{key}'"
                )));
            }
        }
        if let Some(threads) = keyword(options, "threads")? {
            args.threads = threads;
        }
        if let Some(shard) = keyword(options, "shard")? {
            args.shard = shard;
        }
        if let Some(resume) = keyword(options, "resume")? {
            args.resume = resume;
        }
        if let Some(every) = keyword(options, "checkpoint_every")? {
            args.checkpoint_every = every;
        }
        if let Some(progress) = keyword(options, "progress")? {
            args.progress = progress;
        }
        if let Some(csv) = keyword(options, "csv")? {
            args.csv = csv;
        }
        Ok(args)
    }
}

/// `options[name]` as a `T` if given; a failed conversion is pyo3's for a declared argument
/// (the converter's exception with the note "while processing 'name'").
fn keyword<'py, T: FromPyObjectOwned<'py>>(options: &Bound<'py, PyDict>, name: &str) -> PyResult<Option<T>> {
    let Some(value) = options.get_item(name)? else {
        return Ok(None);
    };
    value.extract::<T>().map(Some).map_err(|e| {
        let e: PyErr = e.into();
        let note = format!("while processing '{name}'");
        let _ = e.value(options.py()).call_method1("add_note", (note,));
        e
    })
}

/// The command's `run` of `scene` into `out` (`csv`: as `--csv`): the same files, bitwise.
/// Returns the command's summary line and the records the run wrote (not read back).
#[pyfunction]
#[pyo3(
    signature = (scene, out, **options),
    text_signature = "(scene, out, *, threads=None, shard=None, resume=False, checkpoint_every=60.0, progress=None, csv=False)"
)]
pub(crate) fn run(
    py: Python<'_>,
    scene: &Bound<'_, PyScene>,
    out: PathBuf,
    options: Option<&Bound<'_, PyDict>>,
) -> PyResult<(String, Results)> {
    let RunArgs {
        threads,
        shard,
        resume,
        checkpoint_every,
        progress,
        csv,
    } = RunArgs::new(options)?;
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

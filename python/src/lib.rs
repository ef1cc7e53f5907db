//! `pseudorigid._native`: the Rust side of the Python package. Everything goes through the
//! library's own validated entry points (the command's scene parser and runner,
//! `flow::openfoam`); this file only converts between Python and Rust values and maps the
//! library's typed errors onto the Python exceptions of `pseudorigid.errors`.

use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray2};
use pseudorigid::ellipsoid::PrincipalFrame;
use pseudorigid::flow::FlowField;
use pseudorigid::flow::openfoam::{BlendedFlow, FoamCase, FoamError, FoamFlow};
use pseudorigid::material::NamedLaw;
use pseudorigid::population::columns::{
    FRAME_COLUMNS, Row, Values, at_time, fate_code, frame_measures, record_columns,
};
use pseudorigid::population::{
    Fate, PopulationError, Progress, RunControl, RunOptions, RunOutput, Shard, checkpoint_dir,
};
use pseudorigid::scene::error::Source;
use pseudorigid::scene::run::{Job, run_on, run_options};
use pseudorigid::scene::{Scene, SceneError};
use pseudorigid::tensor::Vec3;
use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyRuntimeError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Condvar, Mutex};
use std::time::Duration;

// ---------------------------------------------------------------------------------------------
// Errors

/// An instance of `pseudorigid.errors.<name>` with `message` and the attributes `attrs`.
fn typed(py: Python<'_>, name: &str, message: &str, attrs: &[(&str, Bound<'_, PyAny>)]) -> PyErr {
    let build = || -> PyResult<PyErr> {
        let class = py.import("pseudorigid.errors")?.getattr(name)?;
        let exc = class.call1((message,))?;
        for (k, v) in attrs {
            exc.setattr(*k, v)?;
        }
        Ok(PyErr::from_value(exc))
    };
    build().unwrap_or_else(|e| e)
}

fn not_found(path: &str, message: &str) -> PyErr {
    PyFileNotFoundError::new_err((2, message.to_string(), path.to_string()))
}

fn io_error(path: &str, source: &std::io::Error, message: &str) -> PyErr {
    if source.kind() == std::io::ErrorKind::NotFound {
        not_found(path, message)
    } else {
        PyOSError::new_err(message.to_string())
    }
}

fn foam_error(py: Python<'_>, e: &FoamError) -> PyErr {
    let message = e.to_string();
    match e {
        FoamError::Io { path, source } => io_error(path, source, &message),
        FoamError::Missing { path } => not_found(path, &message),
        FoamError::Outside { .. } | FoamError::Stencil { .. } => typed(py, "FlowError", &message, &[]),
        _ => typed(py, "MeshError", &message, &[]),
    }
}

fn population_error(py: Python<'_>, e: &PopulationError) -> PyErr {
    let message = e.to_string();
    match e {
        PopulationError::Io { path, source } => io_error(&path.display().to_string(), source, &message),
        PopulationError::ShardOutOfRange { .. } | PopulationError::BadShard { .. } => {
            typed(py, "ParameterError", &message, &[])
        }
        _ => typed(py, "PopulationError", &message, &[]),
    }
}

fn cli_error(py: Python<'_>, e: &SceneError) -> PyErr {
    let message = e.to_string();
    match e {
        SceneError::Read { path, source } => io_error(&path.display().to_string(), source, &message),
        SceneError::Invalid {
            file,
            line,
            column,
            key,
            message: what,
        } => {
            let attrs = || -> PyResult<Vec<(&str, Bound<'_, PyAny>)>> {
                Ok(vec![
                    ("file", file.into_pyobject(py)?.into_any()),
                    ("line", line.into_pyobject(py)?.into_any()),
                    ("column", column.into_pyobject(py)?.into_any()),
                    ("key", key.into_pyobject(py)?.into_any()),
                    ("reason", what.into_pyobject(py)?.into_any()),
                ])
            };
            match attrs() {
                Ok(a) => typed(py, "StudyError", &message, &a),
                Err(e) => e,
            }
        }
        SceneError::Foam(f) => foam_error(py, f),
        SceneError::Population(p) => population_error(py, p),
        SceneError::Output(_) => typed(py, "PseudorigidError", &message, &[]),
        SceneError::Input(_) => typed(py, "ParameterError", &message, &[]),
    }
}

fn scene_error(py: Python<'_>, key: &str, message: &str) -> PyErr {
    let text = format!("<dict>: `{key}`: {message}");
    let attrs = || -> PyResult<Vec<(&str, Bound<'_, PyAny>)>> {
        Ok(vec![
            ("file", "<dict>".into_pyobject(py)?.into_any()),
            ("key", key.into_pyobject(py)?.into_any()),
            ("reason", message.into_pyobject(py)?.into_any()),
        ])
    };
    match attrs() {
        Ok(a) => typed(py, "StudyError", &text, &a),
        Err(e) => e,
    }
}

// ---------------------------------------------------------------------------------------------
// Python values <-> TOML values

/// `obj` as a TOML value; `None` for Python `None` (an absent key). `key` is the dotted path
/// of `obj` for the error.
fn to_toml(obj: &Bound<'_, PyAny>, key: &str) -> Result<Option<toml::Value>, (String, String)> {
    use toml::Value;
    let err = |m: String| (key.to_string(), m);
    if obj.is_none() {
        return Ok(None);
    }
    if let Ok(b) = obj.cast::<PyBool>() {
        return Ok(Some(Value::Boolean(b.is_true())));
    }
    if obj.is_instance_of::<PyInt>() {
        let i: i64 = obj
            .extract()
            .map_err(|_| err(format!("integer {obj} does not fit in 64 bits")))?;
        return Ok(Some(Value::Integer(i)));
    }
    if obj.is_instance_of::<PyFloat>() {
        let x: f64 = obj.extract().map_err(|e: PyErr| err(e.to_string()))?;
        return Ok(Some(Value::Float(x)));
    }
    if let Ok(s) = obj.cast::<PyString>() {
        return Ok(Some(Value::String(s.to_string())));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in d.iter() {
            let name: String = k
                .extract()
                .map_err(|_| err(format!("keys must be strings, got {}", type_name(&k))))?;
            let path = if key.is_empty() {
                name.clone()
            } else {
                format!("{key}.{name}")
            };
            if let Some(v) = to_toml(&v, &path)? {
                let _ = table.insert(name, v);
            }
        }
        return Ok(Some(Value::Table(table)));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let mut items = Vec::new();
        for (i, v) in obj.try_iter().map_err(|e| err(e.to_string()))?.enumerate() {
            let v = v.map_err(|e| err(e.to_string()))?;
            let path = format!("{key}[{i}]");
            match to_toml(&v, &path)? {
                Some(v) => items.push(v),
                None => return Err((path, "None is not allowed in a list".into())),
            }
        }
        return Ok(Some(Value::Array(items)));
    }
    // NumPy arrays and scalars (and anything else that knows its Python form).
    if let Ok(plain) = obj.call_method0("tolist")
        && !plain.is(obj)
    {
        return to_toml(&plain, key);
    }
    Err(err(format!("unsupported value of type {}", type_name(obj))))
}

fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type().name().map_or("?".to_string(), |n| n.to_string())
}

fn from_toml<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    use toml::Value;
    Ok(match v {
        Value::String(s) => s.into_pyobject(py)?.into_any(),
        Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        Value::Float(x) => x.into_pyobject(py)?.into_any(),
        Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any(),
        Value::Array(a) => {
            let list = PyList::empty(py);
            for x in a {
                list.append(from_toml(py, x)?)?;
            }
            list.into_any()
        }
        Value::Table(t) => {
            let dict = PyDict::new(py);
            for (k, x) in t {
                dict.set_item(k, from_toml(py, x)?)?;
            }
            dict.into_any()
        }
    })
}

// ---------------------------------------------------------------------------------------------
// Scenes

/// A validated scene (see `pseudorigid.Scene`).
#[pyclass(name = "Scene", module = "pseudorigid._native", frozen)]
struct PyScene {
    inner: Scene,
}

fn parse_text(py: Python<'_>, text: &str, file: &str, base: &Path) -> PyResult<Scene> {
    py.detach(|| pseudorigid::scene::parse(&Source { file, text }, base))
        .map_err(|e| cli_error(py, &e))
}

#[pymethods]
impl PyScene {
    /// Read and validate a scene file (the command's `validate`).
    #[staticmethod]
    fn from_toml(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let inner = py
            .detach(|| pseudorigid::scene::load(&path))
            .map_err(|e| cli_error(py, &e))?;
        Ok(Self { inner })
    }

    /// Validate a scene's TOML text; relative paths in it are relative to `base`.
    #[staticmethod]
    #[pyo3(signature = (text, base = None, name = "<text>"))]
    fn from_text(py: Python<'_>, text: &str, base: Option<PathBuf>, name: &str) -> PyResult<Self> {
        let base = base.unwrap_or_else(|| PathBuf::from("."));
        Ok(Self {
            inner: parse_text(py, text, name, &base)?,
        })
    }

    /// Validate a scene given as nested dicts (the TOML file's tables); relative paths in it are
    /// relative to `base` (default: the current folder).
    #[staticmethod]
    #[pyo3(signature = (d, base = None))]
    fn from_dict(py: Python<'_>, d: &Bound<'_, PyAny>, base: Option<PathBuf>) -> PyResult<Self> {
        if !d.is_instance_of::<PyDict>() {
            return Err(scene_error(py, "", &format!("a scene is a dict, got {}", type_name(d))));
        }
        let table = match to_toml(d, "") {
            Ok(Some(toml::Value::Table(t))) => t,
            Ok(_) => return Err(scene_error(py, "", "a scene is a dict")),
            Err((key, message)) => return Err(scene_error(py, &key, &message)),
        };
        let text = toml::to_string(&table).map_err(|e| scene_error(py, "", &e.to_string()))?;
        Self::from_text(py, &text, base, "<dict>")
    }

    /// The scene's TOML text (the run's fingerprint).
    fn to_toml(&self) -> &str {
        &self.inner.text
    }

    /// The scene as nested dicts.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let table: toml::Table =
            toml::from_str(&self.inner.text).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        from_toml(py, &toml::Value::Table(table))
    }

    /// Number of particles.
    #[getter]
    fn count(&self) -> u64 {
        self.inner.count()
    }

    /// Run seed.
    #[getter]
    fn seed(&self) -> u64 {
        self.inner.seed
    }

    /// Times of the frames: 0 and every output time.
    #[getter]
    fn frame_times<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_vec(py, self.inner.frame_times())
    }

    /// Whether the scene writes ParaView files.
    #[getter]
    fn vtk(&self) -> bool {
        self.inner.vtk
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene({} particles, {} output times, seed {})",
            self.inner.count(),
            self.inner.outputs.len(),
            self.inner.seed
        )
    }
}

// ---------------------------------------------------------------------------------------------
// Runs

/// Run `work` on a thread of its own while this (the interpreter's) thread waits without the
/// GIL; every `POLL` it calls `progress(done, total)` when the count moved and checks for
/// signals (Ctrl-C). A raised exception asks the run to stop after the particles in flight
/// (their records are checkpointed) and is re-raised once the run has stopped.
fn drive<T: Send>(
    py: Python<'_>,
    control: &RunControl,
    progress: Option<&Bound<'_, PyAny>>,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    const POLL: Duration = Duration::from_millis(100);
    let finished = (Mutex::new(false), Condvar::new());
    std::thread::scope(|s| {
        let handle = s.spawn(|| {
            // Set the flag even if `work` panics, so the waiting thread wakes up.
            struct Done<'a>(&'a (Mutex<bool>, Condvar));
            impl Drop for Done<'_> {
                fn drop(&mut self) {
                    if let Ok(mut done) = self.0.0.lock() {
                        *done = true;
                    }
                    self.0.1.notify_all();
                }
            }
            let _done = Done(&finished);
            work()
        });
        let mut failure: Option<PyErr> = None;
        let mut last = None;
        let mut report = |failure: &mut Option<PyErr>| {
            let now = control.progress();
            if let Some(cb) = progress
                && failure.is_none()
                && last != Some(now)
            {
                last = Some(now);
                if let Err(e) = cb.call1(now) {
                    control.stop();
                    *failure = Some(e);
                }
            }
        };
        loop {
            let done = py.detach(|| {
                let (lock, cvar) = &finished;
                let guard = lock.lock().unwrap_or_else(|p| p.into_inner());
                let (guard, _) = cvar
                    .wait_timeout_while(guard, POLL, |done| !*done)
                    .unwrap_or_else(|p| p.into_inner());
                *guard
            });
            if done {
                break;
            }
            report(&mut failure);
            if failure.is_none()
                && let Err(e) = py.check_signals()
            {
                control.stop();
                failure = Some(e);
            }
        }
        let joined = py.detach(|| handle.join());
        match (failure, joined) {
            (Some(e), _) => Err(e),
            (None, Ok(value)) => {
                let mut failure = None;
                report(&mut failure);
                failure.map_or(Ok(value), Err)
            }
            (None, Err(_)) => Err(PyRuntimeError::new_err(
                "pseudorigid: the run panicked (a bug; please report it)",
            )),
        }
    })
}

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
fn run(
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
        .map_err(|e| cli_error(py, &e))?
        .with_control(control.clone());
    let scene = &scene.get().inner;
    let done = drive(py, &control, progress.as_ref(), || {
        run_on(scene, &out, shard, options, threads, csv)
    })?
    .map_err(|e| cli_error(py, &e))?;
    let results = Results {
        output: done.output,
        times: Some(scene.frame_times()),
    };
    Ok((done.summary, results))
}

/// Run `scene` in memory (no files): its results.
#[pyfunction]
#[pyo3(signature = (scene, *, threads = None, shard = None, progress = None))]
fn run_in_memory(
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
    let output = drive(py, &control, progress.as_ref(), work)?.map_err(|e| cli_error(py, &e))?;
    Ok(Results {
        output,
        times: Some(scene.frame_times()),
    })
}

/// `scene`'s results from its output folder `out`: the checkpoint of shard `shard`, or without
/// `shard` the whole run's (`checkpoint-0000-of-0001`) or else the merge of the shards'.
#[pyfunction]
#[pyo3(signature = (out, scene = None, shard = None))]
fn load_results(
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

// ---------------------------------------------------------------------------------------------
// Results as columns

/// A run's records (see `pseudorigid.Results`).
#[pyclass(name = "Results", module = "pseudorigid._native", frozen)]
struct Results {
    output: RunOutput<NamedLaw>,
    times: Option<Vec<f64>>,
}

fn column<'py>(py: Python<'py>, d: &Bound<'py, PyDict>, name: &str, values: Vec<f64>) -> PyResult<()> {
    d.set_item(name, PyArray1::from_vec(py, values))
}

fn column_i64<'py>(py: Python<'py>, d: &Bound<'py, PyDict>, name: &str, values: Vec<i64>) -> PyResult<()> {
    d.set_item(name, PyArray1::from_vec(py, values))
}

/// `rows × 3` and `rows × 3 × 3` arrays from flat row-major data.
fn matrix<'py>(py: Python<'py>, values: Vec<f64>, shape: &[usize]) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_vec(py, values).reshape(shape.to_vec())?.into_any())
}

#[pymethods]
impl Results {
    /// Number of records.
    fn __len__(&self) -> usize {
        self.output.records.len()
    }

    /// The run's configuration hash.
    #[getter]
    fn config_hash(&self) -> &str {
        &self.output.config_hash
    }

    /// Names of the patches, by patch index.
    #[getter]
    fn patches(&self) -> Vec<String> {
        self.output.patches.clone()
    }

    /// Particles per fate.
    fn counts(&self) -> std::collections::BTreeMap<&'static str, u64> {
        let c = self.output.counts();
        [
            ("deposited", c.deposited),
            ("escaped", c.escaped),
            ("suspended", c.suspended),
            ("failed", c.failed),
        ]
        .into_iter()
        .collect()
    }

    /// One row per particle: the columns of `records.parquet`, in its order (the columns of
    /// `results.csv` with the end state's F, `F11`..`F33`, and step statistics; all from
    /// `population::columns::record_columns`). Where the file has a null a float column holds
    /// NaN and the integer and text columns (`patch`, `patch_name`, `error`) hold None.
    fn records<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let rows: Vec<Row<'_, NamedLaw>> = self
            .output
            .records
            .iter()
            .map(|r| Row::new(r, &self.output.patches))
            .collect();
        let d = PyDict::new(py);
        for c in record_columns::<NamedLaw>() {
            match c.values {
                Values::Count(f) => column_i64(py, &d, c.name, rows.iter().map(|r| f(r) as i64).collect())?,
                Values::Int(f) => d.set_item(c.name, rows.iter().map(f).collect::<Vec<_>>())?,
                Values::Real(f) => column(py, &d, c.name, rows.iter().map(|r| f(r).unwrap_or(f64::NAN)).collect())?,
                Values::Text(f) => d.set_item(c.name, rows.iter().map(f).collect::<Vec<_>>())?,
            }
        }
        Ok(d)
    }

    /// The frames as one long table: a row per particle per frame time, the columns of
    /// `frames.parquet` in its order (frame, time, id, x1..x3, the six independent components
    /// V11, V12, V13, V22, V23, V33 of the symmetric V, r1..r3, flag).
    fn frames<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let Some(times) = &self.times else {
            return Err(typed(
                py,
                "ParameterError",
                "frames need the scene's output times: load the results with their scene",
                &[],
            ));
        };
        let (mut frame, mut id, mut flag) = (Vec::new(), Vec::new(), Vec::new());
        let mut time = Vec::new();
        let mut cols: Vec<Vec<f64>> = vec![Vec::new(); 12];
        for (k, &t) in times.iter().enumerate() {
            for p in at_time(&self.output.records, t) {
                frame.push(k as i64);
                time.push(t);
                id.push(p.id);
                flag.push(p.flag);
                for (c, x) in cols.iter_mut().zip(frame_measures(&p)) {
                    c.push(x);
                }
            }
        }
        let d = PyDict::new(py);
        column_i64(py, &d, "frame", frame)?;
        column(py, &d, "time", time)?;
        column_i64(py, &d, "id", id)?;
        // frames.parquet's measured columns, between `id` and `flag`.
        for (name, c) in FRAME_COLUMNS[3..15].iter().zip(cols) {
            column(py, &d, name, c)?;
        }
        column_i64(py, &d, "flag", flag)?;
        Ok(d)
    }

    /// The kept states of particle `index`: `t` (n), `x`, `v`, `r` (n × 3, r₁ ≥ r₂ ≥ r₃),
    /// `F`, `axes` (n × 3 × 3; rows of `axes` are the current principal axes), its `fate` and
    /// `error` ("" unless it failed).
    fn trajectory<'py>(&self, py: Python<'py>, index: u64) -> PyResult<Bound<'py, PyDict>> {
        let record = self
            .output
            .records
            .binary_search_by_key(&index, |r| r.index)
            .ok()
            .map(|i| &self.output.records[i])
            .ok_or_else(|| {
                typed(
                    py,
                    "ParameterError",
                    &format!("no particle {index} in these results"),
                    &[],
                )
            })?;
        let n = record.samples.len();
        let (mut t, mut x, mut v, mut r, mut f, mut q) = (
            Vec::with_capacity(n),
            Vec::with_capacity(3 * n),
            Vec::with_capacity(3 * n),
            Vec::with_capacity(3 * n),
            Vec::with_capacity(9 * n),
            Vec::with_capacity(9 * n),
        );
        let shape = record.spec.as_ref().map(|s| s.shape.shape_tensor());
        for s in &record.samples {
            t.push(s.t);
            x.extend(s.x.iter());
            v.extend(s.v.iter());
            // Row-major F_ij.
            f.extend(s.f.transpose().iter());
            match shape {
                Some(sh) => {
                    let frame = PrincipalFrame::from_total_distortion(&(s.f * sh));
                    r.extend(frame.r.iter());
                    q.extend(frame.q.transpose().iter());
                }
                None => {
                    r.extend([f64::NAN; 3]);
                    q.extend([f64::NAN; 9]);
                }
            }
        }
        let d = PyDict::new(py);
        column(py, &d, "t", t)?;
        d.set_item("x", matrix(py, x, &[n, 3])?)?;
        d.set_item("v", matrix(py, v, &[n, 3])?)?;
        d.set_item("r", matrix(py, r, &[n, 3])?)?;
        d.set_item("F", matrix(py, f, &[n, 3, 3])?)?;
        d.set_item("axes", matrix(py, q, &[n, 3, 3])?)?;
        d.set_item("fate", record.fate.label())?;
        d.set_item("flag", fate_code(&record.fate))?;
        d.set_item(
            "error",
            match &record.fate {
                Fate::Failed { error } => error.clone(),
                _ => String::new(),
            },
        )?;
        Ok(d)
    }
}

// ---------------------------------------------------------------------------------------------
// OpenFOAM probe

/// u and ∇u of an OpenFOAM case at one time (see `pseudorigid.FoamFlow`): the blended field
/// with the no-slip wall layer that particles see (the default of scene files and `probe`), or
/// with `cellwise` each cell's linear fit.
#[pyclass(name = "FoamFlow", module = "pseudorigid._native", frozen)]
struct PyFoamFlow {
    flow: FoamFlow,
    blend: Option<BlendedFlow>,
    time: f64,
    cells: usize,
}

#[pymethods]
impl PyFoamFlow {
    #[new]
    #[pyo3(signature = (case, time = None, cellwise = false))]
    fn new(py: Python<'_>, case: PathBuf, time: Option<f64>, cellwise: bool) -> PyResult<Self> {
        if !case.exists() {
            let name = case.display().to_string();
            return Err(not_found(&name, &format!("{name}: no such OpenFOAM case folder")));
        }
        if let Some(t) = time
            && !t.is_finite()
        {
            return Err(typed(
                py,
                "ParameterError",
                &format!("time must be finite, got {t}"),
                &[],
            ));
        }
        type Opened = (FoamFlow, Option<BlendedFlow>, f64, usize);
        let opened = py.detach(|| -> Result<Opened, FoamError> {
            let foam = FoamCase::open(&case)?;
            let t = match time {
                Some(t) => t,
                None => *foam.times().last().ok_or_else(|| FoamError::NoSuchTime {
                    case: case.display().to_string(),
                    time: f64::NAN,
                    available: Vec::new(),
                })?,
            };
            let cells = foam.mesh().n_cells();
            let flow = FoamFlow::read(&foam, &[t])?;
            let blend = if cellwise {
                None
            } else {
                Some(BlendedFlow::new(flow.clone())?)
            };
            Ok((flow, blend, t, cells))
        });
        let (flow, blend, time, cells) = opened.map_err(|e| foam_error(py, &e))?;
        Ok(Self {
            flow,
            blend,
            time,
            cells,
        })
    }

    /// The time read.
    #[getter]
    fn time(&self) -> f64 {
        self.time
    }

    /// Number of cells of the mesh.
    #[getter]
    fn cells(&self) -> usize {
        self.cells
    }

    /// u (n × 3), ∇u (n × 3 × 3, `grad_u[k, i, j]` = ∂u_i/∂x_j) and `inside` (n, bool) at the
    /// rows of `points` (n × 3); NaN outside the mesh.
    fn sample<'py>(
        &self,
        py: Python<'py>,
        points: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let a = points.as_array();
        if a.ncols() != 3 {
            return Err(typed(
                py,
                "ParameterError",
                &format!("points must be an n × 3 array, got {} columns", a.ncols()),
                &[],
            ));
        }
        let pts: Vec<Vec3> = a.rows().into_iter().map(|r| Vec3::new(r[0], r[1], r[2])).collect();
        if let Some(i) = pts.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
            return Err(typed(py, "ParameterError", &format!("point {i} is not finite"), &[]));
        }
        let n = pts.len();
        let time = self.time;
        type Columns = (Vec<f64>, Vec<f64>, Vec<bool>);
        let sampled = py.detach(|| -> Result<Columns, FoamError> {
            let (mut u, mut g, mut inside) = (
                Vec::with_capacity(3 * n),
                Vec::with_capacity(9 * n),
                Vec::with_capacity(n),
            );
            let mut hint = None;
            for x in &pts {
                match self.flow.sample_from(x, time, hint) {
                    Ok((cellwise, cell)) => {
                        hint = Some(cell);
                        let s = match &self.blend {
                            Some(b) => b
                                .sample(x, time)
                                .map_err(|e| FoamError::Mesh { reason: e.to_string() })?,
                            None => cellwise,
                        };
                        inside.push(true);
                        u.extend(s.u.iter());
                        g.extend(s.grad_u.transpose().iter());
                    }
                    Err(FoamError::Outside { .. }) => {
                        inside.push(false);
                        u.extend([f64::NAN; 3]);
                        g.extend([f64::NAN; 9]);
                    }
                    Err(e) => return Err(e),
                }
            }
            Ok((u, g, inside))
        });
        let (u, g, inside) = sampled.map_err(|e| foam_error(py, &e))?;
        Ok((
            matrix(py, u, &[n, 3])?,
            matrix(py, g, &[n, 3, 3])?,
            PyArray1::from_vec(py, inside).into_any(),
        ))
    }

    fn __repr__(&self) -> String {
        format!("FoamFlow({} cells, t = {})", self.cells, self.time)
    }
}

/// The Rust side of the `pseudorigid` package.
#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyScene>()?;
    m.add_class::<Results>()?;
    m.add_class::<PyFoamFlow>()?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(run_in_memory, m)?)?;
    m.add_function(wrap_pyfunction!(load_results, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}

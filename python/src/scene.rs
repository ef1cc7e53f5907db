//! The `Scene` class: a scene file (or its text, or its tables as dicts) validated by the
//! command's scene parser.

use crate::errors::{dict_error, scene_error};
use crate::toml_value::{from_toml, to_toml, type_name};
use numpy::PyArray1;
use pseudorigid::scene::Scene;
use pseudorigid::scene::error::Source;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::{Path, PathBuf};

/// A validated scene (see `pseudorigid.Scene`).
#[pyclass(name = "Scene", module = "pseudorigid._native", frozen)]
pub(crate) struct PyScene {
    pub(crate) inner: Scene,
}

fn parse_text(py: Python<'_>, text: &str, file: &str, base: &Path) -> PyResult<Scene> {
    py.detach(|| pseudorigid::scene::parse(&Source { file, text }, base))
        .map_err(|e| scene_error(py, &e))
}

#[pymethods]
impl PyScene {
    /// Read and validate a scene file (the command's `validate`).
    #[staticmethod]
    fn from_toml(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        let inner = py
            .detach(|| pseudorigid::scene::load(&path))
            .map_err(|e| scene_error(py, &e))?;
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
            return Err(dict_error(py, "", &format!("a scene is a dict, got {}", type_name(d))));
        }
        let table = match to_toml(d, "") {
            Ok(Some(toml::Value::Table(t))) => t,
            Ok(_) => return Err(dict_error(py, "", "a scene is a dict")),
            Err((key, message)) => return Err(dict_error(py, &key, &message)),
        };
        let text = toml::to_string(&table).map_err(|e| dict_error(py, "", &e.to_string()))?;
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

//! The library's typed errors as the Python exceptions of `pseudorigid.errors` (and the
//! built-in `FileNotFoundError` and `OSError` for files).

use pseudorigid::flow::openfoam::FoamError;
use pseudorigid::population::PopulationError;
use pseudorigid::scene::SceneError;
use pyo3::exceptions::{PyFileNotFoundError, PyOSError};
use pyo3::prelude::*;

/// An instance of `pseudorigid.errors.<name>` with `message` and the attributes `attrs`.
pub(crate) fn typed(py: Python<'_>, name: &str, message: &str, attrs: &[(&str, Bound<'_, PyAny>)]) -> PyErr {
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

pub(crate) fn not_found(path: &str, message: &str) -> PyErr {
    PyFileNotFoundError::new_err((2, message.to_string(), path.to_string()))
}

pub(crate) fn io_error(path: &str, source: &std::io::Error, message: &str) -> PyErr {
    if source.kind() == std::io::ErrorKind::NotFound {
        not_found(path, message)
    } else {
        PyOSError::new_err(message.to_string())
    }
}

pub(crate) fn foam_error(py: Python<'_>, e: &FoamError) -> PyErr {
    let message = e.to_string();
    match e {
        FoamError::Io { path, source } => io_error(path, source, &message),
        FoamError::Missing { path } => not_found(path, &message),
        FoamError::Outside { .. } | FoamError::Stencil { .. } => typed(py, "FlowError", &message, &[]),
        _ => typed(py, "MeshError", &message, &[]),
    }
}

pub(crate) fn population_error(py: Python<'_>, e: &PopulationError) -> PyErr {
    let message = e.to_string();
    match e {
        PopulationError::Io { path, source } => io_error(&path.display().to_string(), source, &message),
        PopulationError::ShardOutOfRange { .. } | PopulationError::BadShard { .. } => {
            typed(py, "ParameterError", &message, &[])
        }
        _ => typed(py, "PopulationError", &message, &[]),
    }
}

/// A scene's error: where the scene file is wrong (`SceneError`, with its place), or the
/// error of what its run reads and writes.
pub(crate) fn scene_error(py: Python<'_>, e: &SceneError) -> PyErr {
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
                Ok(a) => typed(py, "SceneError", &message, &a),
                Err(e) => e,
            }
        }
        SceneError::Foam(f) => foam_error(py, f),
        SceneError::Population(p) => population_error(py, p),
        SceneError::Output(_) => typed(py, "PseudorigidError", &message, &[]),
        SceneError::Input(_) => typed(py, "ParameterError", &message, &[]),
    }
}

/// A `SceneError` at `key` of a scene given as dicts ([`crate::scene`]'s `from_dict`).
pub(crate) fn dict_error(py: Python<'_>, key: &str, message: &str) -> PyErr {
    let text = format!("<dict>: `{key}`: {message}");
    let attrs = || -> PyResult<Vec<(&str, Bound<'_, PyAny>)>> {
        Ok(vec![
            ("file", "<dict>".into_pyobject(py)?.into_any()),
            ("key", key.into_pyobject(py)?.into_any()),
            ("reason", message.into_pyobject(py)?.into_any()),
        ])
    };
    match attrs() {
        Ok(a) => typed(py, "SceneError", &text, &a),
        Err(e) => e,
    }
}

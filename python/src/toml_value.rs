//! Python values as TOML values and back: a scene given as nested dicts is the TOML text the
//! scene parser reads, and a scene's text is nested dicts again.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// `obj` as a TOML value; `None` for Python `None` (an absent key). `key` is the dotted path
/// of `obj` for the error.
pub(crate) fn to_toml(obj: &Bound<'_, PyAny>, key: &str) -> Result<Option<toml::Value>, (String, String)> {
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

pub(crate) fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type().name().map_or("?".to_string(), |n| n.to_string())
}

pub(crate) fn from_toml<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
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

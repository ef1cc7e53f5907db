//! The `Results` class: a run's records as columns (numpy arrays in dicts, which
//! `pseudorigid.Results` turns into tables and DataFrames).

use crate::errors::typed;
use numpy::{PyArray1, PyArrayMethods};
use pseudorigid::ellipsoid::PrincipalFrame;
use pseudorigid::material::NamedLaw;
use pseudorigid::population::columns::{
    ColumnValues, Row, at_time, fate_code, frame_measure_names, frame_measures, record_columns,
};
use pseudorigid::population::{Fate, RunOutput};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// A run's records (see `pseudorigid.Results`).
#[pyclass(name = "Results", module = "pseudorigid._native", frozen)]
pub(crate) struct Results {
    pub(crate) output: RunOutput<NamedLaw>,
    pub(crate) times: Option<Vec<f64>>,
}

fn column<'py>(py: Python<'py>, d: &Bound<'py, PyDict>, name: &str, values: Vec<f64>) -> PyResult<()> {
    d.set_item(name, PyArray1::from_vec(py, values))
}

fn column_i64<'py>(py: Python<'py>, d: &Bound<'py, PyDict>, name: &str, values: Vec<i64>) -> PyResult<()> {
    d.set_item(name, PyArray1::from_vec(py, values))
}

/// `rows × 3` and `rows × 3 × 3` arrays from flat row-major data.
pub(crate) fn matrix<'py>(py: Python<'py>, values: Vec<f64>, shape: &[usize]) -> PyResult<Bound<'py, PyAny>> {
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
    /// `results.csv` with the end state's F, `F11`..`F33`, step statistics and the slow-manifold
    /// switch's; all from `population::columns::record_columns`). Where the file has a null a float column holds
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
                ColumnValues::Count(f) => column_i64(py, &d, c.name, rows.iter().map(|r| f(r) as i64).collect())?,
                ColumnValues::Int(f) => d.set_item(c.name, rows.iter().map(f).collect::<Vec<_>>())?,
                ColumnValues::Real(f) => {
                    column(py, &d, c.name, rows.iter().map(|r| f(r).unwrap_or(f64::NAN)).collect())?
                }
                ColumnValues::Text(f) => d.set_item(c.name, rows.iter().map(f).collect::<Vec<_>>())?,
            }
        }
        Ok(d)
    }

    /// The frames as one long table: a row per particle per frame time, the columns of
    /// `frames.csv` and `frames.parquet` in their order (frame, time, id, x1..x3, the nine
    /// components V11..V33 of the symmetric V by rows, r1..r3, flag).
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
        let mut cols: Vec<Vec<f64>> = vec![Vec::new(); frame_measure_names().len()];
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
        for (name, c) in frame_measure_names().iter().zip(cols) {
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

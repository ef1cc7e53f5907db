//! The `FoamFlow` class: u and ∇u of an OpenFOAM case at one time, sampled at points.

use crate::errors::{foam_error, not_found, typed};
use crate::results::matrix;
use numpy::{PyArray1, PyReadonlyArray2};
use pseudorigid::flow::FlowField;
use pseudorigid::flow::openfoam::{BlendedFlow, FoamCase, FoamError, FoamFlow};
use pseudorigid::tensor::Vec3;
use pyo3::prelude::*;
use std::path::PathBuf;

/// u and ∇u of an OpenFOAM case at one time (see `pseudorigid.FoamFlow`): the blended field
/// with the no-slip wall layer that particles see (the default of scene files and `probe`), or
/// with `cellwise` each cell's linear fit.
#[pyclass(name = "FoamFlow", module = "pseudorigid._native", frozen)]
pub(crate) struct PyFoamFlow {
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

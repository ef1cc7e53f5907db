//! One time level of a [`super::FoamFlow`]: the cells' velocities and gradients and the
//! no-slip walls' fits, computed from the level's `U` and stored in f64 or f32.
//!
//! # Storage and its error
//! A level costs 12 numbers per cell (u and ∇u: 96 bytes in f64, 48 in f32; a 5 M-cell airway
//! is 0.48 GB or 0.24 GB a level) and 30 per no-slip wall face (the [`WallFit`], always f64:
//! the walls hold $O(N^{2/3})$ of the N cells' data). In f32 each stored component carries a
//! relative rounding error of at most $u_r = 2^{-24} \approx 6.0 \cdot 10^{-8}$, so a cell's
//! sample $u_c + G_c (x − x_c)$ is within
//! ```math
//! |δu_i| \le u_r \Big(|u_{c,i}| + \sum_j |G_{c,ij}|\,|x_j − x_{c,j}|\Big)
//! ```
//! of the f64 one, and $|δG_{ij}| \le u_r |G_{ij}|$ (plus the f64 evaluation's own round-off):
//! far below the O(h²) reconstruction error of any mesh a CFD solver can use. Values beyond
//! f32's range (3.4·10³⁸) are refused, not rounded to infinity.

use super::error::FoamError;
use super::field::VolField;
use super::mesh::PolyMesh;
use super::reconstruct::Stencils;
use super::wall_layer::{WallFit, WallGeometry};
use crate::tensor::{Mat3, Vec3};

/// How a level's cell values are stored ([module docs](self): the error of f32).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Precision {
    /// As computed: the samples are those of an f64 field.
    #[default]
    F64,
    /// Rounded to f32: half the memory, a relative error of at most 2⁻²⁴ per stored component.
    F32,
}

/// The cells' u and ∇u in one precision.
#[derive(Debug, Clone)]
enum Cells {
    F64 { u: Vec<Vec3>, grad: Vec<Mat3> },
    F32 { u: Vec<[f32; 3]>, grad: Vec<[f32; 9]> },
}

/// One time level: cell velocities and gradients, and the no-slip walls' fits.
#[derive(Debug, Clone)]
pub(crate) struct Frame {
    pub(crate) time: f64,
    cells: Cells,
    /// The fit of wall face k of [`super::FoamFlow::walls`] ([`super::wall_layer`]).
    pub(crate) wall_fits: Vec<WallFit>,
}

/// What a level is computed with: the mesh, its stencils, the no-slip wall faces and their
/// layer geometry.
pub(crate) struct Geometry<'a> {
    pub(crate) mesh: &'a PolyMesh,
    pub(crate) stencils: &'a Stencils,
    pub(crate) walls: &'a [u32],
    pub(crate) wall_layer: &'a WallGeometry,
}

fn bad(reason: String) -> FoamError {
    FoamError::Field {
        path: "(velocity)".into(),
        reason,
    }
}

/// Refuse a field whose shape is not a velocity field on `mesh`.
pub(crate) fn check_shape(mesh: &PolyMesh, time: f64, field: &VolField) -> Result<(), FoamError> {
    let n_boundary = mesh.n_faces() - mesh.n_internal_faces();
    let n_patches = mesh.patches().len();
    if field.comps != 3
        || field.internal.len() != 3 * mesh.n_cells()
        || field.boundary.len() != 3 * n_boundary
        || field.fixed.len() != n_patches
    {
        return Err(bad(format!(
            "field at t = {time} has {} components, {} cell and {} boundary values and {} patch conditions for {} cells, {n_boundary} boundary faces and {n_patches} patches",
            field.comps,
            field.internal.len(),
            field.boundary.len(),
            field.fixed.len(),
            mesh.n_cells()
        )));
    }
    if !time.is_finite() {
        return Err(bad(format!("time {time} is not finite")));
    }
    Ok(())
}

impl Frame {
    /// The level of `field` at `time` (its shape checked by [`check_shape`]), stored in
    /// `precision`; an error if a gradient or wall fit overflows, or an f32 value would.
    pub(crate) fn compute(
        geometry: &Geometry<'_>,
        time: f64,
        field: &VolField,
        precision: Precision,
    ) -> Result<Self, FoamError> {
        let mesh = geometry.mesh;
        let grad = geometry.stencils.gradients(mesh, field);
        let u: Vec<Vec3> = field.internal.chunks_exact(3).map(Vec3::from_row_slice).collect();
        let velocity: Vec<Vec3> = geometry
            .walls
            .iter()
            .map(|&f| Vec3::from_row_slice(field.boundary_face(f as usize - mesh.n_internal_faces())))
            .collect();
        let wall_fits = geometry.wall_layer.fits(&velocity, &u, &grad);
        // Finite values whose differences overflow (|u| near f64::MAX) give no field.
        if let Some(cell) = grad.iter().position(|g| !g.iter().all(|c| c.is_finite())) {
            return Err(bad(format!(
                "field at t = {time}: the gradient of cell {cell} overflows"
            )));
        }
        if let Some(k) = wall_fits.iter().position(|f| !f.is_finite()) {
            return Err(bad(format!(
                "field at t = {time}: the wall fit of wall face {k} overflows"
            )));
        }
        let cells = match precision {
            Precision::F64 => Cells::F64 { u, grad },
            Precision::F32 => {
                let u32s: Vec<[f32; 3]> = u.iter().map(|v| [v[0] as f32, v[1] as f32, v[2] as f32]).collect();
                let g32s: Vec<[f32; 9]> = grad
                    .iter()
                    .map(|g| {
                        let mut out = [0.0; 9];
                        out.iter_mut().zip(g.iter()).for_each(|(o, &v)| *o = v as f32);
                        out
                    })
                    .collect();
                let finite = |c: &[f32]| c.iter().all(|v| v.is_finite());
                if let Some(cell) = (0..u32s.len()).find(|&c| !finite(&u32s[c]) || !finite(&g32s[c])) {
                    return Err(bad(format!(
                        "field at t = {time}: cell {cell}'s u = {:?} or ∇u exceeds f32's range (store it in f64)",
                        u[cell]
                    )));
                }
                Cells::F32 { u: u32s, grad: g32s }
            }
        };
        Ok(Self { time, cells, wall_fits })
    }

    /// Velocity of cell c.
    #[inline]
    pub(crate) fn u(&self, c: usize) -> Vec3 {
        match &self.cells {
            Cells::F64 { u, .. } => u[c],
            Cells::F32 { u, .. } => Vec3::new(f64::from(u[c][0]), f64::from(u[c][1]), f64::from(u[c][2])),
        }
    }

    /// Gradient of cell c.
    #[inline]
    pub(crate) fn grad(&self, c: usize) -> Mat3 {
        match &self.cells {
            Cells::F64 { grad, .. } => grad[c],
            Cells::F32 { grad, .. } => Mat3::from_iterator(grad[c].iter().map(|&v| f64::from(v))),
        }
    }

    /// Number of cells.
    pub(crate) fn n_cells(&self) -> usize {
        match &self.cells {
            Cells::F64 { u, .. } => u.len(),
            Cells::F32 { u, .. } => u.len(),
        }
    }

    /// The volume mean of √(2 D:D) over the cells ([`crate::flow::FlowField::strain_rate`]).
    pub(crate) fn strain_rate(&self, mesh: &PolyMesh) -> f64 {
        let volumes = mesh.cell_volumes();
        let total: f64 = volumes.iter().sum();
        let weighted: f64 = (0..self.n_cells())
            .zip(volumes)
            .map(|(c, v)| crate::flow::strain_rate_magnitude(&self.grad(c)) * v)
            .sum();
        weighted / total
    }
}

//! Cellwise linear reconstruction of a cell-centred field: u and ∇u anywhere in a cell.
//!
//! # Scheme
//! In cell c the field is $u(x) = u_c + G_c\\,(x − x_c)$, with $G_c$ the weighted
//! least-squares gradient over the cell's faces: across an internal face the data point is the
//! neighbour's centre and value, on a boundary face it is the face centre and the patch value
//! (the no-slip zero, the inlet profile, ...). With $d_j = x_j − x_c$ and $w_j = |d_j|^{-2}$,
//! ```math
//! G_c = \Big(\sum_j w_j\,(u_j − u_c)\,d_j^{T}\Big)\,M_c^{-1},\qquad M_c = \sum_j w_j\,d_j d_j^{T}.
//! ```
//!
//! # Why this choice
//! - *Exact for linear fields on every cell*: if $u_j = a + G x_j$ for all data points, every
//!   residual vanishes at $G_c = G$, and $M_c$ is non-singular whenever the face directions
//!   span space (every closed cell's do; a flat stencil is reported as
//!   [`FoamError::Stencil`]). This holds for hexahedra, prisms,
//!   tetrahedra and snappyHexMesh's split polyhedra alike, whatever the skewness or
//!   non-orthogonality. OpenFOAM's Gauss-linear gradient and the point values of
//!   volPointInterpolation both lose linear exactness on such cells.
//! - *Wall cells are not extrapolated*: the patch values sit on the wall itself, half a cell
//!   from the centre, so the fit near a wall is an interpolation that uses the boundary
//!   condition, where a cell-only stencil would be one-sided.
//! - *Local*: the inverse-square weights let the nearest data dominate, so the truncation
//!   error of $G_c$ for a smooth field is O(h) and that of u(x) is O(h²)
//!   ($|x − x_c| = O(h)$ times the O(h) gradient error, plus the O(h²) Taylor remainder).
//! - *Cheap*: $M_c^{-1}$ depends on the geometry only and is computed once; each time
//!   directory costs one pass over the faces; a query is one matrix–vector product.
//!
//! The reconstruction is discontinuous across faces by O(h²) in u and O(h) in ∇u; u is not
//! divergence-free at this order either, since the gradient is fitted, not solved for.

use super::error::FoamError;
use super::field::VolField;
use super::mesh::PolyMesh;
use crate::tensor::{Mat3, Vec3};

/// Smallest accepted ratio of the extreme eigenvalues of $M_c$; below it the stencil is flat
/// and the gradient component across it would be amplified round-off.
const MIN_CONDITION: f64 = 1e-10;

/// Inverse normal matrices $M_c^{-1}$ of every cell (geometry only).
#[derive(Debug, Clone)]
pub struct Stencils {
    m_inv: Vec<Mat3>,
}

/// One stencil data point of cell c: the other location and its value.
fn stencil_point<'a>(mesh: &PolyMesh, field: &'a VolField, c: usize, f: usize) -> (Vec3, &'a [f64]) {
    match mesh.neighbour(f) {
        Some(n) => {
            let other = if n == c { mesh.owner(f) } else { n };
            (mesh.cell_centres()[other], field.cell(other))
        }
        None => (mesh.face_centres()[f], field.boundary_face(f - mesh.n_internal_faces())),
    }
}

fn stencil_location(mesh: &PolyMesh, c: usize, f: usize) -> Vec3 {
    match mesh.neighbour(f) {
        Some(n) => mesh.cell_centres()[if n == c { mesh.owner(f) } else { n }],
        None => mesh.face_centres()[f],
    }
}

impl Stencils {
    /// Build and check the normal matrix of every cell.
    pub fn new(mesh: &PolyMesh) -> Result<Self, FoamError> {
        let mut m_inv = Vec::with_capacity(mesh.n_cells());
        for c in 0..mesh.n_cells() {
            let xc = mesh.cell_centres()[c];
            let mut m = Mat3::zeros();
            for &f in mesh.cell_faces(c) {
                let d = stencil_location(mesh, c, f as usize) - xc;
                m += d * d.transpose() / d.norm_squared();
            }
            let eig = m.symmetric_eigenvalues();
            let ratio = eig.min() / eig.max();
            // Also rejects NaN.
            let inverse = m.try_inverse().filter(|_| ratio >= MIN_CONDITION);
            m_inv.push(inverse.ok_or(FoamError::Stencil {
                cell: c,
                points: mesh.cell_faces(c).len(),
                ratio,
            })?);
        }
        Ok(Self { m_inv })
    }

    /// Gradients $G_c$ of a vector field, `G[(i, j)] = ∂u_i/∂x_j`.
    pub fn gradients(&self, mesh: &PolyMesh, field: &VolField) -> Vec<Mat3> {
        debug_assert_eq!(field.comps, 3);
        (0..mesh.n_cells())
            .map(|c| {
                let xc = mesh.cell_centres()[c];
                let uc = Vec3::from_row_slice(field.cell(c));
                let mut b = Mat3::zeros();
                for &f in mesh.cell_faces(c) {
                    let (x, u) = stencil_point(mesh, field, c, f as usize);
                    let d = x - xc;
                    b += (Vec3::from_row_slice(u) - uc) * d.transpose() / d.norm_squared();
                }
                b * self.m_inv[c]
            })
            .collect()
    }
}

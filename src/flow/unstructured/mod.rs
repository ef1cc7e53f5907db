//! Meshed (CFD) flow fields: OpenFOAM results on hexahedral meshes.
//!
//! # Scheme
//! The field lives on the mesh vertices: OpenFOAM's cell-centred u and its Gauss-linear
//! gradient (`postProcess -func 'grad(U)'`) are interpolated to the points by `foamToVTK`
//! (volPointInterpolation, which takes boundary values from the patches, so no-slip and the lid
//! velocity hold exactly on the walls). At a query x the containing hexahedron and the reference
//! coordinates ξ are found by [`locate`] (nearest centre, then a face walk with the exact
//! trilinear point-in-cell test), and u and ∇u are interpolated with the same trilinear shape
//! functions: $u(x) = \sum_k N_k(ξ)\\,u_k$, $∇u(x) = \sum_k N_k(ξ)\\,(∇u)_k$.
//!
//! Order: trilinear interpolation is exact for fields linear in x on any trilinear cell, so
//! the interpolation error is O(h²) in u and in ∇u (relative to the point values); the
//! point values themselves carry the O(h²) error of the second-order finite-volume solution and
//! of the Gauss-linear gradient. u is continuous across cells; ∇u is interpolated
//! independently (not differentiated from u), so it is continuous too, and tr ∇u vanishes only
//! up to the discretisation error.
//!
//! Known limitations of point data: volPointInterpolation averages neighbouring cells, which
//! flattens sharp extrema by O(h²) (about 2 % on the Re = 1000 cavity extrema at 60³), and on the
//! lid edges it averages the patches (u = U/2 there), so inside the top cells next to a side wall
//! the interpolated velocity has a small wall-normal component: a tracer released within one cell
//! of the lid can reach that wall, which callers see as [`FlowError::OutsideDomain`] or as wall
//! contact.
//!
//! Sources: the legacy VTK export ([`vtk`]) or the compact shipped form ([`compact`]);
//! [`MeshedFlow::load`] tells them apart by content. Wall contact for deposition is in
//! [`crate::contact`], the cavity validation against Albensoeder & Kuhlmann in [`crate::scenes::cavity_benchmark`].

pub mod compact;
pub mod error;
pub mod hex;
pub mod locate;
pub mod mesh;
pub mod vtk;

pub use error::MeshError;
pub use locate::{Location, Locator};
pub use mesh::HexMesh;

use super::{FlowField, FlowSample, check_query};
use crate::error::FlowError;
use crate::tensor::{Mat3, Vec3};
use std::path::Path;

/// A steady flow field given at the vertices of a hexahedral mesh, interpolated trilinearly.
#[derive(Debug, Clone)]
pub struct MeshedFlow {
    mesh: HexMesh,
    locator: Locator,
    u: Vec<Vec3>,
    grad_u: Vec<Mat3>,
}

impl MeshedFlow {
    /// Field from a mesh and point data: velocity `u` and gradient `grad_u`
    /// (`grad_u[k][(i, j)] = ∂u_i/∂x_j` at point k).
    pub fn new(mesh: HexMesh, u: Vec<Vec3>, grad_u: Vec<Mat3>) -> Result<Self, MeshError> {
        let n_points = mesh.points().len();
        for (name, expected, len) in [("U", 3, u.len()), ("grad(U)", 9, grad_u.len())] {
            if len != n_points {
                return Err(MeshError::MissingArray {
                    name: name.to_string(),
                    expected,
                    n_points,
                    found: format!("{len} points"),
                });
            }
        }
        if let Some(index) = u.iter().position(|v| !v.iter().all(|c| c.is_finite())) {
            return Err(MeshError::NonFinite {
                what: "velocity",
                index,
            });
        }
        if let Some(index) = grad_u.iter().position(|g| !g.iter().all(|c| c.is_finite())) {
            return Err(MeshError::NonFinite {
                what: "velocity gradient",
                index,
            });
        }
        let locator = Locator::new(&mesh);
        Ok(Self {
            mesh,
            locator,
            u,
            grad_u,
        })
    }

    /// Load a field exported by `foamToVTK -legacy` (point arrays `U` and `grad(U)`) or
    /// written by [`compact::write()`]; the format is recognised from the file's first bytes.
    pub fn load(path: impl AsRef<Path>) -> Result<Self, MeshError> {
        let path = path.as_ref();
        if compact::is_compact(path)? {
            compact::read(path)
        } else {
            Self::from_vtk_grid(vtk::read_legacy(path)?)
        }
    }

    /// Field from a parsed legacy VTK grid. OpenFOAM stores grad(U) as $T_{ij} = ∂_i U_j$,
    /// the transpose of our ∇u.
    pub fn from_vtk_grid(grid: vtk::VtkGrid) -> Result<Self, MeshError> {
        let n_points = grid.points.len();
        let array = |name: &str, comps: usize| -> Result<&Vec<f64>, MeshError> {
            match grid.point_arrays.get(name) {
                Some((c, values)) if *c == comps && values.len() == comps * n_points => Ok(values),
                other => Err(MeshError::MissingArray {
                    name: name.to_string(),
                    expected: comps,
                    n_points,
                    found: other.map_or("nothing".to_string(), |(c, v)| {
                        format!("{c} components, {} values", v.len())
                    }),
                }),
            }
        };
        let u = array("U", 3)?
            .chunks_exact(3)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect();
        let grad_u = array("grad(U)", 9)?
            .chunks_exact(9)
            .map(|c| Mat3::from_row_slice(c).transpose())
            .collect();
        Self::new(HexMesh::new(grid.points, grid.cells)?, u, grad_u)
    }

    /// The mesh.
    pub fn mesh(&self) -> &HexMesh {
        &self.mesh
    }

    /// Velocity at the mesh points.
    pub fn point_velocity(&self) -> &[Vec3] {
        &self.u
    }

    /// Velocity gradient at the mesh points.
    pub fn point_gradient(&self) -> &[Mat3] {
        &self.grad_u
    }

    /// The cell containing `x` and its reference coordinates, `None` outside the mesh.
    pub fn locate(&self, x: &Vec3) -> Option<Location> {
        self.locator.locate(&self.mesh, x)
    }
}

impl FlowField for MeshedFlow {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        check_query(x, t)?;
        let Location { cell, xi } = self.locate(x).ok_or_else(|| FlowError::outside(x))?;
        let weights = hex::shape(&xi);
        let mut sample = FlowSample::steady(Vec3::zeros(), Mat3::zeros());
        for (&v, w) in self.mesh.cells()[cell].iter().zip(weights) {
            sample.u += self.u[v as usize] * w;
            sample.grad_u += self.grad_u[v as usize] * w;
        }
        Ok(sample)
    }
}

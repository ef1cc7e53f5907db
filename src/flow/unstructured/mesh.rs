//! Hexahedral mesh topology: vertices, cells and face neighbours.

use super::error::MeshError;
use super::hex::{self, FACES};
use crate::tensor::Vec3;
use std::collections::HashMap;

/// Marker for "no neighbour": the face lies on the domain boundary.
pub const BOUNDARY: u32 = u32::MAX;

/// A conforming mesh of trilinear hexahedra (VTK vertex order, see [`hex`]).
#[derive(Debug, Clone)]
pub struct HexMesh {
    points: Vec<Vec3>,
    cells: Vec<[u32; 8]>,
    neighbours: Vec<[u32; 6]>,
    centres: Vec<Vec3>,
    lower: Vec3,
    upper: Vec3,
}

impl HexMesh {
    /// Build the mesh, check every cell (indices in range, positive Jacobian at the centre) and
    /// find face neighbours by matching vertex sets.
    pub fn new(points: Vec<Vec3>, cells: Vec<[u32; 8]>) -> Result<Self, MeshError> {
        if cells.is_empty() {
            return Err(MeshError::Empty);
        }
        // Indices are stored as u32 with u32::MAX reserved for the boundary marker.
        if cells.len() >= BOUNDARY as usize {
            return Err(MeshError::TooManyCells { cells: cells.len() });
        }
        if let Some(index) = points.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
            return Err(MeshError::NonFinite {
                what: "point coordinate",
                index,
            });
        }
        let mut centres = Vec::with_capacity(cells.len());
        for (cell, verts) in cells.iter().enumerate() {
            if let Some(&bad) = verts.iter().find(|&&v| v as usize >= points.len()) {
                return Err(MeshError::BadConnectivity {
                    cell,
                    point: i64::from(bad),
                    n_points: points.len(),
                });
            }
            let p = verts.map(|v| points[v as usize]);
            let (centre, j) = hex::map(&p, &Vec3::repeat(0.5));
            let det_j = j.determinant();
            // Also rejects NaN.
            if det_j.is_nan() || det_j <= 0.0 {
                return Err(MeshError::DegenerateCell { cell, det_j });
            }
            centres.push(centre);
        }
        let neighbours = face_neighbours(&cells)?;
        let mut lower = Vec3::repeat(f64::INFINITY);
        let mut upper = Vec3::repeat(f64::NEG_INFINITY);
        for p in cells.iter().flatten().map(|&v| points[v as usize]) {
            lower = lower.inf(&p);
            upper = upper.sup(&p);
        }
        Ok(Self {
            points,
            cells,
            neighbours,
            centres,
            lower,
            upper,
        })
    }

    /// Vertex coordinates.
    pub fn points(&self) -> &[Vec3] {
        &self.points
    }

    /// Cells as 8 vertex indices each.
    pub fn cells(&self) -> &[[u32; 8]] {
        &self.cells
    }

    /// Cell centres x(ξ = ½).
    pub fn centres(&self) -> &[Vec3] {
        &self.centres
    }

    /// Neighbour across face `2d + s` (ξ_d = s) of `cell`, `None` on the boundary.
    pub fn neighbour(&self, cell: usize, face: usize) -> Option<usize> {
        let n = self.neighbours[cell][face];
        (n != BOUNDARY).then_some(n as usize)
    }

    /// Vertex coordinates of one cell.
    pub fn cell_points(&self, cell: usize) -> [Vec3; 8] {
        self.cells[cell].map(|v| self.points[v as usize])
    }

    /// Axis-aligned bounding box (lower, upper corner) of the cells.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        (self.lower, self.upper)
    }
}

fn face_neighbours(cells: &[[u32; 8]]) -> Result<Vec<[u32; 6]>, MeshError> {
    let mut neighbours = vec![[BOUNDARY; 6]; cells.len()];
    // Sorted vertex set of a face -> (first cell, its local face, already matched).
    let mut seen: HashMap<[u32; 4], (u32, usize, bool)> = HashMap::with_capacity(4 * cells.len());
    for (cell, verts) in cells.iter().enumerate() {
        for (face, local) in FACES.iter().enumerate() {
            let mut key = local.map(|l| verts[l]);
            key.sort_unstable();
            match seen.get_mut(&key) {
                Some((_, _, true)) => return Err(MeshError::NonManifoldFace { cell }),
                Some((other, other_face, matched)) => {
                    *matched = true;
                    neighbours[*other as usize][*other_face] = cell as u32;
                    neighbours[cell][face] = *other;
                }
                None => {
                    seen.insert(key, (cell as u32, face, false));
                }
            }
        }
    }
    Ok(neighbours)
}

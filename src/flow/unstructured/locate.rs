//! Point location: nearest cell centre (R*-tree) followed by a walk across faces.
//!
//! # Scheme
//! The start cell is the one whose centre is nearest to x. From there the walk inverts the
//! trilinear map (see [`super::hex`]); while ξ lies outside [0, 1]³ it steps through the face
//! with the largest violation (never straight back). On a convex mesh of convex cells the walk
//! from the nearest centre needs a few steps. When it stops at a boundary face with x beyond it
//! (x outside, or a non-convex domain), cycles, or meets a cell where Newton fails, the
//! [`FALLBACK_CANDIDATES`] cells with the nearest centres are tested directly; if none contains
//! x it is outside the mesh.

use super::hex;
use super::mesh::HexMesh;
use crate::tensor::Vec3;
use rstar::RTree;
use rstar::primitives::GeomWithData;

type Centre = GeomWithData<[f64; 3], u32>;

const MAX_WALK: usize = 64;
/// Cells tested directly when the walk does not end inside a cell.
pub const FALLBACK_CANDIDATES: usize = 16;

/// Spatial index over the cell centres of a [`HexMesh`].
#[derive(Debug, Clone)]
pub struct Locator {
    tree: RTree<Centre>,
}

/// A located point: its cell and reference coordinates ξ in that cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Location {
    /// Containing cell.
    pub cell: usize,
    /// Reference coordinates in [0, 1]³.
    pub xi: Vec3,
}

impl Locator {
    /// Bulk-load the centres of `mesh` into an R*-tree.
    pub fn new(mesh: &HexMesh) -> Self {
        let centres = mesh
            .centres()
            .iter()
            .enumerate()
            .map(|(i, c)| Centre::new([c[0], c[1], c[2]], i as u32))
            .collect();
        Self {
            tree: RTree::bulk_load(centres),
        }
    }

    /// The cell containing `x`, or `None` outside the mesh.
    pub fn locate(&self, mesh: &HexMesh, x: &Vec3) -> Option<Location> {
        let (lower, upper) = mesh.bounds();
        let slack = hex::XI_TOL * (upper - lower).amax();
        if (0..3).any(|d| x[d] < lower[d] - slack || x[d] > upper[d] + slack) {
            return None;
        }
        let query = [x[0], x[1], x[2]];
        let start = self.tree.nearest_neighbor(query)?.data as usize;
        walk(mesh, start, x).or_else(|| {
            self.tree
                .nearest_neighbor_iter(query)
                .take(FALLBACK_CANDIDATES)
                .find_map(|c| {
                    let cell = c.data as usize;
                    let xi = hex::inverse_map(&mesh.cell_points(cell), x)?;
                    hex::contains(&xi).then_some(Location { cell, xi })
                })
        })
    }
}

fn walk(mesh: &HexMesh, start: usize, x: &Vec3) -> Option<Location> {
    let mut cell = start;
    let mut previous = usize::MAX;
    for _ in 0..MAX_WALK {
        let xi = hex::inverse_map(&mesh.cell_points(cell), x)?;
        if hex::contains(&xi) {
            return Some(Location { cell, xi });
        }
        // Faces ordered by how far x lies beyond them; take the worst one that has a neighbour
        // other than the cell just left (avoids ping-pong between two cells).
        let mut violations: Vec<(f64, usize)> = (0..3)
            .flat_map(|d| [(-xi[d], 2 * d), (xi[d] - 1.0, 2 * d + 1)])
            .filter(|&(v, _)| v > hex::XI_TOL)
            .collect();
        violations.sort_by(|a, b| b.0.total_cmp(&a.0));
        let next = violations
            .iter()
            .find_map(|&(_, f)| mesh.neighbour(cell, f).filter(|&n| n != previous))?;
        previous = cell;
        cell = next;
    }
    None
}

//! Point location in polyhedral cells.
//!
//! # Scheme
//! Each cell is split into tetrahedra $(x_c, x_f, v_i, v_{i+1})$: the cell centre, a face
//! centre and one edge of that face. Neighbouring cells share the face triangles
//! $(x_f, v_i, v_{i+1})$, so the tetrahedra of all cells tile the mesh without gaps or overlaps
//! (for cells that are star-shaped about their centre, which `checkMesh` requires).
//! A point x is written in barycentric form about the apex,
//! $x − x_c = α(x_f − x_c) + β(v_i − x_c) + γ(v_{i+1} − x_c)$. If α, β, γ ≥ 0, x lies in the
//! cone from $x_c$ through that face triangle: inside the cell if α + β + γ ≤ 1, otherwise beyond
//! face f. That gives both the inside test and the face to walk through.
//!
//! With a hint (the particle's previous cell) the walk crosses at most [`MAX_WALK`] faces;
//! without one, or when the walk leaves through a boundary face (x outside, or a concave
//! domain), an R*-tree of cell bounding boxes lists every cell whose box holds x and each is
//! tested. The bounding box of a cell contains all its tetrahedra (centres are convex
//! combinations of vertices), so the fallback cannot miss the containing cell.

use super::mesh::PolyMesh;
use crate::tensor::Vec3;
use rstar::RTree;
use rstar::primitives::{GeomWithData, Rectangle};

/// Faces crossed from the hint before falling back to the bounding-box search. A particle
/// moves a fraction of a cell per step, so one or two crossings are the rule; a stale hint
/// (another particle's cell) costs at most this many cell tests before the index is used.
pub const MAX_WALK: usize = 8;
/// Barycentric tolerance: points this close (relative to the tetrahedron) to a face count as
/// inside, so points on shared faces and on the walls are found.
const BARY_TOL: f64 = 1e-10;

type CellBox = GeomWithData<Rectangle<[f64; 3]>, u32>;

/// Spatial index of a [`PolyMesh`] for point location.
#[derive(Debug, Clone)]
pub struct CellLocator {
    boxes: RTree<CellBox>,
}

/// Where a point lies relative to one cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Probe {
    /// Strictly inside the cell.
    Inside,
    /// On the cell's boundary (within the tolerance): other cells may hold the point too.
    OnFace,
    /// Beyond face `f` of the cell (the ray from the cell centre to x crosses it).
    Beyond(usize),
    /// In no cone of the cell (a cell not star-shaped about its centre).
    Lost,
}

/// Test `x` against cell `c`.
pub fn probe(mesh: &PolyMesh, c: usize, x: &Vec3) -> Probe {
    let apex = mesh.cell_centres()[c];
    let d = x - apex;
    let points = mesh.points();
    for &f in mesh.cell_faces(c) {
        let f = f as usize;
        let e0 = mesh.face_centres()[f] - apex;
        let verts = mesh.face(f);
        for (i, &a) in verts.iter().enumerate() {
            let b = verts[(i + 1) % verts.len()];
            let e1 = points[a as usize] - apex;
            let e2 = points[b as usize] - apex;
            let n12 = e1.cross(&e2);
            let det = e0.dot(&n12);
            if det == 0.0 || !det.is_finite() {
                continue;
            }
            let alpha = d.dot(&n12) / det;
            let beta = e0.dot(&d.cross(&e2)) / det;
            let gamma = e0.dot(&e1.cross(&d)) / det;
            if alpha >= -BARY_TOL && beta >= -BARY_TOL && gamma >= -BARY_TOL {
                let beyond = alpha + beta + gamma - 1.0;
                return if beyond < -BARY_TOL {
                    Probe::Inside
                } else if beyond <= BARY_TOL {
                    Probe::OnFace
                } else {
                    Probe::Beyond(f)
                };
            }
        }
    }
    Probe::Lost
}

impl CellLocator {
    /// Bulk-load the cell bounding boxes.
    pub fn new(mesh: &PolyMesh) -> Self {
        let points = mesh.points();
        let boxes = (0..mesh.n_cells())
            .map(|c| {
                let mut lo = Vec3::repeat(f64::INFINITY);
                let mut hi = Vec3::repeat(f64::NEG_INFINITY);
                for &f in mesh.cell_faces(c) {
                    for &v in mesh.face(f as usize) {
                        lo = lo.inf(&points[v as usize]);
                        hi = hi.sup(&points[v as usize]);
                    }
                }
                // Widen by the barycentric tolerance so points on the faces stay inside.
                let pad = (hi - lo).amax() * 1e-9;
                let lo = lo.add_scalar(-pad);
                let hi = hi.add_scalar(pad);
                CellBox::new(
                    Rectangle::from_corners([lo[0], lo[1], lo[2]], [hi[0], hi[1], hi[2]]),
                    c as u32,
                )
            })
            .collect();
        Self {
            boxes: RTree::bulk_load(boxes),
        }
    }

    /// The cell containing `x`, walking from `hint` when given; `None` outside the mesh.
    ///
    /// The answer does not depend on the hint: a point strictly inside a cell has only that
    /// cell, and a point on a face shared by several cells (a centreline of a structured grid,
    /// say) goes to the lowest-numbered of them, so results are reproducible whatever the order
    /// of earlier queries.
    pub fn locate(&self, mesh: &PolyMesh, x: &Vec3, hint: Option<usize>) -> Option<usize> {
        let walked = hint
            .filter(|&h| h < mesh.n_cells())
            .and_then(|start| walk(mesh, start, x));
        if let Some((cell, Probe::Inside)) = walked {
            return Some(cell);
        }
        // On a face, or not found by walking: the cells whose boxes hold x.
        let mut on_face: Option<usize> = None;
        for c in self
            .boxes
            .locate_all_at_point([x[0], x[1], x[2]])
            .map(|b| b.data as usize)
        {
            match probe(mesh, c, x) {
                Probe::Inside => return Some(c),
                Probe::OnFace => on_face = Some(on_face.map_or(c, |o| o.min(c))),
                Probe::Beyond(_) | Probe::Lost => {}
            }
        }
        on_face
    }
}

/// Walk from `start` towards `x` across faces: the cell reached and whether x is strictly
/// inside or on its boundary; `None` if the walk leaves the mesh, gets lost or takes more than
/// [`MAX_WALK`] steps.
fn walk(mesh: &PolyMesh, start: usize, x: &Vec3) -> Option<(usize, Probe)> {
    let mut cell = start;
    for _ in 0..=MAX_WALK {
        match probe(mesh, cell, x) {
            p @ (Probe::Inside | Probe::OnFace) => return Some((cell, p)),
            Probe::Lost => return None,
            Probe::Beyond(f) => {
                let next = mesh.neighbour(f)?;
                cell = if next == cell { mesh.owner(f) } else { next };
            }
        }
    }
    None
}

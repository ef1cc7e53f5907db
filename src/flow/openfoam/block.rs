//! The lid-driven cube cavity's mesh as blockMesh makes it, built in memory.
//!
//! The shipped cavity fields (paper §6.3 at Re = 470, the Re = 1000 validation and the 12³ CI
//! case) are simpleFoam's cell-centred `U` alone; the mesh is one uniform block, cheaper to
//! rebuild than to ship (6 MB gzipped at 60³). [`cavity_block`] rebuilds it in blockMesh's
//! order, so the cell values of a `U` file land on their cells:
//! - points and cells i fastest, then j, then k (blockMesh's lexicographic block order);
//! - internal faces by owner, each owner's faces towards +x, +y, +z (OpenFOAM's upper-triangular
//!   order: neighbours c + 1, c + n, c + n² ascend);
//! - boundary faces patch by patch, `lid` (z = L) then `fixedWalls` in the order of the
//!   cases' `blockMeshDict` (z = 0, x = 0, x = L, y = 0, y = L), all outward, in blockMesh's
//!   order within each plane.
//!
//! Face for face (vertex lists, owners, neighbours, patches) it is the mesh blockMesh made for
//! `cases/cavity-ci` (`tests/flow_openfoam_cavity.rs`), so a field with non-uniform patch
//! values would land on its faces too.

use super::{FoamError, Patch, PolyMesh};
use crate::tensor::Vec3;

/// The cube [0, edge]³ with `cells`³ uniform hexahedra in blockMesh's order, patches `lid`
/// (the face z = edge) and `fixedWalls` (the other five), both of type `wall`.
///
/// Errors: [`FoamError::Mesh`] for no cells, an edge that is not finite and positive, or more
/// points than 32-bit labels address.
pub fn cavity_block(cells: usize, edge: f64) -> Result<PolyMesh, FoamError> {
    let n = cells;
    if n == 0 || !(edge.is_finite() && edge > 0.0) {
        return Err(FoamError::Mesh {
            reason: format!(
                "a cavity block needs at least one cell and a finite positive edge, got {n} cells and edge {edge}"
            ),
        });
    }
    // 3 n²(n + 1) faces of four labels each is the largest count held in u32.
    let labels = (n + 1)
        .checked_pow(3)
        .zip(n.checked_mul(n).and_then(|m| m.checked_mul(12 * (n + 1))));
    if labels.is_none_or(|(points, face_labels)| points.max(face_labels) > u32::MAX as usize) {
        return Err(FoamError::Mesh {
            reason: format!("a cavity block of {n}³ cells exceeds the 32-bit label range"),
        });
    }
    let p = |i: usize, j: usize, k: usize| (i + (n + 1) * (j + (n + 1) * k)) as u32;
    let c = |i: usize, j: usize, k: usize| (i + n * (j + n * k)) as u32;
    let h = edge / n as f64;
    let mut points = Vec::with_capacity((n + 1).pow(3));
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                points.push(Vec3::new(i as f64, j as f64, k as f64) * h);
            }
        }
    }
    // The quadrilateral on the plane {x_d = s} with lower corner (a, b) in the axes d + 1 and
    // d + 2 (cyclic), its normal along +e_d.
    let quad = |d: usize, s: usize, a: usize, b: usize| -> [u32; 4] {
        let at = |u: usize, v: usize| match d {
            0 => p(s, u, v),
            1 => p(v, s, u),
            _ => p(u, v, s),
        };
        [at(a, b), at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)]
    };
    let (mut flat, mut owner, mut neighbour) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let ijk = [i, j, k];
                for d in 0..3 {
                    if ijk[d] + 1 < n {
                        flat.extend(quad(d, ijk[d] + 1, ijk[(d + 1) % 3], ijk[(d + 2) % 3]));
                        owner.push(c(i, j, k));
                        let mut next = ijk;
                        next[d] += 1;
                        neighbour.push(c(next[0], next[1], next[2]));
                    }
                }
            }
        }
    }
    let n_internal = owner.len();
    // Boundary faces: (axis, side) with side 1 the upper plane; the lid first. Within a patch
    // blockMesh runs over the face's two axes with y fastest on the z and x planes and z
    // fastest on the y planes, and starts a lower plane's face at its lowest corner.
    for (d, side) in [(2, 1), (2, 0), (0, 0), (0, 1), (1, 0), (1, 1)] {
        for slow in 0..n {
            for fast in 0..n {
                let (a, b) = if d == 2 { (slow, fast) } else { (fast, slow) };
                let q = quad(d, side * n, a, b);
                flat.extend(if side == 0 { [q[0], q[3], q[2], q[1]] } else { q });
                let mut ijk = [0; 3];
                ijk[d] = side * (n - 1);
                ijk[(d + 1) % 3] = a;
                ijk[(d + 2) % 3] = b;
                owner.push(c(ijk[0], ijk[1], ijk[2]));
            }
        }
    }
    let offsets = (0..=owner.len()).map(|f| 4 * f as u32).collect();
    let patches = vec![
        Patch {
            name: "lid".into(),
            kind: "wall".into(),
            start: n_internal,
            size: n * n,
            coupling: None,
        },
        Patch {
            name: "fixedWalls".into(),
            kind: "wall".into(),
            start: n_internal + n * n,
            size: 5 * n * n,
            coupling: None,
        },
    ];
    PolyMesh::new(points, offsets, flat, owner, neighbour, patches)
}

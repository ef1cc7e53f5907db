//! The trilinear (isoparametric Q1) hexahedron.
//!
//! # Scheme
//! Reference coordinates ξ ∈ [0, 1]³, vertices in VTK order (type 12): the bottom face
//! ξ₃ = 0 is 0‑1‑2‑3 counter-clockwise seen from above, the top face 4‑5‑6‑7 lies above it.
//! The map $x(ξ) = \sum_k N_k(ξ)\\,p_k$ with $N_k = \prod_d ℓ_{k,d}(ξ_d)$, $ℓ = ξ$ or $1 − ξ$,
//! is inverted by Newton's method; for a parallelepiped (a uniform blockMesh cell) the map is
//! affine and one step is exact. A point is in the cell iff its ξ lies in [0, 1]³ up to
//! [`XI_TOL`]: this is the exact membership test of the trilinear solid, and it agrees with the
//! planar-face polyhedron whenever the faces are planar.

use crate::tensor::{Mat3, Vec3};

/// Reference coordinates of the 8 vertices, VTK hexahedron order.
pub const CORNERS: [[f64; 3]; 8] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [1.0, 1.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 0.0, 1.0],
    [1.0, 1.0, 1.0],
    [0.0, 1.0, 1.0],
];

/// Local vertex indices of the 6 faces; face `2d + s` is the face ξ_d = s.
pub const FACES: [[usize; 4]; 6] = [
    [0, 3, 7, 4],
    [1, 2, 6, 5],
    [0, 1, 5, 4],
    [3, 2, 6, 7],
    [0, 1, 2, 3],
    [4, 5, 6, 7],
];

/// Tolerance on ξ for membership: points on shared faces belong to both cells.
pub const XI_TOL: f64 = 1e-9;

const NEWTON_MAX_ITERS: usize = 30;
const NEWTON_TOL: f64 = 1e-13;

/// Trilinear shape functions N_k(ξ).
pub fn shape(xi: &Vec3) -> [f64; 8] {
    let mut n = [0.0; 8];
    for (k, c) in CORNERS.iter().enumerate() {
        n[k] = (0..3).map(|d| if c[d] > 0.5 { xi[d] } else { 1.0 - xi[d] }).product();
    }
    n
}

/// Gradients ∂N_k/∂ξ of the shape functions.
pub fn shape_grad(xi: &Vec3) -> [Vec3; 8] {
    let mut g = [Vec3::zeros(); 8];
    for (k, c) in CORNERS.iter().enumerate() {
        let l = |d: usize| if c[d] > 0.5 { xi[d] } else { 1.0 - xi[d] };
        let dl = |d: usize| if c[d] > 0.5 { 1.0 } else { -1.0 };
        g[k] = Vec3::new(dl(0) * l(1) * l(2), l(0) * dl(1) * l(2), l(0) * l(1) * dl(2));
    }
    g
}

/// Position x(ξ) and Jacobian J = ∂x/∂ξ of the map.
pub fn map(p: &[Vec3; 8], xi: &Vec3) -> (Vec3, Mat3) {
    let n = shape(xi);
    let g = shape_grad(xi);
    let mut x = Vec3::zeros();
    let mut j = Mat3::zeros();
    for k in 0..8 {
        x += p[k] * n[k];
        j += p[k] * g[k].transpose();
    }
    (x, j)
}

/// Reference coordinates ξ of `x` in the cell with vertices `p`, by Newton's method from the
/// cell centre. `None` if the Jacobian is singular along the way or Newton does not settle
/// (then `x` is far outside a strongly distorted cell).
pub fn inverse_map(p: &[Vec3; 8], x: &Vec3) -> Option<Vec3> {
    let mut xi = Vec3::repeat(0.5);
    for _ in 0..NEWTON_MAX_ITERS {
        let (xk, j) = map(p, &xi);
        let step = j.lu().solve(&(x - xk))?;
        xi += step;
        if !xi.iter().all(|c| c.is_finite()) {
            return None;
        }
        if step.amax() < NEWTON_TOL {
            return Some(xi);
        }
    }
    // Newton stalls only at round-off level for reasonable cells; accept a tiny residual.
    let (xk, j) = map(p, &xi);
    let scale = j.abs().max();
    ((x - xk).amax() <= 1e-10 * scale).then_some(xi)
}

/// Whether ξ lies in the closed reference cube (with [`XI_TOL`]).
pub fn contains(xi: &Vec3) -> bool {
    xi.iter().all(|&c| (-XI_TOL..=1.0 + XI_TOL).contains(&c))
}

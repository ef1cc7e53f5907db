//! The flow next to a no-slip wall to second order, with the wall-normal velocity that
//! continuity demands: the wall fits of [`super::BlendedFlow`].
//!
//! # The near-wall expansion
//! Take a wall at rest or moving rigidly in its own plane (velocity $u_w$, tangential derivatives
//! zero), inward unit normal n, distance δ = n·(x − x_f) from the face's plane and tangential
//! position s. No-slip makes every tangential derivative of u vanish on the wall, so
//! ```math
//! u_t(s, δ) = δ\,γ(s) + O(δ^2), \qquad γ = \partial u_t/\partial n\big|_{δ=0},
//! ```
//! γ the wall shear rate (a tangential vector). Continuity, ∂u_n/∂n = −∇ₛ·u_t, integrated from
//! the wall where u_n = 0 gives
//! ```math
//! u_n(s, δ) = −\tfrac12\,δ^2\,∇_s·γ + O(δ^3).
//! ```
//! On a wall of curvature κ the metric factors change both by a relative O(κδ), so the leading
//! coefficient stands. This δ² growth is what carries slow particles to a wall near a stagnation
//! point (the carina of an airway bifurcation): without it they hover in the first cell.
//!
//! # The fit of wall face f
//! With $p_f$ the foot of the wall cell's centre on the face's plane, $r_t = (I − n n^T)(x − p_f)$
//! and $D_f$ the tangential gradient of γ at $p_f$ (a 3×3 map with $D_f n = 0$),
//! ```math
//! L_f(x) = u_w + δ\,(γ_f + D_f r_t) + δ^2 q_f + (c_f δ^2 + e_f δ^3)\,n,\qquad c_f = −\tfrac12 \operatorname{tr} D_f,
//! ```
//! ```math
//! ∇L_f = \big(γ_f + D_f r_t + 2δ q_f + (2c_f δ + 3e_f δ^2)\,n\big)\,n^T + δ\,D_f ,
//! ```
//! the exact derivative of $L_f$ on a flat face. Its terms:
//! - *Tangential*: the profile $u_t = γδ + qδ^2$ through the wall value and the wall cell's
//!   value $u_o$ at depth ρ, with its normal derivative $G_o n$ there (the cell gradient):
//!   $γ = (I − nn^T)\\,[2(u_o − u_w)/ρ − G_o n]$, $q = (I − nn^T)(G_o n − γ)/(2ρ)$. Exact for a
//!   quadratic profile; the cell gradient alone ($G_o n$ = γ + 2qρ) would be first order.
//! - *Normal*: continuity fixes the leading coefficient, $c_f = −\tfrac12 ∇_s·γ$, and the
//!   solver's own value at the centre the next, $e_f = (u_{o,n} − c_f ρ^2)/ρ^3$, so the fit
//!   passes through the cell's value. The cubic is limited to $|e_f| ρ ≤ |c_f|$
//!   (`MAX_CUBIC`): a finite-volume value of $u_n$ at a thin cell's centre has an O(1)
//!   relative error of its own (it is O(ρ²), like $u_n$ itself), and the limit keeps the sign
//!   of continuity's term below the centre, so no spurious stagnation layer appears.
//! - *Trace*: $\operatorname{tr}∇L_f = 3e_f δ^2$: divergence-free to the order of the
//!   expansion.
//!
//! # The surface gradient D
//! By least squares over the neighbouring wall faces (those sharing a vertex with f and
//! turned by less than 45° from it, so a sharp edge between two walls is not differenced
//! across), in f's tangent plane with inverse-square distance weights: exact for a γ linear
//! along the wall. A wall face with fewer than two independent neighbours (an isolated face)
//! gets D = 0, and so no continuity term.
//!
//! # Verification
//! `tests/flow_openfoam.rs` writes Hiemenz's exact stagnation flow
//! ([`crate::flow::stagnation`]) into boxes meshed as users mesh them (uniform and graded
//! blockMesh, 2 and 5 prism layers; hexahedra and prisms): the normal velocity within 10 % of
//! the exact one throughout the first cell, v/δ² within 4 % of continuity's coefficient, second
//! order under refinement, and a sphere's arrival time at the wall within 7 %.

use super::mesh::PolyMesh;
use crate::tensor::{Mat3, Vec3};

/// Smallest cosine of the angle between two wall faces' normals whose shears are differenced
/// for D: 45°. Faceted curved walls turn by a few degrees between faces; a duct's corner by 90°.
const SAME_WALL: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// Smallest ratio of the eigenvalues of the 2×2 normal matrix of D's least-squares fit: below it
/// the neighbours lie on a line and D is left zero.
const MIN_SPREAD: f64 = 1e-6;

/// Geometry of the no-slip wall faces: what their fits need that does not change in time.
#[derive(Debug, Clone)]
pub struct WallGeometry {
    /// Inward unit normal of wall face k.
    normals: Vec<Vec3>,
    /// Face centre $x_f$.
    centres: Vec<Vec3>,
    /// Foot $p_f$ of the wall cell's centre on the face's plane.
    feet: Vec<Vec3>,
    /// Depth ρ of the wall cell's centre above the face's plane.
    depths: Vec<f64>,
    /// Owner cell of wall face k.
    owners: Vec<usize>,
    /// Least-squares stencil of D: neighbours `stencil[offsets[k]..offsets[k + 1]]` as
    /// (wall face j, weight vector a_j) with $∇_s φ = \sum_j a_j (φ_j − φ_k)$.
    offsets: Vec<usize>,
    stencil: Vec<(usize, Vec3)>,
}

/// The fit of one wall face at one time level.
#[derive(Debug, Clone, Copy)]
pub struct WallFit {
    /// Velocity of the wall $u_w$.
    pub velocity: Vec3,
    /// Wall shear rate γ at the foot (tangential).
    pub shear: Vec3,
    /// Tangential gradient D of γ.
    pub shear_gradient: Mat3,
    /// Tangential δ² coefficient q = ½ ∂²u_t/∂n² at the foot.
    pub curvature: Vec3,
    /// The wall-normal velocity $u_n = c δ^2 + e δ^3$: (c, e).
    pub normal: [f64; 2],
}

impl WallFit {
    /// Whether every coefficient is finite.
    pub fn is_finite(&self) -> bool {
        let v = |v: &Vec3| v.iter().all(|c| c.is_finite());
        v(&self.velocity)
            && v(&self.shear)
            && v(&self.curvature)
            && self.shear_gradient.iter().all(|c| c.is_finite())
            && self.normal.iter().all(|c| c.is_finite())
    }
}

/// Largest |e| ρ / |c| of the cubic term in the wall-normal velocity: the cell's value may move
/// u_n at its centre by at most this fraction of continuity's δ² term, so u_n keeps its sign
/// below the centre and no spurious stagnation layer appears inside the wall cell.
const MAX_CUBIC: f64 = 1.0;

impl WallGeometry {
    /// The wall faces `faces` (boundary faces) of `mesh`.
    pub fn new(mesh: &PolyMesh, faces: &[u32]) -> Self {
        let n = faces.len();
        let (mut normals, mut centres, mut feet, mut depths, mut owners) = (
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
            Vec::with_capacity(n),
        );
        for &f in faces {
            let f = f as usize;
            let normal = -mesh.face_areas()[f].normalize();
            let owner = mesh.owner(f);
            let centre = mesh.face_centres()[f];
            let cell = mesh.cell_centres()[owner];
            let depth = normal.dot(&(cell - centre));
            normals.push(normal);
            centres.push(centre);
            feet.push(cell - normal * depth);
            depths.push(depth.abs());
            owners.push(owner);
        }
        // Wall faces sharing a vertex.
        let mut by_vertex: Vec<(u32, usize)> = faces
            .iter()
            .enumerate()
            .flat_map(|(k, &f)| mesh.face(f as usize).iter().map(move |&v| (v, k)))
            .collect();
        by_vertex.sort_unstable();
        let mut offsets = Vec::with_capacity(n + 1);
        offsets.push(0);
        let mut stencil = Vec::new();
        let mut near: Vec<usize> = Vec::new();
        for (k, &f) in faces.iter().enumerate() {
            near.clear();
            for v in mesh.face(f as usize) {
                let from = by_vertex.partition_point(|e| e.0 < *v);
                near.extend(
                    by_vertex[from..]
                        .iter()
                        .take_while(|e| e.0 == *v)
                        .map(|e| e.1)
                        .filter(|&j| j != k && normals[j].dot(&normals[k]) > SAME_WALL),
                );
            }
            near.sort_unstable();
            near.dedup();
            let (e1, e2) = tangent_basis(&normals[k]);
            let offsets_2d: Vec<(usize, [f64; 2], f64)> = near
                .iter()
                .map(|&j| {
                    let d = feet[j] - feet[k];
                    (
                        j,
                        [e1.dot(&d), e2.dot(&d)],
                        1.0 / d.norm_squared().max(f64::MIN_POSITIVE),
                    )
                })
                .collect();
            let (mut a, mut b, mut c) = (0.0, 0.0, 0.0);
            for (_, t, w) in &offsets_2d {
                a += w * t[0] * t[0];
                b += w * t[0] * t[1];
                c += w * t[1] * t[1];
            }
            let det = a * c - b * b;
            let trace = a + c;
            // Smallest over largest eigenvalue of [[a, b], [b, c]] ≥ det / trace².
            if trace > 0.0 && det > MIN_SPREAD * trace * trace {
                for (j, t, w) in offsets_2d {
                    // A⁻¹ w t in the (e1, e2) basis, returned as a vector of the tangent plane.
                    let (g1, g2) = ((c * t[0] - b * t[1]) * w / det, (a * t[1] - b * t[0]) * w / det);
                    stencil.push((j, e1 * g1 + e2 * g2));
                }
            }
            offsets.push(stencil.len());
        }
        Self {
            normals,
            centres,
            feet,
            depths,
            owners,
            offsets,
            stencil,
        }
    }

    /// Number of wall faces.
    pub fn len(&self) -> usize {
        self.depths.len()
    }

    /// Whether there are no wall faces.
    pub fn is_empty(&self) -> bool {
        self.depths.is_empty()
    }

    /// Depth ρ of wall face k's cell centre above the face's plane.
    pub fn depth(&self, k: usize) -> f64 {
        self.depths[k]
    }

    /// The fits of every wall face for one time level: wall velocities `velocity[k]`, the cell
    /// values `u` and the cell gradients `grad`.
    pub fn fits(&self, velocity: &[Vec3], u: &[Vec3], grad: &[Mat3]) -> Vec<WallFit> {
        let tangential = |n: &Vec3, v: Vec3| v - n * n.dot(&v);
        // γ and q from the profile u_t = γδ + qδ² through the centre's value and normal
        // derivative: γ = 2(u_o − u_w)/ρ − G_o n, q = (G_o n − γ)/(2ρ).
        let profiles: Vec<(Vec3, Vec3)> = (0..self.len())
            .map(|k| {
                let (n, o) = (self.normals[k], self.owners[k]);
                let depth = self.depths[k];
                let slope = tangential(&n, grad[o] * n);
                if depth > 0.0 {
                    let shear = tangential(&n, (u[o] - velocity[k]) * (2.0 / depth)) - slope;
                    (shear, (slope - shear) / (2.0 * depth))
                } else {
                    (slope, Vec3::zeros())
                }
            })
            .collect();
        (0..self.len())
            .map(|k| {
                let n = self.normals[k];
                let (shear, curvature) = profiles[k];
                let mut d = Mat3::zeros();
                for (j, a) in &self.stencil[self.offsets[k]..self.offsets[k + 1]] {
                    d += (profiles[*j].0 - shear) * a.transpose();
                }
                // Only the tangential components of γ vary along the wall at this order.
                let project = Mat3::identity() - n * n.transpose();
                let d = project * d;
                let c = -0.5 * d.trace();
                let depth = self.depths[k];
                let e = if depth > 0.0 {
                    let bound = MAX_CUBIC * c.abs() / depth;
                    let fitted = ((u[self.owners[k]] - velocity[k]).dot(&n) - c * depth * depth) / depth.powi(3);
                    // max/min, not clamp: an overflowing field makes the bound NaN, and
                    // `FoamFlow::new` refuses the non-finite fit instead of panicking here.
                    fitted.max(-bound).min(bound)
                } else {
                    0.0
                };
                WallFit {
                    velocity: velocity[k],
                    shear,
                    shear_gradient: d,
                    curvature,
                    normal: [c, e],
                }
            })
            .collect()
    }

    /// u and ∇u of wall face k's fit at x (module docs).
    pub fn evaluate(&self, k: usize, fit: &WallFit, x: &Vec3) -> (Vec3, Mat3) {
        let n = self.normals[k];
        let delta = n.dot(&(x - self.centres[k]));
        let along = x - self.feet[k];
        let r_t = along - n * n.dot(&along);
        let d = fit.shear_gradient;
        let g = fit.shear + d * r_t;
        let [c, e] = fit.normal;
        let u = fit.velocity + g * delta + fit.curvature * (delta * delta) + n * (delta * delta * (c + e * delta));
        let slope = g + fit.curvature * (2.0 * delta) + n * (delta * (2.0 * c + 3.0 * e * delta));
        let grad = slope * n.transpose() + d * delta;
        (u, grad)
    }

    /// The cell owning each wall face.
    pub fn owners(&self) -> &[usize] {
        &self.owners
    }
}

/// Two unit vectors that complete the unit vector n to a right-handed orthonormal basis.
fn tangent_basis(n: &Vec3) -> (Vec3, Vec3) {
    // Cross with the axis least aligned with n: |n × a| ≥ √(2/3).
    let axis = if n[0].abs() <= n[1].abs() && n[0].abs() <= n[2].abs() {
        Vec3::x()
    } else if n[1].abs() <= n[2].abs() {
        Vec3::y()
    } else {
        Vec3::z()
    };
    let e1 = n.cross(&axis).normalize();
    (e1, n.cross(&e1))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tangent_basis_is_orthonormal() {
        for n in [Vec3::x(), -Vec3::z(), Vec3::new(1.0, -2.0, 0.5).normalize()] {
            let (e1, e2) = tangent_basis(&n);
            for (a, b, want) in [(e1, e1, 1.0), (e2, e2, 1.0), (e1, e2, 0.0), (e1, n, 0.0), (e2, n, 0.0)] {
                assert!((a.dot(&b) - want).abs() < 1e-15);
            }
        }
    }
}

//! A continuous velocity field from the cellwise-linear reconstruction: a partition of unity
//! over the cells' linear fits.
//!
//! # Why
//! [`FoamFlow`] evaluates the linear fit of the cell that contains x, so u jumps by O(h²|∇²u|)
//! across every face. An adaptive integrator pays for each jump with rejected steps (its error
//! estimate sees the kink in v), and where the fits on both sides of a face push towards it a
//! particle slides along the face while every step is rejected (a Filippov sliding mode): on
//! the airway bifurcation 1 particle in 20 needed more than 10⁵ steps at rtol 10⁻⁵.
//!
//! # Interpolant
//! With L_c(x) = u_c + G_c (x − x_c) the fit of cell c (exact for linear fields,
//! [`super::reconstruct`]) and the Wendland (1995) C² weight
//! $\phi(s) = (1 − s)^4 (4s + 1)$ for s < 1 (0 beyond),
//! ```math
//! u(x) = \frac{\sum_c \phi(s_c) L_c(x)}{\sum_c \phi(s_c)}, \qquad
//! \nabla u(x) = \frac{\sum_c \phi(s_c) G_c}{\sum_c \phi(s_c)}.
//! ```
//! Both are continuous in x (the weights vanish with two derivatives at the edge of their
//! support), both reproduce a linear field exactly (every L_c and G_c does, and the weights sum
//! to one; near a no-slip wall, see below), and both keep the O(h²) and O(h) accuracy of the
//! fits. The gradient is the blend of the cells' gradients, not the derivative of the blended
//! u: the particle model takes ∇u as the local linear flow at its centre (paper Fig. 1), which
//! this is to O(h).
//!
//! # Material acceleration
//! The fluid-inertia forces ([`crate::hydro::forces`]) need Du/Dt, and a neutrally buoyant
//! particle follows the sampled u only if Du/Dt is the acceleration of a parcel moving with that
//! u: (u·∇)u with ∇ the derivative of the blended u itself. The blend of gradients differs from
//! it by O(h) — in the Re = 470 cavity by 4–5 % along a particle's path, which the two terms turned
//! into a slip of the same relative size instead of the O(τ_p²) a consistent field leaves. So
//! [`FlowSample::convective`] carries the product rule's derivative,
//! ```math
//! \frac{\partial u}{\partial x} = \frac{\sum_i w_i G_i + \sum_i \big(L_i(x) − u(x)\big)\,∇w_i^T}{\sum_i w_i},
//! ```
//! times u, with $∇\phi(s_c) = −20(1 − s_c)^3 M_c(x − x_c)$ for a cell and
//! $∇\omega_f = (\frac{d\phi}{ds}/s^2 − 2\phi/s^3)(x − q_f)/(H_f d_f)$ for a wall face
//! ($q_f$ its point nearest to x). `grad_u`, and so every dataset without the fluid-inertia
//! terms, is unchanged.
//!
//! # Each cell's support is its own, shaped like the cell
//! $s_c(x)^2 = (x − x_c)^T M_c (x − x_c)$ with $M_c = (σ^2 k_c E_c)^{-1}$, $E_c$ the second
//! moment of the cell's vertices about its centre and $k_c$ the largest $v^T E_c^{-1} v$ over
//! its vertices: the support is the ellipsoid through the cell's farthest vertex (in $E_c$'s
//! metric) scaled by σ = 1.2 ([`OVERLAP`]). So it contains the cell, the containing cell always
//! carries weight, and a thin prism-layer cell's support is as thin as the cell. With one
//! radius for every cell (the largest centre-to-vertex distance, as before), a point in the first
//! prism layer was blended with the fits of the layers above it, each extrapolating its linear
//! fit across the layers: the normal velocity there then depended on how the mesh was layered
//! (airway bifurcation, Stk 0.1: DE 0.069 with 2 layers, 0.051 with 5).
//!
//! # No-slip walls
//! Each fit reproduces a wall's no-slip value only to O(h²), and the wall-normal velocity near
//! a wall is itself O(δ²) (δ the wall distance): the cells' fits get neither right. So the
//! faces of the no-slip walls ([`FoamFlow::walls`]) enter the blend as data too, each with
//! its fit $L_f$ ([`FoamFlow::sample_wall`], [`super::wall_layer`]: the wall velocity, the wall
//! shear times δ and the normal velocity −½δ²∇ₛ·γ that continuity demands) and the weight
//! ```math
//! \omega_f(x) = \phi(s_f) s_f^{-2},\qquad s_f = d_f(x)/H_f,
//! ```
//! $d_f$ the distance from x to the face ([`super::walls`]), capped below at $10^{-12}H_f$,
//! and $H_f$ the wall cell's height over the face's plane (its farthest vertex's; at least
//! $2\rho_f$, $\rho_f$ its centre's depth): the support covers the wall cell. $2\rho_f$ is that
//! height for a prism or hexahedron standing on the face, but a snapped cut cell of triangular
//! section has its centroid at a third of its height: with the support $2\rho_f$ the wall fits
//! faded out within the wall cell of the snapped Taylor–Couette annuli without layers, and the
//! cells' own linear fits (first order in ∇u) carried the blend at half the first cell's mean
//! height over the thin cut cells (`paper-figures/near-wall/NOTES.md`, cause 3, item 3):
//! ```math
//! u(x) = \frac{\sum_c \phi_c L_c(x) + \sum_f \omega_f L_f(x)}{\sum_c \phi_c + \sum_f \omega_f},
//! \qquad
//! \nabla u(x) = \frac{\sum_c \phi_c G_c + \sum_f \omega_f G_f}{\sum_c \phi_c + \sum_f \omega_f}.
//! ```
//! - *The wall cells' own fits*: a cell that owns wall faces enters the blend with the mean of
//!   its faces' fits $L_f$ instead of its linear fit, which cannot follow a δ² profile (it
//!   extrapolates the centre's slope to the wall: −2.7·10³ times the exact normal velocity at
//!   1 % of the first cell's height of a stagnation flow). So inside the first cell the blend is
//!   the near-wall expansion: the normal velocity grows as δ² with the coefficient of
//!   continuity and passes through the cell's value, whatever the layering.
//! - *On the wall* $\omega_f$ is infinite (capped at 10²⁴), so u is the wall's velocity.
//! - *Accuracy stays O(h²)*: the wall fit's error is O(δ²) tangentially over δ ≤ H_f.
//! - *Exactness*: every divergence-free linear field is reproduced exactly, with whatever
//!   velocity it gives the wall patches (a moving, transpiring or deforming wall: the wall fit
//!   carries the wall velocity's surface gradient), and a rigidly moving curved wall's
//!   velocity is extended exactly.
//! - *Continuity*: $d_f$ is continuous in x and φ vanishes with two derivatives at s = 1.
//!
//! # Convex edges
//! A wall face's fit is an expansion about its own plane: at a point behind that plane (δ < 0),
//! beyond a convex edge where the wall turns away (the corner of a T-junction, a step), it
//! extrapolates through the wall and reverses its shear. On OpenFOAM's `TJunction` tutorial the
//! inlet duct's side wall, 0.6 mm past the corner, drove the flow into the branch's wall at
//! −1.05 m/s, 1 mm from it, where the cells say +2.9 m/s: 21 of 1 000 tracers stalled on that
//! wall. So a face's weight is multiplied by H(c), c = n·(x − q)/d_f the cosine between its
//! normal and the direction from its nearest point q to x: 1 in front of the face and up to
//! 14.5° behind its plane (a faceted curved wall turns by a few degrees between faces; points
//! above a neighbouring face keep every weight), 0 beyond 30° behind it, smooth between
//! (`in_front`). Its gradient enters ∇ω_f, and concave walls (every point in front of every
//! face near it) are unchanged.
//! Measured against 7°/15°, 25°/45° and no fade: on an exact flow along a convex edge
//! (r^{2/3} sin(2θ/3), h/10 to 1.3h from it) the rms error behind the faces' planes is 0.17,
//! 0.21 (shipped), 0.24 and 0.27 of the field, the largest error 0.64 for each, below the
//! cellwise field's 0.68 (`tests/suite/flow/openfoam/wall_layer.rs`), and on the airway
//! bifurcation none of them changes the fate of any of 10⁵ rigid λ = 20 prolates at Stk 0.3
//! (paired DE difference 0 ± 0; with the fade off 255 records differ, their end points by a
//! median 10⁻⁸ m and at most 1.6 µm).
//!
//! # Just outside the mesh
//! A point inside some cell's support is evaluated even if it lies outside the mesh: the fits
//! extrapolate linearly, exactly for linear fields. Particle boundaries (`contact::MeshBoundary`)
//! measure the gap to the face planes, while location uses the faces' tetrahedral
//! decomposition; on warped snapped faces the two differ by a fraction of the warp, and a
//! particle touching the plane could otherwise have its integrator's trial stages refused tens
//! of µm before the contact is seen (on the airway bifurcation's 0.75 mm mesh: 6 in 40
//! particles). Farther out (in no support) the point is refused as by [`FoamFlow`], with the
//! nearest patch.

use super::grid::BallGrid;
use super::memo;
use super::walls::WallFaces;
use super::{FoamError, FoamFlow};
use crate::error::FlowError;
use crate::flow::{FlowField, FlowSample, Isometry};
use crate::tensor::{Mat3, Vec3};

/// [`FoamFlow`] blended into a continuous field (module docs).
#[derive(Debug, Clone)]
pub struct BlendedFlow {
    flow: FoamFlow,
    /// Each cell's support ellipsoid's bounding ball (its centre, the radius of the sphere
    /// around the ellipsoid), binned.
    balls: BallGrid,
    /// Each cell's support ellipsoid: $M_c$.
    metrics: Vec<Mat3>,
    /// The no-slip wall faces ([`FoamFlow::walls`]), found within their cells' height of a sample.
    walls: WallFaces,
    /// The wall faces owned by cell c: `cell_walls[wall_offsets[c]..wall_offsets[c + 1]]`.
    wall_offsets: Vec<u32>,
    cell_walls: Vec<u32>,
    /// The convex fade's cosines ([`BEHIND`]; `None`: no fade).
    fade: Option<(f64, f64)>,
    /// Identity of this field for [`memo`] (a clone shares it: same data).
    id: u64,
}

/// Scale σ of a cell's support over the ellipsoid through its vertices: neighbouring supports
/// overlap, so every point (a cell's vertex too, at s = 1/σ) lies inside some support, and the
/// blend moves from cell to cell over a fraction of a cell. Not more: with σ = 1.5 the second
/// prism layer's linear fits reached the first cell's centre and moved the normal velocity of
/// a stagnation flow there by 8 %; with 1.2 they stop above it.
pub const OVERLAP: f64 = 1.2;

/// Smallest wall distance, relative to the wall cell's height, in a wall weight: it caps the
/// weight at 10²⁴, where the cells' share of the blend is below round-off, so u on a wall is
/// its wall velocity.
const MIN_WALL_DISTANCE: f64 = 1e-12;

/// Wendland's C² weight on s = d/r ∈ [0, 1].
fn weight(s: f64) -> f64 {
    if s >= 1.0 {
        0.0
    } else {
        let t = 1.0 - s;
        t * t * t * t * (4.0 * s + 1.0)
    }
}

/// Cosines c = n·(x − q)/|x − q| of the direction from a wall face's nearest point q to x
/// below which the face's fit has no weight, and above which it has its full weight (module
/// docs, Convex edges): 30° and 14.5° behind the face's plane.
const BEHIND: (f64, f64) = (-0.5, -0.25);

/// The factor H(c) of a wall face's weight and dH/dc for the fade's cosines (lo, hi) = `fade`
/// ([`BEHIND`]): 0 for c ≤ lo (x well behind the face's plane), 1 for c ≥ hi, and the quintic
/// smoothstep 6σ⁵ − 15σ⁴ + 10σ³ of σ = (c − lo)/(hi − lo) between, which joins both with two
/// continuous derivatives, so the blend stays C¹. Without a fade, 1.
fn in_front(c: f64, fade: Option<(f64, f64)>) -> (f64, f64) {
    let Some((lo, hi)) = fade else {
        return (1.0, 0.0);
    };
    if c <= lo {
        (0.0, 0.0)
    } else if c >= hi {
        (1.0, 0.0)
    } else {
        let sigma = (c - lo) / (hi - lo);
        let s2 = sigma * sigma;
        let h = s2 * sigma * (10.0 + sigma * (6.0 * sigma - 15.0));
        let slope = 30.0 * s2 * (1.0 - sigma) * (1.0 - sigma) / (hi - lo);
        (h, slope)
    }
}

/// Support of cell c (module docs): $M_c$ and the largest semi-axis of its ellipsoid; `None` for
/// a cell whose vertices do not span space.
fn support(mesh: &super::PolyMesh, c: usize) -> Option<(Mat3, f64)> {
    let centre = mesh.cell_centres()[c];
    let mut vertices: Vec<u32> = mesh
        .cell_faces(c)
        .iter()
        .flat_map(|&f| mesh.face(f as usize).iter().copied())
        .collect();
    vertices.sort_unstable();
    vertices.dedup();
    let offsets: Vec<Vec3> = vertices.iter().map(|&v| mesh.points()[v as usize] - centre).collect();
    let moment = offsets.iter().fold(Mat3::zeros(), |m, d| m + d * d.transpose()) / offsets.len() as f64;
    let inverse = moment.try_inverse()?;
    let k = offsets.iter().map(|d| d.dot(&(inverse * d))).fold(0.0, f64::max);
    let largest = moment.symmetric_eigenvalues().max();
    let metric = inverse / (OVERLAP * OVERLAP * k);
    let radius = OVERLAP * (k * largest).sqrt();
    (metric.iter().all(|m| m.is_finite()) && radius.is_finite() && radius > 0.0).then_some((metric, radius))
}

impl BlendedFlow {
    /// The cellwise field's [`FoamFlow::fingerprint`], marked as blended (the blend is
    /// computed from it by the code).
    pub fn fingerprint(&self) -> String {
        format!("blended {}", self.flow.fingerprint())
    }

    /// Blend `flow` (module docs); an error if a cell's vertices do not span space or a
    /// coordinate is not finite (near f64::MAX).
    pub fn new(flow: FoamFlow) -> Result<Self, FoamError> {
        let mesh = flow.mesh();
        let supports = (0..mesh.n_cells())
            .map(|c| {
                support(mesh, c).ok_or_else(|| FoamError::Mesh {
                    reason: format!("cannot blend cell {c}: its vertices do not span space or are not finite"),
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let (metrics, radii): (Vec<Mat3>, Vec<f64>) = supports.into_iter().unzip();
        let balls = BallGrid::new(mesh.cell_centres(), &radii).ok_or_else(|| FoamError::Mesh {
            reason: "cannot bin the cell supports for blending: a centre or radius is not finite".into(),
        })?;
        let layer = flow.wall_layer();
        let heights: Vec<f64> = (0..layer.len()).map(|k| layer.cell_height(k)).collect();
        let walls = WallFaces::new(mesh, flow.walls(), &heights).ok_or_else(|| FoamError::Mesh {
            reason: "cannot bin the wall faces for blending: a face centre or depth is not finite".into(),
        })?;
        let mut owned: Vec<(usize, u32)> = layer.owners().iter().enumerate().map(|(k, &c)| (c, k as u32)).collect();
        owned.sort_unstable();
        let mut wall_offsets = vec![0u32; mesh.n_cells() + 1];
        for &(c, _) in &owned {
            wall_offsets[c + 1] += 1;
        }
        for c in 0..mesh.n_cells() {
            wall_offsets[c + 1] += wall_offsets[c];
        }
        Ok(Self {
            flow,
            balls,
            metrics,
            walls,
            wall_offsets,
            cell_walls: owned.into_iter().map(|(_, k)| k).collect(),
            fade: Some(BEHIND),
            id: memo::new_id(),
        })
    }

    /// The same blend with the convex fade's cosines (lo, hi) in place of [`BEHIND`] (module
    /// docs, Convex edges; lo < hi ≤ 0), or with no fade (`None`). Only to measure the shipped
    /// choice against others (`tests/suite/flow/openfoam/wall_layer.rs`); `None` for cosines
    /// out of order or outside −1 … 0.
    #[doc(hidden)]
    pub fn with_convex_fade(mut self, fade: Option<(f64, f64)>) -> Option<Self> {
        if let Some((lo, hi)) = fade
            && !(-1.0 <= lo && lo < hi && hi <= 0.0)
        {
            return None;
        }
        self.fade = fade;
        self.id = memo::new_id();
        Some(self)
    }

    /// The no-slip wall faces and their supports $H_f$, the wall cells' heights (module docs).
    pub(super) fn wall_faces(&self) -> &WallFaces {
        &self.walls
    }

    /// The radius of the smallest cell support that holds x (the length over which the blend
    /// changes from fit to fit there), `None` where none does.
    pub(super) fn finest_support(&self, x: &Vec3) -> Option<f64> {
        let mut finest: Option<f64> = None;
        self.balls.for_each_containing(x, |c, _, d| {
            let r = self.balls.radius(c);
            if d < r {
                finest = Some(finest.map_or(r, |f| f.min(r)));
            }
        });
        finest
    }

    /// The radius of the largest cell support.
    pub fn radius(&self) -> f64 {
        self.balls.largest_radius()
    }

    /// The fit of cell c in the blend: its linear fit, or for a wall cell the mean of its wall
    /// faces' near-wall fits (module docs).
    fn cell_fit(&self, c: usize, x: &Vec3, t: f64) -> FlowSample {
        let walls = &self.cell_walls[self.wall_offsets[c] as usize..self.wall_offsets[c + 1] as usize];
        if walls.is_empty() {
            return self.flow.sample_cell(c, x, t);
        }
        let (mut u, mut grad_u, mut du_dt) = (Vec3::zeros(), Mat3::zeros(), Vec3::zeros());
        for &k in walls {
            let s = self.flow.sample_wall(k as usize, x, t);
            u += s.u;
            grad_u += s.grad_u;
            du_dt += s.du_dt;
        }
        let n = walls.len() as f64;
        FlowSample::new(u / n, grad_u / n, du_dt / n)
    }

    /// The cellwise field underneath.
    pub fn cellwise(&self) -> &FoamFlow {
        &self.flow
    }

    /// Forget the samples remembered for this field: its levels are about to change
    /// ([`super::Windowed::cellwise_mut`]). A new identity, so no thread's memo matches.
    pub(super) fn forget_samples(&mut self) {
        self.id = memo::new_id();
    }

    /// The cellwise field underneath, to replace its levels.
    pub(super) fn cellwise_levels(&mut self) -> &mut FoamFlow {
        &mut self.flow
    }
}

impl FlowField for BlendedFlow {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        crate::flow::check_query(x, t)?;
        self.flow.check_time(t)?;
        match self.flow.images() {
            Some(images) => images.sample(
                x,
                |y| memo::remembered(self.id, y, t, || self.blend(y, t)),
                |y| self.flow.outside(y),
            ),
            None => memo::remembered(self.id, x, t, || self.blend(x, t)),
        }
    }

    fn image(&self, x: &Vec3, t: f64) -> Option<crate::flow::Crossing> {
        self.flow.image(x, t)
    }

    fn strain_rate(&self) -> Option<f64> {
        self.flow.strain_rate()
    }
}

impl BlendedFlow {
    /// The blend at (x, t) (module docs), with the supports seen across the patches particles
    /// pass through ([`super::images`]): where x lies within a support's reach of a cyclic
    /// patch, a symmetry plane or a wedge, the cells and wall faces whose supports hold its
    /// image beyond that patch join the blend with their fits pulled back, so that the blend
    /// near the patch is the periodic (or mirrored) continuation's.
    fn blend(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        let mut blend = Blend::default();
        self.gather(&mut blend, x, None, t);
        if let Some(images) = self.flow.images() {
            let reach = self.balls.largest_radius().max(self.walls.reach());
            for map in images.near(x, reach) {
                self.gather(&mut blend, &map.point(x), Some(&map), t);
            }
        }
        match blend.finish() {
            Some(sample) => Ok(sample),
            // No support contains x: outside the mesh (refused with the nearest patch), or
            // inside on the edge of its cell's support (that cell's fit).
            None => self.flow.sample(x, t),
        }
    }

    /// Add to `blend` the supports that hold y, with their fits and weight gradients pulled
    /// back by `map` where y is a point's image ($∇_x w = Q^T ∇_y w$).
    fn gather(&self, blend: &mut Blend, y: &Vec3, map: Option<&Isometry>, t: f64) {
        let mut add = |w: f64, grad_w: Vec3, fit: FlowSample| match map {
            None => blend.add(w, grad_w, fit),
            Some(m) => blend.add(w, m.q.transpose() * grad_w, m.pull(&fit)),
        };
        self.balls.for_each_containing(y, |c, centre, _| {
            let offset = y - centre;
            let metric_offset = self.metrics[c] * offset;
            let s = offset.dot(&metric_offset).sqrt();
            let w = weight(s);
            if w > 0.0 {
                // ∇φ(s) = φ'(s) ∇s with φ'(s) = −20 s (1 − s)³ and ∇s = M_c (x − x_c)/s.
                let t3 = (1.0 - s) * (1.0 - s) * (1.0 - s);
                add(w, metric_offset * (-20.0 * t3), self.cell_fit(c, y, t));
            }
        });
        let layer = self.flow.wall_layer();
        self.walls.for_each_within(y, |k, away, height| {
            let d = away.norm();
            let floor = MIN_WALL_DISTANCE * height;
            let s = d.max(floor) / height;
            let w = weight(s) / (s * s);
            // ∇ω_f = (φ'(s)/s² − 2φ(s)/s³) ∇s, ∇s = (x − q)/(d h); zero where the cap holds s.
            let grad_w = if d > floor {
                let t3 = (1.0 - s) * (1.0 - s) * (1.0 - s);
                let slope = -20.0 * t3 / s - 2.0 * weight(s) / (s * s * s);
                away * (slope / (d * height))
            } else {
                Vec3::zeros()
            };
            // Behind the face's plane (module docs, Convex edges): ω_f H(c), c = n·(x − q)/d.
            let (h, grad_h) = match d > 0.0 {
                true => {
                    let n = layer.normal(k);
                    let c = n.dot(&away) / d;
                    let (h, slope) = in_front(c, self.fade);
                    // ∇c = (n − c (x − q)/d)/d: ∇(n·(x − q)) = n in every Voronoi region of a
                    // planar face, ∇d = (x − q)/d.
                    (h, (n - away * (c / d)) * (slope / d))
                }
                false => (1.0, Vec3::zeros()),
            };
            if h > 0.0 {
                add(w * h, grad_w * h + grad_h * w, self.flow.sample_wall(k, y, t));
            }
        });
    }
}

/// The sums of the blend (module docs): the weights w_i, their gradients, and the fits L_i
/// with their gradients G_i and time derivatives.
#[derive(Default)]
struct Blend {
    w: f64,
    grad_w: Vec3,
    u: Vec3,
    grad_u: Mat3,
    du_dt: Vec3,
    /// $\sum_i L_i(x) ∇w_i^T$.
    u_grad_w: Mat3,
}

impl Blend {
    fn add(&mut self, w: f64, grad_w: Vec3, fit: FlowSample) {
        self.w += w;
        self.grad_w += grad_w;
        self.u += fit.u * w;
        self.grad_u += fit.grad_u * w;
        self.du_dt += fit.du_dt * w;
        self.u_grad_w += fit.u * grad_w.transpose();
    }

    /// The blended sample, `None` without weight. Its convective acceleration is the derivative
    /// of the blended u along u (module docs, Material acceleration).
    fn finish(self) -> Option<FlowSample> {
        if self.w <= 0.0 {
            return None;
        }
        let u = self.u / self.w;
        let derivative = (self.grad_u + self.u_grad_w - u * self.grad_w.transpose()) / self.w;
        Some(FlowSample {
            u,
            grad_u: self.grad_u / self.w,
            du_dt: self.du_dt / self.w,
            convective: derivative * u,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flow::openfoam::{cavity_block, read_vol_field};

    /// The shipped 12³ CI cavity (`reference-data/cavity-ci-foam`, L = 0.1 m, lid 0.0813 m/s),
    /// its velocities times `scale`.
    fn ci_cavity_scaled(scale: f64) -> (BlendedFlow, f64, f64) {
        let mesh = cavity_block(12, 0.1).unwrap();
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("reference-data/cavity-ci-foam");
        let mut u = read_vol_field(&dir, "U", &mesh, 3).unwrap();
        u.internal
            .iter_mut()
            .chain(u.boundary.iter_mut())
            .for_each(|v| *v *= scale);
        let flow = BlendedFlow::new(FoamFlow::new(mesh, vec![(0.0, u)]).unwrap()).unwrap();
        (flow, 0.1, 0.0813 * scale)
    }

    fn ci_cavity() -> (BlendedFlow, f64, f64) {
        ci_cavity_scaled(1.0)
    }

    /// The memo of the last sample answers only the same field at the same (x, t): a second
    /// field at the same point (twice the velocities) gets its own u, a repeat gets the first
    /// answer bit for bit, and a point 1 ulp away is evaluated again.
    #[test]
    fn the_last_sample_is_reused_only_for_the_same_field_and_point() {
        let ((one, ..), (two, ..)) = (ci_cavity(), ci_cavity_scaled(2.0));
        let x = Vec3::new(0.031, 0.047, 0.062);
        let first = one.sample(&x, 0.0).unwrap();
        assert_eq!(two.sample(&x, 0.0).unwrap().u, first.u * 2.0);
        assert_eq!(one.sample(&x, 0.0).unwrap(), first);
        assert_eq!(one.sample(&x, 0.0).unwrap(), one.blend(&x, 0.0).unwrap());
        let next = Vec3::new(f64::from_bits(x[0].to_bits() + 1), x[1], x[2]);
        assert_eq!(one.sample(&next, 0.0).unwrap(), one.blend(&next, 0.0).unwrap());
    }

    /// The convective acceleration is the derivative of the blended u along u: against the
    /// central difference of u over ±h along u, at points all over the 12³ CI cavity, from its
    /// centre to 1/40 of the first cell's depth at the walls and into the lid's corners, off
    /// the grid lines (where u is C¹ only: the distance to a face's edge region). The fits and
    /// weights change over ℓ, the smaller of a cell (L/12) and the distance to the nearest wall;
    /// with h = 10⁻⁴ℓ the central difference's truncation is about (h/ℓ)²/6 ≈ 2·10⁻⁹ of
    /// |u|²/ℓ, and its round-off grows as ε|u|/h where h is a few nm (in the lid's corners; up to
    /// 7·10⁻⁷ of U²/L there). 10⁻⁵ of |(u·∇)u| + U²/L is ten times that, and 10⁷ times below
    /// the gap to the blend of gradients (up to 2.5·10² U²/L in the corners; printed, and
    /// required to exceed 10⁻³ so the test can tell the two apart).
    #[test]
    fn convective_acceleration_is_the_derivative_of_u_along_u() {
        let (flow, edge, lid) = ci_cavity();
        let scale = lid * lid / edge;
        let (mut largest_gap, mut worst): (f64, f64) = (0.0, 0.0);
        let fractions = [0.001, 0.013, 0.04, 0.1, 0.27, 0.47, 0.73, 0.9, 0.96, 0.995];
        for &a in &fractions {
            for &b in &fractions {
                for &c in &[0.03, 0.53, 0.985, 0.9995] {
                    let x = Vec3::new(a, b, c) * edge;
                    let wall = [a, b, c, 1.0 - a, 1.0 - b, 1.0 - c]
                        .into_iter()
                        .fold(1.0 / 12.0, f64::min);
                    let h = 1e-4 * wall * edge;
                    let s = flow.sample(&x, 0.0).unwrap();
                    let speed = s.u.norm();
                    if speed < 1e-9 * lid {
                        continue;
                    }
                    let along = s.u / speed;
                    let ahead = flow.sample(&(x + along * h), 0.0).unwrap().u;
                    let behind = flow.sample(&(x - along * h), 0.0).unwrap().u;
                    let difference = (ahead - behind) * (speed / (2.0 * h));
                    let error = (s.convective - difference).norm() / (s.convective.norm() + scale);
                    worst = worst.max(error);
                    assert!(
                        error < 1e-5,
                        "at {x:?}: (u·∇)u {:?}, difference {difference:?}",
                        s.convective
                    );
                    largest_gap = largest_gap.max((s.grad_u * s.u - s.convective).norm() / scale);
                }
            }
        }
        println!("largest |(∇u)_blend u − (u·∇)u| / (U²/L): {largest_gap:.3e}; worst difference {worst:.3e}");
        assert!(largest_gap > 1e-3, "the test cannot tell the two apart");
    }
}

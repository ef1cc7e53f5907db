//! The flow next to a wall to second order, with the wall's own velocity and the wall-normal
//! velocity that continuity demands: the wall fits of [`super::BlendedFlow`].
//!
//! # The near-wall expansion
//! Take a flat wall with inward unit normal n, distance δ = n·(x − x_f) from the face's plane
//! and tangential offset r, moving with a velocity $u_w(r)$ that may vary along it (a rotating
//! or sliding wall, a transpiring or deforming one, an imposed verification field): its surface
//! gradient is $W = ∇_s u_w$ ($W n = 0$). The field's tangential derivatives on the wall are
//! the wall's, so
//! ```math
//! u(r, δ) = u_w(r) + δ\,\big(γ(r) + a\,n\big) + O(δ^2), \qquad γ = (I − nn^T)\,\partial u/\partial n\big|_{δ=0},
//! ```
//! γ the wall shear rate (a tangential vector). Continuity, ∂u_n/∂n = −∇ₛ·u_t, fixes the
//! normal terms order by order: on the wall $a = −∇_s·u_w = −\operatorname{tr} W$, and one order
//! up
//! ```math
//! u_n − u_{w,n} = a\,δ − \tfrac12\,δ^2\,∇_s·γ + O(δ^3).
//! ```
//! At a wall at rest (or sliding rigidly in its own plane) a = 0 and this δ² growth is what
//! carries slow particles to a wall near a stagnation point (the carina of an airway
//! bifurcation): without it they hover in the first cell. On a wall of curvature κ the metric
//! factors change these by a relative O(κδ).
//!
//! # The fit of wall face f
//! With $y = x − x_f$, δ = n·y the height over the face's plane, $p_f$ the foot of the wall
//! cell's centre on the face's plane, $r_t = (I − n n^T)(x − p_f)$ and $D_f$ the surface
//! gradient of γ at $p_f$:
//! ```math
//! L_f(x) = \underbrace{u_w + W_f\,y + (a_f n + m_f)\,δ}_{U_f(x):\ \text{the wall's motion}}
//!   + δ\,(γ_f + D_f r_t) + δ^2 q_f + (c_f δ^2 + e_f δ^3)\,n,
//! ```
//! ```math
//! a_f = −\operatorname{tr} W_f,\qquad m_f = −(I − nn^T)\,W_f^T n,\qquad c_f = −\tfrac12 \operatorname{tr} D_f,
//! ```
//! ```math
//! ∇L_f = W_f + (a_f n + m_f)\,n^T + \big(γ_f + D_f r_t + 2δ q_f + (2c_f δ + 3e_f δ^2)\,n\big)\,n^T + δ\,D_f ,
//! ```
//! the exact derivative of $L_f$, and the fit's gradient $G_f = ∇L_f + γ_f (K_f r_c)^T$ with
//! $r_c = (I − n n^T)(x − x_f)$ the offset from the face centre (the last term vanishes on a
//! flat wall, and on a curved one D's normal row acts on $r_c$ too; *Curved walls* below). Its
//! terms:
//! - *Wall motion* $U_f$: $u_w$ the face's value, $W_f$ by least squares over the neighbouring
//!   wall faces' values (below), a from continuity, and $m_f$ the normal derivative a rigid
//!   motion with this W has ($m = Ω × n$ for $u_w = V + Ω × x$), so a rotating wall's velocity
//!   is extended into the fluid exactly, curved or not. The rest of $L_f$ is the shear part,
//!   zero on the wall.
//! - *Tangential*: the profile $u_t − U_{f,t} = γη + qη^2$ through the values $u_o$ of the
//!   wall cell and $u_1$ of the cell above it (a face neighbour of the wall cell, at plane
//!   height ρ₁ and tangential offset $s_1$ from the foot, moved onto the normal through the
//!   foot by its own gradient, $u_1 − G_1 s_1$):
//!   ```math
//!   q = \frac{v_1/η_1 − v_o/η_o}{η_1 − η_o},\qquad γ = \frac{v_o}{η_o} − qη_o,\qquad v = (I − nn^T)\big(u − U_f\big).
//!   ```
//!   η is the height over the osculating wall through the face centre, $δ + \tfrac12 r_c^T K r_c$
//!   (*Curved walls*): the wall cell's centre stands at $η_o = ρ + \tfrac12 s_f^T K s_f$, and the
//!   moved value of the cell above at $η_1 = ρ_1 + \tfrac12 s_f^T K s_f − \tfrac12 s_1^T K s_1$ (the
//!   gradient at its centre carries the shear's turning over $s_1$ linearly, and misses the
//!   quadratic remainder $\tfrac12 γ s_1^T K s_1$). Both corrections are O(h²), but divided by
//!   ρ = O(h) they were first-order errors of γ wherever a snapped cut cell's centre lies off its
//!   face's centre or the cell above is offset (on a flat wall K = 0 and η = δ). Exact for a
//!   quadratic profile, so γ is second order in the cell size and q first: ∇u at δ = O(h) is
//!   second order.
//!
//!   *Which neighbour*: an error ε of the least-squares gradient $G_1$ moves the value by
//!   $ε s_1$ and γ by $ε s_1 ρ/(ρ_1(ρ_1 − ρ))$; the one-sided alternative below moves γ by
//!   the wall cell's own gradient error, with gain 1. So the cell above is the face neighbour
//!   of smallest gain $g = ρ |s_1| / (ρ_1 (ρ_1 − ρ))$ among those with g < 1 and
//!   ρ₁ ≥ 1.5 ρ (`MIN_ABOVE`, for the divided differences' conditioning). The cone |s₁| ≤ ρ₁ − ρ
//!   used before (a sufficient condition: g ≤ 2/3 in it) left a fifth of the wall faces of the
//!   snapped Taylor–Couette annuli without a cell above: cut cells of triangular section
//!   whose neighbours above sit to the sides, |s₁| ≈ 1.0–1.4 (ρ₁ − ρ), the better one at
//!   g ≈ 0.36. Their shears fell back on the one-sided gradient and were the largest errors of
//!   ∇u at half the first cell (∂u_θ/∂r off by 0.03 of |∇u|max at level 0, 0.02 at level 2).
//!   A wall cell with no such neighbour (one cell across a channel) takes the wall cell's
//!   gradient for the normal derivative at ρ, $G_o n − m = γ + 2qρ$, first order (the
//!   least-squares gradient at a wall cell is one-sided).
//! - *Curved walls*: u is a flat-face expansion: the solver's no-slip wall is the faceted
//!   one, which this keeps (measuring δ over the osculating surface instead moved no-slip off
//!   the faces of a concave pipe). ∇u takes the wall's turning, with the shape operator
//!   $K = ∇_s n$ of the faceted wall (least squares over the neighbours' normals, as W):
//!   γ stays tangential along a curved wall, so D's normal row is $−(Kγ)^T$ (the shear
//!   turns with the wall: ∂u_n/∂r_t = −δ(Kγ)ᵀ), and the shear part grows with
//!   the distance from the curved wall, $δ + \tfrac12 r_c^T K r_c$, so ∇u gets
//!   $γ (K r_c)^T$ beside ∇L_f. Both turnings are measured from the face centre, where the
//!   facet's normal is the wall's (K comes from the normals at the face centres), so the
//!   normal part of the shear at the foot is $−(Kγ)·s_f$, $s_f = (I − nn^T)(p_f − x_f)$: from
//!   the foot instead, both were off by $κ|γ||s_f|$, first order wherever a snapped cut cell's
//!   centre lies off its face's centre (∇u at half the first cell of the snapped
//!   Taylor–Couette annuli without layers 0.045, 0.025, 0.015 of its largest value at levels
//!   0–2, against 0.035, 0.018, 0.010 from the face centre). Both are $κ|γ||r_c|$, first order
//!   in the face size, and trace-free together ($γ^T K r_c − (Kγ)·r_c = 0$), so continuity is
//!   unchanged. What is
//!   left is q's and n's turning, O(δκ) relative. On built quarter annuli (Taylor–Couette)
//!   ∇u at half the first cell's height is then second order (it was first order, at about
//!   half of $κ|γ|h/2$). The turning stays out of u: there it would be a normal velocity
//!   $−δ Kγ·r_c$, linear in δ, on a face that stays no-slip, that is a source or sink of
//!   strength $Kγ·r_c$ on the wall, which carried particles' centres onto the faces where the
//!   flow's normal velocity vanishes as δ² (a 90° bend, point contact at Stk 0.2: 0.170 of
//!   1 000 spheres deposited with it, 0.004 without, none by OpenFOAM's tracker;
//!   `wall_layer::a_curved_wall_at_rest_draws_no_flow_into_its_faces`). Without it u off
//!   the face centre misses the exact smooth wall's normal velocity by $δκ|γ||r_c|$, O(h²) at
//!   δ = O(h).
//! - *Normal*: continuity fixes $a_f$ and $c_f$, and the solver's own value at the centre the
//!   next, $e_f = ((u_o − U_f)·n − c_f ρ^2)/ρ^3$, so the fit passes through the
//!   cell's value. The cubic is limited to $|e_f| ρ ≤ |c_f|$ (`MAX_CUBIC`): a finite-volume
//!   value of $u_n$ at a thin cell's centre has an O(1) relative error of its own (it is O(ρ²),
//!   like $u_n$ itself), and the limit keeps the sign of continuity's term below the centre, so
//!   no spurious stagnation layer appears.
//!
//! What is exact: every divergence-free linear field, with any velocity on the wall (moving,
//! transpiring, deforming), on flat walls of any mesh; a rigidly moving wall, flat or curved;
//! the quadratic normal profile of the shear part. What is assumed: an incompressible field
//! (the normal derivative comes from continuity, not from the data, whose own divergence next
//! to a no-slip wall is discretisation error as large as the δ² term); a wall velocity whose
//! tangential variation is linear over a face (W is constant on it: a quadratic wall velocity
//! leaves ∇u first order, as in the cellwise fits, with a larger constant on uniform boxes).
//! What is not exact: a curved wall whose prescribed velocity strains along it (a linear field
//! imposed on a sphere's faces, a deforming or transpiring curved wall). Its extension $U_f$ is
//! the rigid motion's and its surface divergence enters the normal profile over the face's
//! plane, so the fit misses such a field by $O(κδ)$ relative to the strain: on the snapped
//! sphere of the tests with u = c + Bx (|B| = 4) on every patch, at half the first cell 3e-4
//! in u and 0.3 in ∇u at the sphere, 1.4e-4 and 0.026 at the box walls (snapped to within 0.5°
//! of their planes), where the cellwise field is exact. Such faces are found by
//! [`WallGeometry::strain_on_curvature`] and their patches named in the run's warnings
//! (`FoamFlow::strained_walls`).
//!
//! # Edges and corners
//! Where two walls meet at a concave edge (a duct's corner: wall faces sharing a vertex, turned
//! by more than 45° and each rising from the other's plane into the fluid) the velocity
//! vanishes on both, so next to the edge it is $O(δ_k δ_j)$ and parallel to both walls, and its
//! component along $n_j$ grows as $δ_j^2$ (continuity at wall j) however near wall k. Face k's
//! shear part $δ_k(γ + D r_t) + δ_k^2 q$ knows nothing of wall j: a component of γ along
//! $n_j$ would carry fluid through wall j linearly in the distance where the blend weighs both
//! faces alike, next to the edge, and draw tracers into the edge exponentially (on OpenFOAM's
//! `TJunction` tutorial, 5 cells across a 20 mm duct: u·n/δ = −53 s⁻¹ down to δ = 10⁻¹² m, and
//! 2.2 % of the tracers deposited on its edges). So at such a face γ, q and D keep only their
//! components along the edge (none in a corner, where three walls meet): the part taken out is
//! the exact $∂u_{n_j}/∂n_k$ at the face's foot, $O(δ_j^2) = O(h^2)$, within the fit's order.
//! Convex edges (the carina's ridge, a step's corner) keep the fit as it is: fluid near them
//! lies beyond the other wall's plane. So do edges between walls that move differently (a
//! lid-driven cavity's lid and its side walls): there the velocity jumps at the edge, the flow
//! is singular and not parallel to both walls, and projecting the side wall's shear would
//! drop its O(1) part (it stalled a soft prolate of the Re = 470 cavity in 5.7·10⁷ steps).
//!
//! # The surface gradients D and W
//! By least squares over the neighbouring wall faces (those sharing a vertex with f and
//! turned by less than 45° from it, so a sharp edge between two walls is not differenced
//! across), in f's tangent plane with inverse-square distance weights: D from the shears at
//! the feet, W from the wall velocities at the face centres; exact for values linear along
//! the wall. On a curved wall a neighbour's centre lies
//! O(κh²) off f's plane, where a rigid motion's velocity differs by (a n + m) times the offset:
//! W is estimated again with that difference taken out, until it no longer changes (a
//! contraction by O(κh); otherwise W, and ∇u with it, would be first order wherever the
//! stencil is one-sided, and a rigid rotation would not be exact). A wall face with fewer
//! than two independent neighbours (an isolated face) gets D = W = 0, and so no
//! continuity term.
//!
//! # Verification
//! `tests/suite/flow/openfoam/` writes exact fields into boxes meshed as users mesh them
//! (uniform and graded blockMesh, 2 and 5 prism layers; hexahedra and prisms; snappyHexMesh):
//! - divergence-free linear fields with moving, transpiring walls: exact to round-off;
//! - Taylor–Couette flow at a rotating cylinder (quarter annuli, uniform and layered): u and
//!   ∇u at half the first cell's height second order;
//! - Hiemenz's stagnation flow ([`crate::flow::stagnation`]): the normal velocity within 10 %
//!   of the exact one throughout the first cell, v/δ² within 4 % of continuity's coefficient,
//!   u and ∇u at half the first cell's height second order under refinement, and a sphere's
//!   arrival time at the wall within 7 %.

use super::mesh::PolyMesh;
use crate::tensor::{Mat3, Vec3};

/// Smallest cosine of the angle between two wall faces' normals whose shears are differenced
/// for D: 45°. Faceted curved walls turn by a few degrees between faces; a duct's corner by 90°.
const SAME_WALL: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// Smallest component of another wall's normal left in face k's edge directions for it to take
/// one more out (`edge_projector`): the faces of one wall along a duct's edge repeat its
/// direction, and a third wall at a corner is independent by O(1).
const EDGE_INDEPENDENT: f64 = 1e-6;

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
    /// Height of the wall cell over the face's plane: its farthest vertex's (2ρ for a prism or
    /// hexahedron on the face, up to 3ρ for a cut cell of triangular section).
    heights: Vec<f64>,
    /// Owner cell of wall face k.
    owners: Vec<usize>,
    /// Shape operator $K = ∇_s n$ of the faceted wall at face k (symmetric, tangential; zero
    /// on a flat wall): least squares over the neighbours' normals (module docs, Curved walls).
    shapes: Vec<Mat3>,
    /// Least-squares stencils of the surface gradients: neighbours
    /// `stencil[offsets[k]..offsets[k + 1]]` as (wall face j, a_j, b_j) with
    /// $∇_s φ = \sum_j a_j (φ_j − φ_k)$ for values at the feet (the shear γ, for D) and
    /// $\sum_j b_j (φ_j − φ_k)$ for values at the face centres (the wall velocity, for W).
    offsets: Vec<usize>,
    stencil: Vec<(usize, Vec3, Vec3)>,
    /// The cell above the wall cell along the normal, if there is one (module docs).
    above: Vec<Option<Above>>,
    /// The wall faces meeting face k at a concave edge (module docs, *Edges and corners*):
    /// `edge_faces[edge_offsets[k]..edge_offsets[k + 1]]`.
    edge_offsets: Vec<usize>,
    edge_faces: Vec<usize>,
}

/// The second cell of a wall face's normal profile: the wall cell's face neighbour through which
/// a gradient error moves the shear least (module docs, Which neighbour).
#[derive(Debug, Clone, Copy)]
struct Above {
    /// The cell.
    cell: usize,
    /// Height ρ₁ of its centre above the face's plane (ρ₁ ≥ [`MIN_ABOVE`] ρ).
    height: f64,
    /// Tangential offset s₁ of its centre from the wall cell's foot.
    offset: Vec3,
}

/// Most passes of W's off-plane correction (module docs): each shrinks the error by the
/// stencil's κh (0.1 at 8 faces over a quarter circle), so 16 reach round-off for κh ≤ 0.1.
const MAX_MOTION_PASSES: usize = 16;

/// Smallest ρ₁/ρ of the cell above the wall cell: a neighbour beside the wall cell (ρ₁ ≈ ρ)
/// would make the three-point profile's divided differences ill-conditioned.
const MIN_ABOVE: f64 = 1.5;

/// The fit of one wall face at one time level.
#[derive(Debug, Clone, Copy)]
pub struct WallFit {
    /// Velocity of the wall $u_w$ at the face centre.
    pub velocity: Vec3,
    /// Surface gradient $W = ∇_s u_w$ of the wall velocity ($W n = 0$).
    pub velocity_gradient: Mat3,
    /// Normal derivative $a n + m$ of the wall's own motion extended into the fluid: a = −tr W
    /// from continuity, $m = −(I − nn^T) W^T n$ that of a rigid motion (module docs).
    pub rigid_slope: Vec3,
    /// Wall shear rate γ at the foot (tangential).
    pub shear: Vec3,
    /// Surface gradient D of γ: its tangential rows from the neighbours' shears, its normal
    /// row $−(Kγ)^T$ from the wall's turning (module docs, Curved walls).
    pub shear_gradient: Mat3,
    /// Tangential δ² coefficient q = ½ ∂²u_t/∂n² at the foot.
    pub curvature: Vec3,
    /// The wall-normal velocity beyond the wall's motion, $c δ^2 + e δ^3$: (c, e).
    pub normal: [f64; 2],
}

impl WallFit {
    /// Whether every coefficient is finite.
    pub fn is_finite(&self) -> bool {
        let v = |v: &Vec3| v.iter().all(|c| c.is_finite());
        v(&self.velocity)
            && v(&self.shear)
            && v(&self.curvature)
            && v(&self.rigid_slope)
            && self.velocity_gradient.iter().all(|c| c.is_finite())
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
        let (mut normals, mut centres, mut feet, mut depths, mut heights, mut owners) = (
            Vec::with_capacity(n),
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
            let height = mesh
                .cell_faces(owner)
                .iter()
                .flat_map(|&g| mesh.face(g as usize).iter())
                .map(|&v| normal.dot(&(mesh.points()[v as usize] - centre)));
            heights.push(height.fold(2.0 * depth.abs(), f64::max));
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
        let mut shapes = Vec::with_capacity(n);
        let (mut edge_offsets, mut edge_faces) = (vec![0], Vec::new());
        for (k, &f) in faces.iter().enumerate() {
            near.clear();
            let first_across = edge_faces.len();
            for v in mesh.face(f as usize) {
                let from = by_vertex.partition_point(|e| e.0 < *v);
                for j in by_vertex[from..].iter().take_while(|e| e.0 == *v).map(|e| e.1) {
                    if j == k {
                        continue;
                    }
                    if normals[j].dot(&normals[k]) > SAME_WALL {
                        near.push(j);
                    } else if normals[k].dot(&(centres[j] - centres[k])) > 0.0 {
                        edge_faces.push(j);
                    }
                }
            }
            near.sort_unstable();
            near.dedup();
            let mut across = edge_faces.split_off(first_across);
            across.sort_unstable();
            across.dedup();
            edge_faces.append(&mut across);
            edge_offsets.push(edge_faces.len());
            let (e1, e2) = tangent_basis(&normals[k]);
            // One least-squares gradient in k's tangent plane from offsets `at[j] − at[k]`.
            let weights = |at: &[Vec3]| -> Option<Vec<Vec3>> {
                let planar: Vec<([f64; 2], f64)> = near
                    .iter()
                    .map(|&j| {
                        let d = at[j] - at[k];
                        ([e1.dot(&d), e2.dot(&d)], 1.0 / d.norm_squared().max(f64::MIN_POSITIVE))
                    })
                    .collect();
                let (mut a, mut b, mut c) = (0.0, 0.0, 0.0);
                for (t, w) in &planar {
                    a += w * t[0] * t[0];
                    b += w * t[0] * t[1];
                    c += w * t[1] * t[1];
                }
                let det = a * c - b * b;
                let trace = a + c;
                // Smallest over largest eigenvalue of [[a, b], [b, c]] ≥ det / trace².
                (trace > 0.0 && det > MIN_SPREAD * trace * trace).then(|| {
                    planar
                        .iter()
                        .map(|(t, w)| {
                            // A⁻¹ w t in the (e1, e2) basis, as a vector of the tangent plane.
                            let (g1, g2) = ((c * t[0] - b * t[1]) * w / det, (a * t[1] - b * t[0]) * w / det);
                            e1 * g1 + e2 * g2
                        })
                        .collect()
                })
            };
            let mut shape = Mat3::zeros();
            if let (Some(a), Some(b)) = (weights(&feet), weights(&centres)) {
                // K = ∇ₛn from the normals at the face centres, symmetrised in k's tangent plane.
                let raw = near.iter().zip(&b).fold(Mat3::zeros(), |m, (&j, b)| {
                    m + (normals[j] - normals[k]) * b.transpose()
                });
                let planar = Mat3::identity() - normals[k] * normals[k].transpose();
                let raw = planar * raw * planar;
                shape = (raw + raw.transpose()) * 0.5;
                stencil.extend(near.iter().zip(a.into_iter().zip(b)).map(|(&j, (a, b))| (j, a, b)));
            }
            shapes.push(shape);
            offsets.push(stencil.len());
        }
        let above = (0..n)
            .map(|k| above(mesh, owners[k], normals[k], centres[k], feet[k], depths[k]))
            .collect();
        Self {
            normals,
            centres,
            feet,
            depths,
            heights,
            owners,
            shapes,
            offsets,
            stencil,
            above,
            edge_offsets,
            edge_faces,
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

    /// Inward unit normal of wall face k.
    pub fn normal(&self, k: usize) -> Vec3 {
        self.normals[k]
    }

    /// Depth ρ of wall face k's cell centre above the face's plane.
    pub fn depth(&self, k: usize) -> f64 {
        self.depths[k]
    }

    /// Height ρ₁ over wall face k's plane of the cell above its wall cell, the second point of
    /// the shear's profile (module docs, Which neighbour), if there is one.
    pub fn above_height(&self, k: usize) -> Option<f64> {
        self.above[k].map(|a| a.height)
    }

    /// Height of wall face k's cell over the face's plane: its farthest vertex's, at least 2ρ.
    pub fn cell_height(&self, k: usize) -> f64 {
        self.heights[k]
    }

    /// The fits of every wall face for one time level: wall velocities `velocity[k]` (at the
    /// face centres), the cell values `u` and the cell gradients `grad`.
    pub fn fits(&self, velocity: &[Vec3], u: &[Vec3], grad: &[Mat3]) -> Vec<WallFit> {
        let tangential = |n: &Vec3, v: Vec3| v - n * n.dot(&v);
        let neighbours = |k: usize| &self.stencil[self.offsets[k]..self.offsets[k + 1]];
        // The wall's motion: W = ∇ₛu_w (zero where there is no stencil), a = −tr W and the
        // normal derivative m = −(I − nnᵀ)Wᵀn of its rigid extension (module docs).
        let motions: Vec<(Mat3, f64, Vec3)> = (0..self.len())
            .map(|k| {
                let n = self.normals[k];
                // A neighbour's centre lies off k's plane by O(κh²) on a curved wall, where a
                // rigid motion's velocity changes with its normal derivative a n + m (which the
                // surface gradient determines): each estimate of W gives it, and the next takes
                // it out of the differences.
                let estimate = |slope: Vec3| {
                    neighbours(k).iter().fold(Mat3::zeros(), |w, (j, _, b)| {
                        let off = n.dot(&(self.centres[*j] - self.centres[k]));
                        w + (velocity[*j] - velocity[k] - slope * off) * b.transpose()
                    })
                };
                // The correction is a contraction by O(κh): repeated to round-off (a rigid
                // rotation is then exact), at most MAX_MOTION_PASSES times.
                let mut w = estimate(Vec3::zeros());
                for _ in 0..MAX_MOTION_PASSES {
                    let next = estimate(n * -w.trace() - tangential(&n, w.transpose() * n));
                    let change = (next - w).amax();
                    w = next;
                    if change <= f64::EPSILON * w.amax() {
                        break;
                    }
                }
                (w, -w.trace(), -tangential(&n, w.transpose() * n))
            })
            .collect();
        // U_w(x) = u_w + W(x − x_f) + (a n + m) n·(x − x_f): the part of u that moves with the wall.
        let moving = |k: usize, x: Vec3| {
            let (w, a, m) = motions[k];
            let (n, y) = (self.normals[k], x - self.centres[k]);
            velocity[k] + w * y + (n * a + m) * n.dot(&y)
        };
        // At a concave edge between walls moving alike (at rest, or the same velocity at both
        // faces), the directions along the edge (module docs, Edges and corners).
        let along_edges: Vec<Option<Mat3>> = (0..self.len())
            .map(|k| {
                let across = &self.edge_faces[self.edge_offsets[k]..self.edge_offsets[k + 1]];
                let alike = across.iter().filter(|&&j| velocity[j] == velocity[k]);
                edge_projector(&self.normals[k], alike.map(|&j| self.normals[j]))
            })
            .collect();
        // γ and q of the tangential profile u_t − U_w = γδ + qδ² (module docs).
        let profiles: Vec<(Vec3, Vec3)> = (0..self.len())
            .map(|k| {
                let (n, o, depth) = (self.normals[k], self.owners[k], self.depths[k]);
                let m = motions[k].2;
                if depth <= 0.0 {
                    return (tangential(&n, grad[o] * n) - m, Vec3::zeros());
                }
                // Heights η over the osculating wall through the face centre (module docs,
                // Tangential): the foot lies s_f off the face centre, where that wall is
                // ½ s_fᵀK s_f below the face's plane.
                let bend = |s: Vec3| 0.5 * s.dot(&(self.shapes[k] * s));
                let lift = bend(tangential(&n, self.feet[k] - self.centres[k]));
                let depth_o = depth + lift;
                let near = tangential(&n, u[o] - moving(k, self.feet[k] + n * depth)) / depth_o;
                let (shear, curvature) = match self.above[k] {
                    Some(Above { cell, height, offset }) => {
                        let value = u[cell] - grad[cell] * offset - moving(k, self.feet[k] + n * height);
                        // Moved onto the normal by its gradient, the cell above's value misses the
                        // quadratic remainder ½ γ s₁ᵀK s₁ of the shear's turning: it stands at
                        // this height.
                        let height_1 = height + lift - bend(offset);
                        let far = tangential(&n, value) / height_1;
                        let curvature = (far - near) / (height_1 - depth_o);
                        (near - curvature * depth_o, curvature)
                    }
                    None => {
                        let slope = tangential(&n, grad[o] * n) - m;
                        let shear = near * 2.0 - slope;
                        (shear, (slope - shear) / (2.0 * depth))
                    }
                };
                match along_edges[k] {
                    Some(along) => (along * shear, along * curvature),
                    None => (shear, curvature),
                }
            })
            .collect();
        (0..self.len())
            .map(|k| {
                let n = self.normals[k];
                let (shear, curvature) = profiles[k];
                let d = neighbours(k).iter().fold(Mat3::zeros(), |d, (j, a, _)| {
                    d + (profiles[*j].0 - shear) * a.transpose()
                });
                // The tangential components of γ vary along the wall as the data say (at an
                // edge only those along it); its normal component as the wall turns: γ·n = 0
                // along the wall, so ∂(γ·n)/∂r = −Kγ (module docs, Curved walls).
                let project = along_edges[k].unwrap_or_else(|| Mat3::identity() - n * n.transpose());
                let d = project * d - n * (self.shapes[k] * shear).transpose();
                let (w, a, m) = motions[k];
                // Continuity one order up: ∂²u_n/∂n² = −∇ₛ·γ.
                let c = -0.5 * d.trace();
                let depth = self.depths[k];
                let e = if depth > 0.0 {
                    let height = depth;
                    let bound = MAX_CUBIC * c.abs() / height;
                    let rise = (u[self.owners[k]] - moving(k, self.feet[k] + n * depth)).dot(&n) - c * height * height;
                    let fitted = rise / height.powi(3);
                    // max/min, not clamp: an overflowing field makes the bound NaN, and
                    // `FoamFlow::new` refuses the non-finite fit instead of panicking here.
                    fitted.max(-bound).min(bound)
                } else {
                    0.0
                };
                WallFit {
                    velocity: velocity[k],
                    velocity_gradient: w,
                    rigid_slope: n * a + m,
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
        let y = x - self.centres[k];
        let delta = n.dot(&y);
        let along = x - self.feet[k];
        let r_t = along - n * n.dot(&along);
        let (w, d) = (fit.velocity_gradient, fit.shear_gradient);
        // The wall's turning is measured from the face centre, where the facet's normal is the
        // wall's, not from the foot (module docs, Curved walls): D's normal row acts on
        // r_c = r_t + s_f, s_f the foot's tangential offset from the face centre.
        let foot = self.feet[k] - self.centres[k];
        let s_f = foot - n * n.dot(&foot);
        let kr = self.shapes[k] * (r_t + s_f);
        let g = fit.shear + d * r_t - n * (self.shapes[k] * s_f).dot(&fit.shear);
        let [c, e] = fit.normal;
        // u is the flat-face expansion (module docs, Curved walls): the shear's turning, the
        // normal part of g, enters ∇u only. In u it would be a normal velocity linear in δ
        // with the face still no-slip, i.e. a source or sink of strength Kγ·r_c on the face.
        let u = fit.velocity
            + w * y
            + fit.rigid_slope * delta
            + (g - n * n.dot(&g)) * delta
            + fit.curvature * (delta * delta)
            + n * (delta * delta * (c + e * delta));
        let slope = g + fit.curvature * (2.0 * delta) + n * (delta * (2.0 * c + 3.0 * e * delta));
        // The shear part grows with the distance from the curved wall, δ + ½ r_cᵀK r_c, not
        // from the face's plane: its tangential derivative γ (K r_c)ᵀ (module docs, Curved walls).
        let turning = fit.shear * kr.transpose();
        let grad = w + (fit.rigid_slope + slope) * n.transpose() + d * delta + turning;
        (u, grad)
    }

    /// The cell owning each wall face.
    pub fn owners(&self) -> &[usize] {
        &self.owners
    }

    /// Where the fit of face k is not exact for a linear field (module docs, *What is exact*):
    /// a curved wall whose velocity strains along it. Returns $(|S|, |K|)$ with
    /// $S = \operatorname{sym}\big((I − nn^T) W (I − nn^T)\big)$ the surface strain rate of the
    /// wall's velocity and |K| the largest principal curvature, or `None` where either is nil.
    ///
    /// A rigid motion $V + Ω × x$ has $W = Ω_× (I − nn^T)$ (Ω_× the cross-product matrix of
    /// Ω), whose tangential block is skew, so S = 0 is the condition for the rigid extension
    /// $U_f$ to be the motion's own;
    /// the normal row of W (a transpiring wall's) is free in a rigid motion too, and on a flat
    /// wall every W is extended exactly. Floors: K is a least-squares difference of unit
    /// normals, so a flat wall's is round-off of $1/h$: curvature counts from
    /// $|K|\\,ρ >$ [`STRAIN_FLOOR`]; W of a rigid motion is recovered to round-off times the
    /// stencil's conditioning, so strain counts from $|S| >$ [`STRAIN_FLOOR`] $|W|$.
    pub fn strain_on_curvature(&self, k: usize, fit: &WallFit) -> Option<(f64, f64)> {
        let n = self.normals[k];
        let planar = Mat3::identity() - n * n.transpose();
        let tangential = planar * fit.velocity_gradient * planar;
        let strain = ((tangential + tangential.transpose()) * 0.5).norm();
        let curvature = self.shapes[k].symmetric_eigenvalues().amax();
        (strain > STRAIN_FLOOR * fit.velocity_gradient.norm() && curvature * self.depths[k] > STRAIN_FLOOR)
            .then_some((strain, curvature))
    }
}

/// A no-slip wall patch with faces where the wall layer is not exact for a linear field
/// ([`WallGeometry::strain_on_curvature`]): its velocity strains along a curved wall.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct StrainedWall {
    /// The patch's name.
    pub patch: String,
    /// Its faces where the wall strains and curves (at some held time level).
    pub faces: usize,
    /// Its wall faces.
    pub of: usize,
    /// Largest surface strain rate |S| there.
    pub strain: f64,
    /// Largest principal curvature |K| there.
    pub curvature: f64,
}

/// Relative floor below which a wall's surface strain rate and curvature are round-off
/// ([`WallGeometry::strain_on_curvature`]): both are differences over a face's neighbours
/// divided by their spacing, exact to about 1e-13 relative on the meshes of the tests (the
/// stencil's conditioning ≲ 1e3 times ε), so 1e-8 is far above round-off and far below any
/// strain that moves the field measurably.
pub const STRAIN_FLOOR: f64 = 1e-8;

/// The cell above wall cell `owner` (centre at depth `depth` over the face of inward normal
/// `n`, centre `centre`, foot `foot`): of its face neighbours at least [`MIN_ABOVE`] times as
/// high over the face's plane, the one of smallest gain ρ|s₁|/(ρ₁(ρ₁ − ρ)) if that is below 1
/// (module docs, Which neighbour).
fn above(mesh: &PolyMesh, owner: usize, n: Vec3, centre: Vec3, foot: Vec3, depth: f64) -> Option<Above> {
    let mut best: Option<(f64, Above)> = None;
    for &f in mesh.cell_faces(owner) {
        let f = f as usize;
        let Some(neighbour) = mesh.neighbour(f) else {
            continue;
        };
        let cell = if neighbour == owner { mesh.owner(f) } else { neighbour };
        let x = mesh.cell_centres()[cell];
        let height = n.dot(&(x - centre));
        let along = x - foot;
        let offset = along - n * n.dot(&along);
        // How much an error of the neighbour's gradient, carried into its value over the offset,
        // moves γ; the one-sided slope's gain is 1 (module docs, Which neighbour).
        let gain = depth * offset.norm() / (height * (height - depth));
        if height >= MIN_ABOVE * depth && gain < 1.0 && best.is_none_or(|(b, _)| gain < b) {
            best = Some((gain, Above { cell, height, offset }));
        }
    }
    best.map(|(_, a)| a)
}

/// The projector onto the directions of face k's plane (inward normal `n`) that are parallel to
/// every wall meeting it at a concave edge (inward normals `others`): `None` without such a
/// wall; the zero matrix in a corner, where two or more independent walls meet it.
fn edge_projector(n: &Vec3, others: impl Iterator<Item = Vec3>) -> Option<Mat3> {
    let mut project = Mat3::identity() - n * n.transpose();
    let mut any = false;
    for other in others {
        // The direction of k's plane pointing away from the other wall, with what earlier
        // walls took out removed (Gram–Schmidt): project it out too.
        let away = project * other;
        let size = away.norm();
        if size > EDGE_INDEPENDENT {
            let e = away / size;
            project -= e * e.transpose();
        }
        any = true;
    }
    any.then_some(project)
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

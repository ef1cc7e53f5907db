//! OpenFOAM boundary patches as particle boundaries: the gap between a particle's extent and
//! the nearest face of a set of patches.
//!
//! # Physics
//! A particle is an ellipsoid with barycentre $x_c$, semi-axes $r_a$ and rotation Q (rows: the
//! principal directions). Its extent along a unit vector n is the support distance
//! $h(n) = \sqrt{\sum_a r_a^2 (n·n_a)^2}$, so against a boundary face with centre $x_f$ and
//! outward unit normal $n_f$ the gap is $g = (x_f − x_c)·n_f − h(n_f)$; g ≤ 0 is contact.
//! The gap to a face is measured to the face itself (its fan of triangles about the centre),
//! not to its plane beyond its edges. Where the support point $s = x_c + b\\,n_f / h(n_f)$
//! ($b = Q^T \mathrm{diag}(r_a^2)\\,Q$, the point of the ellipsoid farthest along $n_f$)
//! projects into the face polygon (the face *covers* it), the plane gap is the distance to the
//! face, exactly. Otherwise the nearest point of the face lies on its rim, and the gap is the
//! largest of three lower bounds of the distance from the ellipsoid to the face, each ≤ 0
//! exactly where the ellipsoid meets the face:
//! - the plane gap (the face lies in its plane);
//! - $(s − 1)\\,r_3$, with s the distance from the origin to the face after the affine map
//!   $p ↦ \mathrm{diag}(r_a)^{-1} Q (p − x_c)$, which takes the ellipsoid onto the unit ball
//!   ([`PatchSet::mapped_face_distance`]): a point at s lies on the surface of the ellipsoid
//!   scaled by s about its centre, at least $(s − 1) r_3$ from the ellipsoid; exact for a sphere
//!   and for a point particle of contact radius δ;
//! - $d_f − r_1$, $d_f$ the distance from the centre to the face.
//!
//! The gap is the smallest over the faces whose bounding boxes lie within it plus $r_1$
//! ([`PatchGap::nearest_gap`]). A particle passing over a convex edge (a step's corner, the
//! kink of a snapped wall, a carina) is therefore as far from the wall as it is from the edge:
//! where the gap was the plane gap of the face nearest to the support point, tracers passing
//! 16–172 µm above the corner of OpenFOAM's pitzDaily step were deposited on the plane of its
//! vertical face. Exact for planar walls; on a curved wall meshed with faces of size h
//! whose vertices lie on the surface, within the sagitta O(h²κ) of the gap to the surface (κ
//! the curvature). Wall patches (`type wall`) deposit; generic patches (`type patch`: inlets
//! and outlets) let the particle exit; constraint patches (`empty`, `symmetry*`, `wedge`,
//! `cyclic`, ...) are not particle boundaries ([`PatchRole`]). [`MeshBoundary`] presents the
//! wall and exit patches as a [`Boundary`], so [`super::ContactEvent`] detects deposition and
//! escape on any mesh.
//!
//! # Rims
//! The lower bounds above are distances, unsigned: they say how far the particle is from a
//! face, not on which side of the wall. Where the support point projects into a face, the plane
//! gap carries the side. Where it projects into none, the sign needs the neighbouring faces.
//! Beyond an edge where the fluid's side is convex (the wall of a pipe meshed as a polygon,
//! whose inner angle at each vertex line is below 180°), the wall side holds a wedge between
//! the two faces' normals that projects into neither face: a point particle that crossed one
//! face within a step's slack of the edge (a point particle's slack is half its rest radius,
//! not its contact radius) ended the step in that wedge, at a positive distance from both
//! faces, and was tracked outside the mesh until its step failed. Point particles settling onto
//! a pipe's bottom passed through within 4·10⁻⁴ of its vertex lines that way. For a sphere
//! (a point particle is one of radius δ), whose positive gaps are its centre's distances to
//! the faces less δ, the face with the smallest gap holds the nearest point q of the boundary;
//! where q lies on that face's rim, the centre lies on the wall's side exactly where
//! (x_c − q)·N > 0, with N the angle-weighted pseudo-normal at q: the sum of the normals of
//! the faces through q, each weighted by its polygon's angle at q, π on an edge (Bærentzen and
//! Aanæs, IEEE TVCG 11, 2005, for closed triangle meshes; the ball about x_c of radius
//! |x_c − q| holds no face, so the side at x_c is the side next to q). The gap is then the
//! overlap, −|x_c − q| − δ. This holds at a convex ridge (a step's corner: the centre in the
//! fluid beyond both planes keeps its positive distance), a concave one and a saddle vertex
//! alike. An ellipsoid's uncovered gaps keep their lower bounds: a step moves it at most half
//! its smallest rest semi-axis past a face, so it still meets the face at the step's end
//! unless it has thinned below that.
//!
//! # Clearance
//! A nearest-face query visits every face whose bounding box lies within the gap of the
//! particle, dozens in a tube. Far from the walls a bound does: the distance $d_c$ from the
//! centre c of a bin of a uniform grid to the nearest boundary face (to the face, not its
//! plane), computed once when a particle first enters the bin, bounds the distance from x to
//! the boundary by $d_c − |x − c|$. [`MeshBoundary::clearance`] answers it where
//! $|x − c| ≤ d_c/2$, and only where c lies inside the domain
//! ([`crate::flow::openfoam::PatchSet::inner_distance`]): the ball of radius $d_c$ about c
//! holds no boundary face, so x lies on c's side. An unsigned distance would lend a bound to a
//! point that has left the domain (a particle carried past an outlet within one step), and the
//! contact event, taking it for inside, would never see the exit. A bin centre outside the
//! domain could not lend a bound to a point inside anyway: the segment between them crosses
//! the boundary, so $d_c ≤ |x − c|$. The gap of a point is
//! its distance to the nearest face (above). The answer bounds the distance to the walls; the
//! contact event halves it for the gap ([`super::ContactEvent`]). The grid has 64 bins per face, at most 2²² (64 MiB),
//! over the faces' bounding box.
//!
//! # Room
//! Next to a wall the contact event caps a step by the full speed, because moving along the
//! nearest face can reach another one ([`super::event`]). Where the faces about it are shaped
//! so that it cannot, the gap says so with its room ([`Gap::room`]): about the centre of each
//! face i, the largest ball of radius 8, 4 or 2 times the face's circumradius (holding at most
//! 96 faces) within which either
//! - every face lies on or beyond face i's plane (its points: vertices and centre, within face
//!   i's own warp, the largest distance of its vertices from its plane): a particle that keeps to
//!   the fluid's side of that plane touches none of them (a convex ridge, a flat wall); or
//! - every face has every face on its fluid's side (each within its own warp): the faces bound a
//!   convex region, so a straight move between two points of the fluid stays in it (a pipe's
//!   concave wall, an outlet's rim).
//!
//! The room of a particle is that radius less its distance from the face centre, given only
//! where the face covers the support point (the gap is then the plane's), and no more than the
//! support point's distance to the face's *open* edges plus $r_1$ (`open_edges`: those where
//! the neighbouring face falls away beyond the plane, and those no face of the set shares).
//! Beyond such an edge the plane is no longer the wall: a particle allowed by the room to glide
//! past the corner of a step while sinking towards the plateau touched it mid-step, yet ended
//! the step over the drop with a positive gap (spheres aimed 5° downwards at distances 0.8–0.95
//! of their radius from the edge passed through at 1–10 m/s). Near an open edge the full-speed
//! cap holds, whose slack shrinks with the gap ([`super::event`], Grazing contact). It is computed on
//! first use per face: one query of the faces' boxes within the largest ball, and the heights
//! of their points (kept in three coordinate arrays) over each plane (its cost on the 90° bend:
//! `paper-figures/bend/NOTES.md`, History). A saddle (the inner wall of a bend, the flanks of a carina) passes
//! neither test and keeps the full-speed cap. The tests see each face as its plane, within its
//! warp, as the gap does (a covered face's gap is the distance to its plane, not to its fan of
//! triangles); warps measured: median 0.07 µm, largest 1.1 µm on the 90° bend's wall (faces of
//! circumradius 0.32 mm), median 0.14 µm, largest 28 µm on the shipped bifurcation. Checked
//! against the fans themselves by brute force on the shipped bifurcation
//! (`tests/suite/contact/mod.rs`: a segment–triangle test against every face).

use super::{Approach, Boundary, Extent, Gap, PatchRule};
use crate::ellipsoid::frame::support_distance;
use crate::flow::openfoam::{FoamError, PatchRole, PatchSet, PolyMesh, SetFace};
use crate::tensor::{Mat3, Vec3};
use std::sync::OnceLock;

/// The nearest boundary face to a particle and the gap to it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceGap {
    /// Mesh face index.
    pub face: usize,
    /// Patch index in [`PolyMesh::patches`].
    pub patch: usize,
    /// Gap $g$ (negative: overlap depth).
    pub gap: f64,
    /// Outward unit normal of the face.
    pub normal: Vec3,
    /// Index of the face in the set ([`PatchSet::face`]).
    pub index: usize,
    /// Whether the particle's support point projects into the face, so that `gap` is the gap
    /// to its plane (module docs); otherwise `gap` is a lower bound.
    pub covered: bool,
    /// The support point along `normal`, projected onto the face's plane.
    pub projected: Vec3,
}

/// Gap between an ellipsoidal particle and a boundary.
pub trait PatchGap {
    /// The smallest gap over the boundary's faces near the particle, `None` if it has none.
    fn nearest_gap(&self, centre: &Vec3, semi_axes: &Vec3, q: &Mat3) -> Option<FaceGap>;
}

impl PatchGap for PatchSet {
    fn nearest_gap(&self, centre: &Vec3, semi_axes: &Vec3, q: &Mat3) -> Option<FaceGap> {
        let r2 = semi_axes.component_mul(semi_axes);
        let (r1, r3) = (semi_axes.amax(), semi_axes.amin());
        let inverse = semi_axes.map(|r| 1.0 / r);
        let mut best: Option<FaceGap> = None;
        // Faces in order of their bounding box's distance d_b from the centre: every point of
        // a face lies at least d_b from the centre, so at least d_b − r₁ from the ellipsoid, and
        // each face's gap below is at least that (module docs). Once a box lies farther than
        // the best gap plus r₁, no later face can do better.
        for (i, distance) in self.by_box_distance(centre) {
            if best.is_some_and(|b| distance - r1 > b.gap) {
                break;
            }
            let SetFace {
                face,
                patch,
                centre: face_centre,
                normal: n,
            } = self.face(i);
            let h = support_distance(semi_axes, q, &n);
            let plane = (face_centre - centre).dot(&n) - h;
            // The ellipsoid's extreme point along n (a point particle's centre), projected onto
            // the face plane.
            let support = if h > 0.0 {
                centre + q.transpose() * (q * n).component_mul(&r2) / h
            } else {
                *centre
            };
            let projected = support + n * (face_centre - support).dot(&n);
            let covered = self.covers(i, &projected);
            let gap = if covered {
                plane
            } else {
                // Lower bounds of the distance to the face polygon, each ≤ 0 exactly where the
                // ellipsoid meets it (module docs).
                let polygon = if r3 > 0.0 {
                    (self.mapped_face_distance(i, centre, q, &inverse) - 1.0) * r3
                } else {
                    self.face_offset(i, centre).norm() - r1
                };
                let reach = if r1 > r3 {
                    self.face_offset(i, centre).norm() - r1
                } else {
                    polygon
                };
                plane.max(polygon).max(reach)
            };
            let candidate = FaceGap {
                face,
                patch,
                gap,
                normal: n,
                index: i,
                covered,
                projected,
            };
            // Ties (a support point over a shared edge) go to the lowest face number, so the
            // answer does not depend on the index's traversal order.
            if best.is_none_or(|b| (gap, face) < (b.gap, b.face)) {
                best = Some(candidate);
            }
        }
        // A sphere's positive gaps are its centre's distances to the faces less its radius, so
        // the best face holds the boundary's nearest point q. Where q lies on the face's rim,
        // the distance alone does not say on which side of the wall the centre lies (module
        // docs, Rims).
        if r1 == r3
            && let Some(b) = best.as_mut()
            && !b.covered
            && b.gap > 0.0
        {
            let offset = self.face_offset(b.index, centre);
            if beyond_rim(self, &(centre - offset), &offset) {
                b.gap = -offset.norm() - r1;
            }
        }
        best
    }
}

/// Whether x lies on the wall's side of the boundary, where q = x − `offset` is the nearest
/// point of the set's faces to x and lies on a face's rim (module docs, Rims): whether
/// (x − q)·N > 0 for N the angle-weighted pseudo-normal at q, the sum of the normals of the
/// faces through q, each weighted by its polygon's angle at q (π on an edge). A rim no other
/// face shares (towards a constraint patch) has no side of its own: `false` there.
fn beyond_rim(set: &PatchSet, q: &Vec3, offset: &Vec3) -> bool {
    let tolerance = 1e-9 * set.circumradius();
    let mut normal = Vec3::zeros();
    let mut faces = 0;
    for (j, _) in set.within_box_distance(q, tolerance) {
        if set.face_offset(j, q).norm() > tolerance {
            continue;
        }
        let polygon = set.polygon(j);
        let n = polygon.len();
        let angle = match polygon.iter().position(|v| (v - q).norm() <= tolerance) {
            Some(k) => {
                let (before, after) = (polygon[(k + n - 1) % n] - polygon[k], polygon[(k + 1) % n] - polygon[k]);
                before.angle(&after)
            }
            None => std::f64::consts::PI,
        };
        normal += set.face(j).normal * angle;
        faces += 1;
    }
    faces > 1 && offset.dot(&normal) > 0.0
}

/// The wall and exit patches of a mesh as a contact boundary: walls deposit
/// ([`PatchRule::Stick`]), exits let the particle leave ([`PatchRule::Exit`]). Patch indices in
/// [`Gap::patch`] count these patches only, in mesh order.
#[derive(Debug, Clone)]
pub struct MeshBoundary {
    /// [`MeshBoundary::fingerprint`].
    fingerprint: String,
    set: PatchSet,
    /// Mesh patch index of each boundary patch.
    mesh_patches: Vec<usize>,
    names: Vec<String>,
    rules: Vec<PatchRule>,
    clearance: Clearance,
    /// Each face's [`room`], computed on first use.
    rooms: Vec<OnceLock<f64>>,
    /// Each face's [`open_edges`], computed on first use.
    edges: Vec<OnceLock<Box<[u32]>>>,
}

/// Radii of the neighbourhoods [`room`] tries about a face, in multiples of its circumradius,
/// smallest first.
const ROOM_RADII: [f64; 3] = [2.0, 4.0, 8.0];
/// Faces a neighbourhood may hold: its convexity test is quadratic in them.
const ROOM_FACES: usize = 96;

/// The radius of the largest ball about face i's centre (of [`ROOM_RADII`] times its
/// circumradius) within which every face of the set lies beyond face i's plane, or the faces
/// bound a convex fluid side (module docs, Room); 0 if none.
///
/// Both tests hold in a ball if they hold in a larger one (fewer faces), so the radii are
/// tried from the smallest, and the first that fails ends the search: most faces of a snapped
/// wall fail at the smallest, at the cost of a few dozen pairs.
fn room(set: &PatchSet, i: usize) -> f64 {
    let SetFace { centre, .. } = set.face(i);
    let circumradius = set.polygon(i).iter().map(|v| (v - centre).norm()).fold(0.0, f64::max);
    let largest = ROOM_RADII[ROOM_RADII.len() - 1] * circumradius;
    let (own, tolerance) = (FacePlane::of(set, i), 1e-12 * largest);
    // Every face within the largest ball, in order of its box's distance.
    let mut within: Vec<(usize, f64)> = set.within_box_distance(&centre, largest).collect();
    within.sort_unstable_by(|a, b| a.1.total_cmp(&b.1));
    let mut near: Vec<FacePlane> = Vec::with_capacity(within.len().min(ROOM_FACES));
    let mut points = Points::default();
    let mut room = 0.0;
    for k in ROOM_RADII {
        let radius = k * circumradius;
        let count = within.partition_point(|&(_, d)| d <= radius);
        // More faces than a test may take.
        if count > ROOM_FACES {
            break;
        }
        for &(j, _) in &within[near.len()..count] {
            let face = FacePlane::of(set, j);
            points.extend(face.points());
            near.push(face);
        }
        let supported = points.all_at_least(&own, -(own.warp + tolerance));
        let convex = || near.iter().all(|k| points.all_at_most(k, k.warp + tolerance));
        if !(supported || convex()) {
            break;
        }
        room = radius;
    }
    room
}

/// The edges of face i (k for the edge from vertex k to k + 1 of [`PatchSet::polygon`]) that
/// a particle must not cross within a step that only its normal velocity bounds (module docs,
/// Room): those where the neighbouring face of the set falls away beyond face i's plane by more
/// than face i's warp (a convex ridge), and those that no face of the set shares (the rim
/// towards a constraint patch, or a face of another shape).
fn open_edges(set: &PatchSet, i: usize) -> Box<[u32]> {
    let own = FacePlane::of(set, i);
    let polygon = set.polygon(i);
    let tolerance = 1e-12 * set.circumradius();
    let mut open = Vec::new();
    for (k, a) in polygon.iter().enumerate() {
        let b = &polygon[(k + 1) % polygon.len()];
        let middle = (a + b) * 0.5;
        let neighbour = set
            .within_box_distance(&middle, 0.0)
            .map(|(j, _)| j)
            .filter(|&j| j != i)
            .find(|&j| {
                let p = set.polygon(j);
                p.contains(a) && p.contains(b)
            });
        let falls_away = neighbour.is_none_or(|j| {
            FacePlane::of(set, j)
                .points()
                .any(|p| (p - own.centre).dot(&own.normal) > own.warp + tolerance)
        });
        if falls_away {
            open.push(k as u32);
        }
    }
    open.into_boxed_slice()
}

/// Distance from p to the segment from a to b.
fn segment_distance(p: &Vec3, a: &Vec3, b: &Vec3) -> f64 {
    let ab = b - a;
    let t = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
    if t.is_nan() {
        return (p - a).norm();
    }
    (p - (a + ab * t)).norm()
}

/// A face as the room's tests see it: its plane, its warp and the points that span it.
struct FacePlane<'a> {
    centre: Vec3,
    normal: Vec3,
    /// How far its vertices lie off its plane (a warped face's).
    warp: f64,
    /// Its vertices.
    polygon: &'a [Vec3],
}

impl<'a> FacePlane<'a> {
    fn of(set: &'a PatchSet, j: usize) -> Self {
        let SetFace { centre, normal, .. } = set.face(j);
        let polygon = set.polygon(j);
        Self {
            centre,
            normal,
            warp: polygon
                .iter()
                .map(|v| (v - centre).dot(&normal).abs())
                .fold(0.0, f64::max),
            polygon,
        }
    }

    /// Its vertices and its centre.
    fn points(&self) -> impl Iterator<Item = &Vec3> {
        self.polygon.iter().chain(std::iter::once(&self.centre))
    }
}

/// The points of the faces in a ball, in three arrays of coordinates: the room's tests take
/// every point's height over a plane, (p − c)·n summed in the order of `Vector3::dot` (so
/// every comparison is the one the faces' own vectors gave), in a loop without an early exit
/// over contiguous arrays (whether the compiler vectorises it was not checked).
#[derive(Default)]
struct Points {
    x: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
}

impl Points {
    fn extend<'p>(&mut self, points: impl Iterator<Item = &'p Vec3>) {
        for p in points {
            self.x.push(p[0]);
            self.y.push(p[1]);
            self.z.push(p[2]);
        }
    }

    /// The heights of every point over `plane`, along its outward normal (positive: beyond it,
    /// in the wall), folded by `keep` from `true`.
    fn heights_all(&self, plane: &FacePlane, keep: impl Fn(f64) -> bool) -> bool {
        let (c, n) = (plane.centre, plane.normal);
        self.x.iter().zip(&self.y).zip(&self.z).fold(true, |all, ((x, y), z)| {
            all & keep((x - c[0]) * n[0] + (y - c[1]) * n[1] + (z - c[2]) * n[2])
        })
    }

    /// Whether every point lies at least `low` over `plane`.
    fn all_at_least(&self, plane: &FacePlane, low: f64) -> bool {
        self.heights_all(plane, |h| h >= low)
    }

    /// Whether every point lies at most `high` over `plane`.
    fn all_at_most(&self, plane: &FacePlane, high: f64) -> bool {
        self.heights_all(plane, |h| h <= high)
    }
}

/// Largest number of clearance bins (16 bytes each), and per boundary face.
const MAX_BINS: usize = 1 << 22;
const BINS_PER_FACE: usize = 64;

/// The distances from the centres of a uniform grid's bins to the nearest face, each computed on
/// first use (module docs, Clearance).
#[derive(Debug, Clone)]
struct Clearance {
    origin: Vec3,
    size: f64,
    dims: [usize; 3],
    distances: Vec<OnceLock<f64>>,
}

impl Clearance {
    /// A grid over the faces' bounding box with bins about a face across; an empty grid if the
    /// box is not finite.
    fn new(set: &PatchSet) -> Self {
        let (mut lo, mut hi) = (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY));
        for i in 0..set.len() {
            let c = set.face(i).centre;
            lo = lo.inf(&c);
            hi = hi.sup(&c);
        }
        let margin = set.circumradius();
        let (lo, hi) = (lo.add_scalar(-margin), hi.add_scalar(margin));
        let extent = hi - lo;
        let empty = Self {
            origin: Vec3::zeros(),
            size: 1.0,
            dims: [0; 3],
            distances: Vec::new(),
        };
        if !extent.iter().all(|e| e.is_finite() && *e >= 0.0) || margin.is_nan() || margin <= 0.0 {
            return empty;
        }
        // As many bins as the limits allow (so that most of a duct's lumen lies more than a bin
        // from the walls), coarsened until they fit.
        let limit = MAX_BINS.min(BINS_PER_FACE * set.len()).max(1);
        let mut size = (extent.iter().map(|e| e.max(margin)).product::<f64>() / limit as f64).cbrt();
        let count = |size: f64| extent.map(|e| (e / size).floor() as usize + 1);
        while count(size).iter().product::<usize>() > limit {
            size *= 1.1;
        }
        let dims = count(size);
        Self {
            origin: lo,
            size,
            dims: [dims[0], dims[1], dims[2]],
            distances: (0..dims.iter().product::<usize>()).map(|_| OnceLock::new()).collect(),
        }
    }

    /// The bound at x from its bin (module docs), `None` outside the grid or beyond half the
    /// centre's distance from the centre.
    fn at(&self, set: &PatchSet, x: &Vec3) -> Option<f64> {
        let s = (x - self.origin) / self.size;
        let mut index = [0usize; 3];
        for a in 0..3 {
            if !(s[a] >= 0.0 && s[a] < self.dims[a] as f64) {
                return None;
            }
            index[a] = s[a] as usize;
        }
        let bin = index[0] + self.dims[0] * (index[1] + self.dims[1] * index[2]);
        let centre =
            self.origin + Vec3::new(index[0] as f64 + 0.5, index[1] as f64 + 0.5, index[2] as f64 + 0.5) * self.size;
        let distance = *self.distances[bin].get_or_init(|| set.inner_distance(&centre).unwrap_or(f64::NAN));
        let away = (x - centre).norm();
        (distance.is_finite() && away <= 0.5 * distance).then_some(distance - away)
    }
}

impl MeshBoundary {
    /// The particle boundaries of `mesh`; it needs at least one wall or exit patch with faces,
    /// and no patch with faces of a type particles cannot yet meet
    /// ([`crate::flow::openfoam::check_particle_patches`]).
    pub fn new(mesh: &PolyMesh) -> Result<Self, FoamError> {
        crate::flow::openfoam::check_particle_patches(mesh)?;
        let mut mesh_patches = Vec::new();
        let mut rules = Vec::new();
        for (p, patch) in mesh.patches().iter().enumerate() {
            let rule = match PatchRole::of(&patch.kind) {
                PatchRole::Wall => PatchRule::Stick,
                PatchRole::Exit => PatchRule::Exit,
                PatchRole::Image | PatchRole::Constraint => continue,
            };
            if patch.size > 0 {
                mesh_patches.push(p);
                rules.push(rule);
            }
        }
        if mesh_patches.is_empty() {
            return Err(FoamError::Mesh {
                reason: "no wall or patch-type patch with faces: nothing for particles to touch".into(),
            });
        }
        let names: Vec<String> = mesh_patches.iter().map(|&p| mesh.patches()[p].name.clone()).collect();
        let fingerprint = format!(
            "mesh boundary: {} of mesh {}",
            names
                .iter()
                .zip(&rules)
                .map(|(n, r)| format!("{n} {r:?}"))
                .collect::<Vec<_>>()
                .join(", "),
            mesh.content_hash()
        );
        let set = PatchSet::new(mesh, &mesh_patches);
        Ok(Self {
            fingerprint,
            clearance: Clearance::new(&set),
            rooms: (0..set.len()).map(|_| OnceLock::new()).collect(),
            edges: (0..set.len()).map(|_| OnceLock::new()).collect(),
            set,
            names,
            mesh_patches,
            rules,
        })
    }

    /// What identifies this boundary for a run's configuration hash: its patches with their
    /// rules and the mesh's [`PolyMesh::content_hash`] (the faces are the mesh's).
    pub fn fingerprint(&self) -> &str {
        &self.fingerprint
    }
}

impl Boundary for MeshBoundary {
    fn nearest(&self, x: &Vec3, extent: &Extent) -> Gap {
        // A point particle of contact radius δ is the sphere of radius δ.
        let (axes, q) = match extent {
            Extent::Ellipsoid(frame) => (frame.r, frame.q),
            Extent::Point { radius } => (Vec3::repeat(*radius), Mat3::identity()),
        };
        let hit = self
            .set
            .nearest_gap(x, &axes, &q)
            .expect("MeshBoundary::new keeps at least one face");
        // Room only where the gap is the covered face's plane gap, which the cap closes.
        // The room ends where the support point would pass an open edge of the covered face
        // (module docs, Room): beyond it the face's plane is no longer what the gap measures.
        let room = if hit.covered {
            let centre = self.set.face(hit.index).centre;
            let radius = *self.rooms[hit.index].get_or_init(|| room(&self.set, hit.index));
            let ball = (radius - (x - centre).norm()).max(0.0);
            let polygon = self.set.polygon(hit.index);
            let edges = self.edges[hit.index].get_or_init(|| open_edges(&self.set, hit.index));
            let edge = edges
                .iter()
                .map(|&k| {
                    let k = k as usize;
                    segment_distance(&hit.projected, &polygon[k], &polygon[(k + 1) % polygon.len()])
                })
                .fold(f64::INFINITY, f64::min);
            ball.min(edge + axes.amax())
        } else {
            0.0
        };
        Gap {
            patch: self
                .mesh_patches
                .iter()
                .position(|&p| p == hit.patch)
                .expect("faces come from the listed patches"),
            gap: hit.gap,
            normal: hit.normal,
            room,
        }
    }

    fn patch_name(&self, patch: usize) -> &str {
        &self.names[patch]
    }

    fn rule(&self, patch: usize) -> PatchRule {
        self.rules[patch]
    }

    /// Mesh walls have ridges (a carina) and corners.
    fn approach(&self) -> Approach {
        Approach::AnyDirection
    }

    /// From the bins of a grid (module docs, Clearance).
    fn clearance(&self, x: &Vec3) -> Option<f64> {
        self.clearance.at(&self.set, x)
    }
}

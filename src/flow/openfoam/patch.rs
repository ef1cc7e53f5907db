//! Boundary patches as particle boundaries: the gap between a particle's extent and the
//! nearest face of a set of patches.
//!
//! # Physics
//! A particle is an ellipsoid with barycentre $x_c$, semi-axes $r_a$ and rotation Q (rows: the
//! principal directions). Its extent along a unit vector n is the support distance
//! $h(n) = \sqrt{\sum_a r_a^2 (n·n_a)^2}$, so against a boundary face with centre $x_f$ and
//! outward unit normal $n_f$ the gap is $g = (x_f − x_c)·n_f − h(n_f)$; g ≤ 0 is contact.
//! The face that counts is the one the particle's extreme point faces: among the faces whose
//! bounding boxes are near enough to hold a nearer face ([`PatchSet::nearest_gap`]), those for
//! which the support
//! point $s = x_c + b\\,n_f / h(n_f)$ ($b = Q^T \mathrm{diag}(r_a^2)\\,Q$, the point of the
//! ellipsoid farthest along $n_f$) projects into the face polygon; the smallest of their gaps
//! is the gap. (Taking the smallest plane gap over all nearby faces would be wrong at convex
//! walls, where the planes of neighbouring faces cut into the fluid.) If the support point
//! projects into none of them (over an edge between faces), the face nearest to it is used.
//! Exact for planar walls; on a curved wall meshed with faces of size h whose vertices lie on
//! the surface, within the sagitta O(h²κ) of the gap to the surface (κ the curvature).
//! Wall patches (`type wall`) deposit; generic patches (`type patch`: inlets and outlets)
//! let the particle exit; constraint patches (`empty`, `symmetry*`, `wedge`, `cyclic`, ...)
//! are not particle boundaries. [`MeshBoundary`] presents the wall and exit patches as a
//! [`crate::contact::Boundary`], so [`crate::contact::ContactEvent`] detects deposition and
//! escape on any mesh.

use super::error::FoamError;
use super::mesh::PolyMesh;
use crate::contact::{Approach, Boundary, Extent, Gap, PatchRule};
use crate::ellipsoid::frame::support_distance;
use crate::tensor::{Mat3, Vec3};
use rstar::primitives::{GeomWithData, Rectangle};
use rstar::{PointDistance, RTree};

type FaceCentre = GeomWithData<[f64; 3], u32>;
type FaceBox = GeomWithData<Rectangle<[f64; 3]>, u32>;

/// What a patch means for a particle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PatchRole {
    /// Contact deposits the particle (`type wall`).
    Wall,
    /// Contact means the particle leaves the domain (`type patch`: inlets, outlets).
    Exit,
    /// Not a particle boundary (`empty`, `symmetry`, `symmetryPlane`, `wedge`, `cyclic`, ...).
    Constraint,
}

impl PatchRole {
    /// Role from the patch's geometric type in `constant/polyMesh/boundary`.
    pub fn of(kind: &str) -> Self {
        match kind {
            "wall" => PatchRole::Wall,
            "patch" => PatchRole::Exit,
            _ => PatchRole::Constraint,
        }
    }
}

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
}

/// Gap between an ellipsoidal particle and a boundary.
pub trait PatchGap {
    /// The smallest gap over the boundary's faces near the particle, `None` if it has none.
    fn nearest_gap(&self, centre: &Vec3, semi_axes: &Vec3, q: &Mat3) -> Option<FaceGap>;
}

/// A set of patches of one mesh, indexed by face centre.
#[derive(Debug, Clone)]
pub struct PatchSet {
    tree: RTree<FaceCentre>,
    /// The faces' bounding boxes: visited in order of their distance, a lower bound of the
    /// distance to the face.
    boxes: RTree<FaceBox>,
    faces: Vec<(u32, u32)>,
    centres: Vec<Vec3>,
    normals: Vec<Vec3>,
    /// Face polygons: vertices of face i are `vertices[offsets[i]..offsets[i + 1]]`.
    offsets: Vec<usize>,
    vertices: Vec<Vec3>,
    /// Largest distance from a face's centre to its vertices.
    circumradius: f64,
}

impl PatchSet {
    /// The faces of the patches `patches` (indices into [`PolyMesh::patches`]; out-of-range
    /// indices are ignored).
    pub fn new(mesh: &PolyMesh, patches: &[usize]) -> Self {
        let mut faces = Vec::new();
        for &p in patches {
            if let Some(patch) = mesh.patches().get(p) {
                faces.extend((patch.start..patch.start + patch.size).map(|f| (f as u32, p as u32)));
            }
        }
        let centres: Vec<Vec3> = faces.iter().map(|&(f, _)| mesh.face_centres()[f as usize]).collect();
        let normals = faces
            .iter()
            .map(|&(f, _)| mesh.face_areas()[f as usize].normalize())
            .collect();
        let mut offsets = vec![0];
        let mut vertices = Vec::new();
        for &(f, _) in &faces {
            vertices.extend(mesh.face(f as usize).iter().map(|&v| mesh.points()[v as usize]));
            offsets.push(vertices.len());
        }
        let tree = RTree::bulk_load(
            centres
                .iter()
                .enumerate()
                .map(|(i, c)| FaceCentre::new([c[0], c[1], c[2]], i as u32))
                .collect(),
        );
        let boxes = RTree::bulk_load(
            (0..faces.len())
                .map(|i| {
                    let poly = &vertices[offsets[i]..offsets[i + 1]];
                    let (lo, hi) = poly
                        .iter()
                        .fold((centres[i], centres[i]), |(lo, hi), v| (lo.inf(v), hi.sup(v)));
                    FaceBox::new(
                        Rectangle::from_corners([lo[0], lo[1], lo[2]], [hi[0], hi[1], hi[2]]),
                        i as u32,
                    )
                })
                .collect(),
        );
        let circumradius = (0..faces.len())
            .flat_map(|i| vertices[offsets[i]..offsets[i + 1]].iter().map(move |v| (i, v)))
            .map(|(i, v)| (v - centres[i]).norm())
            .fold(0.0, f64::max);
        Self {
            tree,
            boxes,
            faces,
            centres,
            normals,
            offsets,
            vertices,
            circumradius,
        }
    }

    /// Whether `p` projects into face i (the fan of triangles around its centre).
    fn covers(&self, i: usize, p: &Vec3) -> bool {
        let (c, n) = (self.centres[i], self.normals[i]);
        let poly = &self.vertices[self.offsets[i]..self.offsets[i + 1]];
        poly.iter().enumerate().any(|(k, a)| {
            let b = &poly[(k + 1) % poly.len()];
            // Signed areas of the sub-triangles, relative to the triangle's own, ≥ −1e-12:
            // points on shared edges belong to both faces.
            let area = n.dot(&(a - c).cross(&(b - c)));
            let tol = -1e-12 * area.abs();
            n.dot(&(a - c).cross(&(p - c))) >= tol
                && n.dot(&(b - a).cross(&(p - a))) >= tol
                && n.dot(&(c - b).cross(&(p - b))) >= tol
        })
    }

    /// All patches with the given role.
    pub fn with_role(mesh: &PolyMesh, role: PatchRole) -> Self {
        let ids: Vec<usize> = (0..mesh.patches().len())
            .filter(|&p| PatchRole::of(&mesh.patches()[p].kind) == role)
            .collect();
        Self::new(mesh, &ids)
    }

    /// The particle boundaries: every wall and exit patch (constraint patches left out).
    pub fn boundaries(mesh: &PolyMesh) -> Self {
        let ids: Vec<usize> = (0..mesh.patches().len())
            .filter(|&p| PatchRole::of(&mesh.patches()[p].kind) != PatchRole::Constraint)
            .collect();
        Self::new(mesh, &ids)
    }

    /// Every patch.
    pub fn all(mesh: &PolyMesh) -> Self {
        Self::new(mesh, &(0..mesh.patches().len()).collect::<Vec<_>>())
    }

    /// The face whose centre is nearest to `x`: (face, patch, distance).
    pub fn nearest_face(&self, x: &Vec3) -> Option<(usize, usize, f64)> {
        let hit = self.tree.nearest_neighbor([x[0], x[1], x[2]])?;
        let i = hit.data as usize;
        let (f, p) = self.faces[i];
        Some((f as usize, p as usize, (self.centres[i] - x).norm()))
    }
}

impl PatchGap for PatchSet {
    fn nearest_gap(&self, centre: &Vec3, semi_axes: &Vec3, q: &Mat3) -> Option<FaceGap> {
        let r2 = semi_axes.component_mul(semi_axes);
        let mut covered: Option<FaceGap> = None;
        let mut nearest: Option<(f64, FaceGap)> = None;
        // Faces in order of their bounding box's distance from the centre, a lower bound of
        // the distance to the face. A face that covers the support point's projection is at
        // its plane distance, so once a box lies farther than the best covered gap plus the
        // particle's extent (the support point is within the largest semi-axis of the centre)
        // no later face can do better. Without a covered face the search goes on within the
        // first box's distance plus twice the largest circumradius and semi-axis. (A fixed
        // number of nearest face centres missed a long wall face beside the small faces of an
        // adjacent outlet, and let particles cross the wall unseen.)
        let reach = 2.0 * semi_axes.amax();
        let mut uncovered_bound = f64::INFINITY;
        for hit in self.boxes.nearest_neighbor_iter([centre[0], centre[1], centre[2]]) {
            let i = hit.data as usize;
            let distance = hit.distance_2(&[centre[0], centre[1], centre[2]]).sqrt();
            if let Some(c) = &covered
                && distance > c.gap.abs() + 2.0 * reach
            {
                break;
            }
            if distance > uncovered_bound {
                break;
            }
            if uncovered_bound.is_infinite() {
                uncovered_bound = distance + 2.0 * self.circumradius + 2.0 * reach;
            }
            let n = self.normals[i];
            let h = support_distance(semi_axes, q, &n);
            let gap = (self.centres[i] - centre).dot(&n) - h;
            let (f, p) = self.faces[i];
            let candidate = FaceGap {
                face: f as usize,
                patch: p as usize,
                gap,
                normal: n,
            };
            // The ellipsoid's extreme point along n (a point particle's centre), projected onto
            // the face plane.
            let support = if h > 0.0 {
                centre + q.transpose() * (q * n).component_mul(&r2) / h
            } else {
                *centre
            };
            let projected = support + n * (self.centres[i] - support).dot(&n);
            if self.covers(i, &projected) {
                // Ties (a support point over a shared edge) go to the lowest face number, so
                // the answer does not depend on the index's traversal order.
                if covered.is_none_or(|c| (gap, candidate.face) < (c.gap, c.face)) {
                    covered = Some(candidate);
                }
            } else {
                let d = (self.centres[i] - projected).norm();
                if nearest.is_none_or(|(dn, c)| (d, candidate.face) < (dn, c.face)) {
                    nearest = Some((d, candidate));
                }
            }
        }
        covered.or(nearest.map(|(_, c)| c))
    }
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
}

impl MeshBoundary {
    /// The particle boundaries of `mesh`; it needs at least one wall or exit patch with faces.
    pub fn new(mesh: &PolyMesh) -> Result<Self, FoamError> {
        let mut mesh_patches = Vec::new();
        let mut rules = Vec::new();
        for (p, patch) in mesh.patches().iter().enumerate() {
            let rule = match PatchRole::of(&patch.kind) {
                PatchRole::Wall => PatchRule::Stick,
                PatchRole::Exit => PatchRule::Exit,
                PatchRole::Constraint => continue,
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
        Ok(Self {
            fingerprint,
            set: PatchSet::new(mesh, &mesh_patches),
            names,
            mesh_patches,
            rules,
        })
    }
}

impl MeshBoundary {
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
        Gap {
            patch: self
                .mesh_patches
                .iter()
                .position(|&p| p == hit.patch)
                .expect("faces come from the listed patches"),
            gap: hit.gap,
            normal: hit.normal,
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
}

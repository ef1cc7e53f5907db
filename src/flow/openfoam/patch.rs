//! Boundary patches as geometry: which patches are walls, exits or constraints, and a set of
//! patch faces indexed for nearest-face queries. The gap between a particle and these faces,
//! and the patches as a particle boundary, are contact's (`crate::contact::mesh`).

use super::error::FoamError;
use super::mesh::PolyMesh;
use crate::tensor::Vec3;
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
    /// The particle passes through it and continues from its image: `cyclic`, `cyclicAMI`,
    /// `symmetry`, `symmetryPlane`, `wedge` (`flow::openfoam::images`).
    Image,
    /// Not a particle boundary: `empty` (a 2-D case's front and back) and `processor` (faces
    /// between the processors of a decomposed case, which the reassembled mesh does not have).
    /// Types a particle could cross but that are not handled (`cyclicACMI`, `cyclicSlip`,
    /// `mapped*`, `processorCyclic`, ...) map here too; [`check_particle_patches`] refuses them.
    Constraint,
}

/// Patch types a particle passes through, as the image of itself across the patch
/// (`flow::openfoam::images`): periodic pairs and mirror planes.
pub const IMAGE_PATCH_TYPES: [&str; 5] = ["cyclic", "cyclicAMI", "symmetry", "symmetryPlane", "wedge"];

/// The patch types a particle can meet and that are handled as its boundary: `wall`
/// (deposit), `patch` (exit), `empty` (2-D: the slab's faces, which particles are kept off),
/// `processor` (internal faces of a decomposed case) and the types it passes through
/// ([`IMAGE_PATCH_TYPES`]).
pub const PARTICLE_PATCH_TYPES: [&str; 9] = [
    "wall",
    "patch",
    "empty",
    "processor",
    "cyclic",
    "cyclicAMI",
    "symmetry",
    "symmetryPlane",
    "wedge",
];

impl PatchRole {
    /// Role from the patch's geometric type in `constant/polyMesh/boundary`.
    pub fn of(kind: &str) -> Self {
        match kind {
            "wall" => PatchRole::Wall,
            "patch" => PatchRole::Exit,
            k if IMAGE_PATCH_TYPES.contains(&k) => PatchRole::Image,
            _ => PatchRole::Constraint,
        }
    }

    /// Role of a patch type a particle can meet, `None` for a type not handled as a particle
    /// boundary ([`PARTICLE_PATCH_TYPES`]): `cyclicACMI`, `cyclicSlip`, `mapped*`,
    /// `processorCyclic`, `nonConformal*` and any type unknown here. A particle crossing one
    /// of them would be tracked outside the mesh.
    pub fn of_particle_boundary(kind: &str) -> Option<Self> {
        PARTICLE_PATCH_TYPES.contains(&kind).then(|| Self::of(kind))
    }
}

/// Refuse a mesh with a patch a particle can cross but that is not handled as a particle
/// boundary ([`PatchRole::of_particle_boundary`]): the first such patch with faces, named with
/// its type. A patch without faces cannot be met and is let through (a decomposed case's
/// patch that lies in other processors, a generic mesh's unused patch).
pub fn check_particle_patches(mesh: &PolyMesh) -> Result<(), FoamError> {
    match mesh
        .patches()
        .iter()
        .find(|p| p.size > 0 && PatchRole::of_particle_boundary(&p.kind).is_none())
    {
        Some(p) => Err(FoamError::UnsupportedPatch {
            patch: p.name.clone(),
            kind: p.kind.clone(),
            faces: p.size,
            hint: match p.kind.as_str() {
                "processorCyclic" => "; reconstruct the case (`reconstructPar`) and give the reconstructed case",
                _ => "",
            },
        }),
        None => Ok(()),
    }
}

/// Smallest |n_k| of an `empty` face's unit normal n for the face to count as normal to axis k
/// ([`slab_axis`]): the front and back of an extruded 2-D mesh are planes normal to the axis,
/// their normals ±e_k up to the rounding of the points' coordinates (10⁻¹⁵ relative); a face
/// tilted by more than 1.4·10⁻⁴ rad is no such plane's.
pub const SLAB_NORMAL_COS: f64 = 1.0 - 1e-8;

/// The axis (0, 1, 2) a 2-D mesh is extruded along: the one axis every face of every `empty`
/// patch is normal to (within [`SLAB_NORMAL_COS`]). `None` without `empty` faces, and where
/// they are normal to more than one axis (a 1-D case) or to none.
pub fn slab_axis(mesh: &PolyMesh) -> Option<usize> {
    let mut axis = None;
    for patch in mesh.patches().iter().filter(|p| p.kind == "empty") {
        for f in patch.start..patch.start + patch.size {
            let n = mesh.face_areas()[f].normalize();
            let k = n.iamax();
            if !(n[k].abs() >= SLAB_NORMAL_COS) || axis.is_some_and(|a| a != k) {
                return None;
            }
            axis = Some(k);
        }
    }
    axis
}

/// One face of a [`PatchSet`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SetFace {
    /// Mesh face index.
    pub face: usize,
    /// Patch index in [`PolyMesh::patches`].
    pub patch: usize,
    /// Face centre.
    pub centre: Vec3,
    /// Outward unit normal.
    pub normal: Vec3,
}

/// Cosine between the offset from a boundary's nearest point to x and the inward normal there
/// above which [`PatchSet::inner_distance`] calls x inside (25.8°: warped faces' fan triangles
/// tilt from the face normal by less).
pub const INNER_SIDE_COS: f64 = 0.9;

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

    /// Whether `p` projects into face i of the set (the fan of triangles around its centre).
    pub fn covers(&self, i: usize, p: &Vec3) -> bool {
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

    /// Distance from x to the nearest face of the set (to the face, not its plane; the fans of
    /// triangles around the face centres): faces in order of their bounding boxes' distance,
    /// until a box lies beyond the nearest face found. +∞ for an empty set.
    pub fn surface_distance(&self, x: &Vec3) -> f64 {
        self.nearest_offset(x)
            .map_or(f64::INFINITY, |(offset, _)| offset.norm())
    }

    /// [`Self::surface_distance`] where x lies plainly on the inner side of the boundary, `None`
    /// where it lies outside or the side is unclear.
    ///
    /// Inner means that the offset from the nearest point q to x runs against the outward
    /// normal of q's face, within [`INNER_SIDE_COS`] of it. Where q lies inside a face (x
    /// projects into it), x − q is parallel to the normal and its sign is the side: a closed
    /// boundary with outward normals is crossed once on the segment from x to q, at q, if at
    /// all. Where q lies on an edge or corner, x − q lies in the cone of the outward normals of
    /// the faces meeting there for x outside, so an outside point is mistaken for an inside one
    /// only where two outward normals are more than arccos(−0.9) = 154° apart: a solid wedge
    /// sharper than 26°, which meshed walls of ducts do not have. Points on constraint patches'
    /// side (not in the set) have no side of their own: a 2-D case's `empty` planes are not
    /// particle boundaries.
    pub fn inner_distance(&self, x: &Vec3) -> Option<f64> {
        let (offset, i) = self.nearest_offset(x)?;
        let d = offset.norm();
        (offset.dot(&self.normals[i]) <= -INNER_SIDE_COS * d).then_some(d)
    }

    /// x − q for q the nearest point of the set's faces, with q's face: faces in order of
    /// their bounding boxes' distance, until a box lies beyond the nearest point found.
    fn nearest_offset(&self, x: &Vec3) -> Option<(Vec3, usize)> {
        let mut best: Option<(Vec3, usize)> = None;
        let mut best_d = f64::INFINITY;
        for (i, box_distance) in self.by_box_distance(x) {
            if box_distance >= best_d {
                break;
            }
            let offset = self.face_offset(i, x);
            let d = offset.norm();
            if d < best_d {
                best_d = d;
                best = Some((offset, i));
            }
        }
        best
    }

    /// x − q for q the point of face i (the fan of triangles around its centre) nearest to x.
    pub fn face_offset(&self, i: usize, x: &Vec3) -> Vec3 {
        let (c, poly) = (&self.centres[i], &self.vertices[self.offsets[i]..self.offsets[i + 1]]);
        let mut best = Vec3::repeat(f64::INFINITY);
        for (k, a) in poly.iter().enumerate() {
            let b = &poly[(k + 1) % poly.len()];
            let offset = super::walls::triangle_offset(x, c, a, b);
            if offset.norm_squared() < best.norm_squared() {
                best = offset;
            }
        }
        best
    }

    /// The distance from the origin to face i (its fan of triangles) after the affine map
    /// $p \mapsto D\\,Q\\,(p − x)$ of every point, with $D = \mathrm{diag}(d)$: for $d = 1/r_a$
    /// and Q the rows of an ellipsoid's principal directions this maps the ellipsoid centred
    /// at x onto the unit ball and the face onto a polygon (an affine map keeps planes and
    /// fans), so the ellipsoid meets the face exactly where the distance is at most 1.
    pub fn mapped_face_distance(&self, i: usize, x: &Vec3, q: &crate::tensor::Mat3, d: &Vec3) -> f64 {
        let map = |p: &Vec3| (q * (p - x)).component_mul(d);
        let (c, poly) = (map(&self.centres[i]), self.polygon(i));
        let origin = Vec3::zeros();
        let mut best = f64::INFINITY;
        for (k, a) in poly.iter().enumerate() {
            let (a, b) = (map(a), map(&poly[(k + 1) % poly.len()]));
            best = best.min(super::walls::triangle_offset(&origin, &c, &a, &b).norm());
        }
        best
    }

    /// All patches with the given role.
    pub fn with_role(mesh: &PolyMesh, role: PatchRole) -> Self {
        let ids: Vec<usize> = (0..mesh.patches().len())
            .filter(|&p| PatchRole::of(&mesh.patches()[p].kind) == role)
            .collect();
        Self::new(mesh, &ids)
    }

    /// The particle boundaries: every wall and exit patch (the patches particles pass through
    /// and constraint patches left out).
    pub fn boundaries(mesh: &PolyMesh) -> Self {
        let ids: Vec<usize> = (0..mesh.patches().len())
            .filter(|&p| {
                matches!(
                    PatchRole::of(&mesh.patches()[p].kind),
                    PatchRole::Wall | PatchRole::Exit
                )
            })
            .collect();
        Self::new(mesh, &ids)
    }

    /// Every patch.
    pub fn all(mesh: &PolyMesh) -> Self {
        Self::new(mesh, &(0..mesh.patches().len()).collect::<Vec<_>>())
    }

    /// Number of faces in the set.
    pub fn len(&self) -> usize {
        self.faces.len()
    }

    /// Whether the set has no face.
    pub fn is_empty(&self) -> bool {
        self.faces.is_empty()
    }

    /// Face i of the set: its mesh face and patch indices, centre and outward unit normal.
    pub fn face(&self, i: usize) -> SetFace {
        let (face, patch) = self.faces[i];
        SetFace {
            face: face as usize,
            patch: patch as usize,
            centre: self.centres[i],
            normal: self.normals[i],
        }
    }

    /// The vertices of face i of the set, in order around it (its fan of triangles joins them
    /// to [`SetFace::centre`]).
    pub fn polygon(&self, i: usize) -> &[Vec3] {
        &self.vertices[self.offsets[i]..self.offsets[i + 1]]
    }

    /// Largest distance from a face's centre to its vertices.
    pub fn circumradius(&self) -> f64 {
        self.circumradius
    }

    /// The faces in order of their bounding box's distance from `x` (a lower bound of the
    /// distance to the face): (index in the set, that distance).
    pub fn by_box_distance(&self, x: &Vec3) -> impl Iterator<Item = (usize, f64)> + '_ {
        let p = [x[0], x[1], x[2]];
        self.boxes
            .nearest_neighbor_iter(p)
            .map(move |hit| (hit.data as usize, hit.distance_2(&p).sqrt()))
    }

    /// The faces whose bounding box lies within `radius` of `x`, in no order: (index in the
    /// set, the box's distance, as [`Self::by_box_distance`] gives it). One query of the tree
    /// where the radius is known beforehand, without the incremental search's heap.
    pub fn within_box_distance(&self, x: &Vec3, radius: f64) -> impl Iterator<Item = (usize, f64)> + '_ {
        let p = [x[0], x[1], x[2]];
        // The tree compares squared distances; a hair wider, so that every box whose distance
        // is within `radius` once rooted is found, and the caller's filter decides.
        let wide = radius * (1.0 + 1e-12);
        self.boxes
            .locate_within_distance(p, wide * wide)
            .map(move |hit| (hit.data as usize, hit.distance_2(&p).sqrt()))
            .filter(move |&(_, d)| d <= radius)
    }

    /// The index in the set of the face whose centre is nearest to `x`.
    pub fn nearest(&self, x: &Vec3) -> Option<usize> {
        Some(self.tree.nearest_neighbor([x[0], x[1], x[2]])?.data as usize)
    }

    /// The face whose centre is nearest to `x`: (face, patch, distance).
    pub fn nearest_face(&self, x: &Vec3) -> Option<(usize, usize, f64)> {
        let hit = self.tree.nearest_neighbor([x[0], x[1], x[2]])?;
        let i = hit.data as usize;
        let (f, p) = self.faces[i];
        Some((f as usize, p as usize, (self.centres[i] - x).norm()))
    }
}

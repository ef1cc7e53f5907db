//! Boundary patches as particle boundaries: the gap between a particle's extent and the
//! nearest face of a set of patches.
//!
//! # Physics
//! A particle is an ellipsoid with barycentre $x_c$, semi-axes $r_a$ and rotation Q (rows: the
//! principal directions). Its extent along a unit vector n is the support distance
//! $h(n) = \sqrt{\sum_a r_a^2 (n·n_a)^2}$, so against a boundary face with centre $x_f$ and
//! outward unit normal $n_f$ the gap is $g = (x_f − x_c)·n_f − h(n_f)$; g ≤ 0 is contact.
//! The gap is taken over the [`NEAREST_FACES`] faces whose centres are nearest to $x_c$,
//! treating each face as its plane: exact for planar walls, and on a curved wall meshed with
//! faces of size h it is within O(h²κ) of the gap to the curved surface (κ the curvature).
//! Wall patches (`type wall`) deposit; generic patches (`type patch`: inlets and outlets)
//! let the particle exit; constraint patches (`empty`, `symmetry*`, `wedge`, `cyclic`, ...)
//! are not particle boundaries.

use super::mesh::PolyMesh;
use crate::ellipsoid::frame::support_distance;
use crate::tensor::{Mat3, Vec3};
use rstar::RTree;
use rstar::primitives::GeomWithData;

/// Faces tested for the nearest gap (the nearest ones by centre distance).
pub const NEAREST_FACES: usize = 8;

type FaceCentre = GeomWithData<[f64; 3], u32>;

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
    faces: Vec<(u32, u32)>,
    centres: Vec<Vec3>,
    normals: Vec<Vec3>,
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
        let tree = RTree::bulk_load(
            centres
                .iter()
                .enumerate()
                .map(|(i, c)| FaceCentre::new([c[0], c[1], c[2]], i as u32))
                .collect(),
        );
        Self {
            tree,
            faces,
            centres,
            normals,
        }
    }

    /// All patches with the given role.
    pub fn with_role(mesh: &PolyMesh, role: PatchRole) -> Self {
        let ids: Vec<usize> = (0..mesh.patches().len())
            .filter(|&p| PatchRole::of(&mesh.patches()[p].kind) == role)
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
        self.tree
            .nearest_neighbor_iter([centre[0], centre[1], centre[2]])
            .take(NEAREST_FACES)
            .map(|hit| {
                let i = hit.data as usize;
                let n = self.normals[i];
                let gap = (self.centres[i] - centre).dot(&n) - support_distance(semi_axes, q, &n);
                let (f, p) = self.faces[i];
                FaceGap {
                    face: f as usize,
                    patch: p as usize,
                    gap,
                }
            })
            .min_by(|a, b| a.gap.total_cmp(&b.gap))
    }
}

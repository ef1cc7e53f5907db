//! Patches a particle passes through, as symmetries of the flow: `cyclic` and `cyclicAMI`
//! pairs (translational or rotational), `symmetry` and `symmetryPlane` (mirrors) and the two
//! `wedge` patches of an axisymmetric case.
//!
//! # Physics
//! Each such patch p carries an isometry $T_p$ of the flow ([`crate::flow::image`]) that maps
//! the space just beyond p back into the domain:
//! - a cyclic pair (p, q): the rigid motion that takes p onto q, a translation where their
//!   normals are opposite and otherwise the rotation about the pair's axis by the angle θ with
//!   $R(θ)\\,n_p = −n_q$ (n the outward unit normals);
//! - the two wedges of an axisymmetric mesh: the rotation about the axis (the line where their
//!   planes meet) that takes one onto the other, as a rotational pair;
//! - a symmetry plane: the reflection about the plane of the face nearest to the point.
//!
//! A point x outside the mesh is *beyond* p where it lies on the outer side of p's plane (of
//! its nearest face for a patch that is not planar) and projects onto the patch's extent. The
//! flow there is $u(x) = Q^T u(T_p x)$, so a particle's integration stages may step across p
//! and see the flow on the other side of the pair or of the mirror
//! ([`PatchImages::sample`]); after the step the driver maps the particle's state with $T_p$
//! ([`crate::flow::FlowField::image`]).
//!
//! The blended field's supports see across the patches too ([`PatchImages::near`]): near a
//! patch, the cells and wall faces whose supports hold the point's image join the blend.
//!
//! # What the images do not reach
//! The wall layer's fits ([`super::wall_layer`]) are made from the cells on the wall face's
//! side of the patch: in a periodic channel the sampled velocity near a wall varies along the
//! axis by a few 10⁻⁴ of itself next to the pair. Wall contact and the clearance grid stay
//! those of the walls inside the mesh: a wall that continues across a cyclic pair is
//! measured up to the pair's plane, so a particle whose extent reaches across the plane onto
//! the wall beyond touches it one step later, once it has been mapped. A particle crossing
//! a wedge's axis (r → 0) is not mapped.

use super::error::FoamError;
use super::mesh::PolyMesh;
use super::patch::{IMAGE_PATCH_TYPES, PatchSet};
use crate::error::FlowError;
use crate::flow::{Crossing, FlowSample, Isometry};
use crate::tensor::Vec3;

/// Largest |n_f − n̄| of a patch's face normals about their mean, and largest distance of its
/// face centres from the mean plane relative to the patch's extent, for the patch to count as
/// planar: rounding of the points' coordinates only (10⁻¹⁵ relative) on a plane that
/// blockMesh or extrudeMesh wrote.
const PLANAR_TOL: f64 = 1e-9;

/// Largest misfit of a pair's transform, relative to the patch's extent: the image of p's
/// centroid must lie on q's plane, and p's mean normal map onto −q's, to this tolerance
/// (OpenFOAM's own `matchTolerance` default is 10⁻⁴ of the face size).
const PAIR_TOL: f64 = 1e-4;

/// How many maps a point may need (a corner where a symmetry plane meets a cyclic pair needs
/// two); a point still outside after them is left to the field, which refuses it.
const MAX_MAPS: usize = 3;

/// How a patch maps the space beyond it.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Map {
    /// A mirror about the nearest face's plane.
    Mirror,
    /// A pair's isometry.
    Pair(Isometry),
}

/// One patch a particle passes through.
#[derive(Debug, Clone)]
struct ImagePatch {
    /// Index in [`PolyMesh::patches`].
    patch: usize,
    /// The mean plane (a point and the outward unit normal) where the patch is planar.
    plane: Option<(Vec3, Vec3)>,
    /// The bounding box of the patch's points, widened by its largest face.
    lo: Vec3,
    hi: Vec3,
    map: Map,
}

impl ImagePatch {
    /// The signed distance of x beyond the patch's plane, where the patch is planar and x
    /// projects onto its extent (the box of its points widened by its largest face).
    fn depth(&self, x: &Vec3) -> Option<f64> {
        let (c, n) = self.plane?;
        let depth = (x - c).dot(&n);
        let on = x - depth * n;
        (0..3)
            .all(|k| on[k] >= self.lo[k] && on[k] <= self.hi[k])
            .then_some(depth)
    }

    /// The patch's map; a mirror's about the plane through `point` with unit normal `normal`
    /// (the patch's plane, or its nearest face's where it is not planar).
    fn map_at(&self, point: Vec3, normal: &Vec3) -> Isometry {
        match self.map {
            Map::Pair(map) => map,
            Map::Mirror => Isometry::reflection(point, normal),
        }
    }
}

/// The patches of a mesh a particle passes through, with their maps ([module docs](self)).
#[derive(Debug, Clone)]
pub struct PatchImages {
    patches: Vec<ImagePatch>,
    set: PatchSet,
}

/// The area-weighted centroid, the mean outward unit normal and the extent (box diagonal) of
/// patch `p`'s faces.
fn patch_plane(mesh: &PolyMesh, p: usize) -> (Vec3, Vec3, f64) {
    let patch = &mesh.patches()[p];
    let faces = patch.start..patch.start + patch.size;
    let (mut area, mut moment, mut normal) = (0.0, Vec3::zeros(), Vec3::zeros());
    let (mut lo, mut hi) = (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY));
    for f in faces {
        let a = mesh.face_areas()[f];
        area += a.norm();
        moment += a.norm() * mesh.face_centres()[f];
        normal += a;
        for &v in mesh.face(f) {
            lo = lo.inf(&mesh.points()[v as usize]);
            hi = hi.sup(&mesh.points()[v as usize]);
        }
    }
    (moment / area, normal.normalize(), (hi - lo).norm())
}

/// Whether patch `p` lies in the plane through `c` with unit normal `n` ([`PLANAR_TOL`]).
fn is_planar(mesh: &PolyMesh, p: usize, c: &Vec3, n: &Vec3, extent: f64) -> bool {
    let patch = &mesh.patches()[p];
    (patch.start..patch.start + patch.size).all(|f| {
        (mesh.face_areas()[f].normalize() - n).norm() <= PLANAR_TOL
            && (mesh.face_centres()[f] - c).dot(n).abs() <= PLANAR_TOL * extent
    })
}

/// The isometry that takes patch `p` onto patch `q` (module docs): a translation where their
/// normals are opposite, else the rotation about `axis` (through `centre`) or, where the
/// `boundary` file gives neither, about the line where their planes meet.
fn pair_map(
    mesh: &PolyMesh,
    p: usize,
    q: usize,
    separation: Option<Vec3>,
    axis: Option<Vec3>,
    centre: Option<Vec3>,
) -> Result<Isometry, FoamError> {
    let (cp, np, extent) = patch_plane(mesh, p);
    let (cq, nq, _) = patch_plane(mesh, q);
    let names = || format!("`{}` and `{}`", mesh.patches()[p].name, mesh.patches()[q].name);
    let bad = |reason: String| FoamError::Mesh {
        reason: format!("patches {}: {reason}", names()),
    };
    let map = if np.dot(&nq) <= -1.0 + PAIR_TOL * PAIR_TOL && axis.is_none() {
        // Either sign of a given separation vector: the one that takes p onto q's plane.
        let s = match separation {
            Some(s) if (cp + s - cq).dot(&nq).abs() <= (cp - s - cq).dot(&nq).abs() => s,
            Some(s) => -s,
            None => cq - cp,
        };
        Isometry::translation(s)
    } else {
        let axis = match axis {
            Some(a) if a.norm() > 0.0 => a.normalize(),
            Some(_) => return Err(bad("`rotationAxis` is zero".into())),
            None => np.cross(&nq).normalize(),
        };
        if !axis.iter().all(|a| a.is_finite()) {
            return Err(bad(
                "the normals are parallel: neither a translation nor a rotation".into()
            ));
        }
        let centre = match centre {
            Some(c) => c,
            None => {
                // The point of both planes nearest to the pair's midpoint along the axis.
                let m = nalgebra::Matrix3::from_rows(&[np.transpose(), nq.transpose(), axis.transpose()]);
                let rhs = Vec3::new(np.dot(&cp), nq.dot(&cq), axis.dot(&(0.5 * (cp + cq))));
                m.lu()
                    .solve(&rhs)
                    .ok_or_else(|| bad("the planes do not meet in a line".into()))?
            }
        };
        let flat = |v: Vec3| (v - axis * axis.dot(&v)).normalize();
        let (from, to) = (flat(np), flat(-nq));
        Isometry::rotation(&axis, centre, axis.dot(&from.cross(&to)).atan2(from.dot(&to)))
    };
    let normal_misfit = (map.vector(&np) + nq).norm();
    let plane_misfit = (map.point(&cp) - cq).dot(&nq).abs() / extent;
    if !(normal_misfit <= PAIR_TOL && plane_misfit <= PAIR_TOL) {
        return Err(bad(format!(
            "the transform ({map:?}) takes the first onto the second's plane with misfits {normal_misfit:.2e} \
             (normals) and {plane_misfit:.2e} (centroid offset over the patch's extent), above {PAIR_TOL:.0e}"
        )));
    }
    Ok(map)
}

/// Each patch's pair isometry (module docs), `None` for a patch that is not one of a cyclic
/// pair or of a wedge pair. An error names a pair whose transform cannot be found or does not
/// take one patch onto the other, a cyclic patch whose partner is missing, and a wedge case
/// with other than two `wedge` patches.
pub fn pair_maps(mesh: &PolyMesh) -> Result<Vec<Option<Isometry>>, FoamError> {
    let patches = mesh.patches();
    let mut maps = vec![None; patches.len()];
    let find = |name: &str| patches.iter().position(|p| p.name == name);
    for (p, patch) in patches.iter().enumerate() {
        if patch.size == 0 {
            continue;
        }
        if let (true, Some(c)) = (IMAGE_PATCH_TYPES.contains(&patch.kind.as_str()), &patch.coupling) {
            let q = find(&c.neighbour).ok_or_else(|| FoamError::Mesh {
                reason: format!(
                    "{} patch `{}`: its `neighbourPatch` `{}` is not in the mesh",
                    patch.kind, patch.name, c.neighbour
                ),
            })?;
            let rotational = c.transform.as_deref() == Some("rotational") || c.rotation_axis.is_some();
            maps[p] = Some(pair_map(
                mesh,
                p,
                q,
                c.separation,
                c.rotation_axis.filter(|_| rotational),
                c.rotation_centre.filter(|_| rotational),
            )?);
        }
    }
    let wedges: Vec<usize> = (0..patches.len())
        .filter(|&p| patches[p].kind == "wedge" && patches[p].size > 0)
        .collect();
    match wedges.as_slice() {
        [] => {}
        &[a, b] => {
            maps[a] = Some(pair_map(mesh, a, b, None, None, None)?);
            maps[b] = Some(pair_map(mesh, b, a, None, None, None)?);
        }
        more => {
            return Err(FoamError::Mesh {
                reason: format!(
                    "{} `wedge` patches with faces ({}): an axisymmetric mesh has two",
                    more.len(),
                    more.iter()
                        .map(|&p| patches[p].name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            });
        }
    }
    Ok(maps)
}

impl PatchImages {
    /// The patches of `mesh` a particle passes through, `None` where it has none with faces.
    pub fn new(mesh: &PolyMesh) -> Result<Option<Self>, FoamError> {
        let maps = pair_maps(mesh)?;
        let mut patches = Vec::new();
        for (p, patch) in mesh.patches().iter().enumerate() {
            if patch.size == 0 || !IMAGE_PATCH_TYPES.contains(&patch.kind.as_str()) {
                continue;
            }
            let map = match (maps[p], patch.kind.as_str()) {
                (Some(map), _) => Map::Pair(map),
                (None, "symmetry" | "symmetryPlane") => Map::Mirror,
                (None, kind) => {
                    return Err(FoamError::Mesh {
                        reason: format!("{kind} patch `{}` has no partner (`neighbourPatch`)", patch.name),
                    });
                }
            };
            let (c, n, extent) = patch_plane(mesh, p);
            let (mut lo, mut hi) = (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY));
            let mut widest: f64 = 0.0;
            for f in patch.start..patch.start + patch.size {
                for &v in mesh.face(f) {
                    let x = mesh.points()[v as usize];
                    lo = lo.inf(&x);
                    hi = hi.sup(&x);
                    widest = widest.max((x - mesh.face_centres()[f]).norm());
                }
            }
            patches.push(ImagePatch {
                patch: p,
                plane: is_planar(mesh, p, &c, &n, extent).then_some((c, n)),
                lo: lo - Vec3::repeat(widest),
                hi: hi + Vec3::repeat(widest),
                map,
            });
        }
        if patches.is_empty() {
            return Ok(None);
        }
        let ids: Vec<usize> = patches.iter().map(|p| p.patch).collect();
        Ok(Some(Self {
            set: PatchSet::new(mesh, &ids),
            patches,
        }))
    }

    /// The map of the patch x lies beyond, if any (module docs). Of several, the one x lies
    /// farthest beyond.
    fn beyond(&self, x: &Vec3) -> Option<Crossing> {
        let mut best: Option<(f64, Crossing)> = None;
        let mut consider = |depth: f64, map: Isometry, point: Vec3, normal: Vec3| {
            if depth > 0.0 && best.is_none_or(|(d, _)| depth > d) {
                best = Some((depth, Crossing { map, point, normal }));
            }
        };
        let curved = self.patches.iter().any(|p| p.plane.is_none());
        for (patch, (c, n)) in self.patches.iter().filter_map(|p| Some((p, p.plane?))) {
            if let Some(depth) = patch.depth(x) {
                consider(depth, patch.map_at(c, &n), c, n);
            }
        }
        if curved && let Some(face) = self.set.nearest(x).map(|i| self.set.face(i)) {
            let patch = self.patches.iter().find(|i| i.patch == face.patch)?;
            if patch.plane.is_none() {
                let depth = (x - face.centre).dot(&face.normal);
                consider(depth, patch.map_at(face.centre, &face.normal), face.centre, face.normal);
            }
        }
        best.map(|(_, map)| map)
    }

    /// The maps of the patches within `reach` of x on the domain's side (a planar patch's plane
    /// within reach, x projecting onto its extent; the nearest face's plane of the others): the
    /// images by which a field whose supports reach that far sees across them
    /// ([`super::BlendedFlow`]). A mirror maps about the patch's (or face's) plane.
    pub fn near(&self, x: &Vec3, reach: f64) -> Vec<Isometry> {
        let mut maps = Vec::new();
        let curved = self.patches.iter().any(|p| p.plane.is_none());
        for (patch, (c, n)) in self.patches.iter().filter_map(|p| Some((p, p.plane?))) {
            if patch.depth(x).is_some_and(|d| d <= 0.0 && d > -reach) {
                maps.push(patch.map_at(c, &n));
            }
        }
        if curved && let Some(face) = self.set.nearest(x).map(|i| self.set.face(i)) {
            let depth = (x - face.centre).dot(&face.normal);
            if let Some(patch) = self.patches.iter().find(|i| i.patch == face.patch && i.plane.is_none())
                && depth <= 0.0
                && depth > -reach
            {
                maps.push(patch.map_at(face.centre, &face.normal));
            }
        }
        maps
    }

    /// The flow at x from `inside` (a sample of the mesh's field): where x is outside the mesh
    /// (`outside`) beyond one of the patches, `inside` at its image, pulled back (module docs).
    pub fn sample(
        &self,
        x: &Vec3,
        inside: impl Fn(&Vec3) -> Result<FlowSample, FlowError>,
        outside: impl Fn(&Vec3) -> bool,
    ) -> Result<FlowSample, FlowError> {
        match self.image(x, outside) {
            Some(Crossing { map, .. }) => inside(&map.point(x)).map(|s| map.pull(&s)),
            None => inside(x),
        }
    }

    /// The plane crossed and the map that brings x back inside the mesh, where x is outside
    /// it beyond one of the patches (`outside` says whether a point is outside the mesh; it is
    /// asked only beyond a patch's plane): the plane is the first patch's, the map composes
    /// up to three patches' (a corner). `None` inside, or outside elsewhere.
    pub fn image(&self, x: &Vec3, outside: impl Fn(&Vec3) -> bool) -> Option<Crossing> {
        let first = self.beyond(x)?;
        if !outside(x) {
            return None;
        }
        let mut map = first.map;
        for _ in 1..MAX_MAPS {
            let y = map.point(x);
            let Some(next) = self.beyond(&y).filter(|_| outside(&y)) else {
                break;
            };
            map = compose(&next.map, &map);
        }
        Some(Crossing { map, ..first })
    }
}

/// $T_b ∘ T_a$.
fn compose(b: &Isometry, a: &Isometry) -> Isometry {
    // T_b(T_a x) = Q_b Q_a x + (T_b(T_a 0)) with origin 0.
    let zero = Vec3::zeros();
    Isometry {
        q: b.q * a.q,
        origin: zero,
        shift: b.point(&a.point(&zero)),
    }
}

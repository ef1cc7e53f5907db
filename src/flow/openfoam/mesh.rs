//! The OpenFOAM `polyMesh`: points, faces (any number of vertices), owner and neighbour
//! cells, boundary patches, and the geometry derived from them.
//!
//! # Geometry
//! Computed as OpenFOAM computes it, so that centres agree with the solver's to round-off:
//! a face's centre and area vector come from the triangle fan around its vertex average
//! (area-weighted triangle centroids; the area vector is the sum of the triangle areas, and
//! points out of the owner cell); a cell's centre and volume from the pyramids on its faces
//! with apex at the average of its face centres (volume-weighted pyramid centroids).

use super::error::FoamError;
use super::parse::{Entry, Limit, Parser, Tok, Value, number, read_file};
use crate::tensor::Vec3;
use std::path::Path;

/// One boundary patch: a contiguous range of boundary faces.
#[derive(Debug, Clone, PartialEq)]
pub struct Patch {
    /// Patch name.
    pub name: String,
    /// Geometric type (`wall`, `patch`, `empty`, `symmetryPlane`, ...).
    pub kind: String,
    /// First face.
    pub start: usize,
    /// Number of faces.
    pub size: usize,
    /// A coupled patch's partner and transform, as the `boundary` file gives them (`cyclic`,
    /// `cyclicAMI`); `None` for every other type.
    pub coupling: Option<Coupling>,
}

/// What `constant/polyMesh/boundary` says of a coupled (`cyclic`, `cyclicAMI`) patch: its
/// partner and, where given, its transform. What is not given is found from the two patches'
/// geometry ([`super::images`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Coupling {
    /// The partner patch (`neighbourPatch`).
    pub neighbour: String,
    /// `transform` (`translational`, `rotational`, `noOrdering`, `coincidentFullMatch`, ...).
    pub transform: Option<String>,
    /// `separationVector` of a translational pair.
    pub separation: Option<Vec3>,
    /// `rotationAxis` of a rotational pair.
    pub rotation_axis: Option<Vec3>,
    /// `rotationCentre` of a rotational pair.
    pub rotation_centre: Option<Vec3>,
}

/// A polyhedral mesh with its derived geometry.
#[derive(Debug, Clone)]
pub struct PolyMesh {
    points: Vec<Vec3>,
    face_offsets: Vec<u32>,
    face_points: Vec<u32>,
    owner: Vec<u32>,
    neighbour: Vec<u32>,
    patches: Vec<Patch>,
    cell_offsets: Vec<u32>,
    cell_faces: Vec<u32>,
    face_centres: Vec<Vec3>,
    face_areas: Vec<Vec3>,
    cell_centres: Vec<Vec3>,
    cell_volumes: Vec<f64>,
}

fn mesh_err(reason: String) -> FoamError {
    FoamError::Mesh { reason }
}

impl PolyMesh {
    /// Read `constant/polyMesh` of `case` (each file plain or `.gz`, ASCII or binary).
    pub fn read(case: &Path) -> Result<Self, FoamError> {
        let dir = case.join("constant").join("polyMesh");
        let (path, text) = read_file(&dir.join("faces"), Limit::any())?;
        let mut p = Parser::new(&path, &text);
        let header = p.header()?;
        let (face_offsets, face_points) = match header.class.as_str() {
            "faceCompactList" => {
                let offsets = p.labels()?;
                let flat = p.labels()?;
                (offsets, flat)
            }
            "faceList" => {
                let at = p.offset();
                let n = p.count()?;
                // "3(a b c)" is at least 8 bytes.
                p.check_room(n, 8, at)?;
                p.expect(b'(')?;
                let mut offsets = Vec::with_capacity(n + 1);
                offsets.push(0);
                let mut flat = Vec::new();
                for _ in 0..n {
                    flat.extend(p.labels()?);
                    let end = u32::try_from(flat.len())
                        .map_err(|_| p.error_at(p.offset(), "more than 2^32 face vertices"))?;
                    offsets.push(end);
                }
                p.expect(b')')?;
                (offsets, flat)
            }
            other => return Err(p.error_at(0, format!("faces: unexpected class `{other}`"))),
        };
        p.end()?;

        // The faces first: every point of a valid mesh is a vertex of some face (checkMesh
        // refuses unused points), so there are at most as many points as face vertices, and a
        // gzipped `points` is inflated no further than they can take.
        let (path, text) = read_file(
            &dir.join("points"),
            Limit::entries(face_points.len(), 3, "points (each a vertex of a face)", 0, ""),
        )?;
        let mut p = Parser::new(&path, &text);
        p.header()?;
        let numbers = p.numbers(3)?;
        if numbers.data.len() != 3 * numbers.count {
            return Err(p.error_at(numbers.offset, "uniform point list"));
        }
        p.end()?;
        let points = numbers
            .data
            .chunks_exact(3)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect();

        // One owner per face, at most one neighbour per face.
        let n_faces = face_offsets.len().saturating_sub(1);
        let owner = read_labels(&dir.join("owner"), n_faces)?;
        let neighbour = read_labels(&dir.join("neighbour"), n_faces)?;
        let patches = read_boundary(&dir.join("boundary"))?;
        Self::new(points, face_offsets, face_points, owner, neighbour, patches)
    }

    /// Mesh from raw arrays (faces as compact offsets + vertex list), fully checked.
    pub fn new(
        points: Vec<Vec3>,
        face_offsets: Vec<u32>,
        face_points: Vec<u32>,
        owner: Vec<u32>,
        neighbour: Vec<u32>,
        patches: Vec<Patch>,
    ) -> Result<Self, FoamError> {
        if let Some(i) = points.iter().position(|p| !p.iter().all(|c| c.is_finite())) {
            return Err(mesh_err(format!("point {i} is not finite")));
        }
        let n_faces = face_offsets
            .len()
            .checked_sub(1)
            .ok_or_else(|| mesh_err("faces: empty offset list".into()))?;
        if face_offsets[0] != 0 || face_offsets[n_faces] as usize != face_points.len() {
            return Err(mesh_err(format!(
                "faces: offsets run from {} to {} but there are {} vertex labels",
                face_offsets[0],
                face_offsets[n_faces],
                face_points.len()
            )));
        }
        for f in 0..n_faces {
            let (a, b) = (face_offsets[f], face_offsets[f + 1]);
            if b < a.saturating_add(3) {
                return Err(mesh_err(format!(
                    "face {f} has {} vertices (needs at least 3)",
                    i64::from(b) - i64::from(a)
                )));
            }
        }
        if let Some(&v) = face_points.iter().find(|&&v| v as usize >= points.len()) {
            return Err(mesh_err(format!(
                "a face uses point {v} but there are {} points",
                points.len()
            )));
        }
        if owner.len() != n_faces {
            return Err(mesh_err(format!(
                "owner has {} entries for {n_faces} faces",
                owner.len()
            )));
        }
        let n_internal = neighbour.len();
        // Cell-to-face addressing lists internal faces twice and is indexed by u32.
        if n_faces.saturating_add(n_internal) >= u32::MAX as usize {
            return Err(mesh_err(format!("{n_faces} faces exceed the 32-bit addressing")));
        }
        if n_internal > n_faces {
            return Err(mesh_err(format!(
                "neighbour has {n_internal} entries for {n_faces} faces"
            )));
        }
        let n_cells = owner.iter().chain(&neighbour).max().map_or(0, |&m| m as usize + 1);
        if n_cells == 0 {
            return Err(mesh_err("the mesh has no cells".into()));
        }
        // Every cell has at least 4 faces and a face at most 2 cells, so a mesh of F faces has at
        // most F/2 cells: a larger cell label is corrupt, and sizing the addressing by it could
        // ask for gigabytes (owner = 2³¹ − 1 wanted 8 GiB).
        if n_cells > n_faces / 2 {
            return Err(mesh_err(format!(
                "cell label {} in owner/neighbour, but {n_faces} faces can close at most {} cells",
                n_cells - 1,
                n_faces / 2
            )));
        }
        if let Some(f) = (0..n_internal).find(|&f| owner[f] == neighbour[f]) {
            return Err(mesh_err(format!(
                "internal face {f} has cell {} on both sides",
                owner[f]
            )));
        }
        let mut next = n_internal;
        for p in patches.iter().filter(|p| p.size > 0) {
            let end = p
                .start
                .checked_add(p.size)
                .filter(|&e| e <= n_faces)
                .ok_or_else(|| mesh_err(format!("patch `{}` runs past the last face {n_faces}", p.name)))?;
            if p.start != next {
                return Err(mesh_err(format!(
                    "patch `{}` starts at face {} but the previous boundary faces end at {next}",
                    p.name, p.start
                )));
            }
            next = end;
        }
        if next != n_faces {
            return Err(mesh_err(format!(
                "patches cover boundary faces {n_internal}..{next} but the mesh has {n_faces} faces"
            )));
        }

        // Cell -> faces, compact.
        let mut counts = vec![0u32; n_cells + 1];
        for &c in owner.iter().chain(&neighbour) {
            counts[c as usize + 1] += 1;
        }
        if let Some(c) = (0..n_cells).find(|&c| counts[c + 1] < 4) {
            return Err(mesh_err(format!(
                "cell {c} has {} faces (a closed cell needs at least 4)",
                counts[c + 1]
            )));
        }
        for c in 0..n_cells {
            counts[c + 1] += counts[c];
        }
        let cell_offsets = counts;
        let mut fill = cell_offsets.clone();
        let mut cell_faces = vec![0u32; 2 * n_internal + (n_faces - n_internal)];
        for (f, &c) in owner.iter().enumerate().chain(neighbour.iter().enumerate()) {
            cell_faces[fill[c as usize] as usize] = f as u32;
            fill[c as usize] += 1;
        }

        let mut mesh = Self {
            points,
            face_offsets,
            face_points,
            owner,
            neighbour,
            patches,
            cell_offsets,
            cell_faces,
            face_centres: Vec::new(),
            face_areas: Vec::new(),
            cell_centres: Vec::new(),
            cell_volumes: Vec::new(),
        };
        mesh.geometry()?;
        Ok(mesh)
    }

    fn geometry(&mut self) -> Result<(), FoamError> {
        let n_faces = self.n_faces();
        let (mut centres, mut areas) = (Vec::with_capacity(n_faces), Vec::with_capacity(n_faces));
        for f in 0..n_faces {
            let (c, s) = face_geometry(
                &self
                    .face(f)
                    .iter()
                    .map(|&v| self.points[v as usize])
                    .collect::<Vec<_>>(),
            );
            centres.push(c);
            areas.push(s);
        }
        self.face_centres = centres;
        self.face_areas = areas;
        let n_cells = self.n_cells();
        let (mut centres, mut volumes) = (Vec::with_capacity(n_cells), Vec::with_capacity(n_cells));
        for c in 0..n_cells {
            let faces = self.cell_faces(c);
            let estimate = faces.iter().map(|&f| self.face_centres[f as usize]).sum::<Vec3>() / faces.len() as f64;
            let (mut moment, mut vol3) = (Vec3::zeros(), 0.0);
            for &f in faces {
                let f = f as usize;
                let sign = if self.owner[f] as usize == c { 1.0 } else { -1.0 };
                let v = sign * self.face_areas[f].dot(&(self.face_centres[f] - estimate));
                moment += v * (0.75 * self.face_centres[f] + 0.25 * estimate);
                vol3 += v;
            }
            let volume = vol3 / 3.0;
            // Also rejects NaN.
            if volume.is_nan() || volume <= 0.0 {
                return Err(FoamError::DegenerateCell { cell: c, volume });
            }
            centres.push(moment / vol3);
            volumes.push(volume);
        }
        self.cell_centres = centres;
        self.cell_volumes = volumes;
        Ok(())
    }

    /// A hash (16 hex digits) of the mesh as read: points (every f64's bits), faces, owners,
    /// neighbours and patches (name, type, start, size). Everything else of the mesh is
    /// derived from these. Deterministic (FNV-1a, 64 bit, over a fixed byte layout), the same
    /// for a copy of the case anywhere, and cheap next to reading the mesh (one pass over its
    /// arrays: tens of milliseconds per million cells).
    pub fn content_hash(&self) -> String {
        let mut h = super::Fnv::new(b"pseudorigid polyMesh v1");
        h.f64s(self.points.iter().flat_map(|p| p.iter().copied()));
        for part in [&self.face_offsets, &self.face_points, &self.owner, &self.neighbour] {
            h.u64(part.len() as u64);
            part.iter().for_each(|&v| h.u64(u64::from(v)));
        }
        for p in &self.patches {
            h.bytes(p.name.as_bytes());
            h.bytes(p.kind.as_bytes());
            h.u64(p.start as u64);
            h.u64(p.size as u64);
        }
        h.hex()
    }

    /// Number of cells.
    pub fn n_cells(&self) -> usize {
        self.cell_offsets.len() - 1
    }

    /// Number of faces.
    pub fn n_faces(&self) -> usize {
        self.owner.len()
    }

    /// Number of internal faces (faces `0..n_internal_faces()` have a neighbour).
    pub fn n_internal_faces(&self) -> usize {
        self.neighbour.len()
    }

    /// Vertex coordinates.
    pub fn points(&self) -> &[Vec3] {
        &self.points
    }

    /// Vertex labels of face `f`, ordered so that the right-hand normal points out of the owner.
    pub fn face(&self, f: usize) -> &[u32] {
        &self.face_points[self.face_offsets[f] as usize..self.face_offsets[f + 1] as usize]
    }

    /// Owner cell of face `f`.
    pub fn owner(&self, f: usize) -> usize {
        self.owner[f] as usize
    }

    /// Neighbour cell of face `f`, `None` on the boundary.
    pub fn neighbour(&self, f: usize) -> Option<usize> {
        self.neighbour.get(f).map(|&n| n as usize)
    }

    /// Faces of cell `c`.
    pub fn cell_faces(&self, c: usize) -> &[u32] {
        &self.cell_faces[self.cell_offsets[c] as usize..self.cell_offsets[c + 1] as usize]
    }

    /// Boundary patches in face order.
    pub fn patches(&self) -> &[Patch] {
        &self.patches
    }

    /// Index of the patch owning boundary face `f`, `None` for an internal face.
    pub fn patch_of(&self, f: usize) -> Option<usize> {
        if f < self.n_internal_faces() {
            return None;
        }
        self.patches.iter().position(|p| f >= p.start && f < p.start + p.size)
    }

    /// Face centres.
    pub fn face_centres(&self) -> &[Vec3] {
        &self.face_centres
    }

    /// Face area vectors (magnitude = area, direction out of the owner cell).
    pub fn face_areas(&self) -> &[Vec3] {
        &self.face_areas
    }

    /// Cell centres (centroids).
    pub fn cell_centres(&self) -> &[Vec3] {
        &self.cell_centres
    }

    /// Cell volumes.
    pub fn cell_volumes(&self) -> &[f64] {
        &self.cell_volumes
    }
}

/// Centre and area vector of a polygon (triangle fan around the vertex average).
fn face_geometry(p: &[Vec3]) -> (Vec3, Vec3) {
    if let [a, b, c] = p {
        return ((a + b + c) / 3.0, 0.5 * (b - a).cross(&(c - a)));
    }
    let mean = p.iter().sum::<Vec3>() / p.len() as f64;
    let (mut sum_n, mut sum_a, mut sum_ac) = (Vec3::zeros(), 0.0, Vec3::zeros());
    for (i, a) in p.iter().enumerate() {
        let b = &p[(i + 1) % p.len()];
        let n = (b - a).cross(&(mean - a));
        let area = n.norm();
        sum_n += n;
        sum_a += area;
        sum_ac += area * (a + b + mean);
    }
    let centre = if sum_a > 0.0 { sum_ac / (3.0 * sum_a) } else { mean };
    (centre, 0.5 * sum_n)
}

/// A label list of at most `n_faces` entries (one per face).
fn read_labels(path: &Path, n_faces: usize) -> Result<Vec<u32>, FoamError> {
    let (name, text) = read_file(path, Limit::entries(n_faces, 1, "labels (at most one per face)", 0, ""))?;
    let mut p = Parser::new(&name, &text);
    p.header()?;
    let labels = p.labels()?;
    p.end()?;
    Ok(labels)
}

fn read_boundary(path: &Path) -> Result<Vec<Patch>, FoamError> {
    let (name, text) = read_file(path, Limit::any())?;
    let mut p = Parser::new(&name, &text);
    p.header()?;
    let at = p.offset();
    let n = p.count()?;
    // "a{type patch;nFaces 0;startFace 0;}" is at least 30 bytes.
    p.check_room(n, 30, at)?;
    p.expect(b'(')?;
    let mut patches = Vec::with_capacity(n);
    for _ in 0..n {
        let at = p.offset();
        let name = match p.token()? {
            Tok::Word(w) | Tok::Str(w) => w.to_string(),
            _ => return Err(p.error_at(at, "expected a patch name")),
        };
        p.expect(b'{')?;
        let dict = p.dict_body(at, 1)?;
        let field = |key: &str| -> Result<usize, FoamError> {
            dict.word(key).and_then(|w| w.parse::<usize>().ok()).ok_or_else(|| {
                p.error_at(
                    at,
                    format!("patch `{name}`: `{key}` missing or not a non-negative integer"),
                )
            })
        };
        let (start, size) = (field("startFace")?, field("nFaces")?);
        let kind = dict
            .word("type")
            .ok_or_else(|| p.error_at(at, format!("patch `{name}` has no `type`")))?
            .to_string();
        let coupling = if kind.starts_with("cyclic") {
            let neighbour = dict
                .word("neighbourPatch")
                .ok_or_else(|| p.error_at(at, format!("{kind} patch `{name}` has no `neighbourPatch`")))?
                .to_string();
            let vector = |key: &str| -> Result<Option<Vec3>, FoamError> {
                match dict.get(key) {
                    None => Ok(None),
                    Some((Entry::Values(v), _)) => match v.as_slice() {
                        [Value::List(items)] if items.len() == 3 => {
                            let c: Vec<f64> = items.iter().filter_map(number).filter(|c| c.is_finite()).collect();
                            (c.len() == 3)
                                .then(|| Some(Vec3::new(c[0], c[1], c[2])))
                                .ok_or_else(|| {
                                    p.error_at(at, format!("patch `{name}`: `{key}` is not a finite vector"))
                                })
                        }
                        _ => Err(p.error_at(at, format!("patch `{name}`: `{key}` is not a vector `(x y z)`"))),
                    },
                    Some(_) => Err(p.error_at(at, format!("patch `{name}`: `{key}` is not a vector `(x y z)`"))),
                }
            };
            Some(Coupling {
                neighbour,
                transform: dict.word("transform").map(str::to_string),
                separation: vector("separationVector")?,
                rotation_axis: vector("rotationAxis")?,
                rotation_centre: vector("rotationCentre")?,
            })
        } else {
            None
        };
        patches.push(Patch {
            name,
            kind,
            start,
            size,
            coupling,
        });
    }
    p.expect(b')')?;
    p.end()?;
    Ok(patches)
}

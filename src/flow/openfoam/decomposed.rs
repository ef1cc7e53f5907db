//! Decomposed cases: the `processorN/` directories that `decomposePar` writes (and a solver run
//! in parallel fills with its time directories), read directly and reassembled into the
//! undecomposed mesh and fields, without `reconstructPar`.
//!
//! # What is read
//! Each `processorN/constant/polyMesh` is a mesh like any other (read by [`PolyMesh::read`]),
//! with its addressing back to the undecomposed mesh, as `decomposePar` writes it:
//! - `cellProcAddressing`: the global cell of each local cell;
//! - `faceProcAddressing`: the global face of each local face, 1-based and signed: −(f + 1)
//!   where the local face is global face f reversed (first vertex kept, the others in reverse
//!   order, OpenFOAM's `face::reverseFace`). An inter-processor face is listed by both of its
//!   processors, as it is by the processor of its owner cell and reversed by the processor of
//!   its neighbour cell, which owns it there;
//! - `pointProcAddressing`: the global point of each local point;
//! - `boundaryProcAddressing`: the global patch of each local patch, −1 for the inter-processor
//!   (`processor`) patches.
//!
//! The global mesh is rebuilt from these: points, faces with their global vertex order,
//! owners, neighbours and patches, in the global numbering. It is the mesh `decomposePar`
//! started from, array for array, and its geometry is computed from it as for any mesh, so a
//! flow read decomposed samples bitwise as the flow read from the undecomposed case (checked
//! against OpenFOAM's own decompositions in the tests and in `cases/decomposed-ci.sh`). A field
//! of time t is each processor's `processorN/t/<name>` (read by [`read_vol_field`] on the
//! processor's mesh) placed by the same addressing: its cells, and the faces of the real
//! patches. The values a field stores on processor patches (the other side's cells) are not
//! needed.
//!
//! A patch that no processor's faces reach keeps its name and type from the processors'
//! `boundary` files and starts where the previous patch ends, as OpenFOAM numbers an empty
//! patch.
//!
//! # Untrusted input
//! The global sizes are bounded by the sums of the local ones before anything is allocated:
//! every addressing list must have one entry per local cell, face, point or patch; the cells
//! must be a permutation of `0..Σ cells`; a global point or face label must be below the sum of
//! the local point or face counts. Then every global point must be reached, with the same
//! coordinates (bit for bit) from every processor that has it; every global face once as owner
//! (not reversed) and, if internal, once as neighbour, with the same vertices from both sides;
//! a face of a real patch never reversed, and listed by one processor; internal faces first,
//! then the patches in the order of their global labels, each contiguous; a global patch named
//! and typed alike by every processor. Anything else is a [`FoamError::Decomposition`] naming
//! the file and the first inconsistency, and [`PolyMesh::new`] checks the reassembled mesh as
//! it checks any other.
//!
//! # Errors
//! - a processor directory without its addressing files (a mesh decomposed by hand, or meshed
//!   in parallel by `snappyHexMesh -parallel` and never reconstructed):
//!   [`FoamError::NoProcAddressing`], which names `reconstructParMesh` and `reconstructPar`;
//! - missing processor directories in `processor0 … processorN−1`, the collated format
//!   (`processors<N>/`, one file per field), `processorCyclic` patches (cyclic patches split
//!   between processors) and inconsistent addressing: [`FoamError::Decomposition`];
//! - a time directory missing from one processor: [`FoamError::Missing`] naming its file.
//!
//! Meshes that move or change in time (`processorN/<time>/polyMesh`) are not read: the mesh is
//! `constant/polyMesh`, as for undecomposed cases.

use super::error::FoamError;
use super::field::{VolField, read_vol_field};
use super::mesh::{Patch, PolyMesh};
use super::parse::{Limit, Parser, read_file};
use crate::tensor::Vec3;
use std::ffi::{OsStr, OsString};
use std::path::{Path, PathBuf};

/// Where [`FoamCase::open_with`](super::FoamCase::open_with) reads the mesh and the time
/// directories of a case.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Layout {
    /// The reconstructed data where present, else the decomposed: the mesh from
    /// `constant/polyMesh` if it has one, else reassembled from the processor directories; the
    /// times of the top level and of `processor0/` together, each time read from the top level
    /// where it is there (a case meshed serially, decomposed and solved in parallel reads its
    /// solution from the processors). Mixing is safe: before a field is read from the
    /// processors, their mesh is reassembled and must be the top level's, face for face, or
    /// the read fails with [`FoamError::Decomposition`]. [`FoamCase::open`](super::FoamCase::open)
    /// uses this.
    #[default]
    Auto,
    /// Only the top level, as a serial case: a time or a mesh that only the processors have
    /// is a [`FoamError::Decomposed`] error.
    Reconstructed,
    /// Only the processor directories, even where the top level has the mesh or the time.
    Decomposed,
}

/// The processor directories `processor0 … processorN−1` of a case, by number (empty when the
/// case is not decomposed). Other names are not processor directories.
pub fn processor_dirs(case: &Path) -> Vec<(u64, PathBuf)> {
    let mut dirs: Vec<(u64, PathBuf)> = std::fs::read_dir(case).map_or_else(
        |_| Vec::new(),
        |entries| {
            entries
                .filter_map(Result::ok)
                .filter_map(|e| {
                    let n = e.file_name().to_str()?.strip_prefix("processor")?.to_string();
                    let digits = !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit());
                    digits.then(|| Some((n.parse().ok()?, e.path())))?
                })
                .filter(|(_, p)| p.is_dir())
                .collect()
        },
    );
    dirs.sort_by_key(|d| d.0);
    dirs
}

/// The time directories of `dir` (names that parse as finite numbers), ascending.
pub(crate) fn time_dirs(dir: &Path) -> Result<Vec<(f64, OsString)>, FoamError> {
    let entries = std::fs::read_dir(dir).map_err(|source| FoamError::Io {
        path: dir.display().to_string(),
        source,
    })?;
    let mut times: Vec<(f64, OsString)> = entries
        .filter_map(Result::ok)
        .filter(|e| e.path().is_dir())
        .filter_map(|e| {
            let t = e.file_name().to_str()?.parse::<f64>().ok()?;
            t.is_finite().then(|| (t, e.file_name()))
        })
        .collect();
    times.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok(times)
}

/// A processor's global patch of each local patch, `None` for an inter-processor patch.
type PatchMap = Vec<Option<usize>>;

/// One processor's mesh and where its cells and boundary faces go in the global mesh.
#[derive(Debug, Clone)]
struct Processor {
    dir: PathBuf,
    mesh: PolyMesh,
    /// Global cell of each local cell.
    cells: Vec<u32>,
    /// Per local boundary face (counted from the local first boundary face): its global
    /// boundary face (counted from the global first boundary face), or `u32::MAX` on an
    /// inter-processor patch.
    boundary: Vec<u32>,
    /// Global patch of each local patch, `None` for the inter-processor patches.
    patches: PatchMap,
}

/// A decomposed case's processors, with the addressing that places their cells and boundary
/// faces in the global mesh. [`Decomposition::read`] also returns that mesh.
#[derive(Debug, Clone)]
pub struct Decomposition {
    case: PathBuf,
    processors: Vec<Processor>,
    n_cells: usize,
    n_boundary_faces: usize,
    n_patches: usize,
}

fn inconsistent(path: &Path, reason: impl Into<String>) -> FoamError {
    FoamError::Decomposition {
        path: path.display().to_string(),
        reason: reason.into(),
    }
}

/// A processor's addressing list, entries in `lo..=hi`, one per local item (`count`).
fn addressing(dir: &Path, name: &str, count: usize, lo: i64, hi: i64) -> Result<Vec<i64>, FoamError> {
    let path = dir.join("constant").join("polyMesh").join(name);
    let (shown, text) = read_file(&path, Limit::entries(count, 1, "addressing labels", 0, ""))?;
    let mut p = Parser::new(&shown, &text);
    p.header()?;
    let labels = p.signed_labels()?;
    p.end()?;
    if labels.len() != count {
        return Err(inconsistent(
            &path,
            format!("{} entries for the processor's {count}", labels.len()),
        ));
    }
    if let Some((i, v)) = labels.iter().enumerate().find(|(_, v)| !(lo..=hi).contains(*v)) {
        return Err(inconsistent(&path, format!("entry {i} is {v}, outside {lo}..={hi}")));
    }
    Ok(labels)
}

/// The addressing files `decomposePar` writes, in the order they are checked.
const ADDRESSING: [&str; 4] = [
    "cellProcAddressing",
    "faceProcAddressing",
    "pointProcAddressing",
    "boundaryProcAddressing",
];

/// Where a global face was first seen: processor, local face, reversed.
#[derive(Clone, Copy)]
struct Source {
    processor: u32,
    face: u32,
    reversed: bool,
}

const UNSET: u32 = u32::MAX;

impl Decomposition {
    /// Read the processor directories of `case` and reassemble the global mesh: the
    /// processors' meshes, then their cells, points, patches and faces placed in the global
    /// numbering and checked in that order (module docs), the global mesh built from them.
    pub fn read(case: &Path) -> Result<(Self, PolyMesh), FoamError> {
        let dirs = processor_dirs_with_addressing(case)?;
        let meshes = dirs
            .iter()
            .map(|(_, dir)| PolyMesh::read(dir))
            .collect::<Result<Vec<_>, _>>()?;
        let caps = Caps::of(case, &meshes)?;
        let cells = place_cells(&dirs, &meshes, caps.cells)?;
        let (point_lists, points) = place_points(case, &dirs, &meshes, caps.points)?;
        let (patch_maps, global_patches) = place_patches(case, &dirs, &meshes, caps.patches)?;
        let face_lists = face_addressing(&dirs, &meshes, caps.faces)?;
        let faces = place_faces(&dirs, &meshes, &cells, &point_lists, &patch_maps, &face_lists)?;
        let n_internal = faces.check(case)?;
        let patches = number_patches(global_patches, &faces.patch_of, n_internal);
        let (face_offsets, face_points) = face_vertices(case, &meshes, &point_lists, &faces.source)?;
        let Faces {
            owner, mut neighbour, ..
        } = faces;
        neighbour.truncate(n_internal);
        let n_patches = patches.len();
        let mesh = PolyMesh::new(points, face_offsets, face_points, owner, neighbour, patches)?;

        let processors = dirs
            .into_iter()
            .zip(meshes)
            .zip(cells.into_iter().zip(face_lists).zip(patch_maps))
            .map(|(((_, dir), local), ((cells, faces), patches))| {
                let boundary = boundary_addressing(&local, &faces, &patches, n_internal);
                Processor {
                    dir,
                    mesh: local,
                    cells,
                    boundary,
                    patches,
                }
            })
            .collect();
        let decomposition = Self {
            case: case.to_path_buf(),
            processors,
            n_cells: caps.cells,
            n_boundary_faces: mesh.n_faces() - n_internal,
            n_patches,
        };
        Ok((decomposition, mesh))
    }

    /// Number of processors.
    pub fn n_processors(&self) -> usize {
        self.processors.len()
    }

    /// The time directories of `processor0/`, ascending (time and directory name).
    pub fn times(&self) -> Result<Vec<(f64, OsString)>, FoamError> {
        time_dirs(&self.processors[0].dir)
    }

    /// Field `name` (`comps` = 1 or 3 components) of the time directory named `time` in every
    /// processor, in the global numbering.
    pub fn read_field(&self, time: &OsStr, name: &str, comps: usize) -> Result<VolField, FoamError> {
        if !matches!(comps, 1 | 3) {
            return Err(FoamError::Field {
                path: self.case.join(time).join(name).display().to_string(),
                reason: format!("{comps}-component fields are not supported"),
            });
        }
        let mut internal = vec![0.0; self.n_cells * comps];
        let mut boundary = vec![0.0; self.n_boundary_faces * comps];
        let mut fixed: Vec<Option<bool>> = vec![None; self.n_patches];
        for p in &self.processors {
            let dir = p.dir.join(time);
            let local = read_vol_field(&dir, name, &p.mesh, comps)?;
            for (c, &g) in p.cells.iter().enumerate() {
                internal[g as usize * comps..][..comps].copy_from_slice(local.cell(c));
            }
            for (b, &g) in p.boundary.iter().enumerate().filter(|(_, g)| **g != UNSET) {
                boundary[g as usize * comps..][..comps].copy_from_slice(local.boundary_face(b));
            }
            for (&is_fixed, g) in local.fixed.iter().zip(&p.patches) {
                let Some(g) = *g else { continue };
                if *fixed[g].get_or_insert(is_fixed) != is_fixed {
                    return Err(FoamError::Field {
                        path: dir.join(name).display().to_string(),
                        reason: format!(
                            "the condition of patch `{}` prescribes the value here but not in another processor, or the reverse",
                            p.mesh
                                .patches()
                                .iter()
                                .zip(&p.patches)
                                .find(|(_, q)| **q == Some(g))
                                .map_or("?", |(q, _)| &q.name)
                        ),
                    });
                }
            }
        }
        Ok(VolField {
            comps,
            internal,
            boundary,
            fixed: fixed.into_iter().map(|f| f.unwrap_or(false)).collect(),
        })
    }

    /// Whether `mesh` is the reassembled mesh face for face: the same faces (vertex labels),
    /// owners, neighbours and patches, so that fields placed by this decomposition belong to it.
    /// Points are not compared: a mesh written again at another precision is the same mesh.
    pub(crate) fn fits(reassembled: &PolyMesh, mesh: &PolyMesh) -> bool {
        reassembled.n_cells() == mesh.n_cells()
            && reassembled.n_faces() == mesh.n_faces()
            && reassembled.n_internal_faces() == mesh.n_internal_faces()
            && reassembled.points().len() == mesh.points().len()
            && reassembled.patches() == mesh.patches()
            && (0..mesh.n_faces()).all(|f| {
                reassembled.face(f) == mesh.face(f)
                    && reassembled.owner(f) == mesh.owner(f)
                    && reassembled.neighbour(f) == mesh.neighbour(f)
            })
    }
}

/// The processor directories of `case`, `processor0 … processorN−1` with none missing, each
/// with its addressing files (checked first: a processor directory without them cannot be
/// placed, whatever else it holds). No processor directory is an error that names the collated
/// format if the case is collated.
fn processor_dirs_with_addressing(case: &Path) -> Result<Vec<(u64, PathBuf)>, FoamError> {
    let dirs = processor_dirs(case);
    if dirs.is_empty() {
        let collated = std::fs::read_dir(case).ok().and_then(|entries| {
            entries.filter_map(Result::ok).find_map(|e| {
                let name = e.file_name().to_str()?.to_string();
                name.strip_prefix("processors")?
                    .starts_with(|c: char| c.is_ascii_digit())
                    .then_some(name)
            })
        });
        return Err(match collated {
            Some(name) => inconsistent(
                &case.join(name),
                "collated decomposition (`-fileHandler collated`) is not read: run `reconstructPar`, or decompose with `-fileHandler uncollated`",
            ),
            None => inconsistent(case, "no processor directories"),
        });
    }
    if let Some((k, (n, dir))) = dirs.iter().enumerate().find(|(k, (n, _))| *n != *k as u64) {
        return Err(inconsistent(
            dir,
            format!("processor{n} follows {k} processor directories: processor{k} is missing"),
        ));
    }
    for (_, dir) in &dirs {
        for name in ADDRESSING {
            let path = dir.join("constant").join("polyMesh").join(name);
            let mut gz = path.clone().into_os_string();
            gz.push(".gz");
            if !path.is_file() && !Path::new(&gz).is_file() {
                return Err(FoamError::NoProcAddressing {
                    path: path.display().to_string(),
                });
            }
        }
    }
    Ok(dirs)
}

/// The sums of the processors' local counts: the global cell count, and bounds on the global
/// faces, points and patches, checked against what a `u32` label holds before anything global
/// is allocated.
#[derive(Clone, Copy)]
struct Caps {
    cells: usize,
    faces: usize,
    points: usize,
    patches: usize,
}

impl Caps {
    /// The caps of `meshes`; an error naming `case` if the cells, faces or points overflow a
    /// `u32` label.
    fn of(case: &Path, meshes: &[PolyMesh]) -> Result<Self, FoamError> {
        let total = |f: fn(&PolyMesh) -> usize| meshes.iter().map(f).fold(0usize, usize::saturating_add);
        let caps = Self {
            cells: total(PolyMesh::n_cells),
            faces: total(PolyMesh::n_faces),
            points: total(|m| m.points().len()),
            patches: total(|m| m.patches().len()),
        };
        if caps.cells >= UNSET as usize || caps.faces >= UNSET as usize || caps.points >= UNSET as usize {
            return Err(inconsistent(
                case,
                "the processors hold more than 2³² − 1 cells, faces or points",
            ));
        }
        Ok(caps)
    }
}

/// `n` as an addressing label bound (saturated: the caps are checked against `u32` already).
fn label(n: usize) -> i64 {
    i64::try_from(n).unwrap_or(i64::MAX)
}

/// Each processor's `cellProcAddressing`: the global cell of each local cell, the lists
/// together a permutation of `0..n_cells`.
fn place_cells(dirs: &[(u64, PathBuf)], meshes: &[PolyMesh], n_cells: usize) -> Result<Vec<Vec<u32>>, FoamError> {
    let mut cell_seen = vec![false; n_cells];
    let mut cells = Vec::with_capacity(dirs.len());
    for ((_, dir), mesh) in dirs.iter().zip(meshes) {
        let list = addressing(dir, ADDRESSING[0], mesh.n_cells(), 0, label(n_cells) - 1)?;
        let mut local = Vec::with_capacity(list.len());
        for (c, &g) in list.iter().enumerate() {
            if std::mem::replace(&mut cell_seen[g as usize], true) {
                return Err(inconsistent(
                    &dir.join("constant/polyMesh").join(ADDRESSING[0]),
                    format!("cell {c} is global cell {g}, which another cell already is"),
                ));
            }
            local.push(g as u32);
        }
        cells.push(local);
    }
    Ok(cells)
}

/// Each processor's `pointProcAddressing` (the global point of each local point) and the
/// global points: every one reached, with the same coordinates (bit for bit) from every
/// processor that has it.
fn place_points(
    case: &Path,
    dirs: &[(u64, PathBuf)],
    meshes: &[PolyMesh],
    point_cap: usize,
) -> Result<(Vec<Vec<u32>>, Vec<Vec3>), FoamError> {
    let mut point_lists = Vec::with_capacity(dirs.len());
    for ((_, dir), mesh) in dirs.iter().zip(meshes) {
        let list = addressing(dir, ADDRESSING[2], mesh.points().len(), 0, label(point_cap) - 1)?;
        point_lists.push(list.into_iter().map(|g| g as u32).collect::<Vec<u32>>());
    }
    let n_points = point_lists.iter().flatten().max().map_or(0, |&m| m as usize + 1);
    let mut points = vec![Vec3::zeros(); n_points];
    let mut point_seen = vec![false; n_points];
    for (k, (list, mesh)) in point_lists.iter().zip(meshes).enumerate() {
        for (&g, x) in list.iter().zip(mesh.points()) {
            let g = g as usize;
            if std::mem::replace(&mut point_seen[g], true) {
                if points[g]
                    .iter()
                    .zip(x.iter())
                    .any(|(a, b): (&f64, &f64)| a.to_bits() != b.to_bits())
                {
                    return Err(inconsistent(
                        &dirs[k].1.join("constant/polyMesh/points"),
                        format!(
                            "global point {g} is at {:?} here and at {:?} in another processor",
                            <[f64; 3]>::from(*x),
                            <[f64; 3]>::from(points[g])
                        ),
                    ));
                }
            } else {
                points[g] = *x;
            }
        }
    }
    if let Some(g) = point_seen.iter().position(|&s| !s) {
        return Err(inconsistent(
            case,
            format!("global point {g} (of {n_points}) is in no processor's pointProcAddressing"),
        ));
    }
    Ok((point_lists, points))
}

/// Each processor's `boundaryProcAddressing` (the global patch of each local patch, `None` for
/// an inter-processor patch) and the global patches' names and types, alike in every processor
/// that has them; their starts and sizes are 0 until [`number_patches`].
fn place_patches(
    case: &Path,
    dirs: &[(u64, PathBuf)],
    meshes: &[PolyMesh],
    patch_cap: usize,
) -> Result<(Vec<PatchMap>, Vec<Patch>), FoamError> {
    let mut patch_maps = Vec::with_capacity(dirs.len());
    for ((_, dir), mesh) in dirs.iter().zip(meshes) {
        let path = dir.join("constant/polyMesh").join(ADDRESSING[3]);
        let list = addressing(dir, ADDRESSING[3], mesh.patches().len(), -1, label(patch_cap) - 1)?;
        let mut map = Vec::with_capacity(list.len());
        for (patch, &g) in mesh.patches().iter().zip(&list) {
            map.push(match (patch.kind.as_str(), g) {
                ("processor", _) => None,
                ("processorCyclic", _) => {
                    return Err(inconsistent(
                        &path,
                        format!(
                            "patch `{}` is a cyclic patch split between processors (processorCyclic), which is not read: run `reconstructPar`",
                            patch.name
                        ),
                    ));
                }
                (_, -1) => {
                    return Err(inconsistent(
                        &path,
                        format!("patch `{}` of type `{}` has no global patch", patch.name, patch.kind),
                    ));
                }
                (_, g) => Some(g as usize),
            });
        }
        patch_maps.push(map);
    }
    let n_patches = patch_maps.iter().flatten().flatten().max().map_or(0, |&m| m + 1);
    let mut global_patches: Vec<Option<Patch>> = vec![None; n_patches];
    for (k, (map, mesh)) in patch_maps.iter().zip(meshes).enumerate() {
        for (patch, g) in mesh.patches().iter().zip(map) {
            let Some(g) = *g else { continue };
            match &global_patches[g] {
                None => {
                    global_patches[g] = Some(Patch {
                        name: patch.name.clone(),
                        kind: patch.kind.clone(),
                        start: 0,
                        size: 0,
                        coupling: patch.coupling.clone(),
                    });
                }
                Some(p) if p.name != patch.name || p.kind != patch.kind => {
                    return Err(inconsistent(
                        &dirs[k].1.join("constant/polyMesh/boundary"),
                        format!(
                            "global patch {g} is `{}` ({}) here and `{}` ({}) in another processor",
                            patch.name, patch.kind, p.name, p.kind
                        ),
                    ));
                }
                Some(_) => {}
            }
        }
    }
    if let Some(g) = global_patches.iter().position(Option::is_none) {
        return Err(inconsistent(
            case,
            format!("global patch {g} (of {n_patches}) is in no processor's boundaryProcAddressing"),
        ));
    }
    Ok((patch_maps, global_patches.into_iter().flatten().collect()))
}

/// Each processor's `faceProcAddressing`: per local face its global face, 1-based and signed
/// (negative: reversed), never 0.
fn face_addressing(dirs: &[(u64, PathBuf)], meshes: &[PolyMesh], face_cap: usize) -> Result<Vec<Vec<i64>>, FoamError> {
    let mut face_lists = Vec::with_capacity(dirs.len());
    for ((_, dir), mesh) in dirs.iter().zip(meshes) {
        let cap = label(face_cap);
        let list = addressing(dir, ADDRESSING[1], mesh.n_faces(), -cap, cap)?;
        if let Some(f) = list.iter().position(|&a| a == 0) {
            return Err(inconsistent(
                &dir.join("constant/polyMesh").join(ADDRESSING[1]),
                format!("entry {f} is 0 (the labels are 1-based and signed)"),
            ));
        }
        face_lists.push(list);
    }
    Ok(face_lists)
}

/// The global faces as the processors place them: per global face its owner and neighbour
/// cells, its patch (`UNSET` where unset) and the processor face it was first seen as.
struct Faces {
    owner: Vec<u32>,
    neighbour: Vec<u32>,
    patch_of: Vec<u32>,
    source: Vec<Option<Source>>,
}

/// Place every processor face on its global face (`face_lists`): a face reversed there is
/// seen from its neighbour cell; an internal face is placed twice, once from each side; a real
/// patch's face once and never reversed. Every later sighting of a global face must have the
/// vertices of its first.
fn place_faces(
    dirs: &[(u64, PathBuf)],
    meshes: &[PolyMesh],
    cells: &[Vec<u32>],
    point_lists: &[Vec<u32>],
    patch_maps: &[PatchMap],
    face_lists: &[Vec<i64>],
) -> Result<Faces, FoamError> {
    let n_faces = face_lists
        .iter()
        .flatten()
        .map(|a| a.unsigned_abs() as usize)
        .max()
        .unwrap_or(0);
    let mut owner = vec![UNSET; n_faces];
    let mut neighbour = vec![UNSET; n_faces];
    let mut patch_of = vec![UNSET; n_faces];
    let mut source: Vec<Option<Source>> = vec![None; n_faces];
    let (mut here, mut there) = (Vec::new(), Vec::new());
    for (k, (list, mesh)) in face_lists.iter().zip(meshes).enumerate() {
        let file = dirs[k].1.join("constant/polyMesh").join(ADDRESSING[1]);
        let cell = |c: usize| cells[k][c];
        let mut local_patch = 0;
        for (f, &a) in list.iter().enumerate() {
            let (g, reversed) = (a.unsigned_abs() as usize - 1, a < 0);
            let bad = |reason: String| inconsistent(&file, format!("face {f} (global face {g}): {reason}"));
            let (own, nbr) = match mesh.neighbour(f) {
                Some(n) if reversed => (Some(cell(n)), Some(cell(mesh.owner(f)))),
                Some(n) => (Some(cell(mesh.owner(f))), Some(cell(n))),
                None => {
                    // Faces are in patch order; empty patches have no faces (and any start).
                    let patches = mesh.patches();
                    while patches
                        .get(local_patch)
                        .is_some_and(|p| p.size == 0 || p.start + p.size <= f)
                    {
                        local_patch += 1;
                    }
                    match patch_maps[k].get(local_patch).copied().flatten() {
                        None if reversed => (None, Some(cell(mesh.owner(f)))),
                        None => (Some(cell(mesh.owner(f))), None),
                        Some(_) if reversed => return Err(bad("a patch face listed reversed".into())),
                        Some(p) => {
                            if std::mem::replace(&mut patch_of[g], p as u32) != UNSET {
                                return Err(bad("a patch face listed by two processors".into()));
                            }
                            (Some(cell(mesh.owner(f))), None)
                        }
                    }
                }
            };
            if own.is_some_and(|c| std::mem::replace(&mut owner[g], c) != UNSET) {
                return Err(bad("its owner side is listed twice".into()));
            }
            if nbr.is_some_and(|c| std::mem::replace(&mut neighbour[g], c) != UNSET) {
                return Err(bad("its neighbour side is listed twice".into()));
            }
            let this = Source {
                processor: k as u32,
                face: f as u32,
                reversed,
            };
            match source[g] {
                None => source[g] = Some(this),
                Some(first) => {
                    global_face(meshes, point_lists, first, &mut here);
                    global_face(meshes, point_lists, this, &mut there);
                    if here != there {
                        return Err(bad(format!(
                            "its vertices are {there:?} here and {here:?} in processor{}",
                            first.processor
                        )));
                    }
                }
            }
        }
    }
    Ok(Faces {
        owner,
        neighbour,
        patch_of,
        source,
    })
}

impl Faces {
    /// The number of internal faces, once the placed faces are checked to be a mesh's: every
    /// global face has an owner; internal faces come first, then the patch faces, each patch
    /// contiguous and in the order of the global patch labels. An error names `case` and the
    /// first face that is not.
    fn check(&self, case: &Path) -> Result<usize, FoamError> {
        let Self {
            owner,
            neighbour,
            patch_of,
            ..
        } = self;
        let n_faces = owner.len();
        let n_internal = neighbour.iter().take_while(|&&n| n != UNSET).count();
        for g in 0..n_faces {
            let reason = if owner[g] == UNSET {
                "in no processor, or only reversed"
            } else if g < n_internal && patch_of[g] != UNSET {
                "both internal and on a patch"
            } else if g >= n_internal && neighbour[g] != UNSET {
                "internal but after the first boundary face"
            } else if g >= n_internal && patch_of[g] == UNSET {
                "on an inter-processor patch but listed by one processor only"
            } else if g > n_internal && patch_of[g] < patch_of[g - 1] {
                "on a patch that comes before the previous face's"
            } else {
                continue;
            };
            return Err(inconsistent(
                case,
                format!("global face {g} (of {n_faces}) is {reason}"),
            ));
        }
        Ok(n_internal)
    }
}

/// The global patches numbered: each starts where the previous one ends (the first after the
/// `n_internal` internal faces) and holds the faces `patch_of` gives it, so a patch that no
/// processor's faces reach is empty.
fn number_patches(global_patches: Vec<Patch>, patch_of: &[u32], n_internal: usize) -> Vec<Patch> {
    let mut patches = Vec::with_capacity(global_patches.len());
    let mut start = n_internal;
    for (g, patch) in global_patches.into_iter().enumerate() {
        let size = patch_of[start..].iter().take_while(|&&p| p as usize == g).count();
        patches.push(Patch { start, size, ..patch });
        start += size;
    }
    patches
}

/// The global faces' vertices in global point labels and the global order, from the
/// processor face each was first seen as: the offsets and the concatenated vertex lists of
/// [`PolyMesh::new`].
fn face_vertices(
    case: &Path,
    meshes: &[PolyMesh],
    point_lists: &[Vec<u32>],
    source: &[Option<Source>],
) -> Result<(Vec<u32>, Vec<u32>), FoamError> {
    let mut face_offsets = Vec::with_capacity(source.len() + 1);
    face_offsets.push(0u32);
    let mut face_points = Vec::new();
    let mut here = Vec::new();
    for s in source.iter().flatten() {
        global_face(meshes, point_lists, *s, &mut here);
        face_points.extend_from_slice(&here);
        let end =
            u32::try_from(face_points.len()).map_err(|_| inconsistent(case, "more than 2³² − 1 face vertices"))?;
        face_offsets.push(end);
    }
    Ok((face_offsets, face_points))
}

/// A processor's [`Processor::boundary`]: per local boundary face its global boundary face
/// (its global face `faces` gives, less the `n_internal` internal faces), or `UNSET` on an
/// inter-processor patch (`patches` maps local patches to global ones).
fn boundary_addressing(local: &PolyMesh, faces: &[i64], patches: &[Option<usize>], n_internal: usize) -> Vec<u32> {
    faces[local.n_internal_faces()..]
        .iter()
        .enumerate()
        .map(|(b, &a)| {
            let f = b + local.n_internal_faces();
            match local.patch_of(f).and_then(|p| patches[p]) {
                Some(_) => a as u32 - 1 - n_internal as u32,
                None => UNSET,
            }
        })
        .collect()
}

/// The vertices of a processor's face in global point labels and the global face's order
/// (a reversed face turned back: the first vertex kept, the others reversed).
fn global_face(meshes: &[PolyMesh], point_lists: &[Vec<u32>], s: Source, out: &mut Vec<u32>) {
    let (k, f) = (s.processor as usize, s.face as usize);
    out.clear();
    out.extend(meshes[k].face(f).iter().map(|&v| point_lists[k][v as usize]));
    if s.reversed {
        out[1..].reverse();
    }
}

//! OpenFOAM cases as flow fields: the `polyMesh` and the velocity of one or more time
//! directories, on any polyhedral mesh (blockMesh, snappyHexMesh, gmshToFoam, ...).
//!
//! # Data flow
//! [`FoamCase::open`] reads `constant/polyMesh` ([`mesh`], files ASCII or binary, plain or
//! gzipped, parsed by [`parse`]) and lists the time directories. [`FoamFlow`] reads `U` in the
//! chosen times ([`field`]: cell values and the values on every boundary face from the patch
//! conditions), fits a cellwise-linear reconstruction u(x) = u_c + G_c (x − x_c) that is exact
//! for linear fields on every cell ([`reconstruct`], where the choice is argued), and answers
//! queries by locating the cell ([`locate`]: tetrahedral decomposition, neighbour walk from the
//! previous cell, R*-tree fallback) and evaluating the fit. Between time directories u and ∇u
//! are linear in time; a steady case is one directory. Patches become particle boundaries in
//! [`patch`]. A time level's data (u, ∇u, wall fits; f64 or f32) is a [`frame`]; a transient
//! case too large to hold every level is read lazily, one window of levels at a time, and
//! optionally cycled with a period ([`transient`]).
//!
//! # Decomposed cases
//! A case decomposed by `decomposePar` is read without `reconstructPar` ([`decomposed`]): the
//! `processorN/` meshes and fields are reassembled through the decomposition's addressing into
//! the undecomposed mesh and fields, bit for bit. Where both exist the reconstructed data are
//! read ([`Layout::Auto`], what [`FoamCase::open`] does): the top-level mesh if there is one,
//! each time from the top level if it is there, else from the processors (whose mesh must then
//! be the top level's); [`FoamCase::open_with`] can ask for either side only. Processor
//! directories without the addressing (a mesh made in parallel) are a
//! [`FoamError::NoProcAddressing`] naming `reconstructParMesh`.
//!
//! # Accuracy
//! For a smooth field the reconstruction error is O(h²) in u and O(h) in ∇u, including the
//! cells at walls (checked on three snappyHexMesh refinements in the tests: observed orders
//! 2.05 and 1.06 over the whole mesh, 2.03 and 1.00 in the snapped, layered cells at a curved
//! wall), on top of the discretisation error of the CFD solution itself.
//!
//! # Outside the mesh, outside the time range
//! [`FoamFlow::locate`] reports a point outside the mesh as [`FoamError::Outside`] with the
//! nearest patch. Through [`FlowField`] a point just beyond a boundary face (over the face, and
//! beyond its plane by no more than its owner cell's centre lies inside) is answered by that
//! cell's fit, extrapolated as the blend extrapolates its supports ([`blend`], *Just outside
//! the mesh*): a point particle reaches an exit's or a wall's plane, where its contact fires,
//! only by a step that ends on or past it, and with the field refused there its steps shrank
//! towards the plane until they underflowed (OpenFOAM's pitzDaily, contact radius 0: 197 of
//! 200 tracers failed 5·10⁻¹² m before the outlet). Farther out the point is a
//! [`FlowError::OutsideMesh`] naming the nearest patch. Before the first
//! and after the last time level the field holds that level; a [`TransientFlow`] refuses a time
//! outside its window ([`FlowError::OutsideTimeWindow`]).
//!
//! # The cube cavity
//! The shipped cavity fields of paper §6.3 are simpleFoam's `U` alone; [`block::cavity_block`]
//! rebuilds their uniform blockMesh cube in blockMesh's order, and
//! `studies::cavity_benchmark::ShippedField` reads a field onto it.

pub mod blend;
pub mod block;
pub mod decomposed;
pub mod error;
pub mod field;
pub mod frame;
pub mod grid;
pub mod hermite;
pub mod images;
pub mod locate;
mod memo;
pub mod mesh;
pub mod octree;
pub mod parse;
pub mod patch;
pub mod reconstruct;
pub mod transient;
pub mod wall_layer;
pub mod walls;

pub use blend::BlendedFlow;
pub use block::cavity_block;
pub use decomposed::{Decomposition, Layout};
pub use error::FoamError;
pub use field::{VolField, read_vol_field};
pub use frame::Precision;
pub use locate::CellLocator;
pub use mesh::{Patch, PolyMesh};
pub use octree::OctreeFlow;
pub use patch::{PARTICLE_PATCH_TYPES, PatchRole, PatchSet, SetFace, check_particle_patches, slab_axis};
pub use reconstruct::Stencils;
pub use transient::{Cycle, TransientFlow, Windowed, window_ends};
pub use wall_layer::{WallFit, WallGeometry};

use super::{Crossing, FlowField, FlowSample, check_query};
use crate::error::FlowError;
use crate::tensor::{Mat3, Vec3};
use decomposed::{processor_dirs, time_dirs};
use frame::{Frame, Geometry};
use images::PatchImages;
use std::cell::Cell;
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::OnceLock;

/// Relative tolerance when matching a requested time to a time directory's name.
const TIME_MATCH: f64 = 1e-9;

/// An OpenFOAM case: its mesh and time directories, undecomposed or decomposed
/// ([`decomposed`]: the `processorN/` directories read directly, where [`Layout`] says).
#[derive(Debug, Clone)]
pub struct FoamCase {
    dir: PathBuf,
    mesh: PolyMesh,
    layout: Layout,
    /// Whether the mesh was reassembled from the processor directories.
    decomposed: bool,
    times: Vec<TimeDir>,
    /// The processors, read when the mesh is or when a time only they have is first read.
    decomposition: OnceLock<Decomposition>,
}

/// One time directory: at the top level (`top`), or only in the processors (`None`), under
/// the directory name `name`.
#[derive(Debug, Clone)]
struct TimeDir {
    time: f64,
    top: Option<PathBuf>,
    name: OsString,
}

impl FoamCase {
    /// Read the mesh of the case in `dir` and list its time directories: the reconstructed
    /// data where present, else the processor directories' ([`Layout::Auto`]).
    pub fn open(dir: impl AsRef<Path>) -> Result<Self, FoamError> {
        Self::open_with(dir, Layout::Auto)
    }

    /// Read the mesh of the case in `dir` and list its time directories, from the top level,
    /// the processor directories or both as `layout` says.
    pub fn open_with(dir: impl AsRef<Path>, layout: Layout) -> Result<Self, FoamError> {
        let dir = dir.as_ref().to_path_buf();
        let poly = dir.join("constant").join("polyMesh");
        let has_faces = poly.join("faces").is_file() || poly.join("faces.gz").is_file();
        let processors = processor_dirs(&dir).len();
        let from_processors = match layout {
            Layout::Decomposed => true,
            Layout::Auto => !has_faces && processors > 0,
            Layout::Reconstructed if !has_faces && processors > 0 => {
                return Err(FoamError::Decomposed {
                    case: dir.display().to_string(),
                    processors,
                    what: "constant/polyMesh".into(),
                });
            }
            Layout::Reconstructed => false,
        };
        let decomposition = OnceLock::new();
        let mesh = if from_processors {
            let (d, mesh) = Decomposition::read(&dir)?;
            let _ = decomposition.set(d);
            mesh
        } else {
            PolyMesh::read(&dir)?
        };
        let top = |times: Vec<(f64, OsString)>| -> Vec<TimeDir> {
            times
                .into_iter()
                .map(|(time, name)| TimeDir {
                    time,
                    top: Some(dir.join(&name)),
                    name,
                })
                .collect()
        };
        let in_processors =
            |times: Vec<(f64, OsString)>| times.into_iter().map(|(time, name)| TimeDir { time, top: None, name });
        let mut times = match layout {
            Layout::Reconstructed => top(time_dirs(&dir)?),
            Layout::Decomposed => in_processors(time_dirs(&dir.join("processor0"))?).collect(),
            Layout::Auto => {
                let mut times = top(time_dirs(&dir)?);
                if processors > 0 {
                    let more: Vec<TimeDir> = in_processors(time_dirs(&dir.join("processor0"))?)
                        .filter(|p| !times.iter().any(|t| same_time(t.time, p.time)))
                        .collect();
                    times.extend(more);
                }
                times
            }
        };
        times.sort_by(|a, b| a.time.total_cmp(&b.time));
        Ok(Self {
            dir,
            mesh,
            layout,
            decomposed: from_processors,
            times,
            decomposition,
        })
    }

    /// The mesh.
    pub fn mesh(&self) -> &PolyMesh {
        &self.mesh
    }

    /// Whether the mesh was reassembled from the processor directories ([`decomposed`]).
    pub fn is_decomposed(&self) -> bool {
        self.decomposed
    }

    /// Times of the time directories, ascending.
    pub fn times(&self) -> Vec<f64> {
        self.times.iter().map(|t| t.time).collect()
    }

    fn find_time(&self, t: f64) -> Result<&TimeDir, FoamError> {
        match self.times.iter().find(|d| same_time(d.time, t)) {
            Some(d) => Ok(d),
            None => {
                // Only a case read as serial leaves the processors' times unlisted.
                let processors = processor_dirs(&self.dir).len();
                if self.layout == Layout::Reconstructed && processors > 0 {
                    return Err(FoamError::Decomposed {
                        case: self.dir.display().to_string(),
                        processors,
                        what: format!("time directory {t}"),
                    });
                }
                Err(FoamError::NoSuchTime {
                    case: self.dir.display().to_string(),
                    time: t,
                    available: self.times(),
                })
            }
        }
    }

    /// The top-level directory of time `t` (matched to a relative 1e-9). A time that only the
    /// processor directories have is a [`FoamError::Decomposed`] error: read its fields with
    /// [`FoamCase::read_field`].
    pub fn time_dir(&self, t: f64) -> Result<&Path, FoamError> {
        let d = self.find_time(t)?;
        d.top.as_deref().ok_or_else(|| FoamError::Decomposed {
            case: self.dir.display().to_string(),
            processors: processor_dirs(&self.dir).len(),
            what: format!("time directory {t} at the top level (FoamCase::read_field reads it from the processors)"),
        })
    }

    /// The processors of the case, read on first use; their mesh must be this case's.
    fn decomposition(&self) -> Result<&Decomposition, FoamError> {
        if let Some(d) = self.decomposition.get() {
            return Ok(d);
        }
        let (d, mesh) = Decomposition::read(&self.dir)?;
        if !Decomposition::fits(&mesh, &self.mesh) {
            return Err(FoamError::Decomposition {
                path: self.dir.display().to_string(),
                reason: "the processors' mesh is not constant/polyMesh (a stale decomposition?): run `decomposePar -force`, or `reconstructPar`".into(),
            });
        }
        Ok(self.decomposition.get_or_init(|| d))
    }

    /// The face flux `phi` on the boundary faces at time `t` ([`field::read_boundary_flux`]):
    /// `None` where the time directory has none, or the case is decomposed (the processors'
    /// fluxes are not reassembled).
    pub fn read_boundary_flux(&self, t: f64) -> Result<Option<Vec<f64>>, FoamError> {
        match &self.find_time(t)?.top {
            Some(dir) => field::read_boundary_flux(dir, &self.mesh),
            None => Ok(None),
        }
    }

    /// Read field `name` (`comps` = 1 or 3 components) at time `t`: from the top-level time
    /// directory, or reassembled from the processors' ([`decomposed`]).
    pub fn read_field(&self, t: f64, name: &str, comps: usize) -> Result<VolField, FoamError> {
        let d = self.find_time(t)?;
        match &d.top {
            Some(dir) => read_vol_field(dir, name, &self.mesh, comps),
            None => self.decomposition()?.read_field(&d.name, name, comps),
        }
    }
}

/// The no-slip wall faces: those of every `wall`-type patch p with `fixed[p]` (its velocity
/// prescribed in every time level).
fn no_slip_walls(mesh: &PolyMesh, fixed: &[bool]) -> Vec<u32> {
    (0..mesh.patches().len())
        .filter(|&p| PatchRole::of(&mesh.patches()[p].kind) == PatchRole::Wall && fixed[p])
        .flat_map(|p| {
            let patch = &mesh.patches()[p];
            (patch.start..patch.start + patch.size).map(|f| f as u32)
        })
        .collect()
}

/// The start of a fingerprint's hash of `levels` time levels.
fn level_hash(levels: usize) -> Fnv {
    let mut h = Fnv::new(b"pseudorigid FoamFlow v1");
    h.u64(levels as u64);
    h
}

/// Hash one level: its time and cell velocities (the f64 values as read).
fn hash_level(h: &mut Fnv, time: f64, cells: usize, u: impl Iterator<Item = f64>) {
    h.u64(time.to_bits());
    h.u64(cells as u64);
    h.f64s(u);
}

/// A fingerprint from its levels' hash `h` ([`FoamFlow::fingerprint`]).
fn describe(mesh: &PolyMesh, levels: usize, walls: &[u32], mut h: Fnv) -> String {
    h.u64(walls.len() as u64);
    walls.iter().for_each(|&w| h.u64(u64::from(w)));
    format!(
        "openfoam field: {} cells, {} time levels, mesh {}, U {}",
        mesh.n_cells(),
        levels,
        mesh.content_hash(),
        h.hex()
    )
}

/// Whether two times name the same time directory (a relative 1e-9).
fn same_time(a: f64, b: f64) -> bool {
    (a - b).abs() <= TIME_MATCH * a.abs().max(b.abs()).max(1.0)
}

/// A velocity field on a polyhedral mesh, steady or linear in time between time levels.
#[derive(Debug, Clone)]
pub struct FoamFlow {
    mesh: PolyMesh,
    /// The patches particles pass through ([`images`]).
    images: Option<Arc<PatchImages>>,
    locator: CellLocator,
    boundary: PatchSet,
    /// Faces of the no-slip walls: `wall`-type patches whose condition prescribes the velocity
    /// in every time level ([`VolField::fixed`]).
    walls: Vec<u32>,
    wall_layer: WallGeometry,
    /// The levels held: every level of the field, or a [`transient`] window's.
    frames: Vec<Frame>,
    /// The times at which the levels held answer: every time for a field that holds all its
    /// levels, the held levels' span for a window ([`FoamFlow::check_time`]).
    span: (f64, f64),
    /// Volume mean of √(2 D:D) over the cells of the first time level.
    strain_rate: f64,
}

thread_local! {
    /// The cell of this thread's previous query: the hint for the next one (a particle's
    /// successive queries come from one thread). Any value is safe; a wrong one costs a search.
    static LAST_CELL: Cell<usize> = const { Cell::new(usize::MAX) };
}

/// FNV-1a (64 bit) over a fixed byte layout: the content hashes of meshes and fields (stable
/// across Rust releases and platforms, unlike `std`'s `DefaultHasher`; no dependency, as the
/// `fnv` crate is not part of the feature `mesh`). It guards against mistakes, not forgery.
pub(crate) struct Fnv(u64);

impl Fnv {
    pub(crate) fn new(tag: &[u8]) -> Self {
        let mut h = Self(0xcbf2_9ce4_8422_2325);
        h.bytes(tag);
        h
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    }
    /// A length-prefixed byte string.
    pub(crate) fn bytes(&mut self, bytes: &[u8]) {
        self.u64(bytes.len() as u64);
        self.write(bytes);
    }
    pub(crate) fn u64(&mut self, v: u64) {
        self.write(&v.to_le_bytes());
    }
    pub(crate) fn f64s(&mut self, values: impl Iterator<Item = f64>) {
        values.for_each(|v| self.u64(v.to_bits()));
    }
    pub(crate) fn hex(&self) -> String {
        format!("{:016x}", self.0)
    }
}

impl FoamFlow {
    /// What identifies this field for a run's configuration hash
    /// ([`crate::population::Case::config_hash`]): the mesh's [`PolyMesh::content_hash`], and
    /// a hash of every time level's time and velocity values (the f64 bits as read) and of the
    /// no-slip wall faces (from the boundary conditions of `U`). Gradients, wall fits and the
    /// locator are computed from these by the code, whose version the configuration hash holds
    /// too. By content, not by path or file times: a copy of the case elsewhere (another node
    /// of a sharded run) gives the same fingerprint, and a field solved again gives another.
    pub fn fingerprint(&self) -> String {
        let mut h = level_hash(self.frames.len());
        for f in &self.frames {
            hash_level(
                &mut h,
                f.time,
                f.n_cells(),
                (0..f.n_cells()).flat_map(|c| <[f64; 3]>::from(f.u(c))),
            );
        }
        describe(&self.mesh, self.frames.len(), &self.walls, h)
    }

    /// Velocity `U` of `case` at the given times (one time: steady).
    pub fn read(case: &FoamCase, times: &[f64]) -> Result<Self, FoamError> {
        let fields = times
            .iter()
            .map(|&t| Ok((t, case.read_field(t, "U", 3)?)))
            .collect::<Result<Vec<_>, FoamError>>()?;
        Self::new(case.mesh.clone(), fields)
    }

    /// Field from a mesh and velocity fields at distinct times (any order).
    pub fn new(mesh: PolyMesh, mut fields: Vec<(f64, VolField)>) -> Result<Self, FoamError> {
        if fields.is_empty() {
            return Err(FoamError::Field {
                path: "(velocity)".into(),
                reason: "no time levels".into(),
            });
        }
        fields.sort_by(|a, b| a.0.total_cmp(&b.0));
        if let Some(w) = fields
            .windows(2)
            .find(|w| w[1].0.partial_cmp(&w[0].0) != Some(std::cmp::Ordering::Greater))
        {
            return Err(FoamError::Field {
                path: "(velocity)".into(),
                reason: format!("time levels must be distinct and finite, got {} and {}", w[0].0, w[1].0),
            });
        }
        for (time, field) in &fields {
            frame::check_shape(&mesh, *time, field)?;
        }
        let fixed: Vec<bool> = (0..mesh.patches().len())
            .map(|p| fields.iter().all(|(_, f)| f.fixed[p]))
            .collect();
        let walls = no_slip_walls(&mesh, &fixed);
        let stencils = Stencils::new(&mesh)?;
        let wall_layer = WallGeometry::new(&mesh, &walls);
        let geometry = Geometry {
            mesh: &mesh,
            stencils: &stencils,
            walls: &walls,
            wall_layer: &wall_layer,
        };
        let frames = fields
            .iter()
            .map(|(time, field)| Frame::compute(&geometry, *time, field, Precision::F64))
            .collect::<Result<Vec<_>, _>>()?;
        let strain_rate = frames[0].strain_rate(&mesh);
        Self::assemble(mesh, walls, wall_layer, frames, strain_rate)
    }

    /// The field of `frames` (ascending, at least one) on `mesh`, answering at every time;
    /// an error where the mesh's cyclic or wedge pairs do not fit ([`images::pair_maps`]).
    fn assemble(
        mesh: PolyMesh,
        walls: Vec<u32>,
        wall_layer: WallGeometry,
        frames: Vec<Frame>,
        strain_rate: f64,
    ) -> Result<Self, FoamError> {
        Ok(Self {
            images: PatchImages::new(&mesh)?.map(Arc::new),
            locator: CellLocator::new(&mesh),
            boundary: PatchSet::all(&mesh),
            mesh,
            walls,
            wall_layer,
            frames,
            span: (f64::NEG_INFINITY, f64::INFINITY),
            strain_rate,
        })
    }

    /// The patches particles pass through, with their maps ([`images`]); `None` where the
    /// mesh has none.
    pub fn images(&self) -> Option<&PatchImages> {
        self.images.as_deref()
    }

    /// Whether x lies outside the mesh.
    pub(crate) fn outside(&self, x: &Vec3) -> bool {
        self.locate(x, Some(LAST_CELL.with(Cell::get))).is_err()
    }

    /// The cellwise sample at x inside the mesh, or just outside it (module docs, *Outside
    /// the mesh*).
    fn sample_inside(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        let hint = LAST_CELL.with(Cell::get);
        let cell = match self.locate(x, Some(hint)) {
            Ok(cell) => cell,
            Err(e) => self.just_outside(x).ok_or_else(|| match e {
                FoamError::Outside { x, patch, distance } => FlowError::OutsideMesh { x, patch, distance },
                _ => FlowError::outside(x),
            })?,
        };
        LAST_CELL.with(|c| c.set(cell));
        Ok(self.sample_cell(cell, x, t))
    }

    /// The owner cell of the boundary face nearest to x if x lies just beyond that face: over
    /// the face (within its vertices' radius of its centre, along its plane) and beyond its
    /// plane by no more than the owner cell's centre lies inside it.
    fn just_outside(&self, x: &Vec3) -> Option<usize> {
        let (face, _, _) = self.boundary.nearest_face(x)?;
        let mesh = &self.mesh;
        let (centre, area) = (mesh.face_centres()[face], mesh.face_areas()[face]);
        let n = area.try_normalize(0.0)?;
        let cell = mesh.owner(face);
        let (beyond, depth) = (n.dot(&(x - centre)), n.dot(&(centre - mesh.cell_centres()[cell])));
        let along = (x - centre) - n * beyond;
        let radius = (mesh.face(face).iter())
            .map(|&v| (mesh.points()[v as usize] - centre).norm())
            .fold(0.0, f64::max);
        (beyond <= depth && along.norm() <= radius).then_some(cell)
    }

    /// Hold `frames` (ascending, at least one) instead of the present levels, answering at
    /// the times of `span` ([`transient`]'s window).
    pub(crate) fn hold(&mut self, frames: Vec<Frame>, span: (f64, f64)) {
        debug_assert!(!frames.is_empty());
        self.frames = frames;
        self.span = span;
    }

    /// Refuse a time the levels held cannot answer: outside a [`transient`] window's span
    /// (a field that holds all its levels answers at every time).
    pub fn check_time(&self, t: f64) -> Result<(), FlowError> {
        let (start, end) = self.span;
        if t < start || t > end {
            return Err(FlowError::OutsideTimeWindow { t, start, end });
        }
        Ok(())
    }

    /// The mesh.
    pub fn mesh(&self) -> &PolyMesh {
        &self.mesh
    }

    /// Times of the levels, ascending.
    pub fn times(&self) -> Vec<f64> {
        self.frames.iter().map(|f| f.time).collect()
    }

    /// Whether the velocity is zero in every cell at every level (an unsolved initial
    /// condition, as `0/U` usually is).
    pub fn is_zero(&self) -> bool {
        self.frames
            .iter()
            .all(|f| (0..f.n_cells()).all(|c| f.u(c) == Vec3::zeros()))
    }

    /// The cell containing `x` (walking from `hint` when given), or
    /// [`FoamError::Outside`] with the nearest patch.
    pub fn locate(&self, x: &Vec3, hint: Option<usize>) -> Result<usize, FoamError> {
        self.locator.locate(&self.mesh, x, hint).ok_or_else(|| {
            let (patch, distance) = self
                .boundary
                .nearest_face(x)
                .map_or((String::new(), f64::INFINITY), |(_, p, d)| {
                    (self.mesh.patches()[p].name.clone(), d)
                });
            FoamError::Outside {
                x: [x[0], x[1], x[2]],
                patch,
                distance,
            }
        })
    }

    /// u and ∇u of cell `cell`'s reconstruction at x and time t. Times before the first level
    /// or after the last hold that level (a steady case has one).
    pub fn sample_cell(&self, cell: usize, x: &Vec3, t: f64) -> FlowSample {
        self.in_time(t, |f: &Frame| {
            let g = f.grad(cell);
            (f.u(cell) + g * (x - self.mesh.cell_centres()[cell]), g)
        })
    }

    /// Faces of the no-slip walls: the faces of every `wall`-type patch whose velocity
    /// condition prescribes the value ([`field::FIXED_CONDITIONS`]) in every time level.
    pub fn walls(&self) -> &[u32] {
        &self.walls
    }

    /// The wall layer's geometry ([`wall_layer`]).
    pub fn wall_layer(&self) -> &WallGeometry {
        &self.wall_layer
    }

    /// The no-slip wall patches whose prescribed velocity strains along a curved wall, at any
    /// held level: where the wall layer is not exact for a linear field ([`wall_layer`], *What
    /// is exact*), in the patches' order.
    pub fn strained_walls(&self) -> Vec<wall_layer::StrainedWall> {
        let mut found: Vec<wall_layer::StrainedWall> = Vec::new();
        for patch in self.mesh.patches() {
            let faces = patch.start..patch.start + patch.size;
            let (from, to) = (
                self.walls.partition_point(|&f| (f as usize) < faces.start),
                self.walls.partition_point(|&f| (f as usize) < faces.end),
            );
            let mut wall = wall_layer::StrainedWall {
                patch: patch.name.clone(),
                faces: 0,
                of: to - from,
                strain: 0.0,
                curvature: 0.0,
            };
            for k in from..to {
                let mut strained = false;
                for frame in &self.frames {
                    if let Some((strain, curvature)) = self.wall_layer.strain_on_curvature(k, &frame.wall_fits[k]) {
                        strained = true;
                        wall.strain = wall.strain.max(strain);
                        wall.curvature = wall.curvature.max(curvature);
                    }
                }
                wall.faces += usize::from(strained);
            }
            if wall.faces > 0 {
                found.push(wall);
            }
        }
        found
    }

    /// The fit of wall face k of [`FoamFlow::walls`] at x and time t: the near-wall expansion
    /// to second order, with the wall-normal velocity continuity demands ([`wall_layer`]).
    pub fn sample_wall(&self, k: usize, x: &Vec3, t: f64) -> FlowSample {
        self.in_time(t, |f: &Frame| self.wall_layer.evaluate(k, &f.wall_fits[k], x))
    }

    /// `at` of the levels around t, linear in time between them, and ∂u/∂t of that
    /// interpolant: the levels' difference over their interval, zero before the first level and
    /// after the last (where the field is held).
    fn in_time(&self, t: f64, at: impl Fn(&Frame) -> (Vec3, Mat3)) -> FlowSample {
        let k = self.frames.partition_point(|f| f.time <= t);
        if k == 0 || k == self.frames.len() {
            let (u, grad_u) = at(&self.frames[k.saturating_sub(1)]);
            return FlowSample::steady(u, grad_u);
        }
        let (a, b) = (&self.frames[k - 1], &self.frames[k]);
        let s = (t - a.time) / (b.time - a.time);
        let ((ua, ga), (ub, gb)) = (at(a), at(b));
        FlowSample::new(
            ua * (1.0 - s) + ub * s,
            ga * (1.0 - s) + gb * s,
            (ub - ua) / (b.time - a.time),
        )
    }

    /// Locate x (from `hint`) and sample there: the sample and the cell.
    pub fn sample_from(&self, x: &Vec3, t: f64, hint: Option<usize>) -> Result<(FlowSample, usize), FoamError> {
        let cell = self.locate(x, hint)?;
        Ok((self.sample_cell(cell, x, t), cell))
    }
}

impl FlowField for FoamFlow {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        check_query(x, t)?;
        self.check_time(t)?;
        match self.images() {
            Some(images) => images.sample(x, |y| self.sample_inside(y, t), |y| self.outside(y)),
            None => self.sample_inside(x, t),
        }
    }

    fn image(&self, x: &Vec3, _t: f64) -> Option<Crossing> {
        self.images()?.image(x, |y| self.outside(y))
    }

    /// The volume mean of the cells' √(2 D:D) at the first time level.
    fn strain_rate(&self) -> Option<f64> {
        Some(self.strain_rate).filter(|r| r.is_finite())
    }
}

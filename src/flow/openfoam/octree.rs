//! The blended field tabulated for tracking: trilinear or tricubic Hermite cells of an octree,
//! the blend itself only next to the no-slip walls.
//!
//! # Why
//! A sample of [`BlendedFlow`] visits every cell support that holds the point and every wall
//! face within its support: about 4 800 instructions on the airway bifurcation, of which the
//! scan of the supports is 3 500, three of them per integrator step. The blend is a fixed
//! function of x for a steady case, so it is tabulated once: a sample then descends an octree
//! (three comparisons per level) and interpolates one leaf.
//!
//! # Interpolant
//! Space is cut into cubes of edge $E_0$ (the largest cell support, [`BlendedFlow::radius`]),
//! each the root of an octree. A leaf of edge $E$ with corners $x_k$ carries at each corner the
//! blend's $u_k$, $(\nabla u)_k$ and $((u\cdot\nabla)u)_k$, and inside it
//! ```math
//! u(x) = \sum_{k=1}^{8} N_k(\xi)\,u_k, \qquad N_k(\xi) = \prod_{a=1}^{3} \big(\xi_a\ \text{or}\ 1 − \xi_a\big),
//! \qquad \xi = (x − x_1)/E \in [0, 1]^3,
//! ```
//! the same for ∇u and (u·∇)u, each interpolated as data: ∇u is the blend's gradient (the blend
//! of the cells' gradients), not the derivative of the tabulated u, as in the blend.
//! - *Linear fields are exact*: the blend is, and trilinear interpolation reproduces every
//!   linear function of x.
//! - *Continuity*: where a leaf meets a larger one, its corners on the larger leaf's faces and
//!   edges ("hanging" corners) take the larger leaf's interpolant instead of the blend, coarsest
//!   leaf first, so both sides of every face agree: the restriction of a trilinear function to a
//!   face is bilinear, and bilinear on a sub-rectangle is fixed by its four corners.
//! - *Accuracy*: a leaf is split while the interpolant misses the blend at its 19 edge, face and
//!   body midpoints by more than a quarter of the tolerance (u: [`U_TOLERANCE`] of the field's
//!   largest |u|; ∇u: [`GRADIENT_TOLERANCE`] of its largest |∇u|; either may be infinite), or
//!   its edge exceeds the smallest cell support at its centre (so no mesh cell hides inside a
//!   leaf).
//!
//! # Hermite leaves
//! With [`Interpolant::Hermite`] a leaf's u is tricubic Hermite ([`super::hermite`], Lekien &
//! Marsden 2005) in its corners' u, ∇u and mixed second derivatives ∂²u/∂x_a∂x_b, and ∇u and
//! (u·∇)u are that u's own derivatives. A corner's u and ∇u are the blend's; its mixed
//! derivatives are centred differences of the blend's ∇u over ±ε along each axis, ε half the
//! edge of the smallest leaf it is a corner of, symmetrised; ∂³u/∂x∂y∂z is zero. Hanging
//! corners take the larger leaf's interpolant and all its derivatives there, so the table is
//! C¹ across every face (the bicubic face space restricted to a sub-rectangle is the
//! sub-rectangle's). Linear fields stay exact (their mixed derivatives are zero); a quadratic
//! field would be exact given exact corner data, so the table adds no error of its own at
//! second order: what it misses is the blend's sub-cell structure and the blend's own O(h²)
//! error in u and O(h) in ∇u at the corners. The split test estimates the mixed derivatives from
//! the leaf's own corners (one-sided differences). 200 bytes per node against 128.
//!
//! # The wall layer
//! Within a wall face's support ($d_f < H_f$, the wall cell's height, [`super::blend`]) the
//! blend's wall weights grow as $d_f^{-2}$: there the near-wall expansion (the δ² normal velocity of [`super::wall_layer`]) is not a
//! polynomial of the leaf, so a leaf that comes that near a wall face is a *wall leaf*, where
//! a sample is the blend itself. Wall leaves are refined to [`WALL_LEAF`] times the wall cell's
//! height (within the leaf budget), so the blend is paid for only next to the walls. Between a
//! wall leaf and the tabulated ones the two are joined continuously by a weight χ, 1 at the
//! corners on a wall leaf's boundary and 0 at the others, interpolated like the data:
//! ```math
//! u(x) = (1 − \chi(x))\,u_{\text{table}}(x) + \chi(x)\,u_{\text{blend}}(x),
//! ```
//! (the same for ∇u), exact on linear fields because both parts are. So that χ is 1 on all of a
//! wall leaf's boundary, no tabulated leaf is larger than a wall leaf it touches (such a leaf is
//! split: the octree's balance next to the wall leaves).
//!
//! # Bounded
//! Depth at most [`MAX_LEVEL`] below the root cubes, at most [`LEAVES_PER_CELL`] leaves per mesh
//! cell ([`Options`]; a leaf the depth or the budget leaves unsplit while it misses is left to
//! the blend, as a wall leaf, and [`BuildReport`] counts them), the root cubes at most one per
//! mesh cell. Only the balance next to the wall leaves may split beyond the budget.
//!
//! # Measured: not the default
//! On the shipped airway bifurcation the table is not the field the scenes sample. The blend
//! has structure finer than its cells (each fit takes over from its neighbours' within
//! (σ − 1) = 0.2 of a cell, [`super::blend::OVERLAP`]), which a table must resolve to keep the
//! datasets' fates: mesh-sized leaves shift Fig. 18's deposition at Stk ≥ 0.3, and a
//! tolerance on u that removes the shift saves no time. The measurements (sizes, errors
//! against the blend and an exact field, paired fates, cost; `examples/octree_field`,
//! `examples/octree_fates`) are in `paper-figures/fig18/NOTES.md`, History, "Octree table".

use super::blend::BlendedFlow;
use super::hermite;
use super::memo;
use super::{FoamError, PolyMesh};
use crate::error::FlowError;
use crate::flow::{FlowField, FlowSample};
use crate::tensor::{Mat3, Vec3};
use rstar::{AABB, RTree, RTreeObject};
use std::collections::HashMap;

/// Tolerance of the tabulated u against the blend, relative to the field's largest |u|.
pub const U_TOLERANCE: f64 = 1e-4;
/// Tolerance of the tabulated ∇u against the blend, relative to the field's largest |∇u|.
pub const GRADIENT_TOLERANCE: f64 = 1e-3;
/// Share of each tolerance a leaf's midpoints may use: the largest miss inside a leaf exceeds
/// the largest at its midpoints (measured in the tests).
const CHECK_SHARE: f64 = 0.25;
/// Deepest level below a root cube: leaves down to $E_0/2^{12}$.
pub const MAX_LEVEL: u32 = 12;
/// Leaves allowed per mesh cell.
pub const LEAVES_PER_CELL: usize = 12;
/// Most bytes an octree build may hold by default ([`Options::max_bytes`]), as a multiple of
/// the mesh's own bytes ([`default_max_bytes`]). A mesh takes about 290 bytes per cell (the
/// airway's 83 768 cells 24.5 MB: points, faces, owners, neighbours, face centres and areas,
/// cell centres and volumes). The tables measured on the airway take 0.4–4.9 kB per cell
/// (`paper-figures/fig18/NOTES.md`, History), and their build holds the blend's samples besides (about 175 bytes each, one
/// per lattice point of a leaf, against 128 bytes per tabulated node): at most 2.4 times the
/// table, 12 kB per cell. 64 times the mesh's bytes, about 19 kB per cell, holds that with room
/// to spare. A tolerance the budget cannot meet (1 000 leaves per cell) went on to 1.3–2.7 GiB
/// until killed; the refusal names the bytes it wanted.
pub const MESH_BYTES_MULTIPLE: usize = 64;
/// Least default bound on an octree build's bytes (64 MiB): a small mesh's table may take many
/// leaves per cell (its wall leaves, or a budget raised to resolve a front) at a memory no
/// machine is short of.
pub const MIN_BUILD_BYTES: usize = 64 << 20;

/// The default bound on an octree build's bytes for `mesh` ([`Options::max_bytes`] `None`):
/// [`MESH_BYTES_MULTIPLE`] times the mesh's own bytes, at least [`MIN_BUILD_BYTES`]. The mesh's
/// bytes: 24 per point, 4 per face vertex, 60 per face (its offset, owner, neighbour, centre
/// and area vector) and 32 per cell (its centre and volume).
pub fn default_max_bytes(mesh: &PolyMesh) -> usize {
    let vertices: usize = (0..mesh.n_faces()).map(|f| mesh.face(f).len()).sum();
    let own = mesh.points().len() * 24 + vertices * 4 + mesh.n_faces() * 60 + mesh.n_cells() * 32;
    own.saturating_mul(MESH_BYTES_MULTIPLE).max(MIN_BUILD_BYTES)
}
/// Bytes a blend sample takes in the build's map: its lattice point and datum, one control
/// byte, and the map's spare room (at most 1/8 of it free when full).
const SAMPLE_BYTES: usize = (size_of::<(Lattice, Datum)>() + 1) * 8 / 7;
/// Bytes a tree entry takes in the build: the entry, its level and its lattice corner.
const ENTRY_BYTES: usize = size_of::<u32>() * 2 + size_of::<Lattice>();
/// Edge of a wall leaf over the smallest support $H_f$ (wall cell height) of the wall faces near it.
pub const WALL_LEAF: f64 = 2.0;

/// Components of a trilinear corner's data: u (3), ∇u (9, column-major), (u·∇)u (3), χ.
const DATA: usize = 16;
/// Components of a Hermite corner's data: the eight derivatives of each of u's three
/// components ([`hermite`]), χ.
const HERMITE: usize = 3 * hermite::QUANTITIES + 1;

/// What a tree entry is: a branch (its payload the first of its 8 children), a tabulated leaf
/// (its payload the leaf's index into `corners`) or a wall leaf.
const BRANCH: u32 = 0;
const TABLE: u32 = 1 << 30;
const WALL: u32 = 2 << 30;
const TAG: u32 = 3 << 30;

/// The blend tabulated on an octree (module docs).
#[derive(Debug, Clone)]
pub struct OctreeFlow {
    blend: BlendedFlow,
    table: Table,
    /// Identity of this table for [`super::memo`] (a clone shares it: same data).
    id: u64,
}

/// The octree and its corner data.
#[derive(Debug, Clone)]
struct Table {
    origin: Vec3,
    edge: f64,
    dims: [usize; 3],
    /// Tree entries: the root cubes first (x fastest), then children in blocks of 8.
    tree: Vec<u32>,
    /// Corner node indices of each tabulated leaf, corner k at (k & 1, k >> 1 & 1, k >> 2 & 1).
    corners: Vec<[u32; 8]>,
    /// Each node's data, `stride` numbers, χ the last ([`DATA`] or [`HERMITE`]).
    nodes: Vec<f64>,
    stride: usize,
    interpolant: Interpolant,
    report: BuildReport,
}

/// How a tabulated leaf interpolates between its corners.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Interpolant {
    /// u, ∇u and (u·∇)u each trilinear in the corners' blended values (module docs,
    /// Interpolant): continuous, linear fields exact.
    #[default]
    Trilinear,
    /// u tricubic Hermite in the corners' u, ∇u and mixed second derivatives (Lekien &
    /// Marsden 2005), ∇u and (u·∇)u its own derivatives: C¹, polynomials of degree 3 per
    /// coordinate exact given exact corner data (module docs, Hermite leaves).
    Hermite,
}

impl std::str::FromStr for Interpolant {
    type Err = String;

    /// `trilinear` or `hermite`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "trilinear" => Ok(Self::Trilinear),
            "hermite" => Ok(Self::Hermite),
            other => Err(format!("unknown interpolant {other:?}: trilinear or hermite")),
        }
    }
}

/// How fine the table is built: its tolerances against the blend (relative to the field's
/// largest |u| and |∇u|) and its budget of leaves per mesh cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// Tolerance of u, relative to |u|max.
    pub u_tolerance: f64,
    /// Tolerance of ∇u, relative to |∇u|max.
    pub gradient_tolerance: f64,
    /// Leaves allowed per mesh cell.
    pub leaves_per_cell: usize,
    /// Edge of a wall leaf over the smallest support of the wall faces near it.
    pub wall_leaf: f64,
    /// The tabulated leaves' interpolant.
    pub interpolant: Interpolant,
    /// Most bytes the build may hold (tree and blend samples), `None` for the bound derived from
    /// the mesh ([`default_max_bytes`]): a build that would pass it is refused with
    /// [`FoamError::TableTooLarge`] before it samples more.
    pub max_bytes: Option<usize>,
}

impl Default for Options {
    /// [`U_TOLERANCE`], [`GRADIENT_TOLERANCE`], [`LEAVES_PER_CELL`], [`WALL_LEAF`], the bytes
    /// bound derived from the mesh ([`default_max_bytes`]).
    fn default() -> Self {
        Self {
            u_tolerance: U_TOLERANCE,
            gradient_tolerance: GRADIENT_TOLERANCE,
            leaves_per_cell: LEAVES_PER_CELL,
            wall_leaf: WALL_LEAF,
            interpolant: Interpolant::Trilinear,
            max_bytes: None,
        }
    }
}

/// What building the table found (module docs, Bounded).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BuildReport {
    /// Tabulated leaves.
    pub table_leaves: usize,
    /// Wall leaves (the blend's own samples).
    pub wall_leaves: usize,
    /// Corner nodes of the tabulated leaves.
    pub nodes: usize,
    /// Leaves the depth or the budget left unsplit though a midpoint missed its tolerance
    /// (left to the blend, as wall leaves are).
    pub unconverged: usize,
    /// Largest miss of u at the midpoints of the leaves kept, relative to |u|max.
    pub u_miss: f64,
    /// Largest miss of ∇u (Frobenius) there, relative to |∇u|max.
    pub gradient_miss: f64,
    /// The field's largest |u| over the cell fits.
    pub u_max: f64,
    /// The field's largest |∇u| (Frobenius) over the cell fits.
    pub gradient_max: f64,
    /// Corner nodes that hang on a larger tabulated leaf's face or edge (module docs).
    pub hanging: usize,
    /// Bytes of the table (tree, corners, nodes).
    pub bytes: usize,
    /// Mesh cells.
    pub cells: usize,
}

impl BuildReport {
    /// Bytes of the table per mesh cell.
    pub fn bytes_per_cell(&self) -> f64 {
        self.bytes as f64 / self.cells.max(1) as f64
    }
}

/// A point of the finest lattice: root cube index times 2^MAX_LEVEL plus the offset, per axis.
type Lattice = [u32; 3];

/// A leaf or branch while building: its tree entry, level and lower corner on the lattice.
#[derive(Debug, Clone, Copy)]
struct Cube {
    entry: usize,
    level: u32,
    corner: Lattice,
}

impl Cube {
    /// Edge in lattice units.
    fn span(&self) -> u32 {
        1 << (MAX_LEVEL - self.level)
    }

    /// The lattice point at (i, j, k) halves of the edge from the lower corner, i, j, k ∈ 0..=2.
    fn point(&self, i: u32, j: u32, k: u32) -> Lattice {
        let h = self.span() / 2;
        [self.corner[0] + i * h, self.corner[1] + j * h, self.corner[2] + k * h]
    }

    /// Child c's cube (c's bits: x, y, z halves), at tree entry `entry`.
    fn child(&self, c: usize, entry: usize) -> Cube {
        let h = self.span() / 2;
        let bit = |b: usize| ((c >> b) & 1) as u32 * h;
        Cube {
            entry,
            level: self.level + 1,
            corner: [
                self.corner[0] + bit(0),
                self.corner[1] + bit(1),
                self.corner[2] + bit(2),
            ],
        }
    }
}

/// A wall face's bounding box grown by its support, for the search of the faces a leaf meets.
struct FaceBox {
    face: usize,
    envelope: AABB<[f64; 3]>,
}

impl RTreeObject for FaceBox {
    type Envelope = AABB<[f64; 3]>;
    fn envelope(&self) -> Self::Envelope {
        self.envelope
    }
}

/// The blend's data at one point, `None` outside every support.
type Datum = Option<[f64; DATA]>;

fn datum(sample: &FlowSample) -> [f64; DATA] {
    let mut d = [0.0; DATA];
    d[..3].copy_from_slice(sample.u.as_slice());
    d[3..12].copy_from_slice(sample.grad_u.as_slice());
    d[12..15].copy_from_slice(sample.convective.as_slice());
    d
}

/// Trilinear weights N_k(ξ), k's bits the x, y, z ends.
fn weights(xi: &[f64; 3]) -> [f64; 8] {
    let mut w = [0.0; 8];
    for (k, wk) in w.iter_mut().enumerate() {
        *wk = (0..3)
            .map(|a| if (k >> a) & 1 == 1 { xi[a] } else { 1.0 - xi[a] })
            .product();
    }
    w
}

struct Builder<'a> {
    blend: &'a BlendedFlow,
    time: f64,
    origin: Vec3,
    edge: f64,
    dims: [usize; 3],
    faces: RTree<FaceBox>,
    samples: HashMap<Lattice, Datum>,
    tree: Vec<u32>,
    levels: Vec<u32>,
    corners_of: Vec<Lattice>,
    u_tol: f64,
    gradient_tol: f64,
    budget: usize,
    max_bytes: usize,
    wall_leaf: f64,
    interpolant: Interpolant,
    report: BuildReport,
}

/// A trilinear datum's ∂u_i/∂x_j (∇u column-major after u).
fn gradient_entry(d: &[f64; DATA], i: usize, j: usize) -> f64 {
    d[3 + i + 3 * j]
}

/// Hermite corner data of a cube of edge `edge` from its corners' blended u and ∇u alone, the
/// mixed derivatives the cube's one-sided differences of ∇u, f_xyz zero: what the split test
/// of a Hermite leaf uses (the table's nodes take centred differences, [`Builder::finish`]).
fn hermite_corners(data: &[[f64; DATA]], edge: f64) -> Vec<[f64; HERMITE]> {
    (0..8)
        .map(|k| {
            let mut h = [0.0; HERMITE];
            // ∂(∂u_c/∂x_j)/∂x_a from the corner across axis a.
            let along = |c: usize, j: usize, a: usize| {
                let sign = if (k >> a) & 1 == 0 { 1.0 } else { -1.0 };
                sign * (gradient_entry(&data[k ^ (1 << a)], c, j) - gradient_entry(&data[k], c, j)) / edge
            };
            for c in 0..3 {
                let q = c * hermite::QUANTITIES;
                h[q] = data[k][c];
                for a in 0..3 {
                    h[q + (1 << a)] = gradient_entry(&data[k], c, a);
                }
                for (a, b) in [(0, 1), (0, 2), (1, 2)] {
                    h[q + (1 << a) + (1 << b)] = 0.5 * (along(c, a, b) + along(c, b, a));
                }
            }
            h
        })
        .collect()
}

impl Builder<'_> {
    fn position(&self, p: &Lattice) -> Vec3 {
        let unit = self.edge / f64::from(1u32 << MAX_LEVEL);
        self.origin + Vec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2])) * unit
    }

    fn centre_and_radius(&self, cube: &Cube) -> (Vec3, f64) {
        let unit = self.edge / f64::from(1u32 << MAX_LEVEL);
        let e = f64::from(cube.span()) * unit;
        (
            self.position(&cube.corner) + Vec3::repeat(0.5 * e),
            0.5 * 3f64.sqrt() * e,
        )
    }

    /// The smallest support of the wall faces whose support the cube may meet, `None` if it
    /// meets none.
    fn wall_support(&self, cube: &Cube) -> Option<f64> {
        let (centre, radius) = self.centre_and_radius(cube);
        let walls = self.blend.wall_faces();
        let lo = centre.add_scalar(-radius);
        let hi = centre.add_scalar(radius);
        let query = AABB::from_corners([lo[0], lo[1], lo[2]], [hi[0], hi[1], hi[2]]);
        self.faces
            .locate_in_envelope_intersecting(query)
            .filter(|b| walls.distance(b.face, &centre) - radius < walls.support(b.face))
            .map(|b| walls.support(b.face))
            .reduce(f64::min)
    }

    /// Evaluate the blend at every lattice point not yet sampled (in parallel where the crate
    /// has its thread pool).
    fn sample_all(&mut self, points: Vec<Lattice>) -> Result<(), FoamError> {
        let mut fresh: Vec<Lattice> = points.into_iter().filter(|p| !self.samples.contains_key(p)).collect();
        fresh.sort_unstable();
        fresh.dedup();
        let samples = self.samples.len() + fresh.len();
        let bytes = samples * SAMPLE_BYTES + self.tree.len() * ENTRY_BYTES;
        if bytes > self.max_bytes {
            return Err(FoamError::TableTooLarge {
                bytes,
                limit: self.max_bytes,
                samples,
                leaves: self.leaves(),
                budget: self.budget,
                cells: self.report.cells,
            });
        }
        let evaluate = |p: &Lattice| {
            self.blend
                .sample(&self.position(p), self.time)
                .ok()
                .map(|s| datum(&s))
                .filter(|d| d.iter().all(|v| v.is_finite()))
        };
        #[cfg(feature = "parallel")]
        let values: Vec<Datum> = {
            use rayon::prelude::*;
            fresh.par_iter().map(evaluate).collect()
        };
        #[cfg(not(feature = "parallel"))]
        let values: Vec<Datum> = fresh.iter().map(evaluate).collect();
        self.samples.extend(fresh.into_iter().zip(values));
        Ok(())
    }

    /// The 27 points of a cube (corners, edge and face midpoints, centre).
    fn lattice_points(cube: &Cube) -> impl Iterator<Item = Lattice> + '_ {
        (0..27u32).map(move |n| cube.point(n % 3, n / 3 % 3, n / 9))
    }

    /// Corner k's lattice point (k's bits: the x, y, z ends).
    fn corner(cube: &Cube, k: usize) -> Lattice {
        let end = |b: usize| 2 * ((k >> b) & 1) as u32;
        cube.point(end(0), end(1), end(2))
    }

    /// Largest misses of the cube's interpolant at its 19 midpoints (|Δu| and the
    /// Frobenius norm of Δ∇u); `None` where a point is outside every support.
    fn misses(&self, cube: &Cube) -> Option<(f64, f64)> {
        let data: Vec<[f64; DATA]> = (0..8)
            .map(|k| self.samples[&Self::corner(cube, k)])
            .collect::<Option<_>>()?;
        let edge = f64::from(cube.span()) * self.edge / f64::from(1u32 << MAX_LEVEL);
        let hermite = (self.interpolant == Interpolant::Hermite).then(|| hermite_corners(&data, edge));
        let (mut u_miss, mut g_miss) = (0.0f64, 0.0f64);
        for n in 0..27u32 {
            let (i, j, k) = (n % 3, n / 3 % 3, n / 9);
            if i % 2 == 0 && j % 2 == 0 && k % 2 == 0 {
                continue;
            }
            let exact = self.samples[&cube.point(i, j, k)]?;
            let xi = [f64::from(i) / 2.0, f64::from(j) / 2.0, f64::from(k) / 2.0];
            let mut d = [0.0; 12];
            if let Some(h) = &hermite {
                let (u, g) = hermite::value_and_gradient(|k| &h[k][..HERMITE - 1], &xi, edge);
                d[..3].copy_from_slice(u.as_slice());
                d[3..].copy_from_slice(g.as_slice());
            } else {
                let w = weights(&xi);
                for (c, v) in d.iter_mut().enumerate() {
                    *v = (0..8).map(|q| w[q] * data[q][c]).sum::<f64>();
                }
            }
            let du = (0..3).map(|c| (d[c] - exact[c]).powi(2)).sum::<f64>().sqrt();
            let dg = (3..12).map(|c| (d[c] - exact[c]).powi(2)).sum::<f64>().sqrt();
            u_miss = u_miss.max(du);
            g_miss = g_miss.max(dg);
        }
        Some((u_miss, g_miss))
    }

    /// Split entry `cube` into 8 children appended to the tree.
    fn split(&mut self, cube: &Cube) -> [Cube; 8] {
        let first = self.tree.len();
        self.tree[cube.entry] = BRANCH | first as u32;
        for c in 0..8 {
            let child = cube.child(c, first + c);
            self.tree.push(WALL);
            self.levels.push(child.level);
            self.corners_of.push(child.corner);
        }
        std::array::from_fn(|c| cube.child(c, first + c))
    }

    fn leaves(&self) -> usize {
        // Every split turns one leaf into eight.
        self.tree.len() - (self.tree.len() - self.dims.iter().product::<usize>()) / 8
    }

    /// Decide each cube of one level: split (the children are returned), a wall leaf or a
    /// tabulated leaf (module docs).
    fn settle(&mut self, level: Vec<Cube>) -> Result<Vec<Cube>, FoamError> {
        let walls: Vec<Option<f64>> = level.iter().map(|c| self.wall_support(c)).collect();
        let points: Vec<Lattice> = level
            .iter()
            .zip(&walls)
            .filter(|(_, w)| w.is_none())
            .flat_map(|(c, _)| Self::lattice_points(c).collect::<Vec<_>>())
            .collect();
        self.sample_all(points)?;
        let unit = self.edge / f64::from(1u32 << MAX_LEVEL);
        let mut next = Vec::new();
        for (cube, wall) in level.iter().zip(walls) {
            let e = f64::from(cube.span()) * unit;
            let can_split = cube.level < MAX_LEVEL && self.leaves() + 7 <= self.budget;
            let split = match wall {
                Some(support) => e > self.wall_leaf * support,
                None => {
                    let inside: Vec<Vec3> = Self::lattice_points(cube)
                        .filter(|p| self.samples[p].is_some())
                        .map(|p| self.position(&p))
                        .collect();
                    let finest = inside
                        .iter()
                        .filter_map(|x| self.blend.finest_support(x))
                        .reduce(f64::min);
                    match self.misses(cube) {
                        // Inside the supports: split while coarser than a support or missing.
                        Some((u, g)) => {
                            let missing = u > CHECK_SHARE * self.u_tol || g > CHECK_SHARE * self.gradient_tol;
                            if (missing || finest.is_some_and(|r| e > r)) && can_split {
                                true
                            } else if missing {
                                // Out of depth or budget: the blend itself.
                                self.report.unconverged += 1;
                                false
                            } else {
                                self.tree[cube.entry] = TABLE;
                                self.note_miss(u, g);
                                continue;
                            }
                        }
                        // Across the edge of the supports (an inlet or outlet): down to the
                        // supports' size, then the blend; wholly outside: the blend.
                        None => finest.is_some_and(|r| e > r),
                    }
                }
            };
            if split && can_split {
                next.extend(self.split(cube));
            } else {
                self.tree[cube.entry] = WALL;
            }
        }
        Ok(next)
    }

    fn note_miss(&mut self, u: f64, g: f64) {
        self.report.u_miss = self.report.u_miss.max(u / self.report.u_max);
        self.report.gradient_miss = self.report.gradient_miss.max(g / self.report.gradient_max);
    }

    /// The leaf holding the point `q` of the doubled lattice (twice the lattice coordinates,
    /// so the points half a unit off the lattice have integer coordinates): its entry, level
    /// and lower corner; `None` outside the root cubes.
    fn leaf_at(&self, q: [i64; 3]) -> Option<Cube> {
        let span = 2i64 << MAX_LEVEL;
        let mut root = 0usize;
        for a in (0..3).rev() {
            let r = q[a].div_euclid(span);
            if r < 0 || r >= self.dims[a] as i64 {
                return None;
            }
            root = root * self.dims[a] + r as usize;
        }
        let mut entry = root;
        for _ in 0..=MAX_LEVEL {
            if self.tree[entry] & TAG != BRANCH {
                return Some(Cube {
                    entry,
                    level: self.levels[entry],
                    corner: self.corners_of[entry],
                });
            }
            let cube = Cube {
                entry,
                level: self.levels[entry],
                corner: self.corners_of[entry],
            };
            let h = i64::from(cube.span());
            let c: usize = (0..3)
                .map(|a| usize::from(q[a] >= 2 * i64::from(cube.corner[a]) + h) << a)
                .sum();
            entry = (self.tree[entry] & !TAG) as usize + c;
        }
        None
    }

    /// Split tabulated leaves larger than a wall leaf they touch, until none is (module docs).
    fn balance(&mut self) -> Result<(), FoamError> {
        for _ in 0..4 * MAX_LEVEL {
            let mut coarse: Vec<usize> = Vec::new();
            for entry in 0..self.tree.len() {
                if self.tree[entry] & TAG != WALL {
                    continue;
                }
                let cube = Cube {
                    entry,
                    level: self.levels[entry],
                    corner: self.corners_of[entry],
                };
                let s = 2 * i64::from(cube.span());
                for n in 0..27i64 {
                    let d = [n % 3 - 1, n / 3 % 3 - 1, n / 9 - 1];
                    if d == [0, 0, 0] {
                        continue;
                    }
                    let q: [i64; 3] = std::array::from_fn(|a| {
                        let lo = 2 * i64::from(cube.corner[a]);
                        match d[a] {
                            -1 => lo - 1,
                            0 => lo + s / 2,
                            _ => lo + s + 1,
                        }
                    });
                    if let Some(n) = self.leaf_at(q)
                        && self.tree[n.entry] & TAG == TABLE
                        && n.level < cube.level
                    {
                        coarse.push(n.entry);
                    }
                }
            }
            coarse.sort_unstable();
            coarse.dedup();
            if coarse.is_empty() {
                return Ok(());
            }
            let mut children = Vec::new();
            for entry in coarse {
                let cube = Cube {
                    entry,
                    level: self.levels[entry],
                    corner: self.corners_of[entry],
                };
                children.extend(self.split(&cube));
            }
            let points: Vec<Lattice> = children
                .iter()
                .flat_map(|c| Self::lattice_points(c).collect::<Vec<_>>())
                .collect();
            let walls: Vec<Option<f64>> = children.iter().map(|c| self.wall_support(c)).collect();
            self.sample_all(points)?;
            for (child, wall) in children.iter().zip(walls) {
                let corners_inside = (0..8).all(|k| self.samples[&Self::corner(child, k)].is_some());
                self.tree[child.entry] = if wall.is_none() && corners_inside { TABLE } else { WALL };
            }
        }
        Ok(())
    }
}

impl Builder<'_> {
    /// The corner nodes of the tabulated leaves, their data (χ included) with the hanging
    /// corners constrained (module docs), and the final tree.
    fn finish(mut self) -> Table {
        let leaves: Vec<Cube> = (0..self.tree.len())
            .filter(|&e| self.tree[e] & TAG == TABLE)
            .map(|entry| Cube {
                entry,
                level: self.levels[entry],
                corner: self.corners_of[entry],
            })
            .collect();
        let mut index: HashMap<Lattice, u32> = HashMap::new();
        let mut points: Vec<Lattice> = Vec::new();
        let mut corners: Vec<[u32; 8]> = Vec::with_capacity(leaves.len());
        for (n, leaf) in leaves.iter().enumerate() {
            self.tree[leaf.entry] = TABLE | n as u32;
            corners.push(std::array::from_fn(|k| {
                let p = Self::corner(leaf, k);
                *index.entry(p).or_insert_with(|| {
                    points.push(p);
                    (points.len() - 1) as u32
                })
            }));
        }
        // Each node's data, the deepest leaf it is a point of, and the coarsest tabulated
        // leaf it hangs on (if any).
        let stride = match self.interpolant {
            Interpolant::Trilinear => DATA,
            Interpolant::Hermite => HERMITE,
        };
        let mut nodes = vec![0.0; points.len() * stride];
        let mut deepest = vec![0u32; points.len()];
        let mut hanging: Vec<(u32, usize, Cube)> = Vec::new();
        for (n, p) in points.iter().enumerate() {
            let d = &mut nodes[n * stride..(n + 1) * stride];
            if let Some(s) = self.samples[p] {
                match self.interpolant {
                    Interpolant::Trilinear => d[..DATA - 1].copy_from_slice(&s[..DATA - 1]),
                    Interpolant::Hermite => {
                        for c in 0..3 {
                            d[c * hermite::QUANTITIES] = s[c];
                            for a in 0..3 {
                                d[c * hermite::QUANTITIES + (1 << a)] = gradient_entry(&s, c, a);
                            }
                        }
                    }
                }
            }
            let mut host: Option<Cube> = None;
            for o in 0..8 {
                let q: [i64; 3] = std::array::from_fn(|a| 2 * i64::from(p[a]) + if (o >> a) & 1 == 1 { 1 } else { -1 });
                let Some(leaf) = self.leaf_at(q) else { continue };
                deepest[n] = deepest[n].max(leaf.level);
                match self.tree[leaf.entry] & TAG {
                    WALL => d[stride - 1] = 1.0,
                    TABLE
                        if (0..8).all(|k| Self::corner(&leaf, k) != *p)
                            && host.is_none_or(|h| leaf.level < h.level) =>
                    {
                        host = Some(leaf);
                    }
                    _ => {}
                }
            }
            if let Some(h) = host {
                hanging.push((h.level, n, h));
            }
        }
        if self.interpolant == Interpolant::Hermite {
            let free: Vec<usize> = {
                let mut is_hanging = vec![false; points.len()];
                for &(_, n, _) in &hanging {
                    is_hanging[n] = true;
                }
                (0..points.len())
                    .filter(|&n| !is_hanging[n] && self.samples[&points[n]].is_some())
                    .collect()
            };
            let mixed = self.mixed_derivatives(&free, &points, &deepest);
            for (&n, m) in free.iter().zip(mixed) {
                for c in 0..3 {
                    for (pair, &(a, b)) in [(0, 1), (0, 2), (1, 2)].iter().enumerate() {
                        nodes[n * stride + c * hermite::QUANTITIES + (1 << a) + (1 << b)] = m[3 * c + pair];
                    }
                }
            }
        }
        hanging.sort_by_key(|&(level, n, _)| (level, n));
        self.report.hanging = hanging.len();
        let unit = self.edge / f64::from(1u32 << MAX_LEVEL);
        for (_, n, host) in hanging {
            let span = f64::from(host.span());
            let xi: [f64; 3] = std::array::from_fn(|a| f64::from(points[n][a] - host.corner[a]) / span);
            let w = weights(&xi);
            let ids = corners[(self.tree[host.entry] & !TAG) as usize];
            let node = |k: usize| &nodes[ids[k] as usize * stride..(ids[k] as usize + 1) * stride];
            let mut d = vec![0.0; stride];
            match self.interpolant {
                Interpolant::Trilinear => {
                    for (c, v) in d.iter_mut().enumerate() {
                        *v = (0..8).map(|k| w[k] * node(k)[c]).sum();
                    }
                }
                Interpolant::Hermite => {
                    for q in 0..hermite::QUANTITIES {
                        let v = hermite::derivative(|k| &node(k)[..stride - 1], &xi, span * unit, q);
                        for c in 0..3 {
                            d[c * hermite::QUANTITIES + q] = v[c];
                        }
                    }
                    d[stride - 1] = (0..8).map(|k| w[k] * node(k)[stride - 1]).sum();
                }
            }
            nodes[n * stride..(n + 1) * stride].copy_from_slice(&d);
        }
        let wall_leaves = (0..self.tree.len()).filter(|&e| self.tree[e] & TAG == WALL).count();
        let bytes =
            self.tree.len() * size_of::<u32>() + corners.len() * size_of::<[u32; 8]>() + nodes.len() * size_of::<f64>();
        Table {
            origin: self.origin,
            edge: self.edge,
            dims: self.dims,
            tree: self.tree,
            report: BuildReport {
                table_leaves: corners.len(),
                wall_leaves,
                nodes: points.len(),
                bytes,
                ..self.report
            },
            corners,
            nodes,
            stride,
            interpolant: self.interpolant,
        }
    }

    /// The mixed second derivatives ∂²u_c/∂x_a∂x_b (a < b: xy, xz, yz; 3 per component) at
    /// nodes `which`: centred differences of the blend's ∇u over ±ε along each axis, ε half the
    /// edge of the smallest leaf the node is a corner of (one-sided where a side is outside
    /// every support, zero where both are), symmetrised over the two orders.
    fn mixed_derivatives(&self, which: &[usize], points: &[Lattice], deepest: &[u32]) -> Vec<[f64; 9]> {
        let compute = |&n: &usize| -> [f64; 9] {
            let x = self.position(&points[n]);
            let eps = 0.5 * self.edge / f64::from(1u32 << deepest[n]);
            let at = |y: Vec3| {
                self.blend
                    .sample(&y, self.time)
                    .ok()
                    .map(|s| s.grad_u)
                    .filter(|g| g.iter().all(|v| v.is_finite()))
            };
            let centre = self.samples[&points[n]].map(|s| Mat3::from_column_slice(&s[3..12]));
            // ∂(∇u)/∂x_a.
            let slope: [Mat3; 3] = std::array::from_fn(|a| {
                let step = Vec3::ith(a, eps);
                match (at(x - step), centre, at(x + step)) {
                    (Some(lo), _, Some(hi)) => (hi - lo) / (2.0 * eps),
                    (None, Some(c), Some(hi)) => (hi - c) / eps,
                    (Some(lo), Some(c), None) => (c - lo) / eps,
                    _ => Mat3::zeros(),
                }
            });
            let mut m = [0.0; 9];
            for c in 0..3 {
                for (pair, &(a, b)) in [(0, 1), (0, 2), (1, 2)].iter().enumerate() {
                    m[3 * c + pair] = 0.5 * (slope[b][(c, a)] + slope[a][(c, b)]);
                }
            }
            m
        };
        #[cfg(feature = "parallel")]
        {
            use rayon::prelude::*;
            which.par_iter().map(compute).collect()
        }
        #[cfg(not(feature = "parallel"))]
        which.iter().map(compute).collect()
    }
}

impl OctreeFlow {
    /// Tabulate the steady field `blend` (module docs); an error for a field with more than
    /// one time level or a mesh whose extent is not finite.
    pub fn new(blend: BlendedFlow) -> Result<Self, FoamError> {
        Self::with_options(blend, Options::default())
    }

    /// [`OctreeFlow::new`] with other tolerances or leaf budget; an error for tolerances not
    /// positive, a wall leaf not finite and positive or a budget below one leaf per cell.
    pub fn with_options(blend: BlendedFlow, options: Options) -> Result<Self, FoamError> {
        let Options {
            u_tolerance,
            gradient_tolerance,
            leaves_per_cell,
            wall_leaf,
            interpolant,
            max_bytes,
        } = options;
        // A tolerance may be infinite: leaves sized by the mesh alone (the fates measured in
        // `paper-figures/fig18/NOTES.md`, History).
        if !([u_tolerance, gradient_tolerance].iter().all(|t| *t > 0.0)
            && wall_leaf.is_finite()
            && wall_leaf > 0.0
            && leaves_per_cell >= 1)
        {
            return Err(FoamError::Field {
                path: "(octree)".into(),
                reason: format!(
                    "tolerances {u_tolerance:e} (u) and {gradient_tolerance:e} (∇u) and the wall leaf {wall_leaf:e} \
                     must be positive (the wall leaf finite), and the budget {leaves_per_cell} leaves per cell at least 1"
                ),
            });
        }
        let cellwise = blend.cellwise();
        let times = cellwise.times();
        if times.len() != 1 {
            return Err(FoamError::Field {
                path: "(time directories)".into(),
                reason: format!(
                    "the octree tabulates a steady field (one time level), this one has {}; use the blend",
                    times.len()
                ),
            });
        }
        let mesh = cellwise.mesh();
        let max_bytes = max_bytes.unwrap_or_else(|| default_max_bytes(mesh));
        let (lo, hi) = mesh.points().iter().fold(
            (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.inf(p), hi.sup(p)),
        );
        let n_cells = mesh.n_cells().max(1);
        let mut edge = blend.radius();
        let extent = hi - lo;
        if !(extent.iter().all(|e| e.is_finite()) && edge.is_finite() && edge > 0.0) {
            return Err(FoamError::Mesh {
                reason: format!("cannot tabulate a field on a mesh of extent {extent:?} and support {edge:e}"),
            });
        }
        // The root cubes cover the mesh with a margin of a tenth of a cube; at most one per
        // cell and 2¹⁹ along an axis (lattice coordinates fit u32).
        let origin = lo.add_scalar(-0.1 * edge);
        let dims = loop {
            let dims: [usize; 3] = std::array::from_fn(|a| ((extent[a] + 0.2 * edge) / edge).ceil().max(1.0) as usize);
            if dims.iter().product::<usize>() <= n_cells && dims.iter().all(|&d| d <= 1 << 19) {
                break dims;
            }
            edge *= 2.0;
        };
        let (mut u_max, mut gradient_max) = (0.0f64, 0.0f64);
        for c in 0..mesh.n_cells() {
            let s = cellwise.sample_cell(c, &mesh.cell_centres()[c], times[0]);
            u_max = u_max.max(s.u.norm());
            gradient_max = gradient_max.max(s.grad_u.norm());
        }
        let (u_max, gradient_max) = (u_max.max(f64::MIN_POSITIVE), gradient_max.max(f64::MIN_POSITIVE));
        let walls = blend.wall_faces();
        let faces = RTree::bulk_load(
            (0..walls.len())
                .map(|k| {
                    let grow = walls.support(k);
                    let (lo, hi) = walls
                        .vertices(k)
                        .iter()
                        .fold((walls.centre(k), walls.centre(k)), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
                    let (lo, hi) = (lo.add_scalar(-grow), hi.add_scalar(grow));
                    FaceBox {
                        face: k,
                        envelope: AABB::from_corners([lo[0], lo[1], lo[2]], [hi[0], hi[1], hi[2]]),
                    }
                })
                .collect(),
        );
        let roots = dims.iter().product::<usize>();
        let mut builder = Builder {
            blend: &blend,
            time: times[0],
            origin,
            edge,
            dims,
            faces,
            samples: HashMap::new(),
            tree: vec![WALL; roots],
            levels: vec![0; roots],
            corners_of: (0..roots)
                .map(|r| {
                    let (x, y, z) = (r % dims[0], r / dims[0] % dims[1], r / (dims[0] * dims[1]));
                    [x as u32, y as u32, z as u32].map(|v| v << MAX_LEVEL)
                })
                .collect(),
            u_tol: u_tolerance * u_max,
            gradient_tol: gradient_tolerance * gradient_max,
            budget: leaves_per_cell.saturating_mul(n_cells),
            max_bytes,
            wall_leaf,
            interpolant,
            report: BuildReport {
                u_max,
                gradient_max,
                cells: mesh.n_cells(),
                ..BuildReport::default()
            },
        };
        let mut level: Vec<Cube> = (0..roots)
            .map(|entry| Cube {
                entry,
                level: 0,
                corner: builder.corners_of[entry],
            })
            .collect();
        for _ in 0..=MAX_LEVEL {
            if level.is_empty() {
                break;
            }
            level = builder.settle(level)?;
        }
        builder.balance()?;
        let table = builder.finish();
        Ok(Self {
            blend,
            table,
            id: memo::new_id(),
        })
    }
}

impl OctreeFlow {
    /// What the build found: leaves, nodes, memory and the misses at the leaves' midpoints.
    pub fn report(&self) -> &BuildReport {
        &self.table.report
    }

    /// The blended field underneath (the reference, and the field next to the walls).
    pub fn blended(&self) -> &BlendedFlow {
        &self.blend
    }

    /// The tabulated leaf holding x, x's coordinates ξ in it and its edge, `None` in a wall
    /// leaf or outside the root cubes.
    fn leaf(&self, x: &Vec3) -> Option<(usize, [f64; 3], f64)> {
        let t = &self.table;
        let rel = (x - t.origin) / t.edge;
        let mut entry = 0usize;
        let mut xi = [0.0; 3];
        let mut edge = t.edge;
        for a in (0..3).rev() {
            let f = rel[a].floor();
            if !(f >= 0.0 && f < t.dims[a] as f64) {
                return None;
            }
            entry = entry * t.dims[a] + f as usize;
            xi[a] = rel[a] - f;
        }
        // Doubling ξ and taking off the child's half is exact in binary floating point.
        for _ in 0..=MAX_LEVEL {
            let e = t.tree[entry];
            match e & TAG {
                BRANCH => {
                    let mut child = 0;
                    for (a, v) in xi.iter_mut().enumerate() {
                        *v *= 2.0;
                        if *v >= 1.0 {
                            *v -= 1.0;
                            child |= 1 << a;
                        }
                    }
                    entry = (e & !TAG) as usize + child;
                    edge *= 0.5;
                }
                TABLE => return Some(((e & !TAG) as usize, xi, edge)),
                _ => return None,
            }
        }
        None
    }

    /// Every leaf of the octree, root cube by root cube, depth first.
    pub fn leaves(&self) -> Vec<LeafBox> {
        let t = &self.table;
        let mut out = Vec::new();
        let mut stack: Vec<(usize, Vec3, f64)> = (0..t.dims.iter().product::<usize>())
            .map(|r| {
                let ijk = Vec3::new(
                    (r % t.dims[0]) as f64,
                    (r / t.dims[0] % t.dims[1]) as f64,
                    (r / (t.dims[0] * t.dims[1])) as f64,
                );
                (r, t.origin + ijk * t.edge, t.edge)
            })
            .rev()
            .collect();
        // Each entry is pushed once (a tree has no cycles), so the loop ends.
        while let Some((entry, lower, edge)) = stack.pop() {
            let e = t.tree[entry];
            if e & TAG == BRANCH {
                for c in (0..8).rev() {
                    let bit = |a: usize| ((c >> a) & 1) as f64 * edge / 2.0;
                    stack.push((
                        (e & !TAG) as usize + c,
                        lower + Vec3::new(bit(0), bit(1), bit(2)),
                        edge / 2.0,
                    ));
                }
            } else {
                out.push(LeafBox {
                    lower,
                    edge,
                    tabulated: e & TAG == TABLE,
                });
            }
        }
        out
    }

    /// Whether x lies where a sample is the table alone (a tabulated leaf, χ = 0 there).
    pub fn is_tabulated(&self, x: &Vec3) -> bool {
        self.leaf(x).is_some_and(|(leaf, xi, _)| self.chi(leaf, &xi) <= 0.0)
    }

    /// Node n's data.
    fn node(&self, n: u32) -> &[f64] {
        let stride = self.table.stride;
        &self.table.nodes[n as usize * stride..(n as usize + 1) * stride]
    }

    /// The join's weight χ at ξ in tabulated leaf `leaf` (trilinear in the corners' χ).
    fn chi(&self, leaf: usize, xi: &[f64; 3]) -> f64 {
        let w = weights(xi);
        let last = self.table.stride - 1;
        (0..8)
            .map(|k| w[k] * self.node(self.table.corners[leaf][k])[last])
            .sum()
    }

    /// The tabulated leaf's interpolant at ξ (leaf edge `edge`) and χ there.
    fn tabulated(&self, leaf: usize, xi: &[f64; 3], edge: f64) -> (FlowSample, f64) {
        let ids = &self.table.corners[leaf];
        match self.table.interpolant {
            Interpolant::Trilinear => {
                let w = weights(xi);
                let mut d = [0.0; DATA];
                for (k, &n) in ids.iter().enumerate() {
                    for (dc, v) in d.iter_mut().zip(self.node(n)) {
                        *dc += w[k] * v;
                    }
                }
                let sample = FlowSample {
                    u: Vec3::from_column_slice(&d[..3]),
                    grad_u: Mat3::from_column_slice(&d[3..12]),
                    du_dt: Vec3::zeros(),
                    convective: Vec3::from_column_slice(&d[12..15]),
                };
                (sample, d[DATA - 1])
            }
            Interpolant::Hermite => {
                let (u, grad_u) = hermite::value_and_gradient(|k| &self.node(ids[k])[..HERMITE - 1], xi, edge);
                let sample = FlowSample {
                    u,
                    grad_u,
                    du_dt: Vec3::zeros(),
                    convective: grad_u * u,
                };
                (sample, self.chi(leaf, xi))
            }
        }
    }
}

impl FlowField for OctreeFlow {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        crate::flow::check_query(x, t)?;
        self.blend.cellwise().check_time(t)?;
        memo::remembered(self.id, x, t, || self.evaluate(x, t))
    }

    fn strain_rate(&self) -> Option<f64> {
        self.blend.strain_rate()
    }
}

impl OctreeFlow {
    /// The table at (x, t): a tabulated leaf's interpolant, joined to the blend by χ next to
    /// the wall leaves; the blend in a wall leaf (module docs).
    fn evaluate(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        let Some((leaf, xi, edge)) = self.leaf(x) else {
            return self.blend.sample(x, t);
        };
        let (table, chi) = self.tabulated(leaf, &xi, edge);
        if chi <= 0.0 {
            return Ok(table);
        }
        let b = self.blend.sample(x, t)?;
        let mix = |a: f64, b: f64| (1.0 - chi) * a + chi * b;
        Ok(FlowSample {
            u: table.u.zip_map(&b.u, mix),
            grad_u: table.grad_u.zip_map(&b.grad_u, mix),
            du_dt: Vec3::zeros(),
            convective: table.convective.zip_map(&b.convective, mix),
        })
    }
}

/// A leaf of the table: its lower corner, edge, and whether it is tabulated (else a wall leaf,
/// where a sample is the blend).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LeafBox {
    /// Lower corner.
    pub lower: Vec3,
    /// Edge length.
    pub edge: f64,
    /// Tabulated (trilinear), or a wall leaf.
    pub tabulated: bool,
}

/// Where the table is checked against the blend: points spread over the mesh and points at
/// given fractions of the first cell's height from the wall faces, in from each face's centre.
#[derive(Debug, Clone)]
pub struct CheckPoints {
    /// Points spread over the mesh's bounding box that lie in a mesh cell.
    pub spread: Vec<Vec3>,
    /// (point, patch index, fraction of the first cell's height) next to the wall faces.
    pub near_wall: Vec<(Vec3, usize, f64)>,
}

/// The largest differences of the table from the blend over some points.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Misses {
    /// Points compared.
    pub points: usize,
    /// Largest |u − u_blend| / |u|max.
    pub u: f64,
    /// Largest |∇u − ∇u_blend| / |∇u|max (Frobenius).
    pub gradient: f64,
}

/// SplitMix64 (Steele, Lea & Flood 2014): a fixed sequence of check points for a seed.
fn splitmix(state: &mut u64) -> f64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
}

impl OctreeFlow {
    /// `spread` points drawn uniformly in the mesh's bounding box until that many lie in a
    /// cell (at most 100 draws each), and at every `stride`-th wall face one point at each of
    /// `fractions` of its cell's height in from its centre.
    pub fn check_points(&self, spread: usize, stride: usize, fractions: &[f64], seed: u64) -> CheckPoints {
        let cellwise = self.blend.cellwise();
        let mesh = cellwise.mesh();
        let (lo, hi) = mesh.points().iter().fold(
            (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.inf(p), hi.sup(p)),
        );
        let mut state = seed;
        let mut inside = Vec::with_capacity(spread);
        for _ in 0..100 * spread {
            if inside.len() == spread {
                break;
            }
            let x = lo
                + (hi - lo).component_mul(&Vec3::new(
                    splitmix(&mut state),
                    splitmix(&mut state),
                    splitmix(&mut state),
                ));
            if cellwise.locate(&x, None).is_ok() {
                inside.push(x);
            }
        }
        let layer = cellwise.wall_layer();
        let mut near_wall = Vec::new();
        for (k, &f) in cellwise.walls().iter().enumerate().step_by(stride.max(1)) {
            let f = f as usize;
            let normal = mesh.face_areas()[f].normalize();
            let height = 2.0 * layer.depth(k);
            for &q in fractions {
                let x = mesh.face_centres()[f] - normal * (q * height);
                near_wall.push((x, mesh.patch_of(f).unwrap_or(usize::MAX), q));
            }
        }
        CheckPoints {
            spread: inside,
            near_wall,
        }
    }

    /// The largest differences from the blend at `points` where both answer.
    pub fn misses(&self, points: impl IntoIterator<Item = Vec3>) -> Misses {
        let report = &self.table.report;
        let mut m = Misses::default();
        for x in points {
            if let (Ok(a), Ok(b)) = (self.sample(&x, 0.0), self.blend.sample(&x, 0.0)) {
                m.points += 1;
                m.u = m.u.max((a.u - b.u).norm() / report.u_max);
                m.gradient = m.gradient.max((a.grad_u - b.grad_u).norm() / report.gradient_max);
            }
        }
        m
    }
}

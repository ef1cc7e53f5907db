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
//!
//! # Layout
//! This file holds the table's types and the data layout of its nodes; `build` tabulates the
//! blend ([`OctreeFlow::new`]: the split test, the balance next to the wall leaves, the
//! hanging corners); `budget` bounds the build's bytes ([`default_max_bytes`]); `query`
//! samples the table (the descent to a leaf, its interpolant, the join to the blend); `check`
//! compares it with the blend ([`OctreeFlow::check_points`], [`OctreeFlow::misses`]).

use super::blend::BlendedFlow;
use super::hermite;
use crate::flow::FlowSample;
use crate::tensor::Vec3;

mod budget;
mod build;
mod check;
mod query;

pub use budget::{MESH_BYTES_MULTIPLE, MIN_BUILD_BYTES, default_max_bytes};
pub use check::{CheckPoints, Misses};
pub use query::LeafBox;

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
    /// [`FoamError::TableTooLarge`](crate::flow::openfoam::FoamError::TableTooLarge) before it
    /// samples more.
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

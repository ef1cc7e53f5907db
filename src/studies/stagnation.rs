//! Hiemenz stagnation-point flow written into a meshed box: the meshed field against the exact
//! Navier–Stokes solution near the wall, on meshes made the way users make them (issue 25):
//! blockMesh layerings built in the tests and snappyHexMesh prism layers (`cases/stagnation`,
//! the coarse meshes shipped in `tests/data/stagnation-snappy`).
//!
//! # Physics
//! The box x ∈ [−0.5, 0.5], y ∈ [0, 0.4], z ∈ [0, 0.25] above the no-slip wall y = 0 holds the
//! exact plane stagnation flow ([`Hiemenz`]) with strain a = [`STRAIN`] and ν = [`NU`]
//! (ℓ = √(ν/a) = 0.1), sampled at the cell and boundary-face centres as a solver holds it.
//! Near the wall the normal velocity grows as the square of the wall distance δ, with the
//! coefficient continuity gives from the wall shear,
//! ```math
//! v ≈ c\,δ^2,\qquad c = −\tfrac12\,a\,f''(0)/ℓ,
//! ```
//! which the wall layer ([`BlendedFlow`]) must reproduce and the cellwise linear fits cannot.
//! The measures, over the middle of the wall (x ∈ [−0.35, 0.35], z ∈ [0.05, 0.2], away from
//! the open sides by at least a core cell), with δ₁ the first cell's height there:
//! - the relative error of v at δ = s δ₁ for the fractions s of [`FRACTIONS`];
//! - v/δ² at δ = δ₁/100 against c (the O(δ³) term is 10⁻² of the first cell's there);
//! - the largest |u| and |∇u| errors at heights up to 2 δ₁ ([`wall_layer_points`]), whose
//!   decrease with δ₁ under refinement gives the observed order: on meshes similar under
//!   refinement the band covers the same cells at every level (a band of fixed height would
//!   take in the cells above the prism layers on the finer meshes only, whose larger error
//!   then lowers the observed order until the band holds many of them).

use crate::error::FlowError;
use crate::flow::FlowField;
use crate::flow::openfoam::{BlendedFlow, FoamError, FoamFlow, PatchRole, PolyMesh, VolField};
use crate::flow::stagnation::Hiemenz;
use crate::output::OutputError;
use crate::output::csv::Csv;
use crate::tensor::Vec3;
use std::path::Path;
use thiserror::Error;

/// Strain rate a of the outer flow.
pub const STRAIN: f64 = 1.0;
/// Kinematic viscosity ν: boundary-layer length ℓ = √(ν/a) = 0.1.
pub const NU: f64 = 0.01;
/// Heights in the first cell, as fractions of its height, where the normal velocity is checked:
/// half is the cell's centre (where the solver's value is), the others are where
/// interpolation happens.
pub const FRACTIONS: [f64; 4] = [0.1, 0.25, 0.5, 0.75];
/// Heights of the wall-layer error: this many, evenly spaced over (0, 2] first-cell heights.
/// The error is smallest at the cell centres (the cells hold the exact values) and peaks
/// between them, so a few fixed heights would sample the cells of each mesh at a different
/// phase, and the observed order with them; 40 put 20 in the first cell and 20 in the one
/// above it.
pub const WALL_LAYER_HEIGHTS: usize = 40;

/// Failures of the stagnation scene.
#[derive(Debug, Error)]
pub enum StagnationError {
    /// The mesh could not be read or the field not set up on it.
    #[error(transparent)]
    Foam(#[from] FoamError),
    /// The meshed field failed at a query point.
    #[error(transparent)]
    Flow(#[from] FlowError),
    /// No `wall` patch face lies on y = 0 over the middle of the box.
    #[error("no wall face on y = 0 over the middle of the box")]
    NoWall,
    /// A dataset or figure could not be written.
    #[error(transparent)]
    Output(#[from] OutputError),
}

/// The exact flow of the scene.
pub fn hiemenz() -> Hiemenz {
    // STRAIN and NU are positive constants: `Hiemenz::new` accepts them.
    Hiemenz::new(STRAIN, NU).unwrap_or_else(|_| unreachable!("positive constants"))
}

/// Whether a point lies over the middle of the wall.
fn over_the_middle(x: &Vec3) -> bool {
    x[0].abs() <= 0.35 && (0.05..=0.2).contains(&x[2])
}

/// The Hiemenz flow written into a meshed box: the cellwise and the blended fields and the
/// first cell's height.
#[derive(Debug, Clone)]
pub struct StagnationBox {
    /// Cellwise linear fits of the cell-centre values.
    pub cellwise: FoamFlow,
    /// The same with the second-order wall layer.
    pub blended: BlendedFlow,
    /// Mean height δ₁ of the cells on the wall over its middle: V/A of each (its volume over its
    /// wall face's area, the height of a prism with a face parallel to the wall).
    pub first_cell: f64,
}

/// Mean height δ₁ of the cells on the `wall`-type faces of `mesh` whose centres satisfy `on`:
/// V/A of each (its volume over its wall face's area, the height of a prism with a face
/// parallel to the wall); `None` without such a face.
pub fn first_cell_height(mesh: &PolyMesh, on: impl Fn(&Vec3) -> bool) -> Option<f64> {
    let heights: Vec<f64> = mesh
        .patches()
        .iter()
        .filter(|p| PatchRole::of(&p.kind) == PatchRole::Wall)
        .flat_map(|p| p.start..p.start + p.size)
        .filter(|&f| on(&mesh.face_centres()[f]))
        .map(|f| mesh.cell_volumes()[mesh.owner(f)] / mesh.face_areas()[f].norm())
        .collect();
    (!heights.is_empty()).then(|| heights.iter().sum::<f64>() / heights.len() as f64)
}

impl StagnationBox {
    /// The exact field written at the cell and boundary-face centres of `mesh`, whose wall
    /// patch (type `wall`) covers y = 0.
    pub fn new(mesh: PolyMesh) -> Result<Self, StagnationError> {
        let first_cell =
            first_cell_height(&mesh, |x| x[1].abs() < 1e-9 && over_the_middle(x)).ok_or(StagnationError::NoWall)?;
        let exact = hiemenz();
        // The snapped wall's points lie on y = 0 to round-off, some just below: they take the
        // wall's value.
        let at = |x: &Vec3| exact.sample(&Vec3::new(x[0], x[1].max(0.0), x[2]), 0.0);
        if let Some(e) = mesh
            .cell_centres()
            .iter()
            .chain(mesh.face_centres())
            .find_map(|x| at(x).err())
        {
            return Err(e.into());
        }
        let field = VolField::from_fn(&mesh, |x| at(x).map_or(Vec3::zeros(), |s| s.u));
        let cellwise = FoamFlow::new(mesh, vec![(0.0, field)])?;
        let blended = BlendedFlow::new(cellwise.clone())?;
        Ok(Self {
            cellwise,
            blended,
            first_cell,
        })
    }

    /// The box of an OpenFOAM case's `constant/polyMesh` (`cases/stagnation/Allmesh`).
    pub fn read(case: &Path) -> Result<Self, StagnationError> {
        Self::new(PolyMesh::read(case)?)
    }
}

/// Sixty points at height `y` over the middle of the wall, scattered in x and z by a 64-bit
/// linear congruential generator (Knuth's MMIX constants, seed 41; no dependence on a RNG
/// crate's stream): scattered, not on a grid, so that they do not all share the position in
/// their cell that a grid would give them on every refinement.
pub fn over_the_wall(y: f64) -> Vec<Vec3> {
    let mut state: u64 = 41;
    let mut next = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..60)
        .map(|_| {
            let (x, _, z) = (next(), next(), next());
            Vec3::new(-0.35 + 0.7 * x, y, 0.05 + 0.15 * z)
        })
        .collect()
}

/// Largest relative error |v − v_exact|/|v_exact| of the wall-normal velocity at height y.
pub fn normal_velocity_error(flow: &dyn FlowField, y: f64) -> Result<f64, FlowError> {
    let exact = hiemenz();
    over_the_wall(y).iter().try_fold(0.0f64, |worst, x| {
        let v = exact.sample(x, 0.0)?.u[1];
        Ok(worst.max((flow.sample(x, 0.0)?.u[1] - v).abs() / v.abs()))
    })
}

/// Continuity's coefficient c = −½ a f″(0)/ℓ of v ≈ c δ² at the wall.
pub fn continuity_coefficient() -> f64 {
    let exact = hiemenz();
    -0.5 * STRAIN * exact.wall_curvature() / exact.length()
}

/// The ratio (v/δ²)/c that the wall fit leaves at height `delta`, over the wall faces over the
/// middle of the wall: (smallest, largest); `None` if no face there has a cell above.
///
/// The Hiemenz profile's slope has no cubic term: from
/// $f^{\prime\prime\prime} + f f^{\prime\prime} + 1 − (f^{\prime})^2 = 0$ at the wall,
/// $f^{\prime\prime\prime}(0) = −1$, $f^{(4)}(0) = 0$ and $f^{(5)}(0) = f^{\prime\prime}(0)^2$, so
/// ```math
/// f^{\prime}(η) = f^{\prime\prime}(0) η − \tfrac12 η^2 + \tfrac{1}{24} f^{\prime\prime}(0)^2 η^4 + O(η^5).
/// ```
/// The quadratic through the wall and the heights $η_o = ρ/ℓ$ of the wall cell's centre and
/// $η_1 = ρ_1/ℓ$ of the cell above (`flow::openfoam::wall_layer`, Tangential) takes the
/// quartic's slope at the wall as $−\tfrac{1}{24} f^{\prime\prime}(0)^2 η_o η_1 (η_o + η_1)$, so
/// the shear γ and the fit's $c_f = −½∇ₛ·γ$ come out low by the factor 1 − ε,
/// $ε = \tfrac{1}{24} f^{\prime\prime}(0) η_o η_1 (η_o + η_1)$: third order in the cell size.
/// The fit's cubic $e_f δ^3$ passes through the cell's value $v_o = v(ρ)$ (`wall_layer`,
/// Normal), $e_f = (v_o − c_f ρ^2)/ρ^3$, so at height δ
/// ```math
/// \frac{v}{c\,δ^2} = 1 − ε + \Big(\frac{v_o}{c\,ρ^2} − 1 + ε\Big)\frac{δ}{ρ},
/// \qquad \frac{v_o}{c\,ρ^2} = \frac{f(η_o)}{\tfrac12 f^{\prime\prime}(0)\,η_o^2} = 1 − \frac{η_o}{3 f^{\prime\prime}(0)} + O(η_o^3),
/// ```
/// whose δ³ term, $−δ/(3 f^{\prime\prime}(0) ℓ) + ε δ/ρ$, is the exact profile's own
/// ($v = −\sqrt{aν}\\,f(η)$ with $f = \tfrac12 f^{\prime\prime}(0)η^2 − \tfrac16 η^3 + …$) plus the
/// shear's miss carried up to the centre. `delta` = 0 gives 1 − ε alone. Compared with the
/// measured ratio in `paper-figures/near-wall/NOTES.md`.
pub fn predicted_coefficient_ratio(flow: &StagnationBox, delta: f64) -> Option<(f64, f64)> {
    let exact = hiemenz();
    let (curvature, length) = (exact.wall_curvature(), exact.length());
    let cells = &flow.cellwise;
    let (mesh, layer) = (cells.mesh(), cells.wall_layer());
    cells
        .walls()
        .iter()
        .enumerate()
        .filter(|&(_, &f)| {
            let x = mesh.face_centres()[f as usize];
            x[1].abs() < 1e-9 && over_the_middle(&x)
        })
        .filter_map(|(k, _)| {
            let (rho, far) = (layer.depth(k), layer.above_height(k)?);
            let (near, far) = (rho / length, far / length);
            let eps = curvature / 24.0 * near * far * (near + far);
            let centre = exact.profile(near)[0] / (0.5 * curvature * near * near);
            Some(1.0 - eps + (centre - 1.0 + eps) * delta / rho)
        })
        .fold(None, |range, r| {
            Some(range.map_or((r, r), |(lo, hi): (f64, f64)| (lo.min(r), hi.max(r))))
        })
}

/// The ratio (v/δ²)/c at height δ over the middle of the wall that is furthest from 1.
pub fn coefficient_ratio(flow: &dyn FlowField, delta: f64) -> Result<f64, FlowError> {
    let c = continuity_coefficient();
    over_the_wall(delta).iter().try_fold(1.0f64, |worst, x| {
        let ratio = flow.sample(x, 0.0)?.u[1] / (delta * delta) / c;
        Ok(if (ratio - 1.0).abs() > (worst - 1.0).abs() {
            ratio
        } else {
            worst
        })
    })
}

/// The points of the wall-layer error: [`WALL_LAYER_HEIGHTS`] heights over (0, 2 `first_cell`]
/// over the wall.
pub fn wall_layer_points(first_cell: f64) -> Vec<Vec3> {
    let step = 2.0 * first_cell / WALL_LAYER_HEIGHTS as f64;
    (1..=WALL_LAYER_HEIGHTS)
        .flat_map(|i| over_the_wall(i as f64 * step))
        .collect()
}

/// Largest |u − u_exact| and |∇u − ∇u_exact| (max norms) over `points`.
pub fn velocity_errors(flow: &dyn FlowField, points: &[Vec3]) -> Result<(f64, f64), FlowError> {
    let exact = hiemenz();
    points.iter().try_fold((0.0f64, 0.0f64), |(eu, eg), x| {
        let (s, e) = (flow.sample(x, 0.0)?, exact.sample(x, 0.0)?);
        Ok((eu.max((s.u - e.u).amax()), eg.max((s.grad_u - e.grad_u).amax())))
    })
}

/// The exact field's largest |u| and |∇u| (max norms) in the box, over a 101 × 101 grid of x
/// and y (the field does not depend on z): a = 1 and ℓ = 0.1 put them at x = ±0.5, at the top
/// (|u| = a x f′ = 0.49985) and on the wall (|∂u/∂y| = a x f″(0)/ℓ = 6.163).
pub fn exact_maxima() -> Result<(f64, f64), FlowError> {
    let exact = hiemenz();
    let mut maxima = (0.0f64, 0.0f64);
    for i in 0..=100 {
        for j in 0..=100 {
            let x = Vec3::new(-0.5 + i as f64 / 100.0, 0.4 * j as f64 / 100.0, 0.125);
            let s = exact.sample(&x, 0.0)?;
            maxima = (maxima.0.max(s.u.amax()), maxima.1.max(s.grad_u.amax()));
        }
    }
    Ok(maxima)
}

/// Largest |u − u_exact| and |∇u − ∇u_exact| at half the first cell's height over the middle
/// of the wall, each relative to the exact field's maximum ([`exact_maxima`]): the measures of
/// `paper-figures/near-wall/gradient_order.csv`.
pub fn half_cell_errors(flow: &dyn FlowField, first_cell: f64) -> Result<(f64, f64), FlowError> {
    let (u, grad) = velocity_errors(flow, &over_the_wall(0.5 * first_cell))?;
    let (u_max, grad_max) = exact_maxima()?;
    Ok((u / u_max, grad / grad_max))
}

/// The measures of one mesh of a refinement study.
#[derive(Debug, Clone, PartialEq)]
pub struct WallLayerRow {
    /// Prism layers asked of snappyHexMesh.
    pub layers: usize,
    /// Refinement level (background cells halved `level` times).
    pub level: u32,
    /// Cells of the mesh.
    pub cells: usize,
    /// First cell's height δ₁.
    pub first_cell: f64,
    /// Relative normal-velocity error of the blended field at [`FRACTIONS`] × δ₁.
    pub normal_error: [f64; 4],
    /// The same of the cellwise field.
    pub cellwise_normal_error: [f64; 4],
    /// (v/δ²)/c at δ = δ₁/100, the value furthest from 1 ([`coefficient_ratio`]).
    pub coefficient_ratio: f64,
    /// Largest |u| error of the blended field at the wall-layer points ([`wall_layer_points`]).
    pub velocity_error: f64,
    /// Largest |∇u| error there.
    pub gradient_error: f64,
    /// Largest |u| error at half the first cell's height over the wall, relative to the exact
    /// field's largest |u| ([`half_cell_errors`]).
    pub half_cell_velocity_error: f64,
    /// The same of |∇u|, relative to the exact field's largest |∇u|.
    pub half_cell_gradient_error: f64,
}

impl WallLayerRow {
    /// Measure `flow`, a mesh with `layers` prism layers at refinement `level`.
    pub fn measure(layers: usize, level: u32, flow: &StagnationBox) -> Result<Self, FlowError> {
        let first = flow.first_cell;
        let (mut normal_error, mut cellwise_normal_error) = ([0.0; 4], [0.0; 4]);
        for (i, s) in FRACTIONS.iter().enumerate() {
            normal_error[i] = normal_velocity_error(&flow.blended, s * first)?;
            cellwise_normal_error[i] = normal_velocity_error(&flow.cellwise, s * first)?;
        }
        let (velocity_error, gradient_error) = velocity_errors(&flow.blended, &wall_layer_points(first))?;
        let (half_cell_velocity_error, half_cell_gradient_error) = half_cell_errors(&flow.blended, first)?;
        Ok(Self {
            layers,
            level,
            cells: flow.cellwise.mesh().n_cells(),
            first_cell: first,
            normal_error,
            cellwise_normal_error,
            coefficient_ratio: coefficient_ratio(&flow.blended, first / 100.0)?,
            velocity_error,
            gradient_error,
            half_cell_velocity_error,
            half_cell_gradient_error,
        })
    }
}

/// Which error an observed order is of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Measure {
    /// [`WallLayerRow::velocity_error`].
    Velocity,
    /// [`WallLayerRow::gradient_error`].
    Gradient,
    /// [`WallLayerRow::half_cell_gradient_error`].
    HalfCellGradient,
}

impl Measure {
    fn of(self, row: &WallLayerRow) -> f64 {
        match self {
            Self::Velocity => row.velocity_error,
            Self::Gradient => row.gradient_error,
            Self::HalfCellGradient => row.half_cell_gradient_error,
        }
    }
}

/// Observed order p = ln(e₋/e)/ln(δ₁₋/δ₁) of `measure` from the previous level of the same
/// layering in `rows` (ordered by level within a layering), `None` on a coarsest level.
pub fn observed_order(rows: &[WallLayerRow], i: usize, measure: Measure) -> Option<f64> {
    let (row, previous) = (&rows[i], rows[..i].iter().rev().find(|r| r.layers == rows[i].layers)?);
    Some((measure.of(previous) / measure.of(row)).ln() / (previous.first_cell / row.first_cell).ln())
}

/// The least-squares slope of ln e against ln δ₁ over every level of `layers` in `rows`: the
/// order over the whole refinement, `None` with fewer than two levels. The max-norm error is
/// taken over cells that are not exactly similar from level to level (snapping's smoothing
/// runs a fixed number of sweeps), which moves the step-to-step orders by a few tenths; the
/// fit averages over the steps.
pub fn fitted_order(rows: &[WallLayerRow], layers: usize, measure: Measure) -> Option<f64> {
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.layers == layers)
        .map(|r| (r.first_cell.ln(), measure.of(r).ln()))
        .collect();
    least_squares_slope(&pts)
}

/// The dataset: one row per mesh, numbers with `digits` significant digits (the observed orders
/// with two decimals: from the previous level, and on a layering's finest row fitted over all
/// its levels), errors below 10⁻¹⁰ written 0: they are round-off, of the cellwise field
/// at a centre, where it holds the exact value.
pub fn wall_layer_table(rows: &[WallLayerRow], digits: usize) -> Result<Csv, OutputError> {
    let mut csv = Csv::new(&[
        "layers",
        "level",
        "cells",
        "first_cell",
        "un_error_0.1",
        "un_error_0.25",
        "un_error_0.5",
        "un_error_0.75",
        "un_error_cellwise_0.1",
        "un_error_cellwise_0.25",
        "un_error_cellwise_0.5",
        "un_error_cellwise_0.75",
        "un_over_delta2_ratio",
        "u_error",
        "grad_u_error",
        "order_u",
        "order_grad_u",
        "order_u_fit",
        "order_grad_u_fit",
    ]);
    let g = |v: f64| {
        if v.abs() < 1e-10 {
            "0".to_string()
        } else {
            format!("{v:.*e}", digits.saturating_sub(1))
        }
    };
    for (i, r) in rows.iter().enumerate() {
        let mut fields = vec![
            r.layers.to_string(),
            r.level.to_string(),
            r.cells.to_string(),
            g(r.first_cell),
        ];
        fields.extend(r.normal_error.iter().chain(&r.cellwise_normal_error).map(|&e| g(e)));
        fields.extend([g(r.coefficient_ratio), g(r.velocity_error), g(r.gradient_error)]);
        let finest = rows.get(i + 1).is_none_or(|next| next.layers != r.layers);
        let order = |p: Option<f64>| p.map_or_else(String::new, |p| format!("{p:.2}"));
        for measure in [Measure::Velocity, Measure::Gradient] {
            fields.push(order(observed_order(rows, i, measure)));
        }
        for measure in [Measure::Velocity, Measure::Gradient] {
            fields.push(order(fitted_order(rows, r.layers, measure).filter(|_| finest)));
        }
        csv.push(fields)?;
    }
    Ok(csv)
}

/// One row of the near-wall convergence dataset `paper-figures/near-wall/gradient_order.csv`:
/// an exact flow on one mesh, its u and ∇u errors at half the first cell's height relative to
/// the exact field's maxima.
#[derive(Debug, Clone, PartialEq)]
pub struct OrderRow {
    /// The exact flow: `hiemenz` or `taylor_couette`.
    pub case: &'static str,
    /// Prism layers asked of snappyHexMesh.
    pub layers: usize,
    /// Refinement level.
    pub level: u32,
    /// First cell's height δ₁.
    pub first_cell_height: f64,
    /// Largest |u| error at δ₁/2, relative.
    pub u_rel_err: f64,
    /// Largest |∇u| error at δ₁/2, relative.
    pub grad_rel_err: f64,
}

impl From<&WallLayerRow> for OrderRow {
    fn from(r: &WallLayerRow) -> Self {
        Self {
            case: "hiemenz",
            layers: r.layers,
            level: r.level,
            first_cell_height: r.first_cell,
            u_rel_err: r.half_cell_velocity_error,
            grad_rel_err: r.half_cell_gradient_error,
        }
    }
}

/// The dataset `gradient_order.csv`: `case,layers,level,first_cell_height,u_rel_err,grad_rel_err`,
/// numbers with `digits` significant digits.
pub fn gradient_order_table(rows: &[OrderRow], digits: usize) -> Result<Csv, OutputError> {
    let mut csv = Csv::new(&[
        "case",
        "layers",
        "level",
        "first_cell_height",
        "u_rel_err",
        "grad_rel_err",
    ]);
    let g = |v: f64| format!("{v:.*e}", digits.saturating_sub(1));
    for r in rows {
        csv.push(vec![
            r.case.into(),
            r.layers.to_string(),
            r.level.to_string(),
            g(r.first_cell_height),
            g(r.u_rel_err),
            g(r.grad_rel_err),
        ])?;
    }
    Ok(csv)
}

/// The least-squares slope of ln e against ln δ₁ over the rows of one case and layering, for
/// the velocity (`gradient` false) or the gradient error; `None` with fewer than two rows.
pub fn order_row_slope(rows: &[OrderRow], case: &str, layers: usize, gradient: bool) -> Option<f64> {
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.case == case && r.layers == layers)
        .map(|r| {
            (
                r.first_cell_height.ln(),
                if gradient { r.grad_rel_err } else { r.u_rel_err }.ln(),
            )
        })
        .collect();
    least_squares_slope(&pts)
}

/// Slope of the least-squares line through `pts`, `None` with fewer than two points.
fn least_squares_slope(pts: &[(f64, f64)]) -> Option<f64> {
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    Some(sxy / sxx)
}

/// The |u| error against δ₁ beside a slope-2 guide, and the normal-velocity error at a
/// quarter of the first cell, blended and cellwise (log₁₀ axes), one series per layering.
#[cfg(feature = "plot")]
pub fn wall_layer_figure(rows: &[WallLayerRow]) -> crate::output::plot::Figure {
    use crate::output::plot::{Figure, Panel, Series};
    let mut layerings: Vec<usize> = rows.iter().map(|r| r.layers).collect();
    layerings.dedup();
    let mut velocity = Panel::new(
        "Hiemenz flow on snappyHexMesh meshes: wall-layer error",
        "log10 first-cell height",
        "log10 max |u| error (δ ≤ 2 first cells)",
    );
    let mut normal = Panel::new(
        "Normal velocity at a quarter of the first cell",
        "log10 first-cell height",
        "log10 relative error of u_n",
    );
    for (colour, &n) in layerings.iter().enumerate() {
        let of = |value: &dyn Fn(&WallLayerRow) -> f64| -> Vec<(f64, f64)> {
            rows.iter()
                .filter(|r| r.layers == n)
                .map(|r| (r.first_cell.log10(), value(r).log10()))
                .collect()
        };
        let label = format!("{n} layers");
        velocity = velocity.with(Series::points(label.clone(), of(&|r| r.velocity_error), colour));
        normal = normal
            .with(Series::points(
                format!("{label}, blended"),
                of(&|r| r.normal_error[1]),
                colour,
            ))
            .with(Series::line(
                format!("{label}, cellwise"),
                of(&|r| r.cellwise_normal_error[1]),
                colour,
            ));
    }
    // Through the first row, over the rows' range of δ₁.
    if let Some(a) = rows.first() {
        let through = |h: f64| (h.log10(), (a.velocity_error * (h / a.first_cell).powi(2)).log10());
        let finest = rows.iter().map(|r| r.first_cell).fold(a.first_cell, f64::min);
        velocity = velocity.with(Series::line(
            "slope 2",
            vec![through(a.first_cell), through(finest)],
            layerings.len(),
        ));
    }
    Figure::grid(vec![velocity, normal], 2, (640, 480))
}

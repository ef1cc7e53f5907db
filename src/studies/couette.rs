//! Circular Couette (Taylor–Couette) flow written into snappyHexMesh meshes of the annulus
//! between two cylinders (`cases/taylor-couette`): the wall layer at a rotating curved wall
//! against the exact solution (issue 37).
//!
//! # Physics
//! Between the cylinders r = [`INNER`] (rotating at Ω = [`OMEGA`] about z) and r = [`OUTER`]
//! (at rest) the steady Navier–Stokes solution is the rotation u = ω(r) e_z × x with
//! ```math
//! ω(r) = A + \frac{B}{r^2},\qquad A = −\frac{Ω R_1^2}{R_2^2 − R_1^2},\qquad B = \frac{Ω R_1^2 R_2^2}{R_2^2 − R_1^2},
//! ```
//! at any Reynolds number below the Taylor instability (it has no inertia term to balance:
//! the pressure takes the centripetal part). It is written at the cell and boundary-face
//! centres as a solver holds it, so the rotating inner cylinder's faces carry Ω e_z × x_f
//! (to the O(h²) by which the face centres lie off the cylinder). That O(h²) is the shear times
//! the face centre's depth under the cylinder, which varies from face to face with the snapped
//! faces' widths: the wall fit reads it as a deforming wall, whose surface gradient W (and
//! a = −tr W) is O(h), a first-order error of ∂u_r/∂r and ∂u_θ/(r∂θ) at the wall that no
//! solver field on a rigidly moving or resting wall has (`paper-figures/near-wall/NOTES.md`,
//! 2026-12-02). Writing the rigid motion there instead is worse: the exact cell values then
//! disagree with the faceted no-slip wall by the same shear times depth, an O(h²/ρ) error of
//! the wall shear. The measures: u and ∇u at
//! half the first cell's height over the inner cylinder (60 points around it, mid-depth),
//! relative to the exact field's largest |u| (Ω R₁ = 1) and |∇u| ([`GRAD_MAX`]).

use crate::error::FlowError;
use crate::flow::FlowField;
use crate::flow::openfoam::{BlendedFlow, FoamError, FoamFlow, PolyMesh, VolField};
use crate::studies::stagnation::{OrderRow, first_cell_height};
use crate::tensor::{Mat3, Vec3};
use std::path::Path;

/// Radius of the rotating inner cylinder.
pub const INNER: f64 = 1.0;
/// Radius of the outer cylinder, at rest.
pub const OUTER: f64 = 2.0;
/// Angular velocity of the inner cylinder.
pub const OMEGA: f64 = 1.0;
/// Largest |∇u| (max norm) of the exact field: on the inner wall, where the components of ∇u
/// along the axes reach |ω + r ω′| = |A − B/R₁²| = 5/3 (the shear, with rω′ = −2B/r² = −8/3,
/// less the rotation ω = 1) and fall off with r.
pub const GRAD_MAX: f64 = 5.0 / 3.0;

/// A and B of ω(r) = A + B/r².
fn coefficients() -> (f64, f64) {
    let d = OUTER * OUTER - INNER * INNER;
    (-OMEGA * INNER * INNER / d, OMEGA * INNER * INNER * OUTER * OUTER / d)
}

/// The exact u and ∇u (∂u_i/∂x_j) at x.
pub fn exact(x: &Vec3) -> (Vec3, Mat3) {
    let (a, b) = coefficients();
    let r2 = x[0] * x[0] + x[1] * x[1];
    let omega = a + b / r2;
    // ∂ω/∂x_j = −2B x_j / r⁴.
    let d = -2.0 * b / (r2 * r2);
    let u = Vec3::new(-omega * x[1], omega * x[0], 0.0);
    let g = Mat3::new(
        -d * x[1] * x[0],
        -omega - d * x[1] * x[1],
        0.0,
        omega + d * x[0] * x[0],
        d * x[0] * x[1],
        0.0,
        0.0,
        0.0,
        0.0,
    );
    (u, g)
}

/// The exact field written into a meshed annulus: the cellwise and blended fields and the
/// first cell's height over the inner cylinder.
#[derive(Debug, Clone)]
pub struct CouetteAnnulus {
    /// Cellwise linear fits of the cell-centre values.
    pub cellwise: FoamFlow,
    /// The same with the wall layer.
    pub blended: BlendedFlow,
    /// Mean height δ₁ of the cells on the inner cylinder: V/A of each.
    pub first_cell: f64,
}

impl CouetteAnnulus {
    /// The exact field at the cell and boundary-face centres of `mesh`, whose `wall` patches
    /// include faces on the inner cylinder (within 1 % of its radius).
    pub fn new(mesh: PolyMesh) -> Result<Self, FoamError> {
        let first_cell =
            first_cell_height(&mesh, |x| (x[0].hypot(x[1]) - INNER).abs() < 0.01 * INNER).ok_or_else(|| {
                FoamError::Mesh {
                    reason: format!("no wall face on the inner cylinder r = {INNER}"),
                }
            })?;
        let field = VolField::from_fn(&mesh, |x| exact(x).0);
        let cellwise = FoamFlow::new(mesh, vec![(0.0, field)])?;
        let blended = BlendedFlow::new(cellwise.clone())?;
        Ok(Self {
            cellwise,
            blended,
            first_cell,
        })
    }

    /// The annulus of an OpenFOAM case's `constant/polyMesh` (`cases/taylor-couette/Allmesh`).
    pub fn read(case: &Path) -> Result<Self, FoamError> {
        Self::new(PolyMesh::read(case)?)
    }
}

/// Largest |u − u_exact| and |∇u − ∇u_exact| of `flow` at half the first cell's height over
/// the inner cylinder, relative to Ω R₁ and [`GRAD_MAX`] ([`errors_at`]).
pub fn half_cell_errors(flow: &dyn FlowField, first_cell: f64) -> Result<(f64, f64), FlowError> {
    errors_at(flow, 0.5 * first_cell)
}

/// Largest |u − u_exact| and |∇u − ∇u_exact| of `flow` at `height` over the inner cylinder (60
/// points evenly around it, at z = 0.1), relative to Ω R₁ and [`GRAD_MAX`].
pub fn errors_at(flow: &dyn FlowField, height: f64) -> Result<(f64, f64), FlowError> {
    let r = INNER + height;
    (0..60).try_fold((0.0f64, 0.0f64), |(eu, eg), i| {
        let theta = std::f64::consts::TAU * (i as f64 + 0.25) / 60.0;
        let x = Vec3::new(r * theta.cos(), r * theta.sin(), 0.1);
        let (s, (u, g)) = (flow.sample(&x, 0.0)?, exact(&x));
        Ok((
            eu.max((s.u - u).amax() / (OMEGA * INNER)),
            eg.max((s.grad_u - g).amax() / GRAD_MAX),
        ))
    })
}

/// Heights over the inner cylinder, in first-cell heights δ₁, at which
/// [`blend_against_cellwise`] compares the two fields: through the first two cells.
pub const BAND: [f64; 7] = [0.1, 0.25, 0.5, 0.75, 1.0, 1.5, 2.0];

/// The largest relative ∇u error over the inner cylinder at one height `fraction` δ₁: the
/// blended field's and the cellwise fits'.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BandError {
    /// Height over the inner cylinder in first-cell heights.
    pub fraction: f64,
    /// Largest |∇u − ∇u_exact| / [`GRAD_MAX`] of the blended field (60 points).
    pub blended: f64,
    /// The same of the cellwise fits.
    pub cellwise: f64,
}

/// The ∇u errors of the blended field and of the cellwise fits at each height of [`BAND`]
/// (each the largest over 60 points around the inner cylinder, [`errors_at`]): the
/// wall layer replaces the cellwise fits there, so it should be no worse at any of them.
pub fn blend_against_cellwise(annulus: &CouetteAnnulus) -> Result<Vec<BandError>, FlowError> {
    BAND.iter()
        .map(|&fraction| {
            let height = fraction * annulus.first_cell;
            Ok(BandError {
                fraction,
                blended: errors_at(&annulus.blended, height)?.1,
                cellwise: errors_at(&annulus.cellwise, height)?.1,
            })
        })
        .collect()
}

/// The dataset row of `annulus`, a mesh with `layers` prism layers at refinement `level`.
pub fn order_row(layers: usize, level: u32, annulus: &CouetteAnnulus) -> Result<OrderRow, FlowError> {
    let (u_rel_err, grad_rel_err) = half_cell_errors(&annulus.blended, annulus.first_cell)?;
    Ok(OrderRow {
        case: "taylor_couette",
        layers,
        level,
        first_cell_height: annulus.first_cell,
        u_rel_err,
        grad_rel_err,
    })
}

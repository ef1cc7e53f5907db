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
//! the pressure takes the centripetal part). The measures: u and ∇u at half the first cell's
//! height over the inner cylinder (60 points around it, mid-depth), relative to the exact
//! field's largest |u| (Ω R₁ = 1) and |∇u| ([`GRAD_MAX`]).
//!
//! # What the exact field can verify on a snapped wall
//! The field is written at the cell centres and at the boundary-face centres. The snapped
//! inner wall is faceted: its face centres lie $σ_f = R_1 − r_f$ inside the cylinder
//! (1.2–3.8·10⁻³ at level 0, 0.9–1.2·10⁻⁴ at level 2), outside the flow, by amounts that vary
//! from face to face with the faces' widths. The wall fit takes the facets as the no-slip wall
//! ([`crate::flow::openfoam::wall_layer`]), and no choice of wall values makes the smooth
//! solution data of that wall. Writing the shear part as $f(r) e_θ$ with $f = (ω − Ω) r$,
//! f(R₁) = 0, f′(R₁) = −8/3:
//! - *the exact field at the face centres* (what is written): the shear part vanishes on the
//!   facets, as the fit assumes, but the wall velocity is the rotation plus $f(r_f) e_θ$, a
//!   non-rigid velocity of size (8/3)σ_f that changes by O(h²) from face to face: a surface
//!   gradient W = O(h), which the fit must take as the wall's own deformation (it is exact
//!   for deforming and transpiring walls), and a trace-free O(h) error of ∂u_r/∂r and
//!   ∂u_θ/(r∂θ);
//! - *the rigid motion at the face centres* (what a solver's `rotatingWallVelocity` holds):
//!   W is rigid, but the exact cell values are those of a wall σ_f above the facet, so the
//!   shear is off by σ_f/ρ, O(h), and O(1) in thin layers (σ_f/ρ up to 0.75 at level 0 with
//!   5 layers; ∇u at half the first cell 0.37, 0.12, 0.065 of |∇u|max,
//!   `paper-figures/near-wall/NOTES.md`, What it shows);
//! - *the exact field at the face's point on the cylinder*, where the solution is defined:
//!   $Ω R_1 e_θ$ is not rigid at the face centres either (by Ω σ_f), so both defects remain,
//!   each smaller.
//!
//! A solver's field on the faceted mesh is the solution of the faceted problem, which differs
//! from the smooth one by O(σ) in u and, within a face width of the wall, by O(σ/h) = O(h) in
//! ∇u: what the smooth solution verifies at half the first cell is bounded by that, whatever
//! the fit. So the check keeps the first choice, the only one whose shear part is consistent
//! with the facets, and splits ∇u's error ([`component_errors_at`]): the shear pair
//! ∂u_θ/∂r, ∂u_r/(r∂θ), which the data's non-rigid wall velocity does not reach where the wall
//! cells' centres stand over their faces' centres (its W has e_θ rows only and enters u at
//! the centres as W s_f; the prism layers' centres lie within 4·10⁻⁵ of the normal through
//! their faces' centres), and the stretch pair ∂u_r/∂r, ∂u_θ/(r∂θ), which carries it. The fit
//! itself is second order where the data are consistent: on the quarter annuli of the suite
//! (uniform faces, equal σ_f, so the face values are a rigid rotation) ∇u at half the first
//! cell is asserted second order, and on the snapped annuli with W taken from the rigid
//! rotation's values (a temporary edit, `paper-figures/near-wall/NOTES.md`) the orders are
//! 1.40, 1.77 and 2.93 with 0, 2 and 5 layers.

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

/// The largest errors of ∇u's polar components at `height` over the inner cylinder (the 60
/// points of [`errors_at`]), relative to [`GRAD_MAX`] (module docs, What the exact field can
/// verify).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ComponentErrors {
    /// Of the shear pair ∂u_θ/∂r and ∂u_r/(r∂θ).
    pub shear: f64,
    /// Of the stretch pair ∂u_r/∂r and ∂u_θ/(r∂θ), where the data's non-rigid wall velocity
    /// enters.
    pub stretch: f64,
}

/// The largest errors of `flow`'s ∇u at `height` over the inner cylinder, split into the shear
/// and stretch components ([`ComponentErrors`]).
pub fn component_errors_at(flow: &dyn FlowField, height: f64) -> Result<ComponentErrors, FlowError> {
    let r = INNER + height;
    let start = ComponentErrors {
        shear: 0.0,
        stretch: 0.0,
    };
    (0..60).try_fold(start, |worst, i| {
        let theta = std::f64::consts::TAU * (i as f64 + 0.25) / 60.0;
        let x = Vec3::new(r * theta.cos(), r * theta.sin(), 0.1);
        let e = flow.sample(&x, 0.0)?.grad_u - exact(&x).1;
        let (radial, azimuthal) = (
            Vec3::new(theta.cos(), theta.sin(), 0.0),
            Vec3::new(-theta.sin(), theta.cos(), 0.0),
        );
        let part = |a: &Vec3, b: &Vec3| a.dot(&(e * b)).abs() / GRAD_MAX;
        Ok(ComponentErrors {
            shear: worst
                .shear
                .max(part(&azimuthal, &radial))
                .max(part(&radial, &azimuthal)),
            stretch: worst
                .stretch
                .max(part(&radial, &radial))
                .max(part(&azimuthal, &azimuthal)),
        })
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flow::FlowSample;

    /// The exact field with a constant matrix added to its gradient.
    struct Perturbed(Mat3);

    impl FlowField for Perturbed {
        fn sample(&self, x: &Vec3, _t: f64) -> Result<FlowSample, FlowError> {
            let (u, g) = exact(x);
            Ok(FlowSample::steady(u, g + self.0))
        }
    }

    /// An isotropic error p I is all stretch at every angle, a rotation p (e_x e_yᵀ − e_y e_xᵀ)
    /// all shear (e_θᵀ P e_r = −p): the split is exact up to round-off in the polar basis.
    #[test]
    fn component_errors_split_stretch_from_shear() {
        let p = 0.25;
        let stretch = component_errors_at(&Perturbed(Mat3::identity() * p), 0.1).unwrap();
        let rotation = Mat3::new(0.0, p, 0.0, -p, 0.0, 0.0, 0.0, 0.0, 0.0);
        let shear = component_errors_at(&Perturbed(rotation), 0.1).unwrap();
        let want = p / GRAD_MAX;
        for (got, want) in [
            (stretch.stretch, want),
            (stretch.shear, 0.0),
            (shear.shear, want),
            (shear.stretch, 0.0),
        ] {
            assert!((got - want).abs() < 1e-15, "{got} against {want}");
        }
    }
}

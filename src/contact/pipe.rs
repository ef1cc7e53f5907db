//! Contact of the ellipsoid with the pipe wall (deposition test).
//!
//! # Physics
//! The current ellipsoid has semi-axes r_a along the principal directions n_a (rows of Q,
//! [`crate::ellipsoid::PrincipalFrame`]). Its extent from the barycentre along a unit vector n is
//! the support distance
//! $h(n) = \sqrt{\sum_a r_a^2 (n·n_a)^2} = \sqrt{n·\bar b\\, n}$, $\bar b = \bar F \bar F^T$.
//! For a pipe of radius R along e₁, the outward wall normal at the particle is the radial
//! direction n = x_⊥/|x_⊥| (x_⊥ the part of x_c normal to the axis), and the particle touches the
//! wall when the gap
//! $g = R − |x_⊥| − h(n) ≤ 0$.
//! This treats the wall as its tangent plane at the foot of the barycentre; the curvature error
//! is O(h²/R), below 10⁻⁵ d_eq for the Tian/Cui particles (h ≤ r₁ ≈ 3 d_eq, R ≈ 870 d_eq).
//! On the axis (x_⊥ = 0) every radial direction is a normal, and the gap uses the largest
//! support over them, √(largest eigenvalue of the cross-sectional block of b̄).

use super::{Boundary, Extent, Gap, PatchRule};
use crate::ellipsoid::PrincipalFrame;
use crate::error::{ParamError, positive};
use crate::tensor::{Mat3, Vec3};

/// The wall of an infinite pipe of radius R along e₁ (one patch, `wall`, [`PatchRule::Stick`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PipeWall {
    radius: f64,
}

impl PipeWall {
    /// Pipe of radius `radius` (finite, > 0).
    pub fn new(radius: f64) -> Result<Self, ParamError> {
        Ok(Self {
            radius: positive("pipe radius", radius)?,
        })
    }
}

impl Boundary for PipeWall {
    fn nearest(&self, x: &Vec3, extent: &Extent) -> Gap {
        let x_perp = Vec3::new(0.0, x[1], x[2]);
        let gap = match extent {
            Extent::Ellipsoid(frame) => wall_gap(self.radius, x, frame),
            Extent::Point { radius } => self.radius - x_perp.norm() - radius,
        };
        // On the axis every radial direction is a normal; the gap does not depend on it there.
        let normal = x_perp.try_normalize(0.0).unwrap_or_else(Vec3::y);
        Gap {
            patch: 0,
            gap,
            normal,
            room: 0.0,
        }
    }

    fn patch_name(&self, _patch: usize) -> &str {
        "wall"
    }

    fn rule(&self, _patch: usize) -> PatchRule {
        PatchRule::Stick
    }
}

/// Wall gap g = R − |x_⊥| − h(n) of an ellipsoid in `frame` centred at `x` in a pipe of radius
/// `radius` whose axis is e₁; g ≤ 0 means contact.
pub fn wall_gap(radius: f64, x: &Vec3, frame: &PrincipalFrame) -> f64 {
    let x_perp = Vec3::new(0.0, x[1], x[2]);
    let distance = x_perp.norm();
    if distance > 0.0 {
        radius - distance - frame.support_distance(&(x_perp / distance))
    } else {
        radius - largest_cross_section_support(frame)
    }
}

/// max over unit n ⊥ e₁ of h(n): the square root of the larger eigenvalue of the (2,3) block
/// of b̄ = Qᵀ diag(r²) Q.
fn largest_cross_section_support(frame: &PrincipalFrame) -> f64 {
    let b = frame.to_global(&Mat3::from_diagonal(&frame.r.component_mul(&frame.r)));
    let (p, q, s) = (b[(1, 1)], b[(2, 2)], b[(1, 2)]);
    let mean = 0.5 * (p + q);
    let radius = (0.25 * (p - q) * (p - q) + s * s).sqrt();
    (mean + radius).sqrt()
}

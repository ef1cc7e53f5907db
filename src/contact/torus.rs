//! Contact of the ellipsoid with the wall of a bent pipe: a torus of tube radius a around the
//! circle of radius R_b in the plane x₃ = 0 (a pipe bend without its straight ends).
//!
//! # Physics
//! The tube's centreline point nearest to x is $c = R_b (\cos\phi, \sin\phi, 0)$ with φ the
//! azimuth of x, so the outward wall normal at the particle is n = (x − c)/|x − c| and, as for
//! the straight pipe ([`super::pipe`]), the gap is
//! $g = a − |x − c| − h(n)$ with h the support distance of the particle's extent along n. The
//! wall is taken as its tangent plane at the foot of the barycentre: the curvature error is
//! O(h²/a) as in the straight pipe, and O(h²/R_b) along the bend.

use super::{Boundary, Extent, Gap, PatchRule};
use crate::error::{ParamError, positive};
use crate::tensor::Vec3;

/// The wall of a torus of tube radius a around the circle of radius R_b > a in x₃ = 0 (one
/// patch, `wall`, [`PatchRule::Stick`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TorusWall {
    bend_radius: f64,
    tube_radius: f64,
}

impl TorusWall {
    /// A bend of centreline radius `bend_radius` and tube radius `tube_radius` (both finite,
    /// positive, the tube thinner than the bend).
    pub fn new(bend_radius: f64, tube_radius: f64) -> Result<Self, ParamError> {
        let bend_radius = positive("bend radius", bend_radius)?;
        let tube_radius = positive("tube radius", tube_radius)?;
        if tube_radius >= bend_radius {
            return Err(ParamError::OutOfRange {
                name: "tube radius (below the bend radius)",
                value: tube_radius,
                min: 0.0,
                max: bend_radius,
            });
        }
        Ok(Self {
            bend_radius,
            tube_radius,
        })
    }

    /// The centreline point nearest to x (the +x₁ one on the torus' axis).
    fn centreline(&self, x: &Vec3) -> Vec3 {
        let radial = Vec3::new(x[0], x[1], 0.0).try_normalize(0.0).unwrap_or_else(Vec3::x);
        radial * self.bend_radius
    }
}

impl Boundary for TorusWall {
    fn nearest(&self, x: &Vec3, extent: &Extent) -> Gap {
        let away = x - self.centreline(x);
        let distance = away.norm();
        // On the centreline every direction across the tube is a normal; take the bend's.
        let normal = away
            .try_normalize(0.0)
            .unwrap_or_else(|| self.centreline(x) / self.bend_radius);
        let reach = match extent {
            Extent::Ellipsoid(frame) => frame.support_distance(&normal),
            Extent::Point { radius } => *radius,
        };
        Gap {
            patch: 0,
            gap: self.tube_radius - distance - reach,
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

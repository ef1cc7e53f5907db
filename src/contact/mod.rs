//! Boundaries a particle can touch, and wall contact as a driver event.
//!
//! # Physics
//! A particle is an ellipsoid with barycentre x_c, semi-axes r_a and rotation Q (rows n_a). Its
//! extent along a unit vector n is the support distance
//! $h(n) = \sqrt{\sum_a r_a^2 (n·n_a)^2} = \sqrt{n·\bar b\\,n}$ with $\bar b = \bar F\bar F^T$
//! ([`crate::ellipsoid::frame::support_distance`]); a point particle of contact radius δ has
//! h(n) = δ. It touches a boundary patch with outward normal n at distance d from x_c when the
//! gap g = d − h(n) ≤ 0. Each patch carries a rule: the particle deposits ([`PatchRule::Stick`])
//! or leaves the domain ([`PatchRule::Exit`]).
//!
//! [`ContactEvent`] (in [`event`]) makes a boundary a terminal event of the driver.

pub mod composite;
pub mod event;
#[cfg(feature = "mesh")]
pub mod mesh;
pub mod pipe;
pub mod planes;
pub mod torus;

pub use composite::Composite;
pub use event::{ContactEvent, ContactModel};
#[cfg(feature = "mesh")]
pub use mesh::{FaceGap, MeshBoundary, PatchGap};
pub use pipe::PipeWall;
pub use planes::{Plane, Planes};
pub use torus::TorusWall;

use crate::ellipsoid::PrincipalFrame;
use crate::tensor::Vec3;
use serde::{Deserialize, Serialize};

/// What happens to a particle that touches a patch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum PatchRule {
    /// The particle leaves the domain through this patch.
    Exit,
    /// The particle deposits (sticks) on this patch.
    Stick,
}

/// The extent of a particle seen by a boundary.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Extent {
    /// The current ellipsoid (physical contact).
    Ellipsoid(PrincipalFrame),
    /// A point particle that touches at a fixed distance δ (a point-particle tracker's rule).
    Point {
        /// Contact distance δ.
        radius: f64,
    },
}

impl Extent {
    /// Support distance h(n) along the unit vector `n`.
    pub fn support(&self, n: &Vec3) -> f64 {
        match self {
            Extent::Ellipsoid(frame) => frame.support_distance(n),
            Extent::Point { radius } => *radius,
        }
    }
}

/// The nearest patch and the gap to it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gap {
    /// Index of the patch (as [`Boundary::patch_name`] and [`Boundary::rule`] take it).
    pub patch: usize,
    /// g = d − h(n); negative: overlap depth.
    pub gap: f64,
    /// Outward unit normal n of the patch where the gap is measured.
    pub normal: Vec3,
    /// How far from the barycentre the walls are known to be shaped so that only the velocity
    /// along `normal` can close the gap within a step (an [`Approach::AnyDirection`]
    /// boundary's local [`Approach::Normal`]; [`ContactEvent`] explains the cap): within this
    /// distance every boundary face lies beyond the plane where the gap is measured, or the
    /// fluid's side of the boundary is convex. 0 where the boundary knows no such
    /// neighbourhood.
    pub room: f64,
}

/// Which velocity closes the gap to a boundary's patches within one step (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Approach {
    /// Only the velocity along the nearest patch's normal: one smooth wall, or planes whose
    /// corners the scene guards with its own step cap.
    Normal,
    /// The full speed: corners and ridges, where moving along the nearest patch can reach
    /// another one (mesh walls).
    AnyDirection,
}

/// A boundary made of patches: planar walls, a pipe wall, mesh patches.
pub trait Boundary: Send + Sync {
    /// The patch with the smallest gap to a particle centred at `x` with `extent`.
    fn nearest(&self, x: &Vec3, extent: &Extent) -> Gap;

    /// Name of patch `patch` (for reports).
    fn patch_name(&self, patch: usize) -> &str;

    /// Rule of patch `patch`.
    fn rule(&self, patch: usize) -> PatchRule;

    /// Which velocity closes the gap within a step; [`Approach::Normal`] unless the boundary
    /// has corners or ridges the scene does not guard.
    fn approach(&self) -> Approach {
        Approach::Normal
    }

    /// A lower bound c > 0 of the distance from x to the boundary's faces, where the boundary
    /// knows one without a query: an extent reaching at most R from x is then at least c − R
    /// from them ([`ContactEvent`] skips its query with it). `None` (the default) where it does
    /// not.
    fn clearance(&self, _x: &Vec3) -> Option<f64> {
        None
    }
}

/// No boundary at all: the unbounded linear flows of the shear scenes. Every gap is +∞, so a
/// contact event never fires and a wall-distance ratio is 0.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Unbounded;

impl Boundary for Unbounded {
    fn nearest(&self, _x: &Vec3, _extent: &Extent) -> Gap {
        Gap {
            patch: 0,
            gap: f64::INFINITY,
            normal: Vec3::zeros(),
            room: 0.0,
        }
    }

    fn patch_name(&self, _patch: usize) -> &str {
        "none"
    }

    fn rule(&self, _patch: usize) -> PatchRule {
        PatchRule::Stick
    }
}

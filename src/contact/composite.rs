//! A boundary with planar patches added: outlet or inlet planes that cut an open boundary
//! (a pipe wall, a mesh's walls) to a finite domain.
//!
//! # Physics
//! Each plane w bounds the half-space $\\{x : (x − p_w)·n_w ≤ 0\\}$; its gap is
//! $g_w = (p_w − x_c)·n_w − h(n_w)$ as for [`Planes`]. The composite's gap is the smaller of
//! the planes' and the other boundary's, so the particle touches whichever it reaches first.

use super::{Approach, Boundary, Extent, Gap, PatchRule, Planes};

/// Planar patches `planes` (indices 0..P, P = number of planes) added to `rest` (its patch p
/// becomes P + p).
#[derive(Debug, Clone, PartialEq)]
pub struct Composite<B> {
    planes: Planes,
    rest: B,
}

impl<B: Boundary> Composite<B> {
    /// `planes` added to `rest`.
    pub fn new(planes: Planes, rest: B) -> Self {
        Self { planes, rest }
    }

    /// The planes.
    pub fn planes(&self) -> &Planes {
        &self.planes
    }

    /// The boundary the planes were added to.
    pub fn rest(&self) -> &B {
        &self.rest
    }

    fn plane_count(&self) -> usize {
        self.planes.walls().len()
    }
}

impl<B: Boundary> Boundary for Composite<B> {
    /// The nearer of the nearest plane and the nearest patch of the rest; a tie goes to the
    /// plane (an outlet decides before the wall it cuts). A NaN gap of either is passed on, so
    /// the driver reports it.
    fn nearest(&self, x: &crate::tensor::Vec3, extent: &Extent) -> Gap {
        let plane = self.planes.nearest(x, extent);
        let rest = self.rest.nearest(x, extent);
        if rest.gap < plane.gap || rest.gap.is_nan() {
            Gap {
                patch: rest.patch + self.plane_count(),
                ..rest
            }
        } else {
            plane
        }
    }

    fn patch_name(&self, patch: usize) -> &str {
        match patch.checked_sub(self.plane_count()) {
            None => self.planes.patch_name(patch),
            Some(p) => self.rest.patch_name(p),
        }
    }

    fn rule(&self, patch: usize) -> PatchRule {
        match patch.checked_sub(self.plane_count()) {
            None => self.planes.rule(patch),
            Some(p) => self.rest.rule(p),
        }
    }

    /// The rest's: the planes add only the edges where they cut it, and a particle there
    /// leaves or deposits at once.
    fn approach(&self) -> Approach {
        self.rest.approach()
    }

    /// The rest's clearance, capped by the planes' point gap (exact and cheap).
    fn clearance(&self, x: &crate::tensor::Vec3) -> Option<f64> {
        let plane = self.planes.nearest(x, &Extent::Point { radius: 0.0 }).gap;
        self.rest.clearance(x).map(|c| c.min(plane)).filter(|c| *c > 0.0)
    }
}

//! A convex domain bounded by planar walls (e.g. the lid-driven cavity of paper §6.3,
//! [`crate::studies::cavity::walls`]).
//!
//! # Physics
//! The domain is the intersection of half-spaces $\\{x : (x − p_w)·n_w ≤ 0\\}$, one per wall w
//! with outward unit normal $n_w$. The gap of a particle centred at x_c with support function h
//! is $g_w = (p_w − x_c)·n_w − h(n_w)$ ([`super`]).

use super::{Boundary, Extent, Gap, PatchRule};
use crate::error::ParamError;
use crate::tensor::Vec3;
use serde::{Deserialize, Serialize};

/// One planar wall.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Plane {
    /// Name (for reports), e.g. the OpenFOAM patch.
    pub name: String,
    /// A point on the wall plane.
    pub point: Vec3,
    /// Outward unit normal.
    pub normal: Vec3,
    /// Contact rule.
    pub rule: PatchRule,
}

/// The boundary of a convex domain bounded by planar walls.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Planes {
    walls: Vec<Plane>,
}

impl Planes {
    /// Boundary from at least one wall; normals are normalised and must be finite and non-zero,
    /// points finite.
    pub fn new(walls: Vec<Plane>) -> Result<Self, ParamError> {
        if walls.is_empty() {
            return Err(ParamError::NotPositive {
                name: "number of walls",
                value: 0.0,
            });
        }
        let walls = walls
            .into_iter()
            .map(|mut w| {
                let len = w.normal.norm();
                if !len.is_finite() || len <= 0.0 {
                    return Err(ParamError::NotPositive {
                        name: "wall normal length",
                        value: len,
                    });
                }
                if !w.point.iter().all(|c| c.is_finite()) {
                    return Err(ParamError::NonFinite {
                        name: "wall point",
                        value: w.point.amax(),
                    });
                }
                w.normal /= len;
                Ok(w)
            })
            .collect::<Result<_, _>>()?;
        Ok(Self { walls })
    }

    /// The walls.
    pub fn walls(&self) -> &[Plane] {
        &self.walls
    }

    /// Gap g_w to each wall (negative: overlap).
    pub fn gaps<'a>(&'a self, x: &'a Vec3, extent: &'a Extent) -> impl Iterator<Item = f64> + 'a {
        self.walls
            .iter()
            .map(move |w| (w.point - x).dot(&w.normal) - extent.support(&w.normal))
    }
}

impl Boundary for Planes {
    /// The smallest gap; on a tie (a particle equally near two walls, e.g. in the top corner of
    /// the cavity) the wall listed first wins, so the lid is decided before the side walls.
    fn nearest(&self, x: &Vec3, extent: &Extent) -> Gap {
        let mut best = Gap {
            patch: 0,
            gap: f64::INFINITY,
            normal: self.walls[0].normal,
            room: 0.0,
        };
        for (patch, gap) in self.gaps(x, extent).enumerate() {
            if gap < best.gap || gap.is_nan() {
                best = Gap {
                    patch,
                    gap,
                    normal: self.walls[patch].normal,
                    room: 0.0,
                };
                if gap.is_nan() {
                    break;
                }
            }
        }
        best
    }

    fn patch_name(&self, patch: usize) -> &str {
        &self.walls[patch].name
    }

    fn rule(&self, patch: usize) -> PatchRule {
        self.walls[patch].rule
    }
}

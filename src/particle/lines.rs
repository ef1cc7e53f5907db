//! Material lines through the initial semi-axis points (paper §6.1, Figs 3, 5, 6, 9).
//!
//! # Physics
//! The material point on initial semi-axis a sits at Ξ_a = R_a E′_a; in the current
//! configuration its position relative to the barycentre is ξ_a = F·Ξ_a = F·S·Ē_a. Its length
//! l_a = |ξ_a| distinguishes tumbling (l_a > l_c always) from trembling (l_c > l_a somewhere).

use crate::ellipsoid::Ellipsoid;
use crate::tensor::{Mat3, Vec3};

/// Current material line ξ_a = F·Ξ_a of initial semi-axis `a`.
pub fn material_line(shape: &Ellipsoid, f: &Mat3, a: usize) -> Vec3 {
    f * shape.axis_point(a)
}

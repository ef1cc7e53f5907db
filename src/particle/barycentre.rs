//! Barycentre dynamics (paper eqs. 17, 19).
//!
//! # Physics
//! m v̇_c = m a_G + μ_f K̂ (u − v_c), ẋ_c = v_c, with a_G = β_t g (eq. 13) and K̂ from the drag
//! model. 1/τ_D in eq. 17 is garbled in print; it reads μ_f π r_min/m (physics.md §3.4), i.e.
//! the drag acceleration is (μ_f/m) K̂ (u − v_c).

use crate::tensor::{Mat3, Vec3};

/// One implicit-Euler step of eq. 19 (exactly the paper's update):
/// (1 + Δt μ_f K̂/m) v^{n+1} = v^n + Δt a_G + Δt (μ_f K̂/m) u, then x^{n+1} = x^n + Δt v^{n+1}.
/// Returns (x^{n+1}, v^{n+1}), or `None` if the (positive-definite) system is singular.
pub fn implicit_euler(x: &Vec3, v: &Vec3, u: &Vec3, a_g: &Vec3, drag_rate: &Mat3, dt: f64) -> Option<(Vec3, Vec3)> {
    let lhs = Mat3::identity() + drag_rate * dt;
    let rhs = v + a_g * dt + drag_rate * u * dt;
    let v_new = lhs.lu().solve(&rhs)?;
    Some((x + v_new * dt, v_new))
}

/// Overdamped (St → 0) velocity: μ_f K̂ (u − v) + m a_G = 0 ⇒ v = u + (μ_f K̂/m)⁻¹ a_G.
pub fn overdamped_velocity(u: &Vec3, a_g: &Vec3, drag_rate: &Mat3) -> Option<Vec3> {
    Some(u + drag_rate.lu().solve(a_g)?)
}

//! Named proptest strategies: Haar-random rotations, log-normal-ish shapes, random flows.

use nalgebra::{Matrix3, Vector3};
use proptest::prelude::*;

/// Haar-distributed rotation: axis uniform on the sphere, independent of the angle θ, whose
/// density on [0, π] is (1 − cos θ)/π (the Haar measure of SO(3) in axis-angle form). θ comes
/// from a uniform u ∈ [0, 1) through the inverse of the CDF (θ − sin θ)/π. proptest shrinks u
/// towards 0, where θ = 0 exactly: shrinks to the identity whatever the axis (checked by
/// `strategies_shrink_as_documented` in tests/properties.rs).
pub fn rotation() -> impl Strategy<Value = Matrix3<f64>> {
    (0.0f64..1.0, -1.0f64..1.0, 0.0f64..1.0).prop_map(|(u, z, phi)| {
        let rho = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * std::f64::consts::PI * phi;
        let axis = nalgebra::Unit::new_normalize(Vector3::new(rho * phi.cos(), rho * phi.sin(), z));
        nalgebra::Rotation3::from_axis_angle(&axis, haar_angle(u)).into_inner()
    })
}

/// θ ∈ [0, π] with (θ − sin θ)/π = u, by bisection: the CDF is increasing, 64 halvings of
/// [0, π] reach f64 resolution, and u = 0 returns exactly 0 (the lower end never moves).
fn haar_angle(u: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, std::f64::consts::PI);
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if (mid - mid.sin()) / std::f64::consts::PI < u {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// A standard normal sample by Box–Muller, n = √(−2 ln(1 − u₁)) cos(2π u₂) with u₁, u₂
/// uniform on [0, 1): 1 − u₁ is uniform on (0, 1] like the textbook u₁, so the law is exact.
/// proptest shrinks a float range towards its lower bound, u₁ → 0, where the radius and hence
/// n is 0: shrinks to 0 (the former u₁ ∈ [10⁻¹², 1) shrank to the radius √(2·12 ln 10) = 7.43).
pub fn normal() -> impl Strategy<Value = f64> {
    (0.0f64..1.0, 0.0f64..1.0)
        .prop_map(|(u1, u2)| (-2.0 * (1.0 - u1).ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos())
}

/// Semi-axes with log-uniform ratios in [1/max_ratio, max_ratio] about 1 (shrinks to a sphere).
pub fn semi_axes(max_ratio: f64) -> impl Strategy<Value = [f64; 3]> {
    let l = max_ratio.ln();
    (-l..l, -l..l, -l..l).prop_map(|(a, b, c)| [a.exp(), b.exp(), c.exp()])
}

/// Random matrix with coefficients in [-s, s].
pub fn matrix(s: f64) -> impl Strategy<Value = Matrix3<f64>> {
    proptest::array::uniform9(-s..s).prop_map(|a| Matrix3::from_column_slice(&a))
}

/// Random traceless velocity gradient with coefficients of order s.
pub fn traceless(s: f64) -> impl Strategy<Value = Matrix3<f64>> {
    matrix(s).prop_map(|m| m - Matrix3::identity() * (m.trace() / 3.0))
}

/// Deformation gradient near identity: exp-like stretch-rotation, det > 0 guaranteed by
/// F = R · (1 + sym perturbation of size < 0.45) (eigenvalues in [0.55, 1.45]).
pub fn deformation() -> impl Strategy<Value = Matrix3<f64>> {
    (rotation(), matrix(0.15)).prop_map(|(r, m)| r * (Matrix3::identity() + (m + m.transpose()) * 0.5))
}

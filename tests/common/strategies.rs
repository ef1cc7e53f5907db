//! Named proptest strategies: Haar-random rotations, log-normal-ish shapes, random flows.

use nalgebra::{Matrix3, UnitQuaternion, Vector3, Vector4};
use proptest::prelude::*;

/// Haar-distributed rotation: a normalised 4-vector of independent normals is uniform on S³,
/// and the quaternion map pushes it to the Haar measure on SO(3). Shrinks towards identity.
pub fn rotation() -> impl Strategy<Value = Matrix3<f64>> {
    (normal(), normal(), normal(), normal()).prop_filter_map("degenerate quaternion", |(w, x, y, z)| {
        let v = Vector4::new(w + 1e-3, x, y, z);
        (v.norm() > 1e-6).then(|| {
            UnitQuaternion::from_quaternion(nalgebra::Quaternion::from_vector(v))
                .to_rotation_matrix()
                .into_inner()
        })
    })
}

/// A standard normal sample (Box–Muller on two uniforms); shrinks to 0.
pub fn normal() -> impl Strategy<Value = f64> {
    (1e-12f64..1.0, 0.0f64..1.0).prop_map(|(u1, u2)| {
        let n = (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos();
        if n.is_finite() { n } else { 0.0 }
    })
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

/// Random vector with coefficients in [-s, s].
pub fn vector(s: f64) -> impl Strategy<Value = Vector3<f64>> {
    proptest::array::uniform3(-s..s).prop_map(Vector3::from)
}

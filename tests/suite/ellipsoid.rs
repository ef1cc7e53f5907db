//! Geometry and Jeffery integrals (src/ellipsoid).
use crate::common;

use approx::assert_relative_eq;
use common::reference::integrals_by_quadrature;
use common::strategies;
use nalgebra::Matrix3;
use proptest::prelude::*;
use pseudorigid::ellipsoid::integrals::{carlson_rd, carlson_rf};
use pseudorigid::prelude::*;

/// Requirement of the issue: 1e-12 relative. Carlson's duplication leaves an O(δ⁶) ≈ 1e-20
/// truncation and ~10 ε of round-off; the exp-sinh reference converges to ~1e-15.
const INTEGRAL_RTOL: f64 = 1e-12;

#[test]
fn sphere_closed_forms() {
    for a in [0.5, 1.0, 2.7] {
        let ints = EllipsoidIntegrals::new(&Vec3::new(a, a, a));
        let a2 = a * a;
        let a3 = a2 * a;
        assert_relative_eq!(ints.chi0, 2.0 / a, max_relative = 1e-14);
        for i in 0..3 {
            assert_relative_eq!(ints.alpha[i], 2.0 / (3.0 * a3), max_relative = 1e-14);
            assert_relative_eq!(ints.alpha_p[i], 2.0 / (5.0 * a3 * a2), max_relative = 1e-14);
            assert_relative_eq!(ints.alpha_pp[i], 4.0 / (15.0 * a3), max_relative = 1e-14);
        }
    }
}

#[test]
fn carlson_special_values() {
    // R_F(x,x,x) = x^{-1/2}, R_D(x,x,x) = x^{-3/2}; R_F(0,1,2) = 1.3110287771461 (Carlson 1995 Table).
    assert_relative_eq!(carlson_rf(4.0, 4.0, 4.0).unwrap(), 0.5, max_relative = 1e-15);
    assert_relative_eq!(carlson_rd(4.0, 4.0, 4.0).unwrap(), 0.125, max_relative = 1e-15);
    assert_relative_eq!(
        carlson_rf(1e-300_f64.max(0.0), 1.0, 2.0).unwrap(),
        1.3110287771461,
        max_relative = 1e-12
    );
    assert_relative_eq!(
        carlson_rd(0.0, 2.0, 1.0).unwrap(),
        1.7972103521034,
        max_relative = 1e-12
    );
}

#[test]
fn carlson_matches_quadrature_on_hard_shapes() {
    let shapes = [
        [1.0, 1.0, 1.0],
        [1.0, 1.0 + 3e-6, 1.0 - 2e-6],
        [2.0, 1.0, 1.0],
        [1.0, 2.5, 2.5],
        [20.0, 1.0, 1.0],
        [1.0, 20.0, 20.0],
        [5.0, 4.0, 0.1],
        [3.0, 2.0, 1.0],
        [1.0, 1.0 + 1e-9, 1.0],
    ];
    for r in shapes {
        let ints = EllipsoidIntegrals::new(&Vec3::from(r));
        let (chi0, alpha, alpha_p, alpha_pp) = integrals_by_quadrature(r);
        assert_relative_eq!(ints.chi0, chi0, max_relative = INTEGRAL_RTOL);
        for i in 0..3 {
            assert_relative_eq!(ints.alpha[i], alpha[i], max_relative = INTEGRAL_RTOL);
            assert_relative_eq!(ints.alpha_p[i], alpha_p[i], max_relative = INTEGRAL_RTOL);
            assert_relative_eq!(ints.alpha_pp[i], alpha_pp[i], max_relative = INTEGRAL_RTOL);
        }
    }
}

#[test]
fn shape_tensor_volume_and_euler_tensor() {
    let q = nalgebra::Rotation3::from_euler_angles(0.3, -0.2, 1.1).into_inner();
    let e = Ellipsoid::new([3.0, 2.0, 0.5], q).unwrap();
    let s = e.shape_tensor();
    assert_relative_eq!(s.determinant(), 3.0, max_relative = 1e-14);
    assert_relative_eq!(e.volume(), 4.0 * std::f64::consts::PI, max_relative = 1e-14);
    // Θ = ∫ρ Ξ⊗Ξ dV: along E'_1 the second moment of a solid ellipsoid is m R₁²/5.
    let theta = e.euler_tensor(2.0);
    let e1 = q.column(0);
    assert_relative_eq!((e1.transpose() * theta * e1)[0], 2.0 * 9.0 / 5.0, max_relative = 1e-14);
    // The frame of F̄ = 1·S recovers the semi-axes and the axes up to sign.
    let frame = PrincipalFrame::from_total_distortion(&s);
    assert_relative_eq!(frame.r, Vec3::new(3.0, 2.0, 0.5), max_relative = 1e-13);
    for a in 0..3 {
        assert_relative_eq!((frame.q.row(a) * q.column(a))[0].abs(), 1.0, max_relative = 1e-13);
    }
    assert_relative_eq!(e.axis_point(0), q.column(0) * 3.0, max_relative = 1e-15);
}

#[test]
fn invalid_shapes_are_typed_errors() {
    assert!(matches!(
        Ellipsoid::aligned([1.0, 0.0, 1.0]),
        Err(ParamError::NotPositive { .. })
    ));
    assert!(matches!(
        Ellipsoid::aligned([1.0, f64::NAN, 1.0]),
        Err(ParamError::NotPositive { .. })
    ));
    let reflection = Matrix3::from_diagonal(&Vec3::new(1.0, 1.0, -1.0));
    assert!(matches!(
        Ellipsoid::new([1.0, 1.0, 1.0], reflection),
        Err(ParamError::NotARotation { .. })
    ));
}

proptest! {
    /// abc Σα_i = 2 holds exactly; round-off of three RD evaluations stays below 1e-13.
    #[test]
    fn alpha_sum_identity(r in strategies::semi_axes(20.0)) {
        let ints = EllipsoidIntegrals::new(&Vec3::from(r));
        let sum = ints.abc * ints.alpha.sum();
        prop_assert!((sum - 2.0).abs() < 1e-13, "abc Σα = {sum}");
    }

    /// The integrals come from one duplication sequence shared by R_F and the three R_D
    /// (`joint_duplication`); the public `carlson_rf`/`carlson_rd` run a separate sequence per
    /// integral, and a dual number for α′ = −(4/3) ∂₁R_D. Both are exact up to the O(δ⁶) ≈ 1e-20
    /// tail, so they differ by round-off only: a few ε per duplication step (≤ 10 at ratio 1e3)
    /// and per series term, well under 1e-13.
    #[test]
    fn joint_duplication_matches_separate_carlson(r in strategies::semi_axes(1e3)) {
        let ints = EllipsoidIntegrals::new(&Vec3::from(r));
        let x = ints.x;
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-13 * b.abs();
        prop_assert!(close(ints.chi0, 2.0 * carlson_rf(x[0], x[1], x[2]).unwrap()));
        for i in 0..3 {
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            let rd = carlson_rd(num_dual::Dual64::new(x[j], 1.0), x[k].into(), x[i].into()).unwrap();
            prop_assert!(close(ints.alpha[i], 2.0 / 3.0 * rd.re), "α_{i}: {} vs {}", ints.alpha[i], rd.re);
            prop_assert!(close(ints.alpha_p[k], -4.0 / 3.0 * rd.eps), "α'_{k}: {} vs {}", ints.alpha_p[k], rd.eps);
        }
    }

    /// α''_k = α_i − x_j α'_k = α_j − x_i α'_k: both readings agree (pair symmetry of α').
    #[test]
    fn alpha_double_prime_symmetry(r in strategies::semi_axes(10.0)) {
        let ints = EllipsoidIntegrals::new(&Vec3::from(r));
        for k in 0..3 {
            let (i, j) = ((k + 1) % 3, (k + 2) % 3);
            let other = ints.alpha[j] - ints.x[i] * ints.alpha_p[k];
            prop_assert!((other - ints.alpha_pp[k]).abs() <= 1e-12 * ints.alpha_pp[k].abs());
        }
    }
}

/// Reliability defect 4, frames: the checked frame refuses a non-finite F̄ (NaN, ∞), a singular
/// one (a zero semi-axis) and one whose F̄F̄ᵀ overflows (entries 1e200), with a typed error,
/// where the hot-path frame returns NaN or zero semi-axes; on a valid F̄ the two agree bitwise.
#[test]
fn checked_frames_refuse_bad_distortions() {
    let bad = [
        Mat3::identity() * f64::NAN,
        Mat3::identity() * f64::INFINITY,
        Mat3::from_diagonal(&Vec3::new(1.0, 1.0, 0.0)),
        Mat3::identity() * 1e200,
    ];
    for f_bar in bad {
        let refused = PrincipalFrame::try_from_total_distortion(&f_bar);
        assert!(
            matches!(refused, Err(ParamError::NonFinite { .. } | ParamError::Derived { .. })),
            "{f_bar}: {refused:?}"
        );
    }
    let f_bar = Mat3::new(1.2, 0.3, 0.0, 0.1, 0.9, 0.0, 0.0, 0.0, 1.0);
    assert_eq!(
        PrincipalFrame::try_from_total_distortion(&f_bar).unwrap(),
        PrincipalFrame::from_total_distortion(&f_bar)
    );
}

/// Reliability defect 4, the geometry a user asks of a particle: `try_geometry` refuses a
/// non-finite or singular F, and equals `geometry` on a valid one.
#[test]
fn checked_geometry_refuses_bad_deformations() {
    let particle = Particle::new(
        Ellipsoid::aligned([2.0, 1.0, 0.5]).unwrap(),
        NeoHooke::new(1.0, 10.0).unwrap(),
        Fluid::new(1.0, 1.0).unwrap(),
        1.0,
    )
    .unwrap();
    for f in [
        Mat3::identity() * f64::NAN,
        Mat3::zeros(),
        Mat3::identity() * f64::NEG_INFINITY,
    ] {
        assert!(particle.try_geometry(&f).is_err(), "{f}");
    }
    let f = Mat3::new(1.1, 0.2, 0.0, 0.0, 0.9, 0.1, 0.0, 0.0, 1.0);
    let (checked, hot) = (particle.try_geometry(&f).unwrap(), particle.geometry(&f));
    assert_eq!(
        (checked.frame, checked.ints, checked.traction),
        (hot.frame, hot.ints, hot.traction)
    );
}

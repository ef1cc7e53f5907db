//! Exact reference problems (src/reference) against the literature test vector.
use pseudorigid::reference::{jeffery_flow_aligned_time, jeffery_phi};

/// Jeffery (1922): r = 2, φ(0) = 0: γ̇t = 1 → 40.2174°, 2 → 64.0985°,
/// 5π/4 → 90°, 5 → 102.8890°, 5π/2 → 180°. Printed to 4 decimals of a degree: 1e-4°.
#[test]
fn jeffery_orbit_matches_test_vector() {
    use std::f64::consts::PI;
    for (t, deg) in [
        (1.0, 40.2174),
        (2.0, 64.0985),
        (1.25 * PI, 90.0),
        (5.0, 102.8890),
        (2.5 * PI, 180.0),
    ] {
        assert!(
            (jeffery_phi(2.0, t).to_degrees() - deg).abs() < 1e-4,
            "t = {t}: {}",
            jeffery_phi(2.0, t).to_degrees()
        );
    }
    assert!((jeffery_phi(2.0, jeffery_flow_aligned_time(2.0)) - PI / 2.0).abs() < 1e-14);
}

/// ⟨cos²φ⟩ = 1/(1 + r) against the time average of [`jeffery_phi`] over one period
/// 2π(r + 1/r), by the midpoint rule on 10⁵ points: the integrand is smooth and periodic, so
/// the rule converges spectrally and round-off (≈ 10⁻¹³) is the limit; 10⁻¹⁰ is far above it.
#[test]
fn jeffery_mean_gradient_alignment_is_the_orbit_average() {
    use pseudorigid::reference::jeffery_mean_gradient_alignment;
    for r in [1.0, 3.5, 7.0, 14.0] {
        let period = 2.0 * std::f64::consts::PI * (r + 1.0 / r);
        let n = 100_000;
        let mean = (0..n)
            .map(|k| jeffery_phi(r, (k as f64 + 0.5) * period / n as f64).cos().powi(2))
            .sum::<f64>()
            / n as f64;
        assert!(
            (mean - jeffery_mean_gradient_alignment(r)).abs() < 1e-10,
            "r = {r}: {mean}"
        );
    }
}

/// The quadrature equals the closed form for a constant speed (Gauss–Legendre 3 is exact for
/// the quadratic u, so only round-off remains: 1e-13 relative), converges for a varying speed
/// against a fine reference (error O(panels⁻⁶): 4 panels vs 64 agree to 1e-7 for
/// V = 1 + y/R on [0.5R, R]), and refuses a path outside the pipe.
#[test]
fn poiseuille_settling_distance_quadrature() {
    use pseudorigid::reference::{poiseuille_settling_distance, poiseuille_settling_distance_uniform};
    let (r, u) = (871.0, 277.0);
    let closed = poiseuille_settling_distance_uniform(r, u, 685.0, 870.6, 0.0864).unwrap();
    let quad = poiseuille_settling_distance(r, u, 685.0, 870.6, |_| 0.0864, 3).unwrap();
    assert!((quad - closed).abs() <= 1e-13 * closed, "{quad} vs {closed}");
    let speed = |y: f64| 1.0 + y / r;
    let coarse = poiseuille_settling_distance(r, u, 0.5 * r, r, speed, 4).unwrap();
    let fine = poiseuille_settling_distance(r, u, 0.5 * r, r, speed, 64).unwrap();
    assert!((coarse - fine).abs() <= 1e-7 * fine, "{coarse} vs {fine}");
    assert!(poiseuille_settling_distance(r, u, 685.0, 900.0, speed, 4).is_err());
    assert!(poiseuille_settling_distance_uniform(r, u, 685.0, 870.0, 0.0).is_err());
    assert!(poiseuille_settling_distance(r, u, 685.0, 870.0, |_| 0.0, 4).is_err());
}

/// The Zhang et al. (1997) correlation at Re = 500, θ = 30° against its values evaluated by hand
/// from the formula (five significant digits, double precision in Python: Re^{1/3} = 7.937005, sin 30° = ½; e.g. Stk = 0.1:
/// [0.19 − 0.193 e^{−9.5·0.1^{1.565}}]·7.937005·0.5 = 0.16266), so 5e-5 relative covers the
/// rounding of the hand values; the branches nearly meet at Stk = 0.04 (0.008662 against
/// 0.008539 before the Re^{1/3} sin θ factor, 1.4 %); bad arguments are typed errors.
#[test]
fn zhang_correlation_values() {
    use pseudorigid::reference::zhang_deposition_efficiency;
    let theta = 30f64.to_radians();
    for (stk, de) in [
        (0.005, 0.0037029),
        (0.02, 0.0098491),
        (0.05, 0.052208),
        (0.1, 0.16266),
        (0.2, 0.39772),
        (0.5, 0.72313),
    ] {
        let got = zhang_deposition_efficiency(stk, 500.0, theta).unwrap();
        assert!((got / de - 1.0).abs() < 5e-5, "Stk {stk}: {got} vs {de}");
    }
    let below = zhang_deposition_efficiency(0.04 - 1e-12, 500.0, theta).unwrap();
    let above = zhang_deposition_efficiency(0.04, 500.0, theta).unwrap();
    assert!((below / above - 0.008662 / 0.008539).abs() < 1e-3, "{below} {above}");
    assert!(zhang_deposition_efficiency(0.0, 500.0, theta).is_err());
    assert!(zhang_deposition_efficiency(0.1, f64::NAN, theta).is_err());
    assert!(zhang_deposition_efficiency(0.1, 500.0, 2.0).is_err());
}

/// The Pui et al. (1987) laminar bend fit against its values evaluated by hand from the formula
/// (five significant digits, double precision in Python: at 90° DE = y/(1 + y), y =
/// x^{0.452x + 2.242}, x = Stk/0.171; e.g. Stk = 0.1: x = 0.58480, y = 0.26064, DE = 0.20675),
/// so 5e-5 relative covers the rounding of the hand values; DE(0.171) = ½ exactly at 90°; a
/// 45° bend: 1 − (1 + y)^{−1/2}; bad arguments are typed errors.
#[test]
fn pui_bend_fit_values() {
    use pseudorigid::reference::pui_bend_deposition_efficiency;
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};
    for (stk, de90, de45) in [
        (0.05, 0.051204, 0.025939),
        (0.1, 0.20675, 0.10935),
        (0.3, 0.84632, 0.60798),
        (0.5, 0.97862, 0.85377),
        (1.0, 0.99982, 0.98662),
    ] {
        let got = pui_bend_deposition_efficiency(stk, FRAC_PI_2).unwrap();
        assert!((got / de90 - 1.0).abs() < 5e-5, "Stk {stk}: {got} vs {de90}");
        let got = pui_bend_deposition_efficiency(stk, FRAC_PI_4).unwrap();
        assert!((got / de45 - 1.0).abs() < 5e-5, "Stk {stk} at 45°: {got} vs {de45}");
    }
    assert!((pui_bend_deposition_efficiency(0.171, FRAC_PI_2).unwrap() - 0.5).abs() < 1e-15);
    assert!(pui_bend_deposition_efficiency(0.0, FRAC_PI_2).is_err());
    assert!(pui_bend_deposition_efficiency(f64::NAN, FRAC_PI_2).is_err());
    assert!(pui_bend_deposition_efficiency(0.1, 0.0).is_err());
    assert!(pui_bend_deposition_efficiency(0.1, 4.0).is_err());
}

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

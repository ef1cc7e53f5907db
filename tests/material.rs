//! Constitutive laws (src/material).
mod common;

use common::strategies;
use proptest::prelude::*;
use pseudorigid::material::{piola_ad, tangent_ad};
use pseudorigid::prelude::*;
use pseudorigid::tensor::Scalar;

/// Forward-mode AD is exact up to round-off; the closed forms differ from AD only by the
/// order of floating-point operations, so 1e-12 relative to the stress scale (μ, λ ≤ 1e3).
const AD_RTOL: f64 = 1e-12;

proptest! {
    #[test]
    fn neo_hooke_closed_form_piola_and_tangent_match_ad(f in strategies::deformation(), mu in 0.1f64..10.0, ratio in 1.0f64..1e3) {
        let law = NeoHooke::new(mu, mu * ratio).unwrap();
        let scale = mu * ratio;
        prop_assert!((law.piola(&f) - piola_ad(&law, &f)).abs().max() <= AD_RTOL * scale);
        prop_assert!((law.tangent(&f) - tangent_ad(&law, &f)).abs().max() <= AD_RTOL * scale * 10.0);
    }

    /// Objectivity: W(RF) = W(F) and P(RF) = R P(F), for both laws.
    #[test]
    fn laws_are_objective(f in strategies::deformation(), r in strategies::rotation()) {
        let nh = NeoHooke::new(1.3, 40.0).unwrap();
        let mr = MooneyRivlin::new(0.8, 0.5, 40.0).unwrap();
        prop_assert!((nh.energy(&(r * f)) - nh.energy(&f)).abs() <= 1e-12 * (1.0 + nh.energy(&f).abs()));
        prop_assert!((mr.energy(&(r * f)) - mr.energy(&f)).abs() <= 1e-12 * (1.0 + mr.energy(&f).abs()));
        prop_assert!((nh.piola(&(r * f)) - r * nh.piola(&f)).abs().max() <= 1e-11);
        prop_assert!((mr.piola(&(r * f)) - r * mr.piola(&f)).abs().max() <= 1e-11);
    }

    /// Mooney–Rivlin with μ₂ = 0 is Neo-Hooke.
    #[test]
    fn mooney_rivlin_reduces_to_neo_hooke(f in strategies::deformation()) {
        let nh = NeoHooke::new(1.7, 20.0).unwrap();
        let mr = MooneyRivlin::new(1.7, 0.0, 20.0).unwrap();
        prop_assert!((nh.piola(&f) - mr.piola(&f)).abs().max() <= 1e-12 * 20.0);
    }
}

#[test]
fn reference_state_is_stress_free_with_expected_shear_modulus() {
    let mr = MooneyRivlin::new(0.8, 0.5, 40.0).unwrap();
    let id = Mat3::identity();
    assert!(mr.piola(&id).abs().max() < 1e-14);
    assert!(NeoHooke::new(2.0, 10.0).unwrap().piola(&id).abs().max() < 1e-14);
    // small simple shear γ: σ₁₂ = μ_s γ + O(γ²)
    let g = 1e-6;
    let mut f = id;
    f[(0, 1)] = g;
    let s = mr.cauchy(&f);
    assert!((s[(0, 1)] / g - mr.shear_modulus()).abs() < 1e-5 * mr.shear_modulus());
}

#[test]
fn bad_moduli_are_typed_errors() {
    assert!(matches!(NeoHooke::new(-1.0, 1.0), Err(ParamError::NotPositive { .. })));
    assert!(matches!(
        NeoHooke::from_capillary(0.0, 1.0),
        Err(ParamError::NotPositive { .. })
    ));
    assert!(MooneyRivlin::new(1.0, f64::NAN, 1.0).is_err());
}

/// The generic energy evaluates on dual numbers (compile-time check that W is AD-ready).
#[test]
fn energy_is_generic() {
    fn w<S: Scalar>(f: &nalgebra::Matrix3<S>) -> S {
        NeoHooke::new(1.0, 10.0).unwrap().energy(f)
    }
    let f = Mat3::identity() * 1.1;
    let d = f.map(num_dual::Dual64::from);
    assert!((w(&d).re - w(&f)).abs() < 1e-15);
}

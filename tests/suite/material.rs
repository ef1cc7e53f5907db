//! Constitutive laws (src/material).
use crate::common;

use common::strategies;
use proptest::prelude::*;
use pseudorigid::material::{ExpressionLaw, piola_ad, tangent_ad};
use pseudorigid::prelude::*;
use pseudorigid::tensor::Scalar;

/// Forward-mode AD is exact up to round-off; the closed forms differ from AD only by the
/// order of floating-point operations. `strategies::deformation()` gives F = R(1 + E) with
/// |E_ij| ≤ 0.15, so (Gershgorin) the stretches lie in [0.55, 1.45]: |F| ≤ 1.45,
/// |G| = |F⁻¹| ≤ 1/0.55 = 1.82, |ln J| ≤ 3 ln(1/0.55) = 1.79, κ(F) ≤ 1.45/0.55 = 2.64.
/// Each entry is a chain of at most a few tens of rounded operations (cofactor inverse,
/// determinant, logarithm, three products and sums), each off by ≤ ε relative to the largest
/// intermediate, which is the entry bound B times at most κ² (G enters squared). With 64 as a
/// generous operation count the two sides differ by at most 64 ε κ² B.
fn round_off(bound: f64) -> f64 {
    64.0 * f64::EPSILON * 2.64f64.powi(2) * bound
}

/// Entry bound of P = μ(F − G) + λ ln J G: B_P = μ(1.45 + 1.82) + λ·1.79·1.82.
fn piola_bound(mu: f64, lambda: f64) -> f64 {
    mu * (1.45 + 1.82) + lambda * 1.79 * 1.82
}

/// Entry bound of ∂P/∂F = μ δδ + (μ − λ ln J) G G + λ G G: B_T = μ + (μ + 1.79 λ)·1.82² + λ·1.82².
fn tangent_bound(mu: f64, lambda: f64) -> f64 {
    mu + (mu + 1.79 * lambda) * 1.82f64.powi(2) + lambda * 1.82f64.powi(2)
}

proptest! {
    #[test]
    fn neo_hooke_closed_form_piola_and_tangent_match_ad(f in strategies::deformation(), mu in 0.1f64..10.0, ratio in 1.0f64..1e3) {
        let lambda = mu * ratio;
        let law = NeoHooke::new(mu, lambda).unwrap();
        prop_assert!((law.piola(&f) - piola_ad(&law, &f)).abs().max() <= round_off(piola_bound(mu, lambda)));
        prop_assert!((law.tangent(&f) - tangent_ad(&law, &f)).abs().max() <= round_off(tangent_bound(mu, lambda)));
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

/// The generic energy evaluates on dual numbers, and its derivative is the stress: with
/// F + εE the dual part of W is P(F):E, compared with the closed-form Piola stress (the two
/// share no code path). F = 1.1·1 and |E_ij| ≤ 1 give |P_ij| ≤ μ(1.1 + 1/1.1) + λ|ln 1.331|/1.1
/// < 5 for μ = 1, λ = 10, so P:E has nine terms below 5: round-off ≤ 64 ε · 45.
#[test]
fn energy_is_generic() {
    fn w<S: Scalar>(f: &nalgebra::Matrix3<S>) -> S {
        NeoHooke::new(1.0, 10.0).unwrap().energy(f)
    }
    let f = Mat3::identity() * 1.1;
    let e = Mat3::new(0.3, -1.0, 0.2, 0.5, 0.1, -0.7, 1.0, 0.4, -0.6);
    let d = Mat3::from_fn(|i, j| num_dual::Dual64::new(f[(i, j)], e[(i, j)]));
    let expected = NeoHooke::new(1.0, 10.0).unwrap().piola(&f).component_mul(&e).sum();
    let got = w(&d).eps;
    assert!(
        (got - expected).abs() <= 64.0 * f64::EPSILON * 45.0,
        "{got} vs {expected}"
    );
}

proptest! {
    /// A law written as text (`material::ExpressionLaw`) is the built-in law it writes: the
    /// paper's Neo-Hooke (eq. 9) and Mooney–Rivlin, W, P and the tangent on random F, to the
    /// round-off of the closed forms (the same bounds as above; the expression evaluates the
    /// invariants through C = FᵀF instead of |F|², a few more roundings of the same size). Its
    /// small-strain moduli, read off the AD tangent at F = 1, are the laws' own.
    #[test]
    fn expression_law_is_the_built_in_law(f in strategies::deformation(), mu in 0.1f64..10.0, ratio in 1.0f64..1e3, beta in 0.0f64..1.0) {
        let lambda = mu * ratio;
        let params = |pairs: &[(&str, f64)]| pairs.iter().map(|&(k, v)| (k.to_string(), v)).collect();
        let nh = NeoHooke::new(mu, lambda).unwrap();
        let text = ExpressionLaw::new(
            "mu/2*(I1 - 3) - mu*ln(J) + lambda/2*ln(J)^2",
            params(&[("mu", mu), ("lambda", lambda)]),
        ).unwrap();
        prop_assert!((text.shear_modulus() - mu).abs() <= 1e-12 * mu);
        prop_assert!((text.lame_lambda() - lambda).abs() <= 1e-12 * lambda);
        prop_assert!((text.energy(&f) - nh.energy(&f)).abs() <= 1e-12 * (1.0 + nh.energy(&f).abs()));
        prop_assert!((text.piola(&f) - nh.piola(&f)).abs().max() <= round_off(piola_bound(mu, lambda)));
        prop_assert!((text.tangent(&f) - nh.tangent(&f)).abs().max() <= round_off(tangent_bound(mu, lambda)));
        let (mu1, mu2) = ((1.0 - beta) * mu, beta * mu);
        let mr = MooneyRivlin::new(mu1, mu2, lambda).unwrap();
        let text = ExpressionLaw::new(
            "mu1/2*(I1 - 3 - 2*ln(J)) + mu2/2*(I2 - 3 - 4*ln(J)) + lambda/2*ln(J)^2",
            params(&[("mu1", mu1), ("mu2", mu2), ("lambda", lambda)]),
        ).unwrap();
        prop_assert!((text.shear_modulus() - mr.shear_modulus()).abs() <= 1e-12 * mu);
        prop_assert!((text.piola(&f) - mr.piola(&f)).abs().max() <= round_off(piola_bound(mu, lambda)));
        prop_assert!((text.tangent(&f) - mr.tangent(&f)).abs().max() <= round_off(tangent_bound(mu, lambda)));
    }
}

proptest! {
    /// The laws that say they are isotropic (`Hyperelastic::is_isotropic`) are: W(F Q) = W(F)
    /// for random F and rotations Q (material isotropy; objectivity is W(Q F) = W(F)), to the
    /// round-off of W's O(10) terms of size ≤ |W| + μ + λ. The fibre-reinforced law
    /// (`common::Fibred`) does not say so, and the same check fails for it: its energy
    /// changes by O(k) when Q turns the fibre (so the check can tell the two apart).
    #[test]
    fn laws_that_say_they_are_isotropic_are(f in strategies::deformation(), q in strategies::rotation(), mu in 0.1f64..10.0, ratio in 1.0f64..1e3, beta in 0.0f64..1.0) {
        let lambda = mu * ratio;
        let nh = NeoHooke::new(mu, lambda).unwrap();
        let mr = MooneyRivlin::new((1.0 - beta) * mu, beta * mu, lambda).unwrap();
        let text = ExpressionLaw::new(
            "mu/2*(I1 - 3) - mu*ln(J) + lambda/2*ln(J)^2 + c*(I2 - 3)^2",
            [("mu".to_string(), mu), ("lambda".to_string(), lambda), ("c".to_string(), 0.1 * mu)].into_iter().collect(),
        ).unwrap();
        let fq = f * q;
        let check = |w: f64, wq: f64| (w - wq).abs() <= 1e-12 * (w.abs() + mu + lambda);
        prop_assert!(nh.is_isotropic() && check(nh.energy(&f), nh.energy(&fq)));
        prop_assert!(mr.is_isotropic() && check(mr.energy(&f), mr.energy(&fq)));
        prop_assert!(text.is_isotropic() && check(text.energy(&f), text.energy(&fq)));
    }
}

/// The other side of the check above: a law with a material direction is not invariant under
/// F → F Q and keeps the default `is_isotropic() == false`. At F = diag(1.2, 1, 1/1.2) and Q a
/// quarter turn about e₃ the fibre's I₄ goes from 1.44 to 1, so W changes by (k/2)·0.44².
#[test]
fn a_fibred_law_is_not_isotropic() {
    let fibred = common::Fibred {
        matrix: NeoHooke::new(1.0, 10.0).unwrap(),
        k: 5.0,
    };
    assert!(!fibred.is_isotropic());
    let f = Mat3::from_diagonal(&Vec3::new(1.2, 1.0, 1.0 / 1.2));
    let q = Mat3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0);
    let change: f64 = fibred.energy(&f) - fibred.energy(&(f * q));
    assert!((change - 2.5 * 0.44 * 0.44).abs() < 1e-12, "ΔW = {change}");
}

//! Inertial deposition in a bend with plug flow against the closed form of Yeh (1974) and
//! Cheng & Wang (1975) (`studies::bend_plug`): a limit nobody here computed.

use pseudorigid::studies::bend_plug::{PlugBend, plug_deposition};

/// The closed form itself: η → 0 as Stk → 0, ≈ 4κ/π for small κ = Stkθa/(2a'), and 1 once the
/// shift d = Stk θ a reaches the diameter 2a' of the disc of centres.
#[test]
fn the_closed_form_has_its_limits() {
    let (angle, a) = (std::f64::consts::FRAC_PI_2, 20.0);
    let kappa = |stk: f64| stk * angle * a / (2.0 * (a - 0.5));
    assert_eq!(plug_deposition(0.0, angle, a), 0.0);
    let small = plug_deposition(1e-4, angle, a);
    assert!(
        (small / (4.0 * kappa(1e-4) / std::f64::consts::PI) - 1.0).abs() < 1e-7,
        "{small}"
    );
    assert_eq!(plug_deposition(2.0 * (a - 0.5) / (angle * a), angle, a), 1.0);
}

/// 400 rigid spheres per Stokes number in a 90° bend of R_b/a = 5.7 (Pui et al.'s), a = 20
/// sphere diameters: the tracked deposition efficiency within 3 binomial standard errors of
/// the closed form, plus the closed form's own error, the entry lag: the drift builds up over
/// τ, which shortens the shift by the relative Stk·a/(R_b θ) = 0.11 Stk, so η by at most that
/// share of itself (dη/dκ = (4/π)√(1 − κ²) falls with κ: η is concave with η(0) = 0, so
/// dη/dd ≤ η/d). 3 se: a false alarm in 1 of 370 per point. Every sphere deposits or leaves.
/// The reduced dataset (`paper-figures/bend/analytic.csv`'s columns) is also a snapshot: a
/// regression guard, the closed form is the check.
#[test]
fn tracked_deposition_matches_the_plug_flow_limit() {
    let mut rows = String::from("limit,stk,n,de,exact\n");
    for stk in [0.05, 0.2, 0.4] {
        let bend = PlugBend::new(5.7 * 20.0, 20.0, std::f64::consts::FRAC_PI_2, stk).unwrap();
        let d = bend.deposition(400, 7, 1e-7).unwrap();
        let lag = 0.11 * stk * d.exact;
        println!("Stk {stk}: {} of 400, exact {:.4}", d.deposited, d.exact);
        assert_eq!(d.other, 0, "Stk {stk}: spheres neither deposited nor left");
        rows.push_str(&format!("plug_flow,{stk},400,{:.4},{:.4}\n", d.efficiency(), d.exact));
        assert!(
            (d.efficiency() - d.exact).abs() <= 3.0 * d.stderr().max(binomial_floor(d.exact, 400)) + lag,
            "Stk {stk}: DE {} ± {} against {}",
            d.efficiency(),
            d.stderr(),
            d.exact
        );
    }
    insta::assert_snapshot!(rows);
}

/// The standard error of η at n trials from the exact η (the estimate's own is 0 when no
/// sphere deposits).
fn binomial_floor(eta: f64, n: u64) -> f64 {
    (eta * (1.0 - eta) / n as f64).sqrt()
}

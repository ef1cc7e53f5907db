//! Validity diagnostics (src/diagnostics) against hand-computed values in a simple shear.

use pseudorigid::contact::{PatchRule, Plane, Planes};
use pseudorigid::diagnostics::{Monitor, Thresholds, Validity};
use pseudorigid::prelude::*;

/// A 2:1:1 prolate (d_eq = 2 mm) in water-like fluid (μ = 1e-3 Pa s, ρ = 1000 kg/m³,
/// ν = 1e-6 m²/s) in u = γ̇ y e_x, γ̇ = 0.1 s⁻¹, at y = 5 cm, moving 1 mm/s slower than the
/// fluid, 2 cm below a wall z = 2 cm.
///
/// Re_γ = γ̇ d²/ν = 0.1 · 4e-6/1e-6 = 0.4; Re_s = 1e-3 · 2e-3/1e-6 = 2; r₁ = 2^{2/3} mm;
/// r₁/ℓ_w = r₁/2 cm; r₁|∇u|/|u| = r₁/y. Every value is one or two roundings from the formula.
#[test]
fn monitor_reports_hand_computed_maxima_and_flags() {
    let shape = Ellipsoid::with_volume_diameter([2.0, 1.0, 1.0], 2e-3, Mat3::identity()).unwrap();
    let p = Particle::new(
        shape,
        NeoHooke::new(1.0, 1e3).unwrap(),
        Fluid::new(1e-3, 1e3).unwrap(),
        1e3,
    )
    .unwrap();
    let flow = LinearFlow::simple_shear(0.1).unwrap();
    let wall = Planes::new(vec![Plane {
        name: "top".into(),
        point: Vec3::new(0.0, 0.0, 0.02),
        normal: Vec3::z(),
        rule: PatchRule::Stick,
    }])
    .unwrap();
    let mut monitor = Monitor::new(&p, &flow, &wall);
    // Before any state: only the constant omission, added mass at ρ_f/ρ_p = 1 with Lamb's k
    // across a 2:1 prolate, k = A/(2 − A), A = (2 − A_axis)/2,
    // A_axis = 2(1−e²)/e³ (½ ln((1+e)/(1−e)) − e), e² = 3/4.
    let e = 0.75f64.sqrt();
    let a_axis = 2.0 * (1.0 - e * e) / e.powi(3) * (0.5 * ((1.0 + e) / (1.0 - e)).ln() - e);
    let a_across = 0.5 * (2.0 - a_axis);
    let k_across = a_across / (2.0 - a_across);
    let start = monitor.validity();
    assert!(
        (start.omitted.size("added_mass").unwrap() / k_across - 1.0).abs() < 1e-12,
        "{start:?}"
    );
    assert_eq!(
        Validity {
            omitted: Default::default(),
            ..start
        },
        Validity::default()
    );
    let mut state = State::at_rest(Vec3::new(0.0, 0.05, 0.0));
    state.v = Vec3::new(0.005 - 1e-3, 0.0, 0.0);
    monitor.observe(&state);
    let v = monitor.validity();
    let r1 = 1e-3 * 4f64.cbrt();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-14 * b.abs();
    assert!(close(v.max_re_shear, 0.4), "{}", v.max_re_shear);
    assert!(close(v.max_re_slip, 2.0), "{}", v.max_re_slip);
    assert!(close(v.max_r1, r1), "{}", v.max_r1);
    assert!(close(v.max_r1_over_wall_distance, r1 / 0.02));
    assert!(close(v.max_r1_over_flow_scale, r1 / 0.05));
    assert_eq!((v.states, v.unsampled), (1, 0));
    // Omitted terms: the flow's acceleration (∇u)u vanishes on y-lines of a simple shear
    // (u has no y component), so the undisturbed-flow force is 0 here; Schiller–Naumann's
    // 0.15 Re_s^0.687 and the lift 1.615/(3π) Re_ω^{1/2} C (|ω| = γ̇ in a simple shear, so
    // Re_ω = Re_γ = 0.4). Here ε = Re_ω^{1/2}/Re_s = 0.316 and Re_s = 2: inside Dandy & Dwyer's
    // range, where the term follows Mei's (1992) fit of their lift, C = (1 − 0.3314 √β)
    // e^{−Re_s/10} + 0.3314 √β with β = ½ Re_ω/Re_s = 0.1, so C = 0.84 (issue 61: McLaughlin's
    // J*(ε) decayed by Mei's e^{−Re_s/10}, used before at every Re_s, gave 0.075, 11× less; the
    // monitor before issue 38 used Saffman's C = 1).
    assert_eq!(v.omitted.size("undisturbed_flow"), Some(0.0));
    assert!(close(
        v.omitted.size("schiller_naumann").unwrap(),
        0.15 * 2f64.powf(0.687)
    ));
    let s = 0.3314 * 0.1f64.sqrt();
    let c = (1.0 - s) * (-0.2f64).exp() + s;
    assert!(
        (v.omitted.size("saffman_mei").unwrap() - 1.615 / (3.0 * std::f64::consts::PI) * 0.4f64.sqrt() * c).abs()
            <= 1e-12 * c,
        "{} (C = {c})",
        v.omitted.size("saffman_mei").unwrap()
    );
    assert_eq!(v.omitted.size("cunningham"), Some(0.0), "a liquid has no gas slip");
    // 0.4 and 2 cross 0.1; r₁/ℓ_w = 0.079 and r₁/ℓ_u = 0.032 do not; then the terms above 1 %
    // (the lift 1.615/(3π)·√0.4·0.84 = 9.1 % of the drag; 0.8 % on McLaughlin's J*, before).
    assert_eq!(
        v.flags(&Thresholds::default()),
        vec![
            "re_shear",
            "re_slip",
            "omits_added_mass",
            "omits_schiller_naumann",
            "omits_saffman_mei"
        ]
    );
    assert_eq!(v.cells(&Thresholds::default()).len(), Validity::COLUMNS.len());
    // A later, calmer state does not lower a maximum.
    state.v = flow.sample(&state.x, 0.0).unwrap().u;
    monitor.observe(&state);
    assert_eq!(monitor.validity().max_re_slip, v.max_re_slip);
    assert_eq!(monitor.validity().states, 2);
}

/// Before any run a scene's advice takes each registered term's estimate from the particle
/// alone (`omitted_before_run`): the constant ones as the monitor does, and for the
/// undisturbed-flow force, estimated state by state, its registration's bound ρ_f/ρ_p. The
/// monitor itself does not take that bound (`omitted_constants` keeps it at zero), and a
/// particle that carries the term is not estimated.
#[test]
fn before_a_run_the_undisturbed_flow_force_is_bounded_by_the_density_ratio() {
    use pseudorigid::diagnostics::{omitted_before_run, omitted_constants};
    use pseudorigid::hydro::forces::{self, ForceTerms};
    use pseudorigid::registry::Values;
    let shape = Ellipsoid::with_volume_diameter([1.0; 3], 2e-3, Mat3::identity()).unwrap();
    // Water around a particle of density 2 500 kg/m³: ρ_f/ρ_p = 0.4.
    let p = Particle::new(
        shape,
        NeoHooke::new(1.0, 1e3).unwrap(),
        Fluid::new(1e-3, 1e3).unwrap(),
        2.5e3,
    )
    .unwrap();
    assert_eq!(omitted_before_run(&p).size("undisturbed_flow"), Some(0.4));
    assert_eq!(omitted_constants(&p).size("undisturbed_flow"), Some(0.0));
    // Added mass is constant: both give the same (a sphere's k = ½, so ½ ρ_f/ρ_p).
    let added = omitted_constants(&p).size("added_mass").unwrap();
    assert!((added - 0.2).abs() < 1e-12, "{added}");
    assert_eq!(omitted_before_run(&p).size("added_mass"), Some(added));
    let term = forces::by_name("undisturbed_flow", &Values::new()).unwrap();
    let carrying = p.with_forces(ForceTerms::new(vec![term]).unwrap()).unwrap();
    assert_eq!(omitted_before_run(&carrying).size("undisturbed_flow"), Some(0.0));
}

/// The slip correction left out, in air (μ = 1.8·10⁻⁵ Pa s, ρ = 1.2 kg/m³, so λ = μ/(0.499 ρ c̄)
/// = 64.9 nm with c̄ = 463 m/s): Davies' C = 1 + (2λ/d)(1.257 + 0.4 e^{−1.1 d/(2λ)}) − 1 for a
/// 2 µm sphere of 1 000 kg/m³, times 1 − ρ_f/ρ_p (the slip it corrects is proportional to
/// it), and 0 for a tracer as dense as the air: the README's tracer recipe was warned that it
/// leaves out 5.4 % of `cunningham`, which cannot move a particle without slip.
#[test]
fn the_slip_correction_left_out_is_zero_for_a_tracer_as_dense_as_the_gas() {
    use pseudorigid::diagnostics::omitted_before_run;
    let d: f64 = 2e-6;
    let lambda: f64 = 1.8e-5 / (0.499 * 1.2 * 463.0);
    let davies = 2.0 * lambda / d * (1.257 + 0.4 * (-1.1 * d / (2.0 * lambda)).exp());
    for (rho_p, want) in [(1000.0, davies * (1.0 - 1.2 / 1000.0)), (1.2, 0.0)] {
        let shape = Ellipsoid::with_volume_diameter([1.0; 3], d, Mat3::identity()).unwrap();
        let p = Particle::new(
            shape,
            NeoHooke::new(1.0, 1e3).unwrap(),
            Fluid::new(1.8e-5, 1.2).unwrap(),
            rho_p,
        )
        .unwrap();
        let got = omitted_before_run(&p).size("cunningham").unwrap();
        assert!(
            (got - want).abs() <= 1e-12 * davies,
            "ρ_p = {rho_p}: {got} against {want}"
        );
    }
}

/// The slow manifold in the diagnostics (issue 36, item 3): a stiff sphere (Ca = 10⁻³, so
/// δ = |∇u|/k = 1.5 Ca against δ_max = √rtol = 0.0316) in unit shear, stepped by
/// `slow_manifold` with the monitor fed at every accepted step and the integrator's report
/// added after the run, as `studies::bifurcation::validity` does: the report counts every
/// step the monitor saw, its largest δ is at most δ_max, and nothing is flagged for it. A
/// report with δ above its bound is flagged `manifold_ratio`, also combined with a run that
/// kept to it; combined reports add their steps and keep the δ and δ_max of the run closer to
/// its bound; a validity without a report serialises as before.
#[test]
fn validity_states_the_slow_manifolds_ratio_against_its_bound() {
    use pseudorigid::driver::{Observers, Plan, Problem, integrate};
    use pseudorigid::integrator::IntegratorReport;
    use pseudorigid::integrator::manifold::{Manifold, ManifoldReport};
    use pseudorigid::studies::particles::Shape;
    use pseudorigid::studies::shear_run::unit_shear;
    use pseudorigid::studies::shear_shape::ShearShape;
    let p = ShearShape::new(Shape::Sphere)
        .particle(&ShearScaling::new(1e-3, 1.0, 1e3).unwrap())
        .unwrap();
    let flow = unit_shear();
    let integ = Manifold::new(Stokesian::overdamped(1e-3).unwrap()).unwrap();
    let mut monitor = Monitor::in_linear_flow(&p, &flow);
    let mut memory = Default::default();
    integrate(
        Problem::new(&integ, &p, &flow),
        State::at_rest(Vec3::zeros()),
        &mut memory,
        &Plan::new(5.0, 1e-3).unwrap(),
        &[],
        Observers::none().with_on_step(|step| monitor.observe_step(step)),
    )
    .unwrap();
    let v = monitor.validity().with_integrator(integ.report(&memory));
    let m = v.integrator.manifold.unwrap();
    assert!(m.manifold_steps > m.full_steps && m.entered == 1, "{m:?}");
    assert_eq!(m.manifold_steps + m.full_steps, v.states, "{m:?}");
    assert!(m.max_ratio > 0.0 && m.max_ratio <= m.delta_max, "{m:?}");
    assert_eq!(m.delta_max, 1e-3f64.sqrt());
    let limits = Thresholds::default();
    let flagged = |v: &Validity| v.flags(&limits).contains(&"manifold_ratio".to_string());
    assert!(!flagged(&v), "{v:?}");

    let over = ManifoldReport {
        max_ratio: 1.01 * m.delta_max,
        ..m
    };
    let exceeded = Validity::default().with_integrator(IntegratorReport::manifold(over));
    assert_eq!(exceeded.flags(&limits), ["manifold_ratio"]);
    let both = v.clone().combine(exceeded);
    assert!(flagged(&both), "{both:?}");
    let total = both.integrator.manifold.unwrap();
    assert_eq!(
        (total.manifold_steps, total.max_ratio),
        (2 * m.manifold_steps, over.max_ratio)
    );
    // A larger δ under a looser bound is farther from its bound: the first run's pair stays.
    let loose = ManifoldReport {
        max_ratio: 2.0 * m.max_ratio,
        delta_max: 10.0 * m.delta_max,
        ..m
    };
    let kept = m.combine(loose);
    assert_eq!(
        (kept.max_ratio, kept.delta_max, kept.entered),
        (m.max_ratio, m.delta_max, 2)
    );
    assert_eq!(Validity::default().combine(v.clone()).integrator, v.integrator);

    assert!(
        !serde_json::to_string(&Validity::default())
            .unwrap()
            .contains("manifold")
    );
    let back: Validity = serde_json::from_str(&serde_json::to_string(&v).unwrap()).unwrap();
    assert_eq!(back, v);
}

//! The IMEX stability guard: it terminates on every input (the rotated-sphere hang of the
//! reliability audit), and the default cached guard refuses every step the exact eigenvalue
//! check refuses, on the hard-case set.
use pseudorigid::driver::{Problem, advance};
use pseudorigid::integrator::imex::{StabilityGuard, stability_limit, volume_mode_floor};
use pseudorigid::integrator::{ImexAdaptive, ImexPaper, TimeIntegrator};
use pseudorigid::prelude::*;
use std::sync::mpsc;
use std::time::Duration;

/// Run `f` on a worker thread and fail (instead of hanging the suite) if it takes longer than
/// `secs`: the audit's hang returned never, so any finite bound separates the two outcomes; the
/// bound is 100× the time the body takes on a loaded 2-core machine.
fn with_watchdog(secs: u64, f: impl FnOnce() + Send + 'static) {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        f();
        let _ = tx.send(());
    });
    match rx.recv_timeout(Duration::from_secs(secs)) {
        Ok(()) => {}
        Err(mpsc::RecvTimeoutError::Disconnected) => panic!("the body panicked"),
        Err(mpsc::RecvTimeoutError::Timeout) => panic!("no answer within {secs} s: hang"),
    }
}

/// Rotation by `angle` about the unit axis `n` (Rodrigues), as in the audit's reproducer.
fn rotation(n: Vec3, angle: f64) -> Mat3 {
    let n = n.normalize();
    let k = Mat3::new(0., -n[2], n[1], n[2], 0., -n[0], -n[1], n[0], 0.);
    Mat3::identity() + k * angle.sin() + k * k * (1. - angle.cos())
}

/// Defect 1 of the reliability audit, verbatim: a sphere with rotated axes hung forever in the
/// guard's Schur iteration. Now the step returns, and succeeds: Δt = 1e-4 is far below the
/// sphere's limit ρ*/30 = 3.3e-3.
#[test]
fn rotated_sphere_step_returns() {
    with_watchdog(60, || {
        let q = rotation(Vec3::new(1., 2., 3.), 0.7);
        let p = ShearScaling::new(0.4, 0.1, 1e3)
            .unwrap()
            .particle([1., 1., 1.], q)
            .unwrap();
        let r = ImexPaper::default().step(
            &p,
            &State::at_rest(Vec3::zeros()),
            &LinearFlow::simple_shear(1.0).unwrap(),
            1e-4,
        );
        assert!(r.is_ok(), "{r:?}");
        // The exact guard also terminates, with the sphere's limit ρ*/30 (to 5 %).
        let limit = stability_limit(&p, &State::at_rest(Vec3::zeros())).unwrap();
        assert!((limit * 30.0 / 0.1 - 1.0).abs() < 0.05, "limit {limit}");
    });
}

/// The audit found 27 of 87 rotated spheres hanging; here 200 seeded rotations (axes on a
/// Fibonacci sphere, angles spread over (0, π)) all step, with the exact and the cached guard.
#[test]
fn many_rotated_spheres_and_near_spheres_step() {
    with_watchdog(120, || {
        let flow = LinearFlow::simple_shear(1.0).unwrap();
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        for i in 0..200 {
            let z = 1.0 - 2.0 * (i as f64 + 0.5) / 200.0;
            let (s, c) = (golden * i as f64).sin_cos();
            let n = Vec3::new((1.0 - z * z).sqrt() * c, (1.0 - z * z).sqrt() * s, z);
            let q = rotation(n, std::f64::consts::PI * (i as f64 + 0.5) / 200.0);
            // Spheres and near-spheres (the audit's other hanging class).
            let ratios = [[1.0, 1.0, 1.0], [1.0 + 1e-9, 1.0, 1.0 - 1e-9]][i % 2];
            let p = ShearScaling::new(0.4, 0.1, 1e3).unwrap().particle(ratios, q).unwrap();
            for guard in [StabilityGuard::Exact, StabilityGuard::default()] {
                let imex = ImexPaper {
                    guard,
                    ..ImexPaper::default()
                };
                let r = imex.step(&p, &State::at_rest(Vec3::zeros()), &flow, 1e-4);
                assert!(r.is_ok(), "rotation {i}, {guard:?}: {r:?}");
            }
        }
    });
}

/// The hard-case set of the integrator tests: aspect 20 and 1/20, a sphere, the paper's oblate
/// and a 5:1 prolate, at Ca from 0.1 to 3, ρ* = 0.1, λ_s/μ_s = 1e5. Along each trajectory (run
/// unguarded at Δt = ρ*/400, well inside every explicit limit, with λ_s Δt ≥ 8 μ_f so that the
/// implicit volumetric update is stable too) the step Δt = (1 + 10⁻⁶) × the exact limit is refused by
/// the exact guard by construction; the cached guard must refuse it too, at every state.
#[test]
fn cached_guard_refuses_whatever_the_exact_guard_refuses() {
    let flow = LinearFlow::simple_shear(1.0).unwrap();
    let rho_star = 0.1;
    let shapes = [
        [20.0, 1.0, 1.0],
        [20.0, 20.0, 1.0],
        [1.0, 1.0, 20.0],
        [1.0, 1.0, 1.0],
        [2.5, 2.5, 1.0],
        [5.0, 1.0, 1.0],
    ];
    let mut checked = 0;
    for ratios in shapes {
        for ca in [0.1, 0.5, 3.0] {
            let p = ShearScaling::new(ca, rho_star, 1e5)
                .unwrap()
                .particle(ratios, Mat3::identity())
                .unwrap();
            let cached = ImexPaper::default();
            let mut guard_memory = Default::default();
            let mut run_memory = Default::default();
            let mut s = State::at_rest(Vec3::zeros());
            for n in 0..4000 {
                if n % 20 == 0 {
                    let exact = stability_limit(&p, &s).unwrap();
                    let r = cached.step_with(&p, &s, &mut guard_memory, &flow, exact * (1.0 + 1e-6));
                    assert!(
                        matches!(r, Err(StepError::Unstable { .. })),
                        "{ratios:?} Ca {ca} t = {}: cached guard let Δt = {exact:e} (1 + 1e-6) through",
                        s.t
                    );
                    checked += 1;
                }
                s = ImexPaper::unguarded()
                    .step_with(&p, &s, &mut run_memory, &flow, rho_star / 400.0)
                    .unwrap()
                    .state;
            }
        }
    }
    assert_eq!(checked, 6 * 3 * 200);
}

/// The guard costs little because the limit is recomputed only when C = FᵀF moved by 1 %:
/// over a tumbling run of the paper's oblate (t ≤ 10, 20 000 steps) the step counts model
/// evaluations only (one per step), and a rigid rotation of the state never triggers a
/// re-computation (the limit depends on C only; objectivity of σ̃).
#[test]
fn guard_limit_is_invariant_under_rotation_of_the_current_configuration() {
    let p = ShearScaling::new(0.4, 0.1, 1e3)
        .unwrap()
        .particle([2.5, 2.5, 1.0], Mat3::identity())
        .unwrap();
    let mut s = State::at_rest(Vec3::zeros());
    s.f = Mat3::new(1.3, 0.2, 0.0, -0.1, 0.8, 0.05, 0.0, 0.1, 0.96);
    let base = stability_limit(&p, &s).unwrap();
    for i in 0..20 {
        let r = rotation(Vec3::new(1.0, -0.5 + 0.1 * i as f64, 0.3), 0.3 * i as f64);
        let mut rotated = s;
        rotated.f = r * s.f;
        let limit = stability_limit(&p, &rotated).unwrap();
        // Eigenvalues of similar 9×9 operators agree to round-off times their condition; 1e-8
        // relative is far above round-off (1e-14) and far below the guard's 10 % safety margin.
        assert!((limit / base - 1.0).abs() < 1e-8, "rotation {i}: {limit} vs {base}");
    }
}

/// The volume-mode floor of the literal eq. 12 traction, for a sphere at rest, is the closed
/// form 2μ_f/(3λ_s + 2μ_s) (the oscillator ε̈ = (5/ρR²)[2μ_f ε̇ − (3λ_s + 2μ_s) ε] of a uniform
/// dilation F = (1 + ε)1); the `Dev` and `Source` tractions resist dilation and have none.
#[test]
fn volume_floor_of_a_sphere_is_the_closed_form() {
    let (ca, bulk) = (0.5, 100.0);
    let scaling = ShearScaling::new(ca, 1.0, bulk).unwrap();
    let p = scaling.particle([1.0, 1.0, 1.0], Mat3::identity()).unwrap();
    let s = State::at_rest(Vec3::zeros());
    let (mu_s, lambda_s) = (p.fluid().mu / ca, bulk * p.fluid().mu / ca);
    let expected = 2.0 * p.fluid().mu / (3.0 * lambda_s + 2.0 * mu_s);
    let floor = volume_mode_floor(&p, &s).unwrap();
    // Both sides are a few flops of O(1) numbers: round-off is 1e-15.
    assert!((floor / expected - 1.0).abs() < 1e-12, "{floor} vs {expected}");
    for vol in [VolumetricTraction::Dev, VolumetricTraction::Source] {
        assert_eq!(volume_mode_floor(&p.clone().with_volumetric(vol), &s).unwrap(), 0.0);
    }
}

/// The floor separates growth from decay of a dilation on non-spherical particles too, to
/// within 25 %: a 0.1 % dilation of a particle at rest grows when stepped at 0.8 × the floor and
/// decays at 1.25 × the floor. For the sphere a = 10μ_f/(ρ_s R²) = 40 here and aΔt_v = 0.13,
/// so the per-step energy factor (1 + aΔt)/(1 + ω²Δt²) = (1 + aΔt)/(1 + aΔt·Δt/Δt_v) is ≈ 1.02
/// at 0.8 Δt_v and ≈ 0.97 at 1.25 Δt_v: over 2 000 steps far beyond the 10× asserted either way.
/// Both step sizes lie inside the explicit viscous limit, so only the volume mode can grow.
#[test]
fn volume_floor_separates_growth_from_decay() {
    let flow = LinearFlow::simple_shear(0.0).unwrap();
    for ratios in [[1.0, 1.0, 1.0], [5.0, 1.0, 1.0], [2.5, 2.5, 1.0], [3.0, 1.5, 1.0]] {
        let p = ShearScaling::new(0.5, 1.0, 100.0)
            .unwrap()
            .particle(ratios, Mat3::identity())
            .unwrap();
        let mut s0 = State::at_rest(Vec3::zeros());
        s0.f *= 1.001;
        let floor = volume_mode_floor(&p, &s0).unwrap();
        let limit = stability_limit(&p, &s0).unwrap();
        assert!(
            1.25 * floor < 0.9 * limit,
            "{ratios:?}: window ({floor}, {limit}) too narrow for the test"
        );
        let growth = |dt: f64| {
            let mut s = s0;
            let mut memory = Default::default();
            for _ in 0..2000 {
                match ImexPaper::unguarded().step_with(&p, &s, &mut memory, &flow, dt) {
                    Ok(step) => s = step.state,
                    // A blown-up dilation (inverted or non-finite) is growth.
                    Err(_) => return f64::INFINITY,
                }
            }
            (s.f.determinant() - 1.0).abs() / (s0.f.determinant() - 1.0).abs()
        };
        let (below, above) = (growth(0.8 * floor), growth(1.25 * floor));
        assert!(
            below > 10.0,
            "{ratios:?}: dilation at Δt = 0.8 floor changed by {below}"
        );
        assert!(
            above < 0.1,
            "{ratios:?}: dilation at Δt = 1.25 floor changed by {above}"
        );
    }
}

/// An error-controlled IMEX run with the literal eq. 12 traction at a tolerance that would
/// resolve the anti-damped volume mode stops with a typed error instead of integrating the
/// unphysical dilation; with the `Source` traction the same run finishes with |J − 1| at the
/// elastic level (the shear stress over the bulk modulus: Ca/bulk = 5e-3).
#[test]
fn adaptive_imex_refuses_to_resolve_the_anti_damped_volume_mode() {
    let flow = LinearFlow::simple_shear(1.0).unwrap();
    let p = ShearScaling::new(0.5, 1.0, 100.0)
        .unwrap()
        .particle([2.0, 1.0, 1.0], Mat3::identity())
        .unwrap();
    let integ = ImexAdaptive::new(1e-9).unwrap();
    let paper = advance(
        Problem::new(&integ, &p, &flow),
        State::at_rest(Vec3::zeros()),
        1e-3,
        5.0,
    );
    assert!(
        matches!(paper, Err(StepError::VolumeModeUnresolvable { .. })),
        "{paper:?}"
    );
    let source = p.with_volumetric(VolumetricTraction::Source);
    let (end, _) = advance(
        Problem::new(&integ, &source, &flow),
        State::at_rest(Vec3::zeros()),
        1e-3,
        5.0,
    )
    .unwrap();
    let j = end.f.determinant();
    assert!((j - 1.0).abs() < 5e-3, "J = {j}");
}

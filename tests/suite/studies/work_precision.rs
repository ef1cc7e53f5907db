//! Work-precision scene (src/studies/work_precision): a reduced dataset guarded by a snapshot
//! (integer work counts and errors rounded to 2 significant digits, stable across machines),
//! the exactness of the rigid integrator on its Jeffery orbit, and the agreement of the library
//! with the SciPy peer (benches/peers/inertialess.py).
use pseudorigid::driver::{self, Observers, run};
use pseudorigid::flow::analytic::LinearFlow;
use pseudorigid::integrator::Stokesian;
use pseudorigid::particle::{ShearScaling, State};
use pseudorigid::studies::particles::Shape;
use pseudorigid::studies::scipy_peer::{Peer, PeerCase, PeerMethod};
use pseudorigid::studies::shear_shape::ShearShape;
use pseudorigid::studies::work_precision::{ReferenceProblem, Setting, measure};
use pseudorigid::tensor::Vec3;

fn row(case: ReferenceProblem, setting: Setting) -> String {
    let r = measure(case, setting, None).unwrap();
    format!(
        "{},{},{:e},{:.1e},{},{},{}",
        case.name(),
        setting.integrator(),
        setting.value(),
        r.error,
        r.stats.steps,
        r.stats.rhs_evals,
        r.stats.jac_evals
    )
}

/// The work-precision dataset, reduced. A regression guard (this code's own output), not a check.
#[test]
fn work_precision_reduced_dataset() {
    let rows = [
        row(ReferenceProblem::Jeffery, Setting::Rigid(1e-6)),
        row(ReferenceProblem::Jeffery, Setting::RosenbrockW23(1e-5)),
        row(ReferenceProblem::TankTreading, Setting::RosenbrockW23(1e-5)),
        row(ReferenceProblem::TankTreading, Setting::ImexAdaptive(1e-3)),
    ];
    insta::assert_snapshot!(format!(
        "case,integrator,setting,error,steps,rhs_evals,jac_evals\n{}",
        rows.join("\n")
    ));
}

/// The rigid integrator converges to the exact Jeffery orbit: no model error, so the angle
/// error vanishes with the tolerance at the rate of an order-2 method under error-per-step
/// control, global error ∝ tol^{2/3}. Three decades of tolerance must give 2 ± 0.5 decades.
#[test]
fn rigid_integrator_converges_to_jeffery_orbit() {
    let coarse = measure(ReferenceProblem::Jeffery, Setting::Rigid(1e-6), None)
        .unwrap()
        .error;
    let fine = measure(ReferenceProblem::Jeffery, Setting::Rigid(1e-9), None)
        .unwrap()
        .error;
    let decades = (coarse / fine).log10();
    assert!(
        (1.5..=2.5).contains(&decades),
        "errors {coarse:e} → {fine:e}: {decades} decades"
    );
}

/// The SciPy peer, an independent NumPy/SciPy implementation of the inertialess model written
/// from the paper, and the library's inertialess integrator give the same F(t) for the Fig. 4
/// oblate (2.5, 1, 2.5) at Ca = 0.4 over t ≤ 5.
///
/// Bound: each integrator keeps its local error per accepted step below tol·(1 + |F|), so the
/// global error is at most the sum over its steps, times the amplification of a perturbation
/// over the horizon. That amplification is O(1): the shape relaxes (rate ~ 1/Ca) and the
/// orientation drifts neutrally along a Jeffery-like orbit, so a factor 10 covers it. With
/// rtol = atol = 1e-8 (peer, Radau, ~10² steps) and 1e-10 (library, ~5·10³ steps) the bound is
/// ~5e-5, while F moves by 6e-4 when Ca changes by 0.1 %, so a wrong coefficient in the
/// traction or the elastic stress cannot pass. The peer's values between its steps come from
/// its dense output, whose error is of the order of the local error it interpolates.
#[test]
fn scipy_peer_agrees_with_library() {
    let peer = Peer::from_env();
    if let Err(e) = peer.check() {
        eprintln!("SKIPPED scipy_peer_agrees_with_library: {e}");
        return;
    }
    let (ca, bulk_ratio, t_end, peer_tol, library_tol) = (0.4, 1e5, 5.0, 1e-8, 1e-10);
    let shape = ShearShape::new(Shape::Oblate(2.5));
    let case = PeerCase {
        semi_axes: shape.ratios(),
        ca,
        bulk_ratio,
        t_end,
    };
    let scipy = peer.run(&case, PeerMethod::Radau, peer_tol).unwrap();
    let times: Vec<f64> = scipy.samples.iter().map(|s| s.0).collect();
    assert_eq!(times, [1.0, 2.0, 3.0, 4.0, 5.0]);

    let p = shape
        .particle(&ShearScaling::new(ca, 0.01, bulk_ratio).unwrap())
        .unwrap();
    let mut library = Vec::new();
    let flow = LinearFlow::simple_shear(1.0).unwrap();
    let integrator = Stokesian::overdamped(library_tol).unwrap();
    let (_, stats) = run(
        driver::Problem::new(&integrator, &p, &flow),
        State::at_rest(Vec3::zeros()),
        1e-3,
        &times,
        Observers::none().with_observe(|s| library.push(s.f)),
    )
    .unwrap();

    let f_max = library.iter().map(|f| f.amax()).fold(0.0, f64::max);
    let local_sum = scipy.steps as f64 * peer_tol + stats.steps as f64 * library_tol;
    let bound = 10.0 * local_sum * (1.0 + f_max);
    let diff = scipy
        .samples
        .iter()
        .zip(&library)
        .map(|((_, a), b)| (a - b).amax())
        .fold(0.0, f64::max);
    println!(
        "peer {} steps, library {} steps: max |ΔF| = {diff:.3e}, bound {bound:.3e}",
        scipy.steps, stats.steps
    );
    assert!(diff <= bound, "max |ΔF| = {diff:e} > {bound:e}");
}

//! Work-precision scene (src/scenes/work_precision): a reduced dataset guarded by a snapshot
//! (integer work counts and errors rounded to 2 significant digits, stable across machines),
//! and the exactness of the rigid integrator on its Jeffery orbit.
use pseudorigid::scenes::work_precision::{Case, Setting, measure};

fn row(case: Case, setting: Setting) -> String {
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

#[test]
fn work_precision_reduced_dataset() {
    let rows = [
        row(Case::Jeffery, Setting::Rigid(1e-6)),
        row(Case::Jeffery, Setting::Stokesian(1e-5)),
        row(Case::TankTreading, Setting::Stokesian(1e-5)),
        row(Case::TankTreading, Setting::ImexAdaptive(1e-3)),
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
    let coarse = measure(Case::Jeffery, Setting::Rigid(1e-6), None).unwrap().error;
    let fine = measure(Case::Jeffery, Setting::Rigid(1e-9), None).unwrap().error;
    let decades = (coarse / fine).log10();
    assert!(
        (1.5..=2.5).contains(&decades),
        "errors {coarse:e} → {fine:e}: {decades} decades"
    );
}

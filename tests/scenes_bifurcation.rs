//! The airway bifurcation of paper §6.4 (src/scenes/bifurcation).

use pseudorigid::flow::FlowField;
use pseudorigid::scenes::bifurcation::setup::{self, Airway};
use pseudorigid::tensor::Vec3;
use std::sync::OnceLock;

fn airway() -> &'static Airway {
    static AIRWAY: OnceLock<Airway> = OnceLock::new();
    AIRWAY.get_or_init(|| Airway::open(Airway::shipped_dir()).expect("shipped bifurcation field"))
}

/// The paper's pairs Stk 0.1 ↔ d_eq = 8.06 µm, 0.4 ↔ 16.12 µm, 0.5 ↔ 18.03 µm hold with
/// ρ_p/ρ_f = 1994: the diameters are printed to ±0.005 µm, so Stk (∝ d²) is fixed to a relative
/// 2·0.005/d_eq (1.2e-3 at 8.06 µm); the inverse is exact to round-off (1e-14).
#[test]
fn stokes_number_from_the_paper_pairs() {
    for (stk, d_um) in [(0.1, 8.06), (0.4, 16.12), (0.5, 18.03)] {
        let got = setup::stokes_number(d_um * 1e-6).unwrap();
        let allowed = 2.0 * 0.005 / d_um;
        assert!(
            (got / stk - 1.0).abs() <= allowed,
            "d_eq {d_um} µm: Stk {got}, want {stk} ± {allowed}"
        );
        let d = setup::d_eq_for_stokes(stk).unwrap();
        assert!((setup::stokes_number(d).unwrap() / stk - 1.0).abs() < 1e-14);
    }
    assert!(setup::stokes_number(0.0).is_err());
    assert!(setup::d_eq_for_stokes(f64::NAN).is_err());
    assert!((setup::inlet_velocity() - 1.2425).abs() < 1e-12);
}

/// The shipped field carries the case's patches with their roles, and conserves the inlet flow
/// rate U πR² through a cross-section of the parent (x₁ = 10 mm) and of each daughter (the plane
/// x₁ = 36 mm, one half each). The flux is integrated by the midpoint rule on a 0.05 mm grid over
/// the points the mesh contains; the error budget is the reconstruction's O(h²) velocity error
/// ((0.4/3)² ≈ 2 % of the peak near the wall, less on average), the faceted wall (area deficit
/// ≈ (h/R)²/6 ≈ 0.3 %) and the grid's boundary cells (a 0.05 mm band where u ≈ 0): 3 %.
/// The two daughters split the flow equally by symmetry, to the same 3 %.
#[test]
fn shipped_field_conserves_the_flow_rate() {
    let a = airway();
    let names: Vec<String> = a.flow().mesh().patches().iter().map(|p| p.name.clone()).collect();
    for want in ["inlet", "outlet1", "outlet2", "wall"] {
        assert!(names.iter().any(|n| n == want), "patch {want} missing: {names:?}");
    }
    let q_in = setup::inlet_velocity() * std::f64::consts::PI * setup::RADIUS * setup::RADIUS;
    let h = 5e-5;
    let flux = |x1: f64, y_from: f64, y_to: f64| {
        let mut q = 0.0;
        let ny = ((y_to - y_from) / h).round() as i64;
        let nz = (2.0 * setup::RADIUS / h).round() as i64 + 2;
        for j in 0..ny {
            for k in 0..nz {
                let x = Vec3::new(
                    x1,
                    y_from + (j as f64 + 0.5) * h,
                    -setup::RADIUS - h + (k as f64 + 0.5) * h,
                );
                if let Ok(s) = a.flow().sample(&x, 0.0) {
                    q += s.u[0] * h * h;
                }
            }
        }
        q
    };
    let parent = flux(0.01, -setup::RADIUS - h, setup::RADIUS + h);
    assert!((parent / q_in - 1.0).abs() < 0.03, "parent: {parent:e} vs {q_in:e}");
    let upper = flux(0.036, 0.0, 0.0135);
    let lower = flux(0.036, -0.0135, 0.0);
    for (name, q) in [("outlet1 side", upper), ("outlet2 side", lower)] {
        assert!(
            (q / (0.5 * q_in) - 1.0).abs() < 0.03,
            "{name}: {q:e} vs {:e}",
            0.5 * q_in
        );
    }
}

//! Shear-flow scenes (src/studies): the paper's §6.1 statements, the tank-treading state,
//! integrator convergence of the TU/TR classification, and snapshots of reduced datasets.

#[cfg(all(feature = "mesh", feature = "parallel"))]
mod airway_tree;
mod bend;
#[cfg(feature = "parallel")]
mod bend_plug;
#[cfg(all(feature = "mesh", feature = "parallel"))]
mod bifurcation;
#[cfg(all(feature = "mesh", feature = "parallel"))]
mod bifurcation_breathing;
#[cfg(all(feature = "mesh", feature = "parallel"))]
mod cavity;
mod particles;
mod peer;
mod pipe;
mod work_precision;

use crate::common;

use common::sig;
use pseudorigid::integrator::Stokesian;
use pseudorigid::output::Csv;
use pseudorigid::prelude::*;
use pseudorigid::studies::particles::Shape;
use pseudorigid::studies::phase_boundary::BoundarySearch;
use pseudorigid::studies::phase_map::{self, MapShape, boundary_table};
use pseudorigid::studies::shear_regimes::{Regime, RegimeClassifier};
use pseudorigid::studies::shear_run::{ShearSample, sample, stokesian_scaling};
use pseudorigid::studies::shear_shape::ShearShape;
use pseudorigid::studies::tank_treading::{TankTreading, integrate, roscoe};
use pseudorigid::tensor::dev;

fn oblate_run(ca: f64, times: &[f64]) -> Vec<ShearSample> {
    sample(
        &Stokesian::overdamped(1e-8).unwrap(),
        &ShearShape::new(Shape::Oblate(2.5)),
        &stokesian_scaling(ca).unwrap(),
        times,
        1e-3,
    )
    .unwrap()
    .0
}

fn grid(from: f64, to: f64, step: f64) -> Vec<f64> {
    let n = ((to - from) / step).round() as usize;
    (0..=n).map(|i| from + i as f64 * step).collect()
}

/// Paper §6.1.1 (after Sanagavarapu et al.): the oblate ω₁ = ω₂ = 2.5 tumbles at Ca = 0.4
/// and trembles at Ca = 0.5. The margins (+0.042, −0.021) are far from 0 compared with
/// their integration error (< 1e-5, see the convergence test).
#[test]
fn oblate_2_5_tumbles_at_0_4_and_trembles_at_0_5() {
    let c = RegimeClassifier::stokesian(1e-7).unwrap();
    let tu = c
        .classify(&ShearShape::new(Shape::Oblate(2.5)), &stokesian_scaling(0.4).unwrap())
        .unwrap();
    let tr = c
        .classify(&ShearShape::new(Shape::Oblate(2.5)), &stokesian_scaling(0.5).unwrap())
        .unwrap();
    assert_eq!(tu.regime, Regime::Tumbling, "{tu:?}");
    assert_eq!(tr.regime, Regime::Trembling, "{tr:?}");
    assert!(tu.margin > 0.03 && tr.margin < -0.01, "{tu:?} {tr:?}");
    // The horizon of 8 half Jeffery periods captures the minimum: doubling it leaves the
    // regimes, and the margins move by no more than the integration error (< 1e-5, see the
    // convergence test). (Asserting `horizon ≥ 30` could not fail: it is max(30, ·).)
    let long = RegimeClassifier {
        periods: 16.0,
        ..RegimeClassifier::stokesian(1e-7).unwrap()
    };
    for (short, ca) in [(&tu, 0.4), (&tr, 0.5)] {
        let l = long
            .classify(&ShearShape::new(Shape::Oblate(2.5)), &stokesian_scaling(ca).unwrap())
            .unwrap();
        assert!(l.horizon >= 2.0 * short.horizon - 1e-9, "{l:?}");
        assert_eq!(l.regime, short.regime);
        assert!((l.margin - short.margin).abs() <= 1e-5, "{l:?} vs {short:?}");
    }
}

/// Fig. 4 caption: the first maxima of ω₁ are at t̂ ≈ 7 (Ca 0.4) and ≈ 7.5 (Ca 0.5). The paper
/// quotes them to half a time unit (its snapshots are 0.5 apart), so ±0.25 is the resolution
/// of the statement; the integration error of the peak time is < 1e-3.
#[test]
fn first_shape_maxima_near_7_and_7_5() {
    for (ca, expected) in [(0.4, 7.0), (0.5, 7.5)] {
        let run = oblate_run(ca, &grid(5.0, 10.0, 0.01));
        let peak = run
            .iter()
            .max_by(|a, b| a.section.omega1().total_cmp(&b.section.omega1()))
            .unwrap();
        assert!(
            (peak.t - expected).abs() <= 0.25,
            "Ca = {ca}: max ω₁ = {} at t̂ = {}",
            peak.section.omega1(),
            peak.t
        );
    }
}

/// §6.1.1: at Ca = 0.5 the colours of the material lines are reversed (l_c > l_a) for
/// 23.5 < t̂ < 24; at Ca = 0.4 they never are in that window.
#[test]
fn lines_reverse_between_23_5_and_24_at_ca_0_5() {
    let window = grid(23.5, 24.0, 0.005);
    let inner = &window[1..window.len() - 1];
    let reversed = |ca| oblate_run(ca, inner).iter().any(|s| s.l_c() > s.l_a());
    assert!(reversed(0.5));
    assert!(!reversed(0.4));
}

/// The bisection assumes one TU→TR switch in Ca. On a log grid over [0.02, 4] the regime
/// switches exactly once for an oblate, a prolate and a triaxial shape (a 60-point grid over
/// seven shapes, checked while writing this, showed the same).
#[test]
fn regime_switches_once_in_ca() {
    let c = RegimeClassifier::stokesian(1e-6).unwrap();
    let cas: Vec<f64> = (0..=16).map(|i| 0.02 * 200f64.powf(i as f64 / 16.0)).collect();
    for shape in [
        ShearShape::new(Shape::Oblate(2.5)),
        ShearShape::new(Shape::Prolate(5.0)),
        ShearShape::new(Shape::Triaxial {
            omega1: 0.3,
            omega2: 0.5,
        }),
    ] {
        let regimes: Vec<Regime> = cas
            .iter()
            .map(|&ca| c.classify(&shape, &stokesian_scaling(ca).unwrap()).unwrap().regime)
            .collect();
        let switches = regimes.windows(2).filter(|w| w[0] != w[1]).count();
        assert_eq!(switches, 1, "{shape:?}: {regimes:?}");
        assert_eq!(regimes[0], Regime::Tumbling);
    }
}

/// The TU/TR answer and its margin are converged in the classifier's (Radau IIA) tolerance:
/// the margin's distance to the rtol 1e-8 run is 8e-8 / 8e-9 at rtol 1e-6 and 2e-10 / 2e-9 at
/// 1e-7 (Ca 0.4 / 0.5), at or below the tolerance as an order-5 method with per-step control
/// gives. The bounds (5e-5 and 2e-6, kept from the Rosenbrock 2(3) classifier, whose errors
/// were ~1e-5 and ~3e-7) stay far below what matters: the margin's sensitivity to Ca is ≈ 0.6
/// per unit Ca, so 2e-6 moves the boundary by < 4e-6 ≪ ΔCa = 1e-4.
#[test]
fn regime_and_margin_converged_in_tolerance() {
    for ca in [0.4, 0.5] {
        let scaling = stokesian_scaling(ca).unwrap();
        let m: Vec<_> = [1e-6, 1e-7, 1e-8]
            .iter()
            .map(|&tol| {
                RegimeClassifier::stokesian(tol)
                    .unwrap()
                    .classify(&ShearShape::new(Shape::Oblate(2.5)), &scaling)
                    .unwrap()
            })
            .collect();
        assert!(m.iter().all(|c| c.regime == m[2].regime));
        assert!((m[1].margin - m[2].margin).abs() <= 2e-6, "{m:?}");
        assert!((m[0].margin - m[2].margin).abs() <= 5e-5, "{m:?}");
    }
    let boundary = |tol| {
        BoundarySearch::new(RegimeClassifier::stokesian(tol).unwrap(), 1e-3)
            .find(&ShearShape::new(Shape::Oblate(2.5)))
            .unwrap()
            .ca_critical()
    };
    let (coarse, fine) = (boundary(1e-6), boundary(1e-8));
    assert!((coarse - fine).abs() <= 1e-3, "{coarse} vs {fine}");
}

/// Dense checking: the margin is refined on the dense output around every new minimum, so it
/// does not depend on how densely the steps are sampled. With step ends only (no interior
/// points), plain sampling would miss the minimum by ½|m''|(h/2)², about 1e-3 for Radau's
/// steps here (h ≈ 0.1–0.3, m'' ≈ 0.25); refined, both runs find the minimum of the same
/// interpolant, up to the golden-section bracket (0.618⁴⁰ of a step): 1e-9 is far below the
/// unrefined miss and far above that bracket's effect (~1e-17).
#[test]
fn margin_refinement_makes_sampling_density_irrelevant() {
    let scaling = stokesian_scaling(0.4).unwrap();
    let mut c = RegimeClassifier::stokesian(1e-6).unwrap();
    let dense = c.classify(&ShearShape::new(Shape::Oblate(2.5)), &scaling).unwrap();
    c.substeps = 0;
    let sparse = c.classify(&ShearShape::new(Shape::Oblate(2.5)), &scaling).unwrap();
    assert!((sparse.margin - dense.margin).abs() <= 1e-9, "{sparse:?} {dense:?}");
}

/// The paper's IMEX scheme with inertia gives the same regimes on the Fig. 4 case as the
/// inertialess integrator, and its margin converges to the inertialess one at first order:
/// both differences, shape inertia O(ρ*) and the first-order scheme's O(Δt) with Δt = ρ*/200
/// (inside the explicit limit ρ*/37 of the oblate 2.5), are proportional to ρ*. A third,
/// ρ*-independent difference is the IMEX particle's compressibility, |J − 1| ~ Ca·μ_s/λ_s;
/// λ_s/μ_s = 1e6 makes it negligible (with 1e4 it was a 3.5e-6 floor at Ca 0.5, as large as
/// the inertial part there) and keeps λ_s Δt far above the volumetric condition (2/3)μ_f.
/// Halving ρ* must therefore halve the margin difference: the ratio must lie in [1.5, 2.5],
/// first order with room for the O(ρ*²) remainder.
#[test]
fn paper_imex_agrees_on_the_fig4_regimes() {
    let stokes = RegimeClassifier::stokesian(1e-9).unwrap();
    let shape = ShearShape::new(Shape::Oblate(2.5));
    for ca in [0.4, 0.5] {
        let b = stokes.classify(&shape, &stokesian_scaling(ca).unwrap()).unwrap();
        let diff = |rho_star: f64| {
            let imex = RegimeClassifier::new(ImexPaper::default(), rho_star / 200.0);
            let a = imex
                .classify(&shape, &ShearScaling::new(ca, rho_star, 1e6).unwrap())
                .unwrap();
            assert_eq!(a.regime, b.regime, "Ca = {ca}, ρ* = {rho_star}");
            (a.margin - b.margin).abs()
        };
        let (coarse, fine) = (diff(0.1), diff(0.05));
        let ratio = coarse / fine;
        assert!(
            (1.5..=2.5).contains(&ratio),
            "Ca {ca}: differences {coarse:e}, {fine:e}"
        );
    }
}

/// The time-integrated steady tank-treading state equals the solution of the steady
/// equations. The integration runs at rtol = atol = 1e-9 onto an attracting steady state, so
/// its error there is a small multiple of the tolerance; the Newton residual is 1e-12.
/// 1e-6 leaves a factor ≥ 100 over both.
#[test]
fn tank_treading_integration_matches_steady_equations() {
    for ca in [0.05, 0.3, 1.0] {
        let int = integrate(ca, 1e-9, 60.0 + 100.0 * ca).unwrap();
        let ros = roscoe(ca).unwrap().steady;
        assert!(int.drift <= 1e-7, "Ca = {ca}: drift {}", int.drift);
        let (a, b) = (int.steady, ros);
        for (x, y) in [
            (a.deformation(), b.deformation()),
            (a.theta, b.theta),
            (a.r_long, b.r_long),
            (a.r_short, b.r_short),
            (a.r_vorticity, b.r_vorticity),
        ] {
            assert!((x - y).abs() <= 1e-6, "Ca = {ca}: {a:?} vs {b:?}");
        }
    }
}

/// The steady solution satisfies the balance dev σ̃ = dev σ_el when σ̃ is evaluated by the
/// library's traction code (a check of the hand reduction to four equations), with
/// l_s = V Ω V⁻¹ rebuilt from (λ, θ, ν).
#[test]
fn steady_equations_match_the_traction_model() {
    for ca in [0.1, 1.0] {
        let sol = roscoe(ca).unwrap();
        let s = sol.steady;
        let (c, sn) = (s.theta.cos(), s.theta.sin());
        let q = Mat3::new(c, sn, 0.0, -sn, c, 0.0, 0.0, 0.0, 1.0); // rows n_a
        let lam = Vec3::new(s.r_long, s.r_short, s.r_vorticity) * 2.0;
        let v = q.transpose() * Mat3::from_diagonal(&lam) * q;
        let mut omega = Mat3::zeros();
        omega[(0, 1)] = -sol.nu;
        omega[(1, 0)] = sol.nu;
        let l_s = v * q.transpose() * omega * q * v.try_inverse().unwrap();
        let traction = JefferyRoscoe::from_total_distortion(&(v * 0.5));
        let mut l_f = Mat3::zeros();
        l_f[(0, 1)] = 1.0;
        let sigma = traction.sigma_tilde(&l_s, &l_f, 1.0, VolumetricTraction::Dev);
        let sigma_el = (v * v - Mat3::identity()) / ca;
        let defect = dev(&(sigma - sigma_el)).abs().max();
        assert!(defect <= 1e-9, "Ca = {ca}: |dev(σ̃ − σ_el)| = {defect:e}");
    }
}

/// Small-Ca limits D → 5Ca/4, θ → π/4 − 3Ca/4 with an O(Ca²) error: the error stays below
/// 0.2 Ca² and falls at least 4× per halving of Ca (observed ≈ 8×: the Ca² terms vanish).
#[test]
fn tank_treading_small_ca_limits() {
    let err = |ca: f64| {
        let (s, l) = (roscoe(ca).unwrap().steady, TankTreading::small_ca_limit(ca));
        ((s.deformation() - l.deformation()).abs(), (s.theta - l.theta).abs())
    };
    let cas = [0.04, 0.02, 0.01];
    let errs: Vec<_> = cas.iter().map(|&c| err(c)).collect();
    for (ca, (ed, et)) in cas.iter().zip(&errs) {
        assert!(
            *ed <= 0.2 * ca * ca && *et <= 0.2 * ca * ca,
            "Ca = {ca}: {ed:e}, {et:e}"
        );
    }
    for w in errs.windows(2) {
        assert!(w[0].0 >= 4.0 * w[1].0 && w[0].1 >= 4.0 * w[1].1, "{errs:?}");
    }
}

fn table(header: &[&str], rows: impl IntoIterator<Item = Vec<String>>) -> String {
    let mut csv = Csv::new(header);
    for r in rows {
        csv.push(r).unwrap();
    }
    csv.to_text()
}

/// Fig. 4 dataset, reduced: integer times, 4 significant digits.
/// A regression guard (this code's own output), not a check.
#[test]
fn snapshot_fig4() {
    let times = grid(0.0, 10.0, 1.0);
    let rows = [0.4, 0.5].into_iter().flat_map(|ca| {
        oblate_run(ca, &times).into_iter().map(move |s| {
            vec![
                ca.to_string(),
                s.t.to_string(),
                sig(s.section.omega1(), 4),
                sig(s.section.omega2(), 4),
                sig(s.l_a(), 4),
                sig(s.l_c(), 4),
            ]
        })
    });
    insta::assert_snapshot!(table(&["ca", "t", "omega1", "omega2", "l_a", "l_c"], rows));
}

/// Figs 5/6 dataset, reduced: long-axis angle and line lengths at the snapshot times.
/// A regression guard (this code's own output), not a check.
#[test]
fn snapshot_fig5_fig6() {
    let times = [0.0, 2.0, 4.0, 6.0, 8.0, 22.5, 23.0, 23.5, 24.0, 24.5];
    let rows = [0.4, 0.5].into_iter().flat_map(|ca| {
        oblate_run(ca, &times).into_iter().map(move |s| {
            vec![
                ca.to_string(),
                s.t.to_string(),
                sig(s.section.angle.to_degrees(), 3),
                sig(s.l_a(), 3),
                sig(s.l_c(), 3),
            ]
        })
    });
    insta::assert_snapshot!(table(&["ca", "t", "long_axis_deg", "l_a", "l_c"], rows));
}

/// Figs 7/8 datasets, reduced: a few shapes at ΔCa ≤ 0.01. The bracket ends are bisection
/// nodes, fixed by the regimes alone, so they are exact across machines.
/// A regression guard (this code's own output), not a check.
#[test]
fn snapshot_phase_boundaries() {
    let point = |series, x, shape| MapShape {
        series,
        x,
        shape: ShearShape::new(shape),
    };
    let triaxial = |omega1, omega2| Shape::Triaxial { omega1, omega2 };
    let shapes = [
        point("prolate", 2.0, Shape::Prolate(2.0)),
        point("prolate", 4.0, Shape::Prolate(4.0)),
        point("oblate", 2.5, Shape::Oblate(2.5)),
        point("a_omega1_0.5", 0.2, triaxial(0.5, 0.2)),
        point("b_omega2_0.5", 0.3, triaxial(0.3, 0.5)),
    ];
    let mut search = phase_map::paper_search().unwrap();
    search.tol = 0.01;
    let points = phase_map::compute(&search, &shapes).unwrap();
    insta::assert_snapshot!(boundary_table(&points).unwrap().to_text());
}

/// Tank-treading dataset, reduced: steady equations and integration, 4 significant digits.
/// A regression guard (this code's own output), not a check.
#[test]
fn snapshot_tank_treading() {
    let rows = [0.01, 0.1, 0.5, 1.0, 2.0].into_iter().map(|ca| {
        let s = roscoe(ca).unwrap().steady;
        let i = integrate(ca, 1e-8, 60.0 + 100.0 * ca).unwrap().steady;
        vec![
            ca.to_string(),
            sig(s.r_long, 4),
            sig(s.r_vorticity, 4),
            sig(s.r_short, 4),
            sig(s.deformation(), 4),
            sig(s.theta.to_degrees(), 4),
            sig(i.deformation(), 4),
            sig(i.theta.to_degrees(), 4),
        ]
    });
    insta::assert_snapshot!(table(
        &[
            "ca",
            "r1",
            "r2",
            "r3",
            "D",
            "theta_deg",
            "D_integrated",
            "theta_deg_integrated"
        ],
        rows
    ));
}

mod section {
    use super::common::strategies;
    use proptest::prelude::*;
    use pseudorigid::studies::section::ShearPlaneSection;
    use pseudorigid::tensor::Mat3;
    use std::f64::consts::FRAC_PI_2;

    proptest! {
        /// An ellipsoid with z as a principal axis, rotated by φ about z: the section returns
        /// its in-plane semi-axes, the out-of-plane one, and φ folded into (−π/2, π/2].
        #[test]
        fn section_of_a_rotated_ellipsoid(
            r in strategies::semi_axes(4.0),
            phi in -3.0f64..3.0,
        ) {
            let (long, short) = (r[0].max(r[1]), r[0].min(r[1]));
            prop_assume!(long > 1.01 * short);
            let (c, s) = (phi.cos(), phi.sin());
            let rot = Mat3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0);
            let f_bar = rot * Mat3::from_diagonal(&nalgebra::Vector3::new(long, short, r[2]));
            let sec = ShearPlaneSection::of(&f_bar);
            prop_assert!((sec.r_long - long).abs() <= 1e-12 * long);
            prop_assert!((sec.r_short - short).abs() <= 1e-12 * long);
            prop_assert!((sec.r_out_of_plane - r[2]).abs() <= 1e-12 * r[2]);
            let mut folded = phi;
            while folded > FRAC_PI_2 { folded -= std::f64::consts::PI; }
            while folded <= -FRAC_PI_2 { folded += std::f64::consts::PI; }
            let diff = (sec.angle - folded).abs();
            prop_assert!(diff <= 1e-9 || (std::f64::consts::PI - diff) <= 1e-9, "{} vs {}", sec.angle, folded);
            // every outline point lies on the ellipse
            for (x, y) in sec.outline(16) {
                let (u, v) = (c * x + s * y, -s * x + c * y);
                prop_assert!(((u / long).powi(2) + (v / short).powi(2) - 1.0).abs() <= 1e-9);
            }
        }
    }
}

/// Scenes are generic over the law: the phase-boundary search runs with Mooney–Rivlin without a
/// scene edit. With β = 0 its energy μ/2(I₁ − 3 − 2 ln J) + λ/2 ln²J is the Neo-Hooke energy of
/// eq. 9 term by term, so the bracket must be the Neo-Hooke one (the AD stress equals the
/// closed form to round-off, far below a ΔCa = 1e-3 bisection step). With half the shear
/// modulus in the second invariant the nonlinear response differs and the boundary moves.
#[test]
fn phase_boundary_with_mooney_rivlin_needs_no_scene_edit() {
    use pseudorigid::material::MooneyRivlinFactory;
    let shape = ShearShape::new(Shape::Oblate(2.5));
    let classifier = RegimeClassifier::stokesian(1e-7).unwrap();
    let neo = BoundarySearch::new(classifier, 1e-3).find(&shape).unwrap();
    let mr0 = BoundarySearch::new(classifier.with_law(MooneyRivlinFactory { beta: 0.0 }), 1e-3)
        .find(&shape)
        .unwrap();
    assert_eq!((mr0.ca_tu, mr0.ca_tr), (neo.ca_tu, neo.ca_tr));
    let mr = BoundarySearch::new(classifier.with_law(MooneyRivlinFactory { beta: 0.5 }), 1e-3)
        .find(&shape)
        .unwrap();
    assert!(mr.ca_tr < neo.ca_tu || mr.ca_tu > neo.ca_tr, "{mr:?} vs {neo:?}");
}

/// The shear runs report validity diagnostics: no wall and an exactly linear flow give zero
/// length-scale ratios, the inertialess model assumes Re = 0, and the largest semi-axis over the
/// accepted steps bounds every sampled in-plane semi-axis from above (the ellipse cut through
/// the centre has semi-axes ≤ r₁, and the samples are accepted-step states or dense points
/// between them, which move by ≪ 1e-3 between steps at rtol 1e-8: margin 1e-3).
#[test]
fn shear_runs_report_validity() {
    use pseudorigid::studies::shear_run::oblate_fig4_run;
    let times = grid(0.0, 30.0, 0.5);
    let (run, v) = oblate_fig4_run(0.5, &times).unwrap();
    assert_eq!((v.max_re_shear, v.max_re_slip), (0.0, 0.0));
    assert_eq!((v.max_r1_over_wall_distance, v.max_r1_over_flow_scale), (0.0, 0.0));
    let widest = run.iter().map(|s| s.section.r_long).fold(0.0, f64::max);
    assert!(v.max_r1 >= widest - 1e-3, "max r1 {} < sampled {widest}", v.max_r1);
    assert!(v.states > times.len() as u64 / 2);
}

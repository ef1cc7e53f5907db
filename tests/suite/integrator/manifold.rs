//! The slow-manifold model (src/integrator/manifold.rs, src/particle/manifold.rs): against
//! Roscoe's steady tank-treading and against the full inertialess model on the same particle.

use pseudorigid::error::FlowError;
use pseudorigid::flow::{FlowField, FlowSample};
use pseudorigid::integrator::manifold::{Manifold, ManifoldMemory};
use pseudorigid::integrator::{Stokesian, TimeIntegrator};
use pseudorigid::particle::manifold::SlowManifold;
use pseudorigid::prelude::*;
use pseudorigid::studies::particles::Shape;
use pseudorigid::studies::section::ShearPlaneSection;
use pseudorigid::studies::shear_run::unit_shear;
use pseudorigid::studies::shear_shape::ShearShape;
use pseudorigid::studies::tank_treading::roscoe;

fn sphere(ca: f64) -> Particle<NeoHooke> {
    ShearShape::new(Shape::Sphere)
        .particle(&ShearScaling::new(ca, 1.0, 1e3).unwrap())
        .unwrap()
}

/// Step `integ` from rest to each of `times` exactly; the states there and the memory.
fn states_at<I: TimeIntegrator, F: FlowField>(
    integ: &I,
    particle: &Particle<NeoHooke>,
    flow: &F,
    times: &[f64],
) -> (Vec<State>, I::Memory) {
    let mut memory = I::Memory::default();
    let mut state = State::at_rest(Vec3::zeros());
    let mut dt: f64 = 1e-4;
    let mut out = Vec::new();
    for &t_out in times {
        while state.t < t_out {
            let h = dt.min(t_out - state.t);
            let step = integ.step_with(particle, &state, &mut memory, flow, h).unwrap();
            dt = step.info.dt_next;
            state = step.state;
            if t_out - state.t < 1e-12 * t_out {
                state.t = t_out;
            }
        }
        out.push(state);
    }
    (out, memory)
}

/// A linear flow whose gradient turns and pulses along the path: l_f(t) = γ̇(t) Q(t) L Q(t)ᵀ
/// with L simple shear, Q a rotation about e₃ by t/2 and γ̇ = 1 + sin(t)/2; u = l_f x (the
/// particle stays at the origin). |d∇u/dt| ≈ |∇u|, so the lag behind the flow is as large as
/// the tank-treading's.
pub(super) struct TurningShear;

impl FlowField for TurningShear {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        let (s, c) = (0.5 * t).sin_cos();
        let q = Mat3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0);
        let mut l = Mat3::zeros();
        l[(0, 1)] = 1.0 + 0.5 * t.sin();
        let grad = q * l * q.transpose();
        Ok(FlowSample::new(grad * x, grad, Vec3::zeros()))
    }
}

/// The relaxation rate of a sphere is the closed form k = 2μ_s/(3μ_f) (σ̃ = 5μ_f d_f − 3μ_f d_s
/// + ... and σ_el = 2μ_s ε at small strain), to round-off.
#[test]
fn sphere_relaxation_rate_is_the_closed_form() {
    for ca in [0.1, 1e-3, 1e-6] {
        let k = SlowManifold::of(&sphere(ca)).unwrap().unwrap().relaxation_rate();
        let exact = 2.0 / (3.0 * ca);
        assert!(
            (k - exact).abs() <= 1e-12 * exact,
            "Ca = {ca}: k = {k}, 2/(3Ca) = {exact}"
        );
    }
}

/// A sphere in unit shear on the manifold reaches Roscoe's (1967) steady tank-treading shape:
/// the quasi-static stretch gives D = 5Ca/4, its first correction the tilt θ = π/4 − 3Ca/4, and
/// what is dropped is O(Ca²) (module docs of `particle::manifold`). Bound: the error of D and θ
/// against Roscoe's exact steady state stays below Ca² and falls at least 3× per halving of Ca
/// (order 2 gives 4×; observed 8×, the Ca² terms of D and θ vanish for the sphere). The run is on
/// the manifold after its initial layer (δ = 1.5 Ca ≤ δ_max = 0.1) and never leaves it.
#[test]
fn manifold_sphere_in_shear_is_roscoes_steady_shape() {
    let err = |ca: f64| {
        let p = sphere(ca);
        let integ = Manifold::new(Stokesian::overdamped(1e-8).unwrap())
            .unwrap()
            .with_delta_max(0.1)
            .unwrap();
        let (s, memory): (Vec<State>, ManifoldMemory) = states_at(&integ, &p, &unit_shear(), &[10.0]);
        let report = integ.manifold_report(&memory);
        assert!(
            report.manifold_steps > 2 * report.full_steps && report.entered == 1 && report.left == 0,
            "{report:?}"
        );
        let sec = ShearPlaneSection::of(&p.total_distortion(&s[0].f));
        let exact = roscoe(ca).unwrap().steady;
        let d = (sec.r_long - sec.r_short) / (sec.r_long + sec.r_short);
        ((d - exact.deformation()).abs(), (sec.angle - exact.theta).abs())
    };
    let cas = [0.02, 0.01, 0.005];
    let errs: Vec<_> = cas.iter().map(|&c| err(c)).collect();
    for (ca, (ed, et)) in cas.iter().zip(&errs) {
        assert!(*ed <= ca * ca && *et <= ca * ca, "Ca = {ca}: {ed:e}, {et:e}");
    }
    for w in errs.windows(2) {
        assert!(w[0].0 >= 3.0 * w[1].0 && w[0].1 >= 3.0 * w[1].1, "{errs:?}");
    }
}

/// Against the full model on the same particle in a flow that turns and pulses along the path
/// ([`TurningShear`]; |∇u| ≤ 1.5, |d∇u/dt| ≤ 1.3): the largest |F_manifold − F_full| over
/// t ∈ [1.5, 10] stays below 16 δ² and falls at least 3× per halving of Ca (δ = the largest
/// ratio on the manifold). The bound: the dropped terms are O(δ²) in F and in its rate
/// relative to the flow's, so over the path of length T = 10 at rates ω ≤ 1.5 they add up to
/// at most δ²(1 + ωT) = 16 δ². The full model runs at rtol 10⁻¹⁰, far below the bound. Order 2
/// gives 4× per halving.
#[test]
fn manifold_follows_the_full_model_along_a_turning_flow() {
    let times: Vec<f64> = (1..=20).map(|i| 0.5 * f64::from(i)).collect();
    let err = |ca: f64| {
        let p = sphere(ca);
        let integ = Manifold::new(Stokesian::overdamped(1e-8).unwrap())
            .unwrap()
            .with_delta_max(0.1)
            .unwrap();
        let (reduced, memory) = states_at(&integ, &p, &TurningShear, &times);
        let (full, _) = states_at(&Stokesian::overdamped(1e-10).unwrap(), &p, &TurningShear, &times);
        let report = integ.manifold_report(&memory);
        assert!(
            report.manifold_steps > 2 * report.full_steps && report.left == 0,
            "{report:?}"
        );
        let e = reduced
            .iter()
            .zip(&full)
            .skip(2)
            .map(|(a, b)| (a.f - b.f).norm())
            .fold(0.0, f64::max);
        (e, report.max_ratio)
    };
    let errs: Vec<_> = [0.02, 0.01, 0.005].iter().map(|&c| err(c)).collect();
    for (e, delta) in &errs {
        assert!(*e <= 16.0 * delta * delta, "{errs:?}");
    }
    for w in errs.windows(2) {
        assert!(w[0].0 >= 3.0 * w[1].0, "{errs:?}");
    }
}

/// The steps of the issue: a stiffer particle must not take more steps. Spheres at
/// Ca = 10⁻², 10⁻³, 10⁻⁴, 10⁻⁵ in the turning flow at rtol 10⁻³ (the studies'), to t = 10: on the
/// manifold (δ_max = √rtol) the steps never grow with the stiffness and stay within the rigid
/// sphere's plus the full model's initial layer; the full model alone takes more steps
/// for stiffer particles here (checked, so the test fails on the old code path).
#[test]
fn stiffer_particles_take_no_more_steps_on_the_manifold() {
    let full = Stokesian::new(1e-3).unwrap();
    let cas = [1e-2, 1e-3, 1e-4, 1e-5];
    let reduced: Vec<u64> = cas
        .iter()
        .map(|&ca| steps_of(&Manifold::new(full).unwrap(), &sphere(ca)))
        .collect();
    let old: Vec<u64> = cas.iter().map(|&ca| steps_of(&full, &sphere(ca))).collect();
    let rigid = ShearShape::new(Shape::Sphere)
        .particle_with(
            &ShearScaling::new(1e-2, 1.0, 1e3).unwrap(),
            pseudorigid::material::Rigid,
        )
        .unwrap();
    let rigid = steps_of(&full, &rigid);
    println!("steps: manifold {reduced:?}, full {old:?}, rigid {rigid}");
    for w in reduced.windows(2) {
        assert!(w[1] <= w[0], "manifold {reduced:?}");
    }
    assert!(old.windows(2).any(|w| w[1] > w[0]), "full {old:?}");
}

/// Accepted steps of `integ` from rest to t = 10 in [`TurningShear`].
fn steps_of<I: TimeIntegrator, M: pseudorigid::material::Response>(integ: &I, p: &Particle<M>) -> u64 {
    let mut memory = I::Memory::default();
    let mut state = State::at_rest(Vec3::zeros());
    let mut dt: f64 = 1e-4;
    let mut n = 0;
    while state.t < 10.0 {
        let step = integ
            .step_with(p, &state, &mut memory, &TurningShear, dt.min(10.0 - state.t))
            .unwrap();
        dt = step.info.dt_next;
        state = step.state;
        n += 1;
        if 10.0 - state.t < 1e-12 {
            break;
        }
    }
    n
}

/// δ_max is set only through its checks (issue 61): NaN, ±∞, 0, 1 and 2 are refused with the
/// open interval named, and a tolerance whose √rtol would be δ_max ≥ 1 is refused as `rtol`.
#[test]
fn delta_max_is_refused_outside_the_open_unit_interval() {
    let full = Stokesian::overdamped(1e-8).unwrap();
    let manifold = Manifold::new(full).unwrap();
    assert_eq!(manifold.delta_max(), 1e-4);
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 0.0, 1.0, 2.0, -0.5] {
        let err = manifold.with_delta_max(bad).unwrap_err();
        assert!(
            matches!(err, ParamError::OutsideOpen { name: "delta_max", .. }),
            "{bad}: {err:?}"
        );
        assert!(err.to_string().contains("must lie in (0, 1)"), "{err}");
    }
    assert_eq!(manifold.with_delta_max(0.5).unwrap().delta_max(), 0.5);
    let err = Manifold::new(Stokesian::overdamped(4.0).unwrap()).unwrap_err();
    assert!(
        matches!(
            err,
            ParamError::OutsideOpen {
                name: "rtol",
                value: 4.0,
                ..
            }
        ),
        "{err:?}"
    );
}

/// A prolate of aspect ratio `lambda` whose long axis starts along `axis` (unit), at `ca`.
fn prolate(lambda: f64, ca: f64, axis: Vec3) -> Particle<NeoHooke> {
    let helper = if axis[2].abs() < 0.9 { Vec3::z() } else { Vec3::x() };
    let second = helper.cross(&axis).normalize();
    let third = axis.cross(&second);
    ShearScaling::new(ca, 1.0, 1e3)
        .unwrap()
        .particle([lambda, 1.0, 1.0], Mat3::from_columns(&[axis, second, third]))
        .unwrap()
}

/// The largest angle between the long material lines of the manifold and of the full model
/// (rtol 10⁻¹⁰) over `periods` Jeffery periods in unit shear (sampled 20 times a period from
/// the second half of the first: a first-order phase error that is periodic returns to zero
/// at whole periods), with the manifold's report.
fn orbit_error(
    lambda: f64,
    ca: f64,
    axis: Vec3,
    periods: f64,
) -> (f64, pseudorigid::integrator::manifold::ManifoldReport) {
    let p = prolate(lambda, ca, axis);
    let period = 2.0 * std::f64::consts::PI * (lambda + 1.0 / lambda);
    let times: Vec<f64> = (10..=(20.0 * periods) as usize)
        .map(|i| period * i as f64 / 20.0)
        .collect();
    let integ = Manifold::new(Stokesian::overdamped(1e-10).unwrap())
        .unwrap()
        .with_delta_max(0.3)
        .unwrap();
    let (reduced, memory) = states_at(&integ, &p, &unit_shear(), &times);
    let (full, _) = states_at(&Stokesian::overdamped(1e-10).unwrap(), &p, &unit_shear(), &times);
    let line = |s: &State| pseudorigid::particle::lines::material_line(p.shape(), &s.f, 0).normalize();
    let angle = reduced
        .iter()
        .zip(&full)
        .map(|(a, b)| line(a).dot(&line(b)).abs().min(1.0).acos())
        .fold(0.0, f64::max);
    (angle, integ.manifold_report(&memory))
}

/// Issue 61 measurement: the manifold's orientation error against the full model for stiff
/// prolates, and its ratio over a halving of Ca.
#[test]
#[ignore = "measurement (15 s): cargo test --test suite manifold_prolate_orientation_table -- --ignored --nocapture"]
fn manifold_prolate_orientation_table() {
    let quarter = std::f64::consts::FRAC_PI_4;
    let in_plane = Vec3::new(quarter.cos(), quarter.sin(), 0.0);
    let out_of_plane = Vec3::new(0.5, 0.5, std::f64::consts::FRAC_1_SQRT_2);
    for (name, axis) in [("in plane", in_plane), ("out of plane", out_of_plane)] {
        // λ = 20 relaxes 15× slower (δ ≈ 59 Ca against 4 Ca): on the manifold from Ca ≤ 2.5e-3.
        for (lambda, cas) in [
            (3.0, &[1e-2, 5e-3, 2.5e-3][..]),
            (20.0, &[1e-2, 5e-3, 2.5e-3, 1.25e-3, 6.25e-4, 3.125e-4][..]),
        ] {
            let mut last: Option<f64> = None;
            for &ca in cas {
                let (e, r) = orbit_error(lambda, ca, axis, 5.0);
                println!(
                    "{name}, lambda {lambda}, Ca {ca:.1e}: error {e:.3e}, ratio {:.2}, delta {:.3e}, steps {} on / {} off, left {}",
                    last.map_or(f64::NAN, |l| l / e),
                    r.max_ratio,
                    r.manifold_steps,
                    r.full_steps,
                    r.left
                );
                last = Some(e);
            }
        }
    }
}

/// Issue 61: a stiff prolate (λ = 3) on the manifold follows the full model's orientation to
/// second order in δ, in the shear plane and 45° out of it. The manifold turns it at the
/// deformed particle's spin (`particle::manifold::DeformedSpin`), whose dropped terms are
/// O(δ² |∇u|); Jeffery's orbits neither damp nor amplify a rotation error, so over a strain
/// γ̇t it adds up to O(δ² γ̇t): the largest angle over 5 periods (γ̇t = 105) stays below
/// γ̇t δ², and falls at least 3× per halving of Ca. Order 2 gives 4 (observed 4.00 in plane,
/// 4.15 out of it, so the next order moves it by under 8 %); the rigid twin's spin, first
/// order out of the plane, gave 2.04 there and 2.72 in the plane (`manifold_prolate_orientation_table`).
#[test]
fn manifold_prolate_orientation_is_second_order() {
    let quarter = std::f64::consts::FRAC_PI_4;
    let period = 2.0 * std::f64::consts::PI * (3.0 + 1.0 / 3.0);
    for axis in [
        Vec3::new(quarter.cos(), quarter.sin(), 0.0),
        Vec3::new(0.5, 0.5, std::f64::consts::FRAC_1_SQRT_2),
    ] {
        let errs: Vec<_> = [5e-3, 2.5e-3]
            .iter()
            .map(|&ca| orbit_error(3.0, ca, axis, 5.0))
            .collect();
        for (e, report) in &errs {
            assert!(
                report.left == 0 && report.manifold_steps > 20 * report.full_steps,
                "{report:?}"
            );
            assert!(*e <= 5.0 * period * report.max_ratio.powi(2), "{axis}: {errs:?}");
        }
        assert!(errs[0].0 >= 3.0 * errs[1].0, "{axis}: {errs:?}");
    }
}

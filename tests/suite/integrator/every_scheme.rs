//! One harness, run over every integrator: the same reference problems with exact or
//! independently computed solutions. A new integrator is tested by adding one `harness!` line.
//!
//! Reference problems:
//! - the exact Jeffery (1922) orbit of a quasi-rigid prolate in simple shear;
//! - the steady tank-treading of an initially spherical particle (Roscoe 1967, solved
//!   independently of any time integrator by `studies::tank_treading::roscoe`);
//! - a sphere settling from rest to the Stokes velocity v_s = (2/9)(ρ_s − ρ_f) g a²/μ_f;
//! - a wall-contact event located against its analytic crossing time;
//! - the end state's frame and flow sample shown to `on_step` ([`AcceptedStep`]) against the
//!   ones computed afresh at the step's state.
use pseudorigid::contact::{Boundary, ContactEvent, ContactModel, Extent, Gap, PatchRule};
use pseudorigid::driver::{AcceptedStep, Observers, Plan, Problem, Stop, advance, integrate};
use pseudorigid::ellipsoid::Ellipsoid;
use pseudorigid::integrator::choice::Auto;
use pseudorigid::integrator::manifold::Manifold;
use pseudorigid::integrator::{
    ErrorNorm, Frame, ImexAdaptive, ImexPaper, Scheme, Stokesian, TimeIntegrator, Tolerances,
};
use pseudorigid::material::Response;
use pseudorigid::prelude::*;
use pseudorigid::reference::{jeffery_flow_aligned_time, jeffery_phi};
use pseudorigid::studies::particles::Shape;
use pseudorigid::studies::section::ShearPlaneSection;
use pseudorigid::studies::shear_shape::ShearShape;
use pseudorigid::studies::tank_treading::roscoe;
use pseudorigid::tensor::nearest_rotation;

/// How an integrator is driven through the reference problems.
struct Setup<I> {
    integ: I,
    /// First (or fixed) step for a problem whose fastest rate is 1/γ̇.
    dt: f64,
    /// ρ* of the shear problems: 0 for the inertialess schemes (they ignore shape inertia,
    /// so ρ* only sets the barycentre's response), small for the inertial ones.
    rho_star: f64,
    /// Error of the scheme itself on these problems (its tolerance, or its Δt for first order).
    scheme_error: f64,
}

/// Jeffery orbit: a 3:1 prolate at Ca = 1e-4 starts along the flow and turns by half a period.
/// The exact rigid orbit differs from the pseudo-rigid one by the elastic stretch, O(Ca), and
/// by shape inertia, O(ρ*); each enters the angle with an O(1) constant (rigid-limit test: the
/// period error is ≤ Ca), so 10 (Ca + ρ*) plus 10× the scheme's own error bounds the angle.
fn jeffery_orbit<I: TimeIntegrator>(s: &Setup<I>) {
    let (r, ca) = (3.0, 1e-4);
    let shape = ShearShape::new(Shape::Prolate(r));
    let p = shape
        .particle(&ShearScaling::new(ca, s.rho_star.max(1e-3), 1e5).unwrap())
        .unwrap();
    let flow = LinearFlow::simple_shear(1.0).unwrap();
    let t_end = 0.5 * std::f64::consts::PI * (r + 1.0 / r);
    let (end, _) = advance(
        Problem::new(&s.integ, &p, &flow),
        State::at_rest(Vec3::zeros()),
        s.dt,
        t_end,
    )
    .unwrap();
    let sec = ShearPlaneSection::of(&p.total_distortion(&end.f));
    // ShearPlaneSection measures the long axis from the flow direction x; Jeffery's φ is from
    // the gradient direction y towards x, so the section angle is π/2 − φ (mod π).
    let phi = jeffery_phi(r, jeffery_flow_aligned_time(r) + t_end);
    let diff = (std::f64::consts::FRAC_PI_2 - phi - sec.angle).rem_euclid(std::f64::consts::PI);
    let err = diff.min(std::f64::consts::PI - diff);
    let bound = 10.0 * (ca + s.rho_star) + 10.0 * s.scheme_error;
    assert!(err <= bound, "{}: angle error {err:e} > {bound:e}", s.integ.name());
}

/// Steady tank-treading at Ca = 0.2 against Roscoe's steady equations. After t = 40 (> 20
/// relaxation times 1/(μ_s/μ_f)·… of the shape) the transient is below 1e-7 (the tank-treading
/// study's drift); what remains is shape inertia O(ρ*) and the scheme's error.
fn steady_tank_treading<I: TimeIntegrator>(s: &Setup<I>) {
    let ca = 0.2;
    let p = ShearShape::new(Shape::Sphere)
        .particle(&ShearScaling::new(ca, s.rho_star.max(1e-3), 1e5).unwrap())
        .unwrap();
    let flow = LinearFlow::simple_shear(1.0).unwrap();
    let (end, _) = advance(
        Problem::new(&s.integ, &p, &flow),
        State::at_rest(Vec3::zeros()),
        s.dt,
        40.0,
    )
    .unwrap();
    let sec = ShearPlaneSection::of(&p.total_distortion(&end.f));
    let d = (sec.r_long - sec.r_short) / (sec.r_long + sec.r_short);
    let exact = roscoe(ca).unwrap().steady;
    let bound = 10.0 * s.rho_star + 10.0 * s.scheme_error + 1e-6;
    assert!(
        (d - exact.deformation()).abs() <= bound,
        "{}: D = {d}, Roscoe {}",
        s.integ.name(),
        exact.deformation()
    );
    assert!(
        (sec.angle - exact.theta).abs() <= bound,
        "{}: θ = {}, Roscoe {}",
        s.integ.name(),
        sec.angle,
        exact.theta
    );
}

fn settling_particle() -> (Particle<NeoHooke>, f64) {
    let a = 0.5;
    let shape = Ellipsoid::new([a, a, a], Mat3::identity()).unwrap();
    let p = Particle::new(
        shape,
        NeoHooke::new(1.0, 1e3).unwrap(),
        Fluid::new(1.0, 1.0).unwrap(),
        2.0,
    )
    .unwrap()
    .with_gravity(Vec3::new(0.0, 0.0, -1.0))
    .unwrap();
    (p, 2.0 / 9.0 * (2.0 - 1.0) * a * a)
}

/// A sphere released at rest reaches the Stokes velocity. τ_D = m/(6πμa) = 1/9·…; after
/// t = 40 ≫ 20 τ_D the transient e^{−t/τ_D} is below 1e-15, and every scheme here has the exact
/// steady state as its fixed point (implicit Euler; L-stable Rosenbrock and Radau), so the
/// velocity error is the scheme's error on the transient, damped away: bounded by 10× it.
fn settling_sphere<I: TimeIntegrator>(s: &Setup<I>) {
    let (p, v_s) = settling_particle();
    let (end, _) = advance(
        Problem::new(&s.integ, &p, &Quiescent),
        State::at_rest(Vec3::new(0.0, 0.0, 1e3)),
        s.dt,
        40.0,
    )
    .unwrap();
    let err = (end.v - Vec3::new(0.0, 0.0, -v_s)).norm() / v_s;
    assert!(
        err <= 10.0 * s.scheme_error + 1e-12,
        "{}: relative velocity error {err:e}",
        s.integ.name()
    );
}

struct Floor;

impl Boundary for Floor {
    fn nearest(&self, x: &Vec3, extent: &Extent) -> Gap {
        Gap {
            patch: 0,
            gap: x[2] - extent.support(&-Vec3::z()),
            normal: -Vec3::z(),
            room: 0.0,
        }
    }
    fn patch_name(&self, _: usize) -> &str {
        "floor"
    }
    fn rule(&self, _: usize) -> PatchRule {
        PatchRule::Stick
    }
}

/// The sphere, already at its terminal velocity (x = x₀ + v_s t exactly, which the cubic
/// Hermite dense output reproduces exactly), touches the floor at t* = (h₀ − a)/v_s. The
/// event is located to |g| ≤ 1e-9 d_eq, i.e. |Δt| ≤ 1e-9/v_s = 1.8e-8, plus the scheme's
/// error on a uniform motion (round-off).
fn contact_event<I: TimeIntegrator>(s: &Setup<I>) {
    let (p, v_s) = settling_particle();
    let h0 = 3.0;
    let mut s0 = State::at_rest(Vec3::new(0.0, 0.0, h0));
    s0.v = Vec3::new(0.0, 0.0, -v_s);
    let contact = ContactEvent::new(&Floor, &p, &Quiescent, ContactModel::Extent);
    let mut memory = I::Memory::default();
    let plan = Plan::new(100.0, s.dt).unwrap();
    let out = integrate(
        Problem::new(&s.integ, &p, &Quiescent),
        s0,
        &mut memory,
        &plan,
        &[&contact],
        Observers::none(),
    )
    .unwrap();
    assert_eq!(out.stop, Stop::Event { index: 0 });
    let t_star = (h0 - 0.5) / v_s;
    assert!(
        (out.state.t - t_star).abs() <= 2e-8,
        "{}: t = {}, t* = {t_star}",
        s.integ.name(),
        out.state.t
    );
}

/// What `on_step` is shown of the end state is the end state's, bitwise: the frame
/// `Particle::frame` and the sample `FlowField::sample` give there, whether the scheme carried
/// them or the view computed them. A soft prolate, turned off the flow axes, released off the
/// axis of a Poiseuille flow, where u and ∇u change with x: a frame or sample of the step's
/// start, of an inner evaluation, or at the old barycentre (the IMEX step's) would differ.
/// Returns how many steps carried each (frame, sample) from the scheme.
fn end_evaluation<I: TimeIntegrator, M: Response, D: DragModel>(integ: &I, p: &Particle<M, D>, dt: f64) -> (u32, u32) {
    let flow = Poiseuille::new(1.0, 1.0).unwrap();
    let mut s0 = State::at_rest(Vec3::new(0.4, -0.2, 0.0));
    s0.f = nearest_rotation(&Mat3::new(1.0, 0.3, 0.0, -0.3, 1.0, 0.2, 0.0, -0.2, 1.0));
    let mut memory = I::Memory::default();
    let plan = Plan::new(50.0 * dt, dt).unwrap();
    let (mut steps, mut carried) = (0, (0, 0));
    integrate(
        Problem::new(integ, p, &flow),
        s0,
        &mut memory,
        &plan,
        &[],
        Observers::none().with_on_step(|step: &AcceptedStep| {
            let state = step.state();
            carried.0 += u32::from(step.step().end.frame.is_some());
            carried.1 += u32::from(step.step().end.flow.is_some());
            assert_eq!(
                *step.frame(),
                p.frame(&state.f),
                "{}: frame at t = {}",
                integ.name(),
                state.t
            );
            assert_eq!(
                step.flow().ok(),
                flow.sample(&state.x, state.t).ok().as_ref(),
                "{}: flow at t = {}",
                integ.name(),
                state.t
            );
            steps += 1;
        }),
    )
    .unwrap();
    assert!(steps >= 3, "{}: {steps} steps", integ.name());
    carried
}

/// A soft 2:1 prolate (Ca = 0.2, ρ* = 1e-3) for [`end_evaluation`].
fn soft_prolate() -> Particle<NeoHooke> {
    ShearShape::new(Shape::Prolate(2.0))
        .particle(&ShearScaling::new(0.2, 1e-3, 1e5).unwrap())
        .unwrap()
}

/// The rigid limit, whose F the Stokesian step projects onto SO(3) after its last evaluation:
/// the frame it evaluated is not the end state's, and the view must compute it.
#[test]
fn rigid_end_frame_is_the_projected_states() {
    let soft = soft_prolate();
    let p = soft.rigid_twin();
    let (frames, samples) = end_evaluation(&Stokesian::new(1e-8).unwrap(), &p, 1e-2);
    assert_eq!(frames, 0);
    assert!(samples > 0);
}

/// The schemes outside the harness: the slow-manifold step (its own F, the inner step's x and
/// t) and the automatic choice.
#[test]
fn manifold_and_auto_show_the_end_state() {
    let p = soft_prolate();
    let manifold = Manifold::new(Stokesian::overdamped(1e-8).unwrap()).unwrap();
    end_evaluation(&manifold, &p, 1e-2);
    let auto = Auto {
        tol: Tolerances::new(1e-8, 1e-8, 1e-14).unwrap(),
        norm: ErrorNorm::default(),
    };
    end_evaluation(&auto, &p, 1e-2);
}

macro_rules! harness {
    ($name:ident, $setup:expr) => {
        mod $name {
            use super::*;
            #[test]
            fn jeffery_orbit() {
                super::jeffery_orbit(&$setup);
            }
            #[test]
            fn steady_tank_treading() {
                super::steady_tank_treading(&$setup);
            }
            #[test]
            fn settling_sphere() {
                super::settling_sphere(&$setup);
            }
            #[test]
            fn contact_event() {
                super::contact_event(&$setup);
            }
            #[test]
            fn end_evaluation() {
                let setup = $setup;
                super::end_evaluation(&setup.integ, &super::soft_prolate(), setup.dt);
            }
        }
    };
}

// The paper's scheme at ρ* = 1e-3: Δt = ρ*/100 is inside the explicit limit of every shape here
// (ρ*/30 … ρ*/62) and λ_s Δt ≥ 1e5·1e-4·1e-5… (bulk ratio 1e5) keeps the volumetric update stable.
harness!(
    imex_paper,
    Setup {
        integ: ImexPaper::default(),
        dt: 1e-5,
        rho_star: 1e-3,
        scheme_error: 1e-5,
    }
);
harness!(
    imex_adaptive,
    Setup {
        integ: ImexAdaptive::new(1e-6).unwrap(),
        dt: 1e-5,
        rho_star: 1e-3,
        scheme_error: 1e-4,
    }
);
harness!(
    stokesian_rosenbrock23,
    Setup {
        integ: Stokesian::new(1e-8).unwrap().with_scheme(Scheme::Rosenbrock23),
        dt: 1e-3,
        rho_star: 0.0,
        scheme_error: 1e-7,
    }
);
harness!(
    stokesian_rosenbrock23_body,
    Setup {
        integ: Stokesian::new(1e-8)
            .unwrap()
            .with_scheme(Scheme::Rosenbrock23)
            .with_frame(Frame::Body),
        dt: 1e-3,
        rho_star: 0.0,
        scheme_error: 1e-7,
    }
);
harness!(
    stokesian_radau5,
    Setup {
        integ: Stokesian::new(1e-8).unwrap().with_scheme(Scheme::Radau5),
        dt: 1e-3,
        rho_star: 0.0,
        scheme_error: 1e-7,
    }
);

/// Radau IIA on the model: L-stable with no step-size collapse on a quasi-rigid particle
/// (Ca = 1e-4: the elastic relaxation rate μ_s/μ_f = 1e4 is the stiffness; an explicit or
/// A(α)-only scheme would need Δt ≲ 1e-4). Over one Jeffery half period (t ≈ 5.2) the step must
/// follow the rotation, not the stiffness: with rtol 1e-6 a few hundred steps at most, and once
/// the initial elastic transient (time scale μ_f/μ_s = 1e-4) has decayed, t > 0.1, every step
/// ≥ 1e-2; the work counts are snapshotted.
///
/// Rejections must be the exception, as on Hairer's stiff test problems (Van der Pol at
/// ε = 1e-6 rejects 14 % of its steps at rtol 1e-4 and under 1 % at 1e-6, `tests/radau.rs`):
/// at most one per four accepted steps. This catches the defect this test was written for:
/// Newton's verdict from one quotient plus a controller blind to Newton's reach rejected about
/// one attempt per accepted step here (106 per 101).
///
/// The bounds are the check; the work-count snapshot is a regression guard.
#[test]
fn radau_is_l_stable_on_a_quasi_rigid_particle() {
    let r = 3.0;
    let p = ShearShape::new(Shape::Prolate(r))
        .particle(&ShearScaling::new(1e-4, 1.0, 1e5).unwrap())
        .unwrap();
    let flow = LinearFlow::simple_shear(1.0).unwrap();
    let integ = Stokesian::overdamped(1e-6).unwrap().with_scheme(Scheme::Radau5);
    let mut memory = Default::default();
    let t_end = 0.5 * std::f64::consts::PI * (r + 1.0 / r);
    let mut smallest_after_first = f64::INFINITY;
    let out = integrate(
        Problem::new(&integ, &p, &flow),
        State::at_rest(Vec3::zeros()),
        &mut memory,
        &Plan::new(t_end, 1e-3).unwrap(),
        &[],
        Observers::none().with_on_step(|step| {
            // The last step is shortened to land on t_end.
            if step.dense().t_start() > 0.1 && step.state().t < t_end - 1e-9 {
                smallest_after_first = smallest_after_first.min(step.info().dt);
            }
        }),
    )
    .unwrap();
    assert!(out.stats.steps <= 300, "{:?}", out.stats);
    assert!(4 * out.stats.rejected <= out.stats.steps, "{:?}", out.stats);
    assert!(
        smallest_after_first >= 1e-2,
        "step collapsed to {smallest_after_first:e}"
    );
    insta::assert_snapshot!(format!(
        "steps {} rejected {} model_evals {} jacobians {}",
        out.stats.steps, out.stats.rejected, out.stats.rhs_evals, out.stats.jac_evals
    ));
}

/// Radau IIA on the inertialess model converges at high order: on the oblate Fig. 4 case over
/// t ≤ 5 the error against a 1e-12 run falls by more than 10^{0.8} per decade of tolerance
/// (an order-p method under per-step error control has global error ∝ tol^{p/(p+1)}, 10^{5/6}
/// per decade for p = 5; the Rosenbrock 2(3) pair gives 10^{2/3}), measured over two decades.
#[test]
fn radau_error_falls_faster_than_second_order_with_tolerance() {
    let p = ShearShape::new(Shape::Oblate(2.5))
        .particle(&ShearScaling::new(0.4, 1.0, 1e5).unwrap())
        .unwrap();
    let flow = LinearFlow::simple_shear(1.0).unwrap();
    let run = |tol: f64| {
        let integ = Stokesian::overdamped(tol).unwrap().with_scheme(Scheme::Radau5);
        advance(
            Problem::new(&integ, &p, &flow),
            State::at_rest(Vec3::zeros()),
            1e-3,
            5.0,
        )
        .unwrap()
        .0
        .f
    };
    let reference = run(1e-12);
    let e5 = (run(1e-5) - reference).amax();
    let e7 = (run(1e-7) - reference).amax();
    assert!(e5 / e7 >= 10f64.powf(1.6), "errors {e5:e} (1e-5), {e7:e} (1e-7)");
}

/// One name per integrator: the paper's IMEX scheme is registered under the name its runs and
/// datasets report ([`TimeIntegrator::name`], `imex_paper`), which the registry lists, and the
/// earlier scene files' `imex` reads as it.
#[test]
fn imex_is_registered_under_the_name_it_reports() {
    use pseudorigid::integrator::registry::{by_name, names};
    use pseudorigid::registry::Values;
    assert_eq!(ImexPaper::default().name(), "imex_paper");
    for given in ["imex_paper", "imex"] {
        let integrator = by_name(given, &Values::new()).unwrap();
        assert_eq!(integrator.name(), "imex_paper", "{given}");
    }
    let listed = names();
    assert!(
        listed.contains(&"imex_paper") && !listed.contains(&"imex"),
        "{listed:?}"
    );
}

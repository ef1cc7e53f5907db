//! The driver and integrator settings on the reliability audit's reproducers (defects 6, 7, 9):
//! bad times and settings are typed errors, never a silent NaN, a rewound clock or a hang.
use pseudorigid::driver::{Budget, Observers, Plan, Problem, RunStats, advance, run};
use pseudorigid::integrator::newton::NewtonOptions;
use pseudorigid::integrator::{ImexAdaptive, Stokesian, Tolerances};
use pseudorigid::prelude::*;

fn particle() -> Particle<NeoHooke> {
    ShearScaling::new(0.4, 0.1, 1e3)
        .unwrap()
        .particle([2.5, 2.5, 1.0], Mat3::identity())
        .unwrap()
}

fn shear() -> LinearFlow {
    LinearFlow::simple_shear(1.0).unwrap()
}

/// Defect 6: `run(.., &[NaN], ..)` returned Ok with t = NaN; `advance` from t = 5 to 1 rewound
/// the clock; a NaN or infinite end time reported success after 0 steps.
#[test]
fn bad_times_are_typed_errors() {
    let p = particle();
    let s0 = State::at_rest(Vec3::zeros());
    let r = run(
        Problem::new(&ImexPaper::default(), &p, &shear()),
        s0,
        1e-3,
        &[f64::NAN],
        Observers::none(),
    );
    assert!(matches!(r, Err(StepError::Param(_))), "{r:?}");
    let mut late = s0;
    late.t = 5.0;
    let r = advance(Problem::new(&ImexPaper::default(), &p, &shear()), late, 1e-3, 1.0);
    assert!(matches!(r, Err(StepError::Param(_))), "{r:?}");
    for t_end in [f64::NAN, f64::INFINITY] {
        assert!(Plan::new(t_end, 1e-3).is_err());
    }
    assert!(Plan::new(1.0, 1e-3).unwrap().with_outputs(&[0.5, 0.2]).is_err());
}

/// Defect 7: t = 1 with Δt = 1e-17 and t = 1e5 with Δt = 1e-12 looped forever (t + h == t).
#[test]
fn steps_that_do_not_advance_time_are_refused() {
    let p = particle();
    for (t0, dt) in [(1.0, 1e-17), (1e5, 1e-12)] {
        let mut s = State::at_rest(Vec3::zeros());
        s.t = t0;
        let r = advance(Problem::new(&ImexPaper::default(), &p, &shear()), s, dt, t0 + 1.0);
        assert!(matches!(r, Err(StepError::NoProgress { .. })), "{r:?}");
    }
}

/// A budget bounds every run: exceeding it is a typed error carrying the steps taken.
#[test]
fn budget_is_enforced() {
    let p = particle();
    let plan = Plan::new(10.0, 1e-4).unwrap().with_budget(Budget {
        max_steps: 100,
        wall_time: None,
    });
    let mut memory = Default::default();
    let r = pseudorigid::driver::integrate(
        Problem::new(&ImexPaper::default(), &p, &shear()),
        State::at_rest(Vec3::zeros()),
        &mut memory,
        &plan,
        &[],
        Observers::none(),
    );
    let failure = r.unwrap_err();
    assert!(
        matches!(failure.error, StepError::BudgetExceeded { steps: 100, .. }),
        "{failure:?}"
    );
    assert_eq!(failure.stats.steps, 100);
}

/// A flow that refuses every query after `t_fail` (not a domain boundary: the driver does not
/// retry it).
struct FailsAfter {
    t_fail: f64,
}

impl FlowField for FailsAfter {
    fn sample(&self, x: &Vec3, t: f64) -> Result<pseudorigid::flow::FlowSample, pseudorigid::error::FlowError> {
        if t > self.t_fail {
            return Err(pseudorigid::error::FlowError::NonFiniteSample {
                x: [x[0], x[1], x[2]],
                t,
                u: [f64::INFINITY; 3],
            });
        }
        shear().sample(x, t)
    }
}

/// A run that fails after k accepted steps reports the error, those k steps' statistics and the
/// state after the k-th step: fixed steps of 10⁻³ and a flow that fails after t = 0.0105 accept
/// k = 10 steps. The statistics are those an observer accumulates with [`RunStats::record`].
#[test]
fn a_failed_run_reports_its_statistics_and_last_state() {
    let p = particle();
    let mut memory = Default::default();
    let mut seen = RunStats::default();
    let mut last = None;
    let failure = pseudorigid::driver::integrate(
        Problem::new(&ImexPaper::default(), &p, &FailsAfter { t_fail: 0.0105 }),
        State::at_rest(Vec3::zeros()),
        &mut memory,
        &Plan::new(1.0, 1e-3).unwrap(),
        &[],
        Observers::none().with_on_step(|step| {
            seen.record(step.info());
            last = Some(*step.state());
        }),
    )
    .unwrap_err();
    assert!(matches!(failure.error, StepError::Flow(_)), "{failure:?}");
    assert_eq!(failure.stats.steps, 10);
    assert_eq!(failure.stats, seen);
    assert_eq!(Some(failure.state), last);
    let text = failure.to_string();
    assert!(text.contains("after 10 accepted steps"), "{text}");
    // `?` into a step error keeps the cause.
    let bare: StepError = failure.clone().into();
    assert_eq!(bare, failure.error);
}

/// Defect 9: h_min ≤ 0 or NaN looped forever, `Stokesian::new(NaN)` disabled error control,
/// Newton with tol ≤ 0 ran 4·10⁹ iterations. Each is now refused at construction.
#[test]
fn integrator_settings_validate_themselves() {
    assert!(Stokesian::new(f64::NAN).is_err());
    assert!(Stokesian::new(0.0).is_err());
    assert!(ImexAdaptive::new(-1e-3).is_err());
    for h_min in [0.0, -1.0, f64::NAN] {
        assert!(Tolerances::new(1e-6, 1e-6, h_min).is_err());
    }
    assert!(NewtonOptions::new(0.0, 10).is_err());
    assert!(NewtonOptions::new(1e-12, 0).is_err());
    assert!(NewtonOptions::new(1e-12, u32::MAX).is_err());
}

/// A point particle carried out through an exit: the flow is uniform up to just past the exit
/// plane x₁ = 1 and refuses every point beyond x₁ = 1.001 (as a blended mesh field does beyond
/// its boundary cells' supports). A step of 0.5 that ends past the margin leaves the domain
/// before the exit event can see the crossing; the driver retries it shorter, so the particle
/// escapes at t = 0.9 (from x₁ = 0.1 at unit speed) instead of failing "outside the domain".
#[test]
fn a_step_past_an_exit_is_retried_and_the_particle_escapes() {
    use pseudorigid::contact::{ContactEvent, ContactModel, PatchRule, Plane, Planes};
    use pseudorigid::driver::{Problem, Stop, until_event};
    use pseudorigid::material::Rigid;
    struct Channel;
    impl FlowField for Channel {
        fn sample(&self, x: &Vec3, _t: f64) -> Result<FlowSample, FlowError> {
            if x[0] > 1.001 {
                return Err(FlowError::OutsideMesh {
                    x: [x[0], x[1], x[2]],
                    patch: "outlet".into(),
                    distance: x[0] - 1.001,
                });
            }
            Ok(FlowSample::steady(Vec3::x(), Mat3::zeros()))
        }
    }
    let exit = Planes::new(vec![Plane {
        name: "outlet".into(),
        point: Vec3::x(),
        normal: Vec3::x(),
        rule: PatchRule::Exit,
    }])
    .unwrap();
    let shape = pseudorigid::ellipsoid::Ellipsoid::new([0.01; 3], Mat3::identity()).unwrap();
    let p = Particle::new(shape, Rigid, Fluid::new(1.0, 1.0).unwrap(), 1.0).unwrap();
    let integrator = Stokesian::overdamped(1e-8).unwrap();
    let contact = ContactEvent::new(&exit, &p, &Channel, ContactModel::Barycentre { radius: 0.0 });
    let plan = Plan::new(10.0, 0.5).unwrap().with_dt_max(0.5).unwrap();
    let start = State::at_rest(Vec3::new(0.1, 0.0, 0.0));
    let out = until_event(Problem::new(&integrator, &p, &Channel), start, &plan, &[&contact]).unwrap();
    assert_eq!(out.stop, Stop::Event { index: 0 });
    assert!((out.state.t - 0.9).abs() < 1e-6, "escaped at {}", out.state.t);
}

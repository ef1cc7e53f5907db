//! Seeded fuzzing of the public API: no input may panic, hang or return `Ok` with a non-finite
//! (or corrupt) result.
//!
//! Each class is one function `fn(seed) -> Outcome` that draws its inputs from a SplitMix64
//! stream seeded by `seed`, calls the API and classifies the result. Every case runs under
//! `catch_unwind` on its own worker thread; a watchdog turns a case that does not finish within
//! [`WATCHDOG`] into a `hang` that names the seed (the stuck thread is abandoned, so after
//! [`MAX_HANGS_PER_CLASS`] hangs the rest of that class is skipped instead of stalling CI).
//!
//! Reproduce a failure with `FUZZ_SEED=<base> cargo test --release --test suite cross::fuzz_api`; a case's
//! seed is `base + class index · 2³² + case index`. The long run takes its per-class count from
//! `FUZZ_CASES`: `FUZZ_CASES=100000 cargo test --release --test suite cross::fuzz_api -- --ignored`.
//!
//! To add a class (a driver or integrator family, say), write one `fn(u64) -> Outcome` and add
//! a line to [`CLASSES`].

use pseudorigid::driver::{Budget, Observers, Plan, Problem, integrate};
use pseudorigid::ellipsoid::integrals::{carlson_rd, carlson_rf};
use pseudorigid::flow::openfoam::{FoamCase, FoamFlow, Layout, cavity_block, read_vol_field};
use pseudorigid::integrator::imex::StabilityGuard;
use pseudorigid::integrator::newton::NewtonOptions;
use pseudorigid::integrator::{ImexAdaptive, Scheme, Stokesian, Tolerances};
use pseudorigid::output::{Csv, write_atomic};
use pseudorigid::prelude::*;
use pseudorigid::studies::cavity_benchmark::CI;
use serde_json::Value;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::PathBuf;
use std::sync::mpsc;
use std::time::Duration;

/// Longest a single case may run. The slowest legitimate case (eight threads writing one file,
/// or one 12³ cavity field read and reconstructed) takes milliseconds even unoptimised; a thousand
/// times that is a hang, not a slow machine.
const WATCHDOG: Duration = Duration::from_secs(10);

/// Abandoned (hung) threads keep a core busy; after this many, the class stops.
const MAX_HANGS_PER_CLASS: usize = 2;

/// Cases per class in the CI-sized run (11 classes: a few thousand cases, seconds in release).
const CI_CASES: u64 = 400;

/// What one case observed.
#[derive(Debug)]
enum Outcome {
    /// `Ok` and every number in it finite (and any round trip exact).
    Finite,
    /// A typed error (`Err` of the documented error type).
    Typed,
    /// `Ok` with a NaN/∞ inside, or an output that does not read back: a defect.
    Silent(String),
}

/// Outcome of a supervised case.
#[derive(Debug)]
enum Verdict {
    Finite,
    Typed,
    Silent(String),
    Panic(String),
    Hang,
}

type Case = fn(u64) -> Outcome;

/// The classes, in a fixed order (the order enters the seeds).
const CLASSES: &[(&str, Case)] = &[
    ("scaling", scaling_case),
    ("particle", particle_case),
    ("serde_params", serde_case),
    ("flows", flow_case),
    ("carlson", carlson_case),
    ("integrals", integrals_case),
    ("states", state_case),
    ("foam_u", foam_u_case),
    ("foam_mesh", foam_mesh_case),
    ("outputs", output_case),
    ("driver", driver_case),
    ("steps", step_case),
    ("foam_decomposed", foam_decomposed_case),
];

// ---------------------------------------------------------------------------------------------
// Generator

/// SplitMix64 (Steele, Lea & Flood 2014): tiny, seedable and statistically adequate for input
/// generation; written out here so a seed reproduces a case independently of any crate version.
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Self {
        Self(seed)
    }

    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in 0..n, and 0 for n = 0 (an emptied buffer).
    fn below(&mut self, n: u64) -> u64 {
        self.next_u64().checked_rem(n).unwrap_or(0)
    }

    fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    fn pick<T: Copy>(&mut self, xs: &[T]) -> T {
        xs[self.below(xs.len() as u64) as usize]
    }

    /// 10^(uniform in [lo, hi]).
    fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        10f64.powf(lo + (hi - lo) * self.unit())
    }

    fn normal(&mut self) -> f64 {
        let u1 = 1.0 - self.unit();
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * self.unit()).cos()
    }

    /// A float that is mostly ordinary (positive, 1e-3..1e3) and otherwise an edge case: NaN,
    /// ±∞, ±0, subnormal, overflow-prone, negative, or anywhere in the exponent range.
    fn wild(&mut self) -> f64 {
        match self.below(24) {
            0 => f64::NAN,
            1 => f64::INFINITY,
            2 => f64::NEG_INFINITY,
            3 => self.pick(&[0.0, -0.0]),
            4 => self.pick(&[5e-324, 1e-320, f64::MIN_POSITIVE, 1e-300, 1e-160, 1e-155]),
            5 => self.pick(&[f64::MAX, 1e308, 1e300, 1e160, 1e155, 1e100]),
            6 => -self.log_uniform(-6.0, 6.0),
            7 | 8 => {
                let v = self.log_uniform(-320.0, 308.0);
                if self.chance(0.5) { v } else { -v }
            }
            _ => self.log_uniform(-3.0, 3.0),
        }
    }

    /// Ordinary with probability 0.9, else [`Rng::wild`]: for classes with many parameters, so
    /// that a fair share of cases gets past validation.
    fn mostly(&mut self) -> f64 {
        if self.chance(0.9) {
            self.log_uniform(-3.0, 3.0)
        } else {
            self.wild()
        }
    }

    /// Like [`Rng::wild`] but finite (what JSON can carry).
    fn wild_finite(&mut self) -> f64 {
        let v = self.wild();
        if v.is_finite() { v } else { self.log_uniform(-3.0, 3.0) }
    }

    fn wild_vec(&mut self) -> Vec3 {
        Vec3::new(self.wild_signed(), self.wild_signed(), self.wild_signed())
    }

    /// [`Rng::wild`] with a random sign on ordinary values.
    fn wild_signed(&mut self) -> f64 {
        let v = self.wild();
        if self.chance(0.5) { v } else { -v }
    }

    /// Haar rotation (normalised Gaussian quaternion), sometimes perturbed off SO(3).
    fn rotation(&mut self) -> Mat3 {
        let q = nalgebra::Quaternion::new(self.normal(), self.normal(), self.normal(), self.normal());
        let r = nalgebra::UnitQuaternion::from_quaternion(q)
            .to_rotation_matrix()
            .into_inner();
        match self.below(20) {
            0 => r * self.pick(&[1.0 + 1e-9, -1.0, 0.0, f64::NAN]),
            1 => r + Mat3::from_fn(|_, _| 1e-12 * self.normal()),
            _ => r,
        }
    }

    /// Axis ratios: mostly within 1e-3..1e3, sometimes extreme or invalid.
    fn ratios(&mut self) -> [f64; 3] {
        [0; 3].map(|_| {
            if self.chance(0.8) {
                self.log_uniform(-3.0, 3.0)
            } else {
                self.wild()
            }
        })
    }
}

// ---------------------------------------------------------------------------------------------
// Finiteness checks

fn finite_all(values: impl IntoIterator<Item = f64>) -> bool {
    values.into_iter().all(f64::is_finite)
}

fn check(ok: bool, what: impl FnOnce() -> String) -> Outcome {
    if ok { Outcome::Finite } else { Outcome::Silent(what()) }
}

/// Every cached quantity of a particle is finite, the mass positive, and the rest geometry
/// (frame, integrals, traction coefficients) finite.
fn check_particle<M: Hyperelastic, D: DragModel>(p: &Particle<M, D>) -> Outcome {
    let geometry = p.geometry(&Mat3::identity());
    let ok = p.mass() > 0.0
        && p.volume0() > 0.0
        && finite_all([p.mass(), p.volume0(), p.rho_solid()])
        && finite_all(p.theta_inv().iter().copied())
        && finite_all(p.shape_tensor().iter().copied())
        && finite_all([p.material().shear_modulus(), p.material().lame_lambda()])
        && finite_all(geometry.frame.r.iter().copied())
        && finite_all(geometry.ints.alpha.iter().chain(&geometry.ints.alpha_p).copied())
        && finite_all(geometry.ints.alpha_pp.iter().copied())
        && geometry.ints.chi0.is_finite();
    check(ok, || {
        format!(
            "particle: m = {}, vol = {}, Θ⁻¹ = {:?}, rest r = {:?}, χ₀ = {}",
            p.mass(),
            p.volume0(),
            p.theta_inv().as_slice(),
            geometry.frame.r.as_slice(),
            geometry.ints.chi0
        )
    })
}

fn check_sample(s: &FlowSample, x: &Vec3) -> Outcome {
    check(finite_all(s.u.iter().chain(s.grad_u.iter()).copied()), || {
        format!(
            "flow sample at {:?}: u = {:?}, ∇u = {:?}",
            x.as_slice(),
            s.u.as_slice(),
            s.grad_u.as_slice()
        )
    })
}

macro_rules! typed {
    ($e:expr) => {
        match $e {
            Ok(v) => v,
            Err(_) => return Outcome::Typed,
        }
    };
}

// ---------------------------------------------------------------------------------------------
// Classes

/// Nondimensional groups → Neo-Hooke particle (defects 2 and 4).
fn scaling_case(seed: u64) -> Outcome {
    let mut rng = Rng::new(seed);
    let scaling = if rng.chance(0.8) {
        typed!(ShearScaling::new(rng.wild(), rng.wild(), rng.wild()))
    } else {
        typed!(ShearScaling::from_physical(
            rng.wild(),
            rng.wild(),
            rng.wild(),
            rng.wild(),
            rng.wild(),
            rng.wild()
        ))
    };
    let particle = typed!(scaling.particle(rng.ratios(), rng.rotation()));
    check_particle(&particle)
}

/// Shapes, materials, fluids and densities assembled by hand.
fn particle_case(seed: u64) -> Outcome {
    let mut rng = Rng::new(seed);
    let axes = rng.rotation();
    let shape = if rng.chance(0.5) {
        typed!(Ellipsoid::new([rng.mostly(), rng.mostly(), rng.mostly()], axes))
    } else {
        typed!(Ellipsoid::with_volume_diameter(rng.ratios(), rng.mostly(), axes))
    };
    let fluid = typed!(Fluid::new(rng.mostly(), rng.mostly()));
    let rho = rng.mostly();
    if rng.chance(0.5) {
        let material = typed!(NeoHooke::new(rng.mostly(), rng.mostly()));
        let p = typed!(Particle::new(shape, material, fluid, rho));
        let p = typed!(p.with_gravity(rng.wild_vec()));
        check_particle(&p)
    } else {
        let material = typed!(MooneyRivlin::new(rng.mostly(), rng.mostly(), rng.mostly()));
        let p = typed!(Particle::with_drag(shape, material, StokesSphere, fluid, rho));
        check_particle(&p)
    }
}

/// Replace each number in a JSON document by a finite edge value with probability ½.
fn mutate_json(v: &mut Value, rng: &mut Rng) {
    match v {
        Value::Number(_) if rng.chance(0.5) => {
            *v = serde_json::Number::from_f64(rng.wild_finite()).map_or(Value::Null, Value::Number);
        }
        Value::Array(items) => items.iter_mut().for_each(|x| mutate_json(x, rng)),
        Value::Object(map) => map.values_mut().for_each(|x| mutate_json(x, rng)),
        _ => {}
    }
}

fn mutated<T: serde::Serialize>(valid: &T, rng: &mut Rng) -> String {
    let mut v = serde_json::to_value(valid).expect("parameter types serialise");
    mutate_json(&mut v, rng);
    v.to_string()
}

/// Parameter types read from JSON must not bypass their constructors' validation (defect 2).
fn serde_case(seed: u64) -> Outcome {
    let mut rng = Rng::new(seed);
    let sphere = || Ellipsoid::aligned([0.5; 3]).expect("valid sphere");
    let water = || Fluid::new(1.0, 1.0).expect("valid fluid");
    let neo = || NeoHooke::new(1.0, 10.0).expect("valid law");
    match rng.below(7) {
        0 => {
            let json = mutated(&ShearScaling::new(0.1, 0.1, 1e3).expect("valid"), &mut rng);
            let s: ShearScaling = typed!(serde_json::from_str(&json));
            let p = typed!(s.particle(rng.ratios(), Mat3::identity()));
            check_particle(&p)
        }
        1 => {
            let json = mutated(&neo(), &mut rng);
            let m: NeoHooke = typed!(serde_json::from_str(&json));
            check_particle(&typed!(Particle::new(sphere(), m, water(), 1.0)))
        }
        2 => {
            let json = mutated(&MooneyRivlin::new(1.0, 0.5, 10.0).expect("valid"), &mut rng);
            let m: MooneyRivlin = typed!(serde_json::from_str(&json));
            check_particle(&typed!(Particle::new(sphere(), m, water(), 1.0)))
        }
        3 => {
            let json = mutated(
                &Ellipsoid::new([1.0, 0.5, 0.25], rng.rotation()).unwrap_or(sphere()),
                &mut rng,
            );
            let e: Ellipsoid = typed!(serde_json::from_str(&json));
            check_particle(&typed!(Particle::new(e, neo(), water(), 1.0)))
        }
        4 => {
            let json = mutated(&water(), &mut rng);
            let f: Fluid = typed!(serde_json::from_str(&json));
            let ok = f.mu.is_finite() && f.mu > 0.0 && f.rho.is_finite() && f.rho >= 0.0;
            if !ok {
                return Outcome::Silent(format!("fluid {f:?} accepted"));
            }
            check_particle(&typed!(Particle::new(sphere(), neo(), f, 1.0)))
        }
        5 => {
            let json = mutated(&LinearFlow::simple_shear(1.0).expect("valid"), &mut rng);
            let flow: LinearFlow = typed!(serde_json::from_str(&json));
            let x = Vec3::new(rng.normal(), rng.normal(), rng.normal());
            check_sample(&typed!(flow.sample(&x, 0.0)), &x)
        }
        _ => {
            let json = mutated(&Poiseuille::new(1.0, 1.0).expect("valid"), &mut rng);
            let flow: Poiseuille = typed!(serde_json::from_str(&json));
            let x = Vec3::new(rng.normal(), 0.3 * rng.unit(), 0.3 * rng.unit());
            check_sample(&typed!(flow.sample(&x, 0.0)), &x)
        }
    }
}

/// Analytic flows with edge parameters sampled at edge points (defect 5).
fn flow_case(seed: u64) -> Outcome {
    let mut rng = Rng::new(seed);
    let x = if rng.chance(0.5) {
        Vec3::new(rng.normal(), rng.normal(), rng.normal())
    } else {
        rng.wild_vec()
    };
    let t = if rng.chance(0.8) { rng.unit() } else { rng.wild_signed() };
    let sample = match rng.below(6) {
        0 => LinearFlow::simple_shear(rng.wild_signed()).map(|f| f.sample(&x, t)),
        1 => LinearFlow::planar_extension(rng.wild_signed()).map(|f| f.sample(&x, t)),
        2 => LinearFlow::uniaxial_extension(rng.wild_signed()).map(|f| f.sample(&x, t)),
        3 => {
            let l = Mat3::from_fn(|_, _| rng.wild_signed());
            let l = l - Mat3::identity() * (l.trace() / 3.0);
            LinearFlow::new(rng.wild_vec(), l).map(|f| f.sample(&x, t))
        }
        4 => {
            let (radius, mean) = (rng.wild(), rng.wild_signed());
            // Half the points inside the pipe, scaled with its radius.
            let x = if rng.chance(0.5) && radius.is_finite() {
                Vec3::new(rng.normal(), 0.5 * radius * rng.unit(), 0.5 * radius * rng.unit())
            } else {
                x
            };
            match Poiseuille::new(radius, mean) {
                Ok(f) => match f.sample(&x, t) {
                    Ok(s) => return check_sample(&s, &x),
                    Err(_) => return Outcome::Typed,
                },
                Err(_) => return Outcome::Typed,
            }
        }
        _ => Ok(Quiescent.sample(&x, t)),
    };
    check_sample(&typed!(typed!(sample)), &x)
}

fn carlson_arg(rng: &mut Rng) -> f64 {
    if rng.chance(0.5) {
        rng.log_uniform(-3.0, 3.0)
    } else {
        rng.wild()
    }
}

/// Carlson's R_F and R_D (defect 10).
fn carlson_case(seed: u64) -> Outcome {
    let mut rng = Rng::new(seed);
    let (x, y, z) = (carlson_arg(&mut rng), carlson_arg(&mut rng), carlson_arg(&mut rng));
    let rf = typed!(carlson_rf(x, y, z));
    let rd = typed!(carlson_rd(x, y, z));
    check(rf.is_finite() && rd.is_finite(), || {
        format!("R_F({x}, {y}, {z}) = {rf}, R_D = {rd}")
    })
}

/// Jeffery's integrals of an ellipsoid with edge semi-axes (defect 10).
fn integrals_case(seed: u64) -> Outcome {
    let mut rng = Rng::new(seed);
    let r = Vec3::new(carlson_arg(&mut rng), carlson_arg(&mut rng), carlson_arg(&mut rng));
    // The unchecked constructor must agree with the checked one, or be NaN throughout (its
    // documented path for invalid semi-axes).
    let unchecked = EllipsoidIntegrals::new(&r);
    let Ok(ints) = EllipsoidIntegrals::try_new(&r) else {
        let all_nan = unchecked
            .alpha
            .iter()
            .chain(&unchecked.alpha_p)
            .chain(&unchecked.alpha_pp)
            .all(|v| v.is_nan())
            && unchecked.chi0.is_nan();
        return if all_nan {
            Outcome::Typed
        } else {
            Outcome::Silent(format!("try_new fails but new gives {unchecked:?}"))
        };
    };
    let ok = finite_all(ints.alpha.iter().chain(&ints.alpha_p).chain(&ints.alpha_pp).copied())
        && ints.chi0.is_finite()
        && ints == unchecked;
    check(ok, || format!("integrals of r = {:?}: {ints:?}", r.as_slice()))
}

/// Particle states: validation must reject exactly the non-finite and inverted ones, and a
/// validated state must have a finite principal frame.
fn state_case(seed: u64) -> Outcome {
    let mut rng = Rng::new(seed);
    let entry = |rng: &mut Rng| {
        if rng.chance(0.9) {
            rng.normal()
        } else {
            rng.wild_signed()
        }
    };
    let f = match rng.below(3) {
        0 => Mat3::identity() + Mat3::from_fn(|_, _| 0.3 * rng.normal()),
        1 => rng.rotation() * Mat3::from_diagonal(&Vec3::new(rng.wild(), rng.wild(), rng.wild())),
        _ => Mat3::from_fn(|_, _| entry(&mut rng)),
    };
    let state = State {
        t: if rng.chance(0.9) { rng.unit() } else { rng.wild_signed() },
        x: Vec3::from_fn(|_, _| entry(&mut rng)),
        v: Vec3::from_fn(|_, _| entry(&mut rng)),
        f,
        a: Mat3::from_fn(|_, _| entry(&mut rng)),
    };
    typed!(state.validate());
    let fields = [state.t]
        .into_iter()
        .chain(state.x.iter().copied())
        .chain(state.v.iter().copied());
    if !(finite_all(fields.chain(state.f.iter().copied()).chain(state.a.iter().copied())) && state.det_f() > 0.0) {
        return Outcome::Silent(format!("state accepted: {state:?}"));
    }
    let frame = PrincipalFrame::from_total_distortion(&state.f);
    check(finite_all(frame.r.iter().chain(frame.q.iter()).copied()), || {
        format!("frame of a valid state: {frame:?}")
    })
}

/// One of the integrators with fuzzed settings (defect 9: settings validate themselves).
enum AnyIntegrator {
    Imex(ImexPaper),
    ImexAdaptive(ImexAdaptive),
    Stokesian(Stokesian),
}

fn any_integrator(rng: &mut Rng) -> Result<AnyIntegrator, ParamError> {
    let tol = if rng.chance(0.8) {
        rng.log_uniform(-9.0, -2.0)
    } else {
        rng.wild_signed()
    };
    Ok(match rng.below(5) {
        0 => AnyIntegrator::Imex(ImexPaper::default()),
        1 => AnyIntegrator::Imex(ImexPaper {
            newton: NewtonOptions::new(tol, rng.pick(&[0, 1, 3, 12, 100, 101, u32::MAX]))?,
            guard: rng.pick(&[StabilityGuard::Exact, StabilityGuard::Off, StabilityGuard::default()]),
        }),
        2 => AnyIntegrator::ImexAdaptive(ImexAdaptive::new(tol)?),
        3 => AnyIntegrator::Stokesian(Stokesian::new(tol)?.with_scheme(Scheme::Radau5)),
        _ => {
            let mut s = Stokesian::overdamped(tol)?;
            s.tol = Tolerances::new(tol, rng.mostly(), rng.mostly() * 1e-12)?;
            AnyIntegrator::Stokesian(s.with_scheme(rng.pick(&[Scheme::Radau5, Scheme::Rosenbrock23])))
        }
    })
}

/// A particle that mostly gets past validation (shape, Ca, ρ*, bulk ratio mostly ordinary).
fn any_particle(rng: &mut Rng) -> Result<Particle<NeoHooke>, ParamError> {
    let ratios = [rng.mostly(), rng.mostly(), rng.mostly()].map(|r| r.clamp(-1e6, 1e6));
    let scaling = ShearScaling::new(rng.mostly(), rng.mostly(), rng.mostly())?;
    scaling.particle(ratios, rng.rotation())
}

/// A short run through the driver with fuzzed times, outputs and budget (defects 6 and 7):
/// `Ok` must end exactly at t_end with a finite, oriented state.
fn driver_case(seed: u64) -> Outcome {
    let mut rng = Rng::new(seed);
    let integ = typed!(any_integrator(&mut rng));
    let p = typed!(any_particle(&mut rng));
    let flow = typed!(LinearFlow::simple_shear(if rng.chance(0.8) {
        1.0
    } else {
        rng.wild_signed()
    }));
    let mut start = State::at_rest(Vec3::zeros());
    start.t = if rng.chance(0.7) { 0.0 } else { rng.wild_signed() };
    let t_end = if rng.chance(0.7) {
        start.t + rng.log_uniform(-3.0, 0.0)
    } else {
        rng.wild_signed()
    };
    let dt = if rng.chance(0.7) {
        rng.log_uniform(-5.0, -1.0)
    } else {
        rng.wild_signed()
    };
    let outputs: Vec<f64> = (0..rng.below(4))
        .map(|_| start.t + (t_end - start.t) * rng.unit())
        .collect();
    let plan = typed!(Plan::new(t_end, dt).and_then(|p| p.with_outputs(&outputs)));
    // 2 000 steps bound a case to milliseconds; running out is the typed BudgetExceeded.
    let plan = plan.with_budget(Budget {
        max_steps: 2_000,
        wall_time: Some(Duration::from_secs(2)),
    });
    let end = match &integ {
        AnyIntegrator::Imex(i) => run_plan(i, &p, &flow, start, &plan),
        AnyIntegrator::ImexAdaptive(i) => run_plan(i, &p, &flow, start, &plan),
        AnyIntegrator::Stokesian(i) => run_plan(i, &p, &flow, start, &plan),
    };
    let end = typed!(end);
    check(end.t == t_end && end.validate().is_ok(), || {
        format!("run to t_end = {t_end} ended at {end:?}")
    })
}

fn run_plan<I: TimeIntegrator>(
    integ: &I,
    p: &Particle<NeoHooke>,
    flow: &LinearFlow,
    start: State,
    plan: &Plan,
) -> Result<State, StepError> {
    let mut memory = I::Memory::default();
    integrate(
        Problem::new(integ, p, flow),
        start,
        &mut memory,
        plan,
        &[],
        Observers::none(),
    )
    .map(|o| o.state)
    .map_err(|failure| failure.error)
}

/// Single steps of every integrator from fuzzed states and step sizes: `Ok` must be a finite,
/// oriented state later in time.
fn step_case(seed: u64) -> Outcome {
    let mut rng = Rng::new(seed);
    let integ = typed!(any_integrator(&mut rng));
    let p = typed!(any_particle(&mut rng));
    let flow = typed!(LinearFlow::simple_shear(1.0));
    let mut s = State::at_rest(Vec3::from_fn(|_, _| rng.normal()));
    s.t = if rng.chance(0.8) { rng.unit() } else { rng.wild_signed() };
    s.f = Mat3::identity()
        + Mat3::from_fn(|_, _| {
            if rng.chance(0.9) {
                0.2 * rng.normal()
            } else {
                rng.wild_signed()
            }
        });
    s.a = Mat3::from_fn(|_, _| {
        if rng.chance(0.9) {
            rng.normal()
        } else {
            rng.wild_signed()
        }
    });
    let dt = if rng.chance(0.7) {
        rng.log_uniform(-6.0, 0.0)
    } else {
        rng.wild_signed()
    };
    let next = match &integ {
        AnyIntegrator::Imex(i) => i.step(&p, &s, &flow, dt),
        AnyIntegrator::ImexAdaptive(i) => i.step(&p, &s, &flow, dt),
        AnyIntegrator::Stokesian(i) => i.step(&p, &s, &flow, dt),
    };
    let (next, info) = typed!(next);
    check(
        next.validate().is_ok() && next.t > s.t && info.dt > 0.0 && info.dt <= dt,
        || format!("step of {dt} from {s:?} gave {next:?}, {info:?}"),
    )
}

/// A scratch folder per case (removed afterwards).
struct Scratch(PathBuf);

impl Scratch {
    fn new(class: &str, seed: u64) -> Self {
        let dir = std::env::temp_dir().join(format!("pseudorigid-fuzz-{}-{class}-{seed:x}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        Self(dir)
    }
    fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The shipped 12³ cavity `U` (simpleFoam's ASCII, `reference-data/cavity-ci-foam`), inflated.
fn ci_u_text() -> &'static [u8] {
    static TEXT: std::sync::OnceLock<Vec<u8>> = std::sync::OnceLock::new();
    TEXT.get_or_init(|| {
        use std::io::Read as _;
        let path = CI.dir().join("U.gz");
        let mut text = Vec::new();
        let file = std::fs::File::open(&path).expect("shipped CI field");
        flate2::read::GzDecoder::new(file).read_to_end(&mut text).expect("gzip");
        text
    })
}

/// Corrupted cavity velocity files (the form the cavity fields ship in): byte flips, a
/// truncation, or a number replaced by a wild one or a word, read onto the CI block and
/// sampled; every finite field must sample finite.
fn foam_u_case(seed: u64) -> Outcome {
    let mut rng = Rng::new(seed);
    let mut bytes = ci_u_text().to_vec();
    match rng.below(3) {
        0 => {
            for _ in 0..=rng.below(8) {
                let i = rng.below(bytes.len() as u64) as usize;
                bytes[i] = rng.below(256) as u8;
            }
        }
        1 => bytes.truncate(rng.below(bytes.len() as u64) as usize),
        _ => {
            let numbers: Vec<usize> = (1..bytes.len())
                .filter(|&i| bytes[i].is_ascii_digit() && !bytes[i - 1].is_ascii_alphanumeric() && bytes[i - 1] != b'.')
                .collect();
            let at = numbers[rng.below(numbers.len() as u64) as usize];
            let end = (at..bytes.len())
                .find(|&i| !(bytes[i].is_ascii_alphanumeric() || bytes[i] == b'.' || bytes[i] == b'-'))
                .unwrap_or(bytes.len());
            let with = match rng.below(4) {
                0 => format!("{}", rng.next_u64()),
                1 => format!("{:e}", rng.wild_signed()),
                2 => "nan".to_string(),
                _ => "uniform".to_string(),
            };
            bytes.splice(at..end, with.bytes());
        }
    }
    let dir = Scratch::new("foam_u", seed);
    if std::fs::write(dir.path("U"), &bytes).is_err() {
        return Outcome::Silent("could not write the scratch file".into());
    }
    let mesh = cavity_block(CI.cells, CI.case.edge).expect("valid block");
    let field = typed!(read_vol_field(&dir.0, "U", &mesh, 3));
    let flow = typed!(FoamFlow::new(mesh, vec![(0.0, field)]));
    sample_cavity(&flow, &mut rng)
}

/// Eight samples of a cavity flow at random points of the cube: `Finite` when u and ∇u are
/// finite at all of them, `Typed` at the first error, `Silent` at the first non-finite value.
fn sample_cavity(flow: &FoamFlow, rng: &mut Rng) -> Outcome {
    for _ in 0..8 {
        let x = Vec3::new(rng.unit(), rng.unit(), rng.unit()) * CI.case.edge;
        match flow.sample(&x, 0.0) {
            Ok(s) if s.u.iter().chain(s.grad_u.iter()).all(|v| v.is_finite()) => {}
            Ok(s) => return Outcome::Silent(format!("non-finite sample {s:?} at {x:?}")),
            Err(_) => return Outcome::Typed,
        }
    }
    Outcome::Finite
}

/// The polyMesh files of the 12³ cavity as blockMesh wrote them (`tests/data/cavity-ci-blockmesh`),
/// inflated, by name.
fn ci_mesh_texts() -> &'static [(&'static str, Vec<u8>)] {
    static TEXTS: std::sync::OnceLock<Vec<(&'static str, Vec<u8>)>> = std::sync::OnceLock::new();
    TEXTS.get_or_init(|| {
        use std::io::Read as _;
        let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/cavity-ci-blockmesh/constant/polyMesh");
        ["points", "faces", "owner", "neighbour", "boundary"]
            .into_iter()
            .map(|name| {
                let file = std::fs::File::open(dir.join(format!("{name}.gz"))).expect("shipped CI mesh");
                let mut text = Vec::new();
                flate2::read::GzDecoder::new(file).read_to_end(&mut text).expect("gzip");
                (name, text)
            })
            .collect()
    })
}

/// Byte ranges of the unsigned integers in `text` that stand alone (labels, list sizes), not
/// inside a word or a decimal.
fn integer_tokens(text: &[u8]) -> Vec<std::ops::Range<usize>> {
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < text.len() {
        let starts = text[i].is_ascii_digit()
            && (i == 0 || !(text[i - 1].is_ascii_alphanumeric() || b".-_".contains(&text[i - 1])));
        if !starts {
            i += 1;
            continue;
        }
        let end = (i..text.len())
            .find(|&j| !text[j].is_ascii_digit())
            .unwrap_or(text.len());
        if end == text.len() || !(text[end].is_ascii_alphabetic() || text[end] == b'.' || text[end] == b'e') {
            tokens.push(i..end);
        }
        i = end;
    }
    tokens
}

/// The OpenFOAM mesh reader: one polyMesh file of the CI cavity corrupted (a label or list
/// size set out of range, to 2³¹ − 1, 2⁴⁰, −1 or the cell count; bytes flipped; the file
/// truncated), then the case opened, its `U` read and the flow sampled. Every outcome must be
/// a typed error or a finite field: no panic, no hang, no allocation sized by a corrupt
/// count (a list size of 2⁴⁰ with its data absent is refused, not reserved).
fn foam_mesh_case(seed: u64) -> Outcome {
    let mut rng = Rng::new(seed);
    let texts = ci_mesh_texts();
    let target = rng.below(texts.len() as u64) as usize;
    let mut bytes = texts[target].1.clone();
    let cells = CI.cells.pow(3);
    match rng.below(4) {
        0 | 1 => {
            let tokens = integer_tokens(&bytes);
            // The list's size is the integer followed by a line with `(`: hit it a quarter of
            // the time, else any integer from there on.
            let body = tokens
                .iter()
                .position(|r| bytes[r.end..].starts_with(b"\n("))
                .unwrap_or(0);
            let at = if rng.chance(0.25) {
                body
            } else {
                body + rng.below((tokens.len() - body) as u64) as usize
            };
            let with = match rng.below(6) {
                0 => "2147483647".to_string(),
                1 => (1u64 << 40).to_string(),
                2 => "-1".to_string(),
                3 => cells.to_string(),
                4 => (cells + 1 + rng.below(1000) as usize).to_string(),
                _ => rng.next_u64().to_string(),
            };
            if let Some(r) = tokens.get(at) {
                bytes.splice(r.clone(), with.bytes());
            }
        }
        2 => {
            for _ in 0..=rng.below(8) {
                let i = rng.below(bytes.len() as u64) as usize;
                bytes[i] = rng.below(256) as u8;
            }
        }
        _ => bytes.truncate(rng.below(bytes.len() as u64) as usize),
    }
    let dir = Scratch::new("foam_mesh", seed);
    let mesh_dir = dir.path("constant/polyMesh");
    let written = std::fs::create_dir_all(&mesh_dir).is_ok()
        && std::fs::create_dir_all(dir.path("0")).is_ok()
        && std::fs::write(dir.path("0/U"), ci_u_text()).is_ok()
        && texts.iter().enumerate().all(|(k, (name, text))| {
            std::fs::write(mesh_dir.join(name), if k == target { &bytes } else { text }).is_ok()
        });
    if !written {
        return Outcome::Silent("could not write the scratch case".into());
    }
    let case = typed!(FoamCase::open(&dir.0));
    let field = typed!(case.read_field(0.0, "U", 3));
    let flow = typed!(FoamFlow::new(case.mesh().clone(), vec![(0.0, field)]));
    sample_cavity(&flow, &mut rng)
}

/// The files of the shipped decomposed case (`tests/data/cavity-decomposed`: 18 cells,
/// `decomposePar` into 3 processors), by path relative to the case.
fn decomposed_texts() -> &'static [(PathBuf, Vec<u8>)] {
    static TEXTS: std::sync::OnceLock<Vec<(PathBuf, Vec<u8>)>> = std::sync::OnceLock::new();
    TEXTS.get_or_init(|| {
        let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/cavity-decomposed");
        let mut files = Vec::new();
        for k in 0..3 {
            let dir = PathBuf::from(format!("processor{k}"));
            let mesh = dir.join("constant/polyMesh");
            for name in [
                "cellProcAddressing",
                "faceProcAddressing",
                "pointProcAddressing",
                "boundaryProcAddressing",
                "points",
                "faces",
                "owner",
                "neighbour",
                "boundary",
            ] {
                files.push(mesh.join(name));
            }
            files.push(dir.join("127/U"));
        }
        files
            .into_iter()
            .map(|f| {
                let text = std::fs::read(root.join(&f)).expect("shipped decomposed case");
                (f, text)
            })
            .collect()
    })
}

/// The decomposed reader: one file of a processor of the shipped decomposed case corrupted
/// (the addressing files two times in three): a label or list size set out of range (2³¹ − 1,
/// 2⁴⁰, 0, −1, the cell count), a label's sign flipped (a face turned), bytes flipped, or the
/// file truncated; then the case opened from its processors, `U` read and the flow sampled.
/// Every outcome must be a typed error or a finite field, and no allocation is sized by a
/// corrupt count.
fn foam_decomposed_case(seed: u64) -> Outcome {
    let mut rng = Rng::new(seed);
    let texts = decomposed_texts();
    // Files 0..4 of each processor (of 10) are its addressing.
    let target = if rng.chance(2.0 / 3.0) {
        10 * rng.below(3) as usize + rng.below(4) as usize
    } else {
        rng.below(texts.len() as u64) as usize
    };
    let mut bytes = texts[target].1.clone();
    match rng.below(5) {
        0 | 1 => {
            let tokens = integer_tokens(&bytes);
            if let Some(r) = tokens.get(rng.below(tokens.len().max(1) as u64) as usize) {
                let with = match rng.below(6) {
                    0 => "2147483647".to_string(),
                    1 => (1u64 << 40).to_string(),
                    2 => "0".to_string(),
                    3 => "-1".to_string(),
                    4 => "18".to_string(),
                    _ => rng.below(200).to_string(),
                };
                bytes.splice(r.clone(), with.bytes());
            }
        }
        2 => {
            // A sign flipped: a line that is one label, negated or made positive.
            let lines: Vec<usize> = (0..bytes.len())
                .filter(|&i| (i == 0 || bytes[i - 1] == b'\n') && (bytes[i].is_ascii_digit() || bytes[i] == b'-'))
                .collect();
            if let Some(&at) = lines.get(rng.below(lines.len().max(1) as u64) as usize) {
                if bytes[at] == b'-' {
                    bytes.remove(at);
                } else {
                    bytes.insert(at, b'-');
                }
            }
        }
        3 => {
            for _ in 0..=rng.below(8) {
                let i = rng.below(bytes.len() as u64) as usize;
                bytes[i] = rng.below(256) as u8;
            }
        }
        _ => bytes.truncate(rng.below(bytes.len() as u64) as usize),
    }
    let dir = Scratch::new("foam_decomposed", seed);
    let written = texts.iter().enumerate().all(|(k, (path, text))| {
        let to = dir.0.join(path);
        to.parent().is_some_and(|p| std::fs::create_dir_all(p).is_ok())
            && std::fs::write(to, if k == target { &bytes } else { text }).is_ok()
    });
    if !written {
        return Outcome::Silent("could not write the scratch case".into());
    }
    let case = typed!(FoamCase::open_with(&dir.0, Layout::Decomposed));
    let field = typed!(case.read_field(127.0, "U", 3));
    let flow = typed!(FoamFlow::new(case.mesh().clone(), vec![(0.0, field)]));
    sample_cavity(&flow, &mut rng)
}

/// Outputs: every write reads back whole, concurrent writers never mix, no temporary file is
/// left behind (defect 11).
fn output_case(seed: u64) -> Outcome {
    let mut rng = Rng::new(seed);
    let dir = Scratch::new("out", seed);
    let path = dir.path("data.csv");
    let leftovers = |dir: &Scratch| -> Vec<String> {
        std::fs::read_dir(&dir.0)
            .map(|it| {
                it.filter_map(Result::ok)
                    .map(|e| e.file_name().to_string_lossy().into_owned())
                    .filter(|n| n != "data.csv")
                    .collect()
            })
            .unwrap_or_default()
    };
    match rng.below(3) {
        0 => {
            let mut csv = Csv::new(&["a", "b"]);
            for _ in 0..rng.below(50) {
                typed!(csv.push_numbers(&[rng.wild_signed(), rng.wild_signed()]));
            }
            typed!(csv.write(&path));
            let back = std::fs::read_to_string(&path).unwrap_or_default();
            if back != csv.to_text() {
                return Outcome::Silent("CSV does not read back".to_string());
            }
        }
        1 => {
            // Eight threads race on one file; the survivor must be one writer's whole payload.
            let payloads: Vec<Vec<u8>> = (0..8u8)
                .map(|k| vec![b'a' + k; 1 + rng.below(1 << 16) as usize])
                .collect();
            let results: Vec<bool> = std::thread::scope(|s| {
                let handles: Vec<_> = payloads
                    .iter()
                    .map(|p| s.spawn(|| write_atomic(&path, p).is_ok()))
                    .collect();
                handles.into_iter().map(|h| h.join().unwrap_or(false)).collect()
            });
            let back = std::fs::read(&path).unwrap_or_default();
            if !results.iter().all(|&ok| ok) || !payloads.contains(&back) {
                return Outcome::Silent(format!(
                    "8 concurrent writers: results {results:?}, survivor of {} bytes is {}",
                    back.len(),
                    if payloads.contains(&back) {
                        "one payload"
                    } else {
                        "mixed"
                    }
                ));
            }
        }
        _ => {
            // A target whose parent is a file cannot be written: typed error, nothing left over.
            let blocker = dir.path("blocker");
            std::fs::write(&blocker, b"x").expect("scratch write");
            if write_atomic(blocker.join("data.csv"), b"payload").is_ok() {
                return Outcome::Silent("wrote below a regular file".to_string());
            }
            let left = leftovers(&dir);
            return if left == ["blocker"] {
                Outcome::Typed
            } else {
                Outcome::Silent(format!("left behind: {left:?}"))
            };
        }
    }
    let left = leftovers(&dir);
    check(left.is_empty(), || format!("temporary files left behind: {left:?}"))
}

// ---------------------------------------------------------------------------------------------
// Supervisor

fn run_case(case: Case, seed: u64) -> Verdict {
    let (tx, rx) = mpsc::channel();
    let spawned = std::thread::Builder::new()
        .name(format!("fuzz-{seed:x}"))
        .spawn(move || {
            let result = catch_unwind(AssertUnwindSafe(|| case(seed)));
            let _ = tx.send(result);
        });
    if spawned.is_err() {
        return Verdict::Panic("could not spawn a worker thread".to_string());
    }
    match rx.recv_timeout(WATCHDOG) {
        Ok(Ok(Outcome::Finite)) => Verdict::Finite,
        Ok(Ok(Outcome::Typed)) => Verdict::Typed,
        Ok(Ok(Outcome::Silent(what))) => Verdict::Silent(what),
        Ok(Err(payload)) => Verdict::Panic(
            payload
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default(),
        ),
        Err(_) => Verdict::Hang,
    }
}

#[derive(Default)]
struct Tally {
    cases: u64,
    finite: u64,
    typed: u64,
    panics: u64,
    hangs: u64,
    silent: u64,
    skipped: u64,
    failures: Vec<String>,
}

/// Installs (once per process) a panic hook that is silent on the fuzz workers (threads named
/// `fuzz-…`, see `run_case`) and the previous hook everywhere else: the suite runs every test in
/// one process, and another test's panic message must not be swallowed.
fn quiet_fuzz_workers() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !std::thread::current().name().is_some_and(|n| n.starts_with("fuzz-")) {
                previous(info);
            }
        }));
    });
}

fn env_u64(name: &str) -> Option<u64> {
    std::env::var(name).ok().and_then(|s| s.parse().ok())
}

fn fuzz(cases_per_class: u64) {
    let base = env_u64("FUZZ_SEED").unwrap_or(0);
    // Reproduction aids: run only some classes, start at a case index, print every verdict.
    let only = std::env::var("FUZZ_CLASSES").ok();
    let from = env_u64("FUZZ_FROM").unwrap_or(0);
    let verbose = std::env::var_os("FUZZ_VERBOSE").is_some();
    // Panics are expected to be caught and counted; keep their messages out of the output.
    quiet_fuzz_workers();
    let mut total = Tally::default();
    let mut lines = vec![format!(
        "{:<13} {:>7} {:>7} {:>7} {:>6} {:>6} {:>7} {:>7}",
        "class", "cases", "finite", "typed", "panic", "hang", "silent", "skipped"
    )];
    for (index, (name, case)) in CLASSES.iter().enumerate() {
        if only.as_deref().is_some_and(|o| !o.split(',').any(|c| c == *name)) {
            continue;
        }
        let mut t = Tally::default();
        let started = std::time::Instant::now();
        for k in from..cases_per_class {
            if t.hangs >= MAX_HANGS_PER_CLASS as u64 {
                t.skipped = cases_per_class - k;
                break;
            }
            let seed = base.wrapping_add((index as u64) << 32).wrapping_add(k);
            t.cases += 1;
            if verbose {
                println!("start {name} {k} seed {seed}");
            }
            let verdict = run_case(*case, seed);
            if verbose {
                println!("done {name} {k}: {verdict:?}");
            }
            let failure = match verdict {
                Verdict::Finite => {
                    t.finite += 1;
                    None
                }
                Verdict::Typed => {
                    t.typed += 1;
                    None
                }
                Verdict::Silent(what) => {
                    t.silent += 1;
                    Some(format!("silent non-finite: {what}"))
                }
                Verdict::Panic(msg) => {
                    t.panics += 1;
                    Some(format!("panic: {msg}"))
                }
                Verdict::Hang => {
                    t.hangs += 1;
                    Some("hang".to_string())
                }
            };
            if let Some(mut f) = failure {
                if let Some((cut, _)) = f.char_indices().nth(300) {
                    f.truncate(cut);
                }
                t.failures.push(format!("{name} seed {seed}: {f}"));
            }
        }
        // Elapsed time is printed for information only; nothing asserts on it.
        let line = format!(
            "{:<13} {:>7} {:>7} {:>7} {:>6} {:>6} {:>7} {:>7} {:>7.1}s",
            name,
            t.cases,
            t.finite,
            t.typed,
            t.panics,
            t.hangs,
            t.silent,
            t.skipped,
            started.elapsed().as_secs_f64()
        );
        // Printed as each class ends, so a run that dies still shows the classes before.
        println!("{line}");
        lines.push(line);
        total.cases += t.cases;
        total.finite += t.finite;
        total.typed += t.typed;
        total.panics += t.panics;
        total.hangs += t.hangs;
        total.silent += t.silent;
        total.skipped += t.skipped;
        total.failures.extend(t.failures);
    }
    lines.push(format!(
        "{:<13} {:>7} {:>7} {:>7} {:>6} {:>6} {:>7} {:>7}",
        "total", total.cases, total.finite, total.typed, total.panics, total.hangs, total.silent, total.skipped
    ));
    println!("{}", lines.join("\n"));
    for f in total.failures.iter().take(40) {
        println!("{f}");
    }
    assert!(
        total.failures.is_empty(),
        "{} failing cases (first: {:?}); rerun one with its seed",
        total.failures.len(),
        total.failures.first()
    );
}

#[test]
fn fuzz_ci() {
    fuzz(CI_CASES);
}

#[test]
#[ignore = "long fuzz run: cargo test --release --test suite cross::fuzz_api -- --ignored"]
fn fuzz_long() {
    let cases = std::env::var("FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(100_000);
    fuzz(cases);
}

// ---------------------------------------------------------------------------------------------
// Regressions: the reproducers of the reliability audit (issue 10), verbatim inputs, each run
// under the same watchdog as the fuzz cases so that a regression to a hang fails instead of
// stalling the suite. A case returns `Outcome::Finite` when the API behaved as required (which
// may be a typed error) and `Outcome::Silent` with the evidence otherwise.

/// Run `case` supervised; it reports `Outcome::Finite` when the API behaved as required.
fn supervised(case: Case) {
    let verdict = run_case(case, 0);
    assert!(matches!(verdict, Verdict::Finite), "{verdict:?}");
}

/// Defect 2: Ca = 1e-320 passes `Ca > 0` but 1/Ca overflows; it used to panic in `neo_hooke()`.
#[test]
fn tiny_capillary_number_is_a_typed_error() {
    supervised(|_| {
        let Err(err) = ShearScaling::new(1e-320, 0.1, 1e3) else {
            return Outcome::Silent("Ca = 1e-320 accepted".to_string());
        };
        check(
            matches!(
                err,
                ParamError::Derived {
                    name: "mu_s = 1/Ca",
                    ..
                }
            ),
            || format!("{err:?}"),
        )
    });
}

/// Defect 2: deserialisation used to bypass `ShearScaling::new` (`{"ca":0.0,...}` → panic).
#[test]
fn deserialised_parameters_are_validated() {
    supervised(|_| {
        // Each valid value is serialised, one field is made invalid, and the result must
        // not deserialise; the unedited text must (else the rejection proves nothing).
        fn rejected<T: serde::Serialize + serde::de::DeserializeOwned>(valid: &T, field: &str, bad: Value) -> bool {
            let mut v = serde_json::to_value(valid).expect("serialises");
            let accepts_valid = serde_json::from_value::<T>(v.clone()).is_ok();
            v[field] = bad;
            accepts_valid && serde_json::from_value::<T>(v).is_err()
        }
        let zeros = serde_json::to_value(Mat3::zeros() as Mat3).expect("serialises");
        let stretch = serde_json::to_value(Mat3::identity() as Mat3).expect("serialises");
        let bad = [
            rejected(&ShearScaling::new(0.1, 0.1, 1e3).expect("valid"), "ca", 0.0.into()),
            rejected(&NeoHooke::new(1.0, 1.0).expect("valid"), "mu", (-1.0).into()),
            rejected(&MooneyRivlin::new(1.0, 1.0, 1.0).expect("valid"), "mu2", (-1.0).into()),
            rejected(&Fluid::new(1.0, 1.0).expect("valid"), "rho", (-1.0).into()),
            rejected(&Ellipsoid::aligned([1.0; 3]).expect("valid"), "axes", zeros),
            rejected(&Poiseuille::new(1.0, 1.0).expect("valid"), "radius", 0.0.into()),
            rejected(&LinearFlow::simple_shear(1.0).expect("valid"), "grad_u", stretch),
        ];
        // A valid value still round-trips.
        let s = ShearScaling::new(0.1, 0.2, 1e3).expect("valid");
        let back: ShearScaling = serde_json::from_str(&serde_json::to_string(&s).expect("serialises")).expect("valid");
        check(bad.iter().all(|&b| b) && back == s, || {
            format!("rejections {bad:?}, round trip {back:?}")
        })
    });
}

/// Defect 4: ρ* = 1e300 gave a NaN Θ⁻¹ (the inverse of Θ overflowed). Θ⁻¹ = (5/m) S⁻ᵀS⁻¹ is
/// now formed in closed form: finite, and equal to 5/(m R²) on the axes of a sphere
/// (R = 1/2, m = ρ_s π/6) to round-off. The scaling's ρ* is also its fluid's density, which
/// `Fluid::new` bounds by `FLUID_RANGE` (issue 38, item 6), so a solid of ρ_s = 10³⁰⁰ is built
/// in a fluid of unit density, and the scaling at ρ* = 10³⁰⁰ is a typed error naming ρ_f.
#[test]
fn dense_particle_has_a_finite_inverse_euler_tensor() {
    supervised(|_| {
        let scaled = ShearScaling::new(1.0, 1e300, 1e3).and_then(|s| s.particle([1.0; 3], Mat3::identity()));
        if !matches!(scaled, Err(ParamError::OutOfRange { name, .. }) if name.starts_with("rho_f")) {
            return Outcome::Silent(format!("ρ* = 1e300: {:?}", scaled.map(|p| p.mass())));
        }
        let built = NeoHooke::new(1.0, 1e3)
            .and_then(|law| Particle::new(Ellipsoid::aligned([0.5; 3])?, law, Fluid::new(1.0, 1.0)?, 1e300));
        let p = match built {
            Ok(p) => p,
            Err(e) => return Outcome::Silent(format!("valid particle rejected: {e}")),
        };
        let expected = 5.0 / (p.mass() * 0.25);
        // A handful of roundings in m and 5/(m R²): 1e-14 relative.
        let ok = (p.theta_inv() - Mat3::identity() * expected).amax() <= 1e-14 * expected;
        check(ok, || {
            format!("Θ⁻¹ = {:?}, expected {expected:e}·1", p.theta_inv().as_slice())
        })
    });
}

/// Defect 4: semi-axes whose squares overflow gave a non-finite rest geometry.
#[test]
fn semi_axes_with_overflowing_squares_are_rejected() {
    supervised(|_| {
        let err = Ellipsoid::aligned([1e200, 1.0, 1.0]).err();
        let slender = ShearScaling::new(0.1, 0.1, 1e3).and_then(|s| s.particle([1e200, 1.0, 1.0], Mat3::identity()));
        check(
            matches!(err, Some(ParamError::Derived { .. })) && slender.is_err(),
            || format!("{err:?}, {:?}", slender.err()),
        )
    });
}

/// Defect 5: `Poiseuille::new(1e155, 1.0)` sampled at the wall gave u = NaN (R² overflowed).
/// Now u = 0 there (no slip) and ∂u₁/∂x₂ = −4Ū/R exactly (one product, one quotient).
#[test]
fn wide_pipe_samples_finite_at_the_wall() {
    supervised(|_| {
        let s = match Poiseuille::new(1e155, 1.0).map(|f| f.sample(&Vec3::new(0., 1e155, 0.), 0.)) {
            Ok(Ok(s)) => s,
            other => return Outcome::Silent(format!("{other:?}")),
        };
        check(s.u == Vec3::zeros() && s.grad_u[(0, 1)] == -4.0 / 1e155, || {
            format!("{s:?}")
        })
    });
}

/// Defect 5: a large linear flow overflowed silently far from the origin.
#[test]
fn overflowing_linear_flow_is_a_typed_error() {
    supervised(
        |_| match LinearFlow::simple_shear(1e300).map(|f| f.sample(&Vec3::new(0., 1e10, 0.), 0.)) {
            Ok(Err(FlowError::NonFiniteSample { .. })) => Outcome::Finite,
            other => Outcome::Silent(format!("{other:?}")),
        },
    );
}

/// Defect 10: `carlson_rf(NaN, 1, 1)` and `EllipsoidIntegrals::new` with a NaN never returned.
#[test]
fn carlson_and_integrals_of_nan_return() {
    supervised(|_| {
        let rf = carlson_rf(f64::NAN, 1.0, 1.0);
        let rd = carlson_rd(1.0, 1.0, f64::NAN);
        let checked = EllipsoidIntegrals::try_new(&Vec3::new(f64::NAN, 1.0, 1.0));
        let unchecked = EllipsoidIntegrals::new(&Vec3::new(f64::NAN, 1.0, 1.0));
        check(
            matches!(rf, Err(ParamError::OutOfDomain { .. }))
                && matches!(rd, Err(ParamError::OutOfDomain { .. }))
                && checked.is_err()
                && unchecked.chi0.is_nan(),
            || format!("{rf:?} {rd:?} {checked:?}"),
        )
    });
}

/// Defect 11: 50 rounds of 8 threads writing one file; every survivor is one writer's whole
/// payload and no temporary file is left (the per-process temp name mixed 27 of 50 rounds).
#[test]
fn concurrent_atomic_writes_never_mix() {
    supervised(|_| {
        for round in 0..50 {
            if let Outcome::Silent(what) = output_case(round * 3 + 1) {
                return Outcome::Silent(format!("round {round}: {what}"));
            }
        }
        Outcome::Finite
    });
}

/// Defect 11: a write killed mid-way leaves its temporary file; the next write into that
/// folder removes it when its process is gone, and keeps temporaries of live processes.
#[test]
fn stale_temporaries_are_removed_on_the_next_write() {
    supervised(|_| {
        let dir = Scratch::new("stale", 0);
        let mut child = std::process::Command::new("true").spawn().expect("spawn `true`");
        let dead = child.id();
        let _ = child.wait();
        let stale = dir.path(&format!(".data.csv.pseudorigid-tmp-{dead}-1-0"));
        let live = dir.path(&format!(".data.csv.pseudorigid-tmp-{}-1-999999", std::process::id()));
        std::fs::write(&stale, b"half a file").expect("scratch write");
        std::fs::write(&live, b"in flight").expect("scratch write");
        if write_atomic(dir.path("data.csv"), b"whole").is_err() {
            return Outcome::Silent("write failed".to_string());
        }
        check(!stale.exists() && live.exists(), || {
            format!("stale removed: {}, live kept: {}", !stale.exists(), live.exists())
        })
    });
}

/// Issue "one way", defect 3: `Fluid::new(f64::MAX, …)` made a particle whose first step
/// overflowed (the drag rate μ_f K/m and the viscous traction rate μ_f/(ρ_s R²) are products
/// of representable numbers that are not). Each extreme but finite parameter now either builds
/// a particle whose first small step from rest in shear is finite, or is refused by the
/// constructor with a typed error (`particle::model::MAX_RATE`).
#[test]
fn extreme_finite_parameters_are_refused_or_step_finite() {
    supervised(|_| {
        let mut bad = Vec::new();
        for &big in &[f64::MAX, 1e300, 1e200] {
            let cases = [
                (Fluid::new(big, 1.0), 1.0, 1.0),
                (Fluid::new(1.0, big), 1.0, 1.0),
                (Fluid::new(1.0, 1.0), big, 1.0),
                (Fluid::new(1.0, 1.0), 1.0, big),
                (Fluid::new(1.0, 1.0), 1.0 / big, 1.0),
                (Fluid::new(big, big), big, big),
            ];
            for (k, (fluid, rho_s, mu_s)) in cases.into_iter().enumerate() {
                let Ok(fluid) = fluid else { continue };
                let built = NeoHooke::new(mu_s, mu_s)
                    .and_then(|law| Particle::new(Ellipsoid::aligned([1.0, 0.5, 0.5])?, law, fluid, rho_s));
                let Ok(p) = built else { continue };
                let flow = LinearFlow::simple_shear(1.0).expect("valid");
                let rest = State::at_rest(Vec3::zeros());
                for integ in [
                    AnyIntegrator::Imex(ImexPaper::default()),
                    AnyIntegrator::Stokesian(Stokesian::new(1e-6).expect("valid")),
                ] {
                    let next = match &integ {
                        AnyIntegrator::Imex(i) => i.step(&p, &rest, &flow, 1e-9),
                        AnyIntegrator::Stokesian(i) => i.step(&p, &rest, &flow, 1e-9),
                        AnyIntegrator::ImexAdaptive(i) => i.step(&p, &rest, &flow, 1e-9),
                    };
                    // A step may refuse (an explicit scheme is unstable at any step for some of
                    // these), but with its reason, not a number that overflowed.
                    match next {
                        Ok((s, _)) if s.validate().is_ok() => {}
                        Err(StepError::Unstable { .. }) => {}
                        other => bad.push(format!("{big:e} case {k}: built, then {other:?}")),
                    }
                }
            }
        }
        check(bad.is_empty(), || bad.join("; "))
    });
}

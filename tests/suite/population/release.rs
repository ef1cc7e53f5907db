//! Drug release at a critical deformation (src/particle/release.rs, src/population/release.rs):
//! thresholds that validate themselves, crossings located on the dense output against closed
//! forms, a rigid rotation that never releases, the watch's consistency properties, the
//! steady stretch of a tank-treading sphere (Roscoe's algebraic solution) against the
//! threshold at which release just fires, and the release times of a soft sphere integrated
//! by the library in uniaxial extension against its stretch history by quadrature.

use crate::common::strategies::rotation;
use proptest::prelude::*;
use pseudorigid::driver::{AcceptedStep, Observers, Plan, Problem, StepContext, integrate};
use pseudorigid::ellipsoid::Ellipsoid;
use pseudorigid::flow::analytic::LinearFlow;
use pseudorigid::integrator::dense::Knot;
use pseudorigid::integrator::{Dense, EndEvaluation, Step, StepInfo, Stokesian, TimeIntegrator};
use pseudorigid::material::NeoHooke;
use pseudorigid::particle::release::{ReleaseCriterion, ReleaseError, ReleaseThresholds, largest_stretch};
use pseudorigid::particle::{Fluid, Particle, ShearScaling, State};
use pseudorigid::population::release::{ReleaseObserver, Released};
use pseudorigid::population::{Fate, Observer};
use pseudorigid::studies::particles::Shape;
use pseudorigid::studies::shear_run::unit_shear;
use pseudorigid::studies::shear_shape::ShearShape;
use pseudorigid::studies::tank_treading::roscoe;
use pseudorigid::tensor::{Mat3, Vec3};
use serde::Deserialize;

const MU: f64 = 2.0;

fn sphere() -> Particle<NeoHooke> {
    Particle::new(
        Ellipsoid::aligned([0.5; 3]).unwrap(),
        NeoHooke::new(MU, 1e3).unwrap(),
        Fluid::new(1.0, 1.0).unwrap(),
        1.0,
    )
    .unwrap()
}

/// A known history: x(t), ẋ(t), F(t), Ḟ(t).
type History = dyn Fn(f64) -> (Vec3, Vec3, Mat3, Mat3);

/// Steps of size `h` from 0 to `t_end` with the exact end values and rates of `history` (the
/// Hermite interpolant of exact knots), watched by `release`, finished at `t_stop` (the end
/// state's time; the last step may run past it, as the driver's last step runs past an
/// event); `rigid` marks the interpolants as rotations, as the driver does for rigid particles.
fn watch_history(
    release: &ReleaseObserver,
    history: &History,
    h: f64,
    t_end: f64,
    t_stop: f64,
    rigid: bool,
) -> Released {
    let particle = sphere();
    let state = |t: f64| {
        let (x, v, f, a) = history(t);
        State { t, x, v, f, a }
    };
    let start = state(0.0);
    let mut watch = Observer::<Particle<NeoHooke>, (), ()>::watch(release, &particle, &(), &(), &start);
    // The release watch reads the dense output only; the flow is any.
    let flow = LinearFlow::simple_shear(1.0).unwrap();
    let context = StepContext::new(&particle, &flow);
    let steps = (t_end / h).ceil() as usize;
    for k in 0..steps {
        let (t0, t1) = (k as f64 * h, (k + 1) as f64 * h);
        let dense = Dense::new(t0, h, Knot::of_state(&state(t0)), Knot::of_state(&state(t1)));
        let dense = if rigid { dense.of_rotations() } else { dense };
        let step = Step {
            state: state(t1),
            info: StepInfo::default(),
            dense,
            end: EndEvaluation::default(),
        };
        watch.step(&AcceptedStep::new(&step, &context));
    }
    Released::deserialize(&watch.finish(&Fate::Suspended, &state(t_stop))).unwrap()
}

/// F = diag(e^{εt}, e^{−εt}, 1) (planar extension at rate ε), x = (t, 0, 0).
fn planar_extension(eps: f64) -> impl Fn(f64) -> (Vec3, Vec3, Mat3, Mat3) {
    move |t: f64| {
        let (p, m) = ((eps * t).exp(), (-eps * t).exp());
        (
            Vec3::new(t, 0.0, 0.0),
            Vec3::x(),
            Mat3::from_diagonal(&Vec3::new(p, m, 1.0)),
            Mat3::from_diagonal(&Vec3::new(eps * p, -eps * m, 0.0)),
        )
    }
}

/// Bad thresholds are refused with their numbers; good ones are kept in order.
#[test]
fn thresholds_validate_themselves() {
    use ReleaseCriterion::*;
    assert_eq!(
        ReleaseThresholds::new(PrincipalStretch, vec![]),
        Err(ReleaseError::Empty)
    );
    assert!(matches!(
        ReleaseThresholds::new(PrincipalStretch, vec![1.2, f64::NAN]),
        Err(ReleaseError::NonFinite { index: 1, .. })
    ));
    assert_eq!(
        ReleaseThresholds::new(SemiAxisRatio, vec![1.0]),
        Err(ReleaseError::NotAboveRest {
            criterion: SemiAxisRatio,
            index: 0,
            value: 1.0,
            rest: 1.0
        })
    );
    assert!(matches!(
        ReleaseThresholds::new(EnergyDensity, vec![-0.1]),
        Err(ReleaseError::NotAboveRest { rest: 0.0, .. })
    ));
    assert_eq!(
        ReleaseThresholds::new(PrincipalStretch, vec![1.5, 1.2]),
        Err(ReleaseError::NotIncreasing {
            index: 1,
            value: 1.2,
            previous: 1.5
        })
    );
    let ok = ReleaseThresholds::new(EnergyDensity, vec![0.01, 0.5]).unwrap();
    assert_eq!(ok.levels(), &[0.01, 0.5]);
    assert!(format!("{}", ReleaseThresholds::new(PrincipalStretch, vec![0.9]).unwrap_err()).contains("0.9"));
}

/// In planar extension F = diag(e^{εt}, e^{−εt}, 1) the largest stretch reaches s at
/// t* = ln(s)/ε and the Neo-Hooke energy W = 2μ sinh²(εt) (J = 1) reaches w at
/// t* = asinh(√(w/2μ))/ε. The located crossing matches to the interpolant's error over the
/// criterion's slope, δt ≤ h⁴ε³e^{2εh}/384 for λ₁ (the Hermite remainder h⁴ max|f⁗|/384 of
/// e^{εt}, divided by λ̇ ≥ εe^{ε(t*−h)}) and the same times coth(2εt*) for W (both diagonal
/// entries contribute), plus the location tolerance 10⁻⁹ s/ṡ; x = (t, 0, 0) is linear, so the
/// place is the time to round-off. A run that ends before t* (a deposit inside the last step)
/// records no crossing, though its last step reaches past t*.
#[test]
fn crossing_matches_planar_extension_closed_form() {
    let (eps, h): (f64, f64) = (1.0, 0.1);
    let history = planar_extension(eps);
    let bound = h.powi(4) * eps.powi(3) * (2.0 * eps * h).exp() / 384.0;
    let levels = vec![1.01, 1.3, 2.0, 3.0];
    for criterion in [ReleaseCriterion::PrincipalStretch, ReleaseCriterion::SemiAxisRatio] {
        let release = ReleaseObserver::new(ReleaseThresholds::new(criterion, levels.clone()).unwrap());
        let got = watch_history(&release, &history, h, 1.5, 1.5, false);
        for (s, c) in levels.iter().zip(&got.crossings) {
            let exact = s.ln() / eps;
            if exact > 1.5 {
                assert!(c.is_none(), "{criterion:?} {s}: {c:?}");
                continue;
            }
            let c = c.expect("reached");
            assert!(
                (c.t - exact).abs() <= bound + 1e-9 / eps,
                "{criterion:?} {s}: {} vs {exact}",
                c.t
            );
            assert!((c.x[0] - c.t).abs() <= 1e-14 && c.x[1] == 0.0);
            assert!((c.value - s).abs() <= 1e-9 * s && (c.stretch - s).abs() <= 1e-9 * s);
        }
    }
    let energies = vec![0.05, 0.5, 2.0];
    let release =
        ReleaseObserver::new(ReleaseThresholds::new(ReleaseCriterion::EnergyDensity, energies.clone()).unwrap());
    let got = watch_history(&release, &history, h, 1.5, 1.5, false);
    for (w, c) in energies.iter().zip(&got.crossings) {
        let exact = (w / (2.0 * MU)).sqrt().asinh() / eps;
        let c = c.expect("reached");
        let tol = bound / (2.0 * eps * exact).tanh() + 1e-9 * w / (2.0 * MU * eps * (2.0 * eps * exact).sinh());
        assert!((c.t - exact).abs() <= tol, "W = {w}: {} vs {exact} (±{tol:e})", c.t);
    }
    // λ₁ = 1.3 at t* = 0.2624, inside the third step: stopping at 0.25 records nothing.
    let release = ReleaseObserver::new(ReleaseThresholds::new(ReleaseCriterion::PrincipalStretch, vec![1.3]).unwrap());
    let got = watch_history(&release, &history, h, 0.3, 0.25, false);
    assert_eq!(got.crossings, vec![None]);
    assert!(got.peak.value < 1.3 && (got.peak.t - 0.25).abs() < 1e-15);
}

/// A rigid rotation never releases: with the interpolant marked as rotations (the driver's
/// for rigid particles, [`Dense::of_rotations`]) λ₁ stays 1 to round-off (10⁻¹⁴, the
/// orthogonality of the projected interpolant) over a quarter turn per step.
#[test]
fn rigid_rotation_never_releases() {
    let omega = std::f64::consts::FRAC_PI_2 / 0.1;
    let w = Mat3::new(0.0, -omega, 0.0, omega, 0.0, 0.0, 0.0, 0.0, 0.0);
    let history = move |t: f64| {
        let f = *nalgebra::Rotation3::from_axis_angle(&Vec3::z_axis(), omega * t).matrix();
        (Vec3::zeros(), Vec3::zeros(), f, w * f)
    };
    let release = ReleaseObserver::new(
        ReleaseThresholds::new(ReleaseCriterion::PrincipalStretch, vec![1.0 + 1e-12, 1.01]).unwrap(),
    );
    let got = watch_history(&release, &history, 0.1, 2.0, 2.0, true);
    assert_eq!(got.crossings, vec![None, None]);
    assert!((got.peak.value - 1.0).abs() < 1e-14, "{}", got.peak.value);
}

/// F(t) = R(t) diag(λ, 1/λ, 1) with λ = exp(a sin(ωt + φ)) and R(t) turning about a fixed
/// axis: a history whose stretch rises and falls.
fn oscillating(a: f64, omega: f64, phi: f64, q: Mat3) -> impl Fn(f64) -> (Vec3, Vec3, Mat3, Mat3) {
    move |t: f64| {
        let (l, dl) = ((a * (omega * t + phi).sin()).exp(), a * omega * (omega * t + phi).cos());
        let r = *nalgebra::Rotation3::from_axis_angle(&Vec3::z_axis(), 0.7 * t).matrix();
        let dr = Mat3::new(0.0, -0.7, 0.0, 0.7, 0.0, 0.0, 0.0, 0.0, 0.0) * r;
        let u = Mat3::from_diagonal(&Vec3::new(l, 1.0 / l, 1.0));
        let du = Mat3::from_diagonal(&Vec3::new(l * dl, -dl / l, 0.0));
        let f = q * r * u;
        let x = Vec3::new(t.sin(), t, 0.0);
        (x, Vec3::new(t.cos(), 1.0, 0.0), f, q * (dr * u + r * du))
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// On any history: a level is crossed iff it is at most the recorded peak (the peak and
    /// the crossings come from the same samples); a higher level is crossed no earlier; the
    /// criterion at a crossing is its level to the location tolerance (10⁻⁹ relative), or at
    /// least the level for a history that starts above it (released at the start); a
    /// crossing comes no later than the peak; the recorded stretch is λ₁ of the interpolant
    /// there.
    #[test]
    fn crossings_are_consistent(
        a in 0.0..0.8f64,
        omega in 0.5..6.0f64,
        phi in 0.0..6.3f64,
        h in 0.01..0.3f64,
        q in rotation(),
        raw in proptest::collection::vec(1.0001..2.5f64, 1..5),
    ) {
        let mut levels = raw;
        levels.sort_by(f64::total_cmp);
        levels.dedup();
        let release = ReleaseObserver::new(ReleaseThresholds::new(ReleaseCriterion::PrincipalStretch, levels.clone()).unwrap());
        let got = watch_history(&release, &oscillating(a, omega, phi, q), h, 3.0, 3.0, false);
        let mut last_t = f64::NEG_INFINITY;
        for (s, c) in levels.iter().zip(&got.crossings) {
            prop_assert_eq!(c.is_some(), got.peak.value >= *s, "level {} peak {}", s, got.peak.value);
            if let Some(c) = c {
                prop_assert!(c.t >= last_t && c.t <= got.peak.t);
                // A history that starts above a level releases there, at its start value.
                if c.t == 0.0 {
                    prop_assert!(c.value >= *s);
                } else {
                    prop_assert!((c.value - s).abs() <= 1e-9 * s, "{} at level {}", c.value, s);
                }
                prop_assert!((c.stretch - c.value).abs() <= 1e-12 * s);
                last_t = c.t;
            }
        }
    }
}

/// A soft sphere in unit shear at Ca = 0.1 from rest approaches Roscoe's steady
/// tank-treading shape, λ₁ = r₁/R₀ from the algebraic equations of
/// `studies::tank_treading::roscoe` (no time integration, no traction code of the model): a
/// threshold 0.5 % of λ₁ − 1 below the steady λ₁ fires, and the run's peak lies within 0.5 %
/// of λ₁ − 1 of it. At t = 70 (the tank-treading test's 60 + 100 Ca, where the drift is below
/// 10⁻⁷) the end state is Roscoe's to 10⁻⁶ (that test's bound, a factor 100 over the
/// tolerance); the margin on the peak bounds the transient overshoot of the approach.
#[test]
fn tank_treading_sphere_releases_just_below_roscoe_stretch() {
    let ca = 0.1;
    let steady = roscoe(ca).unwrap().steady;
    let lambda = steady.r_long / 0.5;
    let excess = lambda - 1.0;
    let scaling = ShearScaling::new(ca, 1.0, 1e3).unwrap();
    let particle = ShearShape::new(Shape::Sphere).particle(&scaling).unwrap();
    let flow = unit_shear();
    let levels = vec![1.0 + 0.995 * excess, 1.0 + 1.005 * excess];
    let release = ReleaseObserver::new(ReleaseThresholds::new(ReleaseCriterion::PrincipalStretch, levels).unwrap());
    let start = State::at_rest(Vec3::zeros());
    let mut watch = Observer::<Particle<NeoHooke>, _, ()>::watch(&release, &particle, &flow, &(), &start);
    let integ = Stokesian::overdamped(1e-8).unwrap();
    let mut memory = <Stokesian as TimeIntegrator>::Memory::default();
    let plan = Plan::new(70.0, 1e-3).unwrap();
    let out = integrate(
        Problem::new(&integ, &particle, &flow),
        start,
        &mut memory,
        &plan,
        &[],
        Observers::none().with_on_step(|s| watch.step(s)),
    )
    .unwrap();
    let got = Released::deserialize(&watch.finish(&Fate::Suspended, &out.state)).unwrap();
    assert!(got.crossings[0].is_some(), "peak {} vs steady {lambda}", got.peak.value);
    assert!(
        (got.peak.value - lambda).abs() <= 0.005 * excess,
        "peak {} vs steady {lambda}",
        got.peak.value
    );
    assert!(
        (largest_stretch(&out.state.f) - lambda).abs() <= 1e-6,
        "end λ₁ {}",
        largest_stretch(&out.state.f)
    );
}

/// The axisymmetric reduction of the inertialess model for an initially spherical Neo-Hooke
/// particle in uniaxial extension u = ε̇ (x₁, −x₂/2, −x₃/2), in units μ_f = ε̇ = 1 (so
/// μ_s = 1/Ca): an independent reference for the stretch history λ₁(t), written here without
/// the library (module docs of the test below).
mod uniaxial {
    /// G(e²) = abc α″₂ of a prolate spheroid of eccentricity e (the long axis 1), from the
    /// depolarisation factor N₁ = (1 − e²)(artanh e − e)/e³ in closed form; below e² = ¼ its
    /// power series (the closed form cancels there), whose n-th term is
    /// 4(1 − 2n)e²ⁿ/((2n+1)(2n+3)(2n+5)); G(0) = 4/15, the sphere's.
    pub fn g(e2: f64) -> f64 {
        if e2 < 0.25 {
            (0..80)
                .map(|n| {
                    let n = n as f64;
                    4.0 * (1.0 - 2.0 * n) * e2.powf(n) / ((2.0 * n + 1.0) * (2.0 * n + 3.0) * (2.0 * n + 5.0))
                })
                .sum()
        } else {
            let e = e2.sqrt();
            let s = (e.atanh() - e) / (e * e2);
            1.0 - 4.0 * s + e2 * s + (3.0 * s - 1.0) / e2
        }
    }

    /// The particle's extension rate ε_s (l_s = diag(ε_s, −ε_s/2, −ε_s/2)) at stretch λ:
    /// the balance σ̃₁₁ − σ̃₂₂ = σ_el,11 − σ_el,22 reads K(ε̇ − ε_s) + 3ε_s = (λ² − 1/λ)/Ca
    /// with K = 2/G(1 − λ⁻³).
    pub fn rate(lambda: f64, ca: f64) -> f64 {
        let k = 2.0 / g(1.0 - lambda.powi(-3));
        (k - (lambda * lambda - 1.0 / lambda) / ca) / (k - 3.0)
    }

    /// λ̇ = λ ε_s(λ).
    pub fn lambda_dot(lambda: f64, ca: f64) -> f64 {
        lambda * rate(lambda, ca)
    }

    /// The time at which λ₁ reaches `s` from 1, t(s) = ∫₁ˢ dλ/(λ ε_s(λ)), by composite
    /// Simpson with `n` (even) panels.
    pub fn time_to(s: f64, ca: f64, n: usize) -> f64 {
        let h = (s - 1.0) / n as f64;
        let f = |l: f64| 1.0 / lambda_dot(l, ca);
        let inner: f64 = (1..n)
            .map(|k| if k % 2 == 1 { 4.0 } else { 2.0 } * f(1.0 + k as f64 * h))
            .sum();
        h / 3.0 * (f(1.0) + f(s) + inner)
    }

    /// The stable steady stretch λ∞ (ε_s = 0) by bisection on [1, 3], `None` if ε_s > 0 at 3.
    /// (K grows faster than λ²: ε_s turns positive again at a larger, unstable root, the
    /// stretch beyond which a particle extends without bound.)
    pub fn steady(ca: f64) -> Option<f64> {
        let (mut lo, mut hi) = (1.0, 3.0);
        if rate(hi, ca) > 0.0 {
            return None;
        }
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if rate(mid, ca) > 0.0 { lo = mid } else { hi = mid }
        }
        Some(lo)
    }

    /// max |d⁴λ/dt⁴| over stretches in [1, `top`]: λ⁗ = g(g²g‴ + 4gg′g″ + g′³) for λ̇ = g(λ),
    /// g′, g″, g‴ by central differences of step 10⁻³ (relative error O(10⁻⁶)), sampled
    /// every 10⁻³ in λ.
    pub fn max_fourth_derivative(top: f64, ca: f64) -> f64 {
        let d = 1e-3;
        let gd = |l: f64| lambda_dot(l, ca);
        let mut max: f64 = 0.0;
        let samples = ((top - 1.0) / 1e-3).ceil() as usize;
        for j in 0..=samples {
            let l = 1.0 + (top - 1.0) * j as f64 / samples as f64;
            let (m2, m1, p0, p1, p2) = (gd(l - 2.0 * d), gd(l - d), gd(l), gd(l + d), gd(l + 2.0 * d));
            let g1 = (p1 - m1) / (2.0 * d);
            let g2 = (p1 - 2.0 * p0 + m1) / (d * d);
            let g3 = (p2 - 2.0 * p1 + 2.0 * m1 - m2) / (2.0 * d * d * d);
            max = max.max((p0 * (p0 * p0 * g3 + 4.0 * p0 * g1 * g2 + g1 * g1 * g1)).abs());
        }
        max
    }
}

/// The release event of a particle integrated by the library, against a stretch history
/// computed without it: an initially spherical Neo-Hooke particle (Ca = μ_f ε̇/μ_s = 0.2) in
/// uniaxial extension stays a prolate spheroid, F = diag(λ, λ^{-1/2}, λ^{-1/2}) (by symmetry,
/// with tr l_s = 0), and the balance of the Jeffery–Roscoe stress σ̃ with the elastic one,
/// whose difference σ₁₁ − σ₂₂ is all that is left (the rest is pressure), is one scalar
/// equation for its stretch:
/// ```math
/// \dot\lambda = \lambda\,\varepsilon_s(\lambda),\qquad
/// \varepsilon_s = \frac{K\dot\varepsilon - (\lambda^2 - \lambda^{-1})/\mathrm{Ca}}{K - 3},\qquad
/// K = \frac{2}{abc\,\alpha''_2},
/// ```
/// so λ₁ reaches s at the quadrature t(s) = ∫₁ˢ dλ/(λε_s). The reference shares no code with
/// the run: the prolate integrals are elementary (the library's are Carlson's with a
/// degenerate branch), the balance is one scalar equation (the library solves the 9×9 system
/// of σ̃(l_s) = σ_el(F) with a material stress from automatic differentiation), and the
/// history is a quadrature (the library's is Radau IIA, its dense output and event location).
/// Two limits tie the reduction to the literature: at λ = 1 it gives ε_s = (5/3)ε̇, the strain
/// rate inside a sphere that resists no deformation (Taylor's 5ε̇/(2η + 3) inside a viscous
/// sphere, Proc. R. Soc. A 138 (1932) 41, at viscosity ratio η = 0), and for Ca → 0 the
/// linear response λ∞ − 1 = (5/2) Ca (a strain of (5/2) Ca E/ε̇), whose value in simple shear
/// (principal strain rates ±½) is Roscoe's D → (5/4) Ca. Both are asserted, the second to
/// 10 Ca: the next term is O(Ca²).
///
/// Tolerance of a located crossing, with λ̇ = g(λ). A perturbation of a scalar autonomous
/// solution is carried as δλ(t) = δλ(s) g(λ(t))/g(λ(s)), so the local errors e_k of the
/// steps give a time error Σ e_k/g(λ(t_k)) ≤ N τ (1 + λ)/min g, with e_k ≤ τ(1 + λ) the
/// componentwise control of F₁₁ at τ = rtol = atol (times 10, as the control holds an
/// estimate, not the error); the cubic Hermite interpolant of F₁₁ = λ adds
/// h⁴ max|λ⁗|/384 over λ̇ at the crossing, and the location 10⁻⁹/λ̇. The same bound without
/// the last two terms holds at every step end. The bound is asserted below 10⁻³ h, so a
/// crossing reported at a sample of the dense output (the step's end or one of its
/// [`SAMPLES`](pseudorigid::population::release::SAMPLES) points, up to h/4 late) fails unless
/// it happens to lie that close to the crossing at every level: so reported, λ₁ = 1.05 came
/// 0.44 ms late against a bound of 2.1 µs (h ≤ 13.6 ms).
#[test]
fn release_in_uniaxial_extension_matches_quadrature() {
    let ca = 0.2;
    let tol = 1e-10;
    let t_end = 1.0;
    // The quadrature converges as n⁻⁴: doubling the panels changes it by 16× its error.
    let simpson = |s: f64| uniaxial::time_to(s, ca, 4000);
    assert!((simpson(1.5) - uniaxial::time_to(1.5, ca, 8000)).abs() < 1e-13);
    let steady = uniaxial::steady(ca).expect("a steady stretch at Ca = 0.2");
    assert!(steady > 1.6 && steady < 1.8, "λ∞ = {steady}");
    assert!((uniaxial::rate(1.0, ca) - 5.0 / 3.0).abs() < 1e-14);
    let small = 1e-3;
    let linear = (uniaxial::steady(small).unwrap() - 1.0) / small;
    assert!(
        (linear - 2.5).abs() <= 10.0 * small,
        "(λ∞ − 1)/Ca = {linear} at Ca = {small}"
    );

    let scaling = ShearScaling::new(ca, 1.0, 1e3).unwrap();
    let particle = ShearShape::new(Shape::Sphere).particle(&scaling).unwrap();
    let flow = pseudorigid::flow::analytic::LinearFlow::uniaxial_extension(1.0).unwrap();
    // 1.71 lies above λ∞ = 1.703: approached, never reached.
    let levels = vec![1.05, 1.3, 1.5, 1.71];
    let release =
        ReleaseObserver::new(ReleaseThresholds::new(ReleaseCriterion::PrincipalStretch, levels.clone()).unwrap());
    let start = State::at_rest(Vec3::zeros());
    let mut watch = Observer::<Particle<NeoHooke>, _, ()>::watch(&release, &particle, &flow, &(), &start);
    let integ = Stokesian::overdamped(tol).unwrap();
    let mut memory = <Stokesian as TimeIntegrator>::Memory::default();
    let plan = Plan::new(t_end, 1e-3).unwrap();
    let mut ends: Vec<(f64, f64)> = Vec::new();
    let mut h_max: f64 = 0.0;
    let out = integrate(
        Problem::new(&integ, &particle, &flow),
        start,
        &mut memory,
        &plan,
        &[],
        Observers::none().with_on_step(|s| {
            h_max = h_max.max(s.dense().t_end() - s.dense().t_start());
            ends.push((s.state().t, largest_stretch(&s.state().f)));
            watch.step(s)
        }),
    )
    .unwrap();
    let got = Released::deserialize(&watch.finish(&Fate::Suspended, &out.state)).unwrap();

    let top = ends.last().unwrap().1;
    // min λ̇ over the stretches of the run, sampled every 10⁻³ of the range.
    let g_min = (0..=1000)
        .map(|j| uniaxial::lambda_dot(1.0 + (top - 1.0) * f64::from(j) / 1000.0, ca))
        .fold(f64::INFINITY, f64::min);
    let global = 10.0 * ends.len() as f64 * tol * (1.0 + top) / g_min;
    for &(t, lambda) in &ends {
        let exact = simpson(lambda);
        assert!(
            (t - exact).abs() <= global,
            "step end t = {t}: λ = {lambda} is reached at {exact} (±{global:e})"
        );
    }
    let m4 = uniaxial::max_fourth_derivative(top, ca);
    for (s, c) in levels.iter().zip(&got.crossings) {
        if *s > steady {
            assert!(c.is_none(), "{s} above λ∞ {steady}: {c:?}");
            continue;
        }
        let c = c.expect("reached");
        let exact = simpson(*s);
        let slope = uniaxial::lambda_dot(*s, ca);
        let bound = global + (h_max.powi(4) * m4 / 384.0 + 1e-9) / slope;
        assert!(
            bound < 1e-3 * h_max,
            "the bound {bound:e} does not tell a crossing from its step (h {h_max})"
        );
        assert!(
            (c.t - exact).abs() <= bound,
            "λ₁ = {s}: released at {}, the quadrature's {exact} (±{bound:e}, h_max {h_max})",
            c.t
        );
        assert!(c.x.iter().all(|x| x.abs() < 1e-12));
    }
}

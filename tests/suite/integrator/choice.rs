//! The pieces behind the integrator chosen for the particle (src/integrator/choice.rs): the
//! equilibrium barycentre against the exact slow solution of an inertial particle, the rigid
//! particle's cached geometry against the eigen-decomposition, the polar factor against the
//! SVD, and the block factorisation of the inertialess Jacobian against the dense LU.

use crate::common::heavy_sphere;
use crate::common::strategies::{deformation, rotation};
use proptest::prelude::*;
use pseudorigid::driver::{Observers, Problem, run};
use pseudorigid::integrator::choice::{self, Chosen, ParticleNumbers};
use pseudorigid::integrator::rosenbrock::{Factor, Jacobian};
use pseudorigid::integrator::{BarycentreModel, Scheme, Tolerances};
use pseudorigid::material::Rigid;
use pseudorigid::particle::Model;
use pseudorigid::particle::dynamics::Geometry;
use pseudorigid::particle::inertialess::{BarycentreModel as Barycentre, pack};
use pseudorigid::prelude::*;
use pseudorigid::tensor::nearest_rotation;

/// Planar extension u = (a x, −a y, 0) and a heavy sphere of response time τ = 2ρr²/(9μ)
/// (Stokes drag over the mass). Eq. 17, ẍ = (a x − ẋ)/τ, has the slow solution x₀ e^{s t} with
/// s = (√(1 + 4aτ) − 1)/(2τ) = a − a²τ + 2a³τ² + O(τ³), the one a particle released with
/// ẋ = s x₀ follows exactly. The equilibrium velocity ẋ = u − τ Du/Dt = (a − a²τ) x misses
/// 2a³τ² only, so its error at t = 1/a is 2(aτ)² to leading order: second order in τ, where the
/// overdamped model (ẋ = a x) is first order.
fn extension_error(tau: f64, barycentre: BarycentreModel) -> f64 {
    let (a, mu, rho) = (1.0, 1.0, 1.0);
    let particle = heavy_sphere(tau, mu, rho);
    let flow = LinearFlow::new(Vec3::zeros(), Mat3::from_diagonal(&Vec3::new(a, -a, 0.0))).unwrap();
    let s = ((1.0 + 4.0 * a * tau).sqrt() - 1.0) / (2.0 * tau);
    let x0 = Vec3::new(1.0, 0.0, 0.0);
    let start = State {
        v: x0 * s,
        ..State::at_rest(x0)
    };
    let integ = Stokesian {
        tol: Tolerances::uniform(1e-11).unwrap(),
        barycentre,
        scheme: Scheme::Radau5,
        norm: Default::default(),
        frame: Default::default(),
    };
    let (end, _) = run(
        Problem::new(&integ, &particle, &flow),
        start,
        1e-4,
        &[1.0 / a],
        Observers::none(),
    )
    .unwrap();
    (end.x[0] - (s / a).exp()).abs() / (s / a).exp()
}

/// The inertial barycentre follows the slow solution to the integrator's tolerance (which
/// checks τ = 2ρr²/(9μ) and the set-up); the equilibrium barycentre's error is 2(aτ)² to
/// within 10 % (the next term is O(τ³), 5aτ ≤ 10 % of it) and falls 4× when τ halves; the
/// overdamped one is a²τ, first order.
#[test]
fn equilibrium_barycentre_is_second_order_in_the_response_time() {
    for tau in [0.02, 0.01] {
        assert!(extension_error(tau, Barycentre::Inertial) < 1e-8);
        let eq = extension_error(tau, Barycentre::Equilibrium);
        assert!((eq / (2.0 * tau * tau) - 1.0).abs() < 0.1, "tau {tau}: error {eq:e}");
        let od = extension_error(tau, Barycentre::Overdamped);
        assert!((od / tau - 1.0).abs() < 0.1, "tau {tau}: overdamped error {od:e}");
    }
    let ratio = extension_error(0.02, Barycentre::Equilibrium) / extension_error(0.01, Barycentre::Equilibrium);
    assert!((ratio - 4.0).abs() < 0.4, "error ratio {ratio}");
}

/// The choice follows its documented rules at their thresholds.
#[test]
fn choice_follows_its_rules() {
    let tight = Tolerances::uniform(1e-6).unwrap();
    let loose = Tolerances::new(1e-2, 1e-5, 1e-14).unwrap();
    let numbers = |stokes| ParticleNumbers {
        stokes,
        rho_star: 0.01,
        rigid: true,
        shape_ratio: 0.0,
    };
    let tracer = choice::choose(numbers(choice::EQUILIBRIUM_STOKES), loose).unwrap();
    assert_eq!(tracer.integrator.full().barycentre, BarycentreModel::Equilibrium);
    assert_eq!(tracer.integrator.full().scheme, Scheme::Rosenbrock23);
    let inertial = choice::choose(numbers(2.0 * choice::EQUILIBRIUM_STOKES), tight).unwrap();
    assert_eq!(inertial.integrator.full().barycentre, BarycentreModel::Inertial);
    assert_eq!(inertial.integrator.full().scheme, Scheme::Radau5);
    assert!(!inertial.reason.contains("neglected"));
    let heavy = ParticleNumbers {
        rho_star: 10.0,
        ..numbers(0.1)
    };
    assert!(
        choice::choose(heavy, loose)
            .unwrap()
            .reason
            .contains("inertia is neglected")
    );
    assert!(choice::choose(numbers(f64::NAN), loose).is_err());
    // The slow manifold: elastic particles at δ̄ ≤ MANIFOLD_SHARE √rtol, over the same full model.
    let bound = choice::MANIFOLD_SHARE * loose.rtol().sqrt();
    let elastic = |shape_ratio| ParticleNumbers {
        rigid: false,
        shape_ratio,
        ..numbers(0.1)
    };
    let stiff = choice::choose(elastic(bound), loose).unwrap();
    let Chosen::SlowManifold(manifold) = stiff.integrator else {
        panic!("δ̄ at the bound: {}", stiff.reason)
    };
    assert_eq!(manifold.full.barycentre, BarycentreModel::Inertial);
    assert_eq!(manifold.delta_max(), loose.rtol().sqrt());
    assert!(stiff.reason.contains("on the slow manifold"), "{}", stiff.reason);
    let soft = choice::choose(elastic(1.01 * bound), loose).unwrap();
    assert!(matches!(soft.integrator, Chosen::Full(_)), "{}", soft.reason);
    assert!(matches!(
        choice::choose(numbers(0.1), loose).unwrap().integrator,
        Chosen::Full(_)
    ));
    assert!(choice::choose(elastic(f64::NAN), loose).is_err());
}

/// The shape ratio the choice reads is γ̇/k with the closed forms of both: a sphere's slowest
/// relaxation rate k = 2μ_s/(3μ_f) and a simple shear's strain rate γ̇; a rigid particle's is 0.
#[test]
fn shape_ratio_is_the_strain_rate_over_the_sphere_relaxation_rate() {
    let shear_rate = 40.0;
    let flow = LinearFlow::simple_shear(shear_rate).unwrap();
    let fluid = Fluid::new(1e-3, 1e3).unwrap();
    for mu_s in [0.5, 50.0] {
        let particle = Particle::new(
            Ellipsoid::aligned([1e-5; 3]).unwrap(),
            NeoHooke::new(mu_s, 100.0 * mu_s).unwrap(),
            fluid,
            1e3,
        )
        .unwrap();
        let numbers = ParticleNumbers::of(&particle, &flow).unwrap();
        let exact = shear_rate / (2.0 * mu_s / (3.0 * 1e-3));
        assert!(
            (numbers.shape_ratio - exact).abs() <= 1e-12 * exact,
            "mu_s {mu_s}: {} against {exact}",
            numbers.shape_ratio
        );
    }
    let rigid = Particle::new(Ellipsoid::aligned([1e-5; 3]).unwrap(), Rigid, fluid, 1e3).unwrap();
    assert_eq!(ParticleNumbers::of(&rigid, &flow).unwrap().shape_ratio, 0.0);
    // A law with a material direction is not what the manifold's isotropic stretch describes:
    // the ratio is ∞, so the choice keeps the full shape model however stiff the particle.
    let fibred = Particle::new(
        Ellipsoid::aligned([1e-5; 3]).unwrap(),
        crate::common::Fibred {
            matrix: NeoHooke::new(500.0, 5e4).unwrap(),
            k: 500.0,
        },
        fluid,
        1e3,
    )
    .unwrap();
    let numbers = ParticleNumbers::of(&fibred, &flow).unwrap();
    assert_eq!(numbers.shape_ratio, f64::INFINITY);
    assert!(matches!(
        choice::choose(numbers, Tolerances::uniform(1e-2).unwrap())
            .unwrap()
            .integrator,
        Chosen::Full(_)
    ));
}

proptest! {
    /// Newton's polar iteration gives the SVD's U Vᵀ: both are the unique orthogonal polar
    /// factor; at the deformations' condition numbers (≤ e³ per axis) the two differ by round-off,
    /// 1e-12.
    #[test]
    fn nearest_rotation_is_the_polar_factor(f in deformation()) {
        let svd = f.svd(true, true);
        let expected = svd.u.unwrap() * svd.v_t.unwrap();
        let got = nearest_rotation(&f);
        prop_assert!((got - expected).abs().max() < 1e-12, "{got} vs {expected}");
    }

    /// A rigid particle's cached geometry turned by R is the eigen-decomposition's geometry of
    /// F̄ = R S: the same semi-axes, traction and drag. The semi-axes differ by at least 2 %,
    /// so the eigenvectors are accurate to ε/0.02 ≈ 10⁻¹⁴ and σ̃ and K to 10⁻¹⁰ of their size.
    #[test]
    fn rigid_geometry_is_the_rest_geometry_turned(r in rotation(), l_f in crate::common::strategies::traceless(1.0)) {
        let axes = [3.0, 1.5, 0.7];
        let particle = Particle::new(Ellipsoid::aligned(axes).unwrap(), Rigid, Fluid::new(1.0, 0.0).unwrap(), 1.0).unwrap();
        let cached = particle.geometry(&r);
        let eigen = Geometry::of_total_distortion(&(r * particle.shape_tensor()));
        let close = |a: &Mat3, b: &Mat3| (a - b).abs().max() <= 1e-10 * b.abs().max().max(1e-300);
        prop_assert!((cached.frame.r - eigen.frame.r).abs().max() < 1e-12);
        let l_s = l_f.transpose();
        let vol = VolumetricTraction::default();
        prop_assert!(close(&cached.traction.sigma_tilde(&l_s, &l_f, 1.0, vol), &eigen.traction.sigma_tilde(&l_s, &l_f, 1.0, vol)));
        let drag = |g: &Geometry| Brenner.resistance(&g.frame, &g.ints);
        prop_assert!(close(&drag(&cached), &drag(&eigen)));
    }

    /// The block factorisation of W = 1 − γh J solves as the dense 15×15 LU does, for a rigid
    /// and an elastic particle (both LUs pivot; the blocks' condition numbers are ≤ 10 here, so
    /// the two solutions agree to 1e-12 of their size).
    #[test]
    fn block_factor_solves_like_the_dense_lu(r in rotation(), b in prop::collection::vec(-1.0f64..1.0, 15), h in 1e-3f64..1.0) {
        let shape = Ellipsoid::aligned([2.0, 1.0, 0.5]).unwrap();
        let fluid = Fluid::new(1.0, 1.0).unwrap();
        let flow = LinearFlow::simple_shear(1.0).unwrap();
        let b = pseudorigid::particle::inertialess::InertialessState::from_column_slice(&b);
        let y = pack(&r, &Vec3::new(0.1, 0.2, 0.3), &Vec3::new(0.0, 0.1, 0.0));
        let check = |jac: pseudorigid::particle::inertialess::InertialessJacobian| {
            let block = jac.factor(0.3 * h).solve(&b).unwrap();
            let dense = jac.dense().factor(0.3 * h).solve(&b).unwrap();
            (block - dense).abs().max() <= 1e-12 * dense.abs().max()
        };
        let rigid = Particle::new(shape, Rigid, fluid, 2.0).unwrap();
        let model = Model::new(&rigid, &flow);
        for barycentre in [Barycentre::Inertial, Barycentre::Equilibrium] {
            let e = model.inertialess(barycentre, 0.0, &y).unwrap();
            prop_assert!(check(model.inertialess_jacobian(barycentre, &y, &e)));
        }
        let soft = Particle::new(shape, NeoHooke::new(1.0, 100.0).unwrap(), fluid, 2.0).unwrap();
        let model = Model::new(&soft, &flow);
        let e = model.inertialess(Barycentre::Inertial, 0.0, &y).unwrap();
        prop_assert!(check(model.inertialess_jacobian(Barycentre::Inertial, &y, &e)));
    }
}

/// A sphere thrown at V under `auto` into a flow whose rate makes it a tracer (simple shear
/// γ̇ = 10⁻³/s, St = τγ̇ = 10⁻⁶), along the line y = 0 where the fluid is still, coasts its
/// stopping distance τV (Stokes drag, ẍ = −ẋ/τ: x(∞) = τV, closed form; nothing acts across
/// the line) and keeps its inertia; released at the fluid's velocity it is a tracer. By the
/// flow's rate alone `auto` chose the equilibrium barycentre, which cannot carry a launch: a
/// sphere thrown into a still OpenFOAM field (rate 0) did not move. The tolerance: 10
/// relaxation times leave e⁻¹⁰ = 4.5·10⁻⁵ of τV to go; the integration at rtol 10⁻⁸ adds far
/// less.
#[test]
fn auto_keeps_the_inertia_of_a_thrown_particle() {
    use pseudorigid::driver::{Plan, until_event};
    use pseudorigid::integrator::choice::Auto;
    let (tau, speed) = (1e-3, 2.0);
    let sphere = heavy_sphere(tau, 1.8e-5, 1000.0);
    let flow = LinearFlow::simple_shear(1e-3).unwrap();
    let auto = Auto {
        tol: Tolerances::uniform(1e-8).unwrap(),
        norm: Default::default(),
    };
    let mut thrown = State::at_rest(Vec3::zeros());
    thrown.v = Vec3::new(speed, 0.0, 0.0);
    let chosen = auto.choice_at(&sphere, &flow, &thrown).unwrap();
    assert_eq!(
        chosen.integrator.full().barycentre,
        BarycentreModel::Inertial,
        "{}",
        chosen.reason
    );
    let carried = auto.choice_at(&sphere, &flow, &State::at_rest(Vec3::zeros())).unwrap();
    assert_eq!(carried.integrator.full().barycentre, BarycentreModel::Equilibrium);
    let plan = Plan::new(10.0 * tau, 1e-6).unwrap();
    let end = until_event(Problem::new(&auto, &sphere, &flow), thrown, &plan, &[]).unwrap();
    let stopping = tau * speed;
    assert!(
        (end.state.x[0] / stopping - 1.0).abs() < 1e-4,
        "coasted {} m against τV = {stopping} m",
        end.state.x[0]
    );
}

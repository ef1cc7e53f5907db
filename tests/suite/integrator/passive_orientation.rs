//! A rigid sphere's orientation enters none of its equations, so the Rosenbrock-W step leaves F
//! out of its error test (`Particle::orientation_is_passive`, `integrator::stokesian`): which
//! particles qualify, and that the barycentre still follows a closed form to its tolerance.

use crate::common::heavy_sphere;
use nalgebra::Complex;
use pseudorigid::driver::{Observers, Problem, run};
use pseudorigid::hydro::StokesSphere;
use pseudorigid::hydro::forces::{self, Contribution, ForceContext, ForceTerm, ForceTerms};
use pseudorigid::integrator::{BarycentreModel, ErrorNorm, Scheme, Tolerances};
use pseudorigid::material::Rigid;
use pseudorigid::prelude::*;
use pseudorigid::registry::Values;
use std::f64::consts::PI;
use std::sync::Arc;

/// A thrust along the body's long axis (a swimmer's propulsion): body-fixed data, so it keeps
/// the trait's default answer that the orientation matters.
#[derive(Debug)]
struct Thrust;

impl ForceTerm for Thrust {
    fn name(&self) -> &'static str {
        "thrust"
    }

    fn contribution(&self, ctx: &ForceContext) -> Contribution {
        Contribution {
            force: ctx.frame.q.row(0).transpose() * 1e-9,
            ..Contribution::default()
        }
    }
}

fn rigid(semi_axes: [f64; 3]) -> Particle<Rigid> {
    Particle::new(
        Ellipsoid::aligned(semi_axes).unwrap(),
        Rigid,
        Fluid::new(1e-3, 1e3).unwrap(),
        1e3,
    )
    .unwrap()
}

#[test]
fn only_a_rigid_sphere_whose_drag_and_forces_are_isotropic_is_passive() {
    // (and the rigid twin of an isotropic elastic sphere, which the slow manifold turns)
    let sphere = rigid([1e-5; 3]);
    assert!(sphere.orientation_is_passive());
    assert!(
        !rigid([2e-5, 1e-5, 1e-5]).orientation_is_passive(),
        "a prolate turns its drag"
    );
    let soft = Particle::new(
        Ellipsoid::aligned([1e-5; 3]).unwrap(),
        NeoHooke::new(1.0, 1e3).unwrap(),
        Fluid::new(1e-3, 1e3).unwrap(),
        1e3,
    )
    .unwrap();
    assert!(
        !soft.orientation_is_passive(),
        "an elastic sphere's F is its deformation"
    );
    assert!(
        soft.rigid_twin().orientation_is_passive(),
        "an isotropic elastic sphere's twin turns nothing the slow manifold sees"
    );
    let fibred = Particle::new(
        Ellipsoid::aligned([1e-5; 3]).unwrap(),
        crate::common::Fibred {
            matrix: NeoHooke::new(1.0, 1e3).unwrap(),
            k: 1.0,
        },
        Fluid::new(1e-3, 1e3).unwrap(),
        1e3,
    )
    .unwrap();
    assert!(
        !fibred.rigid_twin().orientation_is_passive(),
        "the twin's rotation turns the fibres of a fibred sphere"
    );
    // Every term of the crate sees a sphere's frame through its shape only.
    let all = forces::names()
        .into_iter()
        .filter(|name| *name != "holzer_sommerfeld")
        .map(|name| {
            // Cunningham's slip needs the gas's mean free path (air's, 66.5 nm); no other
            // term of the crate takes a parameter.
            let values: Values = match name {
                "cunningham" => [("mean_free_path".to_string(), 6.65e-8.into())].into(),
                _ => Values::default(),
            };
            forces::by_name(name, &values).unwrap()
        })
        .collect();
    let with_terms = rigid([1e-5; 3]).with_forces(ForceTerms::new(all).unwrap()).unwrap();
    assert!(with_terms.orientation_is_passive());
    let hs = forces::by_name("holzer_sommerfeld", &Values::default()).unwrap();
    let with_hs = rigid([1e-5; 3])
        .with_forces(ForceTerms::new(vec![hs]).unwrap())
        .unwrap();
    assert!(with_hs.orientation_is_passive());
    let thrust = rigid([1e-5; 3])
        .with_forces(ForceTerms::new(vec![Arc::new(Thrust)]).unwrap())
        .unwrap();
    assert!(
        !thrust.orientation_is_passive(),
        "a body-fixed force keeps F in the test"
    );
    let stokes = Particle::with_drag(
        Ellipsoid::aligned([1e-5; 3]).unwrap(),
        Rigid,
        StokesSphere,
        Fluid::new(1e-3, 1e3).unwrap(),
        1e3,
    )
    .unwrap();
    assert!(stokes.orientation_is_passive());
}

/// A heavy sphere in solid-body rotation u = Ω ẑ × x with Stokes drag, τẍ = u − ẋ: in
/// z = x + iy, τz̈ + ż − iΩz = 0, so z = A e^{λ₁t} + B e^{λ₂t} with
/// λ = (−1 ± √(1 + 4iΩτ))/(2τ), and from rest at z = 1, A = −λ₂/(λ₁ − λ₂), B = λ₁/(λ₁ − λ₂).
/// The sphere spins with Ω all the while (its F turns a full circle per period), which its
/// equations never see.
fn exact(t: f64, omega: f64, tau: f64) -> Complex<f64> {
    let root = (Complex::new(1.0, 4.0 * omega * tau)).sqrt();
    let l1 = (root - 1.0) / (2.0 * tau);
    let l2 = (-root - 1.0) / (2.0 * tau);
    let a = -l2 / (l1 - l2);
    let b = l1 / (l1 - l2);
    a * (l1 * t).exp() + b * (l2 * t).exp()
}

/// The barycentre, tracked with F out of the error test, meets the closed form within the sum
/// of the steps' local tolerances (atol + rtol·r per step, each error carried forward by the
/// flow's growth e^{Re λ₁ T} at most), and F stays a rotation turned by Ω T about ẑ to the
/// accuracy the steps give it (10⁻² here: no tolerance holds it).
#[test]
fn a_passive_sphere_in_solid_body_rotation_follows_the_closed_form() {
    let (omega, mu, rho, tau): (f64, f64, f64, f64) = (1.0, 1.0, 1.0, 0.1);
    let particle = heavy_sphere(tau, mu, rho);
    let r = particle.shape().semi_axes()[0];
    assert!(particle.orientation_is_passive());
    let spin = Mat3::new(0.0, -omega, 0.0, omega, 0.0, 0.0, 0.0, 0.0, 0.0);
    let flow = LinearFlow::new(Vec3::zeros(), spin).unwrap();
    let tol = 1e-6;
    let integ = Stokesian {
        tol: Tolerances::new(tol, tol, 1e-14).unwrap(),
        barycentre: BarycentreModel::Inertial,
        scheme: Scheme::Rosenbrock23,
        norm: ErrorNorm::Tensor,
        frame: Default::default(),
    };
    // A period and a quarter: F has turned by π/2 (mod 2π) at the end.
    let period = 2.5 * PI / omega;
    let (end, stats) = run(
        Problem::new(&integ, &particle, &flow),
        State::at_rest(Vec3::new(1.0, 0.0, 0.0)),
        1e-4,
        &[period],
        Observers::none(),
    )
    .unwrap();
    let z = exact(period, omega, tau);
    let miss = (Complex::new(end.x[0], end.x[1]) - z).norm();
    let l1 = ((Complex::new(1.0, 4.0 * omega * tau)).sqrt() - 1.0) / (2.0 * tau);
    let bound = stats.steps as f64 * (tol + tol * r) * (l1.re * period).exp();
    assert!(
        miss <= bound,
        "|x − exact| = {miss:e} over {} steps, bound {bound:e}",
        stats.steps
    );
    assert!(
        (end.f.transpose() * end.f - Mat3::identity()).norm() < 1e-12,
        "F left SO(3)"
    );
    let turned = end.f[(1, 0)].atan2(end.f[(0, 0)]);
    assert!((turned - PI / 2.0).abs() < 1e-2, "F turned by {turned}, not π/2");
}

//! Plugging in a user constitutive law without touching the solver.
//!
//! A compressible Yeoh solid, written once as an energy generic over num-dual scalars:
//! W = C₁ K + C₂ K² + C₃ K³ + (λ/2)(ln J)², with K = I₁ − 3 − 2 ln J (so F = 1 is stress-free
//! and the small-strain shear modulus is μ_s = 2C₁). P and the tangent come from AD.
//! The example runs an initially spherical particle in simple shear to its tank-treading state.
//!
//! Run: `cargo run --release --example custom_material`

use pseudorigid::driver::{Problem, advance};
use pseudorigid::integrator::Stokesian;
use pseudorigid::prelude::*;
use pseudorigid::tensor::{Scalar, det3};

/// Compressible Yeoh law.
struct Yeoh {
    c: [f64; 3],
    lambda: f64,
}

impl Hyperelastic for Yeoh {
    fn energy<S: Scalar>(&self, f: &Mat3<S>) -> S {
        let ln_j = det3(f).ln();
        let i1 = f.iter().fold(S::from(0.0), |acc, &x| acc + x * x);
        let k = i1 - 3.0 - ln_j * 2.0;
        k * self.c[0] + k * k * self.c[1] + k * k * k * self.c[2] + ln_j * ln_j * (0.5 * self.lambda)
    }
    fn shear_modulus(&self) -> f64 {
        2.0 * self.c[0]
    }
    fn lame_lambda(&self) -> f64 {
        self.lambda
    }
    // A function of I₁ and J only: say so, and a stiff sphere of it may turn untested on the
    // slow manifold (the default, `false`, is always safe).
    fn is_isotropic(&self) -> bool {
        true
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let ca = 0.2; // μ_f γ̇ / μ_s with μ_f = γ̇ = 1
    let mu_s = 1.0 / ca;
    let law = Yeoh {
        c: [mu_s / 2.0, 0.1 * mu_s, 0.01 * mu_s],
        lambda: 1e3 * mu_s,
    };
    let shape = Ellipsoid::with_volume_diameter([1.0, 1.0, 1.0], 1.0, Mat3::identity())?;
    let particle = Particle::new(shape, law, Fluid::new(1.0, 1.0)?, 1.0)?;
    let flow = LinearFlow::simple_shear(1.0)?;
    let (end, stats) = advance(
        Problem::new(&Stokesian::overdamped(1e-8)?, &particle, &flow),
        State::at_rest(Vec3::zeros()),
        1e-3,
        40.0,
    )?;
    let r = particle.geometry(&end.f).frame.r;
    println!(
        "Yeoh particle, Ca = {ca}: steady semi-axes r = ({:.4}, {:.4}, {:.4}) d_eq",
        r[0], r[1], r[2]
    );
    println!(
        "Taylor deformation D = (r1 - r3)/(r1 + r3) = {:.4}",
        (r[0] - r[2]) / (r[0] + r[2])
    );
    println!("{} steps, {} model evaluations", stats.steps, stats.rhs_evals);
    Ok(())
}

//! Shared set-up of the population tests: the settling pipe as a population, with an
//! injector wrapper that fails some particles on purpose and can slow every draw down.

use pseudorigid::contact::{Composite, PipeWall};
use pseudorigid::driver::{Budget, Plan};
use pseudorigid::error::{ParamError, StepError};
use pseudorigid::flow::analytic::Poiseuille;
use pseudorigid::integrator::{BarycentreModel, Stokesian};
use pseudorigid::material::{NeoHooke, Softness};
use pseudorigid::particle::Particle;
use pseudorigid::population::settling_pipe::SettlingPipe;
use pseudorigid::population::{Case, Fingerprint, Injector, ParticleRng, ParticleSpec, RunConfig};
use pseudorigid::prelude::Brenner;
use std::time::Duration;

/// Pipe R = 20, L = 200, Ū = 1, v_s = 0.1, inlet disc radius 15 (units d_eq): a sphere
/// released at y₀ = −10 deposits near x₁ ≈ 83, one on the axis would need x₁ ≈ 266 > L and
/// escapes, so both fates occur.
pub fn pipe() -> SettlingPipe {
    SettlingPipe::new(20.0, 200.0, 1.0, 0.1, 15.0).unwrap()
}

/// Soft prolates (λ = 3, Ca = 0.2) with random orientations in the settling pipe.
pub fn soft_pipe() -> SettlingPipe {
    pipe().with_shape(3.0, 0.2).unwrap()
}

/// The inertial-barycentre integrator of the mixed populations.
pub fn integrator() -> Stokesian {
    Stokesian {
        barycentre: BarycentreModel::Inertial,
        ..Stokesian::new(1e-7).unwrap()
    }
}

/// End time 150: shorter than the slowest particles' residence (a sphere near the axis takes
/// ≈ 100–200 to reach the outlet at centreline speed ≤ 2), so some are suspended; a step budget
/// (no wall-time limit: results must not depend on the machine).
pub fn plan() -> Plan {
    Plan::new(150.0, 0.1).unwrap().with_budget(Budget {
        max_steps: 200_000,
        wall_time: None,
    })
}

/// The settling pipe with particles k ≡ 5 (mod 11) failing to draw, and an optional sleep in
/// every draw (to keep a child process busy long enough to be killed mid-run; a sleep does not
/// change any result).
pub struct Faulty {
    pub inner: SettlingPipe,
    pub delay: Option<Duration>,
}

impl Injector for Faulty {
    type Law = NeoHooke;
    type Drag = Brenner;

    fn draw(&self, index: u64, rng: &mut ParticleRng) -> Result<ParticleSpec<NeoHooke>, StepError> {
        if let Some(d) = self.delay {
            std::thread::sleep(d);
        }
        if index % 11 == 5 {
            return Err(ParamError::NotPositive {
                name: "test: particle chosen to fail",
                value: index as f64,
            }
            .into());
        }
        self.inner.draw(index, rng)
    }

    fn particle(&self, spec: &ParticleSpec<NeoHooke>) -> Result<Particle<Softness<NeoHooke>, Brenner>, ParamError> {
        self.inner.particle(spec)
    }
}

/// The faulty soft pipe without delay and its integrator, owned together so that a test makes
/// its [`Case`] in one line: `let soft = FaultySoftPipe::new(); let case = soft.case(plan());`.
pub struct FaultySoftPipe {
    pub stokes: Stokesian,
    pub pipe: SettlingPipe,
    pub faulty: Faulty,
}

impl FaultySoftPipe {
    pub fn new() -> Self {
        let pipe = soft_pipe();
        Self {
            stokes: integrator(),
            faulty: Faulty {
                inner: pipe.clone(),
                delay: None,
            },
            pipe,
        }
    }

    /// The case of these particles in the pipe's flow and wall, run to `plan`.
    pub fn case(&self, plan: Plan) -> Case<'_, Stokesian, Poiseuille, Composite<PipeWall>, Faulty> {
        Case::new(&self.stokes, self.pipe.flow(), self.pipe.boundary(), &self.faulty, plan)
    }
}

/// The run configuration of the mixed population of `n` particles.
pub fn config(n: u64) -> RunConfig {
    Fingerprint::new("faulty k = 5 mod 11")
        .particles(&soft_pipe())
        .config(20_261_122, n)
}

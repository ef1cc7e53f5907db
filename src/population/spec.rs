//! What one particle of a population is, and how it is drawn from its own generator.
//!
//! # Per-particle seeds
//! Particle k of a run with seed s draws its [`ParticleSpec`] from [`particle_rng`]`(s, k)`:
//! ChaCha12 keyed by s (expanded to the 256-bit key by `rand_core`'s portable
//! `seed_from_u64`) on stream k. ChaCha is a counter-based generator: its output is a keyed
//! function of (stream, block counter), so the 2⁶⁴ streams of one key are independent
//! sequences (Bernstein 2008; the `rand` project uses ChaCha12 for its standard generator), and
//! particle k's numbers depend on (s, k) alone, never on the thread, shard or order that runs
//! it. That is what makes a population the same whatever its layout.

use crate::driver::Plan;
use crate::ellipsoid::Ellipsoid;
use crate::error::{ParamError, StepError};
use crate::hydro::{DragModel, ForceTerms, VolumetricTraction};
use crate::material::{Softness, StressLaw};
use crate::particle::{Fluid, Particle, State};
use crate::tensor::Vec3;
use rand_chacha::ChaCha12Rng;
use rand_chacha::rand_core::SeedableRng;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

/// The generator a particle draws its specification from.
pub type ParticleRng = ChaCha12Rng;

/// The generator of particle `index` in a run with seed `seed`: ChaCha12 keyed by `seed`, on
/// stream `index`.
pub fn particle_rng(seed: u64, index: u64) -> ParticleRng {
    let mut rng = ChaCha12Rng::seed_from_u64(seed);
    rng.set_stream(index);
    rng
}

/// Everything that differs between the particles of a population: the stress-free ellipsoid
/// (semi-axes and initial orientation), the shape response, the solid density, and the
/// injection point and velocity. The injection time is 0 unless the injector draws one
/// ([`Injector::injection`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParticleSpec<L> {
    /// Stress-free ellipsoid B₀: semi-axes along its initial axes (the orientation).
    pub shape: Ellipsoid,
    /// Rigid, or elastic with a hyperelastic law.
    pub softness: Softness<L>,
    /// Solid density ρ_s (> 0; checked when the particle is built).
    pub density: f64,
    /// Injection point x_c(0).
    pub position: Vec3,
    /// Injection velocity v_c(0).
    pub velocity: Vec3,
}

impl<L> ParticleSpec<L> {
    /// The stress-free state at injection (t = 0, F = 1, A = 0).
    pub fn start_state(&self) -> State {
        State {
            v: self.velocity,
            ..State::at_rest(self.position)
        }
    }
}

/// How a population's particles are drawn and built. `draw` must be a function of its
/// arguments only (no clocks, no shared counters): particle `index` is then the same particle
/// in every run layout.
pub trait Injector: Sync {
    /// The hyperelastic law of the elastic particles.
    type Law: StressLaw + Clone + PartialEq + std::fmt::Debug + Serialize + DeserializeOwned;
    /// The drag model of every particle.
    type Drag: DragModel;

    /// The specification of particle `index`, drawn from its own generator `rng`.
    fn draw(&self, index: u64, rng: &mut ParticleRng) -> Result<ParticleSpec<Self::Law>, StepError>;

    /// The particle model of `spec`.
    fn particle(&self, spec: &ParticleSpec<Self::Law>)
    -> Result<Particle<Softness<Self::Law>, Self::Drag>, ParamError>;

    /// The state particle `index` starts from: by default the stress-free state at injection
    /// ([`ParticleSpec::start_state`]). A scene that turns its releases by an initial
    /// deformation (F = a rotation) sets it here.
    fn start_state(&self, _index: u64, spec: &ParticleSpec<Self::Law>) -> State {
        spec.start_state()
    }

    /// The state particle `index` enters the flow with, its time being the injection time:
    /// by default [`Injector::start_state`] (t = 0), drawing nothing from `rng`, so a run
    /// without injection times has the records it always had. A scene whose particles enter
    /// over time (an inhalation) draws the time here from the particle's own generator `rng`,
    /// which [`Injector::draw`] has used before: the spec's draws are then those of the same
    /// scene injected at once, and the particles of the two runs are paired. Like `draw`, a
    /// function of its arguments only. The plan's end time is absolute (a particle injected
    /// at t₀ is tracked to the end time, not for it); the batch runner
    /// ([`super::batch::run_batch`]) starts a particle in the window that contains its time.
    fn injection(
        &self,
        index: u64,
        spec: &ParticleSpec<Self::Law>,
        _rng: &mut ParticleRng,
    ) -> Result<State, StepError> {
        Ok(self.start_state(index, spec))
    }

    /// The plan of particle `index` of `spec`, given the case's `plan`: by default the case's. A
    /// scene whose time limit or step cap depends on the particle (its size, its settling
    /// time) gives it here; like [`Injector::draw`], a function of its arguments only.
    fn plan(&self, _index: u64, _spec: &ParticleSpec<Self::Law>, plan: &Plan) -> Result<Plan, ParamError> {
        Ok(plan.clone())
    }
}

/// What the particles of a population share: drag model, carrier fluid, gravity and the
/// volumetric traction. [`ParticleTemplate::build`] adds a [`ParticleSpec`]'s shape, response
/// and density.
#[derive(Debug, Clone, PartialEq)]
pub struct ParticleTemplate<D> {
    drag: D,
    fluid: Fluid,
    gravity: Vec3,
    volumetric: VolumetricTraction,
    forces: ForceTerms,
}

impl<D: DragModel + Clone> ParticleTemplate<D> {
    /// Particles with drag `drag` in `fluid` under `gravity` (finite).
    pub fn new(drag: D, fluid: Fluid, gravity: Vec3) -> Result<Self, ParamError> {
        for g in gravity.iter() {
            crate::error::finite("gravity", *g)?;
        }
        Ok(Self {
            drag,
            fluid,
            gravity,
            volumetric: VolumetricTraction::default(),
            forces: ForceTerms::default(),
        })
    }

    /// The same template with force terms beyond the paper's ([`crate::hydro::forces`]).
    pub fn with_forces(self, forces: ForceTerms) -> Self {
        Self { forces, ..self }
    }

    /// The same template with another volumetric traction (see [`VolumetricTraction`]).
    pub fn with_volumetric(self, volumetric: VolumetricTraction) -> Self {
        Self { volumetric, ..self }
    }

    /// The particle of `spec`.
    pub fn build<L: StressLaw + Clone>(&self, spec: &ParticleSpec<L>) -> Result<Particle<Softness<L>, D>, ParamError> {
        Particle::with_drag(
            spec.shape,
            spec.softness.clone(),
            self.drag.clone(),
            self.fluid,
            spec.density,
        )?
        .with_gravity(self.gravity)?
        .with_volumetric(self.volumetric)
        .with_forces(self.forces.clone())
    }
}

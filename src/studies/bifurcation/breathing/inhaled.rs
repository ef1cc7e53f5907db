//! The steady study's particles injected over an inhalation (module docs of [`super`]:
//! Injection).

use super::Waveform;
use crate::error::{ParamError, StepError};
use crate::hydro::Brenner;
use crate::material::{NeoHooke, Softness};
use crate::particle::{Particle, State};
use crate::population::{Injector, ParticleRng, ParticleSpec, particle_rng};
use crate::studies::bifurcation::injection::{Injection, Kind};
use crate::studies::bifurcation::setup::Airway;
use rand::RngExt;

/// The steady study's injection ([`Injection`]) spread over an inhalation: the same particles,
/// each entering at its own time with the fluid's velocity then ([module docs](super)).
pub struct Inhaled<'a> {
    steady: Injection<'a>,
    waveform: Waveform,
}

impl<'a> Inhaled<'a> {
    /// Particles of `kind` inhaled into `airway` (whose steady field gives the injection
    /// velocity's profile) as `waveform` says.
    pub fn new(airway: &'a Airway, kind: Kind, waveform: Waveform) -> Result<Self, ParamError> {
        Ok(Self {
            steady: Injection::new(airway, kind)?,
            waveform,
        })
    }

    /// The injection time of particle `index` of a run with seed `seed` (as the runner draws it).
    pub fn injection_time(&self, seed: u64, index: u64) -> Result<f64, StepError> {
        let mut rng = particle_rng(seed, index);
        let spec = self.steady.draw(index, &mut rng)?;
        Ok(self.injection(index, &spec, &mut rng)?.t)
    }
}

impl Injector for Inhaled<'_> {
    type Law = NeoHooke;
    type Drag = Brenner;

    fn draw(&self, index: u64, rng: &mut ParticleRng) -> Result<ParticleSpec<NeoHooke>, StepError> {
        self.steady.draw(index, rng)
    }

    fn particle(&self, spec: &ParticleSpec<NeoHooke>) -> Result<Particle<Softness<NeoHooke>, Brenner>, ParamError> {
        self.steady.particle(spec)
    }

    fn injection(&self, _index: u64, spec: &ParticleSpec<NeoHooke>, rng: &mut ParticleRng) -> Result<State, StepError> {
        let t = self.waveform.injection_time(rng.random::<f64>());
        Ok(State {
            t,
            v: spec.velocity * self.waveform.scale(t),
            ..spec.start_state()
        })
    }
}

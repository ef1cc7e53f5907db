//! Injection at the inlet (paper §6.4): particle k of a run is drawn from its own generator.
//!
//! # Readings where the paper is silent
//! - The disc of diameter 5.5 mm is centred on the parent axis, normal to e₁, at
//!   [`INJECTION_X`] downstream of the inlet plane; points are uniform by area.
//! - The initial orientation of a non-spherical particle is uniform on SO(3) (Haar): the paper
//!   gives none, and a randomly oriented aerosol is the neutral reading.
//! - The injection velocity is the fluid velocity at the injection point (paper: "the local
//!   fluid velocity"); the particle starts stress-free (F = 1).
//! - The shape follows the inertialess (Stokesian) model, the barycentre is inertial (that is
//!   what Stk measures) or, for tracer-like particles, at its equilibrium velocity
//!   ([`crate::integrator::choice`]). The solid's nondimensional density
//!   ρ* = ρ_p γ̇ d_eq²/μ_f at γ̇ ≤ 2·10³ s⁻¹ is 0.87 (Stk 0.005, d_eq = 1.8 µm) to 87
//!   (Stk 0.5, 18 µm): not small, so the shape's (for a rigid particle: the rotation's) inertia
//!   is a neglected effect of order ρ* in the orientation; the barycentre, which decides
//!   impaction, keeps its inertia. (An earlier reading stated ρ* < 0.1 here, which these
//!   numbers contradict.)

use super::setup::{Airway, GRAVITY, INJECTION_DIAMETER, INJECTION_X, d_eq_for_stokes, fluid, rho_particle};
use crate::error::{ParamError, StepError};
use crate::hydro::Brenner;
use crate::hydro::ForceTerms;
use crate::material::{NeoHooke, Softness};
use crate::particle::Particle;
use crate::population::sampling::{haar_rotation, uniform_disc};
use crate::population::{Injector, ParticleRng, ParticleSpec, ParticleTemplate};
use crate::studies::particles::Shape;
use crate::tensor::Vec3;
use serde::Serialize;

/// λ_s/μ_s of the elastic particles. The inertialess model keeps tr l_s = 0, so J = 1 and the
/// bulk term never acts; the value only has to be positive.
const BULK_RATIO: f64 = 1e3;

/// Below this capillary number an elastic particle is run as the rigid limit. Its deformation
/// is O(Ca) (Jeffery–Roscoe: |F̄ − R| ∝ Ca for Ca ≪ 1), four decades below the studies'
/// relative tolerance ([`super::study::RTOL`]) here, so the elastic response cannot be told from
/// the rigid one within the run's own error, while its stiffness (relaxation rate 1/Ca in flow
/// time units) costs the integrator most of its steps. The paper's quasi-rigid μ_s = 10⁵ Pa has
/// Ca = 3.7·10⁻⁸. Checked by a paired run: 150 prolates λ₁ = 5 at Stk = 0.4, elastic
/// μ_s = 10⁵ Pa against rigid, both at rtol 10⁻⁵: the same fates, deposits within 6.6 µm in x₁
/// (the elastic run at rtol 10⁻³ is itself 87 µm from its rtol 10⁻⁵ run).
pub const RIGID_BELOW_CA: f64 = 1e-6;

/// How the particle's shape responds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Material {
    /// Rigid: the limit Ca → 0 (paper Fig. 18).
    Rigid,
    /// Neo-Hookean with this shear modulus μ_s (Pa) (paper: 1e5 quasi-rigid, 1 and 0.5 soft);
    /// run as the rigid limit when its Ca is below [`RIGID_BELOW_CA`].
    ShearModulus(f64),
}

impl Material {
    /// Capillary number Ca = μ_f (U/D)/μ_s with the parent's mean velocity U and diameter D
    /// (the scales of the Stokes number, eq. 25); 0 for [`Material::Rigid`].
    pub fn capillary_number(self) -> f64 {
        match self {
            Material::Rigid => 0.0,
            Material::ShearModulus(mu_s) => fluid().mu * super::setup::inlet_velocity() / super::setup::DIAMETER / mu_s,
        }
    }

    /// Label for datasets: `rigid` or `mu_s=<Pa>`.
    pub fn label(self) -> String {
        match self {
            Material::Rigid => "rigid".into(),
            Material::ShearModulus(mu_s) => format!("mu_s={mu_s}"),
        }
    }

    fn softness(self) -> Result<Softness<NeoHooke>, ParamError> {
        Ok(match self {
            Material::Rigid => Softness::Rigid,
            Material::ShearModulus(_) if self.capillary_number() < RIGID_BELOW_CA => Softness::Rigid,
            Material::ShearModulus(mu_s) => Softness::Elastic(NeoHooke::new(mu_s, BULK_RATIO * mu_s)?),
        })
    }
}

/// One kind of particle: initial shape, material and Stokes number.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Kind {
    /// Initial shape (axis ratios).
    pub shape: Shape,
    /// Shape response.
    pub material: Material,
    /// Stokes number of the parent branch (fixes d_eq, [`super::setup::stokes_number`]).
    pub stokes: f64,
}

/// The injection rule of paper §6.4 for one [`Kind`] of particle in an [`Airway`].
pub struct Injection<'a> {
    airway: &'a Airway,
    kind: Kind,
    d_eq: f64,
    softness: Softness<NeoHooke>,
    template: ParticleTemplate<Brenner>,
}

impl<'a> Injection<'a> {
    /// Particles of `kind` injected into `airway`.
    pub fn new(airway: &'a Airway, kind: Kind) -> Result<Self, ParamError> {
        let template = ParticleTemplate::new(Brenner, fluid(), Vec3::new(GRAVITY, 0.0, 0.0))?;
        Ok(Self {
            airway,
            kind,
            d_eq: d_eq_for_stokes(kind.stokes)?,
            softness: kind.material.softness()?,
            template,
        })
    }

    /// The same injection with force terms beyond the paper's on every particle.
    pub fn with_forces(self, forces: ForceTerms) -> Self {
        Self {
            template: self.template.with_forces(forces),
            ..self
        }
    }

    /// The particle kind.
    pub fn kind(&self) -> Kind {
        self.kind
    }

    /// Volume-equivalent diameter d_eq (m).
    pub fn d_eq(&self) -> f64 {
        self.d_eq
    }

    /// Particle `index` of a run with seed `seed`, as the population runner draws it (from
    /// [`crate::population::particle_rng`]`(seed, index)`): what another tracker needs to
    /// follow the same particles (`examples/openfoam_peer.rs`).
    pub fn particle_spec(&self, seed: u64, index: u64) -> Result<ParticleSpec<NeoHooke>, StepError> {
        self.draw(index, &mut crate::population::particle_rng(seed, index))
    }
}

impl Injector for Injection<'_> {
    type Law = NeoHooke;
    type Drag = Brenner;

    fn draw(&self, _index: u64, rng: &mut ParticleRng) -> Result<ParticleSpec<NeoHooke>, StepError> {
        let centre = Vec3::new(INJECTION_X, 0.0, 0.0);
        let position = uniform_disc(rng, &centre, &Vec3::x(), 0.5 * INJECTION_DIAMETER)?;
        let axes = haar_rotation(rng);
        let shape = self.kind.shape.ellipsoid(self.d_eq, axes)?;
        let velocity = crate::flow::FlowField::sample(self.airway.flow(), &position, 0.0)?.u;
        Ok(ParticleSpec {
            shape,
            softness: self.softness,
            density: rho_particle(),
            position,
            velocity,
        })
    }

    fn particle(&self, spec: &ParticleSpec<NeoHooke>) -> Result<Particle<Softness<NeoHooke>, Brenner>, ParamError> {
        self.template.build(spec)
    }
}

//! Force terms on the barycentre beyond the paper's Stokes drag and reduced gravity: fluid
//! inertia (undisturbed-flow force, added mass), gas slip (Cunningham), finite-Re drag (spheres
//! and ellipsoids) and
//! shear lift. Each term is one file; a particle carries a list of them ([`ForceTerms`]), empty
//! by default, and an empty list leaves every step bit for bit as the paper's.
//!
//! # Physics
//! The paper's barycentre equation (eq. 17), m v̇ = (m − m_f) g + μ_f K̂ (u − v) with
//! m_f = ρ_f vol(B_t) the displaced fluid's mass, is exact for a particle much heavier than
//! its fluid at vanishing particle Reynolds number. With the terms of this module it reads
//! ```math
//! (m\,\mathbf 1 + M_a)\,\dot v = (m - m_f)\,g + c\,\mu_f \hat K (u - v) + \sum_k f_k
//! ```
//! where each term k may add an added-mass tensor to M_a, a factor to the drag correction
//! c = Π c_k, and a force f_k ([`Contribution`]). Dividing by the effective mass M = m 1 + M_a
//! keeps the shape of eq. 17, v̇ = a + R(u − v) with R = M⁻¹ c μ_f K̂ and
//! a = M⁻¹((m − m_f) g + Σ f_k) ([`crate::particle::Forcing`]), so the IMEX step still solves
//! the drag implicitly and the overdamped barycentre still balances it:
//! v = u + (c μ_f K̂)⁻¹((m − m_f) g + Σ f_k), independent of M_a. M is symmetric positive
//! definite for every ρ_p ≥ 0 with added mass on (a bubble has M = M_a), so R stays a
//! positive-definite rate and the implicit drag stays unconditionally stable from bubbles to
//! ρ_p ≫ ρ_f. Terms that depend on the slip u − v are evaluated at the step's lagged velocity
//! by the inertial schemes and iterated to a fixed point by the overdamped barycentre
//! ([`crate::particle::Model::overdamped_velocity`]).
//!
//! What each term assumes, its source and its validity range are in its own file:
//! [`undisturbed`], [`added_mass`], [`cunningham`], [`schiller_naumann`] (spheres),
//! [`holzer_sommerfeld`] (any ellipsoid), [`saffman_mei`].
//!
//! Each file also registers its term ([`Registration`]): its name, its builder from the scene's
//! [`Parameters`] and, where the run's numbers can tell how large the term would be on a particle
//! that leaves it out, that estimate ([`Omission`]), which the validity monitor
//! ([`crate::diagnostics`]) iterates. A drag correlation that depends on the slip, the fluid or
//! the gas is a term's drag factor; one of the shape alone is a [`crate::hydro::DragModel`]
//! (the guide, [`crate::guide`], says why).
//!
//! # What is left out, and when it matters
//! - **Fluid inertia in the shape equation.** The undisturbed flow also loads the force dyad:
//!   its stress integrated against X over the particle gives ρ_f vol(B_t) (l̇ + l²) Θ/m-type
//!   terms, the dyad's analogue of m_f Du/Dt, beside the solid inertia Θ Ä that the paper keeps.
//!   Their ratio is ρ_f/ρ_p. For aerosols (pipe, bifurcation: ρ_f/ρ_p ≈ 10⁻³) the term is a
//!   thousandth of a solid inertia that is itself small (ρ* ≪ 1), so it is negligible. For the
//!   cavity (ρ_f/ρ_p = 0.9995, ρ* ≈ 5.5 at release, i.e. a shear Reynolds number
//!   γ̇ d²/ν ≈ 5) it is as large as the solid inertia: the paper's inertial shape model is then
//!   not more complete than the inertialess one, and a particle Reynolds number of 5 is outside
//!   the Stokes-flow traction of eq. 12 anyway. The validity monitor's `re_shear` flag says so;
//!   this code does not implement the term.
//! - **Basset's history force.** For a sphere,
//!   f_B = (3/2) d² √(π ρ_f μ_f) ∫ (d(u − v)/dt') (t − t')^{−1/2} dt'; against the drag on a slip
//!   that changes over a time T it is of order √(d²/(π ν T)). Aerosols: d²/ν ≤ 2·10⁻⁵ s for
//!   d ≤ 16 µm in air, T ≳ 1 ms (bend and bifurcation transit times), so ≤ 8 %, and only while
//!   the slip changes, with ρ_f/ρ_p ≈ 10⁻³ weighting the fluid's part: negligible. The cavity:
//!   d²/ν = 0.52 s against its circulation time 1.2 s gives about 0.4: the history force changes
//!   the *transients* of the cavity particle's small slip by tens of per cent. With the fluid-
//!   inertia terms on, that slip is mostly the 0.05 % buoyancy drift; the history force would
//!   change how fast it adjusts along the path, which is not modelled (the cavity's NOTES say
//!   what that leaves open). The term is not implemented.

pub mod added_mass;
pub mod cunningham;
pub mod holzer_sommerfeld;
pub mod omission;
pub mod saffman_mei;
pub mod schiller_naumann;
pub mod undisturbed;

pub use added_mass::AddedMass;
pub use cunningham::Cunningham;
pub use holzer_sommerfeld::HolzerSommerfeld;
pub use omission::{Observed, Omission, Rest, Size};
pub use saffman_mei::SaffmanMei;
pub use schiller_naumann::SchillerNaumann;
pub use undisturbed::UndisturbedFlow;

use crate::ellipsoid::{EllipsoidIntegrals, PrincipalFrame};
use crate::error::ParamError;
use crate::flow::FlowSample;
use crate::registry::{self, Entry, Parameters, Values};
use crate::tensor::{Mat3, Vec3};
use std::fmt::Debug;
use std::sync::Arc;

/// What a force term sees: the particle's current shape, its fluid, its velocity and the
/// undisturbed flow sampled at its barycentre.
#[derive(Debug, Clone, Copy)]
pub struct ForceContext<'a> {
    /// Current principal frame (semi-axes r_a, rotation Q).
    pub frame: &'a PrincipalFrame,
    /// Jeffery's integrals of the current shape.
    pub ints: &'a EllipsoidIntegrals,
    /// Fluid viscosity μ_f.
    pub mu_f: f64,
    /// Fluid density ρ_f.
    pub rho_f: f64,
    /// Particle mass m.
    pub mass: f64,
    /// Barycentre velocity v.
    pub v: Vec3,
    /// The undisturbed flow at the barycentre.
    pub flow: &'a FlowSample,
}

impl ForceContext<'_> {
    /// Current volume vol(B_t) = 4π/3 r₁r₂r₃.
    pub fn volume(&self) -> f64 {
        self.frame.volume()
    }

    /// Mass of the displaced fluid, m_f = ρ_f vol(B_t).
    pub fn fluid_mass(&self) -> f64 {
        self.rho_f * self.volume()
    }

    /// Slip u − v of the fluid past the particle.
    pub fn slip(&self) -> Vec3 {
        self.flow.u - self.v
    }

    /// Diameter of the volume-equivalent sphere, d = 2 (r₁r₂r₃)^{1/3}.
    pub fn volume_diameter(&self) -> f64 {
        2.0 * self.frame.r.product().cbrt()
    }

    /// Particle Reynolds number Re_p = ρ_f |u − v| d / μ_f on the volume-equivalent diameter.
    pub fn reynolds(&self) -> f64 {
        self.rho_f * self.slip().norm() * self.volume_diameter() / self.mu_f
    }
}

/// One term's share of the barycentre equation (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contribution {
    /// Factor c_k on the Stokes resistance μ_f K̂ (1: no correction).
    pub drag_factor: f64,
    /// Added-mass tensor, in kg (zero: none).
    pub added_mass: Mat3,
    /// Force f_k, in N.
    pub force: Vec3,
}

impl Default for Contribution {
    fn default() -> Self {
        Self {
            drag_factor: 1.0,
            added_mass: Mat3::zeros(),
            force: Vec3::zeros(),
        }
    }
}

/// A force term on the barycentre. Implement it in one file to add a term, and submit a
/// [`Registration`] there to make it selectable by name from scene files and Python.
pub trait ForceTerm: Send + Sync + Debug {
    /// The term's name in scene files (`particles.forces`).
    fn name(&self) -> &'static str;

    /// Refuse a particle the term has no model for (checked when the particle is built, on its
    /// rest semi-axes). The default admits every ellipsoid.
    fn admits(&self, _semi_axes: &Vec3) -> Result<(), ParamError> {
        Ok(())
    }

    /// The physics the term models when a particle may carry only one term modelling it
    /// ([`FINITE_RE_DRAG`]), else `None` (the default). [`ForceTerms::new`] refuses a list with
    /// two terms of one group.
    fn exclusive_group(&self) -> Option<&'static str> {
        None
    }

    /// The term's share at one state.
    fn contribution(&self, ctx: &ForceContext) -> Contribution;

    /// Whether the term's share on a sphere is the same whatever the rotation of its principal
    /// frame ([`ForceContext::frame`]'s axes): true for a term that sees the frame only through
    /// the shape (every term of this crate). The default, `false`, is the safe answer for a
    /// term with body-fixed data (a propulsion along a body axis, a magnetic moment); with
    /// `true` from every term a rigid sphere's orientation may be left out of the step's error
    /// test ([`crate::particle::Particle::orientation_is_passive`]).
    fn orientation_free_on_spheres(&self) -> bool {
        false
    }
}

/// The group of the finite-Reynolds-number drag corrections ([`schiller_naumann`],
/// [`holzer_sommerfeld`]): each multiplies the Stokes drag by the whole inertial increase of
/// its correlation (c = 1 + …), and the drag factors of a particle's terms multiply, so two of
/// them would apply the increase twice (c_SN c_HS in place of one c). Cunningham's slip
/// correction is not one of them: it corrects for the gas's molecular nature, not for fluid
/// inertia, and multiplies with either.
pub const FINITE_RE_DRAG: &str = "finite-Reynolds-number drag correction";

/// The terms that model the fluid's inertia (the displaced fluid accelerated with the flow,
/// and the fluid accelerated with the particle): of the same order as the particle's own
/// inertia, m_f/m = ρ_f/ρ_p, so a barycentre model without the particle's inertia must not
/// keep them ([`crate::particle::inertialess::BarycentreModel::admits`]).
pub const FLUID_INERTIA: [&str; 2] = [UndisturbedFlow::NAME, AddedMass::NAME];

/// The force terms of a particle, shared between the particles built from one template.
#[derive(Debug, Clone, Default)]
pub struct ForceTerms(Arc<[Arc<dyn ForceTerm>]>);

impl ForceTerms {
    /// The given terms, in order. A term named twice would count twice and is refused
    /// ([`ParamError::Repeated`]), and so are two terms of one [`ForceTerm::exclusive_group`]
    /// ([`ParamError::Conflict`], naming both).
    pub fn new(terms: Vec<Arc<dyn ForceTerm>>) -> Result<Self, ParamError> {
        for (i, term) in terms.iter().enumerate() {
            if terms[..i].iter().any(|t| t.name() == term.name()) {
                return Err(ParamError::Repeated {
                    kind: "force term",
                    name: term.name().to_string(),
                });
            }
            let Some(group) = term.exclusive_group() else {
                continue;
            };
            if let Some(first) = terms[..i].iter().find(|t| t.exclusive_group() == Some(group)) {
                return Err(ParamError::Conflict {
                    what: group,
                    first: first.name().to_string(),
                    second: term.name().to_string(),
                });
            }
        }
        Ok(Self(terms.into()))
    }

    /// No terms: the paper's barycentre equation.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The terms, in order.
    pub fn iter(&self) -> impl Iterator<Item = &dyn ForceTerm> {
        self.0.iter().map(|t| t.as_ref())
    }

    /// Whether every term is [`ForceTerm::orientation_free_on_spheres`] (true for none).
    pub fn orientation_free_on_spheres(&self) -> bool {
        self.iter().all(ForceTerm::orientation_free_on_spheres)
    }

    /// The terms' names, in order.
    pub fn names(&self) -> Vec<&'static str> {
        self.iter().map(ForceTerm::name).collect()
    }

    /// The sum of the terms' contributions at one state.
    pub fn total(&self, ctx: &ForceContext) -> Contribution {
        self.iter().fold(Contribution::default(), |sum, term| {
            let c = term.contribution(ctx);
            Contribution {
                drag_factor: sum.drag_factor * c.drag_factor,
                added_mass: sum.added_mass + c.added_mass,
                force: sum.force + c.force,
            }
        })
    }
}

/// Two lists are equal when they hold the same terms with the same parameters, in order
/// (compared by their `Debug` forms, which show both).
impl PartialEq for ForceTerms {
    fn eq(&self, other: &Self) -> bool {
        self.0.len() == other.0.len()
            && self
                .iter()
                .zip(other.iter())
                .all(|(a, b)| format!("{a:?}") == format!("{b:?}"))
    }
}

/// A force term selectable by name from scene files and Python: its name, how to build it
/// from the scene's parameters (SI units) and, optionally, how the validity monitor estimates
/// it on a particle that leaves it out. Each term registers itself in its own file with
/// `inventory::submit!` (re-exported here), so a new term is one file: selectable by name,
/// and estimated, flagged and recorded by the monitor ([`omission`]).
pub struct Registration {
    /// Name in scene files (`particles.forces`).
    pub name: &'static str,
    /// Build the term; refuse parameters it does not take ([`Parameters::only`]).
    pub build: fn(&Parameters) -> Result<Arc<dyn ForceTerm>, ParamError>,
    /// The size of the term when a particle leaves it out ([`Omission`]); `None`: not estimated.
    pub omitted: Option<Omission>,
}

inventory::collect!(Registration);

pub use inventory;

impl Entry for Registration {
    const KIND: &'static str = "force term";
    fn name(&self) -> &'static str {
        self.name
    }
}

/// The registered names, sorted.
pub fn names() -> Vec<&'static str> {
    registry::names::<Registration>()
}

/// The registry: the term called `name` with parameters `values` (SI units).
pub fn by_name(name: &str, values: &Values) -> Result<Arc<dyn ForceTerm>, ParamError> {
    let entry = registry::find::<Registration>(name)?;
    (entry.build)(&Parameters::new(entry.name, values))
}

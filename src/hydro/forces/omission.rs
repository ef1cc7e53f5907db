//! What the validity monitor estimates of a force term a particle leaves out.
//!
//! A term's [`Registration`] may carry an [`Omission`]: how large the term
//! would be, from the run's own numbers, on a particle that does not carry it, as the relative
//! change it would make to the slip, the drag or the response time. The validity monitor
//! ([`crate::diagnostics`]) iterates the registry, keeps the largest size over a run and flags it
//! (`omits_<term>`) above [`crate::diagnostics::Thresholds::omitted_term`], so a term estimated in
//! its own file is estimated, flagged and recorded with no code elsewhere. Each estimate's
//! physics is documented beside it, in the term's file.

use super::{ForceTerms, Registration};
use crate::flow::FlowSample;
use crate::tensor::Vec3;

/// How the validity monitor estimates a term that a particle leaves out (module docs).
#[derive(Debug, Clone, Copy)]
pub struct Omission {
    /// Where the term stands among the estimates, ascending (ties by name): the order of the
    /// monitor's flags and of its record's `omitted` table. The crate's terms stand at 10
    /// (undisturbed flow), 20 (added mass), 30 (finite-Re drag), 40 (shear lift) and 50 (gas
    /// slip), the order in which the monitor has always listed them, so that the flags of runs
    /// before and after a term is added compare as text.
    pub order: u16,
    /// An exclusive group ([`super::ForceTerm::exclusive_group`]) every term of which models
    /// the effect this estimate measures, so that a particle carrying any of them is not
    /// estimated: Schiller–Naumann's estimate of the finite-Re drag is not taken for a particle
    /// with Hölzer–Sommerfeld's correction ([`super::FINITE_RE_DRAG`]). `None`: only the term
    /// itself carries the effect.
    pub carried_by: Option<&'static str>,
    /// The estimate.
    pub size: Size,
}

/// An estimate of a term left out, and what it depends on.
#[derive(Debug, Clone, Copy)]
pub enum Size {
    /// Fixed by the particle and its fluid: taken when the monitor starts, and by a scene's
    /// advice before any run ([`crate::diagnostics::omitted_constants`]).
    Constant(fn(&Rest) -> f64),
    /// At one observed state; the monitor keeps the largest over the run.
    PerState(StateEstimate),
    /// At one observed state, as [`Size::PerState`], with a bound from the particle alone
    /// that a scene's advice gives before any run, when the flow it needs is not yet sampled
    /// ([`crate::diagnostics::omitted_before_run`]); the monitor takes `at` only.
    PerStateBounded {
        /// The estimate at one observed state.
        at: StateEstimate,
        /// The bound before any run.
        before_run: fn(&Rest) -> f64,
    },
}

impl Size {
    /// The estimate at one observed state, if the size has one.
    pub fn per_state(&self) -> Option<StateEstimate> {
        match *self {
            Size::Constant(_) => None,
            Size::PerState(at) | Size::PerStateBounded { at, .. } => Some(at),
        }
    }

    /// What is known of the size before any run: the constant, or the bound.
    pub fn before_run(&self) -> Option<fn(&Rest) -> f64> {
        match *self {
            Size::Constant(size) | Size::PerStateBounded { before_run: size, .. } => Some(size),
            Size::PerState(_) => None,
        }
    }
}

/// An estimate at one observed state ([`Size::PerState`]).
pub type StateEstimate = fn(&Rest, &Observed) -> f64;

/// The particle as an estimate sees it: the numbers fixed for a run, in the run's units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rest {
    /// Rest semi-axes.
    pub semi_axes: Vec3,
    /// Diameter of the rest volume-equivalent sphere, d_eq = 2 (r₁r₂r₃)^{1/3}.
    pub d_eq: f64,
    /// Fluid viscosity μ_f.
    pub mu_f: f64,
    /// Fluid density ρ_f.
    pub rho_f: f64,
    /// Kinematic viscosity ν = μ_f/ρ_f.
    pub nu: f64,
    /// Reference solid density ρ_p.
    pub rho_p: f64,
    /// Mass m.
    pub mass: f64,
    /// Rest volume vol(B₀).
    pub volume0: f64,
    /// Gravity g.
    pub gravity: Vec3,
}

/// One state the monitor observes, as an estimate sees it.
#[derive(Debug, Clone, Copy)]
pub struct Observed<'a> {
    /// det F: the current volume is vol(B₀) det F.
    pub det_f: f64,
    /// The undisturbed flow at the barycentre.
    pub flow: &'a FlowSample,
    /// Slip Reynolds number Re_s = |u − v| d_eq/ν.
    pub re_slip: f64,
}

impl Registration {
    /// Whether a particle with `terms` carries what this term's [`Omission`] estimates: the term
    /// itself, or a term of the omission's [`Omission::carried_by`] group.
    pub fn carried(&self, terms: &ForceTerms) -> bool {
        let group = self.omitted.and_then(|o| o.carried_by);
        terms
            .iter()
            .any(|t| t.name() == self.name || (group.is_some() && t.exclusive_group() == group))
    }
}

/// The registered terms that carry an [`Omission`], in its order (then by name).
pub fn estimated() -> Vec<(&'static Registration, Omission)> {
    let mut terms: Vec<_> = inventory::iter::<Registration>
        .into_iter()
        .filter_map(|r| r.omitted.map(|o| (r, o)))
        .collect();
    terms.sort_by_key(|(r, o)| (o.order, r.name));
    terms
}

//! Time integrators. One integrator owns one step and the per-particle step memory it keeps
//! between steps; the driver ([`crate::driver`]) owns the loop, events and output.
//!
//! Integrators discretise the model of [`crate::particle::dynamics`] and re-derive no physics.
//! Every step returns a [`Step`]: the new state, a [`StepInfo`] whose counts come from the
//! model wrapper that did the work, and a [`Dense`] interpolant over the step for event location
//! and output.
//!
//! # Physics (paper eqs. 17–22)
//! What is integrated is the barycentre equation ẋ_c = v_c, v̇_c = a_G + (1/τ_D) k·(u − v_c)
//! (eq. 17) and the shape equation Ḟ = A, Ȧ = vol(B₀)[P̃ − P]Θ⁻¹ (eq. 18), evaluated by
//! [`crate::particle::dynamics`]. [`imex`] is the paper's discretisation (eqs. 19–22, §5);
//! [`imex_adaptive`] the same step with error control; [`stokesian`] the inertialess limit
//! Θ → 0 of eq. 18, advanced by [`radau5`] or [`rosenbrock`]. The adaptive schemes share their
//! tolerances, step-controller limits and Jacobian-reuse rule through [`control`].
//!
//! Scene files and the Python package choose an integrator by name ([`registry`]): each
//! registers itself in its own file. [`choice`] picks one from the particle's numbers.

pub mod body_frame;
pub mod choice;
pub mod control;
pub mod dense;
pub mod imex;
pub mod imex_adaptive;
pub mod manifold;
pub mod newton;
pub mod radau5;
pub mod registry;
pub mod report;
pub mod rosenbrock;
pub mod stokesian;

pub use control::{ErrorNorm, JacobianReuse, StepControl, Tolerances};
pub use dense::Dense;
pub use imex::ImexPaper;
pub use imex_adaptive::ImexAdaptive;
pub use registry::{IntegratorRegistration, SceneIntegrator};
pub use report::IntegratorReport;
pub use stokesian::{BarycentreModel, Frame, Scheme, Stokesian};

use crate::error::StepError;
use crate::flow::FlowField;
use crate::hydro::DragModel;
use crate::material::Response;
use crate::particle::{Particle, State, Work};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};

/// Work and convergence record of one accepted step.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct StepInfo {
    /// Step size actually taken.
    pub dt: f64,
    /// Proposed size of the next step (equals `dt` for fixed-step schemes).
    pub dt_next: f64,
    /// Newton iterations (linear solves) in this step.
    pub newton_iters: u32,
    /// Final Newton residual (max-norm), 0 when the scheme has no Newton solve.
    pub residual: f64,
    /// Model evaluations (geometry: frame, integrals, traction coefficients), counted by
    /// [`crate::particle::Model`] where they were computed, rejected attempts included.
    pub rhs_evals: u32,
    /// Jacobians built, counted where they were built.
    pub jac_evals: u32,
    /// Rejected attempts before this step was accepted.
    pub rejected: u32,
}

impl StepInfo {
    /// A record carrying the counts of `work`.
    pub fn from_work(work: Work, dt: f64, dt_next: f64) -> Self {
        Self {
            dt,
            dt_next,
            rhs_evals: work.model_evals,
            jac_evals: work.jac_evals,
            ..Self::default()
        }
    }
}

/// One accepted step: the new state, its record, the interpolant over [t, t + dt] and what
/// the scheme evaluated at the new state.
#[derive(Debug, Clone)]
pub struct Step {
    /// State at t + dt.
    pub state: State,
    /// Work and convergence record.
    pub info: StepInfo,
    /// Dense output over the step.
    pub dense: Dense,
    /// The new state's principal frame and flow sample, where the scheme computed them there.
    pub end: EndEvaluation,
}

/// What a scheme computed exactly at a step's new state (x, F, t) and hands on, so that the
/// step's observers do not compute it again ([`crate::driver::AcceptedStep`]): the principal
/// frame of F (the geometry of the drag and traction at the end of the step) and the flow
/// sample u, ∇u at (x, t). `None` where the scheme evaluated elsewhere: the paper's IMEX step
/// samples the flow at (xⁿ, t^{n+1}), and the rigid limit of [`Stokesian`] projects F onto
/// SO(3) after its last evaluation. A value here is bitwise the one
/// [`crate::particle::Particle::frame`] and [`crate::flow::FlowField::sample`] give at the new
/// state.
#[derive(Debug, Clone, Copy, Default)]
pub struct EndEvaluation {
    /// The principal frame of the new F.
    pub frame: Option<crate::ellipsoid::PrincipalFrame>,
    /// The flow at the new barycentre and time.
    pub flow: Option<crate::flow::FlowSample>,
}

/// Check the inputs of a step: a valid state and a step Δt that is finite, > 0 and advances
/// t in floating point (t + Δt > t; a step below the spacing of t would silently not move).
pub fn check_step(state: &State, dt: f64) -> Result<(), StepError> {
    crate::error::positive("dt", dt)?;
    state.validate()?;
    if state.t + dt <= state.t {
        return Err(StepError::NoProgress { t: state.t, dt });
    }
    Ok(())
}

/// A one-step time integrator for a pseudo-rigid particle.
pub trait TimeIntegrator: Send + Sync {
    /// What the integrator keeps per particle between steps (cached model evaluations, the
    /// Jacobian and its evaluation point, controller history). The driver stores it beside the
    /// [`State`]; a checkpoint serialises it, so a resumed run continues bitwise identically.
    /// `Default` is the memory of a fresh start.
    type Memory: Default + Clone + Send + Serialize + DeserializeOwned + std::fmt::Debug;

    /// Short name of the scheme, as datasets and scene files spell it: `imex_paper`,
    /// `imex_adaptive`, `radau_iia`, `rosenbrock_w23`.
    fn name(&self) -> &'static str;

    /// How the scheme moves the barycentre: with its inertia (the default), or overdamped
    /// (its inertia dropped, as a scene's force advice needs to know).
    fn barycentre(&self) -> BarycentreModel {
        BarycentreModel::Inertial
    }

    /// Advance `state` by `dt` (adaptive schemes may take less; see [`StepInfo::dt`]),
    /// reading and updating the particle's step `memory`.
    fn step_with<M: Response, D: DragModel, F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        state: &State,
        memory: &mut Self::Memory,
        flow: &F,
        dt: f64,
    ) -> Result<Step, StepError>;

    /// What this integrator does for `particle` in `flow`, where that depends on them (the
    /// automatic choice, [`choice::Auto`]): a line for the run log. `None` for a fixed scheme.
    fn describe<M: Response, D: DragModel, F: FlowField + ?Sized>(
        &self,
        _particle: &Particle<M, D>,
        _flow: &F,
    ) -> Option<String> {
        None
    }

    /// What this integrator did for the particle whose step memory is `memory`, beyond the
    /// driver's counts ([`IntegratorReport`]: the slow-manifold switch's steps and switches,
    /// [`manifold`]). Empty by default: an integrator that keeps no account of its own.
    fn report(&self, _memory: &Self::Memory) -> IntegratorReport {
        IntegratorReport::default()
    }

    /// The driver has mapped the particle's state by a symmetry of the flow (a cyclic pair, a
    /// symmetry plane, a wedge: [`crate::flow::FlowField::image`]): drop from `memory` what
    /// it keeps of the flow that is not keyed by the whole state. The default keeps everything,
    /// right for memories whose caches are keyed by (t, y), which a mapped state misses.
    fn mapped(&self, _memory: &mut Self::Memory) {}

    /// One step from a fresh memory (a first step, or a test of a single step).
    fn step<M: Response, D: DragModel, F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        state: &State,
        flow: &F,
        dt: f64,
    ) -> Result<(State, StepInfo), StepError> {
        let mut memory = Self::Memory::default();
        self.step_with(particle, state, &mut memory, flow, dt)
            .map(|s| (s.state, s.info))
    }
}

/// One step for particles of one type, as the driver and the population runner take it. Every
/// [`TimeIntegrator`] is one for every particle type; an integrator chosen by name
/// ([`SceneIntegrator`]) is one for the particles of scene files.
pub trait Stepper<M: Response, D: DragModel>: Send + Sync {
    /// What is kept per particle between steps ([`TimeIntegrator::Memory`]).
    type Memory: Default + Send;

    /// Advance `state` by `dt` ([`TimeIntegrator::step_with`]).
    fn step_particle<F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        state: &State,
        memory: &mut Self::Memory,
        flow: &F,
        dt: f64,
    ) -> Result<Step, StepError>;

    /// What the integrator did for the particle with `memory` ([`TimeIntegrator::report`]).
    fn particle_report(&self, memory: &Self::Memory) -> IntegratorReport;

    /// The particle's state was mapped by a symmetry of the flow ([`TimeIntegrator::mapped`]).
    fn particle_mapped(&self, memory: &mut Self::Memory);
}

impl<I: TimeIntegrator, M: Response, D: DragModel> Stepper<M, D> for I {
    type Memory = I::Memory;

    fn step_particle<F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        state: &State,
        memory: &mut I::Memory,
        flow: &F,
        dt: f64,
    ) -> Result<Step, StepError> {
        self.step_with(particle, state, memory, flow, dt)
    }

    fn particle_report(&self, memory: &I::Memory) -> IntegratorReport {
        self.report(memory)
    }

    fn particle_mapped(&self, memory: &mut I::Memory) {
        self.mapped(memory);
    }
}

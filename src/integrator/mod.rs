//! Time integrators. One integrator owns one step; a driver ([`crate::driver`]) owns the loop.
//!
//! Every step returns a [`StepInfo`] so that work-precision studies count work (model and
//! Jacobian evaluations, Newton iterations), not only seconds.

pub mod imex;
pub mod imex_adaptive;
pub mod newton;
pub mod radau5;
pub mod rosenbrock;
pub mod stokesian;

pub use imex::ImexPaper;
pub use imex_adaptive::ImexAdaptive;
pub use rosenbrock::Tolerances;
pub use stokesian::{BarycentreModel, ShapeResponse, Stokesian};

use crate::error::StepError;
use crate::flow::FlowField;
use crate::hydro::DragModel;
use crate::material::Hyperelastic;
use crate::particle::{Particle, State};
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
    /// Evaluations of the hydrodynamic model (σ̃ with its frame and integrals).
    pub rhs_evals: u32,
    /// Jacobian evaluations.
    pub jac_evals: u32,
    /// Rejected attempts before this step was accepted.
    pub rejected: u32,
}

/// A one-step time integrator for a pseudo-rigid particle.
pub trait TimeIntegrator: Send + Sync {
    /// Short name used in datasets (e.g. `imex_paper`).
    fn name(&self) -> &'static str;

    /// Advance `state` by `dt` (adaptive schemes may take less; see [`StepInfo::dt`]).
    fn step<M: Hyperelastic, D: DragModel, F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        state: &State,
        flow: &F,
        dt: f64,
    ) -> Result<(State, StepInfo), StepError>;
}

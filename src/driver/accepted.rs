//! What the driver shows of an accepted step: the [`Step`] with its end state's principal frame
//! and flow sample, each computed at most once per step.
//!
//! Observers of a run read the end state's geometry and flow: the validity monitor needs r₁
//! (the frame) and u, ∇u at the barycentre ([`crate::diagnostics`]), a scene's watch the shape
//! averages or the slip u − v. The scheme has often evaluated both there already
//! ([`crate::integrator::EndEvaluation`]: Radau IIA and Rosenbrock-W evaluate the model at the
//! new state for the next step, the IMEX step the geometry of F^{n+1} for its drag).
//! [`AcceptedStep`] hands those on and computes what the scheme did not, on first demand, once
//! for every reader of the step, so that the frame is the one of
//! [`crate::particle::Particle::frame`] and the sample the one of
//! [`crate::flow::FlowField::sample`] at the end state, bitwise, whoever computed them.

use crate::ellipsoid::PrincipalFrame;
use crate::error::FlowError;
use crate::flow::{FlowField, FlowSample};
use crate::hydro::DragModel;
use crate::integrator::{Dense, Step, StepInfo};
use crate::material::Response;
use crate::particle::{Particle, State};
use std::cell::OnceCell;

/// The particle and flow in which a run's steps are taken: what [`AcceptedStep`] computes the
/// frame and the sample with, where the step did not carry them.
pub struct StepContext<'a, M, D, F: ?Sized> {
    particle: &'a Particle<M, D>,
    flow: &'a F,
}

impl<'a, M, D, F: ?Sized> StepContext<'a, M, D, F> {
    /// The steps of `particle` in `flow`.
    pub fn new(particle: &'a Particle<M, D>, flow: &'a F) -> Self {
        Self { particle, flow }
    }
}

/// A [`StepContext`] whatever its particle and flow: a watch ([`crate::population::Watch`]) is
/// an object, and so is what it is shown.
trait Evaluate {
    fn frame(&self, f: &crate::tensor::Mat3) -> PrincipalFrame;
    fn sample(&self, state: &State) -> Result<FlowSample, FlowError>;
}

impl<M: Response, D: DragModel, F: FlowField + ?Sized> Evaluate for StepContext<'_, M, D, F> {
    fn frame(&self, f: &crate::tensor::Mat3) -> PrincipalFrame {
        self.particle.frame(f)
    }

    fn sample(&self, state: &State) -> Result<FlowSample, FlowError> {
        self.flow.sample(&state.x, state.t)
    }
}

/// One accepted step as the driver shows it (module docs): the step, and the principal frame
/// and flow sample of its end state.
pub struct AcceptedStep<'a> {
    step: &'a Step,
    context: &'a dyn Evaluate,
    frame: OnceCell<PrincipalFrame>,
    flow: OnceCell<Result<FlowSample, FlowError>>,
}

impl<'a> AcceptedStep<'a> {
    /// `step`, taken in `context`, with what the step carries of its end state
    /// ([`Step::end`]).
    pub fn new<M: Response, D: DragModel, F: FlowField + ?Sized>(
        step: &'a Step,
        context: &'a StepContext<'a, M, D, F>,
    ) -> Self {
        Self {
            step,
            context,
            frame: step.end.frame.map_or_else(OnceCell::new, OnceCell::from),
            flow: step.end.flow.map_or_else(OnceCell::new, |s| OnceCell::from(Ok(s))),
        }
    }

    /// The step.
    pub fn step(&self) -> &Step {
        self.step
    }

    /// The state at its end.
    pub fn state(&self) -> &State {
        &self.step.state
    }

    /// Its work and convergence record.
    pub fn info(&self) -> &StepInfo {
        &self.step.info
    }

    /// Its dense output.
    pub fn dense(&self) -> &Dense {
        &self.step.dense
    }

    /// The principal frame of the end state's F (semi-axes r₁ ≥ r₂ ≥ r₃ and axes).
    pub fn frame(&self) -> &PrincipalFrame {
        self.frame.get_or_init(|| self.context.frame(&self.step.state.f))
    }

    /// The flow at the end state's barycentre and time, or why it cannot be sampled there.
    pub fn flow(&self) -> Result<&FlowSample, &FlowError> {
        self.flow.get_or_init(|| self.context.sample(&self.step.state)).as_ref()
    }
}

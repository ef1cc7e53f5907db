//! Integrators by name: each integrator registers a builder in its own file
//! ([`IntegratorRegistration`], with `inventory::submit!`), and scene files
//! (`[integrator] type = "radau_iia"`) and the Python package build it through [`by_name`].
//!
//! A [`TimeIntegrator`] is generic over the particle it steps, which a value chosen at run time
//! cannot be. What is chosen by name is therefore the integrator for the particles that scene
//! files build, [`SceneParticle`] (a law and a drag model chosen by name): [`SceneIntegrator`]
//! keeps the integrator behind a pointer and its step memory type-erased, and the driver and
//! the population runner take it as a [`Stepper`]. Library code keeps using the integrator
//! types themselves, monomorphised for its particle types.

use super::{BarycentreModel, IntegratorReport, Step, Stepper, TimeIntegrator};
use crate::error::{ParamError, StepError};
use crate::flow::FlowField;
use crate::hydro::drag::NamedDrag;
use crate::material::{NamedLaw, Softness};
use crate::particle::{Particle, State};
use crate::registry::{self, Entry, Parameters, Values};
use std::any::Any;
use std::fmt;
use std::sync::Arc;

pub use inventory;

/// The particle of scene files: a law (or rigid) and a drag model chosen by name.
pub type SceneParticle = Particle<Softness<NamedLaw>, NamedDrag>;

/// An integrator selectable by name: its name in scene files, earlier spellings, and how to
/// build it from its parameters (`[integrator]` without `type`, `dt` and `dt_max`, which the
/// driver's plan takes).
pub struct IntegratorRegistration {
    /// Name in scene files (`integrator.type`).
    pub name: &'static str,
    /// Other names it answers to (earlier scene files').
    pub aliases: &'static [&'static str],
    /// Build it; refuse parameters it does not take ([`Parameters::only`]).
    pub build: fn(&Parameters) -> Result<SceneIntegrator, ParamError>,
}

inventory::collect!(IntegratorRegistration);

impl Entry for IntegratorRegistration {
    const KIND: &'static str = "integrator";
    fn name(&self) -> &'static str {
        self.name
    }
    fn aliases(&self) -> &'static [&'static str] {
        self.aliases
    }
}

/// The registered integrators' names, sorted (aliases left out).
pub fn names() -> Vec<&'static str> {
    registry::names::<IntegratorRegistration>()
}

/// The registry: the integrator called `name` (or an alias) with parameters `values`.
pub fn by_name(name: &str, values: &Values) -> Result<SceneIntegrator, ParamError> {
    let entry = registry::find::<IntegratorRegistration>(name)?;
    (entry.build)(&Parameters::new(entry.name, values))
}

/// For a scheme whose barycentre is inertial only: `overdamped` may be written, but not true.
pub fn inertial_only(p: &Parameters) -> Result<(), ParamError> {
    match p.flag("overdamped")? {
        true => Err(ParamError::Unexpected {
            model: p.model(),
            key: "overdamped".to_string(),
            known: vec![],
        }),
        false => Ok(()),
    }
}

/// The step of an integrator on [`SceneParticle`]s with its memory type-erased: what the
/// vtable of a [`SceneIntegrator`] holds.
trait SceneStep: Send + Sync + fmt::Debug {
    fn scheme(&self) -> &'static str;
    fn barycentre_model(&self) -> BarycentreModel;
    fn describe_scene(&self, particle: &SceneParticle, flow: &dyn FlowField) -> Option<String>;
    fn step_scene(
        &self,
        particle: &SceneParticle,
        state: &State,
        memory: &mut SceneMemory,
        flow: &dyn FlowField,
        dt: f64,
    ) -> Result<Step, StepError>;
    fn report_scene(&self, memory: &SceneMemory) -> IntegratorReport;
    fn mapped_scene(&self, memory: &mut SceneMemory);
}

impl<I: TimeIntegrator + fmt::Debug + 'static> SceneStep for I {
    fn scheme(&self) -> &'static str {
        self.name()
    }
    fn barycentre_model(&self) -> BarycentreModel {
        self.barycentre()
    }
    fn describe_scene(&self, particle: &SceneParticle, flow: &dyn FlowField) -> Option<String> {
        self.describe(particle, flow)
    }
    fn step_scene(
        &self,
        particle: &SceneParticle,
        state: &State,
        memory: &mut SceneMemory,
        flow: &dyn FlowField,
        dt: f64,
    ) -> Result<Step, StepError> {
        // A fresh memory (or one another integrator left) starts as this integrator's default.
        let slot = memory.0.get_or_insert_with(|| Box::new(I::Memory::default()));
        if !slot.is::<I::Memory>() {
            *slot = Box::new(I::Memory::default());
        }
        match slot.downcast_mut::<I::Memory>() {
            Some(m) => self.step_with(particle, state, m, flow, dt),
            None => unreachable!("the slot holds I::Memory: set just above"),
        }
    }
    fn report_scene(&self, memory: &SceneMemory) -> IntegratorReport {
        // A fresh memory (or another integrator's) holds no step of this one.
        memory
            .0
            .as_ref()
            .and_then(|m| m.downcast_ref::<I::Memory>())
            .map_or_else(IntegratorReport::default, |m| self.report(m))
    }
    fn mapped_scene(&self, memory: &mut SceneMemory) {
        if let Some(m) = memory.0.as_mut().and_then(|m| m.downcast_mut::<I::Memory>()) {
            self.mapped(m);
        }
    }
}

/// The step memory of a [`SceneIntegrator`]: its integrator's memory, created at the first
/// step.
#[derive(Default)]
pub struct SceneMemory(Option<Box<dyn Any + Send>>);

impl fmt::Debug for SceneMemory {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(if self.0.is_some() {
            "SceneMemory(..)"
        } else {
            "SceneMemory(fresh)"
        })
    }
}

/// An integrator chosen by name, for [`SceneParticle`]s. Its `Debug` form is its
/// integrator's, so a run's configuration hash does not depend on how it was chosen.
#[derive(Clone)]
pub struct SceneIntegrator(Arc<dyn SceneStep>);

impl SceneIntegrator {
    /// `integrator`, for scene particles.
    pub fn new<I: TimeIntegrator + fmt::Debug + 'static>(integrator: I) -> Self {
        Self(Arc::new(integrator))
    }

    /// The scheme's name ([`TimeIntegrator::name`]).
    pub fn name(&self) -> &'static str {
        self.0.scheme()
    }

    /// Its barycentre model ([`TimeIntegrator::barycentre`]).
    pub fn barycentre(&self) -> BarycentreModel {
        self.0.barycentre_model()
    }

    /// What it does for `particle` in `flow` ([`TimeIntegrator::describe`]).
    pub fn describe(&self, particle: &SceneParticle, flow: &dyn FlowField) -> Option<String> {
        self.0.describe_scene(particle, flow)
    }
}

impl fmt::Debug for SceneIntegrator {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.fmt(f)
    }
}

impl Stepper<Softness<NamedLaw>, NamedDrag> for SceneIntegrator {
    type Memory = SceneMemory;

    fn step_particle<F: FlowField + ?Sized>(
        &self,
        particle: &SceneParticle,
        state: &State,
        memory: &mut SceneMemory,
        flow: &F,
        dt: f64,
    ) -> Result<Step, StepError> {
        self.0.step_scene(particle, state, memory, &flow, dt)
    }

    fn particle_report(&self, memory: &SceneMemory) -> IntegratorReport {
        self.0.report_scene(memory)
    }

    fn particle_mapped(&self, memory: &mut SceneMemory) {
        self.0.mapped_scene(memory);
    }
}

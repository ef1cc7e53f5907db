//! The models a scene file can name, each one type over the library's choices, so that one
//! scene mixes laws and picks its flow and boundary at run time. Laws and drag models are the
//! registries' types (any model registered by name); flows and boundaries stay enums here
//! because what builds them is not a table of parameters (module docs of [`crate::scene`]).

use crate::contact::MeshBoundary;
use crate::contact::{Approach, Boundary, Extent, Gap, PatchRule, PipeWall, Planes, Unbounded};
use crate::error::FlowError;
use crate::flow::analytic::{LinearFlow, Poiseuille, Quiescent};
use crate::flow::openfoam::{BlendedFlow, FoamError, FoamFlow, TransientFlow, window_ends};
use crate::flow::{Crossing, FlowField, FlowSample};
use crate::population::batch::Sliding;
use crate::tensor::Vec3;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError, RwLock};

/// A carrier flow named in a scene.
#[derive(Debug, Clone)]
pub enum SceneFlow {
    /// u = 0.
    Quiescent,
    /// Shear or extension.
    Linear(LinearFlow),
    /// Pipe flow.
    Poiseuille(Poiseuille),
    /// An OpenFOAM case.
    Foam(Box<FoamFlow>),
    /// An OpenFOAM case, blended into a continuous field.
    Blended(Box<BlendedFlow>),
    /// A transient OpenFOAM case, read window by window (a clone shares the field).
    Transient(Arc<SceneTransient>),
}

/// A transient OpenFOAM field as a scene holds it: the levels of one window
/// ([`TransientFlow`], blended or cellwise) and the length of the run's windows.
///
/// # Why a lock
/// The scene's injector samples the field (a particle released with the fluid's velocity) and
/// the batch runner slides it between windows, both through the scene, which a run borrows
/// shared ([`crate::scene::Scene::population`] takes `&self`). The field sits in a
/// [`RwLock`]: samples take it shared, [`Windows::slide`] exclusively, between windows, when
/// no sample is in flight. A shared lock costs a sample two atomic operations; on the
/// oscillating cavity the steps per second stayed within 5 % of the steady runner's. A run
/// holds [`SceneTransient::run`] throughout, so two runs of one scene (two Python threads)
/// take turns instead of sliding each other's windows.
#[derive(Debug)]
pub struct SceneTransient {
    field: RwLock<TransientField>,
    window: f64,
    fingerprint: String,
    run: Mutex<()>,
}

/// The levels of a transient field: blended (the default) or each cell's fit.
#[derive(Debug)]
pub enum TransientField {
    /// Blended into a continuous field with the wall layer.
    Blended(Box<TransientFlow<BlendedFlow>>),
    /// Each cell's linear fit.
    Cellwise(Box<TransientFlow<FoamFlow>>),
}

impl TransientField {
    /// The cellwise field of the held window.
    pub fn cellwise(&self) -> &FoamFlow {
        use crate::flow::openfoam::Windowed;
        match self {
            TransientField::Blended(f) => Windowed::cellwise(f.field()),
            TransientField::Cellwise(f) => f.field(),
        }
    }

    /// The case's times of the levels (one period's for a periodic field).
    pub fn levels(&self) -> &[f64] {
        match self {
            TransientField::Blended(f) => f.levels(),
            TransientField::Cellwise(f) => f.levels(),
        }
    }

    /// How the levels repeat.
    pub fn cycle(&self) -> crate::flow::openfoam::Cycle {
        match self {
            TransientField::Blended(f) => f.cycle(),
            TransientField::Cellwise(f) => f.cycle(),
        }
    }

    fn slide(&mut self, start: f64, end: f64) -> Result<(), FoamError> {
        match self {
            TransientField::Blended(f) => f.slide(start, end),
            TransientField::Cellwise(f) => f.slide(start, end),
        }
    }

    fn fingerprint(&self) -> &str {
        match self {
            TransientField::Blended(f) => f.fingerprint(),
            TransientField::Cellwise(f) => f.fingerprint(),
        }
    }
}

impl SceneTransient {
    /// `field` run in windows of `window` (> 0).
    pub fn new(field: TransientField, window: f64) -> Self {
        Self {
            fingerprint: format!("{}, windows of {window:e}", field.fingerprint()),
            field: RwLock::new(field),
            window,
            run: Mutex::new(()),
        }
    }

    /// The length of the run's windows.
    pub fn window(&self) -> f64 {
        self.window
    }

    /// The window ends of a run from 0 to `t_end` ([`window_ends`] of the window length).
    pub fn window_ends(&self, t_end: f64) -> Vec<f64> {
        window_ends(self.window, t_end)
    }

    /// `f` of the field as held now.
    pub fn with_field<R>(&self, f: impl FnOnce(&TransientField) -> R) -> R {
        f(&self.field.read().unwrap_or_else(PoisonError::into_inner))
    }

    /// Hold the window [start, end] (what a run's first window needs, before any particle is
    /// launched).
    pub fn slide(&self, start: f64, end: f64) -> Result<(), FoamError> {
        self.field
            .write()
            .unwrap_or_else(PoisonError::into_inner)
            .slide(start, end)
    }

    /// Exclusive use of the field for one run (type docs).
    pub fn run(&self) -> MutexGuard<'_, ()> {
        self.run.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// What identifies the field for a run's configuration hash: the levels' content
    /// ([`TransientFlow::fingerprint`]) and the window length.
    pub fn fingerprint(&self) -> &str {
        &self.fingerprint
    }
}

impl FlowField for SceneTransient {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        self.with_field(|f| match f {
            TransientField::Blended(f) => f.sample(x, t),
            TransientField::Cellwise(f) => f.sample(x, t),
        })
    }

    fn strain_rate(&self) -> Option<f64> {
        self.with_field(|f| match f {
            TransientField::Blended(f) => f.strain_rate(),
            TransientField::Cellwise(f) => f.strain_rate(),
        })
    }

    fn image(&self, x: &Vec3, t: f64) -> Option<Crossing> {
        self.with_field(|f| match f {
            TransientField::Blended(f) => f.image(x, t),
            TransientField::Cellwise(f) => f.image(x, t),
        })
    }
}

/// A scene's transient field as the batch runner slides it
/// ([`crate::population::batch::run_batch`]).
#[derive(Debug, Clone, Copy)]
pub struct Windows<'a>(pub &'a SceneTransient);

impl FlowField for Windows<'_> {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        self.0.sample(x, t)
    }

    fn strain_rate(&self) -> Option<f64> {
        self.0.strain_rate()
    }

    fn image(&self, x: &Vec3, t: f64) -> Option<Crossing> {
        self.0.image(x, t)
    }
}

impl Sliding for Windows<'_> {
    type Error = FoamError;

    fn slide(&mut self, start: f64, end: f64) -> Result<(), Self::Error> {
        self.0.slide(start, end)
    }
}

impl SceneFlow {
    /// What identifies the flow for a run's configuration hash: an analytic flow's parameters
    /// (every f64 exact in its `Debug` form), an OpenFOAM field's content
    /// ([`FoamFlow::fingerprint`]).
    pub fn fingerprint(&self) -> String {
        match self {
            SceneFlow::Quiescent => "quiescent".into(),
            SceneFlow::Linear(f) => format!("{f:?}"),
            SceneFlow::Poiseuille(f) => format!("{f:?}"),
            SceneFlow::Foam(f) => f.fingerprint(),
            SceneFlow::Blended(f) => f.fingerprint(),
            SceneFlow::Transient(f) => f.fingerprint().to_string(),
        }
    }

    /// `f` of the cellwise OpenFOAM field (a transient field's held window), `None` for an
    /// analytic flow.
    pub fn with_cellwise<R>(&self, f: impl FnOnce(Option<&FoamFlow>) -> R) -> R {
        match self {
            SceneFlow::Foam(c) => f(Some(c)),
            SceneFlow::Blended(b) => f(Some(b.cellwise())),
            SceneFlow::Transient(t) => t.with_field(|field| f(Some(field.cellwise()))),
            SceneFlow::Quiescent | SceneFlow::Linear(_) | SceneFlow::Poiseuille(_) => f(None),
        }
    }
}

impl crate::population::Identity for SceneFlow {
    /// [`SceneFlow::fingerprint`].
    fn identity(&self) -> String {
        self.fingerprint()
    }
}

impl SceneBoundary {
    /// What identifies the boundary for a run's configuration hash: walls' parameters in
    /// their `Debug` form, a mesh boundary's patches and mesh content
    /// ([`MeshBoundary::fingerprint`]).
    pub fn fingerprint(&self) -> String {
        match self {
            SceneBoundary::Open(_) => "open".into(),
            SceneBoundary::Pipe(b) => format!("{b:?}"),
            SceneBoundary::Planes(b) => format!("{b:?}"),
            SceneBoundary::Mesh(b) => b.fingerprint().to_string(),
        }
    }
}

impl crate::population::Identity for SceneBoundary {
    /// [`SceneBoundary::fingerprint`].
    fn identity(&self) -> String {
        self.fingerprint()
    }
}

impl FlowField for SceneFlow {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        match self {
            SceneFlow::Quiescent => Quiescent.sample(x, t),
            SceneFlow::Linear(f) => f.sample(x, t),
            SceneFlow::Poiseuille(f) => f.sample(x, t),
            SceneFlow::Foam(f) => f.sample(x, t),
            SceneFlow::Blended(f) => f.sample(x, t),
            SceneFlow::Transient(f) => f.sample(x, t),
        }
    }

    fn strain_rate(&self) -> Option<f64> {
        match self {
            SceneFlow::Quiescent => Quiescent.strain_rate(),
            SceneFlow::Linear(f) => f.strain_rate(),
            SceneFlow::Poiseuille(f) => f.strain_rate(),
            SceneFlow::Foam(f) => f.strain_rate(),
            SceneFlow::Blended(f) => f.strain_rate(),
            SceneFlow::Transient(f) => f.strain_rate(),
        }
    }

    fn image(&self, x: &Vec3, t: f64) -> Option<Crossing> {
        match self {
            SceneFlow::Quiescent | SceneFlow::Linear(_) | SceneFlow::Poiseuille(_) => None,
            SceneFlow::Foam(f) => f.image(x, t),
            SceneFlow::Blended(f) => f.image(x, t),
            SceneFlow::Transient(f) => f.image(x, t),
        }
    }
}

/// A boundary named in a scene, or none.
#[derive(Debug, Clone)]
pub enum SceneBoundary {
    /// Nothing to touch: every particle runs to the end time.
    Open(Unbounded),
    /// The pipe wall.
    Pipe(PipeWall),
    /// Planar walls.
    Planes(Planes),
    /// The patches of an OpenFOAM mesh.
    Mesh(Box<MeshBoundary>),
}

impl Boundary for SceneBoundary {
    fn nearest(&self, x: &Vec3, extent: &Extent) -> Gap {
        match self {
            SceneBoundary::Open(b) => b.nearest(x, extent),
            SceneBoundary::Pipe(b) => b.nearest(x, extent),
            SceneBoundary::Planes(b) => b.nearest(x, extent),
            SceneBoundary::Mesh(b) => b.nearest(x, extent),
        }
    }

    fn patch_name(&self, patch: usize) -> &str {
        match self {
            SceneBoundary::Open(b) => b.patch_name(patch),
            SceneBoundary::Pipe(b) => b.patch_name(patch),
            SceneBoundary::Planes(b) => b.patch_name(patch),
            SceneBoundary::Mesh(b) => b.patch_name(patch),
        }
    }

    fn rule(&self, patch: usize) -> PatchRule {
        match self {
            SceneBoundary::Open(b) => b.rule(patch),
            SceneBoundary::Pipe(b) => b.rule(patch),
            SceneBoundary::Planes(b) => b.rule(patch),
            SceneBoundary::Mesh(b) => b.rule(patch),
        }
    }

    fn approach(&self) -> Approach {
        match self {
            SceneBoundary::Open(b) => b.approach(),
            SceneBoundary::Pipe(b) => b.approach(),
            SceneBoundary::Planes(b) => b.approach(),
            SceneBoundary::Mesh(b) => b.approach(),
        }
    }

    fn clearance(&self, x: &Vec3) -> Option<f64> {
        match self {
            SceneBoundary::Open(b) => b.clearance(x),
            SceneBoundary::Pipe(b) => b.clearance(x),
            SceneBoundary::Planes(b) => b.clearance(x),
            SceneBoundary::Mesh(b) => b.clearance(x),
        }
    }
}

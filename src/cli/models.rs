//! The models a scene file can name, each one type over the library's choices, so that one
//! scene mixes laws and picks its flow and boundary at run time. Laws and drag models are the
//! registries' types (any model registered by name); flows and boundaries stay enums here
//! because what builds them is not a table of parameters (module docs of [`super::scene`]).

use crate::contact::MeshBoundary;
use crate::contact::{Approach, Boundary, Extent, Gap, PatchRule, PipeWall, Planes, Unbounded};
use crate::error::FlowError;
use crate::flow::analytic::{LinearFlow, Poiseuille, Quiescent};
use crate::flow::openfoam::{BlendedFlow, FoamFlow};
use crate::flow::{FlowField, FlowSample};
use crate::hydro::drag::NamedDrag;
use crate::material::NamedLaw;
use crate::tensor::Vec3;

/// The law a scene names: any registered law ([`crate::material::registry`]).
pub type SceneLaw = NamedLaw;

/// The drag model a scene names: any registered model ([`crate::hydro::drag::by_name`]).
pub type SceneDrag = NamedDrag;

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
        }
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

impl FlowField for SceneFlow {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        match self {
            SceneFlow::Quiescent => Quiescent.sample(x, t),
            SceneFlow::Linear(f) => f.sample(x, t),
            SceneFlow::Poiseuille(f) => f.sample(x, t),
            SceneFlow::Foam(f) => f.sample(x, t),
            SceneFlow::Blended(f) => f.sample(x, t),
        }
    }

    fn strain_rate(&self) -> Option<f64> {
        match self {
            SceneFlow::Quiescent => Quiescent.strain_rate(),
            SceneFlow::Linear(f) => f.strain_rate(),
            SceneFlow::Poiseuille(f) => f.strain_rate(),
            SceneFlow::Foam(f) => f.strain_rate(),
            SceneFlow::Blended(f) => f.strain_rate(),
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

//! The models a scene file can name, each one type over the library's choices, so that one
//! scene mixes laws and picks its flow and boundary at run time.

use crate::contact::MeshBoundary;
use crate::contact::{Approach, Boundary, Extent, Gap, PatchRule, PipeWall, Planes};
use crate::ellipsoid::{EllipsoidIntegrals, PrincipalFrame};
use crate::error::FlowError;
use crate::flow::analytic::{LinearFlow, Poiseuille, Quiescent};
use crate::flow::openfoam::{BlendedFlow, FoamFlow};
use crate::flow::{FlowField, FlowSample};
use crate::hydro::{Brenner, DragModel, StokesSphere};
use crate::material::{ExpressionLaw, Hyperelastic, MooneyRivlin, NeoHooke};
use crate::tensor::{Mat3, Mat9, Scalar, Vec3};
use serde::{Deserialize, Serialize};

/// A hyperelastic law named in a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum SceneLaw {
    /// Neo-Hooke (paper eq. 9).
    NeoHooke(NeoHooke),
    /// Mooney–Rivlin.
    MooneyRivlin(MooneyRivlin),
    /// A stored energy written in the scene.
    Expression(Box<ExpressionLaw>),
}

impl Hyperelastic for SceneLaw {
    fn energy<S: Scalar>(&self, f: &Mat3<S>) -> S {
        match self {
            SceneLaw::NeoHooke(l) => l.energy(f),
            SceneLaw::MooneyRivlin(l) => l.energy(f),
            SceneLaw::Expression(l) => l.energy(f),
        }
    }
    fn shear_modulus(&self) -> f64 {
        match self {
            SceneLaw::NeoHooke(l) => l.shear_modulus(),
            SceneLaw::MooneyRivlin(l) => l.shear_modulus(),
            SceneLaw::Expression(l) => l.shear_modulus(),
        }
    }
    fn lame_lambda(&self) -> f64 {
        match self {
            SceneLaw::NeoHooke(l) => l.lame_lambda(),
            SceneLaw::MooneyRivlin(l) => l.lame_lambda(),
            SceneLaw::Expression(l) => l.lame_lambda(),
        }
    }
    // The laws' own closed forms, where they have them, stay in use.
    fn piola(&self, f: &Mat3) -> Mat3 {
        match self {
            SceneLaw::NeoHooke(l) => l.piola(f),
            SceneLaw::MooneyRivlin(l) => l.piola(f),
            SceneLaw::Expression(l) => l.piola(f),
        }
    }
    fn tangent(&self, f: &Mat3) -> Mat9 {
        match self {
            SceneLaw::NeoHooke(l) => l.tangent(f),
            SceneLaw::MooneyRivlin(l) => l.tangent(f),
            SceneLaw::Expression(l) => l.tangent(f),
        }
    }
}

/// A drag model named in a scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SceneDrag {
    /// Brenner's ellipsoid resistance.
    Brenner,
    /// Stokes drag of the volume-equivalent sphere.
    StokesSphere,
}

impl DragModel for SceneDrag {
    fn resistance(&self, frame: &PrincipalFrame, ints: &EllipsoidIntegrals) -> Mat3 {
        match self {
            SceneDrag::Brenner => Brenner.resistance(frame, ints),
            SceneDrag::StokesSphere => StokesSphere.resistance(frame, ints),
        }
    }
}

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
            SceneBoundary::Open => "open".into(),
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
}

/// A boundary named in a scene, or none.
#[derive(Debug, Clone)]
pub enum SceneBoundary {
    /// Nothing to touch: every particle runs to the end time.
    Open,
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
            // An infinite gap never closes, and caps no step.
            SceneBoundary::Open => Gap {
                patch: 0,
                gap: f64::INFINITY,
                normal: Vec3::x(),
            },
            SceneBoundary::Pipe(b) => b.nearest(x, extent),
            SceneBoundary::Planes(b) => b.nearest(x, extent),
            SceneBoundary::Mesh(b) => b.nearest(x, extent),
        }
    }

    fn patch_name(&self, patch: usize) -> &str {
        match self {
            SceneBoundary::Open => "none",
            SceneBoundary::Pipe(b) => b.patch_name(patch),
            SceneBoundary::Planes(b) => b.patch_name(patch),
            SceneBoundary::Mesh(b) => b.patch_name(patch),
        }
    }

    fn rule(&self, patch: usize) -> PatchRule {
        match self {
            SceneBoundary::Open => PatchRule::Stick,
            SceneBoundary::Pipe(b) => b.rule(patch),
            SceneBoundary::Planes(b) => b.rule(patch),
            SceneBoundary::Mesh(b) => b.rule(patch),
        }
    }

    fn approach(&self) -> Approach {
        match self {
            SceneBoundary::Open => Approach::Normal,
            SceneBoundary::Pipe(b) => b.approach(),
            SceneBoundary::Planes(b) => b.approach(),
            SceneBoundary::Mesh(b) => b.approach(),
        }
    }
}

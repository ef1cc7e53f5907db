//! Soft and rigid ellipsoids deposited in a symmetric multi-generation airway tree (issue 24):
//! deposition efficiency generation by generation, the paper's conjecture (§6.4, §7) that the
//! softness effect of one bifurcation accumulates over many.
//!
//! # Set-up
//! A Weibel-type symmetric tree of generations 3 to 6 (`cases/airway-tree`): one G3 tube, two
//! G4, four G5, eight G6 tubes ending at the outlets; seven bifurcations of angle 60°.
//! Diameters and lengths are Weibel's model A (Weibel 1963) scaled by 6/5.6, so that the G3 tube
//! is the parent of the paper's bifurcation (D = 6 mm) and everything the bifurcation scene
//! fixes carries over: uniform inflow at Re = 500, air, particle density, the Stokes number
//! of eq. 25 with the G3 velocity and diameter, injection on a disc at the inlet, gravity
//! along e₁, deposition on contact of the particle's extent, ten mean residence times. The
//! flow is read and tracked by the bifurcation's [`Airway`]; this module adds the tree's
//! centrelines ([`tree`]), the generation classifier, an observer of the generations each
//! particle enters ([`observe`]), the per-generation study ([`study`]) and drug release at a
//! critical stretch, where and when soft particles first reach it ([`release`]); the comparison with
//! OpenFOAM's tracker on the same particles, generation by generation ([`peer`]). Every choice
//! the issue leaves open is in `cases/airway-tree/README.md`.
//!
//! # Deposition efficiency per generation
//! ```math
//! DE_g = \frac{n_{dep,g}}{n_{ent,g}}, \qquad \sigma_g = \sqrt{\frac{DE_g (1 - DE_g)}{n_{ent,g}}},
//! ```
//! with n_ent,g the particles that entered generation g ([`tree`]: crossed the inlet plane of
//! a G-g tube; all injected particles for g = 3) and n_dep,g those deposited in a G-g tube or in
//! the bifurcation zone at its end. Given n_ent,g, deposition in g is a Bernoulli trial per
//! particle, hence the binomial error.

pub mod observe;
pub mod peer;
pub mod release;
pub mod study;
pub mod tree;

pub use observe::{Generations, Reached};
pub use study::{GenerationCounts, by_generation, track};
pub use tree::{Location, Part, Tree, TreeError};

use crate::flow::openfoam::FoamError;
use crate::studies::bifurcation::{Airway, BifurcationError, Kind, StudyRun};
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Failures of a tree study.
#[derive(Debug, Error)]
pub enum AirwayTreeError {
    /// The bifurcation machinery (parameters, population runs, output) failed.
    #[error(transparent)]
    Bifurcation(#[from] BifurcationError),
    /// The OpenFOAM case could not be read.
    #[error(transparent)]
    Foam(#[from] FoamError),
    /// The tree description could not be read or used.
    #[error(transparent)]
    Tree(#[from] TreeError),
    /// A dataset or figure could not be written.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
    /// The case's patches do not match the tree's outlets.
    #[error("the case has patches {patches:?}, the tree's outlets are {outlets:?}")]
    Patches {
        /// The mesh's patch names.
        patches: Vec<String>,
        /// The tree's outlet names.
        outlets: Vec<String>,
    },
    /// Another tracker's fate of a particle is missing or cannot be placed in the tree.
    #[error("particle {index}: {reason}")]
    Peer {
        /// Particle index.
        index: u64,
        /// What is wrong.
        reason: String,
    },
    /// A run given to the tree's tracking goes through another airway than the tree's (build
    /// it with [`AirwayTree::study`]).
    #[error("the run is not through this tree's airway (build it with AirwayTree::study)")]
    OtherAirway,
    /// A finished particle's record holds no summary of the observer the study reads (a run
    /// without the [`Generations`] or the release observer, or with other thresholds).
    #[error(transparent)]
    Summary(#[from] crate::population::SummaryError),
}

/// The meshed tree: the flow, boundaries and tracking rule of an [`Airway`] and the tree's
/// centrelines.
#[derive(Debug, Clone)]
pub struct AirwayTree {
    airway: Airway,
    tree: Tree,
}

impl AirwayTree {
    /// The field shipped in `reference-data/airway-tree/<variant>` (made by
    /// `cases/airway-tree/Allrun` and `Allship`; the `rotated` tree is shipped).
    pub fn shipped_dir(variant: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("reference-data/airway-tree")
            .join(variant)
    }

    /// Read the case in `dir` (made by `cases/airway-tree/Allrun`): the flow of its last time
    /// directory and `centrelines.json`. Every outlet of the tree must be a patch of the mesh.
    pub fn open(dir: impl AsRef<Path>) -> Result<Self, AirwayTreeError> {
        let dir = dir.as_ref();
        let airway = Airway::open(dir)?;
        let tree = Tree::read(dir.join("centrelines.json"))?;
        let patches: Vec<String> = airway
            .flow()
            .cellwise()
            .mesh()
            .patches()
            .iter()
            .map(|p| p.name.clone())
            .collect();
        let outlets: Vec<String> = tree.tubes().iter().filter_map(|t| t.outlet.clone()).collect();
        if outlets.is_empty() || !outlets.iter().all(|o| patches.contains(o)) {
            return Err(AirwayTreeError::Patches { patches, outlets });
        }
        Ok(Self { airway, tree })
    }

    /// Flow, boundary and tracking time.
    pub fn airway(&self) -> &Airway {
        &self.airway
    }

    /// The centrelines and the classifier.
    pub fn tree(&self) -> &Tree {
        &self.tree
    }

    /// A run of `n` particles of `kind` through the tree's airway, to be set up further and
    /// tracked by [`study::track`] (the generations) or [`release::track`] (drug release).
    pub fn study(&self, kind: Kind, n: u64) -> StudyRun<'_, '_> {
        StudyRun::new(&self.airway, kind, n)
    }
}

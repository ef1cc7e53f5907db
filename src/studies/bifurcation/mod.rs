//! Soft and quasi-rigid ellipsoids deposited in a symmetric airway bifurcation (paper §6.4,
//! Figs 17–23).
//!
//! # Set-up (paper §6.4)
//! Weibel generation 3: parent and daughters of D = 6 mm, bifurcation angle 60°, total length
//! L = 0.04 m, carina at x₁/L ≈ 0.77, Re = 500 with a uniform inlet profile; the steady field
//! comes from `cases/bifurcation` (geometry, snappyHexMesh, simpleFoam). Particles are injected
//! uniformly on a disc of 5.5 mm at the inlet with the local fluid velocity, gravity acts along
//! the streamwise e₁, a particle deposits when its extent touches the wall, escapes through
//! the outlets, and is suspended if still inside after ten mean residence times.
//!
//! Readings where the paper is silent are listed in `cases/bifurcation/README.md` and at the
//! items they concern ([`setup`]).

pub mod breathing;
pub mod deposition;
pub mod error_norm;
pub mod figures;
pub mod injection;
pub mod setup;
pub mod study;
pub mod validity;

pub use injection::{Injection, Kind, Material};
pub use setup::{Airway, d_eq_for_stokes, stokes_number, zhang_reference};
pub use study::{Efficiency, StudyRun, efficiency_table};

use thiserror::Error;

/// Failures of a bifurcation study.
#[derive(Debug, Error)]
pub enum BifurcationError {
    /// Invalid parameters.
    #[error(transparent)]
    Param(#[from] crate::error::ParamError),
    /// A particle could not be drawn or stepped.
    #[error(transparent)]
    Step(#[from] crate::error::StepError),
    /// The OpenFOAM case could not be read.
    #[error(transparent)]
    Foam(#[from] crate::flow::openfoam::FoamError),
    /// The population run failed (a file, a checkpoint; not a particle).
    #[error(transparent)]
    Population(#[from] crate::population::PopulationError),
    /// A dataset or figure could not be written.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
    /// A ParaView file could not be assembled.
    #[error(transparent)]
    Vtk(#[from] crate::output::vtk::VtkError),
    /// The runs of a mesh study do not pair.
    #[error(transparent)]
    MeshStudy(#[from] crate::population::mesh_study::MeshStudyError),
}

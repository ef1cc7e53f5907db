//! Studies: complete numerical experiments assembled from particles, flows and integrators (a
//! *scene* is a scene file, `crate::cli`'s TOML).
//!
//! Shear-flow studies of paper §6.1 (units of [`crate::particle::ShearScaling`]: lengths d_eq,
//! times 1/γ̇, μ_f = 1, μ_s = 1/Ca; flow u = y e_x, vorticity −e_z):
//! - [`shear_shape`]: a [`particles::Shape`] placed in the shear axes (which body axis starts
//!   along the flow, the gradient and the vorticity);
//! - [`section`]: the ellipse cut by the shear plane (what the paper's figures show);
//! - [`shear_run`]: sampled runs (axes, material lines l_a, l_c) for Figs 4–6;
//! - [`shear_regimes`]: the tumbling/trembling (TU/TR) classifier with dense checking;
//! - [`phase_boundary`]: bisection in Ca for the TU/TR boundary, parallel over shapes (Figs 7, 8);
//! - [`phase_map`]: boundaries over families of shapes, with their dataset and figure;
//! - [`work_precision`]: error against work for every integrator, beside the SciPy peer
//!   ([`scipy_peer`], an independent NumPy/SciPy implementation of the inertialess model);
//! - [`tank_treading`]: steady tank-treading of an initially spherical particle, by time
//!   integration and by Roscoe's (1967) steady algebraic equations.
//!
//! Every study draws its shapes from one family type, [`particles::Shape`] (sphere, prolate,
//! oblate, triaxial), and its particle model from [`particles::ParticleModel`].
//!
//! Real flow fields:
//! - `bend` (features `cli`, `plot`): inertial deposition of spheres in a 90° bend at
//!   Re = 1000 against Pui et al. (1987) (`cases/bend`);
//! - `bifurcation` (features `mesh`, `parallel`): deposition of soft ellipsoids in an airway
//!   bifurcation (§6.4);
//! - `airway_tree` (features `mesh`, `parallel`): the same particles through a symmetric
//!   Weibel tree of generations 3 to 6, deposition efficiency per generation (issue 24);
//! - [`pipe`]: the Tian/Cui laminar pipe flow (§6.2): orientation and deposition of soft
//!   prolate particles;
//! - `cavity` (feature `mesh`): soft and quasi-rigid ellipsoids in the lid-driven cavity (§6.3);
//! - `cavity_benchmark` (feature `mesh`): the cavity flow field against Albensoeder & Kuhlmann
//!   (2005);
//! - `stagnation` (feature `mesh`): the exact Hiemenz stagnation flow written into meshed boxes
//!   (snappyHexMesh prism layers, `cases/stagnation`), the wall layer against it;
//! - `couette` (feature `mesh`): the exact Taylor–Couette flow written into snappyHexMesh
//!   annuli (`cases/taylor-couette`), the wall layer at a rotating curved wall;
//! - `peer` (feature `parallel`): OpenFOAM's own tracker on the same particles
//!   (`benches/peers/openfoam_tracker`), and the race of the two trackers' cost.

#[cfg(all(feature = "mesh", feature = "parallel"))]
pub mod airway_tree;
#[cfg(all(feature = "cli", feature = "plot"))]
pub mod bend;
#[cfg(feature = "parallel")]
pub mod bend_plug;
#[cfg(all(feature = "mesh", feature = "parallel"))]
pub mod bifurcation;
#[cfg(all(feature = "mesh", feature = "parallel"))]
pub mod cavity;
#[cfg(feature = "mesh")]
pub mod cavity_benchmark;
#[cfg(feature = "mesh")]
pub mod couette;
pub mod forces;
pub mod particles;
#[cfg(feature = "parallel")]
pub mod peer;
pub mod phase_boundary;
pub mod phase_map;
pub mod pich;
pub mod pipe;
pub mod scipy_peer;
pub mod section;
pub mod shear_regimes;
pub mod shear_run;
pub mod shear_shape;
#[cfg(feature = "mesh")]
pub mod stagnation;
pub mod tank_treading;
pub mod work_precision;

use crate::error::{ParamError, StepError};
use thiserror::Error;

/// The folder where the examples keep a study's finished runs (created if missing): the
/// environment variable `var`, else `target/<default>` in the crate.
#[cfg(all(feature = "mesh", feature = "parallel"))]
pub fn cache_folder(var: &str, default: &str) -> Result<std::path::PathBuf, crate::output::OutputError> {
    let dir = std::env::var_os(var).map_or_else(
        || {
            std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("target")
                .join(default)
        },
        std::path::PathBuf::from,
    );
    std::fs::create_dir_all(&dir).map_err(|source| crate::output::OutputError::Io {
        path: dir.clone(),
        source,
    })?;
    Ok(dir)
}

/// An example's `[N] [CASE_DIR]` command line: N from the first argument, else the environment
/// variable `var`, else `default`; the case folder from the second argument, if there is one.
pub fn count_and_case(var: &str, default: u64) -> Result<(u64, Option<std::path::PathBuf>), std::num::ParseIntError> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    count_and_case_of(&args, var, default)
}

/// [`count_and_case`] of the arguments `args` (the program's name left out).
pub fn count_and_case_of(
    args: &[String],
    var: &str,
    default: u64,
) -> Result<(u64, Option<std::path::PathBuf>), std::num::ParseIntError> {
    let n = match (args.first(), std::env::var(var)) {
        (Some(a), _) => a.parse()?,
        (None, Ok(v)) => v.parse()?,
        (None, Err(_)) => default,
    };
    Ok((n, args.get(1).map(Into::into)))
}

#[cfg(feature = "parallel")]
impl From<crate::population::PopulationError> for StudyError {
    fn from(e: crate::population::PopulationError) -> Self {
        StudyError::Population(e.to_string())
    }
}

/// Failures of a study.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum StudyError {
    /// A time step failed.
    #[error(transparent)]
    Step(#[from] StepError),
    /// Invalid parameters.
    #[error(transparent)]
    Param(#[from] ParamError),
    /// The SciPy peer of the work-precision study failed or is unavailable.
    #[error(transparent)]
    Peer(#[from] scipy_peer::ScipyPeerError),
    /// No Ca in the allowed range gives both regimes.
    #[error(
        "no TU/TR bracket in Ca ∈ [{ca_min}, {ca_max}]: {regime_at_min:?} at Ca = {ca_min}, {regime_at_max:?} at Ca = {ca_max}"
    )]
    NoBracket {
        /// Smallest Ca tried.
        ca_min: f64,
        /// Largest Ca tried.
        ca_max: f64,
        /// Regime at `ca_min`.
        regime_at_min: shear_regimes::Regime,
        /// Regime at `ca_max`.
        regime_at_max: shear_regimes::Regime,
    },
    /// The steady tank-treading equations were not solved.
    #[error("steady tank-treading solve failed at Ca = {ca}: {iters} Newton iterations, residual {residual:.3e}")]
    SteadyNotConverged {
        /// Capillary number.
        ca: f64,
        /// Iterations performed.
        iters: u32,
        /// Final residual (max-norm).
        residual: f64,
    },
    /// An orbit average needs at least one whole orbit in its window.
    #[error("orbit average over {t_average} time units saw {crossings} orbit crossings (need ≥ 2)")]
    TooFewOrbits {
        /// Downward crossings of ξ_a·e₁ seen.
        crossings: usize,
        /// Length of the averaging window.
        t_average: f64,
    },
    /// A study's population run failed (its checkpoint files, or a record the study cannot
    /// read), as displayed.
    #[error("population run: {0}")]
    Population(String),
    /// A particle's record holds no summary of the study's observer.
    #[cfg(feature = "parallel")]
    #[error(transparent)]
    Summary(#[from] crate::population::SummaryError),
    /// A particle of a study failed; the error as the population runner recorded it.
    #[error("particle failed: {error}")]
    ParticleFailed {
        /// The error, as displayed.
        error: String,
    },
    /// The released particle already overlaps the wall.
    #[error("particle released touching the wall: gap {gap:.3e}")]
    ReleasedInWall {
        /// Wall gap at release (≤ 0).
        gap: f64,
    },
    /// The particle did not reach the wall within the allowed time.
    #[error("particle not deposited by t = {t_max}: wall gap still {gap:.3e}")]
    NotDeposited {
        /// Time limit.
        t_max: f64,
        /// Wall gap at t_max.
        gap: f64,
    },
    /// The contact time was not located to the gap tolerance.
    #[error("wall contact not located: gap {gap:.3e} at t = {t}")]
    ContactNotLocated {
        /// Time of the best contact estimate.
        t: f64,
        /// Its gap.
        gap: f64,
    },
}

/// A failed run inside a study is reported by its cause: a study's results carry their own
/// statistics.
impl From<crate::driver::RunFailure> for StudyError {
    fn from(failure: crate::driver::RunFailure) -> Self {
        Self::Step(failure.error)
    }
}

//! Populations of independent particles: a deterministic runner with progress, checkpoints
//! and sharding (paper §6.4: "a statistically relevant number of soft particles in complex
//! flow situations").
//!
//! # Shape of the API
//! ```text
//! impl Injector for MyInjection {                      // spec.rs: how particle k is drawn
//!     type Law = NeoHooke; type Drag = Brenner;
//!     fn draw(&self, k, rng: &mut ParticleRng) -> Result<ParticleSpec<Law>, StepError>;
//!     fn particle(&self, spec) -> Result<Particle<Softness<Law>, Drag>, ParamError>;  // ParticleTemplate::build
//! }
//! let boundary = contact::Composite::new(outlet_planes, walls);          // or a MeshBoundary
//! let case = Case::new(&integrator, &flow, &boundary, &injector, plan);   // case.rs
//! let config = Fingerprint::new("my study").particles(&kind).flow(&flow).config(seed, n);
//! let shard = Shard::from_env()?.unwrap_or(Shard::ALL);                   // or "k/N".parse()
//! let options = RunOptions::default().resume(true);                      // runner.rs
//! let result = run_in_dir(&case, &config, shard, &out, &options)?;       // the checkpoint only
//! let whole = RunOutput::<NeoHooke>::merge_dir(&out)?;                   // == the unsharded run
//! // or by hand: run(&case, &config, shard, &options.with_checkpoints(dir, interval)),
//! // RunOutput::{read_checkpoint, table, merge, write_json, read_json}, checkpoint_dir
//! ```
//! - [`spec`]: [`ParticleSpec`] (shape and orientation, softness, injection point and
//!   velocity), the [`Injector`] trait, [`ParticleTemplate`], per-particle generators
//!   [`particle_rng`];
//! - [`sampling`]: uniform points on a disc, uniform rotations;
//! - [`case`]: [`Case`] (integrator, flow, boundary, injector, plan, contact model),
//!   [`Case::run_particle`], [`RunConfig`] and the configuration hash;
//! - [`fingerprint`]: [`Fingerprint`], the builder of a [`RunConfig`] from typed parts (the
//!   study's name, the particles' parameters, the [`Identity`] of the flow and the boundary);
//! - [`observe`]: an [`Observer`] of every particle's run, whose summary the record keeps
//!   (a scene's per-run columns);
//! - [`record`]: [`Fate`] (deposited, escaped, suspended, failed), [`ParticleRecord`];
//! - [`columns`]: the columns of a run's tables, defined once for `results.csv`,
//!   `records.parquet`, `frames.parquet` and the Python package;
//! - [`release`]: drug release at a critical deformation, a non-terminal event recorded by
//!   an observer (where and when each threshold is first crossed);
//! - [`runner`]: [`run`] with [`RunOptions`] (parallel or serial, progress, checkpoints);
//! - [`progress`], [`checkpoint`], [`shard`], [`output`]: progress reports, checkpoint files,
//!   shards `k/N`, result files, their standard paths and their merge;
//! - [`gci`]: Richardson extrapolation and the grid convergence index of a quantity on two
//!   or three meshes (Celik et al. 2008), the arithmetic of a mesh study;
//! - [`mesh_study`]: the same particles on two to four meshes, every outcome paired, with its
//!   sampling errors, GCI and verdict;
//! - [`adequacy`]: whether a run on an OpenFOAM field is decided by the wall layer: the
//!   first-cell ratios and the re-track on the field's other reconstruction;
//! - [`settling_pipe`]: a cheap population with a closed-form answer (tests, benches).
//!
//! # Determinism
//! Particle k draws from its own generator (stream k of the run seed) and shares nothing
//! with the others, so its record is a pure function of (case, seed, k): the same serially,
//! on any number of threads, in any shard, and after any number of kills and resumes
//! ([`checkpoint`] says why restarting a particle from its seed is exact). The tests compare
//! the JSON bytes. Two things would break this and are kept out: a wall-time budget in the
//! plan (a particle's fate would depend on the machine's load), and an [`Injector::draw`] that
//! reads anything but its arguments.

#[cfg(feature = "mesh")]
pub mod adequacy;
pub mod batch;
pub mod binomial;
pub mod case;
pub mod checkpoint;
pub mod columns;
pub mod fingerprint;
pub mod gci;
pub mod mesh_study;
pub mod observe;
pub mod output;
pub mod packed;
pub mod peer;
pub mod progress;
pub mod record;
pub mod release;
pub mod runner;
pub mod sampling;
pub mod seal;
pub mod settling_pipe;
pub mod shard;
pub mod spec;

pub use binomial::paired;
pub use case::{Case, CaseObserver, RunConfig};
pub use fingerprint::{Fingerprint, Identity};
pub use observe::{Observer, Watch};
pub use output::{Computed, RunOutput, checkpoint_dir};
pub use progress::Progress;
pub use record::{Fate, FateCounts, ParticleRecord, SummaryError};
pub use runner::{CHECKPOINT_INTERVAL, RunControl, RunOptions, run, run_in_dir};
pub use shard::Shard;
pub use spec::{Injector, ParticleRng, ParticleSpec, ParticleTemplate, particle_rng};

use std::path::PathBuf;
use thiserror::Error;

/// Version of the result and checkpoint files (2: chunks carry seed, size and patch names; 3:
/// kept states packed, [`packed`]).
pub const FORMAT: u32 = 3;

/// Failures of a population run, its files and their merge. (A particle that fails is not
/// one of these: it is recorded as [`Fate::Failed`].)
#[derive(Debug, Error)]
pub enum PopulationError {
    /// A shard index outside 0..count, or count 0.
    #[error("shard {index}/{count} does not exist (need 0 <= index < count)")]
    ShardOutOfRange {
        /// Index asked for.
        index: u64,
        /// Number of shards.
        count: u64,
    },
    /// A shard given as text is not `k/N`.
    #[error("shard `{text}` is not of the form k/N (e.g. 3/16)")]
    BadShard {
        /// The text.
        text: String,
    },
    /// An environment variable that names a shard is not a number.
    #[error("environment variable {name}={value:?} is not a non-negative integer")]
    BadEnvironment {
        /// Variable.
        name: &'static str,
        /// Its value.
        value: String,
    },
    /// A checkpoint, shard or result file belongs to a different run.
    #[error("{} belongs to a different run: configuration hash {found}, this run has {expected}", path.as_ref().map_or("a shard output".to_string(), |p| p.display().to_string()))]
    ConfigMismatch {
        /// File concerned, if one.
        path: Option<PathBuf>,
        /// This run's hash.
        expected: String,
        /// The file's hash.
        found: String,
    },
    /// A checkpoint or shard output of a different sharding.
    #[error("{} holds shard {found}, expected shard {expected}", path.as_ref().map_or("a shard output".to_string(), |p| p.display().to_string()))]
    ShardMismatch {
        /// File concerned, if one.
        path: Option<PathBuf>,
        /// Expected shard.
        expected: Shard,
        /// The file's shard.
        found: Shard,
    },
    /// A checkpoint holds a particle that is not this shard's.
    #[error("{path} holds particle {index}, which is not in shard {shard}")]
    ForeignRecord {
        /// Chunk file.
        path: PathBuf,
        /// Particle index.
        index: u64,
        /// The run's shard.
        shard: Shard,
    },
    /// Two checkpoint chunks hold different records of one particle.
    #[error("{path} holds a record of particle {index} that differs from an earlier chunk's")]
    ConflictingRecords {
        /// The later chunk.
        path: PathBuf,
        /// Particle index.
        index: u64,
    },
    /// A new run would write into the checkpoint of an earlier one.
    #[error("{dir} already holds {chunks} checkpoint chunk(s); resume the run or remove them")]
    CheckpointExists {
        /// Checkpoint folder.
        dir: PathBuf,
        /// Chunk files found.
        chunks: usize,
    },
    /// A merge is missing shards.
    #[error("merge of {count} shards: shards {missing:?} are missing")]
    MissingShards {
        /// Number of shards.
        count: u64,
        /// The first missing shard indices (at most 16).
        missing: Vec<u64>,
    },
    /// A merge got one shard twice.
    #[error("merge: shard {shard} appears twice")]
    RepeatedShard {
        /// The shard.
        shard: Shard,
    },
    /// A shard output does not hold exactly its particles.
    #[error("shard {shard} holds {records} records, not exactly its {expected} particles in order")]
    IncompleteShard {
        /// The shard.
        shard: Shard,
        /// Records found.
        records: u64,
        /// Particles the shard owns.
        expected: u64,
    },
    /// Two shards name one patch index differently.
    #[error("shards disagree on a patch name: `{first}` vs `{second}`")]
    PatchMismatch {
        /// Name in one shard.
        first: String,
        /// Name in another.
        second: String,
    },
    /// A file of another format version.
    #[error("{path} has format {found}, this version reads {expected}")]
    Format {
        /// File.
        path: PathBuf,
        /// Its version.
        found: u32,
        /// The supported version.
        expected: u32,
    },
    /// A checkpoint chunk or result file whose content does not match its checksum: it was
    /// edited or corrupted after it was written ([`seal`]).
    #[error("{path} was changed after it was written: checksum {stored} stored, {computed} computed from its content")]
    Checksum {
        /// File.
        path: PathBuf,
        /// Checksum in the file.
        stored: String,
        /// Checksum of its content.
        computed: String,
    },
    /// A checkpoint chunk or result file without a checksum (written before checksums, or
    /// stripped of it).
    #[error("{path} has no checksum (written by a pseudorigid older than 0.1.0's checksummed files); rerun it")]
    Unsealed {
        /// File.
        path: PathBuf,
    },
    /// A checkpoint chunk or result file written by another version of the code.
    #[error("{path} was written by pseudorigid {found}, this is {expected}; its records may differ, rerun it")]
    Version {
        /// File.
        path: PathBuf,
        /// The version that wrote it.
        found: String,
        /// This version.
        expected: String,
    },
    /// Reading a file failed.
    #[error("cannot read {path}: {source}")]
    Io {
        /// File or folder.
        path: PathBuf,
        /// Underlying error.
        source: std::io::Error,
    },
    /// A file is not valid JSON of the expected shape.
    #[error("{}: {source}", path.as_ref().map_or("JSON".to_string(), |p| p.display().to_string()))]
    Json {
        /// File, if one.
        path: Option<PathBuf>,
        /// Underlying error.
        source: serde_json::Error,
    },
    /// The run was asked to stop ([`RunControl::stop`]) before all its particles were done;
    /// the finished ones are in the checkpoint, if there is one.
    #[error("interrupted after {done} of {total} particles (the finished ones are checkpointed; resume to continue)")]
    Interrupted {
        /// Particles finished.
        done: u64,
        /// Particles of the shard.
        total: u64,
    },
    /// The time windows of a batch run ([`batch`]) are not ascending and finite.
    #[error("time window [{start}, {end}]: {reason}")]
    Window {
        /// Window start.
        start: f64,
        /// Window end.
        end: f64,
        /// What is wrong.
        reason: String,
    },
    /// The flow of a batch run cannot hold a time window ([`batch::Sliding::slide`]).
    #[error("time window [{start}, {end}]: {source}")]
    Slide {
        /// Window start.
        start: f64,
        /// Window end.
        end: f64,
        /// The flow's own error ([`batch::Sliding::Error`]): for a transient OpenFOAM field a
        /// [`crate::flow::openfoam::FoamError`], which `source.downcast_ref` recovers.
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    /// Writing a file failed.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
}

impl PopulationError {
    /// [`PopulationError::Slide`]: the flow could not hold [start, end] because of `source`.
    pub fn slide(start: f64, end: f64, source: impl std::error::Error + Send + Sync + 'static) -> Self {
        Self::Slide {
            start,
            end,
            source: Box::new(source),
        }
    }
}

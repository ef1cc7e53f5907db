//! Failures while reading an OpenFOAM case or building a field from it (sampling failures are
//! [`FlowError`](crate::error::FlowError)s, except [`FoamError::Outside`] which carries the
//! nearest patch).

use thiserror::Error;

/// Why an OpenFOAM case could not be read, checked or queried.
#[derive(Debug, Error)]
pub enum FoamError {
    /// A file could not be opened or read.
    #[error("{path}: {source}")]
    Io {
        /// File concerned.
        path: String,
        /// Underlying I/O error.
        source: std::io::Error,
    },
    /// A file does not follow the OpenFOAM format.
    #[error("{path}:{line}: malformed file at byte {offset}: {reason}")]
    Malformed {
        /// File concerned.
        path: String,
        /// 1-based line of `offset`.
        line: usize,
        /// Byte offset (in the decompressed text) where parsing stopped.
        offset: usize,
        /// What was expected or found.
        reason: String,
    },
    /// A gzipped file inflates to more than what it should hold can take (a decompression
    /// bomb, or a file of the wrong case); inflation stopped at `limit + 1` bytes.
    #[error("{path} inflates to more than {limit} bytes, the most it can take: {basis}")]
    Inflated {
        /// The `.gz` file.
        path: String,
        /// Most inflated bytes accepted.
        limit: u64,
        /// Where the bound comes from, with its numbers.
        basis: String,
    },
    /// A required file is missing (neither plain nor `.gz`).
    #[error("{path} not found (also tried {path}.gz)")]
    Missing {
        /// File looked for.
        path: String,
    },
    /// The case is decomposed for a parallel run and has not been reconstructed.
    #[error(
        "{case} is decomposed into {processors} processor directories and has no {what}: run `reconstructPar` (and `reconstructParMesh` for a meshed-in-parallel case) first"
    )]
    Decomposed {
        /// Case directory.
        case: String,
        /// Number of `processor*` directories.
        processors: usize,
        /// What is missing from the undecomposed case.
        what: String,
    },
    /// A processor directory of a decomposed case lacks the addressing that places it in the
    /// global mesh (`decomposePar` writes it; a mesh made in parallel has none).
    #[error(
        "{path} not found: the decomposed case has no addressing back to the undecomposed mesh; run `reconstructParMesh` (then `reconstructPar` for the fields) first"
    )]
    NoProcAddressing {
        /// The addressing file looked for.
        path: String,
    },
    /// The processor directories of a decomposed case do not fit together.
    #[error("{path}: decomposed case: {reason}")]
    Decomposition {
        /// File or directory concerned.
        path: String,
        /// First inconsistency found.
        reason: String,
    },
    /// No time directory matches the requested time.
    #[error("{case}: no time directory for t = {time}; available: {available:?}")]
    NoSuchTime {
        /// Case directory.
        case: String,
        /// Requested time.
        time: f64,
        /// Time directories found.
        available: Vec<f64>,
    },
    /// The mesh files are individually well-formed but inconsistent with each other.
    #[error("inconsistent mesh: {reason}")]
    Mesh {
        /// First inconsistency found.
        reason: String,
    },
    /// A cell has zero or negative volume.
    #[error("cell {cell} has non-positive volume {volume:.3e}")]
    DegenerateCell {
        /// Cell index.
        cell: usize,
        /// Volume computed from its faces.
        volume: f64,
    },
    /// A field does not fit the mesh or a patch condition cannot be evaluated.
    #[error("{path}: {reason}")]
    Field {
        /// Field file.
        path: String,
        /// What is wrong.
        reason: String,
    },
    /// The least-squares stencil of a cell does not determine a gradient.
    #[error("cell {cell}: gradient stencil of {points} points is degenerate (smallest/largest eigenvalue {ratio:.3e})")]
    Stencil {
        /// Cell index.
        cell: usize,
        /// Stencil size.
        points: usize,
        /// Conditioning of the normal matrix.
        ratio: f64,
    },
    /// Time levels that cannot be cycled with the period asked for
    /// ([`super::transient`]: they must cover one period, and no more).
    #[error("time levels {first} to {last} cannot be cycled with period {period}: {reason}")]
    Period {
        /// The period asked for.
        period: f64,
        /// First level's time.
        first: f64,
        /// Last level's time.
        last: f64,
        /// What is wrong, with the spacing of the levels where it matters.
        reason: String,
    },
    /// A time window that cannot be held ([`super::TransientFlow::slide`]).
    #[error("cannot hold the time window [{start}, {end}]: {reason}")]
    Window {
        /// Window start.
        start: f64,
        /// Window end.
        end: f64,
        /// What is wrong.
        reason: String,
    },
    /// A patch a particle can cross whose type is not handled as a particle boundary
    /// ([`super::patch::check_particle_patches`]): a particle crossing it would be tracked
    /// outside the mesh.
    #[error(
        "patch `{patch}` ({faces} faces) has type `{kind}`, which is not supported as a particle boundary (supported: wall, patch, empty, processor, cyclic, cyclicAMI, symmetry, symmetryPlane, wedge){hint}"
    )]
    UnsupportedPatch {
        /// Patch name.
        patch: String,
        /// Its geometric type in `constant/polyMesh/boundary`.
        kind: String,
        /// Its number of faces.
        faces: usize,
        /// What to do instead, where there is something (empty otherwise).
        hint: &'static str,
    },
    /// Query point outside the mesh.
    #[error("point {x:?} is outside the mesh; nearest patch `{patch}` at distance {distance:.3e}")]
    Outside {
        /// Query point.
        x: [f64; 3],
        /// Name of the patch owning the nearest boundary face.
        patch: String,
        /// Distance from x to the centre of that face.
        distance: f64,
    },
}

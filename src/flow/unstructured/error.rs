//! Failures while reading or assembling a meshed flow field (sampling failures are
//! [`FlowError`](crate::error::FlowError)s).

use thiserror::Error;

/// Why a meshed flow field could not be loaded or built.
#[derive(Debug, Error)]
pub enum MeshError {
    /// The file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// File concerned.
        path: String,
        /// Underlying I/O error.
        source: std::io::Error,
    },
    /// The file does not follow the expected format.
    #[error("{path}: malformed {format} file at byte {offset}: {reason}")]
    Malformed {
        /// File concerned.
        path: String,
        /// Format being parsed (`legacy VTK`, `compact field`).
        format: &'static str,
        /// Byte offset where parsing stopped.
        offset: usize,
        /// What was expected.
        reason: String,
    },
    /// A cell is not a hexahedron (VTK type 12); only hexahedral meshes are supported.
    #[error("cell {cell} has VTK type {vtk_type}, only hexahedra (12) are supported")]
    UnsupportedCell {
        /// Cell index.
        cell: usize,
        /// VTK cell type found.
        vtk_type: i64,
    },
    /// A cell refers to a point that does not exist.
    #[error("cell {cell} refers to point {point} but the mesh has {n_points} points")]
    BadConnectivity {
        /// Cell index.
        cell: usize,
        /// Offending point index.
        point: i64,
        /// Number of points.
        n_points: usize,
    },
    /// A hexahedron is inverted or degenerate (non-positive Jacobian at its centre).
    #[error("cell {cell} is degenerate or inverted: det J = {det_j:.3e} at its centre")]
    DegenerateCell {
        /// Cell index.
        cell: usize,
        /// Jacobian determinant of the trilinear map at the cell centre.
        det_j: f64,
    },
    /// A face is shared by more than two cells.
    #[error("face of cell {cell} is shared by more than two cells")]
    NonManifoldFace {
        /// One of the cells on the face.
        cell: usize,
    },
    /// A required point-data array is missing or has the wrong shape.
    #[error("point array `{name}`: expected {expected} components × {n_points} points, got {found}")]
    MissingArray {
        /// Array name (`U`, `grad(U)`).
        name: String,
        /// Components expected per point.
        expected: usize,
        /// Number of points.
        n_points: usize,
        /// What was found (description).
        found: String,
    },
    /// A coordinate or field value is NaN or infinite.
    #[error("non-finite {what} at index {index}")]
    NonFinite {
        /// Which array.
        what: &'static str,
        /// Entry index.
        index: usize,
    },
    /// More cells than 32-bit indices can address.
    #[error("{cells} cells exceed the 32-bit index range")]
    TooManyCells {
        /// Number of cells.
        cells: usize,
    },
    /// The mesh is empty.
    #[error("the mesh has no cells")]
    Empty,
    /// The compact form needs an axis-aligned structured (rectilinear) grid.
    #[error("the mesh is not an axis-aligned structured grid: {reason}")]
    NotRectilinear {
        /// First violation found.
        reason: String,
    },
}

impl From<crate::output::OutputError> for MeshError {
    /// Writers of fields and reports go through [`crate::output::write_atomic`]; its I/O
    /// failures are this module's [`MeshError::Io`].
    fn from(e: crate::output::OutputError) -> Self {
        match e {
            crate::output::OutputError::Io { path, source } => MeshError::Io {
                path: path.display().to_string(),
                source,
            },
            other => MeshError::Io {
                path: String::new(),
                source: std::io::Error::other(other.to_string()),
            },
        }
    }
}

//! Output helpers shared by the examples: atomic file writes, CSV tables, SVG figures,
//! ParaView files and Parquet tables.
//!
//! Every file is written atomically (temporary file in the same folder, then `rename`), so a
//! reader never sees a half-written dataset and an interrupted run leaves the old one intact.

pub mod atomic;
pub mod csv;
#[cfg(feature = "parquet")]
pub mod parquet;
pub mod plot;
pub mod vtk;

pub use atomic::write_atomic;
pub use csv::Csv;
pub use plot::{Figure, Panel, Series, SeriesStyle};
pub use vtk::{PolyData, VtkError, write_pvd};

use std::path::PathBuf;
use thiserror::Error;

/// Failures while writing datasets or figures.
#[derive(Debug, Error)]
pub enum OutputError {
    /// The file system refused a write, rename or folder creation.
    #[error("cannot write {path}: {source}")]
    Io {
        /// File (or folder) concerned.
        path: PathBuf,
        /// Underlying error.
        source: std::io::Error,
    },
    /// A CSV row does not match the header.
    #[error("CSV row has {got} fields, header has {expected}")]
    Columns {
        /// Header length.
        expected: usize,
        /// Row length.
        got: usize,
    },
    /// The data cannot be written as a VTK file.
    #[error(transparent)]
    Vtk(#[from] VtkError),
    /// The plotting backend failed.
    #[cfg(feature = "plot")]
    #[error("plotting failed: {0}")]
    Plot(String),
    /// The Parquet writer failed.
    #[cfg(feature = "parquet")]
    #[error("Parquet: {0}")]
    Parquet(String),
}

/// `<crate root>/paper-figures/<figure>/<file>`: where the examples put their results.
pub fn paper_figure_path(figure: &str, file: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("paper-figures")
        .join(figure)
        .join(file)
}

//! Minimal CSV tables with a fixed header, written atomically.
//!
//! Numbers are written with Rust's shortest round-trip representation (`{:?}`: exponent
//! notation below 1e-4 and above 1e16), so a dataset reloads bit-for-bit; fields never
//! contain commas (family names are identifiers).

use super::{OutputError, write_atomic};
use std::path::Path;

/// A CSV table under construction.
#[derive(Debug, Clone, PartialEq)]
pub struct Csv {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Csv {
    /// Empty table with column names `header`.
    pub fn new(header: &[&str]) -> Self {
        Self {
            header: header.iter().map(|h| h.to_string()).collect(),
            rows: Vec::new(),
        }
    }

    /// Append a row of already formatted fields.
    pub fn push(&mut self, fields: Vec<String>) -> Result<(), OutputError> {
        if fields.len() != self.header.len() {
            return Err(OutputError::Columns {
                expected: self.header.len(),
                got: fields.len(),
            });
        }
        self.rows.push(fields);
        Ok(())
    }

    /// Append a row of numbers.
    pub fn push_numbers(&mut self, values: &[f64]) -> Result<(), OutputError> {
        self.push(values.iter().map(|v| format!("{v:?}")).collect())
    }

    /// Number of data rows.
    pub fn len(&self) -> usize {
        self.rows.len()
    }

    /// True when there are no data rows.
    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    /// The table as CSV text (header line first, `\n` line ends).
    pub fn to_text(&self) -> String {
        std::iter::once(&self.header)
            .chain(&self.rows)
            .map(|r| r.join(",") + "\n")
            .collect()
    }

    /// Write the table atomically to `path`.
    pub fn write(&self, path: impl AsRef<Path>) -> Result<(), OutputError> {
        write_atomic(path, self.to_text().as_bytes())
    }
}

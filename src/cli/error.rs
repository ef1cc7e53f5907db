//! Errors of the command: a bad scene names its file, line, column and key and says what was
//! expected; run, output and probe failures carry the library's typed errors.

use crate::flow::openfoam::FoamError;
use crate::output::OutputError;
use crate::population::PopulationError;
use std::ops::Range;
use std::path::PathBuf;
use thiserror::Error;

/// What went wrong in the command.
#[derive(Debug, Error)]
pub enum CliError {
    /// A file could not be read.
    #[error("cannot read {path}: {source}")]
    Read {
        /// File.
        path: PathBuf,
        /// Underlying error.
        source: std::io::Error,
    },
    /// The scene file is malformed or holds a bad value.
    #[error("{file}:{line}:{column}: `{key}`: {message}")]
    Scene {
        /// Scene file.
        file: String,
        /// Line (1-based).
        line: usize,
        /// Column (1-based, in characters).
        column: usize,
        /// Dotted key of the offending value (`particles.list[0].material.mu`), or the nearest
        /// key the parser could name.
        key: String,
        /// What is wrong and what was expected.
        message: String,
    },
    /// An OpenFOAM case could not be read.
    #[error(transparent)]
    Foam(#[from] FoamError),
    /// Running, checkpointing or merging the population failed.
    #[error(transparent)]
    Population(#[from] PopulationError),
    /// Writing a result failed.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// Bad command-line input (probe points, merge inputs).
    #[error("{0}")]
    Input(String),
}

/// A scene's text with its file name: turns byte spans into line and column.
#[derive(Debug, Clone, Copy)]
pub struct Source<'a> {
    /// File name as given.
    pub file: &'a str,
    /// Its text.
    pub text: &'a str,
}

impl Source<'_> {
    /// Line and column (1-based) of byte `offset`.
    pub fn line_column(&self, offset: usize) -> (usize, usize) {
        let offset = offset.min(self.text.len());
        // A span may point into a multi-byte character only if the parser is wrong; stay safe.
        let before = self.text.get(..offset).unwrap_or(self.text);
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        (line, column)
    }

    /// The error for `key` at `span`.
    pub fn error(&self, span: Range<usize>, key: impl Into<String>, message: impl Into<String>) -> CliError {
        let (line, column) = self.line_column(span.start);
        CliError::Scene {
            file: self.file.to_string(),
            line,
            column,
            key: key.into(),
            message: message.into(),
        }
    }

    /// A parse error of the TOML deserialiser. Its message names the key for unknown and
    /// missing fields; for a value of the wrong type it names only the type, so the key
    /// written just before the value's span is added.
    pub fn parse_error(&self, e: &toml::de::Error) -> CliError {
        let span = e.span().unwrap_or(0..0);
        let key = self
            .key_before(span.start)
            .or_else(|| self.line_key(span.start))
            .unwrap_or_default();
        self.error(span, key, e.message().trim().to_string())
    }

    /// The key of the `key = value` line holding `offset` (a span inside an inline table or
    /// an array points past the `=`).
    fn line_key(&self, offset: usize) -> Option<String> {
        let start = self.text.get(..offset)?.rfind('\n').map_or(0, |i| i + 1);
        let line = self.text[start..].lines().next()?;
        let (key, _) = line.split_once('=')?;
        let key = key.trim().trim_matches('"');
        let plain = !key.is_empty()
            && key
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.' | '"'));
        plain.then(|| key.to_string())
    }

    /// The key of `key = value` when `offset` is the start of the value.
    fn key_before(&self, offset: usize) -> Option<String> {
        let before = self.text.get(..offset)?.trim_end();
        let before = before.strip_suffix('=')?.trim_end();
        let start = before
            .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '"'))
            .map_or(0, |i| i + 1);
        let key = before[start..].trim_matches('"');
        (!key.is_empty()).then(|| key.to_string())
    }
}

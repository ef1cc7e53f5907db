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
pub enum SceneError {
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
    Invalid {
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
    pub fn error(&self, span: Range<usize>, key: impl Into<String>, message: impl Into<String>) -> SceneError {
        let (line, column) = self.line_column(span.start);
        SceneError::Invalid {
            file: self.file.to_string(),
            line,
            column,
            key: key.into(),
            message: message.into(),
        }
    }

    /// A parse error of the TOML deserialiser, named by the dotted key path of the span it
    /// points at ([`Source::key_path`]): the deserialiser's message names only the leaf of an
    /// unknown or missing field, the type of a wrong value, and nothing for a duplicate key or
    /// table (it was reported as ``` `` ```). A missing field's span is its table, so its
    /// leaf is appended (`end.t_end`, where the table's path `end` was named).
    pub fn parse_error(&self, e: &toml::de::Error) -> SceneError {
        let span = e.span().unwrap_or(0..0);
        let message = e.message().trim();
        let mut key = self.key_path(span.start);
        let missing = message
            .strip_prefix("missing field `")
            .and_then(|rest| rest.split_once('`'))
            .map(|(leaf, _)| leaf);
        if let Some(leaf) = missing {
            // A table's missing field spans the table's header; the document's own has an
            // empty span at 0, where the first line's key is no parent.
            key = if key.is_empty() || span.is_empty() {
                leaf.to_string()
            } else {
                format!("{key}.{leaf}")
            };
        }
        self.error(span.clone(), key, message.to_string())
    }

    /// The dotted key path at byte `offset` (`flow.blend`, `particles.list[0].material.mu`):
    /// the table of the last `[table]` or `[[array]]` header before it (an array of tables
    /// with its index, counted from its headers), then, on the offset's line, the key of its
    /// `key = value`, the keys of the inline tables `{ … }` the offset is in, and the key the
    /// offset points at or is the value of. On a header line it is the header's path. A line
    /// of a multi-line value is read as its own line (scene files write values on one line).
    pub fn key_path(&self, offset: usize) -> String {
        let offset = offset.min(self.text.len());
        let before = self.text.get(..offset).unwrap_or(self.text);
        let line_start = before.rfind('\n').map_or(0, |i| i + 1);
        let mut arrays: Vec<(String, usize)> = Vec::new();
        let mut table = String::new();
        let mut header = |line: &str| {
            let Some((segments, array)) = table_header(line) else {
                return false;
            };
            let name = segments.join(".");
            if array {
                match arrays.iter_mut().find(|(n, _)| *n == name) {
                    Some((_, count)) => *count += 1,
                    None => arrays.push((name, 1)),
                }
            }
            table.clear();
            for (i, segment) in segments.iter().enumerate() {
                if i > 0 {
                    table.push('.');
                }
                table.push_str(segment);
                let prefix = segments[..=i].join(".");
                if let Some((_, count)) = arrays.iter().find(|(n, _)| *n == prefix) {
                    table.push_str(&format!("[{}]", count - 1));
                }
            }
            true
        };
        for line in self.text[..line_start].lines() {
            header(line);
        }
        let line = self.text[line_start..].lines().next().unwrap_or("");
        if header(line) {
            return table;
        }
        let mut keys = inline_keys(&before[line_start..]);
        let rest = &self.text[offset..];
        let word: String = rest.chars().take_while(|&c| bare_key_char(c)).collect();
        if !word.is_empty() && rest[word.len()..].trim_start().starts_with('=') {
            // The offset points at a key (a duplicate, an unknown field): that key.
            keys.push(word);
        }
        std::iter::once(table)
            .chain(keys)
            .filter(|k| !k.is_empty())
            .collect::<Vec<_>>()
            .join(".")
    }
}

/// A character of a bare TOML key, or of a dotted one.
fn bare_key_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.')
}

/// The key segments of a `[table]` or `[[array]]` header line, and whether it is an array of
/// tables; `None` for any other line.
fn table_header(line: &str) -> Option<(Vec<String>, bool)> {
    let line = line.trim();
    let (inner, array) = match line.strip_prefix("[[") {
        Some(rest) => (rest.split_once("]]")?, true),
        None => (line.strip_prefix('[')?.split_once(']')?, false),
    };
    let (name, after) = inner;
    let after = after.trim();
    if !(after.is_empty() || after.starts_with('#')) {
        return None;
    }
    let segments: Vec<String> = name
        .split('.')
        .map(|s| s.trim().trim_matches('"').to_string())
        .collect();
    let valid = segments
        .iter()
        .all(|s| !s.is_empty() && s.chars().all(|c| bare_key_char(c) || c == ' '));
    valid.then_some((segments, array))
}

/// The keys open at the end of `line` (a line's text up to an offset): its `key =`, then the
/// key of each inline table `{ … }` still open, then the key whose value the end is in (an
/// array's elements have the key of the array). Strings are skipped.
fn inline_keys(line: &str) -> Vec<String> {
    enum Open {
        Table(Option<String>),
        Array,
    }
    let mut open: Vec<Open> = Vec::new();
    let mut current: Option<String> = None;
    let mut token = String::new();
    let mut in_token = false;
    let mut chars = line.chars();
    while let Some(c) = chars.next() {
        if bare_key_char(c) {
            if !in_token {
                token.clear();
                in_token = true;
            }
            token.push(c);
            continue;
        }
        in_token = false;
        match c {
            '"' | '\'' => {
                chars.by_ref().find(|&d| d == c);
                token.clear();
            }
            '=' => current = Some(std::mem::take(&mut token)),
            '{' => open.push(Open::Table(current.take())),
            '[' => open.push(Open::Array),
            '}' | ']' => {
                if let Some(Open::Table(key)) = open.pop() {
                    current = key;
                }
            }
            ',' if !matches!(open.last(), Some(Open::Array)) => current = None,
            '#' => break,
            _ => {}
        }
    }
    let mut keys: Vec<String> = open
        .into_iter()
        .filter_map(|o| match o {
            Open::Table(key) => key,
            Open::Array => None,
        })
        .collect();
    keys.extend(current);
    keys
}

//! Checksums of checkpoint chunks (a run's only files of records; resume and merge read them)
//! and of result caches ([`super::RunOutput::write_json`]).
//!
//! A file's JSON object ends with `"version"` (the code version that wrote it) and
//! `"checksum"`: 64-bit FNV-1a over a tag, the version and the canonical JSON of the rest of
//! the object, which holds the records, the configuration hash (code version, seed, size, scene
//! text, flow and boundary fingerprints, integrator, plan), the seed, size and shard. A reader parses the rest, serialises it again and compares:
//! f64 values round-trip exactly and the serialisation is deterministic, so any change of a
//! value (a digit of a coordinate, a fate, an index) changes the checksum, while the file's
//! own formatting does not matter. A file of another code version is refused with that
//! version, not resumed or merged into results that could differ. This detects accidental
//! edits and corruption; it is not a signature against deliberate forgery.

use super::PopulationError;
use serde::Deserialize;
use std::hash::Hasher;
use std::path::Path;

/// The code version written into, and required of, every sealed file: the crate version and
/// a hash of the crate's sources (`build.rs`), so a file written by other code of the same
/// version number is refused too.
pub const VERSION: &str = concat!(env!("CARGO_PKG_VERSION"), "+src.", env!("PSEUDORIGID_SOURCE_HASH"));

/// The checksum of `body` (a JSON object's text) written by code version `version`.
pub fn checksum(version: &str, body: &[u8]) -> String {
    let mut h = fnv::FnvHasher::default();
    for part in [b"pseudorigid seal v1".as_slice(), version.as_bytes(), body] {
        h.write(&(part.len() as u64).to_le_bytes());
        h.write(part);
    }
    format!("{:016x}", h.finish())
}

/// `body` (a JSON object's text) with `"version"` and `"checksum"` appended as its last
/// members.
pub(crate) fn seal(mut body: Vec<u8>) -> Vec<u8> {
    let sum = checksum(VERSION, &body);
    // serde_json writes an object as `{...}`; the seal goes before the closing brace.
    debug_assert_eq!(body.last(), Some(&b'}'));
    let _ = body.pop();
    if body.len() > 1 {
        body.push(b',');
    }
    body.extend_from_slice(format!("\"version\":\"{VERSION}\",\"checksum\":\"{sum}\"}}").as_bytes());
    body
}

#[derive(Deserialize)]
struct Seal {
    version: Option<String>,
    checksum: Option<String>,
}

/// Check the seal of the file `path` with text `text`, whose content re-serialises to
/// `body()`.
pub(crate) fn verify(
    path: &Path,
    text: &[u8],
    body: impl FnOnce() -> Result<Vec<u8>, PopulationError>,
) -> Result<(), PopulationError> {
    let seal: Seal = serde_json::from_slice(text).map_err(|source| PopulationError::Json {
        path: Some(path.to_path_buf()),
        source,
    })?;
    let (Some(version), Some(stored)) = (seal.version, seal.checksum) else {
        return Err(PopulationError::Unsealed {
            path: path.to_path_buf(),
        });
    };
    if version != VERSION {
        return Err(PopulationError::Version {
            path: path.to_path_buf(),
            found: version,
            expected: VERSION.to_string(),
        });
    }
    let computed = checksum(&version, &body()?);
    if computed != stored {
        return Err(PopulationError::Checksum {
            path: path.to_path_buf(),
            stored,
            computed,
        });
    }
    Ok(())
}

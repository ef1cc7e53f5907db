//! Another tracker's fates of the same particles, and the paired comparison of deposition.
//!
//! The peer's file is `index,fate,patch,t,x,y,z` (the `fates.csv` of
//! `benches/peers/openfoam_tracker/run.sh`: fate `deposited`, `escaped`, `suspended` or
//! `not_injected`). Pairing particle by particle: b = deposited by us only, c = by the peer
//! only; the paired (McNemar) standard error of DE_ours − DE_peer is √(b + c − (b − c)²/n)/n and
//! the statistic (b − c)²/(b + c) is χ²₁ under "both deposit with the same probability"
//! (McNemar 1947; [`Pairing`] and its [`crate::population::binomial::PairedFates`], the one
//! place these are counted and computed).

use crate::population::ParticleRecord;
pub use crate::population::binomial::Pairing;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// A peer file that cannot be read.
#[derive(Debug, Error)]
pub enum PeerError {
    /// The file could not be read.
    #[error("{path}: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A malformed header or line.
    #[error("{path}: {reason}")]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
}

/// A particle of ours the peer has no fate for ([`paired_with_peer`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
#[error("particle {index} is missing from the peer's fates")]
pub struct MissingFate {
    /// The particle's index.
    pub index: u64,
}

/// Our records paired with the peer's fates of the same particles, by index: the one place
/// our run is matched with a peer's particle by particle. An error for the first particle
/// of ours the peer has no fate for.
pub fn paired_with_peer<'a, M>(
    records: &'a [ParticleRecord<M>],
    peer: &'a HashMap<u64, PeerFate>,
) -> Result<Vec<(&'a ParticleRecord<M>, &'a PeerFate)>, MissingFate> {
    records
        .iter()
        .map(|r| peer.get(&r.index).map(|p| (r, p)).ok_or(MissingFate { index: r.index }))
        .collect()
}

/// One particle's fate in the peer: `fate`, the patch met (empty if none), time and point as
/// the peer wrote them.
#[derive(Debug, Clone, PartialEq)]
pub struct PeerFate {
    /// `deposited`, `escaped`, `suspended` or `not_injected`.
    pub fate: String,
    /// Patch name.
    pub patch: String,
    /// Time (as written).
    pub t: String,
    /// Point (as written).
    pub x: [String; 3],
}

/// Read a peer's `index,fate,patch,t,x,y,z` file, by particle index.
pub fn read_peer_fates(path: &Path) -> Result<HashMap<u64, PeerFate>, PeerError> {
    let text = std::fs::read_to_string(path).map_err(|source| PeerError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let bad = |reason: String| PeerError::Format {
        path: path.to_path_buf(),
        reason,
    };
    let mut lines = text.lines();
    if lines.next() != Some("index,fate,patch,t,x,y,z") {
        return Err(bad("unexpected header (want index,fate,patch,t,x,y,z)".into()));
    }
    let mut out = HashMap::new();
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        let [k, fate, patch, t, x, y, z] = f.as_slice() else {
            return Err(bad(format!("bad line {line}")));
        };
        let k: u64 = k.parse().map_err(|e| bad(format!("index `{k}`: {e}")))?;
        out.insert(
            k,
            PeerFate {
                fate: fate.to_string(),
                patch: patch.to_string(),
                t: t.to_string(),
                x: [x.to_string(), y.to_string(), z.to_string()],
            },
        );
    }
    Ok(out)
}

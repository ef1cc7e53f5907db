//! Checkpoints: finished particles, written in chunks as they finish.
//!
//! # Why restarting unfinished particles from their seed is exact
//! A checkpoint holds the records of finished particles only, in files
//! `chunk-<n>.json.gz` (gzipped JSON) of one folder, each written atomically
//! ([`crate::output::write_atomic`]): a chunk is on disk whole or not at all, and a chunk once
//! written is never rewritten, so a kill at any instant loses no finished record and leaves
//! no half-written one. A resumed run loads every chunk and runs the particles that have no
//! record, each from the start. A particle's record is a pure function of (case, seed, index)
//! ([`super::Case::run_particle`]), so rerunning an unfinished particle from its seed gives
//! bitwise the record the killed run would have produced, and the resumed run's results equal
//! an uninterrupted run's. What a kill costs is the work on the particles in flight: at most
//! one particle per thread plus the records not yet flushed (one checkpoint interval). Saving
//! mid-flight integrator states would bound the loss further but would make the record depend
//! on where the run was cut: the driver's step-size proposal and output schedule live in its
//! loop, not in the step memory.
//!
//! Each chunk is sealed with the code version and a checksum of its content ([`super::seal`]):
//! a resumed run refuses a chunk that was edited after it was written
//! ([`PopulationError::Checksum`]) or written by another version.

use super::record::ParticleRecord;
use super::shard::Shard;
use super::{FORMAT, PopulationError};
use crate::output::write_atomic;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One chunk file: the records and what a reader needs to make a shard's results of them
/// without the case (seed, size of the whole run, names of the patches its records touched).
#[derive(Serialize, Deserialize)]
struct Chunk<L> {
    format: u32,
    config_hash: String,
    seed: u64,
    particles: u64,
    shard: Shard,
    patches: Vec<String>,
    records: Vec<ParticleRecord<L>>,
}

/// The records of a checkpoint folder and the run they belong to.
pub(crate) struct Loaded<L> {
    /// Configuration hash, seed, size of the whole run and shard (of the chunks; `None`
    /// without chunks).
    pub(crate) run: Option<(String, u64, u64, Shard)>,
    /// Names of patches 0..=p, p the largest patch index of any record.
    pub(crate) patches: Vec<String>,
    /// The records by index.
    pub(crate) records: BTreeMap<u64, ParticleRecord<L>>,
    /// The chunk files, by ascending number.
    pub(crate) files: Vec<(u64, PathBuf)>,
}

/// Prefix and suffix of chunk file names (written gzipped; plain `.json` chunks are read too).
const PREFIX: &str = "chunk-";
const SUFFIX: &str = ".json.gz";
const PLAIN_SUFFIX: &str = ".json";

/// A checkpoint folder of one run's shard.
#[derive(Debug)]
pub(crate) struct Checkpoint {
    dir: PathBuf,
    config_hash: String,
    seed: u64,
    particles: u64,
    shard: Shard,
    next: u64,
}

impl Checkpoint {
    /// Open `dir` for the run with `config_hash` and `shard`: the finished records found there
    /// (by index) and the checkpoint to add chunks to. Chunks of another run or shard, or
    /// records of particles outside the shard, are errors; so is a non-empty checkpoint when
    /// `resume` is false (a new run would mix with an old one).
    pub(crate) fn open<L: Serialize + DeserializeOwned + PartialEq>(
        dir: &Path,
        config_hash: &str,
        config: (u64, u64),
        shard: Shard,
        resume: bool,
    ) -> Result<(Self, BTreeMap<u64, ParticleRecord<L>>), PopulationError> {
        let (seed, particles) = config;
        if !resume {
            let files = chunk_files(dir)?;
            if !files.is_empty() {
                return Err(PopulationError::CheckpointExists {
                    dir: dir.to_path_buf(),
                    chunks: files.len(),
                });
            }
        }
        let loaded = load::<L>(dir, Some((config_hash, seed, particles, shard)))?;
        let next = loaded.files.last().map_or(0, |(n, _)| n + 1);
        Ok((
            Self {
                dir: dir.to_path_buf(),
                config_hash: config_hash.to_string(),
                seed,
                particles,
                shard,
                next,
            },
            loaded.records,
        ))
    }

    /// Whether no chunk has been written to the folder (by this run or the one it resumes).
    pub(crate) fn is_empty(&self) -> bool {
        self.next == 0
    }

    /// Write `records` as the next chunk (atomically).
    /// `patches`: the names of patches 0..=p, p the largest patch index of `records`.
    pub(crate) fn write<L: Serialize>(
        &mut self,
        records: &[ParticleRecord<L>],
        patches: &[String],
    ) -> Result<(), PopulationError> {
        let head = Head {
            config_hash: &self.config_hash,
            seed: self.seed,
            particles: self.particles,
            shard: self.shard,
            patches,
        };
        let text = super::seal::seal(chunk_body(&head, records)?);
        let path = self.dir.join(format!("{PREFIX}{:08}{SUFFIX}", self.next));
        write_atomic(
            &path,
            &gzip(&text).map_err(|source| PopulationError::Io {
                path: path.clone(),
                source,
            })?,
        )?;
        self.next += 1;
        Ok(())
    }
}

/// What a chunk holds besides its records.
struct Head<'a> {
    config_hash: &'a str,
    seed: u64,
    particles: u64,
    shard: Shard,
    patches: &'a [String],
}

/// The JSON text of a chunk, without its seal.
fn chunk_body<L: Serialize>(head: &Head<'_>, records: &[ParticleRecord<L>]) -> Result<Vec<u8>, PopulationError> {
    #[derive(Serialize)]
    struct ChunkRef<'a, L> {
        format: u32,
        config_hash: &'a str,
        seed: u64,
        particles: u64,
        shard: Shard,
        patches: &'a [String],
        records: &'a [ParticleRecord<L>],
    }
    let chunk = ChunkRef {
        format: FORMAT,
        config_hash: head.config_hash,
        seed: head.seed,
        particles: head.particles,
        shard: head.shard,
        patches: head.patches,
        records,
    };
    serde_json::to_vec(&chunk).map_err(|source| PopulationError::Json { path: None, source })
}

/// Read every chunk in `dir` (an absent folder has none), checking each one's seal and that
/// all belong to one run and shard: `expected` (configuration hash, seed, particles of the
/// whole run, shard) if given, else
/// the first chunk's. Records of particles outside the shard, and two different records of
/// one particle, are errors.
pub(crate) fn load<L: DeserializeOwned + Serialize + PartialEq>(
    dir: &Path,
    expected: Option<(&str, u64, u64, Shard)>,
) -> Result<Loaded<L>, PopulationError> {
    let files = chunk_files(dir)?;
    let mut run: Option<(String, u64, u64, Shard)> = expected.map(|(h, seed, n, s)| (h.to_string(), seed, n, s));
    let mut patches: Vec<String> = Vec::new();
    let mut done = BTreeMap::new();
    for (_, path) in &files {
        let text = std::fs::read(path)
            .and_then(gunzip)
            .map_err(|source| PopulationError::Io {
                path: path.clone(),
                source,
            })?;
        let chunk: Chunk<L> = serde_json::from_slice(&text).map_err(|source| PopulationError::Json {
            path: Some(path.clone()),
            source,
        })?;
        if chunk.format != FORMAT {
            return Err(PopulationError::Format {
                path: path.clone(),
                found: chunk.format,
                expected: FORMAT,
            });
        }
        let (hash, seed, particles, shard) =
            run.get_or_insert_with(|| (chunk.config_hash.clone(), chunk.seed, chunk.particles, chunk.shard));
        if chunk.config_hash != *hash || chunk.seed != *seed || chunk.particles != *particles {
            return Err(PopulationError::ConfigMismatch {
                path: Some(path.clone()),
                expected: hash.clone(),
                found: chunk.config_hash,
            });
        }
        if chunk.shard != *shard {
            return Err(PopulationError::ShardMismatch {
                path: Some(path.clone()),
                expected: *shard,
                found: chunk.shard,
            });
        }
        for record in &chunk.records {
            if !(record.index < *particles && shard.owns(record.index)) {
                return Err(PopulationError::ForeignRecord {
                    path: path.clone(),
                    index: record.index,
                    shard: *shard,
                });
            }
            if let Some(old) = done.get(&record.index)
                && old != record
            {
                return Err(PopulationError::ConflictingRecords {
                    path: path.clone(),
                    index: record.index,
                });
            }
        }
        for (a, b) in patches.iter().zip(&chunk.patches) {
            if a != b {
                return Err(PopulationError::PatchMismatch {
                    first: a.clone(),
                    second: b.clone(),
                });
            }
        }
        // The checks above name what is wrong; the seal catches any other change of the
        // chunk's content.
        super::seal::verify(path, &text, || {
            let head = Head {
                config_hash: &chunk.config_hash,
                seed: chunk.seed,
                particles: chunk.particles,
                shard: chunk.shard,
                patches: &chunk.patches,
            };
            chunk_body(&head, &chunk.records)
        })?;
        if chunk.patches.len() > patches.len() {
            patches = chunk.patches;
        }
        done.extend(chunk.records.into_iter().map(|r| (r.index, r)));
    }
    Ok(Loaded {
        run,
        patches,
        records: done,
        files,
    })
}

/// `text` gzipped at the fastest level: the JSON of f64 states shrinks 2.4× (57 → 24 MB on 400
/// particles × 301 frames) for about 5 % of that run's CPU time; the header has no time stamp,
/// so the bytes are a function of the text.
fn gzip(text: &[u8]) -> std::io::Result<Vec<u8>> {
    use std::io::Write as _;
    let mut encoder = flate2::write::GzEncoder::new(Vec::with_capacity(text.len() / 2), flate2::Compression::fast());
    encoder.write_all(text)?;
    encoder.finish()
}

/// The text of a chunk file's bytes: gunzipped if they start with gzip's magic number, else as
/// they are (a plain `.json` chunk).
fn gunzip(bytes: Vec<u8>) -> std::io::Result<Vec<u8>> {
    use std::io::Read as _;
    if !bytes.starts_with(&[0x1f, 0x8b]) {
        return Ok(bytes);
    }
    let mut text = Vec::with_capacity(bytes.len() * 3);
    flate2::read::GzDecoder::new(bytes.as_slice()).read_to_end(&mut text)?;
    Ok(text)
}

/// The chunk files in `dir` (absent folder: none), by ascending number.
fn chunk_files(dir: &Path) -> Result<Vec<(u64, PathBuf)>, PopulationError> {
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(source) => {
            return Err(PopulationError::Io {
                path: dir.to_path_buf(),
                source,
            });
        }
    };
    let mut files = Vec::new();
    for entry in entries {
        let entry = entry.map_err(|source| PopulationError::Io {
            path: dir.to_path_buf(),
            source,
        })?;
        let name = entry.file_name();
        let number = name
            .to_str()
            .and_then(|n| n.strip_prefix(PREFIX))
            .and_then(|n| n.strip_suffix(SUFFIX).or_else(|| n.strip_suffix(PLAIN_SUFFIX)))
            .and_then(|n| n.parse::<u64>().ok());
        if let Some(n) = number {
            files.push((n, entry.path()));
        }
    }
    files.sort_unstable();
    Ok(files)
}

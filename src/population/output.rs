//! The results of a run or a shard: read from its checkpoint (the only file of records a run
//! writes), merged over shards, as a CSV table, or as one JSON file that round-trips every f64
//! exactly (a cache of results, as the bifurcation studies keep).

use super::columns::{Column, ColumnValues, Row, record_columns};
use super::record::{FateCounts, ParticleRecord};
use super::shard::Shard;
use super::{FORMAT, PopulationError};
use crate::integrator::IntegratorReport;
use crate::material::StressLaw;
use crate::output::{Csv, write_atomic};
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The results of a run (or of one shard of it), sorted by particle index.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunOutput<L> {
    /// File format version.
    pub format: u32,
    /// [`super::Case::config_hash`] of the run.
    pub config_hash: String,
    /// Run seed.
    pub seed: u64,
    /// Particles in the whole run (all shards).
    pub particles: u64,
    /// The shard these records are ([`Shard::ALL`] for a whole or merged run).
    pub shard: Shard,
    /// Names of patches 0..=p, p the largest patch index touched.
    pub patches: Vec<String>,
    /// One record per particle of the shard, by ascending index.
    pub records: Vec<ParticleRecord<L>>,
}

/// A run with the wall time its computation took ([`RunOutput::read_or_run`]).
#[derive(Debug, Clone)]
pub struct Computed<L> {
    /// The run.
    pub output: RunOutput<L>,
    /// Wall seconds of the computation: measured when the run was computed, wherever it was
    /// read from; `None` for a cached run whose clock file is missing or unreadable (written
    /// before clock files were kept).
    pub seconds: Option<f64>,
}

impl<L> Computed<L> {
    /// The file beside a cached run's `file` that keeps its computation's wall seconds
    /// (`<file>.seconds`: one decimal number).
    pub fn clock_file(file: &Path) -> PathBuf {
        let mut name = file.as_os_str().to_owned();
        name.push(".seconds");
        PathBuf::from(name)
    }

    /// The computation's wall time for a run log: `12.3 s`, or `time not kept` where unknown.
    pub fn time_label(&self) -> String {
        self.seconds
            .map_or_else(|| "time not kept".into(), |s| format!("{s:.1} s"))
    }

    /// The computation's wall seconds for a table cell: `12.3`, or empty where unknown.
    pub fn seconds_cell(&self) -> String {
        self.seconds.map(|s| format!("{s:.1}")).unwrap_or_default()
    }

    /// The seconds kept beside `file`, if readable and a finite non-negative number.
    fn read_clock(file: &Path) -> Option<f64> {
        let text = std::fs::read_to_string(Self::clock_file(file)).ok()?;
        text.trim().parse::<f64>().ok().filter(|s| s.is_finite() && *s >= 0.0)
    }
}

impl<L: Serialize + DeserializeOwned> RunOutput<L> {
    /// How many particles met each fate.
    pub fn counts(&self) -> FateCounts {
        FateCounts::of(&self.records)
    }

    /// The integrator reports of the records as one ([`IntegratorReport::combine`]): for the
    /// slow manifold the steps on and off it and the switches of every particle it stepped,
    /// the largest δ on it and δ_max; empty where no integrator kept an account.
    pub fn integrator(&self) -> IntegratorReport {
        self.records.iter().map(|r| r.integrator).collect()
    }

    /// The JSON text (compact; shortest round-trip f64, parsed back exactly with serde_json's
    /// `float_roundtrip`), sealed with the code version and a checksum ([`super::seal`]).
    pub fn to_json(&self) -> Result<Vec<u8>, PopulationError> {
        Ok(super::seal::seal(self.body()?))
    }

    /// The JSON text without the seal.
    fn body(&self) -> Result<Vec<u8>, PopulationError> {
        serde_json::to_vec(self).map_err(|source| PopulationError::Json { path: None, source })
    }

    /// Write the JSON file atomically.
    pub fn write_json(&self, path: impl AsRef<Path>) -> Result<(), PopulationError> {
        Ok(write_atomic(path, &self.to_json()?)?)
    }

    /// Read a JSON file written by [`RunOutput::write_json`], checking its seal (an edited
    /// file is [`PopulationError::Checksum`]).
    pub fn read_json(path: impl AsRef<Path>) -> Result<Self, PopulationError> {
        let path = path.as_ref();
        let text = std::fs::read(path).map_err(|source| PopulationError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let out: Self = serde_json::from_slice(&text).map_err(|source| PopulationError::Json {
            path: Some(path.to_path_buf()),
            source,
        })?;
        if out.format != FORMAT {
            return Err(PopulationError::Format {
                path: path.to_path_buf(),
                found: out.format,
                expected: FORMAT,
            });
        }
        super::seal::verify(path, &text, || out.body())?;
        Ok(out)
    }

    /// The run kept in `file` if there is one, else `run()`, then written to `file` (no file:
    /// just `run()`): the finished-run cache of the studies, keyed by a file name the caller
    /// derives from the configuration hash. A file written before checksums, or in another
    /// format, is rerun and replaced; an edited one is an error
    /// ([`PopulationError::Checksum`]).
    ///
    /// The wall time of the computation comes back with the run ([`Computed::seconds`]): when
    /// the run is computed here it is measured and kept beside the file
    /// ([`Computed::clock_file`]), so that a run read back reports the time it took to
    /// compute, not the time of the read. The run's own file stays a function of its
    /// configuration (byte for byte the same on every machine).
    pub fn read_or_run<E: From<PopulationError>>(
        file: Option<&Path>,
        run: impl FnOnce() -> Result<Self, E>,
    ) -> Result<Computed<L>, E> {
        if let Some(file) = file
            && file.is_file()
        {
            match Self::read_json(file) {
                Err(
                    PopulationError::Unsealed { .. } | PopulationError::Version { .. } | PopulationError::Format { .. },
                ) => {}
                read => {
                    return Ok(Computed {
                        output: read?,
                        seconds: Computed::<L>::read_clock(file),
                    });
                }
            }
        }
        let started = std::time::Instant::now();
        let output = run()?;
        let seconds = started.elapsed().as_secs_f64();
        if let Some(file) = file {
            output.write_json(file)?;
            write_atomic(Computed::<L>::clock_file(file), format!("{seconds}\n").as_bytes())
                .map_err(PopulationError::from)?;
        }
        Ok(Computed {
            output,
            seconds: Some(seconds),
        })
    }

    /// Merge the outputs of all shards 0/N … (N−1)/N of one run into the whole run: the same
    /// records, sorted by index, as an unsharded run writes. Refuses outputs of different runs,
    /// a missing or repeated shard, and a shard whose records are not exactly its particles.
    pub fn merge(parts: Vec<Self>) -> Result<Self, PopulationError> {
        let Some(first) = parts.first() else {
            return Err(PopulationError::MissingShards {
                count: 0,
                missing: vec![],
            });
        };
        let (hash, seed, particles, count) = (
            first.config_hash.clone(),
            first.seed,
            first.particles,
            first.shard.count(),
        );
        for p in &parts {
            if p.config_hash != hash || p.seed != seed || p.particles != particles {
                return Err(PopulationError::ConfigMismatch {
                    path: None,
                    expected: hash,
                    found: p.config_hash.clone(),
                });
            }
            if p.shard.count() != count {
                return Err(PopulationError::ShardMismatch {
                    path: None,
                    expected: first.shard,
                    found: p.shard,
                });
            }
        }
        let mut present: Vec<u64> = parts.iter().map(|p| p.shard.index()).collect();
        present.sort_unstable();
        if let Some(w) = present.windows(2).find(|w| w[0] == w[1]) {
            return Err(PopulationError::RepeatedShard {
                shard: Shard::new(w[0], count)?,
            });
        }
        if (present.len() as u64) < count {
            // Indices are distinct and < count, so a gap exists; list the first few.
            let mut missing = Vec::new();
            let mut next = 0;
            for &k in present.iter().chain(std::iter::once(&count)) {
                missing.extend((next..k).take(16 - missing.len()));
                next = k + 1;
                if missing.len() == 16 {
                    break;
                }
            }
            return Err(PopulationError::MissingShards { count, missing });
        }
        let mut patches: Vec<String> = Vec::new();
        for p in &parts {
            let expected = p.shard.indices(particles);
            let got = p.records.iter().map(|r| r.index);
            if p.records.len() as u64 != p.shard.len(particles) || !expected.eq(got) {
                return Err(PopulationError::IncompleteShard {
                    shard: p.shard,
                    records: p.records.len() as u64,
                    expected: p.shard.len(particles),
                });
            }
            for (a, b) in patches.iter().zip(&p.patches) {
                if a != b {
                    return Err(PopulationError::PatchMismatch {
                        first: a.clone(),
                        second: b.clone(),
                    });
                }
            }
            if p.patches.len() > patches.len() {
                patches = p.patches.clone();
            }
        }
        let mut records: Vec<ParticleRecord<L>> = parts.into_iter().flat_map(|p| p.records).collect();
        records.sort_by_key(|r| r.index);
        Ok(Self {
            format: FORMAT,
            config_hash: hash,
            seed,
            particles,
            shard: Shard::ALL,
            patches,
            records,
        })
    }

    /// The results of shard `shard` of the run in output folder `dir`, read from its
    /// checkpoint ([`checkpoint_dir`]): every chunk's seal checked, and the shard complete
    /// (every particle it owns has a record; else [`PopulationError::IncompleteShard`]).
    pub fn read_checkpoint(dir: impl AsRef<Path>, shard: Shard) -> Result<Self, PopulationError>
    where
        L: PartialEq,
    {
        Self::read_checkpoint_dir(checkpoint_dir(dir, shard))
    }

    /// [`RunOutput::read_checkpoint`] of the checkpoint folder `folder` (any name).
    pub fn read_checkpoint_dir(folder: impl AsRef<Path>) -> Result<Self, PopulationError>
    where
        L: PartialEq,
    {
        let folder = folder.as_ref();
        let loaded = super::checkpoint::load::<L>(folder, None)?;
        let Some((config_hash, seed, particles, shard)) = loaded.run else {
            return Err(PopulationError::Io {
                path: folder.to_path_buf(),
                source: std::io::Error::new(std::io::ErrorKind::NotFound, "no checkpoint chunks"),
            });
        };
        let expected = shard.len(particles);
        if loaded.records.len() as u64 != expected {
            return Err(PopulationError::IncompleteShard {
                shard,
                records: loaded.records.len() as u64,
                expected,
            });
        }
        Ok(Self {
            format: FORMAT,
            config_hash,
            seed,
            particles,
            shard,
            patches: loaded.patches,
            records: loaded.records.into_values().collect(),
        })
    }

    /// [`RunOutput::merge`] of every shard checkpoint ([`checkpoint_dir`]) in `dir`.
    pub fn merge_dir(dir: impl AsRef<Path>) -> Result<Self, PopulationError>
    where
        L: PartialEq,
    {
        let dir = dir.as_ref();
        let io = |source| PopulationError::Io {
            path: dir.to_path_buf(),
            source,
        };
        let mut paths = Vec::new();
        for entry in std::fs::read_dir(dir).map_err(io)? {
            let entry = entry.map_err(io)?;
            let name = entry.file_name();
            if name.to_str().and_then(parse_checkpoint_name).is_some() {
                paths.push(entry.path());
            }
        }
        paths.sort();
        Self::merge(paths.iter().map(Self::read_checkpoint_dir).collect::<Result<_, _>>()?)
    }
}

/// Where shard `shard` of a run in `dir` keeps its checkpoint: `dir/checkpoint-<k>-of-<N>`
/// (k, N zero-padded to 4 digits, so the folders sort by shard). A finished shard's checkpoint
/// holds all its records: it is the shard's result file.
pub fn checkpoint_dir(dir: impl AsRef<Path>, shard: Shard) -> PathBuf {
    dir.as_ref()
        .join(format!("checkpoint-{:04}-of-{:04}", shard.index(), shard.count()))
}

/// The shard of a [`checkpoint_dir`] folder name.
fn parse_checkpoint_name(name: &str) -> Option<(u64, u64)> {
    let (k, n) = name.strip_prefix("checkpoint-")?.split_once("-of-")?;
    Some((k.parse().ok()?, n.parse().ok()?))
}

impl<L: StressLaw + Serialize + DeserializeOwned> RunOutput<L> {
    /// One row per particle: the columns of [`record_columns`] that `results.csv` has
    /// ([`Column::csv`]). Numbers in their shortest round-trip form; empty fields where a
    /// quantity does not exist; in text, commas and line breaks replaced by spaces.
    pub fn table(&self) -> Result<Csv, PopulationError> {
        let columns: Vec<Column<L>> = record_columns().into_iter().filter(|c| c.csv).collect();
        let header: Vec<&str> = columns.iter().map(|c| c.name).collect();
        let mut csv = Csv::new(&header);
        for record in &self.records {
            let row = Row::new(record, &self.patches);
            csv.push(columns.iter().map(|c| field(&c.values, &row)).collect())?;
        }
        Ok(csv)
    }
}

/// The CSV field of a column's value in `row`.
fn field<L>(values: &ColumnValues<L>, row: &Row<'_, L>) -> String {
    match values {
        ColumnValues::Count(f) => f(row).to_string(),
        ColumnValues::Int(f) => f(row).map(|v| v.to_string()).unwrap_or_default(),
        ColumnValues::Real(f) => f(row).map(|v| format!("{v:?}")).unwrap_or_default(),
        ColumnValues::Text(f) => f(row).map(|v| v.replace([',', '\n', '\r'], " ")).unwrap_or_default(),
    }
}

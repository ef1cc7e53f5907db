//! Deterministic shards of a population.
//!
//! Shard k of N owns the particles with index i ≡ k (mod N). Round-robin rather than
//! contiguous blocks: when the cost or kind of a particle varies with its index (an injector
//! that sweeps a parameter over the index, or a disc filled in index order), every shard still
//! gets a representative mix, so shards take about equally long and each one is an unbiased
//! sample of the population. Merging sorts by index, so the layout does not show in the result.

use super::PopulationError;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// Shard `index` of `count` (0 ≤ index < count).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(try_from = "ShardRaw")]
pub struct Shard {
    index: u64,
    count: u64,
}

#[derive(Deserialize)]
struct ShardRaw {
    index: u64,
    count: u64,
}

impl TryFrom<ShardRaw> for Shard {
    type Error = PopulationError;
    fn try_from(raw: ShardRaw) -> Result<Self, PopulationError> {
        Shard::new(raw.index, raw.count)
    }
}

impl Shard {
    /// The whole population as one shard, 0/1.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Shard `index` of `count`; needs count ≥ 1 and index < count.
    pub fn new(index: u64, count: u64) -> Result<Self, PopulationError> {
        if count == 0 || index >= count {
            return Err(PopulationError::ShardOutOfRange { index, count });
        }
        Ok(Self { index, count })
    }

    /// The shard given by a Slurm job array, if the environment holds one:
    /// `SLURM_ARRAY_TASK_ID` − `SLURM_ARRAY_TASK_MIN` (0 when unset) of
    /// `SLURM_ARRAY_TASK_COUNT`. The array must be contiguous (`--array=0-(N-1)`, no step).
    pub fn from_env() -> Result<Option<Self>, PopulationError> {
        Self::from_vars(|name| std::env::var(name).ok())
    }

    /// [`Shard::from_env`] with the variables looked up by `var`.
    pub fn from_vars(var: impl Fn(&str) -> Option<String>) -> Result<Option<Self>, PopulationError> {
        let number = |name: &'static str| -> Result<Option<u64>, PopulationError> {
            var(name)
                .map(|text| {
                    text.trim()
                        .parse()
                        .map_err(|_| PopulationError::BadEnvironment { name, value: text })
                })
                .transpose()
        };
        let (Some(id), Some(count)) = (number("SLURM_ARRAY_TASK_ID")?, number("SLURM_ARRAY_TASK_COUNT")?) else {
            return Ok(None);
        };
        let min = number("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
        let index = id
            .checked_sub(min)
            .ok_or(PopulationError::ShardOutOfRange { index: id, count })?;
        Self::new(index, count).map(Some)
    }

    /// This shard's index k.
    pub fn index(&self) -> u64 {
        self.index
    }

    /// The number of shards N.
    pub fn count(&self) -> u64 {
        self.count
    }

    /// Whether particle `particle` belongs to this shard.
    pub fn owns(&self, particle: u64) -> bool {
        particle % self.count == self.index
    }

    /// The indices of this shard's particles among `particles`, ascending.
    pub fn indices(&self, particles: u64) -> impl Iterator<Item = u64> + use<> {
        let (index, count) = (self.index, self.count);
        (0..particles.saturating_sub(index).div_ceil(count)).map(move |j| index + j * count)
    }

    /// How many of `particles` this shard owns.
    pub fn len(&self, particles: u64) -> u64 {
        particles.saturating_sub(self.index).div_ceil(self.count)
    }

    /// Whether this shard owns none of `particles`.
    pub fn is_empty(&self, particles: u64) -> bool {
        self.len(particles) == 0
    }
}

impl Default for Shard {
    fn default() -> Self {
        Self::ALL
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// Parses `k/N`, as `--shard 3/16`.
impl FromStr for Shard {
    type Err = PopulationError;
    fn from_str(text: &str) -> Result<Self, PopulationError> {
        let bad = || PopulationError::BadShard { text: text.to_string() };
        let (k, n) = text.split_once('/').ok_or_else(bad)?;
        let k = k.trim().parse().map_err(|_| bad())?;
        let n = n.trim().parse().map_err(|_| bad())?;
        Self::new(k, n)
    }
}

//! The steady and inhaled runs of one particle kind, paired particle by particle: the
//! discordant deposits (McNemar's comparison, [`PairedFates`]) and the deposits by injection
//! time.

use super::{Inhaled, Waveform};
use crate::error::ParamError;
use crate::material::NeoHooke;
use crate::population::binomial::Pairing;
use crate::population::{Fate, RunOutput, paired};
use crate::studies::bifurcation::BifurcationError;
use crate::studies::bifurcation::injection::Kind;
use crate::studies::bifurcation::setup::Airway;

/// One particle kind run steady and inhaled: the same particles, with their injection times.
#[derive(Debug)]
pub struct BreathingPair {
    /// The particle kind.
    pub kind: Kind,
    /// The steady study's run ([`StudyRun`](crate::studies::bifurcation::StudyRun)).
    pub steady: RunOutput<NeoHooke>,
    /// The inhaled run ([`run_inhaled`](super::run_inhaled)).
    pub cyclic: RunOutput<NeoHooke>,
    /// Injection time of each particle of the inhaled run, by index.
    pub times: Vec<f64>,
}

impl BreathingPair {
    /// Pair `steady` and `cyclic` runs of `kind` (seed `seed`, the same particles) in `airway`
    /// inhaled as `waveform`; an error if their particles differ.
    pub fn new(
        airway: &Airway,
        kind: Kind,
        waveform: Waveform,
        seed: u64,
        steady: RunOutput<NeoHooke>,
        cyclic: RunOutput<NeoHooke>,
    ) -> Result<Self, BifurcationError> {
        let same = paired(&steady.records, &cyclic.records).is_ok_and(|mut pairs| pairs.all(|(a, b)| a.spec == b.spec));
        if !same {
            return Err(ParamError::OutOfRange {
                name: "paired runs (the steady and inhaled runs must hold the same particles)",
                value: cyclic.records.len() as f64,
                min: steady.records.len() as f64,
                max: steady.records.len() as f64,
            }
            .into());
        }
        let inhaled = Inhaled::new(airway, kind, waveform)?;
        let times = cyclic
            .records
            .iter()
            .map(|r| inhaled.injection_time(seed, r.index))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            kind,
            steady,
            cyclic,
            times,
        })
    }

    /// The pairs, the inhaled run first: b = deposited inhaled only, c = steady only;
    /// ΔDE = DE_cyclic − DE_steady is its [`crate::population::binomial::PairedFates::difference`].
    pub fn pairing(&self) -> Result<Pairing, ParamError> {
        Pairing::of_records(&self.cyclic.records, &self.steady.records)
    }
}

/// The particles of `pair` whose injection time lies in bin b of `bins` equal bins of the
/// inhalation [0, `duration`]: for each bin (t_start, t_end, particles, deposited inhaled,
/// deposited steady).
pub fn by_phase(pair: &BreathingPair, duration: f64, bins: usize) -> Vec<(f64, f64, u64, u64, u64)> {
    let mut rows: Vec<(f64, f64, u64, u64, u64)> = (0..bins)
        .map(|b| {
            let w = duration / bins as f64;
            (b as f64 * w, (b + 1) as f64 * w, 0, 0, 0)
        })
        .collect();
    for ((a, b), &t) in pair.steady.records.iter().zip(&pair.cyclic.records).zip(&pair.times) {
        if matches!(b.fate, Fate::Failed { .. }) || bins == 0 {
            continue;
        }
        let k = ((t / duration * bins as f64).floor().max(0.0) as usize).min(bins - 1);
        rows[k].2 += 1;
        rows[k].3 += u64::from(deposited(&b.fate));
        rows[k].4 += u64::from(deposited(&a.fate));
    }
    rows
}

fn deposited(f: &Fate) -> bool {
    matches!(f, Fate::Deposited { .. })
}

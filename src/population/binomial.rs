//! Fractions of a population and their binomial standard errors.
//!
//! Each of n particles has an outcome (deposition, release in a generation) independently with
//! probability p, so the count k is binomial and the fraction f = k/n estimates p with
//! standard error $\sqrt{f(1 − f)/n}$ (the normal approximation, good where nf and n(1 − f)
//! are more than a few; the studies report counts beside it).
//!
//! # Paired fates
//! Two runs (two trackers, two fields, steady and inhaled) of the same n particles pair each
//! particle's two outcomes. Only the discordant pairs carry the difference: with b the
//! particles only the first run deposits and c those only the second deposits, the cells of
//! the 2×2 table are multinomial with probabilities (p_both, p_b, p_c, p_neither), and the
//! paired difference of the two fractions and its variance are
//! ```math
//! \hat d = \frac{b - c}{n}, \qquad
//! \operatorname{Var}\hat d = \frac{p_b + p_c - (p_b - p_c)^2}{n}
//! ```
//! (the concordant pairs cancel). [`PairedFates`] estimates it with p_b = b/n, p_c = c/n, and
//! under "both runs deposit with the same probability" (p_b = p_c) with the null variance
//! (p_b + p_c)/n, whose statistic (b − c)/√(b + c) is McNemar's (McNemar 1947, Psychometrika
//! 12:153). Far tighter than two independent binomial errors when most particles meet the
//! same fate in both runs.

use crate::error::ParamError;
use crate::population::{Fate, ParticleRecord};

/// f = k/n, 0 if n = 0.
pub fn fraction(k: u64, n: u64) -> f64 {
    if n == 0 { 0.0 } else { k as f64 / n as f64 }
}

/// The binomial standard error $\sqrt{f(1 − f)/n}$ of f = k/n, 0 if n = 0.
pub fn stderr(k: u64, n: u64) -> f64 {
    if n == 0 {
        0.0
    } else {
        let f = fraction(k, n);
        (f * (1.0 - f) / n as f64).sqrt()
    }
}

/// The discordant pairs of two runs of the same n particles: b deposited by the first only,
/// c by the second only (module docs). Made by [`PairedFates::new`], which checks the counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PairedFates {
    b: u64,
    c: u64,
    n: u64,
}

impl PairedFates {
    /// b pairs deposited by the first run only and c by the second only, out of n pairs; an
    /// error unless n > 0 and b + c ≤ n.
    pub fn new(b: u64, c: u64, n: u64) -> Result<Self, ParamError> {
        if n == 0 {
            return Err(ParamError::NotPositive {
                name: "n (pairs)",
                value: 0.0,
            });
        }
        match b.checked_add(c) {
            Some(discordant) if discordant <= n => Ok(Self { b, c, n }),
            _ => Err(ParamError::OutOfRange {
                name: "b + c (discordant pairs)",
                value: b as f64 + c as f64,
                min: 0.0,
                max: n as f64,
            }),
        }
    }

    /// b: deposited by the first run only.
    pub fn first_only(&self) -> u64 {
        self.b
    }

    /// c: deposited by the second run only.
    pub fn second_only(&self) -> u64 {
        self.c
    }

    /// n: the pairs.
    pub fn pairs(&self) -> u64 {
        self.n
    }

    /// The paired difference of the deposited fractions, first − second:
    /// $\hat d = (b - c)/n$.
    pub fn difference(&self) -> f64 {
        (self.b as f64 - self.c as f64) / self.n as f64
    }

    /// The standard error of [`Self::difference`] (module docs):
    /// $\sqrt{b + c - (b - c)^2/n}/n$, the square root of the multinomial variance with
    /// the observed cell fractions (0 when every pair is discordant one way).
    pub fn stderr(&self) -> f64 {
        let (b, c, n) = (self.b as f64, self.c as f64, self.n as f64);
        (b + c - (b - c).powi(2) / n).max(0.0).sqrt() / n
    }

    /// The standard error of [`Self::difference`] under "both runs deposit with the same
    /// probability" (p_b = p_c, McNemar 1947): $\sqrt{b + c}/n$, never below
    /// [`Self::stderr`].
    pub fn stderr_under_null(&self) -> f64 {
        ((self.b + self.c) as f64).sqrt() / self.n as f64
    }

    /// McNemar's statistic $z = (b - c)/\sqrt{b + c}$, standard normal under the null for
    /// many discordant pairs (0 if b + c = 0).
    pub fn z(&self) -> f64 {
        let discordant = self.b + self.c;
        if discordant > 0 {
            (self.b as f64 - self.c as f64) / (discordant as f64).sqrt()
        } else {
            0.0
        }
    }

    /// McNemar's $\chi^2 = (b - c)^2/(b + c)$ = z², χ²₁ under the null, without continuity
    /// correction (McNemar 1947; 0 if b + c = 0).
    pub fn chi2(&self) -> f64 {
        let (b, c) = (self.b as f64, self.c as f64);
        if b + c > 0.0 { (b - c).powi(2) / (b + c) } else { 0.0 }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 30 of 120: f = 1/4 and √(3/16/120) = 0.0395…; none of none is 0 with error 0.
    #[test]
    fn fraction_and_error() {
        assert_eq!(fraction(30, 120), 0.25);
        assert!((stderr(30, 120) - (0.25f64 * 0.75 / 120.0).sqrt()).abs() < 1e-17);
        assert_eq!((fraction(0, 0), stderr(0, 0)), (0.0, 0.0));
        assert_eq!(stderr(120, 120), 0.0);
    }
}

/// The records of two runs of the same particles, paired by index: the one place two runs
/// are matched particle by particle (count them with [`Pairing`], or compare anything else of
/// each pair). An error unless both hold the same particles in the same order.
pub fn paired<'a, M>(
    first: &'a [ParticleRecord<M>],
    second: &'a [ParticleRecord<M>],
) -> Result<impl Iterator<Item = (&'a ParticleRecord<M>, &'a ParticleRecord<M>)>, ParamError> {
    if first.len() != second.len() {
        return Err(ParamError::OutOfRange {
            name: "records of the second run (the first run's count)",
            value: second.len() as f64,
            min: first.len() as f64,
            max: first.len() as f64,
        });
    }
    if let Some((a, b)) = first.iter().zip(second).find(|(a, b)| a.index != b.index) {
        return Err(ParamError::OutOfRange {
            name: "particle index of the second run (the first run's)",
            value: b.index as f64,
            min: a.index as f64,
            max: a.index as f64,
        });
    }
    Ok(first.iter().zip(second))
}

/// The 2×2 table of deposition in two runs of the same particles: the first run (`ours`) and
/// the second (`peer`: another tracker, field, model or mesh). The one place pairs are
/// counted: from booleans ([`Pairing::add`], or collected from `(first, second)` pairs) or
/// from two runs' records ([`Pairing::of_records`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct Pairing {
    /// Deposited by both.
    pub both: u64,
    /// Deposited by us only (b).
    pub only_ours: u64,
    /// Deposited by the peer only (c).
    pub only_peer: u64,
    /// Deposited by neither.
    pub neither: u64,
}

impl Pairing {
    /// The two runs' records of the same particles, paired by index: deposited
    /// ([`Fate::Deposited`]) in the first, in the second. An error unless both hold the same
    /// particles in the same order ([`paired`]).
    pub fn of_records<M>(first: &[ParticleRecord<M>], second: &[ParticleRecord<M>]) -> Result<Self, ParamError> {
        let deposited = |r: &ParticleRecord<M>| matches!(r.fate, Fate::Deposited { .. });
        Ok(paired(first, second)?
            .map(|(a, b)| (deposited(a), deposited(b)))
            .collect())
    }

    /// Add one particle: deposited by us, by the peer.
    pub fn add(&mut self, ours: bool, peer: bool) {
        match (ours, peer) {
            (true, true) => self.both += 1,
            (true, false) => self.only_ours += 1,
            (false, true) => self.only_peer += 1,
            (false, false) => self.neither += 1,
        }
    }

    /// Particles paired.
    pub fn n(&self) -> u64 {
        self.both + self.only_ours + self.only_peer + self.neither
    }

    /// The discordant pairs, b = us only and c = the peer only over [`Self::n`]; `None` if no
    /// particle is paired (b + c ≤ n holds by construction, so that is the only refusal).
    pub fn fates(&self) -> Option<PairedFates> {
        PairedFates::new(self.only_ours, self.only_peer, self.n()).ok()
    }

    /// [`Self::fates`], or 0 ± 0 (b = c = 0 over one pair) where no particle is paired.
    pub fn fates_or_zero(&self) -> PairedFates {
        self.fates().unwrap_or(PairedFates { b: 0, c: 0, n: 1 })
    }

    /// Paired difference DE_ours − DE_peer over the paired particles and its (McNemar) standard
    /// error √(b + c − (b − c)²/n)/n ([`PairedFates::difference`], [`PairedFates::stderr`]);
    /// (0, 0) if none.
    pub fn difference(&self) -> (f64, f64) {
        self.fates().map_or((0.0, 0.0), |f| (f.difference(), f.stderr()))
    }

    /// McNemar's χ² = (b − c)²/(b + c) without continuity correction ([`PairedFates::chi2`]; 0 if
    /// b + c = 0).
    pub fn mcnemar_chi2(&self) -> f64 {
        self.fates().map_or(0.0, |f| f.chi2())
    }
}

impl FromIterator<(bool, bool)> for Pairing {
    /// The table of `(deposited in the first run, in the second)` pairs.
    fn from_iter<I: IntoIterator<Item = (bool, bool)>>(pairs: I) -> Self {
        let mut table = Self::default();
        for (first, second) in pairs {
            table.add(first, second);
        }
        table
    }
}

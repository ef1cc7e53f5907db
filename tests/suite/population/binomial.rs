//! The paired fates of two runs of the same particles (`population::binomial::PairedFates`):
//! McNemar's difference and standard errors against the moments of the per-particle
//! differences summed by hand, their symmetries, and the refusal of counts that cannot be a
//! 2×2 table.

use proptest::prelude::*;
use pseudorigid::error::ParamError;
use pseudorigid::population::binomial::PairedFates;
use pseudorigid::population::peer::Pairing;

/// A 2×2 table (both, b, c, neither) with at least one pair.
fn table() -> impl Strategy<Value = (u64, u64, u64, u64)> {
    (0u64..400, 0u64..400, 0u64..400, 0u64..400).prop_filter("at least one pair", |(a, b, c, d)| a + b + c + d > 0)
}

/// The per-particle differences D = X − Y (first deposits − second deposits) of the table:
/// +1 for the b pairs, −1 for the c pairs, 0 for the concordant ones.
fn differences(both: u64, b: u64, c: u64, neither: u64) -> Vec<f64> {
    let mut d = Vec::new();
    d.extend(std::iter::repeat_n(0.0, both as usize));
    d.extend(std::iter::repeat_n(1.0, b as usize));
    d.extend(std::iter::repeat_n(-1.0, c as usize));
    d.extend(std::iter::repeat_n(0.0, neither as usize));
    d
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * (1.0 + b.abs())
}

proptest! {
    /// The difference is the mean of D; its standard error is √(Var D / n) with the variance of
    /// D over the cells' observed fractions (the multinomial plug-in, summed particle by
    /// particle); under p_b = p_c, E D = 0 and the variance is the mean of D².
    #[test]
    fn moments_of_the_differences((both, b, c, neither) in table()) {
        let n = both + b + c + neither;
        let f = PairedFates::new(b, c, n).unwrap();
        let d = differences(both, b, c, neither);
        let m = d.len() as f64;
        let mean = d.iter().sum::<f64>() / m;
        let var = d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / m;
        let var_null = d.iter().map(|x| x * x).sum::<f64>() / m;
        prop_assert!(close(f.difference(), mean), "{} vs {mean}", f.difference());
        prop_assert!(close(f.stderr(), (var / m).sqrt()), "{} vs {}", f.stderr(), (var / m).sqrt());
        prop_assert!(close(f.stderr_under_null(), (var_null / m).sqrt()));
        prop_assert_eq!((f.first_only(), f.second_only(), f.pairs()), (b, c, n));
    }

    /// Swapping the runs flips the difference and z and keeps the errors and χ²; equal
    /// discordant counts give no difference.
    #[test]
    fn symmetry((both, b, c, neither) in table()) {
        let n = both + b + c + neither;
        let (f, g) = (PairedFates::new(b, c, n).unwrap(), PairedFates::new(c, b, n).unwrap());
        prop_assert_eq!(f.difference(), -g.difference());
        prop_assert_eq!(f.z(), -g.z());
        prop_assert_eq!(f.stderr(), g.stderr());
        prop_assert_eq!(f.stderr_under_null(), g.stderr_under_null());
        prop_assert_eq!(f.chi2(), g.chi2());
        let even = PairedFates::new(b.min(c), b.min(c), n).unwrap();
        prop_assert_eq!((even.difference(), even.z(), even.chi2()), (0.0, 0.0, 0.0));
    }

    /// The observed-fraction error never exceeds the null one (they differ by (b − c)²/n under
    /// the root); χ² = z², z = difference / null error, and the 2×2 table's `Pairing` reports
    /// the same numbers.
    #[test]
    fn errors_and_statistics_agree((both, b, c, neither) in table()) {
        let n = both + b + c + neither;
        let f = PairedFates::new(b, c, n).unwrap();
        prop_assert!(f.stderr() <= f.stderr_under_null());
        prop_assert!(close(f.chi2(), f.z() * f.z()));
        if b + c > 0 {
            prop_assert!(close(f.z(), f.difference() / f.stderr_under_null()));
        } else {
            prop_assert_eq!((f.z(), f.chi2(), f.stderr_under_null()), (0.0, 0.0, 0.0));
        }
        let p = Pairing { both, only_ours: b, only_peer: c, neither };
        prop_assert_eq!(p.fates(), Some(f));
        prop_assert_eq!(p.difference(), (f.difference(), f.stderr()));
        prop_assert_eq!(p.mcnemar_chi2(), f.chi2());
    }
}

/// All pairs discordant one way: the observed-fraction error vanishes (b + c − (b − c)²/n = 0),
/// the null one does not; 30 of 120 one way and 10 the other: d = 1/6, σ = √(40 − 400/120)/120.
#[test]
fn worked_values() {
    let f = PairedFates::new(7, 0, 7).unwrap();
    assert_eq!((f.difference(), f.stderr()), (1.0, 0.0));
    assert!((f.stderr_under_null() - 7f64.sqrt() / 7.0).abs() < 1e-16);
    let f = PairedFates::new(30, 10, 120).unwrap();
    assert!((f.difference() - 1.0 / 6.0).abs() < 1e-16);
    assert!((f.stderr() - (40.0f64 - 400.0 / 120.0).sqrt() / 120.0).abs() < 1e-16);
    assert!((f.z() - 20.0 / 40f64.sqrt()).abs() < 1e-15);
    assert!((f.chi2() - 10.0).abs() < 1e-14);
}

/// No pairs, more discordant pairs than pairs, or counts whose sum overflows: refused.
#[test]
fn refuses_bad_counts() {
    assert!(matches!(PairedFates::new(0, 0, 0), Err(ParamError::NotPositive { .. })));
    assert!(matches!(PairedFates::new(3, 4, 6), Err(ParamError::OutOfRange { .. })));
    assert!(matches!(
        PairedFates::new(u64::MAX, 1, u64::MAX),
        Err(ParamError::OutOfRange { .. })
    ));
    assert!(PairedFates::new(3, 3, 6).is_ok());
    assert_eq!(Pairing::default().fates(), None);
    assert_eq!(Pairing::default().difference(), (0.0, 0.0));
}

/// The expressions the committed datasets were written with before `PairedFates` held them
/// (peer tables: observed-fraction error and χ²; the bifurcation's and the tree's paired
/// tables, breathing: null error and z over max(n, 1)), reproduced bit for bit.
#[test]
fn the_datasets_formulas_bit_for_bit() {
    for n in [1u64, 2, 7, 100, 1000, 100_000] {
        for b in (0..=n).step_by((n / 50).max(1) as usize) {
            for c in (0..=n - b).step_by((n / 37).max(1) as usize) {
                let f = PairedFates::new(b, c, n).unwrap();
                let (bf, cf, nf) = (b as f64, c as f64, n as f64);
                assert_eq!(f.difference().to_bits(), ((bf - cf) / nf).to_bits());
                assert_eq!(
                    f.stderr().to_bits(),
                    ((bf + cf - (bf - cf).powi(2) / nf).max(0.0).sqrt() / nf).to_bits()
                );
                let chi2 = if bf + cf > 0.0 {
                    (bf - cf).powi(2) / (bf + cf)
                } else {
                    0.0
                };
                assert_eq!(f.chi2().to_bits(), chi2.to_bits());
                assert_eq!(
                    f.stderr_under_null().to_bits(),
                    (((c + b) as f64).sqrt() / nf).to_bits()
                );
                let sd = ((c + b) as f64).sqrt();
                let z = if sd > 0.0 { (b as f64 - c as f64) / sd } else { 0.0 };
                assert_eq!(f.z().to_bits(), z.to_bits());
            }
        }
    }
}

/// A record of particle `index`, deposited or suspended.
fn record(index: u64, deposited: bool) -> pseudorigid::population::ParticleRecord<()> {
    use pseudorigid::driver::RunStats;
    use pseudorigid::population::{Fate, ParticleRecord};
    ParticleRecord {
        index,
        spec: None,
        fate: if deposited {
            Fate::Deposited {
                patch: 0,
                position: Default::default(),
                time: 0.0,
            }
        } else {
            Fate::Suspended
        },
        end: None,
        stats: RunStats::default(),
        integrator: Default::default(),
        samples: Vec::new(),
        observed: serde_json::Value::Null,
    }
}

proptest! {
    /// The one pairing: the table collected from (first, second) pairs, and from two runs'
    /// records, holds the four cells counted by hand, and its fates are those of the counts.
    #[test]
    fn pairs_are_counted_into_the_two_by_two_table(pairs in prop::collection::vec((any::<bool>(), any::<bool>()), 1..200)) {
        let cell = |x: bool, y: bool| pairs.iter().filter(|p| **p == (x, y)).count() as u64;
        let expected = Pairing { both: cell(true, true), only_ours: cell(true, false), only_peer: cell(false, true), neither: cell(false, false) };
        let collected: Pairing = pairs.iter().copied().collect();
        prop_assert_eq!(collected, expected);
        let (first, second): (Vec<_>, Vec<_>) =
            pairs.iter().enumerate().map(|(k, (x, y))| (record(k as u64, *x), record(k as u64, *y))).unzip();
        prop_assert_eq!(Pairing::of_records(&first, &second).unwrap(), expected);
        prop_assert_eq!(
            collected.fates_or_zero(),
            PairedFates::new(expected.only_ours, expected.only_peer, pairs.len() as u64).unwrap()
        );
    }
}

/// Records of different particles, or of different counts, are not paired; no pair is 0 ± 0.
#[test]
fn records_of_other_particles_are_not_paired() {
    let first = [record(0, true), record(1, false)];
    assert!(Pairing::of_records(&first, &[record(0, true), record(2, false)]).is_err());
    assert!(Pairing::of_records(&first, &[record(0, true)]).is_err());
    let none = Pairing::of_records::<()>(&[], &[]).unwrap();
    assert_eq!(
        (
            none.n(),
            none.fates_or_zero().difference(),
            none.fates_or_zero().stderr()
        ),
        (0, 0.0, 0.0)
    );
}

/// Our records meet a peer's fates by particle index, in our order; the first particle of ours
/// the peer has no fate for is named.
#[test]
fn peer_fates_are_paired_by_index() {
    use pseudorigid::population::peer::{MissingFate, PeerFate, paired_with_peer};
    let fate = |name: &str| PeerFate {
        fate: name.into(),
        patch: String::new(),
        t: String::new(),
        x: Default::default(),
    };
    let peer = std::collections::HashMap::from([(2, fate("deposited")), (0, fate("escaped"))]);
    let ours = [record(0, false), record(2, true)];
    let pairs = paired_with_peer(&ours, &peer).unwrap();
    let indexed: Vec<(u64, &str)> = pairs.iter().map(|(r, p)| (r.index, p.fate.as_str())).collect();
    assert_eq!(indexed, [(0, "escaped"), (2, "deposited")]);
    assert_eq!(
        paired_with_peer(&[record(0, false), record(1, true)], &peer).unwrap_err(),
        MissingFate { index: 1 }
    );
}

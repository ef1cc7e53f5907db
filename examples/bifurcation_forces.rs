//! The airway bifurcation (paper §6.4) with gas slip and finite-Re drag: quasi-rigid spheres at
//! Stk 0.1 and 0.4, the same N particles with the paper's model and with `cunningham`
//! (λ = 66.5 nm, air at 20 °C, 1 atm) and `schiller_naumann`, paired particle by particle.
//! Prints DE both ways, the deposits lost and gained and the paired difference with its
//! standard error √(lost + gained)/N; the numbers are in `paper-figures/fig19/NOTES.md`.
//!
//! ```text
//! cargo run --release --example bifurcation_forces -- [N] [CASE_DIR]
//! ```
//! Runs are cached with the figures' (`figures::cache_dir`): the paper-model runs of Fig. 19 at
//! the same N are reused.

use pseudorigid::hydro::ForceTerms;
use pseudorigid::hydro::forces::{Cunningham, SchillerNaumann};
use pseudorigid::population::binomial::Pairing;
use pseudorigid::studies::bifurcation::{Efficiency, StudyRun, figures};
use std::sync::Arc;

/// Mean free path of air at 20 °C and 1 atm (Hinds, Aerosol Technology, eq. 2.25).
const MEAN_FREE_PATH: f64 = 66.5e-9;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (n, airway) = figures::arguments()?;
    let forces = ForceTerms::new(vec![
        Arc::new(Cunningham::new(MEAN_FREE_PATH)?),
        Arc::new(SchillerNaumann),
    ])?;
    for kind in figures::softness_kinds(&[1.0], &[1e5], &[0.1, 0.4]) {
        let paper = figures::run_cached(StudyRun::new(&airway, kind, n))?.output;
        let with = figures::run_cached(StudyRun::new(&airway, kind, n).forces(&forces))?.output;
        let pairing = Pairing::of_records(&with.records, &paper.records)?;
        let (gained, lost) = (pairing.only_ours, pairing.only_peer);
        let fates = pairing.fates().ok_or("no particles paired")?;
        let (a, b) = (Efficiency::of(kind, &paper), Efficiency::of(kind, &with));
        println!(
            "Stk {}: DE {:.4} ± {:.4} (paper's model) -> {:.4} ± {:.4} (slip + finite-Re drag); \
             lost {lost}, gained {gained}: paired ΔDE {:+.4} ± {:.4}",
            kind.stokes,
            a.de(),
            a.stderr(),
            b.de(),
            b.stderr(),
            fates.difference(),
            fates.stderr_under_null()
        );
    }
    Ok(())
}

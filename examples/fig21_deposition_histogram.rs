//! Paper Fig. 21: streamwise deposition histograms of spheres and prolates λ₁ = 5 at
//! Stk = 0.1, quasi-rigid (μ_s = 10⁵ Pa) against soft (μ_s = 1 and 0.5 Pa), with the mean streamwise
//! deposition and its standard error.
//!
//! ```text
//! cargo run --release --example fig21_deposition_histogram -- [N] [CASE_DIR]
//! ```
//! N particles per kind (default 100 000; also `PSEUDORIGID_BIF_N`). Writes
//! `paper-figures/fig21/{histogram.csv, histogram.svg, summary.csv}`.

use pseudorigid::studies::bifurcation::figures;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (n, airway) = figures::arguments()?;
    let kinds = figures::softness_kinds(&[1.0, 5.0], &[1e5, 1.0, 0.5], &[0.1]);
    let runs = figures::deposits_of(&airway, &kinds, n)?;
    figures::write_histograms("fig21", "Fig. 21: streamwise deposition, Stk = 0.1", &runs)?;
    Ok(())
}

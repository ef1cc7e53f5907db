//! Paper Fig. 23: streamwise deposition histograms of spheres and prolates λ₁ = 5 at
//! Stk = 0.4, quasi-rigid (μ_s = 10⁵ Pa) against soft (μ_s = 0.5 Pa), with the mean streamwise
//! deposition and its standard error.
//!
//! ```text
//! cargo run --release --example fig23_deposition_histogram -- [N] [CASE_DIR]
//! ```
//! N particles per kind (default 100 000; also `PSEUDORIGID_BIF_N`). Writes
//! `paper-figures/fig23/{histogram.csv, histogram.svg, summary.csv}`.

use pseudorigid::studies::bifurcation::figures;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (n, airway) = figures::arguments()?;
    let kinds = figures::softness_kinds(&[1.0, 5.0], &[1e5, 0.5], &[0.4]);
    let runs = figures::deposits_of(&airway, &kinds, n)?;
    figures::write_histograms("fig23", "Fig. 23: streamwise deposition, Stk = 0.4", &runs)?;
    Ok(())
}

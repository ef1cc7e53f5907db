//! Paper Fig. 20: where spheres and prolates λ₁ = 5 deposit at Stk = 0.1, quasi-rigid
//! (μ_s = 10⁵ Pa) against soft (μ_s = 0.5 Pa), with their shapes at deposition.
//!
//! ```text
//! cargo run --release --example fig20_deposition_map -- [N] [CASE_DIR]
//! ```
//! N particles per kind (default 100 000; also `PSEUDORIGID_BIF_N`). Writes
//! `paper-figures/fig20/{deposits.csv, deposits.vtp, summary.csv, map.svg}`: the position, patch,
//! semi-axes and left stretch V = √(F̄F̄ᵀ) of the deposits of the first
//! `figures::MAP_PARTICLES` particles per kind, and over every deposit the largest r₁ and
//! where it occurs.

use pseudorigid::studies::bifurcation::figures;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (n, airway) = figures::arguments()?;
    let kinds = figures::softness_kinds(&[1.0, 5.0], &[1e5, 0.5], &[0.1]);
    let runs = figures::deposits_of(&airway, &kinds, n)?;
    figures::write_maps("fig20", "Fig. 20, Stk = 0.1", &airway, &runs)?;
    Ok(())
}

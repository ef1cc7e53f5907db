//! Paper Fig. 22: where spheres and prolates λ₁ = 5 deposit at Stk = 0.4, quasi-rigid
//! (μ_s = 10⁵ Pa) against soft (μ_s = 0.5 Pa), with their shapes at deposition.
//!
//! ```text
//! cargo run --release --example fig22_deposition_map -- [N] [CASE_DIR]
//! ```
//! N particles per kind (default 100 000; also `PSEUDORIGID_BIF_N`). Writes
//! `paper-figures/fig22/{deposits.csv, deposits.vtp, summary.csv, map.svg}`: the position, patch,
//! semi-axes and left stretch V = √(F̄F̄ᵀ) of the deposits of the first
//! `figures::MAP_PARTICLES` particles per kind, and over every deposit the largest r₁ and
//! where it occurs.

use pseudorigid::studies::bifurcation::figures;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (n, airway) = figures::arguments()?;
    let kinds = figures::softness_kinds(&[1.0, 5.0], &[1e5, 0.5], &[0.4]);
    let runs = figures::deposits_of(&airway, &kinds, n)?;
    figures::write_maps("fig22", "Fig. 22, Stk = 0.4", &airway, &runs)?;
    Ok(())
}

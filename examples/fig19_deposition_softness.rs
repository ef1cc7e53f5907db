//! Paper Fig. 19 (and its text): deposition efficiency against Stk for spheres and prolates
//! λ₁ = 2, 5, quasi-rigid (μ_s = 10⁵ Pa) against soft (μ_s = 1 and 0.5 Pa), and the streamwise
//! deposition histograms at Stk = 0.1.
//!
//! ```text
//! cargo run --release --example fig19_deposition_softness -- [N] [CASE_DIR]
//! ```
//! N particles per kind (default 100 000; also `PSEUDORIGID_BIF_N`). Writes
//! `paper-figures/fig19/{de.csv, de.svg, histogram.csv, histogram.svg, summary.csv, softness_pairs.csv,
//! validity.csv}`
//! (softness_pairs: the same particles quasi-rigid and soft, [`figures::paired_table`];
//! validity: the diagnostics of the first 50 particles of each kind).

use pseudorigid::output::paper_figure_path;
use pseudorigid::studies::bifurcation::{Kind, Material, figures};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (n, airway) = figures::arguments()?;
    let kinds = figures::softness_kinds(&[1.0, 2.0, 5.0], &[1e5, 1.0, 0.5], &[0.1, 0.4]);
    let rows = figures::efficiencies(&airway, &kinds, n)?;
    figures::write_efficiencies(&rows, &paper_figure_path("fig19", "de.csv"))?;
    figures::efficiency_figure(&rows, "Fig. 19: DE of spheres and prolates, quasi-rigid vs soft")
        .write(paper_figure_path("fig19", "de.svg"))?;
    let pairs: Vec<_> = kinds
        .iter()
        .filter(|k| k.material != Material::ShearModulus(1e5))
        .map(|&soft| {
            (
                Kind {
                    material: Material::ShearModulus(1e5),
                    ..soft
                },
                soft,
            )
        })
        .collect();
    figures::paired_table(&pairs, n, &airway)?.write(paper_figure_path("fig19", "softness_pairs.csv"))?;
    figures::write_validity("fig19", &airway, &kinds)?;
    let at_01: Vec<_> = kinds.into_iter().filter(|k| k.stokes == 0.1).collect();
    let runs = figures::deposits_of(&airway, &at_01, n)?;
    figures::write_histograms("fig19", "Fig. 19: streamwise deposition, Stk = 0.1", &runs)?;
    Ok(())
}

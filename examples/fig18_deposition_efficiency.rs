//! Paper Fig. 18: deposition efficiency DE against Stk in the airway bifurcation for rigid
//! prolates λ = 20 (Ca → 0), with the Zhang et al. (1997) correlation beside it.
//!
//! ```text
//! cargo run --release --example fig18_deposition_efficiency -- [N] [CASE_DIR]
//! ```
//! N particles per Stokes number (default 100 000; also `PSEUDORIGID_BIF_N`), in the case
//! `CASE_DIR` (default: the shipped field). Writes `paper-figures/fig18/de.csv`, `de.svg`,
//! `effective_stokes.csv` (DE beside the correlation at the Stokes number the prolates' drag
//! implies) and `validity.csv` (the diagnostics of the first 50 particles of each Stk).

use pseudorigid::output::paper_figure_path;
use pseudorigid::studies::bifurcation::{Kind, Material, figures, study};
use pseudorigid::studies::cavity::Shape;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (n, airway) = figures::arguments()?;
    let kinds: Vec<Kind> = figures::FIG18_STOKES
        .iter()
        .map(|&stokes| Kind {
            shape: Shape::Prolate(20.0),
            material: Material::Rigid,
            stokes,
        })
        .collect();
    let rows = figures::efficiencies(&airway, &kinds, n)?;
    figures::write_efficiencies(&rows, &paper_figure_path("fig18", "de.csv"))?;
    study::effective_stokes_table(&rows)?.write(paper_figure_path("fig18", "effective_stokes.csv"))?;
    figures::efficiency_figure(&rows, "Fig. 18: rigid prolates λ = 20 (Ca → 0)")
        .write(paper_figure_path("fig18", "de.svg"))?;
    figures::write_validity("fig18", &airway, &kinds)?;
    Ok(())
}

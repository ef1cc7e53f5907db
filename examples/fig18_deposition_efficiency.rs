//! Paper Fig. 18: deposition efficiency DE against Stk in the airway bifurcation for rigid
//! prolates λ = 20 (Ca → 0), with the Zhang et al. (1997) correlation beside it.
//!
//! ```text
//! cargo run --release --example fig18_deposition_efficiency -- [N] [CASE_DIR] [--band MESH_DIR...]
//! ```
//! N particles per Stokes number (default 100 000; also `PSEUDORIGID_BIF_N`), in the case
//! `CASE_DIR` (default: the shipped field). Writes `paper-figures/fig18/de.csv`, `de.svg`,
//! `effective_stokes.csv` (DE beside the correlation at the Stokes number the prolates' drag
//! implies) and `validity.csv` (the diagnostics of the first 50 particles of each Stk).
//!
//! `--band MESH_DIR...`: one to three other solutions of the same airway
//! (`cases/bifurcation/Allrun H DIR`): at each Stk of [`figures::FIG18_BAND_STOKES`] the same
//! particles run on every mesh and the mesh study of their fates gives `de.csv`'s
//! `de_extrapolated,gci,p` (empty where the procedure gives no bar, and everywhere without
//! `--band`), the band in `de.svg`, and `mesh_study.csv` (the study's row per Stk, verdict
//! included).

use pseudorigid::output::paper_figure_path;
use pseudorigid::studies::bifurcation::{Airway, Kind, Material, figures, study};
use pseudorigid::studies::cavity::Shape;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (n, dirs) = figures::arguments_and_band()?;
    let kinds: Vec<Kind> = figures::FIG18_STOKES
        .iter()
        .map(|&stokes| Kind {
            shape: Shape::Prolate(20.0),
            material: Material::Rigid,
            stokes,
        })
        .collect();
    let opened = figures::open_cases(&dirs)?;
    let cases: Vec<(&str, &Airway)> = opened.iter().map(|(label, a)| (label.as_str(), a)).collect();
    let airway = cases[0].1;
    let (rows, studies) = figures::banded_efficiencies(&cases, &kinds, n, &figures::FIG18_BAND_STOKES)?;
    if cases.len() == 1 {
        eprintln!("no --band meshes: de.csv's de_extrapolated, gci and p are left empty");
    }
    figures::write_banded_efficiencies(&rows, &studies, &paper_figure_path("fig18", "de.csv"))?;
    study::effective_stokes_table(&rows)?.write(paper_figure_path("fig18", "effective_stokes.csv"))?;
    figures::banded_figure(&rows, &studies, "Fig. 18: rigid prolates λ = 20 (Ca → 0)")
        .write(paper_figure_path("fig18", "de.svg"))?;
    figures::write_validity("fig18", airway, &kinds)?;
    Ok(())
}

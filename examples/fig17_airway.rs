//! Paper Fig. 17: the airway bifurcation, and the check that its mesh resolves what the
//! figures report. The same N rigid spheres at Stk = 0.005, 0.1, 0.2 and 0.4 are tracked
//! through the shipped field and through the other cases given (made by
//! `cases/bifurcation/Allrun H DIR [LAYERS]`, e.g. H = 0.2e-3 around the shipped 0.3e-3, and the
//! shipped size with 5 prism layers instead of 2); DE must change by less than its standard
//! error between the shipped field and the others, and the paired statistic (`paired_z`) says
//! whether the particles that change fate change it one way. At Stk = 0.005 the particles
//! are nearly tracers, which a no-slip wall keeps away: any numerical floor of DE (a velocity
//! error at the wall carrying them into it) shows in that row.
//!
//! ```text
//! cargo run --release --example fig17_airway -- N CASE_DIR...
//! ```
//! Writes `paper-figures/fig17/mesh_check.csv` ([`figures::mesh_check`]), one row per case and
//! Stokes number, cases labelled by the cell size in their `log.summary`
//! ([`figures::case_label`]); with two to four cases layered as the shipped field (one
//! refinement family: the cases with other prism layers are in the check only) also
//! `mesh_study.csv`, the mesh study of DE at each Stokes number
//! ([`pseudorigid::population::mesh_study::MeshStudy::table`]: each mesh's value, the paired
//! increments, the apparent order, the extrapolated DE, its GCI and the verdict).

use pseudorigid::output::paper_figure_path;
use pseudorigid::population::mesh_study::MeshStudy;
use pseudorigid::studies::bifurcation::{Airway, Kind, Material, figures};
use pseudorigid::studies::cavity::Shape;
use std::path::PathBuf;

/// The Stokes numbers checked: near-tracers (a numerical floor shows here), the carina's
/// saddle regime where the wall layer decides (0.1, 0.2), and inertial impaction (0.4).
const STOKES: [f64; 4] = [0.005, 0.1, 0.2, 0.4];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some((n, others)) = args.split_first().filter(|(_, rest)| !rest.is_empty()) else {
        return Err("usage: fig17_airway N CASE_DIR...".into());
    };
    let mut dirs = vec![Airway::shipped_dir()];
    dirs.extend(others.iter().map(PathBuf::from));
    let opened = figures::open_cases(&dirs)?;
    let cases: Vec<(&str, &Airway)> = opened.iter().map(|(label, a)| (label.as_str(), a)).collect();
    // The refinement family of the mesh study: the cases layered as the shipped field.
    let layers = dirs
        .iter()
        .map(|d| Ok(figures::case_summary(d)?.1))
        .collect::<Result<Vec<u32>, std::io::Error>>()?;
    let family: Vec<usize> = (0..dirs.len()).filter(|&i| layers[i] == layers[0]).collect();
    let mut table = String::new();
    let mut studies: Vec<(String, MeshStudy)> = Vec::new();
    for stokes in STOKES {
        let kind = Kind {
            shape: Shape::Prolate(1.0),
            material: Material::Rigid,
            stokes,
        };
        let (check, outputs) = figures::mesh_check(&cases, kind, n.parse()?)?;
        let text = check.to_text();
        table.push_str(if table.is_empty() {
            &text
        } else {
            text.split_once('\n').map_or("", |t| t.1)
        });
        if (2..=4).contains(&family.len()) {
            let of_family = |i: usize| (cases[i], outputs[i].clone());
            let (family_cases, family_outputs): (Vec<_>, Vec<_>) = family.iter().map(|&i| of_family(i)).unzip();
            studies.push((stokes.to_string(), figures::study_of(&family_cases, &family_outputs)?));
        }
    }
    pseudorigid::output::write_atomic(paper_figure_path("fig17", "mesh_check.csv"), table.as_bytes())?;
    print!("{table}");
    if !studies.is_empty() {
        let keyed: Vec<(&str, &MeshStudy)> = studies.iter().map(|(k, s)| (k.as_str(), s)).collect();
        MeshStudy::table(&keyed, Some("stk"), Some("deposited"))?
            .write(paper_figure_path("fig17", "mesh_study.csv"))?;
    }
    Ok(())
}

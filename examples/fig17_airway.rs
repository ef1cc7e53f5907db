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
//! Stokes number, cases labelled by the cell size in their `log.summary`.

use pseudorigid::output::paper_figure_path;
use pseudorigid::studies::bifurcation::{Airway, Kind, Material, figures};
use pseudorigid::studies::cavity::Shape;
use std::path::{Path, PathBuf};

/// "h=0.3mm layers=2" from the `cell_size=0.3e-3` and `layers=2` lines that `Allrun` writes to
/// `log.summary` (a summary without `layers` predates the option: 2 layers).
fn label(dir: &Path) -> Result<String, Box<dyn std::error::Error>> {
    let summary = std::fs::read_to_string(dir.join("log.summary"))?;
    let value = |key: &str| summary.lines().find_map(|l| l.strip_prefix(key)).map(str::trim);
    let h: f64 = value("cell_size=")
        .ok_or_else(|| format!("{}: no cell_size in log.summary", dir.display()))?
        .parse()?;
    let layers = value("layers=").unwrap_or("2");
    Ok(format!("h={}mm layers={layers}", h * 1e3))
}

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
    let mut cases = Vec::new();
    for (i, dir) in dirs.iter().enumerate() {
        let name = if i == 0 {
            format!("{} (shipped)", label(dir)?)
        } else {
            label(dir)?
        };
        cases.push((name, Airway::open(dir)?));
    }
    let cases: Vec<(&str, &Airway)> = cases.iter().map(|(name, a)| (name.as_str(), a)).collect();
    let mut table = String::new();
    for stokes in STOKES {
        let kind = Kind {
            shape: Shape::Prolate(1.0),
            material: Material::Rigid,
            stokes,
        };
        let text = figures::mesh_check(&cases, kind, n.parse()?)?.to_text();
        table.push_str(if table.is_empty() {
            &text
        } else {
            text.split_once('\n').map_or("", |t| t.1)
        });
    }
    pseudorigid::output::write_atomic(paper_figure_path("fig17", "mesh_check.csv"), table.as_bytes())?;
    print!("{table}");
    Ok(())
}

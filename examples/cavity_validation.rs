//! Validate the OpenFOAM cube cavity at Re = 1000 against Albensoeder & Kuhlmann (2005).
//!
//! ```text
//! cases/cavity-re1000/Allrun
//! cargo run --release --example cavity_validation -- [FIELD] [REFERENCE_CSV] [OUT_DIR]
//! ```
//! Defaults: `cases/cavity-re1000/export/cavity.vtk`,
//! `reference-data/cavity_re1000_albensoeder_kuhlmann.csv`, `paper-figures/cavity-validation`.
//! Writes `centrelines.csv`, `extrema.csv` and `centrelines.svg` there.

use pseudorigid::flow::unstructured::MeshedFlow;
use pseudorigid::scenes::cavity_benchmark::report::{plot_centrelines_svg, write_centrelines_csv, write_extrema_csv};
use pseudorigid::scenes::cavity_benchmark::{CavityCase, ReferenceTable, compare_extrema};
use std::path::PathBuf;

/// cases/cavity-re1000/system/caseParameters: L = 0.1 m, U = 0.173 m/s, ν = 17.3 mm²/s.
const CASE: CavityCase = CavityCase {
    edge: 0.1,
    lid_speed: 0.173,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    // A fresh OpenFOAM export if there is one, otherwise the shipped compact field.
    let fresh = "cases/cavity-re1000/export/cavity.vtk";
    let shipped = "reference-data/cavity_re1000.prf";
    let default = if std::path::Path::new(fresh).exists() {
        fresh
    } else {
        shipped
    };
    let field = PathBuf::from(args.next().unwrap_or(default.into()));
    let reference = PathBuf::from(
        args.next()
            .unwrap_or("reference-data/cavity_re1000_albensoeder_kuhlmann.csv".into()),
    );
    let out = args.next().map_or_else(
        || pseudorigid::output::paper_figure_path("cavity-validation", ""),
        PathBuf::from,
    );
    std::fs::create_dir_all(&out)?;

    let flow = MeshedFlow::load(&field)?;
    let table = ReferenceTable::read_csv(&reference)?;
    let rows = compare_extrema(&CASE, &flow, &table)?;
    write_extrema_csv(&out.join("extrema.csv"), &rows)?;
    write_centrelines_csv(&out.join("centrelines.csv"), &CASE, &flow, &table)?;
    let cells = flow.mesh().cells().len();
    plot_centrelines_svg(
        &out.join("centrelines.svg"),
        "Cube cavity, Re = 1000: centreline velocities",
        &format!("OpenFOAM simpleFoam, {cells} cells"),
        &CASE,
        &flow,
        &table,
    )?;
    println!("{cells} cells from {}", field.display());
    println!("quantity  simulated (at)          A&K (at)               error");
    for r in &rows {
        println!(
            "{:8}  {:+.5} ({:.4})   {:+.5} ({:.4})   {:+.2} %",
            r.which.name(),
            r.simulated.value,
            r.simulated.position,
            r.reference.value,
            r.reference.position,
            100.0 * r.relative_error()
        );
    }
    Ok(())
}

//! Validate the OpenFOAM cube cavity at Re = 1000 against Albensoeder & Kuhlmann (2005).
//!
//! ```text
//! cargo run --release --example cavity_validation -- [CASE] [REFERENCE_CSV] [OUT_DIR]
//! ```
//! CASE is a solved OpenFOAM case (`cases/cavity-re1000/Allrun`), read at its last time, or
//! `shipped` (the default): the shipped field (`reference-data/cavity-re1000-foam`). Defaults:
//! `reference-data/cavity_re1000_albensoeder_kuhlmann.csv`, `paper-figures/cavity-validation`.
//! Writes `centrelines.csv`, `extrema.csv` and `centrelines.svg` there.

use pseudorigid::flow::openfoam::{FoamCase, FoamFlow};
use pseudorigid::studies::cavity_benchmark::report::{plot_centrelines_svg, write_centrelines_csv, write_extrema_csv};
use pseudorigid::studies::cavity_benchmark::{RE1000, ReferenceTable, compare_extrema};
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let case_dir = args.next().filter(|a| a != "shipped");
    let reference = PathBuf::from(
        args.next()
            .unwrap_or("reference-data/cavity_re1000_albensoeder_kuhlmann.csv".into()),
    );
    let out = args.next().map_or_else(
        || pseudorigid::output::paper_figure_path("cavity-validation", ""),
        PathBuf::from,
    );
    std::fs::create_dir_all(&out)?;

    // The cellwise reconstruction, as `tests/suite/flow/openfoam/block.rs` checks it.
    let (flow, source) = match &case_dir {
        Some(dir) => {
            let case = FoamCase::open(dir)?;
            let last = *case.times().last().ok_or("the case has no time directory")?;
            (FoamFlow::read(&case, &[last])?, format!("{dir}, t = {last}"))
        }
        None => (RE1000.load()?, RE1000.dir().display().to_string()),
    };
    let case = RE1000.case;
    let table = ReferenceTable::read_csv(&reference)?;
    let rows = compare_extrema(&case, &flow, &table)?;
    write_extrema_csv(&out.join("extrema.csv"), &rows)?;
    write_centrelines_csv(&out.join("centrelines.csv"), &case, &flow, &table)?;
    let cells = flow.mesh().n_cells();
    plot_centrelines_svg(
        &out.join("centrelines.svg"),
        "Cube cavity, Re = 1000: centreline velocities",
        &format!("OpenFOAM simpleFoam, {cells} cells"),
        &case,
        &flow,
        &table,
    )?;
    println!("{cells} cells from {source}");
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

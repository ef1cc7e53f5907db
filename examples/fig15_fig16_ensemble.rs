//! Outcome fractions of the Figs 15/16 releases over the set-up's uncertainties: initial
//! orientation (nominal + 8 spread over a hemisphere), lid direction (as shipped and mirrored)
//! and the field scaled by 0.98 and 1.02 (within its ≈ 4 % grid error), inertial shapes, 100 s,
//! events after 95 s flagged. Writes `paper-figures/fig15_fig16/{outcome_fractions.csv,
//! ensemble_runs.csv}`.
//!
//! Run: `cargo run --release --example fig15_fig16_ensemble [inertialess] [orientations]
//! [fluid-inertia] [orientations] [scales…]` (defaults: inertial shapes, 9 orientations, scales
//! 0.98 1.02); `inertialess` writes `outcome_fractions_inertialess.csv` and
//! `ensemble_runs_inertialess.csv` instead, and `fluid-inertia` adds the undisturbed-flow force
//! and added mass (`studies::cavity::fluid_inertia`) and `_fluid_inertia` to the file names.

use pseudorigid::output::paper_figure_path;
use pseudorigid::studies::cavity::{
    Cavity, Ensemble, ShapeModel, Variant, fig15_fig16_releases, fluid_inertia, member_table, outcome_fraction_table,
};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let start = Instant::now();
    let mut args = std::env::args().skip(1).peekable();
    let inertialess = args.next_if(|a| a == "inertialess").is_some();
    let with_fluid_inertia = args.next_if(|a| a == "fluid-inertia").is_some();
    let (model, shape_suffix) = if inertialess {
        (ShapeModel::Inertialess, "_inertialess")
    } else {
        (ShapeModel::Inertial, "")
    };
    let (forces, terms_suffix) = if with_fluid_inertia {
        (fluid_inertia()?, "_fluid_inertia")
    } else {
        (Default::default(), "")
    };
    let suffix = format!("{shape_suffix}{terms_suffix}");
    let count: usize = args.next().map_or(Ok(9), |a| a.parse())?;
    let scales: Vec<f64> = args.map(|a| a.parse()).collect::<Result<_, _>>()?;
    let scales = if scales.is_empty() { vec![0.98, 1.02] } else { scales };
    let flow = pseudorigid::studies::cavity::shipped_flow()?;
    let releases = fig15_fig16_releases();
    let variants: Vec<Variant> = [false, true]
        .into_iter()
        .flat_map(|mirrored| scales.iter().map(move |&scale| Variant { mirrored, scale }))
        .collect();
    let cavity = Cavity::new(&flow)?.with_shape_model(model).with_forces(forces);
    let ensemble = Ensemble {
        releases,
        variants,
        orientations: count,
        t_max: 100.0,
        tol: 1e-6,
        checkpoints: None,
    };
    let members = ensemble.run(&cavity)?;
    let table = outcome_fraction_table(&members)?;
    print!("{}", table.to_text());
    table.write(paper_figure_path(
        "fig15_fig16",
        &format!("outcome_fractions{suffix}.csv"),
    ))?;
    member_table(&members)?.write(paper_figure_path("fig15_fig16", &format!("ensemble_runs{suffix}.csv")))?;
    let failed = members.iter().filter(|m| m.run.is_err()).count();
    println!(
        "fig15_fig16_ensemble: {} runs ({failed} failed), wall time {:.1} s",
        members.len(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

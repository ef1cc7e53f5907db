//! Paper Figs 15 and 16: soft prolate (λ₁ = 1, 2, 5, 8) and oblate (λ₁ = λ₂ = 2, 5, 8)
//! ellipsoids at Ca = 0.001, 0.25, 0.5, 0.75 in the Re = 470 cavity, tracked for 100 s with
//! solid inertia (ρ* ≈ 5.5 at release; `studies::cavity` docs). `inertialess` as an argument
//! runs the inertialess shape model instead and writes `outcomes_inertialess.csv` only, for
//! comparison. `fluid-inertia` adds the undisturbed-flow force and added mass
//! (`studies::cavity::fluid_inertia`), which the paper's model leaves out, and writes the same
//! files with `_fluid_inertia` in their names beside the paper-faithful ones. Writes
//! `paper-figures/fig15_fig16/`.
//!
//! Run: `cargo run --release --example fig15_fig16_cavity_soft [-- inertialess] [fluid-inertia]`

use pseudorigid::output::Figure;
use pseudorigid::studies::cavity::{
    Cavity, Contact, Shape, ShapeModel, Tracking, fig15_fig16_releases, fluid_inertia, outcome_table, trajectory_panel,
    trajectory_table,
};
use pseudorigid::tensor::Mat3;
use rayon::prelude::*;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let start = Instant::now();
    let flow = pseudorigid::studies::cavity::shipped_flow()?;
    let args: Vec<String> = std::env::args().skip(1).collect();
    let inertialess = args.iter().any(|a| a == "inertialess");
    let with_fluid_inertia = args.iter().any(|a| a == "fluid-inertia");
    let model = if inertialess {
        ShapeModel::Inertialess
    } else {
        ShapeModel::Inertial
    };
    let mut cavity = Cavity::new(&flow)?.with_shape_model(model);
    if with_fluid_inertia {
        cavity = cavity.with_forces(fluid_inertia()?);
    }
    let terms = if with_fluid_inertia { "_fluid_inertia" } else { "" };
    let path =
        |stem: &str, ext: &str| pseudorigid::output::paper_figure_path("fig15_fig16", &format!("{stem}{terms}.{ext}"));
    let releases = fig15_fig16_releases();
    let runs = releases
        .par_iter()
        .map(|r| {
            cavity.track(
                *r,
                &Mat3::identity(),
                &Tracking {
                    contact: Contact::Barycentre,
                    t_max: 100.0,
                    tol: 1e-6,
                    dt_out: 0.1,
                },
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    for run in &runs {
        println!(
            "{:12} Ca {:5}: {:?} ({} steps)",
            run.release.shape.label(),
            run.release.softness.ca(),
            run.outcome(),
            run.stats.steps
        );
    }
    if inertialess {
        outcome_table(&runs)?.write(path("outcomes_inertialess", "csv"))?;
        return Ok(());
    }
    trajectory_table(&runs)?.write(path("trajectories", "csv"))?;
    outcome_table(&runs)?.write(path("outcomes", "csv"))?;
    // One panel per initial shape, in the order of the releases.
    let mut shapes: Vec<Shape> = Vec::new();
    for r in &releases {
        if !shapes.contains(&r.shape) {
            shapes.push(r.shape);
        }
    }
    let panels = shapes
        .iter()
        .map(|s| {
            let mine: Vec<_> = runs.iter().filter(|r| r.release.shape == *s).cloned().collect();
            trajectory_panel(&mine, &s.label())
        })
        .collect();
    Figure::grid(panels, 4, (420, 420)).write(path("trajectories", "svg"))?;
    println!(
        "fig15_fig16_cavity_soft: wall time {:.1} s",
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

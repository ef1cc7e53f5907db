//! Paper Fig. 14: quasi-rigid prolate ellipsoids (λ = 2 and 5, Ca → 0) in the Re = 470
//! lid-driven cavity, tracked for 5 s. Writes `paper-figures/fig14/`. `fluid-inertia` adds the
//! undisturbed-flow force and added mass (`studies::cavity::fluid_inertia`), which the paper's
//! model leaves out, and writes the same files with `_fluid_inertia` in their names.
//!
//! Run: `cargo run --release --example fig14_cavity_rigid [-- fluid-inertia]`

use pseudorigid::output::{Figure, paper_figure_path};
use pseudorigid::studies::cavity::{
    Cavity, Contact, Launch, Shape, Tracking, fluid_inertia, outcome_table, trajectory_panel, trajectory_table,
};
use pseudorigid::studies::particles::Deformability;
use pseudorigid::tensor::Mat3;
use rayon::prelude::*;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let start = Instant::now();
    let flow = pseudorigid::studies::cavity::shipped_flow()?;
    let with_fluid_inertia = std::env::args().skip(1).any(|a| a == "fluid-inertia");
    let mut cavity = Cavity::new(&flow)?;
    if with_fluid_inertia {
        cavity = cavity.with_forces(fluid_inertia()?);
    }
    let terms = if with_fluid_inertia { "_fluid_inertia" } else { "" };
    let path = |stem: &str, ext: &str| paper_figure_path("fig14", &format!("{stem}{terms}.{ext}"));
    println!("release shear rate γ̇₀ = {:.4} 1/s", cavity.release_shear_rate());
    let releases = [Shape::Prolate(2.0), Shape::Prolate(5.0)].map(|shape| Launch {
        shape,
        softness: Deformability::Rigid,
    });
    // Both contact models: the paper's point-particle reading and the particle's extent.
    let jobs: Vec<(Launch, Contact)> = [Contact::Barycentre, Contact::Extent]
        .iter()
        .flat_map(|&c| releases.map(|r| (r, c)))
        .collect();
    let runs = jobs
        .par_iter()
        .map(|(r, c)| {
            cavity.track(
                *r,
                &Mat3::identity(),
                &Tracking {
                    contact: *c,
                    t_max: 5.0,
                    tol: 1e-7,
                    dt_out: 0.02,
                },
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    for run in &runs {
        println!(
            "{} ({}): {:?} ({} steps)",
            run.release.shape.label(),
            run.contact.label(),
            run.outcome(),
            run.stats.steps
        );
    }
    trajectory_table(&runs)?.write(path("trajectories", "csv"))?;
    outcome_table(&runs)?.write(path("outcomes", "csv"))?;
    Figure::single(trajectory_panel(&runs, "Fig. 14: rigid prolates, 5 s")).write(path("trajectories", "svg"))?;
    println!("fig14_cavity_rigid: wall time {:.1} s", start.elapsed().as_secs_f64());
    Ok(())
}

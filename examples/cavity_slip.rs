//! The cavity particle's drift relative to the fluid, with and without the fluid-inertia force
//! terms (issue 20's target; `paper-figures/fig15_fig16/NOTES.md`).
//!
//! ```text
//! cargo run --release --example cavity_slip -- [SECONDS]
//! ```
//! Tracks the rigid sphere and the rigid 2:1 prolate from the paper's release point (§6.3) for
//! SECONDS (default 20) with the paper's model and with `fluid_inertia()` (undisturbed flow and
//! added mass), at the paper's densities and neutrally buoyant (ρ_f = ρ_p: no buoyancy drift, so
//! the slip is the inertial drift alone), and writes `paper-figures/fig15_fig16/slip.csv`:
//! outcome, the slip |v − u(x)| (maximum and time median over the accepted steps) and the
//! median along the path of the quasi-steady slip of a Stokes sphere
//! ([`Cavity::quasi_steady_slip`]: its inertial part falls by ρ_p/|ρ_p − ρ_f| ≈ 2 000 with the
//! terms, to zero for a neutrally buoyant particle, its buoyancy part not at all), with the
//! median and largest gap |(∇u)u − a|/|a| along the path between the blend of the cells'
//! gradients times u and the field's acceleration a along u (what the terms would use if they
//! built Du/Dt from `grad_u`). It also prints how far the field's ∇u is from central
//! differences (±0.1 mm, 6 % of a cell) of its u on
//! lattices in the interior and under the lid.

use pseudorigid::flow::FlowField;
use pseudorigid::output::{Csv, paper_figure_path};
use pseudorigid::studies::cavity::{
    Cavity, Contact, D_EQ, EDGE, Launch, NU, RHO_PARTICLE, Shape, Tracking, fluid_inertia, rho_fluid, shipped_flow,
};
use pseudorigid::studies::particles::Deformability;
use pseudorigid::tensor::{Mat3, Vec3};
use rayon::prelude::*;

/// Half-width of the central difference along the streamline [m].
const STEP: f64 = 1e-4;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

/// Median, 90th percentile and largest relative gap ‖∇u − D_h u‖/‖D_h u‖ between the field's
/// gradient and central differences (±[`STEP`]) of its velocity, on a 20³ lattice filling the
/// box `lo`..`hi` (units of L).
fn gradient_consistency(flow: &impl FlowField, lo: Vec3, hi: Vec3) -> Result<[f64; 3], Box<dyn std::error::Error>> {
    let n = 20;
    let mut gaps = Vec::new();
    for i in 0..n * n * n {
        let s = Vec3::new((i % n) as f64, ((i / n) % n) as f64, (i / (n * n)) as f64).add_scalar(0.5) / n as f64;
        let x = (lo + (hi - lo).component_mul(&s)) * EDGE;
        let grad = flow.sample(&x, 0.0)?.grad_u;
        let mut fd = grad;
        for j in 0..3 {
            let e = Vec3::ith(j, STEP);
            let column = (flow.sample(&(x + e), 0.0)?.u - flow.sample(&(x - e), 0.0)?.u) / (2.0 * STEP);
            fd.set_column(j, &column);
        }
        gaps.push((grad - fd).norm() / fd.norm());
    }
    gaps.sort_by(f64::total_cmp);
    Ok([gaps[gaps.len() / 2], gaps[gaps.len() * 9 / 10], gaps[gaps.len() - 1]])
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let seconds: f64 = std::env::args().nth(1).map_or(Ok(20.0), |s| s.parse())?;
    let flow = shipped_flow()?;
    for (name, lo, hi) in [
        ("interior [0.1, 0.9]³", Vec3::repeat(0.1), Vec3::repeat(0.9)),
        (
            "under the lid, z ∈ [0.9, 0.99]",
            Vec3::new(0.1, 0.1, 0.9),
            Vec3::new(0.9, 0.9, 0.99),
        ),
    ] {
        let [median, p90, largest] = gradient_consistency(&flow, lo, hi)?;
        println!("‖∇u − D_h u‖/‖D_h u‖ {name}: median {median:.3}, 90th percentile {p90:.3}, largest {largest:.2}");
    }
    // (neutrally buoyant, with the terms)
    let cavities = [(false, false), (false, true), (true, false), (true, true)].map(|(neutral, terms)| {
        let mut cavity = Cavity::new(&flow)?;
        if neutral {
            cavity = cavity.neutrally_buoyant()?;
        }
        if terms {
            cavity = cavity.with_forces(fluid_inertia()?);
        }
        Ok::<_, Box<dyn std::error::Error>>(((neutral, terms), cavity))
    });
    let cavities = cavities.into_iter().collect::<Result<Vec<_>, _>>()?;
    let shapes = [Shape::Prolate(1.0), Shape::Prolate(2.0)];
    let jobs: Vec<(Shape, usize)> = shapes
        .iter()
        .flat_map(|&s| (0..cavities.len()).map(move |c| (s, c)))
        .collect();
    let runs = jobs
        .par_iter()
        .map(|&(shape, c)| {
            let release = Launch {
                shape,
                softness: Deformability::Rigid,
            };
            cavities[c].1.track(
                release,
                &Mat3::identity(),
                &Tracking {
                    contact: Contact::Barycentre,
                    t_max: seconds,
                    tol: 1e-7,
                    dt_out: 0.01,
                },
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut csv = Csv::new(&[
        "shape",
        "fluid_density",
        "forces",
        "outcome",
        "t_end",
        "max_slip",
        "median_slip",
        "predicted_median_slip",
        "median_dudt_gap",
        "max_dudt_gap",
    ]);
    println!(
        "buoyancy drift of the sphere τ_b g = {:.3e} m/s; ρ_p/|ρ_p − ρ_f| = {:.0}",
        (RHO_PARTICLE - rho_fluid()).abs() * D_EQ * D_EQ * 9.81 / (18.0 * rho_fluid() * NU),
        RHO_PARTICLE / (RHO_PARTICLE - rho_fluid()).abs()
    );
    for (run, &(shape, c)) in runs.iter().zip(&jobs) {
        let ((neutral, terms), cavity) = &cavities[c];
        let along = cavity.quasi_steady_slip(run)?;
        let predicted = median(along.iter().map(|q| q.slip).collect());
        let gap = median(along.iter().map(|q| q.acceleration_gap).collect());
        let largest = along.iter().map(|q| q.acceleration_gap).fold(0.0, f64::max);
        let (neutral, terms) = (*neutral, *terms);
        let forces = if terms { "fluid_inertia" } else { "paper" };
        let density = if neutral { "neutral" } else { "paper" };
        let t_end = run.path.last().map_or(0.0, |p| p.0);
        let outcome = format!("{:?}", run.outcome()).replace(',', ";");
        println!(
            "{:10} ρ_f {density:7} {forces:13} {outcome:30} t_end {t_end:7.3} slip max {:.3e} median {:.3e} m/s; quasi-steady {predicted:.3e}; (∇u)u gap median {gap:.3}, max {largest:.2}",
            shape.label(),
            run.slip.max,
            run.slip.median,
        );
        csv.push(vec![
            shape.label(),
            density.into(),
            forces.into(),
            outcome,
            format!("{t_end:.3}"),
            format!("{:.3e}", run.slip.max),
            format!("{:.3e}", run.slip.median),
            format!("{predicted:.3e}"),
            format!("{gap:.3}"),
            format!("{largest:.3}"),
        ])?;
    }
    for pair in runs.chunks(2) {
        println!(
            "{}: slip ratio paper/fluid-inertia: max {:.1}, median {:.1}",
            pair[0].release.shape.label(),
            pair[0].slip.max / pair[1].slip.max,
            pair[0].slip.median / pair[1].slip.median
        );
    }
    csv.write(paper_figure_path("fig15_fig16", "slip.csv"))?;
    Ok(())
}

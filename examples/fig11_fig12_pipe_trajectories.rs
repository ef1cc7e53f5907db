//! Paper Figs 11 and 12: initially prolate particles (λ₁ = 3.5 and 7, λ₂ = 1, r₃ = 0.5 µm)
//! released at x₂ = −1.65 mm in the Tian/Cui pipe flow and tracked until they touch the wall,
//! for Ca → 0 (rigid) and Ca = 0.2, 0.25, 0.5, 0.9 (the figures list 0.2, the text 0.25: both
//! are run).
//!
//! Every case is run twice, at rtol = atol = 1e-7 and at half that tolerance; the second
//! distance is the convergence check in `deposition.csv`.
//! Writes `paper-figures/fig11/{trajectories.csv, trajectories.svg, deposition.csv}` and
//! `paper-figures/fig12/{direction_cosines.csv, direction_cosines.svg}`.

use pseudorigid::output::{Figure, Panel, paper_figure_path};
use pseudorigid::studies::pipe::datasets::{
    DepositionRow, Run, deposition_rows, deposition_table, direction_cosine_panel, direction_cosine_table,
    trajectory_panel, trajectory_table,
};
use pseudorigid::studies::pipe::{PipeCase, deposition_study};
use std::error::Error;
use std::time::Instant;

const LAMBDAS: [f64; 2] = [3.5, 7.0];
const CAS: [f64; 5] = [0.0, 0.2, 0.25, 0.5, 0.9];
const TOL: f64 = 1e-7;
/// Recorded samples per Jeffery period at the release point.
const PER_ORBIT: f64 = 40.0;
/// Window of the zoomed direction-cosine panels [s].
const ZOOM_SECONDS: f64 = 0.3;

fn main() -> Result<(), Box<dyn Error>> {
    let start = Instant::now();
    let cases = PipeCase::grid(&LAMBDAS, &CAS);
    let runs = deposition_study(&cases, TOL, PER_ORBIT)?;
    let main_time = start.elapsed();
    let checks = deposition_study(&cases, 0.5 * TOL, 0.0)?;
    let rows = deposition_rows(&runs, &checks);
    rows.iter().for_each(report);
    deposition_table(&rows)?.write(paper_figure_path("fig11", "deposition.csv"))?;

    let views: Vec<Run<'_>> = runs.iter().map(|(s, d)| (s, d.samples.as_slice())).collect();
    let of = |l: f64| -> Vec<Run<'_>> {
        views
            .iter()
            .copied()
            .filter(|(s, _)| s.particle_data.lambda1() == l)
            .collect()
    };
    trajectory_table(&views)?.write(paper_figure_path("fig11", "trajectories.csv"))?;
    direction_cosine_table(&views)?.write(paper_figure_path("fig12", "direction_cosines.csv"))?;
    let (a, b) = (of(LAMBDAS[0]), of(LAMBDAS[1]));
    Figure::grid(
        vec![
            trajectory_panel(&a, "Fig. 11(a): λ1 = 3.5, barycentre path"),
            trajectory_panel(&b, "Fig. 11(b): λ1 = 7, barycentre path"),
        ],
        1,
        (900, 420),
    )
    .write(paper_figure_path("fig11", "trajectories.svg"))?;
    let cosine = |runs: &[Run<'_>], title: &str, t_end| direction_cosine_panel(runs, 0, title, t_end);
    let panels: Vec<Panel> = vec![
        cosine(&a, "Fig. 12: λ1 = 3.5, l_a · e1", None),
        cosine(&a, "λ1 = 3.5, first 0.3 s", Some(ZOOM_SECONDS)),
        cosine(&b, "Fig. 12: λ1 = 7, l_a · e1", None),
        cosine(&b, "λ1 = 7, first 0.3 s", Some(ZOOM_SECONDS)),
    ];
    Figure::grid(panels, 2, (700, 380)).write(paper_figure_path("fig12", "direction_cosines.svg"))?;
    println!(
        "fig11_fig12_pipe_trajectories: wall time {:.2?} (main runs {main_time:.2?})",
        start.elapsed()
    );
    Ok(())
}

fn report(r: &DepositionRow) {
    let extra = r.extra_deq.map_or(String::from("—"), |e| format!("{e:+.0}"));
    let paper = r
        .paper_statement()
        .map_or(String::new(), |(rel, v)| format!("  paper: {rel} +{v}"));
    println!(
        "λ1 = {:<3} Ca = {:<4}: deposits after {:.3} s at x1 = {:.0} d_eq ({:.3} m{}), extra vs rigid {extra} d_eq{paper}; tol/2 changes it by {:.1e} (relative to the extra), {} steps; <(p.e2)^2> {:.3}, <r1/r3> {:.2}, max r1/r3 {:.2}",
        r.lambda1,
        r.ca,
        r.t_s,
        r.distance_deq,
        r.distance_m,
        if r.beyond_pipe { ", beyond L" } else { "" },
        r.tolerance_change(),
        r.steps,
        r.shape.mean_gradient_alignment().unwrap_or(f64::NAN),
        r.shape.mean_aspect().unwrap_or(f64::NAN),
        r.shape.max_aspect()
    );
}

//! Paper Figs 5 and 6: shear-plane outlines of the initially oblate particle (2.5 : 1 : 2.5)
//! at Ca = 0.4 (TU) and 0.5 (TR), with the in-plane long axis (black) and the material lines
//! l_a, l_c coloured green for max(l_a, l_c) and red for min(l_a, l_c), as in the paper.
//! Fig. 5: t̂ = 0, 2, 4, 6, 8; Fig. 6: t̂ = 22.5, 23, 23.5, 24, 24.5.
//!
//! Writes `paper-figures/fig5_fig6/snapshots.csv` (one row per snapshot; angles in degrees
//! from the flow direction) and `fig5.svg`, `fig6.svg`.

use pseudorigid::output::{Csv, Figure, Panel, Series, paper_figure_path};
use pseudorigid::studies::shear_run::{ShearSample, oblate_fig4_run};
use std::error::Error;
use std::time::Instant;

const FIG5: [f64; 5] = [0.0, 2.0, 4.0, 6.0, 8.0];
const FIG6: [f64; 5] = [22.5, 23.0, 23.5, 24.0, 24.5];
const GREEN: usize = 2;
const RED: usize = 1;

fn snapshot_panel(ca: f64, s: &ShearSample) -> Panel {
    let segment = |v: &pseudorigid::tensor::Vec3| vec![(0.0, 0.0), (v[0], v[1])];
    let (tip_x, tip_y) = s.section.long_axis_tip();
    let (long, short) = if s.l_a() >= s.l_c() {
        (s.xi_a, s.xi_c)
    } else {
        (s.xi_c, s.xi_a)
    };
    Panel::new(format!("Ca = {ca}, t̂ = {}", s.t), "x / d_eq", "y / d_eq")
        .with(Series::line("", s.section.outline(120), 3))
        .with(Series::line("", vec![(-tip_x, -tip_y), (tip_x, tip_y)], 0))
        .with(Series::line("", segment(&long), GREEN))
        .with(Series::line("", segment(&short), RED))
        .with_ranges((-1.5, 1.5), (-1.5, 1.5))
}

fn main() -> Result<(), Box<dyn Error>> {
    let start = Instant::now();
    let mut csv = Csv::new(&[
        "ca",
        "t",
        "r_inplane_long",
        "r_inplane_short",
        "long_axis_deg",
        "xi_a_x",
        "xi_a_y",
        "xi_c_x",
        "xi_c_y",
        "l_a",
        "l_c",
    ]);
    let times: Vec<f64> = FIG5.iter().chain(&FIG6).copied().collect();
    let (mut fig5, mut fig6) = (Vec::new(), Vec::new());
    for ca in [0.4, 0.5] {
        let (run, _) = oblate_fig4_run(ca, &times)?;
        for s in &run {
            csv.push_numbers(&[
                ca,
                s.t,
                s.section.r_long,
                s.section.r_short,
                s.section.angle.to_degrees(),
                s.xi_a[0],
                s.xi_a[1],
                s.xi_c[0],
                s.xi_c[1],
                s.l_a(),
                s.l_c(),
            ])?;
            let target = if s.t < 20.0 { &mut fig5 } else { &mut fig6 };
            target.push(snapshot_panel(ca, s));
        }
    }
    let dir = "fig5_fig6";
    csv.write(paper_figure_path(dir, "snapshots.csv"))?;
    Figure::grid(fig5, 5, (300, 300)).write(paper_figure_path(dir, "fig5.svg"))?;
    Figure::grid(fig6, 5, (300, 300)).write(paper_figure_path(dir, "fig6.svg"))?;
    println!("fig5_fig6_snapshots: wall time {:.2?}", start.elapsed());
    Ok(())
}

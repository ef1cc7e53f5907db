//! Paper Fig. 4: in-plane and out-of-plane aspect ratios of the initially oblate particle
//! (semi-axes 2.5 : 1 : 2.5 along flow, gradient, vorticity; ω₁(0) = ω₂(0) = 2.5) at
//! Ca = 0.4 (TU) and Ca = 0.5 (TR) for t̂ ≤ 30, with the material lines l_a and l_c.
//!
//! ω₁ = r_inplane_long / r_inplane_short and ω₂ = r_out_of_plane / r_inplane_short, where the
//! in-plane axes are those of the ellipse cut by the shear plane z = 0 and r_out_of_plane is
//! the half-chord along the vorticity axis (oblate convention of the paper, both ≥ 1 here).
//!
//! Writes `paper-figures/fig4/axes.csv` and `paper-figures/fig4/axes.svg`, and the runs'
//! validity diagnostics (shared with Figs 5, 6) to `paper-figures/fig4/validity.csv`.

use pseudorigid::output::{Csv, Figure, Panel, Series, paper_figure_path};
use pseudorigid::studies::shear_run::{oblate_fig4_run, validity_table};
use std::error::Error;
use std::time::Instant;

fn main() -> Result<(), Box<dyn Error>> {
    let start = Instant::now();
    let times: Vec<f64> = (0..=600).map(|i| f64::from(i) * 0.05).collect();
    let mut csv = Csv::new(&[
        "ca",
        "t",
        "r_inplane_long",
        "r_inplane_short",
        "r_out_of_plane",
        "omega1",
        "omega2",
        "l_a",
        "l_c",
    ]);
    let mut panels = Vec::new();
    let mut validity = Vec::new();
    for ca in [0.4, 0.5] {
        let (run, checks) = oblate_fig4_run(ca, &times)?;
        validity.push((ca, checks));
        for s in &run {
            let sec = s.section;
            csv.push_numbers(&[
                ca,
                s.t,
                sec.r_long,
                sec.r_short,
                sec.r_out_of_plane,
                sec.omega1(),
                sec.omega2(),
                s.l_a(),
                s.l_c(),
            ])?;
        }
        let (peak_t, peak) = run
            .iter()
            .take_while(|s| s.t <= 10.0)
            .map(|s| (s.t, s.section.omega1()))
            .fold((0.0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
        println!("Ca = {ca}: first maximum ω₁ = {peak:.3} at t̂ = {peak_t:.2}");
        let series = |f: &dyn Fn(&pseudorigid::studies::shear_run::ShearSample) -> f64| {
            run.iter().map(|s| (s.t, f(s))).collect::<Vec<_>>()
        };
        let regime = if ca < 0.45 { "TU" } else { "TR" };
        panels.push(
            Panel::new(format!("Ca = {ca} ({regime})"), "t̂ = γ̇t", "aspect ratio")
                .with(Series::line("ω₁ (in plane)", series(&|s| s.section.omega1()), 1))
                .with(Series::line("ω₂ (out of plane)", series(&|s| s.section.omega2()), 3)),
        );
        panels.push(
            Panel::new(format!("Ca = {ca}: material lines"), "t̂ = γ̇t", "length / d_eq")
                .with(Series::line("l_a", series(&|s| s.l_a()), 2))
                .with(Series::line("l_c", series(&|s| s.l_c()), 1)),
        );
    }
    csv.write(paper_figure_path("fig4", "axes.csv"))?;
    validity_table(&validity)?.write(paper_figure_path("fig4", "validity.csv"))?;
    Figure::grid(panels, 2, (560, 400)).write(paper_figure_path("fig4", "axes.svg"))?;
    println!("fig4_oblate: wall time {:.2?}", start.elapsed());
    Ok(())
}

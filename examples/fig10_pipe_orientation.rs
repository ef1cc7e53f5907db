//! Paper Fig. 10: direction cosines of the material line l_a (barycentre → point A, initially
//! the tip of the long axis along the flow) of the Tian/Cui λ₁ = 14 prolate particle released
//! at x₂ = −1.65 mm in laminar pipe flow, for Ca → 0 (rigid), 0.01, 0.05 and 0.1, over 0.5 s.
//!
//! Prints the measured orbit periods against Jeffery's 2π(λ + 1/λ)/γ̇₀ at the release point.
//! Writes `paper-figures/fig10/direction_cosines.csv` and `paper-figures/fig10/direction_cosines.svg`.

use pseudorigid::output::{Figure, paper_figure_path};
use pseudorigid::studies::pipe::datasets::{Run, direction_cosine_panel, direction_cosine_table};
use pseudorigid::studies::pipe::orbit::{jeffery_period, orbit_periods};
use pseudorigid::studies::pipe::{PipeCase, orientation_study};
use std::error::Error;
use std::time::Instant;

const LAMBDA: f64 = 14.0;
const CAS: [f64; 4] = [0.0, 0.01, 0.05, 0.1];
const T_END_SECONDS: f64 = 0.5;
const OUTPUTS: usize = 2500;
const TOL: f64 = 1e-7;

fn main() -> Result<(), Box<dyn Error>> {
    let start = Instant::now();
    let runs = orientation_study(&PipeCase::grid(&[LAMBDA], &CAS), T_END_SECONDS, OUTPUTS, TOL)?;
    let views: Vec<Run<'_>> = runs.iter().map(|(s, v)| (s, v.as_slice())).collect();
    for (scene, samples) in &runs {
        let t_jeffery = jeffery_period(LAMBDA, 1.0) * scene.time_unit;
        let periods: Vec<String> = orbit_periods(samples)
            .iter()
            .map(|p| format!("{:.4}", p * scene.time_unit))
            .collect();
        println!(
            "Ca = {:<5} orbit periods [s]: {}  (Jeffery at release: {t_jeffery:.4} s)",
            scene.softness.ca(),
            periods.join(", ")
        );
    }
    direction_cosine_table(&views)?.write(paper_figure_path("fig10", "direction_cosines.csv"))?;
    Figure::grid(
        vec![
            direction_cosine_panel(&views, 0, "Fig. 10(a): λ1 = 14, l_a · e1", None),
            direction_cosine_panel(&views, 1, "Fig. 10(b): λ1 = 14, l_a · e2", None),
        ],
        1,
        (900, 420),
    )
    .write(paper_figure_path("fig10", "direction_cosines.svg"))?;
    println!("fig10_pipe_orientation: wall time {:.2?}", start.elapsed());
    Ok(())
}

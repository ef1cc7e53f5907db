//! Paper Fig. 8: sections of the TU/TR phase diagram of initially triaxial particles in
//! Sanagavarapu's ratios, semi-axes (1, ω₁, ω₂) along (flow, gradient, vorticity):
//! (a) ω₁ = r_short/r_long (in-plane) = 0.5 fixed, ω₂ = r_vorticity/r_long = 0.1 … 1;
//! (b) ω₂ = 0.5 fixed, ω₁ = 0.1 … 0.9. Boundaries resolved to ΔCa ≤ 0.001.
//!
//! Writes `paper-figures/fig8/boundary.csv` and `paper-figures/fig8/boundary.svg`.

use pseudorigid::output::{Figure, paper_figure_path};
use pseudorigid::studies::particles::Shape;
use pseudorigid::studies::phase_map::{self, MapShape, boundary_panel, boundary_table, validity_table};
use pseudorigid::studies::shear_shape::ShearShape;
use std::error::Error;
use std::time::Instant;

fn main() -> Result<(), Box<dyn Error>> {
    let start = Instant::now();
    let tenths = |from: u32, to: u32| (from..=to).map(|i| f64::from(i) / 10.0);
    let point = |series, x, omega1, omega2| MapShape {
        series,
        x,
        shape: ShearShape::new(Shape::Triaxial { omega1, omega2 }),
    };
    let section_a = tenths(1, 10).map(|w2| point("a_omega1_0.5", w2, 0.5, w2));
    let section_b = tenths(1, 9).map(|w1| point("b_omega2_0.5", w1, w1, 0.5));
    let shapes: Vec<_> = section_a.chain(section_b).collect();
    let points = phase_map::compute(&phase_map::paper_search()?, &shapes)?;
    for p in &points {
        let b = &p.boundary;
        println!(
            "{}  ω = {:.1}: Ca_c ∈ [{:.4}, {:.4}]  ({} runs)",
            p.series, p.x, b.ca_tu, b.ca_tr, b.evaluations
        );
    }
    boundary_table(&points)?.write(paper_figure_path("fig8", "boundary.csv"))?;
    // The paper search is inertialess (Re = 0 by assumption).
    validity_table(&points, true)?.write(paper_figure_path("fig8", "validity.csv"))?;
    let (a, b): (Vec<_>, Vec<_>) = points.into_iter().partition(|p| p.series.starts_with('a'));
    Figure::grid(
        vec![
            boundary_panel(&a, "Fig. 8(a): ω₁ = 0.5", "ω₂ = r_vorticity / r_long"),
            boundary_panel(&b, "Fig. 8(b): ω₂ = 0.5", "ω₁ = r_short / r_long (in plane)"),
        ],
        2,
        (560, 440),
    )
    .write(paper_figure_path("fig8", "boundary.svg"))?;
    println!("fig8_triaxial: wall time {:.2?}", start.elapsed());
    Ok(())
}

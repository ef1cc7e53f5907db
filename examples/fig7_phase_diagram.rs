//! Paper Fig. 7: critical Ca of the TU/TR transition against the aspect ratio of initially
//! prolate (λ, 1, 1) and oblate (λ, 1, λ) particles, λ = 1.25 … 5, resolved to ΔCa ≤ 0.001.
//!
//! Writes `paper-figures/fig7/boundary.csv` and `paper-figures/fig7/boundary.svg`.

use pseudorigid::output::{Figure, paper_figure_path};
use pseudorigid::studies::particles::Shape;
use pseudorigid::studies::phase_map::{self, MapShape, boundary_panel, boundary_table, validity_table};
use pseudorigid::studies::shear_shape::ShearShape;
use std::error::Error;
use std::time::Instant;

const ASPECT_RATIOS: [f64; 10] = [1.25, 1.5, 1.75, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0];

fn main() -> Result<(), Box<dyn Error>> {
    let start = Instant::now();
    let shapes: Vec<MapShape> = [Shape::Prolate as fn(f64) -> Shape, Shape::Oblate]
        .iter()
        .flat_map(|family| {
            ASPECT_RATIOS.map(|x| {
                let shape = family(x);
                MapShape {
                    series: shape.family(),
                    x,
                    shape: ShearShape::new(shape),
                }
            })
        })
        .collect();
    let points = phase_map::compute(&phase_map::paper_search()?, &shapes)?;
    for p in &points {
        let b = &p.boundary;
        println!(
            "{:8} λ = {:4}: Ca_c ∈ [{:.4}, {:.4}]  ({} runs)",
            p.series, p.x, b.ca_tu, b.ca_tr, b.evaluations
        );
    }
    boundary_table(&points)?.write(paper_figure_path("fig7", "boundary.csv"))?;
    // The paper search is inertialess (Re = 0 by assumption).
    validity_table(&points, true)?.write(paper_figure_path("fig7", "validity.csv"))?;
    Figure::single(boundary_panel(
        &points,
        "Fig. 7: TU/TR boundary, prolate (λ,1,1) and oblate (λ,1,λ)",
        "initial aspect ratio λ",
    ))
    .write(paper_figure_path("fig7", "boundary.svg"))?;
    println!("fig7_phase_diagram: wall time {:.2?}", start.elapsed());
    Ok(())
}

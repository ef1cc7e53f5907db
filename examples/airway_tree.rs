//! Issue 24, item 4: deposition efficiency generation by generation in a symmetric Weibel tree
//! (G3 to G6, seven bifurcations), rigid against soft particles on the same particles.
//!
//! ```text
//! cargo run --release --example airway_tree -- [N] [CASE_DIR]
//! ```
//! N particles per (shape, μ_s, Stk) point (default 10 000; also `PSEUDORIGID_TREE_N`) through
//! the case `CASE_DIR` (default: the shipped rotated tree, `reference-data/airway-tree/rotated`).
//! Points: spheres and prolates λ₁ = 5, rigid and Neo-Hookean μ_s = 1 and 0.5 Pa, Stk 0.1 and
//! 0.4 (the bifurcation's Fig. 19 set). Particle k has the same injection in every run (the
//! seed of the bifurcation datasets). Writes `paper-figures/airway-tree/`:
//! `de_by_generation.csv` (`shape,mu_s,stk,generation,n_entered,n_deposited,de,de_stderr`),
//! `de_by_generation.svg`, `paired_by_generation.csv` (rigid against each soft material, the
//! same particles) and `timing.csv` (wall time per point). Finished runs are kept in
//! `target/airway-tree-runs` (or `PSEUDORIGID_TREE_CACHE`) and read back.

use pseudorigid::output::{Csv, paper_figure_path};
use pseudorigid::studies::airway_tree::study::{self, de_figure, de_table, paired, paired_table};
use pseudorigid::studies::airway_tree::{AirwayTree, by_generation};
use pseudorigid::studies::bifurcation::{Kind, Material};
use pseudorigid::studies::count_and_case;
use pseudorigid::studies::particles::Shape;

/// Particles per point when neither the command line nor `PSEUDORIGID_TREE_N` says.
const DEFAULT_N: u64 = 10_000;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (n, dir) = count_and_case("PSEUDORIGID_TREE_N", DEFAULT_N)?;
    let tree = AirwayTree::open(dir.unwrap_or_else(|| AirwayTree::shipped_dir("rotated")))?;
    eprintln!(
        "{} tree, {} cells, tracking time {:.4} s",
        tree.tree().variant(),
        tree.airway().flow().cellwise().mesh().n_cells(),
        tree.airway().tracking_time()
    );
    let materials = [
        Material::Rigid,
        Material::ShearModulus(1.0),
        Material::ShearModulus(0.5),
    ];
    let mut rows = Vec::new();
    let mut pairs = Vec::new();
    let mut timing = Csv::new(&["shape", "mu_s", "stk", "n", "seconds", "steps"]);
    for stokes in [0.1, 0.4] {
        for shape in [Shape::Sphere, Shape::Prolate(5.0)] {
            let mut outputs = Vec::new();
            for material in materials {
                let kind = Kind {
                    shape,
                    material,
                    stokes,
                };
                let computed = study::track(
                    &tree,
                    tree.study(kind, n).cache(&study::cache_dir()?),
                    &pseudorigid::population::RunOptions::default(),
                )?;
                let (time, seconds) = (computed.time_label(), computed.seconds_cell());
                let out = computed.output;
                let steps: u64 = out.records.iter().map(|r| r.stats.steps).sum();
                let counts = by_generation(tree.tree(), &out)?;
                eprintln!("{kind:?}: {:?} in {time} ({steps} steps)", out.counts());
                for c in &counts {
                    eprintln!(
                        "  G{}: {} of {} deposited, DE = {:.4} ± {:.4}",
                        c.generation,
                        c.deposited,
                        c.entered,
                        c.de(),
                        c.stderr()
                    );
                }
                timing.push(vec![
                    shape.label(),
                    study::mu_s_label(material),
                    stokes.to_string(),
                    n.to_string(),
                    seconds,
                    steps.to_string(),
                ])?;
                rows.push((kind, counts));
                outputs.push((kind, out));
            }
            let (reference, rigid) = &outputs[0];
            for (soft, out) in &outputs[1..] {
                pairs.push((*reference, *soft, paired(tree.tree(), rigid, out)?));
            }
        }
    }
    de_table(&rows)?.write(paper_figure_path("airway-tree", "de_by_generation.csv"))?;
    paired_table(&pairs)?.write(paper_figure_path("airway-tree", "paired_by_generation.csv"))?;
    timing.write(paper_figure_path("airway-tree", "timing.csv"))?;
    de_figure(&rows, &format!("{} tree G3-G6", tree.tree().variant()))
        .write(paper_figure_path("airway-tree", "de_by_generation.svg"))?;
    Ok(())
}

//! Issue 24, item 5: drug release at a critical stretch in the symmetric Weibel tree (G3 to
//! G6): where and when soft particles first reach each threshold of their largest principal
//! stretch λ₁, tracked on past it.
//!
//! ```text
//! cargo run --release --example airway_release -- [N] [CASE_DIR]
//! ```
//! N particles per (shape, μ_s, Stk) point (default 1000; also `PSEUDORIGID_RELEASE_N`) through
//! the case `CASE_DIR` (default: the shipped rotated tree). Points: the tree study's soft ones,
//! spheres and prolates λ₁ = 5, Neo-Hookean μ_s = 1 and 0.5 Pa, Stk 0.1 and 0.4, the same
//! particles as `airway_tree` (its seed); λ₁ thresholds
//! [`STRETCH_LEVELS`](pseudorigid::studies::airway_tree::release::STRETCH_LEVELS). Writes
//! `paper-figures/airway-tree/`: `release.csv`
//! (`shape,mu_s,stk,threshold,generation,n_released,fraction,fraction_stderr`),
//! `release_times.csv` (whole tree and release times per threshold), `release.svg`,
//! `release_map.vtp` (ParaView: one point per release event of particles 0 to 999) and
//! `release_map.parquet` (the same events), and
//! `release_timing.csv`. Finished runs are kept with the tree study's
//! (`target/airway-tree-runs` or `PSEUDORIGID_TREE_CACHE`) and read back.

use pseudorigid::output::{Csv, paper_figure_path};
use pseudorigid::studies::airway_tree::AirwayTree;
use pseudorigid::studies::airway_tree::release::{
    ReleaseResults, release_figure, release_map, release_table, release_times_table, stretch_thresholds, track,
    write_release_parquet,
};
use pseudorigid::studies::airway_tree::study::{cache_dir, mu_s_label};
use pseudorigid::studies::bifurcation::{Kind, Material};
use pseudorigid::studies::count_and_case;
use pseudorigid::studies::particles::Shape;

/// Particles per point when neither the command line nor `PSEUDORIGID_RELEASE_N` says.
const DEFAULT_N: u64 = 1000;

/// The release maps show the particles with index below this (the statistics use all N).
const MAP_PARTICLES: u64 = 1000;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (n, dir) = count_and_case("PSEUDORIGID_RELEASE_N", DEFAULT_N)?;
    let tree = AirwayTree::open(dir.unwrap_or_else(|| AirwayTree::shipped_dir("rotated")))?;
    let thresholds = stretch_thresholds();
    let mut rows = Vec::new();
    let mut timing = Csv::new(&["shape", "mu_s", "stk", "n", "seconds", "steps"]);
    for stokes in [0.1, 0.4] {
        for shape in [Shape::Sphere, Shape::Prolate(5.0)] {
            for material in [Material::ShearModulus(1.0), Material::ShearModulus(0.5)] {
                let kind = Kind {
                    shape,
                    material,
                    stokes,
                };
                let computed = track(
                    &tree,
                    tree.study(kind, n).cache(&cache_dir()?),
                    &thresholds,
                    &pseudorigid::population::RunOptions::default(),
                )?;
                let out = &computed.output;
                let steps: u64 = out.records.iter().map(|r| r.stats.steps).sum();
                let releases = ReleaseResults::of(tree.tree(), &thresholds, out)?;
                eprintln!(
                    "{kind:?}: {:?} in {} ({steps} steps)",
                    out.counts(),
                    computed.time_label()
                );
                for &s in thresholds.levels() {
                    if let Some(t) = releases.times(s) {
                        eprintln!(
                            "  lambda1 >= {s}: {} of {} released, t = {:.4} ± {:.4} s (median {:.4})",
                            t.count, releases.n, t.mean, t.stderr, t.median
                        );
                    }
                }
                timing.push(vec![
                    shape.label(),
                    mu_s_label(material),
                    stokes.to_string(),
                    n.to_string(),
                    computed.seconds_cell(),
                    steps.to_string(),
                ])?;
                rows.push((kind, releases));
            }
        }
    }
    let counts: Vec<_> = rows
        .iter()
        .map(|(kind, r)| (*kind, r.by_generation(tree.tree())))
        .collect();
    release_table(&counts)?.write(paper_figure_path("airway-tree", "release.csv"))?;
    release_times_table(&rows)?.write(paper_figure_path("airway-tree", "release_times.csv"))?;
    timing.write(paper_figure_path("airway-tree", "release_timing.csv"))?;
    release_figure(tree.tree(), &rows, &format!("{} tree", tree.tree().variant()))
        .write(paper_figure_path("airway-tree", "release.svg"))?;
    let map: Vec<_> = rows.iter().map(|(kind, r)| (*kind, r)).collect();
    release_map(&map, MAP_PARTICLES)?
        .single_precision()?
        .write(paper_figure_path("airway-tree", "release_map.vtp"))?;
    write_release_parquet(
        &map,
        MAP_PARTICLES,
        &paper_figure_path("airway-tree", "release_map.parquet"),
    )?;
    Ok(())
}

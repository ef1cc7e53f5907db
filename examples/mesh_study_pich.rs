//! The mesh study verified where the exact answer is known, solver included (issue 58,
//! item 2): gravitational deposition from laminar flow in a horizontal pipe (Pich 1972) on
//! three meshes of the pipe solved by simpleFoam (`cases/pich-solved/Allrun N DIR`), tracked
//! through `pseudorigid study` at several Pich parameters ε (`studies::pich`).
//!
//! ```text
//! for n in 4 6 9; do cases/pich-solved/Allrun $n target/pich-solved/n$n; done
//! cargo run --release --example mesh_study_pich -- target/pich-solved/n9 target/pich-solved/n6 target/pich-solved/n4 [N]
//! ```
//! N particles per mesh and ε (default 2 000). Writes `pich.csv` (`point,cells_1,cells_2,
//! cells_3,value_1,value_2,value_3,p,extrapolated,gci,exact`: mesh 1 the finest, p the
//! apparent order, `gci` the band in the fraction's units, empty where no order was observed)
//! and `pich.svg` to `paper-figures/mesh-study/` (or `$MESH_STUDY_OUT`), each ε's study
//! (`study.csv`, `study.json`, the runs) under `target/mesh-study-pich/eps<ε>/`.

use pseudorigid::output::{Csv, Figure, Panel, Series};
use pseudorigid::population::mesh_study::MeshStudy;
use pseudorigid::population::{Progress, Shard};
use pseudorigid::scene::load_study;
use pseudorigid::scene::study::{FORMAL_ORDER, StudyOptions, run_study};
use pseudorigid::studies::pich;
use std::path::{Path, PathBuf};

/// Pich parameters of the dataset: deposited fractions from about 0.16 to 0.8.
const EPSILONS: [f64; 3] = [0.1, 0.3, 0.6];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: mesh_study_pich CASE CASE CASE [N]";
    if args.len() < 3 {
        return Err(usage.into());
    }
    let cases: Vec<String> = args[..3]
        .iter()
        .map(|c| std::fs::canonicalize(c).map(|p| p.display().to_string()))
        .collect::<Result<_, _>>()?;
    let count: u64 = args.get(3).map_or(Ok(2_000), |n| n.parse())?;
    let out = std::env::var_os("MESH_STUDY_OUT").map_or_else(
        || Path::new(env!("CARGO_MANIFEST_DIR")).join("paper-figures/mesh-study"),
        PathBuf::from,
    );
    let work = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/mesh-study-pich");
    std::fs::create_dir_all(&out)?;
    let mut csv = Csv::new(&[
        "point",
        "cells_1",
        "cells_2",
        "cells_3",
        "value_1",
        "value_2",
        "value_3",
        "p",
        "extrapolated",
        "gci",
        "exact",
    ]);
    let (mut exact_curve, mut fine, mut extrapolated) = (Vec::new(), Vec::new(), Vec::new());
    for &epsilon in &EPSILONS {
        let dir = work.join(format!("eps{epsilon}"));
        std::fs::create_dir_all(&dir)?;
        let scene = dir.join("study.toml");
        std::fs::write(&scene, pich::scene(&cases, epsilon, count, 1))?;
        let options = StudyOptions {
            checkpoint_every: 30.0,
            resume: true,
            progress: Progress::Auto,
            threads: None,
            csv: false,
            formal_order: FORMAL_ORDER,
        };
        print!("{}", run_study(&load_study(&scene)?, &dir, Shard::ALL, &options)?);
        let study: MeshStudy = serde_json::from_slice(&std::fs::read(dir.join("study.json"))?)?;
        let o = study
            .outcomes
            .iter()
            .find(|o| o.outcome == "deposited:wall")
            .ok_or("no particle deposited on the wall")?;
        let exact = pich::exact(epsilon)?;
        let e = o.estimate.as_ref();
        let cell = |v: Option<f64>| v.map_or(String::new(), |x| format!("{x:.6}"));
        let mut row = vec![epsilon.to_string()];
        row.extend(study.meshes.iter().map(|m| m.cells.to_string()));
        row.extend(o.values.iter().map(|v| format!("{v:.6}")));
        row.extend([
            cell(e.and_then(|e| e.p_apparent)),
            cell(e.map(|e| e.extrapolated)),
            cell(e.map(|e| e.band)),
            format!("{exact:.6}"),
        ]);
        csv.push(row)?;
        println!(
            "eps = {epsilon}: exact {exact:.4}; {}",
            e.map_or("no estimate".into(), |e| format!(
                "extrapolated {:.4} ± {:.4}: |extrapolated − exact| = {:.4} {} GCI",
                e.extrapolated,
                e.band,
                (e.extrapolated - exact).abs(),
                if (e.extrapolated - exact).abs() <= e.band {
                    "<="
                } else {
                    ">"
                }
            ))
        );
        fine.push((epsilon, o.values[0]));
        if let Some(e) = e {
            extrapolated.push((epsilon, e.extrapolated));
        }
    }
    for k in 1..=60 {
        let epsilon = k as f64 / 60.0 * 0.7;
        exact_curve.push((epsilon, pich::exact(epsilon)?));
    }
    csv.write(out.join("pich.csv"))?;
    Figure::single(
        Panel::new(
            "Pich (1972) deposition on simpleFoam meshes",
            "epsilon = (3/4)(L/d)(v_s/U)",
            "deposited fraction",
        )
        .with(Series::line("Pich (1972)", exact_curve, 0))
        .with(Series::points("finest mesh", fine, 1))
        .with(Series::points("extrapolated (three meshes)", extrapolated, 2)),
    )
    .write(out.join("pich.svg"))?;
    println!("pich.csv and pich.svg in {}", out.display());
    Ok(())
}

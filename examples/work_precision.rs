//! Work-precision diagrams of every integrator on the three reference problems of
//! `studies::work_precision`. Writes `paper-figures/work-precision/work_precision.csv` and
//! `work_precision.svg`, beside the SciPy peer (`benches/peers/inertialess.py`, rows
//! `scipy_radau` / `scipy_lsoda`), and the peer's wall time over the fastest library
//! integrator's at equal error in `peer_ratios.csv`.
//!
//! Run: `cargo run --release --example work_precision`
//! (Python from `PSEUDORIGID_PYTHON`, default `python3`; without NumPy/SciPy the peer rows are
//! skipped with a message.)

use pseudorigid::output::{Csv, Figure, Panel, Series};
use pseudorigid::studies::scipy_peer::Peer;
use pseudorigid::studies::work_precision::{
    RATIO_ERRORS, Record, ReferenceProblem, error_floor, has_peer, measure, oblate_reference, peer_ratios, sweep,
    work_at_error,
};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let start = Instant::now();
    let reference = oblate_reference()?;
    let peer = Peer::from_env().check();
    // The error floor of each case the peer runs: its measure applied to the peer's
    // high-accuracy run.
    let mut floors: Vec<(ReferenceProblem, f64)> = Vec::new();
    match &peer {
        Ok(()) => {
            for case in [
                ReferenceProblem::Jeffery,
                ReferenceProblem::TankTreading,
                ReferenceProblem::Oblate,
            ]
            .into_iter()
            .filter(|&c| has_peer(c))
            {
                let floor = error_floor(case, Some(&reference))?;
                println!("{} error floor (SciPy DOP853 at 1e-13): {floor:.3e}", case.name());
                floors.push((case, floor));
            }
        }
        Err(e) => println!("skipping the SciPy peer rows: {e}"),
    }
    let mut records: Vec<Record> = Vec::new();
    for case in [
        ReferenceProblem::Jeffery,
        ReferenceProblem::TankTreading,
        ReferenceProblem::Oblate,
    ] {
        for setting in sweep(case).into_iter().filter(|s| s.peer().is_none() || peer.is_ok()) {
            let rec = match measure(case, setting, Some(&reference)) {
                Ok(rec) => rec,
                Err(e) => {
                    println!(
                        "{:14} {:14} {:9.2e}  FAILED: {e}",
                        case.name(),
                        setting.integrator(),
                        setting.value()
                    );
                    continue;
                }
            };
            println!(
                "{:14} {:14} {:9.2e}  error {:9.3e}  wall {:8.4} s  steps {:8}  rhs {:9}",
                case.name(),
                setting.integrator(),
                setting.value(),
                rec.error,
                rec.wall_s,
                rec.stats.steps,
                rec.stats.rhs_evals
            );
            records.push(rec);
        }
    }

    let mut csv = Csv::new(&[
        "case",
        "integrator",
        "setting",
        "error",
        "wall_s",
        "steps",
        "rhs_evals",
        "jac_evals",
    ]);
    for r in &records {
        csv.push(vec![
            r.case.name().into(),
            r.setting.integrator().into(),
            format!("{:e}", r.setting.value()),
            format!("{:.6e}", r.error),
            format!("{:.6e}", r.wall_s),
            r.stats.steps.to_string(),
            r.stats.rhs_evals.to_string(),
            r.stats.jac_evals.to_string(),
        ])?;
    }
    csv.write(pseudorigid::output::paper_figure_path(
        "work-precision",
        "work_precision.csv",
    ))?;

    let mut integrators: Vec<&str> = Vec::new();
    for r in &records {
        if !integrators.contains(&r.setting.integrator()) {
            integrators.push(r.setting.integrator());
        }
    }
    let mut panels = Vec::new();
    for case in [
        ReferenceProblem::Jeffery,
        ReferenceProblem::TankTreading,
        ReferenceProblem::Oblate,
    ] {
        for (x_label, wall) in [("log10 wall time [s]", true), ("log10 model evaluations", false)] {
            let mut panel = Panel::new(case.name(), x_label, "log10 error");
            for (color, name) in integrators.iter().enumerate() {
                let pts: Vec<(f64, f64)> = records
                    .iter()
                    .filter(|r| r.case == case && r.setting.integrator() == *name && r.error > 0.0)
                    .map(|r| {
                        let x = if wall {
                            r.wall_s.max(1e-6)
                        } else {
                            r.stats.rhs_evals as f64
                        };
                        (x.log10(), r.error.log10())
                    })
                    .collect();
                if !pts.is_empty() {
                    panel = panel.with(Series::line(*name, pts, color));
                }
            }
            panels.push(panel);
        }
    }
    Figure::grid(panels, 2, (520, 380)).write(pseudorigid::output::paper_figure_path(
        "work-precision",
        "work_precision.svg",
    ))?;

    // Equal error: the best error each inertial scheme reaches on the oblate case, and the
    // work the inertialess integrator needs for the same error.
    for name in ["imex_paper", "imex_adaptive"] {
        let best = records
            .iter()
            .filter(|r| r.case == ReferenceProblem::Oblate && r.setting.integrator() == name)
            .min_by(|a, b| a.error.total_cmp(&b.error));
        if let Some(best) = best
            && let Some((evals, wall)) = work_at_error(&records, ReferenceProblem::Oblate, "rosenbrock_w23", best.error)
        {
            println!(
                "oblate, error {:.2e}: {name} {} evaluations / {:.3} s; rosenbrock_w23 {:.0} / {:.4} s → {:.0}x fewer evaluations, {:.0}x less time",
                best.error,
                best.stats.rhs_evals,
                best.wall_s,
                evals,
                wall,
                best.stats.rhs_evals as f64 / evals,
                best.wall_s / wall
            );
        }
    }
    // The library against the SciPy peer at equal error, on levels at least 10× above the
    // case's error floor (below it both curves measure the reference, not the integrator).
    if !floors.is_empty() {
        println!("peer wall time / fastest library wall time at equal error");
        let mut csv = Csv::new(&[
            "case",
            "error",
            "best_integrator",
            "library_wall_s",
            "peer",
            "peer_wall_s",
            "ratio",
        ]);
        let rows = floors.iter().flat_map(|&(case, floor)| {
            let levels: Vec<f64> = RATIO_ERRORS.into_iter().filter(|&e| e >= 10.0 * floor).collect();
            peer_ratios(&records, case, &levels)
        });
        for r in rows {
            println!(
                "  {:14} error {:7.0e}: {:13} {:9.3e} s  {:12} {:9.3e} s  ratio {:7.1}",
                r.case.name(),
                r.error,
                r.best_integrator,
                r.library_wall_s,
                r.peer,
                r.peer_wall_s,
                r.ratio
            );
            csv.push(vec![
                r.case.name().into(),
                format!("{:e}", r.error),
                r.best_integrator.into(),
                format!("{:.6e}", r.library_wall_s),
                r.peer.into(),
                format!("{:.6e}", r.peer_wall_s),
                format!("{:.4e}", r.ratio),
            ])?;
        }
        csv.write(pseudorigid::output::paper_figure_path(
            "work-precision",
            "peer_ratios.csv",
        ))?;
    }
    println!("work_precision finished in {:.1} s", start.elapsed().as_secs_f64());
    Ok(())
}

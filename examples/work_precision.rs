//! Work-precision diagrams of every integrator on the three reference problems of
//! `scenes::work_precision`. Writes `paper-figures/work-precision/work_precision.csv` and
//! `work_precision.svg`.
//!
//! Run: `cargo run --release --example work_precision`

use pseudorigid::output::{Csv, Figure, Panel, Series};
use pseudorigid::scenes::work_precision::{Case, Record, Setting, measure, oblate_reference, work_at_error};
use std::time::Instant;

const RHO_STAR: f64 = 0.01;

fn settings(case: Case) -> Vec<Setting> {
    let mut s: Vec<Setting> = [80.0, 160.0, 320.0, 640.0]
        .iter()
        .map(|d| Setting::ImexPaper(RHO_STAR / d))
        .collect();
    s.extend([1e-3, 1e-4, 1e-5, 1e-6].map(Setting::ImexAdaptive));
    s.extend([1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9].map(Setting::Stokesian));
    if case == Case::Jeffery {
        s.extend([1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10].map(Setting::Rigid));
    }
    s
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let start = Instant::now();
    let reference = oblate_reference()?;
    let mut records: Vec<Record> = Vec::new();
    for case in [Case::Jeffery, Case::TankTreading, Case::Oblate] {
        for setting in settings(case) {
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
    csv.write("paper-figures/work-precision/work_precision.csv")?;

    let integrators = ["imex_paper", "imex_adaptive", "stokesian", "rigid"];
    let mut panels = Vec::new();
    for case in [Case::Jeffery, Case::TankTreading, Case::Oblate] {
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
    Figure::grid(panels, 2, (520, 380)).write("paper-figures/work-precision/work_precision.svg")?;

    // Equal error: the best error each inertial scheme reaches on the oblate case, and the
    // work the inertialess integrator needs for the same error.
    for name in ["imex_paper", "imex_adaptive"] {
        let best = records
            .iter()
            .filter(|r| r.case == Case::Oblate && r.setting.integrator() == name)
            .min_by(|a, b| a.error.total_cmp(&b.error));
        if let Some(best) = best
            && let Some((evals, wall)) = work_at_error(&records, Case::Oblate, "stokesian", best.error)
        {
            println!(
                "oblate, error {:.2e}: {name} {} evaluations / {:.3} s; stokesian {:.0} / {:.4} s → {:.0}x fewer evaluations, {:.0}x less time",
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
    println!("work_precision finished in {:.1} s", start.elapsed().as_secs_f64());
    Ok(())
}

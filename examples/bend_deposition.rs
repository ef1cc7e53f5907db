//! Inertial deposition of spheres in a 90° bend (Re = 1000, R_o/a = 5.6) against Pui,
//! Romay-Novas & Liu (1987): DE against Stk with binomial errors beside the reference.
//!
//! ```text
//! cargo run --release --example bend_deposition -- [--tol T] [--residence-times R] [--no-blend] [N] [CASE_DIR] [STK...]
//! ```
//! The options change the dataset's [`Settings`] to measure their effect (same particles).
//! N spheres per Stokes number (default 2 000), tracked through the solved case `CASE_DIR`
//! (default `target/bend/case`, made by `cases/bend/Allrun` with its default mesh if it has no
//! `bend.summary`) at the Stokes numbers [`STOKES`] (or those given). Set-up and definitions:
//! `pseudorigid::scenes::bend`. Writes `deposition.csv` (`stk,n_injected,n_deposited,de,
//! de_stderr,reference_de`), `fates.csv` (every fate per Stk) and `deposition.svg` to
//! `paper-figures/bend/`, or to the folder `$BEND_OUT` if set (the CI check's reduced study).

use pseudorigid::population::RunOptions;
use pseudorigid::scenes::bend::{BendCase, SEED, Settings, deposition_figure, deposition_table};
use std::path::PathBuf;
use std::process::Command;
use std::time::Instant;

/// The dataset's Stokes numbers: the rise of the reference from 5 % to 99.98 %.
const STOKES: [f64; 8] = [0.05, 0.08, 0.1, 0.15, 0.2, 0.3, 0.5, 1.0];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut settings = Settings::default();
    let mut value = |flag: &str| -> Result<Option<f64>, Box<dyn std::error::Error>> {
        match args.iter().position(|a| a == flag) {
            None => Ok(None),
            Some(i) if i + 1 < args.len() => {
                let v = args[i + 1].parse()?;
                args.drain(i..=i + 1);
                Ok(Some(v))
            }
            Some(_) => Err(format!("{flag} needs a value").into()),
        }
    };
    if let Some(t) = value("--tol")? {
        settings.tol = t;
    }
    if let Some(r) = value("--residence-times")? {
        settings.residence_times = r;
    }
    if let Some(i) = args.iter().position(|a| a == "--no-blend") {
        settings.blend = false;
        args.remove(i);
    }
    let n: u64 = args.first().map(|s| s.parse()).transpose()?.unwrap_or(2000);
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let dir = args
        .get(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target/bend/case"));
    let stokes: Vec<f64> = if args.len() > 2 {
        args[2..].iter().map(|s| s.parse()).collect::<Result<_, _>>()?
    } else {
        STOKES.to_vec()
    };
    if !dir.join("bend.summary").is_file() {
        let status = Command::new("sh")
            .arg(root.join("cases/bend/Allrun"))
            .arg(&dir)
            .status()?;
        if !status.success() {
            return Err(format!("cases/bend/Allrun {}: {status}", dir.display()).into());
        }
    }
    let case = BendCase::open(&dir)?;
    let out = std::env::var_os("BEND_OUT").map_or_else(|| root.join("paper-figures/bend"), PathBuf::from);
    std::fs::create_dir_all(&out)?;
    println!("{settings:?}");
    println!(
        "bend: {} cells, Re = {:.1}, U = {:.4} m/s, residence time {:.4} s",
        case.cells,
        case.reynolds(),
        case.mean_velocity,
        case.residence_time
    );
    let mut rows = Vec::new();
    let mut fates = String::from("stk,d_m,n_injected,bend,tubes,escaped,suspended,failed,wall_s\n");
    for &stk in &stokes {
        let start = Instant::now();
        let row = case.run(stk, n, SEED, settings, RunOptions::default().quiet())?;
        let wall = start.elapsed().as_secs_f64();
        println!(
            "Stk {stk}: d = {:.3} µm, DE = {:.4} ± {:.4} (reference {:.4}); tubes {}, escaped {}, suspended {}, failed {}; {wall:.0} s",
            1e6 * case.diameter_for_stokes(stk)?,
            row.de(),
            row.stderr(),
            row.reference()?,
            row.tubes,
            row.escaped,
            row.suspended,
            row.failed
        );
        fates.push_str(&format!(
            "{stk},{:e},{},{},{},{},{},{},{wall:.1}\n",
            case.diameter_for_stokes(stk)?,
            row.injected,
            row.bend,
            row.tubes,
            row.escaped,
            row.suspended,
            row.failed
        ));
        rows.push(row);
    }
    deposition_table(&rows)?.write(out.join("deposition.csv"))?;
    std::fs::write(out.join("fates.csv"), fates)?;
    deposition_figure(
        &rows,
        &format!("90° bend, Re = {:.0}, R_o/a = 5.6: N = {n} per Stk", case.reynolds()),
    )
    .write(out.join("deposition.svg"))?;
    Ok(())
}

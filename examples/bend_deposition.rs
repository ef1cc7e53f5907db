//! Inertial deposition of spheres in a 90° bend (Re = 1000, R_o/a = 5.6) against Pui,
//! Romay-Novas & Liu (1987): DE against Stk with binomial errors beside the reference.
//!
//! ```text
//! cargo run --release --example bend_deposition -- [--tol T] [--residence-times R] [--no-blend] [--point-contact | --contact-radius R] [--lift] [N] [CASE_DIR] [STK...]
//! ```
//! The options change the dataset's [`Settings`] to measure their effect (same particles);
//! `--lift` adds Schiller–Naumann drag and Saffman–Mei lift (`particles.forces`).
//!
//! `--peer`: instead, OpenFOAM's own tracker (`benches/peers/openfoam_tracker/run.sh`:
//! `icoUncoupledKinematicParcelFoam`, sphereDrag in its Stokes limit, cellPoint interpolation,
//! no gravity, the same tracking time) follows the same N spheres per Stk (drawn by the scene's
//! injector, written as `particles.csv` in `target/bend-peer/<cells>_stk<STK>/`), and the fates
//! are paired one by one (`population::peer`): deposition on the bend's wall by both, by one,
//! by neither. Output: `peer_<cells>_stk<STK>.csv` (columns `cells,stk,n,both,only_ours,
//! only_openfoam,neither,de_ours,de_openfoam,de_difference,se_paired,mcnemar_chi2,ours_tubes,
//! ours_escaped,ours_suspended,ours_failed,openfoam_tubes,openfoam_escaped,openfoam_suspended,
//! openfoam_not_injected,wall_ours_s,wall_openfoam_s`) in the output folder and `pairs.csv`
//! (per particle) in the work folder.
//! N spheres per Stokes number (default 2 000), tracked through the solved case `CASE_DIR`
//! (default `target/bend/case`, made by `cases/bend/Allrun` with its default mesh if it has no
//! `bend.summary`) at the Stokes numbers [`STOKES`] (or those given). Set-up and definitions:
//! `pseudorigid::studies::bend`. Writes `deposition.csv` (`stk,n_injected,n_deposited,de,
//! de_stderr,reference_de`), `fates.csv` (every fate per Stk) and `deposition.svg` to
//! `paper-figures/bend/`, or to the folder `$BEND_OUT` if set (the CI check's reduced study).

use pseudorigid::population::peer::{Pairing, paired_with_peer};
use pseudorigid::population::{Fate, RunOptions};
use pseudorigid::studies::bend::{
    BendCase, SEED, Settings, deposition_figure, deposition_table, on_bend_wall, peer_on_bend_wall,
};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
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
    if let Some(r) = value("--contact-radius")? {
        settings.contact_radius = Some(r);
    }
    if let Some(r) = value("--residence-times")? {
        settings.residence_times = r;
    }
    if let Some(i) = args.iter().position(|a| a == "--no-blend") {
        settings.blend = false;
        args.remove(i);
    }
    if let Some(i) = args.iter().position(|a| a == "--lift") {
        settings.forces = &["schiller_naumann", "saffman_mei"];
        args.remove(i);
    }
    if let Some(i) = args.iter().position(|a| a == "--point-contact") {
        settings.contact_radius = Some(0.0);
        args.remove(i);
    }
    let peer = args
        .iter()
        .position(|a| a == "--peer")
        .map(|i| args.remove(i))
        .is_some();
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
    if peer {
        for &stk in &stokes {
            compare_with_openfoam(&case, &root, &out, stk, n)?;
        }
        return Ok(());
    }
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

/// `--peer`: OpenFOAM's tracker and ours on the same `n` spheres of Stokes number `stk`.
fn compare_with_openfoam(
    case: &BendCase,
    root: &Path,
    out: &Path,
    stk: f64,
    n: u64,
) -> Result<(), Box<dyn std::error::Error>> {
    let name = format!("{}_stk{stk}", case.cells);
    let work = root.join("target/bend-peer").join(&name);
    let particles = case.peer_particles(stk, n, SEED)?;
    let peer = case
        .openfoam_tracker(root, Settings::default())?
        .run(&case.dir, &particles, &work)?;
    let wall_openfoam = peer.summary.wall_seconds;

    let start = Instant::now();
    let ours = case.run_output(stk, n, SEED, Settings::default(), RunOptions::default().quiet())?;
    let wall_ours = start.elapsed().as_secs_f64();

    let mut pairing = Pairing::default();
    let mut counts = [0u64; 8];
    let mut pairs = String::from("index,ours,ours_patch,openfoam,openfoam_patch,openfoam_t\n");
    for (r, p) in paired_with_peer(&ours.records, &peer.fates)? {
        let patch = r.fate.patch().map_or("", |i| ours.patches[i].as_str());
        let ours_bend = on_bend_wall(r, &ours.patches);
        let peer_bend = peer_on_bend_wall(p);
        pairing.add(ours_bend, peer_bend);
        match (&r.fate, ours_bend) {
            (Fate::Deposited { .. }, false) => counts[0] += 1,
            (Fate::Escaped { .. }, _) => counts[1] += 1,
            (Fate::Suspended, _) => counts[2] += 1,
            (Fate::Failed { .. }, _) => counts[3] += 1,
            _ => {}
        }
        match p.fate.as_str() {
            "deposited" if !peer_bend => counts[4] += 1,
            "escaped" => counts[5] += 1,
            "suspended" => counts[6] += 1,
            "not_injected" => counts[7] += 1,
            _ => {}
        }
        writeln!(
            pairs,
            "{},{},{patch},{},{},{}",
            r.index,
            r.fate.label(),
            p.fate,
            p.patch,
            p.t
        )?;
    }
    std::fs::write(work.join("pairs.csv"), pairs)?;
    let m = pairing.n() as f64;
    let de_ours = (pairing.both + pairing.only_ours) as f64 / m;
    let de_of = (pairing.both + pairing.only_peer) as f64 / m;
    let (diff, se) = pairing.difference();
    let header = "cells,stk,n,both,only_ours,only_openfoam,neither,de_ours,de_openfoam,de_difference,se_paired,mcnemar_chi2,ours_tubes,ours_escaped,ours_suspended,ours_failed,openfoam_tubes,openfoam_escaped,openfoam_suspended,openfoam_not_injected,wall_ours_s,wall_openfoam_s";
    let row = format!(
        "{},{stk},{n},{},{},{},{},{de_ours:.5},{de_of:.5},{diff:.5},{se:.5},{:.3},{},{},{},{},{},{},{},{},{wall_ours:.1},{wall_openfoam:.1}",
        case.cells,
        pairing.both,
        pairing.only_ours,
        pairing.only_peer,
        pairing.neither,
        pairing.mcnemar_chi2(),
        counts[0],
        counts[1],
        counts[2],
        counts[3],
        counts[4],
        counts[5],
        counts[6],
        counts[7]
    );
    std::fs::write(out.join(format!("peer_{name}.csv")), format!("{header}\n{row}\n"))?;
    println!("{header}\n{row}");
    Ok(())
}

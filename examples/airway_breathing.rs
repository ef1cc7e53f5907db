//! Issue 24, item 3: a breathing cycle in the airway bifurcation. Particles inhaled with a
//! sinusoidal flow rate (T = 4 s, the mean inspiratory flow of the steady Re = 500 case,
//! Womersley number 0.97) through the pimpleFoam field of `cases/bifurcation-breathing`,
//! against the steady field on the same particles.
//!
//! ```text
//! nice -n 10 cases/bifurcation-breathing/Allrun /tmp/breath
//! cargo run --release --example airway_breathing -- [N] [BREATH_CASE] [STEADY_RE785_CASE]
//! ```
//! N particles per point (default 100 000; also `PSEUDORIGID_BREATH_N`); BREATH_CASE the
//! solved inhalation (default `PSEUDORIGID_BREATH_CASE`, else `/tmp/breath`); optionally a
//! simpleFoam solution of the same mesh at the peak Reynolds number, for the quasi-steady check.
//! Points: spheres, rigid and Neo-Hookean μ_s = 0.5 Pa, Stk 0.1 and 0.4 (the steady Stk, G3's
//! U and D). Writes `paper-figures/airway-breathing/`: `de.csv` (steady and cyclic DE with
//! binomial errors), `paired.csv` (the same particles steady and cyclic, McNemar),
//! `by_phase.csv` (DE by injection time), `deposits.csv` and `breathing.svg` (deposition maps
//! steady vs cyclic, DE by injection time), `flow_rates.csv` (the solution's conservation
//! against the prescribed inlet), `field_check.csv` (the field against steady solutions at the
//! same Reynolds number) and `timing.csv`; with `PSEUDORIGID_BREATH_QUASI_N=M`, also
//! `quasi_steady.csv`: the rigid points' first M particles through the steady field scaled by
//! the flow rate (the breath without the flow's change of shape). Finished runs are kept in the bifurcation studies'
//! cache (`target/bifurcation-runs`, or `PSEUDORIGID_BIF_CACHE`) and read back.

use pseudorigid::flow::openfoam::FoamCase;
use pseudorigid::output::{Csv, paper_figure_path};
use pseudorigid::population::RunOptions;
use pseudorigid::studies::bifurcation::breathing::{
    self, Breath, BreathingPair, Waveform, de_table, field_difference, flow_rate_table, map_table, paired_table,
    phase_table,
};
use pseudorigid::studies::bifurcation::{Airway, Kind, Material, StudyRun, figures};
use pseudorigid::studies::count_and_case;
use pseudorigid::studies::particles::Shape;
use std::path::PathBuf;
use std::time::Instant;

/// Bins of the injection time over the inhalation (0.2 s each).
const PHASE_BINS: usize = 10;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (n, dir) = count_and_case("PSEUDORIGID_BREATH_N", figures::DEFAULT_N)?;
    let dir = dir
        .or_else(|| std::env::var_os("PSEUDORIGID_BREATH_CASE").map(PathBuf::from))
        .unwrap_or_else(|| PathBuf::from("/tmp/breath"));
    let peak_case = std::env::args().nth(3).map(PathBuf::from);
    let waveform = Waveform::rest();
    let airway = Airway::open(Airway::shipped_dir())?;
    let clock = Instant::now();
    let mut breath = Breath::open(&dir, waveform)?;
    eprintln!(
        "breath {}: {} levels, windows {}, Womersley {:.3}, opened in {:.1} s",
        dir.display(),
        breath.flow().levels().len(),
        breath.windows().len() - 1,
        breathing::womersley_number(),
        clock.elapsed().as_secs_f64()
    );
    let out = |file: &str| paper_figure_path("airway-breathing", file);
    flow_rate_table(&dir, &airway, waveform)?.write(out("flow_rates.csv"))?;
    field_check(&dir, peak_case, waveform)?.write(out("field_check.csv"))?;

    let cache = figures::cache_dir()?;
    std::fs::create_dir_all(&cache)?;
    let mut pairs = Vec::new();
    let mut timing = Csv::new(&["shape", "mu_s", "stk", "flow", "n", "seconds", "steps"]);
    for stokes in [0.1, 0.4] {
        for material in [Material::Rigid, Material::ShearModulus(0.5)] {
            let kind = Kind {
                shape: Shape::Sphere,
                material,
                stokes,
            };
            let steady = figures::run_cached(StudyRun::new(&airway, kind, n))?;
            let cyclic = breathing::run_inhaled(
                &airway,
                &mut breath,
                kind,
                n,
                figures::SEED,
                &RunOptions::default().quiet(),
                Some(&cache),
            )?;
            for (flow, run) in [("steady", &steady), ("cyclic", &cyclic)] {
                let steps: u64 = run.output.records.iter().map(|r| r.stats.steps).sum();
                eprintln!(
                    "{kind:?} {flow}: {:?} in {} ({steps} steps)",
                    run.output.counts(),
                    run.time_label()
                );
                timing.push(vec![
                    kind.shape.label(),
                    material.label(),
                    stokes.to_string(),
                    flow.into(),
                    n.to_string(),
                    run.seconds_cell(),
                    steps.to_string(),
                ])?;
            }
            pairs.push(BreathingPair::new(
                &airway,
                kind,
                waveform,
                figures::SEED,
                steady.output,
                cyclic.output,
            )?);
        }
    }
    de_table(&pairs)?.write(out("de.csv"))?;
    paired_table(&pairs)?.write(out("paired.csv"))?;
    phase_table(&pairs, waveform, PHASE_BINS)?.write(out("by_phase.csv"))?;
    map_table(&pairs)?.write(out("deposits.csv"))?;
    breathing::figure(&pairs, waveform, PHASE_BINS).write(out("breathing.svg"))?;
    timing.write(out("timing.csv"))?;
    if let Ok(m) = std::env::var("PSEUDORIGID_BREATH_QUASI_N") {
        quasi_steady(&airway, &pairs, m.parse()?)?.write(out("quasi_steady.csv"))?;
    }
    Ok(())
}

/// The rigid points once more, the first `m` particles, through the quasi-steady breath: the
/// shipped Re = 500 field scaled by U_in(t)/U at the levels of the pimpleFoam case (the flow's
/// shape never changes; α → 0 at fixed Re), beside the steady and pimpleFoam runs of the same
/// particles. Columns `shape,mu_s,stk,n,de_steady,de_quasi_steady,de_cyclic` with their
/// binomial standard errors.
fn quasi_steady(airway: &Airway, pairs: &[BreathingPair], m: u64) -> Result<Csv, Box<dyn std::error::Error>> {
    use pseudorigid::population::Fate;
    use pseudorigid::population::binomial::{fraction, stderr};
    let waveform = Waveform::rest();
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("target/breath-quasi-steady");
    // Every 50 ms (80 levels a period): linear interpolation in time errs by π²/(2·80²) = 8e-4
    // of the amplitude.
    let times: Vec<f64> = (0..=40).map(|k| 0.05 * f64::from(k)).collect();
    breathing::write_quasi_steady(&Airway::shipped_dir(), &dir, waveform, &times)?;
    let mut breath = Breath::open(&dir, waveform)?;
    let mut csv = Csv::new(&[
        "shape",
        "mu_s",
        "stk",
        "n",
        "de_steady",
        "de_steady_stderr",
        "de_quasi_steady",
        "de_quasi_steady_stderr",
        "de_cyclic",
        "de_cyclic_stderr",
    ]);
    for p in pairs.iter().filter(|p| p.kind.material == Material::Rigid) {
        let q = breathing::run_inhaled(
            airway,
            &mut breath,
            p.kind,
            m,
            figures::SEED,
            &RunOptions::default().quiet(),
            Some(&figures::cache_dir()?),
        )?;
        let count = |records: &[pseudorigid::population::ParticleRecord<_>]| {
            records
                .iter()
                .take(m as usize)
                .filter(|r| matches!(r.fate, Fate::Deposited { .. }))
                .count() as u64
        };
        let (ds, dq, dc) = (
            count(&p.steady.records),
            count(&q.output.records),
            count(&p.cyclic.records),
        );
        eprintln!(
            "{:?} quasi-steady: {:?} in {}",
            p.kind,
            q.output.counts(),
            q.time_label()
        );
        let mut row = vec![
            p.kind.shape.label(),
            "inf".into(),
            p.kind.stokes.to_string(),
            m.to_string(),
        ];
        for d in [ds, dq, dc] {
            row.push(format!("{:.5}", fraction(d, m)));
            row.push(format!("{:.5}", stderr(d, m)));
        }
        csv.push(row)?;
    }
    Ok(csv)
}

/// The solution against steady ones at the same Reynolds number: the level at which the inlet
/// velocity is nearest the steady U (t ≈ 0.44 s, accelerating, and ≈ 1.56 s, decelerating)
/// against the shipped Re = 500 field scaled to that level's inlet velocity, and, with
/// `peak_case`, the peak level (t = 1 s) against a steady solution at Re = 785.
fn field_check(
    dir: &std::path::Path,
    peak_case: Option<PathBuf>,
    waveform: Waveform,
) -> Result<Csv, Box<dyn std::error::Error>> {
    let case = FoamCase::open(dir)?;
    let shipped = FoamCase::open(Airway::shipped_dir())?;
    let mut csv = Csv::new(&["t", "u_in_over_u", "reference", "scale", "rel_l2", "rel_max"]);
    let times = case.times();
    let nearest = |target: f64, lo: f64, hi: f64| {
        times.iter().copied().filter(|&t| t > lo && t < hi).min_by(|a, b| {
            (waveform.scale(*a) - target)
                .abs()
                .total_cmp(&(waveform.scale(*b) - target).abs())
        })
    };
    let half = 0.5 * waveform.duration();
    for t in [nearest(1.0, 0.0, half), nearest(1.0, half, waveform.duration())]
        .into_iter()
        .flatten()
    {
        let s = waveform.scale(t);
        let (l2, max) = field_difference(&case, t, &shipped, s)?;
        csv.push(vec![
            format!("{t}"),
            format!("{s:.5}"),
            "simpleFoam Re 500 (shipped), scaled".into(),
            format!("{s:.5}"),
            format!("{l2:.4e}"),
            format!("{max:.4e}"),
        ])?;
    }
    if let Some(peak) = peak_case
        && let Some(t) = nearest(0.5 * std::f64::consts::PI, 0.0, waveform.duration())
    {
        let s = waveform.scale(t) / (0.5 * std::f64::consts::PI);
        let (l2, max) = field_difference(&case, t, &FoamCase::open(&peak)?, s)?;
        csv.push(vec![
            format!("{t}"),
            format!("{:.5}", waveform.scale(t)),
            "simpleFoam Re 785.4 (peak)".into(),
            format!("{s:.5}"),
            format!("{l2:.4e}"),
            format!("{max:.4e}"),
        ])?;
    }
    Ok(csv)
}

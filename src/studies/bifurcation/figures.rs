//! What the figure examples share: arguments, the Stokes numbers of each figure, the loops over
//! particle kinds, the datasets and the pictures.

use super::BifurcationError;
use super::deposition::{Deposit, deposits};
#[cfg(feature = "plot")]
use super::deposition::{histogram, histogram_table, map_table, summary_table};
use super::injection::Kind;
use super::setup::{Airway, zhang_reference};
use super::study::{Efficiency, StudyRun, banded_efficiency_table, efficiency_table};
use crate::material::NeoHooke;
use crate::output::paper_figure_path;
use crate::output::vtk::{PointValues, PolyData};
use crate::output::{Figure, Panel, Series};
use crate::population::RunOptions;
use crate::population::binomial::Pairing;
use crate::population::mesh_study::{FORMAL_ORDER, MeshRun, MeshStudy};
use crate::population::{Computed, RunOutput, paired};
use std::path::{Path, PathBuf};

/// Stokes numbers of Fig. 18 (the paper's range 0.005–0.5).
pub const FIG18_STOKES: [f64; 10] = [0.005, 0.01, 0.02, 0.04, 0.06, 0.08, 0.1, 0.2, 0.3, 0.5];

/// Stokes numbers of Fig. 18 that carry a mesh-study band when the example is given other
/// meshes: from 0.1 up, where the wall layer and the carina decide DE and the mesh's error
/// is of the size of DE's changes (the four-mesh runs: 0.004–0.026); below, DE ≤ 0.06 and a
/// band costs a fine-mesh run per point for an error below the binomial one.
pub const FIG18_BAND_STOKES: [f64; 4] = [0.1, 0.2, 0.3, 0.5];

pub use super::study::SEED;

/// Particles per kind when neither the command line nor `PSEUDORIGID_BIF_N` says (paper: 10⁵).
pub const DEFAULT_N: u64 = 100_000;

/// `[N] [CASE_DIR]` from the command line: N particles per kind (else `PSEUDORIGID_BIF_N`,
/// else [`DEFAULT_N`]) in the case `CASE_DIR` (else the shipped field).
pub fn arguments() -> Result<(u64, Airway), Box<dyn std::error::Error>> {
    let (n, dir) = crate::studies::count_and_case("PSEUDORIGID_BIF_N", DEFAULT_N)?;
    Ok((n, Airway::open(dir.unwrap_or_else(Airway::shipped_dir))?))
}

/// `[N] [CASE_DIR] [--band MESH_DIR...]`: N as in [`arguments`], and the case folders: first
/// `CASE_DIR` (else the shipped field), then the other solutions of the same airway that a
/// mesh study pairs with it (none without `--band`).
pub fn arguments_and_band() -> Result<(u64, Vec<PathBuf>), std::num::ParseIntError> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let split = args.iter().position(|a| a == "--band").unwrap_or(args.len());
    let (n, dir) = crate::studies::count_and_case_of(&args[..split], "PSEUDORIGID_BIF_N", DEFAULT_N)?;
    let mut dirs = vec![dir.unwrap_or_else(Airway::shipped_dir)];
    dirs.extend(args.get(split + 1..).unwrap_or_default().iter().map(PathBuf::from));
    Ok((n, dirs))
}

/// The cell size H (m) and the prism layers of a case, from the `cell_size=0.3e-3` and
/// `layers=2` lines that `cases/bifurcation/Allrun` writes to its `log.summary` (a summary
/// without `layers` predates the option: 2 layers).
pub fn case_summary(dir: &Path) -> Result<(f64, u32), std::io::Error> {
    let summary = std::fs::read_to_string(dir.join("log.summary"))?;
    let value = |key: &str| summary.lines().find_map(|l| l.strip_prefix(key)).map(str::trim);
    let bad = |what: String| std::io::Error::new(std::io::ErrorKind::InvalidData, format!("{}: {what}", dir.display()));
    let h = value("cell_size=").ok_or_else(|| bad("no cell_size in log.summary".into()))?;
    let layers = value("layers=").unwrap_or("2");
    Ok((
        h.parse()
            .map_err(|e| bad(format!("cell_size {h:?} in log.summary: {e}")))?,
        layers
            .parse()
            .map_err(|e| bad(format!("layers {layers:?} in log.summary: {e}")))?,
    ))
}

/// `h=0.3mm layers=2` ([`case_summary`]), ` (shipped)` added for the shipped field.
pub fn case_label(dir: &Path) -> Result<String, std::io::Error> {
    let (h, layers) = case_summary(dir)?;
    let shipped = if dir == Airway::shipped_dir() { " (shipped)" } else { "" };
    Ok(format!("h={}mm layers={layers}{shipped}", millimetres(h)))
}

/// A cell size H (m) in millimetres as `Allrun` was given it: H·10³ rounded to the micrometre,
/// so that 0.12e-3 prints as `0.12`, not `0.12000000000000001`.
pub fn millimetres(h: f64) -> f64 {
    (h * 1e6).round() / 1e3
}

/// Open each case of `dirs`, labelled by [`case_label`].
pub fn open_cases(dirs: &[PathBuf]) -> Result<Vec<(String, Airway)>, Box<dyn std::error::Error>> {
    dirs.iter()
        .map(|dir| Ok((case_label(dir)?, Airway::open(dir)?)))
        .collect()
}

/// The folder where finished runs are kept between examples (created if missing):
/// `PSEUDORIGID_BIF_CACHE`, else `target/bifurcation-runs` in the crate.
pub fn cache_dir() -> Result<PathBuf, crate::output::OutputError> {
    crate::studies::cache_folder("PSEUDORIGID_BIF_CACHE", "bifurcation-runs")
}

/// `run` (parallel, progress on stderr) from [`cache_dir`] if an example ran it before.
pub fn run_cached(run: StudyRun<'_, '_>) -> Result<Computed<NeoHooke>, BifurcationError> {
    run.cache(&cache_dir()?).run_timed(&RunOptions::default())
}

/// Run `n` particles of each kind (parallel, progress on stderr) and count their fates.
pub fn efficiencies(airway: &Airway, kinds: &[Kind], n: u64) -> Result<Vec<Efficiency>, BifurcationError> {
    let mut rows = Vec::with_capacity(kinds.len());
    for &kind in kinds {
        let computed = run_cached(StudyRun::new(airway, kind, n))?;
        let out = &computed.output;
        let row = Efficiency::of(kind, out);
        let steps: u64 = out.records.iter().map(|r| r.stats.steps).sum();
        eprintln!(
            "{kind:?}: DE = {:.4} ± {:.4} ({:?}), {steps} steps in {}",
            row.de(),
            row.stderr(),
            row.counts,
            computed.time_label()
        );
        rows.push(row);
    }
    Ok(rows)
}

/// Mesh studies, each of one particle kind.
pub type KindStudies = Vec<(Kind, MeshStudy)>;

/// [`efficiencies`] on the first of `cases`, and the mesh study ([`mesh_study`]) over all of
/// them of each kind whose Stokes number is in `band_stokes` (none with one case).
pub fn banded_efficiencies(
    cases: &[(&str, &Airway)],
    kinds: &[Kind],
    n: u64,
    band_stokes: &[f64],
) -> Result<(Vec<Efficiency>, KindStudies), BifurcationError> {
    let Some((_, first)) = cases.first() else {
        return Ok((Vec::new(), Vec::new()));
    };
    let rows = efficiencies(first, kinds, n)?;
    let mut studies = Vec::new();
    for &kind in kinds
        .iter()
        .filter(|k| cases.len() > 1 && band_stokes.contains(&k.stokes))
    {
        let (_, study) = mesh_study(cases, kind, n)?;
        if let Some(d) = study.outcome("deposited") {
            eprintln!("{kind:?} on {} meshes: {}", cases.len(), d.verdict);
        }
        studies.push((kind, study));
    }
    Ok((rows, studies))
}

/// Write the efficiency table ([`efficiency_table`]).
pub fn write_efficiencies(rows: &[Efficiency], path: &Path) -> Result<(), BifurcationError> {
    Ok(efficiency_table(rows)?.write(path)?)
}

/// Write the efficiency table with the mesh studies' bands ([`banded_efficiency_table`]) to
/// `path`, and the studies' `deposited` rows ([`MeshStudy::table`], led by `stk`) to
/// `mesh_study.csv` beside it (only if there are studies).
pub fn write_banded_efficiencies(
    rows: &[Efficiency],
    studies: &[(Kind, MeshStudy)],
    path: &Path,
) -> Result<(), BifurcationError> {
    banded_efficiency_table(rows, studies)?.write(path)?;
    if !studies.is_empty() {
        let labels: Vec<String> = studies.iter().map(|(k, _)| k.stokes.to_string()).collect();
        let keyed: Vec<(&str, &MeshStudy)> = labels
            .iter()
            .map(String::as_str)
            .zip(studies.iter().map(|(_, s)| s))
            .collect();
        MeshStudy::table(&keyed, Some("stk"), Some("deposited"))?.write(path.with_file_name("mesh_study.csv"))?;
    }
    Ok(())
}

/// [`efficiency_figure`] with each study's extrapolated DE and its GCI band (where the
/// procedure stands behind one, [`crate::population::mesh_study::OutcomeStudy::error_bar`]).
pub fn banded_figure(rows: &[Efficiency], studies: &[(Kind, MeshStudy)], title: &str) -> Figure {
    let mut panel = efficiency_panel(rows, title);
    let bars: Vec<(f64, f64, f64)> = studies
        .iter()
        .filter_map(|(k, s)| {
            let e = s.outcome("deposited")?.error_bar()?;
            Some((k.stokes.log10(), e.extrapolated, e.band))
        })
        .collect();
    let colour = 7;
    panel = panel.with(Series::points(
        "extrapolated DE, GCI band (mesh study)",
        bars.iter().map(|&(x, y, _)| (x, y)).collect(),
        colour,
    ));
    for &(x, y, band) in &bars {
        panel = panel.with(Series::line("", vec![(x, y - band), (x, y + band)], colour));
    }
    Figure::single(panel)
}

/// DE against log₁₀ Stk: one series per (shape, material) with DE ± 2 standard errors as
/// separate point series, and the Zhang et al. correlation as a line.
pub fn efficiency_figure(rows: &[Efficiency], title: &str) -> Figure {
    Figure::single(efficiency_panel(rows, title))
}

/// The panel of [`efficiency_figure`].
fn efficiency_panel(rows: &[Efficiency], title: &str) -> Panel {
    let mut panel = Panel::new(title, "log10 Stk", "DE").with_ranges((-2.4, -0.2), (0.0, 1.0));
    let mut groups: Vec<(String, Vec<&Efficiency>)> = Vec::new();
    for r in rows {
        let key = format!("{} {}", r.kind.shape.label(), r.kind.material.label());
        match groups.iter_mut().find(|(k, _)| *k == key) {
            Some((_, g)) => g.push(r),
            None => groups.push((key, vec![r])),
        }
    }
    for (i, (key, g)) in groups.iter().enumerate() {
        let pts = |s: f64| {
            g.iter()
                .map(|r| (r.kind.stokes.log10(), r.de() + s * r.stderr()))
                .collect()
        };
        panel = panel
            .with(Series::points(key.clone(), pts(0.0), i + 1))
            .with(Series::line(format!("{key} ± 2σ"), pts(2.0), i + 1))
            .with(Series::line("", pts(-2.0), i + 1));
    }
    let zhang: Vec<(f64, f64)> = (0..=100)
        .filter_map(|k| {
            let lg = -2.4 + 2.2 * f64::from(k) / 100.0;
            zhang_reference(10f64.powf(lg)).ok().map(|de| (lg, de))
        })
        .collect();
    panel.with(Series::line("Zhang et al. (1997), θ = 30°, Re = 500", zhang, 0))
}

/// Kinds of the softness study (paper Figs 19–23): spheres and prolates λ₁ = 2, 5, quasi-rigid
/// (μ_s = 10⁵ Pa) and soft (μ_s = 1 and 0.5 Pa), at each Stokes number of `stokes`.
pub fn softness_kinds(shapes: &[f64], moduli: &[f64], stokes: &[f64]) -> Vec<Kind> {
    let mut kinds = Vec::new();
    for &stk in stokes {
        for &lambda in shapes {
            for &mu_s in moduli {
                kinds.push(Kind {
                    shape: crate::studies::particles::Shape::Prolate(lambda),
                    material: super::injection::Material::ShearModulus(mu_s),
                    stokes: stk,
                });
            }
        }
    }
    kinds
}

/// Streamwise bins of the histograms: 50 over x₁/L ∈ [0, 1] (0.8 mm each).
pub const BINS: usize = 50;

/// The deposits of each kind's run, with the number injected.
pub fn deposits_of(
    airway: &Airway,
    kinds: &[Kind],
    n: u64,
) -> Result<Vec<(Kind, u64, Vec<Deposit>)>, BifurcationError> {
    kinds
        .iter()
        .map(|&kind| {
            let out = run_cached(StudyRun::new(airway, kind, n))?.output;
            Ok((kind, out.counts().total(), deposits(airway, kind, &out)?))
        })
        .collect()
}

/// Write `histogram.csv` and `summary.csv` of `runs` and `histogram.svg` (the fraction of the
/// injected particles per bin against x₁/L, one line per kind) into `paper-figures/<figure>/`
/// (feature `plot`: the SVG is part of what it writes).
#[cfg(feature = "plot")]
pub fn write_histograms(figure: &str, title: &str, runs: &[(Kind, u64, Vec<Deposit>)]) -> Result<(), BifurcationError> {
    histogram_table(runs, BINS)?.write(paper_figure_path(figure, "histogram.csv"))?;
    summary_table(runs)?.write(paper_figure_path(figure, "summary.csv"))?;
    let mut panel = Panel::new(title, "x1/L", "deposited fraction per bin").with_ranges((0.5, 1.0), (0.0, 0.2));
    let mut top: f64 = 0.0;
    for (i, (kind, injected, deps)) in runs.iter().enumerate() {
        let pts: Vec<(f64, f64)> = histogram(deps, BINS)
            .into_iter()
            .enumerate()
            .map(|(k, c)| ((k as f64 + 0.5) / BINS as f64, c as f64 / (*injected).max(1) as f64))
            .collect();
        top = pts.iter().fold(top, |m, p| m.max(p.1));
        let label = format!("{} {} Stk {}", kind.shape.label(), kind.material.label(), kind.stokes);
        panel = panel.with(Series::line(label, pts, i));
    }
    let panel = panel.with_ranges((0.5, 1.0), (0.0, (1.1 * top).max(1e-3)));
    Figure::single(panel).write(paper_figure_path(figure, "histogram.svg"))?;
    Ok(())
}

/// Particles per kind whose deposits the maps show: those with index below this. Particles are
/// independent and identically drawn, so they are a random sample of the run's deposits; the
/// maps' size then does not grow with N (at Stk 0.4, 10⁴ particles per kind left 28 000
/// deposits and 19 MB of map files), while `summary.csv` still covers every deposit.
pub const MAP_PARTICLES: u64 = 1000;

/// Write `summary.csv` (every deposit: mean x₁/L, largest r₁ and where) and, for the deposits of
/// the first [`MAP_PARTICLES`] particles of each kind, `deposits.csv` (the map: position,
/// patch, r₁..r₃ and V), `deposits.vtp` and `map.svg` (deposits projected on the bifurcation
/// plane x₁–x₂, and r₁ against x₁/L) into `paper-figures/<figure>/` (feature `plot`).
#[cfg(feature = "plot")]
pub fn write_maps(
    figure: &str,
    title: &str,
    airway: &Airway,
    runs: &[(Kind, u64, Vec<Deposit>)],
) -> Result<(), BifurcationError> {
    summary_table(runs)?.write(paper_figure_path(figure, "summary.csv"))?;
    let shown: Vec<(Kind, u64, Vec<Deposit>)> = runs
        .iter()
        .map(|(kind, n, deps)| {
            let sample = deps.iter().filter(|d| d.index < MAP_PARTICLES).copied().collect();
            (*kind, (*n).min(MAP_PARTICLES), sample)
        })
        .collect();
    let runs = &shown;
    map_table(runs, airway.boundary())?.write(paper_figure_path(figure, "deposits.csv"))?;
    deposits_vtp(runs)?.write(paper_figure_path(figure, "deposits.vtp"))?;
    let mut plane = Panel::new(format!("{title}: deposits on the x1-x2 plane"), "x1 [mm]", "x2 [mm]")
        .with_ranges((0.0, 40.0), (-14.0, 14.0));
    let mut stretch = Panel::new(format!("{title}: semi-major axis at deposition"), "x1/L", "r1 [um]");
    let mut r1_top: f64 = 0.0;
    for (i, (kind, _, deps)) in runs.iter().enumerate() {
        let label = format!("{} {}", kind.shape.label(), kind.material.label());
        plane = plane.with(Series::points(
            label.clone(),
            deps.iter().map(|d| (d.x[0] * 1e3, d.x[1] * 1e3)).collect(),
            i,
        ));
        r1_top = deps.iter().fold(r1_top, |m, d| m.max(d.r[0] * 1e6));
        stretch = stretch.with(Series::points(
            label,
            deps.iter()
                .map(|d| (d.x[0] / super::setup::LENGTH, d.r[0] * 1e6))
                .collect(),
            i,
        ));
    }
    let stretch = stretch.with_ranges((0.0, 1.0), (0.0, (1.1 * r1_top).max(1.0)));
    Figure::grid(vec![plane, stretch], 1, (900, 500)).write(paper_figure_path(figure, "map.svg"))?;
    Ok(())
}

/// The deposits of `runs` as ParaView vertices (m): `V` = √(F̄F̄ᵀ) as the active tensors (a
/// Tensor Glyph with a sphere source draws each particle as deposited), `r1`..`r3`, the `patch`
/// index, the particle `id` and `kind`, the index of its run in `runs` (the row order of
/// `summary.csv`).
pub fn deposits_vtp(runs: &[(Kind, u64, Vec<Deposit>)]) -> Result<PolyData, BifurcationError> {
    let all: Vec<(usize, &Deposit)> = runs
        .iter()
        .enumerate()
        .flat_map(|(k, (_, _, deps))| deps.iter().map(move |d| (k, d)))
        .collect();
    let column = |f: &dyn Fn(&Deposit) -> f64| PointValues::Float64(all.iter().map(|(_, d)| f(d)).collect());
    let ints = |f: &dyn Fn(usize, &Deposit) -> i64| PointValues::Int64(all.iter().map(|&(k, d)| f(k, d)).collect());
    let v = all.iter().flat_map(|(_, d)| d.v.iter().copied()).collect();
    Ok(PolyData::vertices(all.iter().map(|(_, d)| d.x).collect())?
        .with_array("id", 1, ints(&|_, d| d.index as i64))?
        .with_array("kind", 1, ints(&|k, _| k as i64))?
        .with_array("patch", 1, ints(&|_, d| d.patch as i64))?
        .with_array("V", 9, PointValues::Float64(v))?
        .with_array("r1", 1, column(&|d| d.r[0]))?
        .with_array("r2", 1, column(&|d| d.r[1]))?
        .with_array("r3", 1, column(&|d| d.r[2]))?
        .with_active_tensors("V")?)
}

/// The same `n` particles of `kind` in each of `cases` (cached runs, [`run_cached`]) and the
/// mesh study of their fates ([`study_of`]).
pub fn mesh_study(
    cases: &[(&str, &Airway)],
    kind: Kind,
    n: u64,
) -> Result<(Vec<RunOutput<NeoHooke>>, MeshStudy), BifurcationError> {
    let outputs = runs_on(cases, kind, n)?;
    let study = study_of(cases, &outputs)?;
    Ok((outputs, study))
}

/// The same `n` particles of `kind` in each of `cases` (cached runs, [`run_cached`]).
fn runs_on(cases: &[(&str, &Airway)], kind: Kind, n: u64) -> Result<Vec<RunOutput<NeoHooke>>, BifurcationError> {
    cases
        .iter()
        .map(|(_, airway)| Ok(run_cached(StudyRun::new(airway, kind, n))?.output))
        .collect()
}

/// The mesh study of `outputs`, the runs of the same particles on `cases` ([`MeshStudy`]:
/// three dimensions, the formal order [`FORMAL_ORDER`] of simpleFoam's linear-upwind
/// solution and the linear reconstruction; two to four cases of distinct cell counts).
pub fn study_of(cases: &[(&str, &Airway)], outputs: &[RunOutput<NeoHooke>]) -> Result<MeshStudy, BifurcationError> {
    let runs: Vec<MeshRun<'_, NeoHooke>> = cases
        .iter()
        .zip(outputs)
        .map(|((label, airway), output)| MeshRun {
            label,
            cells: airway.flow().cellwise().mesh().n_cells() as u64,
            output,
        })
        .collect();
    Ok(MeshStudy::new(&runs, 3, FORMAL_ORDER)?)
}

/// The mesh check: the same particles (same seed) of `kind` in several cases of the airway; a
/// row per case `case,cells,mean_residence_time,max_speed,stk,n,n_deposited,de,de_stderr,
/// fates_changed,deposits_gained,deposits_lost,paired_z` where `fates_changed` counts the
/// particles whose fate (deposited, escaped, suspended) differs from the first case's,
/// `deposits_gained` those deposited here but not there, `deposits_lost` the reverse, and
/// `paired_z` = (gained − lost)/√(gained + lost), McNemar's statistic ([`crate::population::binomial::PairedFates::z`];
/// |z| > 3: the DE moved beyond what the particles' randomness explains); and the runs, one
/// per case (for [`study_of`]).
pub fn mesh_check(
    cases: &[(&str, &Airway)],
    kind: Kind,
    n: u64,
) -> Result<(crate::output::Csv, Vec<RunOutput<NeoHooke>>), BifurcationError> {
    let mut csv = crate::output::Csv::new(&[
        "case",
        "cells",
        "mean_residence_time",
        "max_speed",
        "stk",
        "n",
        "n_deposited",
        "de",
        "de_stderr",
        "fates_changed",
        "deposits_gained",
        "deposits_lost",
        "paired_z",
    ]);
    let outputs = runs_on(cases, kind, n)?;
    let Some(first) = outputs.first() else {
        return Ok((csv, outputs));
    };
    for ((name, airway), out) in cases.iter().zip(&outputs) {
        let row = Efficiency::of(kind, out);
        let changed = paired(&first.records, &out.records)?
            .filter(|(a, b)| a.fate.label() != b.fate.label())
            .count();
        // This mesh's run first, the first mesh's second: b = gained, c = lost.
        let pairing = Pairing::of_records(&out.records, &first.records)?;
        let (gained, lost) = (pairing.only_ours, pairing.only_peer);
        let z = pairing.fates().map_or(0.0, |f| f.z());
        csv.push(vec![
            (*name).to_string(),
            airway.flow().cellwise().mesh().n_cells().to_string(),
            format!("{:.5}", airway.mean_residence_time()),
            format!("{:.4}", airway.max_speed()),
            kind.stokes.to_string(),
            row.finished().to_string(),
            row.counts.deposited.to_string(),
            format!("{:.4}", row.de()),
            format!("{:.4}", row.stderr()),
            changed.to_string(),
            gained.to_string(),
            lost.to_string(),
            format!("{z:.2}"),
        ])?;
    }
    Ok((csv, outputs))
}

/// Particles per kind re-run under the validity monitor ([`super::validity`]).
pub const VALIDITY_SAMPLE: u64 = 50;

/// Write `paper-figures/<figure>/validity.csv`: the validity summary of the first
/// [`VALIDITY_SAMPLE`] particles of each kind.
pub fn write_validity(figure: &str, airway: &Airway, kinds: &[Kind]) -> Result<(), BifurcationError> {
    let rows = kinds
        .iter()
        .map(|&k| Ok((k, super::validity::sample(airway, k, SEED, VALIDITY_SAMPLE)?)))
        .collect::<Result<Vec<_>, BifurcationError>>()?;
    super::validity::summary_table(&rows)?.write(paper_figure_path(figure, "validity.csv"))?;
    Ok(())
}

/// Paired comparison of softness: the same particles (same seed) as quasi-rigid (`reference`)
/// and soft kinds. A row per pair `shape,stk,reference,soft,n,dep_to_esc,esc_to_dep,delta_de,
/// delta_de_stderr`: the particles whose deposition changes either way, ΔDE = (esc→dep −
/// dep→esc)/n and its standard error √(dep→esc + esc→dep)/n (McNemar's test: under no effect the
/// discordant particles split evenly; [`crate::population::binomial::PairedFates::stderr_under_null`]). Far tighter than
/// comparing two independent DEs, because most particles meet the same fate either way.
pub fn paired_table(pairs: &[(Kind, Kind)], n: u64, airway: &Airway) -> Result<crate::output::Csv, BifurcationError> {
    let mut csv = crate::output::Csv::new(&[
        "shape",
        "stk",
        "reference",
        "soft",
        "n",
        "dep_to_esc",
        "esc_to_dep",
        "delta_de",
        "delta_de_stderr",
    ]);
    for (reference, soft) in pairs {
        let (a, b) = (
            run_cached(StudyRun::new(airway, *reference, n))?.output,
            run_cached(StudyRun::new(airway, *soft, n))?.output,
        );
        // The soft run first: b = gained (esc→dep), c = lost; without any pair, 0 ± 0.
        let pairing = Pairing::of_records(&b.records, &a.records)?;
        let (gained, lost) = (pairing.only_ours, pairing.only_peer);
        let fates = pairing.fates_or_zero();
        csv.push(vec![
            reference.shape.label(),
            reference.stokes.to_string(),
            reference.material.label(),
            soft.material.label(),
            a.records.len().to_string(),
            lost.to_string(),
            gained.to_string(),
            format!("{:.4}", fates.difference()),
            format!("{:.4}", fates.stderr_under_null()),
        ])?;
    }
    Ok(csv)
}

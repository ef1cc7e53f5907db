//! Datasets and figure panels of paper Figs 10–12.
//!
//! Tables carry λ₁ and Ca (0: rigid limit) in every row; times are in seconds, positions in
//! d_eq of the particle concerned (which differs between aspect ratios because r₃ is fixed).
//! Every recorded sample is written; runs are thinned where they are recorded.

use super::setup::PipeSetup;
use super::tracking::{Deposition, PipeSample, ShapeStats};
use crate::diagnostics::{Thresholds, Validity};
use crate::output::{Csv, OutputError, Panel, Series};

/// A particle's setup with its samples.
pub type Run<'a> = (&'a PipeSetup, &'a [PipeSample]);

/// The paper's statements on the extra streamwise travel of soft particles over the rigid one
/// (§6.2.1, text): (λ₁, Ca, relation, Δx₁ in d_eq). Figs 11/12 list
/// Ca = 0.2 where the text quotes 0.25.
pub const PAPER_EXTRA_TRAVEL: [(f64, f64, &str, f64); 4] = [
    (3.5, 0.25, "approx", 4500.0),
    (3.5, 0.9, "more than", 35000.0),
    (7.0, 0.25, "more than", 35000.0),
    (7.0, 0.9, "more than", 313000.0),
];

/// `lambda1,ca,t_s,cos1,cos2,cos3`: direction cosines of l_a (Figs 10, 12).
pub fn direction_cosine_table(runs: &[Run<'_>]) -> Result<Csv, OutputError> {
    let mut csv = Csv::new(&["lambda1", "ca", "t_s", "cos1", "cos2", "cos3"]);
    for (setup, samples) in runs {
        for s in samples.iter() {
            let c = s.direction_cosines();
            csv.push_numbers(&[lambda1(setup), ca(setup), s.t * setup.time_unit, c[0], c[1], c[2]])?;
        }
    }
    Ok(csv)
}

/// `lambda1,ca,t_s,x1_deq,x2_deq,x3_deq,gap_deq`: barycentre paths and wall gaps (Fig. 11).
pub fn trajectory_table(runs: &[Run<'_>]) -> Result<Csv, OutputError> {
    let mut csv = Csv::new(&["lambda1", "ca", "t_s", "x1_deq", "x2_deq", "x3_deq", "gap_deq"]);
    for (setup, samples) in runs {
        for s in samples.iter() {
            csv.push_numbers(&[
                lambda1(setup),
                ca(setup),
                s.t * setup.time_unit,
                s.x[0],
                s.x[1],
                s.x[2],
                s.gap,
            ])?;
        }
    }
    Ok(csv)
}

/// cos(l_a, e_k) against time (s), one line per particle, up to `t_end` seconds if given.
pub fn direction_cosine_panel(runs: &[Run<'_>], k: usize, title: &str, t_end: Option<f64>) -> Panel {
    let mut panel = Panel::new(title, "t [s]", format!("cos(l_a, e{})", k + 1));
    for (i, (setup, samples)) in runs.iter().enumerate() {
        let points = samples
            .iter()
            .filter(|s| t_end.is_none_or(|te| s.t * setup.time_unit <= te))
            .map(|s| (s.t * setup.time_unit, s.direction_cosines()[k]))
            .collect();
        panel = panel.with(Series::line(label(setup), points, i));
    }
    panel.y_range = Some((-1.05, 1.05));
    panel
}

/// x₂ against x₁ (both in d_eq), one line per particle, with the wall x₂ = −R.
pub fn trajectory_panel(runs: &[Run<'_>], title: &str) -> Panel {
    let mut panel = Panel::new(title, "x1 / d_eq", "x2 / d_eq");
    let mut x_end: f64 = 0.0;
    for (i, (setup, samples)) in runs.iter().enumerate() {
        let points: Vec<(f64, f64)> = samples.iter().map(|s| (s.x[0], s.x[1])).collect();
        x_end = x_end.max(points.last().map_or(0.0, |p| p.0));
        panel = panel.with(Series::line(label(setup), points, i));
    }
    if let Some((setup, _)) = runs.first() {
        let wall = -setup.flow.radius;
        panel = panel.with(Series::line("wall", vec![(0.0, wall), (x_end, wall)], 6));
    }
    panel
}

/// One row of the deposition table.
#[derive(Debug, Clone, PartialEq)]
pub struct DepositionRow {
    /// λ₁.
    pub lambda1: f64,
    /// Ca (0: rigid).
    pub ca: f64,
    /// d_eq (µm).
    pub d_eq_um: f64,
    /// Time to contact (s).
    pub t_s: f64,
    /// Streamwise deposition distance (d_eq).
    pub distance_deq: f64,
    /// The same (m).
    pub distance_m: f64,
    /// Distance minus the rigid particle's of the same λ₁ (d_eq), if that was run.
    pub extra_deq: Option<f64>,
    /// Distance of the check run at a tighter tolerance (d_eq).
    pub check_distance_deq: f64,
    /// Accepted steps of the main run.
    pub steps: u64,
    /// True if the distance exceeds the pipe length L (the particle would have left the pipe).
    pub beyond_pipe: bool,
    /// Time averages ⟨(p·e₂)²⟩, ⟨r₁/r₃⟩ and max r₁/r₃ of the main run.
    pub shape: ShapeStats,
    /// Validity diagnostics of the main run (r₁ in d_eq).
    pub validity: Validity,
}

impl DepositionRow {
    /// |distance − check distance| relative to |extra| (or to the distance for the rigid case):
    /// the tolerance error of the quantity the paper reports.
    pub fn tolerance_change(&self) -> f64 {
        let scale = self.extra_deq.filter(|e| *e != 0.0).unwrap_or(self.distance_deq);
        (self.distance_deq - self.check_distance_deq).abs() / scale.abs()
    }

    /// The paper's statement for this case, if it makes one.
    pub fn paper_statement(&self) -> Option<(&'static str, f64)> {
        PAPER_EXTRA_TRAVEL
            .iter()
            .find(|(l, c, _, _)| *l == self.lambda1 && *c == self.ca)
            .map(|(_, _, rel, value)| (*rel, *value))
    }
}

/// Rows from the main runs and check runs (same cases, same order, tighter tolerance).
pub fn deposition_rows(runs: &[(PipeSetup, Deposition)], checks: &[(PipeSetup, Deposition)]) -> Vec<DepositionRow> {
    let rigid = |l: f64| {
        runs.iter()
            .find(|(s, _)| lambda1(s) == l && ca(s) == 0.0)
            .map(|(_, d)| d.distance())
    };
    runs.iter()
        .zip(checks)
        .map(|((setup, run), (_, check))| {
            let l = setup.length_unit;
            DepositionRow {
                lambda1: lambda1(setup),
                ca: ca(setup),
                d_eq_um: l * 1e6,
                t_s: run.contact().t * setup.time_unit,
                distance_deq: run.distance(),
                distance_m: run.distance() * l,
                extra_deq: rigid(lambda1(setup)).map(|r| run.distance() - r),
                check_distance_deq: check.distance(),
                steps: run.steps,
                beyond_pipe: run.distance() * l > setup.flow_data.length,
                shape: run.shape,
                validity: run.validity.clone(),
            }
        })
        .collect()
}

/// `lambda1,ca,d_eq_um,t_dep_s,x1_dep_deq,x1_dep_m,extra_vs_rigid_deq,paper_relation,
/// paper_extra_deq,x1_dep_deq_check,tolerance_change,beyond_pipe_length,steps,mean_p_e2_sq,
/// mean_r1_over_r3,max_r1_over_r3` (p the current long axis; time averages over the run),
/// then the validity columns [`Validity::COLUMNS`] under the default [`Thresholds`].
pub fn deposition_table(rows: &[DepositionRow]) -> Result<Csv, OutputError> {
    let mut header = vec![
        "lambda1",
        "ca",
        "d_eq_um",
        "t_dep_s",
        "x1_dep_deq",
        "x1_dep_m",
        "extra_vs_rigid_deq",
        "paper_relation",
        "paper_extra_deq",
        "x1_dep_deq_check",
        "tolerance_change",
        "beyond_pipe_length",
        "steps",
        "mean_p_e2_sq",
        "mean_r1_over_r3",
        "max_r1_over_r3",
    ];
    header.extend(Validity::COLUMNS);
    let mut csv = Csv::new(&header);
    let limits = Thresholds::default();
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| v.to_string());
    for r in rows {
        let paper = r.paper_statement();
        let mut cells = vec![
            r.lambda1.to_string(),
            r.ca.to_string(),
            r.d_eq_um.to_string(),
            r.t_s.to_string(),
            r.distance_deq.to_string(),
            r.distance_m.to_string(),
            opt(r.extra_deq),
            paper.map_or(String::new(), |p| p.0.to_string()),
            opt(paper.map(|p| p.1)),
            r.check_distance_deq.to_string(),
            r.tolerance_change().to_string(),
            r.beyond_pipe.to_string(),
            r.steps.to_string(),
            opt(r.shape.mean_gradient_alignment()),
            opt(r.shape.mean_aspect()),
            r.shape.max_aspect().to_string(),
        ];
        cells.extend(r.validity.cells(&limits));
        csv.push(cells)?;
    }
    Ok(csv)
}

fn lambda1(setup: &PipeSetup) -> f64 {
    setup.particle_data.lambda1()
}

fn ca(setup: &PipeSetup) -> f64 {
    setup.softness.ca()
}

fn label(setup: &PipeSetup) -> String {
    match ca(setup) {
        0.0 => format!("λ1 = {}, Ca → 0 (rigid)", lambda1(setup)),
        c => format!("λ1 = {}, Ca = {c}", lambda1(setup)),
    }
}

//! Tables and panels of single runs.

use super::*;

/// Trajectories as CSV: `contact,shape,ca,t,x_over_l,y_over_l,z_over_l` (ca empty: rigid limit).
pub fn trajectory_table(runs: &[CavityRun]) -> Result<crate::output::Csv, crate::output::OutputError> {
    let mut csv = crate::output::Csv::new(&["contact", "shape", "ca", "t", "x_over_l", "y_over_l", "z_over_l"]);
    for run in runs {
        for (t, x) in &run.path {
            csv.push(vec![
                run.contact.label().into(),
                run.release.shape.label(),
                run.release.ca().map(|c| c.to_string()).unwrap_or_default(),
                format!("{t:.4}"),
                format!("{:.5}", x[0] / EDGE),
                format!("{:.5}", x[1] / EDGE),
                format!("{:.5}", x[2] / EDGE),
            ])?;
        }
    }
    Ok(csv)
}

/// Outcomes as CSV: `contact,shape,ca,outcome,wall,t_end,x_over_l,y_over_l,z_over_l,steps,
/// shape_model,max_slip,median_slip` (slip [`Slip`] in m/s), then the validity columns
/// [`Validity::COLUMNS`] under the default [`Thresholds`] (r₁ in m).
pub fn outcome_table(runs: &[CavityRun]) -> Result<crate::output::Csv, crate::output::OutputError> {
    let mut csv = crate::output::Csv::new(&outcome_header());
    let limits = Thresholds::default();
    for run in runs {
        csv.push(outcome_cells(run, &limits))?;
    }
    Ok(csv)
}

pub(super) fn outcome_header() -> Vec<&'static str> {
    let mut header = vec![
        "contact",
        "shape",
        "ca",
        "outcome",
        "wall",
        "t_end",
        "x_over_l",
        "y_over_l",
        "z_over_l",
        "steps",
        "shape_model",
        "max_slip",
        "median_slip",
    ];
    header.extend(Validity::COLUMNS);
    header
}

pub(super) fn outcome_cells(run: &CavityRun, limits: &Thresholds) -> Vec<String> {
    let (t, x) = run.path.last().copied().unwrap_or((0.0, release_point()));
    let outcome = run.outcome();
    let wall = match outcome {
        CavityFate::Deposited { wall, .. } => wall.to_string(),
        CavityFate::Failed { reason, .. } => reason.replace(',', ";"),
        CavityFate::Exited { .. } | CavityFate::Suspended => String::new(),
    };
    let mut cells = vec![
        run.contact.label().into(),
        run.release.shape.label(),
        run.release.ca().map(|c| c.to_string()).unwrap_or_default(),
        outcome.label().into(),
        wall,
        format!("{t:.3}"),
        format!("{:.4}", x[0] / EDGE),
        format!("{:.4}", x[1] / EDGE),
        format!("{:.4}", x[2] / EDGE),
        run.stats.steps.to_string(),
        run.shape_model.label().into(),
        format!("{:.3e}", run.slip.max),
        format!("{:.3e}", run.slip.median),
    ];
    cells.extend(run.validity.cells(limits));
    cells
}

/// Trajectories projected on the x–z plane (the paper's x₂/L = 0.4 view), one panel.
pub fn trajectory_panel(runs: &[CavityRun], title: &str) -> crate::output::Panel {
    let mut panel = crate::output::Panel::new(title, "x/L", "z/L").with_ranges((0.0, 1.0), (0.0, 1.0));
    for (i, run) in runs.iter().enumerate() {
        let label = match run.release.ca() {
            Some(ca) => format!("{} Ca={ca}", run.release.shape.label()),
            None => format!("{} Ca→0", run.release.shape.label()),
        };
        let pts = run.path.iter().map(|(_, x)| (x[0] / EDGE, x[2] / EDGE)).collect();
        panel = panel.with(crate::output::Series::line(label, pts, i));
    }
    panel
}

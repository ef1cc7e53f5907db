//! Files of the cavity validation: centreline CSV, extrema CSV and an SVG plot.

use super::{CavityCase, Centreline, ExtremumComparison, LinePoint, ReferenceTable};
use crate::error::FlowError;
use crate::flow::FlowField;
use crate::output::write_atomic;
use std::fmt::Write as _;
use std::path::Path;

/// Dense samples per centreline in the CSV and the plot.
pub const PROFILE_SAMPLES: usize = 121;

/// Why a report could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// Sampling the flow failed.
    #[error(transparent)]
    Flow(#[from] FlowError),
    /// Writing a file, drawing or writing the plot failed.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
}

/// Atomic write (see [`crate::output::atomic`]): an interrupted report leaves the previous
/// file whole.
fn write(path: &Path, text: &str) -> Result<(), crate::output::OutputError> {
    write_atomic(path, text.as_bytes())
}

/// `line,position,simulated,reference`: the simulated profile at [`PROFILE_SAMPLES`]
/// equispaced positions (reference empty) and at every reference position (both filled).
pub fn write_centrelines_csv(
    path: &Path,
    case: &CavityCase,
    flow: &impl FlowField,
    reference: &ReferenceTable,
) -> Result<(), ReportError> {
    let mut out = String::from("line,position,simulated,reference\n");
    for line in Centreline::ALL {
        let mut rows: Vec<(LinePoint, Option<f64>)> = case
            .profile(flow, line, PROFILE_SAMPLES)?
            .into_iter()
            .map(|p| (p, None))
            .collect();
        for r in reference.profile(line) {
            let simulated = case.sample(flow, line, r.position)?;
            rows.push((
                LinePoint {
                    position: r.position,
                    value: simulated,
                },
                Some(r.value),
            ));
        }
        rows.sort_by(|a, b| a.0.position.total_cmp(&b.0.position));
        for (p, r) in rows {
            let reference = r.map_or(String::new(), |v| format!("{v:.6}"));
            let _ = writeln!(out, "{},{:.6},{:.6},{reference}", line.name(), p.position, p.value);
        }
    }
    write(path, &out)?;
    Ok(())
}

/// `quantity,simulated,position_simulated,reference,position_reference,relative_error_percent`.
pub fn write_extrema_csv(path: &Path, rows: &[ExtremumComparison]) -> Result<(), crate::output::OutputError> {
    let mut out =
        String::from("quantity,simulated,position_simulated,reference,position_reference,relative_error_percent\n");
    for r in rows {
        let _ = writeln!(
            out,
            "{},{:.7},{:.5},{:.7},{:.5},{:.3}",
            r.which.name(),
            r.simulated.value,
            r.simulated.position,
            r.reference.value,
            r.reference.position,
            100.0 * r.relative_error()
        );
    }
    write(path, &out)
}

/// Two panels (u on the vertical centreline, w on the horizontal one): simulated curve and
/// reference markers, drawn through [`crate::output::Figure`].
#[cfg(feature = "plot")]
pub fn plot_centrelines_svg(
    path: &Path,
    title: &str,
    simulated_label: &str,
    case: &CavityCase,
    flow: &impl FlowField,
    reference: &ReferenceTable,
) -> Result<(), ReportError> {
    use crate::output::{Figure, Panel, Series};
    let mut panels = Vec::new();
    for line in Centreline::ALL {
        // Vertical line: height on the ordinate, as in the benchmark papers.
        let (xs, ys, x_label, y_label) = match line {
            Centreline::Vertical => ((-0.4, 1.05), (0.0, 1.0), "u_x / U", "z / L  (x = y = L/2)"),
            Centreline::Horizontal => ((0.0, 1.0), (-0.5, 0.3), "x / L  (y = z = L/2)", "u_z / U"),
        };
        let xy = |p: &LinePoint| match line {
            Centreline::Vertical => (p.value, p.position),
            Centreline::Horizontal => (p.position, p.value),
        };
        let simulated = case.profile(flow, line, PROFILE_SAMPLES)?.iter().map(xy).collect();
        let markers = reference.profile(line).iter().map(xy).collect();
        panels.push(
            Panel::new(format!("{title}: {} centreline", line.name()), x_label, y_label)
                .with_ranges(xs, ys)
                .with(Series::line(simulated_label, simulated, 0))
                .with(Series::points("Albensoeder & Kuhlmann 2005", markers, 1)),
        );
    }
    Figure::grid(panels, 2, (500, 480)).write(path)?;
    Ok(())
}

//! Files of the cavity validation: centreline CSV, extrema CSV and an SVG plot.

use super::{CavityCase, Centreline, ExtremumComparison, LinePoint, ReferenceTable};
use crate::error::FlowError;
use crate::flow::FlowField;
use crate::flow::unstructured::MeshError;
use crate::output::write_atomic;
#[cfg(feature = "plot")]
use plotters::prelude::*;
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
    /// Writing a file failed.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// The plotting backend failed.
    #[cfg(feature = "plot")]
    #[error("plot {path}: {reason}")]
    Plot {
        /// Output file.
        path: String,
        /// Backend message.
        reason: String,
    },
}

/// Atomic write (see [`crate::output::atomic`]): an interrupted report leaves the previous
/// file whole.
fn write(path: &Path, text: &str) -> Result<(), MeshError> {
    write_atomic(path, text.as_bytes()).map_err(MeshError::from)
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
pub fn write_extrema_csv(path: &Path, rows: &[ExtremumComparison]) -> Result<(), MeshError> {
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
/// reference markers.
#[cfg(feature = "plot")]
pub fn plot_centrelines_svg(
    path: &Path,
    title: &str,
    simulated_label: &str,
    case: &CavityCase,
    flow: &impl FlowField,
    reference: &ReferenceTable,
) -> Result<(), ReportError> {
    let plot_err = |e: &dyn std::fmt::Display| ReportError::Plot {
        path: path.display().to_string(),
        reason: e.to_string(),
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1000, 480)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| plot_err(&e))?;
        let root = root.titled(title, ("sans-serif", 20)).map_err(|e| plot_err(&e))?;
        let panels = root.split_evenly((1, 2));
        for (panel, line) in panels.iter().zip(Centreline::ALL) {
            let simulated = case.profile(flow, line, PROFILE_SAMPLES)?;
            // Vertical line: height on the ordinate, as in the benchmark papers.
            let (xs, ys, x_label, y_label) = match line {
                Centreline::Vertical => (-0.4..1.05, 0.0..1.0, "u_x / U", "z / L  (x = y = L/2)"),
                Centreline::Horizontal => (0.0..1.0, -0.5..0.3, "x / L  (y = z = L/2)", "u_z / U"),
            };
            let xy = |p: &LinePoint| match line {
                Centreline::Vertical => (p.value, p.position),
                Centreline::Horizontal => (p.position, p.value),
            };
            let mut chart = ChartBuilder::on(panel)
                .margin(15)
                .x_label_area_size(40)
                .y_label_area_size(55)
                .build_cartesian_2d(xs, ys)
                .map_err(|e| plot_err(&e))?;
            chart
                .configure_mesh()
                .x_desc(x_label)
                .y_desc(y_label)
                .draw()
                .map_err(|e| plot_err(&e))?;
            chart
                .draw_series(LineSeries::new(simulated.iter().map(xy), BLUE.stroke_width(2)))
                .map_err(|e| plot_err(&e))?
                .label(simulated_label)
                .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], BLUE.stroke_width(2)));
            chart
                .draw_series(
                    reference
                        .profile(line)
                        .iter()
                        .map(|p| Circle::new(xy(p), 4, RED.filled())),
                )
                .map_err(|e| plot_err(&e))?
                .label("Albensoeder & Kuhlmann 2005")
                .legend(|(x, y)| Circle::new((x + 10, y), 4, RED.filled()));
            chart
                .configure_series_labels()
                .border_style(BLACK)
                .background_style(WHITE.mix(0.8))
                .draw()
                .map_err(|e| plot_err(&e))?;
        }
        root.present().map_err(|e| plot_err(&e))?;
    }
    write(path, &svg)?;
    Ok(())
}

//! TU/TR phase maps: boundaries over families of shapes (paper Figs 7, 8), their CSV dataset
//! and their figure.
//!
//! The dataset has one row per shape, `family,r_flow,r_gradient,r_vorticity,ca_tu,ca_tr`:
//! the series the shape belongs to (its [`MapShape::series`], e.g. `prolate` in Fig. 7 or a
//! section `a_omega1_0.5` in Fig. 8) and its initial semi-axes along flow, gradient and
//! vorticity relative to each other (ratios, not d_eq units).

use super::StudyError;
use super::phase_boundary::{BoundarySearch, RegimeBoundary};
use super::shear_regimes::RegimeClassifier;
use super::shear_shape::ShearShape;
use crate::diagnostics::Validity;
use crate::integrator::{Stokesian, TimeIntegrator};
use crate::material::LawFactory;
use crate::output::{Csv, OutputError, Panel, Series};

/// One shape of a map: the series it is drawn in and its abscissa.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapShape {
    /// Series label (the dataset's `family` column and the figure's legend).
    pub series: &'static str,
    /// Abscissa (aspect ratio, ω₁ or ω₂).
    pub x: f64,
    /// The placed shape.
    pub shape: ShearShape,
}

/// One located boundary and the series and abscissa it is plotted at.
#[derive(Debug, Clone, PartialEq)]
pub struct MapPoint {
    /// Series label.
    pub series: &'static str,
    /// Abscissa (aspect ratio, ω₁ or ω₂).
    pub x: f64,
    /// The boundary of that shape.
    pub boundary: RegimeBoundary,
}

/// The search used for the paper maps: inertialess Radau IIA classifier at rtol = atol = 1e-7
/// (the margin is converged to ~1e-7 there, far below its ~0.6 ΔCa sensitivity; the brackets
/// equal those at 1e-8) and ΔCa ≤ 1e-4.
pub fn paper_search() -> Result<BoundarySearch<Stokesian>, crate::error::ParamError> {
    Ok(BoundarySearch::new(RegimeClassifier::stokesian(1e-7)?, 1e-4))
}

/// Boundaries of all `shapes`, in parallel.
pub fn compute<I: TimeIntegrator + Sync, L: LawFactory + Sync>(
    search: &BoundarySearch<I, L>,
    shapes: &[MapShape],
) -> Result<Vec<MapPoint>, StudyError> {
    let list: Vec<ShearShape> = shapes.iter().map(|s| s.shape).collect();
    search
        .find_all(&list)
        .into_iter()
        .zip(shapes)
        .map(|(b, s)| {
            b.map(|boundary| MapPoint {
                series: s.series,
                x: s.x,
                boundary,
            })
        })
        .collect()
}

/// The boundary dataset.
pub fn boundary_table(points: &[MapPoint]) -> Result<Csv, OutputError> {
    let mut csv = Csv::new(&["family", "r_flow", "r_gradient", "r_vorticity", "ca_tu", "ca_tr"]);
    for p in points {
        let ([flow, gradient, vorticity], b) = (p.boundary.shape.ratios(), &p.boundary);
        csv.push(vec![
            p.series.to_string(),
            flow.to_string(),
            gradient.to_string(),
            vorticity.to_string(),
            b.ca_tu.to_string(),
            b.ca_tr.to_string(),
        ])?;
    }
    Ok(csv)
}

/// Validity diagnostics of the runs bracketing each boundary:
/// `family,r_flow,r_gradient,r_vorticity`, then [`Validity::COLUMNS`] (r₁ in d_eq, default
/// thresholds). `inertialess`: the search ran the inertialess model, which assumes Re = 0
/// ([`Validity::inertialess`]); the shear flow is unbounded and linear, so the length-scale
/// ratios are 0 by construction.
pub fn validity_table(points: &[MapPoint], inertialess: bool) -> Result<Csv, OutputError> {
    let mut header = vec!["family", "r_flow", "r_gradient", "r_vorticity"];
    header.extend(Validity::COLUMNS);
    let mut csv = Csv::new(&header);
    let limits = crate::diagnostics::Thresholds::default();
    for p in points {
        let [flow, gradient, vorticity] = p.boundary.shape.ratios();
        let v = if inertialess {
            p.boundary.validity.clone().inertialess()
        } else {
            p.boundary.validity.clone()
        };
        let mut cells = vec![
            p.series.to_string(),
            flow.to_string(),
            gradient.to_string(),
            vorticity.to_string(),
        ];
        cells.extend(v.cells(&limits));
        csv.push(cells)?;
    }
    Ok(csv)
}

/// Ca_c against x, one line per series, with the bracket ends as points.
pub fn boundary_panel(points: &[MapPoint], title: &str, x_label: &str) -> Panel {
    let mut series: Vec<&str> = points.iter().map(|p| p.series).collect();
    series.dedup();
    let mut panel = Panel::new(title, x_label, "Ca (TU below, TR above)");
    for (i, name) in series.iter().enumerate() {
        let of = |f: fn(&RegimeBoundary) -> f64| -> Vec<(f64, f64)> {
            points
                .iter()
                .filter(|p| p.series == *name)
                .map(|p| (p.x, f(&p.boundary)))
                .collect()
        };
        panel = panel
            .with(Series::line(*name, of(RegimeBoundary::ca_critical), i + 1))
            .with(Series::points("", of(|b| b.ca_tu), i + 1))
            .with(Series::points("", of(|b| b.ca_tr), i + 1));
    }
    panel
}

//! SVG line and scatter figures (plotters, SVG backend) shared by all examples.
//!
//! A [`Figure`] is a grid of [`Panel`]s; a panel holds [`Series`] drawn as lines or points.
//! Ranges default to the data range plus 5 %; set them explicitly for equal-aspect outlines.
//! The figure descriptions are always available; rendering them needs the `plot` feature.

#[cfg(feature = "plot")]
use super::{OutputError, write_atomic};
#[cfg(feature = "plot")]
use plotters::prelude::*;
#[cfg(feature = "plot")]
use std::path::Path;

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SeriesStyle {
    /// Polyline through the points.
    Line,
    /// Filled circles (reference data, phase-boundary points).
    Points,
}

#[cfg(feature = "plot")]
/// Colours by index: black, red, green, blue, orange, purple, grey.
const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 0, 0),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(127, 127, 127),
];

/// One data series.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text (empty: no legend entry).
    pub label: String,
    /// (x, y) points.
    pub points: Vec<(f64, f64)>,
    /// Line or points.
    pub style: SeriesStyle,
    /// Palette index (wraps).
    pub color: usize,
}

impl Series {
    /// A polyline.
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>, color: usize) -> Self {
        Self {
            label: label.into(),
            points,
            style: SeriesStyle::Line,
            color,
        }
    }

    /// A scatter series.
    pub fn points(label: impl Into<String>, points: Vec<(f64, f64)>, color: usize) -> Self {
        Self {
            style: SeriesStyle::Points,
            ..Self::line(label, points, color)
        }
    }
}

/// One chart: title, axis labels, series and optional fixed ranges.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Panel {
    /// Caption.
    pub title: String,
    /// x-axis description.
    pub x_label: String,
    /// y-axis description.
    pub y_label: String,
    /// Data.
    pub series: Vec<Series>,
    /// Fixed x range (default: data range + 5 %).
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range (default: data range + 5 %).
    pub y_range: Option<(f64, f64)>,
}

impl Panel {
    /// Panel with a title and axis labels and no data yet.
    pub fn new(title: impl Into<String>, x_label: impl Into<String>, y_label: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            ..Self::default()
        }
    }

    /// Add a series.
    pub fn with(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }

    /// Fix both ranges.
    pub fn with_ranges(mut self, x: (f64, f64), y: (f64, f64)) -> Self {
        self.x_range = Some(x);
        self.y_range = Some(y);
        self
    }

    #[cfg(feature = "plot")]
    fn data_range(&self, pick: impl Fn(&(f64, f64)) -> f64) -> (f64, f64) {
        let (lo, hi) = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().map(&pick))
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
        if !(lo.is_finite() && hi.is_finite()) {
            return (0.0, 1.0);
        }
        let pad = if hi > lo { 0.05 * (hi - lo) } else { 1.0 };
        (lo - pad, hi + pad)
    }
}

/// A grid of panels, `columns` wide, each `panel_size` pixels.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// Panels in row-major order.
    pub panels: Vec<Panel>,
    /// Panels per row.
    pub columns: usize,
    /// Width and height of one panel in pixels.
    pub panel_size: (u32, u32),
}

impl Figure {
    /// A one-panel figure of 640 × 480 pixels.
    pub fn single(panel: Panel) -> Self {
        Self::grid(vec![panel], 1, (640, 480))
    }

    /// A grid figure.
    pub fn grid(panels: Vec<Panel>, columns: usize, panel_size: (u32, u32)) -> Self {
        Self {
            panels,
            columns: columns.max(1),
            panel_size,
        }
    }

    /// Render to SVG text.
    #[cfg(feature = "plot")]
    pub fn to_svg(&self) -> Result<String, OutputError> {
        let plot_err = |e: &dyn std::fmt::Display| OutputError::Plot(e.to_string());
        let rows = self.panels.len().div_ceil(self.columns).max(1);
        let size = (self.panel_size.0 * self.columns as u32, self.panel_size.1 * rows as u32);
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
            root.fill(&WHITE).map_err(|e| plot_err(&e))?;
            let areas = root.split_evenly((rows, self.columns));
            for (area, panel) in areas.iter().zip(&self.panels) {
                draw_panel(area, panel).map_err(|e| plot_err(&e))?;
            }
            root.present().map_err(|e| plot_err(&e))?;
        }
        Ok(svg)
    }

    /// Render and write atomically to `path`.
    #[cfg(feature = "plot")]
    pub fn write(&self, path: impl AsRef<Path>) -> Result<(), OutputError> {
        write_atomic(path, self.to_svg()?.as_bytes())
    }
}

#[cfg(feature = "plot")]
type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;

#[cfg(feature = "plot")]
fn draw_panel(area: &Area<'_>, panel: &Panel) -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
    let (x0, x1) = panel.x_range.unwrap_or_else(|| panel.data_range(|p| p.0));
    let (y0, y1) = panel.y_range.unwrap_or_else(|| panel.data_range(|p| p.1));
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 15))
        .margin(8)
        .x_label_area_size(32)
        .y_label_area_size(48)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    chart
        .configure_mesh()
        .x_desc(panel.x_label.as_str())
        .y_desc(panel.y_label.as_str())
        .light_line_style(WHITE)
        .draw()?;
    let mut legend = false;
    for s in &panel.series {
        let color = PALETTE[s.color % PALETTE.len()];
        let anno = match s.style {
            SeriesStyle::Line => chart.draw_series(LineSeries::new(s.points.iter().copied(), color.stroke_width(2)))?,
            SeriesStyle::Points => chart.draw_series(s.points.iter().map(|&p| Circle::new(p, 3, color.filled())))?,
        };
        if !s.label.is_empty() {
            legend = true;
            anno.label(s.label.as_str())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], color.stroke_width(2)));
        }
    }
    if legend {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 12))
            .draw()?;
    }
    Ok(())
}

//! The picture of the paired runs: deposits steady against inhaled, and DE by injection
//! time.

use super::{BreathingPair, MAP_PARTICLES, Waveform, by_phase};
use crate::output::{Figure, Panel, Series};
use crate::population::Fate;
use crate::studies::bifurcation::setup::LENGTH;

/// The pictures: for each kind, its deposits on the x₁–x₂ plane steady against inhaled (the
/// first [`MAP_PARTICLES`] particles), then a panel per Stokes number with DE against the
/// injection time, inhaled (points, ± 2σ lines) and steady on the same particles (lines).
pub fn figure(pairs: &[BreathingPair], waveform: Waveform, bins: usize) -> Figure {
    let mut panels = Vec::new();
    for p in pairs {
        let label = format!(
            "{} {} Stk {}",
            p.kind.shape.label(),
            p.kind.material.label(),
            p.kind.stokes
        );
        let mut plane = Panel::new(format!("{label}: deposits"), "x1 [mm]", "x2 [mm]")
            .with_ranges((0.0, LENGTH * 1e3), (-14.0, 14.0));
        for (i, (flow, out)) in [("steady", &p.steady), ("cyclic", &p.cyclic)].into_iter().enumerate() {
            let pts = out
                .records
                .iter()
                .filter(|r| r.index < MAP_PARTICLES)
                .filter_map(|r| match r.fate {
                    Fate::Deposited { position, .. } => Some((position[0] * 1e3, position[1] * 1e3)),
                    _ => None,
                })
                .collect();
            plane = plane.with(Series::points(flow, pts, i));
        }
        panels.push(plane);
    }
    let mut stokes: Vec<f64> = pairs.iter().map(|p| p.kind.stokes).collect();
    stokes.dedup();
    for stk in stokes {
        let mut panel = Panel::new(format!("Stk {stk}: DE by injection time"), "t_injected [s]", "DE")
            .with_ranges((0.0, waveform.duration()), (0.0, 1.0));
        for (i, p) in pairs.iter().filter(|p| p.kind.stokes == stk).enumerate() {
            let rows = by_phase(p, waveform.duration(), bins);
            let mid = |r: &(f64, f64, u64, u64, u64)| 0.5 * (r.0 + r.1);
            let de = |k: u64, n: u64, s: f64| {
                crate::population::binomial::fraction(k, n) + s * crate::population::binomial::stderr(k, n)
            };
            let name = format!("{} {}", p.kind.shape.label(), p.kind.material.label());
            panel = panel
                .with(Series::points(
                    format!("{name} cyclic"),
                    rows.iter().map(|r| (mid(r), de(r.3, r.2, 0.0))).collect(),
                    2 * i,
                ))
                .with(Series::line(
                    format!("{name} cyclic ± 2σ"),
                    rows.iter().map(|r| (mid(r), de(r.3, r.2, 2.0))).collect(),
                    2 * i,
                ))
                .with(Series::line(
                    "",
                    rows.iter().map(|r| (mid(r), de(r.3, r.2, -2.0))).collect(),
                    2 * i,
                ))
                .with(Series::line(
                    format!("{name} steady, same particles"),
                    rows.iter().map(|r| (mid(r), de(r.4, r.2, 0.0))).collect(),
                    2 * i + 1,
                ));
        }
        panels.push(panel);
    }
    Figure::grid(panels, 2, (620, 420))
}

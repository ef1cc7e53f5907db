//! Inertial deposition in a 90° bend against its two analytic limits (the module
//! `studies::bend_plug`): plug flow against its closed form (Yeh 1974), and Poiseuille's profile
//! without secondary flow against the onset's closed form (issue 61). Rigid spheres at Pui et
//! al.'s (1987) curvature ratio R_b/a = 5.7 (`limit` = `plug_flow`, `onset`) and, for the
//! onset, in a gentler bend of R_b/a = 25 with half as many spheres (`onset_gentle`: the
//! closed form neglects terms ∝ a/R_b), written to `paper-figures/bend/analytic.csv`
//! (`limit,stk,n,de,de_stderr,exact`) and plotted in `analytic.svg`.
//!
//! ```text
//! cargo run --release --example bend_analytic [-- N]
//! ```

use pseudorigid::output::atomic::write_atomic;
use pseudorigid::output::plot::{Figure, Panel, Series};
use pseudorigid::studies::bend_plug::{AnalyticBend, Profile, onset_deposition, plug_deposition};
use std::f64::consts::FRAC_PI_2;
use std::fmt::Write;

/// Tube radius in sphere diameters.
const TUBE: f64 = 20.0;

/// One set of rows: its `limit` label, profile, curvature ratio R_b/a, Stokes numbers, the
/// share of N tracked and the plot's legend and colour.
struct Rows {
    label: &'static str,
    profile: Profile,
    ratio: f64,
    stokes: &'static [f64],
    share: u64,
    legend: &'static str,
    color: usize,
}

/// The plug's deposition grows linearly from 0; the parabolic profile's sets in near
/// Stk ≈ ln(4a)/(4θ) ≈ 0.7 (module docs), and its closed form holds at Stk ≲ 0.3 in Pui et
/// al.'s bend (its corrections grow as Stk² a/R_b).
const ROWS: [Rows; 3] = [
    Rows {
        label: "plug_flow",
        profile: Profile::Plug,
        ratio: 5.7,
        stokes: &[0.02, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5],
        share: 1,
        legend: "plug flow, R_b/a = 5.7",
        color: 0,
    },
    Rows {
        label: "onset",
        profile: Profile::Parabolic,
        ratio: 5.7,
        stokes: &[0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.7, 1.0],
        share: 1,
        legend: "Poiseuille, no Dean flow, R_b/a = 5.7",
        color: 1,
    },
    Rows {
        label: "onset_gentle",
        profile: Profile::Parabolic,
        ratio: 25.0,
        stokes: &[0.5, 0.7, 1.0],
        share: 2,
        legend: "Poiseuille, no Dean flow, R_b/a = 25",
        color: 2,
    },
];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: u64 = std::env::args().nth(1).map_or(Ok(2000), |a| a.parse())?;
    let mut csv = String::from("limit,stk,n,de,de_stderr,exact\n");
    let curve = |exact: fn(f64, f64, f64) -> f64| {
        (0..=100)
            .map(|i| {
                let stk = f64::from(i) / 100.0;
                (stk, exact(stk, FRAC_PI_2, TUBE))
            })
            .collect()
    };
    let mut panel = Panel::new("90° bend, a = 20 d", "Stk = τU/a", "deposition efficiency")
        .with(Series::line(
            "plug flow: closed form (Yeh 1974)",
            curve(plug_deposition),
            0,
        ))
        .with(Series::line(
            "Poiseuille, no Dean flow: closed form",
            curve(onset_deposition),
            1,
        ));
    for rows in &ROWS {
        let count = n / rows.share;
        let mut points = Vec::new();
        for &stk in rows.stokes {
            let bend = AnalyticBend::new(rows.profile, rows.ratio * TUBE, TUBE, FRAC_PI_2, stk)?;
            let d = bend.deposition(count, 1, 1e-7)?;
            // The standard error from the exact η: the estimate's own is 0 with no deposit.
            let se = (d.exact * (1.0 - d.exact) / count as f64).sqrt();
            println!(
                "{} Stk {stk}: DE {:.4} ± {:.4} against {:.4} ({:+.1} se of the exact), {} neither deposited nor left",
                rows.label,
                d.efficiency(),
                d.stderr(),
                d.exact,
                (d.efficiency() - d.exact) / se,
                d.other
            );
            points.push((stk, d.efficiency()));
            writeln!(
                csv,
                "{},{stk},{count},{:.5},{:.5},{:.5}",
                rows.label,
                d.efficiency(),
                d.stderr(),
                d.exact
            )?;
        }
        let legend = format!("{}: tracked, N = {count}", rows.legend);
        panel = panel.with(Series::points(legend, points, rows.color));
    }
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("paper-figures/bend");
    write_atomic(dir.join("analytic.csv"), csv.as_bytes())?;
    Figure::single(panel).write(dir.join("analytic.svg"))?;
    println!("wrote {}/analytic.{{csv,svg}}", dir.display());
    Ok(())
}

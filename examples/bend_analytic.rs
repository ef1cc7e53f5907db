//! Inertial deposition in a 90° bend with plug flow against its closed form (Yeh 1974; the
//! module `studies::bend_plug`): rigid spheres at Pui et al.'s (1987) curvature ratio R_b/a = 5.7,
//! written to `paper-figures/bend/analytic.csv` (`limit,stk,n,de,de_stderr,exact`) and
//! plotted in `analytic.svg`.
//!
//! ```text
//! cargo run --release --example bend_analytic [-- N]
//! ```

use pseudorigid::output::atomic::write_atomic;
use pseudorigid::output::plot::{Figure, Panel, Series};
use pseudorigid::studies::bend_plug::PlugBend;
use pseudorigid::studies::bend_plug::plug_deposition;
use std::fmt::Write;

/// Tube radius in sphere diameters and Pui et al.'s curvature ratio.
const TUBE: f64 = 20.0;
const CURVATURE_RATIO: f64 = 5.7;
const STOKES: [f64; 7] = [0.02, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: u64 = std::env::args().nth(1).map_or(Ok(2000), |a| a.parse())?;
    let mut csv = String::from("limit,stk,n,de,de_stderr,exact\n");
    let mut tracked = Vec::new();
    for stk in STOKES {
        let bend = PlugBend::new(CURVATURE_RATIO * TUBE, TUBE, std::f64::consts::FRAC_PI_2, stk)?;
        let d = bend.deposition(n, 1, 1e-7)?;
        let z = (d.efficiency() - d.exact) / d.stderr().max(f64::MIN_POSITIVE);
        println!(
            "Stk {stk}: DE {:.4} ± {:.4} against {:.4} ({z:+.1} se), {} neither deposited nor left",
            d.efficiency(),
            d.stderr(),
            d.exact,
            d.other
        );
        tracked.push((stk, d.efficiency()));
        writeln!(
            csv,
            "plug_flow,{stk},{n},{:.5},{:.5},{:.5}",
            d.efficiency(),
            d.stderr(),
            d.exact
        )?;
    }
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("paper-figures/bend");
    write_atomic(dir.join("analytic.csv"), csv.as_bytes())?;
    let exact = (0..=100)
        .map(|i| {
            let stk = 0.6 * f64::from(i) / 100.0;
            (stk, plug_deposition(stk, std::f64::consts::FRAC_PI_2, TUBE))
        })
        .collect();
    Figure::single(
        Panel::new(
            "90° bend, plug flow, R_b/a = 5.7",
            "Stk = τU/a",
            "deposition efficiency",
        )
        .with(Series::line("closed form (Yeh 1974)", exact, 0))
        .with(Series::points(format!("tracked, N = {n}"), tracked, 1)),
    )
    .write(dir.join("analytic.svg"))?;
    println!("wrote {}/analytic.{{csv,svg}}", dir.display());
    Ok(())
}

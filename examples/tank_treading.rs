//! Steady tank-treading of an initially spherical Neo-Hooke particle in simple shear:
//! D = (r₁ − r₃)/(r₁ + r₃) of the in-plane axes and the inclination θ of the long axis from
//! the flow direction, for Ca ∈ [0.01, 2], by time integration (inertialess, rtol 1e-9, run to
//! t̂ = 60 + 100 Ca, long enough for the slowest relaxation at Ca = 2), compared with the
//! steady algebraic (Roscoe 1967) route and the small-Ca limits D = 5Ca/4, θ = π/4 − 3Ca/4.
//!
//! Writes `paper-figures/tank_treading/steady.csv` (integrated: r₁ in-plane long, r₂ along
//! the vorticity, r₃ in-plane short), `comparison.csv`, `steady.svg` and the runs' validity
//! diagnostics `validity.csv`.

use pseudorigid::output::{Csv, Figure, Panel, Series, paper_figure_path};
use pseudorigid::studies::shear_run::validity_table;
use pseudorigid::studies::tank_treading::{TankTreading, integrate, roscoe};
use std::error::Error;
use std::time::Instant;

/// (Ca, time-integrated, steady equations, small-Ca limit).
type Row = (f64, TankTreading, TankTreading, TankTreading);

fn main() -> Result<(), Box<dyn Error>> {
    let start = Instant::now();
    let n = 40;
    let cas: Vec<f64> = (0..=n)
        .map(|i| 0.01 * 200f64.powf(f64::from(i) / f64::from(n)))
        .collect();
    let mut steady = Csv::new(&["ca", "r1", "r2", "r3", "D", "theta_deg"]);
    let mut comparison = Csv::new(&[
        "ca",
        "D_integrated",
        "D_roscoe",
        "D_small_ca",
        "theta_deg_integrated",
        "theta_deg_roscoe",
        "theta_deg_small_ca",
        "drift",
    ]);
    let mut rows = Vec::new();
    let mut validity = Vec::new();
    for &ca in &cas {
        let int = integrate(ca, 1e-9, 60.0 + 100.0 * ca)?;
        validity.push((ca, int.validity));
        let ros = roscoe(ca)?.steady;
        let lim = TankTreading::small_ca_limit(ca);
        let s = int.steady;
        steady.push_numbers(&[
            ca,
            s.r_long,
            s.r_vorticity,
            s.r_short,
            s.deformation(),
            s.theta.to_degrees(),
        ])?;
        comparison.push_numbers(&[
            ca,
            s.deformation(),
            ros.deformation(),
            lim.deformation(),
            s.theta.to_degrees(),
            ros.theta.to_degrees(),
            lim.theta.to_degrees(),
            int.drift,
        ])?;
        println!(
            "Ca = {ca:.4}: D = {:.6} (Roscoe {:.6}), θ = {:.4}° (Roscoe {:.4}°), drift {:.1e}",
            s.deformation(),
            ros.deformation(),
            s.theta.to_degrees(),
            ros.theta.to_degrees(),
            int.drift
        );
        rows.push((ca, s, ros, lim));
    }
    let dir = "tank_treading";
    steady.write(paper_figure_path(dir, "steady.csv"))?;
    comparison.write(paper_figure_path(dir, "comparison.csv"))?;
    validity_table(&validity)?.write(paper_figure_path(dir, "validity.csv"))?;
    let curve = |f: &dyn Fn(&Row) -> f64, cap: f64| {
        rows.iter()
            .filter(|r| r.0 <= cap)
            .map(|r| (r.0, f(r)))
            .collect::<Vec<_>>()
    };
    let d_panel = Panel::new("Deformation", "Ca", "D = (r₁ − r₃)/(r₁ + r₃)")
        .with(Series::points(
            "time integration",
            curve(&|r| r.1.deformation(), 2.0),
            3,
        ))
        .with(Series::line(
            "Roscoe (steady equations)",
            curve(&|r| r.2.deformation(), 2.0),
            1,
        ))
        .with(Series::line("small Ca: 5Ca/4", curve(&|r| r.3.deformation(), 0.8), 6));
    let t_panel = Panel::new("Inclination", "Ca", "θ (degrees)")
        .with(Series::points(
            "time integration",
            curve(&|r| r.1.theta.to_degrees(), 2.0),
            3,
        ))
        .with(Series::line(
            "Roscoe (steady equations)",
            curve(&|r| r.2.theta.to_degrees(), 2.0),
            1,
        ))
        .with(Series::line(
            "small Ca: 45° − (3/4)Ca rad",
            curve(&|r| r.3.theta.to_degrees(), 0.8),
            6,
        ));
    Figure::grid(vec![d_panel, t_panel], 2, (560, 420)).write(paper_figure_path(dir, "steady.svg"))?;
    println!("tank_treading: wall time {:.2?}", start.elapsed());
    Ok(())
}

//! The force terms against their closed forms (`paper-figures/forces/`): Lamb's added-mass
//! coefficients of spheroids (aspect ratios 1, 2, 5, 10, prolate and oblate) and of the 3:2:1
//! ellipsoid, and a sphere settling from rest with added mass and the undisturbed-flow force
//! at ρ_p/ρ_f = 1000, 2, 1.0005 and 0.1 against v_t(1 − e^{−t/τ}), τ = (ρ_p + ½ρ_f)d²/(18μ).
//!
//! Writes `added_mass.csv` (`a1,a2,a3,axis,k`), `settling.csv`
//! (`rho_p,rho_f,d,mu,g,t,v_numeric,v_exact`) and a picture of each.

use pseudorigid::output::paper_figure_path;
use pseudorigid::studies::forces::{
    SettlingCase, added_mass_csv, added_mass_figure, added_mass_table, settle, settling_csv, settling_figure,
};
use std::error::Error;

/// Settling samples per case over 6τ, and the integrator's tolerance.
const SAMPLES: usize = 30;
const TOL: f64 = 1e-12;

fn main() -> Result<(), Box<dyn Error>> {
    let added = added_mass_table()?;
    for r in &added {
        println!("a = {:?}, axis {}: k = {:.10}", r.semi_axes.as_slice(), r.axis, r.k);
    }
    added_mass_csv(&added)?.write(paper_figure_path("forces", "added_mass.csv"))?;
    added_mass_figure(&added).write(paper_figure_path("forces", "added_mass.svg"))?;
    let mut settling = Vec::new();
    for case in SettlingCase::dataset() {
        let rows = settle(&case, SAMPLES, TOL)?;
        let worst = rows.iter().map(|r| (r.v_numeric - r.v_exact).abs()).fold(0.0, f64::max);
        println!(
            "ρ_p/ρ_f = {}: v_t = {:.4e} m/s, τ = {:.4e} s, largest |v − exact| = {worst:.2e} m/s",
            case.rho_p / case.rho_f,
            case.terminal_velocity(),
            case.response_time()
        );
        settling.extend(rows);
    }
    settling_csv(&settling)?.write(paper_figure_path("forces", "settling.csv"))?;
    settling_figure(&settling).write(paper_figure_path("forces", "settling.svg"))?;
    Ok(())
}

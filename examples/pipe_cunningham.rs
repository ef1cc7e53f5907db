//! Cunningham slip on the paper's fibres in air (Figs 11/12 set-up, `studies::pipe`): the
//! deposition distance and time of prolates λ₁ = 3.5 and 7, rigid and Ca = 0.25, without and
//! with the `cunningham` force term (λ = 66.5 nm, air at 20 °C and 1 atm), at tol 10⁻⁷.
//! Prints one line per case; the numbers are in `paper-figures/fig11/NOTES.md`.
//!
//! Run: `cargo run --release --example pipe_cunningham`

use pseudorigid::hydro::forces::{Cunningham, ForceTerms};
use pseudorigid::studies::pipe::PipeSetup;
use pseudorigid::studies::pipe::tracking::track_to_deposition;
use std::sync::Arc;
/// Mean free path of air at 20 °C and 1 atm (Hinds, Aerosol Technology, eq. 2.25).
const MEAN_FREE_PATH: f64 = 66.5e-9;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    for lambda1 in [3.5, 7.0] {
        for ca in [0.0, 0.25] {
            let mut out = vec![];
            for slip in [false, true] {
                let mut scene = PipeSetup::tian_cui(lambda1, ca)?;
                let d_eq = scene.length_unit;
                if slip {
                    let c = Cunningham::new(MEAN_FREE_PATH / d_eq)?;
                    scene.particle = scene
                        .particle
                        .clone()
                        .with_forces(ForceTerms::new(vec![Arc::new(c)])?)?;
                }
                let integ = scene.integrator(1e-7)?;
                let t_max = 20.0 * scene.sphere_settling_time();
                let dep = track_to_deposition(&scene, &integ, 1e-3, t_max, f64::INFINITY)?;
                out.push((dep.distance() * d_eq, dep.contact().t * scene.time_unit));
            }
            println!(
                "lambda1 {lambda1} ca {ca}: x1_dep {:.4} m -> {:.4} m (ratio {:.4}); t {:.3} s -> {:.3} s",
                out[0].0,
                out[1].0,
                out[1].0 / out[0].0,
                out[0].1,
                out[1].1
            );
        }
    }
    Ok(())
}

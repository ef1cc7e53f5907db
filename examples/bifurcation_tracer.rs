//! Track rigid spheres through a bifurcation case and report their fates: the end-to-end check
//! of `cases/bifurcation-ci.sh` (a freshly meshed and solved case, read and tracked).
//!
//! ```text
//! cargo run --release --example bifurcation_tracer -- CASE_DIR N STK
//! ```
//! Fails (exit status 1) if a particle fails or if none leaves through an outlet.

use pseudorigid::population::RunOptions;
use pseudorigid::studies::bifurcation::{Airway, Efficiency, Kind, Material, StudyRun};
use pseudorigid::studies::cavity::Shape;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [dir, n, stk] = args.as_slice() else {
        return Err("usage: bifurcation_tracer CASE_DIR N STK".into());
    };
    let airway = Airway::open(dir)?;
    let kind = Kind {
        shape: Shape::Prolate(1.0),
        material: Material::Rigid,
        stokes: stk.parse()?,
    };
    let out = StudyRun::new(&airway, kind, n.parse()?)
        .seed(1)
        .run(&RunOptions::default().quiet())?;
    let row = Efficiency::of(kind, &out);
    println!(
        "{dir}: {} cells, mean residence time {:.4} s, max speed {:.3} m/s; Stk {stk}: {:?}, DE = {:.3} ± {:.3}",
        airway.flow().cellwise().mesh().n_cells(),
        airway.mean_residence_time(),
        airway.max_speed(),
        row.counts,
        row.de(),
        row.stderr()
    );
    if row.counts.failed > 0 || row.counts.escaped == 0 {
        return Err("bifurcation_tracer: failed particles, or none escaped".into());
    }
    Ok(())
}

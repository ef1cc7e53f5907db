//! Paper Fig. 17: the airway bifurcation, and the check that its mesh resolves what the
//! figures report. The same N rigid spheres at Stk = 0.1 and 0.4 are tracked through the
//! shipped field (0.4 mm cells) and through a finer case (0.3 mm cells, made by
//! `cases/bifurcation/Allrun 0.3e-3 DIR`); DE must change by less than its standard error.
//!
//! ```text
//! cargo run --release --example fig17_airway -- N FINE_CASE_DIR
//! ```
//! Writes `paper-figures/fig17/mesh_check.csv` ([`figures::mesh_check`]).

use pseudorigid::output::paper_figure_path;
use pseudorigid::scenes::bifurcation::{Airway, Kind, Material, figures};
use pseudorigid::scenes::cavity::Shape;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [n, fine] = args.as_slice() else {
        return Err("usage: fig17_airway N FINE_CASE_DIR".into());
    };
    let shipped = Airway::open(Airway::shipped_dir())?;
    let fine = Airway::open(fine)?;
    let mut table = String::new();
    for stokes in [0.1, 0.4] {
        let kind = Kind {
            shape: Shape::Prolate(1.0),
            material: Material::Rigid,
            stokes,
        };
        let csv = figures::mesh_check(&[("h=0.4mm (shipped)", &shipped), ("h=0.3mm", &fine)], kind, n.parse()?)?;
        let text = csv.to_text();
        table.push_str(if table.is_empty() {
            &text
        } else {
            text.split_once('\n').map_or("", |t| t.1)
        });
    }
    pseudorigid::output::write_atomic(paper_figure_path("fig17", "mesh_check.csv"), table.as_bytes())?;
    print!("{table}");
    Ok(())
}

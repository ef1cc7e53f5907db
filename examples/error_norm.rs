//! The integrator's error norm on the airway bifurcation: the componentwise norm (the studies'
//! until this comparison) against the frame-independent tensor norm, each paired particle by particle with Radau IIA at
//! rtol 10⁻⁵ (`studies::bifurcation::error_norm`).
//!
//! ```text
//! cargo run --release --example error_norm -- [N] [CASE_DIR]
//! ```
//! N particles per kind (default 1 000; also `PSEUDORIGID_BIF_N`). Kinds: rigid prolates
//! λ = 20 at Stk 0.01, 0.2 and 0.5 (Fig. 18), soft spheres μ_s = 1 Pa at Stk 0.1 and soft prolates
//! λ₁ = 5, μ_s = 0.5 Pa at Stk 0.4 (Fig. 19). Writes `paper-figures/work-precision/error_norm.csv`
//! and `error_norm.svg`.

use pseudorigid::output::paper_figure_path;
use pseudorigid::studies::bifurcation::error_norm::{SETTINGS, compare, figure, table};
use pseudorigid::studies::bifurcation::{Airway, Kind, Material, figures};
use pseudorigid::studies::cavity::Shape;
use pseudorigid::studies::count_and_case;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (n, dir) = count_and_case("PSEUDORIGID_BIF_N", 1000)?;
    let airway = Airway::open(dir.unwrap_or_else(Airway::shipped_dir))?;
    let kinds = [
        (Shape::Prolate(20.0), Material::Rigid, 0.01),
        (Shape::Prolate(20.0), Material::Rigid, 0.2),
        (Shape::Prolate(20.0), Material::Rigid, 0.5),
        (Shape::Sphere, Material::ShearModulus(1.0), 0.1),
        (Shape::Prolate(5.0), Material::ShearModulus(0.5), 0.4),
    ];
    let mut rows = Vec::new();
    for (shape, material, stokes) in kinds {
        let kind = Kind {
            shape,
            material,
            stokes,
        };
        let kind_rows = compare(&airway, kind, &SETTINGS, n, figures::SEED)?;
        for r in &kind_rows {
            eprintln!(
                "{} {} Stk {}: {:?} rtol {:.0e}: CPU {:.2} s, {:.1} steps, {:.1} rejected, {} changed",
                shape.label(),
                material.label(),
                stokes,
                r.setting.norm,
                r.setting.rtol,
                r.cpu_s.unwrap_or(f64::NAN),
                r.steps,
                r.rejected,
                r.fates_changed
            );
        }
        rows.extend(kind_rows);
    }
    table(&rows, true)?.write(paper_figure_path("work-precision", "error_norm.csv"))?;
    figure(&rows).write(paper_figure_path("work-precision", "error_norm.svg"))?;
    Ok(())
}

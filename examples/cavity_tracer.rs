//! Track a passive tracer through an exported cavity field (CI end-to-end check).
//!
//! ```text
//! cargo run --release --example cavity_tracer -- CASE [LID_SPEED] [SECONDS]
//! ```
//! CASE is a solved OpenFOAM cavity case of the cube [0, 0.1 m]³ (`cases/cavity-ci/Allrun`),
//! read at its last time and blended with the no-slip wall layer (`flow::openfoam`). The tracer
//! starts at the paper's release point (0.467 L, 0.4 L, 0.983 L) (§6.3) and follows ẋ = u(x)
//! with classical RK4 (dt = 0.1 h/U) until SECONDS or until a stage leaves the mesh. The run
//! fails unless the field has the lid speed at the lid and the tracer moves.

use pseudorigid::error::FlowError;
use pseudorigid::flow::FlowField;
use pseudorigid::flow::openfoam::{BlendedFlow, FoamCase, FoamFlow};
use pseudorigid::tensor::Vec3;

const EDGE: f64 = 0.1;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let dir = args.first().ok_or("usage: cavity_tracer CASE [LID_SPEED] [SECONDS]")?;
    let lid_speed: f64 = args.get(1).map_or(Ok(0.0813), |s| s.parse())?;
    let seconds: f64 = args.get(2).map_or(Ok(2.0), |s| s.parse())?;
    let case = FoamCase::open(dir)?;
    let last = *case.times().last().ok_or("the case has no time directory")?;
    let flow = BlendedFlow::new(FoamFlow::read(&case, &[last])?)?;
    let cells = flow.cellwise().mesh().n_cells();

    let lid = flow.sample(&(Vec3::new(0.5, 0.5, 1.0) * EDGE), 0.0)?.u;
    if (lid - Vec3::new(lid_speed, 0.0, 0.0)).amax() > 1e-3 * lid_speed {
        return Err(format!("lid velocity {lid:?}, expected ({lid_speed}, 0, 0)").into());
    }

    let cells_per_edge = (cells as f64).cbrt();
    let dt = 0.1 * EDGE / cells_per_edge / lid_speed;
    let steps = (seconds / dt).ceil() as usize;
    let u = |x: &Vec3| flow.sample(x, 0.0).map(|s| s.u);
    let mut x = Vec3::new(0.467, 0.4, 0.983) * EDGE;
    let rk4 = |x: &Vec3| -> Result<Vec3, FlowError> {
        let k1 = u(x)?;
        let k2 = u(&(x + k1 * (0.5 * dt)))?;
        let k3 = u(&(x + k2 * (0.5 * dt)))?;
        let k4 = u(&(x + k3 * dt))?;
        Ok((k1 + 2.0 * k2 + 2.0 * k3 + k4) * (dt / 6.0))
    };
    let mut path_length = 0.0;
    let mut taken = 0;
    let mut ending = "time limit";
    while taken < steps {
        match rk4(&x) {
            Ok(dx) => {
                path_length += dx.norm();
                x += dx;
                taken += 1;
            }
            Err(FlowError::OutsideDomain { .. } | FlowError::OutsideMesh { .. }) => {
                ending = "reached a wall";
                break;
            }
            Err(e) => return Err(e.into()),
        }
    }
    println!(
        "{} cells; tracer after {:.2} s ({taken} RK4 steps, {ending}): x/L = ({:.4}, {:.4}, {:.4}), path {:.4} L",
        cells,
        taken as f64 * dt,
        x[0] / EDGE,
        x[1] / EDGE,
        x[2] / EDGE,
        path_length / EDGE
    );
    if path_length < 0.05 * EDGE {
        return Err(format!("tracer barely moved: path {path_length:.3e} m").into());
    }
    Ok(())
}

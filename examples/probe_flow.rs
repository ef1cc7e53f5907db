//! Probe an OpenFOAM case by hand: u and ∇u at listed points.
//!
//! ```text
//! cargo run --release --example probe_flow -- CASE_DIR TIME POINTS.csv OUT.csv
//! ```
//! CASE_DIR is an undecomposed OpenFOAM case (mesh in `constant/polyMesh`, ASCII or binary,
//! plain or gzipped); TIME names a time directory holding `U` (or `latest`). POINTS.csv has a
//! header line and columns `x,y,z`. OUT.csv gets
//! `x,y,z,inside,u1,u2,u3,l11,l12,l13,l21,l22,l23,l31,l32,l33` with l_ij = ∂u_i/∂x_j from the
//! cellwise least-squares reconstruction (`flow::openfoam::reconstruct`); `inside` is 1 or 0,
//! and the values are NaN where the point is outside the mesh. Each query walks from the
//! previous point's cell, so points along a line are fast.

use pseudorigid::flow::openfoam::{FoamCase, FoamError, FoamFlow};
use pseudorigid::output::Csv;
use pseudorigid::tensor::Vec3;

const USAGE: &str = "usage: probe_flow CASE_DIR TIME|latest POINTS.csv OUT.csv";

fn read_points(path: &str) -> Result<Vec<Vec3>, Box<dyn std::error::Error>> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{path}: {e}"))?;
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty());
    let header: Vec<&str> = lines
        .next()
        .map_or(Vec::new(), |(_, l)| l.split(',').map(str::trim).collect());
    if header != ["x", "y", "z"] {
        return Err(format!("{path}: header must be `x,y,z`, found {header:?}").into());
    }
    lines
        .map(|(i, line)| {
            let v: Vec<f64> = line
                .split(',')
                .map(|s| s.trim().parse::<f64>())
                .collect::<Result<_, _>>()
                .map_err(|e| format!("{path}:{}: {e}", i + 1))?;
            match v.as_slice() {
                [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(Vec3::new(*x, *y, *z)),
                _ => Err(format!("{path}:{}: expected three finite numbers", i + 1).into()),
            }
        })
        .collect()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [case_dir, time, points, out] = args.as_slice() else {
        return Err(USAGE.into());
    };
    let case = FoamCase::open(case_dir)?;
    let time = match time.as_str() {
        "latest" => *case.times().last().ok_or("the case has no time directories")?,
        t => t.parse().map_err(|e| format!("TIME `{t}`: {e}"))?,
    };
    let flow = FoamFlow::read(&case, &[time])?;
    let points = read_points(points)?;

    let mut table = Csv::new(&[
        "x", "y", "z", "inside", "u1", "u2", "u3", "l11", "l12", "l13", "l21", "l22", "l23", "l31", "l32", "l33",
    ]);
    let (mut hint, mut inside) = (None, 0);
    for x in &points {
        let mut row: Vec<String> = x.iter().map(|c| format!("{c:?}")).collect();
        match flow.sample_from(x, time, hint) {
            Ok((s, cell)) => {
                hint = Some(cell);
                inside += 1;
                row.push("1".into());
                row.extend(s.u.iter().map(|c| format!("{c:?}")));
                // Row-major: l11, l12, l13, l21, ...
                row.extend((0..9).map(|k| format!("{:?}", s.grad_u[(k / 3, k % 3)])));
            }
            Err(FoamError::Outside { .. }) => {
                row.push("0".into());
                row.extend(std::iter::repeat_n("NaN".to_string(), 12));
            }
            Err(e) => return Err(e.into()),
        }
        table.push(row)?;
    }
    table.write(out)?;
    eprintln!(
        "probe_flow: {} cells, t = {time}: {inside} of {} points inside, written to {out}",
        case.mesh().n_cells(),
        points.len()
    );
    Ok(())
}

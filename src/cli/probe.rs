//! `probe`: u and ∇u of an OpenFOAM case at listed points.
//!
//! POINTS.csv has a header line `x,y,z` and one point per line. The output has the columns
//! `x,y,z,inside,u1,u2,u3,l11,l12,l13,l21,l22,l23,l31,l32,l33` with l_ij = ∂u_i/∂x_j of the
//! field the particles see by default, the blended field with its no-slip wall layer
//! (`flow::openfoam::BlendedFlow`), or with `cellwise` of the containing cell's least-squares
//! fit (`flow::openfoam::reconstruct`); `inside` is 1 or 0, and the values are NaN where the
//! point is outside the mesh. Each query walks from the previous point's cell, so points along
//! a line are fast.

use crate::flow::FlowField;
use crate::flow::openfoam::{BlendedFlow, FoamCase, FoamError, FoamFlow};
use crate::output::Csv;
use crate::scene::SceneError;
use crate::tensor::Vec3;
use std::path::Path;

/// Points allowed in one probe file (a line of 10⁷ points is 0.5 GB of output).
pub const MAX_POINTS: usize = 10_000_000;

/// Read `x,y,z` points.
pub fn read_points(path: &Path) -> Result<Vec<Vec3>, SceneError> {
    let name = path.display();
    let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let mut lines = text.lines().enumerate().filter(|(_, l)| !l.trim().is_empty());
    let header: Vec<&str> = lines
        .next()
        .map_or(Vec::new(), |(_, l)| l.split(',').map(str::trim).collect());
    if header != ["x", "y", "z"] {
        return Err(SceneError::Input(format!(
            "{name}: header must be `x,y,z`, found {header:?}"
        )));
    }
    lines
        .take(MAX_POINTS + 1)
        .map(|(i, line)| {
            let v: Vec<f64> = line
                .split(',')
                .map(|s| s.trim().parse::<f64>())
                .collect::<Result<_, _>>()
                .map_err(|e| SceneError::Input(format!("{name}:{}: {e}", i + 1)))?;
            match v.as_slice() {
                [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok(Vec3::new(*x, *y, *z)),
                _ => Err(SceneError::Input(format!(
                    "{name}:{}: expected three finite numbers",
                    i + 1
                ))),
            }
        })
        .enumerate()
        .map(|(n, p)| {
            if n == MAX_POINTS {
                Err(SceneError::Input(format!("{name}: more than {MAX_POINTS} points")))
            } else {
                p
            }
        })
        .collect()
}

/// Sample the case in `case_dir` at time `time` (`latest` or a number) at the points of
/// `points`, blended or `cellwise`, write the table to `out`, and return a one-line summary.
pub fn probe(case_dir: &Path, time: &str, points: &Path, out: &Path, cellwise: bool) -> Result<String, SceneError> {
    let case = FoamCase::open(case_dir)?;
    let time = match time {
        "latest" => *case
            .times()
            .last()
            .ok_or_else(|| SceneError::Input(format!("{}: the case has no time directories", case_dir.display())))?,
        t => t
            .parse()
            .ok()
            .filter(|t: &f64| t.is_finite())
            .ok_or_else(|| SceneError::Input(format!("TIME `{t}` is neither `latest` nor a finite number")))?,
    };
    let flow = FoamFlow::read(&case, &[time])?;
    let blend = if cellwise {
        None
    } else {
        Some(BlendedFlow::new(flow.clone())?)
    };
    let points = read_points(points)?;
    let mut table = Csv::new(&[
        "x", "y", "z", "inside", "u1", "u2", "u3", "l11", "l12", "l13", "l21", "l22", "l23", "l31", "l32", "l33",
    ]);
    let (mut hint, mut inside) = (None, 0);
    for x in &points {
        let mut row: Vec<String> = x.iter().map(|c| format!("{c:?}")).collect();
        match flow.sample_from(x, time, hint) {
            Ok((cells, cell)) => {
                hint = Some(cell);
                let s = match &blend {
                    Some(b) => b.sample(x, time).map_err(|e| SceneError::Input(e.to_string()))?,
                    None => cells,
                };
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
    Ok(format!(
        "probe: {} cells, t = {time}, {} field: {inside} of {} points inside, written to {}",
        case.mesh().n_cells(),
        if cellwise { "cellwise" } else { "blended" },
        points.len(),
        out.display()
    ))
}

//! The files of a finished run: per-particle results, ParaView frames at the output times with
//! their `.pvd` index, trajectories as polylines, and the same numbers as CSV.
//!
//! A frame at time t shows every particle at its last state at or before t. Its `flag` says
//! what the particle is doing then: 0 while it moves, afterwards its fate
//! ([`fate_code`](crate::population::columns::fate_code)). A deposited particle therefore stays
//! where it touched, flagged 1, in every later frame. The particles of a frame are
//! [`at_time`], beside the columns of a run's tables.

use crate::material::NamedLaw;
use crate::output::vtk::{CloudPoint, PointValues, PolyData, particle_cloud, write_pvd};
use crate::output::{Csv, OutputError};
use crate::population::columns::{FRAME_COLUMNS, at_time, frame_measures};
use crate::population::{ParticleRecord, RunOutput};
use crate::scene::error::SceneError;
use crate::tensor::Vec3;
use std::path::Path;

/// Columns of `trajectories.csv`: every kept state of every particle.
pub const TRAJECTORY_HEADER: [&str; 5] = ["id", "t", "x1", "x2", "x3"];

/// Whether a run writes CSV tables: when `asked`, and always without the feature `parquet`
/// (CSV is then the only table format).
pub fn csv_tables(asked: bool) -> bool {
    asked || !cfg!(feature = "parquet")
}

/// Write a run's tables into `dir`: with the feature `parquet`, `records.parquet` and
/// `frames.parquet` at `times`; with CSV ([`csv_tables`]`(csv)`), `results.csv`. With `vtk`,
/// the frames at `times` (`vtk/particles_*.vtp`, `particles.pvd`; `frames.csv` with CSV) and
/// the trajectories (`vtk/trajectories.vtp`; `trajectories.csv` with CSV). The records
/// themselves are in the run's checkpoint. Returns the number of frames written in any
/// format (without `vtk` and without `parquet`, none).
pub fn write_run(
    output: &RunOutput<NamedLaw>,
    times: &[f64],
    vtk: bool,
    csv: bool,
    dir: &Path,
) -> Result<usize, SceneError> {
    let csv = csv_tables(csv);
    if csv {
        output.table()?.write(dir.join("results.csv"))?;
    }
    #[cfg(feature = "parquet")]
    {
        crate::scene::parquet::write_records(output, &dir.join("records.parquet"))?;
        crate::scene::parquet::write_frames(output, times, &dir.join("frames.parquet"))?;
    }
    if !vtk {
        // The frames are in `frames.parquet` alone, if anywhere.
        return Ok(if cfg!(feature = "parquet") { times.len() } else { 0 });
    }
    let mut index = Vec::with_capacity(times.len());
    // One row per particle per frame ([`FRAME_COLUMNS`]), the numbers of the `.vtp` files.
    let mut table = Csv::new(&FRAME_COLUMNS);
    for (frame, &t) in times.iter().enumerate() {
        let points: Vec<CloudPoint> = at_time(&output.records, t).collect();
        for p in points.iter().filter(|_| csv) {
            let mut row = vec![frame.to_string(), format!("{t:?}"), p.id.to_string()];
            row.extend(frame_measures(p).iter().map(|c| format!("{c:?}")));
            row.push(p.flag.to_string());
            table.push(row)?;
        }
        let name = format!("vtk/particles_{frame:06}.vtp");
        particle_cloud(&points)
            .and_then(PolyData::single_precision)
            .map_err(OutputError::from)?
            .write(dir.join(&name))?;
        index.push((t, name));
    }
    write_pvd(dir.join("particles.pvd"), &index)?;
    if csv {
        table.write(dir.join("frames.csv"))?;
    }
    write_trajectories(&output.records, dir, csv)?;
    Ok(times.len())
}

/// One polyline per particle through its kept states, with point arrays `id` and `t`.
fn write_trajectories(records: &[ParticleRecord<NamedLaw>], dir: &Path, csv: bool) -> Result<(), SceneError> {
    let mut points: Vec<Vec3> = Vec::new();
    let (mut ids, mut ts, mut lines) = (Vec::new(), Vec::new(), Vec::new());
    let mut table = Csv::new(&TRAJECTORY_HEADER);
    for r in records.iter().filter(|r| !r.samples.is_empty()) {
        let start = points.len();
        for s in &r.samples {
            points.push(s.x);
            ids.push(r.index as i64);
            ts.push(s.t);
            if !csv {
                continue;
            }
            let mut row = vec![r.index.to_string(), format!("{:?}", s.t)];
            row.extend(s.x.iter().map(|c| format!("{c:?}")));
            table.push(row)?;
        }
        lines.push((start..points.len()).collect());
    }
    let data = PolyData::polylines(points, lines)
        .and_then(|d| d.with_array("id", 1, PointValues::Int64(ids)))
        .and_then(|d| d.with_array("t", 1, PointValues::Float64(ts)))
        .and_then(PolyData::single_precision)
        .map_err(OutputError::from)?;
    data.write(dir.join("vtk/trajectories.vtp"))?;
    if csv {
        table.write(dir.join("trajectories.csv"))?;
    }
    Ok(())
}

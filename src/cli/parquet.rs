//! The analysis tables of a run as Parquet (feature `parquet`): `records.parquet`, one row per
//! particle, and `frames.parquet`, one row per particle per frame. Every f64 is stored as
//! written (PLAIN, dictionary or BYTE_STREAM_SPLIT pages, Snappy), so a reader gets the records
//! bit for bit; a value that does not exist (the patch of a suspended particle, μ_s of a rigid
//! one) is null.
//!
//! The frames keep the six independent components of the symmetric V = √(F̄F̄ᵀ); the frame
//! index, time, id and flag repeat and compress to a few bits per row. The measured columns
//! (position, V, r) rarely repeat, so they skip the dictionary and are written
//! BYTE_STREAM_SPLIT: the k-th bytes of all values are stored together, which groups the
//! slowly varying sign, exponent and leading mantissa bytes where Snappy finds them. On the
//! 400-particle shear run of the README this takes `frames.parquet` from 101 to 71 bytes per
//! particle-frame.

use super::error::CliError;
use super::frames::at_time;
use super::models::SceneLaw;
use crate::material::{Softness, StressLaw};
use crate::output::parquet::Table;
use crate::output::vtk::stretch;
use crate::population::{Fate, RunOutput};
use serde::Serialize;
use serde::de::DeserializeOwned;
use std::path::Path;

/// `records.parquet`: index, fate, patch and its name, the end state (t, x, r₁..r₃, F), the
/// particle's spec (injection point, rest semi-axes, μ_s), step statistics and the error of a
/// failed particle.
pub fn write_records<L: StressLaw + Serialize + DeserializeOwned>(
    output: &RunOutput<L>,
    path: &Path,
) -> Result<(), CliError> {
    let recs = &output.records;
    let mut t = Table::default();
    t.u64("index", recs.iter().map(|r| r.index).collect());
    t.text("fate", recs.iter().map(|r| Some(r.fate.label().to_string())).collect());
    t.i64_or_null("patch", recs.iter().map(|r| r.fate.patch().map(|p| p as i64)).collect());
    t.text(
        "patch_name",
        recs.iter()
            .map(|r| {
                r.fate
                    .patch()
                    .map(|p| output.patches.get(p).cloned().unwrap_or_default())
            })
            .collect(),
    );
    let end = |f: &dyn Fn(&crate::particle::State) -> f64| -> Vec<Option<f64>> {
        recs.iter().map(|r| r.end.as_ref().map(f)).collect()
    };
    t.f64_or_null("t", end(&|s| s.t));
    for i in 0..3 {
        t.f64_or_null(&format!("x{}", i + 1), end(&|s| s.x[i]));
    }
    for i in 0..3 {
        t.f64_or_null(
            &format!("r{}", i + 1),
            recs.iter().map(|r| r.end_frame().map(|f| f.r[i])).collect(),
        );
    }
    for i in 0..3 {
        for j in 0..3 {
            t.f64_or_null(&format!("F{}{}", i + 1, j + 1), end(&|s| s.f[(i, j)]));
        }
    }
    for i in 0..3 {
        t.f64_or_null(
            &format!("x0_{}", i + 1),
            recs.iter().map(|r| r.spec.as_ref().map(|s| s.position[i])).collect(),
        );
    }
    for i in 0..3 {
        t.f64_or_null(
            &format!("rest_r{}", i + 1),
            recs.iter()
                .map(|r| r.spec.as_ref().map(|s| s.shape.semi_axes()[i]))
                .collect(),
        );
    }
    t.f64_or_null(
        "mu_s",
        recs.iter()
            .map(|r| match r.spec.as_ref().map(|s| &s.softness) {
                Some(Softness::Elastic(law)) => Some(law.shear_modulus()),
                _ => None,
            })
            .collect(),
    );
    t.f64_or_null(
        "rho_s",
        recs.iter().map(|r| r.spec.as_ref().map(|s| s.density)).collect(),
    );
    t.u64("steps", recs.iter().map(|r| r.stats.steps).collect());
    t.u64("rejected", recs.iter().map(|r| r.stats.rejected).collect());
    t.u64("rhs_evals", recs.iter().map(|r| r.stats.rhs_evals).collect());
    t.u64("jac_evals", recs.iter().map(|r| r.stats.jac_evals).collect());
    t.text(
        "error",
        recs.iter()
            .map(|r| match &r.fate {
                Fate::Failed { error } => Some(error.clone()),
                _ => None,
            })
            .collect(),
    );
    Ok(t.write(path)?)
}

/// Columns of `frames.parquet`.
pub const FRAME_COLUMNS: [&str; 16] = [
    "frame", "time", "id", "x1", "x2", "x3", "V11", "V12", "V13", "V22", "V23", "V33", "r1", "r2", "r3", "flag",
];

/// `frames.parquet`: every particle at every frame time (the numbers of `frames.csv`, V by its
/// six independent components).
pub fn write_frames(output: &RunOutput<SceneLaw>, times: &[f64], path: &Path) -> Result<(), CliError> {
    let (mut frame, mut time, mut id, mut flag) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); 12];
    for (k, &t) in times.iter().enumerate() {
        for p in at_time(&output.records, t) {
            let (v, r) = stretch(&p.f_bar);
            frame.push(k as i64);
            time.push(t);
            id.push(p.id);
            flag.push(p.flag);
            let row = [
                p.x[0],
                p.x[1],
                p.x[2],
                v[(0, 0)],
                v[(0, 1)],
                v[(0, 2)],
                v[(1, 1)],
                v[(1, 2)],
                v[(2, 2)],
                r[0],
                r[1],
                r[2],
            ];
            for (c, x) in cols.iter_mut().zip(row) {
                c.push(x);
            }
        }
    }
    let mut t = Table::default();
    t.i64("frame", frame);
    t.f64("time", time);
    t.i64("id", id);
    for (name, c) in FRAME_COLUMNS[3..15].iter().zip(cols) {
        t.f64_measured(name, c);
    }
    t.i64("flag", flag);
    Ok(t.write(path)?)
}

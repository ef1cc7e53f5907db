//! Where particles deposit: streamwise histograms (paper Figs 19, 21, 23), deposition maps
//! with the deposited shapes (Figs 20, 22) and the largest semi-axis r₁ among them.

use super::BifurcationError;
use super::injection::{Injection, Kind};
use super::setup::{Airway, LENGTH};
use crate::contact::Boundary;
use crate::material::NeoHooke;
use crate::output::Csv;
use crate::population::{Fate, Injector, RunOutput};
use crate::tensor::{Mat3, Vec3};

/// One deposited particle: where, on which patch, and its shape there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Deposit {
    /// Particle index.
    pub index: u64,
    /// Barycentre at contact (m).
    pub x: Vec3,
    /// Patch index of the boundary.
    pub patch: usize,
    /// Left stretch of the total distortion, V = √(F̄F̄ᵀ) with F̄ = F S (m): the current
    /// ellipsoid is V·(unit ball) about x.
    pub v: Mat3,
    /// Semi-axes r₁ ≥ r₂ ≥ r₃ (m).
    pub r: Vec3,
}

/// The deposits of a run of `kind` in `airway`, by particle index.
pub fn deposits(airway: &Airway, kind: Kind, output: &RunOutput<NeoHooke>) -> Result<Vec<Deposit>, BifurcationError> {
    let injection = Injection::new(airway, kind)?;
    let mut out = Vec::new();
    for r in &output.records {
        let (Fate::Deposited { patch, position, .. }, Some(spec), Some(end)) = (&r.fate, &r.spec, &r.end) else {
            continue;
        };
        let particle = injection.particle(spec)?;
        let frame = particle.frame(&end.f);
        let v = frame.q.transpose() * Mat3::from_diagonal(&frame.r) * frame.q;
        out.push(Deposit {
            index: r.index,
            x: *position,
            patch: *patch,
            v,
            r: frame.r,
        });
    }
    Ok(out)
}

/// Counts of deposits in `bins` equal bins of x₁/L over [0, 1] (deposits outside are clamped to
/// the end bins: the wall ends at the inlet and outlet planes).
pub fn histogram(deposits: &[Deposit], bins: usize) -> Vec<u64> {
    let mut counts = vec![0u64; bins];
    if bins == 0 {
        return counts;
    }
    for d in deposits {
        let s = (d.x[0] / LENGTH * bins as f64).floor();
        let k = if s.is_nan() {
            0
        } else {
            (s.max(0.0) as usize).min(bins - 1)
        };
        counts[k] += 1;
    }
    counts
}

/// Mean x₁/L of the deposits and its standard error (sample standard deviation / √n); `None`
/// for fewer than two deposits.
pub fn mean_position(deposits: &[Deposit]) -> Option<(f64, f64)> {
    let n = deposits.len();
    if n < 2 {
        return None;
    }
    let xs = deposits.iter().map(|d| d.x[0] / LENGTH);
    let mean = xs.clone().sum::<f64>() / n as f64;
    let var = xs.map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1) as f64;
    Some((mean, (var / n as f64).sqrt()))
}

/// The deposit with the largest r₁.
pub fn largest(deposits: &[Deposit]) -> Option<&Deposit> {
    deposits.iter().max_by(|a, b| a.r[0].total_cmp(&b.r[0]))
}

/// Label of a kind for tables: `shape,material,stk`.
fn kind_cells(kind: &Kind) -> Vec<String> {
    vec![kind.shape.label(), kind.material.label(), kind.stokes.to_string()]
}

/// `shape,material,stk,bin,x1_over_l_lo,x1_over_l_hi,count,fraction_of_injected`.
pub fn histogram_table(runs: &[(Kind, u64, Vec<Deposit>)], bins: usize) -> Result<Csv, BifurcationError> {
    let mut csv = Csv::new(&[
        "shape",
        "material",
        "stk",
        "bin",
        "x1_over_l_lo",
        "x1_over_l_hi",
        "count",
        "fraction_of_injected",
    ]);
    for (kind, injected, deps) in runs {
        for (k, c) in histogram(deps, bins).into_iter().enumerate() {
            let mut row = kind_cells(kind);
            row.extend([
                k.to_string(),
                format!("{:.3}", k as f64 / bins as f64),
                format!("{:.3}", (k + 1) as f64 / bins as f64),
                c.to_string(),
                format!("{:.6}", c as f64 / (*injected).max(1) as f64),
            ]);
            csv.push(row)?;
        }
    }
    Ok(csv)
}

/// `shape,material,stk,n_deposited,mean_x1_over_l,mean_stderr,r1_max,r1_max_x1_over_l,
/// r1_max_x2,r1_max_x3`: mean streamwise deposition and the largest deposited semi-axis with
/// its place (x₂, x₃ in m).
pub fn summary_table(runs: &[(Kind, u64, Vec<Deposit>)]) -> Result<Csv, BifurcationError> {
    let mut csv = Csv::new(&[
        "shape",
        "material",
        "stk",
        "n_deposited",
        "mean_x1_over_l",
        "mean_stderr",
        "r1_max",
        "r1_max_x1_over_l",
        "r1_max_x2",
        "r1_max_x3",
    ]);
    for (kind, _, deps) in runs {
        let mut row = kind_cells(kind);
        row.push(deps.len().to_string());
        match mean_position(deps) {
            Some((m, s)) => row.extend([format!("{m:.4}"), format!("{s:.4}")]),
            None => row.extend([String::new(), String::new()]),
        }
        match largest(deps) {
            Some(d) => row.extend([
                format!("{:.4e}", d.r[0]),
                format!("{:.4}", d.x[0] / LENGTH),
                format!("{:.4e}", d.x[1]),
                format!("{:.4e}", d.x[2]),
            ]),
            None => row.extend([String::new(), String::new(), String::new(), String::new()]),
        }
        csv.push(row)?;
    }
    Ok(csv)
}

/// `shape,material,stk,index,x1,x2,x3,patch,r1,r2,r3,v11,v12,v13,v22,v23,v33` (m): one row per
/// deposit (V is symmetric).
pub fn map_table(runs: &[(Kind, u64, Vec<Deposit>)], boundary: &impl Boundary) -> Result<Csv, BifurcationError> {
    let mut csv = Csv::new(&[
        "shape", "material", "stk", "index", "x1", "x2", "x3", "patch", "r1", "r2", "r3", "v11", "v12", "v13", "v22",
        "v23", "v33",
    ]);
    for (kind, _, deps) in runs {
        for d in deps {
            let mut row = kind_cells(kind);
            row.push(d.index.to_string());
            row.extend(d.x.iter().map(|c| format!("{c:.6e}")));
            row.push(boundary.patch_name(d.patch).to_string());
            row.extend(d.r.iter().map(|c| format!("{c:.5e}")));
            for (i, j) in [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)] {
                row.push(format!("{:.5e}", d.v[(i, j)]));
            }
            csv.push(row)?;
        }
    }
    Ok(csv)
}

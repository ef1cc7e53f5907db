//! The datasets of the paired runs: DE per flow, the paired change, DE by injection time and
//! the deposit maps.

use super::{BreathingPair, Waveform, by_phase};
use crate::output::Csv;
use crate::population::Fate;
use crate::studies::bifurcation::BifurcationError;
use crate::studies::bifurcation::injection::Kind;

/// μ_s for the tables: `inf` for rigid, else Pa.
fn mu_s(kind: Kind) -> String {
    crate::studies::airway_tree::study::mu_s_label(kind.material)
}

/// `shape,mu_s,stk,flow,n,n_deposited,n_escaped,n_suspended,n_failed,de,de_stderr`, a row per
/// kind and flow (`steady`, `cyclic`); DE over the particles that did not fail, binomial
/// standard error ([`crate::population::binomial`]).
pub fn de_table(pairs: &[BreathingPair]) -> Result<Csv, BifurcationError> {
    let mut csv = Csv::new(&[
        "shape",
        "mu_s",
        "stk",
        "flow",
        "n",
        "n_deposited",
        "n_escaped",
        "n_suspended",
        "n_failed",
        "de",
        "de_stderr",
    ]);
    for p in pairs {
        for (flow, out) in [("steady", &p.steady), ("cyclic", &p.cyclic)] {
            let c = out.counts();
            let n = c.total() - c.failed;
            csv.push(vec![
                p.kind.shape.label(),
                mu_s(p.kind),
                p.kind.stokes.to_string(),
                flow.into(),
                n.to_string(),
                c.deposited.to_string(),
                c.escaped.to_string(),
                c.suspended.to_string(),
                c.failed.to_string(),
                format!("{:.5}", crate::population::binomial::fraction(c.deposited, n)),
                format!("{:.5}", crate::population::binomial::stderr(c.deposited, n)),
            ])?;
        }
    }
    Ok(csv)
}

/// `shape,mu_s,stk,n,steady_only,cyclic_only,delta_de,delta_de_stderr,paired_z`: the same
/// particles steady and inhaled, ΔDE = (cyclic_only − steady_only)/n with McNemar's standard
/// error √(steady_only + cyclic_only)/n and z = ΔDE over it ([`BreathingPair::pairing`]).
pub fn paired_table(pairs: &[BreathingPair]) -> Result<Csv, BifurcationError> {
    let mut csv = Csv::new(&[
        "shape",
        "mu_s",
        "stk",
        "n",
        "steady_only",
        "cyclic_only",
        "delta_de",
        "delta_de_stderr",
        "paired_z",
    ]);
    for p in pairs {
        let pairing = p.pairing()?;
        let (gained, lost) = (pairing.only_ours, pairing.only_peer);
        let fates = pairing.fates_or_zero();
        csv.push(vec![
            p.kind.shape.label(),
            mu_s(p.kind),
            p.kind.stokes.to_string(),
            p.steady.records.len().to_string(),
            lost.to_string(),
            gained.to_string(),
            format!("{:.5}", fates.difference()),
            format!("{:.5}", fates.stderr_under_null()),
            format!("{:.2}", fates.z()),
        ])?;
    }
    Ok(csv)
}

/// `shape,mu_s,stk,t_start,t_end,u_in_over_u,n,de_cyclic,de_cyclic_stderr,de_steady,
/// de_steady_stderr`: DE by injection time in `bins` bins of the inhalation, inhaled and (the
/// same particles) steady; `u_in_over_u` is U_in/U at the bin's middle.
pub fn phase_table(pairs: &[BreathingPair], waveform: Waveform, bins: usize) -> Result<Csv, BifurcationError> {
    let mut csv = Csv::new(&[
        "shape",
        "mu_s",
        "stk",
        "t_start",
        "t_end",
        "u_in_over_u",
        "n",
        "de_cyclic",
        "de_cyclic_stderr",
        "de_steady",
        "de_steady_stderr",
    ]);
    use crate::population::binomial::{fraction, stderr};
    for p in pairs {
        for (t0, t1, n, dc, ds) in by_phase(p, waveform.duration(), bins) {
            csv.push(vec![
                p.kind.shape.label(),
                mu_s(p.kind),
                p.kind.stokes.to_string(),
                format!("{t0:.3}"),
                format!("{t1:.3}"),
                format!("{:.4}", waveform.scale(0.5 * (t0 + t1))),
                n.to_string(),
                format!("{:.5}", fraction(dc, n)),
                format!("{:.5}", stderr(dc, n)),
                format!("{:.5}", fraction(ds, n)),
                format!("{:.5}", stderr(ds, n)),
            ])?;
        }
    }
    Ok(csv)
}

/// Particles per kind whose deposits the maps show (as
/// [`figures::MAP_PARTICLES`](crate::studies::bifurcation::figures::MAP_PARTICLES)).
pub const MAP_PARTICLES: u64 = crate::studies::bifurcation::figures::MAP_PARTICLES;

/// `shape,mu_s,stk,flow,index,t_injected,t_deposited,x1,x2,x3`: the deposits of the first
/// [`MAP_PARTICLES`] particles of each kind, steady and inhaled.
pub fn map_table(pairs: &[BreathingPair]) -> Result<Csv, BifurcationError> {
    let mut csv = Csv::new(&[
        "shape",
        "mu_s",
        "stk",
        "flow",
        "index",
        "t_injected",
        "t_deposited",
        "x1",
        "x2",
        "x3",
    ]);
    for p in pairs {
        for (flow, out) in [("steady", &p.steady), ("cyclic", &p.cyclic)] {
            for (r, t) in out.records.iter().zip(&p.times) {
                let Fate::Deposited { position, time, .. } = r.fate else {
                    continue;
                };
                if r.index >= MAP_PARTICLES {
                    continue;
                }
                let t_inj = if flow == "steady" { 0.0 } else { *t };
                csv.push(vec![
                    p.kind.shape.label(),
                    mu_s(p.kind),
                    p.kind.stokes.to_string(),
                    flow.into(),
                    r.index.to_string(),
                    format!("{t_inj:.5}"),
                    format!("{time:.5}"),
                    format!("{:.6e}", position[0]),
                    format!("{:.6e}", position[1]),
                    format!("{:.6e}", position[2]),
                ])?;
            }
        }
    }
    Ok(csv)
}

//! Deposition studies: populations of one particle kind, their deposition efficiency with its
//! binomial error, and the paper's figures' datasets.
//!
//! # Statistics
//! Each particle deposits independently with probability p, so the deposited count of n
//! particles is binomial and DE = n_dep/n estimates p with standard error
//! $\sqrt{DE(1 − DE)/n}$. Failed particles (an integration error) are left out of n and reported.

use super::BifurcationError;
use super::injection::{Injection, Kind};
use super::setup::Airway;
use crate::driver::{Budget, Plan};
use crate::error::ParamError;
use crate::integrator::{BarycentreModel, Stokesian, Tolerances};
use crate::material::NeoHooke;
use crate::output::Csv;
use crate::population::{Case, Fate, FateCounts, RunConfig, RunOptions, RunOutput, Shard, run};
use serde::Serialize;
use std::path::Path;

/// Relative error tolerance of the integrator (absolute: [`ATOL`], SI units). Checked by a
/// paired run: the same 200 rigid spheres at Stk = 0.1 meet the same fates at rtol 10⁻³ and
/// 10⁻⁴ (atol 10⁻⁶ and 10⁻⁷), and the deposits agree in x₁/L to 10⁻⁴.
pub const RTOL: f64 = 1e-3;
/// Absolute tolerance (SI): 10⁻⁶ m on positions, 10⁻⁶ m/s on velocities (10⁻⁶ of the inlet
/// speed), 10⁻⁶ on F; see [`RTOL`] for the check.
pub const ATOL: f64 = 1e-6;
/// First step (s) (the integrator adapts it at once).
pub const DT0: f64 = 1e-6;
/// Longest distance a particle may travel in one step (m): a quarter of the shipped mesh's
/// 0.4 mm cells. The contact event caps a step by the approach to the *nearest* wall face only;
/// at the carina ridge a particle heading for the face across the ridge was carried through it
/// within one step (its trial stages left the mesh: 1–4 particles in 1000 failed so), as in a
/// corner. Capping every step at this length / the field's largest speed keeps each step to a
/// fraction of a cell and of the carina's 1.2 mm radius.
pub const STEP_LENGTH: f64 = 1e-4;
/// Accepted steps allowed per particle (10⁶: a particle that needs more is stuck, not slow).
pub const MAX_STEPS: u64 = 1_000_000;

/// The integrator of the studies: inertialess shape, inertial barycentre, rtol [`RTOL`],
/// atol [`ATOL`].
pub fn integrator() -> Result<Stokesian, ParamError> {
    Ok(Stokesian {
        tol: Tolerances::new(RTOL, ATOL, 1e-14)?,
        barycentre: BarycentreModel::Inertial,
        ..Stokesian::new(RTOL)?
    })
}

/// Track particles until contact, exit or [`Airway::tracking_time`], with steps of at most
/// [`STEP_LENGTH`] at the field's largest speed.
pub fn plan(airway: &Airway) -> Result<Plan, ParamError> {
    let dt_max = STEP_LENGTH / airway.max_speed();
    Ok(Plan::new(airway.tracking_time(), DT0)?
        .with_dt_max(dt_max)?
        .with_budget(Budget {
            max_steps: MAX_STEPS,
            wall_time: None,
        }))
}

/// The run of `n` particles of `kind` with run seed `seed` (or its shard `shard`). With
/// `cache` a folder, a finished run is kept there as `<config hash>.json` and read back instead
/// of rerun (the hash covers everything that determines the results).
pub fn run_kind(
    airway: &Airway,
    kind: Kind,
    n: u64,
    seed: u64,
    shard: Shard,
    options: &RunOptions,
    cache: Option<&Path>,
) -> Result<RunOutput<NeoHooke>, BifurcationError> {
    let injection = Injection::new(airway, kind)?;
    let integ = integrator()?;
    let plan = plan(airway)?;
    let case = Case::new(&integ, airway.flow(), airway.boundary(), &injection, plan);
    let config = RunConfig {
        seed,
        particles: n,
        fingerprint: format!(
            "bifurcation {kind:?}; residence time {:e}; cells {}; blend radius {:e}",
            airway.mean_residence_time(),
            airway.flow().cellwise().mesh().n_cells(),
            airway.flow().radius()
        ),
    };
    let file = cache.map(|dir| dir.join(format!("{}-{shard}.json", case.config_hash(&config)).replace('/', "of")));
    if let Some(file) = &file
        && file.is_file()
    {
        return Ok(RunOutput::read_json(file)?);
    }
    let out = run(&case, &config, shard, options)?;
    if let Some(file) = &file {
        out.write_json(file)?;
    }
    Ok(out)
}

/// Deposition efficiency of one particle kind.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Efficiency {
    /// The particle kind.
    pub kind: Kind,
    /// Fates.
    pub counts: FateCounts,
}

impl Efficiency {
    /// Count the fates of a run of `kind`.
    pub fn of(kind: Kind, output: &RunOutput<NeoHooke>) -> Self {
        Self {
            kind,
            counts: output.counts(),
        }
    }

    /// Particles that finished (deposited, escaped or suspended).
    pub fn finished(&self) -> u64 {
        self.counts.total() - self.counts.failed
    }

    /// DE = n_dep/n over the finished particles (0 if none).
    pub fn de(&self) -> f64 {
        let n = self.finished();
        if n == 0 {
            0.0
        } else {
            self.counts.deposited as f64 / n as f64
        }
    }

    /// Binomial standard error √(DE(1 − DE)/n).
    pub fn stderr(&self) -> f64 {
        let n = self.finished();
        if n == 0 {
            0.0
        } else {
            (self.de() * (1.0 - self.de()) / n as f64).sqrt()
        }
    }
}

/// `shape,ca,stk,n_injected,n_deposited,n_escaped,n_suspended,de,de_stderr`: n_injected
/// counts every particle, failed ones included (none in the shipped datasets; DE leaves them
/// out).
pub fn efficiency_table(rows: &[Efficiency]) -> Result<Csv, crate::output::OutputError> {
    let mut csv = Csv::new(&[
        "shape",
        "ca",
        "stk",
        "n_injected",
        "n_deposited",
        "n_escaped",
        "n_suspended",
        "de",
        "de_stderr",
    ]);
    for r in rows {
        csv.push(vec![
            r.kind.shape.label(),
            format!("{:.4e}", r.kind.material.capillary_number()),
            r.kind.stokes.to_string(),
            r.counts.total().to_string(),
            r.counts.deposited.to_string(),
            r.counts.escaped.to_string(),
            r.counts.suspended.to_string(),
            format!("{:.5}", r.de()),
            format!("{:.5}", r.stderr()),
        ])?;
    }
    Ok(csv)
}

/// The deposited particles of a run: (index, barycentre x, time).
pub fn deposits(output: &RunOutput<NeoHooke>) -> impl Iterator<Item = (u64, crate::tensor::Vec3, f64)> + '_ {
    output.records.iter().filter_map(|r| match r.fate {
        Fate::Deposited { position, time, .. } => Some((r.index, position, time)),
        _ => None,
    })
}

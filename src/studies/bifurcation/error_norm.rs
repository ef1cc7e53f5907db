//! The integrator's error norm on the airway bifurcation: cost and accuracy of the
//! componentwise norm (the studies' setting until the tensor norm replaced it) against the
//! frame-independent tensor norm
//! ([`crate::integrator::ErrorNorm`]), each paired particle by particle with a tight reference.
//!
//! # What is compared
//! For each kind, the same N particles (the studies' seed) are tracked with the studies'
//! scheme ([`super::study::integrator`]: inertialess shape, Rosenbrock-W 2(3), atol
//! [`super::study::ATOL`]) under each [`NormSetting`] (the studies': tensor norm at rtol
//! [`super::study::RTOL`] = 10⁻³), and once with
//! the reference: Radau IIA(5) at rtol 10⁻⁵, atol 10⁻⁸, where both norms give the same
//! solution to well below the studies' tolerance (its componentwise weights are 10³ times
//! tighter than the looser setting's). Per setting: the process's CPU time, accepted and
//! rejected steps per particle, deposits, the fates that differ from the reference's
//! (deposited against not), and how far the deposits that agree lie from the reference's
//! (median and 90th percentile). A fate that flips with the integrator is what the
//! studies' tolerance argument bounds ([`super::study::RTOL`]: about 1 in 10³).

use super::study::{ATOL, StudyRun, integrator};
use super::{Airway, BifurcationError, Kind};
use crate::integrator::{ErrorNorm, Scheme, Stokesian, Tolerances};
use crate::material::NeoHooke;
use crate::output::Csv;
use crate::output::plot::{Figure, Panel, Series};
use crate::population::progress::process_cpu_seconds;
use crate::population::{Fate, RunOptions, RunOutput, paired};

/// One integrator setting: the error norm and rtol (atol stays the studies' [`ATOL`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormSetting {
    /// How the local error is measured.
    pub norm: ErrorNorm,
    /// Relative tolerance.
    pub rtol: f64,
}

/// The settings compared: componentwise at 10⁻² (the studies' before) and the tensor norm at
/// 10⁻², 3·10⁻³ and 10⁻³ (the studies' now).
pub const SETTINGS: [NormSetting; 4] = [
    NormSetting {
        norm: ErrorNorm::Componentwise,
        rtol: 1e-2,
    },
    NormSetting {
        norm: ErrorNorm::Tensor,
        rtol: 1e-2,
    },
    NormSetting {
        norm: ErrorNorm::Tensor,
        rtol: 3e-3,
    },
    NormSetting {
        norm: ErrorNorm::Tensor,
        rtol: 1e-3,
    },
];

/// Reference tolerances: Radau IIA(5) at rtol 10⁻⁵, atol 10⁻⁸.
pub const REFERENCE: (f64, f64) = (1e-5, 1e-8);

/// One kind under one setting, against the reference.
#[derive(Debug, Clone)]
pub struct NormRow {
    /// The particles.
    pub kind: Kind,
    /// Particles tracked.
    pub n: u64,
    /// The integrator setting.
    pub setting: NormSetting,
    /// CPU time of the run (s; the process's, over every thread). `None` where it cannot be read.
    pub cpu_s: Option<f64>,
    /// Accepted steps per particle.
    pub steps: f64,
    /// Rejected attempts per particle.
    pub rejected: f64,
    /// Particles deposited.
    pub deposited: u64,
    /// Particles deposited in one run and not in the other (setting against reference).
    pub fates_changed: u64,
    /// Median and 90th percentile of the distance between the deposits of the particles both
    /// runs deposit (m); NaN when there are none.
    pub shift: (f64, f64),
}

fn timed(
    airway: &Airway,
    kind: Kind,
    integ: &Stokesian,
    n: u64,
    seed: u64,
) -> Result<(RunOutput<NeoHooke>, Option<f64>), BifurcationError> {
    let quiet = RunOptions::default().quiet();
    let before = process_cpu_seconds();
    let out = StudyRun::new(airway, kind, n)
        .seed(seed)
        .integrator(*integ)
        .run(&quiet)?;
    let cpu = before.zip(process_cpu_seconds()).map(|(a, b)| b - a);
    Ok((out, cpu))
}

fn deposited(fate: &Fate) -> bool {
    matches!(fate, Fate::Deposited { .. })
}

/// The rows of `kind` (one per setting of `settings`), N particles with run seed `seed`.
pub fn compare(
    airway: &Airway,
    kind: Kind,
    settings: &[NormSetting],
    n: u64,
    seed: u64,
) -> Result<Vec<NormRow>, BifurcationError> {
    let chosen = integrator(airway, kind)?.integrator.full();
    let reference = Stokesian {
        scheme: Scheme::Radau5,
        tol: Tolerances::new(REFERENCE.0, REFERENCE.1, 1e-14)?,
        ..chosen
    }
    .with_norm(ErrorNorm::Componentwise);
    let (reference, _) = timed(airway, kind, &reference, n, seed)?;
    let mut rows = Vec::with_capacity(settings.len());
    for &setting in settings {
        let integ = Stokesian {
            tol: Tolerances::new(setting.rtol, ATOL, 1e-14)?,
            ..chosen
        }
        .with_norm(setting.norm);
        let (out, cpu_s) = timed(airway, kind, &integ, n, seed)?;
        let mut shifts = Vec::new();
        let mut fates_changed = 0;
        for (a, b) in paired(&out.records, &reference.records)? {
            match (deposited(&a.fate), deposited(&b.fate), a.end, b.end) {
                (true, true, Some(sa), Some(sb)) => shifts.push((sa.x - sb.x).norm()),
                (x, y, _, _) if x != y => fates_changed += 1,
                _ => {}
            }
        }
        shifts.sort_by(f64::total_cmp);
        let quantile = |p: f64| match shifts.len() {
            0 => f64::NAN,
            len => shifts[((len - 1) as f64 * p).round() as usize],
        };
        let per = |total: u64| total as f64 / n.max(1) as f64;
        rows.push(NormRow {
            kind,
            n,
            setting,
            cpu_s,
            steps: per(out.records.iter().map(|r| r.stats.steps).sum()),
            rejected: per(out.records.iter().map(|r| r.stats.rejected).sum()),
            deposited: out.counts().deposited,
            fates_changed,
            shift: (quantile(0.5), quantile(0.9)),
        });
    }
    Ok(rows)
}

fn norm_name(norm: ErrorNorm) -> &'static str {
    match norm {
        ErrorNorm::Componentwise => "componentwise",
        ErrorNorm::Tensor => "tensor",
    }
}

/// `error_norm.csv`: `shape,material,stk,n,norm,rtol,cpu_s,steps_per_particle,
/// rejected_per_particle,n_deposited,fates_changed,shift_median_m,shift_p90_m`; with
/// `with_cpu` false the CPU column is left empty (a snapshot must not hold a time).
pub fn table(rows: &[NormRow], with_cpu: bool) -> Result<Csv, BifurcationError> {
    let mut csv = Csv::new(&[
        "shape",
        "material",
        "stk",
        "n",
        "norm",
        "rtol",
        "cpu_s",
        "steps_per_particle",
        "rejected_per_particle",
        "n_deposited",
        "fates_changed",
        "shift_median_m",
        "shift_p90_m",
    ]);
    for r in rows {
        csv.push(vec![
            r.kind.shape.label(),
            r.kind.material.label(),
            r.kind.stokes.to_string(),
            r.n.to_string(),
            norm_name(r.setting.norm).into(),
            format!("{:.0e}", r.setting.rtol),
            match (with_cpu, r.cpu_s) {
                (true, Some(cpu)) => format!("{cpu:.2}"),
                _ => String::new(),
            },
            format!("{:.1}", r.steps),
            format!("{:.1}", r.rejected),
            r.deposited.to_string(),
            r.fates_changed.to_string(),
            format!("{:.2e}", r.shift.0),
            format!("{:.2e}", r.shift.1),
        ])?;
    }
    Ok(csv)
}

/// One panel per kind: fates changed per 10³ particles against CPU time per particle, the
/// componentwise setting as a point and the tensor norm's rtol sweep as a line.
pub fn figure(rows: &[NormRow]) -> Figure {
    let mut panels = Vec::new();
    let mut start = 0;
    while start < rows.len() {
        let kind = rows[start].kind;
        let end = start + rows[start..].iter().take_while(|r| r.kind == kind).count();
        let point = |r: &NormRow| {
            let cpu_ms = r.cpu_s.unwrap_or(f64::NAN) * 1e3 / r.n.max(1) as f64;
            (cpu_ms, 1e3 * r.fates_changed as f64 / r.n.max(1) as f64)
        };
        let of = |norm: ErrorNorm| -> Vec<(f64, f64)> {
            rows[start..end]
                .iter()
                .filter(|r| r.setting.norm == norm)
                .map(point)
                .collect()
        };
        panels.push(
            Panel::new(
                format!("{} {} Stk {}", kind.shape.label(), kind.material.label(), kind.stokes),
                "CPU per particle (ms)",
                "fates changed per 1000",
            )
            .with(Series::points(
                "componentwise, rtol 1e-2",
                of(ErrorNorm::Componentwise),
                0,
            ))
            .with(Series::line("tensor, rtol 1e-2 … 1e-3", of(ErrorNorm::Tensor), 1)),
        );
        start = end;
    }
    Figure::grid(panels, 3, (360, 280))
}

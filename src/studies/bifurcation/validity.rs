//! Validity diagnostics of the bifurcation's particles ([`crate::diagnostics`]): particle
//! Reynolds numbers and size ratios along the trajectories of a sample of each run.
//!
//! The population runner reports fates, not trajectories, so the diagnostics re-run particles
//! 0..count of a run (same seed, injection, integrator, plan and contact rule, hence the same
//! trajectories) under a [`Monitor`] fed at every accepted step, with what the slow-manifold
//! switch did where the study's integrator put a stiff particle on it
//! ([`Validity::with_integrator`]).

use super::BifurcationError;
use super::injection::{Injection, Kind};
use super::setup::Airway;
use super::study::{integrator, plan};
use crate::contact::{ContactEvent, ContactModel};
use crate::diagnostics::{Monitor, Thresholds, Validity};
use crate::driver::{Observers, Problem, integrate};
use crate::integrator::TimeIntegrator;
use crate::output::Csv;
use crate::population::{Injector, particle_rng};

/// Validity of particles 0..`count` of the run of `kind` with seed `seed`; a particle whose run
/// fails keeps the maxima observed before the failure.
pub fn sample(airway: &Airway, kind: Kind, seed: u64, count: u64) -> Result<Vec<Validity>, BifurcationError> {
    let injection = Injection::new(airway, kind)?;
    let integ = integrator(airway, kind)?.integrator;
    let plan = plan(airway)?;
    let mut out = Vec::with_capacity(count.min(1 << 20) as usize);
    for k in 0..count {
        let Ok(spec) = injection.draw(k, &mut particle_rng(seed, k)) else {
            continue;
        };
        let particle = injection.particle(&spec)?;
        let contact = ContactEvent::new(airway.boundary(), &particle, airway.flow(), ContactModel::Extent);
        let mut monitor = Monitor::new(&particle, airway.flow(), airway.boundary());
        let start = spec.start_state();
        monitor.observe(&start);
        let mut memory = Default::default();
        // A failed run keeps what was observed up to the failure.
        let _ = integrate(
            Problem::new(&integ, &particle, airway.flow()),
            start,
            &mut memory,
            &plan,
            &[&contact],
            Observers::none().with_on_step(|step| monitor.observe_step(step)),
        );
        out.push(monitor.validity().with_integrator(integ.report(&memory)));
    }
    Ok(out)
}

/// `shape,material,stk,particles,` the largest of each [`Validity`] maximum over the sample
/// (r₁ in m), then for each threshold of [`Thresholds::default`] the fraction of particles that
/// crossed it.
pub fn summary_table(rows: &[(Kind, Vec<Validity>)]) -> Result<Csv, BifurcationError> {
    let mut csv = Csv::new(&[
        "shape",
        "material",
        "stk",
        "particles",
        "max_re_shear",
        "max_re_slip",
        "max_r1",
        "max_r1_over_wall_distance",
        "max_r1_over_flow_scale",
        "frac_re_shear",
        "frac_re_slip",
        "frac_r1_over_wall_distance",
        "frac_r1_over_flow_scale",
    ]);
    let limits = Thresholds::default();
    for (kind, sample) in rows {
        let n = sample.len().max(1) as f64;
        let max = |f: &dyn Fn(&Validity) -> f64| sample.iter().map(f).fold(0.0, f64::max);
        let frac = |flag: &str| {
            sample
                .iter()
                .filter(|v| v.flags(&limits).iter().any(|f| f == flag))
                .count() as f64
                / n
        };
        csv.push(vec![
            kind.shape.label(),
            kind.material.label(),
            kind.stokes.to_string(),
            sample.len().to_string(),
            format!("{:.3e}", max(&|v| v.max_re_shear)),
            format!("{:.3e}", max(&|v| v.max_re_slip)),
            format!("{:.3e}", max(&|v| v.max_r1)),
            format!("{:.3e}", max(&|v| v.max_r1_over_wall_distance)),
            format!("{:.3e}", max(&|v| v.max_r1_over_flow_scale)),
            format!("{:.3}", frac("re_shear")),
            format!("{:.3}", frac("re_slip")),
            format!("{:.3}", frac("r1_over_wall_distance")),
            format!("{:.3}", frac("r1_over_flow_scale")),
        ])?;
    }
    Ok(csv)
}

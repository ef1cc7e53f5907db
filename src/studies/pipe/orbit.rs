//! Orbit periods of the material line l_a (paper Fig. 10 discussion).
//!
//! # Physics (Jeffery 1922)
//! A rigid spheroid of aspect ratio λ whose axis lies in the shear plane of a simple shear of
//! rate γ̇ rotates with period $T = 2\pi(\lambda + 1/\lambda)/\dot\gamma$; the axis passes the
//! gradient direction twice per period, so the direction cosine of l_a with the flow direction
//! e₁ crosses zero downwards once per period. In the pipe the particle samples the local shear
//! rate 4Ū|x_⊥|/R², which changes slowly as it settles.

use super::setup::PipeSetup;
use super::tracking::PipeSample;
use crate::driver::{Observers, Plan, Problem, integrate};
use crate::error::positive;
use crate::flow::analytic::LinearFlow;
use crate::hydro::DragModel;
use crate::integrator::TimeIntegrator;
use crate::particle::State;
use crate::particle::lines::material_line;
use crate::studies::StudyError;
use std::f64::consts::PI;

/// Jeffery's period 2π(λ + 1/λ)/γ̇ of a rigid spheroid with aspect ratio `aspect`.
pub fn jeffery_period(aspect: f64, shear_rate: f64) -> f64 {
    2.0 * PI * (aspect + 1.0 / aspect) / shear_rate
}

/// Times at which cos(l_a, e₁) crosses zero from above, linearly interpolated between samples.
pub fn downward_crossings(samples: &[PipeSample]) -> Vec<f64> {
    samples
        .windows(2)
        .filter_map(|w| {
            let (c0, c1) = (w[0].direction_cosines()[0], w[1].direction_cosines()[0]);
            (c0 > 0.0 && c1 <= 0.0).then(|| w[0].t + (w[1].t - w[0].t) * c0 / (c0 - c1))
        })
        .collect()
}

/// Orbit periods: differences of successive downward crossings.
pub fn orbit_periods(samples: &[PipeSample]) -> Vec<f64> {
    downward_crossings(samples).windows(2).map(|w| w[1] - w[0]).collect()
}

/// Orbit-averaged settling mobility ⟨e₂·K̂⁻¹e₂⟩ (units 1/length of the setup) of the setup's
/// particle in the simple shear u = γ̇ x₂ e₁ that it sees locally in the pipe at shear rate
/// `shear_rate` (pipe units: γ̇ = |x₂|/|x₂⁰| there, and Ca scales with γ̇ since μ_s is fixed).
///
/// The particle starts stress-free with its long axis along e₁, as released in the pipe. After
/// `t_transient` the mobility is integrated over the accepted steps (trapezoidal rule) and
/// averaged between the first and the last downward zero crossing of ξ_a·e₁ within
/// `t_average` more, i.e. over whole orbits: a partial orbit would bias the mean by up to the
/// orbit amplitude over the number of orbits. Fails with [`StudyError::TooFewOrbits`] unless
/// at least two crossings are seen.
pub fn shear_averaged_mobility<I: TimeIntegrator>(
    setup: &PipeSetup,
    integrator: &I,
    shear_rate: f64,
    t_transient: f64,
    t_average: f64,
) -> Result<f64, StudyError> {
    let flow = LinearFlow::simple_shear(positive("shear rate", shear_rate)?)?;
    let t_transient = positive("transient time", t_transient)?;
    let t_end = t_transient + positive("averaging time", t_average)?;
    let p = &setup.particle;
    let mobility = |s: &State| -> Result<f64, StudyError> {
        let geo = p.geometry(&s.f);
        let k = p.drag().resistance(&geo.frame, &geo.ints);
        let k_inv = k.try_inverse().ok_or(crate::error::StepError::NonFinite {
            what: "drag tensor",
            t: s.t,
        })?;
        Ok(k_inv[(1, 1)])
    };
    let cosine = |s: &State| {
        let xi = material_line(p.shape(), &s.f, 0);
        xi[0] / xi.norm()
    };
    let start = State::at_rest(setup.release);
    let plan = Plan::new(t_end, 1e-3)?.with_outputs(&[t_transient, t_end])?;
    let mut memory = I::Memory::default();
    // (t, mobility, cos) of the previous state; ∫mobility dt since t_transient;
    // (t, integral) at the first and the last downward crossing, and their count.
    let mut last = (start.t, mobility(&start)?, cosine(&start));
    let mut integral = 0.0;
    let mut first: Option<(f64, f64)> = None;
    let mut latest: Option<(f64, f64)> = None;
    let mut count = 0usize;
    let mut failure = None;
    integrate(
        Problem::new(integrator, p, &flow),
        start,
        &mut memory,
        &plan,
        &[],
        Observers::none().with_on_step(|step| {
            let s = step.state();
            let m = match mobility(s) {
                Ok(m) => m,
                Err(e) => {
                    failure.get_or_insert(e);
                    return;
                }
            };
            let c = cosine(s);
            let (t0, m0, c0) = last;
            if t0 >= t_transient {
                if c0 > 0.0 && c <= 0.0 {
                    let frac = c0 / (c0 - c);
                    let at = (
                        t0 + frac * (s.t - t0),
                        integral + frac * (s.t - t0) * (m0 + 0.5 * frac * (m - m0)),
                    );
                    first.get_or_insert(at);
                    latest = Some(at);
                    count += 1;
                }
                integral += 0.5 * (s.t - t0) * (m0 + m);
            }
            last = (s.t, m, c);
        }),
    )?;
    if let Some(e) = failure {
        return Err(e);
    }
    match (first, latest) {
        (Some((ta, ia)), Some((tb, ib))) if count >= 2 => Ok((ib - ia) / (tb - ta)),
        _ => Err(StudyError::TooFewOrbits {
            crossings: count,
            t_average,
        }),
    }
}

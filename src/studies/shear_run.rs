//! Sampled shear-flow runs: the in-plane section and the material lines l_a, l_c at chosen
//! times (paper Figs 4–6).
//!
//! # Physics (paper §6.1, Fig. 3)
//! The material points A and C sit initially on the in-shear-plane semi-axes, A on the longer
//! one; their lines from the barycentre are ξ = F·Ξ ([`crate::particle::lines`]).

use super::StudyError;
use super::particles::Shape;
use super::section::ShearPlaneSection;
use super::shear_shape::ShearShape;
use crate::diagnostics::{Monitor, Validity};
use crate::driver::{Observers, Problem, run};
use crate::flow::analytic::LinearFlow;
use crate::integrator::{Stokesian, TimeIntegrator};
use crate::particle::lines::material_line;
use crate::particle::{ShearScaling, State};
use crate::tensor::Vec3;

/// State of a shear run at one output time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShearSample {
    /// Time t̂ = γ̇t.
    pub t: f64,
    /// Ellipse in the shear plane.
    pub section: ShearPlaneSection,
    /// Material line ξ_a through A (initially on the longer in-plane semi-axis).
    pub xi_a: Vec3,
    /// Material line ξ_c through C (initially on the shorter in-plane semi-axis).
    pub xi_c: Vec3,
}

impl ShearSample {
    /// l_a = |ξ_a|.
    pub fn l_a(&self) -> f64 {
        self.xi_a.norm()
    }

    /// l_c = |ξ_c|.
    pub fn l_c(&self) -> f64 {
        self.xi_c.norm()
    }
}

/// The paper's shear flow u = γ̇ y e_x with γ̇ = 1.
pub fn unit_shear() -> LinearFlow {
    LinearFlow::simple_shear(1.0).expect("finite shear rate")
}

/// Groups for inertialess runs at capillary number `ca`: in the overdamped Stokesian model
/// without gravity ρ* does not enter, and tr l_s = 0 keeps J = 1 so λ_s does not either.
pub fn stokesian_scaling(ca: f64) -> Result<ShearScaling, StudyError> {
    Ok(ShearScaling::new(ca, 1.0, 1e3)?)
}

/// Run `shape` at the groups `scaling` from rest in unit shear and sample it at `times`
/// (ascending; 0 allowed), starting with step `dt0`; with the run's validity diagnostics over
/// every accepted step (as measured: the caller marks inertialess runs).
pub fn sample<I: TimeIntegrator>(
    integrator: &I,
    shape: &ShearShape,
    scaling: &ShearScaling,
    times: &[f64],
    dt0: f64,
) -> Result<(Vec<ShearSample>, Validity), StudyError> {
    let particle = shape.particle(scaling)?;
    let (a, c) = shape.in_plane_axes();
    let mut out = Vec::with_capacity(times.len());
    let flow = unit_shear();
    let start = State::at_rest(Vec3::zeros());
    let mut monitor = Monitor::in_linear_flow(&particle, &flow);
    monitor.observe(&start);
    run(
        Problem::new(integrator, &particle, &flow),
        start,
        dt0,
        times,
        Observers::new(
            |s| {
                out.push(ShearSample {
                    t: s.t,
                    section: ShearPlaneSection::of(&particle.total_distortion(&s.f)),
                    xi_a: material_line(particle.shape(), &s.f, a),
                    xi_c: material_line(particle.shape(), &s.f, c),
                })
            },
            |step| monitor.observe_step(step),
        ),
    )?;
    Ok((out, monitor.validity()))
}

/// The paper's §6.1.1 run (Figs 4–6): oblate ω₁ = ω₂ = 2.5 at `ca`, inertialess at rtol 1e-8,
/// sampled at `times`, with its validity diagnostics (r₁ in d_eq).
pub fn oblate_fig4_run(ca: f64, times: &[f64]) -> Result<(Vec<ShearSample>, Validity), StudyError> {
    let (samples, validity) = sample(
        &Stokesian::overdamped(1e-8)?,
        &ShearShape::new(Shape::Oblate(2.5)),
        &stokesian_scaling(ca)?,
        times,
        1e-3,
    )?;
    Ok((samples, validity.inertialess()))
}

/// Validity diagnostics of shear runs as CSV: `ca`, then [`Validity::COLUMNS`] under the
/// default thresholds (r₁ in d_eq).
pub fn validity_table(runs: &[(f64, Validity)]) -> Result<crate::output::Csv, crate::output::OutputError> {
    let mut header = vec!["ca"];
    header.extend(Validity::COLUMNS);
    let mut csv = crate::output::Csv::new(&header);
    let limits = crate::diagnostics::Thresholds::default();
    for (ca, validity) in runs {
        let mut cells = vec![ca.to_string()];
        cells.extend(validity.cells(&limits));
        csv.push(cells)?;
    }
    Ok(csv)
}

//! Work-precision study: error against wall time and against evaluations for every integrator
//! on three reference problems (issue "Speed against error").
//!
//! Cases (units of [`ShearScaling`]: d_eq, 1/γ̇, μ_f = 1):
//! - `jeffery`: a rigid prolate spheroid r = 5 with its axis along the flow; the exact
//!   Jeffery orbit gives the error of the long axis' in-plane angle at t = 20. Elastic
//!   integrators run it at Ca = 1e-4, whose own model error (≈ 0.2 Ca relative) is the floor;
//! - `tank_treading`: an initially spherical particle at Ca = 0.2 after t = 30 against
//!   Roscoe's steady state: |ΔD| + |Δθ|;
//! - `oblate`: the Fig. 4 oblate (2.5:2.5:1) at Ca = 0.4 over t ≤ 30 against the tightest
//!   inertialess run: max over t = 1, 2, …, 30 of |F − F_ref|∞.
//!
//! Inertial integrators use ρ* = 0.01 (a micro-particle; the paper's Δt ≤ ρ*/200 rule then
//! means Δt ≤ 5e-5) and λ_s/μ_s = 1e5: the literal volumetric traction of the paper is
//! anti-damped unless λ_s Δt ≳ (2/3)μ_f (physics.md §7, condition 2), so the scheme also has a
//! *lower* bound on Δt; with λ_s/μ_s = 1e4 the oblate case inverts at Δt = ρ*/640.
//! The oblate reference is inertialess, so inertial runs also carry the O(ρ*) model
//! difference (≈ 3e-4 here) in their error.

use super::SceneError;
use super::tank_treading::roscoe;
use crate::driver::{RunStats, run};
use crate::flow::analytic::LinearFlow;
use crate::integrator::{ImexAdaptive, ImexPaper, Stokesian, TimeIntegrator};
use crate::material::NeoHooke;
use crate::particle::lines::material_line;
use crate::particle::{Particle, ShearScaling, State};
use crate::reference::{jeffery_flow_aligned_time, jeffery_phi};
use crate::tensor::{Mat3, Vec3};
use serde::Serialize;
use std::time::Instant;

/// Reference problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Case {
    /// Rigid prolate r = 5 on its Jeffery orbit.
    Jeffery,
    /// Tank-treading sphere at Ca = 0.2 against Roscoe.
    TankTreading,
    /// Oblate 2.5 at Ca = 0.4 against the tightest run.
    Oblate,
}

impl Case {
    /// Name used in the dataset.
    pub fn name(self) -> &'static str {
        match self {
            Case::Jeffery => "jeffery",
            Case::TankTreading => "tank_treading",
            Case::Oblate => "oblate",
        }
    }
}

/// Integrator and its accuracy setting (a tolerance, or Δt for the fixed-step scheme).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Setting {
    /// `imex_paper` with fixed Δt.
    ImexPaper(f64),
    /// `imex_adaptive` with tolerance.
    ImexAdaptive(f64),
    /// `stokesian` (overdamped barycentre) with tolerance.
    Stokesian(f64),
    /// `rigid` with tolerance.
    Rigid(f64),
}

impl Setting {
    /// Integrator name.
    pub fn integrator(&self) -> &'static str {
        match self {
            Setting::ImexPaper(_) => "imex_paper",
            Setting::ImexAdaptive(_) => "imex_adaptive",
            Setting::Stokesian(_) => "stokesian",
            Setting::Rigid(_) => "rigid",
        }
    }
    /// The accuracy knob (Δt or tolerance).
    pub fn value(&self) -> f64 {
        match *self {
            Setting::ImexPaper(v) | Setting::ImexAdaptive(v) | Setting::Stokesian(v) | Setting::Rigid(v) => v,
        }
    }
}

/// One point of the work-precision diagram.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Record {
    /// Problem.
    pub case: Case,
    /// Integrator and setting.
    pub setting: Setting,
    /// Error against the reference.
    pub error: f64,
    /// Wall time in seconds.
    pub wall_s: f64,
    /// Work statistics.
    pub stats: RunStats,
}

const RHO_STAR: f64 = 0.01;
const BULK: f64 = 1e5;
const JEFFERY_R: f64 = 5.0;
const JEFFERY_T: f64 = 20.0;

fn shear() -> LinearFlow {
    LinearFlow::simple_shear(1.0).expect("finite")
}

fn particle(case: Case) -> Result<Particle<NeoHooke>, SceneError> {
    let (ca, ratios, axes) = match case {
        Case::Jeffery => (1e-4, [JEFFERY_R, 1.0, 1.0], Mat3::identity()),
        Case::TankTreading => (0.2, [1.0, 1.0, 1.0], Mat3::identity()),
        // paper §6.1.1: r1 along the flow, r3 along the gradient, r2 along the vorticity
        Case::Oblate => (
            0.4,
            [2.5, 2.5, 1.0],
            Mat3::new(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0),
        ),
    };
    Ok(ShearScaling::new(ca, RHO_STAR, BULK)?.particle(ratios, axes)?)
}

fn t_end(case: Case) -> f64 {
    match case {
        Case::Jeffery => JEFFERY_T,
        Case::TankTreading | Case::Oblate => 30.0,
    }
}

/// Run `case` with `setting`, sampling F at t = 1, 2, …, t_end.
fn trajectory(case: Case, setting: Setting) -> Result<(Vec<State>, RunStats, f64), SceneError> {
    let p = particle(case)?;
    let times: Vec<f64> = (1..=t_end(case) as usize).map(|i| i as f64).collect();
    let mut samples = Vec::with_capacity(times.len());
    let start = Instant::now();
    let s0 = State::at_rest(Vec3::zeros());
    let observe = |s: &State| samples.push(*s);
    let stats = match setting {
        // The scheme itself is timed, without the per-step stability guard; every Δt used in
        // the study is below the explicit limit (ρ*/62 for the r = 5 prolate).
        Setting::ImexPaper(dt) => {
            let imex = ImexPaper {
                check_stability: false,
                ..ImexPaper::default()
            };
            run(&imex, &p, s0, &shear(), dt, &times, observe, |_, _| {})?.1
        }
        Setting::ImexAdaptive(tol) => drive(&ImexAdaptive::new(tol), &p, s0, &times, observe)?,
        Setting::Stokesian(tol) => drive(&Stokesian::overdamped(tol), &p, s0, &times, observe)?,
        Setting::Rigid(tol) => drive(&Stokesian::rigid(tol), &p, s0, &times, observe)?,
    };
    Ok((samples, stats, start.elapsed().as_secs_f64()))
}

fn drive<I: TimeIntegrator>(
    integ: &I,
    p: &Particle<NeoHooke>,
    s0: State,
    times: &[f64],
    observe: impl FnMut(&State),
) -> Result<RunStats, SceneError> {
    Ok(run(integ, p, s0, &shear(), 1e-3, times, observe, |_, _| {})?.1)
}

/// In-plane angle of the long material line, measured from the gradient axis towards the flow.
fn long_axis_angle(p: &Particle<NeoHooke>, s: &State) -> f64 {
    let l = material_line(p.shape(), &s.f, 0);
    l[0].atan2(l[1])
}

/// Error of one run against the case's reference (`reference` only for [`Case::Oblate`]).
pub fn measure(case: Case, setting: Setting, reference: Option<&[State]>) -> Result<Record, SceneError> {
    let (samples, stats, wall_s) = trajectory(case, setting)?;
    let last = samples.last().expect("at least one output time");
    let error = match case {
        Case::Jeffery => {
            let p = particle(case)?;
            let mut d =
                long_axis_angle(&p, last) - jeffery_phi(JEFFERY_R, jeffery_flow_aligned_time(JEFFERY_R) + JEFFERY_T);
            d -= (d / std::f64::consts::PI).round() * std::f64::consts::PI;
            d.abs()
        }
        Case::TankTreading => {
            let exact = roscoe(0.2)?.steady;
            let p = particle(case)?;
            let sec = super::section::ShearPlaneSection::of(&p.total_distortion(&last.f));
            (sec.deformation() - exact.deformation()).abs() + (sec.angle - exact.theta).abs()
        }
        Case::Oblate => {
            let reference = reference.expect("oblate case needs a reference run");
            crate::tensor::max_or_nan(samples.iter().zip(reference).map(|(a, b)| (a.f - b.f).amax()))
        }
    };
    Ok(Record {
        case,
        setting,
        error,
        wall_s,
        stats,
    })
}

/// The tightest inertialess run of the oblate case (the reference for [`Case::Oblate`]).
pub fn oblate_reference() -> Result<Vec<State>, SceneError> {
    Ok(trajectory(Case::Oblate, Setting::Stokesian(1e-11))?.0)
}

/// Work needed by `integrator` to reach `error` in `case`, by log-log interpolation between
/// its two bracketing records: (model evaluations, wall seconds). `None` if not bracketed.
pub fn work_at_error(records: &[Record], case: Case, integrator: &str, error: f64) -> Option<(f64, f64)> {
    let mut pts: Vec<&Record> = records
        .iter()
        .filter(|r| r.case == case && r.setting.integrator() == integrator && r.error > 0.0)
        .collect();
    pts.sort_by(|a, b| b.error.total_cmp(&a.error));
    pts.windows(2)
        .find(|w| w[0].error >= error && error >= w[1].error)
        .map(|w| {
            let s = (error.ln() - w[0].error.ln()) / (w[1].error.ln() - w[0].error.ln());
            let lerp = |a: f64, b: f64| (a.ln() + s * (b.ln() - a.ln())).exp();
            (
                lerp(w[0].stats.rhs_evals as f64, w[1].stats.rhs_evals as f64),
                lerp(w[0].wall_s.max(1e-9), w[1].wall_s.max(1e-9)),
            )
        })
}

//! Work-precision study: error against wall time and against evaluations for every integrator
//! on three reference problems (issue "Speed against error").
//!
//! Cases (units of [`ShearScaling`]: d_eq, 1/γ̇, μ_f = 1):
//! - `jeffery`: a rigid prolate spheroid r = 5 with its axis along the flow; the exact
//!   Jeffery orbit gives the error of the long axis' in-plane angle at t = 20. Elastic
//!   integrators run it at Ca = 1e-4, whose own model error (≈ 0.2 Ca relative) is the floor;
//! - `tank_treading`: an initially spherical particle at Ca = 0.2 after t = 30 against
//!   Roscoe's steady state: |ΔD| + |Δθ|;
//! - `oblate`: the Fig. 4 oblate (2.5:2.5:1) at Ca = 0.4 over t ≤ 30 against a tight
//!   inertialess Radau IIA run ([`oblate_reference`]): max over t = 1, 2, …, 30 of |F − F_ref|∞.
//!
//! The SciPy peer ([`super::scipy_peer`], `solve_ivp` with Radau and LSODA on an independent
//! NumPy implementation of the inertialess model) runs the tank-treading and oblate cases under
//! the same error measures; [`peer_ratios`] compares its wall time with the fastest library
//! integrator's at equal error, and [`error_floor`] gives the error below which a case's measure
//! no longer resolves an integrator.
//!
//! Inertial integrators use ρ* = 0.01 (a micro-particle; the paper's Δt ≤ ρ*/200 rule then
//! means Δt ≤ 5e-5) and λ_s/μ_s = 1e5: the literal volumetric traction of the paper is
//! anti-damped unless λ_s Δt ≳ (2/3)μ_f ([`crate::integrator::imex`]), so the scheme also has a
//! *lower* bound on Δt; with λ_s/μ_s = 1e4 the oblate case inverts at Δt = ρ*/640.
//! The oblate reference is inertialess, so inertial runs also carry the O(ρ*) model
//! difference (≈ 3e-4 here) in their error.

use super::StudyError;
use super::particles::Shape;
use super::scipy_peer::{Peer, PeerCase, PeerMethod, PeerRun};
use super::shear_shape::ShearShape;
use super::tank_treading::roscoe;
use crate::driver::{self, Observers, RunStats, run};
use crate::flow::analytic::LinearFlow;
use crate::integrator::{ImexAdaptive, ImexPaper, Scheme, Stokesian, TimeIntegrator};
use crate::material::{NeoHooke, Response, Rigid};
use crate::particle::lines::material_line;
use crate::particle::{Particle, ShearScaling, State};
use crate::reference::{jeffery_flow_aligned_time, jeffery_phi};
use crate::tensor::Vec3;
use serde::Serialize;
use std::time::Instant;

/// Reference problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum ReferenceProblem {
    /// Rigid prolate r = 5 on its Jeffery orbit.
    Jeffery,
    /// Tank-treading sphere at Ca = 0.2 against Roscoe.
    TankTreading,
    /// Oblate 2.5 at Ca = 0.4 against a tight Radau IIA run.
    Oblate,
}

impl ReferenceProblem {
    /// Name used in the dataset.
    pub fn name(self) -> &'static str {
        match self {
            ReferenceProblem::Jeffery => "jeffery",
            ReferenceProblem::TankTreading => "tank_treading",
            ReferenceProblem::Oblate => "oblate",
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
    /// `rosenbrock_w23` (Rosenbrock-W 2(3), overdamped barycentre) with tolerance.
    RosenbrockW23(f64),
    /// `radau_iia` (Radau IIA order 5, overdamped barycentre) with tolerance.
    RadauIia(f64),
    /// `rigid` with tolerance.
    Rigid(f64),
    /// The SciPy peer, `solve_ivp(method="Radau")` at rtol = atol = tolerance.
    ScipyRadau(f64),
    /// The SciPy peer, `solve_ivp(method="LSODA")` at rtol = atol = tolerance.
    ScipyLsoda(f64),
}

impl Setting {
    /// Integrator name.
    pub fn integrator(&self) -> &'static str {
        match self {
            Setting::ImexPaper(_) => "imex_paper",
            Setting::ImexAdaptive(_) => "imex_adaptive",
            Setting::RosenbrockW23(_) => Scheme::Rosenbrock23.name(),
            Setting::RadauIia(_) => Scheme::Radau5.name(),
            Setting::Rigid(_) => "rigid",
            Setting::ScipyRadau(_) => PeerMethod::Radau.integrator(),
            Setting::ScipyLsoda(_) => PeerMethod::Lsoda.integrator(),
        }
    }
    /// The accuracy knob (Δt or tolerance).
    pub fn value(&self) -> f64 {
        match *self {
            Setting::ImexPaper(v)
            | Setting::ImexAdaptive(v)
            | Setting::RosenbrockW23(v)
            | Setting::RadauIia(v)
            | Setting::Rigid(v)
            | Setting::ScipyRadau(v)
            | Setting::ScipyLsoda(v) => v,
        }
    }

    /// The SciPy method and tolerance, for the peer's settings.
    pub fn peer(&self) -> Option<(PeerMethod, f64)> {
        match *self {
            Setting::ScipyRadau(tol) => Some((PeerMethod::Radau, tol)),
            Setting::ScipyLsoda(tol) => Some((PeerMethod::Lsoda, tol)),
            _ => None,
        }
    }
}

/// The settings of the study for `case`: every integrator with its sweep of Δt or tolerance.
/// This table is the one place that lists the integrators; a new one is a line here.
pub fn sweep(case: ReferenceProblem) -> Vec<Setting> {
    const DECADES: [f64; 7] = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9];
    let mut s: Vec<Setting> = [80.0, 160.0, 320.0, 640.0]
        .iter()
        .map(|d| Setting::ImexPaper(RHO_STAR / d))
        .collect();
    s.extend([1e-3, 1e-4, 1e-5, 1e-6].map(Setting::ImexAdaptive));
    s.extend(DECADES.map(Setting::RosenbrockW23));
    s.extend(DECADES.map(Setting::RadauIia));
    if case == ReferenceProblem::Jeffery {
        s.extend([1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10].map(Setting::Rigid));
    }
    if has_peer(case) {
        // Two more decades so the library's curve spans the error levels of the ratio table.
        s.extend([1e-10, 1e-11].map(Setting::RosenbrockW23));
        s.extend([1e-10, 1e-11].map(Setting::RadauIia));
        // Down to an error of ≈ 1e-10 (Radau at 1e-10, LSODA at 1e-12 on the oblate case), so
        // the peer's curves span the 1e-4 … 1e-9 error levels of the ratio table.
        s.extend([1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10].map(Setting::ScipyRadau));
        s.extend([1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12].map(Setting::ScipyLsoda));
    }
    s
}

/// One point of the work-precision diagram.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Record {
    /// ReferenceProblem.
    pub case: ReferenceProblem,
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

/// Initial shape and capillary number of `case`.
fn definition(case: ReferenceProblem) -> (ShearShape, f64) {
    match case {
        ReferenceProblem::Jeffery => (ShearShape::new(Shape::Prolate(JEFFERY_R)), 1e-4),
        ReferenceProblem::TankTreading => (ShearShape::new(Shape::Sphere), 0.2),
        // paper §6.1.1: ω₁ = ω₂ = 2.5, the short axis along the gradient
        ReferenceProblem::Oblate => (ShearShape::new(Shape::Oblate(2.5)), 0.4),
    }
}

fn particle(case: ReferenceProblem) -> Result<Particle<NeoHooke>, StudyError> {
    let (shape, ca) = definition(case);
    Ok(shape.particle(&ShearScaling::new(ca, RHO_STAR, BULK)?)?)
}

/// The peer's version of `case` (it runs the inertialess model, so ρ* does not enter).
fn peer_case(case: ReferenceProblem) -> PeerCase {
    let (shape, ca) = definition(case);
    PeerCase {
        semi_axes: shape.ratios(),
        ca,
        bulk_ratio: BULK,
        t_end: t_end(case),
    }
}

fn t_end(case: ReferenceProblem) -> f64 {
    match case {
        ReferenceProblem::Jeffery => JEFFERY_T,
        ReferenceProblem::TankTreading | ReferenceProblem::Oblate => 30.0,
    }
}

/// Run `case` with `setting`, sampling F at t = 1, 2, …, t_end.
fn trajectory(case: ReferenceProblem, setting: Setting) -> Result<(Vec<State>, RunStats, f64), StudyError> {
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
            run(
                driver::Problem::new(&ImexPaper::unguarded(), &p, &shear()),
                s0,
                dt,
                &times,
                Observers::none().with_observe(observe),
            )?
            .1
        }
        Setting::ImexAdaptive(tol) => drive(&ImexAdaptive::new(tol)?, &p, s0, &times, observe)?,
        Setting::RosenbrockW23(tol) => drive(
            &Stokesian::overdamped(tol)?.with_scheme(Scheme::Rosenbrock23),
            &p,
            s0,
            &times,
            observe,
        )?,
        Setting::RadauIia(tol) => drive(
            &Stokesian::overdamped(tol)?.with_scheme(Scheme::Radau5),
            &p,
            s0,
            &times,
            observe,
        )?,
        Setting::Rigid(tol) => {
            let (shape, ca) = definition(case);
            let rigid = shape.particle_with(&ShearScaling::new(ca, RHO_STAR, BULK)?, Rigid)?;
            drive(
                &Stokesian::overdamped(tol)?.with_scheme(Scheme::Rosenbrock23),
                &rigid,
                s0,
                &times,
                observe,
            )?
        }
        // The peer reports the wall time of its own solve, without the interpreter's start-up.
        Setting::ScipyRadau(tol) => return peer_trajectory(case, PeerMethod::Radau, tol),
        Setting::ScipyLsoda(tol) => return peer_trajectory(case, PeerMethod::Lsoda, tol),
    };
    Ok((samples, stats, start.elapsed().as_secs_f64()))
}

fn peer_trajectory(
    case: ReferenceProblem,
    method: PeerMethod,
    tol: f64,
) -> Result<(Vec<State>, RunStats, f64), StudyError> {
    let run = Peer::from_env().run(&peer_case(case), method, tol)?;
    let stats = RunStats {
        steps: run.steps,
        rhs_evals: run.rhs_evals,
        jac_evals: run.jac_evals,
        ..RunStats::default()
    };
    Ok((peer_states(&run), stats, run.wall_s))
}

/// The peer's samples as states. They carry F only: x, v and A are not part of the
/// inertialess shape problem, and no error measure reads them.
fn peer_states(run: &PeerRun) -> Vec<State> {
    run.samples
        .iter()
        .map(|&(t, f)| State {
            t,
            f,
            ..State::at_rest(Vec3::zeros())
        })
        .collect()
}

fn drive<I: TimeIntegrator, M: Response>(
    integ: &I,
    p: &Particle<M>,
    s0: State,
    times: &[f64],
    observe: impl FnMut(&State),
) -> Result<RunStats, StudyError> {
    Ok(run(
        driver::Problem::new(integ, p, &shear()),
        s0,
        1e-3,
        times,
        Observers::none().with_observe(observe),
    )?
    .1)
}

/// In-plane angle of the long material line, measured from the gradient axis towards the flow.
fn long_axis_angle(p: &Particle<NeoHooke>, s: &State) -> f64 {
    let l = material_line(p.shape(), &s.f, 0);
    l[0].atan2(l[1])
}

/// Runs faster than this are timed [`REPEATS`] times and keep the fastest: on a shared machine a
/// single millisecond-scale timing is mostly scheduling noise, and the minimum is the estimate
/// least affected by other load.
const SHORT_RUN_S: f64 = 0.1;
/// Repetitions of a short run (library and peer alike).
const REPEATS: usize = 5;

/// Error of one run against the case's reference (`reference` only for [`ReferenceProblem::Oblate`]).
/// Runs shorter than 0.1 s are repeated five times and report their fastest wall time.
pub fn measure(case: ReferenceProblem, setting: Setting, reference: Option<&[State]>) -> Result<Record, StudyError> {
    let (samples, stats, mut wall_s) = trajectory(case, setting)?;
    if wall_s < SHORT_RUN_S {
        for _ in 1..REPEATS {
            wall_s = wall_s.min(trajectory(case, setting)?.2);
        }
    }
    Ok(Record {
        case,
        setting,
        error: error_of(case, &samples, reference)?,
        wall_s,
        stats,
    })
}

/// The case's error measure of a run sampled at t = 1, 2, …, t_end.
fn error_of(case: ReferenceProblem, samples: &[State], reference: Option<&[State]>) -> Result<f64, StudyError> {
    let last = samples.last().expect("at least one output time");
    Ok(match case {
        ReferenceProblem::Jeffery => {
            let p = particle(case)?;
            let mut d =
                long_axis_angle(&p, last) - jeffery_phi(JEFFERY_R, jeffery_flow_aligned_time(JEFFERY_R) + JEFFERY_T);
            d -= (d / std::f64::consts::PI).round() * std::f64::consts::PI;
            d.abs()
        }
        ReferenceProblem::TankTreading => {
            let exact = roscoe(definition(case).1)?.steady;
            let p = particle(case)?;
            let sec = super::section::ShearPlaneSection::of(&p.total_distortion(&last.f));
            (sec.deformation() - exact.deformation()).abs() + (sec.angle - exact.theta).abs()
        }
        ReferenceProblem::Oblate => {
            let reference = reference.expect("oblate case needs a reference run");
            crate::tensor::max_or_nan(samples.iter().zip(reference).map(|(a, b)| (a.f - b.f).amax()))
        }
    })
}

/// Whether the SciPy peer runs `case`. It does not run the Jeffery case: its error there is the
/// elastic model's distance to the rigid orbit (≈ 0.2 Ca), the same for every inertialess
/// solver, so equal-error comparisons cannot be read from it.
pub fn has_peer(case: ReferenceProblem) -> bool {
    case != ReferenceProblem::Jeffery
}

/// The error the case's measure gives to the SciPy peer's high-accuracy run (DOP853 at
/// rtol = atol = 1e-13, within ≈ 1e-11 of the converged F here): the floor below which the
/// case's errors measure its reference (the oblate reference run, or the residual transient
/// against Roscoe's steady state), not an integrator.
pub fn error_floor(case: ReferenceProblem, reference: Option<&[State]>) -> Result<f64, StudyError> {
    let run = Peer::from_env().reference(&peer_case(case), PeerMethod::Dop853)?;
    error_of(case, &peer_states(&run), reference)
}

/// A tight inertialess run of the oblate case (the reference for [`ReferenceProblem::Oblate`]).
///
/// `radau_iia` at 1e-13. The Rosenbrock 2(3) reference used before (1e-13,
/// ≈ 2.4·10⁵ steps) sat ≈ 1.7e-8 from the converged F: every Radau run from 1e-7 down and the
/// peer's tightest runs all stopped at that floor. Radau's global error falls about as fast as
/// its tolerance here (3.4e-5, 3.7e-6, 3.5e-7 at 1e-4, 1e-5, 1e-6), so this run is ≈ 1e-12 from
/// the converged F; [`error_floor`] measures it against the SciPy peer (≈ 5e-12, the size of
/// the peer's own dense-output error).
pub fn oblate_reference() -> Result<Vec<State>, StudyError> {
    Ok(trajectory(ReferenceProblem::Oblate, Setting::RadauIia(1e-13))?.0)
}

/// Work needed by `integrator` to reach `error` in `case`, by log-log interpolation between
/// its two bracketing records: (model evaluations, wall seconds). `None` if not bracketed.
pub fn work_at_error(records: &[Record], case: ReferenceProblem, integrator: &str, error: f64) -> Option<(f64, f64)> {
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

/// Error levels of the library-against-peer comparison: each decade from 1e-4 to 1e-9.
pub const RATIO_ERRORS: [f64; 6] = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9];

/// Wall time of a SciPy peer against the fastest library integrator at one error level.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PeerRatio {
    /// ReferenceProblem.
    pub case: ReferenceProblem,
    /// Error level.
    pub error: f64,
    /// The library integrator with the least interpolated wall time at `error`.
    pub best_integrator: &'static str,
    /// Its wall time.
    pub library_wall_s: f64,
    /// The peer's integrator name (`scipy_radau`, `scipy_lsoda`).
    pub peer: &'static str,
    /// The peer's wall time at `error`.
    pub peer_wall_s: f64,
    /// `peer_wall_s / library_wall_s`: how many times faster the library is.
    pub ratio: f64,
}

/// For each error in `errors` and each peer with records for `case`: the wall times of the peer
/// and of the fastest library integrator at that error, both interpolated log-log along their
/// work-precision curves ([`work_at_error`]). Levels that the peer or every library integrator
/// does not bracket are left out.
pub fn peer_ratios(records: &[Record], case: ReferenceProblem, errors: &[f64]) -> Vec<PeerRatio> {
    let mut library: Vec<&'static str> = Vec::new();
    let mut peers: Vec<&'static str> = Vec::new();
    for r in records.iter().filter(|r| r.case == case) {
        let names = if r.setting.peer().is_some() {
            &mut peers
        } else {
            &mut library
        };
        if !names.contains(&r.setting.integrator()) {
            names.push(r.setting.integrator());
        }
    }
    let mut rows = Vec::new();
    for &error in errors {
        let best = library
            .iter()
            .filter_map(|&name| work_at_error(records, case, name, error).map(|(_, wall)| (name, wall)))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        let Some((best_integrator, library_wall_s)) = best else {
            continue;
        };
        for &peer in &peers {
            if let Some((_, peer_wall_s)) = work_at_error(records, case, peer, error) {
                rows.push(PeerRatio {
                    case,
                    error,
                    best_integrator,
                    library_wall_s,
                    peer,
                    peer_wall_s,
                    ratio: peer_wall_s / library_wall_s,
                });
            }
        }
    }
    rows
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(setting: Setting, error: f64, wall_s: f64, rhs_evals: u64) -> Record {
        Record {
            case: ReferenceProblem::Oblate,
            setting,
            error,
            wall_s,
            stats: RunStats {
                rhs_evals,
                ..RunStats::default()
            },
        }
    }

    /// On a curve that is a straight line in log-log (wall ∝ error^(-1/2)), the interpolation
    /// is exact up to round-off in ln/exp (a few ulps of numbers of size 1e2).
    #[test]
    fn work_at_error_is_exact_on_a_power_law() {
        let wall = |e: f64| 1e-3 * e.powf(-0.5);
        let records: Vec<Record> = [1e-2, 1e-4, 1e-6]
            .iter()
            .map(|&e| record(Setting::RosenbrockW23(e), e, wall(e), (10.0 / e) as u64))
            .collect();
        let (evals, w) = work_at_error(&records, ReferenceProblem::Oblate, "rosenbrock_w23", 3e-5).unwrap();
        assert!((w / wall(3e-5) - 1.0).abs() < 1e-12, "{w} vs {}", wall(3e-5));
        assert!((evals / (10.0 / 3e-5) - 1.0).abs() < 1e-12, "{evals}");
        assert_eq!(
            work_at_error(&records, ReferenceProblem::Oblate, "rosenbrock_w23", 1e-7),
            None
        );
        assert_eq!(work_at_error(&records, ReferenceProblem::Oblate, "rigid", 1e-4), None);
    }

    /// Two library integrators, the faster one changing with the error, against a peer that
    /// only reaches down to 1e-6: the ratio uses the faster one at each level and skips the
    /// level the peer does not reach.
    #[test]
    fn peer_ratios_pick_the_fastest_library_integrator() {
        let records = vec![
            record(Setting::RosenbrockW23(1e-3), 1e-3, 1.0, 1),
            record(Setting::RosenbrockW23(1e-9), 1e-9, 1.0, 1),
            record(Setting::Rigid(1e-3), 1e-3, 0.1, 1),
            record(Setting::Rigid(1e-9), 1e-9, 10.0, 1),
            record(Setting::ScipyRadau(1e-3), 1e-3, 100.0, 1),
            record(Setting::ScipyRadau(1e-6), 1e-6, 100.0, 1),
        ];
        let rows = peer_ratios(&records, ReferenceProblem::Oblate, &[1e-4, 1e-8]);
        assert_eq!(rows.len(), 1, "{rows:?}");
        // rigid at 1e-4: one sixth of the way from 0.1 s to 10 s in log-log, 10^(-1 + 2/6)
        let rigid = 10f64.powf(-2.0 / 3.0);
        assert_eq!(rows[0].best_integrator, "rigid");
        assert!((rows[0].library_wall_s / rigid - 1.0).abs() < 1e-12);
        assert!((rows[0].ratio - 100.0 / rigid).abs() < 1e-9);
        assert_eq!(rows[0].peer, "scipy_radau");
    }
}

//! Stiff elastic particles on their slow manifold ([`crate::particle::manifold`]): the rotation
//! integrated as a rigid body's, the shape the quasi-static stretch with its first correction,
//! and the full inertialess model ([`Stokesian`]) wherever the expansion's ratio says not.
//!
//! # Why
//! A stiff particle's stretch relaxes at k ∝ μ_s/μ_f, far faster than the flow changes along
//! its path, and the full model's step controller follows that relaxation: in the airway
//! bifurcation 1 000 soft spheres at Stk 0.1 took 276 k, 310 k, 320 k and 437 k Rosenbrock-W
//! steps for μ_s = 0.5, 5, 50 and 500 Pa against 164 k rigid. On the manifold the integrated
//! state is the rigid body's (R, x, v), stepped by the same scheme as a rigid particle
//! ([`crate::particle::Particle::manifold_twin`]: the rest geometry turned, no Carlson
//! integrals, and for a sphere no eigen-decomposition; a non-sphere's twin spins as the
//! deformed particle, one eigen-decomposition per evaluation, section Non-spheres), and the
//! stretch V(R, ∇u, d∇u/dt) is evaluated once per step at its end: F = V R.
//!
//! # The switch
//! The expansion parameter δ = max(|∇u|, |d∇u/dt|^½)/k ([`SlowManifold::ratio`]) is measured
//! on every step, d∇u/dt as the change of ∇u over the step. The dropped terms are O(δ²) in F
//! at a given rotation, and O(δ² |∇u|) in the rotation's rate (section Non-spheres; an
//! isotropic sphere's shape does not depend on its rotation at all). The full model holds F
//! to its relative tolerance rtol, so the manifold is used where δ ≤ δ_max = √rtol
//! ([`Manifold::new`]): its error is then of the full model's own size per unit strain (a
//! non-sphere's orientation on Jeffery's neutral orbits gathers it along the path, as the
//! full model's own error does). A
//! manifold step whose δ exceeds δ_max is discarded and taken again by the full model from
//! the same state (F = V R is a valid state of it); the full model hands back when δ ≤ δ_max/2
//! (a factor of two of hysteresis, so the switch does not chatter at the boundary) and,
//! after release, not before ln(1/δ_max)/k: a particle released undeformed is off the manifold
//! by ε₀ = O(δ), which the full model relaxes as e^{−kt} to O(δ²).
//! A rigid particle is passed to the full model unchanged.
//!
//! The run log states the rule and k ([`TimeIntegrator::describe`]); the steps on and off the
//! manifold, the switches and the largest δ on it are kept per particle in the step memory
//! ([`ManifoldReport`], read by [`TimeIntegrator::report`] into an [`IntegratorReport`]) and
//! reach the
//! population's records and their columns (`manifold_steps`, `full_steps`,
//! `manifold_entered`, `manifold_left`, `manifold_max_ratio`, `manifold_delta_max`:
//! [`crate::population::columns`]), the validity diagnostics
//! ([`crate::diagnostics::Validity::integrator`], which flag a step above δ_max) and the
//! command's summary line (the share of steps on the manifold).
//!
//! `auto` and the studies' integrator ([`super::choice`]) take this model for an elastic
//! particle whose δ at the flow's mean strain rate is at most
//! `MANIFOLD_SHARE` (`integrator::choice`) of δ_max, where it was measured to pay
//! (the table there); a scene may also name it (`slow_manifold`).
//!
//! # Non-spheres
//! The rigid twin of a non-sphere ([`crate::particle::Particle::manifold_twin`]) does not turn
//! at Jeffery's spin Ω of its rest shape: a deformed particle spins otherwise, by O(δ |∇u|),
//! and on Jeffery's neutrally stable orbits nothing pulls that error back, so it would grow
//! along the path at first order in δ. It turns at the deformed particle's spin
//! ([`crate::particle::manifold::DeformedSpin`]: Jeffery's torque-free spin of the deformed
//! ellipsoid V R S in the gradient less the particle's own strain rate, from the torque balance
//! of σ̃, paper eq. 12), whose dropped terms are O(δ² |∇u|). d∇u/dt is the last step's, held
//! over the step (exact in a steady linear flow). For an isotropic sphere R enters nothing
//! (B = V², section below) and the twin is the rigid one. Measured
//! (`tests/suite/integrator/manifold.rs`, `manifold_prolate_orientation_table`, ignored, 15 s):
//! neo-Hookean prolates of aspect ratio λ in unit shear from rest, long axis at 45° in the shear
//! plane or 45° out of it; the largest angle between the long material lines on the manifold
//! (δ_max = 0.3) and of the full model at rtol 10⁻¹⁰, sampled 20 times a period over 5 Jeffery
//! periods; the ratio is to the previous Ca's. Rigid spin: the twin at Ω (before issue 61).
//!
//! | λ | Ca | δ | in plane: rigid spin | in plane: deformed spin | out of plane: rigid spin | out of plane: deformed spin |
//! |---|---|---|---|---|---|---|
//! | 3 | 1e-2 | 0.040 | 3.51e-2 | 6.73e-2 | 1.02e-1 | 3.48e-2 |
//! | 3 | 5e-3 | 0.020 | 1.15e-2, 3.06 | 1.68e-2, 4.00 | 4.93e-2, 2.08 | 8.11e-3, 4.30 |
//! | 3 | 2.5e-3 | 0.010 | 4.23e-3, 2.72 | 4.21e-3, 4.00 | 2.42e-2, 2.04 | 1.95e-3, 4.15 |
//! | 20 | 1.25e-3 | 0.074 | 1.83e-2 | 6.78e-2 | 6.58e-2 | 6.02e-2 |
//! | 20 | 6.25e-4 | 0.037 | 4.52e-3, 4.06 | 1.74e-2, 3.90 | 3.44e-2, 1.91 | 1.49e-2, 4.03 |
//! | 20 | 3.125e-4 | 0.019 | 1.13e-3, 4.02 | 4.37e-3, 3.98 | 1.77e-2, 1.95 | 3.70e-3, 4.03 |
//!
//! With the deformed spin the error is second order everywhere; the rigid spin is first order
//! out of the plane (an orbit drift) and in the plane of λ = 3 (a phase error that is periodic,
//! so it vanishes at whole periods). In the plane of λ = 20 the rigid spin's first-order error
//! is too small to show and its second-order constant is 4× smaller than the deformed spin's.
//! λ = 20 relaxes 15× slower than λ = 3: at Ca ≥ 5·10⁻³, δ > δ_max/2 and it never enters the
//! manifold.
//!
//! # Measured (`examples/manifold_bifurcation`, 1 000 spheres at Stk 0.1, one thread)
//! The airway bifurcation's spheres, the studies' integrator (Rosenbrock-W 2(3), rtol 10⁻³,
//! tensor norm) as the full model, and both against a reference (the full model by Radau IIA at
//! rtol 10⁻⁶) on the same particles: fates, and ΔB = |B − B_ref| with B = F Fᵀ at 39 common
//! times of every path. Rigid: 165 346 steps, 1.00 s CPU (1.30 s when run first, before the
//! caches are warm: the spread of these CPU times).
//!
//! | μ_s (Pa) | full: steps, CPU | manifold: steps, CPU | steps on the manifold | ΔB median, max (full) | ΔB median, max (manifold) | fates changed (full, manifold) |
//! |---|---|---|---|---|---|---|
//! | 0.5 | 274 k (1.66×), 2.40× | 262 k (1.58×), 2.73× | 9 % | 8.4e-4, 7.0e-2 | 5.4e-4, 5.7e-2 | 0, 0 |
//! | 5 | 323 k (1.95×), 3.02× | 183 k (1.11×), 1.57× | 85 % | 4.5e-4, 2.2e-2 | 1.7e-5, 2.1e-2 | 0, 1 |
//! | 50 | 334 k (2.02×), 2.97× | 166 k (1.003×), 1.19× | 99 % | 4.4e-4, 4.0e-2 | 4.4e-7, 2.9e-3 | 0, 0 |
//! | 500 | 457 k (2.76×), 3.94× | 166 k (1.001×), 1.19× | 99 % | 1.7e-3, 2.3e-1 | 6.9e-8, 2.7e-4 | 0, 0 |
//!
//! From 5 Pa up the manifold takes the rigid sphere's steps within 11 % and no more for a
//! stiffer particle, and its shape is closer to the reference than the full model's at the
//! studies' tolerance (whose W-method error estimate lets F's fast relaxation pass with errors
//! up to 0.23 in B at 500 Pa). A manifold step costs 1.19× a rigid one (the quasi-static point
//! at its end). At 0.5 Pa the spheres deform by up to |B − 1| = 3.1 near the walls, where
//! δ > δ_max: the shape is not slaved to the flow there and the full model runs 91 % of the
//! steps; those steps are rejected 0.82 times each against 0.33 in the full model's own run
//! (1 334 exits from the manifold over 1 000 particles), which costs 14 % CPU over the full
//! model alone. Why a handover raises the rejections of the full steps after it is not known.
//!
//! # The rotation of an isotropic sphere is not tested
//! The table above tested the rigid twin's rotation R. For a sphere whose law is isotropic
//! ([`crate::material::Hyperelastic::is_isotropic`]) nothing on the manifold depends on R: the
//! turned rest geometry is the same sphere, V depends on ∇u alone, and B = F Fᵀ = V R Rᵀ V = V².
//! So the twin's step measures only x and v, as a rigid sphere's does
//! ([`crate::particle::Particle::orientation_is_passive`]); F = V R still carries R, integrated
//! but not controlled. A law that does not say it is isotropic never goes on the manifold
//! ([`super::choice`]): the quasi-static stretch here is the isotropic small-strain one.
//! Measured on the airway bifurcation's spheres with the studies' integrator: with R untested
//! the manifold takes 1.04–1.29× a rigid sphere's CPU from 5 to 500 Pa, and no fate changed
//! (steps, reference errors and a callgrind breakdown: `paper-figures/peer-race/NOTES.md`,
//! History).

use super::dense::Knot;
use super::stokesian::StokesianMemory;
use super::{Dense, IntegratorReport, Step, Stokesian, TimeIntegrator};
use crate::error::{ParamError, StepError};
use crate::flow::FlowField;
use crate::hydro::DragModel;
use crate::material::Response;
use crate::particle::manifold::SlowManifold;
use crate::particle::{Particle, State};
use crate::tensor::{Mat3, nearest_rotation};
use serde::{Deserialize, Serialize};

/// The full model where the slow-manifold expansion does not hold, the manifold elsewhere
/// (module docs).
#[derive(Debug, Clone, Copy)]
pub struct Manifold {
    /// The full model, and the scheme that steps the rotation on the manifold.
    pub full: Stokesian,
    /// The largest expansion ratio δ on the manifold, in (0, 1) ([`Self::with_delta_max`]).
    delta_max: f64,
}

impl Manifold {
    /// The manifold over `full` with δ_max = √rtol (module docs); rtol must lie in (0, 1).
    pub fn new(full: Stokesian) -> Result<Self, ParamError> {
        let rtol = full.tol.rtol();
        if !(rtol > 0.0 && rtol < 1.0) {
            return Err(ParamError::OutsideOpen {
                name: "rtol",
                value: rtol,
                min: 0.0,
                max: 1.0,
            });
        }
        Ok(Self {
            delta_max: rtol.sqrt(),
            full,
        })
    }

    /// The same with another δ_max (finite, in (0, 1)).
    pub fn with_delta_max(self, delta_max: f64) -> Result<Self, ParamError> {
        if !(delta_max > 0.0 && delta_max < 1.0) {
            return Err(ParamError::OutsideOpen {
                name: "delta_max",
                value: delta_max,
                min: 0.0,
                max: 1.0,
            });
        }
        Ok(Self { delta_max, ..self })
    }

    /// The largest expansion ratio δ_max on the manifold, in (0, 1).
    pub fn delta_max(&self) -> f64 {
        self.delta_max
    }

    /// What the switch did for the particle with step memory `memory`.
    pub fn manifold_report(&self, memory: &ManifoldMemory) -> ManifoldReport {
        ManifoldReport {
            delta_max: self.delta_max,
            ..memory.report
        }
    }

    /// The time the full model runs after release before the manifold may take over:
    /// ln(1/δ_max)/k (module docs).
    pub fn initial_layer(&self, manifold: &SlowManifold) -> f64 {
        (1.0 / self.delta_max).ln() / manifold.relaxation_rate()
    }
}

/// What the switch did for one particle ([`Manifold::manifold_report`]): every accepted step
/// is counted once, on the manifold or of the full model, so the two counts add up to the
/// driver's accepted steps ([`crate::driver::RunStats::steps`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct ManifoldReport {
    /// Steps on the manifold.
    pub manifold_steps: u64,
    /// Steps of the full model (a rigid particle's all are).
    pub full_steps: u64,
    /// Switches from the full model to the manifold.
    pub entered: u32,
    /// Switches from the manifold to the full model (each one discarded manifold step).
    pub left: u32,
    /// The largest δ of an accepted manifold step (0 before the first).
    pub max_ratio: f64,
    /// The bound δ_max of the integrator ([`Manifold::delta_max`]): a manifold step whose δ
    /// exceeds it is discarded, so `max_ratio` ≤ `delta_max` ([`Self::exceeded`]).
    pub delta_max: f64,
}

impl ManifoldReport {
    /// Whether an accepted manifold step ran above δ_max. The switch discards every such
    /// step, so this is never true of a report of [`Manifold`]: the validity diagnostics
    /// check it ([`crate::diagnostics::Validity::integrator`], flag `manifold_ratio`).
    pub fn exceeded(&self) -> bool {
        self.max_ratio > self.delta_max
    }

    /// The reports of two runs as one (a population's total, the runs of a phase boundary):
    /// steps and switches added, and the largest δ and δ_max of the run that came closer to
    /// its own bound (the larger δ where both ran under one bound), so the total
    /// [`Self::exceeded`] where either run did.
    pub fn combine(self, other: Self) -> Self {
        let closer = if other.max_ratio * self.delta_max > self.max_ratio * other.delta_max {
            other
        } else {
            self
        };
        Self {
            manifold_steps: self.manifold_steps + other.manifold_steps,
            full_steps: self.full_steps + other.full_steps,
            entered: self.entered + other.entered,
            left: self.left + other.left,
            ..closer
        }
    }

    /// The run summary's account of the switch, with `steps` the run's accepted steps: the
    /// steps on the manifold among them and, if it took any, the largest δ on it against δ_max.
    pub fn summary(&self, steps: u64) -> String {
        let percent = if steps > 0 {
            100.0 * self.manifold_steps as f64 / steps as f64
        } else {
            0.0
        };
        let ratio = if self.manifold_steps > 0 {
            format!(
                ", largest delta {:.3e} {} delta_max = {:.3e}",
                self.max_ratio,
                if self.exceeded() { ">" } else { "<=" },
                self.delta_max
            )
        } else {
            String::new()
        };
        format!(
            "; slow manifold: {} of {steps} steps ({percent:.1} %){ratio}",
            self.manifold_steps
        )
    }
}

/// Step memory of [`Manifold`].
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct ManifoldMemory {
    full: StokesianMemory,
    rigid: StokesianMemory,
    on_manifold: bool,
    /// The particle's first time.
    released: Option<f64>,
    /// ∇u at the last accepted state, with its time.
    gradient: Option<(f64, Mat3)>,
    /// ε₀ at the last accepted state on the manifold, with its time.
    strain: Option<(f64, Mat3)>,
    /// d∇u/dt over the last accepted step, with the time it ended.
    #[serde(default)]
    gradient_rate: Option<(f64, Mat3)>,
    /// The switch's record; its `delta_max` is the integrator's, filled in by
    /// [`Manifold::manifold_report`].
    report: ManifoldReport,
    /// The particle's constants: a function of the particle, recomputed after a checkpoint.
    #[serde(skip)]
    constants: Option<Option<SlowManifold>>,
}

impl Manifold {
    /// One step on the manifold, or `None` where δ > δ_max (module docs).
    fn manifold_step<M: Response, D: DragModel, F: FlowField + ?Sized>(
        &self,
        manifold: &SlowManifold,
        particle: &Particle<M, D>,
        state: &State,
        memory: &mut ManifoldMemory,
        flow: &F,
        dt: f64,
    ) -> Result<Option<Step>, StepError> {
        let Some((_, l_0)) = memory.gradient.filter(|(t, _)| *t == state.t) else {
            return Ok(None);
        };
        let r_0 = nearest_rotation(&state.f);
        let strain_0 = match memory.strain {
            Some((t, e)) if t == state.t => e,
            _ => manifold.quasi_static(particle, &r_0, &l_0, state.t)?.strain,
        };
        let gradient_rate = match memory.gradient_rate {
            Some((t, rate)) if t == state.t => rate,
            _ => Mat3::zeros(),
        };
        let twin = particle.manifold_twin(&gradient_rate);
        let rigid_state = State { f: r_0, ..*state };
        let inner = self.full.step_with(&twin, &rigid_state, &mut memory.rigid, flow, dt)?;
        let Some((t_1, l_1)) = memory.rigid.end_gradient() else {
            unreachable!("an accepted Stokesian step records its end gradient")
        };
        let h = t_1 - state.t;
        let rate = (l_1 - l_0).norm() / h;
        let ratio = manifold.ratio(&l_0, rate).max(manifold.ratio(&l_1, rate));
        if ratio.is_nan() || ratio > self.delta_max {
            return Ok(None);
        }
        let r_1 = inner.state.f;
        let q_1 = manifold.quasi_static(particle, &r_1, &l_1, t_1)?;
        let strain_rate = (q_1.strain - strain_0) / h;
        let v_1 = manifold.stretch(&q_1, &strain_rate, t_1)?;
        let f_1 = v_1 * r_1;
        // Ḟ = V̇ R + V Ω R, with V̇ = ε̇₀ to the order kept.
        let a_1 = strain_rate * r_1 + v_1 * q_1.spin * r_1;
        let next = State {
            f: f_1,
            a: a_1,
            ..inner.state
        };
        next.validate()?;
        memory.gradient = Some((t_1, l_1));
        memory.gradient_rate = Some((t_1, (l_1 - l_0) / h));
        memory.strain = Some((t_1, q_1.strain));
        memory.report.manifold_steps += 1;
        memory.report.max_ratio = memory.report.max_ratio.max(ratio);
        let start = Knot {
            x: state.x,
            x_dot: state.v,
            f: state.f,
            f_dot: state.a,
        };
        let end = Knot {
            x: next.x,
            x_dot: next.v,
            f: f_1,
            f_dot: a_1,
        };
        Ok(Some(Step {
            dense: Dense::new(state.t, h, start, end),
            state: next,
            info: inner.info,
            // The same x and t; F is the manifold's, not the one the inner step evaluated.
            end: super::EndEvaluation {
                frame: None,
                ..inner.end
            },
        }))
    }
}

impl TimeIntegrator for Manifold {
    type Memory = ManifoldMemory;

    fn name(&self) -> &'static str {
        "slow_manifold"
    }

    fn barycentre(&self) -> super::BarycentreModel {
        self.full.barycentre
    }

    fn step_with<M: Response, D: DragModel, F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        state: &State,
        memory: &mut ManifoldMemory,
        flow: &F,
        dt: f64,
    ) -> Result<Step, StepError> {
        let constants = match memory.constants {
            Some(c) => c,
            None => {
                let c = SlowManifold::of(particle)?;
                memory.constants = Some(c);
                c
            }
        };
        let Some(manifold) = constants else {
            let step = self.full.step_with(particle, state, &mut memory.full, flow, dt)?;
            memory.report.full_steps += 1;
            return Ok(step);
        };
        let released = *memory.released.get_or_insert(state.t);
        if memory.on_manifold {
            if let Some(step) = self.manifold_step(&manifold, particle, state, memory, flow, dt)? {
                return Ok(step);
            }
            memory.on_manifold = false;
            memory.report.left += 1;
            memory.rigid = StokesianMemory::default();
            memory.full = StokesianMemory::default();
        }
        let step = self.full.step_with(particle, state, &mut memory.full, flow, dt)?;
        memory.report.full_steps += 1;
        let Some((t_1, l_1)) = memory.full.end_gradient() else {
            unreachable!("an accepted Stokesian step records its end gradient")
        };
        let ratio = memory.gradient.filter(|(t, _)| *t == state.t).map(|(t_0, l_0)| {
            let rate = (l_1 - l_0) / (t_1 - t_0);
            memory.gradient_rate = Some((t_1, rate));
            manifold.ratio(&l_0, rate.norm()).max(manifold.ratio(&l_1, rate.norm()))
        });
        memory.gradient = Some((t_1, l_1));
        let relaxed = t_1 - released >= self.initial_layer(&manifold);
        if relaxed && ratio.is_some_and(|r| r <= 0.5 * self.delta_max) {
            memory.on_manifold = true;
            memory.report.entered += 1;
            memory.strain = None;
            memory.rigid = StokesianMemory::default();
        }
        Ok(step)
    }

    fn report(&self, memory: &ManifoldMemory) -> IntegratorReport {
        IntegratorReport::manifold(self.manifold_report(memory))
    }

    /// ∇u and ε₀ are kept by time alone: a mapped state at the same time needs them afresh
    /// (the next step leaves the manifold for one full step and finds them).
    fn mapped(&self, memory: &mut ManifoldMemory) {
        memory.gradient = None;
        memory.gradient_rate = None;
        memory.strain = None;
    }

    fn describe<M: Response, D: DragModel, F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        _flow: &F,
    ) -> Option<String> {
        Some(match SlowManifold::of(particle) {
            Ok(Some(m)) => format!(
                "slow manifold where delta = max(|grad u|, |d grad u/dt|^(1/2))/k <= {:.3e} \
                 (back below {:.3e}, not before {:.3e} after release), k = {:.3e}; \
                 elsewhere the full model, {}",
                self.delta_max,
                0.5 * self.delta_max,
                self.initial_layer(&m),
                m.relaxation_rate(),
                self.full.scheme.name()
            ),
            Ok(None) => format!("rigid: the full model, {}", self.full.scheme.name()),
            Err(e) => format!("no slow manifold: {e}"),
        })
    }
}

// Selectable by name: `[integrator] type = "slow_manifold"` with `tol` (rtol = atol of the full
// model), `overdamped` and `norm` as for `radau_iia`, and `delta_max` (default √tol, in (0, 1)).
// The full model's scheme is the one `auto` takes at that tolerance
// ([`Scheme::for_rtol`](super::Scheme::for_rtol): Rosenbrock-W 2(3) at tol ≥ 10⁻³, Radau IIA below), so that a
// particle off the manifold, and a rigid one, costs what it costs under `auto`.
inventory::submit! {
    super::IntegratorRegistration {
        name: "slow_manifold",
        aliases: &[],
        build: |p| {
            p.only(&["tol", "overdamped", "norm", "delta_max"])?;
            let tol = p.positive("tol")?;
            let full = if p.flag("overdamped")? {
                Stokesian::overdamped(tol)
            } else {
                Stokesian::new(tol)
            }?
            .with_scheme(super::Scheme::for_rtol(tol))
            .with_norm(super::stokesian::error_norm(p)?);
            let manifold = match p.positive("delta_max") {
                Err(ParamError::Missing { .. }) => Manifold::new(full)?,
                Ok(delta_max) => Manifold::new(full)?.with_delta_max(delta_max)?,
                Err(e) => return Err(e),
            };
            Ok(super::SceneIntegrator::new(manifold))
        },
    }
}

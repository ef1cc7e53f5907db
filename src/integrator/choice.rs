//! The integrator chosen for the particle: the scheme and the barycentre model of
//! [`Stokesian`] from the particle's numbers, with the reason written out for the run log.
//!
//! # Rules (each measured; the numbers are in the constants' docs)
//! - **Shape**: inertialess (eq. 18 with Θ → 0), the only shape model this choice gives. Its
//!   error is O(ρ*) with ρ* = ρ_p γ̇ d_eq²/μ_f (the shape's inertial time over the flow's);
//!   above [`RHO_STAR_INERTIALESS`] the reason says so, and an elastic particle that needs its
//!   shape inertia must force the paper's IMEX scheme (`imex_adaptive`).
//! - **Barycentre**: the equilibrium velocity ([`BarycentreModel::Equilibrium`], first order
//!   in the response time) for St ≤ [`EQUILIBRIUM_STOKES`], its full inertia
//!   ([`BarycentreModel::Inertial`]) above. St = τ γ̇ is the particle's largest response time
//!   over the flow's time scale, the volume mean of the strain rate ([`ParticleNumbers::of`]),
//!   or, if larger, the distance a launch's slip carries the particle before it relaxes, in
//!   equivalent diameters ([`ParticleNumbers::at`]): a particle thrown into still fluid is not
//!   overdamped.
//! - **Scheme**: the Rosenbrock-W 2(3) pair at loose tolerances (rtol ≥ [`ROSENBROCK_RTOL`]),
//!   where its two evaluations per step beat Radau IIA's three to four, and Radau IIA(5)
//!   below, where accuracy sets the step and order 5 takes 15–20× fewer ([`Scheme`]'s table).
//!   Rigid or soft does not change the scheme: both measurements below hold for either.
//! - **Stiff elastic particles**: the slow manifold over that full model
//!   ([`super::manifold`]: the shape slaved to the local velocity gradient, the full model
//!   where the expansion does not hold) where the flow's mean expansion ratio
//!   δ̄ = γ̇/k ([`ParticleNumbers::shape_ratio`], k the slowest elastic relaxation rate) is at
//!   most [`MANIFOLD_SHARE`] of the manifold's δ_max = √rtol; the full model elsewhere.
//!   Non-spheres too: the manifold turns them at the deformed particle's spin, second order
//!   in δ along Jeffery's orbits as the shape is ([`super::manifold`], section Non-spheres).
//!
//! The user can still force any integrator: this is a default, not a restriction. Scene files
//! and Python name it `auto` ([`Auto`]: the choice made per particle at its first step, from
//! [`ParticleNumbers::at`]: a particle launched with a slip keeps its inertia, section
//! Barycentre; printed per injection group in the run log for particles launched at the fluid's
//! velocity).

use super::control::ErrorNorm;
use super::manifold::{Manifold, ManifoldMemory};
use super::stokesian::{ROSENBROCK_RTOL, StokesianMemory};
use super::{BarycentreModel, Frame, IntegratorReport, Scheme, Step, Stokesian, TimeIntegrator, Tolerances};
use crate::error::{ParamError, StepError};
use crate::flow::FlowField;
use crate::hydro::DragModel;
use crate::material::{Response, StressLaw};
use crate::particle::manifold::SlowManifold;
use crate::particle::{Particle, State};
use crate::tensor::Mat3;
use serde::{Deserialize, Serialize};

/// Largest St for the equilibrium barycentre. Measured on the airway bifurcation (rigid
/// λ = 20 prolates, rtol 10⁻², 4 000 particles paired with the inertial barycentre,
/// `examples/barycentre_choice.rs`, `paper-figures/fig18/barycentre_choice.csv`; for these
/// particles St = τ γ̇ = 2.71 Stk, with Stk of paper eq. 25): at Stk ≤ 0.02 (St ≤ 0.054) at most
/// 1 fate in 4 000 changes (the integration tolerance itself moves about 1 in 10³,
/// `studies::bifurcation::study::RTOL`) with 2.4–4.3× fewer steps; at Stk = 0.04 (St = 0.11) the
/// equilibrium model loses 3 of 23 deposits, at 0.06 4 of 30 and at 0.1 20 of 53: the O(St²)
/// terms it drops decide impaction at the carina, where the flow's local time scale is much
/// shorter than the volume mean 1/γ̇. 0.06 lies between the last passing and the first failing
/// measurement.
pub const EQUILIBRIUM_STOKES: f64 = 0.06;

/// ρ* above which the reason states that the shape's inertia is neglected. The shape's
/// inertia relaxes on the time ρ_p d_eq²/μ_f = ρ*/γ̇, so the inertialess shape departs from the
/// inertial one by O(ρ*) (`tests/suite/integrator/every_scheme.rs` bounds it by 10 ρ* in
/// shear); 0.1 keeps that below the studies' 10⁻² tolerance.
pub const RHO_STAR_INERTIALESS: f64 = 0.1;

/// Largest δ̄/δ_max at which an elastic particle goes on the slow manifold, δ̄ = γ̇/k the
/// expansion ratio at the flow's mean strain rate and δ_max = √rtol the manifold's own bound.
/// Measured on the airway bifurcation (`examples/manifold_bifurcation -- 1000 7 MU_S`,
/// neo-Hookean spheres at Stk 0.1, the studies' rtol 10⁻³, so δ_max = 0.0316; one thread; CPU
/// per particle over a rigid sphere's, same particles; fates changed against the full model
/// by Radau IIA at rtol 10⁻⁶ on the same 1 000):
///
/// | μ_s (Pa) | δ̄/δ_max | full model: CPU, fates changed | slow manifold: CPU, fates changed | steps on the manifold |
/// |---|---|---|---|---|
/// | 0.5 | 1.47 | 1.73, 0 | 1.98, 0 | 9 % |
/// | 1 | 0.74 | 2.04, 1 | 2.59, 1 | 17 % |
/// | 2 | 0.37 | 2.24, 0 | 2.49, 0 | 41 % |
/// | 3 | 0.245 | 2.27, 0 | 1.65, 3 (96 → 99 deposited) | 63 % |
/// | 5 | 0.147 | 2.07, 0 | 1.10, 1 | 85 % |
/// | 50 | 0.0147 | 2.06, 0 | 0.86, 0 | 99 % |
/// | 500 | 0.00147 | 2.72, 0 | 0.91, 0 | 99 % |
///
/// Up to 2 Pa the manifold costs more than it saves (the shape is not slaved where the
/// particle meets the walls' shear, and each exit is a discarded step); at 3 Pa it saves 27 %
/// but moves 3 fates of 1 000 toward the rigid sphere's (99 deposited), three times what the
/// integration tolerance moves (`crate::studies::bifurcation::study::RTOL`); from 5 Pa it
/// takes the rigid sphere's CPU within 10 % and moves at most the tolerance's fate. 0.2 lies
/// between the 3 Pa and 5 Pa measurements. (CPU times on a shared machine carry ±15 %: the
/// rigid run repeated gave 0.73–0.82 of its first time.)
pub const MANIFOLD_SHARE: f64 = 0.2;

/// The numbers the choice reads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParticleNumbers {
    /// Stokes number: the particle's response time over the flow's time scale.
    pub stokes: f64,
    /// ρ* = ρ_p γ̇ d_eq²/μ_f, the shape's inertia against the viscous traction.
    pub rho_star: f64,
    /// A rigid particle (Ca → 0).
    pub rigid: bool,
    /// δ̄ = γ̇/k: the slow-manifold expansion ratio ([`SlowManifold::ratio`]) at the flow's
    /// mean strain rate, k the particle's slowest elastic relaxation rate
    /// ([`SlowManifold::relaxation_rate`]); 0 for a rigid particle, ∞ where the flow has no
    /// rate or the law is not isotropic ([`crate::material::Hyperelastic::is_isotropic`]: the
    /// manifold's quasi-static stretch is the isotropic small-strain one, so such a particle
    /// keeps the full shape model).
    pub shape_ratio: f64,
}

impl ParticleNumbers {
    /// The largest response time of `particle`'s rest shape, τ = m/(μ_f λ_min(K̂)): the
    /// e-folding time of its slip in the slowest direction of the drag tensor, what
    /// [`ParticleNumbers::of`] divides by the flow's time scale (and what a stopping distance
    /// τU is made of).
    pub fn response_time<M: Response, D: DragModel>(particle: &Particle<M, D>) -> Result<f64, ParamError> {
        let rest = particle.try_geometry(&Mat3::identity())?;
        let resistance = particle.drag().resistance(&rest.frame, &rest.ints);
        let slowest = resistance.symmetric_eigenvalues().min();
        Ok(particle.mass() / (particle.fluid().mu * slowest))
    }

    /// The numbers of `particle` in `flow`: the largest response time of the rest shape,
    /// τ = m/(μ_f λ_min(K̂)) (the slowest direction of the drag tensor), over the flow's time
    /// scale 1/γ̇ ([`FlowField::strain_rate`]; a flow without one gives St = ∞, so the particle
    /// keeps its inertia), and ρ* = ρ_p γ̇ d_eq²/μ_f.
    pub fn of<M: Response, D: DragModel, F: FlowField + ?Sized>(
        particle: &Particle<M, D>,
        flow: &F,
    ) -> Result<Self, ParamError> {
        let tau = Self::response_time(particle)?;
        let rate = flow.strain_rate().unwrap_or(f64::INFINITY);
        let d_eq = 2.0 * particle.shape().semi_axes().product().cbrt();
        let isotropic = particle.elastic().is_none_or(|law| law.is_isotropic());
        let shape_ratio = match SlowManifold::of(particle)? {
            Some(m) if isotropic => rate / m.relaxation_rate(),
            Some(_) => f64::INFINITY,
            None => 0.0,
        };
        Ok(Self {
            stokes: tau * rate,
            rho_star: particle.rho_solid() * rate * d_eq * d_eq / particle.fluid().mu,
            rigid: particle.elastic().is_none(),
            shape_ratio,
        })
    }

    /// [`Self::of`] for a particle starting in `state`, whose Stokes number is at least its
    /// launch's: $τ\\,|v − u(x)|/d_{eq}$, the distance its initial slip carries it before it
    /// relaxes, in equivalent diameters. A particle thrown into still fluid (St = 0 by the flow's
    /// rate alone) keeps its inertia; one released at the fluid's velocity is chosen as before.
    /// A state outside the flow leaves the flow's number alone (its first step fails anyway).
    pub fn at<M: Response, D: DragModel, F: FlowField + ?Sized>(
        particle: &Particle<M, D>,
        flow: &F,
        state: &State,
    ) -> Result<Self, ParamError> {
        let numbers = Self::of(particle, flow)?;
        let Ok(sample) = flow.sample(&state.x, state.t) else {
            return Ok(numbers);
        };
        let d_eq = 2.0 * particle.shape().semi_axes().product().cbrt();
        let launch = Self::response_time(particle)? * (state.v - sample.u).norm() / d_eq;
        Ok(Self {
            stokes: if launch.is_finite() {
                numbers.stokes.max(launch)
            } else {
                numbers.stokes
            },
            ..numbers
        })
    }
}

/// An integrator and why it was chosen.
#[derive(Debug, Clone)]
pub struct Choice {
    /// The integrator.
    pub integrator: Chosen,
    /// One line for the run log: the numbers and the rules they met.
    pub reason: String,
}

/// What [`choose`] picks: the full inertialess model, or the slow manifold over it.
#[derive(Debug, Clone, Copy)]
pub enum Chosen {
    /// The full model.
    Full(Stokesian),
    /// The slow manifold where it holds, the full model elsewhere.
    SlowManifold(Manifold),
}

impl Chosen {
    /// The full model (the slow manifold's own where it does not hold).
    pub fn full(&self) -> Stokesian {
        match self {
            Chosen::Full(full) => *full,
            Chosen::SlowManifold(m) => m.full,
        }
    }

    /// The same choice with the full model measuring its error by `norm`.
    pub fn with_norm(self, norm: ErrorNorm) -> Self {
        match self {
            Chosen::Full(full) => Chosen::Full(full.with_norm(norm)),
            Chosen::SlowManifold(mut m) => {
                m.full = m.full.with_norm(norm);
                Chosen::SlowManifold(m)
            }
        }
    }
}

impl From<Stokesian> for Chosen {
    fn from(full: Stokesian) -> Self {
        Chosen::Full(full)
    }
}

/// Step memory of [`Chosen`]: the memory of the integrator it holds.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct ChosenMemory {
    full: StokesianMemory,
    manifold: ManifoldMemory,
}

impl TimeIntegrator for Chosen {
    type Memory = ChosenMemory;

    fn name(&self) -> &'static str {
        match self {
            Chosen::Full(full) => full.name(),
            Chosen::SlowManifold(m) => m.name(),
        }
    }

    fn barycentre(&self) -> BarycentreModel {
        self.full().barycentre
    }

    fn step_with<M: Response, D: DragModel, F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        state: &State,
        memory: &mut ChosenMemory,
        flow: &F,
        dt: f64,
    ) -> Result<Step, StepError> {
        match self {
            Chosen::Full(full) => full.step_with(particle, state, &mut memory.full, flow, dt),
            Chosen::SlowManifold(m) => m.step_with(particle, state, &mut memory.manifold, flow, dt),
        }
    }

    fn report(&self, memory: &ChosenMemory) -> IntegratorReport {
        match self {
            Chosen::Full(full) => full.report(&memory.full),
            Chosen::SlowManifold(m) => m.report(&memory.manifold),
        }
    }

    fn mapped(&self, memory: &mut ChosenMemory) {
        match self {
            Chosen::Full(full) => full.mapped(&mut memory.full),
            Chosen::SlowManifold(m) => m.mapped(&mut memory.manifold),
        }
    }

    fn describe<M: Response, D: DragModel, F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        flow: &F,
    ) -> Option<String> {
        match self {
            Chosen::Full(full) => full.describe(particle, flow),
            Chosen::SlowManifold(m) => m.describe(particle, flow),
        }
    }
}

/// The integrator for a particle with `numbers` at tolerances `tol` (module docs).
pub fn choose(numbers: ParticleNumbers, tol: Tolerances) -> Result<Choice, ParamError> {
    // St = ∞ (a flow with no time scale) is allowed: the particle keeps its inertia.
    if numbers.stokes.is_nan() || numbers.stokes < 0.0 {
        return Err(ParamError::NotPositive {
            name: "Stokes number",
            value: numbers.stokes,
        });
    }
    let stokes = numbers.stokes;
    let rho_star = numbers.rho_star;
    if rho_star.is_nan() || rho_star < 0.0 {
        return Err(ParamError::NotPositive {
            name: "rho*",
            value: rho_star,
        });
    }
    let shape_ratio = numbers.shape_ratio;
    if shape_ratio.is_nan() || shape_ratio < 0.0 {
        return Err(ParamError::NotPositive {
            name: "shape ratio",
            value: shape_ratio,
        });
    }
    let equilibrium = stokes <= EQUILIBRIUM_STOKES;
    let scheme = Scheme::for_rtol(tol.rtol());
    let rosenbrock = scheme == Scheme::Rosenbrock23;
    let full = Stokesian {
        tol,
        barycentre: if equilibrium {
            BarycentreModel::Equilibrium
        } else {
            BarycentreModel::Inertial
        },
        scheme,
        norm: ErrorNorm::default(),
        frame: Frame::Lab,
    };
    let manifold = Manifold::new(full)?;
    let slow = !numbers.rigid && shape_ratio <= MANIFOLD_SHARE * manifold.delta_max();
    let shape = if numbers.rigid {
        String::new()
    } else {
        format!(
            ", {}: gamma/k = {shape_ratio:.3e} {} {MANIFOLD_SHARE} delta_max = {:.3e}",
            if slow {
                "on the slow manifold"
            } else {
                "full shape model"
            },
            if slow { "<=" } else { ">" },
            MANIFOLD_SHARE * manifold.delta_max()
        )
    };
    let reason = format!(
        "{} inertialess shape, {} barycentre, {}: St = {stokes:.3e} {} {EQUILIBRIUM_STOKES}, rtol = {:.0e} {} \
         {ROSENBROCK_RTOL:.0e}, rho* = {rho_star:.3e}{}",
        if numbers.rigid { "rigid" } else { "elastic" },
        if equilibrium { "equilibrium" } else { "inertial" },
        scheme.name(),
        if equilibrium { "<=" } else { ">" },
        tol.rtol(),
        if rosenbrock { ">=" } else { "<" },
        if rho_star > RHO_STAR_INERTIALESS {
            format!(" > {RHO_STAR_INERTIALESS}: the shape's inertia is neglected (an O(rho*) error)")
        } else {
            String::new()
        }
    ) + &shape;
    Ok(Choice {
        integrator: if slow {
            Chosen::SlowManifold(manifold)
        } else {
            Chosen::Full(full)
        },
        reason,
    })
}

/// The integrator chosen per particle ([`choose`] on [`ParticleNumbers::of`]) at tolerances
/// `tol`, at the particle's first step.
#[derive(Debug, Clone, Copy)]
pub struct Auto {
    /// Error tolerances.
    pub tol: Tolerances,
    /// How the chosen integrator measures the local error.
    pub norm: ErrorNorm,
}

impl Auto {
    /// The choice for `particle` in `flow`, launched at the fluid's velocity.
    pub fn choice<M: Response, D: DragModel, F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        flow: &F,
    ) -> Result<Choice, ParamError> {
        self.chosen(ParticleNumbers::of(particle, flow)?)
    }

    /// The choice for `particle` in `flow` starting in `state`: its launch's slip counts
    /// ([`ParticleNumbers::at`]).
    pub fn choice_at<M: Response, D: DragModel, F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        flow: &F,
        state: &State,
    ) -> Result<Choice, ParamError> {
        self.chosen(ParticleNumbers::at(particle, flow, state)?)
    }

    fn chosen(&self, numbers: ParticleNumbers) -> Result<Choice, ParamError> {
        let choice = choose(numbers, self.tol)?;
        Ok(Choice {
            integrator: choice.integrator.with_norm(self.norm),
            ..choice
        })
    }
}

/// Step memory of [`Auto`]: the chosen integrator and its memory. The choice is a function of
/// the particle, the flow, the tolerances and the Stokes number of the first step's state
/// ([`ParticleNumbers::at`]), so a checkpoint keeps that number and a resumed run chooses as
/// the first did.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct AutoMemory {
    #[serde(skip)]
    chosen: Option<Chosen>,
    /// The Stokes number of the choice, once made.
    #[serde(default)]
    stokes: Option<f64>,
    inner: ChosenMemory,
}

impl TimeIntegrator for Auto {
    type Memory = AutoMemory;

    fn name(&self) -> &'static str {
        "auto"
    }

    fn step_with<M: Response, D: DragModel, F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        state: &State,
        memory: &mut AutoMemory,
        flow: &F,
        dt: f64,
    ) -> Result<Step, StepError> {
        let chosen = match memory.chosen {
            Some(chosen) => chosen,
            None => {
                let numbers = match memory.stokes {
                    Some(stokes) => ParticleNumbers {
                        stokes,
                        ..ParticleNumbers::of(particle, flow).map_err(StepError::Param)?
                    },
                    None => ParticleNumbers::at(particle, flow, state).map_err(StepError::Param)?,
                };
                let chosen = self.chosen(numbers).map_err(StepError::Param)?.integrator;
                memory.stokes = Some(numbers.stokes);
                memory.chosen = Some(chosen);
                chosen
            }
        };
        chosen.step_with(particle, state, &mut memory.inner, flow, dt)
    }

    /// The chosen integrator's report; empty before the first step (nothing chosen yet).
    fn report(&self, memory: &AutoMemory) -> IntegratorReport {
        memory
            .chosen
            .map_or_else(IntegratorReport::default, |c| c.report(&memory.inner))
    }

    fn mapped(&self, memory: &mut AutoMemory) {
        if let Some(chosen) = memory.chosen {
            chosen.mapped(&mut memory.inner);
        }
    }

    fn describe<M: Response, D: DragModel, F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        flow: &F,
    ) -> Option<String> {
        Some(match self.choice(particle, flow) {
            Ok(choice) => choice.reason,
            Err(e) => format!("no choice: {e}"),
        })
    }
}

// Selectable by name: `[integrator] type = "auto"` with `tol` (rtol = atol) and `norm`.
inventory::submit! {
    super::IntegratorRegistration {
        name: "auto",
        aliases: &[],
        build: |p| {
            p.only(&["tol", "norm"])?;
            Ok(super::SceneIntegrator::new(Auto {
                tol: Tolerances::uniform(p.positive("tol")?)?,
                norm: super::stokesian::error_norm(p)?,
            }))
        },
    }
}

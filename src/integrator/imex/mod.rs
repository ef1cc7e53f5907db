//! The paper's implicit–explicit integrator (§5), exactly as published.
//!
//! # Physics (paper eqs. 17–22)
//! The step integrates the shape equation Ḟ = A, Ȧ = vol(B₀)[P̃ − P]Θ⁻¹ (eq. 18) and the
//! barycentre equation (eq. 17, with 1/τ_D = π μ_f r_min/m) with the paper's splitting: the
//! elastic stress P implicit (eq. 21), the fluid load P̃* explicit in the old solid velocity
//! gradient (eq. 22), the barycentre by implicit Euler (eqs. 19, 20). First order in Δt. Its
//! two stability conditions are derived in [`crate::theory::stability`].
//!
//! # Algorithm (paper §5)
//! 1. (r, Q)ⁿ from F̄ⁿ F̄ⁿᵀ; l_sⁿ = Aⁿ(Fⁿ)⁻¹; σ̃* = σ̃(rⁿ, Qⁿ; l_sⁿ, l_f^{n+1}) — **explicit** and
//!    frozen during the Newton iterations.
//! 2. Newton for F^{n+1} (from an extrapolated start, see below) on
//!    $R(F) = F - F^n - \Delta t A^n - \Delta t^2 \mathrm{vol}(B_0)\\,[J\tilde\sigma^* F^{-T} - P(F)]\\,\Theta^{-1} = 0$
//!    (eq. 18 discretised). The Jacobian is assembled from ∂(Jσ̃*F⁻ᵀ)/∂F by num-dual AD and
//!    the material tangent ∂P/∂F (AD of W, or a closed form checked against AD).
//! 3. A^{n+1} = (F^{n+1} − Fⁿ)/Δt.
//! 4. K̂ and a_G from F̄^{n+1}, then implicit Euler for the barycentre (eq. 19):
//!    (1 + Δt R) v^{n+1} = vⁿ + Δt a_G + Δt R u, x^{n+1} = xⁿ + Δt v^{n+1}, R = μ_f K̂/m.
//!
//! The flow is sampled at (xⁿ, t^{n+1}). Stability needs Δt ≲ ρ*/30…ρ*/120 (explicit viscous
//! term, [`stability_limit`]) and, with [`VolumetricTraction::Paper`], λ_s Δt ≳ μ_f.
//!
//! # Step memory
//! The geometry of F^{n+1} (needed for the drag in step 4) is the geometry of Fⁿ in step 1 of
//! the next step, so [`ImexMemory`] keeps it: one model evaluation per step instead of two.
//! It also keeps the Newton Jacobian across steps (a chord iteration): the Jacobian is
//! 1 − O(Δt²λ_s/ρ*) and changes by O(Δt) per step, so a kept one still contracts the residual
//! fast; it is rebuilt whenever an iteration contracts by less than 20×. The converged F^{n+1}
//! meets the same Newton tolerance either way.
//!
//! # Stability
//! The scheme's two stability conditions, the explicit viscous limit and the volume-mode floor,
//! and the guard that enforces them are in [`stability`].
//!
//! [`VolumetricTraction::Paper`]: crate::hydro::VolumetricTraction::Paper

pub mod stability;

pub use stability::{StabilityGuard, stability_limit, volume_mode_floor};

use super::dense::{Dense, Knot};
use super::newton::{self, NewtonOptions};
use super::{Step, StepInfo, TimeIntegrator};
use crate::error::StepError;
use crate::flow::FlowField;
use crate::hydro::DragModel;
use crate::material::{Response, StressLaw};
use crate::particle::dynamics::{Geometry, Model, traction_load};
use crate::particle::{Particle, State};
use crate::tensor::{Mat3, Mat9, mat3, vec9};
use nalgebra::{Const, SVector};
use num_dual::DualVec;
use serde::{Deserialize, Serialize};
use stability::StepWindow;

/// The paper's fixed-step IMEX scheme.
#[derive(Debug, Clone, Copy, Default)]
pub struct ImexPaper {
    /// Newton controls (default: |R|∞ ≤ 1e-12, at most 12 iterations).
    pub newton: NewtonOptions,
    /// Stability guard (default [`StabilityGuard::Cached`]).
    pub guard: StabilityGuard,
}

impl ImexPaper {
    /// The scheme without a stability check.
    pub fn unguarded() -> Self {
        Self {
            guard: StabilityGuard::Off,
            ..Self::default()
        }
    }
}

/// Step memory of the IMEX schemes: pure caches of functions of F, so a checkpoint need not
/// store them (they are recomputed bitwise identically after a resume).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct ImexMemory {
    /// Geometry of the last accepted F, keyed by that F.
    #[serde(skip)]
    geometry: Option<(Mat3, Geometry)>,
    /// Step window and the C = FᵀF it was computed at.
    #[serde(skip)]
    guard: Option<(Mat3, StepWindow)>,
    /// The Newton Jacobian kept across steps (not a cache: it changes the iterates at the
    /// Newton tolerance, so checkpoints keep it).
    newton: newton::JacobianCache,
    /// (F^{n+1}, Aⁿ, Δt) of the last accepted step: the history of the extrapolated Newton
    /// start (kept by checkpoints for the same reason).
    history: Option<(Mat3, Mat3, f64)>,
}

impl ImexMemory {
    /// Geometry of `f`: cached when `f` is the last accepted F, else one model evaluation.
    pub(crate) fn geometry<M: Response, D: DragModel, F: FlowField + ?Sized>(
        &self,
        model: &Model<M, D, F>,
        f: &Mat3,
        t: f64,
    ) -> Result<Geometry, StepError> {
        match &self.geometry {
            Some((key, geo)) if key == f => Ok(*geo),
            _ => model.geometry(f, t),
        }
    }

    /// What a step that ended at `f` evaluated there: the frame of its geometry (the flow was
    /// sampled at the old barycentre).
    pub(crate) fn end(&self, f: &Mat3) -> super::EndEvaluation {
        super::EndEvaluation {
            frame: self.geometry.filter(|(key, _)| key == f).map(|(_, geo)| geo.frame),
            flow: None,
        }
    }

    /// The stable step window at `f` under `guard`, re-computed only when needed: `None` for
    /// [`StabilityGuard::Off`]. The cached window's upper end carries the guard's safety factor.
    pub(crate) fn window<M: Response, D: DragModel>(
        &mut self,
        guard: StabilityGuard,
        particle: &Particle<M, D>,
        f: &Mat3,
        geo: &Geometry,
        t: f64,
    ) -> Result<Option<StepWindow>, StepError> {
        match guard {
            StabilityGuard::Off => Ok(None),
            StabilityGuard::Exact => StepWindow::at(particle, f, geo, t).map(Some),
            StabilityGuard::Cached { rel_change, safety } => {
                let c = f.transpose() * f;
                let fresh = match &self.guard {
                    Some((c_ref, _)) => (c - c_ref).amax() <= rel_change * c_ref.amax(),
                    None => false,
                };
                if !fresh {
                    self.guard = Some((c, StepWindow::at(particle, f, geo, t)?));
                }
                Ok(self.guard.map(|(_, w)| StepWindow {
                    max: safety * w.max,
                    min: w.min,
                }))
            }
        }
    }
}

/// Shape update of one IMEX step: F^{n+1} and the Newton record.
pub(crate) fn shape_update<M: Response, D: DragModel, F: FlowField + ?Sized>(
    model: &Model<M, D, F>,
    state: &State,
    sigma_star: &Mat3,
    dt: f64,
    opts: NewtonOptions,
    jacobian: &mut newton::JacobianCache,
    history: Option<(Mat3, Mat3, f64)>,
) -> Result<newton::NewtonResult, StepError> {
    let particle = model.particle;
    let c = dt * dt * particle.volume0();
    let theta_inv = *particle.theta_inv();
    let anchor = state.f + state.a * dt;
    // Start Newton from Fⁿ + Δt A^{n+1} with A^{n+1} extrapolated linearly from Aⁿ⁻¹, Aⁿ: the
    // start is then O(Δt³) from F^{n+1} instead of O(Δt²), which saves about one iteration.
    let start = match history {
        Some((f_key, a_prev, dt_prev)) if f_key == state.f => anchor + (state.a - a_prev) * (dt * dt / dt_prev),
        _ => anchor,
    };
    let theta_inv_norm = theta_inv.amax();
    let t_new = state.t + dt;
    // The scheme integrates eq. 18, which needs the elastic stress.
    let material = particle.elastic().ok_or(StepError::RigidParticle {
        integrator: "imex_paper",
    })?;
    newton::solve_cached(
        vec9(&start),
        opts,
        jacobian,
        |x| {
            let f = mat3(x);
            crate::particle::dynamics::check_orientation(&f, t_new)?;
            let (load, stress) = (traction_load(&f, sigma_star), material.piola(&f));
            // Round-off of R: ε times its largest term (|X Θ⁻¹|∞ ≤ 3|X|∞|Θ⁻¹|∞ bounds the products).
            let scaled = 3.0 * c * theta_inv_norm * load.amax().max(stress.amax());
            let floor = f64::EPSILON * f.amax().max(anchor.amax()).max(scaled);
            Ok((vec9(&(f - anchor - (load - stress) * theta_inv * c)), floor))
        },
        |x| {
            model.count_jacobian();
            // vec(X Θ⁻¹) = (Θ⁻ᵀ ⊗ 1) vec(X)
            let right_theta: Mat9 = theta_inv.transpose().kronecker(&Mat3::identity());
            let (_, d_load) = num_dual::jacobian(
                |v: SVector<DualVec<f64, Const<9>>, 9>| vec9(&traction_load(&mat3(&v), sigma_star)),
                x,
            );
            Mat9::identity() - right_theta * (d_load - material.tangent(&mat3(x))) * c
        },
    )
}

/// Implicit Euler on eq. 19 (the paper's barycentre update):
/// (1 + Δt R) v^{n+1} = vⁿ + Δt a_G + Δt R u, x^{n+1} = xⁿ + Δt v^{n+1}.
fn barycentre_update(
    state: &State,
    u: &crate::tensor::Vec3,
    forcing: &crate::particle::Forcing,
    dt: f64,
) -> Result<(crate::tensor::Vec3, crate::tensor::Vec3), StepError> {
    let lhs = Mat3::identity() + forcing.drag_rate * dt;
    let rhs = state.v + forcing.a_g * dt + forcing.drag_rate * u * dt;
    let v = lhs.lu().solve(&rhs).ok_or(StepError::NonFinite {
        what: "barycentre system",
        t: state.t + dt,
    })?;
    Ok((state.x + v * dt, v))
}

impl ImexPaper {
    /// One paper step with `memory`; the guard is the caller's business (see
    /// [`TimeIntegrator::step_with`]).
    pub(crate) fn unguarded_step<M: Response, D: DragModel, F: FlowField + ?Sized>(
        &self,
        model: &Model<M, D, F>,
        state: &State,
        geo: &Geometry,
        memory: &mut ImexMemory,
        dt: f64,
    ) -> Result<(State, newton::NewtonResult), StepError> {
        let t_new = state.t + dt;
        let sample = model.sample(&state.x, t_new)?;
        let sigma_star = model.sigma_tilde(geo, &state.l_s(), &sample.grad_u);
        let sol = shape_update(
            model,
            state,
            &sigma_star,
            dt,
            self.newton,
            &mut memory.newton,
            memory.history,
        )?;
        let f_new = mat3(&sol.x);
        let geo_new = model.geometry(&f_new, t_new)?;
        let forcing = model.forcing(&geo_new, f_new.determinant(), &sample, &state.v, t_new)?;
        let (x, v) = barycentre_update(state, &sample.u, &forcing, dt)?;
        let next = State {
            t: t_new,
            x,
            v,
            f: f_new,
            a: (f_new - state.f) / dt,
        };
        next.validate()?;
        memory.geometry = Some((f_new, geo_new));
        memory.history = Some((f_new, state.a, dt));
        Ok((next, sol))
    }
}

impl TimeIntegrator for ImexPaper {
    type Memory = ImexMemory;

    fn name(&self) -> &'static str {
        "imex_paper"
    }

    fn step_with<M: Response, D: DragModel, F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        state: &State,
        memory: &mut ImexMemory,
        flow: &F,
        dt: f64,
    ) -> Result<Step, StepError> {
        super::check_step(state, dt)?;
        let model = Model::new(particle, flow);
        let geo = memory.geometry(&model, &state.f, state.t)?;
        if let Some(window) = memory.window(self.guard, particle, &state.f, &geo, state.t)?
            && dt > window.max
        {
            return Err(StepError::Unstable {
                dt,
                limit: window.max,
                reason: "explicit viscous traction",
            });
        }
        let (next, sol) = self.unguarded_step(&model, state, &geo, memory, dt)?;
        let info = StepInfo {
            newton_iters: sol.iters,
            residual: sol.residual,
            ..StepInfo::from_work(model.work(), dt, dt)
        };
        Ok(Step {
            dense: Dense::new(state.t, dt, Knot::of_state(state), Knot::of_state(&next)),
            end: memory.end(&next.f),
            state: next,
            info,
        })
    }
}

// Selectable by name: `[integrator] type = "imex_paper"` (the name datasets and run logs give
// it, [`TimeIntegrator::name`]; `imex` is kept as an alias), fixed `dt`, inertial barycentre
// only.
inventory::submit! {
    super::IntegratorRegistration {
        name: "imex_paper",
        aliases: &["imex"],
        build: |p| {
            p.only(&["overdamped"])?;
            super::registry::inertial_only(p)?;
            Ok(super::SceneIntegrator::new(ImexPaper::default()))
        },
    }
}

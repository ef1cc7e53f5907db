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
//! # Stability guard
//! The explicit viscous limit depends on F only through C = FᵀF: rotating the current
//! configuration, F ↦ RF, maps the explicit operator E to R∘E∘Rᵀ (objectivity of σ̃), a
//! similarity that keeps its eigenvalues. [`StabilityGuard::Cached`] therefore computes the
//! limit once and re-uses it while C stays within a relative distance δ = 5 % of the C it was
//! computed at, refusing steps beyond a safety fraction 0.9 of it: the limit moves by about as
//! much as C does, so a 5 % move of C stays inside the 10 % margin. A test checks that along
//! trajectories of shapes of aspect 1/20…20 at Ca 0.1…3 the cached guard refuses every step the
//! exact check refuses (`tests/stability_guard.rs`). Rigid rotation (tumbling) never triggers a re-check, so on a
//! tumbling particle the eigenproblem is solved once per appreciable change of shape.
//!
//! [`VolumetricTraction::Paper`]: crate::hydro::VolumetricTraction::Paper

use super::dense::{Dense, Knot};
use super::newton::{self, NewtonOptions};
use super::{Step, StepInfo, TimeIntegrator};
use crate::error::StepError;
use crate::flow::FlowField;
use crate::hydro::DragModel;
use crate::material::{Hyperelastic, Response};
use crate::particle::dynamics::{Geometry, Model, traction_load};
use crate::particle::{Particle, State};
use crate::tensor::{Mat3, Mat9, inv_transpose, mat3, vec9};
use nalgebra::{Const, SVector, Schur};
use num_dual::DualVec;
use serde::{Deserialize, Serialize};

/// How the IMEX step checks the explicit viscous stability limit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StabilityGuard {
    /// No check (the caller guarantees Δt).
    Off,
    /// Re-compute the limit only when C = FᵀF moved by more than `rel_change` (max-norm,
    /// relative; default 0.05) since it was last computed; refuse Δt > `safety` × limit
    /// (default 0.9).
    Cached {
        /// Relative change of C that triggers a re-computation (default 0.05).
        rel_change: f64,
        /// Fraction of the limit allowed (default 0.9).
        safety: f64,
    },
    /// Solve the 9×9 eigenproblem every step and refuse Δt > limit.
    Exact,
}

impl Default for StabilityGuard {
    fn default() -> Self {
        Self::Cached {
            rel_change: 0.05,
            safety: 0.9,
        }
    }
}

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

/// The step sizes for which the IMEX scheme is linearly stable at one configuration:
/// min < Δt ≤ max.
///
/// * `max` is the explicit viscous limit ([`stability_limit`]).
/// * `min` is [`volume_mode_floor`]: nonzero only for the literal eq. 12 traction
///   ([`VolumetricTraction::Paper`]), whose volume mode is anti-damped.
///
/// Both depend on F only through C = FᵀF (objectivity), so the cached guard keys both on C.
///
/// [`VolumetricTraction::Paper`]: crate::hydro::VolumetricTraction::Paper
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StepWindow {
    pub(crate) max: f64,
    pub(crate) min: f64,
}

impl StepWindow {
    /// No restriction (the guard is off).
    pub(crate) const UNBOUNDED: Self = Self {
        max: f64::INFINITY,
        min: 0.0,
    };

    fn at<M: Response, D: DragModel>(
        particle: &Particle<M, D>,
        f: &Mat3,
        geo: &Geometry,
        t: f64,
    ) -> Result<Self, StepError> {
        Ok(Self {
            max: stability_limit_at(particle, f, geo, t)?,
            min: volume_floor_at(particle, f, geo, t)?,
        })
    }
}

/// Smallest Δt at which the IMEX step keeps the volume mode from growing: 0 unless the
/// traction anti-damps dilation (the literal eq. 12, [`VolumetricTraction::Paper`]).
///
/// Along the dilation of the current configuration, δF = F (l_s = 1), Jeffery–Roscoe's
/// deviatoric traction vanishes and only the volumetric term acts: σ̃(l_s = 1) = 2μ_f·1 for
/// the literal eq. 12 (anti-damping), 0 for `Dev`, −4μ_f·1 for `Source`. Projected on δF,
/// eq. 18 is the oscillator ẍ = a ẋ − ω² x with the Rayleigh quotients
/// $a = \langle F, \mathrm{vol}(B_0) J \tilde\sigma(1) F^{-T}\Theta^{-1}\rangle / |F|^2$ and
/// $\omega^2 = \langle F, \mathrm{vol}(B_0)\\,(\partial P/\partial F : F)\\,\Theta^{-1}\rangle / |F|^2$.
/// The IMEX step (a explicit, ω² implicit) multiplies the mode's energy by
/// (1 + aΔt)/(1 + ω²Δt²) per step, so it is stable iff Δt > a/ω², the value returned. For a
/// sphere at rest this is the exact 2μ_f/(3λ_s + 2μ_s); for deformed shapes dilation is not
/// exactly an eigenmode, and `tests/stability_guard.rs` checks growth below and decay above
/// the floor on stretched shapes. For a rigid particle the floor is 0 (no shape dynamics).
///
/// Note that the continuous model itself is anti-damped along dilation with the literal
/// eq. 12: only the scheme's numerical damping at Δt > a/ω² hides it, so an error-controlled
/// integrator that resolves the mode ([`super::ImexAdaptive`] at a tight tolerance) must
/// refuse to go below the floor.
///
/// [`VolumetricTraction::Paper`]: crate::hydro::VolumetricTraction::Paper
pub fn volume_mode_floor<M: Response, D: DragModel>(
    particle: &Particle<M, D>,
    state: &State,
) -> Result<f64, StepError> {
    volume_floor_at(particle, &state.f, &particle.geometry(&state.f), state.t)
}

fn volume_floor_at<M: Response, D: DragModel>(
    particle: &Particle<M, D>,
    f: &Mat3,
    geo: &Geometry,
    t: f64,
) -> Result<f64, StepError> {
    let Some(law) = particle.elastic() else {
        return Ok(0.0);
    };
    // σ̃(l_s = 1) is isotropic for every variant, so the principal frame needs no rotation.
    let sigma = geo
        .traction
        .sigma_principal(&Mat3::zeros(), &Mat3::identity(), particle.volumetric())
        * particle.fluid().mu;
    let theta_inv = particle.theta_inv();
    let vol0 = particle.volume0();
    let a = (f.determinant() * vol0 * sigma * inv_transpose(f) * theta_inv).dot(f);
    if a.is_nan() {
        return Err(StepError::NonFinite {
            what: "volume-mode damping",
            t,
        });
    }
    if a <= 0.0 {
        return Ok(0.0);
    }
    let stiffness = (mat3(&(law.tangent(f) * vec9(f))) * theta_inv * vol0).dot(f);
    if stiffness.is_nan() {
        return Err(StepError::NonFinite {
            what: "volume-mode stiffness",
            t,
        });
    }
    if stiffness <= 0.0 {
        // No elastic restoring force along dilation: nothing can out-damp the mode.
        return Ok(f64::INFINITY);
    }
    Ok(a / stiffness)
}

/// Largest Δt for which the explicit viscous term of the IMEX scheme is stable at `state`.
///
/// The explicit part is Ȧ = E A with E: A ↦ vol(B₀) J σ̃(l_s = A F⁻¹; l_f = 0) F⁻ᵀ Θ⁻¹, a
/// linear map on 9-vectors. Forward Euler on it is stable iff |1 + Δt λ| ≤ 1 for every
/// eigenvalue λ = a + ib with a < 0, i.e. Δt ≤ −2a/|λ|². Eigenvalues with a ≥ 0 are not viscous
/// damping (the volumetric anti-damping of the `paper` traction is left to the implicit
/// elastic update, which needs λ_s Δt ≳ μ_f).
pub fn stability_limit<M: Response, D: DragModel>(particle: &Particle<M, D>, state: &State) -> Result<f64, StepError> {
    stability_limit_at(particle, &state.f, &particle.geometry(&state.f), state.t)
}

/// Iteration cap of the Schur decomposition: a 9×9 QR iteration converges in a few dozen sweeps
/// when it converges at all.
const SCHUR_MAX_ITERS: usize = 300;
/// Deflation threshold of the Schur iteration (see [`stability_limit_at`]).
const SCHUR_EPS: f64 = 64.0 * f64::EPSILON;

fn stability_limit_at<M: Response, D: DragModel>(
    particle: &Particle<M, D>,
    f: &Mat3,
    geo: &Geometry,
    t: f64,
) -> Result<f64, StepError> {
    // The operator is assembled in the principal frame: the similarity A ↦ Q A Qᵀ keeps its
    // eigenvalues and removes the arbitrary frame of a (near-)spherical particle, whose
    // rotated operator made nalgebra's Schur iteration cycle.
    let q = geo.frame.q;
    let f_p = q * f * q.transpose();
    let f_inv = inv_transpose(&f_p).transpose();
    let theta_inv = q * particle.theta_inv() * q.transpose();
    let scale = f.determinant() * particle.volume0() * particle.fluid().mu;
    let mut op = Mat9::zeros();
    for k in 0..9 {
        let mut a = Mat3::zeros();
        a[k] = 1.0;
        let sigma = geo
            .traction
            .sigma_principal(&Mat3::zeros(), &(a * f_inv), particle.volumetric());
        op.set_column(k, &vec9(&(sigma * f_inv.transpose() * theta_inv * scale)));
    }
    if op.iter().any(|c| !c.is_finite()) {
        return Err(StepError::NonFinite {
            what: "explicit viscous operator",
            t,
        });
    }
    // nalgebra's shifted QR deflates when a subdiagonal entry falls below eps times its
    // neighbours; with eps = f64::EPSILON that test is never met for a degenerate spectrum
    // (spheres) whose round-off sits just above it, and unbounded it iterated forever. Deflating
    // at 64ε changes eigenvalues by O(64ε‖E‖), nothing for a stability limit. Every attempt
    // below is bounded; failing all, the step is refused with a typed error.
    let norm = op.amax();
    if let Some(schur) = [op, op.transpose()]
        .into_iter()
        .find_map(|m| Schur::try_new(m, SCHUR_EPS, SCHUR_MAX_ITERS))
    {
        return Ok(limit_of_eigenvalues(
            schur.complex_eigenvalues().iter().map(|l| (l.re, l.norm_sqr())),
        ));
    }
    // A (near-)sphere's operator is nearly symmetric: E = H + K with H = sym E and ‖K‖₂ = k
    // small. By Bauer–Fike every eigenvalue of E lies within k of an eigenvalue h of H, so a
    // mode with h < −k has Re λ ≤ h + k < 0 and |λ| ≤ |h| + k, and Δt ≤ 2(|h| − k)/(|h| + k)²
    // is a safe limit for it.
    let k = (op - op.transpose()).scale(0.5).norm();
    if k <= 1e-6 * norm
        && let Some(eig) =
            nalgebra::SymmetricEigen::try_new((op + op.transpose()).scale(0.5), SCHUR_EPS, SCHUR_MAX_ITERS)
    {
        return Ok(eig
            .eigenvalues
            .iter()
            .filter(|&&h| h < -k)
            .map(|&h| 2.0 * (h.abs() - k) / (h.abs() + k).powi(2))
            .fold(f64::INFINITY, f64::min));
    }
    // Otherwise perturb by 10⁻¹² and 10⁻¹⁰ of the norm in a fixed pseudo-random direction: a
    // perturbation δ moves a simple eigenvalue by O(δ), one of a 2×2 Jordan block by
    // O(√δ) ≤ 10⁻⁵ relative, far inside the guard's safety margin.
    let noise = Mat9::from_fn(|i, j| ((7 * i + 3 * j + 1) as f64).sin());
    [op + noise * (1e-12 * norm), op + noise * (1e-10 * norm)]
        .into_iter()
        .find_map(|m| Schur::try_new(m, SCHUR_EPS, SCHUR_MAX_ITERS))
        .map(|schur| limit_of_eigenvalues(schur.complex_eigenvalues().iter().map(|l| (l.re, l.norm_sqr()))))
        .ok_or(StepError::StabilityUnknown { t })
}

/// min over eigenvalues λ = a + ib with a < 0 of −2a/|λ|², from (a, |λ|²) pairs.
fn limit_of_eigenvalues(eig: impl Iterator<Item = (f64, f64)>) -> f64 {
    eig.filter(|&(re, _)| re < 0.0)
        .map(|(re, abs2)| -2.0 * re / abs2)
        .fold(f64::INFINITY, f64::min)
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
            state: next,
            info,
        })
    }
}

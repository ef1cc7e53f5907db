//! The paper's implicit–explicit integrator (§5), exactly as published.
//!
//! # Algorithm (paper §5, physics.md §3.3)
//! 1. (r, Q)ⁿ from F̄ⁿ F̄ⁿᵀ; l_sⁿ = Aⁿ(Fⁿ)⁻¹; σ̃* = σ̃(rⁿ, Qⁿ; l_sⁿ, l_f^{n+1}) — **explicit** and
//!    frozen during the Newton iterations.
//! 2. Newton for F^{n+1} from the predictor Fⁿ + ΔtAⁿ on
//!    $R(F) = F - F^n - \Delta t A^n - \Delta t^2 \mathrm{vol}(B_0)\,[J\tilde\sigma^* F^{-T} - P(F)]\,\Theta^{-1} = 0$.
//!    The Jacobian is assembled from ∂(Jσ̃*F⁻ᵀ)/∂F by num-dual AD and the material tangent
//!    ∂P/∂F (AD of W, or a closed form checked against AD).
//! 3. A^{n+1} = (F^{n+1} − Fⁿ)/Δt.
//! 4. k^{n+1}, a_G^{n+1} from F̄^{n+1}, then implicit Euler for the barycentre (eq. 19).
//!
//! The flow is sampled at (xⁿ, t^{n+1}). Stability needs Δt ≲ ρ*/30…ρ*/120 (explicit viscous
//! term) and, with [`VolumetricTraction::Paper`], λ_s Δt ≳ μ_f (physics.md §7).
//!
//! [`VolumetricTraction::Paper`]: crate::hydro::VolumetricTraction::Paper

use super::newton::{self, NewtonOptions};
use super::{StepInfo, TimeIntegrator};
use crate::error::StepError;
use crate::flow::FlowField;
use crate::hydro::DragModel;
use crate::hydro::gravity::reduced_gravity;
use crate::material::Hyperelastic;
use crate::particle::{Particle, State, barycentre};
use crate::tensor::{Mat3, Mat9, Vec9, det3, inv_transpose, lift, mat3, vec9};
use nalgebra::{Const, SVector};
use num_dual::DualVec;

/// The paper's fixed-step IMEX scheme.
#[derive(Debug, Clone, Copy)]
pub struct ImexPaper {
    /// Newton controls (default: |R|∞ ≤ 1e-12, at most 12 iterations).
    pub newton: NewtonOptions,
    /// Refuse steps beyond the explicit viscous stability limit ([`stability_limit`]) with
    /// [`StepError::Unstable`] (default on; costs one 9×9 eigenvalue problem per step).
    pub check_stability: bool,
}

impl Default for ImexPaper {
    fn default() -> Self {
        Self {
            newton: NewtonOptions::default(),
            check_stability: true,
        }
    }
}

/// Largest Δt for which the explicit viscous term of the IMEX scheme is stable at `state`.
///
/// The explicit part is Ȧ = E A with E: A ↦ vol(B₀) J σ̃(l_s = A F⁻¹; l_f = 0) F⁻ᵀ Θ⁻¹, a
/// linear map on 9-vectors. Forward Euler on it is stable iff |1 + Δt λ| ≤ 1 for every
/// eigenvalue λ = a + ib with a < 0, i.e. Δt ≤ −2a/|λ|² (physics.md §7, condition 1).
/// Eigenvalues with a ≥ 0 are not viscous damping (the volumetric anti-damping of the
/// `paper` traction is condition 2 and is left to the implicit elastic update).
pub fn stability_limit<M: Hyperelastic, D: DragModel>(particle: &Particle<M, D>, state: &State) -> f64 {
    let geo = particle.geometry(state);
    let f_inv = inv_transpose(&state.f).transpose();
    let j = state.f.determinant();
    let mu_f = particle.fluid().mu;
    let mut op = Mat9::zeros();
    for q in 0..9 {
        let mut a = Mat3::zeros();
        a[q] = 1.0;
        let sigma = geo
            .traction
            .sigma_tilde(&(a * f_inv), &Mat3::zeros(), mu_f, particle.volumetric());
        op.set_column(
            q,
            &vec9(&(sigma * f_inv.transpose() * particle.theta_inv() * (j * particle.volume0()))),
        );
    }
    op.complex_eigenvalues()
        .iter()
        .filter(|l| l.re < 0.0)
        .map(|l| -2.0 * l.re / l.norm_sqr())
        .fold(f64::INFINITY, f64::min)
}

/// J σ̃* F⁻ᵀ for a frozen σ̃*, generic so that AD gives its derivative in F.
fn traction_piola<S: crate::tensor::Scalar>(f: &Mat3<S>, sigma_star: &Mat3) -> Mat3<S> {
    lift::<S>(sigma_star) * inv_transpose(f) * det3(f)
}

/// Shape update of one IMEX step: F^{n+1} and the Newton record.
pub(crate) fn shape_update<M: Hyperelastic, D: DragModel>(
    particle: &Particle<M, D>,
    state: &State,
    sigma_star: &Mat3,
    dt: f64,
    opts: NewtonOptions,
) -> Result<newton::NewtonResult, StepError> {
    let c = dt * dt * particle.volume0();
    let theta_inv = *particle.theta_inv();
    let anchor = state.f + state.a * dt;
    // vec(X Θ⁻¹) = (Θ⁻ᵀ ⊗ 1) vec(X)
    let right_theta: Mat9 = theta_inv.transpose().kronecker(&Mat3::identity());
    let material = particle.material();
    newton::solve(vec9(&anchor), opts, |x, want_jac| {
        let f = mat3(x);
        let det_f = f.determinant();
        if !(det_f > 0.0) {
            return Err(StepError::Inverted { det_f, t: state.t + dt });
        }
        let p = material.piola(&f);
        let r = f - anchor - (traction_piola(&f, sigma_star) - p) * theta_inv * c;
        let jac = want_jac.then(|| {
            let (_, d_pt) = num_dual::jacobian(
                |v: SVector<DualVec<f64, Const<9>>, 9>| vec9(&traction_piola(&mat3(&v), sigma_star)),
                x,
            );
            Mat9::identity() - right_theta * (d_pt - material.tangent(&f)) * c
        });
        Ok((vec9(&r), jac))
    })
}

impl TimeIntegrator for ImexPaper {
    fn name(&self) -> &'static str {
        "imex_paper"
    }

    fn step<M: Hyperelastic, D: DragModel, F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        state: &State,
        flow: &F,
        dt: f64,
    ) -> Result<(State, StepInfo), StepError> {
        crate::error::positive("dt", dt)?;
        state.validate()?;
        if self.check_stability {
            let limit = stability_limit(particle, state);
            if dt > limit {
                return Err(StepError::Unstable {
                    dt,
                    limit,
                    reason: "explicit viscous traction (physics.md §7)",
                });
            }
        }
        let t_new = state.t + dt;
        let mu_f = particle.fluid().mu;
        let sample = flow.sample(&state.x, t_new)?;

        let geo = particle.geometry(state);
        let sigma_star = geo
            .traction
            .sigma_tilde(&state.l_s(), &sample.grad_u, mu_f, particle.volumetric());
        let sol = shape_update(particle, state, &sigma_star, dt, self.newton)?;
        let f_new = mat3(&sol.x);
        let a_new = (f_new - state.f) / dt;

        let mut next = State {
            t: t_new,
            x: state.x,
            v: state.v,
            f: f_new,
            a: a_new,
        };
        let geo_new = particle.geometry(&next);
        let drag_rate = particle.drag().resistance(&geo_new.frame, &geo_new.ints) * (mu_f / particle.mass());
        let a_g = reduced_gravity(
            particle.gravity(),
            particle.rho_solid(),
            particle.fluid().rho,
            f_new.determinant(),
        );
        let (x, v) = barycentre::implicit_euler(&state.x, &state.v, &sample.u, &a_g, &drag_rate, dt).ok_or(
            StepError::NonFinite {
                what: "barycentre system",
                t: t_new,
            },
        )?;
        next.x = x;
        next.v = v;
        next.validate()?;
        let info = StepInfo {
            dt,
            dt_next: dt,
            newton_iters: sol.iters,
            residual: sol.residual,
            rhs_evals: 1,
            jac_evals: sol.iters,
            rejected: 0,
        };
        Ok((next, info))
    }
}

/// Flattened residual helper for tests: R(F) of the Newton problem at `f`.
pub fn imex_residual<M: Hyperelastic, D: DragModel>(
    particle: &Particle<M, D>,
    state: &State,
    sigma_star: &Mat3,
    dt: f64,
    f: &Mat3,
) -> Vec9 {
    let c = dt * dt * particle.volume0();
    let p = particle.material().piola(f);
    vec9(&(f - state.f - state.a * dt - (traction_piola(f, sigma_star) - p) * particle.theta_inv() * c))
}

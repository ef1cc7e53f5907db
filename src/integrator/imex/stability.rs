//! Linear stability of the paper's IMEX step: the explicit viscous limit
//! ([`stability_limit`]), the volume-mode floor ([`volume_mode_floor`]), and the guard that
//! refuses steps outside them ([`StabilityGuard`]).
//!
//! # Physics (paper eqs. 18, 21, 22)
//! The step treats the fluid load P̃* of eq. 22 explicitly and the elastic stress P of eq. 21
//! implicitly; the derivation of both conditions is in [`crate::theory::stability`].
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

use crate::error::StepError;
use crate::hydro::DragModel;
use crate::material::{Response, StressLaw};
use crate::particle::dynamics::Geometry;
use crate::particle::{Particle, State};
use crate::tensor::{Mat3, Mat9, inv_transpose, mat3, vec9};
use nalgebra::Schur;

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

    pub(crate) fn at<M: Response, D: DragModel>(
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
/// integrator that resolves the mode ([`crate::integrator::ImexAdaptive`] at a tight tolerance) must
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

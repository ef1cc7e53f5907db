//! The three-stage Radau IIA collocation method of order 5 (Hairer & Wanner, *Solving Ordinary
//! Differential Equations II*, §IV.8, the RADAU5 algorithm), one accepted step per call, on a
//! fixed-size state y′ = f(t, y), y ∈ ℝᴺ, with a caller-supplied (possibly approximate) Jacobian.
//!
//! # Physics
//! None of its own: a generic solver of y′ = f(t, y). [`super::stokesian`] applies it to the
//! inertialess shape equation (paper eq. 18 with Θ → 0) and the barycentre equation (eq. 17).
//!
//! # Scheme
//! Collocation at c = ((4 − √6)/10, (4 + √6)/10, 1) with the Butcher matrix
//! ```math
//! A = \begin{pmatrix}
//!  \frac{88 - 7\sqrt6}{360} & \frac{296 - 169\sqrt6}{1800} & \frac{-2 + 3\sqrt6}{225} \\
//!  \frac{296 + 169\sqrt6}{1800} & \frac{88 + 7\sqrt6}{360} & \frac{-2 - 3\sqrt6}{225} \\
//!  \frac{16 - \sqrt6}{36} & \frac{16 + \sqrt6}{36} & \frac19
//! \end{pmatrix},\qquad b = A_{3\cdot}
//! ```
//! (stiffly accurate: y₁ = Y₃). The stage increments Zᵢ = Yᵢ − y₀ solve
//! Z = h (A ⊗ I) F(Z), F(Z)ᵢ = f(t + cᵢh, y₀ + Zᵢ). The method is L-stable (R(∞) = 0), so
//! components relaxing faster than 1/h are damped in one step instead of ringing.
//!
//! **Simplified Newton in eigen-coordinates.** A⁻¹ has one real eigenvalue γ and a complex
//! pair α ± iβ:
//! γ = 3 + 3^{2/3} − 3^{1/3}, α = 3 + (3^{1/3} − 3^{2/3})/2, β = (3^{5/6} + 3^{7/6})/2.
//! With T = (v_γ, Re v, Im v), the eigenvectors of A⁻¹ for γ and α + iβ scaled to a last
//! component of 1, T⁻¹A⁻¹T = diag(γ, [[α, β], [−β, α]]). In W = (T⁻¹ ⊗ I) Z one Newton
//! iteration with the Jacobian J is one real and one complex N×N solve,
//! ```math
//! (\tfrac{\gamma}{h} - J)\,\Delta W_1 = G_1 - \tfrac{\gamma}{h} W_1,\qquad
//! (\tfrac{\alpha - i\beta}{h} - J)(\Delta W_2 + i\Delta W_3)
//!   = G_2 + iG_3 - \tfrac{\alpha - i\beta}{h}(W_2 + iW_3),
//! ```
//! G = (T⁻¹ ⊗ I) F(Z), instead of one 3N×3N solve. Convergence is monitored by the contraction
//! rate θ, the geometric mean of the last two quotients ‖ΔWₖ‖/‖ΔWₖ₋₁‖ (at most 7 iterations;
//! an attempt is abandoned early when θ ≥ 0.99 or when θ predicts that the remaining
//! iterations cannot reach the tolerance).
//!
//! **Newton's rate** (where this departs from RADAU5). RADAU5 and SciPy's port judge
//! divergence and slow convergence from the first quotient ‖ΔW₂‖/‖ΔW₁‖ alone. On a stiff
//! problem whose stiff subspace moves along the solution, that quotient is no rate: on a
//! quasi-rigid particle (Ca = 1e-4, elastic rate 1/Ca) the stiff stretch directions rotate with
//! the particle during the step, so the Jacobian frozen at y₀ couples them to the rotation
//! (which is not stiff): an error in the stretch feeds the rotation with a gain a ≈ hλφ/γ (λ
//! the stiff rate, φ the angle turned in the step) and the rotation feeds the stretch back
//! with a gain b ≈ φ. The increments then alternate, quotients a, b, a, b… (measured: 1.1,
//! 0.035, 0.6, 0.035 at h ≈ 0.2), and the iteration contracts at √(ab) ≈ 0.2 per step while the
//! first quotient says "diverged". Rate-based verdicts therefore wait for the smoothed rate
//! (k ≥ 3), at the price of at most one more iteration on a truly diverging attempt; an exact
//! (finite-difference) Jacobian behaves the same, so it is the iteration's test, not the
//! Jacobian. With RADAU5's test every second attempt on that case was rejected.
//!
//! The same structure makes θ grow like h^{3/2}…h² (√(ab) with a ∝ h², b ∝ h; measured
//! exponent ≈ 2), much faster than the error estimate shrinks the step: err ≈ 1e-4 asks for
//! ×8 while Newton stops converging at ×2. So, after the convergence-rate control of
//! Gustafsson & Söderlind (1997, *SIAM J. Sci. Comput.* 18, 23), an accepted step whose
//! smoothed rate was measured (k ≥ 3) grows at most to h·(θ_target/θ)^{1/2}, θ_target = 0.1,
//! and never shrinks for it (the step did converge). Results on the quasi-rigid case are
//! insensitive to θ_target between 0.05 and 0.15; Hairer's test problems (Van der Pol,
//! Robertson) change by a few per cent at most.
//!
//! **Error estimate** (Hairer & Wanner, §IV.8, "Error estimation"): with γ₀ = 1/γ and the embedded
//! weights e = (−13 − 7√6, −13 + 7√6, −1)/3 (already divided by γ₀),
//! err = (γ/h − J)⁻¹ [f(t₀, y₀) + (e₁Z₁ + e₂Z₂ + e₃Z₃)/h], an O(h⁴) estimate whose filter
//! (γ/h − J)⁻¹ keeps it bounded for stiff components. On the first step and after a rejection
//! an estimate above 1 is filtered once more, err ← (γ/h − J)⁻¹[f(t₀, y₀ + err) + (e·Z)/h]
//! (one more evaluation), which removes the spurious growth of err for very stiff problems.
//!
//! **Step size** (§IV.8, "Step size selection"): h_new = h·fac·err^{−1/4} with the safety
//! factor reduced for slow Newton
//! (fac = 0.9·(2k_max + 1)/(2k_max + k)), and Gustafsson's predictive controller
//! h_new = fac·h·(h/h_old)·err^{−1/4}(err_old/err)^{1/4} taken when smaller; growth ≤ 8,
//! shrink ≥ 1/5, no growth right after a rejection, and no growth past Newton's reach (above).
//!
//! **Starting values** for Newton come from the previous step's collocation polynomial
//! extrapolated to t₀ + cᵢh (when h is at most 8 old steps); **Jacobian reuse**: the Jacobian is kept for the next step while
//! Newton converges within two iterations or contracts fast (θ ≤ 10⁻³), and refreshed when
//! Newton fails with a Jacobian taken at another point. LU factors depend on h and are rebuilt
//! on every attempt; they are not kept.
//!
//! **Dense output**: the collocation polynomial u of degree 3 through (0, y₀), (cᵢ, y₀ + Zᵢ),
//! exact at both ends of the step and of order 3 inside it.
//!
//! # Why Radau IIA and not a Rosenbrock (Rodas) pair
//! A Rosenbrock method has the Jacobian inside its order conditions: Rodas4/Rodas5P reach order
//! 4/5 only with the exact J, and with an arbitrary approximation only the conditions of a
//! W-method remain, which they satisfy to low order only (W-methods of high order need many
//! more stages). Radau IIA is a fully implicit Runge–Kutta method: the Jacobian only enters
//! Newton's iteration matrix, so the converged stages, and with them the order 5 and the
//! L-stability, do not depend on it; an approximate J (frozen frame and integrals, or a
//! Jacobian reused over several steps) costs Newton iterations, not accuracy. The callers'
//! Jacobians are approximate by design, and reusing one Jacobian over many steps is where
//! Radau saves most of its work.
//!
//! # Tolerances
//! Norms are weighted root-mean-square norms (Hairer's choice) with weights atol + rtol·|y₀ᵢ|
//! in Newton and atol + rtol·max(|y₀ᵢ|, |y₁ᵢ|) in the error test, or the same with each block
//! of the state (a vector, a tensor) weighted by its norm ([`super::control::ErrorNorm`]); a
//! position block, if the tolerances name one, is weighted by atol + rtol·ℓ in both instead of
//! its own size (`Tolerances::with_position`: steps independent of the origin); rtol and atol act on the
//! O(h⁴) local estimate directly, as in SciPy's
//! `solve_ivp(method="Radau")` (RADAU5 itself maps rtol ↦ 0.1·rtol^{2/3} first).
//!
//! Hand-written rather than taken from an ODE crate for the same reasons as
//! [`super::rosenbrock`]: the callers need one accepted step per call with its work counts,
//! step memory that checkpoints can hold, and static sizes for N = 12 or 15.

use super::control::{JacobianReuse, StepControl, Tolerances};
use crate::error::{StepError, finite, positive};
use nalgebra::{Complex, Const, DimMin, Matrix3, SMatrix, SVector, Vector3};
use serde::{Deserialize, Serialize};
use std::ops::Range;

/// c₁ = (4 − √6)/10.
const C1: f64 = 0.155_051_025_721_682_2;
/// c₂ = (4 + √6)/10.
const C2: f64 = 0.644_948_974_278_317_8;
/// Real eigenvalue of A⁻¹, γ = 3 + 3^{2/3} − 3^{1/3}.
const GAMMA: f64 = 3.637_834_252_744_496;
/// Real part of the complex eigenvalues of A⁻¹, α = 3 + (3^{1/3} − 3^{2/3})/2.
const ALPHA: f64 = 2.681_082_873_627_752_3;
/// Imaginary part of the complex eigenvalues of A⁻¹, β = (3^{5/6} + 3^{7/6})/2.
const BETA: f64 = 3.050_430_199_247_410_5;
/// Embedded-estimate weights e/γ₀ = ((−13 − 7√6)/3, (−13 + 7√6)/3, −1/3).
const E: [f64; 3] = [-10.048_809_399_827_416, 1.382_142_733_160_749, -1.0 / 3.0];
/// T = (v_γ, Re v, Im v): eigenvectors of A⁻¹ for γ and α + iβ, last component 1
/// (40-digit computation, rounded once; the test `transformation_diagonalises_a_inverse`
/// checks T⁻¹A⁻¹T against the closed forms).
const T: [[f64; 3]; 3] = [
    [
        0.094_438_762_488_975_24,
        -0.141_255_295_020_954_2,
        0.030_029_194_105_147_424,
    ],
    [
        0.250_213_122_965_333_3,
        0.204_129_352_293_799_94,
        -0.382_942_112_757_261_9,
    ],
    [1.0, 1.0, 0.0],
];
/// T⁻¹ (same computation).
const T_INV: [[f64; 3]; 3] = [
    [4.178_718_591_551_905, 0.327_682_820_761_062_37, 0.523_376_445_499_449_5],
    [
        -4.178_718_591_551_905,
        -0.327_682_820_761_062_37,
        0.476_623_554_500_550_44,
    ],
    [0.502_872_634_945_786_8, -2.571_926_949_855_605, 0.596_039_204_828_224_9],
];

/// Newton iterations per attempt (RADAU5's default).
const NEWTON_MAX_ITERS: u32 = 7;
/// The step controller's limits (Hairer & Wanner, §IV.8): safety 0.9, h_new/h within
/// [0.2, 8] (growth ≤ 8, shrink per error-test rejection ≥ 1/5), h/2 after a failed Newton
/// solve or evaluation (RADAU5's "unexpected rejection"), 50 failed attempts per call before
/// [`StepError::StepSizeUnderflow`].
pub const CONTROL: StepControl = StepControl {
    safety: 0.9,
    accept: (0.2, 8.0),
    reject: (0.2, 1.0),
    failure_shrink: 0.5,
    max_rejections: 50,
};
/// Keep the Jacobian for the next step while Newton's rate θ ≤ 10⁻³ (or it needed at most two
/// iterations).
pub const JACOBIAN_REUSE: JacobianReuse = JacobianReuse { contraction: 1e-3 };
/// Contraction rate treated as divergence.
const THETA_DIVERGED: f64 = 0.99;
/// Newton's smoothed rate at which the step stops growing (module docs, "Newton's rate"):
/// from θ = 0.1, seven iterations shrink an increment by 10⁻⁶, far below `fnewt`.
const THETA_TARGET: f64 = 0.1;
/// Shrink after a rejected first step (RADAU5: the initial h was a guess).
const SHRINK_FIRST: f64 = 0.1;
/// Floor of the error estimate in the controller (avoids err^{-1/4} = ∞).
const ERR_FLOOR: f64 = 1e-10;
/// Floor of the previous error in Gustafsson's ratio (RADAU5's value).
const ERR_OLD_FLOOR: f64 = 1e-2;

/// Dense output of one step: the collocation polynomial of degree 3 on [t, t + h].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RadauDense<const N: usize> {
    /// State at the step start.
    y0: SVector<f64, N>,
    /// Stage increments Zᵢ = Yᵢ − y₀ (columns).
    z: SMatrix<f64, N, 3>,
}

impl<const N: usize> RadauDense<N> {
    /// The interpolant at t + s h. Exact (bitwise the step's values) at s = 0 and s = 1, of
    /// order 3 for s ∈ (0, 1); outside [0, 1] it extrapolates the polynomial (which is how the
    /// next step's Newton starting values are predicted).
    pub fn eval(&self, s: f64) -> SVector<f64, N> {
        self.y0 + self.increment(s)
    }

    /// u(s) − y₀ = Σᵢ Zᵢ ℓᵢ(s), without the cancellation of forming u first.
    fn increment(&self, s: f64) -> SVector<f64, N> {
        self.z * lagrange(s)
    }
}

/// Lagrange basis on the nodes (0, c₁, c₂, 1) for the three nodes other than 0 (the increment
/// vanishes at s = 0). ℓ₃ is written so that ℓ₃(1) is exactly 1 and ℓ₁(1) = ℓ₂(1) = 0.
fn lagrange(s: f64) -> Vector3<f64> {
    Vector3::new(
        s * (s - C2) * (s - 1.0) / (C1 * (C1 - C2) * (C1 - 1.0)),
        s * (s - C1) * (s - 1.0) / (C2 * (C2 - C1) * (C2 - 1.0)),
        s * (s - C1) * (s - C2) / ((1.0 - C1) * (1.0 - C2)),
    )
}

/// The Jacobian in use and where it was taken.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct JacobianRecord<const N: usize> {
    j: SMatrix<f64, N, N>,
    t: f64,
    y: SVector<f64, N>,
    /// Newton contracted fast enough with it to keep it for the next step.
    reusable: bool,
}

/// What the previous accepted step leaves for the next one.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct LastStep<const N: usize> {
    /// Where it ended: the history continues only from exactly this point.
    t_end: f64,
    y_end: SVector<f64, N>,
    /// Step size and error estimate (floored), for Gustafsson's controller.
    h: f64,
    err: f64,
    /// Newton's last η = θ/(1 − θ), which starts the next convergence test.
    eta: f64,
    /// Collocation polynomial, extrapolated for the next starting values.
    dense: RadauDense<N>,
}

/// Step memory of [`step`] for one trajectory: the Jacobian with its evaluation point, and the
/// previous step (h, error, Newton rate, collocation polynomial). `Default` is a cold start,
/// and a call that returns an error leaves the memory cold.
///
/// The history is used only when the next call starts exactly where the last step ended (same
/// t and y, bitwise); otherwise (a driver reset the state, or the memory belongs to another
/// trajectory) the call starts cold but may still reuse the Jacobian, which only affects
/// Newton's convergence.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct RadauMemory<const N: usize> {
    jacobian: Option<JacobianRecord<N>>,
    last: Option<LastStep<N>>,
}

/// Outcome of one accepted step of [`step`].
#[derive(Debug, Clone)]
pub struct RadauStep<const N: usize> {
    /// State at t + h.
    pub y: SVector<f64, N>,
    /// Step taken.
    pub h: f64,
    /// Proposed next step.
    pub h_next: f64,
    /// Collocation polynomial on [t, t + h].
    pub dense: RadauDense<N>,
    /// Right-hand-side evaluations (accepted and rejected attempts).
    pub rhs_evals: u32,
    /// Jacobian evaluations.
    pub jac_evals: u32,
    /// LU factorisations (one real and one complex N×N per attempt).
    pub lu_decomps: u32,
    /// Newton iterations (each: three evaluations, one real and one complex solve).
    pub newton_iters: u32,
    /// Failed attempts (error test, Newton, or evaluation) before the accepted one.
    pub rejected: u32,
}

/// Work counters, incremented where the work is done.
#[derive(Debug, Default)]
struct Work {
    rhs: u32,
    jac: u32,
    lu: u32,
    newton: u32,
}

/// The right-hand side, counted.
struct Rhs<F, const N: usize> {
    f: F,
}

impl<F, const N: usize> Rhs<F, N>
where
    F: FnMut(f64, &SVector<f64, N>) -> Result<SVector<f64, N>, StepError>,
{
    fn eval(&mut self, work: &mut Work, t: f64, y: &SVector<f64, N>) -> Result<SVector<f64, N>, StepError> {
        work.rhs += 1;
        (self.f)(t, y)
    }

    /// An evaluation inside an attempt: `None` when it should reject the attempt (an inverted
    /// or non-finite trial state, or a non-finite value), other errors propagate.
    fn trial(&mut self, work: &mut Work, t: f64, y: &SVector<f64, N>) -> Result<Option<SVector<f64, N>>, StepError> {
        match self.eval(work, t, y) {
            Ok(f) if f.iter().all(|v| v.is_finite()) => Ok(Some(f)),
            Ok(_) | Err(StepError::Inverted { .. }) | Err(StepError::NonFinite { .. }) => Ok(None),
            Err(e) => Err(e),
        }
    }
}

/// Evaluate the Jacobian, counted and checked.
fn jacobian<const N: usize>(
    jac: &mut impl FnMut(f64, &SVector<f64, N>) -> Result<SMatrix<f64, N, N>, StepError>,
    work: &mut Work,
    t: f64,
    y: &SVector<f64, N>,
) -> Result<JacobianRecord<N>, StepError> {
    work.jac += 1;
    let j = jac(t, y)?;
    if j.iter().any(|v| !v.is_finite()) {
        return Err(StepError::NonFinite { what: "Jacobian", t });
    }
    Ok(JacobianRecord {
        j,
        t,
        y: *y,
        reusable: false,
    })
}

/// LU factors of the real and the complex iteration matrices for one h.
struct Factors<const N: usize>
where
    Const<N>: DimMin<Const<N>, Output = Const<N>>,
{
    real: nalgebra::linalg::LU<f64, Const<N>, Const<N>>,
    complex: nalgebra::linalg::LU<Complex<f64>, Const<N>, Const<N>>,
    /// γ/h and (α − iβ)/h.
    mu_real: f64,
    mu_complex: Complex<f64>,
}

impl<const N: usize> Factors<N>
where
    Const<N>: DimMin<Const<N>, Output = Const<N>>,
{
    fn new(j: &SMatrix<f64, N, N>, h: f64, work: &mut Work) -> Self {
        let mu_real = GAMMA / h;
        let mu_complex = Complex::new(ALPHA / h, -BETA / h);
        work.lu += 2;
        Self {
            real: (SMatrix::<f64, N, N>::identity() * mu_real - j).lu(),
            complex: (SMatrix::<Complex<f64>, N, N>::identity() * mu_complex - j.map(|v| Complex::new(v, 0.0))).lu(),
            mu_real,
            mu_complex,
        }
    }

    /// (γ/h − J)⁻¹ b, `None` when singular or not finite.
    fn solve_real(&self, b: &SVector<f64, N>) -> Option<SVector<f64, N>> {
        self.real.solve(b).filter(|x| x.iter().all(|v| v.is_finite()))
    }

    /// ((α − iβ)/h − J)⁻¹ b, `None` when singular or not finite.
    fn solve_complex(&self, b: &SVector<Complex<f64>, N>) -> Option<SVector<Complex<f64>, N>> {
        self.complex
            .solve(b)
            .filter(|x| x.iter().all(|v| v.re.is_finite() && v.im.is_finite()))
    }
}

fn matrix3(m: &[[f64; 3]; 3]) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| m[i][j])
}

/// Weighted RMS norm of the columns of `x` (any count) with weights `scale`.
fn rms<const N: usize, const K: usize>(x: &SMatrix<f64, N, K>, scale: &SVector<f64, N>) -> f64 {
    let sum: f64 = x.column_iter().map(|c| c.component_div(scale).norm_squared()).sum();
    (sum / (N * K) as f64).sqrt()
}

/// A converged collocation solve.
struct Stages<const N: usize> {
    z: SMatrix<f64, N, 3>,
    iters: u32,
    /// Last contraction rate; `None` when Newton converged in one iteration.
    theta: Option<f64>,
    eta: f64,
}

/// A failed collocation solve: retry with h times `shrink` (or first with a fresh Jacobian).
struct NewtonFailure {
    shrink: f64,
}

/// One collocation system: the step (t, y, h), its LU factors, and Newton's norm (weights
/// `scale`) and tolerance `fnewt`.
struct Collocation<'a, const N: usize>
where
    Const<N>: DimMin<Const<N>, Output = Const<N>>,
{
    t: f64,
    y: &'a SVector<f64, N>,
    h: f64,
    factors: &'a Factors<N>,
    scale: &'a SVector<f64, N>,
    fnewt: f64,
}

/// Simplified Newton for the collocation system from the starting increments `z0` with
/// η₀ = `eta0` (the first iteration's convergence test uses the previous step's rate).
fn solve_stages<const N: usize, F>(
    sys: &Collocation<'_, N>,
    z0: SMatrix<f64, N, 3>,
    eta0: f64,
    rhs: &mut Rhs<F, N>,
    work: &mut Work,
) -> Result<Result<Stages<N>, NewtonFailure>, StepError>
where
    Const<N>: DimMin<Const<N>, Output = Const<N>>,
    F: FnMut(f64, &SVector<f64, N>) -> Result<SVector<f64, N>, StepError>,
{
    let Collocation {
        t,
        y,
        h,
        factors,
        scale,
        fnewt,
    } = *sys;
    let t_mat = matrix3(&T).transpose();
    let t_inv = matrix3(&T_INV).transpose();
    let c = [C1, C2, 1.0];
    let mut z = z0;
    let mut w = z * t_inv;
    let mut eta = eta0;
    let mut theta = None;
    let mut norm_old = f64::NAN;
    let mut rate_old = f64::NAN;
    for k in 1..=NEWTON_MAX_ITERS {
        work.newton += 1;
        let mut f = SMatrix::<f64, N, 3>::zeros();
        for (i, ci) in c.iter().enumerate() {
            match rhs.trial(work, t + ci * h, &(y + z.column(i)))? {
                Some(fi) => f.set_column(i, &fi),
                None => {
                    return Ok(Err(NewtonFailure {
                        shrink: CONTROL.failure_shrink,
                    }));
                }
            }
        }
        let g = f * t_inv;
        let b_real = g.column(0) - w.column(0) * factors.mu_real;
        let b_complex = SVector::<Complex<f64>, N>::from_fn(|r, _| {
            Complex::new(g[(r, 1)], g[(r, 2)]) - factors.mu_complex * Complex::new(w[(r, 1)], w[(r, 2)])
        });
        let (Some(dw_real), Some(dw_complex)) = (
            factors.solve_real(&b_real.into_owned()),
            factors.solve_complex(&b_complex),
        ) else {
            return Ok(Err(NewtonFailure {
                shrink: CONTROL.failure_shrink,
            }));
        };
        let dw = SMatrix::<f64, N, 3>::from_columns(&[dw_real, dw_complex.map(|v| v.re), dw_complex.map(|v| v.im)]);
        let norm = rms(&dw, scale);
        if !norm.is_finite() {
            return Ok(Err(NewtonFailure {
                shrink: CONTROL.failure_shrink,
            }));
        }
        // Whether this iteration may end Newton: not after a first quotient ≥ 1 (below).
        let mut may_stop = true;
        if k > 1 {
            // Hairer's smoothed rate: the geometric mean of the last two quotients.
            let rate = norm / norm_old;
            let th = if k == 2 { rate } else { (rate * rate_old).sqrt() };
            rate_old = rate;
            theta = Some(th);
            if k == 2 && th >= THETA_DIVERGED {
                // One quotient is no verdict (module docs, "Newton's rate"): iterate once more
                // and judge the smoothed rate.
                may_stop = false;
            } else if th >= THETA_DIVERGED {
                return Ok(Err(NewtonFailure {
                    shrink: CONTROL.failure_shrink,
                }));
            } else {
                eta = th / (1.0 - th);
            }
            // Error left after the remaining iterations, predicted from the smoothed rate: if
            // it cannot reach the tolerance, shrink h now by the factor that would make it
            // (RADAU5, which predicts from the first quotient already).
            let left = NEWTON_MAX_ITERS.saturating_sub(1 + k);
            let predicted = eta * norm * th.powi(left as i32) / fnewt;
            if k > 2 && predicted >= 1.0 {
                let q = predicted.clamp(1e-4, 20.0);
                return Ok(Err(NewtonFailure {
                    shrink: 0.8 * q.powf(-1.0 / (4.0 + f64::from(left))),
                }));
            }
        }
        norm_old = norm.max(f64::EPSILON);
        w += dw;
        z = w * t_mat;
        if may_stop && eta * norm <= fnewt {
            return Ok(Ok(Stages {
                z,
                iters: k,
                theta,
                eta,
            }));
        }
    }
    Ok(Err(NewtonFailure {
        shrink: CONTROL.failure_shrink,
    }))
}

/// Take one accepted Radau IIA step from (t, y), trying `h` first, with norms weighted over the
/// state's `blocks` ([`Tolerances::weights`]; `None`: each component on its own).
///
/// `rhs(t, y)` returns f; an error of kind [`StepError::Inverted`] or [`StepError::NonFinite`]
/// (or a non-finite value) at a trial state rejects the attempt and halves h, other errors
/// propagate. At (t, y) itself every error propagates: no step size can repair it.
/// `jac(t, y)` returns an approximation of ∂f/∂y; it affects Newton's convergence only.
///
/// # Errors
/// [`StepError::Param`] for a non-finite t, h ≤ 0 or not finite, rtol or atol ≤ 0;
/// [`StepError::NonFinite`] for a non-finite y, f(t, y) or Jacobian;
/// [`StepError::StepSizeUnderflow`] when h < `tol.h_min()` or after 50 failed attempts.
// The state (t, y), the trial h, the tolerances, the norm's blocks, the step memory and the two
// callbacks: what one Radau IIA step reads; a struct of them would only rename the arguments.
#[allow(clippy::too_many_arguments)]
pub fn step<const N: usize>(
    t: f64,
    y: &SVector<f64, N>,
    h: f64,
    tol: Tolerances,
    blocks: Option<&[Range<usize>]>,
    mem: &mut RadauMemory<N>,
    rhs: impl FnMut(f64, &SVector<f64, N>) -> Result<SVector<f64, N>, StepError>,
    mut jac: impl FnMut(f64, &SVector<f64, N>) -> Result<SMatrix<f64, N, N>, StepError>,
) -> Result<RadauStep<N>, StepError>
where
    Const<N>: DimMin<Const<N>, Output = Const<N>>,
{
    finite("t", t)?;
    positive("h", h)?;
    positive("rtol", tol.rtol())?;
    positive("atol", tol.atol())?;
    finite("h_min", tol.h_min())?;
    if y.iter().any(|v| !v.is_finite()) {
        return Err(StepError::NonFinite {
            what: "state at the step start",
            t,
        });
    }
    // Taken out of the memory: it is written back only with an accepted step, so any error
    // leaves it cold. A deserialised memory is data, hence the guard on the old h.
    let last = mem.last.take().filter(|l| l.t_end == t && l.y_end == *y && l.h > 0.0);
    let stored_jacobian = mem.jacobian.take();
    let mut work = Work::default();
    let mut rhs = Rhs { f: rhs };
    let f0 = rhs.eval(&mut work, t, y)?;
    if f0.iter().any(|v| !v.is_finite()) {
        return Err(StepError::NonFinite {
            what: "right-hand side at the step start",
            t,
        });
    }
    let mut jacobian_in_use = match stored_jacobian {
        Some(r) if r.reusable => r,
        _ => jacobian(&mut jac, &mut work, t, y)?,
    };
    let scale0 = tol.weights(y, y, blocks);
    // Newton must be more accurate than the error test (Hairer & Wanner, §IV.8, "Stopping
    // criterion"), but not beyond what round-off in a scaled norm allows.
    let fnewt = (10.0 * f64::EPSILON / tol.rtol()).max(0.03_f64.min(tol.rtol().sqrt()));
    let mut eta = last.as_ref().map_or(1.0, |l| l.eta);
    let mut h = h;
    let mut rejected = 0;
    let mut err = f64::NAN;
    loop {
        if h < tol.h_min() || rejected >= CONTROL.max_rejections {
            return Err(StepError::StepSizeUnderflow { dt: h, t, error: err });
        }
        let fresh = jacobian_in_use.t == t && jacobian_in_use.y == *y;
        let factors = Factors::new(&jacobian_in_use.j, h, &mut work);
        let z0 = match &last {
            // Y_i ≈ u_old(t + c_i h) on the previous step's collocation polynomial, as far as
            // the controller itself would extrapolate: after a step clipped by the caller (to
            // an output time, say) the polynomial's round-off grows like (h/h_old)³.
            Some(l) if h <= CONTROL.accept.1 * l.h => {
                let end = l.dense.increment(1.0);
                let column = |c: f64| l.dense.increment(1.0 + c * h / l.h) - end;
                SMatrix::<f64, N, 3>::from_columns(&[column(C1), column(C2), column(1.0)])
            }
            _ => SMatrix::zeros(),
        };
        let eta0 = eta.max(f64::EPSILON).powf(0.8);
        let sys = Collocation {
            t,
            y,
            h,
            factors: &factors,
            scale: &scale0,
            fnewt,
        };
        let stages = solve_stages(&sys, z0, eta0, &mut rhs, &mut work)?;
        let stages = match stages {
            Ok(s) => s,
            Err(NewtonFailure { shrink }) => {
                rejected += 1;
                if fresh {
                    h *= shrink;
                } else {
                    // A Jacobian from another point is the first suspect: refresh it, same h.
                    jacobian_in_use = jacobian(&mut jac, &mut work, t, y)?;
                }
                continue;
            }
        };
        eta = stages.eta;
        let y_new = y + stages.z.column(2);
        let ez = (stages.z * Vector3::new(E[0], E[1], E[2])) / h;
        let scale = tol.weights(y, &y_new, blocks);
        err = match factors.solve_real(&(f0 + ez)) {
            Some(e) => {
                let mut err_now = rms(&e, &scale);
                if err_now >= 1.0 && (last.is_none() || rejected > 0) {
                    // The filtered second estimate; if its evaluation fails the first stands.
                    if let Some(f1) = rhs.trial(&mut work, t, &(y + e))? {
                        err_now = factors.solve_real(&(f1 + ez)).map_or(err_now, |e2| rms(&e2, &scale));
                    }
                }
                err_now
            }
            None => f64::NAN,
        };
        // A NaN estimate is a failure, never an acceptance.
        if err.is_nan() {
            rejected += 1;
            h *= CONTROL.failure_shrink;
            continue;
        }
        let err_c = err.max(ERR_FLOOR);
        let iters = f64::from(stages.iters);
        let k_max = f64::from(NEWTON_MAX_ITERS);
        let safety = CONTROL.safety;
        let fac = safety.min(safety * (1.0 + 2.0 * k_max) / (iters + 2.0 * k_max));
        // quot = h/h_new, within [1/8, 5] (the accepted range, inverted).
        let (quot_min, quot_max) = (1.0 / CONTROL.accept.1, 1.0 / CONTROL.accept.0);
        let mut quot = (err_c.powf(0.25) / fac).clamp(quot_min, quot_max);
        if err > 1.0 {
            rejected += 1;
            h *= if last.is_none() {
                SHRINK_FIRST
            } else {
                (1.0 / quot).clamp(CONTROL.reject.0, CONTROL.reject.1)
            };
            continue;
        }
        if let Some(l) = &last {
            // Gustafsson's predictive controller (Hairer & Wanner, §IV.8).
            let gus = (l.h / h) * (err_c * err_c / l.err).powf(0.25) / safety;
            quot = quot.max(gus.clamp(quot_min, quot_max));
        }
        let mut h_next = h / quot;
        if let (true, Some(th)) = (stages.iters >= 3, stages.theta) {
            // Grow no further than where θ ∝ h² predicts THETA_TARGET (module docs, "Newton's
            // rate"); never shrink for it: this step converged.
            h_next = h_next.min(h * (THETA_TARGET / th).sqrt().max(1.0));
        }
        if rejected > 0 {
            h_next = h_next.min(h);
        }
        let dense = RadauDense { y0: *y, z: stages.z };
        // Keep J while Newton needs at most two iterations or contracts fast (RADAU5's θ rule
        // with SciPy's two-iteration refinement, which halves the Jacobian evaluations on
        // Van der Pol and Robertson for a few per cent more evaluations of f).
        jacobian_in_use.reusable = stages.iters <= 2 || stages.theta.is_none_or(|th| JACOBIAN_REUSE.keeps_rate(th));
        mem.jacobian = Some(jacobian_in_use);
        mem.last = Some(LastStep {
            t_end: t + h,
            y_end: y_new,
            h,
            err: err_c.max(ERR_OLD_FLOOR),
            eta,
            dense: dense.clone(),
        });
        return Ok(RadauStep {
            y: y_new,
            h,
            h_next,
            dense,
            rhs_evals: work.rhs,
            jac_evals: work.jac,
            lu_decomps: work.lu,
            newton_iters: work.newton,
            rejected,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s6() -> f64 {
        6.0_f64.sqrt()
    }

    /// The Butcher matrix from its closed form.
    fn butcher_a() -> Matrix3<f64> {
        let s = s6();
        Matrix3::new(
            (88.0 - 7.0 * s) / 360.0,
            (296.0 - 169.0 * s) / 1800.0,
            (-2.0 + 3.0 * s) / 225.0,
            (296.0 + 169.0 * s) / 1800.0,
            (88.0 + 7.0 * s) / 360.0,
            (-2.0 - 3.0 * s) / 225.0,
            (16.0 - s) / 36.0,
            (16.0 + s) / 36.0,
            1.0 / 9.0,
        )
    }

    /// Each literal is its closed form rounded once; the runtime closed form adds a few
    /// roundings of O(1) terms without cancellation, so 4 ε relative covers both.
    #[test]
    fn constants_match_closed_forms() {
        let s = s6();
        let c3 = 3.0_f64.cbrt();
        let pairs = [
            (C1, (4.0 - s) / 10.0),
            (C2, (4.0 + s) / 10.0),
            (GAMMA, 3.0 + c3 * c3 - c3),
            (ALPHA, 3.0 + 0.5 * (c3 - c3 * c3)),
            (BETA, 0.5 * (3.0_f64.powf(5.0 / 6.0) + 3.0_f64.powf(7.0 / 6.0))),
            (E[0], (-13.0 - 7.0 * s) / 3.0),
            (E[1], (-13.0 + 7.0 * s) / 3.0),
            (E[2], -1.0 / 3.0),
        ];
        for (literal, closed) in pairs {
            assert!(
                (literal - closed).abs() <= 4.0 * f64::EPSILON * closed.abs(),
                "{literal} vs {closed}"
            );
        }
    }

    /// Radau IIA of order 5 satisfies the collocation conditions C(3),
    /// Σⱼ aᵢⱼ cⱼ^{k−1} = cᵢ^k/k (k ≤ 3), and the quadrature conditions B(5),
    /// Σᵢ bᵢ cᵢ^{k−1} = 1/k (k ≤ 5), with b the last row of A. Terms are O(1), so the sums
    /// are exact to a few ε.
    #[test]
    fn tableau_satisfies_order_conditions() {
        let a = butcher_a();
        let c = [C1, C2, 1.0];
        for i in 0..3 {
            for k in 1..=3 {
                let lhs: f64 = (0..3).map(|j| a[(i, j)] * c[j].powi(k - 1)).sum();
                assert!((lhs - c[i].powi(k) / f64::from(k)).abs() < 1e-15, "C({k}) row {i}");
            }
        }
        for k in 1..=5 {
            let lhs: f64 = (0..3).map(|i| a[(2, i)] * c[i].powi(k - 1)).sum();
            assert!((lhs - 1.0 / f64::from(k)).abs() < 1e-15, "B({k})");
        }
    }

    /// T⁻¹A⁻¹T = diag(γ, [[α, β], [−β, α]]) and T·T⁻¹ = I. The entries of A⁻¹ are ≤ 6 and those
    /// of T, T⁻¹ ≤ 4.2, so each triple product sums 27 terms of size ≤ 100 with relative
    /// rounding ε: 27·100·ε ≈ 6e-13 bounds the error; the inverse of A adds κ(A)·ε ≈ 1e-14.
    #[test]
    fn transformation_diagonalises_a_inverse() {
        let a_inv = butcher_a().try_inverse().unwrap();
        let t = matrix3(&T);
        let t_inv = matrix3(&T_INV);
        let lambda = Matrix3::new(GAMMA, 0.0, 0.0, 0.0, ALPHA, BETA, 0.0, -BETA, ALPHA);
        let d = t_inv * a_inv * t - lambda;
        assert!(d.amax() < 6e-13, "{d}");
        let id = t * t_inv - Matrix3::identity();
        assert!(id.amax() < 27.0 * 20.0 * f64::EPSILON, "{id}");
    }

    /// The Lagrange basis reproduces the nodes exactly where the dense output promises it.
    #[test]
    fn lagrange_basis_is_exact_at_the_step_ends() {
        assert_eq!(lagrange(0.0), Vector3::zeros());
        assert_eq!(lagrange(1.0), Vector3::new(0.0, 0.0, 1.0));
        // At the interior nodes it is the unit vectors up to rounding of O(1) products.
        for (i, c) in [C1, C2].iter().enumerate() {
            let l = lagrange(*c);
            for k in 0..3 {
                let expected = if k == i { 1.0 } else { 0.0 };
                assert!((l[k] - expected).abs() < 1e-14);
            }
        }
    }

    /// Fixed steps of the collocation solve with a fresh exact Jacobian and Newton converged to
    /// round-off (weights 1e-13 absolute): the global error at t = 1 must fall as h⁵.
    fn fixed_step_error<const N: usize>(
        y0: SVector<f64, N>,
        steps: u32,
        f: impl Fn(f64, &SVector<f64, N>) -> SVector<f64, N>,
        jac: impl Fn(f64, &SVector<f64, N>) -> SMatrix<f64, N, N>,
        exact: impl Fn(f64) -> SVector<f64, N>,
    ) -> f64
    where
        Const<N>: DimMin<Const<N>, Output = Const<N>>,
    {
        let h = 1.0 / f64::from(steps);
        let mut y = y0;
        let mut work = Work::default();
        let mut rhs = Rhs {
            f: |t: f64, y: &SVector<f64, N>| Ok(f(t, y)),
        };
        for n in 0..steps {
            let t = f64::from(n) * h;
            let factors = Factors::new(&jac(t, &y), h, &mut work);
            // Newton's early abort predicts from θ whether 7 iterations reach the tolerance,
            // which from Z = 0 to weights of 1e-12 they need not: tighten by 1e-2 per restart.
            let mut z = SMatrix::zeros();
            for weight in [1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12] {
                let scale = SVector::<f64, N>::repeat(weight);
                let sys = Collocation {
                    t,
                    y: &y,
                    h,
                    factors: &factors,
                    scale: &scale,
                    fnewt: 0.03,
                };
                z = solve_stages(&sys, z, 1.0, &mut rhs, &mut work)
                    .unwrap()
                    .unwrap_or_else(|_| panic!("Newton failed at step {n}"))
                    .z;
            }
            y += z.column(2);
        }
        (y - exact(1.0)).amax()
    }

    /// Least-squares slope of log(error) against log(h) over halvings.
    fn observed_order(errors: &[f64]) -> f64 {
        let n = errors.len() as f64;
        let xs: Vec<f64> = (0..errors.len()).map(|k| -(k as f64) * 2.0_f64.ln()).collect();
        let ys: Vec<f64> = errors.iter().map(|e| e.ln()).collect();
        let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
        let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
        let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
        sxy / sxx
    }

    /// Linear y′ = A y, A = [[−1, 10], [−10, −1]]: y = e^{−t}(cos 10t, −sin 10t) from (1, 0).
    /// Steps 10…80 (h·ω from 1 to 1/8): errors from ~5e-4 down to ~1e-8, far above the
    /// Newton floor (0.03 × weights 1e-12 per step); the slope is 5 up to the O(h) drift of the error constant
    /// over the range, allowed ±0.3.
    #[test]
    fn observed_order_is_five_linear() {
        let a = SMatrix::<f64, 2, 2>::new(-1.0, 10.0, -10.0, -1.0);
        let errors: Vec<f64> = [10, 20, 40, 80]
            .iter()
            .map(|&n| {
                fixed_step_error(
                    SVector::<f64, 2>::new(1.0, 0.0),
                    n,
                    |_, y| a * y,
                    |_, _| a,
                    |t| SVector::<f64, 2>::new((10.0 * t).cos(), -(10.0 * t).sin()) * (-t).exp(),
                )
            })
            .collect();
        let p = observed_order(&errors);
        assert!((p - 5.0).abs() < 0.3, "order {p}, errors {errors:?}");
    }

    /// Nonlinear rotation y′ = 10 r (−y₂, y₁), r = |y|², from (1, 0): r stays 1, so
    /// y = (cos 10t, sin 10t), while the Jacobian depends on y.
    fn rotation(_t: f64, y: &SVector<f64, 2>) -> SVector<f64, 2> {
        SVector::<f64, 2>::new(-y[1], y[0]) * (10.0 * y.norm_squared())
    }

    fn rotation_jacobian(_t: f64, y: &SVector<f64, 2>) -> SMatrix<f64, 2, 2> {
        let r = y.norm_squared();
        SMatrix::<f64, 2, 2>::new(
            -20.0 * y[0] * y[1],
            -10.0 * r - 20.0 * y[1] * y[1],
            10.0 * r + 20.0 * y[0] * y[0],
            20.0 * y[0] * y[1],
        )
    }

    fn rotation_errors(jac: impl Fn(f64, &SVector<f64, 2>) -> SMatrix<f64, 2, 2>) -> Vec<f64> {
        [20, 40, 80, 160]
            .iter()
            .map(|&n| {
                fixed_step_error(SVector::<f64, 2>::new(1.0, 0.0), n, rotation, &jac, |t| {
                    SVector::<f64, 2>::new((10.0 * t).cos(), (10.0 * t).sin())
                })
            })
            .collect()
    }

    /// Steps 20…160 (h·ω from 1/2 to 1/16): errors from ~4e-4 to ~1e-8 against a Newton
    /// floor of 0.03·1e-12 per step; slope 5 ± 0.3 as in the linear case.
    #[test]
    fn observed_order_is_five_nonlinear() {
        let errors = rotation_errors(rotation_jacobian);
        let p = observed_order(&errors);
        assert!((p - 5.0).abs() < 0.3, "order {p}, errors {errors:?}");
    }

    /// The reason for Radau over Rosenbrock: the Jacobian only drives Newton, so with a
    /// deliberately wrong one (the rotation part 20 % too weak) the converged stages, hence
    /// the errors, are those of the exact-Jacobian run up to the Newton floor: each run's
    /// stages are within 0.03·1e-12 of the collocation solution per step, and the rotation
    /// neither damps nor amplifies, so the two errors differ by at most n·2·0.03·1e-12
    /// (≤ 1e-11 at n = 160, against errors ≥ 1e-8). The order stays 5.
    #[test]
    fn order_does_not_depend_on_the_jacobian() {
        let exact = rotation_errors(rotation_jacobian);
        let approximate = rotation_errors(|t, y| rotation_jacobian(t, y) * 0.8);
        for ((a, e), n) in approximate.iter().zip(&exact).zip([20.0, 40.0, 80.0, 160.0]) {
            assert!((a - e).abs() <= n * 2.0 * 0.03 * 1e-12, "{a:e} vs {e:e}");
        }
        let p = observed_order(&approximate);
        assert!((p - 5.0).abs() < 0.3, "order {p}, errors {approximate:?}");
    }
}

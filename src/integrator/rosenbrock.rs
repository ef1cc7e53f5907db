//! Shampine's L-stable Rosenbrock(-W) pair of order 2(3) (the MATLAB `ode23s` formulas,
//! Shampine & Reichelt 1997), on a fixed-size state with a caller-supplied Jacobian.
//!
//! # Physics
//! None of its own: a generic solver of y′ = f(t, y). [`super::stokesian`] applies it to the
//! inertialess shape equation (paper eq. 18 with Θ → 0) and the barycentre equation (eq. 17).
//!
//! # Scheme
//! d = 1/(2 + √2), e₃₂ = 6 + √2, W = 1 − h d J:
//! k₁ = W⁻¹F₀, F₁ = f(t + h/2, y + h k₁/2), k₂ = W⁻¹(F₁ − k₁) + k₁, y₁ = y + h k₂,
//! F₂ = f(t + h, y₁), k₃ = W⁻¹[F₂ − e₃₂(k₂ − F₁) − 2(k₁ − F₀)], err = h(k₁ − 2k₂ + k₃)/6.
//! The second-order solution keeps its order for an approximate J (a W-method), which is what
//! lets the callers freeze slowly varying, non-stiff parts of the Jacobian.
//!
//! F₂ = f(y₁) is the F₀ of the next step (first same as last): the caller passes F₀ and J in,
//! and gets F₂ back with the caller's payload of that evaluation, so an accepted step costs two
//! new evaluations of f.
//!
//! A caller whose equation has a first integral I(y) the exact flow keeps may hand an
//! [`Invariant`]: y₁ is then projected onto I(y₁) = I(y) before F₂ is evaluated, the error
//! estimate's component across the level set (what the projection removes) is dropped, and an
//! attempt whose drift before the projection exceeds the invariant's bound is rejected like one
//! whose error does. The invariant also says in which variables the error is measured (a
//! moving frame's state is measured in the fixed frame, so the weights are the same as without
//! it). The projection moves y₁ by the drift, which is O(h³) for the order-2
//! solution, so the local error stays O(h³) and the order 2 (Hairer, Lubich & Wanner,
//! *Geometric Numerical Integration*, §IV.4, standard projection).
//!
//! Hand-written rather than taken from an ODE crate because the callers need per-step control
//! (one accepted step per call with its work counts, per-particle memory, static sizes).

use super::control::{ErrorOrder, StepControl, Tolerances};
use crate::error::{StepError, positive};
use nalgebra::{Const, DimMin, LU, SMatrix, SVector};
use std::ops::Range;

const D: f64 = 0.292_893_218_813_452_5; // 1/(2+√2)
const E32: f64 = 7.414_213_562_373_095; // 6+√2

/// The step controller (err ∝ h³): h·clamp(0.8 err^{−1/3}, 0.2, 5) after an accepted step,
/// h·clamp(0.8 err^{−1/3}, 0.1, 0.5) after a rejected one, h/4 after a failed attempt, and 60
/// rejected attempts (each at least halves h: 18 decades).
pub const CONTROL: StepControl = StepControl {
    safety: 0.8,
    accept: (0.2, 5.0),
    reject: (0.1, 0.5),
    failure_shrink: 0.25,
    max_rejections: 60,
};

/// The Jacobian as a step needs it: W = 1 − γh J factorised once per attempt. A dense J is one
/// LU; a caller whose J has structure (blocks, a Kronecker factor) factorises that instead.
pub trait Jacobian<const N: usize> {
    /// The factorisation of W.
    type Factor: Factor<N>;
    /// Factorise W = 1 − `gamma_h` J.
    fn factor(&self, gamma_h: f64) -> Self::Factor;
}

/// A factorised W = 1 − γh J.
pub trait Factor<const N: usize> {
    /// W⁻¹ b, or `None` where W is singular.
    fn solve(&self, b: &SVector<f64, N>) -> Option<SVector<f64, N>>;
}

impl<const N: usize> Jacobian<N> for SMatrix<f64, N, N>
where
    Const<N>: DimMin<Const<N>, Output = Const<N>>,
{
    type Factor = LU<f64, Const<N>, Const<N>>;

    fn factor(&self, gamma_h: f64) -> Self::Factor {
        (SMatrix::<f64, N, N>::identity() - self * gamma_h).lu()
    }
}

impl<const N: usize> Factor<N> for LU<f64, Const<N>, Const<N>>
where
    Const<N>: DimMin<Const<N>, Output = Const<N>>,
{
    fn solve(&self, b: &SVector<f64, N>) -> Option<SVector<f64, N>> {
        LU::solve(self, b)
    }
}

/// A first integral of y′ = f the step holds by projection (module docs).
pub trait Invariant<const N: usize> {
    /// Move `y` back onto the level set of the step's start; returns the drift removed, relative
    /// to the invariant's value (a number to compare with [`Invariant::allowed_drift`]).
    fn project(&self, y: &mut SVector<f64, N>) -> f64;
    /// The error estimate `err` at `y` with its component across the level set removed.
    fn along(&self, y: &SVector<f64, N>, err: &SVector<f64, N>) -> SVector<f64, N>;
    /// The largest relative drift a step may remove by projection.
    fn allowed_drift(&self) -> f64;
    /// A state or error vector `v` at τ into the step as the error test measures it (a
    /// caller whose state is a moving frame's measures in the fixed one).
    fn measured(&self, tau: f64, v: &SVector<f64, N>) -> SVector<f64, N>;
}

/// How an attempt is judged: the tolerances, the state's blocks the error norm measures as
/// wholes ([`Tolerances::scaled_error`]), and the invariant the step holds, if any.
#[derive(Clone, Copy)]
pub struct ErrorTest<'a, const N: usize> {
    /// Tolerances.
    pub tol: Tolerances,
    /// Blocks measured as wholes (`None`: componentwise).
    pub blocks: Option<&'a [Range<usize>]>,
    /// The first integral held by projection.
    pub invariant: Option<&'a dyn Invariant<N>>,
}

/// Outcome of one accepted adaptive step.
pub struct Accepted<const N: usize, P> {
    /// New state.
    pub y: SVector<f64, N>,
    /// Step taken.
    pub h: f64,
    /// Proposed next step.
    pub h_next: f64,
    /// f(t + h, y) at the new state (the next step's F₀).
    pub f_new: SVector<f64, N>,
    /// The caller's payload of that evaluation.
    pub payload: P,
    /// Rejected attempts.
    pub rejected: u32,
}

/// Take one accepted step from (t, y) with f(t, y) = `f0` and Jacobian `j`, trying `h` first,
/// judged by `test` ([`ErrorTest`]).
///
/// `rhs(t, y)` returns f and a payload, or an error; an `Inverted`/`NonFinite` error (e.g. an
/// inverted trial state) rejects the attempt and quarters h, any other error is returned.
pub fn step<const N: usize, P>(
    t: f64,
    y: &SVector<f64, N>,
    f0: &SVector<f64, N>,
    j: &impl Jacobian<N>,
    h: f64,
    test: ErrorTest<'_, N>,
    mut rhs: impl FnMut(f64, &SVector<f64, N>) -> Result<(SVector<f64, N>, P), StepError>,
) -> Result<Accepted<N, P>, StepError> {
    let ErrorTest { tol, blocks, invariant } = test;
    let mut h = positive("h", h)?;
    for rejected in 0..=CONTROL.max_rejections {
        if h < tol.h_min() {
            break;
        }
        let attempt = (|| {
            let w = j.factor(h * D);
            let solve = |b: SVector<f64, N>| {
                w.solve(&b).ok_or(StepError::NonFinite {
                    what: "Rosenbrock matrix",
                    t,
                })
            };
            let k1 = solve(*f0)?;
            let (f1, _) = rhs(t + 0.5 * h, &(y + k1 * (0.5 * h)))?;
            let k2 = solve(f1 - k1)? + k1;
            let mut y1 = y + k2 * h;
            let drift = invariant.map_or(0.0, |i| i.project(&mut y1) / i.allowed_drift());
            let (f2, payload) = rhs(t + h, &y1)?;
            let k3 = solve(f2 - (k2 - f1) * E32 - (k1 - f0) * 2.0)?;
            let err = (k1 - k2 * 2.0 + k3) * (h / 6.0);
            let err = match invariant {
                Some(i) => tol.scaled_error(
                    &i.measured(h, &i.along(&y1, &err)),
                    &i.measured(0.0, y),
                    &i.measured(h, &y1),
                    blocks,
                ),
                None => tol.scaled_error(&err, y, &y1, blocks),
            }
            .max(drift);
            Ok::<_, StepError>((y1, f2, payload, err))
        })();
        match attempt {
            Ok((y1, f_new, payload, err)) if err <= 1.0 => {
                return Ok(Accepted {
                    y: y1,
                    h,
                    h_next: h * CONTROL.grow(ErrorOrder::Three, err),
                    f_new,
                    payload,
                    rejected,
                });
            }
            Ok((_, _, _, err)) => {
                h *= CONTROL.shrink(ErrorOrder::Three, err);
            }
            Err(StepError::Inverted { .. }) | Err(StepError::NonFinite { .. }) => {
                h *= CONTROL.failure_shrink;
            }
            Err(e) => return Err(e),
        }
    }
    Err(StepError::StepSizeUnderflow {
        dt: h,
        t,
        error: f64::NAN,
    })
}

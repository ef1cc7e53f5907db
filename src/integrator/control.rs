//! Step-size and Jacobian control shared by the adaptive schemes: the tolerances and the
//! smallest step ([`Tolerances`]), the step controller's limits and its rejection cap
//! ([`StepControl`]), and when a Jacobian is kept ([`JacobianReuse`]).
//!
//! # Physics
//! None: these settings decide how finely the model's equations are resolved, never what they
//! say.
//!
//! # The controllers
//! [`super::rosenbrock`] and [`super::imex_adaptive`] use the elementary controller
//! ```math
//! h_\text{new} = h \cdot \operatorname{clamp}\!\left(s\,\mathrm{err}^{-1/q},\ \phi_{\min},\ \phi_{\max}\right)
//! ```
//! with err the scaled local error estimate (accepted for err ≤ 1), s the safety factor and q
//! the order in h of that estimate ([`ErrorOrder`]): the accepted step grows within
//! [`StepControl::accept`], a rejected one shrinks within [`StepControl::reject`], and a failed
//! attempt (Newton, an inverted or non-finite trial state) shrinks by
//! [`StepControl::failure_shrink`]. [`super::radau5`] applies Hairer's controller with
//! Gustafsson's predictive step and a safety factor reduced for slow Newton (see its module
//! docs) within the same kind of limits. Each scheme's limits are its published or
//! measured values, given once in its module as a `StepControl` constant; the arithmetic of
//! each formula is kept exactly as the schemes always computed it, so step sequences (and
//! every dataset) are bitwise those of the separate controllers this module replaces.

use crate::error::{ParamError, positive};
use nalgebra::SVector;
use serde::{Deserialize, Serialize};
use std::ops::Range;

/// Error-control settings of an adaptive integrator (validated: rtol, atol finite and > 0,
/// 0 < h_min finite).
///
/// # A position's scale
/// A relative tolerance measures a quantity against its own size, and a position has none: |x|
/// is its distance from wherever the mesh's origin happens to be. Measured against
/// max(|x₀|, |x₁|), a particle's position was held to 10–50 µm per step in the airway (10–50 mm
/// from the origin) and would be held to 100–300 µm in a CT geometry placed 0.1–0.3 m out, the
/// same particle in the same flow. A state's position block (three components, see
/// [`Tolerances::with_position`]) is therefore measured against a length ℓ that does not
/// depend on the origin or the axes:
/// ```math
/// \frac{\lVert e_x\rVert}{\mathrm{atol} + \mathrm{rtol}\,\ell}
/// ```
/// (componentwise: each |e_{x,i}| against the same weight). The inertialess integrator
/// ([`super::Stokesian`]) takes ℓ = the particle's largest rest semi-axis r₁: its surface is
/// held to rtol·r₁ through F (|δF| ≲ rtol |F|), so its centre is held to the same length, and
/// the contact event measures gaps in the same particle lengths. A domain length (an airway's
/// diameter, a mesh's extent) would leave the test as loose as it was at the airway's origin
/// distance, but it is a property of each scene, which the scheme does not see and a scene file
/// may not state. Where atol ≫ rtol·r₁ (the bifurcation studies: atol 10⁻⁵ m against
/// rtol·r₁ ≤ 10⁻⁷ m) the position is held to atol, the studies' stated "a particle radius".
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    rtol: f64,
    atol: f64,
    h_min: f64,
    /// The first component of the state's position block and the length ℓ it is measured
    /// against (`None`: every component against its own size).
    position: Option<(usize, f64)>,
}

impl Tolerances {
    /// Relative and absolute tolerances and the smallest step before giving up with
    /// [`crate::error::StepError::StepSizeUnderflow`].
    pub fn new(rtol: f64, atol: f64, h_min: f64) -> Result<Self, ParamError> {
        Ok(Self {
            rtol: positive("rtol", rtol)?,
            atol: positive("atol", atol)?,
            h_min: positive("h_min", h_min)?,
            position: None,
        })
    }

    /// The same tolerances with the three components `start..start + 3` of the state a position,
    /// measured against atol + rtol·`length` instead of its own size (a finite `length` > 0;
    /// see the type's docs).
    pub fn with_position(self, start: usize, length: f64) -> Result<Self, ParamError> {
        Ok(Self {
            position: Some((start, positive("position length", length)?)),
            ..self
        })
    }

    /// The position block and its length, if set ([`Tolerances::with_position`]).
    pub fn position(&self) -> Option<(std::ops::Range<usize>, f64)> {
        self.position.map(|(start, length)| (start..start + 3, length))
    }

    /// The size a component or block is measured against: ℓ for the position (a component of
    /// it, or the block itself), else the larger of its sizes at the two states.
    fn size(&self, block: &Range<usize>, a: f64, b: f64) -> f64 {
        match self.position {
            Some((start, length)) if block.start >= start && block.end <= start + 3 => length,
            _ => a.max(b),
        }
    }

    /// rtol = atol = `tol`, h_min = 1e-12.
    pub fn uniform(tol: f64) -> Result<Self, ParamError> {
        Self::new(tol, tol, 1e-12)
    }

    /// Relative tolerance.
    pub fn rtol(&self) -> f64 {
        self.rtol
    }

    /// Absolute tolerance.
    pub fn atol(&self) -> f64 {
        self.atol
    }

    /// Smallest step.
    pub fn h_min(&self) -> f64 {
        self.h_min
    }

    /// The error estimate `err` of a step from `y0` to `y1` measured block by block: the largest
    /// over the `blocks` (ranges of components, each a vector or tensor of the state; `None`:
    /// each component on its own) of
    /// ```math
    /// \frac{\lVert e_b\rVert_2}{\mathrm{atol} + \mathrm{rtol}\,\max(\lVert y_{0,b}\rVert_2,\ \lVert y_{1,b}\rVert_2)},
    /// ```
    /// accepted for ≤ 1. Each component on its own gives the componentwise mixed norm
    /// max_i |e_i|/(atol + rtol max(|y0_i|, |y1_i|)). The position block, if set, is measured
    /// against atol + rtol·ℓ instead (type docs). NaN anywhere gives +∞ (a rejection).
    /// Why blocks: [`ErrorNorm`].
    pub fn scaled_error<const N: usize>(
        &self,
        err: &SVector<f64, N>,
        y0: &SVector<f64, N>,
        y1: &SVector<f64, N>,
        blocks: Option<&[Range<usize>]>,
    ) -> f64 {
        let mut worst = 0.0_f64;
        let mut measure = |e: f64, size: f64| -> bool {
            let s = e / (self.atol + self.rtol * size);
            worst = worst.max(s);
            s.is_nan()
        };
        let nan = match blocks {
            None => (0..N).any(|i| measure(err[i].abs(), self.size(&(i..i + 1), y0[i].abs(), y1[i].abs()))),
            Some(blocks) => blocks.iter().any(|b| {
                let norm = |v: &SVector<f64, N>| v.rows_range(b.clone()).norm();
                measure(norm(err), self.size(b, norm(y0), norm(y1)))
            }),
        };
        if nan { f64::INFINITY } else { worst }
    }

    /// The weights of a weighted norm, atol + rtol max(|y0_b|, |y1_b|) for every component of
    /// each block b (`None`: each component its own block; `y1` = `y0` for one state's), and
    /// atol + rtol·ℓ for the position's components if set (type docs).
    /// A root-mean-square norm with these weights measures each block by its Euclidean norm.
    pub fn weights<const N: usize>(
        &self,
        y0: &SVector<f64, N>,
        y1: &SVector<f64, N>,
        blocks: Option<&[Range<usize>]>,
    ) -> SVector<f64, N> {
        match blocks {
            None => SVector::<f64, N>::from_fn(|i, _| {
                self.atol + self.rtol * self.size(&(i..i + 1), y0[i].abs(), y1[i].abs())
            }),
            Some(blocks) => {
                let mut w = SVector::<f64, N>::repeat(self.atol);
                for b in blocks {
                    let norm = |v: &SVector<f64, N>| v.rows_range(b.clone()).norm();
                    let s = self.atol + self.rtol * self.size(b, norm(y0), norm(y1));
                    w.rows_range_mut(b.clone()).fill(s);
                }
                w
            }
        }
    }
}

/// How a step's local error is measured against the tolerances: each component on its own, or
/// each vector and tensor of the state as a whole.
///
/// The componentwise test holds every entry of F to atol + rtol |F_ij|. The entries of a
/// rotating F pass through zero, so there the test holds them to atol alone, whatever the size
/// of F, and the step sequence depends on how the lab axes happen to lie against the particle.
/// Measured as wholes (Frobenius norm of δF, Euclidean norms of δx and δv) the test does not
/// depend on the lab frame; with the position measured against a length rather than |x|
/// ([`Tolerances`]) it does not depend on the origin either, under either norm. On the airway bifurcation at the studies' rtol 10⁻² it removes
/// nearly all rejected steps (84 of 125 per particle come from the near-zero entries), but it
/// is also a looser test there; at equal fates against a tight reference (rtol 10⁻³ tensor
/// against 10⁻² componentwise) it costs 1.05–1.2× less, at 3·10⁻³ 1.4–1.7× less for up to 2 more
/// fates changed in 2 000 (`examples/error_norm.rs`, `paper-figures/work-precision/NOTES.md`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ErrorNorm {
    /// max_i |e_i|/(atol + rtol max(|y0_i|, |y1_i|)) (the default, and what every dataset
    /// before this option used).
    #[default]
    Componentwise,
    /// Each vector and tensor of the state by its Euclidean (Frobenius) norm.
    Tensor,
}

/// Order q of a local error estimate, err ∝ h^q: the elementary controller's exponent is 1/q.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorOrder {
    /// err ∝ h² (a first-order scheme's estimate; exponent ½, evaluated as s/√err).
    Two,
    /// err ∝ h³ (a second-order scheme's estimate; exponent ⅓, evaluated as s·err^{−1/3}).
    Three,
}

/// Limits of a step controller: the factor h_new/h after an accepted step, after a rejected
/// one and after a failed attempt, and the number of rejected attempts allowed in one step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepControl {
    /// Safety factor s.
    pub safety: f64,
    /// Range of h_new/h after an accepted step (the upper end also for err = 0).
    pub accept: (f64, f64),
    /// Range of h_new/h after a rejection by the error test.
    pub reject: (f64, f64),
    /// h_new/h after a failed attempt (Newton, an inverted or non-finite trial state).
    pub failure_shrink: f64,
    /// Rejected attempts allowed in one step before
    /// [`crate::error::StepError::StepSizeUnderflow`].
    pub max_rejections: u32,
}

impl StepControl {
    /// s·err^{−1/q}, unclamped (err > 0).
    fn factor(&self, order: ErrorOrder, err: f64) -> f64 {
        match order {
            ErrorOrder::Two => self.safety / err.sqrt(),
            ErrorOrder::Three => self.safety * err.powf(-1.0 / 3.0),
        }
    }

    /// Elementary controller: h_new/h after an accepted step with scaled error `err` ≤ 1.
    pub fn grow(&self, order: ErrorOrder, err: f64) -> f64 {
        if err == 0.0 {
            self.accept.1
        } else {
            self.factor(order, err).clamp(self.accept.0, self.accept.1)
        }
    }

    /// Elementary controller: h_new/h after a rejected step with scaled error `err` > 1; a
    /// non-finite error counts as a failed attempt.
    pub fn shrink(&self, order: ErrorOrder, err: f64) -> f64 {
        if err.is_finite() {
            self.factor(order, err).clamp(self.reject.0, self.reject.1)
        } else {
            self.failure_shrink
        }
    }
}

/// When a Newton Jacobian is kept: while the iteration contracts at least by `contraction`
/// per iteration (|Δ_{k+1}| ≤ contraction·|Δ_k|, or a measured rate θ ≤ contraction).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JacobianReuse {
    /// Largest contraction factor per iteration with which the Jacobian is kept.
    pub contraction: f64,
}

impl JacobianReuse {
    /// Whether an iteration that took a norm from `old` to `new` keeps the Jacobian.
    pub fn keeps(&self, new: f64, old: f64) -> bool {
        new <= self.contraction * old
    }

    /// Whether a measured contraction rate `theta` keeps the Jacobian.
    pub fn keeps_rate(&self, theta: f64) -> bool {
        theta <= self.contraction
    }
}

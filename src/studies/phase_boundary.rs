//! TU/TR phase boundary in Ca for a given initial shape (paper §6.1.2–6.1.3, Figs 7, 8).
//!
//! # Method
//! Small Ca (stiff particle) tumbles and large Ca trembles. Starting from an initial bracket
//! the search widens it geometrically (halving the lower end while it trembles, doubling the
//! upper end while it tumbles, within [ca_min, ca_max]), then bisects until
//! ca_tr − ca_tu ≤ `tol`. The result is the bracket itself: ca_tu is the largest Ca found
//! tumbling and ca_tr the smallest found trembling, with the margins min(l_a − l_c) there.
//! The paper resolved ΔCa = 0.005 and Sanagavarapu et al. ΔCa = 0.05; the default here is
//! 0.001. Shapes are independent and run in parallel (rayon).

use super::StudyError;
use super::shear_regimes::{Classification, Regime, RegimeClassifier};
use super::shear_shape::ShearShape;
use crate::diagnostics::Validity;
use crate::integrator::TimeIntegrator;
use crate::material::{LawFactory, NeoHookeFactory};
use crate::particle::ShearScaling;

/// Bracket search settings.
#[derive(Debug, Clone, Copy)]
pub struct BoundarySearch<I, L = NeoHookeFactory> {
    /// Classifier used at every Ca.
    pub classifier: RegimeClassifier<I, L>,
    /// ρ* and λ_s/μ_s of the particles (Ca is replaced).
    pub base: ShearScaling,
    /// Initial bracket guess (lower, upper).
    pub initial: (f64, f64),
    /// Smallest Ca the widening may reach.
    pub ca_min: f64,
    /// Largest Ca the widening may reach.
    pub ca_max: f64,
    /// Target bracket width ΔCa.
    pub tol: f64,
}

/// A located phase boundary.
#[derive(Debug, Clone, PartialEq)]
pub struct RegimeBoundary {
    /// Shape searched.
    pub shape: ShearShape,
    /// Largest Ca found tumbling.
    pub ca_tu: f64,
    /// Smallest Ca found trembling.
    pub ca_tr: f64,
    /// min(l_a − l_c) at ca_tu (> 0).
    pub margin_tu: f64,
    /// min(l_a − l_c) at ca_tr (< 0).
    pub margin_tr: f64,
    /// Classification runs used.
    pub evaluations: u32,
    /// Validity diagnostics of the two bracketing runs, combined (as measured).
    pub validity: Validity,
}

impl RegimeBoundary {
    /// Bracket midpoint, the boundary estimate (error ≤ half the bracket width).
    pub fn ca_critical(&self) -> f64 {
        0.5 * (self.ca_tu + self.ca_tr)
    }
}

impl<I: TimeIntegrator, L: LawFactory> BoundarySearch<I, L> {
    /// Search with bracket guess (0.1, 1), limits [1e-3, 20] and ΔCa ≤ `tol`.
    pub fn new(classifier: RegimeClassifier<I, L>, tol: f64) -> Self {
        Self {
            classifier,
            base: ShearScaling::new(1.0, 1.0, 1e3).expect("valid constants"),
            initial: (0.1, 1.0),
            ca_min: 1e-3,
            ca_max: 20.0,
            tol,
        }
    }

    fn classify(&self, shape: &ShearShape, ca: f64) -> Result<Classification, StudyError> {
        self.classifier.classify_ca(shape, ca, &self.base)
    }

    /// Locate the boundary for one shape.
    pub fn find(&self, shape: &ShearShape) -> Result<RegimeBoundary, StudyError> {
        let mut evaluations = 0;
        let mut eval = |ca: f64| {
            evaluations += 1;
            self.classify(shape, ca).map(|c| (ca, c))
        };
        let (mut lo, mut hi) = (eval(self.initial.0)?, eval(self.initial.1)?);
        while lo.1.regime == Regime::Trembling {
            if lo.0 <= self.ca_min {
                return Err(self.no_bracket(lo.1.regime, hi.1.regime, lo.0, hi.0));
            }
            let ca = (0.5 * lo.0).max(self.ca_min);
            hi = lo;
            lo = eval(ca)?;
        }
        while hi.1.regime == Regime::Tumbling {
            if hi.0 >= self.ca_max {
                return Err(self.no_bracket(lo.1.regime, hi.1.regime, lo.0, hi.0));
            }
            let ca = (2.0 * hi.0).min(self.ca_max);
            lo = hi;
            hi = eval(ca)?;
        }
        while hi.0 - lo.0 > self.tol {
            let mid_ca = 0.5 * (lo.0 + hi.0);
            // A tolerance below the float spacing of Ca (or ≤ 0, or NaN in the caller's
            // hands) would never be met: stop when the bracket cannot shrink any more.
            if mid_ca <= lo.0 || mid_ca >= hi.0 {
                break;
            }
            let mid = eval(mid_ca)?;
            match mid.1.regime {
                Regime::Tumbling => lo = mid,
                Regime::Trembling => hi = mid,
            }
        }
        Ok(RegimeBoundary {
            shape: *shape,
            ca_tu: lo.0,
            ca_tr: hi.0,
            margin_tu: lo.1.margin,
            margin_tr: hi.1.margin,
            evaluations,
            validity: lo.1.validity.combine(hi.1.validity),
        })
    }

    /// Locate the boundaries of many shapes in parallel (order preserved).
    pub fn find_all(&self, shapes: &[ShearShape]) -> Vec<Result<RegimeBoundary, StudyError>>
    where
        I: Sync,
    {
        crate::parallel::map(shapes, |s| self.find(s))
    }

    fn no_bracket(&self, at_min: Regime, at_max: Regime, lo: f64, hi: f64) -> StudyError {
        StudyError::NoBracket {
            ca_min: lo,
            ca_max: hi,
            regime_at_min: at_min,
            regime_at_max: at_max,
        }
    }
}

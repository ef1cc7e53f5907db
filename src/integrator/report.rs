//! What an integrator did for one particle beyond the driver's counts
//! ([`crate::driver::RunStats`]): the account an integrator keeps of its own choices, read from
//! its step memory ([`super::TimeIntegrator::report`]). Records, tables, the run's summary and
//! the validity diagnostics hold this report and name no integrator's own type.

use super::manifold::ManifoldReport;
use serde::{Deserialize, Serialize};

/// One particle's (or, combined, a run's) integrator accounts, one field per integrator that
/// keeps one; a field is `None` where that integrator did not step the particle.
///
/// Serialized as its one account, the slow manifold's (`null` where empty), so records,
/// checkpoints and validity JSON read and write as before this type: the fields holding it are
/// named `manifold` there.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct IntegratorReport {
    /// What the slow-manifold switch did ([`super::manifold`]): its steps on and off the
    /// manifold, its switches and the largest expansion ratio δ on it against the bound
    /// δ_max; `None` where the slow-manifold integrator did not step the particle (every other
    /// integrator, and [`super::choice::Auto`] where it chose the full model).
    pub manifold: Option<ManifoldReport>,
}

impl IntegratorReport {
    /// The report of a particle the slow-manifold integrator stepped.
    pub fn manifold(report: ManifoldReport) -> Self {
        Self { manifold: Some(report) }
    }

    /// Whether no integrator kept an account (what the serialized forms leave out).
    pub fn is_empty(&self) -> bool {
        self.manifold.is_none()
    }

    /// The reports of two runs as one (a population's total, the runs of a phase boundary):
    /// each integrator's accounts combined ([`ManifoldReport::combine`]), or the one there is.
    pub fn combine(self, other: Self) -> Self {
        Self {
            manifold: match (self.manifold, other.manifold) {
                (Some(a), Some(b)) => Some(a.combine(b)),
                (a, b) => a.or(b),
            },
        }
    }

    /// Names of the integrators' own bounds that an accepted step crossed, for the validity
    /// flags ([`crate::diagnostics::Validity::flags`]): `manifold_ratio` where a step on the
    /// slow manifold ran above δ_max ([`ManifoldReport::exceeded`]).
    pub fn flags(&self) -> impl Iterator<Item = &'static str> {
        self.manifold
            .filter(ManifoldReport::exceeded)
            .map(|_| "manifold_ratio")
            .into_iter()
    }

    /// The run summary's account of the integrators, with `steps` the run's accepted steps
    /// (empty where none kept one): [`ManifoldReport::summary`].
    pub fn summary(&self, steps: u64) -> String {
        self.manifold.map(|m| m.summary(steps)).unwrap_or_default()
    }
}

impl FromIterator<IntegratorReport> for IntegratorReport {
    /// The reports combined ([`IntegratorReport::combine`]); empty for none.
    fn from_iter<T: IntoIterator<Item = IntegratorReport>>(iter: T) -> Self {
        iter.into_iter().fold(Self::default(), Self::combine)
    }
}

//! What became of one particle.

use super::spec::ParticleSpec;
use crate::driver::RunStats;
use crate::ellipsoid::PrincipalFrame;
use crate::integrator::IntegratorReport;
use crate::particle::State;
use crate::tensor::Vec3;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// The terminal event of one particle.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Fate {
    /// It touched a [`crate::contact::PatchRule::Stick`] patch.
    Deposited {
        /// Patch index ([`crate::contact::Boundary::patch_name`]).
        patch: usize,
        /// Barycentre at contact.
        position: Vec3,
        /// Time of contact.
        time: f64,
    },
    /// It touched a [`crate::contact::PatchRule::Exit`] patch.
    Escaped {
        /// Patch index.
        patch: usize,
        /// Time of exit.
        time: f64,
    },
    /// It was still inside at the end time.
    Suspended,
    /// Drawing, building or advancing it failed; the run went on with the others.
    Failed {
        /// The error, as displayed.
        error: String,
    },
}

impl Fate {
    /// Short label for tables: `deposited`, `escaped`, `suspended` or `failed`.
    pub fn label(&self) -> &'static str {
        match self {
            Fate::Deposited { .. } => "deposited",
            Fate::Escaped { .. } => "escaped",
            Fate::Suspended => "suspended",
            Fate::Failed { .. } => "failed",
        }
    }

    /// The patch touched, if any.
    pub fn patch(&self) -> Option<usize> {
        match self {
            Fate::Deposited { patch, .. } | Fate::Escaped { patch, .. } => Some(*patch),
            Fate::Suspended | Fate::Failed { .. } => None,
        }
    }
}

/// One particle of a population: what it was and what became of it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParticleRecord<L> {
    /// Particle index k (its generator is stream k of the run seed).
    pub index: u64,
    /// Its specification; `None` only when drawing it failed.
    pub spec: Option<ParticleSpec<L>>,
    /// Its terminal event.
    pub fate: Fate,
    /// The last state: at contact, exit or the end time, or the last accepted one before a
    /// failure; `None` only when drawing it failed.
    pub end: Option<State>,
    /// Work of its run.
    pub stats: RunStats,
    /// What the integrator did in its run beyond the step counts
    /// ([`crate::integrator::TimeIntegrator::report`]): the slow-manifold switch's account
    /// where the slow-manifold integrator stepped it (`slow_manifold`, or `auto`'s and the
    /// studies' choice for a stiff elastic particle). In the JSON under its earlier name
    /// `manifold`, absent where empty (a record without it reads as before).
    #[serde(rename = "manifold", default, skip_serializing_if = "IntegratorReport::is_empty")]
    pub integrator: IntegratorReport,
    /// Its states at the start, at the plan's output times and at its event, when the case
    /// keeps them ([`super::Case::with_samples`]); empty otherwise. Stored packed
    /// ([`super::packed`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty", with = "super::packed")]
    pub samples: Vec<State>,
    /// What the case's observer kept of the run ([`super::Case::with_observer`]); null
    /// without an observer, or when the particle could not be drawn, built or planned.
    #[serde(default, skip_serializing_if = "serde_json::Value::is_null")]
    pub observed: serde_json::Value,
}

/// A record's observer summary could not be read as the type asked for.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("particle {index}: its record holds no {summary} summary ({reason})")]
pub struct SummaryError {
    /// Particle index.
    pub index: u64,
    /// The summary's type as asked for.
    pub summary: &'static str,
    /// Why: none kept (a run without the observer), or one of another shape.
    pub reason: String,
}

impl<L> ParticleRecord<L> {
    /// What the case's observer kept of this particle's run ([`Self::observed`]), read as `S`,
    /// the type its watch summarised into ([`super::Watch::finish`]).
    ///
    /// # Errors
    /// [`SummaryError`] naming the particle: the record holds no summary (a run without the
    /// observer, or a particle that could not be drawn) or one of another shape.
    pub fn summary<S: DeserializeOwned>(&self) -> Result<S, SummaryError> {
        let error = |reason: String| SummaryError {
            index: self.index,
            summary: std::any::type_name::<S>(),
            reason,
        };
        if self.observed.is_null() {
            return Err(error("none kept".into()));
        }
        S::deserialize(&self.observed).map_err(|e| error(e.to_string()))
    }

    /// The current ellipsoid at the end (semi-axes r₁ ≥ r₂ ≥ r₃ and axes of F̄ = F·S; its
    /// tensor V = √(F̄F̄ᵀ) = Qᵀ diag(r) Q is what ParaView's tensor glyphs draw).
    pub fn end_frame(&self) -> Option<PrincipalFrame> {
        let (spec, end) = (self.spec.as_ref()?, self.end.as_ref()?);
        Some(PrincipalFrame::from_total_distortion(
            &(end.f * spec.shape.shape_tensor()),
        ))
    }
}

/// How many particles met each fate.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct FateCounts {
    /// Deposited on a wall.
    pub deposited: u64,
    /// Escaped through an exit.
    pub escaped: u64,
    /// Still inside at the end time.
    pub suspended: u64,
    /// Failed.
    pub failed: u64,
}

impl FateCounts {
    /// Count the fates of `records`.
    pub fn of<'a, L: 'a>(records: impl IntoIterator<Item = &'a ParticleRecord<L>>) -> Self {
        let mut c = Self::default();
        for r in records {
            match r.fate {
                Fate::Deposited { .. } => c.deposited += 1,
                Fate::Escaped { .. } => c.escaped += 1,
                Fate::Suspended => c.suspended += 1,
                Fate::Failed { .. } => c.failed += 1,
            }
        }
        c
    }

    /// All particles counted.
    pub fn total(&self) -> u64 {
        self.deposited + self.escaped + self.suspended + self.failed
    }
}

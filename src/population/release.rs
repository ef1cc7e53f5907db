//! Drug release at a critical deformation as a non-terminal event: an [`Observer`] that
//! records, for each level of a [`ReleaseThresholds`], where and when a particle's release
//! criterion ([`crate::particle::release`]) first reaches it, and keeps tracking. The run is
//! the unobserved one (an observer only reads), so fates and deposits do not depend on it.
//!
//! # Locating a crossing
//! Each accepted step is sampled on its dense output ([`crate::integrator::Dense`]) at
//! [`SAMPLES`] equally spaced times after its start, and the criterion c is evaluated there.
//! When a sample reaches a level s not reached before, the crossing c(t) = s is solved
//! between that sample and the previous one (where c < s) by the driver's event location on
//! the same interpolant ([`crate::driver::locate_root`], to |c − s| ≤ 10⁻⁹ s). The located time
//! differs from the exact solution's by the interpolant's error in c over the slope of c:
//! δt ≈ δc/ċ, with δc = O(h⁴) for the cubic Hermite interpolant of exact end values (an F of
//! a known history: h⁴ε³/384 for F = diag(e^{εt}, e^{−εt}, 1), tested) and of the order of the
//! scheme's local error otherwise, the accuracy at which the driver locates wall contacts.
//!
//! An excursion above s that starts and ends between two samples is not seen; so that the
//! record is consistent with itself, the peak reported ([`Released::peak`]) is the largest c
//! over the same samples, and a level is crossed iff it is at most the peak.
//!
//! The driver shows a step before it locates a terminal event within it, so the last step
//! may run past the end of the run: a step is processed when the next one arrives, and the
//! last one only up to the end state's time ([`Watch::finish`]). A crossing at or before the
//! end (a deposit, the end time, the last state before a failure) is recorded.

use super::observe::{Observer, Watch};
use super::record::Fate;
use crate::driver::{AcceptedStep, locate_root};
use crate::hydro::DragModel;
use crate::integrator::Dense;
use crate::material::Response;
use crate::particle::release::{ReleaseThresholds, largest_stretch};
use crate::particle::{Particle, State};
use serde::{Deserialize, Serialize};

/// Samples per step on the dense output (the step's end included).
pub const SAMPLES: usize = 4;

/// The first crossing of one level.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Crossing {
    /// Time t (s, or the scene's time unit).
    pub t: f64,
    /// Barycentre x at t.
    pub x: [f64; 3],
    /// The criterion at t (the level to 10⁻⁹ relative).
    pub value: f64,
    /// The largest principal stretch λ₁ at t (equal to `value` for that criterion).
    pub stretch: f64,
}

/// The largest criterion value seen (over the samples).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Peak {
    /// Time of the peak.
    pub t: f64,
    /// The criterion there.
    pub value: f64,
}

/// What a run keeps: its peak and the first crossing of each level (`None`: never reached),
/// in the order of [`ReleaseThresholds::levels`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Released {
    /// Largest criterion over the run's samples.
    pub peak: Peak,
    /// First crossing per level.
    pub crossings: Vec<Option<Crossing>>,
}

/// Watches each particle's release criterion against `thresholds`.
#[derive(Debug, Clone, PartialEq)]
pub struct ReleaseObserver {
    thresholds: ReleaseThresholds,
}

impl ReleaseObserver {
    /// The observer of `thresholds`.
    pub fn new(thresholds: ReleaseThresholds) -> Self {
        Self { thresholds }
    }

    /// The criterion and its levels.
    pub fn thresholds(&self) -> &ReleaseThresholds {
        &self.thresholds
    }
}

impl<M: Response, D: DragModel, F: ?Sized, B: ?Sized> Observer<Particle<M, D>, F, B> for ReleaseObserver {
    fn fingerprint(&self) -> String {
        format!(
            "release: first crossing of {} at {:?}, {SAMPLES} samples per step, Illinois on the dense output",
            self.thresholds.criterion().label(),
            self.thresholds.levels()
        )
    }

    fn watch<'w>(
        &'w self,
        particle: &'w Particle<M, D>,
        _flow: &'w F,
        _boundary: &'w B,
        start: &State,
    ) -> Box<dyn Watch + 'w> {
        let value = self.thresholds.criterion().value(particle, &start.f);
        let mut watching = Watching {
            particle,
            thresholds: &self.thresholds,
            last: (start.t, value),
            peak: Peak { t: start.t, value },
            crossings: vec![None; self.thresholds.levels().len()],
            pending: None,
        };
        watching.record(start, value);
        Box::new(watching)
    }
}

struct Watching<'w, M, D> {
    particle: &'w Particle<M, D>,
    thresholds: &'w ReleaseThresholds,
    /// Time and criterion of the last sample.
    last: (f64, f64),
    peak: Peak,
    crossings: Vec<Option<Crossing>>,
    /// The last step shown, processed when the next arrives or the run ends.
    pending: Option<Dense>,
}

impl<M: Response, D: DragModel> Watching<'_, M, D> {
    fn value(&self, state: &State) -> f64 {
        self.thresholds.criterion().value(self.particle, &state.f)
    }

    /// Levels reached at `state` (the start only: every other sample brackets its crossings).
    fn record(&mut self, state: &State, value: f64) {
        for (k, &level) in self.thresholds.levels().iter().enumerate() {
            if self.crossings[k].is_none() && value >= level {
                self.crossings[k] = Some(self.crossing(state, value));
            }
        }
    }

    fn crossing(&self, state: &State, value: f64) -> Crossing {
        Crossing {
            t: state.t,
            x: state.x.into(),
            value,
            stretch: largest_stretch(&state.f),
        }
    }

    /// Samples of `dense` up to `t_stop`, their crossings located on it.
    fn process(&mut self, dense: &Dense, t_stop: f64) {
        let (t0, t1) = (dense.t_start(), dense.t_end().min(t_stop));
        if t1 <= t0 {
            return;
        }
        let thresholds = self.thresholds;
        for j in 1..=SAMPLES {
            let t = if j == SAMPLES {
                t1
            } else {
                t0 + (t1 - t0) * j as f64 / SAMPLES as f64
            };
            let state = dense.state_at(t);
            let value = self.value(&state);
            if value > self.peak.value {
                self.peak = Peak { t, value };
            }
            for (k, &level) in thresholds.levels().iter().enumerate() {
                if self.crossings[k].is_some() || value < level {
                    continue;
                }
                let gap = |s: &State| level - self.value(s);
                // A NaN on the interpolant has no crossing to locate: keep the sample.
                let at = locate_root(
                    &gap,
                    dense,
                    (self.last.0, level - self.last.1),
                    (t, level - value),
                    level,
                )
                .unwrap_or(state);
                let v = self.value(&at);
                self.crossings[k] = Some(self.crossing(&at, v));
            }
            self.last = (t, value);
        }
    }
}

impl<M: Response, D: DragModel> Watch for Watching<'_, M, D> {
    fn step(&mut self, step: &AcceptedStep) {
        if let Some(dense) = self.pending.replace(*step.dense()) {
            self.process(&dense, f64::INFINITY);
        }
    }

    fn finish(mut self: Box<Self>, _fate: &Fate, end: &State) -> serde_json::Value {
        if let Some(dense) = self.pending.take() {
            self.process(&dense, end.t);
        }
        serde_json::to_value(Released {
            peak: self.peak,
            crossings: self.crossings,
        })
        .expect("Released is plain data")
    }
}

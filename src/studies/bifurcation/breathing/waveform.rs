//! The inhalation's flow rate: the breath's period, its Womersley number and the waveform
//! U_in(t)/U with the injection times it implies (module docs of [`super`]: Physics,
//! Injection).

use crate::studies::bifurcation::setup::{NU, RADIUS};
use serde::Serialize;
use std::f64::consts::PI;

/// Period T of the breath at rest (s): 15 breaths a minute.
pub const PERIOD: f64 = 4.0;

/// Womersley number α = R√(ω/ν) of the parent at [`PERIOD`] ([module docs](super)).
pub fn womersley_number() -> f64 {
    RADIUS * (2.0 * PI / PERIOD / NU).sqrt()
}

/// How the inlet velocity changes over one inhalation, relative to the steady U.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Waveform {
    /// The first half of a sine of this period, with peak (π/2) U ([module docs](super)).
    Sine {
        /// Period T of the breath (s).
        period: f64,
    },
    /// The steady U for this long: the steady field with particles entering uniformly in
    /// time, which must give the steady study's fates (a check of the machinery).
    Constant {
        /// Duration of the inhalation (s).
        duration: f64,
    },
}

impl Waveform {
    /// The breath at rest: a sine of period [`PERIOD`].
    pub fn rest() -> Self {
        Waveform::Sine { period: PERIOD }
    }

    /// The inhalation's duration: T/2 for a sine.
    pub fn duration(self) -> f64 {
        match self {
            Waveform::Sine { period } => 0.5 * period,
            Waveform::Constant { duration } => duration,
        }
    }

    /// U_in(t)/U over the inhalation (0 outside it).
    pub fn scale(self, t: f64) -> f64 {
        if !(0.0..=self.duration()).contains(&t) {
            return 0.0;
        }
        match self {
            Waveform::Sine { period } => 0.5 * PI * (2.0 * PI * t / period).sin(),
            Waveform::Constant { .. } => 1.0,
        }
    }

    /// The injection time of a particle whose uniform draw is `u` ∈ [0, 1): the inverse of
    /// the distribution function of times at a rate ∝ U_in(t) ([module docs](super)).
    pub fn injection_time(self, u: f64) -> f64 {
        match self {
            Waveform::Sine { period } => (1.0 - 2.0 * u).clamp(-1.0, 1.0).acos() * period / (2.0 * PI),
            Waveform::Constant { duration } => u * duration,
        }
    }
}

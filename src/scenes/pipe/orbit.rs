//! Orbit periods of the material line l_a (paper Fig. 10 discussion).
//!
//! # Physics (Jeffery 1922)
//! A rigid spheroid of aspect ratio λ whose axis lies in the shear plane of a simple shear of
//! rate γ̇ rotates with period $T = 2\pi(\lambda + 1/\lambda)/\dot\gamma$; the axis passes the
//! gradient direction twice per period, so the direction cosine of l_a with the flow direction
//! e₁ crosses zero downwards once per period. In the pipe the particle samples the local shear
//! rate 4Ū|x_⊥|/R², which changes slowly as it settles.

use super::tracking::PipeSample;
use std::f64::consts::PI;

/// Jeffery's period 2π(λ + 1/λ)/γ̇ of a rigid spheroid with aspect ratio `aspect`.
pub fn jeffery_period(aspect: f64, shear_rate: f64) -> f64 {
    2.0 * PI * (aspect + 1.0 / aspect) / shear_rate
}

/// Times at which cos(l_a, e₁) crosses zero from above, linearly interpolated between samples.
pub fn downward_crossings(samples: &[PipeSample]) -> Vec<f64> {
    samples
        .windows(2)
        .filter_map(|w| {
            let (c0, c1) = (w[0].direction_cosines()[0], w[1].direction_cosines()[0]);
            (c0 > 0.0 && c1 <= 0.0).then(|| w[0].t + (w[1].t - w[0].t) * c0 / (c0 - c1))
        })
        .collect()
}

/// Orbit periods: differences of successive downward crossings.
pub fn orbit_periods(samples: &[PipeSample]) -> Vec<f64> {
    downward_crossings(samples).windows(2).map(|w| w[1] - w[0]).collect()
}

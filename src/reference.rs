//! Reference problems with exact solutions, shared by tests, benches and examples.

use std::f64::consts::{FRAC_PI_2, PI};

/// Jeffery's in-plane orbit of a rigid spheroid with aspect ratio r in simple shear
/// u = γ̇ y e_x (Jeffery 1922): the symmetry axis' angle φ from the gradient
/// axis y towards the flow, with φ(0) = 0, satisfies tan φ = r tan(γ̇ t r/(r² + 1)).
/// Returned unwrapped (continuous in t). Time is in units of 1/γ̇.
pub fn jeffery_phi(r: f64, t: f64) -> f64 {
    let s = t * r / (r * r + 1.0);
    let turns = ((s + FRAC_PI_2) / PI).floor();
    (r * (s - turns * PI).tan()).atan() + turns * PI
}

/// Time at which the orbit of [`jeffery_phi`] passes φ = π/2 (axis along the flow):
/// t₀ = (π/2)(r² + 1)/r. An orbit started with the axis along the flow is φ(t₀ + t).
pub fn jeffery_flow_aligned_time(r: f64) -> f64 {
    FRAC_PI_2 * (r * r + 1.0) / r
}

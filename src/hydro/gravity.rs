//! Gravity reduced by buoyancy (paper eqs. 13, 17).
//!
//! # Physics (paper eqs. 13, 17)
//! a_G = β_t g with β_t = (ρ_t − ρ_f)/ρ_t and ρ_t = ρ₀/J: the mass m = ρ₀ vol(B₀) is constant
//! while the displaced volume vol(B_t) = J vol(B₀) follows the deformation.

use crate::tensor::Vec3;

/// Mass-specific reduced gravity a_G = (1 − ρ_f J/ρ₀) g.
pub fn reduced_gravity(g: &Vec3, rho_solid: f64, rho_fluid: f64, det_f: f64) -> Vec3 {
    g * (1.0 - rho_fluid * det_f / rho_solid)
}

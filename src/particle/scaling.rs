//! Nondimensional groups of the shear-flow problems (paper eqs. 23, 24).
//!
//! # Physics (paper §6, eqs. 23, 24)
//! Units: lengths in d_eq, times in 1/γ̇, stresses in μ_f γ̇. Then μ_f = 1, γ̇ = 1, the
//! stress-free ellipsoid has R₁R₂R₃ = 1/8, μ_s = 1/Ca with Ca = μ_f γ̇/μ_s, and inertia enters
//! only through ρ* = ρ_s γ̇ d_eq²/μ_f = (ρ_s/ρ_f) Re_γ̇.

use super::{Fluid, Particle};
use crate::ellipsoid::Ellipsoid;
use crate::error::{ParamError, derived, positive};
use crate::material::{NeoHooke, Response};
use serde::{Deserialize, Serialize};

/// Capillary number, dimensionless density and bulk ratio of a neutrally buoyant particle.
///
/// Built only through [`ShearScaling::new`] (deserialisation included), which also checks the
/// derived moduli μ_s = 1/Ca and λ_s = (λ_s/μ_s)·μ_s, so [`ShearScaling::neo_hooke`] cannot fail.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "ShearScalingRaw", into = "ShearScalingRaw")]
pub struct ShearScaling {
    ca: f64,
    rho_star: f64,
    bulk_ratio: f64,
    solid: NeoHooke,
}

/// The serialised form of [`ShearScaling`] (unchecked).
#[derive(Serialize, Deserialize)]
struct ShearScalingRaw {
    ca: f64,
    rho_star: f64,
    bulk_ratio: f64,
}

impl TryFrom<ShearScalingRaw> for ShearScaling {
    type Error = ParamError;
    fn try_from(raw: ShearScalingRaw) -> Result<Self, ParamError> {
        Self::new(raw.ca, raw.rho_star, raw.bulk_ratio)
    }
}

impl From<ShearScaling> for ShearScalingRaw {
    fn from(s: ShearScaling) -> Self {
        Self {
            ca: s.ca,
            rho_star: s.rho_star,
            bulk_ratio: s.bulk_ratio,
        }
    }
}

impl ShearScaling {
    /// Validated groups: Ca, ρ*, λ_s/μ_s finite and > 0, and the moduli μ_s = 1/Ca and λ_s
    /// finite and > 0 (Ca = 1e-320 passes the first test and overflows 1/Ca).
    pub fn new(ca: f64, rho_star: f64, bulk_ratio: f64) -> Result<Self, ParamError> {
        let (ca, rho_star, bulk_ratio) = (
            positive("Ca", ca)?,
            positive("rho*", rho_star)?,
            positive("lambda_s/mu_s", bulk_ratio)?,
        );
        let mu = derived("mu_s = 1/Ca", 1.0 / ca, &[ca])?;
        let lambda = derived("lambda_s = (lambda_s/mu_s) mu_s", bulk_ratio * mu, &[bulk_ratio, mu])?;
        Ok(Self {
            ca,
            rho_star,
            bulk_ratio,
            solid: NeoHooke::new(mu, lambda)?,
        })
    }

    /// Ca = μ_f γ̇ / μ_s.
    pub fn ca(&self) -> f64 {
        self.ca
    }

    /// ρ* = ρ_s γ̇ d_eq² / μ_f.
    pub fn rho_star(&self) -> f64 {
        self.rho_star
    }

    /// λ_s / μ_s.
    pub fn bulk_ratio(&self) -> f64 {
        self.bulk_ratio
    }
    /// Groups from physical data: fluid viscosity μ_f, shear rate γ̇, solid moduli μ_s and λ_s,
    /// solid density ρ_s and volume-equivalent diameter d_eq (SI or any consistent units).
    pub fn from_physical(
        mu_f: f64,
        shear_rate: f64,
        mu_s: f64,
        lambda_s: f64,
        rho_s: f64,
        d_eq: f64,
    ) -> Result<Self, ParamError> {
        let (mu_f, g, mu_s) = (
            positive("mu_f", mu_f)?,
            positive("shear rate", shear_rate)?,
            positive("mu_s", mu_s)?,
        );
        Self::new(
            mu_f * g / mu_s,
            positive("rho_s", rho_s)? * g * positive("d_eq", d_eq)?.powi(2) / mu_f,
            positive("lambda_s", lambda_s)? / mu_s,
        )
    }

    /// The Neo-Hooke solid μ_s = 1/Ca, λ_s = bulk_ratio · μ_s.
    pub fn neo_hooke(&self) -> NeoHooke {
        self.solid
    }

    /// Neutrally buoyant Neo-Hooke particle with axis ratios `ratios` along `axes` (columns),
    /// scaled to d_eq = 1.
    pub fn particle(&self, ratios: [f64; 3], axes: crate::tensor::Mat3) -> Result<Particle<NeoHooke>, ParamError> {
        self.particle_with(ratios, axes, self.neo_hooke())
    }

    /// The same particle with another shape response: any law (whose moduli then replace
    /// 1/Ca), or [`crate::material::Rigid`].
    pub fn particle_with<M: Response>(
        &self,
        ratios: [f64; 3],
        axes: crate::tensor::Mat3,
        response: M,
    ) -> Result<Particle<M>, ParamError> {
        let shape = Ellipsoid::with_volume_diameter(ratios, 1.0, axes)?;
        Particle::new(shape, response, Fluid::new(1.0, self.rho_star)?, self.rho_star)
    }
}

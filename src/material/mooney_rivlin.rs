//! Compressible Mooney–Rivlin solid.
//!
//! # Physics (generalises paper eq. 9)
//! With C = FᵀF, I₁ = tr C, I₂ = ½[(tr C)² − tr C²] and J = det F:
//!
//! $W = \frac{\mu_1}{2}(I_1 - 3 - 2\ln J) + \frac{\mu_2}{2}(I_2 - 3 - 4\ln J) + \frac{\lambda}{2}(\ln J)^2$.
//!
//! The ln J terms make F = 1 stress-free (∂I₂/∂F = 4·1 there); the small-strain shear modulus is
//! μ_s = μ₁ + μ₂ and μ₂ = 0 recovers Neo-Hooke (eq. 9). P and the tangent come from AD.

use super::Hyperelastic;
use crate::error::{ParamError, derived, positive};
use crate::tensor::{Mat3, Scalar, det3};
use serde::{Deserialize, Serialize};

/// Mooney–Rivlin law with moduli μ₁, μ₂ and Lamé parameter λ.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "MooneyRivlinRaw", into = "MooneyRivlinRaw")]
pub struct MooneyRivlin {
    mu1: f64,
    mu2: f64,
    lambda: f64,
}

/// The serialised form of a [`MooneyRivlin`] (unchecked).
#[derive(Serialize, Deserialize)]
struct MooneyRivlinRaw {
    mu1: f64,
    mu2: f64,
    lambda: f64,
}

impl TryFrom<MooneyRivlinRaw> for MooneyRivlin {
    type Error = ParamError;
    fn try_from(raw: MooneyRivlinRaw) -> Result<Self, ParamError> {
        Self::new(raw.mu1, raw.mu2, raw.lambda)
    }
}

impl From<MooneyRivlin> for MooneyRivlinRaw {
    fn from(m: MooneyRivlin) -> Self {
        Self {
            mu1: m.mu1,
            mu2: m.mu2,
            lambda: m.lambda,
        }
    }
}

impl MooneyRivlin {
    /// Law with μ₁ > 0, μ₂ ≥ 0, λ > 0.
    pub fn new(mu1: f64, mu2: f64, lambda: f64) -> Result<Self, ParamError> {
        if !(mu2.is_finite() && mu2 >= 0.0) {
            return Err(ParamError::NotPositive {
                name: "mu2 (must be >= 0)",
                value: mu2,
            });
        }
        let mu1 = positive("mu1", mu1)?;
        derived("mu_s = mu1 + mu2", mu1 + mu2, &[mu1, mu2])?;
        Ok(Self {
            mu1,
            mu2,
            lambda: positive("lambda", lambda)?,
        })
    }
}

impl Hyperelastic for MooneyRivlin {
    fn energy<S: Scalar>(&self, f: &Mat3<S>) -> S {
        let c = f.transpose() * f;
        let i1 = c.trace();
        let tr_c2 = c.iter().fold(S::from(0.0), |acc, &x| acc + x * x);
        let i2 = (i1 * i1 - tr_c2) * 0.5;
        let ln_j = det3(f).ln();
        (i1 - 3.0 - ln_j * 2.0) * (0.5 * self.mu1)
            + (i2 - 3.0 - ln_j * 4.0) * (0.5 * self.mu2)
            + ln_j * ln_j * (0.5 * self.lambda)
    }

    fn shear_modulus(&self) -> f64 {
        self.mu1 + self.mu2
    }

    fn lame_lambda(&self) -> f64 {
        self.lambda
    }

    /// W is a function of I₁, I₂ and J.
    fn is_isotropic(&self) -> bool {
        true
    }
}

// Selectable by name: `material = { law = "mooney_rivlin", mu1 = μ₁, mu2 = μ₂, lambda = λ_s }`.
inventory::submit! {
    super::LawRegistration {
        name: "mooney_rivlin",
        build: |p| {
            p.only(&["mu1", "mu2", "lambda"])?;
            Ok(std::sync::Arc::new(MooneyRivlin::new(p.number("mu1")?, p.number("mu2")?, p.positive("lambda")?)?))
        },
    }
}

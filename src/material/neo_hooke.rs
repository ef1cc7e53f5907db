//! Compressible Neo-Hooke solid (paper eq. 9).
//!
//! # Physics (paper eq. 9)
//! $W = \frac{\mu_s}{2}(\mathrm{tr}\\,F^TF - 3) - \mu_s \ln J + \frac{\lambda_s}{2}(\ln J)^2$, so
//! $P = \mu_s (F - F^{-T}) + \lambda_s \ln J\\, F^{-T}$ (eq. 9) and, with G = F⁻¹,
//! $\partial P_{iJ}/\partial F_{lK} = \mu_s\delta_{il}\delta_{JK} + (\mu_s - \lambda_s\ln J) G_{Ki}G_{Jl}
//! \\;+\\; \lambda_s G_{Ji}G_{Kl}$ (derived from eq. 9). The closed forms are an optimisation; a test checks
//! both against AD of W.

use super::Hyperelastic;
use crate::error::{ParamError, derived, positive};
use crate::tensor::{Mat3, Mat9, Scalar, det3};
use serde::{Deserialize, Serialize};

/// Neo-Hooke law with shear modulus μ_s and Lamé parameter λ_s.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "NeoHookeRaw", into = "NeoHookeRaw")]
pub struct NeoHooke {
    mu: f64,
    lambda: f64,
}

/// The serialised form of a [`NeoHooke`] (unchecked).
#[derive(Serialize, Deserialize)]
struct NeoHookeRaw {
    mu: f64,
    lambda: f64,
}

impl TryFrom<NeoHookeRaw> for NeoHooke {
    type Error = ParamError;
    fn try_from(raw: NeoHookeRaw) -> Result<Self, ParamError> {
        Self::new(raw.mu, raw.lambda)
    }
}

impl From<NeoHooke> for NeoHookeRaw {
    fn from(m: NeoHooke) -> Self {
        Self {
            mu: m.mu,
            lambda: m.lambda,
        }
    }
}

impl NeoHooke {
    /// Neo-Hooke solid; both moduli finite and > 0.
    pub fn new(mu: f64, lambda: f64) -> Result<Self, ParamError> {
        Ok(Self {
            mu: positive("mu_s", mu)?,
            lambda: positive("lambda_s", lambda)?,
        })
    }

    /// Nondimensional solid for capillary number `ca` (μ_s = 1/Ca in units μ_f γ̇) and
    /// bulk ratio λ_s/μ_s.
    pub fn from_capillary(ca: f64, bulk_ratio: f64) -> Result<Self, ParamError> {
        let (ca, ratio) = (positive("Ca", ca)?, positive("lambda_s/mu_s", bulk_ratio)?);
        let mu = derived("mu_s = 1/Ca", 1.0 / ca, &[ca])?;
        Self::new(
            mu,
            derived("lambda_s = (lambda_s/mu_s) mu_s", ratio * mu, &[ratio, mu])?,
        )
    }
}

impl Hyperelastic for NeoHooke {
    fn energy<S: Scalar>(&self, f: &Mat3<S>) -> S {
        let ln_j = det3(f).ln();
        let i1 = f.iter().fold(S::from(0.0), |acc, &c| acc + c * c);
        (i1 - 3.0) * (0.5 * self.mu) - ln_j * self.mu + ln_j * ln_j * (0.5 * self.lambda)
    }

    fn shear_modulus(&self) -> f64 {
        self.mu
    }

    fn lame_lambda(&self) -> f64 {
        self.lambda
    }

    /// W is a function of I₁ and J.
    fn is_isotropic(&self) -> bool {
        true
    }

    fn piola(&self, f: &Mat3) -> Mat3 {
        let f_inv_t = crate::tensor::inv_transpose(f);
        let ln_j = f.determinant().ln();
        (f - f_inv_t) * self.mu + f_inv_t * (self.lambda * ln_j)
    }

    fn tangent(&self, f: &Mat3) -> Mat9 {
        let g = crate::tensor::inv_transpose(f).transpose();
        let ln_j = f.determinant().ln();
        let c1 = self.mu - self.lambda * ln_j;
        // Row (i, J) = i + 3J, column (l, K) = l + 3K.
        Mat9::from_fn(|row, col| {
            let (i, jj) = (row % 3, row / 3);
            let (l, kk) = (col % 3, col / 3);
            let id = if i == l && jj == kk { self.mu } else { 0.0 };
            id + c1 * g[(kk, i)] * g[(jj, l)] + self.lambda * g[(jj, i)] * g[(kk, l)]
        })
    }
}

// Selectable by name: `material = { law = "neo_hooke", mu = μ_s, lambda = λ_s }`.
inventory::submit! {
    super::LawRegistration {
        name: "neo_hooke",
        build: |p| {
            p.only(&["mu", "lambda"])?;
            Ok(std::sync::Arc::new(NeoHooke::new(p.positive("mu")?, p.positive("lambda")?)?))
        },
    }
}

//! When a drug-loaded particle releases its load: a measure of its deformation, the
//! [`ReleaseCriterion`], and the levels at which release is assumed, [`ReleaseThresholds`]. The
//! population watch that records where and when each level is first crossed is
//! `population::release`.
//!
//! # Physics
//! A pseudo-rigid particle has one deformation gradient F (paper eqs. 1, 2), so every material
//! fibre stretches between the smallest and the largest principal stretch of F, and the
//! largest,
//! ```math
//! \lambda_1 = \sqrt{\max \operatorname{eig}(F^T F)},
//! ```
//! is the stretch of the most stretched fibre of the whole particle. Three measures are offered:
//! - [`ReleaseCriterion::PrincipalStretch`] λ₁ (default): the fibre stretch at which a brittle
//!   gel network or a gel shell ruptures and frees its cargo. Rupture stretches of hydrogels in
//!   tension span more than a decade: about 1.2 for a calcium-alginate gel, about 7 for a
//!   polyacrylamide gel and beyond 20 for their hybrid (Sun et al., Nature 489 (2012) 133–136).
//!   The brittle end (λ₁ ≈ 1.2) is the relevant one for a carrier meant to open in the airways;
//!   which level a real carrier opens at is a property of the carrier, not of this model, so
//!   the level is a parameter and a study scans a list of them ([`ReleaseThresholds`]).
//! - [`ReleaseCriterion::SemiAxisRatio`] r₁/r₁⁰: the longest current semi-axis (of F̄ = F·S,
//!   paper §5) over the longest rest semi-axis, what an image of the particle shows. For a
//!   sphere it is λ₁; for an ellipsoid it is at most λ₁ (a fibre along the long axis stretches
//!   by r₁/r₁⁰ or less when the particle also turns within its shape).
//! - [`ReleaseCriterion::EnergyDensity`] W(F) in Pa, the law's strain-energy density per rest
//!   volume (paper eq. 9 for Neo-Hooke): the energy criterion of rupture (a critical stored
//!   energy) rather than the stretch criterion; for a uniaxial Neo-Hooke stretch λ it is
//!   W = ½μ_s(λ² + 2/λ − 3). A rigid particle has W = 0 and never releases.
//!
//! Assumed: release is instantaneous and complete at the first crossing, and does not change
//! the particle (it is recorded, the particle is tracked on unchanged). Shear-triggered
//! carriers that release above a critical load exist (Korin et al., Science 337 (2012)
//! 738–742, for platelet-sized aggregates in stenosed vessels); a stretch level for airway
//! carriers has not been measured.

use crate::hydro::DragModel;
use crate::material::{Response, StressLaw};
use crate::particle::Particle;
use crate::tensor::Mat3;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// What is compared with the release thresholds (module docs).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum ReleaseCriterion {
    /// Largest principal stretch λ₁ = √(max eig FᵀF) (dimensionless, 1 at rest).
    #[default]
    PrincipalStretch,
    /// Longest current over longest rest semi-axis r₁/r₁⁰ (dimensionless, 1 at rest).
    SemiAxisRatio,
    /// Strain-energy density W(F) of the particle's law (Pa, 0 at rest; 0 for a rigid one).
    EnergyDensity,
}

impl ReleaseCriterion {
    /// The criterion's value at rest (F = 1): thresholds must lie above it.
    pub fn at_rest(self) -> f64 {
        match self {
            Self::PrincipalStretch | Self::SemiAxisRatio => 1.0,
            Self::EnergyDensity => 0.0,
        }
    }

    /// Short name for datasets: `lambda1`, `r1_over_r1_0`, `energy_density`.
    pub fn label(self) -> &'static str {
        match self {
            Self::PrincipalStretch => "lambda1",
            Self::SemiAxisRatio => "r1_over_r1_0",
            Self::EnergyDensity => "energy_density",
        }
    }

    /// The criterion of `particle` at deformation `f`.
    pub fn value<M: Response, D: DragModel>(self, particle: &Particle<M, D>, f: &Mat3) -> f64 {
        match self {
            Self::PrincipalStretch => largest_stretch(f),
            Self::SemiAxisRatio => particle.frame(f).r[0] / particle.shape().semi_axes().max(),
            Self::EnergyDensity => particle.elastic().map_or(0.0, |law| law.energy_at(f)),
        }
    }
}

/// λ₁ = √(max eig FᵀF), the largest singular value of F.
pub fn largest_stretch(f: &Mat3) -> f64 {
    (f.transpose() * f).symmetric_eigenvalues().max().max(0.0).sqrt()
}

/// A threshold list that cannot be used.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ReleaseError {
    /// No threshold was given.
    #[error("no release threshold given")]
    Empty,
    /// A threshold is NaN or infinite.
    #[error("release threshold {index} is {value}, not finite")]
    NonFinite {
        /// Position in the list.
        index: usize,
        /// The value.
        value: f64,
    },
    /// A threshold is at or below the criterion's value at rest, so every particle would
    /// release at its start.
    #[error("release threshold {index} = {value} of {criterion:?} is not above its value at rest, {rest}")]
    NotAboveRest {
        /// The criterion.
        criterion: ReleaseCriterion,
        /// Position in the list.
        index: usize,
        /// The value.
        value: f64,
        /// The criterion at rest.
        rest: f64,
    },
    /// The thresholds are not strictly increasing.
    #[error("release threshold {index} = {value} does not exceed the one before it, {previous}")]
    NotIncreasing {
        /// Position in the list.
        index: usize,
        /// The value.
        value: f64,
        /// The threshold before it.
        previous: f64,
    },
}

/// A criterion and strictly increasing levels above its value at rest: each level is one
/// assumed release threshold, so one run gives the released fraction against the threshold.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReleaseThresholds {
    criterion: ReleaseCriterion,
    levels: Vec<f64>,
}

impl ReleaseThresholds {
    /// The levels `levels` of `criterion`: finite, strictly increasing, above the value at
    /// rest ([`ReleaseCriterion::at_rest`]), at least one.
    pub fn new(criterion: ReleaseCriterion, levels: Vec<f64>) -> Result<Self, ReleaseError> {
        if levels.is_empty() {
            return Err(ReleaseError::Empty);
        }
        let rest = criterion.at_rest();
        for (index, &value) in levels.iter().enumerate() {
            if !value.is_finite() {
                return Err(ReleaseError::NonFinite { index, value });
            }
            if value <= rest {
                return Err(ReleaseError::NotAboveRest {
                    criterion,
                    index,
                    value,
                    rest,
                });
            }
            if index > 0 && value <= levels[index - 1] {
                return Err(ReleaseError::NotIncreasing {
                    index,
                    value,
                    previous: levels[index - 1],
                });
            }
        }
        Ok(Self { criterion, levels })
    }

    /// The criterion.
    pub fn criterion(&self) -> ReleaseCriterion {
        self.criterion
    }

    /// The levels, increasing.
    pub fn levels(&self) -> &[f64] {
        &self.levels
    }
}

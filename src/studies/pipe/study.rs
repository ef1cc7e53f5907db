//! The paper's parameter studies over aspect ratio and softness, one particle per case, run in
//! parallel (particles are independent).

use super::setup::PipeSetup;
use super::tracking::{PipeSample, sample_orientation};
use crate::driver::output_times;
use crate::studies::StudyError;

/// First trial step (1/γ̇₀); the adaptive integrators correct it within a few steps.
pub(super) const DT0: f64 = 1e-3;
/// Time limit of a deposition run in units of the sphere settling time (an upper bound on
/// the settling speed, see [`PipeSetup::sphere_settling_time`]).
#[cfg(feature = "parallel")]
pub(super) const SETTLING_TIMES: f64 = 50.0;

/// One Tian/Cui particle: prolate aspect ratio λ₁ and capillary number (0: rigid limit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PipeCase {
    /// λ₁ = r₁/r₃.
    pub lambda1: f64,
    /// Ca at the release point; 0 selects the rigid integrator.
    pub ca: f64,
}

impl PipeCase {
    /// All combinations of `lambdas` and `cas`, λ-major.
    pub fn grid(lambdas: &[f64], cas: &[f64]) -> Vec<Self> {
        lambdas
            .iter()
            .flat_map(|&lambda1| cas.iter().map(move |&ca| Self { lambda1, ca }))
            .collect()
    }

    /// The setup of this case.
    pub fn setup(&self) -> Result<PipeSetup, StudyError> {
        Ok(PipeSetup::tian_cui(self.lambda1, self.ca)?)
    }
}

/// Orientation histories sampled at `count` even times up to `t_end_seconds` (s), at
/// rtol = atol = `tol`.
pub fn orientation_study(
    cases: &[PipeCase],
    t_end_seconds: f64,
    count: usize,
    tol: f64,
) -> Result<Vec<(PipeSetup, Vec<PipeSample>)>, StudyError> {
    crate::parallel::map(cases, |case| {
        let setup = case.setup()?;
        let times = output_times(t_end_seconds / setup.time_unit, count);
        let samples = sample_orientation(&setup, &setup.integrator(tol)?, &times, DT0)?;
        Ok((setup, samples))
    })
    .into_iter()
    .collect()
}

//! The paper's parameter studies over aspect ratio and softness, one particle per case, run in
//! parallel (particles are independent).

use super::setup::PipeScene;
use super::tracking::{PipeSample, sample_orientation};
use crate::driver::output_times;
use crate::scenes::SceneError;

/// First trial step (1/γ̇₀); the adaptive integrators correct it within a few steps.
pub(super) const DT0: f64 = 1e-3;
/// Time limit of a deposition run in units of the sphere settling time (an upper bound on
/// the settling speed, see [`PipeScene::sphere_settling_time`]).
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

    /// The scene of this case.
    pub fn scene(&self) -> Result<PipeScene, SceneError> {
        Ok(PipeScene::tian_cui(self.lambda1, self.ca)?)
    }
}

/// Orientation histories sampled at `count` even times up to `t_end_seconds` (s), at
/// rtol = atol = `tol`.
pub fn orientation_study(
    cases: &[PipeCase],
    t_end_seconds: f64,
    count: usize,
    tol: f64,
) -> Result<Vec<(PipeScene, Vec<PipeSample>)>, SceneError> {
    crate::parallel::map(cases, |case| {
        let scene = case.scene()?;
        let times = output_times(t_end_seconds / scene.time_unit, count);
        let samples = sample_orientation(&scene, &scene.integrator(tol)?, &times, DT0)?;
        Ok((scene, samples))
    })
    .into_iter()
    .collect()
}

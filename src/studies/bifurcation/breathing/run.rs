//! The inhaled run: the steady study's particles tracked window by window through a
//! [`Breath`].

use super::{Breath, Inhaled};
use crate::driver::{Budget, Plan};
use crate::material::NeoHooke;
use crate::population::batch::{Batch, run_batch};
use crate::population::{Computed, Fingerprint, RunOptions, RunOutput, Shard};
use crate::studies::bifurcation::BifurcationError;
use crate::studies::bifurcation::injection::Kind;
use crate::studies::bifurcation::setup::Airway;
use crate::studies::bifurcation::study::{DT0, MAX_STEPS, integrator};
use std::path::Path;

/// The run of `n` particles of `kind` (seed `seed`) inhaled through `breath`, injected as
/// [`Inhaled`] with the steady field of `airway`, tracked by the steady study's integrator
/// ([`integrator`]: chosen on the steady field's numbers, so both runs step alike) to the end
/// of the inhalation, window by window. With `cache` a folder, a finished run is kept there as
/// `breath-<config hash>.json` and read back instead of rerun, with the wall time its
/// computation took ([`RunOutput::read_or_run`]).
pub fn run_inhaled(
    airway: &Airway,
    breath: &mut Breath,
    kind: Kind,
    n: u64,
    seed: u64,
    options: &RunOptions,
    cache: Option<&Path>,
) -> Result<Computed<NeoHooke>, BifurcationError> {
    let integ = integrator(airway, kind)?.integrator;
    let inhaled = Inhaled::new(airway, kind, breath.waveform)?;
    let plan = Plan::new(breath.waveform.duration(), DT0)?.with_budget(Budget {
        max_steps: MAX_STEPS,
        wall_time: None,
    });
    let batch = Batch::new(&integ, &breath.boundary, &inhaled, plan);
    let windows = breath.windows();
    let config = Fingerprint::new("bifurcation breathing")
        .particles(&kind)
        .with("waveform", &breath.waveform)
        .identity("injection profile", airway.flow())
        .flow(&breath.flow)
        .boundary(&breath.boundary)
        .config(seed, n);
    let file = cache.map(|dir| dir.join(format!("breath-{}.json", batch.case(&breath.flow).config_hash(&config))));
    RunOutput::read_or_run(file.as_deref(), || {
        Ok(run_batch(
            &batch,
            &mut breath.flow,
            &windows,
            &config,
            Shard::ALL,
            options,
        )?)
    })
}

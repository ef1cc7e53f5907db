//! What a case keeps of a particle beyond its fate: an [`Observer`] watches each particle's
//! run (the start, output and event states the driver shows, and every accepted step) and
//! leaves a summary in its record ([`super::ParticleRecord::observed`]), plain data kept as
//! JSON (checkpoints, shards) and read back as its own type by
//! [`super::ParticleRecord::summary`] (a record without it, or with another kind, is a
//! [`super::SummaryError`] naming the particle).
//!
//! A scene's per-run columns (validity maxima, slip against the fluid, a trajectory sampled at
//! its own cadence) are observations: they come from the same run that decides the fate, so a
//! study needs neither a second loop nor a re-run of its particles. A watch only reads what it
//! is shown, so the fate and the work of a run are the same with or without one; its summary
//! is a function of the run, hence of (case, seed, index), and checkpoints and shards keep it
//! like the rest of the record.
//!
//! An accepted step is shown as the driver's [`AcceptedStep`]: with the end state's principal
//! frame and flow sample, carried from the scheme where it computed them and otherwise computed
//! once for every reader, so a watch that needs r₁, u or ∇u there asks the step
//! ([`AcceptedStep::frame`], [`AcceptedStep::flow`]) instead of computing them again.

use super::record::Fate;
use crate::driver::AcceptedStep;
use crate::particle::State;

/// Builds a [`Watch`] for each particle of a case. `P` is the particle, `F` the flow and `B`
/// the boundary of the case.
pub trait Observer<P, F: ?Sized, B: ?Sized>: Sync {
    /// What the summaries hold and how they are computed, for the configuration hash
    /// ([`super::Case::config_hash`]): records with other summaries belong to another run.
    fn fingerprint(&self) -> String;

    /// Start watching `particle` released at `start` in `flow` within `boundary`.
    fn watch<'w>(&'w self, particle: &'w P, flow: &'w F, boundary: &'w B, start: &State) -> Box<dyn Watch + 'w>;
}

/// One particle's watch.
pub trait Watch {
    /// A state the driver shows: the start, each output time of the plan, the event.
    fn output(&mut self, _state: &State) {}

    /// An accepted step, with its end state's frame and flow sample.
    fn step(&mut self, _step: &AcceptedStep) {}

    /// The run ended with `fate` at `end` (the event, the end time, or the last accepted state
    /// before a failure): the summary the record keeps.
    fn finish(self: Box<Self>, fate: &Fate, end: &State) -> serde_json::Value;
}

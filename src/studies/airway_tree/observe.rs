//! Which generations a particle entered: an [`Observer`] of each run that classifies the
//! barycentre of every accepted step and of the end state ([`Tree::classify`]) and keeps the
//! deepest location reached.
//!
//! # Why the deepest location is enough
//! The generations along any path from the inlet are nested (a particle reaches generation
//! g + 1 only through a tube of generation g and its bifurcation zone), so "entered g" is
//! "reached a generation ≥ g". A step cannot jump a tube: the contact event caps each step by
//! the gap to the nearest wall (less than a tube radius, ≤ 3 mm), and the shortest tube
//! region (a G6 tube past its entry) is longer than 6 mm, so every generation a particle
//! passes shows in some accepted step.

use super::tree::{Location, Part, Tree};
use crate::driver::AcceptedStep;
use crate::particle::State;
use crate::population::{Fate, Observer, Watch};
use serde::{Deserialize, Serialize};

/// What a run keeps: the deepest location reached (`None` if no state could be classified,
/// which a finite run never leaves).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Reached {
    /// Deepest generation reached (tube or bifurcation zone).
    pub generation: u8,
    /// Its tube (for a bifurcation zone, the parent tube).
    pub tube: usize,
    /// Whether the deepest location was a bifurcation zone.
    pub zone: bool,
}

/// Watches each particle's generations in `tree`.
pub struct Generations<'t> {
    tree: &'t Tree,
}

impl<'t> Generations<'t> {
    /// The observer for particles in `tree`.
    pub fn new(tree: &'t Tree) -> Self {
        Self { tree }
    }
}

impl<P, F: ?Sized, B: ?Sized> Observer<P, F, B> for Generations<'_> {
    fn fingerprint(&self) -> String {
        format!(
            "deepest generation by the nearest centreline; {}",
            self.tree.fingerprint()
        )
    }

    fn watch<'w>(&'w self, _particle: &'w P, _flow: &'w F, _boundary: &'w B, start: &State) -> Box<dyn Watch + 'w> {
        let mut watching = Watching {
            tree: self.tree,
            deepest: None,
        };
        watching.see(start);
        Box::new(watching)
    }
}

struct Watching<'t> {
    tree: &'t Tree,
    deepest: Option<Location>,
}

impl Watching<'_> {
    fn see(&mut self, state: &State) {
        // A non-finite state ends the run as a failure; it has no location to keep.
        let Ok(here) = self.tree.classify(&state.x) else {
            return;
        };
        // The first location of the deepest generation is kept.
        if self.deepest.is_none_or(|d| here.generation > d.generation) {
            self.deepest = Some(here);
        }
    }
}

impl Watch for Watching<'_> {
    fn output(&mut self, state: &State) {
        self.see(state);
    }

    fn step(&mut self, step: &AcceptedStep) {
        self.see(step.state());
    }

    fn finish(mut self: Box<Self>, _fate: &Fate, end: &State) -> serde_json::Value {
        self.see(end);
        match self.deepest {
            Some(d) => serde_json::to_value(Reached {
                generation: d.generation,
                tube: d.tube,
                zone: d.part == Part::Bifurcation,
            })
            .expect("Reached is plain data"),
            None => serde_json::Value::Null,
        }
    }
}

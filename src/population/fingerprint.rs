//! What identifies a run beyond its integrator, plan, contact model and observer: the
//! [`RunConfig::fingerprint`] text, composed from typed parts so that no study writes it by
//! hand.
//!
//! ```text
//! let config = Fingerprint::new("bifurcation")      // the study's name (a scene: its text)
//!     .particles(&kind)                             // the injector's parameters, `Debug`
//!     .flow(airway.flow())                          // an `Identity`: the field as read
//!     .boundary(airway.boundary())
//!     .with("forces", &forces)                      // anything else, by name, `Debug`
//!     .config(seed, n);                             // RunConfig { seed, particles, fingerprint }
//! ```
//! The text is the first line, then one line `name: value` per part, in the order given. A
//! `Debug` form prints every f64 exactly (shortest round trip), so two parts print alike only
//! if they are equal. [`Case::config_hash`](super::Case::config_hash) hashes it with the rest.

use super::RunConfig;
use std::fmt::{Debug, Write};

/// Something whose identity enters a run's configuration hash and whose `Debug` form would
/// not do: a field read from files (identified by its content, not its path) or a boundary
/// on a mesh (whose `Debug` text would be as large as the mesh).
pub trait Identity {
    /// The text that identifies it: the same for two values that give the same records.
    fn identity(&self) -> String;
}

// The identities of OpenFOAM fields and mesh boundaries, their content's fingerprints: here,
// not beside the types, since the flow and contact layers know nothing of populations.
#[cfg(feature = "mesh")]
mod mesh {
    use super::Identity;
    use crate::contact::MeshBoundary;
    use crate::flow::openfoam::{BlendedFlow, FoamFlow, TransientFlow, Windowed};

    impl Identity for FoamFlow {
        fn identity(&self) -> String {
            self.fingerprint()
        }
    }

    impl Identity for BlendedFlow {
        fn identity(&self) -> String {
            self.fingerprint()
        }
    }

    impl<F: Windowed> Identity for TransientFlow<F> {
        fn identity(&self) -> String {
            self.fingerprint().to_string()
        }
    }

    impl Identity for MeshBoundary {
        fn identity(&self) -> String {
            self.fingerprint().to_string()
        }
    }
}

/// The builder of a run's [`RunConfig`] and its fingerprint (module docs).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Fingerprint {
    text: String,
}

impl Fingerprint {
    /// A run of `study`: its name, or a scene's text (the first line or lines).
    pub fn new(study: impl Into<String>) -> Self {
        Self { text: study.into() }
    }

    /// The fingerprint of `config`, to add parts to (a batch run's windows,
    /// [`super::batch::batch_config`]).
    pub fn of(config: &RunConfig) -> Self {
        Self::new(config.fingerprint.clone())
    }

    /// Add the particles' parameters: what the injector draws them from (`particles: …`).
    pub fn particles(self, particles: &impl Debug) -> Self {
        self.with("particles", particles)
    }

    /// Add the flow field's identity (`flow: …`).
    pub fn flow(self, flow: &(impl Identity + ?Sized)) -> Self {
        self.identity("flow", flow)
    }

    /// Add the boundary's identity (`boundary: …`).
    pub fn boundary(self, boundary: &(impl Identity + ?Sized)) -> Self {
        self.identity("boundary", boundary)
    }

    /// Add another part by its identity (`name: …`).
    pub fn identity(self, name: &str, part: &(impl Identity + ?Sized)) -> Self {
        self.line(name, format_args!("{}", part.identity()))
    }

    /// Add another part by its `Debug` form (`name: …`).
    pub fn with(self, name: &str, value: &(impl Debug + ?Sized)) -> Self {
        self.line(name, format_args!("{value:?}"))
    }

    /// The configuration of a run of `particles` particles with seed `seed`.
    pub fn config(self, seed: u64, particles: u64) -> RunConfig {
        RunConfig {
            seed,
            particles,
            fingerprint: self.text,
        }
    }

    fn line(mut self, name: &str, value: std::fmt::Arguments<'_>) -> Self {
        // Writing to a String cannot fail.
        let _ = write!(self.text, "\n{name}: {value}");
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Named(&'static str);

    impl Identity for Named {
        fn identity(&self) -> String {
            self.0.into()
        }
    }

    /// The study's name, then one `name: value` line per part in the order given, every f64
    /// exact.
    #[test]
    fn one_line_per_part() {
        let config = Fingerprint::new("study")
            .particles(&(0.1, 2u8))
            .flow(&Named("field"))
            .boundary(&Named("walls"))
            .with("forces", &[1e-300])
            .config(7, 3);
        assert_eq!(
            config,
            RunConfig {
                seed: 7,
                particles: 3,
                fingerprint: "study\nparticles: (0.1, 2)\nflow: field\nboundary: walls\nforces: [1e-300]".into(),
            }
        );
        let more = Fingerprint::of(&config).with("batch windows", &[0.0, 1.0]).config(7, 3);
        assert!(more.fingerprint.ends_with("[1e-300]\nbatch windows: [0.0, 1.0]"));
    }
}

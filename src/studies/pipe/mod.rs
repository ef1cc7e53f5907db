//! Laminar pipe flow (paper §6.2, Figs 9–12): a prolate particle released off-axis in the
//! Tian/Cui Hagen–Poiseuille air flow, settling under gravity until it touches the wall.
//!
//! - [`setup`]: the physical set-up (SI) and its nondimensional form (d_eq, 1/γ̇₀, μ_f γ̇₀);
//! - [`tracking`]: orientation histories and tracking to deposition;
//! - [`orbit`]: Jeffery periods and the measured orbit periods of l_a;
//! - [`study`]: the paper's (λ₁, Ca) cases and orientation study, in parallel;
//! - [`deposition`]: the deposition study, through the population runner (feature `parallel`);
//! - [`datasets`]: the CSV tables and figure panels of Figs 10–12.

pub mod datasets;
#[cfg(feature = "parallel")]
pub mod deposition;
pub mod orbit;
pub mod setup;
pub mod study;
pub mod tracking;

pub use crate::studies::particles::{Deformability, Shape};
#[cfg(feature = "parallel")]
pub use deposition::deposition_study;
pub use setup::{PipeFlowData, PipeParticleData, PipeSetup};
pub use study::{PipeCase, orientation_study};
pub use tracking::{Deposition, PipeSample, ShapeStats, sample_orientation, track_to_deposition};

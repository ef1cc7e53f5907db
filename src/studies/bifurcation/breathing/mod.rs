//! A breathing cycle in the bifurcation (issue 24, item 3): particles inhaled with a
//! sinusoidal flow rate through the transient field of `cases/bifurcation-breathing`, against
//! the steady inhalation of paper §6.4 on the same particles.
//!
//! # Physics
//! The inhalation half of a sinusoidal breath of period T (at rest, 15 breaths a minute:
//! T = 4 s) drives the parent's uniform inlet with
//! ```math
//! U_{in}(t) = U_p \sin(\omega t), \qquad \omega = 2\pi/T, \qquad 0 \le t \le T/2,
//! \qquad U_p = \tfrac{\pi}{2} U,
//! ```
//! so the mean over the inhalation is the steady case's U = 1.2425 m/s (Re = 500) and the
//! peak Reynolds number is 785. The Womersley number
//! ```math
//! \alpha = R\sqrt{\omega/\nu} = 0.97
//! ```
//! (R = 3 mm, ν = 1.491e-5 m²/s) says the viscous diffusion time R²/ν = 0.6 s is about the
//! time 1/ω = 0.64 s in which the flow rate changes: the flow is nearly quasi-steady, and the
//! convective time L/U = 0.03 s is shorter still.
//!
//! # Injection
//! The inhaled air carries a constant aerosol concentration c, so particles cross the inlet at
//! the rate c Q(t), proportional to sin ωt. A particle's injection time has the distribution
//! function F(t) = (1 − cos ωt)/2 over the inhalation and is drawn by its inverse,
//! $t = \arccos(1 - 2u)/\omega$, from a uniform u of the particle's own generator after its
//! steady draw (`Injector::injection`): particle k has the disc point, orientation and
//! shape of the steady study's particle k, and the two runs are paired particle by particle.
//! Its velocity is the steady field's at the injection point scaled by $U_{in}(t)/U$: the
//! inlet is uniform in both fields, and the particle relaxes to the transient field's velocity
//! in its response time (1.9 ms at Stk 0.4), 0.1 % of the inhalation.
//!
//! # Tracking
//! Particles are tracked through the solved inhalation, to t = T/2; the exhalation is not
//! solved, and a particle still inside at its end is suspended. The field holds two levels at
//! a time ([`TransientFlow`](crate::flow::openfoam::TransientFlow)): the batch runner advances
//! every live particle to the next written level, then slides the window.
//!
//! # Files
//! `waveform.rs` ([`Waveform`], [`PERIOD`], [`womersley_number`]), `inhaled.rs` (the
//! injection, [`Inhaled`]), `field.rs` (the transient field [`Breath`] and its checks:
//! [`write_quasi_steady`], [`flow_rate_table`], [`field_difference`]), `run.rs`
//! ([`run_inhaled`]), `paired.rs` (the two runs paired, [`BreathingPair`], [`by_phase`]),
//! `tables.rs` (the datasets) and `figure.rs` ([`figure`]).

mod field;
mod figure;
mod inhaled;
mod paired;
mod run;
mod tables;
mod waveform;

pub use field::{Breath, field_difference, flow_rate_table, write_quasi_steady};
pub use figure::figure;
pub use inhaled::Inhaled;
pub use paired::{BreathingPair, by_phase};
pub use run::run_inhaled;
pub use tables::{MAP_PARTICLES, de_table, map_table, paired_table, phase_table};
pub use waveform::{PERIOD, Waveform, womersley_number};

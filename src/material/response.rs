//! How a particle's shape responds to load: elastically, with a hyperelastic law, or not at all.
//!
//! # Physics (paper eqs. 9, 18; Jeffery 1922)
//! An elastic particle carries the stress P = ∂W/∂F of its law (eq. 9) and its shape follows
//! eq. 18 (or its inertialess limit). A rigid particle (Ca → 0, μ_s → ∞) keeps F a rotation that
//! spins at Jeffery's (1922) torque-free rate; no stress is ever evaluated. The choice is part
//! of the model, made with the particle: `Particle<NeoHooke>` is elastic, `Particle<Rigid>`
//! rigid, and `Particle<Softness<L>>` either, decided per particle (a study mixing both).

use super::{Hyperelastic, StressLaw};
use crate::tensor::{Mat3, Scalar};
use serde::{Deserialize, Serialize};

/// The shape response of a particle.
pub trait Response: Send + Sync {
    /// The hyperelastic law of an elastic particle.
    type Law: StressLaw;

    /// The law, or `None` for a rigid particle.
    fn elastic(&self) -> Option<&Self::Law>;
}

/// Every hyperelastic law is an elastic response.
impl<M: Hyperelastic> Response for M {
    type Law = M;

    fn elastic(&self) -> Option<&M> {
        Some(self)
    }
}

/// A rigid particle: Jeffery rotation, no elasticity.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Rigid;

/// The law of a rigid particle: a type without values, so no law is ever built or evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoLaw {}

impl Hyperelastic for NoLaw {
    fn energy<S: Scalar>(&self, _f: &Mat3<S>) -> S {
        match *self {}
    }
    fn shear_modulus(&self) -> f64 {
        match *self {}
    }
    fn lame_lambda(&self) -> f64 {
        match *self {}
    }
    fn is_isotropic(&self) -> bool {
        match *self {}
    }
}

impl Response for Rigid {
    type Law = NoLaw;

    fn elastic(&self) -> Option<&NoLaw> {
        None
    }
}

/// Rigid or elastic with law `L`, decided per particle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Softness<L> {
    /// Rigid (Ca → 0).
    Rigid,
    /// Elastic with this law.
    Elastic(L),
}

impl<L: StressLaw> Response for Softness<L> {
    type Law = L;

    fn elastic(&self) -> Option<&L> {
        match self {
            Softness::Rigid => None,
            Softness::Elastic(law) => Some(law),
        }
    }
}

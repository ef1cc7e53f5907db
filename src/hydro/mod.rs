//! Hydrodynamic loads on the ellipsoid: the Jeffery–Roscoe traction stress σ̃ that drives the
//! shape (paper eqs. 12, 15, 16), Brenner's translational drag (eq. 14), and gravity with
//! buoyancy (eq. 13).
//!
//! # Physics (paper §3, eqs. 10–17)
//! The fluid acts on a pseudo-rigid particle through two resultants of its surface traction
//! (eqs. 10, 11): the force, whose mean part is Brenner's drag ([`drag`], eq. 14), and the
//! force dyad, whose fluctuating part is vol(B_t) σ̃ with the Jeffery–Roscoe stress
//! ([`traction`], eqs. 12, 15) and enters the shape equation as P̃ = Jσ̃F⁻ᵀ (eq. 16). Gravity
//! reduced by buoyancy ([`gravity`], eq. 13) acts on the barycentre only (eq. 17). Fluid inertia,
//! gas slip, finite-Re drag and lift are optional terms beyond the paper ([`forces`]). The closed
//! forms and their derivations: [`crate::theory::traction`], [`crate::theory::drag`].

pub mod drag;
pub mod forces;
pub mod gravity;
pub mod traction;

pub use drag::{Brenner, DragModel, StokesSphere};
pub use forces::{ForceTerm, ForceTerms};
pub use traction::{InertialessSolver, JefferyRoscoe, VolumetricTraction, jeffery_spin};

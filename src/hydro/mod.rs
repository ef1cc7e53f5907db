//! Hydrodynamic loads on the ellipsoid: the Jeffery–Roscoe traction stress σ̃ that drives the
//! shape (paper eqs. 12, 15, 16), Brenner's translational drag (eq. 14), and gravity with
//! buoyancy (eq. 13).

pub mod drag;
pub mod gravity;
pub mod traction;

pub use drag::{Brenner, DragModel, StokesSphere};
pub use traction::{InertialessSolver, JefferyRoscoe, VolumetricTraction, jeffery_spin};

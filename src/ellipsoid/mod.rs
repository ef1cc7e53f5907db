//! The ellipsoid: its stress-free shape (the shape tensor S, paper eq. 4), its current principal
//! frame (r_a, Q from F̄F̄ᵀ) and the Jeffery ellipsoid integrals that the hydrodynamics needs.

pub mod frame;
pub mod integrals;
pub mod shape;

pub use frame::PrincipalFrame;
pub use integrals::EllipsoidIntegrals;
pub use shape::Ellipsoid;

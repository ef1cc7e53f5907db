//! The ellipsoid: its stress-free shape (the shape tensor S, paper eq. 4), its current principal
//! frame (r_a, Q from F̄F̄ᵀ) and the Jeffery ellipsoid integrals that the hydrodynamics needs.
//!
//! # Physics (paper eqs. 4, 5, 8, 20, A.1, A.2)
//! The particle is the unit sphere mapped by F̄ = F·S (eqs. 4, 5): [`shape`] holds S, the
//! volume vol(B₀) = (4π/3) det S and the Euler tensor Θ = (m/5) S Sᵀ (eq. 8); [`frame`] the
//! current semi-axes r_a = √eig(F̄F̄ᵀ) and rotation Q (eqs. 20, A.1, A.2); [`integrals`] the
//! integrals over the confocal family that the traction (eq. 12) and the drag (eq. 14) are
//! built from ([`crate::theory::ellipsoid_integrals`]).

pub mod frame;
pub mod integrals;
pub mod shape;

pub use frame::PrincipalFrame;
pub use integrals::EllipsoidIntegrals;
pub use shape::Ellipsoid;

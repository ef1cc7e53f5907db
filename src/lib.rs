//! # pseudorigid
//!
//! Soft, initially ellipsoidal micro-particles carried by viscous flow, modelled as
//! *pseudo-rigid bodies* (Cohen & Muncaster; Wedel et al.): a barycentre x_c plus one affine
//! deformation gradient F per particle.
//!
//! The model in ten lines (paper equation numbers in parentheses):
//! - shape: the stress-free ellipsoid is S·(unit sphere) (eq. 4); the current one is F̄ = F·S, with
//!   semi-axes r_a = √eig(F̄F̄ᵀ) and rotation Q (§5);
//! - shape dynamics: Ḟ = A, Ȧ = vol(B₀)[P̃ − P]Θ⁻¹ (eq. 18) with Θ = (m/5)SSᵀ (eq. 8);
//! - elastic stress P = ∂W/∂F from any hyperelastic energy W(F) (eq. 9) ([`material`]);
//! - fluid load P̃ = Jσ̃F⁻ᵀ (eq. 16) with the Jeffery–Roscoe traction σ̃ (eq. 12) ([`hydro::traction`]);
//! - barycentre: m v̇_c = m a_G + μ_f K̂(u − v_c) (eq. 13, 14, 17) with Brenner's K̂ ([`hydro::drag`]);
//! - the carrier flow supplies u and l_f = ∇u at x_c (Fig. 1) ([`flow`]);
//! - time stepping: the paper's IMEX scheme (§5) ([`integrator::imex`]) and faster variants.
//!
//! Units are the caller's: any consistent set works. [`particle::ShearScaling`] builds the
//! paper's nondimensional shear-flow particles (lengths d_eq, times 1/γ̇, stresses μ_f γ̇).

pub mod contact;
pub mod diagnostics;
pub mod driver;
pub mod ellipsoid;
pub mod error;
pub mod flow;
pub mod hydro;
pub mod integrator;
pub mod material;
pub mod output;
pub mod particle;
pub mod population;
pub mod reference;
pub mod scenes;
pub mod tensor;

/// The names most programs need.
pub mod prelude {
    pub use crate::ellipsoid::{Ellipsoid, EllipsoidIntegrals, PrincipalFrame};
    pub use crate::error::{FlowError, ParamError, StepError};
    pub use crate::flow::analytic::{LinearFlow, Poiseuille, Quiescent};
    pub use crate::flow::{FlowField, FlowSample};
    pub use crate::hydro::{Brenner, DragModel, JefferyRoscoe, StokesSphere, VolumetricTraction};
    pub use crate::integrator::{ImexPaper, StepInfo, TimeIntegrator};
    pub use crate::material::{Hyperelastic, MooneyRivlin, NeoHooke};
    pub use crate::particle::{Fluid, Particle, ShearScaling, State};
    pub use crate::tensor::{Mat3, Vec3};
}

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
//!
//! # Equation map
//! Where each equation of Wedel et al. lives (numbers as in the paper):
//!
//! | paper | what | item |
//! |---|---|---|
//! | eqs. 1–3 | affine motion x = x_c + F·Ξ, A = Ḟ | [`particle::State`] |
//! | eq. 4 | shape tensor S = Σ R_a E′_a ⊗ Ē_a | [`ellipsoid::Ellipsoid::shape_tensor`] |
//! | eq. 5 | total distortion F̄ = F·S | [`particle::Particle::total_distortion`] |
//! | eqs. 6, 7 | barycentre and shape balance | [`particle::dynamics`] |
//! | eq. 8 | mass m, Euler tensor Θ = (m/5)SSᵀ | [`particle::Particle::mass`], [`ellipsoid::Ellipsoid::euler_tensor`] |
//! | eq. 9 | Neo-Hooke Piola stress | [`material::NeoHooke`] (any law: [`material::Hyperelastic`]) |
//! | eqs. 10, 11, 15 | traction split; σ̃ as first moment of the traction | [`theory::traction`] |
//! | eq. 12 | Jeffery–Roscoe traction stress σ̃ | [`hydro::JefferyRoscoe::sigma_tilde`], [`theory::traction`] |
//! | eq. 13 | gravity reduced by buoyancy | [`hydro::gravity::reduced_gravity`] |
//! | eq. 14 | Brenner's drag | [`hydro::Brenner`], [`theory::drag`] |
//! | eq. 16 | fluid load P̃ = Jσ̃F⁻ᵀ | [`particle::dynamics::traction_load`] |
//! | eq. 17 | barycentre ODE (β_t, 1/τ_D = πμ_f r_min/m) | [`particle::Model::forcing`], [`particle::Forcing`] |
//! | eq. 18 | shape ODE Ȧ = vol(B₀)[P̃ − P]Θ⁻¹ | [`integrator::imex`]; Θ → 0: [`particle::Model::inertialess_rate`], [`particle::inertialess`] (right-hand side and Jacobian), [`integrator::stokesian`] |
//! | eqs. 19, 20 | implicit Euler for the barycentre | [`integrator::imex`] |
//! | eqs. 21, 22, §5 | the IMEX shape step | [`integrator::ImexPaper`], stability: [`theory::stability`], [`integrator::imex::stability`] |
//! | §5 | r_a, Q from eig(F̄F̄ᵀ) (r_a = √λ_a) | [`ellipsoid::PrincipalFrame`], [`theory::paper_errata`] |
//! | eqs. 23, 24 | capillary and shear Reynolds numbers | [`particle::ShearScaling`], [`diagnostics`] |
//! | eqs. 25, 26 | Stokes number, particle time | `studies::cavity` (feature `mesh`; the paper's values rechecked there) |
//! | eqs. A.1, A.2 | rotation Q, principal components X′ = QXQᵀ | [`ellipsoid::PrincipalFrame::to_principal`] |
//!
//! Jeffery's ellipsoid integrals behind eqs. 12 and 14: [`ellipsoid::integrals`],
//! [`theory::ellipsoid_integrals`].
//!
//! # Further reading
//! - [`theory`]: the derivations the code relies on, in closed form with their sources, and
//!   the paper's misprints and inconsistencies ([`theory::paper_errata`]).
//! - [`guide`]: add your own material law, drag model, force term, flow reader, boundary, integrator or study.
//! - Every model module opens with a *Physics* section: the equations, the paper's equation
//!   numbers, and the limits they are tested in.
//!
//! The formulas render with KaTeX on docs.rs; locally build with
//! `RUSTDOCFLAGS="--html-in-header docs/katex-header.html" cargo doc --no-deps`.

#![warn(missing_docs)]

#[cfg(feature = "cli")]
pub mod cli;
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
mod parallel;
pub mod particle;
#[cfg(feature = "parallel")]
pub mod population;
pub mod reference;
pub mod registry;
#[cfg(feature = "cli")]
pub mod scene;
pub mod studies;
pub mod tensor;

#[doc = include_str!("../docs/guide.md")]
pub mod guide {}

/// Derivations the code relies on, self-contained, with their literature sources: the closed
/// forms the paper defers to its predecessor, how they are evaluated, the stability of the
/// paper's time step, and the paper's misprints and inconsistencies.
pub mod theory {
    #[doc = include_str!("../docs/theory/traction.md")]
    pub mod traction {}
    #[doc = include_str!("../docs/theory/ellipsoid_integrals.md")]
    pub mod ellipsoid_integrals {}
    #[doc = include_str!("../docs/theory/drag.md")]
    pub mod drag {}
    #[doc = include_str!("../docs/theory/stability.md")]
    pub mod stability {}
    #[doc = include_str!("../docs/theory/paper_errata.md")]
    pub mod paper_errata {}
    #[doc = include_str!("../docs/theory/near_wall.md")]
    pub mod near_wall {}
}

/// The names most programs need.
pub mod prelude {
    pub use crate::ellipsoid::{Ellipsoid, EllipsoidIntegrals, PrincipalFrame};
    pub use crate::error::{FlowError, ParamError, StepError};
    pub use crate::flow::analytic::{LinearFlow, Poiseuille, Quiescent};
    pub use crate::flow::{FlowField, FlowSample};
    pub use crate::hydro::{Brenner, DragModel, JefferyRoscoe, StokesSphere, VolumetricTraction};
    pub use crate::integrator::{ImexPaper, StepInfo, Stokesian, TimeIntegrator};
    pub use crate::material::{Hyperelastic, MooneyRivlin, NeoHooke};
    pub use crate::particle::{Fluid, Particle, ShearScaling, State};
    pub use crate::tensor::{Mat3, Vec3};
}

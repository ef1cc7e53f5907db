//! Hyperelastic constitutive laws.
//!
//! A law is one stored-energy function W(F) per unit reference volume, written once generic
//! over num-dual scalars. The Piola stress P = ∂W/∂F and the tangent ∂P/∂F follow by automatic
//! differentiation; a law may override them with closed forms as an optimisation, which a test
//! must check against AD (see `tests/material.rs`).
//!
//! To add a law, implement [`Hyperelastic`] in one file and register it there by name
//! ([`registry`]) for scene files and Python (see the [guide](crate::guide)).
//!
//! # Physics (paper §2.4, eqs. 7, 9)
//! The particle's elastic response enters the shape equation (eq. 7, and eq. 18 after the
//! traction is inserted) only through the first Piola–Kirchhoff stress P = ∂W/∂F of a
//! homogeneous, hyperelastic solid. The paper uses the compressible Neo-Hooke law (eq. 9,
//! [`NeoHooke`]) "without loss of generality"; [`MooneyRivlin`] is a second law. A law must
//! leave F = 1 stress-free and be objective (W a function of C = FᵀF); its small-strain shear
//! modulus μ_s sets Ca = μ_f γ̇/μ_s (eq. 23), its λ_s the compressibility J − 1 = O(σ/λ_s).

pub mod expression;
pub mod mooney_rivlin;
pub mod neo_hooke;
pub mod registry;
pub mod response;

pub use expression::ExpressionLaw;
pub use mooney_rivlin::MooneyRivlin;
pub use neo_hooke::NeoHooke;
pub use registry::{LawRegistration, NamedLaw};
pub use response::{NoLaw, Response, Rigid, Softness};

use crate::tensor::{Mat3, Mat9, Scalar, mat3, vec9};
use nalgebra::{Const, SVector};
use num_dual::{Dual2Vec, DualVec, hessian};

/// A hyperelastic solid defined by its stored energy W(F).
pub trait Hyperelastic: Send + Sync {
    /// Stored energy per unit reference volume, W(F), for any num-dual scalar.
    fn energy<S: Scalar>(&self, f: &Mat3<S>) -> S;

    /// Small-strain shear modulus μ_s (used for Ca = μ_f γ̇ / μ_s).
    fn shear_modulus(&self) -> f64;

    /// Small-strain first Lamé parameter λ_s (bulk stiffness; J − 1 ~ stress/λ_s).
    fn lame_lambda(&self) -> f64;

    /// Whether W depends on F only through the invariants of C = FᵀF: material isotropy,
    /// W(F Q) = W(F) for every rotation Q. A sphere of such a law has no direction of its own,
    /// so its rotation on the slow manifold enters nothing the model sees
    /// ([`crate::particle::Particle::orientation_is_passive`]), and only such a law has the
    /// manifold's isotropic quasi-static stretch ([`crate::integrator::manifold`]). Default
    /// `false`: a law with fibres or other material directions keeps its particles' rotation
    /// in the error test and the full shape model.
    fn is_isotropic(&self) -> bool {
        false
    }

    /// First Piola–Kirchhoff stress P = ∂W/∂F (by AD unless overridden).
    fn piola(&self, f: &Mat3) -> Mat3 {
        piola_ad(self, f)
    }

    /// Tangent ∂P_iJ/∂F_kL as a 9×9 matrix on column-major flattened tensors (AD by default).
    fn tangent(&self, f: &Mat3) -> Mat9 {
        tangent_ad(self, f)
    }

    /// Cauchy stress σ_el = P Fᵀ / J.
    fn cauchy(&self, f: &Mat3) -> Mat3 {
        self.piola(f) * f.transpose() / f.determinant()
    }
}

/// What the solvers ask of a law: the stress P and its tangent at a real F, W(F), and the
/// small-strain moduli. Unlike [`Hyperelastic`] it has no generic method, so a law chosen by
/// name at run time ([`NamedLaw`]) is one; every [`Hyperelastic`] law is one.
pub trait StressLaw: Send + Sync {
    /// W(F) per unit reference volume.
    fn energy_at(&self, f: &Mat3) -> f64;
    /// First Piola–Kirchhoff stress P = ∂W/∂F.
    fn piola(&self, f: &Mat3) -> Mat3;
    /// Tangent ∂P/∂F (9×9, column-major flattened tensors).
    fn tangent(&self, f: &Mat3) -> Mat9;
    /// Cauchy stress σ_el = P Fᵀ / J.
    fn cauchy(&self, f: &Mat3) -> Mat3;
    /// Small-strain shear modulus μ_s.
    fn shear_modulus(&self) -> f64;
    /// Small-strain first Lamé parameter λ_s.
    fn lame_lambda(&self) -> f64;
    /// Material isotropy ([`Hyperelastic::is_isotropic`]).
    fn is_isotropic(&self) -> bool;
}

impl<M: Hyperelastic> StressLaw for M {
    fn energy_at(&self, f: &Mat3) -> f64 {
        self.energy(f)
    }
    fn piola(&self, f: &Mat3) -> Mat3 {
        Hyperelastic::piola(self, f)
    }
    fn tangent(&self, f: &Mat3) -> Mat9 {
        Hyperelastic::tangent(self, f)
    }
    fn cauchy(&self, f: &Mat3) -> Mat3 {
        Hyperelastic::cauchy(self, f)
    }
    fn shear_modulus(&self) -> f64 {
        Hyperelastic::shear_modulus(self)
    }
    fn lame_lambda(&self) -> f64 {
        Hyperelastic::lame_lambda(self)
    }
    fn is_isotropic(&self) -> bool {
        Hyperelastic::is_isotropic(self)
    }
}

/// Builds a law from the small-strain moduli a scene prescribes: shear modulus μ_s (= 1/Ca in
/// the shear-flow units) and first Lamé parameter λ_s. Scenes take a factory, so the paper's
/// studies run with any law without a scene edit.
pub trait LawFactory: Send + Sync {
    /// The law built.
    type Law: Hyperelastic;

    /// The law with small-strain moduli μ_s and λ_s.
    fn law(&self, mu_s: f64, lambda_s: f64) -> Result<Self::Law, crate::error::ParamError>;
}

/// Builds [`NeoHooke`] laws (the paper's eq. 9).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NeoHookeFactory;

impl LawFactory for NeoHookeFactory {
    type Law = NeoHooke;

    fn law(&self, mu_s: f64, lambda_s: f64) -> Result<NeoHooke, crate::error::ParamError> {
        NeoHooke::new(mu_s, lambda_s)
    }
}

/// Builds [`MooneyRivlin`] laws with μ₁ = (1 − β)μ_s and μ₂ = βμ_s, whose small-strain shear
/// modulus is μ₁ + μ₂ = μ_s; β = 0 is Neo-Hooke-like.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MooneyRivlinFactory {
    /// Share β ∈ [0, 1] of the second invariant.
    pub beta: f64,
}

impl LawFactory for MooneyRivlinFactory {
    type Law = MooneyRivlin;

    fn law(&self, mu_s: f64, lambda_s: f64) -> Result<MooneyRivlin, crate::error::ParamError> {
        if !(0.0..=1.0).contains(&self.beta) {
            return Err(crate::error::ParamError::OutOfRange {
                name: "Mooney-Rivlin share beta",
                value: self.beta,
                min: 0.0,
                max: 1.0,
            });
        }
        MooneyRivlin::new((1.0 - self.beta) * mu_s, self.beta * mu_s, lambda_s)
    }
}

/// P = ∂W/∂F by forward-mode AD (nine dual directions).
pub fn piola_ad<M: Hyperelastic + ?Sized>(law: &M, f: &Mat3) -> Mat3 {
    let (_, g) = num_dual::gradient(|v: SVector<DualVec<f64, Const<9>>, 9>| law.energy(&mat3(&v)), &vec9(f));
    mat3(&g)
}

/// ∂P/∂F = ∂²W/∂F∂F by second-order AD.
pub fn tangent_ad<M: Hyperelastic + ?Sized>(law: &M, f: &Mat3) -> Mat9 {
    let (_, _, h) = hessian(|v: SVector<Dual2Vec<f64, Const<9>>, 9>| law.energy(&mat3(&v)), &vec9(f));
    h
}

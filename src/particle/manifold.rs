//! The slow manifold of a stiff elastic particle: its shape as a function of its rotation and
//! the local velocity gradient, for the reduced model of
//! [`crate::integrator::manifold`]. Part of the model's equations beside
//! [`super::inertialess`], whose balance it expands.
//!
//! # Physics (paper eq. 18 with Θ → 0, expanded in the relaxation time)
//! Write the deformation as a stretch of the rotated rest shape, F = V R with V = 1 + ε, ε
//! symmetric and traceless (the particle is incompressible, tr l_s = 0). The inertialess
//! balance σ̃(l_s) = σ_el(F) (eq. 18 with Θ → 0) is affine in l_s, so with the rigid body's
//! spin Ω (Jeffery's torque-free rate of the rest shape turned by R) and its interior stress
//! σ̃_r = σ̃(Ω),
//! ```math
//! l_s = \Omega + \mathcal{G}\,(\sigma_\text{el} - \tilde\sigma_r), \qquad
//! \operatorname{sym} l_s = \mathring\varepsilon = \dot\varepsilon + \varepsilon\,\Omega - \Omega\,\varepsilon + O(\varepsilon^2),
//! ```
//! with 𝒢 the inverse of σ̃'s linear part ([`crate::hydro::InertialessSolver`]) and ε̊ the
//! corotational rate of the stretch. Its symmetric part, ℳ = sym 𝒢 on deviatoric symmetric
//! stresses (five dimensions), is negative definite: ε relaxes at the rates of
//! −2μ_s ℳ, at least at the smallest eigenvalue of its symmetric part, the relaxation rate
//! k ([`SlowManifold::relaxation_rate`];
//! k = 2μ_s/(3μ_f) for a sphere, where σ̃ = 5μ_f d_f − 3μ_f d_s + ...). With σ_el = 2μ_s ε +
//! O(ε²) (the small-strain shear modulus) the shape follows the flow on the manifold
//! ```math
//! \varepsilon = \varepsilon_0 + \frac{\mathcal{M}^{-1}\mathring\varepsilon_0}{2\mu_s} + O(\delta^2),
//! \qquad \varepsilon_0 = \frac{\operatorname{dev}\tilde\sigma_r}{2\mu_s},
//! ```
//! the quasi-static shape ε₀ = O(|∇u|/k) (the stretch whose elastic stress carries the rigid
//! body's interior stress) and its first correction in the relaxation time, the lag behind a
//! flow that turns against the particle or changes along the path (ε̊₀ = O(ε₀ ω), so the
//! correction is O(ε₀ ω/k)), with
//! ```math
//! \delta = \frac{\max\left(|\nabla u|,\ |\mathrm{d}\nabla u/\mathrm{d}t|^{1/2}\right)}{k}
//! ```
//! ([`SlowManifold::ratio`]). The terms dropped are O(δ²) in F at the given rotation: the
//! elastic and geometric nonlinearities O(ε₀²) and the next term of the expansion
//! O(ε₀ (ω/k)²). The rotation turns at the rigid body's spin Ω for a sphere and at the
//! deformed particle's ([`DeformedSpin`], O(δ |∇u|) off Ω) for a non-sphere, with an error
//! O(δ² |∇u|) ([`crate::integrator::manifold`], section Non-spheres). For a sphere in
//! simple shear (Ca = μ_f γ̇/μ_s, k = 2/(3 Ca) γ̇, Ω the vorticity) ε₀ = (5 Ca/2) E/γ̇ and the
//! correction tilts it by −3Ca/4: Taylor's deformation D = 5Ca/4 and the inclination
//! θ = π/4 − 3Ca/4, the small-Ca limit of Roscoe's (1967) steady state (Gao, Hu & Ponte
//! Castañeda 2011 for neo-Hookean spheres), which the tests check against the closed form.

use super::{Geometry, Particle};
use crate::ellipsoid::PrincipalFrame;
use crate::error::{ParamError, StepError};
use crate::hydro::{DragModel, InertialessSolver, VolumetricTraction, jeffery_spin};
use crate::material::{Response, StressLaw};
use crate::tensor::{Mat3, dev, sym};
use nalgebra::{SMatrix, SVector};

/// An orthonormal basis (Frobenius) of the deviatoric symmetric 3×3 matrices.
fn basis() -> [Mat3; 5] {
    let r2 = std::f64::consts::SQRT_2;
    let r6 = 6.0_f64.sqrt();
    let pair = |i: usize, j: usize| {
        let mut m = Mat3::zeros();
        m[(i, j)] = 1.0 / r2;
        m[(j, i)] = 1.0 / r2;
        m
    };
    [
        Mat3::from_diagonal(&crate::tensor::Vec3::new(1.0 / r2, -1.0 / r2, 0.0)),
        Mat3::from_diagonal(&crate::tensor::Vec3::new(1.0 / r6, 1.0 / r6, -2.0 / r6)),
        pair(0, 1),
        pair(0, 2),
        pair(1, 2),
    ]
}

fn coordinates(m: &Mat3) -> SVector<f64, 5> {
    let b = basis();
    SVector::<f64, 5>::from_fn(|a, _| b[a].dot(m))
}

/// ℳ = sym 𝒢 in [`basis`] coordinates: the strain rate a deviatoric stress increment drives.
fn strain_response(solver: &InertialessSolver) -> SMatrix<f64, 5, 5> {
    let b = basis();
    let mut m = SMatrix::<f64, 5, 5>::zeros();
    for (col, e) in b.iter().enumerate() {
        m.set_column(col, &coordinates(&sym(&solver.velocity_gradient_increment(e))));
    }
    m
}

/// The constants of a stiff elastic particle's slow manifold (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlowManifold {
    rate: f64,
    mu_s: f64,
}

/// A point of the slow manifold: the rigid body's spin and quasi-static strain at one rotation
/// and velocity gradient, with the strain response that corrects it.
#[derive(Debug, Clone)]
pub struct QuasiStatic {
    /// The rigid body's spin Ω (Jeffery's torque-free rate).
    pub spin: Mat3,
    /// The quasi-static strain ε₀ = dev σ̃_r/(2μ_s).
    pub strain: Mat3,
    response: SMatrix<f64, 5, 5>,
}

impl SlowManifold {
    /// The manifold of `particle`, or `None` for a rigid one. The relaxation rate k is the
    /// slowest rate of −2μ_s ℳ at the rest shape, bounded from below by the smallest
    /// eigenvalue of its symmetric part (the same at every rotation, since ℳ turns with the
    /// particle).
    pub fn of<M: Response, D: DragModel>(particle: &Particle<M, D>) -> Result<Option<Self>, ParamError> {
        let Some(law) = particle.elastic() else {
            return Ok(None);
        };
        let mu_s = law.shear_modulus();
        let rest = particle.rest_geometry();
        let solver = rest
            .traction
            .inertialess(&Mat3::zeros(), particle.fluid().mu)
            .ok_or(ParamError::Derived {
                name: "rest inertialess traction operator",
                value: f64::NAN,
                inputs: particle.shape().semi_axes().iter().copied().collect(),
            })?;
        // The symmetric part's smallest eigenvalue: |ε| decays at least at this rate,
        // d|ε|²/dt = −2 ε·(Aε) ≤ −2 λ_min(sym A) |ε|² (A = −2μ_s ℳ); it is the rate itself where
        // A is symmetric (the sphere). A symmetric eigen-solver always converges, where a
        // general one (Schur) need not.
        let a = strain_response(&solver) * (-2.0 * mu_s);
        let rate = ((a + a.transpose()) * 0.5).symmetric_eigenvalues().min();
        if !(rate > 0.0 && rate.is_finite()) {
            return Err(ParamError::Derived {
                name: "elastic relaxation rate k",
                value: rate,
                inputs: vec![mu_s, particle.fluid().mu],
            });
        }
        Ok(Some(Self { rate, mu_s }))
    }

    /// The slowest elastic relaxation rate k (1/time).
    pub fn relaxation_rate(&self) -> f64 {
        self.rate
    }

    /// δ = max(|∇u|, |d∇u/dt|^½)/k for the velocity gradient `l_f` (Frobenius norm) changing
    /// along the path at the rate `l_f_rate` (Frobenius norm of d∇u/dt): the expansion's small
    /// parameter (module docs).
    pub fn ratio(&self, l_f: &Mat3, l_f_rate: f64) -> f64 {
        l_f.norm().max(l_f_rate.sqrt()) / self.rate
    }

    /// The quasi-static point at the rotation `rotation` in the velocity gradient `l_f` at
    /// time `t` (for errors).
    pub fn quasi_static<M: Response, D: DragModel>(
        &self,
        particle: &Particle<M, D>,
        rotation: &Mat3,
        l_f: &Mat3,
        t: f64,
    ) -> Result<QuasiStatic, StepError> {
        let geo = particle.rest_geometry().turned(rotation);
        let mu_f = particle.fluid().mu;
        let spin = jeffery_spin(&geo.frame, l_f);
        let sigma = geo.traction.sigma_tilde(&spin, l_f, mu_f, particle.volumetric());
        let solver = geo.traction.inertialess(l_f, mu_f).ok_or(StepError::NonFinite {
            what: "inertialess traction operator",
            t,
        })?;
        Ok(QuasiStatic {
            spin,
            strain: dev(&sigma) / (2.0 * self.mu_s),
            response: strain_response(&solver),
        })
    }

    /// The stretch V = 1 + ε on the manifold at the point `q`, with ε₀ changing at the rate
    /// `strain_rate` (dε₀/dt along the path, lab frame), scaled to det V = 1 (module docs).
    pub fn stretch(&self, q: &QuasiStatic, strain_rate: &Mat3, t: f64) -> Result<Mat3, StepError> {
        let corotational = strain_rate + q.strain * q.spin - q.spin * q.strain;
        let c = q
            .response
            .lu()
            .solve(&coordinates(&sym(&corotational)))
            .ok_or(StepError::NonFinite {
                what: "slow-manifold strain response",
                t,
            })?;
        let correction = basis()
            .iter()
            .zip(c.iter())
            .fold(Mat3::zeros(), |acc, (e, c)| acc + e * *c);
        let v = Mat3::identity() + q.strain + correction / (2.0 * self.mu_s);
        let det = v.determinant();
        if !(det > 0.0 && det.is_finite()) {
            return Err(StepError::Inverted { det_f: det, t });
        }
        Ok(v / det.cbrt())
    }
}

/// The spin of the deformed particle on the manifold, to first order in δ, for the rigid twin
/// that turns it ([`Particle::manifold_twin`]). With F = V R, Ṙ Rᵀ = skw l_s + O(δ² |∇u|), and
/// the torque balance skw σ̃ = 0 of eq. 12 ([`crate::hydro::traction`]: in the principal frame
/// s_ij − s_ji = (c^d_ij − c^d_ji) d_ij + (c^w_ij + c^w_ji) w_ij with g = l_f − l_s) gives
/// (ω_f − ω_s)_ij = (x_i − x_j)/(x_i + x_j) (d_f − d_s)_ij, x_i the squared semi-axes of the
/// current ellipsoid (Jeffery 1922 for d_s = 0; Roscoe 1967 for a deforming surface):
/// ```math
/// W = \operatorname{Jeffery}\big(V R S,\; l_f - \mathring\varepsilon_0\big), \qquad
/// \mathring\varepsilon_0 = \varepsilon_0\big(R,\; \dot l_f + l_f\,\Omega - \Omega\, l_f\big),
/// ```
/// [`jeffery_spin`] of the ellipsoid F S with the manifold's stretch V = 1 + ε₀ + ℳ⁻¹ε̊₀/(2μ_s)
/// (module docs), in the gradient less the particle's own strain rate d_s = ε̊. At a fixed R
/// the quasi-static strain ε₀ = dev σ̃(Ω, l_f)/(2μ_s) is linear in l_f (Ω is), and it turns
/// with R, so its corotational rate is ε₀ of the corotational rate of l_f. Dropped: ε̊ − ε̊₀
/// and the terms of V and of Ṙ Rᵀ − skw l_s quadratic in ε, so W − Ṙ Rᵀ = O(δ² |∇u|); V = 1 + ε₀
/// alone would do as much, but was measured 1.6× further off along Jeffery's orbits
/// ([`crate::integrator::manifold`], section Non-spheres).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeformedSpin {
    /// The small-strain shear modulus μ_s.
    pub mu_s: f64,
    /// d∇u/dt along the path, held over the step.
    pub gradient_rate: Mat3,
}

impl DeformedSpin {
    /// The spin W at the rotation `rotation` whose rest geometry turned is `geo`, for the shape
    /// tensor `shape` (S) in the flow gradient `l_f`, fluid viscosity `mu_f`.
    pub fn spin(
        &self,
        geo: &Geometry,
        rotation: &Mat3,
        shape: &Mat3,
        l_f: &Mat3,
        mu_f: f64,
        vol: VolumetricTraction,
    ) -> Mat3 {
        let strain = |l: &Mat3| {
            let w = jeffery_spin(&geo.frame, l);
            dev(&geo.traction.sigma_tilde(&w, l, mu_f, vol)) / (2.0 * self.mu_s)
        };
        let omega = jeffery_spin(&geo.frame, l_f);
        let own = strain(&(self.gradient_rate + l_f * omega - omega * l_f));
        let lag = geo
            .traction
            .inertialess(l_f, mu_f)
            .and_then(|solver| strain_response(&solver).lu().solve(&coordinates(&sym(&own))))
            .map_or(Mat3::zeros(), |c| {
                basis()
                    .iter()
                    .zip(c.iter())
                    .fold(Mat3::zeros(), |acc, (e, c)| acc + e * *c)
                    / (2.0 * self.mu_s)
            });
        let deformed = (Mat3::identity() + strain(l_f) + lag) * rotation * shape;
        jeffery_spin(&PrincipalFrame::from_total_distortion(&deformed), &(l_f - own))
    }
}

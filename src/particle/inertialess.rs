//! The inertialess model's equations: the right-hand side y′ = f(t, y) of the state
//! y = (F, x, v) ∈ ℝ¹⁵ and its (W-method) Jacobian, which [`crate::integrator::Stokesian`]
//! advances by Radau IIA or Rosenbrock-W. Part of the model's equations beside
//! [`super::dynamics`], whose pieces it assembles.
//!
//! # Physics (paper eq. 18 in the limit Θ → 0, eq. 17)
//! For a micro-particle Θ ∝ ρ* is negligible and eq. 18 degenerates to the balance P̃ = P,
//! i.e. σ̃(l_s) = σ_el(F) with σ_el = P Fᵀ/J; with tr l_s = 0 (incompressible particle) this
//! is the 9×9 linear system of [`InertialessSolver`], and the shape evolves by Ḟ = l_s(F) F
//! ([`Model::inertialess_rate`]). A rigid particle spins with Jeffery's torque-free rate. The
//! barycentre is inertial (eq. 17), v̇ = a_G + R(u − v), ẋ = v; overdamped (St → 0),
//! ẋ = u + R⁻¹a_G; or at its equilibrium velocity to first order in the response time,
//! ẋ = u + R⁻¹(a_G − Du/Dt); with the drag rate R = μ_f K̂/m ([`BarycentreModel`]).
//!
//! # Jacobian
//! Exact in the elastic response and frozen in the hydrodynamic operator: with the principal
//! frame, the integrals and the factorised operator of σ̃ held at the evaluation point,
//! ```math
//! \delta\sigma_\text{el} = \frac{\delta P\,F^T + P\,\delta F^T}{J} - \sigma_\text{el}\,\operatorname{tr}(F^{-1}\delta F),
//! \qquad \delta\dot F = \delta l_s\,F + l_s\,\delta F,
//! ```
//! with δP from the material tangent and δl_s from [`InertialessSolver`]; for a rigid particle
//! the spin is frozen, δḞ = l_s δF. The barycentre block is ∂ẋ/∂v = 1, ∂v̇/∂x = R l_f,
//! ∂v̇/∂v = −R (inertial) or ∂ẋ/∂x = l_f (overdamped and equilibrium). Radau IIA's order does not depend on the
//! Jacobian and the Rosenbrock-W pair keeps its order with such an approximation
//! ([`crate::integrator::stokesian`]).
//!
//! [`InertialessSolver`]: crate::hydro::InertialessSolver

use super::dynamics::Model;
use crate::ellipsoid::PrincipalFrame;
use crate::error::{ParamError, StepError};
use crate::flow::{FlowField, FlowSample};
use crate::hydro::forces::{FLUID_INERTIA, ForceTerms};
use crate::hydro::{DragModel, InertialessSolver};
use crate::material::{Response, StressLaw};
use crate::tensor::{Mat3, Vec3, inv_transpose, mat3, vec9};
use nalgebra::{SMatrix, SVector};

/// The inertialess state y = (vec F, x, v).
pub type InertialessState = SVector<f64, 15>;
/// The tensor and vectors of an [`InertialessState`]: vec F, x, v. An error norm that measures
/// each as a whole does not depend on the orientation of the lab frame
/// ([`crate::integrator::control::ErrorNorm`]).
pub const STATE_BLOCKS: [std::ops::Range<usize>; 3] = [0..9, 9..12, 12..15];
/// ∂f/∂y of the inertialess right-hand side (module docs), block-diagonal: with the
/// hydrodynamic operator frozen, Ḟ does not depend on (x, v) and (ẋ, v̇) not on F, so the
/// shape block (9×9) and the barycentre block (6×6) are all there is. A rigid particle's shape
/// block is the frozen spin acting on each column of δF, δḞ = l_s δF.
#[derive(Debug, Clone)]
pub struct InertialessJacobian {
    /// ∂Ḟ/∂F.
    pub shape: ShapeJacobian,
    /// ∂(ẋ, v̇)/∂(x, v).
    pub barycentre: BarycentreJacobian,
}

/// The barycentre block ∂(ẋ, v̇)/∂(x, v) of an [`InertialessJacobian`], by its 3×3 blocks.
#[derive(Debug, Clone, Copy)]
pub enum BarycentreJacobian {
    /// Inertial (eq. 17): ∂ẋ/∂x = 0, ∂ẋ/∂v = 1, ∂v̇/∂x = A = R l_f, ∂v̇/∂v = −R (R the drag rate).
    Inertial {
        /// A = R l_f.
        coupling: Mat3,
        /// R.
        drag_rate: Mat3,
    },
    /// Overdamped or equilibrium: ∂ẋ/∂x = l_f, and v is not integrated (its rows are zero).
    Drift(Mat3),
}

impl BarycentreJacobian {
    /// The 6×6 block.
    pub fn block(&self) -> SMatrix<f64, 6, 6> {
        let mut jac = SMatrix::<f64, 6, 6>::zeros();
        match self {
            BarycentreJacobian::Inertial { coupling, drag_rate } => {
                jac.fixed_view_mut::<3, 3>(0, 3).copy_from(&Mat3::identity());
                jac.fixed_view_mut::<3, 3>(3, 0).copy_from(coupling);
                jac.fixed_view_mut::<3, 3>(3, 3).copy_from(&(-drag_rate));
            }
            BarycentreJacobian::Drift(l_f) => {
                jac.fixed_view_mut::<3, 3>(0, 0).copy_from(l_f);
            }
        }
        jac
    }
}

/// The shape block ∂ vec Ḟ/∂ vec F of an [`InertialessJacobian`].
#[derive(Debug, Clone)]
// One per step, on the stack: boxing the larger variant would allocate in every step.
#[allow(clippy::large_enum_variant)]
pub enum ShapeJacobian {
    /// δḞ = l_s δF (rigid: the spin frozen over the step): the 9×9 block is 1₃ ⊗ l_s.
    Spin(Mat3),
    /// The full 9×9 block (elastic).
    Full(SMatrix<f64, 9, 9>),
}

impl ShapeJacobian {
    /// The 9×9 block.
    pub fn block(&self) -> SMatrix<f64, 9, 9> {
        match self {
            ShapeJacobian::Spin(l_s) => {
                let mut block = SMatrix::<f64, 9, 9>::zeros();
                for c in 0..3 {
                    block.fixed_view_mut::<3, 3>(3 * c, 3 * c).copy_from(l_s);
                }
                block
            }
            ShapeJacobian::Full(block) => *block,
        }
    }
}

impl InertialessJacobian {
    /// The 15×15 matrix.
    pub fn dense(&self) -> SMatrix<f64, 15, 15> {
        let mut jac = SMatrix::<f64, 15, 15>::zeros();
        jac.fixed_view_mut::<9, 9>(0, 0).copy_from(&self.shape.block());
        jac.fixed_view_mut::<6, 6>(9, 9).copy_from(&self.barycentre.block());
        jac
    }
}

/// How the barycentre moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BarycentreModel {
    /// m v̇ = m a_G + μ_f K̂ (u − v), ẋ = v.
    #[default]
    Inertial,
    /// St → 0: ẋ = u + (μ_f K̂/m)⁻¹ a_G; v is reported as that velocity.
    Overdamped,
    /// The equilibrium velocity to first order in the response time τ = ‖R⁻¹‖ (Maxey 1987,
    /// *J. Fluid Mech.* 174; Ferry & Balachandar 2001, *Int. J. Multiphase Flow* 27):
    /// ```math
    /// \dot x = u + R^{-1}\left(a - \frac{Du}{Dt}\right) + O(\tau^2),
    /// \qquad \frac{Du}{Dt} = \partial_t u + (u\cdot\nabla)u .
    /// ```
    /// Eq. 17 reads v = u + R⁻¹(a − v̇); along the path v̇ = ∂_t u + (v·∇)u + O(τ) and
    /// v − u = O(τ), so v̇ = Du/Dt + O(τ), and the neglected terms (including Ṙ, the drag
    /// tensor turning with the particle) are O(τ²). The slip, and so the inertial drift that
    /// deposits particles by impaction, is kept to first order, where [`Self::Overdamped`]
    /// drops it; the stiff relaxation of v towards u, which sets the steps of [`Self::Inertial`]
    /// at small τ, is gone. The velocity error is O(St²) of the flow speed, with St the
    /// response time over the flow's time scale; `v` is reported as ẋ.
    Equilibrium,
}

impl BarycentreModel {
    /// Refuse the force terms `forces` this model contradicts: an overdamped barycentre drops
    /// the particle's inertia (v̇ = 0), so it cannot keep the fluid's
    /// ([`crate::hydro::forces::FLUID_INERTIA`]: same order, ρ_f/ρ_p;
    /// [`ParamError::OverdampedFluidInertia`] says why). The equilibrium barycentre keeps
    /// both to first order in the response time (v̇ = Du/Dt), and the inertial one both in
    /// full, so they take every term.
    pub fn admits(&self, forces: &ForceTerms) -> Result<(), ParamError> {
        match (self, forces.names().into_iter().find(|n| FLUID_INERTIA.contains(n))) {
            (BarycentreModel::Overdamped, Some(term)) => Err(ParamError::OverdampedFluidInertia { term }),
            _ => Ok(()),
        }
    }
}

/// y = (vec F, x, v).
pub fn pack(f: &Mat3, x: &Vec3, v: &Vec3) -> InertialessState {
    let mut y = InertialessState::zeros();
    y.fixed_rows_mut::<9>(0).copy_from(&vec9(f));
    y.fixed_rows_mut::<3>(9).copy_from(x);
    y.fixed_rows_mut::<3>(12).copy_from(v);
    y
}

/// (F, x, v) of y (or (Ḟ, ẋ, v̇) of y′).
pub fn unpack(y: &InertialessState) -> (Mat3, Vec3, Vec3) {
    (
        mat3(&y.fixed_rows::<9>(0).into_owned()),
        y.fixed_rows::<3>(9).into_owned(),
        y.fixed_rows::<3>(12).into_owned(),
    )
}

/// Everything the right-hand side computes at one state, kept for the Jacobian there.
#[derive(Debug, Clone)]
pub struct InertialessRate {
    f_dot: Mat3,
    l_s: Mat3,
    x_dot: Vec3,
    v_dot: Vec3,
    drag_rate: Mat3,
    /// The flow at the barycentre, and the principal frame of F, at the evaluated (t, y): what
    /// an accepted step carries of its end state ([`crate::integrator::EndEvaluation`]).
    sample: FlowSample,
    frame: PrincipalFrame,
    /// `None` in the rigid limit.
    solver: Option<InertialessSolver>,
}

impl InertialessRate {
    /// y′ = (vec Ḟ, ẋ, v̇).
    pub fn vector(&self) -> InertialessState {
        pack(&self.f_dot, &self.x_dot, &self.v_dot)
    }

    /// Ḟ = l_s F.
    pub fn f_dot(&self) -> Mat3 {
        self.f_dot
    }

    /// ẋ.
    pub fn x_dot(&self) -> Vec3 {
        self.x_dot
    }

    /// v̇.
    pub fn v_dot(&self) -> Vec3 {
        self.v_dot
    }

    /// The particle's velocity gradient l_s (Ḟ = l_s F).
    pub fn l_s(&self) -> Mat3 {
        self.l_s
    }

    /// The flow's velocity gradient l_f = ∇u at the barycentre.
    pub fn l_f(&self) -> Mat3 {
        self.sample.grad_u
    }

    /// The flow sampled at the barycentre.
    pub fn sample(&self) -> &FlowSample {
        &self.sample
    }

    /// The principal frame of the evaluated F.
    pub fn frame(&self) -> &PrincipalFrame {
        &self.frame
    }
}

impl<M: Response, D: DragModel, F: FlowField + ?Sized> Model<'_, M, D, F> {
    /// The inertialess right-hand side at (t, y): one model evaluation.
    pub fn inertialess(
        &self,
        barycentre: BarycentreModel,
        t: f64,
        y: &InertialessState,
    ) -> Result<InertialessRate, StepError> {
        let (f, x, v) = unpack(y);
        let geo = self.geometry(&f, t)?;
        let sample = self.sample(&x, t)?;
        let (l_s, solver) = self.inertialess_rate(&geo, &f, &sample.grad_u, t)?;
        let forcing = self.forcing(&geo, f.determinant(), &sample, &v, t)?;
        let (x_dot, v_dot) = match barycentre {
            BarycentreModel::Inertial => (v, forcing.acceleration(&sample.u, &v)),
            BarycentreModel::Overdamped => (
                self.overdamped_velocity(&geo, f.determinant(), &sample, &forcing, &Vec3::zeros(), t)?,
                Vec3::zeros(),
            ),
            BarycentreModel::Equilibrium => (
                self.overdamped_velocity(
                    &geo,
                    f.determinant(),
                    &sample,
                    &forcing,
                    &sample.material_acceleration(),
                    t,
                )?,
                Vec3::zeros(),
            ),
        };
        Ok(InertialessRate {
            f_dot: l_s * f,
            l_s,
            x_dot,
            v_dot,
            drag_rate: forcing.drag_rate,
            sample,
            frame: geo.frame,
            solver,
        })
    }

    /// W-method Jacobian at y from the evaluation `e` there (module docs): exact elastic part,
    /// frozen hydrodynamic operator, linear-flow coupling of the barycentre. Counted.
    pub fn inertialess_jacobian(
        &self,
        barycentre: BarycentreModel,
        y: &InertialessState,
        e: &InertialessRate,
    ) -> InertialessJacobian {
        self.count_jacobian();
        let barycentre = barycentre_jacobian(barycentre, e);
        let Some(solver) = &e.solver else {
            // Rigid: d(W_s F) ≈ W_s dF with the spin frozen over the step (W-method).
            return InertialessJacobian {
                shape: ShapeJacobian::Spin(e.l_s),
                barycentre,
            };
        };
        let Some(law) = self.particle.elastic() else {
            unreachable!("an evaluation with an inertialess solver belongs to an elastic particle")
        };
        let (f, _, _) = unpack(y);
        let det_f = f.determinant();
        let p = law.piola(&f);
        let sigma = p * f.transpose() / det_f;
        let tangent = law.tangent(&f);
        let f_inv_t = inv_transpose(&f);
        let mut block = SMatrix::<f64, 9, 9>::zeros();
        for q in 0..9 {
            let mut df = Mat3::zeros();
            df[q] = 1.0;
            let dp = mat3(&tangent.column(q).into_owned());
            // δσ = (δP Fᵀ + P δFᵀ)/J − σ tr(F⁻¹δF)
            let d_sigma = (dp * f.transpose() + p * df.transpose()) / det_f - sigma * f_inv_t[q];
            let dl_s = solver.velocity_gradient_increment(&d_sigma);
            block.column_mut(q).copy_from(&vec9(&(dl_s * f + e.l_s * df)));
        }
        InertialessJacobian {
            shape: ShapeJacobian::Full(block),
            barycentre,
        }
    }
}

/// ∂(ẋ, v̇)/∂(x, v): ∂ẋ/∂v = 1, ∂v̇/∂x = R l_f, ∂v̇/∂v = −R (inertial), or ∂ẋ/∂x = l_f.
fn barycentre_jacobian(model: BarycentreModel, e: &InertialessRate) -> BarycentreJacobian {
    match model {
        BarycentreModel::Inertial => BarycentreJacobian::Inertial {
            coupling: e.drag_rate * e.l_f(),
            drag_rate: e.drag_rate,
        },
        // The drift R⁻¹(a − Du/Dt) varies with x on the flow's scale, τ times slower than u.
        BarycentreModel::Overdamped | BarycentreModel::Equilibrium => BarycentreJacobian::Drift(e.l_f()),
    }
}

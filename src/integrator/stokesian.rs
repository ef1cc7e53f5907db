//! Inertialess (Stokesian) shape dynamics with adaptive Rosenbrock stepping.
//!
//! # Physics (physics.md §9.5, §9.7)
//! For a micro-particle Θ ∝ ρ* is negligible and eq. 18 degenerates to the balance P̃ = P,
//! i.e. σ̃(l_s) = σ_el(F) with σ_el = P Fᵀ/J. With tr l_s = 0 (incompressible particle) this is
//! the 9×9 linear system of [`InertialessSolver`], and the shape evolves by Ḟ = l_s(F) F.
//! The barycentre is either inertial, m v̇ = m a_G + μ_f K̂(u − v), ẋ = v, or overdamped
//! (St → 0), ẋ = u + (μ_f K̂/m)⁻¹ a_G.
//!
//! # Scheme
//! The state y = (F, x, v) ∈ ℝ¹⁵ is advanced by the L-stable Rosenbrock-W 2(3) pair
//! ([`super::rosenbrock`]). The Jacobian is exact (num-dual tangent of W) in the elastic
//! response and freezes the principal frame and integrals of the hydrodynamic operator for
//! the step; the W-method keeps order 2 with such an approximation (tested).
//!
//! Stiffness: the elastic relaxation rate is ~μ_s/μ_f = 1/Ca, the drag rate 1/τ_D; both are
//! handled implicitly, so Δt follows accuracy, not ρ*.
//!
//! [`InertialessSolver`]: crate::hydro::InertialessSolver

use super::rosenbrock::{self, Tolerances};
use super::{StepInfo, TimeIntegrator};
use crate::error::StepError;
use crate::flow::FlowField;
use crate::hydro::DragModel;
use crate::hydro::gravity::reduced_gravity;
use crate::material::Hyperelastic;
use crate::particle::{Particle, State};
use crate::tensor::{Mat3, Vec3, inv_transpose, mat3, vec9};
use nalgebra::{SMatrix, SVector};

type Y = SVector<f64, 15>;
type Jac = SMatrix<f64, 15, 15>;

/// How the barycentre moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BarycentreModel {
    /// m v̇ = m a_G + μ_f K̂ (u − v), ẋ = v.
    #[default]
    Inertial,
    /// St → 0: ẋ = u + (μ_f K̂/m)⁻¹ a_G; v is reported as that velocity.
    Overdamped,
}

/// How the shape responds to the flow.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ShapeResponse {
    /// Elastic and inertialess: σ̃(l_s) = σ_el(F), tr l_s = 0.
    #[default]
    Elastic,
    /// Rigid limit Ca = 0: F stays a rotation spinning at Jeffery's torque-free rate,
    /// w_s,ij = w_f,ij − ((x_i − x_j)/(x_i + x_j)) d_f,ij in the principal frame (Jeffery 1922).
    /// No elasticity is evaluated; F is projected back onto SO(3) after every step.
    Rigid,
}

/// Adaptive inertialess integrator (elastic or rigid shape).
#[derive(Debug, Clone, Copy)]
pub struct Stokesian {
    /// Error tolerances.
    pub tol: Tolerances,
    /// Barycentre model.
    pub barycentre: BarycentreModel,
    /// Shape response.
    pub shape: ShapeResponse,
}

impl Stokesian {
    /// Elastic integrator with rtol = atol = `tol` and an inertial barycentre.
    pub fn new(tol: f64) -> Self {
        Self {
            tol: Tolerances::uniform(tol),
            barycentre: BarycentreModel::Inertial,
            shape: ShapeResponse::Elastic,
        }
    }

    /// Elastic, with an overdamped barycentre.
    pub fn overdamped(tol: f64) -> Self {
        Self {
            barycentre: BarycentreModel::Overdamped,
            ..Self::new(tol)
        }
    }

    /// Rigid limit (Ca = 0): Jeffery rotation plus Brenner drag, overdamped barycentre.
    pub fn rigid(tol: f64) -> Self {
        Self {
            shape: ShapeResponse::Rigid,
            ..Self::overdamped(tol)
        }
    }
}

/// Jeffery's torque-free spin of the current (rigid) ellipsoid in the flow `l_f`.
pub fn jeffery_spin(frame: &crate::ellipsoid::PrincipalFrame, l_f: &Mat3) -> Mat3 {
    let lf = frame.to_principal(l_f);
    let x = frame.r.component_mul(&frame.r);
    let ws = Mat3::from_fn(|i, j| {
        if i == j {
            0.0
        } else {
            0.5 * (lf[(i, j)] - lf[(j, i)]) - (x[i] - x[j]) / (x[i] + x[j]) * 0.5 * (lf[(i, j)] + lf[(j, i)])
        }
    });
    frame.to_global(&ws)
}

fn pack(f: &Mat3, x: &Vec3, v: &Vec3) -> Y {
    let mut y = Y::zeros();
    y.fixed_rows_mut::<9>(0).copy_from(&vec9(f));
    y.fixed_rows_mut::<3>(9).copy_from(x);
    y.fixed_rows_mut::<3>(12).copy_from(v);
    y
}

fn unpack(y: &Y) -> (Mat3, Vec3, Vec3) {
    (
        mat3(&y.fixed_rows::<9>(0).into_owned()),
        y.fixed_rows::<3>(9).into_owned(),
        y.fixed_rows::<3>(12).into_owned(),
    )
}

/// Everything the right-hand side computes at one state.
struct Evaluation {
    f_dot: Mat3,
    l_s: Mat3,
    x_dot: Vec3,
    v_dot: Vec3,
    drag_rate: Mat3,
    l_f: Mat3,
    /// `None` in the rigid limit.
    solver: Option<crate::hydro::InertialessSolver>,
}

fn evaluate<M: Hyperelastic, D: DragModel, F: FlowField + ?Sized>(
    particle: &Particle<M, D>,
    flow: &F,
    model: BarycentreModel,
    shape: ShapeResponse,
    t: f64,
    y: &Y,
) -> Result<Evaluation, StepError> {
    let (f, x, v) = unpack(y);
    let det_f = f.determinant();
    if !(det_f > 0.0) {
        return Err(StepError::Inverted { det_f, t });
    }
    let sample = flow.sample(&x, t)?;
    let mu_f = particle.fluid().mu;
    let geo = particle.geometry(&State {
        t,
        x,
        v,
        f,
        a: Mat3::zeros(),
    });
    let (l_s, solver) = match shape {
        ShapeResponse::Elastic => {
            let solver = geo
                .traction
                .inertialess(&sample.grad_u, mu_f)
                .ok_or(StepError::NonFinite {
                    what: "inertialess traction operator",
                    t,
                })?;
            (solver.velocity_gradient(&particle.material().cauchy(&f)), Some(solver))
        }
        ShapeResponse::Rigid => (jeffery_spin(&geo.frame, &sample.grad_u), None),
    };
    let drag_rate = particle.drag().resistance(&geo.frame, &geo.ints) * (mu_f / particle.mass());
    let a_g = reduced_gravity(particle.gravity(), particle.rho_solid(), particle.fluid().rho, det_f);
    let (x_dot, v_dot) = match model {
        BarycentreModel::Inertial => (v, a_g + drag_rate * (sample.u - v)),
        BarycentreModel::Overdamped => {
            let drift = drag_rate
                .lu()
                .solve(&a_g)
                .ok_or(StepError::NonFinite { what: "drag tensor", t })?;
            (sample.u + drift, Vec3::zeros())
        }
    };
    Ok(Evaluation {
        f_dot: l_s * f,
        l_s,
        x_dot,
        v_dot,
        drag_rate,
        l_f: sample.grad_u,
        solver,
    })
}

fn rhs_vector(e: &Evaluation) -> Y {
    pack(&e.f_dot, &e.x_dot, &e.v_dot)
}

/// W-method Jacobian: exact elastic part, frozen hydrodynamic operator, linear-flow coupling.
fn jacobian<M: Hyperelastic, D: DragModel>(
    particle: &Particle<M, D>,
    model: BarycentreModel,
    y: &Y,
    e: &Evaluation,
) -> Jac {
    let (f, _, _) = unpack(y);
    let mut jac = Jac::zeros();
    barycentre_jacobian(&mut jac, model, e);
    let Some(solver) = &e.solver else {
        // Rigid: d(W_s F) ≈ W_s dF with the spin frozen over the step (W-method).
        for q in 0..9 {
            let mut df = Mat3::zeros();
            df[q] = 1.0;
            jac.fixed_view_mut::<9, 1>(0, q).copy_from(&vec9(&(e.l_s * df)));
        }
        return jac;
    };
    let law = particle.material();
    let det_f = f.determinant();
    let p = law.piola(&f);
    let sigma = p * f.transpose() / det_f;
    let tangent = law.tangent(&f);
    let f_inv_t = inv_transpose(&f);
    for q in 0..9 {
        let mut df = Mat3::zeros();
        df[q] = 1.0;
        let dp = mat3(&tangent.column(q).into_owned());
        // δσ = (δP Fᵀ + P δFᵀ)/J − σ tr(F⁻¹δF)
        let d_sigma = (dp * f.transpose() + p * df.transpose()) / det_f - sigma * f_inv_t[q];
        let dl_s = solver.velocity_gradient_increment(&d_sigma);
        jac.fixed_view_mut::<9, 1>(0, q)
            .copy_from(&vec9(&(dl_s * f + e.l_s * df)));
    }
    jac
}

fn barycentre_jacobian(jac: &mut Jac, model: BarycentreModel, e: &Evaluation) {
    match model {
        BarycentreModel::Inertial => {
            jac.fixed_view_mut::<3, 3>(9, 12).copy_from(&Mat3::identity());
            jac.fixed_view_mut::<3, 3>(12, 9).copy_from(&(e.drag_rate * e.l_f));
            jac.fixed_view_mut::<3, 3>(12, 12).copy_from(&(-e.drag_rate));
        }
        BarycentreModel::Overdamped => {
            jac.fixed_view_mut::<3, 3>(9, 9).copy_from(&e.l_f);
        }
    }
}

impl TimeIntegrator for Stokesian {
    fn name(&self) -> &'static str {
        match self.shape {
            ShapeResponse::Elastic => "stokesian",
            ShapeResponse::Rigid => "rigid",
        }
    }

    fn step<M: Hyperelastic, D: DragModel, F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        state: &State,
        flow: &F,
        dt: f64,
    ) -> Result<(State, StepInfo), StepError> {
        crate::error::positive("dt", dt)?;
        state.validate()?;
        let (model, shape) = (self.barycentre, self.shape);
        let y0 = pack(&state.f, &state.x, &state.v);
        let acc = rosenbrock::step(
            state.t,
            &y0,
            dt,
            self.tol,
            |t, y| evaluate(particle, flow, model, shape, t, y).map(|e| rhs_vector(&e)),
            |t, y| evaluate(particle, flow, model, shape, t, y).map(|e| jacobian(particle, model, y, &e)),
        )?;
        let (mut f, x, v) = unpack(&acc.y);
        if shape == ShapeResponse::Rigid {
            // Polar projection onto SO(3): the nearest rotation to the integrated F.
            let svd = f.svd(true, true);
            f = svd.u.expect("requested") * svd.v_t.expect("requested");
        }
        let (a, _, _) = unpack(&acc.f_new);
        let v = match model {
            BarycentreModel::Inertial => v,
            BarycentreModel::Overdamped => acc.f_new.fixed_rows::<3>(9).into_owned(),
        };
        let next = State {
            t: state.t + acc.h,
            x,
            v,
            f,
            a,
        };
        next.validate()?;
        let info = StepInfo {
            dt: acc.h,
            dt_next: acc.h_next,
            newton_iters: 0,
            residual: 0.0,
            rhs_evals: acc.rhs_evals + 1,
            jac_evals: acc.jac_evals,
            rejected: acc.rejected,
        };
        Ok((next, info))
    }
}

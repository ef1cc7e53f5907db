//! Inertialess (Stokesian) shape dynamics with adaptive, L-stable stepping: Radau IIA of order 5
//! ([`Scheme::Radau5`]) or a Rosenbrock-W pair of order 2(3) ([`Scheme::Rosenbrock23`]).
//!
//! # Physics (paper eq. 18 in the limit Θ → 0)
//! For a micro-particle Θ ∝ ρ* is negligible and eq. 18 degenerates to the balance P̃ = P,
//! i.e. σ̃(l_s) = σ_el(F) with σ_el = P Fᵀ/J. With tr l_s = 0 (incompressible particle) this is
//! the 9×9 linear system of [`InertialessSolver`], and the shape evolves by Ḟ = l_s(F) F.
//! The barycentre is either inertial, m v̇ = m a_G + μ_f K̂(u − v), ẋ = v, or overdamped
//! (St → 0), ẋ = u + (μ_f K̂/m)⁻¹ a_G.
//!
//! # Scheme
//! The state y = (F, x, v) ∈ ℝ¹⁵ is advanced by Radau IIA(5) ([`super::radau5`]) or by the
//! L-stable Rosenbrock-W 2(3) pair ([`super::rosenbrock`]). Radau's order does not depend on the
//! Jacobian (only its Newton convergence does), which matters here because the Jacobian below
//! is approximate; the Rosenbrock-W pair keeps its order 2 with an approximate Jacobian by
//! construction, and a higher-order Rosenbrock method (Rodas) would not. The Jacobian is exact
//! (num-dual tangent of W) in the elastic
//! response and freezes the principal frame and integrals of the hydrodynamic operator for
//! the step; the W-method keeps order 2 with such an approximation (tested).
//!
//! Stiffness: the elastic relaxation rate is ~μ_s/μ_f = 1/Ca, the drag rate 1/τ_D; both are
//! handled implicitly, so Δt follows accuracy, not ρ*.
//!
//! [`InertialessSolver`]: crate::hydro::InertialessSolver

use super::control::Tolerances;
use super::dense::{Dense, Knot};
use super::radau5::{self, RadauMemory};
use super::rosenbrock;
use super::{Step, StepInfo, TimeIntegrator};
use crate::error::{ParamError, StepError};
use crate::flow::FlowField;
use crate::hydro::{DragModel, InertialessSolver};
use crate::material::{Hyperelastic, Response};
use crate::particle::{Model, Particle, State};
use crate::tensor::{Mat3, Vec3, inv_transpose, mat3, nearest_rotation, vec9};
use nalgebra::{SMatrix, SVector};
use serde::{Deserialize, Serialize};

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

/// The time-stepping scheme of [`Stokesian`].
///
/// # Which one: measured (`examples/scheme_choice`, error against Radau at 10⁻⁴ × tol)
/// | scene, particle | tol | Rosenbrock23 | Radau5 |
/// |---|---|---|---|
/// | pipe Figs 11/12, λ₁ = 3.5, Ca = 0.25, to deposition | 1e-7 | 9.0 s, 6.7 d_eq | 0.60 s, 0.018 d_eq |
/// | pipe Fig. 10, λ₁ = 14, Ca = 0.05, 0.5 s | 1e-7 | 0.65 s, 4e-6 | 0.034 s, 1e-9 |
/// | cavity, rigid λ₁ = 2, 5 s | 1e-7 | 1 ms, 1.5e-6 m | 2 ms, 1.2e-8 m |
/// | cavity inertialess, λ₁ = 2, Ca = 0.25, 100 s | 1e-6 | 0.29 s, 2.6e-3 m | 0.45 s, 5.6e-6 m |
/// | bifurcation, soft sphere Stk 0.4 (step cap) | 1e-3 | 14 ms, 4e-8 m | 15 ms, 1e-7 m |
/// | population settling pipe, 2000 rigid spheres¹ | 1e-6 | 2.98 s CPU | 1.61 s CPU |
///
/// ¹ `examples/population_scaling` on one thread; the same fates (1036 deposited, 964 escaped).
///
/// Where accuracy sets the step, Radau IIA costs 15–20× less time at 10²–10³× less error;
/// where the step is capped (the bifurcation's step length) the two cost the same, and where
/// the field is piecewise (the cavity mesh) Radau costs up to 1.5× per step for 10²× less
/// error. Radau IIA is therefore the default. Where the switch moved a reduced dataset, the new
/// value is the one a tight reference run gives: Figs 5/6 at rtol 1e-8 (long-axis angle
/// −65.651° and 6.746° against Rosenbrock's −65.644° and 6.741°; reference −65.651079° and
/// 6.746392° at rtol 1e-12), and the Figs 11/12 contact tilt (cos 0.543463, Rosenbrock
/// 0.543514). [`Scheme::Rosenbrock23`] stays for the work-precision comparison and for
/// callers that want the cheaper step when accuracy does not matter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scheme {
    /// Radau IIA, order 5 ([`super::radau5`]).
    #[default]
    Radau5,
    /// Shampine's Rosenbrock-W 2(3) (`ode23s`), two model evaluations per accepted step.
    Rosenbrock23,
}

/// Adaptive inertialess integrator. The shape response is the particle's: elastic for a
/// hyperelastic law, Jeffery rotation for a [`crate::material::Rigid`] particle (Ca → 0, no
/// elasticity evaluated; F is projected back onto SO(3) after every step).
#[derive(Debug, Clone, Copy)]
pub struct Stokesian {
    /// Error tolerances.
    pub tol: Tolerances,
    /// Barycentre model.
    pub barycentre: BarycentreModel,
    /// Time-stepping scheme.
    pub scheme: Scheme,
}

impl Stokesian {
    /// Elastic integrator with rtol = atol = `tol` (finite, > 0) and an inertial barycentre.
    pub fn new(tol: f64) -> Result<Self, ParamError> {
        Ok(Self {
            tol: Tolerances::uniform(tol)?,
            barycentre: BarycentreModel::Inertial,
            scheme: Scheme::default(),
        })
    }

    /// The same integrator with another scheme.
    pub fn with_scheme(self, scheme: Scheme) -> Self {
        Self { scheme, ..self }
    }

    /// Elastic, with an overdamped barycentre.
    pub fn overdamped(tol: f64) -> Result<Self, ParamError> {
        Ok(Self {
            barycentre: BarycentreModel::Overdamped,
            ..Self::new(tol)?
        })
    }
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
#[derive(Debug, Clone)]
pub(crate) struct Evaluation {
    f_dot: Mat3,
    l_s: Mat3,
    x_dot: Vec3,
    v_dot: Vec3,
    drag_rate: Mat3,
    l_f: Mat3,
    /// `None` in the rigid limit.
    solver: Option<InertialessSolver>,
}

/// The right-hand side of the inertialess model at (t, y): one model evaluation.
pub(crate) fn evaluate<M: Response, D: DragModel, F: FlowField + ?Sized>(
    model: &Model<M, D, F>,
    barycentre: BarycentreModel,
    t: f64,
    y: &Y,
) -> Result<Evaluation, StepError> {
    let (f, x, v) = unpack(y);
    let geo = model.geometry(&f, t)?;
    let sample = model.sample(&x, t)?;
    let (l_s, solver) = model.inertialess_rate(&geo, &f, &sample.grad_u, t)?;
    let forcing = model.forcing(&geo, f.determinant());
    let (x_dot, v_dot) = match barycentre {
        BarycentreModel::Inertial => (v, forcing.acceleration(&sample.u, &v)),
        BarycentreModel::Overdamped => (forcing.overdamped_velocity(&sample.u, t)?, Vec3::zeros()),
    };
    Ok(Evaluation {
        f_dot: l_s * f,
        l_s,
        x_dot,
        v_dot,
        drag_rate: forcing.drag_rate,
        l_f: sample.grad_u,
        solver,
    })
}

pub(crate) fn rhs_vector(e: &Evaluation) -> Y {
    pack(&e.f_dot, &e.x_dot, &e.v_dot)
}

/// W-method Jacobian: exact elastic part, frozen hydrodynamic operator, linear-flow coupling.
pub(crate) fn jacobian<M: Response, D: DragModel, F: FlowField + ?Sized>(
    model: &Model<M, D, F>,
    barycentre: BarycentreModel,
    y: &Y,
    e: &Evaluation,
) -> Jac {
    model.count_jacobian();
    let (f, _, _) = unpack(y);
    let mut jac = Jac::zeros();
    barycentre_jacobian(&mut jac, barycentre, e);
    let Some(solver) = &e.solver else {
        // Rigid: d(W_s F) ≈ W_s dF with the spin frozen over the step (W-method).
        for q in 0..9 {
            let mut df = Mat3::zeros();
            df[q] = 1.0;
            jac.fixed_view_mut::<9, 1>(0, q).copy_from(&vec9(&(e.l_s * df)));
        }
        return jac;
    };
    let Some(law) = model.particle.elastic() else {
        unreachable!("an evaluation with an inertialess solver belongs to an elastic particle")
    };
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

/// Step memory of [`Stokesian`]: the evaluation at the last accepted state (first same as
/// last), keyed by (t, y). A pure cache of a function of (t, y): a checkpoint need not store it.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct StokesianMemory {
    #[serde(skip)]
    last: Option<(f64, Y, Evaluation)>,
    /// Radau's Jacobian, controller history and starting-value polynomial (not a cache: it
    /// changes the next step, so checkpoints keep it).
    radau: RadauMemory<15>,
}

impl TimeIntegrator for Stokesian {
    type Memory = StokesianMemory;

    fn name(&self) -> &'static str {
        match self.scheme {
            Scheme::Radau5 => "stokesian_radau5",
            Scheme::Rosenbrock23 => "stokesian",
        }
    }

    fn step_with<M: Response, D: DragModel, F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        state: &State,
        memory: &mut StokesianMemory,
        flow: &F,
        dt: f64,
    ) -> Result<Step, StepError> {
        super::check_step(state, dt)?;
        let barycentre = self.barycentre;
        let rigid = particle.elastic().is_none();
        let model = Model::new(particle, flow);
        let y0 = pack(&state.f, &state.x, &state.v);
        let e0 = match memory.last.take() {
            Some((t, y, e)) if t == state.t && y == y0 => e,
            _ => evaluate(&model, barycentre, state.t, &y0)?,
        };
        let f0 = rhs_vector(&e0);
        let eval = |t: f64, y: &Y| evaluate(&model, barycentre, t, y);
        let acc = match self.scheme {
            Scheme::Rosenbrock23 => {
                let jac = jacobian(&model, barycentre, &y0, &e0);
                rosenbrock::step(state.t, &y0, &f0, &jac, dt, self.tol, |t, y| {
                    eval(t, y).map(|e| (rhs_vector(&e), e))
                })?
            }
            Scheme::Radau5 => {
                let step = radau5::step(
                    state.t,
                    &y0,
                    dt,
                    self.tol,
                    &mut memory.radau,
                    |t, y| {
                        if t == state.t && *y == y0 {
                            Ok(f0)
                        } else {
                            eval(t, y).map(|e| rhs_vector(&e))
                        }
                    },
                    |t, y| {
                        if t == state.t && *y == y0 {
                            Ok(jacobian(&model, barycentre, y, &e0))
                        } else {
                            eval(t, y).map(|e| jacobian(&model, barycentre, y, &e))
                        }
                    },
                )?;
                // Ḟ at the new state (the state's A and the end knot of the dense output), and
                // the next step's first evaluation.
                let e1 = eval(state.t + step.h, &step.y)?;
                rosenbrock::Accepted {
                    y: step.y,
                    h: step.h,
                    h_next: step.h_next,
                    f_new: rhs_vector(&e1),
                    payload: e1,
                    rejected: step.rejected,
                }
            }
        };
        let (mut f, x, v) = unpack(&acc.y);
        if rigid {
            // Polar projection onto SO(3): the nearest rotation to the integrated F.
            f = nearest_rotation(&f);
        }
        let (a, x_dot, _) = unpack(&acc.f_new);
        let v = match barycentre {
            BarycentreModel::Inertial => v,
            BarycentreModel::Overdamped => x_dot,
        };
        if state.t + acc.h <= state.t {
            return Err(StepError::NoProgress { t: state.t, dt: acc.h });
        }
        let next = State {
            t: state.t + acc.h,
            x,
            v,
            f,
            a,
        };
        next.validate()?;
        if !rigid {
            // The projection of the rigid limit moves F off the evaluated point.
            memory.last = Some((next.t, acc.y, acc.payload));
        }
        let start = Knot {
            x: state.x,
            x_dot: e0.x_dot,
            f: state.f,
            f_dot: e0.f_dot,
        };
        let end = Knot { x, x_dot, f, f_dot: a };
        Ok(Step {
            dense: if rigid {
                Dense::new(state.t, acc.h, start, end).of_rotations()
            } else {
                Dense::new(state.t, acc.h, start, end)
            },
            state: next,
            info: StepInfo {
                rejected: acc.rejected,
                ..StepInfo::from_work(model.work(), acc.h, acc.h_next)
            },
        })
    }
}

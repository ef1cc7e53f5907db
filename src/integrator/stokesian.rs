//! Inertialess (Stokesian) shape dynamics with adaptive, L-stable stepping: Radau IIA of order 5
//! ([`Scheme::Radau5`]) or a Rosenbrock-W pair of order 2(3) ([`Scheme::Rosenbrock23`]).
//!
//! # Physics (paper eq. 18 in the limit Θ → 0, eq. 17)
//! The model's equations, y′ = f(t, y) for y = (F, x, v) with the balance σ̃(l_s) = σ_el(F),
//! Ḟ = l_s F and an inertial or overdamped barycentre, and their Jacobian are
//! [`crate::particle::inertialess`]; this module only advances them.
//!
//! # Scheme
//! The state y ∈ ℝ¹⁵ is advanced by Radau IIA(5) ([`super::radau5`]) or by the L-stable
//! Rosenbrock-W 2(3) pair ([`super::rosenbrock`]). Radau's order does not depend on the
//! Jacobian (only its Newton convergence does), which matters here because the model's
//! Jacobian is approximate (exact in the elastic response, with the principal frame and
//! integrals of the hydrodynamic operator frozen for the step); the Rosenbrock-W pair keeps
//! its order 2 with such an approximate Jacobian by construction (tested), and a higher-order
//! Rosenbrock method (Rodas) would not.
//!
//! Stiffness: the elastic relaxation rate is ~μ_s/μ_f = 1/Ca, the drag rate 1/τ_D; both are
//! handled implicitly, so Δt follows accuracy, not ρ*.
//!
//! # A rigid sphere's orientation is not tested
//! A rigid sphere with isotropic drag and force terms
//! ([`Particle::orientation_is_passive`]) has an orientation that enters none of its
//! equations: F ∈ SO(3) turns nothing its drag, spin, contact or forces see. The Rosenbrock-W
//! step still integrates F (and projects it onto SO(3)) but measures only x and v in its error
//! test, so the steps follow the barycentre alone: a quarter to a third fewer steps for the
//! airway's rigid spheres, fates unchanged but for one in 2 000 (measured in
//! `paper-figures/fig17/NOTES.md`, History). The closed form of a heavy sphere in solid-body
//! rotation checks the barycentre (`tests/suite/integrator/passive_orientation.rs`). Radau IIA
//! keeps F in its weighted norm: its Newton iteration measures convergence in the same norm.
//!
//! The same holds for the rigid twin that turns a stiff elastic sphere on the slow manifold
//! ([`super::manifold`]) when its law is isotropic
//! ([`crate::material::Hyperelastic::is_isotropic`]): the stretch V there depends on the flow
//! alone and the shape B = V² on nothing of the rotation (measured in the manifold's module
//! docs).

use super::body_frame::BodyStep;
use super::control::{ErrorNorm, Tolerances};
use super::dense::{Dense, Knot};
use super::radau5::{self, RadauMemory};
use super::rosenbrock;
use super::{EndEvaluation, Step, StepInfo, TimeIntegrator};
use crate::error::{ParamError, StepError};
use crate::flow::FlowField;
use crate::hydro::DragModel;
use crate::material::Response;
pub use crate::particle::inertialess::BarycentreModel;
use crate::particle::inertialess::{
    BarycentreJacobian, InertialessJacobian, InertialessRate, InertialessState as Y, STATE_BLOCKS, ShapeJacobian, pack,
    unpack,
};
use crate::particle::{Model, Particle, State};
use crate::tensor::{Mat3, nearest_rotation};
use nalgebra::{LU, SMatrix, U3, U9};
use serde::{Deserialize, Serialize};

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

impl Scheme {
    /// The scheme for relative tolerance `rtol`: the Rosenbrock-W 2(3) pair at rtol ≥
    /// [`ROSENBROCK_RTOL`], Radau IIA(5) below. Every integrator that wraps an inertialess full
    /// model by tolerance alone takes its scheme from here (`auto`, and the slow manifold's
    /// full model).
    pub fn for_rtol(rtol: f64) -> Self {
        if rtol >= ROSENBROCK_RTOL {
            Scheme::Rosenbrock23
        } else {
            Scheme::Radau5
        }
    }
}

/// Smallest rtol at which the Rosenbrock-W pair is chosen ([`Scheme::for_rtol`]). At rtol 10⁻²
/// (the deposition studies) it costs half of Radau's CPU time on the bifurcation's rigid
/// prolates (1.6 s against 3.1 s at Stk 0.005, equilibrium barycentre; 2.4 s against 3.7 s at
/// Stk 0.1, inertial; 1 000 particles, `examples/population_scaling`); at 10⁻³ the two cost the
/// same (soft sphere, [`Scheme`]'s table), and from 10⁻⁶ down Radau costs 2–20× less.
pub const ROSENBROCK_RTOL: f64 = 1e-3;

/// The frame in which [`Scheme::Rosenbrock23`] steps an elastic particle's shape
/// ([`super::body_frame`]). Radau IIA and rigid particles step the lab frame either way.
///
/// # Which one: measured ([`super::body_frame`]'s table, airway bifurcation, 1 000 spheres)
/// The body frame takes the rigid particle's steps for a stiff particle (μ_s = 50, 500 Pa:
/// 1.08 and 0.99 steps per rigid step against the lab frame's 2.02 and 2.76, with 12–340× less
/// shape error) and 1.12–1.33× the lab frame's steps for a soft one (0.5, 5 Pa).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Frame {
    /// y = (F, x, v) as it is: the reference.
    #[default]
    Lab,
    /// F = Q(τ)G with Q turning at the start's spin, det F held by projection
    /// ([`super::body_frame`]).
    Body,
}

impl Frame {
    /// The frame's name in scene files: `lab` or `body`.
    pub fn name(&self) -> &'static str {
        match self {
            Frame::Lab => "lab",
            Frame::Body => "body",
        }
    }
}

impl Scheme {
    /// The scheme's name in datasets and scene files: `radau_iia` or `rosenbrock_w23`.
    pub fn name(&self) -> &'static str {
        match self {
            Scheme::Radau5 => "radau_iia",
            Scheme::Rosenbrock23 => "rosenbrock_w23",
        }
    }
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
    /// How the local error is measured: F, x and v each as a whole, or componentwise. Either
    /// way the position x is measured against the particle's largest rest semi-axis r₁, not
    /// its distance from the origin ([`Tolerances`]).
    pub norm: ErrorNorm,
    /// The frame of the Rosenbrock-W step of an elastic particle ([`Frame`]).
    pub frame: Frame,
}

impl Stokesian {
    /// Elastic integrator with rtol = atol = `tol` (finite, > 0) and an inertial barycentre.
    pub fn new(tol: f64) -> Result<Self, ParamError> {
        Ok(Self {
            tol: Tolerances::uniform(tol)?,
            barycentre: BarycentreModel::Inertial,
            scheme: Scheme::default(),
            norm: ErrorNorm::default(),
            frame: Frame::default(),
        })
    }

    /// The same integrator stepping elastic particles in another frame.
    pub fn with_frame(self, frame: Frame) -> Self {
        Self { frame, ..self }
    }

    /// The same integrator with another scheme.
    pub fn with_scheme(self, scheme: Scheme) -> Self {
        Self { scheme, ..self }
    }

    /// The same integrator with another error norm.
    pub fn with_norm(self, norm: ErrorNorm) -> Self {
        Self { norm, ..self }
    }

    /// The blocks of the state the error norm measures as wholes (`None`: componentwise).
    fn blocks(&self) -> Option<&'static [std::ops::Range<usize>]> {
        match self.norm {
            ErrorNorm::Componentwise => None,
            ErrorNorm::Tensor => Some(&STATE_BLOCKS),
        }
    }

    /// The blocks the Rosenbrock-W error test measures: [`Self::blocks`], without F's where
    /// the particle's orientation is passive ([`Particle::orientation_is_passive`]: a rigid
    /// sphere, whose steps then follow x and v alone).
    fn tested_blocks(&self, passive_orientation: bool) -> Option<&'static [std::ops::Range<usize>]> {
        /// Each component of y on its own (the componentwise norm as blocks).
        const COMPONENTS: [std::ops::Range<usize>; 15] = [
            0..1,
            1..2,
            2..3,
            3..4,
            4..5,
            5..6,
            6..7,
            7..8,
            8..9,
            9..10,
            10..11,
            11..12,
            12..13,
            13..14,
            14..15,
        ];
        let f_end = STATE_BLOCKS[0].end;
        match (self.norm, passive_orientation) {
            (_, false) => self.blocks(),
            (ErrorNorm::Componentwise, true) => Some(&COMPONENTS[f_end..]),
            (ErrorNorm::Tensor, true) => Some(&STATE_BLOCKS[1..]),
        }
    }

    /// Elastic, with an overdamped barycentre.
    pub fn overdamped(tol: f64) -> Result<Self, ParamError> {
        Ok(Self {
            barycentre: BarycentreModel::Overdamped,
            ..Self::new(tol)?
        })
    }
}

/// Step memory of [`Stokesian`]: the evaluation at the last accepted state (first same as
/// last), keyed by (t, y). A pure cache of a function of (t, y): a checkpoint need not store it.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct StokesianMemory {
    #[serde(skip)]
    last: Option<(f64, Y, InertialessRate)>,
    /// The time of the last accepted state and the flow's velocity gradient there (read by
    /// [`super::manifold`]; a cache like `last`).
    #[serde(skip)]
    end_gradient: Option<(f64, Mat3)>,
    /// Radau's Jacobian, controller history and starting-value polynomial (not a cache: it
    /// changes the next step, so checkpoints keep it).
    radau: RadauMemory<15>,
}

impl StokesianMemory {
    /// The flow's velocity gradient at the last accepted state, with its time.
    pub fn end_gradient(&self) -> Option<(f64, Mat3)> {
        self.end_gradient
    }
}

impl TimeIntegrator for Stokesian {
    type Memory = StokesianMemory;

    fn name(&self) -> &'static str {
        match (self.scheme, self.frame) {
            (Scheme::Rosenbrock23, Frame::Body) => "rosenbrock_w23_body",
            (scheme, _) => scheme.name(),
        }
    }

    fn barycentre(&self) -> BarycentreModel {
        self.barycentre
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
        // Every step, not only the first: a caller may hand any memory with any particle, and
        // the check is a comparison of a few names against a step's tens of model evaluations.
        barycentre.admits(particle.forces())?;
        let rigid = particle.elastic().is_none();
        let model = Model::new(particle, flow);
        let y0 = pack(&state.f, &state.x, &state.v);
        let e0 = match memory.last.take() {
            Some((t, y, e)) if t == state.t && y == y0 => e,
            _ => model.inertialess(barycentre, state.t, &y0)?,
        };
        let f0 = e0.vector();
        let eval = |t: f64, y: &Y| model.inertialess(barycentre, t, y);
        let jacobian = |y: &Y, e: &InertialessRate| model.inertialess_jacobian(barycentre, y, e);
        // The position x = y[9..12] against the particle's largest rest semi-axis, not |x|
        // (`Tolerances`: translation-independent steps).
        let r1 = particle.shape().semi_axes().max();
        let tol = self.tol.with_position(STATE_BLOCKS[1].start, r1)?;
        let acc = match self.scheme {
            Scheme::Rosenbrock23 if self.frame == Frame::Body && !rigid => BodyStep {
                t0: state.t,
                y0: &y0,
                e0: &e0,
                tol,
                blocks: self.blocks(),
            }
            .take(jacobian(&y0, &e0), dt, eval)?,
            Scheme::Rosenbrock23 => {
                let jac = jacobian(&y0, &e0);
                let test = rosenbrock::ErrorTest {
                    tol,
                    blocks: self.tested_blocks(particle.orientation_is_passive()),
                    invariant: None,
                };
                rosenbrock::step(state.t, &y0, &f0, &jac, dt, test, |t, y| {
                    eval(t, y).map(|e| (e.vector(), e))
                })?
            }
            Scheme::Radau5 => {
                let step = radau5::step(
                    state.t,
                    &y0,
                    dt,
                    tol,
                    self.blocks(),
                    &mut memory.radau,
                    |t, y| {
                        if t == state.t && *y == y0 {
                            Ok(f0)
                        } else {
                            eval(t, y).map(|e| e.vector())
                        }
                    },
                    |t, y| {
                        if t == state.t && *y == y0 {
                            Ok(jacobian(y, &e0).dense())
                        } else {
                            eval(t, y).map(|e| jacobian(y, &e).dense())
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
                    f_new: e1.vector(),
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
            BarycentreModel::Overdamped | BarycentreModel::Equilibrium => x_dot,
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
        memory.end_gradient = Some((next.t, acc.payload.l_f()));
        // Evaluated at the new (t, x) and, unless the rigid projection moved it, the new F.
        let end = EndEvaluation {
            frame: (!rigid).then(|| *acc.payload.frame()),
            flow: Some(*acc.payload.sample()),
        };
        // The next step starts from this step's end evaluation. A rigid particle's F was
        // projected onto SO(3) after it, by the step's own error (O(h³)): the evaluation at the
        // unprojected F stands in for the projected one (its rate and Jacobian), an O(ε)
        // change that saves the Rosenbrock-W step one of its three evaluations and Radau IIA
        // one per step (measured on the Rosenbrock-W step: steps within 0.1 %, fates paired
        // unchanged; `paper-figures/fig18/NOTES.md`).
        let key = if rigid { pack(&next.f, &next.x, &next.v) } else { acc.y };
        memory.last = Some((next.t, key, acc.payload));
        let start = Knot {
            x: state.x,
            x_dot: e0.x_dot(),
            f: state.f,
            f_dot: e0.f_dot(),
        };
        let knot = Knot { x, x_dot, f, f_dot: a };
        Ok(Step {
            dense: if rigid {
                Dense::new(state.t, acc.h, start, knot).of_rotations()
            } else {
                Dense::new(state.t, acc.h, start, knot)
            },
            end,
            state: next,
            info: StepInfo {
                rejected: acc.rejected,
                ..StepInfo::from_work(model.work(), acc.h, acc.h_next)
            },
        })
    }
}

/// W = 1 − γh J of the block-diagonal inertialess Jacobian, factorised block by block: a
/// 3×3 LU for a rigid particle's shape (1₃ ⊗ (1 − γh l_s) acts on each column of F) or a 9×9
/// one, and one 3×3 LU for the barycentre, where one 15×15 LU cost about 12 times as much.
///
/// The inertial barycentre's block, with c = γh, A = R l_f and B = −R,
/// ```math
/// W = \begin{pmatrix} I & −cI \\ −cA & I − cB \end{pmatrix}, \qquad
/// W \begin{pmatrix} p \\ q \end{pmatrix} = \begin{pmatrix} r \\ s \end{pmatrix}
/// \iff (I − cB − c^2 A) q = s + cA r, \qquad p = r + c q,
/// ```
/// is solved through its Schur complement (one 3×3 system in place of a 6×6 LU: the same
/// solution in exact arithmetic, rounded differently); the drift barycentre's
/// W acts on x alone (v is not integrated).
pub struct InertialessFactor {
    shape: ShapeFactor,
    barycentre: BarycentreFactor,
}

// One per step, on the stack: boxing the larger variant would allocate in every step.
#[allow(clippy::large_enum_variant)]
enum ShapeFactor {
    Spin(LU<f64, U3, U3>),
    Full(LU<f64, U9, U9>),
}

/// The barycentre's part of an [`InertialessFactor`].
enum BarycentreFactor {
    /// The Schur complement 1 − cB − c²A, with c and A.
    Inertial {
        schur: LU<f64, U3, U3>,
        c: f64,
        coupling: Mat3,
    },
    /// 1 − c l_f on x; v passes unchanged.
    Drift(LU<f64, U3, U3>),
}

impl rosenbrock::Jacobian<15> for InertialessJacobian {
    type Factor = InertialessFactor;

    fn factor(&self, gamma_h: f64) -> InertialessFactor {
        InertialessFactor {
            shape: match &self.shape {
                ShapeJacobian::Spin(l_s) => ShapeFactor::Spin((Mat3::identity() - l_s * gamma_h).lu()),
                ShapeJacobian::Full(block) => {
                    ShapeFactor::Full((SMatrix::<f64, 9, 9>::identity() - block * gamma_h).lu())
                }
            },
            barycentre: match self.barycentre {
                BarycentreJacobian::Inertial { coupling, drag_rate } => BarycentreFactor::Inertial {
                    schur: (Mat3::identity() + drag_rate * gamma_h - coupling * (gamma_h * gamma_h)).lu(),
                    c: gamma_h,
                    coupling,
                },
                BarycentreJacobian::Drift(l_f) => BarycentreFactor::Drift((Mat3::identity() - l_f * gamma_h).lu()),
            },
        }
    }
}

impl rosenbrock::Factor<15> for InertialessFactor {
    fn solve(&self, b: &Y) -> Option<Y> {
        let mut out = Y::zeros();
        match &self.shape {
            ShapeFactor::Spin(lu) => {
                let columns = lu.solve(&Mat3::from_column_slice(&b.as_slice()[..9]))?;
                out.fixed_rows_mut::<9>(0).copy_from_slice(columns.as_slice());
            }
            ShapeFactor::Full(lu) => {
                out.fixed_rows_mut::<9>(0)
                    .copy_from(&lu.solve(&b.fixed_rows::<9>(0).into_owned())?);
            }
        }
        let r = b.fixed_rows::<3>(9).into_owned();
        let s = b.fixed_rows::<3>(12).into_owned();
        let (p, q) = match &self.barycentre {
            BarycentreFactor::Inertial { schur, c, coupling } => {
                let q = schur.solve(&(s + coupling * r * *c))?;
                (r + q * *c, q)
            }
            BarycentreFactor::Drift(lu) => (lu.solve(&r)?, s),
        };
        out.fixed_rows_mut::<3>(9).copy_from(&p);
        out.fixed_rows_mut::<3>(12).copy_from(&q);
        Some(out)
    }
}

/// A scene's `norm`: `"componentwise"` (also when absent) or `"tensor"` ([`ErrorNorm`]).
pub(super) fn error_norm(p: &crate::registry::Parameters) -> Result<ErrorNorm, ParamError> {
    p.choice(
        "norm",
        &[
            ("componentwise", ErrorNorm::Componentwise),
            ("tensor", ErrorNorm::Tensor),
        ],
        "\"componentwise\" or \"tensor\"",
    )
}

/// A scene's `frame`: `"lab"` (also when absent) or `"body"` ([`Frame`]).
fn frame(p: &crate::registry::Parameters) -> Result<Frame, ParamError> {
    p.choice(
        "frame",
        &[("lab", Frame::Lab), ("body", Frame::Body)],
        "\"lab\" or \"body\"",
    )
}

/// The inertialess integrator with `scheme`, from a scene's `tol`, `overdamped` and `norm`, and
/// for the Rosenbrock-W pair its `frame`.
fn by_scheme(p: &crate::registry::Parameters, scheme: Scheme) -> Result<super::SceneIntegrator, ParamError> {
    let frame = match scheme {
        Scheme::Radau5 => {
            p.only(&["tol", "overdamped", "norm"])?;
            Frame::Lab
        }
        Scheme::Rosenbrock23 => {
            p.only(&["tol", "overdamped", "norm", "frame"])?;
            frame(p)?
        }
    };
    let tol = p.positive("tol")?;
    let made = if p.flag("overdamped")? {
        Stokesian::overdamped(tol)
    } else {
        Stokesian::new(tol)
    };
    Ok(super::SceneIntegrator::new(
        made?.with_scheme(scheme).with_norm(error_norm(p)?).with_frame(frame),
    ))
}

// Selectable by name: `[integrator] type = "radau_iia"` (also `stokesian`, the library's default
// scheme, and `stokesian_radau5`, earlier scene files' names) and `"rosenbrock_w23"` (also
// `stokesian_rosenbrock23`), with `tol`, `overdamped` and `norm`, and the latter with `frame`
// (`"lab"` or `"body"`).
inventory::submit! {
    super::IntegratorRegistration {
        name: "radau_iia",
        aliases: &["stokesian", "stokesian_radau5"],
        build: |p| by_scheme(p, Scheme::Radau5),
    }
}
inventory::submit! {
    super::IntegratorRegistration {
        name: "rosenbrock_w23",
        aliases: &["stokesian_rosenbrock23"],
        build: |p| by_scheme(p, Scheme::Rosenbrock23),
    }
}

//! The model's equations, in one place. Integrators discretise these and re-derive no physics.
//!
//! # Physics (paper §2–§5; equation numbers of Wedel et al.)
//! - geometry of the current shape from F alone: F̄ = F·S (eq. 4), r_a = √eig(F̄F̄ᵀ) and the
//!   rotation Q (§5, with the paper's "r_a = λ_a" read as r_a = √λ_a), Jeffery's integrals and
//!   the traction coefficients of σ̃ ([`Geometry`]);
//! - the fluid load on the shape, P̃ = J σ̃ F⁻ᵀ (eq. 16), with the Jeffery–Roscoe traction σ̃
//!   (eq. 12) ([`Model::sigma_tilde`], [`traction_load`]);
//! - the inertialess shape rate (eq. 18 with Θ → 0): σ̃(l_s) = σ_el(F) with tr l_s = 0, so
//!   Ḟ = l_s F ([`Model::inertialess_rate`]); for a rigid particle Jeffery's (1922) torque-free
//!   spin ([`crate::hydro::traction::jeffery_spin`]);
//! - the barycentre forcing (eqs. 13, 14, 17): drag rate μ_f K̂/m (the paper's 1/τ_D, eq. 17,
//!   read as μ_f π r_min/m) and reduced gravity a_G = β_t g ([`Model::forcing`]), with the
//!   particle's optional force terms (fluid inertia, slip, finite-Re drag, lift:
//!   [`crate::hydro::forces`]) folded into the same two quantities.
//!
//! # Counting work
//! [`Model`] wraps a particle and a flow for one step and counts what it computes, as argmin
//! counts cost evaluations inside its problem wrapper: a geometry (eigen-decomposition, Carlson
//! integrals, traction coefficients) is one *model evaluation*, the unit of the work-precision
//! studies, because it dominates every integrator's cost and is the same work in all of them.
//! Jacobians are counted where they are built. [`crate::integrator::StepInfo`] reports these
//! counts, so they cannot drift from what was computed.

use super::Particle;
use crate::ellipsoid::{EllipsoidIntegrals, PrincipalFrame};
use crate::error::{ParamError, StepError};
use crate::flow::{FlowField, FlowSample};
use crate::hydro::forces::ForceContext;
use crate::hydro::gravity::reduced_gravity;
use crate::hydro::{DragModel, InertialessSolver, JefferyRoscoe, jeffery_spin};
use crate::material::{Response, StressLaw};
use crate::tensor::{Mat3, Scalar, Vec3, det3, inv_transpose, lift};
use std::cell::Cell;

/// Everything that depends on the current shape only: r_a, Q, integrals, σ̃ coefficients.
#[derive(Debug, Clone, Copy)]
pub struct Geometry {
    /// Principal frame (r_a, Q).
    pub frame: PrincipalFrame,
    /// Jeffery integrals.
    pub ints: EllipsoidIntegrals,
    /// Traction coefficients.
    pub traction: JefferyRoscoe,
}

impl Geometry {
    /// Geometry of the total distortion F̄ = F·S (precondition: F̄ finite and non-singular;
    /// otherwise NaN, promptly, [preconditions](crate::error#preconditions)).
    pub fn of_total_distortion(f_bar: &Mat3) -> Self {
        let frame = PrincipalFrame::from_total_distortion(f_bar);
        let ints = EllipsoidIntegrals::new(&frame.r);
        Self {
            traction: JefferyRoscoe::new(&frame, &ints),
            frame,
            ints,
        }
    }

    /// The geometry of the same ellipsoid turned by the rotation `rotation` (a rigid particle's
    /// F): the semi-axes, the integrals and the traction coefficients depend on the semi-axes
    /// only, so only the frame turns, Q ↦ Q Rᵀ, once for the geometry and its traction
    /// coefficients (which hold the same frame: [`Self::of_total_distortion`]).
    pub fn turned(&self, rotation: &Mat3) -> Self {
        let frame = self.frame.turned(rotation);
        Self {
            frame,
            ints: self.ints,
            traction: self.traction.in_frame(frame),
        }
    }

    /// Geometry of the total distortion F̄ = F·S, or why it does not exist: a frame,
    /// integrals or traction coefficients that are not finite.
    pub fn try_of_total_distortion(f_bar: &Mat3) -> Result<Self, ParamError> {
        let frame = PrincipalFrame::try_from_total_distortion(f_bar)?;
        let ints = EllipsoidIntegrals::try_new(&frame.r)?;
        Ok(Self {
            traction: JefferyRoscoe::try_new(&frame, &ints)?,
            frame,
            ints,
        })
    }
}

/// Work done by a [`Model`]: the counts behind [`crate::integrator::StepInfo`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Work {
    /// Model evaluations: geometries computed (frame, integrals, traction coefficients).
    pub model_evals: u32,
    /// Jacobians built.
    pub jac_evals: u32,
    /// Flow samples taken.
    pub flow_samples: u32,
}

/// Barycentre forcing of eq. 17: v̇ = a + R(u − v). With the paper's terms only, R = μ_f K̂/m
/// and a = a_G; force terms ([`crate::hydro::forces`]) make R = M⁻¹ c μ_f K̂ and
/// a = M⁻¹(m a_G + Σ f_k) with the effective mass M = m 1 + M_a.
#[derive(Debug, Clone, Copy)]
pub struct Forcing {
    /// Drag rate R = μ_f K̂/m (eq. 14 over the mass), or M⁻¹ c μ_f K̂ with force terms.
    pub drag_rate: Mat3,
    /// Every acceleration but the drag's: the reduced gravity a_G = β_t g (eq. 13), with force
    /// terms M⁻¹(m a_G + Σ f_k).
    pub a_g: Vec3,
}

impl Forcing {
    /// Acceleration a + R(u − v) of eq. 17.
    pub fn acceleration(&self, u: &Vec3, v: &Vec3) -> Vec3 {
        self.a_g + self.drag_rate * (u - v)
    }

    /// The velocity at which the drag balances every other acceleration and the particle's
    /// own acceleration `accel`: a + R(u − v) = v̇ ⇒ v = u + R⁻¹(a − v̇). With v̇ = 0 this is
    /// the overdamped (St → 0) velocity; with v̇ = Du/Dt, the equilibrium velocity
    /// ([`crate::particle::inertialess::BarycentreModel::Equilibrium`]).
    pub fn overdamped_velocity(&self, u: &Vec3, accel: &Vec3, t: f64) -> Result<Vec3, StepError> {
        let drift = self
            .drag_rate
            .lu()
            .solve(&(self.a_g - accel))
            .ok_or(StepError::NonFinite { what: "drag tensor", t })?;
        Ok(u + drift)
    }
}

/// Cap on the iterations of the overdamped slip with slip-dependent force terms.
///
/// The map G: v ↦ u + R(v)⁻¹a(v) has, along the slip, the slope λ = −e with e = d ln c/d ln Re
/// the elasticity of the drag factor c: e < 0.687 for Schiller–Naumann below Re_p = 1000, e = 1
/// exactly above it (Newton's regime, C_D = 0.44), e → 1 for Hölzer–Sommerfeld at large Re. The
/// plain iteration v ← G(v) contracts by |λ|, so at e = 1 it cycles between two slips. Each
/// step is therefore relaxed, v ← v + ω(G(v) − v), with ω = 1/(1 − λ) from the slope measured on
/// the last step (a secant estimate, clamped to λ ∈ [−9, 0]): for a map linear
/// along the slip this removes the error in one step, ω = 1 in the Stokes regime (λ = 0: the
/// plain iteration), ½ in Newton's. 200 steps leave the cap far from any converging case; a
/// lift whose rotation of the slip defeats the estimate is outside its model (Saffman's lift
/// is weaker than the drag for Re_ω ≪ 1).
pub const MAX_SLIP_ITERATIONS: u32 = 200;

/// Smallest slope of the slip map the relaxation trusts (ω ≥ 1/(1 − λ) = 0.1): a drag factor's
/// elasticity above 9 is no drag law's.
const MIN_SLIP_SLOPE: f64 = -9.0;

/// Relative change of the overdamped velocity at which its iteration stops: a few ulps of
/// the slip.
const SLIP_TOLERANCE: f64 = 4.0 * f64::EPSILON;

/// A particle in a flow for the duration of one step, counting the work it does.
pub struct Model<'a, M, D, F: ?Sized> {
    /// The particle.
    pub particle: &'a Particle<M, D>,
    /// The carrier flow.
    pub flow: &'a F,
    work: Cell<Work>,
}

impl<'a, M: Response, D: DragModel, F: FlowField + ?Sized> Model<'a, M, D, F> {
    /// Wrap a particle and a flow with zero work.
    pub fn new(particle: &'a Particle<M, D>, flow: &'a F) -> Self {
        Self {
            particle,
            flow,
            work: Cell::new(Work::default()),
        }
    }

    /// Work done so far.
    pub fn work(&self) -> Work {
        self.work.get()
    }

    fn count(&self, f: impl FnOnce(&mut Work)) {
        let mut w = self.work.get();
        f(&mut w);
        self.work.set(w);
    }

    /// Record a Jacobian built by the caller from this model's derivatives.
    pub fn count_jacobian(&self) {
        self.count(|w| w.jac_evals += 1);
    }

    /// Geometry of the shape F̄ = F·S: one model evaluation. Refuses det F ≤ 0 or NaN.
    pub fn geometry(&self, f: &Mat3, t: f64) -> Result<Geometry, StepError> {
        check_orientation(f, t)?;
        self.count(|w| w.model_evals += 1);
        Ok(self.particle.geometry(f))
    }

    /// Flow velocity u and gradient l_f = ∇u at (x, t).
    pub fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, StepError> {
        self.count(|w| w.flow_samples += 1);
        Ok(self.flow.sample(x, t)?)
    }

    /// Jeffery–Roscoe traction σ̃(l_s; l_f) of eq. 12 for the particle's fluid and volumetric
    /// treatment.
    pub fn sigma_tilde(&self, geo: &Geometry, l_s: &Mat3, l_f: &Mat3) -> Mat3 {
        geo.traction
            .sigma_tilde(l_s, l_f, self.particle.fluid().mu, self.particle.volumetric())
    }

    /// Inertialess shape rate (eq. 18 with Θ → 0). Elastic: the l_s with σ̃(l_s) = σ_el(F),
    /// tr l_s = 0, and the factorised operator for Jacobians. Rigid: Jeffery's torque-free spin,
    /// and no operator.
    pub fn inertialess_rate(
        &self,
        geo: &Geometry,
        f: &Mat3,
        l_f: &Mat3,
        t: f64,
    ) -> Result<(Mat3, Option<InertialessSolver>), StepError> {
        let Some(law) = self.particle.elastic() else {
            let p = self.particle;
            let spin = match p.deformed_spin() {
                Some(d) => d.spin(geo, f, p.shape_tensor(), l_f, p.fluid().mu, p.volumetric()),
                None => jeffery_spin(&geo.frame, l_f),
            };
            return Ok((spin, None));
        };
        let solver = geo
            .traction
            .inertialess(l_f, self.particle.fluid().mu)
            .ok_or(StepError::NonFinite {
                what: "inertialess traction operator",
                t,
            })?;
        Ok((solver.velocity_gradient(&law.cauchy(f)), Some(solver)))
    }

    /// Barycentre forcing at the shape `geo` with det F = `det_f`, velocity `v` and the flow
    /// `sample` at the barycentre, at time t (eqs. 13, 14, 17, and the particle's force terms).
    pub fn forcing(
        &self,
        geo: &Geometry,
        det_f: f64,
        sample: &FlowSample,
        v: &Vec3,
        t: f64,
    ) -> Result<Forcing, StepError> {
        let p = self.particle;
        let resistance = p.drag().resistance(&geo.frame, &geo.ints);
        let a_g = reduced_gravity(p.gravity(), p.rho_solid(), p.fluid().rho, det_f);
        if p.forces().is_empty() {
            return Ok(Forcing {
                drag_rate: resistance * (p.fluid().mu / p.mass()),
                a_g,
            });
        }
        let ctx = ForceContext {
            frame: &geo.frame,
            ints: &geo.ints,
            mu_f: p.fluid().mu,
            rho_f: p.fluid().rho,
            mass: p.mass(),
            v: *v,
            flow: sample,
        };
        let total = p.forces().total(&ctx);
        let effective_mass = Mat3::identity() * p.mass() + total.added_mass;
        // M = m 1 + M_a is symmetric positive definite (M_a is a Gram form ρ_f V Qᵀ diag(k) Q, k > 0).
        let mass = effective_mass.cholesky().ok_or(StepError::NonFinite {
            what: "effective mass m 1 + M_a",
            t,
        })?;
        Ok(Forcing {
            drag_rate: mass.solve(&(resistance * (p.fluid().mu * total.drag_factor))),
            a_g: mass.solve(&(a_g * p.mass() + total.force)),
        })
    }

    /// The overdamped barycentre velocity at the shape `geo` (drag balances every other force
    /// and the particle's assumed acceleration `accel`: zero for St → 0, Du/Dt for the
    /// equilibrium velocity), given the `forcing` there at any velocity. Force terms that
    /// depend on the slip are iterated to their fixed point from v = u (at most
    /// [`MAX_SLIP_ITERATIONS`] times); without force terms the forcing does not depend on v
    /// and one solve is exact.
    pub fn overdamped_velocity(
        &self,
        geo: &Geometry,
        det_f: f64,
        sample: &FlowSample,
        forcing: &Forcing,
        accel: &Vec3,
        t: f64,
    ) -> Result<Vec3, StepError> {
        if self.particle.forces().is_empty() {
            return forcing.overdamped_velocity(&sample.u, accel, t);
        }
        let map = |v: &Vec3| {
            self.forcing(geo, det_f, sample, v, t)?
                .overdamped_velocity(&sample.u, accel, t)
        };
        let mut v = sample.u;
        let mut residual = map(&v)? - v;
        let mut change = residual.norm();
        let mut relaxation = 1.0;
        for _ in 0..MAX_SLIP_ITERATIONS {
            if change <= SLIP_TOLERANCE * (v + residual - sample.u).norm() {
                return Ok(v + residual);
            }
            v += residual * relaxation;
            let next = map(&v)? - v;
            // The slope λ of the map along the residual, from the residual's change over the
            // relaxed step (ρ = 1 + ω(λ − 1)), and the relaxation 1/(1 − λ) that would remove
            // a linear map's error in one step (module docs of MAX_SLIP_ITERATIONS).
            let rho = next.dot(&residual) / (change * change);
            let slope = (1.0 + (rho - 1.0) / relaxation).clamp(MIN_SLIP_SLOPE, 0.0);
            relaxation = 1.0 / (1.0 - slope);
            residual = next;
            change = residual.norm();
        }
        Err(StepError::SlipNotConverged {
            iters: MAX_SLIP_ITERATIONS,
            change,
            t,
        })
    }
}

/// Fluid load P̃ = J σ̃ F⁻ᵀ of eq. 16 for a given σ̃, generic so that AD gives ∂P̃/∂F.
pub fn traction_load<S: Scalar>(f: &Mat3<S>, sigma: &Mat3) -> Mat3<S> {
    lift::<S>(sigma) * inv_transpose(f) * det3(f)
}

/// Refuse an inverted or non-finite deformation gradient (det F ≤ 0 or NaN).
pub fn check_orientation(f: &Mat3, t: f64) -> Result<(), StepError> {
    let det_f = f.determinant();
    if det_f.is_nan() || det_f <= 0.0 {
        return Err(StepError::Inverted { det_f, t });
    }
    if !det_f.is_finite() {
        return Err(StepError::NonFinite {
            what: "deformation gradient",
            t,
        });
    }
    Ok(())
}

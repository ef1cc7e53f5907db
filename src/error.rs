//! Typed errors. Each variant carries the numbers that explain the failure.
//!
//! # Preconditions
//! User data enters through constructors that validate it and return these errors
//! ([`crate::ellipsoid::Ellipsoid::new`], [`crate::particle::Particle::new`], the laws, flows
//! and integrators, `State::validate`), and a step refuses a non-finite state or geometry with a
//! [`StepError`]. Below them, the geometry's low-level functions run once or more per model
//! evaluation and return plain numbers: they assume the preconditions listed here and, outside
//! them, return NaN or ∞ promptly (no panic, no loop) for the caller's check to catch. Each has a
//! checked form for data that has not been through a constructor:
//!
//! | function | precondition | checked form |
//! |---|---|---|
//! | [`carlson_rf`](crate::ellipsoid::integrals::carlson_rf), [`carlson_rd`](crate::ellipsoid::integrals::carlson_rd) | finite arguments ≥ 0, at most one zero (R_D: z > 0) | they return `Result` |
//! | [`EllipsoidIntegrals::new`](crate::ellipsoid::EllipsoidIntegrals::new) | semi-axes finite and > 0, squares in range | [`EllipsoidIntegrals::try_new`](crate::ellipsoid::EllipsoidIntegrals::try_new) |
//! | [`PrincipalFrame::from_total_distortion`](crate::ellipsoid::PrincipalFrame::from_total_distortion) | F̄ finite and non-singular | [`PrincipalFrame::try_from_total_distortion`](crate::ellipsoid::PrincipalFrame::try_from_total_distortion) |
//! | [`JefferyRoscoe::new`](crate::hydro::JefferyRoscoe::new), [`JefferyRoscoe::from_total_distortion`](crate::hydro::JefferyRoscoe::from_total_distortion) | finite frame and integrals | [`JefferyRoscoe::try_new`](crate::hydro::JefferyRoscoe::try_new), [`JefferyRoscoe::try_from_total_distortion`](crate::hydro::JefferyRoscoe::try_from_total_distortion) |
//! | [`Geometry::of_total_distortion`](crate::particle::dynamics::Geometry::of_total_distortion), [`Particle::geometry`](crate::particle::Particle::geometry) | F finite with det F > 0 | [`Geometry::try_of_total_distortion`](crate::particle::dynamics::Geometry::try_of_total_distortion), [`Particle::try_geometry`](crate::particle::Particle::try_geometry) |
//! | [`support_distance`](crate::ellipsoid::frame::support_distance), [`jeffery_spin`](crate::hydro::jeffery_spin), [`reduced_gravity`](crate::hydro::gravity::reduced_gravity), [`tensor`](crate::tensor) helpers | finite arguments (a unit normal; det ≠ 0 for inverses) | the frame or geometry they take is checked above |

use crate::tensor::Vec3;
use thiserror::Error;

/// Invalid model parameters (shape, material, fluid, scaling).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ParamError {
    /// A parameter that must be finite and strictly positive is not.
    #[error("parameter `{name}` must be finite and > 0, got {value}")]
    NotPositive {
        /// Parameter name as in the docs.
        name: &'static str,
        /// Offending value.
        value: f64,
    },
    /// A parameter that must be finite is NaN or infinite.
    #[error("parameter `{name}` must be finite, got {value}")]
    NonFinite {
        /// Parameter name.
        name: &'static str,
        /// Offending value.
        value: f64,
    },
    /// A parameter lies outside its allowed interval.
    #[error("parameter `{name}` must lie in [{min}, {max}], got {value}")]
    OutOfRange {
        /// Parameter name.
        name: &'static str,
        /// Offending value.
        value: f64,
        /// Smallest allowed value.
        min: f64,
        /// Largest allowed value.
        max: f64,
    },
    /// A parameter lies outside its allowed open interval (an end is itself refused).
    #[error("parameter `{name}` must lie in ({min}, {max}), got {value}")]
    OutsideOpen {
        /// Parameter name.
        name: &'static str,
        /// Offending value.
        value: f64,
        /// Greatest lower bound, not allowed.
        min: f64,
        /// Least upper bound, not allowed.
        max: f64,
    },
    /// A quantity derived from valid parameters overflows, underflows or loses its sign
    /// (1/Ca, λ_s = ratio·μ_s, R², mass, Θ⁻¹, the rest geometry, ...).
    #[error("derived quantity `{name}` = {value:e} is not finite and > 0 (from {inputs:?})")]
    Derived {
        /// Derived quantity.
        name: &'static str,
        /// Its computed value.
        value: f64,
        /// The inputs it was computed from, in the order of the docs.
        inputs: Vec<f64>,
    },
    /// A stored energy written as an expression that does not parse, names an unknown
    /// symbol, or whose reference state is not a stress-free stable solid.
    #[error("energy `{energy}`, at character {position}: {message}")]
    Expression {
        /// Byte offset in the energy's text.
        position: usize,
        /// What is wrong.
        message: String,
        /// The energy's text.
        energy: String,
    },
    /// Arguments outside the domain of a special function (Carlson's R_F, R_D).
    #[error("{function}({x:e}, {y:e}, {z:e}) is undefined: {reason}")]
    OutOfDomain {
        /// Function name.
        function: &'static str,
        /// First argument.
        x: f64,
        /// Second argument.
        y: f64,
        /// Third argument.
        z: f64,
        /// Which condition fails.
        reason: &'static str,
    },
    /// A model, or a model's parameter, selected by a name nobody registered.
    #[error("unknown {kind} `{name}`; known: {known:?}")]
    Unknown {
        /// What was looked up.
        kind: &'static str,
        /// The name given.
        name: String,
        /// The names that exist.
        known: Vec<&'static str>,
    },
    /// A parameter the model needs is not given.
    #[error("`{model}` needs `{key}`")]
    Missing {
        /// The model's registered name.
        model: &'static str,
        /// The parameter.
        key: String,
    },
    /// A parameter the model does not take.
    #[error("`{model}` does not take `{key}`; it takes {known:?}")]
    Unexpected {
        /// The model's registered name.
        model: &'static str,
        /// The parameter given.
        key: String,
        /// The parameters it takes.
        known: Vec<&'static str>,
    },
    /// A parameter of the wrong kind (text where a number belongs, ...).
    #[error("parameter `{key}` must be {expected}")]
    WrongType {
        /// The parameter.
        key: String,
        /// What it must be.
        expected: &'static str,
    },
    /// One model given twice in a list where each may appear once (a force term named twice
    /// would add its force twice).
    #[error("{kind} `{name}` given twice: it would count twice; give it once")]
    Repeated {
        /// What the list holds.
        kind: &'static str,
        /// The model given twice.
        name: String,
    },
    /// Two models of the same physics chosen together, which would count it twice (two
    /// finite-Reynolds-number drag corrections on one particle, ...).
    #[error("`{first}` and `{second}` are both a {what}: together they count it twice; keep one")]
    Conflict {
        /// The physics both model.
        what: &'static str,
        /// The model given first.
        first: String,
        /// The model given second.
        second: String,
    },
    /// An overdamped barycentre (the particle's inertia dropped, v̇ = 0) with a force term of the
    /// fluid's inertia kept: in Maxey & Riley's small-Stokes expansion the slip is
    /// τ (1 − ρ_f/ρ_p) (g − Du/Dt) to first order, the particle's inertia and the fluid's
    /// entering together (τ = m/(3πμ_f d) for a sphere); keeping only the fluid's gives the
    /// drift τ (ρ_f/ρ_p)(1 + C_a) Du/Dt with both terms (C_a = ½ for a sphere), which is in
    /// neither limit: a neutrally buoyant 100 µm sphere in water in solid-body rotation at
    /// Ω = 10 s⁻¹, r = 1 cm drifts inwards at 0.8 mm/s where it should follow the fluid.
    #[error(
        "`integrator.overdamped` = true drops the particle's inertia and the force term `{term}` \
         (particles.forces) keeps the fluid's, which is of the same order (rho_f/rho_p): together they make a \
         drift that is in neither model (a neutrally buoyant particle drifts across the streamlines of a \
         rotating flow); drop `{term}`, or keep the particle's inertia (overdamped = false, or type = \"auto\", \
         whose equilibrium barycentre keeps both to first order in the Stokes number)"
    )]
    OverdampedFluidInertia {
        /// The fluid-inertia term ([`crate::hydro::forces::FLUID_INERTIA`]).
        term: &'static str,
    },
    /// The initial axes are not a right-handed orthonormal triad.
    #[error("initial axes are not a rotation: |QᵀQ − 1| = {orthogonality_defect:.3e}, det = {det}")]
    NotARotation {
        /// Max-norm of QᵀQ − 1.
        orthogonality_defect: f64,
        /// Determinant of the axes matrix.
        det: f64,
    },
}

impl ParamError {
    /// The parameter the error is about, where it names one (a model built by name from a
    /// scene's keys: the key to point at).
    pub fn key(&self) -> Option<&str> {
        match self {
            ParamError::NotPositive { name, .. }
            | ParamError::NonFinite { name, .. }
            | ParamError::OutOfRange { name, .. } => Some(name),
            ParamError::Missing { key, .. }
            | ParamError::Unexpected { key, .. }
            | ParamError::WrongType { key, .. } => Some(key),
            // Only the expression law has an energy written as text, under the key `energy`.
            ParamError::Expression { .. } => Some("energy"),
            _ => None,
        }
    }
}

/// Failures of the flow field at a query point.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FlowError {
    /// The point lies outside the flow domain.
    #[error("point {x:?} is outside the flow domain")]
    OutsideDomain {
        /// Query point.
        x: [f64; 3],
    },
    /// The point lies outside a meshed flow domain, past the named boundary patch.
    #[error("point {x:?} is outside the mesh, {distance:.3e} from its nearest patch `{patch}`")]
    OutsideMesh {
        /// Query point.
        x: [f64; 3],
        /// Name of the boundary patch nearest to the point.
        patch: String,
        /// Distance to that patch's nearest face.
        distance: f64,
    },
    /// The field's value at a valid point overflows (the parameters are too large for the
    /// query's distance from the origin, or the flow was built from non-finite data).
    #[error("flow at {x:?}, t = {t} is not finite: u = {u:?}")]
    NonFiniteSample {
        /// Query point.
        x: [f64; 3],
        /// Query time.
        t: f64,
        /// The non-finite velocity (the gradient may be the non-finite part).
        u: [f64; 3],
    },
    /// The time lies outside the time levels a windowed transient field holds
    /// (`flow::openfoam::TransientFlow`): the window must be slid there first.
    #[error("t = {t} is outside the time window [{start}, {end}] the field holds")]
    OutsideTimeWindow {
        /// Query time.
        t: f64,
        /// First time the window answers.
        start: f64,
        /// Last time the window answers.
        end: f64,
    },
    /// The query itself is not finite.
    #[error("non-finite query point {x:?} at t = {t}")]
    NonFiniteQuery {
        /// Query point.
        x: [f64; 3],
        /// Query time.
        t: f64,
    },
}

impl FlowError {
    /// Outside-domain error for a point.
    pub fn outside(x: &Vec3) -> Self {
        FlowError::OutsideDomain { x: [x[0], x[1], x[2]] }
    }
}

/// Failures of one time step of a particle.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum StepError {
    /// Newton's method did not reach the tolerance.
    #[error("Newton did not converge: {iters} iterations, residual {residual:.3e}")]
    NewtonNotConverged {
        /// Iterations performed.
        iters: u32,
        /// Final residual (max-norm).
        residual: f64,
    },
    /// The deformation gradient lost orientation (det F ≤ 0): the particle inverted.
    #[error("particle inverted: det F = {det_f:.6e} at t = {t}")]
    Inverted {
        /// det F of the offending iterate.
        det_f: f64,
        /// Time at which it happened.
        t: f64,
    },
    /// A state or input quantity is NaN or infinite.
    #[error("non-finite {what} at t = {t}")]
    NonFinite {
        /// Which quantity.
        what: &'static str,
        /// Time.
        t: f64,
    },
    /// The time step exceeds the stability limit of an explicit part of the scheme.
    #[error("time step {dt:.3e} exceeds the stability limit {limit:.3e} ({reason})")]
    Unstable {
        /// Requested step.
        dt: f64,
        /// Estimated stability limit.
        limit: f64,
        /// Which term limits the step.
        reason: &'static str,
    },
    /// An error-controlled IMEX step would go below the step at which the scheme damps the
    /// anti-damped volume mode of the literal eq. 12 traction (see
    /// `integrator::imex::volume_mode_floor`).
    #[error(
        "the error control asks for dt = {dt:.3e} at t = {t}, below the volume-mode floor {floor:.3e} under which \
         the literal eq. 12 traction makes dilation grow; use VolumetricTraction::Source or Dev, or a looser tolerance"
    )]
    VolumeModeUnresolvable {
        /// Step the error control asked for.
        dt: f64,
        /// Floor a/ω² of the volume mode.
        floor: f64,
        /// Time.
        t: f64,
    },
    /// The eigenvalues behind the explicit stability limit could not be computed (the bounded
    /// Schur iteration did not converge), so the step cannot be certified stable.
    #[error("stability limit unknown at t = {t}: the 9×9 eigenproblem did not converge")]
    StabilityUnknown {
        /// Time.
        t: f64,
    },
    /// An adaptive integrator shrank the step below its floor.
    #[error("step size underflow: dt = {dt:.3e} at t = {t} (error estimate {error:.3e})")]
    StepSizeUnderflow {
        /// Step size reached.
        dt: f64,
        /// Time.
        t: f64,
        /// Last scaled error estimate.
        error: f64,
    },
    /// The integrator needs an elastic law and the particle is rigid.
    #[error("{integrator} integrates the elastic shape dynamics (eq. 18) and cannot step a rigid particle")]
    RigidParticle {
        /// The integrator's name.
        integrator: &'static str,
    },
    /// A run used up its step or wall-time budget.
    #[error("budget exceeded after {steps} steps ({wall_s:.1} s) at t = {t}")]
    BudgetExceeded {
        /// Accepted steps taken.
        steps: u64,
        /// Time reached.
        t: f64,
        /// Wall-clock seconds used.
        wall_s: f64,
    },
    /// A step would not advance time in floating point (t + dt == t).
    #[error("step dt = {dt:.3e} does not advance t = {t}")]
    NoProgress {
        /// Time.
        t: f64,
        /// Step that vanished against t.
        dt: f64,
    },
    /// The overdamped barycentre's slip did not settle: a force term that depends on the
    /// slip has no fixed point the iteration reaches.
    #[error("overdamped slip not converged after {iters} iterations (last change {change:.3e} m/s) at t = {t}")]
    SlipNotConverged {
        /// Iterations performed.
        iters: u32,
        /// Last change of the velocity.
        change: f64,
        /// Time.
        t: f64,
    },
    /// An event's zero crossing was not located on the dense output.
    #[error("event not located: gap {gap:.3e} at t = {t}")]
    EventNotLocated {
        /// Best estimate of the event time.
        t: f64,
        /// Gap there.
        gap: f64,
    },
    /// The flow field could not be sampled.
    #[error(transparent)]
    Flow(#[from] FlowError),
    /// Invalid parameters were passed to the step.
    #[error(transparent)]
    Param(#[from] ParamError),
}

/// Check that a derived quantity is finite and strictly positive; `inputs` explain it.
pub fn derived(name: &'static str, value: f64, inputs: &[f64]) -> Result<f64, ParamError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(ParamError::Derived {
            name,
            value,
            inputs: inputs.to_vec(),
        })
    }
}

/// Check that `value` is finite and strictly positive.
pub fn positive(name: &'static str, value: f64) -> Result<f64, ParamError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(ParamError::NotPositive { name, value })
    }
}

/// Check that `value` is finite.
pub fn finite(name: &'static str, value: f64) -> Result<f64, ParamError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ParamError::NonFinite { name, value })
    }
}

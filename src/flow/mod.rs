//! Carrier flows. The particle needs the undisturbed fluid velocity u and its gradient
//! l_f = ∇u (`(l_f)_ij = ∂u_i/∂x_j`) at its barycentre (paper Fig. 1, one-way coupling).
//! Analytic fields live in [`analytic`]; meshed CFD fields implement the same trait.
//!
//! # Physics (paper §1.2, Fig. 1, eqs. 17, 22)
//! One-way coupling: the flow is computed without the particles (the macro-scale problem of
//! Fig. 1) and each particle reads u and l_f = ∇u of the undisturbed flow at its barycentre,
//! for the drag (u, eq. 17) and the traction (l_f, eq. 22). The particle must be small against
//! the length over which ∇u changes ([`crate::diagnostics`]).

pub mod analytic;
pub mod bend_poiseuille;
pub mod image;
#[cfg(feature = "mesh")]
pub mod openfoam;
pub mod stagnation;

use crate::error::FlowError;
use crate::tensor::{Mat3, Vec3};
pub use image::{Crossing, Isometry};

/// Velocity, velocity gradient and local acceleration of the undisturbed flow at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlowSample {
    /// Fluid velocity u.
    pub u: Vec3,
    /// Velocity gradient l_f, `(l_f)_ij = ∂u_i/∂x_j`.
    pub grad_u: Mat3,
    /// Local acceleration ∂u/∂t (zero in a steady flow). The fluid-inertia force terms
    /// ([`crate::hydro::forces`]) need the material acceleration Du/Dt = ∂u/∂t + (u·∇)u.
    pub du_dt: Vec3,
    /// Convective acceleration (u·∇)u: the derivative of the sampled u along u. It is
    /// `grad_u * u` wherever `grad_u` is the derivative of u; a field whose `grad_u` is an
    /// estimate of the flow's gradient rather than the derivative of its own u
    /// ([`openfoam::BlendedFlow`]) gives here the derivative of its u, so a fluid parcel
    /// moving with the sampled u has exactly the acceleration Du/Dt of the sample.
    pub convective: Vec3,
}

impl FlowSample {
    /// A sample whose `grad_u` is the derivative of u: (u·∇)u = (∇u)u.
    pub fn new(u: Vec3, grad_u: Mat3, du_dt: Vec3) -> Self {
        Self {
            u,
            grad_u,
            du_dt,
            convective: grad_u * u,
        }
    }

    /// A sample of a steady flow (∂u/∂t = 0) whose `grad_u` is the derivative of u.
    pub fn steady(u: Vec3, grad_u: Mat3) -> Self {
        Self::new(u, grad_u, Vec3::zeros())
    }

    /// Material acceleration of the fluid, Du/Dt = ∂u/∂t + (u·∇)u.
    pub fn material_acceleration(&self) -> Vec3 {
        self.du_dt + self.convective
    }
}

/// A carrier flow field: u and ∇u at (x, t).
///
/// Implementations must be cheap to share across threads (`Send + Sync`) because particles are
/// advanced in parallel. A point outside the domain is a [`FlowError::OutsideDomain`], never a
/// silent extrapolation.
pub trait FlowField: Send + Sync {
    /// Sample u and ∇u at position `x` and time `t`.
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError>;

    /// The flow's rate γ̇: the strain-rate magnitude √(2 D:D), D = sym ∇u, averaged over the
    /// domain by volume. 1/γ̇ is the flow's time scale in a particle's Stokes number τ γ̇
    /// ([`crate::integrator::choice`]). `None` (the default) where the field cannot say; the
    /// automatic integrator choice then keeps the particle's inertia.
    fn strain_rate(&self) -> Option<f64> {
        None
    }

    /// Where x lies outside the domain beyond a patch the particle passes through (a cyclic
    /// patch, a symmetry plane, a wedge), the plane crossed and the symmetry of the flow that
    /// maps x back inside ([`image`]); `None` inside the domain and for a field without such
    /// patches (the default). The driver maps a particle's state with it where its barycentre
    /// crossed the plane.
    fn image(&self, _x: &Vec3, _t: f64) -> Option<Crossing> {
        None
    }
}

/// √(2 D:D) with D = sym ∇u: the shear rate of a simple shear, the strain-rate magnitude of
/// any linear flow.
pub fn strain_rate_magnitude(grad_u: &Mat3) -> f64 {
    let d = (grad_u + grad_u.transpose()) * 0.5;
    (2.0 * d.dot(&d)).sqrt()
}

impl<T: FlowField + ?Sized> FlowField for &T {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        (**self).sample(x, t)
    }

    fn strain_rate(&self) -> Option<f64> {
        (**self).strain_rate()
    }

    fn image(&self, x: &Vec3, t: f64) -> Option<Crossing> {
        (**self).image(x, t)
    }
}

/// Reject non-finite queries before they reach a field implementation.
pub(crate) fn check_query(x: &Vec3, t: f64) -> Result<(), FlowError> {
    if x.iter().all(|c| c.is_finite()) && t.is_finite() {
        Ok(())
    } else {
        Err(FlowError::NonFiniteQuery {
            x: [x[0], x[1], x[2]],
            t,
        })
    }
}

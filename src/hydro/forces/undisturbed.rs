//! The undisturbed-flow force: the pressure gradient and viscous stress of the flow the
//! particle displaces.
//!
//! # Physics (Maxey & Riley 1983, eq. 3.23; Gatignol 1983)
//! The stress of the undisturbed flow integrated over the particle's surface is the force
//! that would accelerate the displaced fluid with the flow, m_f (Du/Dt − g); its gravity part
//! −m_f g is the buoyancy already in the paper's reduced gravity (eq. 13), so the term adds
//! ```math
//! f = m_f\,\frac{Du}{Dt},\qquad \frac{Du}{Dt} = \frac{\partial u}{\partial t} + (\nabla u)\,u,
//! ```
//! m_f = ρ_f vol(B_t), with u, ∇u and ∂u/∂t of the undisturbed flow at the barycentre
//! ([`crate::flow::FlowSample::material_acceleration`]; ∂u/∂t from the time interpolation of
//! transient fields, zero in steady ones). Shape enters only through the volume: the integral
//! of a linear flow's stress over any closed surface is the displaced fluid's. Relative to the
//! particle's inertia the term is of order ρ_f/ρ_p; it matters for particles in liquids and
//! not for aerosols (ρ_f/ρ_p ≈ 10⁻³). Faxén's curvature corrections (∝ r² ∇²u) are left out,
//! as is the curvature of u across the particle in the rest of the model.

use super::{Contribution, ForceContext, ForceTerm, Registration, no_parameters};
use crate::error::ParamError;
use std::collections::BTreeMap;
use std::sync::Arc;

/// The undisturbed-flow (pressure-gradient) force m_f Du/Dt (module docs).
#[derive(Debug, Clone, Copy, Default)]
pub struct UndisturbedFlow;

impl UndisturbedFlow {
    /// Name in scene files.
    pub const NAME: &'static str = "undisturbed_flow";
}

impl ForceTerm for UndisturbedFlow {
    fn name(&self) -> &'static str {
        Self::NAME
    }

    fn contribution(&self, ctx: &ForceContext) -> Contribution {
        Contribution {
            force: ctx.flow.material_acceleration() * ctx.fluid_mass(),
            ..Contribution::default()
        }
    }
}

fn build(parameters: &BTreeMap<String, f64>) -> Result<Arc<dyn ForceTerm>, ParamError> {
    no_parameters(UndisturbedFlow::NAME, parameters)?;
    Ok(Arc::new(UndisturbedFlow))
}

inventory::submit! {
    Registration {
        name: UndisturbedFlow::NAME,
        build,
    }
}

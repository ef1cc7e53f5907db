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

use super::{Contribution, ForceContext, ForceTerm, Observed, Omission, Registration, Rest, Size};
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

    /// m_f Du/Dt: no frame.
    fn orientation_free_on_spheres(&self) -> bool {
        true
    }

    fn contribution(&self, ctx: &ForceContext) -> Contribution {
        Contribution {
            force: ctx.flow.material_acceleration() * ctx.fluid_mass(),
            ..Contribution::default()
        }
    }
}

/// The term's size where it is left out: in quasi-steady slip (v̇ ≈ Du/Dt) the drag balances
/// m Du/Dt − (m − m_f) g without the term and (m − m_f)(Du/Dt − g) with it (added mass cancels
/// there), so omitting it changes the slip by
/// ```math
/// \frac{m_f\,|Du/Dt|}{|(m - m_f)(Du/Dt - g)|},
/// ```
/// about ρ_f/(ρ_p − ρ_f) where the flow's acceleration dominates gravity (2 000 for the cavity's
/// particle) and ρ_f/ρ_p·|Du/Dt|/g where gravity dominates; 0 where Du/Dt = 0, ∞ where the
/// driving vanishes but the term does not (a neutrally buoyant particle in an accelerating
/// flow).
fn omitted(rest: &Rest, at: &Observed) -> f64 {
    let m_f = rest.rho_f * rest.volume0 * at.det_f;
    let du_dt = at.flow.material_acceleration();
    let driving = (du_dt - rest.gravity) * (rest.mass - m_f);
    match (m_f * du_dt.norm(), driving.norm()) {
        (0.0, _) => 0.0,
        (num, den) if den > 0.0 => num / den,
        _ => f64::INFINITY,
    }
}

inventory::submit! {
    Registration {
        name: UndisturbedFlow::NAME,
        build: |p| {
            p.only(&[])?;
            Ok(Arc::new(UndisturbedFlow))
        },
        omitted: Some(Omission {
            order: 10,
            carried_by: None,
            size: Size::PerStateBounded {
                at: omitted,
                before_run: density_ratio,
            },
        }),
    }
}

/// The term's size before a run, from the particle alone: the density ratio ρ_f/ρ_p, the
/// factor in front of |Du/Dt| over the driving (`omitted`) where the flow's acceleration is
/// comparable to the rest of the driving. A scene's advice names the term above
/// [`crate::diagnostics::Thresholds::omitted_term`] of it.
fn density_ratio(rest: &Rest) -> f64 {
    rest.rho_f / rest.rho_p
}

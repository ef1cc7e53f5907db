//! Added mass of an ellipsoid: the fluid the particle must accelerate with it.
//!
//! # Physics (Lamb, *Hydrodynamics*, 6th ed., §§114–115; Maxey & Riley 1983)
//! An ellipsoid with semi-axes r_i translating along its axis i through an ideal fluid
//! carries the added mass ρ_f vol(B_t) k_i with
//! ```math
//! k_i = \frac{A_i}{2 - A_i},\qquad
//! A_i = r_1 r_2 r_3 \int_0^\infty \frac{d\lambda}{(r_i^2 + \lambda)\,\Delta(\lambda)},\qquad
//! \Delta = \sqrt{(r_1^2+\lambda)(r_2^2+\lambda)(r_3^2+\lambda)}
//! ```
//! (Lamb's α₀, β₀, γ₀), i.e. A_i = r₁r₂r₃ α_i with Jeffery's α_i of
//! [`crate::ellipsoid::EllipsoidIntegrals`] (Carlson's R_D): Σ A_i = 2, a sphere has A = 2/3 and
//! k = ½. In global components M_a = ρ_f vol(B_t) Qᵀ diag(k) Q in the current principal frame.
//! In unsteady Stokes flow the same tensor multiplies the particle's acceleration relative to
//! the fluid's (Maxey & Riley's ½ m_f (Du/Dt − dv/dt) for a sphere, with Du/Dt in place of
//! d u/dt along the path to the order of the rest of the model), so the term adds M_a to the
//! particle's inertia and the force M_a Du/Dt. The rate of change of M_a as the particle
//! deforms (a deformation added inertia) is not included: it is of the order of
//! M_a |v − u| |l_s| against the drag, which the validity monitor can estimate.

use super::{Contribution, ForceContext, ForceTerm, Omission, Registration, Rest, Size};
use crate::ellipsoid::EllipsoidIntegrals;
use crate::tensor::{Mat3, Vec3};
use std::sync::Arc;

/// Added mass with the ellipsoid's tensor (module docs).
#[derive(Debug, Clone, Copy, Default)]
pub struct AddedMass;

impl AddedMass {
    /// Name in scene files.
    pub const NAME: &'static str = "added_mass";
}

/// Lamb's coefficients k_i = A_i/(2 − A_i) for translation along each semi-axis r_i, with
/// A_i = r₁r₂r₃ α_i from `ints` (module docs).
pub fn coefficients(ints: &EllipsoidIntegrals) -> Vec3 {
    ints.alpha.map(|alpha| {
        let a = ints.abc * alpha;
        a / (2.0 - a)
    })
}

impl ForceTerm for AddedMass {
    fn name(&self) -> &'static str {
        Self::NAME
    }

    /// ρ_f vol Qᵀ diag(k) Q with k₁ = k₂ = k₃ = ½ on a sphere.
    fn orientation_free_on_spheres(&self) -> bool {
        true
    }

    fn contribution(&self, ctx: &ForceContext) -> Contribution {
        let k = coefficients(ctx.ints);
        let added_mass: Mat3 = ctx.frame.to_global(&Mat3::from_diagonal(&k)) * ctx.fluid_mass();
        Contribution {
            added_mass,
            force: added_mass * ctx.flow.material_acceleration(),
            ..Contribution::default()
        }
    }
}

/// The term's size where it is left out: the response time m/(c μ_f K) grows by M_a/m, at most
/// (ρ_f/ρ_p) max k_i with Lamb's coefficients of the rest shape (½ ρ_f/ρ_p for a sphere); NaN
/// for a rest shape outside Carlson's domain.
fn omitted(rest: &Rest) -> f64 {
    let k_max = EllipsoidIntegrals::try_new(&rest.semi_axes).map_or(f64::NAN, |ints| coefficients(&ints).max());
    rest.rho_f / rest.rho_p * k_max
}

inventory::submit! {
    Registration {
        name: AddedMass::NAME,
        build: |p| {
            p.only(&[])?;
            Ok(Arc::new(AddedMass))
        },
        omitted: Some(Omission {
            order: 20,
            carried_by: None,
            size: Size::Constant(omitted),
        }),
    }
}

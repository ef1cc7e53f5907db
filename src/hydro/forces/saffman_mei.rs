//! Shear lift on a sphere: Saffman's force with Mei's finite-Reynolds-number correction.
//!
//! # Physics (Saffman 1965, 1968 corrigendum; Mei 1992; Crowe et al., *Multiphase Flows with
//! Droplets and Particles*, 2nd ed., §4.4)
//! A sphere of diameter d slipping with w = u − v through a flow of vorticity ω = ∇ × u feels
//! ```math
//! f = 1.615\, d^2 \sqrt{\rho_f \mu_f / |\omega|}\;(w \times \omega)\; C(\mathrm{Re}_p, \beta),
//! ```
//! Saffman's 6.46 μ a² |w| √(|ω|/ν) in vector form, pointing towards the faster fluid for a
//! sphere that lags it. Saffman's result assumes Re_p = ρ_f|w|d/μ_f ≪ Re_ω^{1/2} ≪ 1 with
//! Re_ω = ρ_f|ω|d²/μ_f. Mei (1992) fitted Dandy & Dwyer's (1990) numerical lift for
//! 0.1 ≤ Re_p ≤ 100 with β = ½ Re_ω/Re_p ∈ [0.005, 0.4]:
//! ```math
//! C = (1 - 0.3314\,\beta^{1/2})\,e^{-\mathrm{Re}_p/10} + 0.3314\,\beta^{1/2}\quad(\mathrm{Re}_p \le 40),\qquad
//! C = 0.0524\,(\beta\,\mathrm{Re}_p)^{1/2}\quad(\mathrm{Re}_p > 40),
//! ```
//! which tends to 1 (Saffman) as Re_p → 0. The two branches do not meet at Re_p = 40 for small
//! β (0.041 against 0.023 at β = 0.005), as in Mei's paper; the lift is a few per cent of
//! Saffman's there either way. The force is that of an unbounded shear: within a
//! few diameters of a wall the lift changes sign and size (Cherukat & McLaughlin 1994), which
//! this term does not model. Ellipsoids: the shear lift of a non-spherical particle depends on
//! its orientation and no closed form or accepted correlation covers the shapes of this code
//! (only spheroids at moderate Re by resolved simulation, e.g. Ouchene et al. 2016), so the
//! term admits spheres only.

use super::schiller_naumann::sphere_only;
use super::{Contribution, ForceContext, ForceTerm, Registration, no_parameters};
use crate::error::ParamError;
use crate::tensor::Vec3;
use std::collections::BTreeMap;
use std::sync::Arc;

/// Saffman's shear lift with Mei's correction (module docs).
#[derive(Debug, Clone, Copy, Default)]
pub struct SaffmanMei;

impl SaffmanMei {
    /// Name in scene files.
    pub const NAME: &'static str = "saffman_mei";

    /// Mei's ratio C of the lift to Saffman's at Re_p ≥ 0 and Re_ω ≥ 0 (β = ½ Re_ω/Re_p).
    ///
    /// The branch Re_p ≤ 40 is evaluated as
    /// C = e^{−Re_p/10} + 0.3314 √(Re_ω/2) (1 − e^{−Re_p/10})/√Re_p, the same expression with β
    /// written out: as Re_p → 0 at any Re_ω the second term vanishes like √(Re_ω Re_p)/30 and
    /// C → 1, Saffman's own limit, which is its value at Re_p = 0. Formed through β, it was
    /// (1 − ∞)·1 + ∞ (NaN) at Re_p = 0, and at small Re_p the two large terms (1 − s) e^{…} and
    /// s cancelled to 0 once s = 0.3314 √β exceeded 1/ε.
    pub fn mei_ratio(re_p: f64, re_omega: f64) -> f64 {
        let half = 0.5 * re_omega;
        if re_p == 0.0 {
            1.0
        } else if re_p <= 40.0 {
            let decay = -re_p / 10.0;
            decay.exp() - 0.3314 * half.sqrt() * decay.exp_m1() / re_p.sqrt()
        } else {
            0.0524 * half.sqrt()
        }
    }
}

/// Vorticity ω = ∇ × u of a velocity gradient with `(l)_ij = ∂u_i/∂x_j`.
pub fn vorticity(grad_u: &crate::tensor::Mat3) -> Vec3 {
    Vec3::new(
        grad_u[(2, 1)] - grad_u[(1, 2)],
        grad_u[(0, 2)] - grad_u[(2, 0)],
        grad_u[(1, 0)] - grad_u[(0, 1)],
    )
}

impl ForceTerm for SaffmanMei {
    fn name(&self) -> &'static str {
        Self::NAME
    }

    fn admits(&self, semi_axes: &Vec3) -> Result<(), ParamError> {
        sphere_only(
            "saffman_mei: relative spread of the semi-axes (a sphere's lift)",
            semi_axes,
        )
    }

    fn contribution(&self, ctx: &ForceContext) -> Contribution {
        let omega = vorticity(&ctx.flow.grad_u);
        let w = ctx.slip();
        let magnitude = omega.norm();
        if magnitude == 0.0 || w.norm() == 0.0 {
            return Contribution::default();
        }
        let d = ctx.volume_diameter();
        let re_p = ctx.reynolds();
        let re_omega = ctx.rho_f * magnitude * d * d / ctx.mu_f;
        let ratio = Self::mei_ratio(re_p, re_omega);
        Contribution {
            force: w.cross(&omega) * (1.615 * d * d * (ctx.rho_f * ctx.mu_f / magnitude).sqrt() * ratio),
            ..Contribution::default()
        }
    }
}

fn build(parameters: &BTreeMap<String, f64>) -> Result<Arc<dyn ForceTerm>, ParamError> {
    no_parameters(SaffmanMei::NAME, parameters)?;
    Ok(Arc::new(SaffmanMei))
}

inventory::submit! {
    Registration {
        name: SaffmanMei::NAME,
        build,
    }
}

//! Shear lift on a sphere: Saffman's force, reduced by McLaughlin's J(ε) where the slip
//! competes with the shear at small Reynolds numbers, and following Mei's fit of Dandy &
//! Dwyer's finite-Reynolds-number lift from Re_p = 1 on.
//!
//! # Physics (Saffman 1965, 1968 corrigendum; McLaughlin 1991; Dandy & Dwyer 1990, JFM
//! 216:381; Mei 1992; Crowe et al., *Multiphase Flows with Droplets and Particles*, 2nd ed., §4.4)
//! A sphere of diameter d slipping with w = u − v through a flow of vorticity ω = ∇ × u feels
//! ```math
//! f = 1.615\, d^2 \sqrt{\rho_f \mu_f / |\omega|}\;(w \times \omega)\; C,
//! ```
//! Saffman's 6.46 μ a² |w| √(|ω|/ν) in vector form (C = 1), pointing towards the faster fluid
//! for a sphere that lags it. Saffman's result assumes Re_p = ρ_f|w|d/μ_f ≪ Re_ω^{1/2} ≪ 1
//! with Re_ω = ρ_f|ω|d²/μ_f, i.e. ε → ∞ with
//! ```math
//! \varepsilon = \frac{\mathrm{Re}_\omega^{1/2}}{\mathrm{Re}_p} = \frac{\sqrt{|\omega|\,\nu}}{|w|},
//! ```
//! the ratio of the Oseen length ν/|w| to the Saffman length √(ν/|ω|). ε is McLaughlin's
//! (1991) parameter; it is the same whether both Reynolds numbers are formed with the radius
//! (as McLaughlin does, Re_G = G a²/ν, Re_s = V a/ν) or both with the diameter (Mei 1992),
//! because the length cancels in √(L²)/L. (Mei's β = ½ Re_ω/Re_p does depend on the choice:
//! it is the diameter's here, β = |ω| d/(2|w|), so ε² = 2β/Re_p.)
//!
//! **ε of order 1 or smaller** (McLaughlin 1991, JFM 224:261): for Re_p, Re_ω ≪ 1 at any ε the
//! lift is Saffman's times J(ε)/J(∞), with J(∞) = 2.255 = 6.46 π/9 (McLaughlin writes the lift
//! (9/π) μ a² |w| √(|ω|/ν) J); as ε falls below 1 the lift "rapidly decreases to very small
//! values" (his abstract) and changes sign near ε ≈ 0.2. Mei (1992) fitted McLaughlin's J:
//! ```math
//! J^*(\varepsilon) = \frac{J(\varepsilon)}{J(\infty)}
//!   = \frac{\{1 + \tanh[2.5(\log_{10}\varepsilon + 0.191)]\}\,\{0.667 + \tanh[6(\varepsilon - 0.32)]\}}{2 \cdot 1.667}
//! ```
//! (Mei's 0.6765{…}{…} divided by its own ε → ∞ value 0.6765·2·1.667 = 2.2554, so that
//! J* → 1 exactly: Saffman's limit; dividing by 2.255 instead would give 1.0002).
//! J*(1) = 0.722, J*(0.5) = 0.320, J*(0.3) = 0.053, J*(0.2) = 0.0022; J* < 0 below ε = 0.186,
//! with |J*| < 0.003 there, and J* → 0 as ε → 0 (like ε^{2.17}; the fit's, not McLaughlin's
//! ε⁵ ln ε, tail — both are negligible against Saffman's force).
//!
//! **Finite Re_p** (Mei 1992): Mei fitted Dandy & Dwyer's (1990) numerical lift for
//! 0.1 ≤ Re_p ≤ 100 with β = ½ Re_ω/Re_p ∈ [0.005, 0.4]:
//! ```math
//! C = (1 - 0.3314\,\beta^{1/2})\,e^{-\mathrm{Re}_p/10} + 0.3314\,\beta^{1/2}\quad(\mathrm{Re}_p \le 40),\qquad
//! C = 0.0524\,(\beta\,\mathrm{Re}_p)^{1/2}\quad(\mathrm{Re}_p > 40),
//! ```
//! which tends to 1 (Saffman) as Re_p → 0 at fixed β ([`SaffmanMei::mei_ratio`]).
//!
//! Outside the data the formula is extrapolated, not refused: for Re_p > 100 the branch
//! 0.0524 √(β Re_p) grows without bound at fixed β; for β < 0.005 (at Re_p ≥ 1: ε < 0.1) C
//! tends to e^{−Re_p/10}, a lift ∝ |ω|^{1/2} where a shear weak against the slip gives one
//! that vanishes faster (McLaughlin's ε → 0 limit at low Re_p); for β > 0.4 the term
//! 0.3314 √β grows without bound (Re_ω = 2β Re_p > 0.8 at Re_p ≥ 1, beyond Saffman's
//! Re_ω ≪ 1 as well). The fit also jumps at Re_p = 40, by (1 − 0.3314 √β) e^{−4}
//! (≤ 1.8 % of Saffman's lift). The validity monitor flags the Reynolds numbers
//! (`re_slip`, `re_shear`), not β.
//!
//! **The term** ([`SaffmanMei::lift_ratio`]): the two sources disagree where they meet. At
//! ε < 1 McLaughlin's J* falls towards 0 while Mei's fit of Dandy & Dwyer stays near its
//! e^{−Re_p/10} (at Re_p = 1: 0.91 of Saffman's for β = 0.005–0.05, where ε = 0.1–0.32 and
//! J* is −0.002 to 0.07). Each is used where it is the better source:
//!
//! - **Re_p ≤ 0.1**, McLaughlin's asymptotics (Re_p, Re_ω ≪ 1, any ε): his J*(ε) takes the
//!   place of Saffman's low-Re value 1 in Mei's form,
//! ```math
//! C_{\mathrm{M}} = J^*(\varepsilon)\,e^{-\mathrm{Re}_p/10} + 0.3314\,\beta^{1/2}\,\bigl(1 - e^{-\mathrm{Re}_p/10}\bigr),
//! ```
//!   which is J*(ε) to within Re_p/10 + 0.3314 √β Re_p/10 (≤ 1.2 % of Saffman's lift
//!   for β ≤ 0.4), Saffman's 1 as Re_p → 0 at fixed β (then ε → ∞), and Mei's C wherever J* = 1
//!   (within 1.2 % for ε ≥ 5).
//! - **Re_p ≥ 1**, Dandy & Dwyer's range (0.1 ≤ Re_p ≤ 100, the Navier–Stokes solutions Mei
//!   fitted): Mei's own C ([`SaffmanMei::mei_ratio`]), there the fit is the data.
//! - **0.1 < Re_p < 1**, a C¹ hand-over in x = log₁₀ Re_p + 1 ∈ (0, 1):
//! ```math
//! C = C_{\mathrm{M}} + h(x)\,(C_{\mathrm{Mei}} - C_{\mathrm{M}}),\qquad h(x) = x^2 (3 - 2x),
//! ```
//!   so C and its slope in log Re_p are continuous at both ends (h = 0, 1 and h′ = 0 there)
//!   and C lies between the two fits. The step's own share of the slope is at most
//!   1.5 |C_Mei − C_M| = 1.5 |1 − J*| e^{−Re_p/10} per decade of Re_p (h′ ≤ 3/2, reached at
//!   Re_p = 0.32).
//!
//! The step's ends are where each source's footing ends, not a fit to data: McLaughlin's
//! theory needs Re_p ≪ 1, and from Re_p = 1 on Mei's fit is the only one of the two with
//! data under it. At Dandy & Dwyer's lowest Re_p, 0.1, the two already disagree (Mei's fit
//! close to 1, J* ≤ 0.72 for β ≤ 0.05, ε ≤ 1) while McLaughlin's asymptotics still hold
//! (Re_p = 0.1, Re_ω = 2β Re_p ≤ 0.01); between 0.1 and 1 neither source is clearly better,
//! and no data here decide it. Before, the combination C_M held at every Re_p ≤ 40 and
//! departed from Mei's fit of the data by 13× at Re_p = 1, β = 0.05, 2 500× at β = 0.005
//! (near J*'s zero), and 3.4–26× at Re_p = 10. Loth & Dorgan (2009, Environ. Fluid Mech. 9:187) give a combined
//! J(ε)/finite-Re correlation, but its formula could not be checked against the paper here,
//! so it is not used. At the bend's outer wall (ε ≈ 0.3–1.3, Re_p ≪ 1) the lift is
//! 0.05–0.82 of Saffman's.
//!
//! The force is that of an unbounded shear: within a few diameters of a wall the lift changes
//! sign and size (Cherukat & McLaughlin 1994), which this term does not model. Ellipsoids: the
//! shear lift of a non-spherical particle depends on its orientation and no closed form or
//! accepted correlation covers the shapes of this code (only spheroids at moderate Re by
//! resolved simulation, e.g. Ouchene et al. 2016), so the term admits spheres only.

use super::schiller_naumann::sphere_only;
use super::{Contribution, ForceContext, ForceTerm, Observed, Omission, Registration, Rest, Size};
use crate::error::ParamError;
use crate::tensor::Vec3;
use std::sync::Arc;

/// Saffman's shear lift with McLaughlin's and Mei's corrections (module docs).
#[derive(Debug, Clone, Copy, Default)]
pub struct SaffmanMei;

impl SaffmanMei {
    /// Name in scene files.
    pub const NAME: &'static str = "saffman_mei";

    /// Mei's ratio C of the lift to Saffman's at Re_p ≥ 0 and Re_ω ≥ 0 (β = ½ Re_ω/Re_p),
    /// Saffman's ε → ∞ limit at every Re_p (module docs; [`SaffmanMei::lift_ratio`] is the
    /// term's ratio).
    ///
    /// The branch Re_p ≤ 40 is evaluated as
    /// C = e^{−Re_p/10} + 0.3314 √(Re_ω/2) (1 − e^{−Re_p/10})/√Re_p, the same expression with β
    /// written out: as Re_p → 0 at any Re_ω the second term vanishes like √(Re_ω Re_p)/30 and
    /// C → 1, Saffman's own limit, which is its value at Re_p = 0. Formed through β, it was
    /// (1 − ∞)·1 + ∞ (NaN) at Re_p = 0, and at small Re_p the two large terms (1 − s) e^{…} and
    /// s cancelled to 0 once s = 0.3314 √β exceeded 1/ε.
    pub fn mei_ratio(re_p: f64, re_omega: f64) -> f64 {
        Self::decay(1.0, re_p, re_omega)
    }

    /// McLaughlin's reduction J*(ε) = J(ε)/J(∞) of Saffman's lift in Mei's fit (module docs),
    /// for ε ≥ 0 (∞ allowed): 1 at ε = ∞, 0 at ε = 0, finite everywhere (log₁₀ 0 = −∞ and
    /// tanh(±∞) = ±1 in IEEE arithmetic). NaN for a NaN ε.
    pub fn mclaughlin_ratio(eps: f64) -> f64 {
        (1.0 + (2.5 * (eps.log10() + 0.191)).tanh()) * (0.667 + (6.0 * (eps - 0.32)).tanh()) / (2.0 * 1.667)
    }

    /// McLaughlin's ε = Re_ω^{1/2}/Re_p = √(|ω|ν)/|w| from the two Reynolds numbers (each on
    /// the same length), ∞ at Re_p = 0: within the term (|w|, |ω|, d > 0) Re_p = 0 means ν = ∞
    /// (ρ_f = 0), where ε = √(|ω|ν)/|w| is ∞ too, whatever Re_ω is.
    pub fn epsilon(re_p: f64, re_omega: f64) -> f64 {
        if re_p == 0.0 {
            f64::INFINITY
        } else {
            re_omega.sqrt() / re_p
        }
    }

    /// The term's ratio C of the lift to Saffman's at Re_p ≥ 0 and Re_ω ≥ 0 (module docs):
    /// McLaughlin's J*(ε) in the place of Saffman's low-Re value in Mei's C up to Re_p = 0.1,
    /// Mei's own C ([`SaffmanMei::mei_ratio`]) from Re_p = 1 on, a C¹ step in log₁₀ Re_p
    /// between. Re_p → 0 at fixed ε gives J*(ε); Re_p → 0 at fixed β gives 1; Re_p > 40 gives
    /// Mei's large-Re branch. Finite for finite Re_p, Re_ω ≥ 0.
    pub fn lift_ratio(re_p: f64, re_omega: f64) -> f64 {
        if re_p <= MCLAUGHLIN_RE {
            return Self::mclaughlin_mei_ratio(re_p, re_omega);
        }
        let mei = Self::mei_ratio(re_p, re_omega);
        if re_p >= DANDY_DWYER_RE {
            return mei;
        }
        let low = Self::mclaughlin_mei_ratio(re_p, re_omega);
        let x = (re_p / MCLAUGHLIN_RE).log10() / (DANDY_DWYER_RE / MCLAUGHLIN_RE).log10();
        low + x * x * (3.0 - 2.0 * x) * (mei - low)
    }

    /// C_M: McLaughlin's J*(ε) in the place of Saffman's low-Re value 1 in Mei's C (module
    /// docs), the term's ratio up to Re_p = 0.1.
    fn mclaughlin_mei_ratio(re_p: f64, re_omega: f64) -> f64 {
        Self::decay(Self::mclaughlin_ratio(Self::epsilon(re_p, re_omega)), re_p, re_omega)
    }

    /// C = c₀ e^{−Re_p/10} + 0.3314 √β (1 − e^{−Re_p/10}) (Re_p ≤ 40), 0.0524 √(β Re_p) above,
    /// with c₀ the low-Re value (Saffman's 1 or McLaughlin's J*).
    fn decay(low_re: f64, re_p: f64, re_omega: f64) -> f64 {
        let half = 0.5 * re_omega;
        if re_p == 0.0 {
            low_re
        } else if re_p <= 40.0 {
            let decay = -re_p / 10.0;
            low_re * decay.exp() - 0.3314 * half.sqrt() * decay.exp_m1() / re_p.sqrt()
        } else {
            0.0524 * half.sqrt()
        }
    }
}

/// Re_p up to which the term is McLaughlin's J*(ε) in Mei's decay, C_M (module docs).
const MCLAUGHLIN_RE: f64 = 0.1;
/// Re_p from which the term is Mei's fit of Dandy & Dwyer (module docs).
const DANDY_DWYER_RE: f64 = 1.0;

/// The unit vector along `v` and its length, the length formed from `v` scaled by its largest
/// component (finite for every finite `v`); `v` itself and its largest component for a zero
/// or non-finite `v`, so that NaN and ∞ reach the force.
fn direction(v: &Vec3) -> (Vec3, f64) {
    let largest = v.amax();
    if largest == 0.0 || !largest.is_finite() {
        return (*v, largest);
    }
    let scaled = v / largest;
    let length = scaled.norm();
    (scaled / length, largest * length)
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

    /// A function of the slip and the vorticity.
    fn orientation_free_on_spheres(&self) -> bool {
        true
    }

    /// Formed as f = 1.615 d² √(ρ_f μ_f) |w| |ω|^{1/2} C (ŵ × ω̂), each norm of a vector scaled
    /// by its largest component first: |ω| and |w| stay finite up to f64's largest number (an
    /// unscaled norm overflowed past 1.3·10¹⁵⁴, and 0·∞ made the force NaN), so the force is
    /// right wherever it is representable; beyond, its non-zero components are ±∞, never NaN,
    /// and the step refuses the state.
    fn contribution(&self, ctx: &ForceContext) -> Contribution {
        let (w_hat, w) = direction(&ctx.slip());
        let (omega_hat, magnitude) = direction(&vorticity(&ctx.flow.grad_u));
        if magnitude == 0.0 || w == 0.0 {
            return Contribution::default();
        }
        let d = ctx.volume_diameter();
        let re_p = ctx.rho_f * w * d / ctx.mu_f;
        let re_omega = ctx.rho_f * magnitude * d * d / ctx.mu_f;
        let ratio = Self::lift_ratio(re_p, re_omega);
        let size = 1.615 * d * d * (ctx.rho_f * ctx.mu_f).sqrt() * w * magnitude.sqrt() * ratio;
        Contribution {
            force: w_hat.cross(&omega_hat).map(|c| if c == 0.0 { 0.0 } else { c * size }),
            ..Contribution::default()
        }
    }
}

/// The lift's size where it is left out: this term's lift over the Stokes drag,
/// ```math
/// \frac{1.615\, d^2 \sqrt{\rho_f \mu_f |\omega|}\,|w|\,C}{3\pi \mu_f d\, |w|}
///   = \frac{1.615}{3\pi}\,\mathrm{Re}_\omega^{1/2}\, C,\qquad \mathrm{Re}_\omega = |\omega| d^2/\nu,
/// ```
/// with d = d_eq and the term's own C = [`SaffmanMei::lift_ratio`]`(Re_s, Re_ω)`: McLaughlin's
/// J*(ε) where the slip competes with the shear (ε = Re_ω^{1/2}/Re_s of order 1 or smaller)
/// up to Re_s = 0.1, Mei's fit of Dandy & Dwyer from Re_s = 1 on, Saffman's C = 1 as the slip
/// vanishes (ε → ∞). Saffman's limit alone overstated the lift 1.4× at ε = 1 and 19× at
/// ε = 0.3 (Re_s ≪ 1).
fn omitted(rest: &Rest, at: &Observed) -> f64 {
    let re_omega = vorticity(&at.flow.grad_u).norm() * rest.d_eq * rest.d_eq / rest.nu;
    1.615 / (3.0 * std::f64::consts::PI) * re_omega.sqrt() * SaffmanMei::lift_ratio(at.re_slip, re_omega)
}

inventory::submit! {
    Registration {
        name: SaffmanMei::NAME,
        build: |p| {
            p.only(&[])?;
            Ok(Arc::new(SaffmanMei))
        },
        omitted: Some(Omission {
            order: 40,
            carried_by: None,
            size: Size::PerState(omitted),
        }),
    }
}

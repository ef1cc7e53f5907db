//! Finite-Reynolds-number drag of a non-spherical particle: Hölzer & Sommerfeld's correlation,
//! as a factor on Brenner's exact Stokes tensor.
//!
//! # Physics (Hölzer & Sommerfeld, *Powder Technol.* 184, 361–365, 2008)
//! With Re_p = ρ_f |u − v| d/μ_f on the volume-equivalent diameter d, the sphericity
//! φ = π d²/S (S the surface area) and the crosswise sphericity φ⊥ = (π d²/4)/A⊥ (A⊥ the area
//! projected along the slip), the drag coefficient (on π d²/4) is
//! ```math
//! C_D = \frac{8}{\mathrm{Re}_p\sqrt{φ_⊥}} + \frac{16}{\mathrm{Re}_p\sqrt{φ}}
//!     + \frac{3}{\sqrt{\mathrm{Re}_p}\,φ^{3/4}} + 0.42 \cdot 10^{0.4(-\log_{10} φ)^{0.2}}\,\frac1{φ_⊥},
//! ```
//! fitted to 2 061 measurements of spheres, spheroids, cubes, cylinders and discs up to
//! Re_p ≈ 10⁵ with a mean relative deviation of 14.1 %. Its first two terms are its own
//! Stokes limit; this term divides them out and multiplies Brenner's exact, anisotropic
//! resistance by
//! ```math
//! c = 1 + \mathrm{Re}_p\,\frac{3/(\sqrt{\mathrm{Re}_p}\,φ^{3/4}) + 0.42\cdot10^{0.4(-\log_{10}φ)^{0.2}}/φ_⊥}{8/\sqrt{φ_⊥} + 16/\sqrt{φ}},
//! ```
//! so the drag is exact as Re_p → 0 and carries the correlation's inertial increase beyond
//! (a sphere: c = 1 + (3√Re + 0.42 Re)/24, within 18 % of Schiller–Naumann up to Re = 800 (17.3 % there),
//! which is the correlations' own scatter).
//! S = 4π r₁r₂r₃ R_G(r₁⁻², r₂⁻², r₃⁻²) (DLMF 19.33.1), with R_G from R_F and R_D
//! (DLMF 19.21.10, the middle argument last so that no difference cancels), and
//! A⊥ = π r₁r₂r₃ (Σ n_a²/r_a²)^{1/2} for the slip direction n in the principal frame.
//! The factor is scalar: the correlation gives the drag's size along the slip, not a tensor,
//! which is the usual reading of it (and exact for a sphere).

use super::{Contribution, FINITE_RE_DRAG, ForceContext, ForceTerm, Registration};
use crate::ellipsoid::integrals::{carlson_rd, carlson_rf};
use crate::tensor::Vec3;
use std::f64::consts::PI;
use std::sync::Arc;

/// Hölzer–Sommerfeld drag correction (module docs).
#[derive(Debug, Clone, Copy, Default)]
pub struct HolzerSommerfeld;

impl HolzerSommerfeld {
    /// Name in scene files.
    pub const NAME: &'static str = "holzer_sommerfeld";

    /// The factor c on the Stokes drag at Re_p ≥ 0 with sphericities φ and φ⊥, written as
    /// c = 1 + (3√Re_p/φ^{3/4} + Re_p · 0.42·10^{…}/φ⊥)/(8/√φ⊥ + 16/√φ) (the module's form with
    /// Re_p multiplied in), so that it is finite at Re_p = 0, where it is the Stokes limit 1:
    /// Re_p · 3/√Re_p was 0 · ∞ there (a fluid of density 0, or a slip whose Re_p underflows).
    pub fn factor(re: f64, phi: f64, phi_cross: f64) -> f64 {
        let stokes = 8.0 / phi_cross.sqrt() + 16.0 / phi.sqrt();
        let newton = 0.42 * 10f64.powf(0.4 * (-phi.log10()).max(0.0).powf(0.2)) / phi_cross;
        1.0 + (3.0 * re.sqrt() / phi.powf(0.75) + re * newton) / stokes
    }
}

/// Surface area of the ellipsoid with semi-axes `r`, S = 4π r₁r₂r₃ R_G(r₁⁻², r₂⁻², r₃⁻²);
/// NaN for semi-axes outside Carlson's domain.
pub fn surface_area(r: &Vec3) -> f64 {
    let mut x = [r[0].powi(-2), r[1].powi(-2), r[2].powi(-2)];
    x.sort_by(f64::total_cmp);
    // z the middle argument: (x − z)(y − z) ≤ 0, so the three terms of R_G add.
    let (x, z, y) = (x[0], x[1], x[2]);
    let (Ok(rf), Ok(rd)) = (carlson_rf(x, y, z), carlson_rd(x, y, z)) else {
        return f64::NAN;
    };
    let rg = 0.5 * (z * rf - (x - z) * (y - z) * rd / 3.0 + (x * y / z).sqrt());
    4.0 * PI * r.product() * rg
}

impl ForceTerm for HolzerSommerfeld {
    fn name(&self) -> &'static str {
        Self::NAME
    }

    fn exclusive_group(&self) -> Option<&'static str> {
        Some(FINITE_RE_DRAG)
    }

    /// A sphere's crosswise area and sphericities do not depend on the slip's direction in its frame.
    fn orientation_free_on_spheres(&self) -> bool {
        true
    }

    fn contribution(&self, ctx: &ForceContext) -> Contribution {
        let slip = ctx.slip();
        let speed = slip.norm();
        if speed == 0.0 {
            return Contribution::default();
        }
        let r = ctx.frame.r;
        let d = ctx.volume_diameter();
        let n = ctx.frame.q * (slip / speed);
        let projected = PI * r.product() * n.component_div(&r).norm();
        let phi = PI * d * d / surface_area(&r);
        let phi_cross = 0.25 * PI * d * d / projected;
        Contribution {
            drag_factor: Self::factor(ctx.reynolds(), phi, phi_cross),
            ..Contribution::default()
        }
    }
}

// Not estimated on its own: Schiller–Naumann's estimate of the finite-Re drag stands for every
// correction of FINITE_RE_DRAG, and is not taken for a particle that carries this one.
inventory::submit! {
    Registration {
        name: HolzerSommerfeld::NAME,
        build: |p| {
            p.only(&[])?;
            Ok(Arc::new(HolzerSommerfeld))
        },
        omitted: None,
    }
}

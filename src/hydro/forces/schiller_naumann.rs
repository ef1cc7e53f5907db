//! Finite-Reynolds-number drag of a sphere: Schiller & Naumann's correction to Stokes' law.
//!
//! # Physics (Schiller & Naumann 1933; Clift, Grace & Weber, *Bubbles, Drops and Particles*,
//! 1978, Table 5.2)
//! With Re_p = ρ_f |u − v| d/μ_f the drag is Stokes' times
//! ```math
//! c = 1 + 0.15\,\mathrm{Re}_p^{0.687}\quad(\mathrm{Re}_p \le 1000),\qquad
//! c = 0.44\,\mathrm{Re}_p/24\quad(\mathrm{Re}_p > 1000,\ \text{Newton's regime}),
//! ```
//! within about 5 % of the standard drag curve for Re_p < 800 (Clift et al.). The factor
//! multiplies the particle's Stokes resistance μ_f K̂; it is a sphere's correlation, so the
//! term admits spherical particles only (rest semi-axes equal to 10⁻⁶): a soft sphere's
//! deformation is assumed small enough that the volume-equivalent diameter carries it. For
//! ellipsoids at finite Re use [`super::HolzerSommerfeld`].

use super::{Contribution, FINITE_RE_DRAG, ForceContext, ForceTerm, Observed, Omission, Registration, Rest, Size};
use crate::error::ParamError;
use crate::tensor::Vec3;
use std::sync::Arc;

/// Relative spread of the rest semi-axes below which a particle counts as a sphere.
pub const SPHERE_SPREAD: f64 = 1e-6;

/// Schiller–Naumann drag correction (module docs).
#[derive(Debug, Clone, Copy, Default)]
pub struct SchillerNaumann;

impl SchillerNaumann {
    /// Name in scene files.
    pub const NAME: &'static str = "schiller_naumann";

    /// The factor c(Re_p) on Stokes' drag.
    pub fn factor(re: f64) -> f64 {
        if re <= 1000.0 {
            1.0 + 0.15 * re.powf(0.687)
        } else {
            0.44 * re / 24.0
        }
    }
}

/// Refuse a rest shape whose semi-axes spread by more than [`SPHERE_SPREAD`]; `what` names
/// the term and why in the error.
pub(crate) fn sphere_only(what: &'static str, semi_axes: &Vec3) -> Result<(), ParamError> {
    let spread = (semi_axes.max() - semi_axes.min()) / semi_axes.max();
    if spread <= SPHERE_SPREAD {
        Ok(())
    } else {
        Err(ParamError::OutOfRange {
            name: what,
            value: spread,
            min: 0.0,
            max: SPHERE_SPREAD,
        })
    }
}

impl ForceTerm for SchillerNaumann {
    fn name(&self) -> &'static str {
        Self::NAME
    }

    fn admits(&self, semi_axes: &Vec3) -> Result<(), ParamError> {
        sphere_only(
            "schiller_naumann: relative spread of the semi-axes (a sphere's correlation)",
            semi_axes,
        )
    }

    fn exclusive_group(&self) -> Option<&'static str> {
        Some(FINITE_RE_DRAG)
    }

    /// Spheres only, and its factor is a function of the slip's Reynolds number.
    fn orientation_free_on_spheres(&self) -> bool {
        true
    }

    fn contribution(&self, ctx: &ForceContext) -> Contribution {
        Contribution {
            drag_factor: Self::factor(ctx.reynolds()),
            ..Contribution::default()
        }
    }
}

/// The finite-Re drag's size where no correction of [`FINITE_RE_DRAG`] is carried: this
/// correlation's increase c − 1 = 0.15 Re_s^{0.687} at the slip Reynolds number, the relative
/// change of the drag (a sphere's correlation, taken as the size for every shape).
fn omitted(_: &Rest, at: &Observed) -> f64 {
    SchillerNaumann::factor(at.re_slip) - 1.0
}

inventory::submit! {
    Registration {
        name: SchillerNaumann::NAME,
        build: |p| {
            p.only(&[])?;
            Ok(Arc::new(SchillerNaumann))
        },
        omitted: Some(Omission {
            order: 30,
            carried_by: Some(FINITE_RE_DRAG),
            size: Size::PerState(omitted),
        }),
    }
}

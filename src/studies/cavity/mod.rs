//! Soft and quasi-rigid ellipsoids in the lid-driven cavity (paper §6.3, Figs 13–16).
//!
//! # Set-up (paper §6.3)
//! Cube L = 0.1 m, lid z = L moving at U = 0.0813 m/s along +x, ν_f = 17.3 mm²/s (Re = 470),
//! steady field from OpenFOAM (simpleFoam's `U` on 60³ cells, `reference-data/cavity-re470-foam`,
//! read by [`crate::flow::openfoam`]: [`shipped_flow`]). Particles: d_eq = 3 mm,
//! ρ_p = 1209.395 kg/m³ and ρ* = (ρ_f − ρ_p)/ρ_f = +0.05 %, so ρ_f = ρ_p/(1 − 5e-4) ≈ 1210 kg/m³;
//! gravity −9.81 m/s² e_z; release at (0.467 L, 0.4 L, 0.983 L) with the local fluid velocity.
//! Ca = μ_f γ̇₀/μ_s with γ̇₀ = √(2 d:d) of the flow at the release point (the paper computes
//! Ca "depending on the shear rate at the injection position").
//!
//! Readings where the paper is silent: the initial long axis is along the lid motion x (for
//! oblate shapes the two long axes span x–y, the short one is vertical); the barycentre is
//! inertial (St ≈ 0.02).
//!
//! Shape dynamics ([`ShapeModel`]): at the release point γ̇₀ = 10.6 s⁻¹, so the shape's
//! nondimensional density is ρ* = ρ_p γ̇₀ d_eq²/μ_f ≈ 5.5, not small: solid inertia is not
//! negligible against the viscous load, and the paper integrates it (§5). Figs 15/16 therefore
//! use the inertial model ([`ShapeModel::Inertial`], the paper's IMEX step with error control);
//! [`ShapeModel::Inertialess`] (ρ* → 0) is kept for comparison and for the rigid limit, which
//! has no shape dynamics. Caution: for thin soft shapes (oblate 5 and 8, prolate 5 at high Ca)
//! the inertial runs change outcome between tolerances 10⁻⁶ and 10⁻⁷, where a fast mode
//! (dilatational: |J − 1| grows to O(1), which reverses the 0.05 % buoyancy) grows and lifts
//! the particle to the lid within a second; see the
//! Figs 15/16 dataset notes. The particle Reynolds number at release is Re_γ = γ̇₀ d_eq²/ν ≈ 5.5:
//! creeping flow at the particle scale is itself violated ([`crate::diagnostics`]).
//!
//! Where the paper contradicts itself (§6, §6.3), this scene follows the stated set-up:
//! - it quotes u⁰ = 0.367 m/s at the release point, 4.5× the lid speed; the field gives
//!   ≈ 0.062 m/s there (its Re_p ≈ 64 "worst case" rests on the larger value);
//! - it quotes Stk = 0.0023, but its eqs. 25–26 with d_eq = 3 mm, U = 0.0813 m/s, L = 0.1 m give
//!   (ρ_p/ρ_f) d_eq² U/(18 ν_f L) = 0.0235;
//! - its sentence on λ₁ = 8 says particles with Ca ≥ 0.25 leave through the lid and that the one
//!   with Ca ≥ 0.75 sticks to the right wall.
//!
//! Set-up uncertainties ([`Variant`]): the lid direction is given only in a figure, the field
//! carries the grid error of its solver (≈ 4 %), and outcomes depend on the initial
//! orientation; [`Variant`] mirrors the lid motion and scales the field, and
//! [`Cavity::track`] turns the release.
//!
//! Wall rules (paper §6.3): a particle touching the lid leaves the cavity; one touching any
//! other wall sticks. In the top corners a particle can be equally near the lid and a side wall;
//! the lid is decided first ([`Planes::nearest`](crate::contact::Boundary::nearest) lets the
//! first-listed wall win ties), so such a particle exits: it has reached the lid's height, which
//! is the paper's exit criterion. Contact uses the particle's extent (support distance of the
//! ellipsoid, [`crate::contact`]) or, as a point-particle tracker would, the barycentre only
//! ([`Contact`]). The release point is 1.7 mm below the lid while the particles are 2.4–4.8 mm
//! long, so with the extent rule a tilting prolate touches the lid within a fraction of a second.
//!
//! # Layout
//! This module holds the set-up's numbers, walls ([`walls`]) and releases; `setup` the choices
//! a run is made of ([`Contact`], [`Launch`], [`Variant`], [`ShapeModel`], [`fluid_inertia`]);
//! `tracking` particles through the cavity ([`Cavity`], [`Tracking`], [`CavityRun`],
//! [`CavityFate`], [`MemberError`], [`Slip`]): releases are a population of
//! [`crate::population`] (an injector, the cavity's observer of path, validity and slip), a
//! run keeps the record's [`crate::population::Fate`] and [`CavityFate`] reads it in the
//! cavity's terms; `datasets` the
//! tables and panels of single runs; `ensemble` the outcome fractions over orientations and
//! field variants ([`Ensemble`], [`Member`]).

use super::StudyError;
use crate::contact::{ContactModel, PatchRule, Plane, Planes};
use crate::diagnostics::{Monitor, Thresholds, Validity};
use crate::driver::{Plan, RunStats};
use crate::error::{ParamError, StepError};
use crate::flow::FlowField;
use crate::flow::openfoam::{BlendedFlow, FoamError};
use crate::hydro::forces::{AddedMass, UndisturbedFlow};
use crate::hydro::{Brenner, DragModel, ForceTerms, VolumetricTraction};
use crate::integrator::{BarycentreModel, ImexAdaptive, Scheme, Stokesian, TimeIntegrator};
use crate::material::{LawFactory, NeoHookeFactory};
use crate::particle::{Fluid, Particle, State};
pub use crate::studies::particles::Shape;
use crate::studies::particles::{Deformability, ParticleModel, StudyResponse};
use crate::tensor::{Mat3, Vec3, sym};
use serde::Serialize;
use std::sync::Arc;

mod datasets;
mod ensemble;
mod setup;
mod tracking;

pub use datasets::*;
pub use ensemble::*;
pub use setup::*;
pub use tracking::*;

/// Contact distance of [`Contact::Barycentre`]: 0.15 d_eq, the smallest rest semi-axis of the
/// most elongated shapes of §6.3 (prolate 8: r_min = d_eq/(2·8^{1/3}) = 0.25 d_eq) with margin,
/// so that the integrator's trial stages (which move ≤ 0.25 r_min per step) stay in the mesh.
pub const BARYCENTRE_CONTACT_DISTANCE: f64 = 0.15 * D_EQ;

/// Cavity edge L (m).
pub const EDGE: f64 = 0.1;
/// Lid velocity [m/s].
pub const LID_VELOCITY: f64 = 0.0813;
/// Kinematic viscosity [m²/s].
pub const NU: f64 = 17.3e-6;
/// Particle density [kg/m³].
pub const RHO_PARTICLE: f64 = 1209.395;
/// ρ* = (ρ_f − ρ_p)/ρ_f.
pub const RHO_STAR: f64 = 5e-4;
/// Volume-equivalent diameter (m).
pub const D_EQ: f64 = 3e-3;

/// Fluid density ρ_f = ρ_p/(1 − ρ*).
pub fn rho_fluid() -> f64 {
    RHO_PARTICLE / (1.0 - RHO_STAR)
}

/// The shipped Re = 470 field ([`crate::studies::cavity_benchmark::RE470`]) as the scene samples
/// it: the cells' linear fits blended continuously, with the second-order no-slip wall layer
/// ([`BlendedFlow`]), so the gradient a particle reads is consistent with the velocity it
/// reads to O(h) and the lid and wall velocities hold on the walls.
pub fn shipped_flow() -> Result<BlendedFlow, FoamError> {
    BlendedFlow::new(crate::studies::cavity_benchmark::RE470.load()?)
}

/// Names of the cavity's walls in patch order ([`walls`]): the lid, then the bottom and the
/// side walls x = 0, x = L, y = 0, y = L.
pub const WALL_NAMES: [&str; 6] = ["lid", "bottom", "x0", "x1", "y0", "y1"];

/// The cube [0, L]³ of paper §6.3 with edge `edge`: the lid z = L ([`PatchRule::Exit`]: a
/// particle touching it leaves the cavity) first, then the five other walls
/// ([`PatchRule::Stick`]), named as [`WALL_NAMES`]. The lid is listed first so that it wins
/// ties in the top corners ([`Planes::nearest`](crate::contact::Boundary::nearest)).
pub fn walls(edge: f64) -> Result<Planes, ParamError> {
    let l = crate::error::positive("cavity edge", edge)?;
    let wall = |name: &str, point: Vec3, normal: Vec3, rule| Plane {
        name: name.to_string(),
        point,
        normal,
        rule,
    };
    let (o, top) = (Vec3::zeros(), Vec3::repeat(l));
    let [lid, bottom, x0, x1, y0, y1] = WALL_NAMES;
    Planes::new(vec![
        wall(lid, top, Vec3::z(), PatchRule::Exit),
        wall(bottom, o, -Vec3::z(), PatchRule::Stick),
        wall(x0, o, -Vec3::x(), PatchRule::Stick),
        wall(x1, top, Vec3::x(), PatchRule::Stick),
        wall(y0, o, -Vec3::y(), PatchRule::Stick),
        wall(y1, top, Vec3::y(), PatchRule::Stick),
    ])
}

/// Release point (0.467 L, 0.4 L, 0.983 L).
pub fn release_point() -> Vec3 {
    Vec3::new(0.467, 0.4, 0.983) * EDGE
}

/// The 28 soft releases of Figs 15/16: prolates λ₁ = 1, 2, 5, 8 and oblates λ₁ = 2, 5, 8 at
/// Ca = 0.001, 0.25, 0.5, 0.75.
pub fn fig15_fig16_releases() -> Vec<Launch> {
    let shapes = [
        Shape::Prolate(1.0),
        Shape::Prolate(2.0),
        Shape::Prolate(5.0),
        Shape::Prolate(8.0),
        Shape::Oblate(2.0),
        Shape::Oblate(5.0),
        Shape::Oblate(8.0),
    ];
    shapes
        .iter()
        .flat_map(|&shape| {
            [0.001, 0.25, 0.5, 0.75].map(|ca| Launch {
                shape,
                softness: Deformability::Elastic { ca },
            })
        })
        .collect()
}

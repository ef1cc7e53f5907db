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
//! [`Cavity::track_oriented`] turns the release.
//!
//! Wall rules (paper §6.3): a particle touching the lid leaves the cavity; one touching any
//! other wall sticks. In the top corners a particle can be equally near the lid and a side wall;
//! the lid is decided first ([`Planes::nearest`] lets the first-listed wall win ties), so such a
//! particle exits: it has reached the lid's height, which is the paper's exit criterion. Contact
//! uses the particle's extent (support distance of the ellipsoid, [`crate::contact`]) or, as a
//! point-particle tracker would, the barycentre only ([`Contact`]). The release point is 1.7 mm
//! below the lid while the particles are 2.4–4.8 mm long, so with the extent rule a
//! tilting prolate touches the lid within a fraction of a second.

use super::SceneError;
use crate::contact::{Boundary, ContactEvent, ContactModel, PatchRule, Planes};
use crate::diagnostics::{Monitor, Thresholds, Validity};
use crate::driver::{Plan, RunStats, Stop, integrate};
use crate::error::{ParamError, StepError};
use crate::flow::FlowField;
use crate::flow::openfoam::{BlendedFlow, FoamError};
use crate::hydro::forces::{AddedMass, UndisturbedFlow};
use crate::hydro::{Brenner, DragModel, ForceTerms, VolumetricTraction};
use crate::integrator::{BarycentreModel, ImexAdaptive, Scheme, Stokesian, TimeIntegrator};
use crate::material::{LawFactory, NeoHookeLaw};
use crate::particle::{Fluid, Particle, State};
pub use crate::scenes::particles::Shape;
use crate::scenes::particles::{Deformability, ParticleModel, SceneResponse};
use crate::tensor::{Mat3, Vec3, sym};
use serde::Serialize;
use std::sync::Arc;

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

/// The shipped Re = 470 field ([`crate::scenes::cavity_benchmark::RE470`]) as the scene samples
/// it: the cells' linear fits blended continuously, with the second-order no-slip wall layer
/// ([`BlendedFlow`]), so the gradient a particle reads is consistent with the velocity it
/// reads to O(h) and the lid and wall velocities hold on the walls.
pub fn shipped_flow() -> Result<BlendedFlow, FoamError> {
    BlendedFlow::new(crate::scenes::cavity_benchmark::RE470.load()?)
}

/// Release point (0.467 L, 0.4 L, 0.983 L).
pub fn release_point() -> Vec3 {
    Vec3::new(0.467, 0.4, 0.983) * EDGE
}

/// The 28 soft releases of Figs 15/16: prolates λ₁ = 1, 2, 5, 8 and oblates λ₁ = 2, 5, 8 at
/// Ca = 0.001, 0.25, 0.5, 0.75.
pub fn fig15_fig16_releases() -> Vec<Release> {
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
            [0.001, 0.25, 0.5, 0.75].map(|ca| Release {
                shape,
                softness: Deformability::Elastic { ca },
            })
        })
        .collect()
}

/// What touches a wall.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Contact {
    /// The particle's surface (support distance of the current ellipsoid): physical.
    Extent,
    /// The barycentre (a point particle, as a point-particle tracker does), touching at a fixed
    /// distance of [`BARYCENTRE_CONTACT_DISTANCE`] from a wall. The distance is fixed, not a
    /// fraction of the current shape: a soft particle thinning in the corner flow would
    /// otherwise shrink its own margin to nothing and park against the wall.
    Barycentre,
}

impl Contact {
    /// Label for datasets.
    pub fn label(self) -> &'static str {
        match self {
            Contact::Extent => "extent",
            Contact::Barycentre => "barycentre",
        }
    }
}

/// One release: shape and softness (Ca at the release shear rate γ̇₀).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Release {
    /// Initial shape.
    pub shape: Shape,
    /// Deformability.
    pub softness: Deformability,
}

impl Release {
    /// Capillary number, or `None` for the rigid limit.
    pub fn ca(&self) -> Option<f64> {
        match self.softness {
            Deformability::Rigid => None,
            Deformability::Elastic { ca } => Some(ca),
        }
    }
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum Outcome {
    /// Left through the lid.
    Exited {
        /// Time (s).
        t: f64,
    },
    /// Stuck to a wall.
    Deposited {
        /// Time (s).
        t: f64,
        /// Wall name.
        wall: String,
    },
    /// Still suspended at the end of tracking.
    Suspended,
    /// The particle's run failed (a typed step error), recorded instead of ending the study.
    Failed {
        /// Time of the last accepted step (s).
        t: f64,
        /// The error.
        reason: String,
    },
}

/// A tracked particle.
#[derive(Debug, Clone, Serialize)]
pub struct CavityRun {
    /// The release.
    pub release: Release,
    /// Contact model used.
    pub contact: Contact,
    /// Shape model used (inertialess for the rigid limit whatever was asked).
    pub shape_model: ShapeModel,
    /// (t, x) samples [s, m].
    pub path: Vec<(f64, Vec3)>,
    /// Outcome.
    pub outcome: Outcome,
    /// Work.
    pub stats: RunStats,
    /// Validity diagnostics over the accepted steps (r₁ in m).
    pub validity: Validity,
    /// Slip relative to the fluid over the accepted steps.
    pub slip: Slip,
}

/// The particle's slip |v − u(x)| relative to the undisturbed fluid at its barycentre over a
/// run's accepted steps [m/s]: the drift that the fluid-inertia force terms act on
/// (`paper-figures/fig15_fig16/NOTES.md`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Slip {
    /// Largest slip.
    pub max: f64,
    /// Median over time: each step's end-state slip weighted by the step's length, so that the
    /// short steps near walls do not outvote the rest of the path.
    pub median: f64,
}

impl Slip {
    /// From (step length, slip) samples; zeros for none.
    fn of(mut samples: Vec<(f64, f64)>) -> Self {
        samples.sort_by(|a, b| a.1.total_cmp(&b.1));
        let total: f64 = samples.iter().map(|s| s.0).sum();
        let mut seen = 0.0;
        let median = samples
            .iter()
            .find(|(dt, _)| {
                seen += dt;
                seen >= 0.5 * total
            })
            .map_or(0.0, |s| s.1);
        Self {
            max: samples.last().map_or(0.0, |s| s.1),
            median,
        }
    }
}

/// One point of [`Cavity::quasi_steady_slip`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct QuasiSteady {
    /// The quasi-steady slip |w| [m/s].
    pub slip: f64,
    /// |A − a|/|a|: how far the field's (∇u)u is from the true acceleration along the
    /// streamline.
    pub acceleration_gap: f64,
}

/// How the shape responds (the barycentre is inertial in both).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum ShapeModel {
    /// Inertialess shape (ρ* → 0): [`Stokesian`] at rtol = atol = tol, Radau IIA unless
    /// [`Cavity::with_scheme`] says otherwise.
    Inertialess,
    /// Solid inertia as in the paper: [`ImexAdaptive`] with local tolerance tol.
    Inertial,
}

impl ShapeModel {
    /// Label for datasets.
    pub fn label(self) -> &'static str {
        match self {
            ShapeModel::Inertialess => "inertialess",
            ShapeModel::Inertial => "inertial",
        }
    }
}

/// A variant of the shipped field within the set-up's uncertainty.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Variant {
    /// Mirror about x = L/2: the lid moves along −x (the release point stays where it is).
    pub mirrored: bool,
    /// Factor on u and ∇u (the field's grid error is ≈ 4 %).
    pub scale: f64,
}

impl Default for Variant {
    fn default() -> Self {
        Self {
            mirrored: false,
            scale: 1.0,
        }
    }
}

/// The shipped field seen through a [`Variant`]: with J = diag(−1, 1, 1) and the mirror
/// x ↦ Jx + L e_x, u′(x) = s J u(Jx + L e_x) and ∇u′(x) = s J ∇u(Jx + L e_x) J.
struct VariantFlow<'a> {
    mesh: &'a BlendedFlow,
    variant: Variant,
}

impl FlowField for VariantFlow<'_> {
    fn sample(&self, x: &Vec3, t: f64) -> Result<crate::flow::FlowSample, crate::error::FlowError> {
        let s = self.variant.scale;
        if !self.variant.mirrored {
            let mut sample = self.mesh.sample(x, t)?;
            sample.u *= s;
            sample.grad_u *= s;
            return Ok(sample);
        }
        let j = Mat3::from_diagonal(&Vec3::new(-1.0, 1.0, 1.0));
        let mut sample = self.mesh.sample(&Vec3::new(EDGE - x[0], x[1], x[2]), t)?;
        sample.u = j * sample.u * s;
        sample.grad_u = j * sample.grad_u * j * s;
        Ok(sample)
    }
}

/// The fluid-inertia force terms a particle of nearly the fluid's density needs (the cavity's
/// ρ_p/ρ_f = 1 − ρ* = 0.9995): the undisturbed-flow force and added mass
/// ([`crate::hydro::forces`]).
pub fn fluid_inertia() -> Result<ForceTerms, ParamError> {
    ForceTerms::new(vec![Arc::new(UndisturbedFlow), Arc::new(AddedMass)])
}

/// The cavity experiment: flow field, walls, fluid and the particle model (law family and drag;
/// the paper's Neo-Hooke and Brenner by default).
pub struct Cavity<'a, L = NeoHookeLaw, D = Brenner> {
    flow: VariantFlow<'a>,
    boundary: Planes,
    fluid: Fluid,
    shear_rate: f64,
    shape_model: ShapeModel,
    /// Scheme of the inertialess path.
    scheme: Scheme,
    model: ParticleModel<L, D>,
    /// Force terms beyond the paper's (none: the paper's model).
    forces: ForceTerms,
}

impl<'a> Cavity<'a> {
    /// Experiment on a loaded Re = 470 field ([`shipped_flow`]), inertialess shapes, the paper's
    /// particle model.
    pub fn new(flow: &'a BlendedFlow) -> Result<Self, SceneError> {
        let d = sym(&flow.sample(&release_point(), 0.0).map_err(StepError::from)?.grad_u);
        let shear_rate = (2.0 * d.component_mul(&d).sum()).sqrt();
        Ok(Self {
            flow: VariantFlow {
                mesh: flow,
                variant: Variant::default(),
            },
            boundary: Planes::cavity(EDGE)?,
            fluid: Fluid::new(rho_fluid() * NU, rho_fluid())?,
            shear_rate,
            shape_model: ShapeModel::Inertialess,
            scheme: Scheme::Radau5,
            model: ParticleModel::default(),
            forces: ForceTerms::default(),
        })
    }
}

impl<'a, L: LawFactory, D: DragModel + Clone> Cavity<'a, L, D> {
    /// The same experiment with another particle model (law family, drag, bulk ratio).
    pub fn with_model<L2: LawFactory, D2: DragModel + Clone>(self, model: ParticleModel<L2, D2>) -> Cavity<'a, L2, D2> {
        Cavity {
            flow: self.flow,
            boundary: self.boundary,
            fluid: self.fluid,
            shear_rate: self.shear_rate,
            shape_model: self.shape_model,
            scheme: self.scheme,
            model,
            forces: self.forces,
        }
    }

    /// The same experiment with force terms beyond the paper's on the particle (e.g. the
    /// fluid-inertia terms [`fluid_inertia`]).
    pub fn with_forces(self, forces: ForceTerms) -> Self {
        Self { forces, ..self }
    }

    /// The same experiment with another scheme for the inertialess shape model (and the rigid
    /// limit, which always takes that path).
    pub fn with_scheme(self, scheme: Scheme) -> Self {
        Self { scheme, ..self }
    }

    /// The same experiment with another shape model.
    pub fn with_shape_model(self, shape_model: ShapeModel) -> Self {
        Self { shape_model, ..self }
    }

    /// The same experiment in a variant of the field. The particles keep their stiffness: Ca
    /// stays defined by the nominal field's γ̇₀ (the particle is real, the field uncertain).
    pub fn with_variant(self, variant: Variant) -> Result<Self, SceneError> {
        crate::error::positive("field scale", variant.scale)?;
        Ok(Self {
            flow: VariantFlow { variant, ..self.flow },
            ..self
        })
    }

    /// The same experiment with a neutrally buoyant particle (ρ_f = ρ_p, ν unchanged).
    pub fn neutrally_buoyant(self) -> Result<Self, SceneError> {
        Ok(Self {
            fluid: Fluid::new(RHO_PARTICLE * NU, RHO_PARTICLE)?,
            ..self
        })
    }

    /// The experiment's flow (the shipped field in its [`Variant`]) at `x`.
    pub fn sample(&self, x: &Vec3) -> Result<crate::flow::FlowSample, crate::error::FlowError> {
        self.flow.sample(x, 0.0)
    }

    /// Along `run`'s output path, the slip a Stokes sphere of the particle's volume has in
    /// quasi-steady motion (Maxey & Riley 1983 without the history force): with v̇ = a, the
    /// fluid's true acceleration along the streamline, the barycentre equation gives
    /// ```math
    /// ζ (u − v) = (m + C_m m_f)\,a − (C_u + C_m)\,m_f A − (m − m_f)\,g,\qquad ζ = 3πμ_f d_{eq},
    /// ```
    /// C_u = 1 with the undisturbed-flow force, C_m = ½ with added mass (0 without), and A the
    /// field's (∇u)u that those terms use. Without the terms the inertial drift is m a/ζ; with
    /// both it is (m − m_f) a/ζ, smaller by ρ_p/|ρ_p − ρ_f| (2 000 here), plus 1.5 m_f (a − A)/ζ
    /// wherever the field's gradient is not the derivative of its velocity. a is the central
    /// difference of u over ±`step` along the streamline. For other shapes it is an estimate.
    pub fn quasi_steady_slip(&self, run: &CavityRun, step: f64) -> Result<Vec<QuasiSteady>, SceneError> {
        crate::error::positive("difference step", step)?;
        let names = self.forces.names();
        let c_u = if names.contains(&UndisturbedFlow::NAME) {
            1.0
        } else {
            0.0
        };
        let c_m = if names.contains(&AddedMass::NAME) { 0.5 } else { 0.0 };
        let volume = std::f64::consts::PI / 6.0 * D_EQ.powi(3);
        let (m, m_f) = (RHO_PARTICLE * volume, self.fluid.rho * volume);
        let zeta = 3.0 * std::f64::consts::PI * self.fluid.mu * D_EQ;
        let g = Vec3::new(0.0, 0.0, -9.81);
        let mut out = Vec::with_capacity(run.path.len());
        for (_, x) in &run.path {
            let s = self.flow.sample(x, 0.0).map_err(StepError::from)?;
            let field = s.material_acceleration();
            let speed = s.u.norm();
            if speed == 0.0 {
                continue;
            }
            let along = s.u * (step / speed);
            let ahead = self.flow.sample(&(x + along), 0.0).map_err(StepError::from)?;
            let behind = self.flow.sample(&(x - along), 0.0).map_err(StepError::from)?;
            let true_acceleration = (ahead.u - behind.u) * (speed / (2.0 * step));
            let lag = (true_acceleration * (m + c_m * m_f) - field * ((c_u + c_m) * m_f) - g * (m - m_f)) / zeta;
            out.push(QuasiSteady {
                slip: lag.norm(),
                acceleration_gap: (field - true_acceleration).norm() / true_acceleration.norm(),
            });
        }
        Ok(out)
    }

    /// γ̇₀ = √(2 d:d) at the release point [1/s].
    pub fn release_shear_rate(&self) -> f64 {
        self.shear_rate
    }

    fn particle(&self, release: &Release) -> Result<Particle<SceneResponse<L>, D>, SceneError> {
        let shape = release.shape.ellipsoid(D_EQ, Mat3::identity())?;
        // The inertial runs are error-controlled, so they resolve what the traction does to the
        // volume mode: the literal eq. 12 anti-damps dilation (see
        // `integrator::imex::volume_mode_floor`; at tol 1e-7 J − 1 grew from 3e-5 to 1.6), the
        // source-flow term resists it as a fluid does. Shapes are unaffected (|J − 1| ≈ 1e-4
        // at λ_s/μ_s = 1e3); the inertialess model keeps tr l_s = 0 and ignores the choice.
        // The rigid limit (Ca → 0) is a rigid particle: Jeffery rotation, no elasticity.
        let particle = self.model.particle(
            shape,
            release.softness,
            self.fluid.mu * self.shear_rate,
            self.fluid,
            RHO_PARTICLE,
        )?;
        Ok(particle
            .with_gravity(Vec3::new(0.0, 0.0, -9.81))?
            .with_volumetric(VolumetricTraction::Source)
            .with_forces(self.forces.clone())?)
    }

    /// Track `release` for `t_max` seconds with tolerance `tol`, sampling every `dt_out`;
    /// `contact` decides what must touch a wall.
    pub fn track(
        &self,
        release: Release,
        contact_model: Contact,
        t_max: f64,
        tol: f64,
        dt_out: f64,
    ) -> Result<CavityRun, SceneError> {
        self.track_oriented(release, contact_model, &Mat3::identity(), t_max, tol, dt_out)
    }

    /// [`Self::track`] with the release turned by the rotation `turn` (its axes become
    /// turn·(e_x, e_y, e_z)); F = turn, so the stress-free shape is turned as a rigid body.
    pub fn track_oriented(
        &self,
        release: Release,
        contact_model: Contact,
        turn: &Mat3,
        t_max: f64,
        tol: f64,
        dt_out: f64,
    ) -> Result<CavityRun, SceneError> {
        let model = match (self.shape_model, release.softness) {
            (ShapeModel::Inertial, Deformability::Elastic { .. }) => ShapeModel::Inertial,
            _ => ShapeModel::Inertialess,
        };
        match model {
            ShapeModel::Inertial => {
                let integ = ImexAdaptive::new(tol)?;
                self.track_with(&integ, model, release, contact_model, turn, t_max, dt_out)
            }
            ShapeModel::Inertialess => {
                // Rigid releases are rigid particles (see `particle`); the integrator is the same.
                let mut integ = Stokesian::new(tol)?.with_scheme(self.scheme);
                integ.barycentre = BarycentreModel::Inertial;
                self.track_with(&integ, model, release, contact_model, turn, t_max, dt_out)
            }
        }
    }

    #[allow(clippy::too_many_arguments)] // the release, its integrator and the run's limits
    fn track_with<I: TimeIntegrator>(
        &self,
        integ: &I,
        shape_model: ShapeModel,
        release: Release,
        contact_model: Contact,
        turn: &Mat3,
        t_max: f64,
        dt_out: f64,
    ) -> Result<CavityRun, SceneError> {
        let defect = (turn.transpose() * turn - Mat3::identity()).amax();
        if defect > 1e-12 || turn.determinant() <= 0.0 {
            return Err(crate::error::ParamError::NotARotation {
                orthogonality_defect: defect,
                det: turn.determinant(),
            }
            .into());
        }
        let p = self.particle(&release)?;
        let mut s0 = State::at_rest(release_point());
        s0.f = *turn;
        s0.v = self.flow.sample(&s0.x, 0.0).map_err(StepError::from)?.u;
        let model = match contact_model {
            Contact::Extent => ContactModel::Extent,
            Contact::Barycentre => ContactModel::Barycentre {
                radius: BARYCENTRE_CONTACT_DISTANCE,
            },
        };
        let contact = ContactEvent::new(&self.boundary, &p, &self.flow, model);
        let mut monitor = Monitor::new(&p, &self.flow, &self.boundary);
        monitor.observe(&s0);
        // No step may carry the particle further than a quarter of its smallest semi-axis
        // (|u| ≤ U_lid): in the corners two walls are near at once, and the contact event
        // watches only the nearest.
        let dt_max = 0.25 * p.shape().semi_axes().min() / LID_VELOCITY;
        let plan = Plan::new(t_max, dt_max)?.with_dt_max(dt_max)?;
        let path = std::cell::RefCell::new(Vec::new());
        let mut slips = Vec::new();
        let mut next_out = dt_out;
        let mut memory = Default::default();
        let end = match integrate(
            integ,
            &p,
            &self.flow,
            s0,
            &mut memory,
            &plan,
            &[&contact],
            |s| path.borrow_mut().push((s.t, s.x)),
            |step| {
                monitor.observe(&step.state);
                if let Ok(fluid) = self.flow.sample(&step.state.x, step.state.t) {
                    slips.push((step.info.dt, (step.state.v - fluid.u).norm()));
                }
                if step.state.t >= next_out {
                    path.borrow_mut().push((step.state.t, step.state.x));
                    next_out = dt_out * ((step.state.t / dt_out).floor() + 1.0);
                }
            },
        ) {
            Ok(end) => end,
            Err(failure) => {
                // A failed particle is an outcome of the study, as in the population runner.
                let mut path = path.into_inner();
                path.push((failure.state.t, failure.state.x));
                return Ok(CavityRun {
                    release,
                    contact: contact_model,
                    shape_model,
                    path,
                    outcome: Outcome::Failed {
                        t: failure.state.t,
                        reason: failure.error.to_string(),
                    },
                    stats: failure.stats,
                    validity: monitor.validity(),
                    slip: Slip::of(slips),
                });
            }
        };
        let outcome = match end.stop {
            Stop::Event { .. } => {
                let near = contact.nearest(&end.state);
                match self.boundary.rule(near.patch) {
                    PatchRule::Exit => Outcome::Exited { t: end.state.t },
                    PatchRule::Stick => Outcome::Deposited {
                        t: end.state.t,
                        wall: self.boundary.patch_name(near.patch).to_string(),
                    },
                }
            }
            Stop::EndTime => {
                let mut path = path.borrow_mut();
                if path.last().is_none_or(|(t, _)| *t < end.state.t) {
                    path.push((end.state.t, end.state.x));
                }
                Outcome::Suspended
            }
        };
        let path = path.into_inner();
        let stats = end.stats;
        Ok(CavityRun {
            release,
            contact: contact_model,
            shape_model,
            path,
            outcome,
            stats,
            validity: monitor.validity(),
            slip: Slip::of(slips),
        })
    }
}

/// Trajectories as CSV: `contact,shape,ca,t,x_over_l,y_over_l,z_over_l` (ca empty: rigid limit).
pub fn trajectory_table(runs: &[CavityRun]) -> Result<crate::output::Csv, crate::output::OutputError> {
    let mut csv = crate::output::Csv::new(&["contact", "shape", "ca", "t", "x_over_l", "y_over_l", "z_over_l"]);
    for run in runs {
        for (t, x) in &run.path {
            csv.push(vec![
                run.contact.label().into(),
                run.release.shape.label(),
                run.release.ca().map(|c| c.to_string()).unwrap_or_default(),
                format!("{t:.4}"),
                format!("{:.5}", x[0] / EDGE),
                format!("{:.5}", x[1] / EDGE),
                format!("{:.5}", x[2] / EDGE),
            ])?;
        }
    }
    Ok(csv)
}

/// Outcomes as CSV: `contact,shape,ca,outcome,wall,t_end,x_over_l,y_over_l,z_over_l,steps,
/// shape_model,max_slip,median_slip` (slip [`Slip`] in m/s), then the validity columns
/// [`Validity::COLUMNS`] under the default [`Thresholds`] (r₁ in m).
pub fn outcome_table(runs: &[CavityRun]) -> Result<crate::output::Csv, crate::output::OutputError> {
    let mut csv = crate::output::Csv::new(&outcome_header());
    let limits = Thresholds::default();
    for run in runs {
        csv.push(outcome_cells(run, &limits))?;
    }
    Ok(csv)
}

fn outcome_header() -> Vec<&'static str> {
    let mut header = vec![
        "contact",
        "shape",
        "ca",
        "outcome",
        "wall",
        "t_end",
        "x_over_l",
        "y_over_l",
        "z_over_l",
        "steps",
        "shape_model",
        "max_slip",
        "median_slip",
    ];
    header.extend(Validity::COLUMNS);
    header
}

fn outcome_cells(run: &CavityRun, limits: &Thresholds) -> Vec<String> {
    let (t, x) = run.path.last().copied().unwrap_or((0.0, release_point()));
    let (kind, wall) = match &run.outcome {
        Outcome::Exited { .. } => ("exited", String::new()),
        Outcome::Deposited { wall, .. } => ("deposited", wall.clone()),
        Outcome::Suspended => ("suspended", String::new()),
        Outcome::Failed { reason, .. } => ("failed", reason.replace(',', ";")),
    };
    let mut cells = vec![
        run.contact.label().into(),
        run.release.shape.label(),
        run.release.ca().map(|c| c.to_string()).unwrap_or_default(),
        kind.into(),
        wall,
        format!("{t:.3}"),
        format!("{:.4}", x[0] / EDGE),
        format!("{:.4}", x[1] / EDGE),
        format!("{:.4}", x[2] / EDGE),
        run.stats.steps.to_string(),
        run.shape_model.label().into(),
        format!("{:.3e}", run.slip.max),
        format!("{:.3e}", run.slip.median),
    ];
    cells.extend(run.validity.cells(limits));
    cells
}

/// Trajectories projected on the x–z plane (the paper's x₂/L = 0.4 view), one panel.
pub fn trajectory_panel(runs: &[CavityRun], title: &str) -> crate::output::Panel {
    let mut panel = crate::output::Panel::new(title, "x/L", "z/L").with_ranges((0.0, 1.0), (0.0, 1.0));
    for (i, run) in runs.iter().enumerate() {
        let label = match run.release.ca() {
            Some(ca) => format!("{} Ca={ca}", run.release.shape.label()),
            None => format!("{} Ca→0", run.release.shape.label()),
        };
        let pts = run.path.iter().map(|(_, x)| (x[0] / EDGE, x[2] / EDGE)).collect();
        panel = panel.with(crate::output::Series::line(label, pts, i));
    }
    panel
}

/// Initial orientations of an ensemble: the identity (the nominal release) and `count − 1`
/// rotations that carry the shape's symmetry axis (e_x for prolates, e_z for oblates) to
/// directions spread evenly over a hemisphere (a Fibonacci lattice; axis and −axis give the
/// same ellipsoid), each by the smallest rotation. A triaxial shape has no symmetry axis: its
/// first axis r₁ is spread, and the rotation about it is the smallest one, not sampled; a
/// sphere looks the same in every orientation.
pub fn orientations(shape: Shape, count: usize) -> Vec<Mat3> {
    let axis = match shape {
        Shape::Oblate(_) => Vec3::z(),
        Shape::Sphere | Shape::Prolate(_) | Shape::Triaxial { .. } => Vec3::x(),
    };
    let others = count.saturating_sub(1);
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut out = Vec::with_capacity(count);
    if count > 0 {
        out.push(Mat3::identity());
    }
    for k in 0..others {
        let z = 1.0 - (k as f64 + 0.5) / others as f64;
        let rho = (1.0 - z * z).sqrt();
        let phi = golden * k as f64;
        let target = Vec3::new(rho * phi.cos(), rho * phi.sin(), z);
        let turn = nalgebra::Rotation3::rotation_between(&axis, &target)
            .unwrap_or_else(|| nalgebra::Rotation3::from_axis_angle(&Vec3::y_axis(), std::f64::consts::PI));
        out.push(turn.into_inner());
    }
    out
}

/// One ensemble member: the variant and orientation it was run in, and its run (or the error
/// that stopped it).
#[derive(Debug, Clone)]
pub struct Member {
    /// Field variant.
    pub variant: Variant,
    /// Index into [`orientations`] (0: nominal).
    pub orientation: usize,
    /// The run, or why it failed.
    pub run: Result<CavityRun, String>,
}

/// Events (exit or deposition) after this time (s) are flagged as sensitive to the paper's
/// 100 s tracking horizon.
pub const LATE_EVENT: f64 = 95.0;

/// Outcome fractions per (shape, Ca) over the members given:
/// `shape,ca,shape_model,runs,failed,exited,deposited,suspended,late_events,deposit_walls,
/// nominal_outcome` where the fractions are of the runs that finished, `late_events` the
/// fraction of them with an event after [`LATE_EVENT`], `deposit_walls` the walls hit with
/// counts (`x1:5;bottom:2`) and `nominal_outcome` the outcome of the nominal member
/// (orientation 0, lid +x, scale 1) if it was run.
pub fn outcome_fraction_table(members: &[Member]) -> Result<crate::output::Csv, crate::output::OutputError> {
    let mut csv = crate::output::Csv::new(&[
        "shape",
        "ca",
        "shape_model",
        "runs",
        "failed",
        "exited",
        "deposited",
        "suspended",
        "late_events",
        "deposit_walls",
        "nominal_outcome",
    ]);
    let mut keys: Vec<(String, Option<f64>)> = Vec::new();
    let key = |m: &Member| -> Option<(String, Option<f64>)> {
        m.run.as_ref().ok().map(|r| (r.release.shape.label(), r.release.ca()))
    };
    for m in members {
        if let Some(k) = key(m)
            && !keys.contains(&k)
        {
            keys.push(k);
        }
    }
    for (shape, ca) in keys {
        let group: Vec<&Member> = members
            .iter()
            .filter(|m| key(m).as_ref() == Some(&(shape.clone(), ca)))
            .collect();
        // A run that failed as a particle (`Outcome::Failed`) counts as failed, like one whose
        // set-up failed; the fractions are over the runs that finished.
        let runs: Vec<&CavityRun> = group
            .iter()
            .filter_map(|m| m.run.as_ref().ok())
            .filter(|r| !matches!(r.outcome, Outcome::Failed { .. }))
            .collect();
        let n = runs.len() as f64;
        // No finished run (every member failed): the fractions are empty cells, not 0/0.
        let frac = |f: &dyn Fn(&CavityRun) -> bool| match runs.is_empty() {
            true => String::new(),
            false => format!("{:.3}", runs.iter().filter(|r| f(r)).count() as f64 / n),
        };
        let mut walls: Vec<(String, usize)> = Vec::new();
        for r in &runs {
            if let Outcome::Deposited { wall, .. } = &r.outcome {
                match walls.iter_mut().find(|(w, _)| w == wall) {
                    Some((_, c)) => *c += 1,
                    None => walls.push((wall.clone(), 1)),
                }
            }
        }
        let nominal = group
            .iter()
            .find(|m| m.orientation == 0 && m.variant == Variant::default())
            .and_then(|m| m.run.as_ref().ok())
            .map(|r| outcome_label(&r.outcome))
            .unwrap_or_default();
        let shape_model = group
            .iter()
            .find_map(|m| m.run.as_ref().ok())
            .map(|r| r.shape_model.label())
            .unwrap_or_default();
        csv.push(vec![
            shape,
            ca.map(|c| c.to_string()).unwrap_or_default(),
            shape_model.into(),
            group.len().to_string(),
            (group.len() - runs.len()).to_string(),
            frac(&|r| matches!(r.outcome, Outcome::Exited { .. })),
            frac(&|r| matches!(r.outcome, Outcome::Deposited { .. })),
            frac(&|r| matches!(r.outcome, Outcome::Suspended)),
            frac(&|r| event_time(&r.outcome).is_some_and(|t| t > LATE_EVENT)),
            walls
                .iter()
                .map(|(w, c)| format!("{w}:{c}"))
                .collect::<Vec<_>>()
                .join(";"),
            nominal,
        ])?;
    }
    Ok(csv)
}

/// Per-member table: `mirrored,scale,orientation,error` followed by the [`outcome_table`]
/// columns (empty on error).
pub fn member_table(members: &[Member]) -> Result<crate::output::Csv, crate::output::OutputError> {
    let mut header = vec!["mirrored", "scale", "orientation", "error"];
    let inner = outcome_header();
    header.extend(&inner);
    let mut csv = crate::output::Csv::new(&header);
    let limits = Thresholds::default();
    for m in members {
        let mut cells = vec![
            m.variant.mirrored.to_string(),
            m.variant.scale.to_string(),
            m.orientation.to_string(),
        ];
        match &m.run {
            Ok(run) => {
                cells.push(String::new());
                cells.extend(outcome_cells(run, &limits));
            }
            Err(e) => {
                cells.push(e.replace([',', '"', '\n'], " "));
                cells.extend(inner.iter().map(|_| String::new()));
            }
        }
        csv.push(cells)?;
    }
    Ok(csv)
}

fn outcome_label(outcome: &Outcome) -> String {
    match outcome {
        Outcome::Exited { .. } => "exited".into(),
        Outcome::Deposited { wall, .. } => format!("deposited:{wall}"),
        Outcome::Suspended => "suspended".into(),
        Outcome::Failed { .. } => "failed".into(),
    }
}

fn event_time(outcome: &Outcome) -> Option<f64> {
    match outcome {
        Outcome::Exited { t } | Outcome::Deposited { t, .. } => Some(*t),
        Outcome::Suspended | Outcome::Failed { .. } => None,
    }
}

/// Run every release in every variant and in `count` orientations ([`orientations`]) for
/// `t_max` seconds at tolerance `tol` with barycentre contact, in parallel. A failed run is
/// kept as its error message, so one failure does not hide the rest of the ensemble.
#[allow(clippy::too_many_arguments)]
pub fn ensemble(
    flow: &BlendedFlow,
    shape_model: ShapeModel,
    forces: &ForceTerms,
    releases: &[Release],
    variants: &[Variant],
    count: usize,
    t_max: f64,
    tol: f64,
) -> Result<Vec<Member>, SceneError> {
    let cavities = variants
        .iter()
        .map(|v| {
            let cavity = Cavity::new(flow)?
                .with_shape_model(shape_model)
                .with_forces(forces.clone())
                .with_variant(*v)?;
            Ok((*v, cavity))
        })
        .collect::<Result<Vec<_>, SceneError>>()?;
    let jobs: Vec<(usize, Release, usize, Mat3)> = cavities
        .iter()
        .enumerate()
        .flat_map(|(c, _)| {
            releases.iter().flat_map(move |r| {
                orientations(r.shape, count)
                    .into_iter()
                    .enumerate()
                    .map(move |(k, turn)| (c, *r, k, turn))
            })
        })
        .collect();
    Ok(crate::parallel::map(&jobs, |(c, release, k, turn)| {
        let (variant, cavity) = &cavities[*c];
        Member {
            variant: *variant,
            orientation: *k,
            run: cavity
                .track_oriented(*release, Contact::Barycentre, turn, t_max, tol, t_max)
                .map_err(|e| e.to_string()),
        }
    }))
}

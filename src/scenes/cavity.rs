//! Soft and quasi-rigid ellipsoids in the lid-driven cavity (paper §6.3, Figs 13–16).
//!
//! # Set-up (paper §6.3)
//! Cube L = 0.1 m, lid z = L moving at U = 0.0813 m/s along +x, ν_f = 17.3 mm²/s (Re = 470),
//! steady field from OpenFOAM (`reference-data/cavity_re470.prf`). Particles: d_eq = 3 mm,
//! ρ_p = 1209.395 kg/m³ and ρ* = (ρ_f − ρ_p)/ρ_f = +0.05 %, so ρ_f = ρ_p/(1 − 5e-4) ≈ 1210 kg/m³;
//! gravity −9.81 m/s² e_z; release at (0.467 L, 0.4 L, 0.983 L) with the local fluid velocity.
//! Ca = μ_f γ̇₀/μ_s with γ̇₀ = √(2 d:d) of the flow at the release point (the paper computes
//! Ca "depending on the shear rate at the injection position").
//!
//! Readings where the paper is silent: the initial long axis is along the lid motion x (for
//! oblate shapes the two long axes span x–y, the short one is vertical); the barycentre is
//! inertial (St ≈ 0.02); shapes are inertialess (ρ* of the shape dynamics ≈ ρ_p γ̇₀ d²/μ_f
//! ≈ 0.5 for γ̇₀ ≈ 1 s⁻¹, but the shape relaxes on the viscous time scale).
//!
//! Wall rules (paper §6.3): a particle touching the lid leaves the cavity; one touching any
//! other wall sticks. Contact uses the particle's extent (support distance, `flow::unstructured`)
//! or, as a point-particle tracker would, the barycentre only ([`Contact`]). The release point
//! is 1.7 mm below the lid while the particles are 2.4–4.8 mm long, so with the extent rule a
//! tilting prolate touches the lid within a fraction of a second.

use super::SceneError;
use crate::contact::{Boundary, ContactEvent, ContactModel, PatchRule, Planes};
use crate::driver::{Plan, RunStats, Stop, integrate};
use crate::ellipsoid::Ellipsoid;
use crate::error::StepError;
use crate::flow::FlowField;
use crate::flow::unstructured::MeshedFlow;
use crate::integrator::{BarycentreModel, Stokesian};
use crate::material::{NeoHooke, Softness};
use crate::particle::{Fluid, Particle, State};
use crate::tensor::{Mat3, Vec3, sym};
use serde::Serialize;

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

/// Release point (0.467 L, 0.4 L, 0.983 L).
pub fn release_point() -> Vec3 {
    Vec3::new(0.467, 0.4, 0.983) * EDGE
}

/// Initial shape family.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Shape {
    /// Semi-axes λ₁ : 1 : 1.
    Prolate(f64),
    /// Semi-axes λ₁ : λ₁ : 1.
    Oblate(f64),
}

impl Shape {
    fn ratios(self) -> [f64; 3] {
        match self {
            Shape::Prolate(l) => [l, 1.0, 1.0],
            Shape::Oblate(l) => [l, l, 1.0],
        }
    }
    /// Label for datasets, e.g. `prolate_5`.
    pub fn label(self) -> String {
        match self {
            Shape::Prolate(l) => format!("prolate_{l}"),
            Shape::Oblate(l) => format!("oblate_{l}"),
        }
    }
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

/// One release: shape and softness (`None`: rigid limit Ca → 0).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Release {
    /// Initial shape.
    pub shape: Shape,
    /// Capillary number, or `None` for the rigid limit.
    pub ca: Option<f64>,
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
}

/// A tracked particle.
#[derive(Debug, Clone, Serialize)]
pub struct CavityRun {
    /// The release.
    pub release: Release,
    /// Contact model used.
    pub contact: Contact,
    /// (t, x) samples [s, m].
    pub path: Vec<(f64, Vec3)>,
    /// Outcome.
    pub outcome: Outcome,
    /// Work.
    pub stats: RunStats,
}

/// The cavity experiment: flow field, walls and fluid.
pub struct Cavity<'a> {
    flow: &'a MeshedFlow,
    boundary: Planes,
    fluid: Fluid,
    shear_rate: f64,
}

impl<'a> Cavity<'a> {
    /// Experiment on a loaded Re = 470 field.
    pub fn new(flow: &'a MeshedFlow) -> Result<Self, SceneError> {
        let d = sym(&flow.sample(&release_point(), 0.0).map_err(StepError::from)?.grad_u);
        let shear_rate = (2.0 * d.component_mul(&d).sum()).sqrt();
        Ok(Self {
            flow,
            boundary: Planes::cavity(EDGE)?,
            fluid: Fluid::new(rho_fluid() * NU, rho_fluid())?,
            shear_rate,
        })
    }

    /// γ̇₀ = √(2 d:d) at the release point [1/s].
    pub fn release_shear_rate(&self) -> f64 {
        self.shear_rate
    }

    fn particle(&self, release: &Release) -> Result<Particle<Softness<NeoHooke>>, SceneError> {
        // The rigid limit (Ca → 0) is a rigid particle: Jeffery rotation, no elasticity.
        let response = match release.ca {
            None => Softness::Rigid,
            Some(ca) => {
                let mu_s = self.fluid.mu * self.shear_rate / ca;
                Softness::Elastic(NeoHooke::new(mu_s, 1e3 * mu_s)?)
            }
        };
        let shape = Ellipsoid::with_volume_diameter(release.shape.ratios(), D_EQ, Mat3::identity())?;
        Ok(Particle::new(shape, response, self.fluid, RHO_PARTICLE)?.with_gravity(Vec3::new(0.0, 0.0, -9.81))?)
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
        let p = self.particle(&release)?;
        let mut integ = match release.ca {
            Some(_) => Stokesian::new(tol)?,
            None => Stokesian::new(tol)?,
        };
        integ.barycentre = BarycentreModel::Inertial;
        let mut s0 = State::at_rest(release_point());
        s0.v = self.flow.sample(&s0.x, 0.0).map_err(StepError::from)?.u;
        let model = match contact_model {
            Contact::Extent => ContactModel::Extent,
            Contact::Barycentre => ContactModel::Barycentre {
                radius: BARYCENTRE_CONTACT_DISTANCE,
            },
        };
        let contact = ContactEvent::new(&self.boundary, &p, self.flow, model);
        // No step may carry the particle further than a quarter of its smallest semi-axis
        // (|u| ≤ U_lid): in the corners two walls are near at once, and the contact event
        // watches only the nearest.
        let dt_max = 0.25 * p.shape().semi_axes().min() / LID_VELOCITY;
        let plan = Plan::new(t_max, dt_max)?.with_dt_max(dt_max)?;
        let path = std::cell::RefCell::new(Vec::new());
        let mut next_out = dt_out;
        let mut memory = Default::default();
        let end = integrate(
            &integ,
            &p,
            self.flow,
            s0,
            &mut memory,
            &plan,
            &[&contact],
            |s| path.borrow_mut().push((s.t, s.x)),
            |step| {
                if step.state.t >= next_out {
                    path.borrow_mut().push((step.state.t, step.state.x));
                    next_out = dt_out * ((step.state.t / dt_out).floor() + 1.0);
                }
            },
        )?;
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
            path,
            outcome,
            stats,
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
                run.release.ca.map(|c| c.to_string()).unwrap_or_default(),
                format!("{t:.4}"),
                format!("{:.5}", x[0] / EDGE),
                format!("{:.5}", x[1] / EDGE),
                format!("{:.5}", x[2] / EDGE),
            ])?;
        }
    }
    Ok(csv)
}

/// Outcomes as CSV: `contact,shape,ca,outcome,wall,t_end,x_over_l,y_over_l,z_over_l,steps`.
pub fn outcome_table(runs: &[CavityRun]) -> Result<crate::output::Csv, crate::output::OutputError> {
    let mut csv = crate::output::Csv::new(&[
        "contact", "shape", "ca", "outcome", "wall", "t_end", "x_over_l", "y_over_l", "z_over_l", "steps",
    ]);
    for run in runs {
        let (t, x) = run.path.last().copied().unwrap_or((0.0, release_point()));
        let (kind, wall) = match &run.outcome {
            Outcome::Exited { .. } => ("exited", String::new()),
            Outcome::Deposited { wall, .. } => ("deposited", wall.clone()),
            Outcome::Suspended => ("suspended", String::new()),
        };
        csv.push(vec![
            run.contact.label().into(),
            run.release.shape.label(),
            run.release.ca.map(|c| c.to_string()).unwrap_or_default(),
            kind.into(),
            wall,
            format!("{t:.3}"),
            format!("{:.4}", x[0] / EDGE),
            format!("{:.4}", x[1] / EDGE),
            format!("{:.4}", x[2] / EDGE),
            run.stats.steps.to_string(),
        ])?;
    }
    Ok(csv)
}

/// Trajectories projected on the x–z plane (the paper's x₂/L = 0.4 view), one panel.
pub fn trajectory_panel(runs: &[CavityRun], title: &str) -> crate::output::Panel {
    let mut panel = crate::output::Panel::new(title, "x/L", "z/L").with_ranges((0.0, 1.0), (0.0, 1.0));
    for (i, run) in runs.iter().enumerate() {
        let label = match run.release.ca {
            Some(ca) => format!("{} Ca={ca}", run.release.shape.label()),
            None => format!("{} Ca→0", run.release.shape.label()),
        };
        let pts = run.path.iter().map(|(_, x)| (x[0] / EDGE, x[2] / EDGE)).collect();
        panel = panel.with(crate::output::Series::line(label, pts, i));
    }
    panel
}

//! A cheap population with a closed-form answer, shared by the tests and the runner's bench:
//! particles injected across a Poiseuille pipe settle under gravity onto the wall or leave
//! through an outlet plane.
//!
//! # Physics
//! Units d_eq = μ_f = 1, no fluid density (no buoyancy, ρ_f = 0), solid density 1, so the
//! mass is m = π/6. The flow is $u = 2\bar U (1 − r^2/R^2)\\, e_1$ in a pipe of radius R along e₁;
//! gravity g acts along −e₂. The inlet is x₁ = 0 (particles are injected there, uniformly on
//! a disc of radius r_in, with the local fluid velocity), the wall sticks, and the plane
//! x₁ = L is an exit. A rigid sphere in Stokes flow has K̂ = 3π d_eq 1 (Brenner 1963 for a
//! sphere), so its overdamped barycentre (St → 0) moves with ẋ = u + v_s with the settling
//! velocity $v_s = m g/(3π μ_f d_{eq}) = g/18$ along −e₂ (Stokes' law), which is the closed
//! form of [`sphere_deposition`].

use super::sampling::{haar_rotation, uniform_disc};
use super::spec::{Injector, ParticleRng, ParticleSpec, ParticleTemplate};
use crate::contact::{Composite, PatchRule, PipeWall, Plane, Planes};
use crate::ellipsoid::Ellipsoid;
use crate::error::{ParamError, StepError, positive};
use crate::flow::FlowField;
use crate::flow::analytic::Poiseuille;
use crate::hydro::Brenner;
use crate::material::{NeoHooke, Softness};
use crate::particle::{Fluid, Particle};
use crate::tensor::{Mat3, Vec3};

/// λ_s/μ_s of the elastic particles (the inertialess model keeps J = 1, so it never acts).
const BULK_RATIO: f64 = 1e3;

/// Solid density in these units (so m = π/6 for d_eq = 1).
const DENSITY: f64 = 1.0;

/// The settling pipe: flow, boundary (outlet plane, then the wall) and injection rule.
#[derive(Debug, Clone)]
pub struct SettlingPipe {
    flow: Poiseuille,
    boundary: Composite<PipeWall>,
    template: ParticleTemplate<Brenner>,
    length: f64,
    inlet_radius: f64,
    aspect_ratio: f64,
    ca: f64,
    settling_velocity: f64,
}

impl SettlingPipe {
    /// Pipe of radius `radius` and length `length` with bulk velocity `mean_velocity`;
    /// particles settle at `settling_velocity` (the rigid sphere's Stokes velocity; all > 0)
    /// and are injected on the inlet disc of radius `inlet_radius` (0 < r_in < R − 1/2, so a
    /// sphere starts clear of the wall). Rigid spheres; see [`SettlingPipe::with_shape`].
    pub fn new(
        radius: f64,
        length: f64,
        mean_velocity: f64,
        settling_velocity: f64,
        inlet_radius: f64,
    ) -> Result<Self, ParamError> {
        let radius = positive("pipe radius", radius)?;
        let inlet_radius = positive("inlet disc radius", inlet_radius)?;
        if inlet_radius >= radius - 0.5 {
            return Err(ParamError::OutOfRange {
                name: "inlet disc radius (a sphere must start inside the pipe)",
                value: inlet_radius,
                min: 0.0,
                max: radius - 0.5,
            });
        }
        let settling_velocity = positive("settling velocity", settling_velocity)?;
        let length = positive("pipe length", length)?;
        let outlet = Planes::new(vec![Plane {
            name: "outlet".to_string(),
            point: Vec3::new(length, 0.0, 0.0),
            normal: Vec3::x(),
            rule: PatchRule::Exit,
        }])?;
        // m g/(3π) = v_s with m = π/6: g = 18 v_s.
        let gravity = Vec3::new(0.0, -18.0 * settling_velocity, 0.0);
        Ok(Self {
            flow: Poiseuille::new(radius, positive("mean velocity", mean_velocity)?)?,
            boundary: Composite::new(outlet, PipeWall::new(radius)?),
            template: ParticleTemplate::new(Brenner, Fluid::new(1.0, 0.0)?, gravity)?,
            length,
            inlet_radius,
            aspect_ratio: 1.0,
            ca: 0.0,
            settling_velocity,
        })
    }

    /// Prolate particles of aspect ratio `aspect_ratio` (≥ 1; 1: spheres) with uniformly random
    /// orientations, rigid for `ca` = 0 and Neo-Hooke with capillary number `ca` (units μ_f = 1,
    /// time 1) otherwise.
    pub fn with_shape(mut self, aspect_ratio: f64, ca: f64) -> Result<Self, ParamError> {
        if !(aspect_ratio.is_finite() && aspect_ratio >= 1.0) {
            return Err(ParamError::OutOfRange {
                name: "aspect ratio",
                value: aspect_ratio,
                min: 1.0,
                max: f64::INFINITY,
            });
        }
        if !(ca.is_finite() && ca >= 0.0) {
            return Err(ParamError::NotPositive {
                name: "Ca (>= 0)",
                value: ca,
            });
        }
        self.aspect_ratio = aspect_ratio;
        self.ca = ca;
        Ok(self)
    }

    /// The carrier flow.
    pub fn flow(&self) -> &Poiseuille {
        &self.flow
    }

    /// Outlet plane (patch 0, exit) and pipe wall (patch 1, stick).
    pub fn boundary(&self) -> &Composite<PipeWall> {
        &self.boundary
    }

    /// Pipe length L (the outlet plane is x₁ = L).
    pub fn length(&self) -> f64 {
        self.length
    }

    /// The rigid sphere's settling velocity v_s.
    pub fn settling_velocity(&self) -> f64 {
        self.settling_velocity
    }
}

impl Injector for SettlingPipe {
    type Law = NeoHooke;
    type Drag = Brenner;

    fn draw(&self, _index: u64, rng: &mut ParticleRng) -> Result<ParticleSpec<NeoHooke>, StepError> {
        let position = uniform_disc(rng, &Vec3::zeros(), &Vec3::x(), self.inlet_radius)?;
        let orientation = if self.aspect_ratio > 1.0 {
            haar_rotation(rng)
        } else {
            Mat3::identity()
        };
        let shape = Ellipsoid::with_volume_diameter([self.aspect_ratio, 1.0, 1.0], 1.0, orientation)?;
        let softness = if self.ca > 0.0 {
            Softness::Elastic(NeoHooke::from_capillary(self.ca, BULK_RATIO)?)
        } else {
            Softness::Rigid
        };
        Ok(ParticleSpec {
            shape,
            softness,
            density: DENSITY,
            position,
            velocity: self.flow.sample(&position, 0.0)?.u,
        })
    }

    fn particle(&self, spec: &ParticleSpec<NeoHooke>) -> Result<Particle<Softness<NeoHooke>, Brenner>, ParamError> {
        self.template.build(spec)
    }
}

/// Where an overdamped rigid sphere of radius `a` released at (0, y₀, z₀) in the Poiseuille
/// flow of radius R and bulk velocity Ū, settling at v_s along −e₂, touches the wall
/// (|x_⊥| = R − a): (x₁, y, z₀, t) with
/// $y = −\sqrt{(R − a)^2 − z_0^2}$, $t = (y_0 − y)/v_s$ and
/// $x_1 = \frac{2\bar U}{v_s}\left[\left(1 − \frac{z_0^2}{R^2}\right)(y_0 − y) − \frac{y_0^3 − y^3}{3R^2}\right]$,
/// the integral of u₁ = 2Ū(1 − (y² + z₀²)/R²) over the fall. `None` if the release point is not
/// clear of the wall.
pub fn sphere_deposition(radius: f64, mean_velocity: f64, v_s: f64, a: f64, y0: f64, z0: f64) -> Option<[f64; 4]> {
    let reach = radius - a;
    if y0 * y0 + z0 * z0 >= reach * reach {
        return None;
    }
    let y = -(reach * reach - z0 * z0).sqrt();
    let r2 = radius * radius;
    let x1 = 2.0 * mean_velocity / v_s * ((1.0 - z0 * z0 / r2) * (y0 - y) - (y0.powi(3) - y.powi(3)) / (3.0 * r2));
    Some([x1, y, z0, (y0 - y) / v_s])
}

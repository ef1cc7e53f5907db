//! Inertial deposition in a pipe bend with plug flow: the analytic limit the bend's OpenFOAM
//! study ([`super::bend`]) is checked against (issue 37, item 3a).
//!
//! # Physics
//! A bend of angle θ is the torus section 0 ≤ φ ≤ θ of tube radius a around the circle of
//! radius R_b ([`TorusWall`]); the flow is the plug flow u = U e_φ ([`BendPlug`], Yeh 1974's
//! idealisation: flat profile, no secondary flow). Rigid spheres of diameter d (units d = μ_f
//! = 1, no fluid density) enter uniformly over the inlet disc φ = 0 with the fluid's velocity
//! and leave through the plane φ = θ. With Stokes drag a sphere relaxes to the fluid over
//! τ = ρ_p d²/(18 μ_f), and the Stokes number is the one of Pui et al. (1987), Stk = τU/a.
//!
//! # Closed form (Stk → 0)
//! In the centrifugal field U²/ρ a sphere drifts across the streamlines at τU²/ρ along e_ρ
//! (quasi-steady Stokes drag). It crosses the bend in ρθ/U, so every sphere moves
//! d = τUθ = Stk·θ·a along e_ρ of its cross-section, whatever its ρ. Its centre touches the
//! wall at a' = a − ½ from the tube's axis, so the deposited share is that of the inlet disc of
//! radius a' that the shift by d carries out of it, one minus the two discs' overlap:
//! ```math
//! \eta = 1 − \frac{2}{\pi}\left(\arccos\kappa − \kappa\sqrt{1 − \kappa^2}\right),
//! \qquad \kappa = \frac{d}{2a'} = \frac{\mathrm{Stk}\,\theta\,a}{2a'},
//! ```
//! and η = 1 for κ ≥ 1 (Yeh 1974; Cheng & Wang 1975). The corrections are of relative order
//! Stk·a/(R_b θ): the drift builds up over τ after the entry, so the lag shortens d by τ·τU²/R_b.

use crate::contact::{Composite, PatchRule, Plane, Planes, TorusWall};
use crate::driver::{Budget, Plan};
use crate::ellipsoid::Ellipsoid;
use crate::error::{ParamError, StepError, positive};
use crate::flow::FlowField;
use crate::flow::analytic::BendPlug;
use crate::hydro::Brenner;
use crate::integrator::{BarycentreModel, Stokesian};
use crate::material::{NeoHooke, Softness};
use crate::particle::{Fluid, Particle};
use crate::population::sampling::uniform_disc;
use crate::population::{Case, Fate, Injector, ParticleRng, ParticleSpec, ParticleTemplate, binomial};
use crate::tensor::{Mat3, Vec3};

/// The bend: geometry, flow and the spheres' Stokes number (module docs).
#[derive(Debug, Clone)]
pub struct PlugBend {
    flow: BendPlug,
    boundary: Composite<TorusWall>,
    template: ParticleTemplate<Brenner>,
    bend_radius: f64,
    tube_radius: f64,
    angle: f64,
    density: f64,
}

/// Deposited and injected spheres of one Stokes number, with the closed form.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlugDeposition {
    /// Stokes number τU/a.
    pub stk: f64,
    /// Spheres injected.
    pub n: u64,
    /// Spheres deposited on the wall.
    pub deposited: u64,
    /// Spheres that neither deposited nor left (failed or still inside at the end).
    pub other: u64,
    /// The closed form η ([`plug_deposition`]).
    pub exact: f64,
}

impl PlugDeposition {
    /// Deposition efficiency η = deposited/n.
    pub fn efficiency(&self) -> f64 {
        binomial::fraction(self.deposited, self.n)
    }

    /// Its binomial standard error.
    pub fn stderr(&self) -> f64 {
        binomial::stderr(self.deposited, self.n)
    }
}

/// The closed-form deposition efficiency of the module docs for a sphere of diameter 1 in a
/// bend of angle `angle` and tube radius `tube_radius` at Stokes number `stk`.
pub fn plug_deposition(stk: f64, angle: f64, tube_radius: f64) -> f64 {
    let reach = tube_radius - 0.5;
    let kappa = stk * angle * tube_radius / (2.0 * reach);
    if kappa >= 1.0 {
        1.0
    } else {
        1.0 - 2.0 / std::f64::consts::PI * (kappa.acos() - kappa * (1.0 - kappa * kappa).sqrt())
    }
}

impl PlugBend {
    /// A bend of angle `angle` (0 < θ < π), centreline radius `bend_radius` and tube radius
    /// `tube_radius` (> 1, below R_b) in units of the sphere diameter, plug speed 1, spheres
    /// of Stokes number `stk` (> 0).
    pub fn new(bend_radius: f64, tube_radius: f64, angle: f64, stk: f64) -> Result<Self, ParamError> {
        if !(angle > 0.0 && angle < std::f64::consts::PI) {
            return Err(ParamError::OutOfRange {
                name: "bend angle",
                value: angle,
                min: 0.0,
                max: std::f64::consts::PI,
            });
        }
        if !(tube_radius > 1.0) {
            return Err(ParamError::OutOfRange {
                name: "tube radius (sphere diameters)",
                value: tube_radius,
                min: 1.0,
                max: f64::INFINITY,
            });
        }
        let stk = positive("Stokes number", stk)?;
        // The exit plane through the x₃ axis at φ = θ, its outward normal along +e_φ(θ).
        let outlet = Planes::new(vec![Plane {
            name: "outlet".to_string(),
            point: Vec3::zeros(),
            normal: Vec3::new(-angle.sin(), angle.cos(), 0.0),
            rule: PatchRule::Exit,
        }])?;
        Ok(Self {
            flow: BendPlug { speed: 1.0 },
            boundary: Composite::new(outlet, TorusWall::new(bend_radius, tube_radius)?),
            template: ParticleTemplate::new(Brenner, Fluid::new(1.0, 0.0)?, Vec3::zeros())?,
            bend_radius,
            tube_radius,
            angle,
            // τ = ρ_p/18 (d = μ_f = 1) and Stk = τU/a with U = 1.
            density: 18.0 * stk * tube_radius,
        })
    }

    /// Stokes number τU/a.
    pub fn stk(&self) -> f64 {
        self.density / (18.0 * self.tube_radius)
    }

    /// Track `n` spheres (seed `seed`) with the inertial Rosenbrock integrator at rtol `tol` until
    /// they deposit or leave (an end time of 4 transit times at the outer wall).
    pub fn deposition(&self, n: u64, seed: u64, tol: f64) -> Result<PlugDeposition, ParamError> {
        let integrator = Stokesian {
            barycentre: BarycentreModel::Inertial,
            ..Stokesian::new(tol)?
        };
        let transit = (self.bend_radius + self.tube_radius) * self.angle;
        let plan = Plan::new(4.0 * transit, 4.0 * transit)?.with_budget(Budget {
            max_steps: 1_000_000,
            wall_time: None,
        });
        let case = Case::new(&integrator, &self.flow, &self.boundary, self, plan);
        let (mut deposited, mut other) = (0, 0);
        for index in 0..n {
            match case.run_particle(seed, index).fate {
                Fate::Deposited { .. } => deposited += 1,
                Fate::Escaped { .. } => {}
                _ => other += 1,
            }
        }
        Ok(PlugDeposition {
            stk: self.stk(),
            n,
            deposited,
            other,
            exact: plug_deposition(self.stk(), self.angle, self.tube_radius),
        })
    }
}

impl Injector for PlugBend {
    type Law = NeoHooke;
    type Drag = Brenner;

    /// Uniform over the inlet disc of radius a − ½ (the centres that fit in the tube), with the
    /// fluid's velocity.
    fn draw(&self, _index: u64, rng: &mut ParticleRng) -> Result<ParticleSpec<NeoHooke>, StepError> {
        let centre = Vec3::new(self.bend_radius, 0.0, 0.0);
        let position = uniform_disc(rng, &centre, &Vec3::y(), self.tube_radius - 0.5)?;
        Ok(ParticleSpec {
            shape: Ellipsoid::with_volume_diameter([1.0, 1.0, 1.0], 1.0, Mat3::identity())?,
            softness: Softness::Rigid,
            density: self.density,
            position,
            velocity: self.flow.sample(&position, 0.0)?.u,
        })
    }

    fn particle(&self, spec: &ParticleSpec<NeoHooke>) -> Result<Particle<Softness<NeoHooke>, Brenner>, ParamError> {
        self.template.build(spec)
    }
}

//! Inertial deposition in a pipe bend with two analytic profiles: the limits the bend's
//! OpenFOAM study ([`super::bend`]) is checked against (issue 37, item 3a; issue 61).
//!
//! # Physics
//! A bend of angle θ is the torus section 0 ≤ φ ≤ θ of tube radius a around the circle of
//! radius R_b ([`TorusWall`]). The flow runs along the arc without secondary flow, either as
//! the plug flow u = U e_φ ([`BendPlug`], Yeh 1974's idealisation) or with Poiseuille's profile
//! u = 2U(1 − r²/a²) e_φ, r the distance from the tube's centreline ([`BendPoiseuille`]: a
//! developed laminar inlet with the Dean vortices switched off), U the mean speed either way.
//! Rigid spheres of diameter d (units d = μ_f = 1, no fluid density) enter over the inlet disc
//! φ = 0 with the fluid's velocity, spread as the fluid's flux carries them (uniformly for the
//! plug, with density ∝ u for the parabolic profile), and leave through the plane φ = θ. With
//! Stokes drag a sphere relaxes to the fluid over τ = ρ_p d²/(18 μ_f), and the Stokes number
//! is the one of Pui et al. (1987), Stk = τU/a.
//!
//! # Plug flow in closed form (Stk → 0)
//! In the centrifugal field U²/ρ a sphere drifts across the streamlines at τU²/ρ along e_ρ
//! (quasi-steady Stokes drag). It crosses the bend in ρθ/U, so every sphere moves
//! d = τUθ = Stk·θ·a along e_ρ of its cross-section, whatever its ρ. Its centre touches the
//! wall at a' = a − ½ from the tube's axis, so the deposited share is that of the inlet disc of
//! radius a' that the shift by d carries out of it, one minus the two discs' overlap:
//! ```math
//! \eta = 1 − \frac{2}{\pi}\left(\arccos\kappa − \kappa\sqrt{1 − \kappa^2}\right),
//! \qquad \kappa = \frac{d}{2a^\prime} = \frac{\mathrm{Stk}\,\theta\,a}{2a^\prime},
//! ```
//! and η = 1 for κ ≥ 1 (Yeh 1974; Cheng & Wang 1975). The corrections are of relative order
//! Stk·a/(R_b θ): the drift builds up over τ after the entry, so the lag shortens d by τ·τU²/R_b.
//!
//! # Parabolic profile: the onset (Stk → 0)
//! The same quasi-steady drift, τf²/ρ along e_ρ with f = 2U(1 − r²/a²) the local speed, now
//! slows as the sphere nears the wall. A sphere runs along the arc at dφ/dt = f/ρ, so along
//! its path dρ/dφ = τf: ρ cancels (the curvature ratio drops out) and x₃ stays fixed. In units
//! of a, ξ = (ρ − R_b)/a, ζ = x₃/a and c² = 1 − ζ², with τ = Stk·a/U,
//! ```math
//! \frac{d\xi}{d\varphi} = 2\,\mathrm{Stk}\,(c^2 − \xi^2)
//! \quad\Rightarrow\quad
//! \xi(\varphi) = c\tanh\!\left(\operatorname{artanh}\frac{\xi_0}{c} + 2\,\mathrm{Stk}\,c\,\varphi\right),
//! ```
//! a Riccati equation with constant c on each line ζ. The drift vanishes at the wall ξ = c,
//! which a point never reaches: a sphere deposits by its extent, when its centre reaches
//! α = a'/a, i.e. ξ = b = √(α² − ζ²) < c. It does so within the bend iff ξ(θ) ≥ b, i.e. iff it
//! entered at ξ₀ ≥ ξ_c(ζ) = max(−b, c tanh(artanh(b/c) − 2 Stk θ c)). Weighting the entry
//! points by the flux, 1 − ξ² − ζ² over the disc of centres ξ² + ζ² ≤ α², whose total is
//! π(α² − α⁴/2),
//! ```math
//! \eta = \frac{1}{\pi(\alpha^2 − \alpha^4/2)}\int_{−\alpha}^{\alpha}
//! \left[c^2(b − \xi_c) − \frac{b^3 − \xi_c^3}{3}\right]d\zeta
//! ```
//! ([`onset_deposition`]: one quadrature, in ζ = α sin ψ so that the end points are smooth).
//! For small Stk, b − ξ_c = 2 Stk θ (c² − b²) = 2 Stk θ (1 − α²) on every line, so
//! ```math
//! \eta \simeq \frac{4}{\pi}\,\mathrm{Stk}\,\theta\,\frac{2(1 − \alpha^2)^2}{\alpha(2 − \alpha^2)}
//! \approx \frac{8}{\pi}\,\frac{\mathrm{Stk}\,\theta}{a^2}
//! ```
//! (a in sphere diameters): the plug's (4/π)κ ≈ (2/π) Stk θ times 4/a², because the spheres
//! that can still reach the wall ride in the slow fluid near it. η becomes of order one only
//! when the phase 2 Stk θ c reaches artanh(b/c) ≈ ½ ln(4a), near Stk ≈ ln(4a)/(4θ): an onset
//! in Stk whose place depends on the sphere's size only logarithmically. This is the plug-flow
//! argument of Yeh (1974) and Cheng & Wang (1975) carried out with the local speed along the
//! sphere's path; it was derived here, not checked against a published formula for this flow.
//!
//! The closed form is first order in τ against the flow's times along the path. The next
//! order, all ∝ a/R_b, holds the entry lag (the phase falls short by Δφ = τf/ρ ≤
//! 2 Stk a/(R_b − a)), and, absent for the plug, the sphere's radial inertia and the lag of its
//! azimuthal speed behind f as it crosses the profile: each changes the drift by up to
//! 2τ²f|∂f/∂r|/ρ ≤ 6.2 Stk² a/(R_b − a), max f|∂f/∂r| = 3.08 U²/a at r = a/√3. Near the onset
//! η is steep in the phase, so these matter early: at R_b/a = 5.7 the closed form holds to
//! Stk ≈ 0.3 (`paper-figures/bend/NOTES.md`).

use crate::contact::{Composite, PatchRule, Plane, Planes, TorusWall};
use crate::driver::{Budget, Plan};
use crate::ellipsoid::Ellipsoid;
use crate::error::{FlowError, ParamError, StepError, positive};
use crate::flow::analytic::BendPlug;
use crate::flow::bend_poiseuille::BendPoiseuille;
use crate::flow::{FlowField, FlowSample};
use crate::hydro::Brenner;
use crate::integrator::{BarycentreModel, Stokesian};
use crate::material::{NeoHooke, Softness};
use crate::particle::{Fluid, Particle};
use crate::population::sampling::uniform_disc;
use crate::population::{Case, Fate, Injector, ParticleRng, ParticleSpec, ParticleTemplate, binomial};
use crate::tensor::{Mat3, Vec3};
use rand::RngExt;

/// The axial profile along the bend (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Profile {
    /// u = U e_φ: the plug-flow limit.
    Plug,
    /// u = 2U(1 − r²/a²) e_φ without secondary flow: the onset limit.
    Parabolic,
}

impl Profile {
    /// The name of the limit in `paper-figures/bend/analytic.csv`'s `limit` column.
    pub fn limit(self) -> &'static str {
        match self {
            Self::Plug => "plug_flow",
            Self::Parabolic => "onset",
        }
    }
}

/// One flow for either profile, so that the bend has one type.
#[derive(Debug, Clone, Copy)]
enum BendFlow {
    Plug(BendPlug),
    Parabolic(BendPoiseuille),
}

impl FlowField for BendFlow {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        match self {
            Self::Plug(flow) => flow.sample(x, t),
            Self::Parabolic(flow) => flow.sample(x, t),
        }
    }
}

/// The bend: geometry, profile and the spheres' Stokes number (module docs).
#[derive(Debug, Clone)]
pub struct AnalyticBend {
    profile: Profile,
    flow: BendFlow,
    boundary: Composite<TorusWall>,
    template: ParticleTemplate<Brenner>,
    bend_radius: f64,
    tube_radius: f64,
    angle: f64,
    density: f64,
}

/// Deposited and injected spheres of one Stokes number, with the closed form.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BendDeposition {
    /// Stokes number τU/a.
    pub stk: f64,
    /// Spheres injected.
    pub n: u64,
    /// Spheres deposited on the wall.
    pub deposited: u64,
    /// Spheres that neither deposited nor left (failed or still inside at the end).
    pub other: u64,
    /// The closed form η ([`plug_deposition`] or [`onset_deposition`]).
    pub exact: f64,
}

impl BendDeposition {
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
/// bend of angle `angle` and tube radius `tube_radius` at Stokes number `stk`, plug flow.
pub fn plug_deposition(stk: f64, angle: f64, tube_radius: f64) -> f64 {
    let reach = tube_radius - 0.5;
    let kappa = stk * angle * tube_radius / (2.0 * reach);
    if kappa >= 1.0 {
        1.0
    } else {
        1.0 - 2.0 / std::f64::consts::PI * (kappa.acos() - kappa * (1.0 - kappa * kappa).sqrt())
    }
}

/// Panels of the composite 3-point Gauss–Legendre rule in ψ of [`onset_deposition`]: the
/// integrand is smooth but for the kink where ξ_c reaches −b (all of a line deposits), so the
/// error is O(panels⁻²) there and O(panels⁻⁶) elsewhere; 2 000 panels put it below 10⁻⁷
/// (halving them moves η by less than that, `studies::bend_plug` tests).
const ONSET_PANELS: usize = 2000;

/// The closed-form deposition efficiency of the module docs for a sphere of diameter 1 in a
/// bend of angle `angle` and tube radius `tube_radius` (> ½) at Stokes number `stk`, with
/// Poiseuille's profile and no secondary flow: the onset limit.
pub fn onset_deposition(stk: f64, angle: f64, tube_radius: f64) -> f64 {
    let alpha = (tube_radius - 0.5) / tube_radius;
    let phase = 2.0 * stk * angle;
    // The flux-weighted deposited area on the line ζ = α sin ψ, times dζ/dψ.
    let line = |psi: f64| {
        let zeta = alpha * psi.sin();
        let c = (1.0 - zeta * zeta).sqrt();
        let b = alpha * psi.cos();
        let from = (c * ((b / c).atanh() - phase * c).tanh()).max(-b);
        (c * c * (b - from) - (b * b * b - from * from * from) / 3.0) * alpha * psi.cos()
    };
    let node = (0.6f64).sqrt();
    let rule = [(-node, 5.0 / 9.0), (0.0, 8.0 / 9.0), (node, 5.0 / 9.0)];
    let h = std::f64::consts::PI / ONSET_PANELS as f64;
    let mut sum = 0.0;
    for k in 0..ONSET_PANELS {
        let mid = -std::f64::consts::FRAC_PI_2 + (k as f64 + 0.5) * h;
        for (x, w) in rule {
            sum += 0.5 * h * w * line(mid + 0.5 * h * x);
        }
    }
    let alpha2 = alpha * alpha;
    (sum / (std::f64::consts::PI * (alpha2 - 0.5 * alpha2 * alpha2))).clamp(0.0, 1.0)
}

impl AnalyticBend {
    /// A bend of angle `angle` (0 < θ < π), centreline radius `bend_radius` and tube radius
    /// `tube_radius` (> 1, below R_b) in units of the sphere diameter, mean speed 1 with the
    /// axial `profile`, spheres of Stokes number `stk` (> 0).
    pub fn new(profile: Profile, bend_radius: f64, tube_radius: f64, angle: f64, stk: f64) -> Result<Self, ParamError> {
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
        let flow = match profile {
            Profile::Plug => BendFlow::Plug(BendPlug { speed: 1.0 }),
            Profile::Parabolic => BendFlow::Parabolic(BendPoiseuille::new(bend_radius, tube_radius, 1.0)?),
        };
        Ok(Self {
            profile,
            flow,
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

    /// The axial profile.
    pub fn profile(&self) -> Profile {
        self.profile
    }

    /// The closed form for this bend and Stokes number.
    pub fn exact(&self) -> f64 {
        match self.profile {
            Profile::Plug => plug_deposition(self.stk(), self.angle, self.tube_radius),
            Profile::Parabolic => onset_deposition(self.stk(), self.angle, self.tube_radius),
        }
    }

    /// Track `n` spheres (seed `seed`) with the inertial Rosenbrock integrator at rtol `tol` until
    /// they deposit or leave (an end time of 4 transit times at the outer wall at the mean
    /// speed: the parabolic profile's slowest spheres, ½ from the wall, move at 2/a of it).
    pub fn deposition(&self, n: u64, seed: u64, tol: f64) -> Result<BendDeposition, ParamError> {
        let integrator = Stokesian {
            barycentre: BarycentreModel::Inertial,
            ..Stokesian::new(tol)?
        };
        let slowest = match self.profile {
            Profile::Plug => 1.0,
            Profile::Parabolic => 2.0 * (1.0 - ((self.tube_radius - 0.5) / self.tube_radius).powi(2)),
        };
        let transit = (self.bend_radius + self.tube_radius) * self.angle / slowest;
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
        Ok(BendDeposition {
            stk: self.stk(),
            n,
            deposited,
            other,
            exact: self.exact(),
        })
    }
}

impl Injector for AnalyticBend {
    type Law = NeoHooke;
    type Drag = Brenner;

    /// Over the inlet disc of radius a − ½ (the centres that fit in the tube) as the flux
    /// carries them, with the fluid's velocity: uniformly for the plug; for the parabolic
    /// profile w = r²/a² has density ∝ 1 − w on [0, α²], drawn by inverting its distribution,
    /// w − w²/2 = q·(α² − α⁴/2) for q uniform, and the angle is uniform.
    fn draw(&self, _index: u64, rng: &mut ParticleRng) -> Result<ParticleSpec<NeoHooke>, StepError> {
        let centre = Vec3::new(self.bend_radius, 0.0, 0.0);
        let reach = self.tube_radius - 0.5;
        let position = match self.profile {
            Profile::Plug => uniform_disc(rng, &centre, &Vec3::y(), reach)?,
            Profile::Parabolic => {
                let (q, turn): (f64, f64) = (rng.random(), rng.random());
                let alpha2 = (reach / self.tube_radius).powi(2);
                let w = 1.0 - (1.0 - q * (2.0 * alpha2 - alpha2 * alpha2)).sqrt();
                let (r, psi) = (self.tube_radius * w.sqrt(), std::f64::consts::TAU * turn);
                centre + r * Vec3::new(psi.cos(), 0.0, psi.sin())
            }
        };
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

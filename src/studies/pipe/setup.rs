//! The Tian/Cui laminar pipe flow with a released prolate particle (paper §6.2, Fig. 9), in
//! physical units and in the nondimensional form that is integrated.
//!
//! # Physics
//! Hagen–Poiseuille air flow along e₁ in a pipe of radius R = D/2,
//! $u = 2\bar U (1 − r^2/R^2)\\, e_1$. The particle is released at x₀ = (0, x₂⁰, 0) with its long
//! axis along e₁ (Fig. 9), moving with the local fluid velocity (§6.2). The shear rate there,
//! $\dot\gamma_0 = 4\bar U |x_2^0|/R^2 = 725.85\ \mathrm{s^{-1}}$ for Tian/Cui, sets the capillary number
//! Ca = μ_f γ̇₀/μ_s (eq. 23); the paper quotes ω_f = 726.95 s⁻¹ (0.15 % more).
//! Gravity acts along −e₂. The paper does not state its direction; this choice keeps the
//! motion in the x₁–x₂ plane of Fig. 9 and lets the particle, released below the axis, settle
//! towards the nearer wall.
//!
//! # Units
//! The integration uses the paper's scales (§6 intro): lengths in d_eq, times in 1/γ̇₀,
//! stresses in μ_f γ̇₀, with μ_f = ρ_f ν_f. Hence μ_f = 1, μ_s = 1/Ca, R* = R/d_eq,
//! Ū* = Ū/(γ̇₀ d_eq), g* = g/(γ̇₀² d_eq) and densities ρ* = ρ γ̇₀ d_eq²/μ_f (solid and fluid
//! alike, so buoyancy keeps its ratio). Every state component is then O(1)…O(10⁵), which
//! suits the uniform error tolerances of the adaptive integrators.

use crate::contact::PipeWall;
use crate::error::{FlowError, ParamError, finite, positive};
use crate::flow::FlowField;
use crate::flow::analytic::Poiseuille;
use crate::hydro::gravity::reduced_gravity;
use crate::hydro::{Brenner, DragModel};
use crate::integrator::{BarycentreModel, Scheme, Stokesian};
use crate::material::{self, Hyperelastic, LawFactory, NeoHooke};
use crate::particle::{Fluid, Particle, State};
use crate::studies::particles::{Deformability, ParticleModel, Shape};
use crate::tensor::{Mat3, Vec3};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// The carrier flow and release point in SI units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PipeFlowData {
    /// Pipe diameter D (m).
    pub diameter: f64,
    /// Mean (bulk) velocity Ū (m/s); the centreline velocity is 2Ū.
    pub mean_velocity: f64,
    /// Kinematic viscosity ν_f (m²/s).
    pub nu_f: f64,
    /// Fluid density ρ_f (kg/m³).
    pub rho_f: f64,
    /// Pipe length L (m); the flow model is the infinite pipe, L only flags particles that
    /// would leave the real one before depositing.
    pub length: f64,
    /// Magnitude of gravity (m/s²), acting along −e₂.
    pub gravity: f64,
    /// Release coordinate x₂⁰ (m) (x₁⁰ = x₃⁰ = 0).
    pub release_x2: f64,
}

impl PipeFlowData {
    /// Tian et al. / Cui et al. (paper §6.2; Tian et al. 2012, Cui et al.): D = 4.2 mm, Ū = 0.485 m/s,
    /// ν_f = 1.491e-5 m²/s (the paper prints mm²/s, a typo), ρ_f = 1.208 kg/m³, L = 0.7 m,
    /// x₂⁰ = −1.65 mm, g = 9.81 m/s².
    pub fn tian_cui() -> Self {
        Self {
            diameter: 4.2e-3,
            mean_velocity: 0.485,
            nu_f: 1.491e-5,
            rho_f: 1.208,
            length: 0.7,
            gravity: 9.81,
            release_x2: -1.65e-3,
        }
    }

    /// Dynamic viscosity μ_f = ρ_f ν_f (Pa s).
    pub fn mu_f(&self) -> f64 {
        self.rho_f * self.nu_f
    }

    /// Shear rate at the release point, γ̇₀ = 4Ū|x₂⁰|/R² (1/s).
    pub fn release_shear_rate(&self) -> f64 {
        let radius = 0.5 * self.diameter;
        4.0 * self.mean_velocity * self.release_x2.abs() / (radius * radius)
    }
}

/// A stress-free particle in SI units: its shape, placed with body axis a along e_a (r₁
/// along the flow e₁, r₂ along e₂ in the plane of motion), sized by its smallest semi-axis.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PipeParticleData {
    /// Shape family and semi-axis ratios.
    pub shape: Shape,
    /// Smallest semi-axis (m), r₃ for the spheroids.
    pub r_minor: f64,
    /// Solid density ρ_p (kg/m³).
    pub rho_p: f64,
}

impl PipeParticleData {
    /// The Tian/Cui particle: r₃ = 0.5 µm, ρ_p = 2560 kg/m³, of `shape` (prolates with λ₁ = 14
    /// in Fig. 10; 3.5 and 7 in Figs 11, 12, where the paper calls the set-up "identical", so
    /// r₃ is kept).
    pub fn tian_cui(shape: Shape) -> Self {
        Self {
            shape,
            r_minor: 0.5e-6,
            rho_p: 2560.0,
        }
    }

    /// λ₁ = r₁/r₃, the aspect ratio the pipe datasets are labelled by.
    pub fn lambda1(&self) -> f64 {
        let [r1, _, r3] = self.shape.ratios();
        r1 / r3
    }

    /// Volume-equivalent diameter d_eq = 2 (r₁r₂r₃)^{1/3} (m).
    pub fn d_eq(&self) -> Result<f64, ParamError> {
        self.shape.volume_diameter(self.r_minor)
    }
}

/// The shape response of the pipe's particles under the paper's Neo-Hooke law.
pub type PipeMaterial = material::Softness<NeoHooke>;

/// The nondimensional problem: flow, particle, release state and unit conversions.
#[derive(Debug, Clone)]
pub struct PipeSetup<M = NeoHooke, D = Brenner> {
    /// Poiseuille flow in units of d_eq and 1/γ̇₀.
    pub flow: Poiseuille,
    /// The pipe wall (radius R/d_eq).
    pub wall: PipeWall,
    /// The particle: elastic, or rigid for [`Deformability::Rigid`].
    pub particle: Particle<material::Softness<M>, D>,
    /// Physical flow data it was scaled from.
    pub flow_data: PipeFlowData,
    /// Physical particle data it was scaled from.
    pub particle_data: PipeParticleData,
    /// Deformability it was built with.
    pub softness: Deformability,
    /// Release point x₀ (d_eq).
    pub release: Vec3,
    /// Length unit d_eq (m).
    pub length_unit: f64,
    /// Time unit 1/γ̇₀ (s).
    pub time_unit: f64,
}

impl PipeSetup {
    /// Scale the physical set-up with the paper's particle model (Neo-Hooke, Brenner drag); the
    /// long axis r₁ starts along e₁, r₂ along e₂, r₃ along e₃.
    pub fn new(flow: PipeFlowData, particle: PipeParticleData, softness: Deformability) -> Result<Self, ParamError> {
        Self::with_model(flow, particle, softness, &ParticleModel::default())
    }

    /// The Tian/Cui set-up with a prolate particle of aspect ratio `lambda1` and softness `ca`
    /// (0: rigid).
    pub fn tian_cui(lambda1: f64, ca: f64) -> Result<Self, ParamError> {
        Self::new(
            PipeFlowData::tian_cui(),
            PipeParticleData::tian_cui(Shape::Prolate(lambda1)),
            Deformability::from_ca(ca)?,
        )
    }
}

impl<M: Hyperelastic, D: DragModel> PipeSetup<M, D> {
    /// [`PipeSetup::new`] with another law family and drag model.
    pub fn with_model<L: LawFactory<Law = M>>(
        flow: PipeFlowData,
        particle: PipeParticleData,
        softness: Deformability,
        model: &ParticleModel<L, D>,
    ) -> Result<Self, ParamError>
    where
        D: Clone,
    {
        for (name, v) in [
            ("pipe diameter", flow.diameter),
            ("nu_f", flow.nu_f),
            ("rho_f", flow.rho_f),
            ("r_minor", particle.r_minor),
            ("rho_p", particle.rho_p),
        ] {
            positive(name, v)?;
        }
        finite("mean velocity", flow.mean_velocity)?;
        finite("gravity", flow.gravity)?;
        let d_eq = particle.d_eq()?;
        let shear_rate = positive("release shear rate", flow.release_shear_rate())?;
        let (l, t) = (d_eq, 1.0 / shear_rate);
        let mu_f = flow.mu_f();
        let density = |rho: f64| rho * shear_rate * d_eq * d_eq / mu_f;
        let shape = particle.shape.ellipsoid(1.0, Mat3::identity())?;
        // Stresses in units of μ_f γ̇₀, so μ_s = 1/Ca. The inertialess model keeps tr l_s = 0,
        // so J = 1 and the bulk ratio never acts.
        let model = model
            .particle(
                shape,
                softness,
                1.0,
                Fluid::new(1.0, density(flow.rho_f))?,
                density(particle.rho_p),
            )?
            .with_gravity(Vec3::new(0.0, -flow.gravity * t * t / l, 0.0))?;
        Ok(Self {
            flow: Poiseuille::new(0.5 * flow.diameter / l, flow.mean_velocity * t / l)?,
            wall: PipeWall::new(0.5 * flow.diameter / l)?,
            particle: model,
            flow_data: flow,
            particle_data: particle,
            softness,
            release: Vec3::new(0.0, flow.release_x2 / l, 0.0),
            length_unit: l,
            time_unit: t,
        })
    }

    /// Terminal settling time of the volume-equivalent sphere from the release point to the
    /// wall in quiescent fluid, (R − |x₀|)/v_s with v_s = m|a_G|/(3π μ_f) (Stokes drag of a
    /// sphere of diameter 1). The sphere has the least Stokes drag of all bodies of its volume
    /// (Hill & Power 1956), so no particle settles faster: a scale for time limits.
    pub fn sphere_settling_time(&self) -> f64 {
        let a_g = reduced_gravity(
            self.particle.gravity(),
            self.particle.rho_solid(),
            self.particle.fluid().rho,
            1.0,
        );
        let v_s = self.particle.mass() * a_g.norm() / (3.0 * PI * self.particle.fluid().mu);
        (self.flow.radius - self.release.norm()) / v_s
    }

    /// Stress-free particle at x₀ moving with the fluid, v = u(x₀) (paper §6.2).
    pub fn initial_state(&self) -> Result<State, FlowError> {
        let mut state = State::at_rest(self.release);
        state.v = self.flow.sample(&self.release, 0.0)?.u;
        Ok(state)
    }

    /// Adaptive inertialess integrator at rtol = atol = `tol` with an inertial barycentre
    /// (m v̇ = m a_G + μ_f K̂(u − v)); the rigid limit keeps the same barycentre model, so rigid
    /// and soft runs differ only in the shape response.
    pub fn integrator(&self, tol: f64) -> Result<Stokesian, ParamError> {
        Ok(Stokesian {
            barycentre: BarycentreModel::Inertial,
            scheme: Scheme::Radau5,
            ..Stokesian::new(tol)?
        })
    }
}

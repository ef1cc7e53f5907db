//! Constant data of a particle: shape, material, drag law, fluid, gravity, and the derived
//! mass m = ρ₀ vol(B₀) and Euler tensor Θ = (m/5) S Sᵀ (paper eq. 8).
//!
//! # Physics (paper eqs. 8, 13, 17)
//! For a homogeneous solid ellipsoid of density ρ₀ and rest shape S, eq. 8 gives
//! m = ρ₀ vol(B₀) with vol(B₀) = (4π/3) det S, and Θ = ∫ρ₀ Ξ⊗Ξ dV = (m/5) S Sᵀ (the second
//! moment of the unit ball is (4π/15) 1). The mass is constant; the current density
//! ρ_t = ρ₀/J and the buoyancy factor β_t (eqs. 13, 17) follow the volume.

use super::dynamics::Geometry;
use super::manifold::DeformedSpin;
use crate::ellipsoid::{Ellipsoid, EllipsoidIntegrals, PrincipalFrame};
use crate::error::{ParamError, derived, finite, positive};
use crate::hydro::{Brenner, DragModel, ForceTerms, JefferyRoscoe, VolumetricTraction};
use crate::material::{Response, Rigid, StressLaw};
use crate::tensor::{Mat3, Vec3, nearest_rotation};
use serde::{Deserialize, Serialize};

/// Largest rest-state rate (1/time, in the particle's units) a particle may have: 10¹⁵⁰, so
/// that its square, which error norms and Jacobian products form, stays below f64's 1.8·10³⁰⁸.
/// Physical rates are nowhere near it in any unit system (a 1 nm particle of 1 kg/m³ in a
/// fluid of 10⁶ Pa s has μ_f/(ρ_s R²) = 10²⁴ s⁻¹).
pub const MAX_RATE: f64 = 1e150;

/// Carrier fluid: dynamic viscosity μ_f and density ρ_f.
///
/// The fields are public for reading; deserialisation goes through [`Fluid::new`], and
/// [`Particle::with_drag`] checks them again, so a hand-built invalid value cannot reach a step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "FluidRaw")]
pub struct Fluid {
    /// Dynamic viscosity μ_f.
    pub mu: f64,
    /// Density ρ_f.
    pub rho: f64,
}

/// The serialised form of a [`Fluid`] (unchecked).
#[derive(Deserialize)]
struct FluidRaw {
    mu: f64,
    rho: f64,
}

impl TryFrom<FluidRaw> for Fluid {
    type Error = ParamError;
    fn try_from(raw: FluidRaw) -> Result<Self, ParamError> {
        Self::new(raw.mu, raw.rho)
    }
}

/// The range [10⁻⁵⁰, 10⁵⁰] of a fluid's viscosity μ_f and of a non-zero density ρ_f, in any
/// consistent units. Physical fluids span μ_f ≈ 10⁻⁶ (dilute gases) to 10²¹ Pa s (the
/// mantle) and ρ_f ≈ 10⁻⁵ (rarefied gases) to 1.4·10⁴ kg/m³ (mercury), a unit system (µm, µs, pg, or the
/// paper's nondimensional scales) moves them by at most some 20 orders, so a physical fluid
/// is at least 10 orders inside the range. Outside it a value is a slip, and the products a
/// step forms of it with the other inputs (μ_f γ̇ L², ρ_f |u − v| d/μ_f, ρ_f vol, the Saffman
/// lift's √(ρ_f μ_f)) overflow or vanish (`Fluid::new(f64::MAX, 1.0)` was accepted, and only
/// a particle's rest-rate check refused it afterwards).
pub const FLUID_RANGE: (f64, f64) = (1e-50, 1e50);

impl Fluid {
    /// Fluid with μ_f in [`FLUID_RANGE`] and ρ_f = 0 or in [`FLUID_RANGE`] (ρ_f = 0: no fluid
    /// inertia, the paper's heavy-particle limit).
    pub fn new(mu: f64, rho: f64) -> Result<Self, ParamError> {
        let (min, max) = FLUID_RANGE;
        if !(min..=max).contains(&mu) {
            return Err(ParamError::OutOfRange {
                name: "mu_f",
                value: mu,
                min,
                max,
            });
        }
        if !(rho == 0.0 || (min..=max).contains(&rho)) {
            return Err(ParamError::OutOfRange {
                name: "rho_f (or exactly 0)",
                value: rho,
                min,
                max,
            });
        }
        Ok(Self { mu, rho })
    }
}

/// A pseudo-rigid particle model (everything that does not change during a run).
#[derive(Debug, Clone)]
pub struct Particle<M, D = Brenner> {
    shape: Ellipsoid,
    material: M,
    drag: D,
    fluid: Fluid,
    rho_solid: f64,
    gravity: Vec3,
    volumetric: VolumetricTraction,
    forces: ForceTerms,
    // Derived, cached: S, m, vol(B₀), Θ⁻¹, the rest geometry, and a rigid particle's copy of it.
    s: Mat3,
    rest: Option<Geometry>,
    rigid: Option<Geometry>,
    mass: f64,
    volume0: f64,
    theta_inv: Mat3,
    /// A rigid twin of an elastic particle whose law is not isotropic ([`Particle::rigid_twin`]):
    /// its rotation stands for the elastic particle's, which the law's material directions
    /// need, so it is never passive ([`Particle::orientation_is_passive`]).
    anisotropic_twin: bool,
    /// A rigid twin that turns at the deformed particle's spin ([`Particle::manifold_twin`]).
    deformed_spin: Option<DeformedSpin>,
}

impl<M: Response> Particle<M, Brenner> {
    /// Particle with Brenner drag, the paper's volumetric traction and no gravity.
    pub fn new(shape: Ellipsoid, material: M, fluid: Fluid, rho_solid: f64) -> Result<Self, ParamError> {
        Self::with_drag(shape, material, Brenner, fluid, rho_solid)
    }
}

impl<M: Response, D: DragModel> Particle<M, D> {
    /// Particle with an explicit drag model.
    pub fn with_drag(shape: Ellipsoid, material: M, drag: D, fluid: Fluid, rho_solid: f64) -> Result<Self, ParamError> {
        let rho_solid = positive("rho_s", rho_solid)?;
        // Public fields: a hand-built fluid has not been through Fluid::new.
        let fluid = Fluid::new(fluid.mu, fluid.rho)?;
        if let Some(law) = material.elastic() {
            positive("shear modulus mu_s", law.shear_modulus())?;
            finite("Lame parameter lambda_s", law.lame_lambda())?;
        }
        let s = shape.shape_tensor();
        let volume0 = shape.volume();
        let mass = derived("mass m = rho_s vol(B0)", rho_solid * volume0, &[rho_solid, volume0])?;
        let theta_inv = shape.euler_tensor_inverse(mass)?;
        let particle = Self {
            shape,
            material,
            drag,
            fluid,
            rho_solid,
            gravity: Vec3::zeros(),
            volumetric: VolumetricTraction::default(),
            forces: ForceTerms::default(),
            s,
            rest: None,
            rigid: None,
            mass,
            volume0,
            theta_inv,
            anisotropic_twin: false,
            deformed_spin: None,
        };
        particle.check_rest_geometry()?;
        let rest = Geometry::try_of_total_distortion(&s)?;
        let rigid = match particle.material.elastic() {
            None => Some(rest),
            Some(_) => None,
        };
        Ok(Self {
            rest: Some(rest),
            rigid,
            ..particle
        })
    }

    /// The rest state's integrals, traction coefficients and drag must be finite: an ellipsoid
    /// whose R_a² are representable can still be too slender for Jeffery's integrals.
    fn check_rest_geometry(&self) -> Result<(), ParamError> {
        let frame = PrincipalFrame::from_total_distortion(&self.s);
        let ints = EllipsoidIntegrals::try_new(&frame.r)?;
        let traction_ok = JefferyRoscoe::new(&frame, &ints).is_finite();
        let drag = self.drag.resistance(&frame, &ints);
        match drag.iter().find(|c| !c.is_finite()) {
            Some(&value) => Err(ParamError::Derived {
                name: "rest drag tensor K",
                value,
                inputs: self.shape.semi_axes().iter().copied().collect(),
            }),
            None if !traction_ok => Err(ParamError::Derived {
                name: "rest traction coefficients",
                value: f64::NAN,
                inputs: self.shape.semi_axes().iter().copied().collect(),
            }),
            None => self.check_rates(drag.amax()),
        }
    }

    /// The rest state's rates must stay below [`MAX_RATE`]: the drag rate μ_f |K|/m, and the
    /// viscous and elastic rates μ_f/(ρ_s R²) and (μ_s + |λ_s|)/(ρ_s R²) over the smallest
    /// semi-axis R. Each parameter can be representable while these products are not, and an
    /// integrator forms their squares (error norms, Jacobian products), so a larger rate ends
    /// a step in a non-finite number instead of here.
    fn check_rates(&self, drag_max: f64) -> Result<(), ParamError> {
        let r_min = self.shape.semi_axes().iter().copied().fold(f64::INFINITY, f64::min);
        let inertia = self.rho_solid * r_min * r_min;
        let elastic = self
            .material
            .elastic()
            .map_or(0.0, |law| law.shear_modulus() + law.lame_lambda().abs());
        let mu = self.fluid.mu;
        let rates = [
            ("rest drag rate mu_f |K|/m", mu / self.mass * drag_max),
            ("rest viscous rate mu_f/(rho_s R_min^2)", mu / inertia),
            (
                "rest elastic rate (mu_s + |lambda_s|)/(rho_s R_min^2)",
                elastic / inertia,
            ),
        ];
        match rates.into_iter().find(|(_, rate)| !(*rate <= MAX_RATE)) {
            Some((name, value)) => Err(ParamError::OutOfRange {
                name,
                value,
                min: 0.0,
                max: MAX_RATE,
            }),
            None => Ok(()),
        }
    }

    /// Set the gravitational acceleration g.
    pub fn with_gravity(mut self, g: Vec3) -> Result<Self, ParamError> {
        for c in g.iter() {
            finite("gravity", *c)?;
        }
        self.gravity = g;
        Ok(self)
    }

    /// Choose the volumetric treatment of the traction (see [`VolumetricTraction`]).
    pub fn with_volumetric(mut self, vol: VolumetricTraction) -> Self {
        self.volumetric = vol;
        self
    }

    /// Add force terms beyond the paper's drag and reduced gravity ([`crate::hydro::forces`]);
    /// each term checks that it has a model for this particle's rest shape.
    pub fn with_forces(mut self, forces: ForceTerms) -> Result<Self, ParamError> {
        let semi_axes = self.shape.semi_axes();
        for term in forces.iter() {
            term.admits(&semi_axes)?;
        }
        self.forces = forces;
        Ok(self)
    }

    /// The force terms beyond the paper's (none by default).
    pub fn forces(&self) -> &ForceTerms {
        &self.forces
    }

    /// Stress-free ellipsoid B₀.
    pub fn shape(&self) -> &Ellipsoid {
        &self.shape
    }
    /// Shape tensor S.
    pub fn shape_tensor(&self) -> &Mat3 {
        &self.s
    }
    /// Shape response: a constitutive law, [`crate::material::Rigid`] or [`crate::material::Softness`].
    pub fn material(&self) -> &M {
        &self.material
    }
    /// Drag model.
    pub fn drag(&self) -> &D {
        &self.drag
    }
    /// Carrier fluid.
    pub fn fluid(&self) -> &Fluid {
        &self.fluid
    }
    /// Reference density ρ₀.
    pub fn rho_solid(&self) -> f64 {
        self.rho_solid
    }
    /// Gravity g.
    pub fn gravity(&self) -> &Vec3 {
        &self.gravity
    }
    /// Volumetric traction model.
    pub fn volumetric(&self) -> VolumetricTraction {
        self.volumetric
    }
    /// Mass m = ρ₀ vol(B₀).
    pub fn mass(&self) -> f64 {
        self.mass
    }
    /// vol(B₀).
    pub fn volume0(&self) -> f64 {
        self.volume0
    }
    /// Θ⁻¹.
    pub fn theta_inv(&self) -> &Mat3 {
        &self.theta_inv
    }

    /// Total distortion F̄ = F·S.
    pub fn total_distortion(&self, f: &Mat3) -> Mat3 {
        f * self.s
    }

    /// The current ellipsoid's principal frame (semi-axes r₁ ≥ r₂ ≥ r₃ and axes) at
    /// deformation F: the frame of F̄ = F·S; for a rigid particle the rest frame turned by the
    /// rotation nearest F ([`Self::geometry`]). Not counted, like [`Self::geometry`].
    pub fn frame(&self, f: &Mat3) -> PrincipalFrame {
        match &self.rigid {
            Some(rest) => rest.frame.turned(&nearest_rotation(f)),
            None => PrincipalFrame::from_total_distortion(&self.total_distortion(f)),
        }
    }

    /// Geometry (frame, integrals, traction coefficients) of the shape with deformation F, for
    /// analysis outside a step. Not counted: inside a step use
    /// [`Model::geometry`](super::Model::geometry), which refuses det F ≤ 0, counts the model
    /// evaluation and then calls this, so the two cannot drift apart.
    ///
    /// A rigid particle's shape is its rest shape turned by F's rotation R (F is a rotation up
    /// to the integration error, and the integrator projects it back onto SO(3) after every
    /// step): its semi-axes, integrals and traction coefficients are computed once, at
    /// construction, and only the frame turns, Q = Q₀ Rᵀ with R the rotation nearest F. This
    /// skips the eigen-decomposition and Carlson's integrals, most of a rigid particle's
    /// evaluation; for F ∈ SO(3) it is the same geometry up to round-off (tested).
    pub fn geometry(&self, f: &Mat3) -> Geometry {
        match &self.rigid {
            Some(rest) => rest.turned(&nearest_rotation(f)),
            None => Geometry::of_total_distortion(&self.total_distortion(f)),
        }
    }

    /// The geometry at `f`, or why it does not exist (`f` not finite or singular, an
    /// ellipsoid too slender for f64): [`Self::geometry`] for F from user data.
    pub fn try_geometry(&self, f: &Mat3) -> Result<Geometry, ParamError> {
        match &self.rigid {
            Some(rest) => {
                if let Some(&value) = f.iter().find(|v| !v.is_finite()) {
                    return Err(ParamError::NonFinite {
                        name: "deformation gradient F",
                        value,
                    });
                }
                let det_f = f.determinant();
                if !(det_f > 0.0) {
                    return Err(ParamError::NotPositive {
                        name: "det F of a rigid particle",
                        value: det_f,
                    });
                }
                Ok(rest.turned(&nearest_rotation(f)))
            }
            None => Geometry::try_of_total_distortion(&self.total_distortion(f)),
        }
    }

    /// The rest shape's geometry (F = 1), computed once at construction.
    pub fn rest_geometry(&self) -> Geometry {
        match self.rest {
            Some(rest) => rest,
            None => unreachable!("every constructor sets the rest geometry"),
        }
    }

    /// The same particle made rigid (the limit Ca → 0): shape, drag, fluid, density, gravity,
    /// traction and force terms shared, the material replaced by [`Rigid`], the rest geometry
    /// reused. The slow-manifold model ([`crate::integrator::manifold`]) turns it as a
    /// stiff elastic sphere's rotation ([`Self::manifold_twin`]). No allocation: the drag is
    /// borrowed and the force terms are shared.
    pub fn rigid_twin(&self) -> Particle<Rigid, &D> {
        Particle {
            shape: self.shape,
            material: Rigid,
            drag: &self.drag,
            fluid: self.fluid,
            rho_solid: self.rho_solid,
            gravity: self.gravity,
            volumetric: self.volumetric,
            forces: self.forces.clone(),
            s: self.s,
            rest: self.rest,
            rigid: self.rest,
            mass: self.mass,
            volume0: self.volume0,
            theta_inv: self.theta_inv,
            anisotropic_twin: self.anisotropic_twin || self.elastic().is_some_and(|law| !law.is_isotropic()),
            deformed_spin: None,
        }
    }

    /// The rigid twin that the slow manifold turns ([`crate::integrator::manifold`]): for an
    /// elastic non-sphere it spins as the deformed particle does to first order in δ
    /// ([`DeformedSpin`]), with the flow gradient changing along the path at `gradient_rate`
    /// (d∇u/dt, held over the step); otherwise [`Self::rigid_twin`] (a sphere's rotation
    /// enters nothing on the manifold).
    pub fn manifold_twin(&self, gradient_rate: &Mat3) -> Particle<Rigid, &D> {
        let r = self.shape.semi_axes();
        let deformed_spin = match self.elastic() {
            Some(law) if r.max() != r.min() => Some(DeformedSpin {
                mu_s: law.shear_modulus(),
                gradient_rate: *gradient_rate,
            }),
            _ => None,
        };
        Particle {
            deformed_spin,
            ..self.rigid_twin()
        }
    }

    /// The deformed particle's spin a rigid twin turns at ([`Self::manifold_twin`]), if any.
    pub fn deformed_spin(&self) -> Option<&DeformedSpin> {
        self.deformed_spin.as_ref()
    }

    /// Whether the particle's orientation enters none of its equations: a rigid sphere whose
    /// drag is [`DragModel::isotropic_on_spheres`] and whose force terms are all
    /// [`crate::hydro::forces::ForceTerm::orientation_free_on_spheres`]. Its rotation then
    /// turns nothing the model sees: the drag, Jeffery's spin, the contact's extent, the
    /// traction and every force are the same for any F ∈ SO(3). The Rosenbrock-W step still
    /// integrates F (the output carries it) but leaves it out of its error test, so the steps
    /// follow the barycentre alone ([`crate::integrator::Stokesian`]). Never for an elastic
    /// particle (its F is its deformation). The rigid twin of an elastic sphere
    /// ([`Self::rigid_twin`], the slow manifold's rotation) is passive when its law is
    /// isotropic ([`crate::material::Hyperelastic::is_isotropic`]): the manifold's stretch V
    /// then depends on the flow alone, and the shape B = F Fᵀ = V² on nothing of the rotation.
    pub fn orientation_is_passive(&self) -> bool {
        let r = self.shape.semi_axes();
        self.elastic().is_none()
            && !self.anisotropic_twin
            && r.max() == r.min()
            && self.drag.isotropic_on_spheres()
            && self.forces.orientation_free_on_spheres()
    }

    /// The hyperelastic law, or `None` for a rigid particle.
    pub fn elastic(&self) -> Option<&M::Law> {
        self.material.elastic()
    }

    /// Elastic energy W(F) vol(B₀) of a state (0 for a rigid particle).
    pub fn elastic_energy(&self, f: &Mat3) -> f64 {
        self.elastic().map_or(0.0, |law| law.energy_at(f) * self.volume0)
    }
}

//! Analytic linear and pipe flows.
//!
//! # Physics (paper §6.1 simple shear, §6.2 Poiseuille pipe)
//! - quiescent: u = 0;
//! - simple shear: u = γ̇ x₂ e₁, so l_f = γ̇ e₁⊗e₂ and the vorticity is −γ̇ e₃;
//! - planar extension: u = ε̇ (x₁, −x₂, 0);
//! - uniaxial extension: u = ε̇ (x₁, −x₂/2, −x₃/2);
//! - Poiseuille pipe along e₁ with radius R and mean velocity Ū:
//!   $u = 2Ū (1 − r²/R²) e_1$, r the distance from the axis; outside r > R is out of the domain.

use super::{FlowField, FlowSample, check_query};
use crate::error::{FlowError, ParamError, finite, positive};
use crate::tensor::{Mat3, Vec3};
use serde::{Deserialize, Serialize};

/// Fluid at rest.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize)]
pub struct Quiescent;

impl FlowField for Quiescent {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        check_query(x, t)?;
        Ok(FlowSample::steady(Vec3::zeros(), Mat3::zeros()))
    }
}

/// Linear flow u = u₀ + L·x with a constant gradient L (shear, extensions, any combination).
///
/// The fields are public for reading; deserialisation goes through [`LinearFlow::new`], and
/// [`FlowField::sample`] rejects a non-finite result (a far query point, or a hand-built value)
/// with [`FlowError::NonFiniteSample`].
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
#[serde(try_from = "LinearFlowRaw")]
pub struct LinearFlow {
    /// Velocity at the origin.
    pub u0: Vec3,
    /// Constant velocity gradient L.
    pub grad_u: Mat3,
}

/// The serialised form of a [`LinearFlow`] (unchecked).
#[derive(Deserialize)]
struct LinearFlowRaw {
    u0: Vec3,
    grad_u: Mat3,
}

impl TryFrom<LinearFlowRaw> for LinearFlow {
    type Error = ParamError;
    fn try_from(raw: LinearFlowRaw) -> Result<Self, ParamError> {
        Self::new(raw.u0, raw.grad_u)
    }
}

/// `Ok(sample)` when u and ∇u are finite, else the typed error with the numbers.
pub(super) fn finite_sample(sample: FlowSample, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
    if sample.u.iter().chain(sample.grad_u.iter()).all(|c| c.is_finite()) {
        Ok(sample)
    } else {
        Err(FlowError::NonFiniteSample {
            x: [x[0], x[1], x[2]],
            t,
            u: [sample.u[0], sample.u[1], sample.u[2]],
        })
    }
}

impl LinearFlow {
    /// General linear flow; the gradient must be finite and traceless (incompressible).
    pub fn new(u0: Vec3, grad_u: Mat3) -> Result<Self, ParamError> {
        for c in u0.iter().chain(grad_u.iter()) {
            finite("linear flow coefficient", *c)?;
        }
        let scale = grad_u.abs().max().max(1.0);
        if grad_u.trace().abs() > 1e-12 * scale {
            return Err(ParamError::NonFinite {
                name: "tr grad_u (must be 0)",
                value: grad_u.trace(),
            });
        }
        Ok(Self { u0, grad_u })
    }

    /// Simple shear u = γ̇ x₂ e₁.
    pub fn simple_shear(shear_rate: f64) -> Result<Self, ParamError> {
        let mut l = Mat3::zeros();
        l[(0, 1)] = finite("shear rate", shear_rate)?;
        Self::new(Vec3::zeros(), l)
    }

    /// Planar extension u = ε̇ (x₁, −x₂, 0).
    pub fn planar_extension(rate: f64) -> Result<Self, ParamError> {
        let r = finite("extension rate", rate)?;
        Self::new(Vec3::zeros(), Mat3::from_diagonal(&Vec3::new(r, -r, 0.0)))
    }

    /// Uniaxial extension u = ε̇ (x₁, −x₂/2, −x₃/2).
    pub fn uniaxial_extension(rate: f64) -> Result<Self, ParamError> {
        let r = finite("extension rate", rate)?;
        Self::new(Vec3::zeros(), Mat3::from_diagonal(&Vec3::new(r, -0.5 * r, -0.5 * r)))
    }

    /// The same flow seen in a frame rotated by `q` (x′ = q x): u′ = q u₀, L′ = q L qᵀ.
    pub fn rotated(&self, q: &Mat3) -> Self {
        Self {
            u0: q * self.u0,
            grad_u: q * self.grad_u * q.transpose(),
        }
    }
}

impl FlowField for LinearFlow {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        check_query(x, t)?;
        let sample = FlowSample::steady(self.u0 + self.grad_u * x, self.grad_u);
        finite_sample(sample, x, t)
    }

    fn strain_rate(&self) -> Option<f64> {
        Some(super::strain_rate_magnitude(&self.grad_u))
    }
}

/// Hagen–Poiseuille flow in a straight circular pipe whose axis is the x₁ axis.
///
/// The fields are public for reading; deserialisation goes through [`Poiseuille::new`], and
/// sampling rejects a non-finite result.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
#[serde(try_from = "PoiseuilleRaw")]
pub struct Poiseuille {
    /// Pipe radius R.
    pub radius: f64,
    /// Mean (bulk) velocity Ū; the centreline velocity is 2Ū.
    pub mean_velocity: f64,
}

/// The serialised form of a [`Poiseuille`] flow (unchecked).
#[derive(Deserialize)]
struct PoiseuilleRaw {
    radius: f64,
    mean_velocity: f64,
}

impl TryFrom<PoiseuilleRaw> for Poiseuille {
    type Error = ParamError;
    fn try_from(raw: PoiseuilleRaw) -> Result<Self, ParamError> {
        Self::new(raw.radius, raw.mean_velocity)
    }
}

impl Poiseuille {
    /// Pipe of radius `radius` with bulk velocity `mean_velocity`. The centreline velocity 2Ū
    /// and the wall shear rate 4|Ū|/R must be finite (they bound u and ∇u in the pipe).
    pub fn new(radius: f64, mean_velocity: f64) -> Result<Self, ParamError> {
        let radius = positive("pipe radius", radius)?;
        let mean_velocity = finite("mean velocity", mean_velocity)?;
        finite("centreline velocity 2U", 2.0 * mean_velocity)?;
        finite("wall shear rate 4U/R", 4.0 * mean_velocity / radius)?;
        Ok(Self { radius, mean_velocity })
    }

    /// Wall shear rate magnitude at distance `r` from the axis, |du/dr| = 4Ū r / R².
    pub fn shear_rate(&self, r: f64) -> f64 {
        4.0 * self.mean_velocity / self.radius * (r / self.radius)
    }
}

impl FlowField for Poiseuille {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        check_query(x, t)?;
        // Coordinates in units of R: R² may overflow (R = 1e155) where (x/R)² cannot.
        let (y, z) = (x[1] / self.radius, x[2] / self.radius);
        let rho2 = y * y + z * z;
        if rho2 > 1.0 {
            return Err(FlowError::outside(x));
        }
        let umax = 2.0 * self.mean_velocity;
        let wall_rate = 2.0 * umax / self.radius;
        let mut grad_u = Mat3::zeros();
        grad_u[(0, 1)] = -wall_rate * y;
        grad_u[(0, 2)] = -wall_rate * z;
        let sample = FlowSample::steady(Vec3::new(umax * (1.0 - rho2), 0.0, 0.0), grad_u);
        finite_sample(sample, x, t)
    }

    /// The cross-section mean of |du/dr| = 4Ū r/R²: (1/πR²) ∫₀^R (4Ū r/R²) 2πr dr = 8|Ū|/(3R).
    fn strain_rate(&self) -> Option<f64> {
        Some(8.0 * self.mean_velocity.abs() / (3.0 * self.radius))
    }
}

/// Plug flow around a bend: u = U e_φ at every point, e_φ = (−sin φ, cos φ, 0) the azimuthal
/// direction about the x₃ axis, the flow of a torus-shaped bend with a flat profile and no
/// secondary flow (Yeh 1974's idealisation). With ρ = √(x₁² + x₂²),
/// ```math
/// u = \frac{U}{\rho}(−x_2, x_1, 0),\qquad
/// \nabla u = \frac{U}{\rho^3}\begin{pmatrix} x_1 x_2 & −x_1^2 & 0\\ x_2^2 & −x_1 x_2 & 0\\ 0 & 0 & 0\end{pmatrix},
/// ```
/// divergence-free, with the centripetal acceleration (u·∇)u = −(U²/ρ) e_ρ. Defined off the
/// x₃ axis (ρ > 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BendPlug {
    /// Speed U.
    pub speed: f64,
}

impl FlowField for BendPlug {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        check_query(x, t)?;
        let rho = x[0].hypot(x[1]);
        if !(rho > 0.0) {
            return Err(FlowError::outside(x));
        }
        let u = Vec3::new(-x[1], x[0], 0.0) * (self.speed / rho);
        let c = self.speed / (rho * rho * rho);
        let grad_u = Mat3::new(
            c * x[0] * x[1],
            -c * x[0] * x[0],
            0.0,
            c * x[1] * x[1],
            -c * x[0] * x[1],
            0.0,
            0.0,
            0.0,
            0.0,
        );
        finite_sample(FlowSample::steady(u, grad_u), x, t)
    }
}

/// A smooth divergence-free cellular flow, the curl of
/// $A = UL (\sin ξ_2 \sin ξ_3, \sin ξ_3 \sin ξ_1, \sin ξ_1 \sin ξ_2)$ with $ξ = x/L$:
/// ```math
/// u = U\begin{pmatrix} \sin ξ_1(\cos ξ_2 − \cos ξ_3)\\ \sin ξ_2(\cos ξ_3 − \cos ξ_1)\\ \sin ξ_3(\cos ξ_1 − \cos ξ_2)\end{pmatrix}.
/// ```
/// Not a flow of any of the paper's scenes: a field with curvature on the scale L everywhere,
/// to be written into a mesh's cells and patches and read back, so that a reconstruction of
/// cell data (the blend, its tables) is compared with the exact u and ∇u
/// (`examples/octree_field`).
#[derive(Debug, Clone, Copy)]
pub struct Cellular {
    /// Velocity scale U.
    pub speed: f64,
    /// Length scale L (a cell of the pattern is πL wide).
    pub length: f64,
}

impl Cellular {
    /// The field with velocity scale `speed` (finite) and length scale `length` (positive).
    pub fn new(speed: f64, length: f64) -> Result<Self, ParamError> {
        Ok(Self {
            speed: finite("cellular flow speed", speed)?,
            length: positive("cellular flow length", length)?,
        })
    }
}

impl FlowField for Cellular {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        check_query(x, t)?;
        let (u, l) = (self.speed, self.length);
        let sc: [(f64, f64); 3] = std::array::from_fn(|a| (x[a] / l).sin_cos());
        let (s, c) = (sc.map(|p| p.0), sc.map(|p| p.1));
        let velocity = Vec3::new(s[0] * (c[1] - c[2]), s[1] * (c[2] - c[0]), s[2] * (c[0] - c[1])) * u;
        // ∂u_i/∂x_j, i the row.
        let grad_u = Mat3::new(
            c[0] * (c[1] - c[2]),
            -s[0] * s[1],
            s[0] * s[2],
            s[1] * s[0],
            c[1] * (c[2] - c[0]),
            -s[1] * s[2],
            -s[2] * s[0],
            s[2] * s[1],
            c[2] * (c[0] - c[1]),
        ) * (u / l);
        finite_sample(FlowSample::steady(velocity, grad_u), x, t)
    }
}

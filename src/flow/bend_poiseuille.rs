//! Poiseuille's profile carried around a bend without secondary flow: the flow of the bend's
//! onset limit (`studies::bend_plug`, issue 61).
//!
//! # Physics
//! A torus-shaped bend: the tube of radius a about the circle of radius R_b in the plane
//! x₃ = 0 centred on the x₃ axis. With ρ = √(x₁² + x₂²) and r the distance from the tube's
//! centreline, r² = (ρ − R_b)² + x₃², the velocity is the parabolic profile of mean speed U
//! along the arc,
//! ```math
//! u = f\,e_\varphi,\qquad f = 2U\left(1 − \frac{r^2}{a^2}\right),\qquad
//! e_\varphi = \frac{(−x_2, x_1, 0)}{\rho},
//! ```
//! so the fluid moves on circles about the x₃ axis, as in a bend with its Dean vortices switched
//! off: the developed-profile counterpart of the plug flow [`super::analytic::BendPlug`] (Yeh
//! 1974's idealisation), a Navier–Stokes solution only as R_b/a → ∞. With g = f/ρ, u = g (−x₂, x₁, 0) and
//! ```math
//! \nabla u = g\begin{pmatrix}0 & −1 & 0\\ 1 & 0 & 0\\ 0 & 0 & 0\end{pmatrix}
//! + (−x_2, x_1, 0)^{\mathsf T} \otimes \nabla g,\qquad
//! \nabla g = \frac{1}{\rho}\left(\frac{x_1}{\rho}\Big(\partial_\rho f − \frac{f}{\rho}\Big),
//! \frac{x_2}{\rho}\Big(\partial_\rho f − \frac{f}{\rho}\Big), \partial_3 f\right),
//! ```
//! with ∂_ρ f = −4U(ρ − R_b)/a² and ∂₃f = −4U x₃/a². It is divergence-free (f does not depend
//! on φ), and its centripetal acceleration is (u·∇)u = −(f²/ρ) e_ρ. The profile is that of a
//! straight pipe ([`super::analytic::Poiseuille`]) at every section; points beyond the wall,
//! r > a, are outside the domain.

use super::analytic::finite_sample;
use super::{FlowField, FlowSample, check_query};
use crate::error::{FlowError, ParamError, finite, positive};
use crate::tensor::Vec3;

/// Poiseuille flow around a torus-shaped bend, without secondary flow (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BendPoiseuille {
    bend_radius: f64,
    tube_radius: f64,
    mean_velocity: f64,
}

impl BendPoiseuille {
    /// A bend of centreline radius `bend_radius` R_b and tube radius `tube_radius` a < R_b
    /// (the torus must not cross its axis) with mean velocity `mean_velocity` U.
    pub fn new(bend_radius: f64, tube_radius: f64, mean_velocity: f64) -> Result<Self, ParamError> {
        let bend_radius = positive("bend radius", bend_radius)?;
        let tube_radius = positive("tube radius", tube_radius)?;
        if !(tube_radius < bend_radius) {
            return Err(ParamError::OutOfRange {
                name: "tube radius",
                value: tube_radius,
                min: 0.0,
                max: bend_radius,
            });
        }
        let mean_velocity = finite("mean velocity", mean_velocity)?;
        finite("centreline velocity 2U", 2.0 * mean_velocity)?;
        Ok(Self {
            bend_radius,
            tube_radius,
            mean_velocity,
        })
    }

    /// Centreline radius R_b.
    pub fn bend_radius(&self) -> f64 {
        self.bend_radius
    }

    /// Tube radius a.
    pub fn tube_radius(&self) -> f64 {
        self.tube_radius
    }

    /// Mean velocity U over the cross-section; the centreline's is 2U.
    pub fn mean_velocity(&self) -> f64 {
        self.mean_velocity
    }
}

impl FlowField for BendPoiseuille {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        check_query(x, t)?;
        let rho = x[0].hypot(x[1]);
        // Coordinates across the tube in units of a, as in the straight pipe.
        let (s, z) = ((rho - self.bend_radius) / self.tube_radius, x[2] / self.tube_radius);
        let r2 = s * s + z * z;
        if !(r2 <= 1.0 && rho > 0.0) {
            return Err(FlowError::outside(x));
        }
        let (umax, a) = (2.0 * self.mean_velocity, self.tube_radius);
        let f = umax * (1.0 - r2);
        let (df_rho, df_z) = (-2.0 * umax * s / a, -2.0 * umax * z / a);
        let g = f / rho;
        let radial = (df_rho - g) / rho;
        let grad_g = Vec3::new(x[0] / rho * radial, x[1] / rho * radial, df_z / rho);
        let along = Vec3::new(-x[1], x[0], 0.0);
        let mut grad_u = along * grad_g.transpose();
        grad_u[(0, 1)] -= g;
        grad_u[(1, 0)] += g;
        finite_sample(FlowSample::steady(along * g, grad_u), x, t)
    }
}

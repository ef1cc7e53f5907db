//! Steady tank-treading of an initially spherical Neo-Hooke particle in simple shear.
//!
//! # Physics (Roscoe 1967; paper §6.1)
//! An initially spherical particle (radius R₀ = 1/2) reaches a steady state with fixed shape
//! and orientation while its material rotates through that shape. Such a motion is affine,
//! F(t) = V·R(t) with V = Qᵀ diag(λ₁, λ₂, λ₃) Q fixed and R(t) a rotation about the vorticity
//! axis, so l_s = ḞF⁻¹ = V Ω V⁻¹ with Ω = ṘRᵀ skew. In the body frame
//! (n₁ the in-plane long axis at angle θ from the flow, n₂ in-plane short, n₃ = e_z):
//!
//! $l_{s,12}^{\prime} = -\nu\\,\lambda_1/\lambda_2,\quad l_{s,21}^{\prime} = \nu\\,\lambda_2/\lambda_1$, all other
//! components 0 (a pure tank-treading rotation; the shape b̄ = R₀²V² is stationary),
//!
//! and FFᵀ = V² makes the elastic stress σ_el = μ_s(V² − 1) + p1 constant (J = 1).
//! The fluid gradient in the body frame is l′_f,11 = −l′_f,22 = ½ sin 2θ,
//! l′_f,12 = cos²θ, l′_f,21 = −sin²θ. With g = l_f − l_s, d = sym g, w = skw g and
//! x_i = r_i² = R₀²λ_i², the steady inertialess balance dev σ̃ = dev σ_el of the
//! Jeffery–Roscoe traction ([`crate::hydro::traction`]) reduces to four algebraic equations:
//!
//! 1. torque-free (Jeffery): $w_{12} = e\\,d_{12}$, $e = (x_1 - x_2)/(x_1 + x_2)$;
//! 2. no in-plane shear stress: $2 d_{s,12} + K d_{12} = 0$, $K = 4/(abc\\,\alpha_3^{\prime} (x_1+x_2))$;
//! 3. first normal-stress balance (Roscoe's I):
//!    $\frac{2}{abc\\,\Sigma^{\prime\prime}}(\alpha_1^{\prime\prime} + \alpha_2^{\prime\prime})\sin 2\theta = (\lambda_1^2 - \lambda_2^2)/Ca$;
//! 4. second one (Roscoe's J): $\frac{2}{abc\\,\Sigma^{\prime\prime}}\alpha_1^{\prime\prime} \sin 2\theta = (\lambda_1^2 - \lambda_3^2)/Ca$,
//!
//! with λ₃ = 1/(λ₁λ₂). Here d₁₂ = ½cos 2θ − ½ν(λ₂/λ₁ − λ₁/λ₂),
//! w₁₂ = ½ + ½ν(λ₁/λ₂ + λ₂/λ₁) and d_s,12 = ½ν(λ₂/λ₁ − λ₁/λ₂). For a given shape (λ₁, λ₂),
//! equations 1–2 are linear in (cos 2θ, ν); Newton on (λ₁, λ₂) then solves 3–4. Nothing here
//! integrates in time, and σ̃ is not evaluated through the library's traction code: only the
//! Jeffery integrals α′, α″ are shared.
//!
//! Small Ca: the sphere has 2(α″₁+α″₂)/(abcΣ'') = 5, so D = (r₁ − r₃)/(r₁ + r₃) → (5/4)Ca and
//! θ → π/4 − (3/4)Ca (Roscoe 1967, small-Ca expansion); the error is O(Ca²).

use super::StudyError;
use super::particles::Shape;
use super::section::ShearPlaneSection;
use super::shear_run::unit_shear;
use super::shear_shape::ShearShape;
use crate::diagnostics::{Monitor, Validity};
use crate::driver::{Observers, Problem, run};
use crate::ellipsoid::EllipsoidIntegrals;
use crate::integrator::Stokesian;
use crate::particle::{ShearScaling, State};
use crate::tensor::Vec3;
use nalgebra::{Matrix2, Vector2};
use std::f64::consts::FRAC_PI_4;

/// Radius of the initial sphere in units of d_eq.
const R0: f64 = 0.5;

/// Steady shape and orientation of a tank-treading particle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TankTreading {
    /// Capillary number.
    pub ca: f64,
    /// In-plane long semi-axis r₁.
    pub r_long: f64,
    /// Semi-axis along the vorticity.
    pub r_vorticity: f64,
    /// In-plane short semi-axis r₃.
    pub r_short: f64,
    /// Inclination of the long axis from the flow direction (radians, first quadrant).
    pub theta: f64,
}

impl TankTreading {
    /// Taylor deformation D = (r₁ − r₃)/(r₁ + r₃) of the in-plane axes.
    pub fn deformation(&self) -> f64 {
        (self.r_long - self.r_short) / (self.r_long + self.r_short)
    }

    /// Small-Ca limit: D = (5/4)Ca, θ = π/4 − (3/4)Ca (semi-axes from D at constant volume
    /// are not part of the limit; they are set to R₀(1 ± D) and R₀).
    pub fn small_ca_limit(ca: f64) -> Self {
        let d = 1.25 * ca;
        Self {
            ca,
            r_long: R0 * (1.0 + d),
            r_vorticity: R0,
            r_short: R0 * (1.0 - d),
            theta: FRAC_PI_4 - 0.75 * ca,
        }
    }
}

/// The steady state solved from the algebraic equations, with the tank-treading rate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoscoeSolution {
    /// Shape and inclination.
    pub steady: TankTreading,
    /// ν of l′_s (negative: the material turns clockwise like the vorticity −e_z).
    pub nu: f64,
    /// Newton iterations over the whole continuation path.
    pub iterations: u32,
}

/// Shape-dependent pieces of the steady equations at in-plane stretches (λ₁, λ₂).
struct Steady {
    cos2: f64,
    nu: f64,
    residual: Vector2<f64>,
}

fn steady_equations(ca: f64, l1: f64, l2: f64) -> Option<Steady> {
    let l3 = 1.0 / (l1 * l2);
    let r = Vec3::new(R0 * l1, R0 * l2, R0 * l3);
    let ints = EllipsoidIntegrals::new(&r);
    let (x, app, abc) = (ints.x, ints.alpha_pp, ints.abc);
    let e = (x[0] - x[1]) / (x[0] + x[1]);
    let k = 4.0 / (abc * ints.alpha_p[2] * (x[0] + x[1]));
    let p = l1 / l2 + l2 / l1;
    let q = l2 / l1 - l1 / l2;
    // Equations 1–2, linear in (c, ν) = (cos 2θ, ν):
    //   ½K c + q(1 − ½K) ν = 0,   −½e c + ½(p + e q) ν = −½.
    let m = Matrix2::new(0.5 * k, q * (1.0 - 0.5 * k), -0.5 * e, 0.5 * (p + e * q));
    let sol = m.lu().solve(&Vector2::new(0.0, -0.5))?;
    let (cos2, nu) = (sol[0], sol[1]);
    if cos2.is_nan() || cos2.abs() >= 1.0 {
        return None;
    }
    let sin2 = (1.0 - cos2 * cos2).sqrt();
    let sigma2 = app[0] * app[1] + app[1] * app[2] + app[2] * app[0];
    let c = 2.0 / (abc * sigma2) * sin2 * ca;
    let residual = Vector2::new(
        c * (app[0] + app[1]) - (l1 * l1 - l2 * l2),
        c * app[0] - (l1 * l1 - l3 * l3),
    );
    Some(Steady { cos2, nu, residual })
}

/// Solve the steady tank-treading equations at `ca` by damped Newton on (λ₁, λ₂) to a residual
/// of 1e-12 λ₁², continued
/// in Ca from 0.01 (or `ca` if smaller) in steps of ×1.2 from the small-Ca guess.
pub fn roscoe(ca: f64) -> Result<RoscoeSolution, StudyError> {
    crate::error::positive("Ca", ca)?;
    let fail = |iters, residual| StudyError::SteadyNotConverged { ca, iters, residual };
    let mut c = ca.min(0.01);
    let mut l = Vector2::new(1.0 + 1.25 * c, 1.0 - 1.25 * c);
    let mut iterations = 0;
    loop {
        let mut s = steady_equations(c, l[0], l[1]).ok_or(fail(iterations, f64::NAN))?;
        // The residual is a difference of O(λ₁²) terms: round-off sets its floor.
        let tol = 1e-12 * l[0] * l[0];
        let mut converged = false;
        for _ in 0..50 {
            if s.residual.amax() <= tol {
                converged = true;
                break;
            }
            iterations += 1;
            let h = 1e-7;
            let mut jac = Matrix2::zeros();
            for j in 0..2 {
                let mut lp = l;
                let mut lm = l;
                lp[j] += h;
                lm[j] -= h;
                let (rp, rm) = (
                    steady_equations(c, lp[0], lp[1]).ok_or(fail(iterations, s.residual.amax()))?,
                    steady_equations(c, lm[0], lm[1]).ok_or(fail(iterations, s.residual.amax()))?,
                );
                jac.set_column(j, &((rp.residual - rm.residual) / (2.0 * h)));
            }
            let dl = jac
                .lu()
                .solve(&-s.residual)
                .ok_or(fail(iterations, s.residual.amax()))?;
            // Damping: halve until the trial shape is admissible and the residual drops.
            let mut step = 1.0;
            loop {
                let trial = l + dl * step;
                match steady_equations(c, trial[0], trial[1]) {
                    Some(t) if t.residual.amax() < s.residual.amax() => {
                        l = trial;
                        s = t;
                        break;
                    }
                    _ if step > 1e-6 => step *= 0.5,
                    _ => return Err(fail(iterations, s.residual.amax())),
                }
            }
        }
        if !converged {
            return Err(fail(iterations, s.residual.amax()));
        }
        if c >= ca {
            let l3 = 1.0 / (l[0] * l[1]);
            return Ok(RoscoeSolution {
                steady: TankTreading {
                    ca,
                    r_long: R0 * l[0],
                    r_vorticity: R0 * l3,
                    r_short: R0 * l[1],
                    theta: 0.5 * s.cos2.acos(),
                },
                nu: s.nu,
                iterations,
            });
        }
        c = (1.2 * c).min(ca);
    }
}

/// The steady state by time integration: an initially spherical particle in unit shear,
/// inertialess integration (Radau IIA) with rtol = atol = `tol` up to `t_end`.
#[derive(Debug, Clone, PartialEq)]
pub struct IntegratedSteady {
    /// State read at t_end.
    pub steady: TankTreading,
    /// max(|ΔD|, |Δθ|) between t_end − 1 and t_end: how far from steady the run still is.
    pub drift: f64,
    /// Validity diagnostics of the run (inertialess: Re = 0 by assumption; r₁ in d_eq).
    pub validity: Validity,
}

/// Integrate the initially spherical particle at `ca` to `t_end` (≥ 1).
pub fn integrate(ca: f64, tol: f64, t_end: f64) -> Result<IntegratedSteady, StudyError> {
    let scaling = ShearScaling::new(ca, 1.0, 1e3)?;
    let particle = ShearShape::new(Shape::Sphere).particle(&scaling)?;
    let mut read = Vec::with_capacity(2);
    let flow = unit_shear();
    let start = State::at_rest(Vec3::zeros());
    let mut monitor = Monitor::in_linear_flow(&particle, &flow);
    monitor.observe(&start);
    run(
        Problem::new(&Stokesian::overdamped(tol)?, &particle, &flow),
        start,
        1e-3,
        &[t_end - 1.0, t_end],
        Observers::new(
            |s| {
                let sec = ShearPlaneSection::of(&particle.total_distortion(&s.f));
                read.push(TankTreading {
                    ca,
                    r_long: sec.r_long,
                    r_vorticity: sec.r_out_of_plane,
                    r_short: sec.r_short,
                    theta: sec.angle,
                });
            },
            |step| monitor.observe_step(step),
        ),
    )?;
    let (before, end) = (read[0], read[1]);
    Ok(IntegratedSteady {
        steady: end,
        drift: (end.deformation() - before.deformation())
            .abs()
            .max((end.theta - before.theta).abs()),
        validity: monitor.validity().inertialess(),
    })
}

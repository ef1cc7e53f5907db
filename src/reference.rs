//! Reference problems with exact solutions, shared by tests, benches and examples.

use crate::error::ParamError;
use std::f64::consts::{FRAC_PI_2, PI};

/// Jeffery's in-plane orbit of a rigid spheroid with aspect ratio r in simple shear
/// u = γ̇ y e_x (Jeffery 1922): the symmetry axis' angle φ from the gradient
/// axis y towards the flow, with φ(0) = 0, satisfies tan φ = r tan(γ̇ t r/(r² + 1)).
/// Returned unwrapped (continuous in t). Time is in units of 1/γ̇.
pub fn jeffery_phi(r: f64, t: f64) -> f64 {
    let s = t * r / (r * r + 1.0);
    let turns = ((s + FRAC_PI_2) / PI).floor();
    (r * (s - turns * PI).tan()).atan() + turns * PI
}

/// Time at which the orbit of [`jeffery_phi`] passes φ = π/2 (axis along the flow):
/// t₀ = (π/2)(r² + 1)/r. An orbit started with the axis along the flow is φ(t₀ + t).
pub fn jeffery_flow_aligned_time(r: f64) -> f64 {
    FRAC_PI_2 * (r * r + 1.0) / r
}

/// Time average of (p·e_y)² over Jeffery's orbit of [`jeffery_phi`], p the unit symmetry axis:
/// with tan φ = r tan τ and τ uniform in time, $\langle\cos^2\phi\rangle = \frac{2}{\pi}
/// \int_0^{\pi/2} \frac{d\tau}{1 + r^2\tan^2\tau} = \frac{1}{1 + r}$
/// (substitute s = tan τ and close the contour, or check r = 1: ½). Independent of γ̇, so it
/// also holds while the shear rate a particle sees drifts slowly.
pub fn jeffery_mean_gradient_alignment(r: f64) -> f64 {
    1.0 / (1.0 + r)
}

/// Jeffery-orbit average of the settling mobility e_y·K̂⁻¹e_y of a rigid spheroid whose
/// symmetry axis p tumbles in the flow–gradient plane: K̂⁻¹ = pp/K_a + (1 − pp)/K_t, so
/// $\langle e_y·\hat K^{-1} e_y\rangle = w/K_a + (1 − w)/K_t$ with w = 1/(1 + r) from
/// [`jeffery_mean_gradient_alignment`]. The flow-wise part of K̂⁻¹e_y, ∝ sin φ cos φ, is odd in
/// the orbit phase and averages to zero. `k_axial`, `k_transverse` are the principal
/// resistances (K̂ of Brenner 1963, dimensions of length).
pub fn jeffery_averaged_settling_mobility(r: f64, k_axial: f64, k_transverse: f64) -> f64 {
    let w = jeffery_mean_gradient_alignment(r);
    w / k_axial + (1.0 - w) / k_transverse
}

/// Hagen–Poiseuille flow u = 2Ū(1 − y²/R²) e_x of radius R and mean velocity Ū, crossed by a
/// particle settling along the radius from |y| = `from` to `to` at a speed V(|y|) while it moves
/// with the flow: the streamwise distance it travels is
/// $D = \int_{y_0}^{y_1} \frac{u(y)}{V(y)}\\,dy$
/// (dx/dt = u, d|y|/dt = V; the settling drift along the flow averages out over an orbit,
/// [`jeffery_averaged_settling_mobility`]). Composite 3-point Gauss–Legendre on `panels`
/// equal panels: exact for a constant V (u is quadratic), error O(panels⁻⁶) for smooth V.
pub fn poiseuille_settling_distance(
    radius: f64,
    mean_velocity: f64,
    from: f64,
    to: f64,
    speed: impl Fn(f64) -> f64,
    panels: usize,
) -> Result<f64, ParamError> {
    validate_settling_path(radius, mean_velocity, from, to)?;
    crate::error::positive("quadrature panels", panels as f64)?;
    // Gauss–Legendre nodes ±√(3/5), 0 with weights 5/9, 8/9 on [−1, 1].
    let node = (0.6f64).sqrt();
    let rule = [(-node, 5.0 / 9.0), (0.0, 8.0 / 9.0), (node, 5.0 / 9.0)];
    let h = (to - from) / panels as f64;
    let mut sum = 0.0;
    for k in 0..panels {
        let mid = from + (k as f64 + 0.5) * h;
        for (x, w) in rule {
            let y = mid + 0.5 * h * x;
            let u = 2.0 * mean_velocity * (1.0 - y * y / (radius * radius));
            sum += 0.5 * h * w * u / speed(y);
        }
    }
    crate::error::finite("settling distance (speed must be non-zero and finite)", sum)
}

/// [`poiseuille_settling_distance`] for a constant settling speed V, in closed form:
/// $D = \frac{2\bar U}{V}\Big[y - \frac{y^3}{3R^2}\Big]_{y_0}^{y_1}$.
pub fn poiseuille_settling_distance_uniform(
    radius: f64,
    mean_velocity: f64,
    from: f64,
    to: f64,
    speed: f64,
) -> Result<f64, ParamError> {
    validate_settling_path(radius, mean_velocity, from, to)?;
    let speed = crate::error::positive("settling speed", speed)?;
    let antiderivative = |y: f64| y - y * y * y / (3.0 * radius * radius);
    Ok(2.0 * mean_velocity / speed * (antiderivative(to) - antiderivative(from)))
}

/// R > 0, Ū finite and both ends of the settling path inside the pipe, 0 ≤ |y| ≤ R.
fn validate_settling_path(radius: f64, mean_velocity: f64, from: f64, to: f64) -> Result<(), ParamError> {
    crate::error::positive("pipe radius", radius)?;
    crate::error::finite("mean velocity", mean_velocity)?;
    for (name, y) in [("settling start |y|", from), ("settling end |y|", to)] {
        if !(0.0..=radius).contains(&y) {
            return Err(ParamError::OutOfRange {
                name,
                value: y,
                min: 0.0,
                max: radius,
            });
        }
    }
    Ok(())
}

/// Inertial deposition efficiency in one airway bifurcation, the empirical correlation of
/// Zhang, Asgharian & Anjilvel (Aerosol Sci. Technol. 26 (1997) 97–110), used by the paper's
/// Fig. 18 (its ref. \[45\]):
/// ```math
/// DE = \begin{cases} 0.000654\, e^{55.7\,Stk^{0.954}}\, Re^{1/3} \sin\theta & Stk < 0.04 \\
/// \big[0.19 − 0.193\, e^{−9.5\,Stk^{1.565}}\big]\, Re^{1/3} \sin\theta & Stk \ge 0.04 \end{cases}
/// ```
/// with Stk = ρ_p d² U/(18 μ_f D) and Re = U D/ν of the parent branch (U its mean velocity, D
/// its diameter) and θ the branching angle between the parent and a daughter axis (half the
/// angle between the daughters). The two branches meet at Stk = 0.04 within 1.4 %. The formula is
/// not clipped: it exceeds 1 for large Stk sin θ (e.g. θ = 60°, Stk ≳ 0.3 at Re = 500), which
/// says the correlation is used outside its range.
pub fn zhang_deposition_efficiency(stokes: f64, reynolds: f64, theta: f64) -> Result<f64, ParamError> {
    let stokes = crate::error::positive("Stokes number", stokes)?;
    let reynolds = crate::error::positive("Reynolds number", reynolds)?;
    if !(theta.is_finite() && theta > 0.0 && theta <= FRAC_PI_2) {
        return Err(ParamError::OutOfRange {
            name: "branching angle theta (rad)",
            value: theta,
            min: 0.0,
            max: FRAC_PI_2,
        });
    }
    let shape = if stokes < 0.04 {
        0.000654 * (55.7 * stokes.powf(0.954)).exp()
    } else {
        0.19 - 0.193 * (-9.5 * stokes.powf(1.565)).exp()
    };
    Ok(shape * reynolds.cbrt() * theta.sin())
}

/// Pich's (1972, J. Aerosol Sci. 3, 351–361) fraction of the particle flow deposited by
/// gravitational settling (speed v_s) from fully developed laminar flow (mean speed Ū) in a
/// horizontal circular tube of diameter d and length L, the particles entering uniformly
/// mixed (flux-weighted):
/// ```math
/// P = \frac{2}{\pi}\Big[2\varepsilon\sqrt{1 - \varepsilon^{2/3}} - \varepsilon^{1/3}\sqrt{1 - \varepsilon^{2/3}} + \arcsin\varepsilon^{1/3}\Big],
/// \qquad \varepsilon = \frac{3}{4}\frac{L}{d}\frac{v_s}{\bar U}
/// ```
/// (also Heyder & Gebhart 1977, eq. 5); P = 1 for ε ≥ 1, and P ≈ 16ε/(3π) for small ε (the
/// settling flux v_s over the projected wall 2RL against the particle flow πR²Ū).
pub fn pich_deposition(epsilon: f64) -> Result<f64, ParamError> {
    let epsilon = crate::error::positive("Pich's epsilon", epsilon)?;
    let c = epsilon.cbrt().min(1.0);
    let root = (1.0 - c * c).sqrt();
    Ok(2.0 / PI * (2.0 * epsilon.min(1.0) * root - c * root + c.asin()))
}

/// Inertial deposition efficiency of a bend of circular cross-section in laminar flow, the fit
/// of Pui, Romay-Novas & Liu (Aerosol Sci. Technol. 7 (1987) 301–315) to their Re = 1000
/// measurements (curvature ratio R_o/a = 5.6 and 5.7), which agree with the theory of Cheng &
/// Wang (Atmos. Environ. 15 (1981) 301–306):
/// ```math
/// DE = 1 − \Big[1 + \Big(\frac{Stk}{0.171}\Big)^{0.452\,Stk/0.171 + 2.242}\Big]^{−2θ/π}
/// ```
/// with Stk = ρ_p d² C_c U/(9 μ_f D) = τ_p U/a (τ_p = ρ_p d² C_c/(18 μ_f) the particle's
/// response time, U the mean velocity, D = 2a the tube diameter) and θ the bend angle
/// (0 < θ ≤ π; 90°: DE = y/(1 + y) with y the power above). DE(0.171) = ½ at θ = π/2.
pub fn pui_bend_deposition_efficiency(stokes: f64, theta: f64) -> Result<f64, ParamError> {
    let stokes = crate::error::positive("Stokes number", stokes)?;
    if !(theta.is_finite() && theta > 0.0 && theta <= PI) {
        return Err(ParamError::OutOfRange {
            name: "bend angle theta (rad)",
            value: theta,
            min: 0.0,
            max: PI,
        });
    }
    let x = stokes / 0.171;
    let y = x.powf(0.452 * x + 2.242);
    Ok(1.0 - (1.0 + y).powf(-2.0 * theta / PI))
}

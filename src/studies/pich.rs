//! Gravitational deposition from laminar flow in a horizontal pipe (Pich 1972), the exact
//! answer a mesh study of a *solved* flow must converge to (issue 58, item 2).
//!
//! The pipe of `cases/pich-solved` (radius R = 1, length L = 4, axis z; ν = 1, ρ_f = 1,
//! Ū = 1 from the Poiseuille pressure drop 8νŪL/R² = 32) carries point particles (radius
//! a = 0.01, ρ_s = 2, overdamped, point contact) injected at [`INLET_OFFSET`] inside the inlet
//! by the exact flow's flux (a disc weighted by Poiseuille's profile, so particle k starts at the
//! same point on every mesh and the study's paired errors see only the particles whose fate the
//! mesh changes; a point beyond a coarse mesh's faceted wall fails its particle), settling along −y at the Stokes speed $v_s = 2(\rho_s - \rho_f) g a^2/(9\mu)$. Pich's
//! parameter is $\varepsilon = \frac{3}{4}\frac{L}{d}\frac{v_s}{\bar U} = \frac{3 L v_s}{8 R \bar U}$,
//! so the scene sets g for a given ε, and the deposited fraction's limit under mesh refinement
//! is [`exact`]: [`crate::reference::pich_deposition`] over the tracked length L − δ.

/// Pipe radius R.
pub const RADIUS: f64 = 1.0;
/// Pipe length L.
pub const LENGTH: f64 = 4.0;
/// Mean speed Ū of the exact flow.
pub const MEAN_SPEED: f64 = 1.0;
/// Particle radius a.
pub const PARTICLE_RADIUS: f64 = 0.01;
/// Fluid viscosity μ = ρν (ν = 1, ρ_f = 1).
pub const VISCOSITY: f64 = 1.0;
/// ρ_s − ρ_f.
pub const DENSITY_EXCESS: f64 = 1.0;

/// How far inside the inlet the particles start, δ: off the inlet patch's plane, so a point
/// particle is not on a boundary face at t = 0. The tracked length is L − δ.
pub const INLET_OFFSET: f64 = 1e-3;

/// Pich's deposited fraction for the scene of parameter `epsilon` (defined on the whole length
/// L): the closed form at ε(L − δ)/L, the length the particles travel from [`INLET_OFFSET`].
pub fn exact(epsilon: f64) -> Result<f64, crate::error::ParamError> {
    crate::reference::pich_deposition(epsilon * (LENGTH - INLET_OFFSET) / LENGTH)
}

/// The gravity g that makes Pich's parameter ε: v_s = 8εRŪ/(3L), g = 9μ v_s/(2Δρ a²).
pub fn gravity(epsilon: f64) -> f64 {
    let settling = 8.0 * epsilon * RADIUS * MEAN_SPEED / (3.0 * LENGTH);
    9.0 * VISCOSITY * settling / (2.0 * DENSITY_EXCESS * PARTICLE_RADIUS * PARTICLE_RADIUS)
}

/// The study scene of `count` particles (seed `seed`) at Pich parameter `epsilon` on the
/// solved `cases` (folders as the scene should name them: relative to the scene file, or
/// absolute).
pub fn scene(cases: &[String], epsilon: f64, count: u64, seed: u64) -> String {
    let cases: Vec<String> = cases.iter().map(|c| format!("{c:?}")).collect();
    format!(
        r#"seed = {seed}
[flow]
type = "openfoam"
cases = [{cases}]
[fluid]
viscosity = {VISCOSITY:?}
density = 1.0
gravity = [0.0, {g:?}, 0.0]
[boundary]
type = "mesh"
contact_radius = 0.0
[particles]
density = {rho:?}
[particles.inject]
count = {count}
semi_axes = [{PARTICLE_RADIUS:?}, {PARTICLE_RADIUS:?}, {PARTICLE_RADIUS:?}]
region = {{ type = "disc", centre = [0.0, 0.0, {INLET_OFFSET:?}], normal = [0.0, 0.0, 1.0], radius = {RADIUS:?}, weight = "poiseuille" }}
material = {{ law = "rigid" }}
[integrator]
type = "radau_iia"
overdamped = true
tol = 1e-7
dt = 1e-3
[end]
t_end = {t_end:?}
[output]
vtk = false
adequacy_sample = 0
"#,
        cases = cases.join(", "),
        g = -gravity(epsilon),
        rho = 1.0 + DENSITY_EXCESS,
        t_end = 50.0 * LENGTH / MEAN_SPEED,
    )
}

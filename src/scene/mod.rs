//! The scene-file language: a TOML file that describes a whole run (flow, fluid, boundary,
//! particles, integrator, end, output), read and validated here and run by
//! [`run::run_on`]; the `pseudorigid` command ([`crate::cli`]) and the Python package are its
//! two front ends. Example scenes are in `scenes/` at the top of the repository.
//!
//! From a scene file to library objects. Every value goes through the constructor of the
//! type it becomes (`Plan::new`, `NeoHooke::new`, `Ellipsoid::new`, `Stokesian::new`, ...),
//! and a value it refuses is reported at its line and column with its dotted key.
//!
//! # Keys
//! Every table refuses unknown keys. Units are the caller's (any consistent set).
//!
//! | key | meaning |
//! |---|---|
//! | `seed` | run seed (default 0); injected particle k draws from stream k of it |
//! | `[flow] type` | `quiescent`, `shear`, `planar_extension`, `uniaxial_extension`, `poiseuille`, `openfoam` |
//! | `flow.rate` | γ̇ or ε̇ of the linear flows |
//! | `flow.radius`, `flow.mean_velocity` | Poiseuille pipe along e₁: R and Ū (centreline 2Ū) |
//! | `flow.case`, `flow.time` | OpenFOAM case folder (relative to the scene file; an absolute path or one climbing with `..` is read as given: the command reads what the scene names, and writes nothing but under `--out`; every patch with faces must be of type `wall`, `patch`, `empty` or `processor`: a case with a `cyclic`, `wedge`, `symmetry`, ... patch is refused with the patch named, as not yet a particle boundary; in a 2-D case, every `empty` face normal to one axis, each particle's barycentre is held in its plane: `driver::Plan::with_hold`) and time: a number or `"latest"` (the default), a steady field (one that is zero in every cell is refused unless `flow.still = true`); a list of times or a range `{ start, end, period }`, a transient field (see *Transient fields*) |
//! | `flow.cases` | instead of `flow.case`: two to four OpenFOAM cases of one geometry, a mesh study (`pseudorigid study`, [`study`]): the scene runs on each with the same seed, and every outcome's fraction is reported per mesh with the GCI of the finest |
//! | `flow.precision`, `flow.window` | transient fields only: `"f64"` (default) or `"f32"` storage of the levels; the length of the run's time windows (default: the smallest spacing of the levels) |
//! | `flow.still` | `openfoam` only: `true` reads a case whose U is zero in every cell as still fluid (settling in a closed box, particles thrown into still air), and refuses one whose U is not; default `false`, where a zero field is refused as a likely initial condition |
//! | `flow.blend` | `true` (default): the continuous field with the second-order no-slip wall layer (`flow::openfoam::BlendedFlow`); `false`: each cell's linear fit (discontinuous at faces, no wall-normal velocity near walls) |
//! | `[fluid] viscosity`, `density`, `gravity` | μ_f, ρ_f, g (default 0) |
//! | `[boundary] type` | `pipe` (needs `radius`), `planes` (needs `[[boundary.walls]]`), `mesh` (the case's patches) |
//! | `boundary.walls` | `name`, `point`, `normal` (outward), `rule` = `stick` or `exit` |
//! | `boundary.contact_radius` | touch at this distance from the barycentre, ≥ 0 (0: point contact; default: the particle's extent touches) |
//! | `[particles] density`, `drag`, `volumetric` | ρ_s of every entry and group that gives no `density` of its own; a registered drag model (`crate::hydro::drag`): `brenner` (default) or `stokes_sphere`, or a table `{ model = "…", … }` for a model with parameters; the volumetric traction `paper` (default, the literal eq. 12), `dev` or `source` (needed by `imex_adaptive` at tight tolerances: the literal eq. 12 anti-damps dilation) |
//! | `[particles] forces` | force terms beyond the paper's drag and reduced gravity, by name (`crate::hydro::forces`): `undisturbed_flow`, `added_mass` (Lamb's ellipsoid tensor), `schiller_naumann` and `saffman_mei` (spheres only), `holzer_sommerfeld` (finite-Re drag of any ellipsoid), or a table such as `{ term = "cunningham", mean_free_path = 6.65e-8 }` (λ in m; 66.5 nm for air at 20 °C, 1 atm); default none, the paper's model |
//! | `[[particles.list]]` | `density` (default `particles.density`), `semi_axes`, `position`, `orientation = { axis, angle }` (radians), `velocity` or `fluid_velocity = true`, `material` |
//! | `[particles.inject]` or several `[[particles.inject]]` groups | `count`, `density` (default `particles.density`), `region` (`{ type = "point", at }`, `{ type = "disc", centre, normal, radius, weight }` with `weight = "area"` (default) or `"poiseuille"` (by the flux of fully developed laminar pipe flow of that radius: the same point for particle k on every mesh of a study; a point drawn outside the mesh fails its particle) or `{ type = "patch", name }`: on an OpenFOAM patch weighted by the inflow through each face (the case's face flux `phi` where the steady field's time directory has it, else the cell fits' −u·S), moved inside by the particle's largest semi-axis, or by `boundary.contact_radius` if that is larger), `semi_axes`, `orientation` or `random_orientation = true`, `fluid_velocity`, `material`; group g's particles follow those of groups 0..g in the index, and particle k draws from stream k whichever group it is in |
//! | `material` | a registered law (`crate::material::registry`) and its parameters: `{ law = "neo_hooke", mu, lambda }`, `{ law = "mooney_rivlin", mu1, mu2, lambda }`, `{ law = "rigid" }`, or a law written in the scene: `{ law = "expression", energy = "…", parameters = { name = value, … } }` with W(I1, I2, J) in `+ - * / ^ ( )`, `ln`, `exp`, `sqrt` (`material::expression`; μ_s and λ_s are read off its tangent at F = 1; `scenes/yeoh_oblate.toml`) |
//! | `[integrator] type` | a registered integrator (`crate::integrator::registry`): `imex` (the paper's, fixed `dt`; also `imex_paper`), `imex_adaptive`, `radau_iia` (inertialess, Radau IIA of order 5: the library's `Stokesian` default), `rosenbrock_w23` (inertialess, the Rosenbrock-W 2(3) pair), `auto` (chosen per particle from its Stokes number and the tolerance, `crate::integrator::choice`; the choice per injection group is printed as a `note:` line), `slow_manifold` (stiff elastic particles on their slow manifold, `crate::integrator::manifold`, with an optional `delta_max` in (0, 1), default √tol) (all five need `tol`); earlier scene files' `stokesian` and `stokesian_radau5` are read as `radau_iia`, `stokesian_rosenbrock23` as `rosenbrock_w23` |
//! | `integrator.dt`, `dt_max`, `overdamped` | first (or fixed) step (required, except for `auto`, whose default first step is 10⁻⁶ `end.t_end`: `timing::AUTO_FIRST_STEP`), largest step, overdamped barycentre (`radau_iia`, `rosenbrock_w23`) |
//! | `integrator.frame` | the frame of `rosenbrock_w23`'s step of an elastic particle: `"lab"` (the default) or `"body"` (turning with the particle's spin, det F held: `crate::integrator::body_frame`; fewer steps for stiff particles, more for soft ones); refused by the other integrators |
//! | `integrator.norm` | how the local error is measured (`radau_iia`, `rosenbrock_w23`, `auto`): `"componentwise"` (the default) or `"tensor"`, F, x and v each by its norm, independent of the frame's orientation (`crate::integrator::ErrorNorm`; cost against accuracy on the bifurcation: `paper-figures/work-precision/NOTES.md`) |
//! | `[end] t_end`, `max_steps` | end time of every particle's run; accepted steps allowed per particle |
//! | `[output] every`, `vtk` | output interval (default: the end only); write ParaView files (default true) |
//! | `output.adequacy_sample` | particles of the mesh-adequacy diagnostic's first look (`scene::adequacy`; the sample doubles while no difference shows, until a shift of 0.01 is bounded or the run's own steps are spent): the first min(N, n) by index run again on the other reconstruction of the field (cellwise for a blended run, blended for `flow.blend = false`) and paired with the run; default 200 on a steady OpenFOAM field, 0 (none) elsewhere; refused above 0 on an analytic flow and on a transient field |
//!
//! # Transient fields
//! `flow.time = [t0, t1, ...]` (times of the case's time directories, ascending, at least two)
//! or `flow.time = { start = .., end = .., period = .. }` (the case's time directories in
//! [start, end], by default its first and last, the first often `0`, the initial condition;
//! at least two) reads a transient field:
//! linear in time between the levels, before the first level and after the last the field
//! holds that level. With `period` the levels repeat with that period (a breathing cycle):
//! give the levels of one period, e.g. `{ start = 1, end = 1.5, period = 0.5 }` for the second
//! period of a solution written to t = 1.5; a level at start + period is the next cycle's first
//! and is not read. Particle time is the case's time: every particle starts at t = 0 (so with
//! levels from t = 1 on, a non-periodic field holds its first level until t = 1, while a
//! periodic one maps t = 0 onto the cycle) and runs to `end.t_end`.
//!
//! The field is read lazily (`flow::openfoam::TransientFlow`): it holds the levels of one
//! window of time, and the run (`population::batch::run_batch`) advances every live particle
//! to the window's end before the window slides. `flow.window` is the window's length; the
//! default, the smallest spacing of the levels (the wrap from the last level to the next
//! cycle's first included), holds at most three levels at a time whatever their number. A
//! longer window holds more levels at once; a shorter one costs each particle one more landing
//! step per window. On the oscillating cavity (`cases/oscillating-cavity/scene.toml`, 300
//! tracers, four periods of 200 levels) windows of 0.0025 s (the default), 0.01 s and 0.05 s
//! took 385 k, 489 k and 309 k steps and ended within 2.6 µm of each other (tolerance 10⁻⁶,
//! a 0.1 m cavity); the steps per second were within 5 % of the steady runner's on one level
//! (one run each, on a loaded machine). Fates are those of a run holding every level; positions differ by the
//! step control's tolerance (only the steps landing on the window ends differ). Checkpoints
//! are written at window ends and hold the particles finished by then: a killed run resumes
//! with those and runs the others again from the start (the same records, bit for bit, as a
//! run not killed). In a closed domain (a cavity), where most particles live to `t_end`, a
//! kill therefore costs nearly the whole run: split long runs into shards instead. Progress counts finished particles plus those in flight weighted by the share of
//! the time run so far. `flow.precision = "f32"` stores the levels in single precision (half
//! the memory, a relative error below 2⁻²⁴ per component). Injection sees the field at t = 0:
//! a `patch` region is weighted by the inflow of the level at or before t = 0 (a patch with no
//! inflow then, such as an inlet at the start of a sinusoidal cycle, is refused), and
//! `fluid_velocity` samples u(x, 0).
//!
//! # Mesh adequacy
//! Every run on an OpenFOAM field prints `note: adequacy:` lines (`scene::adequacy`): the
//! first-cell height 2ρ at the walls (median and max over the no-slip wall faces) against each
//! injection group's largest semi-axis and stopping distance τ_p·U (τ_p the response time of
//! the `auto` integrator's Stokes number, U the field's largest cell speed), with what the
//! ratios mean (both below 1: the particles' deposition is decided inside the wall layer,
//! which models the flow there rather than resolving it). A whole run on a steady field then
//! re-tracks the first `output.adequacy_sample` particles on the other reconstruction of the
//! same solution and pairs their fates with the run's (McNemar's paired difference of the
//! deposition fractions and its standard error), doubling the sample while nothing shows until
//! it could detect a shift of 0.01 or its budget (the run's own steps) ends; a
//! `warning: adequacy:` line says when the deposition moves by more than the warning bound
//! (two paired standard errors for one look, Bonferroni's over several): the near-wall
//! resolution, not the particles, sets the answer. The log gives the smallest shift the
//! sample could detect. The numbers and every pair go to `adequacy.json`. The
//! re-track runs after the run from its records: records, tables, checkpoints and `--resume`
//! are unchanged by it. A shard prints the ratios only; `merge` re-tracks the whole run's first
//! particles (the same sample however the run was split). A transient field gets the ratios
//! only.
//!
//! A particle's run ends at `t_end` (*suspended*), when it touches a `stick` wall
//! (*deposited*) or an `exit` (*escaped*), or when a step fails (*failed*, with the error).
//!
//! # Output (in `--out DIR`)
//! Every result is written once. `checkpoint-<k>-of-<N>/` holds the records of shard k of N
//! (the whole run: `checkpoint-0000-of-0001/`) as sealed, gzipped JSON chunks, every f64 exact: after a
//! kill, `run --resume` continues and gives bitwise the results of an uninterrupted run, and
//! `merge` reads the shards' checkpoints. With the feature `parquet` the tables are
//! `records.parquet` (one row per particle) and `frames.parquet` (`scene::parquet`); a shard writes
//! `records/part-<k>-of-<N>.parquet` and `frames/part-<k>-of-<N>.parquet`, so each folder
//! reads as one dataset. CSV tables (`results.csv`, one row per particle with its spec's injection point, rest
//! semi-axes, μ_s and ρ_s, `frames.csv`,
//! `trajectories.csv`; a shard's `results-<k>-of-<N>.csv`) are written with `--csv`, and
//! always without the feature `parquet`. With `vtk` (the default), `particles.pvd` with
//! `vtk/particles_NNNNNN.vtp` (one per output time: the particles with `V` = √(F̄F̄ᵀ) for
//! ParaView's Tensor Glyph, `r1`..`r3`, `id`, `flag` 0 moving, 1 deposited, 2 escaped, 3
//! suspended, 4 failed) and `vtk/trajectories.vtp` (polylines), binary (appended, zlib) in
//! single precision, as `foamToVTK` writes (the exact values are in the tables). `--shard k/N`
//! (or `SLURM_ARRAY_TASK_ID`/`SLURM_ARRAY_TASK_COUNT`) runs one shard; `merge` joins the shards
//! into the files of the whole run. `adequacy.json` (a run on an OpenFOAM field; *Mesh
//! adequacy*) is written by a whole run and by `merge`.

pub mod adequacy;
mod carrier;
pub mod error;
pub mod frames;
pub mod inject;
pub mod models;
#[cfg(feature = "parquet")]
pub mod parquet;
mod particles;
pub mod run;
pub mod schema;
pub mod study;
mod timing;

pub use error::{SceneError, Source};

use crate::contact::MeshBoundary;
use crate::contact::{ContactModel, PatchRule, PipeWall, Plane, Planes};
use crate::driver::{Budget, Plan};
use crate::ellipsoid::Ellipsoid;
use crate::error::ParamError;
use crate::flow::FlowField;
use crate::flow::analytic::{LinearFlow, Poiseuille};
use crate::flow::openfoam::{
    BlendedFlow, Cycle, FoamCase, FoamFlow, Precision, TransientFlow, check_particle_patches, slab_axis,
};
use crate::hydro::drag::NamedDrag;
use crate::hydro::{ForceTerms, VolumetricTraction, drag, forces};
use crate::integrator::SceneIntegrator;
use crate::material::NamedLaw;
use crate::material::{self, Softness};
use crate::particle::Fluid;
use crate::population::ParticleTemplate;
use crate::registry::{Value, Values};
use crate::scene::inject::{Group, ParticleSource, Placement, SceneInjector, Velocity};
use crate::scene::models::{SceneBoundary, SceneFlow, SceneTransient, TransientField};
use crate::scene::schema::*;
use crate::tensor::{Mat3, Vec3};
use nalgebra::{Rotation3, Unit};
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::Path;
use std::sync::Arc;
use toml::Spanned;

/// Particles the mesh-adequacy diagnostic ([`crate::scene::adequacy`]) re-tracks first by
/// default (`output.adequacy_sample`; the sample then doubles while nothing is resolved): the paired standard error of a deposition fraction near f over
/// n pairs is at most √(f(1 − f)·2/n), 0.07 at f = 0.5 and n = 200, so a shift of a tenth of
/// the particles' fates is seen; 200 particles cost a fifth of the TJunction tutorial's
/// 1 000-tracer run. Here, with the key it defaults, so that the diagnostic imports the scene
/// and not the reverse.
pub const DEFAULT_SAMPLE: u64 = 200;

/// Output times allowed per particle: beyond this a run is a time series of one particle,
/// better written by a program than by the command.
pub const MAX_OUTPUTS: u64 = 100_000;
/// States kept in memory over all particles and output times (each state is 200 bytes, so
/// this is 400 MB).
pub const MAX_SAMPLES: u64 = 2_000_000;
/// Particles allowed in one scene (the population runner's results hold one record each).
pub const MAX_PARTICLES: u64 = 100_000_000;
/// Time windows allowed in a run on a transient field (each is a pass over the live particles
/// and a checkpoint).
pub const MAX_WINDOWS: u64 = 1_000_000;
/// Steps allowed per particle unless `end.max_steps` says otherwise.
pub const DEFAULT_MAX_STEPS: u64 = 10_000_000;

/// What a model's parameter may be, as an error says it.
const VALUE_KINDS: &str = "must be a number, true or false, text, or a table of numbers";

/// A parameter as the registries take it; `None` for what no model takes (arrays, dates,
/// tables of non-numbers).
fn to_value(v: &toml::Value) -> Option<Value> {
    match v {
        toml::Value::Float(x) => Some(Value::Number(*x)),
        // TOML integers are numbers too (`lambda = 50`); beyond 2⁵³ they round, as in any f64.
        toml::Value::Integer(i) => Some(Value::Number(*i as f64)),
        toml::Value::Boolean(b) => Some(Value::Flag(*b)),
        toml::Value::String(s) => Some(Value::Text(s.clone())),
        toml::Value::Table(t) => t
            .iter()
            .map(|(k, v)| match v {
                toml::Value::Float(x) => Some((k.clone(), *x)),
                toml::Value::Integer(i) => Some((k.clone(), *i as f64)),
                _ => None,
            })
            .collect::<Option<BTreeMap<String, f64>>>()
            .map(Value::Table),
        toml::Value::Array(_) | toml::Value::Datetime(_) => None,
    }
}

/// A model's table split into its name and its parameters, with where each is written.
struct ModelKeys {
    /// Dotted key of the table (`particles.list[0].material`).
    prefix: String,
    /// The key of the name (`law`, `type`).
    name_key: &'static str,
    /// The model's name.
    name: String,
    /// Where the name is written.
    at: Range<usize>,
    /// The parameters.
    values: Values,
    /// Where each parameter is written.
    spans: BTreeMap<String, Range<usize>>,
}

/// A validated scene: everything a run needs.
#[derive(Debug)]
pub struct Scene {
    /// Run seed.
    pub seed: u64,
    /// Carrier flow.
    pub flow: SceneFlow,
    /// Walls and exits.
    pub boundary: SceneBoundary,
    /// Extent or point contact.
    pub contact: ContactModel,
    /// What the particles share.
    pub template: ParticleTemplate<NamedDrag>,
    /// The particles.
    pub particles: ParticleSource,
    /// Time integrator.
    pub integrator: SceneIntegrator,
    /// End time, first step, step cap and budget, output times.
    pub plan: Plan,
    /// Output times (ascending, the last one t_end).
    pub outputs: Vec<f64>,
    /// Write ParaView files.
    pub vtk: bool,
    /// Particles the mesh-adequacy diagnostic re-tracks on the other reconstruction of the
    /// field (`output.adequacy_sample`, [`crate::scene::adequacy`]); 0: none.
    pub adequacy_sample: u64,
    /// The scene text (the run's fingerprint for checkpoints and shards).
    pub text: String,
}

impl Scene {
    /// Number of particles.
    pub fn count(&self) -> u64 {
        self.particles.count()
    }

    /// The injection rule over this scene's flow.
    pub fn injector(&self) -> SceneInjector<'_> {
        SceneInjector::new(&self.template, &self.particles, &self.flow)
    }

    /// The population case of a steady run of this scene with `injector` ([`Self::injector`]):
    /// its integrator, flow, boundary, plan and contact model (the run adds the samples, the
    /// adequacy re-track does not).
    pub fn case<'a>(
        &'a self,
        injector: &'a SceneInjector<'a>,
    ) -> crate::population::Case<'a, SceneIntegrator, SceneFlow, SceneBoundary, SceneInjector<'a>> {
        crate::population::Case::new(
            &self.integrator,
            &self.flow,
            &self.boundary,
            injector,
            self.plan.clone(),
        )
        .with_contact(self.contact)
    }

    /// Each list entry and injection group with its scene-file key.
    pub(crate) fn placements(&self) -> Vec<(String, &Placement)> {
        match &self.particles {
            ParticleSource::List(list) => list
                .iter()
                .enumerate()
                .map(|(i, p)| (format!("particles.list[{i}]"), p))
                .collect(),
            ParticleSource::Inject(groups) => groups
                .iter()
                .enumerate()
                .map(|(g, group)| (format!("particles.inject[{g}]"), &group.placement))
                .collect(),
        }
    }

    /// What the integrator does for each list entry and injection group, where that depends
    /// on the particle (`type = "auto"`, [`crate::integrator::choice::Auto`]): one line per
    /// choice, for the run log (`grouped`: entries with the same numbers share a line).
    pub fn integrator_log(&self) -> Vec<String> {
        grouped(
            self.placements()
                .into_iter()
                .filter_map(|(key, placement)| {
                    let particle = self.template.build(&placement.spec(Vec3::zeros())).ok()?;
                    let what = self.integrator.describe(&particle, &self.flow)?;
                    Some((key, format!("integrator {}: {what}", self.integrator.name())))
                })
                .collect(),
        )
    }

    /// Integrator choices the particles contradict: an overdamped barycentre
    /// (`integrator.overdamped`) for particles whose Stokes number
    /// ([`crate::integrator::choice::ParticleNumbers`], the automatic choice's) is above
    /// [`EQUILIBRIUM_STOKES`](crate::integrator::choice::EQUILIBRIUM_STOKES). Above it even the
    /// equilibrium barycentre, first order in St, loses deposits to the O(St²) terms it drops;
    /// the overdamped one drops the O(St) slip as well, so it is further off. A flow without a
    /// time scale (St = ∞: a quiescent fluid) says nothing about it and is not warned about.
    /// One line per list entry and injection group (`grouped`).
    pub fn integrator_advice(&self) -> Vec<String> {
        use crate::integrator::choice::{EQUILIBRIUM_STOKES, ParticleNumbers};
        if self.integrator.barycentre() != crate::integrator::BarycentreModel::Overdamped {
            return Vec::new();
        }
        grouped(
            self.placements()
                .into_iter()
                .filter_map(|(key, placement)| {
                    let particle = self.template.build(&placement.spec(Vec3::zeros())).ok()?;
                    let stokes = ParticleNumbers::of(&particle, &self.flow).ok()?.stokes;
                    (stokes.is_finite() && stokes > EQUILIBRIUM_STOKES).then(|| {
                        (
                            key,
                            format!(
                                "`integrator.overdamped` = true drops the particles' inertia, but their Stokes number \
                                 St = {stokes:.3e} > {EQUILIBRIUM_STOKES} says it matters (above {EQUILIBRIUM_STOKES} \
                                 even the first-order equilibrium barycentre misses deposits); use \
                                 `overdamped = false` or `type = \"auto\"`"
                            ),
                        )
                    })
                })
                .collect(),
        )
    }

    /// Force terms the scene leaves out although its numbers say they matter, before any
    /// run: for each list entry and injection group, what each registered term's estimate
    /// says from the particle and the fluid alone ([`crate::diagnostics::omitted_before_run`]:
    /// added mass from ρ_f/ρ_p, gas slip from d_eq and the mean free path, the
    /// undisturbed-flow force's bound ρ_f/ρ_p, its size where gravity and the flow's
    /// acceleration are comparable), above 1 %, in the registry's order. One line
    /// per kind and term (`grouped`: entries with the same numbers share a line); the run's
    /// own numbers (Re, shear, the flow's acceleration) are in the validity monitor of the
    /// library's scenes.
    ///
    /// An overdamped barycentre (`integrator.overdamped`) drops the particle's inertia by
    /// assumption; the fluid-inertia terms are of the same order (slip ∝ τ(ρ_p − ρ_f)Du/Dt in
    /// Maxey & Riley's small-Stokes expansion), so such a scene is not warned about
    /// `undisturbed_flow` and `added_mass` (it is refused with them,
    /// [`crate::integrator::BarycentreModel::admits`]), only about the terms that survive
    /// that limit.
    pub fn force_advice(&self) -> Vec<String> {
        let limit = crate::diagnostics::Thresholds::default().omitted_term;
        let overdamped = self.integrator.barycentre() == crate::integrator::BarycentreModel::Overdamped;
        let inertial = crate::hydro::forces::FLUID_INERTIA;
        let mut advice = Vec::new();
        for (key, placement) in self.placements() {
            let Ok(particle) = self.template.build(&placement.spec(Vec3::zeros())) else {
                continue;
            };
            let omitted = crate::diagnostics::omitted_before_run(&particle);
            for (term, size) in omitted
                .sizes()
                .filter(|&(term, size)| size > limit && !(overdamped && inertial.contains(&term)))
            {
                advice.push((
                    key.clone(),
                    format!(
                        "the scene leaves out `{term}`, which its numbers put at {:.2} % (add it to particles.forces)",
                        100.0 * size
                    ),
                ));
            }
        }
        grouped(advice)
    }
}

/// `key: message` lines with the lines of one message joined: the first key names them, with
/// the count of the others (`particles.list[0] and 299 other entries: ...`), so a list of 300
/// like particles gives one line where it gave 300. In the order of each message's first key.
pub(crate) fn grouped(lines: Vec<(String, String)>) -> Vec<String> {
    let mut groups: Vec<(String, String, usize)> = Vec::new();
    for (key, message) in lines {
        match groups.iter_mut().find(|(_, m, _)| *m == message) {
            Some((_, _, count)) => *count += 1,
            None => groups.push((key, message, 1)),
        }
    }
    groups
        .into_iter()
        .map(|(key, message, count)| match count {
            1 => format!("{key}: {message}"),
            2 => format!("{key} and 1 other entry: {message}"),
            n => format!("{key} and {} other entries: {message}", n - 1),
        })
        .collect()
}

/// Read and validate the scene file at `path`.
pub fn load(path: &Path) -> Result<Scene, SceneError> {
    let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let file = path.display().to_string();
    let base = path.parent().unwrap_or(Path::new("."));
    parse(
        &Source {
            file: &file,
            text: &text,
        },
        base,
    )
}

/// Read and validate the mesh study at `path`: a scene whose `flow.cases` names two to four
/// OpenFOAM cases of one geometry; one scene per case, in the order given, each the scene with
/// `flow.case` set to that case (the same seed, particles and integrator on every mesh).
pub fn load_study(path: &Path) -> Result<Vec<(String, Scene)>, SceneError> {
    let text = std::fs::read_to_string(path).map_err(|source| SceneError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let file = path.display().to_string();
    let src = Source {
        file: &file,
        text: &text,
    };
    let base = path.parent().unwrap_or(Path::new("."));
    let raw: Document = toml::from_str(&text).map_err(|e| src.parse_error(&e))?;
    let at = raw.flow.kind.span();
    let Some(cases) = raw.flow.cases.as_ref() else {
        return Err(src.error(at, "flow.cases", "a mesh study names its meshes' cases in `flow.cases`"));
    };
    if let Some(case) = &raw.flow.case {
        return Err(src.error(case.span(), "flow.case", "give `flow.case` or `flow.cases`, not both"));
    }
    if !(2..=4).contains(&cases.get_ref().len()) {
        return Err(src.error(
            cases.span(),
            "flow.cases",
            format!("{} cases: a mesh study takes two to four", cases.get_ref().len()),
        ));
    }
    cases
        .get_ref()
        .iter()
        .map(|case| {
            // Each scene from its own parse of the text, its case in place of the list.
            let mut one: Document = toml::from_str(&text).map_err(|e| src.parse_error(&e))?;
            one.flow.cases = None;
            one.flow.case = Some(case.clone());
            let scene = Builder {
                src: &src,
                boundary_flux: std::cell::OnceCell::new(),
            }
            .scene(one, base)?;
            Ok((case.get_ref().clone(), scene))
        })
        .collect()
}

/// Validate a scene's text; relative paths in it are relative to `base`.
pub fn parse(src: &Source<'_>, base: &Path) -> Result<Scene, SceneError> {
    let raw: Document = toml::from_str(src.text).map_err(|e| src.parse_error(&e))?;
    Builder {
        src,
        boundary_flux: std::cell::OnceCell::new(),
    }
    .scene(raw, base)
}

struct Builder<'a> {
    src: &'a Source<'a>,
    /// A steady OpenFOAM field's face flux `phi` on the boundary faces at its first time, where
    /// the case has one ([`FoamCase::read_boundary_flux`]): the inflow a `patch` injection
    /// region is weighted by.
    boundary_flux: std::cell::OnceCell<Vec<f64>>,
}

impl Builder<'_> {
    fn err(&self, span: Range<usize>, key: &str, message: impl Into<String>) -> SceneError {
        self.src.error(span, key, message)
    }

    /// A library constructor's refusal, reported at `span` for `key`.
    fn param(&self, span: Range<usize>, key: &str, e: ParamError) -> SceneError {
        self.err(span, key, e.to_string())
    }

    fn finite(&self, v: &Num, key: &str) -> Result<f64, SceneError> {
        let x = *v.get_ref();
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.err(v.span(), key, format!("must be a finite number, got {x}")))
        }
    }

    fn positive(&self, v: &Num, key: &str) -> Result<f64, SceneError> {
        let x = self.finite(v, key)?;
        if x > 0.0 {
            Ok(x)
        } else {
            Err(self.err(v.span(), key, format!("must be > 0, got {x}")))
        }
    }

    fn vec3(&self, v: &Num3, key: &str) -> Result<Vec3, SceneError> {
        let a = v.get_ref().0;
        match a.iter().position(|c| !c.is_finite()) {
            Some(i) => Err(self.err(
                v.span(),
                key,
                format!("component {} must be finite, got {}", i + 1, a[i]),
            )),
            None => Ok(Vec3::from(a)),
        }
    }

    fn scene(&self, raw: Document, base: &Path) -> Result<Scene, SceneError> {
        let flow = self.flow(&raw.flow, base)?;
        let boundary = self.boundary(raw.boundary.as_ref(), &flow)?;
        let contact = match raw.boundary.as_ref().and_then(|b| b.contact_radius.as_ref()) {
            Some(r) => ContactModel::Barycentre {
                radius: match self.finite(r, "boundary.contact_radius")? {
                    radius if radius >= 0.0 => radius,
                    radius => {
                        return Err(self.err(
                            r.span(),
                            "boundary.contact_radius",
                            format!("must be >= 0 (0: point contact), got {radius}"),
                        ));
                    }
                },
            },
            None => ContactModel::Extent,
        };
        if let SceneFlow::Transient(field) = &flow {
            self.first_window(field, &raw)?;
        }
        let forces = self.forces(&raw.particles.get_ref().forces)?;
        let template = self.template(&raw.fluid, raw.particles.get_ref(), forces.clone())?;
        // How far from its barycentre a particle touches a wall when it is not its extent:
        // injection through a patch starts particles beyond it.
        let contact_radius = match contact {
            ContactModel::Barycentre { radius } => radius,
            ContactModel::Extent => 0.0,
        };
        let particles = self.particles(&raw.particles, &template, &flow, contact_radius)?;
        let (integrator, dt, dt_max) = self.integrator(&raw.integrator)?;
        self.barycentre_admits(&integrator, &forces, &raw.integrator)?;
        let (mut plan, outputs) = self.plan(dt.as_ref(), dt_max.as_ref(), &raw.end, &raw.output, particles.count())?;
        // A 2-D case: its particles are held in their plane, as OpenFOAM's tracker holds them.
        if let Some(axis) = flow.with_cellwise(|c| c.and_then(|c| slab_axis(c.mesh()))) {
            plan = plan
                .with_hold(axis)
                .map_err(|e| self.param(raw.flow.kind.span(), "flow.case", e))?;
        }
        let adequacy_sample = self.adequacy_sample(&raw.output, &flow)?;
        Ok(Scene {
            seed: raw.seed,
            flow,
            boundary,
            contact,
            template,
            particles,
            integrator,
            plan,
            outputs,
            vtk: raw.output.vtk.unwrap_or(true),
            adequacy_sample,
            text: self.src.text.to_string(),
        })
    }

    /// `output.adequacy_sample`: the particles the mesh-adequacy diagnostic re-tracks
    /// ([`crate::scene::adequacy`]), by default [`DEFAULT_SAMPLE`] on a steady
    /// OpenFOAM field and none elsewhere. A positive value is refused on an analytic flow (no
    /// mesh, no wall layer) and on a transient field (the re-track is not implemented there).
    fn adequacy_sample(&self, output: &OutputSpec, flow: &SceneFlow) -> Result<u64, SceneError> {
        let steady_foam = matches!(flow, SceneFlow::Foam(_) | SceneFlow::Blended(_));
        let Some(sample) = &output.adequacy_sample else {
            return Ok(if steady_foam { DEFAULT_SAMPLE } else { 0 });
        };
        let n = *sample.get_ref();
        match flow {
            _ if n == 0 || steady_foam => Ok(n),
            SceneFlow::Transient(_) => Err(self.err(
                sample.span(),
                "output.adequacy_sample",
                format!("got {n}: the re-track is not implemented on a transient field; give 0 (the adequacy line is printed all the same)"),
            )),
            _ => Err(self.err(
                sample.span(),
                "output.adequacy_sample",
                format!("got {n}: an analytic flow has no mesh and no wall layer to re-track on; needs `flow.type = \"openfoam\"` (or 0)"),
            )),
        }
    }

    /// The integrator's barycentre model takes the particles' force terms
    /// ([`crate::integrator::BarycentreModel::admits`], which every step checks too): refused
    /// at `integrator.overdamped`, naming the force term's key as well.
    fn barycentre_admits(
        &self,
        integrator: &SceneIntegrator,
        forces: &ForceTerms,
        table: &ModelTable,
    ) -> Result<(), SceneError> {
        let Err(e) = integrator.barycentre().admits(forces) else {
            return Ok(());
        };
        let at = table.get_ref().get("overdamped").map_or(table.span(), |v| v.span());
        let term = match &e {
            ParamError::OverdampedFluidInertia { term } => forces.names().iter().position(|n| n == term),
            _ => None,
        };
        let key = match term {
            Some(i) => format!("integrator.overdamped, particles.forces[{i}]"),
            None => "integrator.overdamped, particles.forces".to_string(),
        };
        Err(self.param(at, &key, e))
    }

    /// A transient field's windows to `end.t_end` are at most [`MAX_WINDOWS`], and the field
    /// holds the first: the injection (a patch's inflow, the fluid's velocity) sees the field
    /// at t = 0.
    fn first_window(&self, field: &SceneTransient, raw: &Document) -> Result<(), SceneError> {
        let t_end = self.positive(&raw.end.t_end, "end.t_end")?;
        let (span, key) = match (&raw.flow.window, &raw.flow.time) {
            (Some(w), _) => (w.span(), "flow.window"),
            (None, Some(t)) => (t.span(), "flow.time"),
            (None, None) => (raw.flow.kind.span(), "flow.type"),
        };
        let windows = t_end / field.window();
        if windows > MAX_WINDOWS as f64 {
            return Err(self.err(
                span,
                key,
                format!(
                    "t_end / window = {t_end} / {} = {windows:e} windows; at most {MAX_WINDOWS}",
                    field.window()
                ),
            ));
        }
        let ends = field.window_ends(t_end);
        // A transient field always has `flow.time`; its levels are what a slide reads.
        let (span, key) = raw.flow.time.as_ref().map_or((span, key), |t| (t.span(), "flow.time"));
        field
            .slide(ends[0], ends[1])
            .map_err(|e| self.err(span, key, e.to_string()))
    }

    /// `value`, which the chosen kind (`kind` at `at`) needs.
    fn need<'v, T>(
        &self,
        value: &'v Option<Spanned<T>>,
        at: Range<usize>,
        key: &str,
        kind: &str,
    ) -> Result<&'v Spanned<T>, SceneError> {
        value
            .as_ref()
            .ok_or_else(|| self.err(at, key, format!("`{kind}` needs `{key}`")))
    }

    /// The model named under `name_key` in `table` (at `prefix`) and its parameters: every
    /// other key but `skip` (keys the scene itself reads).
    fn model_keys(
        &self,
        table: &ModelTable,
        prefix: &str,
        name_key: &'static str,
        skip: &[&str],
    ) -> Result<ModelKeys, SceneError> {
        let key = format!("{prefix}.{name_key}");
        let written = table
            .get_ref()
            .get(name_key)
            .ok_or_else(|| self.err(table.span(), &key, format!("`{prefix}` needs `{name_key}`")))?;
        let toml::Value::String(name) = written.get_ref() else {
            return Err(self.err(written.span(), &key, "must be a name (text)"));
        };
        let (mut values, mut spans) = (Values::new(), BTreeMap::new());
        for (k, v) in table.get_ref() {
            if k == name_key || skip.contains(&k.as_str()) {
                continue;
            }
            let value =
                to_value(v.get_ref()).ok_or_else(|| self.err(v.span(), &format!("{prefix}.{k}"), VALUE_KINDS))?;
            values.insert(k.clone(), value);
            spans.insert(k.clone(), v.span());
        }
        Ok(ModelKeys {
            prefix: prefix.to_string(),
            name_key,
            name: name.clone(),
            at: written.span(),
            values,
            spans,
        })
    }

    /// A registry's refusal of a model's table, at the key it names: an unknown model at its
    /// name, a missing parameter at the name, a bad one where it is written, and a refusal of
    /// the combination (a constructor's) at the name with every parameter's key.
    fn model_error(&self, m: &ModelKeys, e: ParamError) -> SceneError {
        let own = |k: &str| format!("{}.{k}", m.prefix);
        let (span, key) = match (&e, e.key()) {
            (ParamError::Unknown { .. }, _) => (m.at.clone(), own(m.name_key)),
            (ParamError::Missing { key, .. }, _) => (m.at.clone(), own(key)),
            (_, Some(k)) if m.spans.contains_key(k) => (m.spans[k].clone(), own(k)),
            _ if m.spans.is_empty() => (m.at.clone(), own(m.name_key)),
            _ => (
                m.at.clone(),
                m.spans.keys().map(|k| own(k)).collect::<Vec<_>>().join(", "),
            ),
        };
        self.param(span, &key, e)
    }

    /// The number `key` of `table` (at `prefix`), if written.
    fn table_number(&self, table: &ModelTable, prefix: &str, key: &str) -> Result<Option<Num>, SceneError> {
        let Some(v) = table.get_ref().get(key) else {
            return Ok(None);
        };
        match v.get_ref() {
            toml::Value::Float(x) => Ok(Some(Spanned::new(v.span(), *x))),
            toml::Value::Integer(i) => Ok(Some(Spanned::new(v.span(), *i as f64))),
            _ => Err(self.err(v.span(), &format!("{prefix}.{key}"), "must be a number")),
        }
    }

    /// Keys given that the chosen kind does not take: `(key, given)` pairs.
    fn refuse(&self, given: &[(&str, bool)], at: Range<usize>, kind: &str) -> Result<(), SceneError> {
        match given.iter().find(|(_, g)| *g) {
            Some((key, _)) => Err(self.err(at, key, format!("`{kind}` does not take `{key}`"))),
            None => Ok(()),
        }
    }
}

//! The `pseudorigid` command: run a scene described in a TOML file without writing Rust,
//! resume it after a kill, split it into shards and merge them, and look at it in ParaView.
//!
//! ```text
//! pseudorigid validate SCENE.toml
//! pseudorigid run SCENE.toml [--out DIR] [--shard k/N] [--resume] [--checkpoint-every S] [--threads N] [--quiet] [--csv]
//! pseudorigid merge SCENE.toml [--out DIR] [--csv]
//! pseudorigid probe CASE_DIR TIME|latest POINTS.csv OUT.csv
//! ```
//!
//! # Scene files
//! Every table refuses unknown keys. Units are the caller's (any consistent set). Example
//! scenes are in `scenes/` at the top of the repository.
//!
//! | key | meaning |
//! |---|---|
//! | `seed` | run seed (default 0); injected particle k draws from stream k of it |
//! | `[flow] type` | `quiescent`, `shear`, `planar_extension`, `uniaxial_extension`, `poiseuille`, `openfoam` |
//! | `flow.rate` | γ̇ or ε̇ of the linear flows |
//! | `flow.radius`, `flow.mean_velocity` | Poiseuille pipe along e₁: R and Ū (centreline 2Ū) |
//! | `flow.case`, `flow.time` | OpenFOAM case folder (relative to the scene file; an absolute path or one climbing with `..` is read as given: the command reads what the scene names, and writes nothing but under `--out`) and time: a number or `"latest"` (the default), a steady field (one that is zero in every cell is refused); a list of times or a range `{ start, end, period }`, a transient field (see *Transient fields*) |
//! | `flow.precision`, `flow.window` | transient fields only: `"f64"` (default) or `"f32"` storage of the levels; the length of the run's time windows (default: the smallest spacing of the levels) |
//! | `flow.blend` | `true` (default): the continuous field with the second-order no-slip wall layer (`flow::openfoam::BlendedFlow`); `false`: each cell's linear fit (discontinuous at faces, no wall-normal velocity near walls) |
//! | `[fluid] viscosity`, `density`, `gravity` | μ_f, ρ_f, g (default 0) |
//! | `[boundary] type` | `pipe` (needs `radius`), `planes` (needs `[[boundary.walls]]`), `mesh` (the case's patches) |
//! | `boundary.walls` | `name`, `point`, `normal` (outward), `rule` = `stick` or `exit` |
//! | `boundary.contact_radius` | touch at this distance from the barycentre, ≥ 0 (0: point contact; default: the particle's extent touches) |
//! | `[particles] density`, `drag`, `volumetric` | ρ_s of every entry and group that gives no `density` of its own; a registered drag model (`crate::hydro::drag`): `brenner` (default) or `stokes_sphere`, or a table `{ model = "…", … }` for a model with parameters; the volumetric traction `paper` (default, the literal eq. 12), `dev` or `source` (needed by `imex_adaptive` at tight tolerances: the literal eq. 12 anti-damps dilation) |
//! | `[particles] forces` | force terms beyond the paper's drag and reduced gravity, by name (`crate::hydro::forces`): `undisturbed_flow`, `added_mass` (Lamb's ellipsoid tensor), `schiller_naumann` and `saffman_mei` (spheres only), `holzer_sommerfeld` (finite-Re drag of any ellipsoid), or a table such as `{ term = "cunningham", mean_free_path = 6.65e-8 }` (λ in m; 66.5 nm for air at 20 °C, 1 atm); default none, the paper's model |
//! | `[[particles.list]]` | `density` (default `particles.density`), `semi_axes`, `position`, `orientation = { axis, angle }` (radians), `velocity` or `fluid_velocity = true`, `material` |
//! | `[particles.inject]` or several `[[particles.inject]]` groups | `count`, `density` (default `particles.density`), `region` (`{ type = "point", at }`, `{ type = "disc", centre, normal, radius }` or `{ type = "patch", name }`: on an OpenFOAM patch weighted by the inflow through each face (the case's face flux `phi` where the steady field's time directory has it, else the cell fits' −u·S), moved inside by the particle's largest semi-axis, or by `boundary.contact_radius` if that is larger), `semi_axes`, `orientation` or `random_orientation = true`, `fluid_velocity`, `material`; group g's particles follow those of groups 0..g in the index, and particle k draws from stream k whichever group it is in |
//! | `material` | a registered law (`crate::material::registry`) and its parameters: `{ law = "neo_hooke", mu, lambda }`, `{ law = "mooney_rivlin", mu1, mu2, lambda }`, `{ law = "rigid" }`, or a law written in the scene: `{ law = "expression", energy = "…", parameters = { name = value, … } }` with W(I1, I2, J) in `+ - * / ^ ( )`, `ln`, `exp`, `sqrt` (`material::expression`; μ_s and λ_s are read off its tangent at F = 1; `scenes/yeoh_oblate.toml`) |
//! | `[integrator] type` | a registered integrator (`crate::integrator::registry`): `imex` (the paper's, fixed `dt`; also `imex_paper`), `imex_adaptive`, `radau_iia` (inertialess, Radau IIA of order 5: the library's `Stokesian` default), `rosenbrock_w23` (inertialess, the Rosenbrock-W 2(3) pair), `auto` (chosen per particle from its Stokes number and the tolerance, `crate::integrator::choice`; the choice per injection group is printed as a `note:` line) (all four need `tol`); earlier scene files' `stokesian` and `stokesian_radau5` are read as `radau_iia`, `stokesian_rosenbrock23` as `rosenbrock_w23` |
//! | `integrator.dt`, `dt_max`, `overdamped` | first (or fixed) step, largest step, overdamped barycentre (`radau_iia`, `rosenbrock_w23`) |
//! | `integrator.norm` | how the local error is measured (`radau_iia`, `rosenbrock_w23`, `auto`): `"componentwise"` (the default) or `"tensor"`, F, x and v each by its norm, independent of the frame's orientation (`crate::integrator::ErrorNorm`; cost against accuracy on the bifurcation: `paper-figures/work-precision/NOTES.md`) |
//! | `[end] t_end`, `max_steps` | end time of every particle's run; accepted steps allowed per particle |
//! | `[output] every`, `vtk` | output interval (default: the end only); write ParaView files (default true) |
//! | `output.adequacy_sample` | particles of the mesh-adequacy diagnostic's re-track (`cli::adequacy`): the first min(N, n) by index run again on the other reconstruction of the field (cellwise for a blended run, blended for `flow.blend = false`) and paired with the run; default 200 on a steady OpenFOAM field, 0 (none) elsewhere; refused above 0 on an analytic flow and on a transient field |
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
//! Every run on an OpenFOAM field prints `note: adequacy:` lines (`cli::adequacy`): the
//! first-cell height 2ρ at the walls (median and max over the no-slip wall faces) against each
//! injection group's largest semi-axis and stopping distance τ_p·U (τ_p the response time of
//! the `auto` integrator's Stokes number, U the field's largest cell speed), with what the
//! ratios mean (both below 1: the particles' deposition is decided inside the wall layer,
//! which models the flow there rather than resolving it). A whole run on a steady field then
//! re-tracks the first `output.adequacy_sample` particles on the other reconstruction of the
//! same solution and pairs their fates with the run's (McNemar's paired difference of the
//! deposition fractions and its standard error); a `warning: adequacy:` line says when the
//! deposition moves by more than two paired standard errors: the near-wall resolution, not
//! the particles, sets the answer. The numbers and every pair go to `adequacy.json`. The
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
//! `records.parquet` (one row per particle) and `frames.parquet` (`cli::parquet`); a shard writes
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
pub mod error;
pub mod frames;
pub mod inject;
pub mod models;
#[cfg(feature = "parquet")]
pub mod parquet;
pub mod probe;
pub mod run;
pub mod scene;
pub mod schema;

pub use error::CliError;
pub use scene::{Scene, load};

use crate::population::{CHECKPOINT_INTERVAL, Progress, Shard};
use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};

/// Soft ellipsoidal micro-particles in viscous flow (pseudo-rigid bodies, Wedel et al.).
#[derive(Debug, Parser)]
#[command(name = "pseudorigid", version, about)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Check a scene file: every error names file, line, column and key.
    Validate {
        /// Scene file (TOML).
        scene: PathBuf,
    },
    /// Run a scene (or one shard of it).
    Run {
        /// Scene file (TOML).
        scene: PathBuf,
        /// Output folder (default: `<scene name>-out` in the current folder).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Run shard k of N (`k/N`, 0 ≤ k < N); default: from SLURM_ARRAY_TASK_ID and
        /// SLURM_ARRAY_TASK_COUNT if set, else the whole run.
        #[arg(long)]
        shard: Option<Shard>,
        /// Continue from the checkpoint in the output folder.
        #[arg(long)]
        resume: bool,
        /// Seconds between checkpoints.
        #[arg(long, default_value_t = CHECKPOINT_INTERVAL.as_secs_f64())]
        checkpoint_every: f64,
        /// Worker threads (default: all cores).
        #[arg(long)]
        threads: Option<usize>,
        /// No progress report.
        #[arg(long)]
        quiet: bool,
        /// Write the tables as CSV too (`results.csv`, `frames.csv`, `trajectories.csv`;
        /// always, without the feature `parquet`).
        #[arg(long)]
        csv: bool,
    },
    /// Merge the shard files of a run into the whole run's files.
    Merge {
        /// Scene file (TOML) of the sharded run.
        scene: PathBuf,
        /// Folder holding the shards' `checkpoint-<k>-of-<N>` (default as for `run`).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Write the tables as CSV too (always, without the feature `parquet`).
        #[arg(long)]
        csv: bool,
    },
    /// u and ∇u of an OpenFOAM case at listed points.
    Probe {
        /// OpenFOAM case: reconstructed, or decomposed (`processorN/`, read directly).
        case: PathBuf,
        /// Time directory, or `latest`.
        time: String,
        /// CSV with header `x,y,z`.
        points: PathBuf,
        /// Output CSV.
        out: PathBuf,
        /// The containing cell's linear fit instead of the blended field the particles see.
        #[arg(long)]
        cellwise: bool,
    },
}

/// `<scene stem>-out` in the current folder.
fn default_out(scene: &Path) -> PathBuf {
    let stem = scene.file_stem().map_or("scene".into(), |s| s.to_string_lossy());
    PathBuf::from(format!("{stem}-out"))
}

/// `line` after the transient field's levels and windows ([`Scene::flow_log`]) and the
/// integrator's choices ([`Scene::integrator_log`]), one `note:` line each, and the scene's
/// warnings about an integrator its particles contradict ([`Scene::integrator_advice`]) and
/// force terms it leaves out ([`Scene::force_advice`]), one `warning:` line each.
fn with_advice(scene: &Scene, line: String) -> String {
    let mut text: String = scene
        .flow_log()
        .into_iter()
        .chain(scene.integrator_log())
        .map(|n| format!("note: {n}\n"))
        .collect();
    text.extend(
        scene
            .integrator_advice()
            .into_iter()
            .chain(scene.force_advice())
            .map(|w| format!("warning: {w}\n")),
    );
    text.push_str(&line);
    text
}

/// Carry out `cli`; returns the lines to print on success (warnings, then the summary).
pub fn execute(cli: Cli) -> Result<String, CliError> {
    match cli.command {
        Command::Validate { scene } => {
            let s = load(&scene)?;
            Ok(with_advice(
                &s,
                format!(
                    "{}: valid ({} particles, {} output times)",
                    scene.display(),
                    s.count(),
                    s.outputs.len()
                ),
            ))
        }
        Command::Run {
            scene,
            out,
            shard,
            resume,
            checkpoint_every,
            threads,
            quiet,
            csv,
        } => {
            let s = load(&scene)?;
            let out = out.unwrap_or_else(|| default_out(&scene));
            let shard = match shard {
                Some(k) => k,
                None => Shard::from_env()?.unwrap_or(Shard::ALL),
            };
            let progress = if quiet { Progress::Quiet } else { Progress::Auto };
            let options = run::run_options(&out, checkpoint_every, resume, progress)?;
            run::run_on(&s, &out, shard, options, threads, csv).map(|done| {
                let adequacy = done.adequacy.as_ref().map_or(String::new(), adequacy::Adequacy::log);
                with_advice(&s, adequacy + &done.summary)
            })
        }
        Command::Merge { scene, out, csv } => {
            let s = load(&scene)?;
            run::merge(&s, &out.unwrap_or_else(|| default_out(&scene)), csv)
        }
        Command::Probe {
            case,
            time,
            points,
            out,
            cellwise,
        } => probe::probe(&case, &time, &points, &out, cellwise),
    }
}

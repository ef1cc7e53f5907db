//! The `pseudorigid` command: run a scene described in a TOML file without writing Rust,
//! resume it after a kill, split it into shards and merge them, and look at it in ParaView.
//!
//! ```text
//! pseudorigid validate SCENE.toml
//! pseudorigid run SCENE.toml [--out DIR] [--shard k/N] [--resume] [--checkpoint-every S] [--threads N] [--quiet] [--csv]
//! pseudorigid merge SCENE.toml [--out DIR] [--csv]
//! pseudorigid study STUDY.toml [--out DIR] [--shard k/N] [--resume] [--merge] [--order P] [...]
//! pseudorigid probe CASE_DIR TIME|latest POINTS.csv OUT.csv
//! ```
//!
//! The scene-file language (keys, transient fields, mesh adequacy, output files) is
//! [`crate::scene`]'s; this module is the command around it.

pub mod probe;

use crate::population::{CHECKPOINT_INTERVAL, Progress, Shard};
use crate::scene::study::{FORMAL_ORDER, StudyOptions, merge_study, run_study};
use crate::scene::{Scene, SceneError, adequacy, load, load_study, run};
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
    Run(RunArgs),
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
    /// A mesh study: a scene whose `flow.cases` names two to four solutions of one geometry,
    /// run on each (`OUT/mesh-<k>/`, each as `run` would), every outcome paired across them
    /// with the GCI of the finest (`OUT/study.csv`, `OUT/study.json`; `pseudorigid::scene::study`).
    Study {
        /// The scene (with `flow.cases`) and its run's options, as for `run`, each mesh's.
        #[command(flatten)]
        run: RunArgs,
        /// Merge every mesh's shards and write the study's tables, instead of running.
        #[arg(long)]
        merge: bool,
        /// The formal order of the chain, capping the order the GCI uses.
        #[arg(long, default_value_t = FORMAL_ORDER)]
        order: f64,
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

/// A scene file and how to run it: `run`'s arguments, and `study`'s for each of its meshes.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Output folder (default: `<scene name>-out` in the current folder).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Run shard k of N (`k/N`, 0 ≤ k < N; of every mesh in a study, then `study --merge`);
    /// default: from SLURM_ARRAY_TASK_ID and SLURM_ARRAY_TASK_COUNT if set, else the whole run.
    #[arg(long)]
    pub shard: Option<Shard>,
    /// Continue from the checkpoints in the output folder.
    #[arg(long)]
    pub resume: bool,
    /// Seconds between checkpoints.
    #[arg(long, default_value_t = CHECKPOINT_INTERVAL.as_secs_f64())]
    pub checkpoint_every: f64,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// No progress report.
    #[arg(long)]
    pub quiet: bool,
    /// Write the tables as CSV too (`results.csv`, `frames.csv`, `trajectories.csv`;
    /// always, without the feature `parquet`).
    #[arg(long)]
    pub csv: bool,
}

impl RunArgs {
    /// The output folder: `--out`, else `<scene stem>-out`.
    fn out(&self) -> PathBuf {
        self.out.clone().unwrap_or_else(|| default_out(&self.scene))
    }

    /// The shard: `--shard`, else the job array's from the environment, else the whole run.
    fn shard(&self) -> Result<Shard, SceneError> {
        match self.shard {
            Some(k) => Ok(k),
            None => Ok(Shard::from_env()?.unwrap_or(Shard::ALL)),
        }
    }

    /// The progress report `--quiet` asks for.
    fn progress(&self) -> Progress {
        if self.quiet { Progress::Quiet } else { Progress::Auto }
    }
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
pub fn execute(cli: Cli) -> Result<String, SceneError> {
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
        Command::Run(args) => {
            let s = load(&args.scene)?;
            let out = args.out();
            let options = run::run_options(&out, args.checkpoint_every, args.resume, args.progress())?;
            run::run_on(&s, &out, args.shard()?, options, args.threads, args.csv).map(|done| {
                let adequacy = done.adequacy.as_ref().map_or(String::new(), adequacy::Adequacy::log);
                with_advice(&s, adequacy + &done.summary)
            })
        }
        Command::Merge { scene, out, csv } => {
            let s = load(&scene)?;
            run::merge(&s, &out.unwrap_or_else(|| default_out(&scene)), csv)
        }
        Command::Study { run, merge, order } => {
            let meshes = load_study(&run.scene)?;
            let out = run.out();
            if merge {
                return merge_study(&meshes, &out, run.csv, order);
            }
            let options = StudyOptions {
                checkpoint_every: run.checkpoint_every,
                resume: run.resume,
                progress: run.progress(),
                threads: run.threads,
                csv: run.csv,
                formal_order: order,
            };
            run_study(&meshes, &out, run.shard()?, &options)
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

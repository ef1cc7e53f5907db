//! `pseudorigid study`: a scene whose `flow.cases` names two to four OpenFOAM solutions of one
//! geometry ([`super::load_study`]) run on each of them, the same particles (the same seed)
//! on every mesh, and every outcome's fraction paired across the meshes with its
//! discretisation error ([`crate::population::mesh_study`]).
//!
//! Each mesh's run is an ordinary run of the scene with that case, in `OUT/mesh-<k>/` (k from
//! 1, in the order of `flow.cases`): checkpointed, resumable with `--resume`, split with
//! `--shard k/N` and joined with `study --merge`, exactly as `run` and `merge` do. A whole run
//! (or the merge) then writes `OUT/study.csv` and `OUT/study.json`: per outcome the value on
//! each mesh, the refinement ratios from the cell counts (h = (V/N)^{1/d}, d = 2 for a slab
//! case), the apparent order, the extrapolated value and the GCI of the finest mesh by the
//! three-grid procedure of Celik et al. (2008), the binomial and paired standard errors, and a
//! verdict in words.
//!
//! The same particles: particle k draws the same shape, orientation, density and injection
//! rule on every mesh. Points and discs inject at the same places; a `patch` region picks a
//! face by the inflow of each mesh's own faces, so the injection points differ between meshes
//! (the pairing is then of the same draws, not of the same positions).

use super::run::{self, Job};
use super::{Scene, SceneError};
use crate::flow::openfoam::slab_axis;
use crate::material::NamedLaw;
use crate::output::atomic::write_atomic;
use crate::population::mesh_study::{MeshRun, MeshStudy};
use crate::population::{Progress, RunOutput, Shard};
use std::path::{Path, PathBuf};

pub use crate::population::mesh_study::FORMAL_ORDER;

/// Where mesh k's (from 1) run goes.
pub fn mesh_dir(out: &Path, k: usize) -> PathBuf {
    out.join(format!("mesh-{k}"))
}

/// Cells of `scene`'s mesh and the dimension of its representative size (2 for a slab case,
/// else 3).
fn mesh_size(label: &str, scene: &Scene) -> Result<(u64, u32), SceneError> {
    scene
        .flow
        .with_cellwise(|c| {
            c.map(|c| {
                let mesh = c.mesh();
                (mesh.n_cells() as u64, if slab_axis(mesh).is_some() { 2 } else { 3 })
            })
        })
        .ok_or_else(|| SceneError::Input(format!("{label}: a mesh study needs an OpenFOAM field")))
}

/// How a study is run: the run options every mesh shares.
#[derive(Debug, Clone)]
pub struct StudyOptions {
    /// Seconds between checkpoints.
    pub checkpoint_every: f64,
    /// Continue from the checkpoints.
    pub resume: bool,
    /// Progress reports.
    pub progress: Progress,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// Write CSV tables too.
    pub csv: bool,
    /// The chain's formal order ([`FORMAL_ORDER`] by default).
    pub formal_order: f64,
}

/// Run shard `shard` of the study `meshes` ([`super::load_study`]) into `out`, one mesh after
/// the other; a whole run also writes the study's tables ([`write_study`]). Returns the lines
/// to print: one per mesh, then the study's.
pub fn run_study(
    meshes: &[(String, Scene)],
    out: &Path,
    shard: Shard,
    options: &StudyOptions,
) -> Result<String, SceneError> {
    let mut lines = String::new();
    let mut outputs = Vec::with_capacity(meshes.len());
    for (k, (label, scene)) in meshes.iter().enumerate() {
        let dir = mesh_dir(out, k + 1);
        let run_options = run::run_options(&dir, options.checkpoint_every, options.resume, options.progress)?;
        let done = run::run_on(scene, &dir, shard, run_options, options.threads, options.csv)?;
        lines.push_str(&format!("mesh {} ({label}): {}\n", k + 1, done.summary));
        outputs.push(done.output);
    }
    if shard == Shard::ALL {
        lines.push_str(&write_study(meshes, &outputs, out, options.formal_order)?);
    }
    Ok(lines)
}

/// Merge each mesh's shards in `out` (as `merge` does) and write the study's tables.
pub fn merge_study(meshes: &[(String, Scene)], out: &Path, csv: bool, formal_order: f64) -> Result<String, SceneError> {
    let mut lines = String::new();
    let mut outputs = Vec::with_capacity(meshes.len());
    for (k, (label, scene)) in meshes.iter().enumerate() {
        let dir = mesh_dir(out, k + 1);
        lines.push_str(&format!(
            "mesh {} ({label}): {}\n",
            k + 1,
            run::merge(scene, &dir, csv)?
        ));
        outputs.push(scene.population(&Job::Merge { dir })?);
    }
    lines.push_str(&write_study(meshes, &outputs, out, formal_order)?);
    Ok(lines)
}

/// The study of the whole runs `outputs` of `meshes`: `study.csv` and `study.json` in `out`
/// ([`MeshStudy::csv`]; the JSON holds every number of the CSV with each increment's
/// discordant counts). Returns one line per outcome, its verdict.
pub fn write_study(
    meshes: &[(String, Scene)],
    outputs: &[RunOutput<NamedLaw>],
    out: &Path,
    formal_order: f64,
) -> Result<String, SceneError> {
    let mut runs = Vec::with_capacity(meshes.len());
    let mut dimension = 3;
    for ((label, scene), output) in meshes.iter().zip(outputs) {
        let (cells, d) = mesh_size(label, scene)?;
        dimension = d;
        runs.push(MeshRun { label, cells, output });
    }
    let study = MeshStudy::new(&runs, dimension, formal_order).map_err(|e| SceneError::Input(e.to_string()))?;
    study.csv()?.write(out.join("study.csv"))?;
    let json = serde_json::to_vec_pretty(&study).map_err(|e| SceneError::Input(format!("study.json: {e}")))?;
    write_atomic(out.join("study.json"), &json)?;
    let cells: Vec<String> = study
        .meshes
        .iter()
        .map(|m| format!("{} ({} cells)", m.label, m.cells))
        .collect();
    let mut lines = format!(
        "mesh study of {} particles on {}, finest first; study.csv and study.json in {}\n",
        study.particles,
        cells.join(", "),
        out.display()
    );
    for o in &study.outcomes {
        let values: Vec<String> = o.values.iter().map(|v| format!("{v:.4}")).collect();
        lines.push_str(&format!("{}: {} — {}\n", o.outcome, values.join(", "), o.verdict));
    }
    Ok(lines)
}

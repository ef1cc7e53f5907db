//! The mesh-adequacy diagnostic of a scene's run on an OpenFOAM field (issue 39): computed by
//! [`crate::population::adequacy`] from the scene's field, particles, case and seed, and here
//! put in words for the run log ([`Adequacy::log`]) and written to `adequacy.json`
//! ([`Adequacy::write`]). A shard (`--shard k/N`) gets the ratios only and `merge` re-tracks
//! the whole run; a transient field gets the ratios only (the re-track would need a second
//! sliding field: not implemented).

use crate::material::NamedLaw;
use crate::population::ParticleRecord;
use crate::population::adequacy::sensitivity;
pub use crate::population::adequacy::{
    Grown, Look, ParticleScales, RESOLVE, RETRACK_STEP_FACTOR, RETRACK_STEP_FLOOR, Reconstruction, Resolution,
    Retracked, STEP_BUDGET, Sensitivity, Stop, WARN_SIGMAS, WallResolution, detectable, grow, warn_sigmas,
};
use crate::scene::Scene;
use crate::scene::error::SceneError;
use crate::scene::models::SceneFlow;
use crate::tensor::Vec3;
use serde::Serialize;
use std::path::Path;

/// The file of the diagnostic in a run's output folder.
pub const FILE: &str = "adequacy.json";

/// Why a run has no re-track.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Skipped {
    /// `output.adequacy_sample = 0`.
    Off,
    /// A shard of a run: `merge` re-tracks.
    Shard,
    /// A transient field (not implemented).
    Transient,
}

/// The diagnostic of one run on an OpenFOAM field: written as [`FILE`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Adequacy {
    /// The wall layer's depth against the particles; `None` if the case has no no-slip wall.
    pub resolution: Option<Resolution>,
    /// The re-track, if one was run.
    pub sensitivity: Option<Sensitivity>,
    /// Why not, if not.
    pub skipped: Option<Skipped>,
}

impl Adequacy {
    /// The run log's lines: `note: adequacy: …` lines and a `warning: adequacy: …` line when
    /// the re-track moves the deposition (each ends with a newline).
    pub fn log(&self) -> String {
        let mut lines = Vec::new();
        match &self.resolution {
            None => lines.push("note: adequacy: the case has no no-slip wall: nothing deposits".to_string()),
            Some(r) => {
                lines.push(format!(
                    "note: adequacy: first-cell height at the walls 2ρ = {:.3e} (median), {:.3e} (max) over {} wall \
                     faces; field speed U = {:.3e} (largest cell value)",
                    r.walls.median, r.walls.max, r.walls.faces, r.speed
                ));
                let groups = r
                    .particles
                    .iter()
                    .map(|p| {
                        (
                            p.key.clone(),
                            format!(
                                "largest semi-axis a = {:.3e} = {} × 2ρ, stopping distance τ_p·U = {:.3e} × {:.3e} = \
                                 {:.3e} = {} × 2ρ (median): {}",
                                p.largest_semi_axis,
                                ratio(p.size_ratio),
                                p.response_time,
                                r.speed,
                                p.stopping_distance,
                                ratio(p.stopping_ratio),
                                p.verdict()
                            ),
                        )
                    })
                    .collect();
                lines.extend(
                    crate::scene::grouped(groups)
                        .into_iter()
                        .map(|l| format!("note: adequacy: {l}")),
                );
                lines.extend(r.strained_walls.iter().map(|w| {
                    format!(
                        "warning: adequacy: wall patch `{}`: its prescribed velocity strains along the curved wall on {} \
                         of its {} faces (surface strain rate up to {:.3e}, curvature up to {:.3e}): the wall layer \
                         extends only a rigid wall motion exactly on a curved wall, so u and ∇u within the first \
                         cells there miss by O(κδ) of that strain; the cellwise field (`flow.blend = false`) has no \
                         such term",
                        w.patch, w.faces, w.of, w.strain, w.curvature
                    )
                }));
            }
        }
        match (&self.sensitivity, self.skipped) {
            (Some(s), _) => {
                let p = &s.pairing;
                let undecided = if s.undecided > 0 {
                    format!(
                        " ({} of them left out, undecided: their re-track took over {RETRACK_STEP_FACTOR}× their \
                         steps in the run, sliding along cell faces, or failed)",
                        s.undecided
                    )
                } else {
                    String::new()
                };
                let failed: u64 = s.failed_in_run.iter().map(|f| f.2).sum();
                if failed > 0 {
                    let wall = s
                        .failed_in_run
                        .iter()
                        .filter(|f| f.1 == "wall")
                        .map(|f| f.2)
                        .sum::<u64>();
                    lines.push(format!(
                        "warning: adequacy: {failed} of the first {} particles failed in the run and are left out \
                         of the comparison; nearest patch where they failed: {}. {}",
                        p.n() + s.undecided + failed,
                        s.failed_in_run
                            .iter()
                            .map(|(name, kind, n)| format!("`{name}` ({kind}) {n}"))
                            .collect::<Vec<_>>()
                            .join(", "),
                        if wall < failed {
                            "A failure at a patch that is not a wall is not the wall mesh's doing: see the run's \
                             failure messages"
                        } else {
                            "See the run's failure messages"
                        }
                    ));
                }
                lines.push(format!(
                    "note: adequacy: the first {} particles re-tracked on the {} field{undecided}: deposited {} ({}) \
                     against {} ({}); {} by the {} field only, {} by the {} field only: difference {:+.4} ± {:.4} \
                     (paired standard error; the run's own binomial error {:.4})",
                    p.n() + s.undecided + failed,
                    s.other_field,
                    p.both + p.only_ours,
                    s.run_field,
                    p.both + p.only_peer,
                    s.other_field,
                    p.only_ours,
                    s.run_field,
                    p.only_peer,
                    s.other_field,
                    s.difference,
                    s.stderr,
                    s.run_stderr
                ));
                let stop = match s.stop {
                    Stop::Resolved => "the difference is resolved".to_string(),
                    Stop::Bounded => format!("a shift of {RESOLVE} would have shown"),
                    Stop::AllParticles => "every particle of the run is in".to_string(),
                    Stop::Budget => format!(
                        "a larger sample would pass the budget of {STEP_BUDGET}× the run's steps (spent {} of {})",
                        s.steps.0, s.steps.1
                    ),
                };
                let looks = if s.looks == 1 {
                    "1 look".to_string()
                } else {
                    format!("{} looks, the sample doubled after each", s.looks)
                };
                lines.push(format!(
                    "note: adequacy: {looks}, stopped because {stop}; the smallest shift this \
                     sample detects with 80 % power is {:.4} (a difference beyond {:.2} paired standard errors warns, 5 % false \
                     alarms over the looks)",
                    s.detectable,
                    s.sigmas
                ));
                if s.warning {
                    // The paired standard error vanishes when every pair is discordant one way.
                    let sigmas = if s.stderr > 0.0 {
                        format!(
                            "{:.1} paired standard errors, more than {:.2}",
                            s.difference.abs() / s.stderr,
                            s.sigmas
                        )
                    } else {
                        format!("all {} pairs that differ, one way", p.only_ours + p.only_peer)
                    };
                    lines.push(format!(
                        "warning: adequacy: the deposition fraction moves by {:.4} ({sigmas}) between the {} and the \
                         {} field: the mesh is too coarse at the walls for these particles, and the near-wall \
                         resolution, not the particles, sets the answer; refine the first cells (below the \
                         particles' size or stopping distance) and compare again",
                        s.difference.abs(),
                        s.run_field,
                        s.other_field
                    ));
                }
                lines.push(
                    "note: adequacy: both fields interpolate the same solution, so this cannot see the solver's own \
                     discretisation error: for that, solve the case on two to four meshes and run them as a mesh \
                     study (`flow.cases = [...]`, `pseudorigid study SCENE.toml`)"
                        .to_string(),
                );
            }
            (None, Some(Skipped::Off)) => {
                lines.push("note: adequacy: no re-track (`output.adequacy_sample = 0`)".to_string());
            }
            (None, Some(Skipped::Shard)) => {
                lines.push("note: adequacy: the re-track on the other field is done by `merge`".to_string());
            }
            (None, Some(Skipped::Transient)) => lines.push(
                "note: adequacy: no re-track on a transient field (not implemented): compare with `flow.blend = \
                 false` by hand"
                    .to_string(),
            ),
            (None, None) => {}
        }
        lines.into_iter().map(|l| l + "\n").collect()
    }

    /// The text of [`FILE`]: pretty JSON of the diagnostic with the run log's lines
    /// ([`Self::log`]) under `log`, so a reader (Python's `Results.adequacy` and `adequacy`)
    /// shows the same words.
    pub fn json(&self) -> Result<String, SceneError> {
        let mut value = serde_json::to_value(self).map_err(|e| SceneError::Input(format!("{FILE}: {e}")))?;
        if let serde_json::Value::Object(map) = &mut value {
            let lines = self.log().lines().map(serde_json::Value::from).collect();
            map.insert("log".into(), serde_json::Value::Array(lines));
        }
        serde_json::to_string_pretty(&value).map_err(|e| SceneError::Input(format!("{FILE}: {e}")))
    }

    /// Write it to `dir`/[`FILE`] (atomically) as [`Self::json`].
    pub fn write(&self, dir: &Path) -> Result<(), SceneError> {
        crate::output::atomic::write_atomic(dir.join(FILE), self.json()?.as_bytes())?;
        Ok(())
    }
}

/// Remove `dir`/[`FILE`] if it exists (a run without a diagnostic into a folder that holds an
/// earlier run's).
pub fn remove(dir: &Path) -> Result<(), SceneError> {
    match std::fs::remove_file(dir.join(FILE)) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(SceneError::Input(format!(
            "cannot remove the earlier run's {}: {e}",
            dir.join(FILE).display()
        ))),
        _ => Ok(()),
    }
}

/// The diagnostic of `scene`'s run whose records are `records` (a shard's if `shard`, which
/// then gets no re-track): `None` on an analytic flow. The re-track samples
/// `scene.adequacy_sample` particles ([`crate::population::adequacy`]).
pub fn adequacy(
    scene: &Scene,
    records: &[ParticleRecord<NamedLaw>],
    shard: bool,
) -> Result<Option<Adequacy>, SceneError> {
    let Some(resolution) = resolution(scene) else {
        return Ok(None);
    };
    let run_on = match &scene.flow {
        SceneFlow::Blended(blended) => Some(Reconstruction::Blended(blended)),
        SceneFlow::Foam(cells) => Some(Reconstruction::Cellwise(cells)),
        SceneFlow::Transient(_) | SceneFlow::Quiescent | SceneFlow::Linear(_) | SceneFlow::Poiseuille(_) => None,
    };
    let (sensitivity, skipped) = match run_on {
        _ if scene.adequacy_sample == 0 => (None, Some(Skipped::Off)),
        _ if shard => (None, Some(Skipped::Shard)),
        None => (None, Some(Skipped::Transient)),
        Some(run_on) => {
            let injector = scene.injector();
            let case = scene.case(&injector);
            let s = sensitivity(&case, scene.seed, run_on, records, scene.adequacy_sample)?;
            (Some(s), None)
        }
    };
    Ok(Some(Adequacy {
        resolution,
        sensitivity,
        skipped,
    }))
}

/// The wall layer's depth against each list entry and injection group of `scene`: `None` on
/// an analytic flow, `Some(None)` on a case without no-slip walls.
fn resolution(scene: &Scene) -> Option<Option<Resolution>> {
    scene.flow.with_cellwise(|cells| {
        let cells = cells?;
        // An entry the template refuses fails in the run itself, with its error.
        let particles: Vec<_> = scene
            .placements()
            .into_iter()
            .filter_map(|(key, placement)| Some((key, scene.template.build(&placement.spec(Vec3::zeros())).ok()?)))
            .collect();
        Some(Resolution::of(cells, particles.iter().map(|(key, p)| (key.clone(), p))))
    })
}

/// A ratio to the first cell for the log: three decimals, or three digits below 0.01 (a
/// tracer's are ~10⁻⁴).
fn ratio(x: f64) -> String {
    if x >= 0.01 {
        format!("{x:.3}")
    } else {
        format!("{x:.2e}")
    }
}

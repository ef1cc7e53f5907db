//! Whether a run on an OpenFOAM field can be trusted near the walls: the mesh-adequacy
//! diagnostic (issue 39), computed from what a study holds: the steady field's two
//! reconstructions ([`Reconstruction`]), the run's [`Case`], seed and records. A scene's run
//! gets it through `crate::scene::adequacy`, which adds the log and `adequacy.json`.
//!
//! # What decides a deposit, and where
//! Next to a no-slip wall the field a particle sees is the wall layer's near-wall expansion
//! (`flow::openfoam::wall_layer`) inside the wall cells, fitted through the solver's values
//! at the wall cell's centre (height ρ over the face) and the cell above: a model of the flow
//! there, not resolved data. The first cell is 2ρ high. A particle of largest semi-axis a
//! touches when its barycentre comes within about a of the wall; a particle of response time
//! τ_p ([`ParticleNumbers::response_time`]) carried at speed U coasts a stopping distance
//! τ_p U. So
//! - **a < 2ρ and τ_p U < 2ρ**: the particle must enter the first cell to touch, and it follows
//!   the modelled flow there: where and whether it deposits is decided inside the wall layer,
//!   and the answer depends on it;
//! - **τ_p U ≥ 2ρ**: its inertia carries it across the first cell: impaction is decided by
//!   the resolved flow above it;
//! - **a ≥ 2ρ** (and τ_p U < 2ρ): it touches with its barycentre above the first cell
//!   (interception by resolved cells), but it spans a cell or more, so the flow is not linear
//!   across it.
//!
//! The threshold 1 of both ratios is where the touch or the coasting crosses the first cell's
//! top. The heights are the wall faces' ([`WallResolution`]: median and largest 2ρ over every
//! no-slip wall face of the case; a wall the particles never reach counts too, so the median is
//! the case's, not the particles' path's). U is the largest cell-centre speed of the field at
//! t = 0, so τ_p U is the largest stopping distance any particle can have: if even that is
//! below the first cell, the inertia does not reach through it.
//!
//! # How much the answer moves: the re-track
//! The ratios say whether the wall layer decides; the re-track measures by how much. The first
//! min(N, `output.adequacy_sample`) particles by index (a scene's `output.adequacy_sample`, default [`DEFAULT_SAMPLE`](crate::scene::DEFAULT_SAMPLE); the same
//! particles every time) are run again from the same injection on the other reconstruction of
//! the same solution: the cellwise field (each cell's linear fit, no wall layer) for a run on
//! the blended field, the blended field for a run with `flow.blend = false`. Their fates are
//! paired with the run's ([`Pairing`]: deposited by the run only b, by the re-track only c);
//! the paired (McNemar) difference of the deposition fractions is (b − c)/n with standard error
//! √(b + c − (b − c)²/n)/n, and a **warning** is printed when |b − c|/n exceeds
//! [`WARN_SIGMAS`] of them. Two fields that interpolate the same solution and differ only
//! below the second cell then give different answers: the near-wall resolution, not the
//! particles, sets the deposition. A re-track may take [`RETRACK_STEP_FACTOR`] times the
//! particle's steps in the run (plus [`RETRACK_STEP_FLOOR`]); one that needs more is sliding
//! along a face of the cellwise field and is left out of the pairing as *undecided*, counted
//! in the log. A particle that failed in the run itself is left out too, and the log names the
//! patches nearest to where the run's failures happened: a failure at an inlet, an outlet or a
//! coupled patch is not the wall mesh's doing, and is not blamed on it.
//!
//! # How large a sample
//! The first `output.adequacy_sample` particles are one look; while no difference shows, the
//! sample doubles (the next particles by index) until one of: the difference exceeds the
//! warning bound; the sample could have detected a shift of [`RESOLVE`] with 80 % power
//! ([`detectable`]); every particle is in; or the next look would take the re-track past
//! [`STEP_BUDGET`] times the run's own accepted steps (predicted from the last look's steps per
//! particle). Steps, not seconds, so the result does not depend on the machine. The warning
//! bound is Bonferroni's over the most looks the run's size allows ([`warn_sigmas`]), so the
//! chance of a false alarm over all looks stays ≤ 5 % (the suite measures it by simulation of
//! the rule, `adequacy_rule_keeps_false_alarms_and_reaches_its_power`). The log prints the
//! smallest shift the sample it used detects with 80 % power: a silence means "no shift that
//! large", not "no shift". A shift of 0.01 needs about (z + 0.84)²·d/0.01² pairs at a discordant
//! share d: ~10 000 at d = 0.1 with three looks (z = 2.39), so on a run of fewer particles the check is
//! bounded by the run's size, and the log says so.
//!
//! Measured on OpenFOAM's own cases and the repository's T-junction at three resolutions
//! (300 spheres of a = 0.4 mm, 2 500 kg/m³, τ_p U/D ≈ 0.09; 200 re-tracked):
//!
//! | case | 2ρ | a/2ρ, τ_p U/2ρ | deposited, blended : cellwise | paired difference | warning |
//! |---|---|---|---|---|---|
//! | `cases/tjunction`, 4 cells across | 2.5 mm | 0.16, 0.55 | 115 : 151 | −0.180 ± 0.027 | yes (6.6 se) |
//! | `cases/tjunction`, 8 across | 1.25 mm | 0.32, 1.30 | 150 : 139 | +0.055 ± 0.023 | yes (2.4 se) |
//! | `cases/tjunction`, 16 across | 0.625 mm | 0.64, 2.72 | 119 : 122 | −0.015 ± 0.009 | no (1.7 se) |
//!
//! Its 1 000 point tracers (`cases/tjunction/scene.toml`), the same way: the cellwise field
//! deposits 61, 18 and 1 of the first 200 (undecided 61, 9, 0) where the blended field deposits
//! none, a warning at 10.4 and 4.5 paired standard errors on the coarse and shipped meshes and
//! none on the fine one.
//!
//! On the pimpleFoam `TJunction` tutorial (5 cells across a 20 mm duct), 1 000 flux-weighted
//! point tracers: none deposits on the blended field; of the first 200 re-tracked on the
//! cellwise field 66 deposit and 133 slide along faces (undecided): a warning, rightly, since
//! on that mesh the answer is the near-wall reconstruction's. Run and re-track took 84 s of CPU
//! together; with the re-track unbounded, the re-track alone ran past 63 min.
//!
//! On the airway bifurcation, read against a mesh study of the same runs
//! (`cases/bifurcation/study.toml`: 10⁴ rigid spheres at Stk 0.1 on 0.4, 0.3 and 0.2 mm, the
//! default sample and budget; `paper-figures/mesh-study/NOTES.md`, *The airway*):
//!
//! | mesh | re-track: looks, pairs, blended − cellwise | warning | the study: this mesh − the next finer, ± paired se |
//! |---|---|---|---|
//! | 0.4 mm | 2, 400, +0.020 | yes | +0.0083 ± 0.0010 |
//! | 0.3 mm (shipped) | 3, 798, +0.015 | yes | +0.0013 ± 0.0008 |
//! | 0.2 mm | 4, 1 600, +0.0013 (a 0.0078 shift detectable) | no | (finest) |
//!
//! Right about the cellwise field on every mesh, but as a test of the *solution* the 0.3 mm
//! warning is a false alarm: the solution there is within 0.0013 of the finer one. The check
//! sees the reconstruction's sensitivity, which bounds nothing about the solver's error; three
//! meshes give no rate. Its message says so and points to `pseudorigid study`.
//!
//! The re-track runs after the run, in memory, from the run's records: the run's records,
//! tables, checkpoints and `--resume` are those of a run without it, bit for bit. A shard
//! (`--shard k/N`) prints the ratios only; `merge` re-tracks the first particles of the whole
//! run, so the sample is the same however the run was split. A transient field gets the ratios
//! only (the re-track would need a second sliding field: not implemented). The results go to
//! the run log and to `adequacy.json` in the output folder
//! ([`crate::scene::adequacy::Adequacy`]).

use super::peer::Pairing;
use super::{Case, Fate, Injector, ParticleRecord, binomial};
use crate::contact::Boundary;
use crate::driver::Budget;
use crate::flow::FlowField;
use crate::flow::openfoam::wall_layer::StrainedWall;
use crate::flow::openfoam::{BlendedFlow, FoamError, FoamFlow};
use crate::hydro::DragModel;
use crate::integrator::Stepper;
use crate::integrator::choice::ParticleNumbers;
use crate::material::{Response, Softness};
use crate::particle::Particle;
use rayon::prelude::*;
use serde::Serialize;

/// Paired standard errors beyond which the re-track warns: two, a two-sided 95 % test in the
/// normal approximation. At a handful of discordant pairs that approximation is liberal (4
/// particles deposited by one field only and none by the other warn; McNemar's exact p is
/// 0.125 there): it errs towards warning, which is the side to err on for a diagnostic.
pub const WARN_SIGMAS: f64 = 2.0;

/// A re-tracked particle may take this many times its accepted steps in the run, plus
/// [`RETRACK_STEP_FLOOR`], before it is left out as undecided. Both fields interpolate the
/// same solution along the same path, so a particle's steps differ between them by the
/// rejections the cellwise field's jumps across faces cost, a small factor; far beyond it, a
/// particle is sliding along a face where the fits on both sides push towards it, every step
/// rejected (the Filippov sliding mode `flow::openfoam::BlendedFlow`'s docs describe): on
/// OpenFOAM's `TJunction` tutorial, unbounded, 200 point tracers took 63 min of CPU on the
/// cellwise field against 1 min for the run's 1 000 on the blended one.
pub const RETRACK_STEP_FACTOR: u64 = 10;

/// Steps a re-tracked particle may take on top of [`RETRACK_STEP_FACTOR`] times its own: room
/// for a particle that failed or stopped early in the run.
pub const RETRACK_STEP_FLOOR: u64 = 1_000;

/// The shift in deposition fraction the re-track tries to resolve: it grows its sample until
/// it could have detected this difference with 80 % power ([`detectable`]), or until a
/// difference shows, or its budget is spent (module docs, *How large a sample*). One per cent
/// is the size of the sampling error of a 10⁴-particle run's fraction near 0.1–0.5.
pub const RESOLVE: f64 = 0.01;

/// The re-track's budget: its accepted steps may reach this multiple of the run's own (summed
/// over every particle of the run), so the diagnostic at most doubles a run's tracking cost. The
/// first sample is re-tracked whatever it costs.
pub const STEP_BUDGET: f64 = 1.0;

/// One-sided normal quantile of 80 % power, Φ⁻¹(0.8).
const POWER_QUANTILE: f64 = 0.841_621_233_572_914_3;

/// Φ⁻¹(1 − 0.025/K) for K = 1, 2, …, 16 (SciPy's `norm.ppf`, to 6 decimals): the two-sided
/// 5 % Bonferroni bound over K looks.
const BONFERRONI: [f64; 16] = [
    1.959_964, 2.241_403, 2.393_980, 2.497_705, 2.575_829, 2.638_257, 2.690_110, 2.734_369, 2.772_921, 2.807_034,
    2.837_597, 2.865_260, 2.890_512, 2.913_726, 2.935_199, 2.955_167,
];

/// Paired standard errors beyond which a re-track of at most `looks` looks warns: [`WARN_SIGMAS`]
/// for one, Bonferroni's Φ⁻¹(1 − 0.025/K) over K looks beyond (the false-alarm rate of the
/// whole sequence stays ≤ 5 % whichever look stops it; the looks double the sample, so
/// they are less correlated than equally spaced ones and Pocock's tighter bounds do not hold).
pub fn warn_sigmas(looks: u32) -> f64 {
    let k = usize::try_from(looks.max(1)).unwrap_or(usize::MAX);
    BONFERRONI
        .get(k - 1)
        .copied()
        .unwrap_or(BONFERRONI[15])
        .max(WARN_SIGMAS)
}

/// The smallest shift δ in deposition fraction a re-track with `pairing` would detect with 80 %
/// power at `sigmas` paired standard errors: δ = (z + z₀.₈)·σ(δ), σ(δ) = √(max(d, δ)/n)
/// with d the discordant share (b + c)/n: a shift δ needs at least δn discordant pairs, so
/// δ = max((z + z₀.₈)√(d/n), (z + z₀.₈)²/n); ∞ with nothing paired.
pub fn detectable(pairing: &Pairing, sigmas: f64) -> f64 {
    let n = pairing.n() as f64;
    if n == 0.0 {
        return f64::INFINITY;
    }
    let z = sigmas + POWER_QUANTILE;
    let d = (pairing.only_ours + pairing.only_peer) as f64 / n;
    (z * (d / n).sqrt()).max(z * z / n)
}

/// Why the re-track stopped growing its sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stop {
    /// The difference exceeded the warning bound: a warning.
    Resolved,
    /// It could have detected a shift of [`RESOLVE`]: none is there.
    Bounded,
    /// Every particle of the run is re-tracked.
    AllParticles,
    /// The next sample would pass [`STEP_BUDGET`].
    Budget,
}

/// The first-cell heights 2ρ of the no-slip wall faces (ρ: the wall cell's centre over the
/// face's plane, `flow::openfoam::WallGeometry::depth`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WallResolution {
    /// No-slip wall faces.
    pub faces: usize,
    /// Median 2ρ (the upper median for an even count).
    pub median: f64,
    /// Largest 2ρ.
    pub max: f64,
}

impl WallResolution {
    /// The heights of `flow`'s wall faces; `None` if the case has no no-slip wall.
    pub fn of(flow: &FoamFlow) -> Option<Self> {
        let layer = flow.wall_layer();
        let mut heights: Vec<f64> = (0..layer.len()).map(|k| 2.0 * layer.depth(k)).collect();
        heights.sort_by(f64::total_cmp);
        Some(Self {
            faces: heights.len(),
            median: *heights.get(heights.len() / 2)?,
            max: *heights.last()?,
        })
    }
}

/// One list entry's or injection group's sizes against the first cell.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ParticleScales {
    /// Its scene key (`particles.inject[0]`, `particles.list[3]`).
    pub key: String,
    /// Largest semi-axis a of the rest shape.
    pub largest_semi_axis: f64,
    /// Response time τ_p ([`ParticleNumbers::response_time`]).
    pub response_time: f64,
    /// τ_p U with U [`Resolution::speed`].
    pub stopping_distance: f64,
    /// a over the median first-cell height.
    pub size_ratio: f64,
    /// τ_p U over the median first-cell height.
    pub stopping_ratio: f64,
}

impl ParticleScales {
    /// What the ratios mean (module docs), in words.
    pub fn verdict(&self) -> &'static str {
        if self.stopping_ratio >= 1.0 {
            "its inertia carries it across the first cell: impaction is decided by the resolved flow above it"
        } else if self.size_ratio >= 1.0 {
            "it touches with its barycentre above the first cell (interception by resolved cells), but it spans a \
             cell or more, so the flow is not linear across it"
        } else {
            "both below 1: a particle must enter the first cell to touch and follows the modelled flow there, so \
             its deposition is decided inside the wall layer and depends on it"
        }
    }
}

/// The wall layer's depth against the particles (module docs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Resolution {
    /// First-cell heights over the wall faces.
    pub walls: WallResolution,
    /// U: the largest cell-centre speed of the field at t = 0.
    pub speed: f64,
    /// Each list entry and injection group.
    pub particles: Vec<ParticleScales>,
    /// The no-slip walls where the wall layer is not exact for a linear field: a prescribed
    /// velocity straining along a curved wall (`flow::openfoam::wall_layer`, *What is exact*).
    pub strained_walls: Vec<StrainedWall>,
}

/// One re-tracked particle: its fate in the run and on the other field.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Retracked {
    /// Particle index.
    pub index: u64,
    /// Fate in the run (`Fate::label`).
    pub run: &'static str,
    /// Fate on the other field.
    pub other: &'static str,
}

/// The re-track of the first particles on the other field (module docs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sensitivity {
    /// The field of the run: `blended` or `cellwise`.
    pub run_field: &'static str,
    /// The field of the re-track: the other one.
    pub other_field: &'static str,
    /// Deposited by both, by the run only (b), by the re-track only (c), by neither; the
    /// undecided particles left out.
    pub pairing: Pairing,
    /// Re-tracked particles whose re-track did not finish (beyond [`RETRACK_STEP_FACTOR`]
    /// times their steps in the run, or failed): left out of the pairing.
    pub undecided: u64,
    /// Sampled particles that failed in the run itself, by the patch nearest to where they
    /// failed (name, type, count; most first): left out of the pairing, and not the wall
    /// mesh's doing where the patch is not a wall.
    pub failed_in_run: Vec<(String, String, u64)>,
    /// Deposition fraction of the sample in the run.
    pub run_fraction: f64,
    /// Deposition fraction of the sample on the other field.
    pub other_fraction: f64,
    /// Its binomial standard error over the whole run (`population::binomial::stderr`).
    pub run_stderr: f64,
    /// Paired difference (b − c)/n, run minus re-track.
    pub difference: f64,
    /// Its paired (McNemar) standard error.
    pub stderr: f64,
    /// The warning bound in paired standard errors ([`warn_sigmas`] of the most looks the
    /// run's size allows).
    pub sigmas: f64,
    /// |difference| > `sigmas` · stderr, with at least one discordant pair.
    pub warning: bool,
    /// The smallest shift this sample would have detected with 80 % power ([`detectable`]).
    pub detectable: f64,
    /// Looks taken (the sample doubled between them).
    pub looks: u32,
    /// Why the sample stopped growing.
    pub stop: Stop,
    /// Accepted steps of the re-track against the run's own.
    pub steps: (u64, u64),
    /// The particles, by index.
    pub particles: Vec<Retracked>,
}

impl Resolution {
    /// The wall layer's depth on `cells` (the cellwise reconstruction of the run's field) against
    /// `particles`, one per list entry or injection group with its key (module docs); `None` on a
    /// case without no-slip walls. A particle whose response time cannot be found is left out
    /// (it fails in the run itself, with its error).
    pub fn of<'p, M: Response + 'p, D: DragModel + 'p>(
        cells: &FoamFlow,
        particles: impl IntoIterator<Item = (String, &'p Particle<M, D>)>,
    ) -> Option<Self> {
        let walls = WallResolution::of(cells)?;
        let centres = cells.mesh().cell_centres();
        let speed = centres
            .iter()
            .enumerate()
            .map(|(c, x)| cells.sample_cell(c, x, 0.0).u.norm())
            .fold(0.0, f64::max);
        let particles = particles
            .into_iter()
            .filter_map(|(key, particle)| {
                let tau = ParticleNumbers::response_time(particle).ok()?;
                let a = particle.shape().semi_axes().max();
                Some(ParticleScales {
                    key,
                    largest_semi_axis: a,
                    response_time: tau,
                    stopping_distance: tau * speed,
                    size_ratio: a / walls.median,
                    stopping_ratio: tau * speed / walls.median,
                })
            })
            .collect();
        Some(Self {
            walls,
            speed,
            particles,
            strained_walls: cells.strained_walls(),
        })
    }
}

/// The reconstruction of a steady OpenFOAM solution a run was on; the re-track takes the other.
#[derive(Debug, Clone, Copy)]
pub enum Reconstruction<'a> {
    /// The blended field (the wall layer in the wall cells); the re-track is on its cellwise
    /// field.
    Blended(&'a BlendedFlow),
    /// The cellwise field (`flow.blend = false`); the re-track is on the blended field over it.
    Cellwise(&'a FoamFlow),
}

impl Reconstruction<'_> {
    /// The cellwise field under either: its mesh and wall faces.
    pub fn cells(&self) -> &FoamFlow {
        match self {
            Reconstruction::Blended(blended) => blended.cellwise(),
            Reconstruction::Cellwise(cells) => cells,
        }
    }
}

/// A re-track of some of a run's records on the other field: their fates and accepted steps.
type Retrack<'a, L> = Box<dyn Fn(&[&ParticleRecord<L>]) -> Vec<(Fate, u64)> + 'a>;

/// The particles of `records` (the run of `case` with `seed` on `run_on`), by index, re-tracked
/// on the other reconstruction of the same field and paired with their fates in `records`
/// (module docs): the first min(N, `sample`), then twice as many at each look until the
/// difference is resolved, a shift of [`RESOLVE`] is bounded, every particle is in, or
/// [`STEP_BUDGET`] would be passed.
///
/// # Errors
/// [`FoamError`] where the blended field cannot be built over a cellwise run's field.
pub fn sensitivity<I, F, B, J>(
    case: &Case<'_, I, F, B, J>,
    seed: u64,
    run_on: Reconstruction<'_>,
    records: &[ParticleRecord<J::Law>],
    sample: u64,
) -> Result<Sensitivity, FoamError>
where
    I: Stepper<Softness<J::Law>, J::Drag> + std::fmt::Debug,
    F: FlowField + ?Sized,
    B: Boundary + ?Sized,
    J: Injector,
{
    let (run_field, other_field, other): (_, _, Retrack<'_, J::Law>) = match run_on {
        Reconstruction::Blended(blended) => (
            "blended",
            "cellwise",
            Box::new(move |runs| retrack(case, seed, blended.cellwise(), runs)),
        ),
        Reconstruction::Cellwise(cells) => {
            let blended = BlendedFlow::new(cells.clone())?;
            (
                "cellwise",
                "blended",
                Box::new(move |runs| retrack(case, seed, &blended, runs)),
            )
        }
    };
    let mut sorted: Vec<&ParticleRecord<J::Law>> = records.iter().collect();
    sorted.sort_by_key(|r| r.index);
    let run_steps: u64 = records.iter().map(|r| r.stats.steps).sum();
    let mut fates: Vec<Fate> = Vec::new();
    let grown = grow(
        usize::try_from(sample).unwrap_or(usize::MAX),
        sorted.len(),
        STEP_BUDGET * run_steps as f64,
        |range| {
            let runs = &sorted[range];
            let other_fates = other(runs);
            let looked = runs
                .iter()
                .zip(&other_fates)
                .map(|(r, (o, steps))| {
                    // A failure in the run is counted in `failed_in_run`; one in the re-track
                    // is undecided.
                    let pair = match (&r.fate, o) {
                        (Fate::Failed { .. }, _) => Look::FailedInRun,
                        (_, Fate::Failed { .. }) => Look::Undecided,
                        (run, other) => Look::Paired(deposited(run), deposited(other)),
                    };
                    (pair, *steps)
                })
                .collect();
            fates.extend(other_fates.into_iter().map(|(o, _)| o));
            looked
        },
    );
    let chosen = &sorted[..grown.sample];
    let deposited_in_run = records.iter().filter(|r| deposited(&r.fate)).count() as u64;
    let pairing = grown.pairing;
    let (difference, stderr) = pairing.difference();
    Ok(Sensitivity {
        run_field,
        other_field,
        pairing,
        undecided: grown.undecided,
        failed_in_run: failures_by_patch(run_on.cells(), chosen),
        run_fraction: binomial::fraction(pairing.both + pairing.only_ours, pairing.n()),
        other_fraction: binomial::fraction(pairing.both + pairing.only_peer, pairing.n()),
        run_stderr: binomial::stderr(deposited_in_run, records.len() as u64),
        difference,
        stderr,
        sigmas: grown.sigmas,
        warning: grown.stop == Stop::Resolved,
        detectable: grown.detectable,
        looks: grown.looks,
        stop: grown.stop,
        steps: (grown.steps, run_steps),
        particles: chosen
            .iter()
            .zip(&fates)
            .map(|(r, o)| Retracked {
                index: r.index,
                run: r.fate.label(),
                other: o.label(),
            })
            .collect(),
    })
}

/// One re-tracked particle as the sequential rule sees it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Look {
    /// Deposited in the run, deposited on the other field.
    Paired(bool, bool),
    /// The re-track did not finish: left out of the pairing.
    Undecided,
    /// The particle failed in the run: left out of the pairing.
    FailedInRun,
}

/// Where the sequential re-track stopped ([`grow`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Grown {
    /// Particles re-tracked (the first, by index).
    pub sample: usize,
    /// Their pairing.
    pub pairing: Pairing,
    /// Re-tracks that did not finish.
    pub undecided: u64,
    /// Looks taken.
    pub looks: u32,
    /// The warning bound in paired standard errors.
    pub sigmas: f64,
    /// The smallest shift detected with 80 % power ([`detectable`]).
    pub detectable: f64,
    /// Why it stopped.
    pub stop: Stop,
    /// Accepted steps of the re-track.
    pub steps: u64,
}

/// The sequential rule (module docs, *How large a sample*) over `total` particles: `retrack`
/// gives the particles of an index range as [`Look`]s with their accepted steps; the first
/// look takes min(`first`, `total`), each next one doubles the sample, within `budget` steps.
/// At most ⌈log₂(total/first)⌉ + 1 looks, so the loop is bounded by the run's size.
pub fn grow(
    first: usize,
    total: usize,
    budget: f64,
    mut retrack: impl FnMut(std::ops::Range<usize>) -> Vec<(Look, u64)>,
) -> Grown {
    let mut sizes = vec![first.min(total)];
    while let Some(&n) = sizes.last().filter(|&&n| n > 0 && n < total) {
        sizes.push(n.saturating_mul(2).min(total));
    }
    let sigmas = warn_sigmas(u32::try_from(sizes.len()).unwrap_or(u32::MAX));
    let mut grown = Grown {
        sample: 0,
        pairing: Pairing::default(),
        undecided: 0,
        looks: 0,
        sigmas,
        detectable: f64::INFINITY,
        stop: Stop::AllParticles,
        steps: 0,
    };
    for (k, &n) in sizes.iter().enumerate() {
        for (look, s) in retrack(grown.sample..n) {
            grown.steps = grown.steps.saturating_add(s);
            match look {
                Look::Paired(run, other) => grown.pairing.add(run, other),
                Look::Undecided => grown.undecided += 1,
                Look::FailedInRun => {}
            }
        }
        grown.sample = n;
        grown.looks = u32::try_from(k + 1).unwrap_or(u32::MAX);
        grown.detectable = detectable(&grown.pairing, sigmas);
        let (difference, stderr) = grown.pairing.difference();
        // The next look's cost, predicted from this one's steps per particle.
        let over_budget = sizes
            .get(k + 1)
            .is_some_and(|&m| grown.steps as f64 * m as f64 / n.max(1) as f64 > budget);
        let discordant = grown.pairing.only_ours + grown.pairing.only_peer;
        let stop = if discordant > 0 && difference.abs() > sigmas * stderr {
            Some(Stop::Resolved)
        } else if grown.detectable <= RESOLVE {
            Some(Stop::Bounded)
        } else if over_budget {
            Some(Stop::Budget)
        } else {
            None
        };
        if let Some(stop) = stop {
            return Grown { stop, ..grown };
        }
    }
    // Every look taken: every particle is in.
    grown
}

/// The run's failures among `chosen`, by the patch of `cells`' mesh nearest to where each
/// failed (its last accepted state), most first.
fn failures_by_patch<L>(cells: &FoamFlow, chosen: &[&ParticleRecord<L>]) -> Vec<(String, String, u64)> {
    let mesh = cells.mesh();
    let set = crate::flow::openfoam::PatchSet::all(mesh);
    let mut counts: Vec<(String, String, u64)> = Vec::new();
    for r in chosen.iter().filter(|r| matches!(r.fate, Fate::Failed { .. })) {
        let (name, kind) = r
            .end
            .and_then(|end| set.nearest_face(&end.x))
            .map_or(("(not started)".to_string(), "-".to_string()), |(_, p, _)| {
                (mesh.patches()[p].name.clone(), mesh.patches()[p].kind.clone())
            });
        match counts.iter_mut().find(|(n, _, _)| *n == name) {
            Some(c) => c.2 += 1,
            None => counts.push((name, kind, 1)),
        }
    }
    counts.sort_by_key(|c| std::cmp::Reverse(c.2));
    counts
}

/// Whether `fate` is a deposit.
fn deposited(fate: &Fate) -> bool {
    matches!(fate, Fate::Deposited { .. })
}

/// The fates (and accepted steps) of the particles of `runs` on `flow` instead of the case's:
/// the same injection (drawn and started on the case's field, so each starts where it started
/// in the run), integrator, boundary, contact and plan, with at most [`RETRACK_STEP_FACTOR`]
/// times the particle's steps in the run plus [`RETRACK_STEP_FLOOR`] (beyond: `Failed`,
/// undecided), in parallel on the current rayon pool.
fn retrack<I, F, B, J, G>(
    case: &Case<'_, I, F, B, J>,
    seed: u64,
    flow: &G,
    runs: &[&ParticleRecord<J::Law>],
) -> Vec<(Fate, u64)>
where
    I: Stepper<Softness<J::Law>, J::Drag> + std::fmt::Debug,
    F: FlowField + ?Sized,
    B: Boundary + ?Sized,
    J: Injector,
    G: FlowField + ?Sized,
{
    let budget = case.plan().budget();
    runs.par_iter()
        .map(|r| {
            let steps = r
                .stats
                .steps
                .saturating_mul(RETRACK_STEP_FACTOR)
                .saturating_add(RETRACK_STEP_FLOOR);
            let plan = case.plan().clone().with_budget(Budget {
                max_steps: steps.min(budget.max_steps),
                ..budget
            });
            let record = case.on(flow, plan).run_particle(seed, r.index);
            (record.fate, record.stats.steps)
        })
        .collect()
}

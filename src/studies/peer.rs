//! OpenFOAM's own particle tracker as a peer, driven from Rust, and the race between it and
//! pseudorigid on the same particles (issue 23, "time to result").
//!
//! # The peer
//! `benches/peers/openfoam_tracker/run.sh` tracks given spheres with OpenFOAM v1912's
//! `icoUncoupledKinematicParcelFoam` on a solved case's frozen field (sphereDrag in its Stokes
//! limit, cellPoint interpolation, the analytical velocity update over sub-steps of at most
//! 0.3 of a cell, outer steps of 10⁻⁴ s, every patch removing the parcel; its README).
//! [`OpenFoamTracker::run`] writes the particles (`index,x,y,z,u,v,w,d,rho`, SI), runs the
//! script and reads back every particle's fate ([`crate::population::peer`]) and what the run
//! cost ([`TrackerSummary`]). The airway and the airway tree (`examples/openfoam_peer.rs`,
//! `studies::airway_tree::peer`), the bend
//! (`examples/bend_deposition.rs --peer`) and the race (`examples/openfoam_race.rs`) run it
//! through here.
//!
//! # What the race measures ([`RaceRow`])
//! Per tracker, on the same N particles of the same field:
//! - **particle-steps**: ours, the accepted steps summed over the particles
//!   ([`crate::driver::RunStats::steps`]; rejected attempts are apart, in `rejected`);
//!   OpenFOAM, the parcel outer steps Σₖ Nₖ₋₁ (Nₖ the parcels left after outer step k, from
//!   the cloud's report in the log, N₀ the injected ones). v1912 counts no finer unit: each
//!   parcel outer step is at least one sub-step (one force evaluation and analytical velocity
//!   update) and is split further where the 0.3-cell limit or a face crossing ends a sub-step,
//!   so its sub-steps are at least this count.
//! - **wall time**: ours, reading the case (mesh, field, wall grid) and tracking every
//!   particle to its fate; OpenFOAM, its tracking process (reading the case, tracking, writing
//!   its log; the injection phase that only locates the parcels is left out). On a shared
//!   machine both depend on the load; the **CPU time** (user + system of the process:
//!   OpenFOAM's `ExecutionTime`, ours from `/proc/self/stat` around the run) depends on it
//!   much less, and for one thread it is the per-core cost.
//! - **CPU time, loading and tracking apart** ([`CpuSplit`]): ours, parsing the scene (reading
//!   the mesh and field, building the wall grid) and then the population run; OpenFOAM's
//!   tracking process up to the start of its time loop (reading the mesh, U, phi and the
//!   cloud) and after it (`run.sh` measures both from outside the process: `/proc/<pid>/stat`
//!   when the log says `Starting time loop`, the rusage at exit). The loading is the fixed
//!   cost of a run; the tracking's cost per particle is what more particles cost. OpenFOAM's
//!   two parts add up to more than its `ExecutionTime` (the race's `cpu_s`): that clock starts
//!   after the process has loaded its libraries (about 0.08 s) and stops at the last time step.
//! - **DE** = deposited / finished (particles neither failed nor left uninjected), with the
//!   binomial standard error √(DE(1 − DE)/n); what counts as deposited is the scene's (the
//!   bend: on `wall_bend`).
//! - **paired fates** against OpenFOAM ([`Pairing`]): both, ours only, OpenFOAM only,
//!   neither; the paired difference DE_ours − DE_openfoam with its McNemar standard error.

use crate::population::peer::{Pairing, PeerError, PeerFate, paired_with_peer, read_peer_fates};
use crate::population::progress::process_cpu_seconds;
use crate::population::{Fate, ParticleRecord, RunOutput};
use crate::tensor::Vec3;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;
use thiserror::Error;

/// What the peer needs of one particle: where it starts, how fast, its size and density (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PeerParticle {
    /// Barycentre at injection (m).
    pub position: Vec3,
    /// Initial velocity (m/s).
    pub velocity: Vec3,
    /// Diameter (m) (the volume-equivalent one).
    pub diameter: f64,
    /// Density (kg/m³).
    pub density: f64,
}

/// The peer's input: `index,x,y,z,u,v,w,d,rho`, particle k as row k.
pub fn particles_csv(particles: &[PeerParticle]) -> String {
    let mut csv = String::from("index,x,y,z,u,v,w,d,rho\n");
    for (k, p) in particles.iter().enumerate() {
        let (x, u) = (p.position, p.velocity);
        // Writing to a String cannot fail. `{}` of an f64 is its shortest round-trip text.
        let _ = writeln!(
            csv,
            "{k},{},{},{},{},{},{},{},{}",
            x.x, x.y, x.z, u.x, u.y, u.z, p.diameter, p.density
        );
    }
    csv
}

/// Failures of a peer run.
#[derive(Debug, Error)]
pub enum PeerRunError {
    /// A file or folder could not be written or read, or the script not started.
    #[error("{path}: {source}")]
    Io {
        /// The file, folder or script.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The script ran and failed (its message is on standard error).
    #[error("{script} failed ({status})")]
    Script {
        /// The script.
        script: PathBuf,
        /// Its exit status.
        status: String,
    },
    /// The script's `summary.txt` lacks a value or has a malformed one.
    #[error("{path}: {source}")]
    Summary {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        source: TrackerSummaryError,
    },
    /// The script's `fates.csv` could not be read.
    #[error(transparent)]
    Fates(#[from] PeerError),
    /// A particle of ours has no fate in the peer's file.
    #[error("particle {index} is missing from the peer's fates")]
    Missing {
        /// Its index.
        index: u64,
    },
}

/// A `key=value` line of the tracker's `summary.txt` that is missing or does not parse
/// ([`TrackerSummary::parse`]).
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum TrackerSummaryError {
    /// No line `key=...`.
    #[error("no `{key}=`")]
    Missing {
        /// The key.
        key: &'static str,
    },
    /// The value of `key` is not a number of the key's kind.
    #[error("`{key}={value}`: {reason}")]
    Malformed {
        /// The key.
        key: &'static str,
        /// Its value, trimmed.
        value: String,
        /// The number parser's message.
        reason: String,
    },
}

/// OpenFOAM's tracker for one case: the script, and the tracking time, gravity and fluid
/// density the case's own scene uses (a kinematic case has no density of its own).
#[derive(Debug, Clone, PartialEq)]
pub struct OpenFoamTracker {
    /// `benches/peers/openfoam_tracker/run.sh`.
    pub script: PathBuf,
    /// Tracking time (s) (`END_TIME`).
    pub end_time: f64,
    /// Gravity (m/s²) (`GRAVITY`).
    pub gravity: Vec3,
    /// Fluid density (kg/m³) (`FLUID_RHO`).
    pub fluid_density: f64,
    /// Kinematic viscosity (m²/s) (`NU`) for a case without `constant/transportProperties`
    /// (the shipped fields of `reference-data` keep only the mesh and U); `None`: the case's.
    pub viscosity: Option<f64>,
}

/// The fates and the cost of one run of the peer.
#[derive(Debug, Clone, PartialEq)]
pub struct OpenFoamRun {
    /// Fate of every particle, by index.
    pub fates: HashMap<u64, PeerFate>,
    /// What the run cost.
    pub summary: TrackerSummary,
}

/// What `run.sh` reports of its run (`summary.txt`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackerSummary {
    /// Wall time of both phases (injection and tracking) and the script's helpers (s).
    pub wall_seconds: f64,
    /// Wall time of the tracking process alone (s).
    pub track_wall_seconds: f64,
    /// CPU time of the tracking process (its last `ExecutionTime`) (s).
    pub cpu_seconds: f64,
    /// CPU time of the tracking process split where its time loop starts: reading the mesh,
    /// U, phi and the cloud, then the time loop (tracking, writing) (user + system, from
    /// `/proc` and the process's rusage; `peer.py timed`).
    pub cpu: CpuSplit,
    /// CPU time of the injection process (it reads the case, injects the parcels, locates them
    /// in the mesh and writes the cloud) (s).
    pub inject_cpu_seconds: f64,
    /// Outer time steps.
    pub outer_steps: u64,
    /// Parcel outer steps Σₖ Nₖ₋₁ (module docs).
    pub parcel_steps: u64,
}

impl TrackerSummary {
    /// Read the `key=value` lines of `summary.txt`.
    pub fn parse(text: &str) -> Result<Self, TrackerSummaryError> {
        fn get<T: std::str::FromStr>(text: &str, key: &'static str) -> Result<T, TrackerSummaryError>
        where
            T::Err: std::fmt::Display,
        {
            let value = text
                .lines()
                .find_map(|l| l.strip_prefix(key).and_then(|v| v.strip_prefix('=')))
                .ok_or(TrackerSummaryError::Missing { key })?
                .trim();
            value.parse().map_err(|e: T::Err| TrackerSummaryError::Malformed {
                key,
                value: value.to_string(),
                reason: e.to_string(),
            })
        }
        Ok(Self {
            wall_seconds: get(text, "wall_seconds")?,
            track_wall_seconds: get(text, "track_wall_seconds")?,
            cpu_seconds: get(text, "execution_seconds")?,
            cpu: CpuSplit {
                load_seconds: get(text, "load_cpu_seconds")?,
                track_seconds: get(text, "track_cpu_seconds")?,
            },
            inject_cpu_seconds: get(text, "inject_cpu_seconds")?,
            outer_steps: get(text, "time_steps")?,
            parcel_steps: get(text, "parcel_steps")?,
        })
    }
}

impl OpenFoamTracker {
    /// The tracker of the repository at `root` (its `benches/peers/openfoam_tracker/run.sh`).
    pub fn new(
        root: &Path,
        end_time: f64,
        gravity: Vec3,
        fluid_density: f64,
    ) -> Result<Self, crate::error::ParamError> {
        crate::error::positive("tracking time", end_time)?;
        crate::error::positive("fluid density", fluid_density)?;
        // A NaN or infinite component makes the norm NaN or infinite.
        crate::error::finite("gravity", gravity.norm())?;
        Ok(Self {
            script: root.join("benches/peers/openfoam_tracker/run.sh"),
            end_time,
            gravity,
            fluid_density,
            viscosity: None,
        })
    }

    /// The same tracker with the fluid's kinematic viscosity `nu` given (> 0) instead of read
    /// from the case.
    pub fn with_viscosity(self, nu: f64) -> Result<Self, crate::error::ParamError> {
        Ok(Self {
            viscosity: Some(crate::error::positive("kinematic viscosity", nu)?),
            ..self
        })
    }

    /// Track `particles` (particle k is index k) through the solved case `case_dir`: writes
    /// `work/particles.csv`, runs the script into `work/openfoam` (its case and logs stay
    /// there) and reads its fates and summary. OpenFOAM runs serially.
    pub fn run(&self, case_dir: &Path, particles: &[PeerParticle], work: &Path) -> Result<OpenFoamRun, PeerRunError> {
        let io = |path: &Path| {
            let path = path.to_path_buf();
            move |source| PeerRunError::Io { path, source }
        };
        std::fs::create_dir_all(work).map_err(io(work))?;
        let input = work.join("particles.csv");
        std::fs::write(&input, particles_csv(particles)).map_err(io(&input))?;
        let out = work.join("openfoam");
        let g = self.gravity;
        let mut command = Command::new("sh");
        let _ = command
            .arg(&self.script)
            .arg(case_dir)
            .arg(&input)
            .arg(&out)
            .env("END_TIME", format!("{:e}", self.end_time))
            .env("GRAVITY", format!("({:e} {:e} {:e})", g.x, g.y, g.z))
            .env("FLUID_RHO", format!("{:e}", self.fluid_density));
        if let Some(nu) = self.viscosity {
            let _ = command.env("NU", format!("{nu:e}"));
        }
        let status = command.status().map_err(io(&self.script))?;
        if !status.success() {
            return Err(PeerRunError::Script {
                script: self.script.clone(),
                status: status.to_string(),
            });
        }
        let fates = read_peer_fates(&out.join("fates.csv"))?;
        let path = out.join("summary.txt");
        let text = std::fs::read_to_string(&path).map_err(io(&path))?;
        let summary = TrackerSummary::parse(&text).map_err(|source| PeerRunError::Summary { path, source })?;
        Ok(OpenFoamRun { fates, summary })
    }
}

/// Wall and CPU time of some work.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cost {
    /// Wall time (s).
    pub wall_seconds: f64,
    /// CPU time of the process over the same span (s) (`None` where `/proc` is missing).
    pub cpu_seconds: Option<f64>,
}

impl Cost {
    /// The cost of this work followed by `next`: wall and CPU times added (no CPU time if
    /// either lacks it).
    pub fn then(self, next: Cost) -> Cost {
        Cost {
            wall_seconds: self.wall_seconds + next.wall_seconds,
            cpu_seconds: self.cpu_seconds.zip(next.cpu_seconds).map(|(a, b)| a + b),
        }
    }
}

/// A tracker's CPU time (user + system, s) split into loading the case (mesh, field and what
/// is built from them before the first particle moves) and tracking the particles: the
/// loading is the fixed cost of a run, the tracking grows with the particles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CpuSplit {
    /// Loading the case (s).
    pub load_seconds: f64,
    /// Tracking (s).
    pub track_seconds: f64,
}

impl CpuSplit {
    /// From the measured costs of loading and of tracking (`None` if either has no CPU time).
    pub fn of(load: Cost, track: Cost) -> Option<Self> {
        Some(Self {
            load_seconds: load.cpu_seconds?,
            track_seconds: track.cpu_seconds?,
        })
    }

    /// Loading and tracking (s).
    pub fn total(&self) -> f64 {
        self.load_seconds + self.track_seconds
    }
}

/// How a race row of ours was run: the particle model, the integrator and its settings, the
/// threads, and what the run cost ([`RaceRow::pseudorigid`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Entrant<'a> {
    /// The particle model (`rigid`, `neo_hooke mu_s=… Pa`).
    pub particle: &'a str,
    /// The integrator and its settings.
    pub integrator: &'a str,
    /// Threads the run used.
    pub threads: usize,
    /// Its wall and CPU time, loading and tracking.
    pub cost: Cost,
    /// Its CPU time split into loading and tracking, if measured.
    pub cpu: Option<CpuSplit>,
}

/// Run `work` and measure its [`Cost`]. The CPU time is the whole process's: run nothing else
/// meanwhile.
pub fn timed<T>(work: impl FnOnce() -> T) -> (T, Cost) {
    let cpu0 = process_cpu_seconds();
    let start = Instant::now();
    let out = work();
    let wall_seconds = start.elapsed().as_secs_f64();
    let cpu_seconds = cpu0.zip(process_cpu_seconds()).map(|(a, b)| b - a);
    (
        out,
        Cost {
            wall_seconds,
            cpu_seconds,
        },
    )
}

/// The line cost = fixed + N × marginal through the points `(N, cost)` by least squares with
/// weights 1/N (the variance of a sum of N particles' costs grows as N, so the runs of many
/// particles do not drown the few-particle ones that fix the intercept): `(fixed, marginal)`.
/// `None` unless the points hold two distinct N, every N > 0.
pub fn marginal_fit(points: &[(u64, f64)]) -> Option<(f64, f64)> {
    if points.iter().any(|&(n, _)| n == 0) {
        return None;
    }
    let (mut s, mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for &(n, y) in points {
        let (x, w) = (n as f64, 1.0 / n as f64);
        s += w;
        sx += w * x;
        sy += w * y;
        sxx += w * x * x;
        sxy += w * x * y;
    }
    let det = s * sxx - sx * sx;
    // Relative to the scale of the N: one distinct N leaves det at round-off.
    if points.is_empty() || !(det > 1e-9 * s * sxx) {
        return None;
    }
    let marginal = (s * sxy - sx * sy) / det;
    Some(((sy - marginal * sx) / s, marginal))
}

/// One tracker's line of the race (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct RaceRow {
    /// `openfoam` or `pseudorigid`.
    pub tracker: String,
    /// The particles' response: `rigid` or the law (`neo_hooke mu_s=1`).
    pub particle: String,
    /// The time integrator, with its tolerance or steps.
    pub integrator: String,
    /// Threads the tracker ran on.
    pub threads: usize,
    /// Particles given.
    pub particles: u64,
    /// Particle-steps.
    pub steps: u64,
    /// What [`RaceRow::steps`] counts: `accepted steps` or `parcel outer steps`.
    pub steps_unit: String,
    /// Rejected step attempts (ours; `None` for OpenFOAM, which rejects none).
    pub rejected: Option<u64>,
    /// Wall and CPU time.
    pub cost: Cost,
    /// CPU time split into loading the case and tracking, if measured.
    pub cpu: Option<CpuSplit>,
    /// Deposited (the scene's rule).
    pub deposited: u64,
    /// Particles with a fate: neither failed nor left uninjected.
    pub finished: u64,
    /// Still inside at the end time.
    pub suspended: u64,
    /// Fates against OpenFOAM's, particle by particle (`None` for OpenFOAM's own row).
    pub pairing: Option<Pairing>,
}

impl RaceRow {
    /// OpenFOAM's row: `n` particles given, `deposited` says which of its fates count.
    pub fn openfoam(run: &OpenFoamRun, n: u64, integrator: &str, deposited: impl Fn(&PeerFate) -> bool) -> Self {
        let fates = run.fates.values();
        let finished = fates.clone().filter(|f| f.fate != "not_injected").count() as u64;
        Self {
            tracker: "openfoam".into(),
            particle: "rigid".into(),
            integrator: integrator.into(),
            threads: 1,
            particles: n,
            steps: run.summary.parcel_steps,
            steps_unit: "parcel outer steps".into(),
            rejected: None,
            cost: Cost {
                wall_seconds: run.summary.track_wall_seconds,
                cpu_seconds: Some(run.summary.cpu_seconds),
            },
            cpu: Some(run.summary.cpu),
            deposited: fates.clone().filter(|f| deposited(f)).count() as u64,
            finished,
            suspended: fates.filter(|f| f.fate == "suspended").count() as u64,
            pairing: None,
        }
    }

    /// Our row from the records of `entrant`'s run `out`: `deposited` says which records count
    /// (given the run's patch names); paired particle by particle with `peer`'s fates (every
    /// particle of ours must have one) under `peer_deposited`.
    pub fn pseudorigid<L>(
        entrant: Entrant<'_>,
        out: &RunOutput<L>,
        deposited: impl Fn(&ParticleRecord<L>, &[String]) -> bool,
        peer: &HashMap<u64, PeerFate>,
        peer_deposited: impl Fn(&PeerFate) -> bool,
    ) -> Result<Self, PeerRunError> {
        let mut pairing = Pairing::default();
        let (mut dep, mut finished, mut suspended, mut steps, mut rejected) = (0, 0, 0, 0, 0);
        let pairs = paired_with_peer(&out.records, peer).map_err(|e| PeerRunError::Missing { index: e.index })?;
        for (r, p) in pairs {
            let ours = deposited(r, &out.patches);
            pairing.add(ours, peer_deposited(p));
            dep += u64::from(ours);
            finished += u64::from(!matches!(r.fate, Fate::Failed { .. }));
            suspended += u64::from(matches!(r.fate, Fate::Suspended));
            steps += r.stats.steps;
            rejected += r.stats.rejected;
        }
        let Entrant {
            particle,
            integrator,
            threads,
            cost,
            cpu,
        } = entrant;
        Ok(Self {
            tracker: "pseudorigid".into(),
            particle: particle.into(),
            integrator: integrator.into(),
            threads,
            particles: out.records.len() as u64,
            steps,
            steps_unit: "accepted steps".into(),
            rejected: Some(rejected),
            cost,
            cpu,
            deposited: dep,
            finished,
            suspended,
            pairing: Some(pairing),
        })
    }

    /// DE = deposited / finished (0 if none finished).
    pub fn de(&self) -> f64 {
        crate::population::binomial::fraction(self.deposited, self.finished)
    }

    /// Binomial standard error √(DE(1 − DE)/n) over the finished particles.
    pub fn de_stderr(&self) -> f64 {
        crate::population::binomial::stderr(self.deposited, self.finished)
    }

    /// Particles that failed or were never injected.
    pub fn lost(&self) -> u64 {
        self.particles - self.finished
    }

    /// Wall time per particle (s).
    pub fn wall_per_particle(&self) -> f64 {
        self.cost.wall_seconds / self.particles.max(1) as f64
    }

    /// CPU time per particle (s), if measured.
    pub fn cpu_per_particle(&self) -> Option<f64> {
        self.cost.cpu_seconds.map(|c| c / self.particles.max(1) as f64)
    }

    /// Tracking CPU time per particle (s), loading left out, if measured.
    pub fn cpu_track_per_particle(&self) -> Option<f64> {
        self.cpu.map(|c| c.track_seconds / self.particles.max(1) as f64)
    }
}

/// The columns of [`race_csv`].
pub const RACE_COLUMNS: [&str; 28] = [
    "tracker",
    "particle",
    "integrator",
    "threads",
    "particles",
    "particle_steps",
    "steps_unit",
    "steps_per_particle",
    "rejected",
    "wall_s",
    "cpu_s",
    "wall_per_particle_ms",
    "cpu_per_particle_ms",
    "cpu_load_s",
    "cpu_track_s",
    "cpu_track_per_particle_ms",
    "deposited",
    "finished",
    "suspended",
    "lost",
    "de",
    "de_stderr",
    "both",
    "only_ours",
    "only_openfoam",
    "neither",
    "de_difference",
    "se_paired",
];

/// The race as CSV ([`RACE_COLUMNS`]; empty fields where a value does not apply or was not
/// measured; a comma in a label becomes a semicolon, as the table is not quoted).
pub fn race_csv(rows: &[RaceRow]) -> Result<crate::output::Csv, crate::output::OutputError> {
    let mut csv = crate::output::Csv::new(&RACE_COLUMNS);
    let opt = |x: Option<String>| x.unwrap_or_default();
    let text = |x: &str| x.replace(',', ";");
    for r in rows {
        let pair = r.pairing.map(|p| (p, p.difference()));
        csv.push(vec![
            text(&r.tracker),
            text(&r.particle),
            text(&r.integrator),
            r.threads.to_string(),
            r.particles.to_string(),
            r.steps.to_string(),
            text(&r.steps_unit),
            format!("{:.1}", r.steps as f64 / r.particles.max(1) as f64),
            opt(r.rejected.map(|x| x.to_string())),
            format!("{:.2}", r.cost.wall_seconds),
            opt(r.cost.cpu_seconds.map(|c| format!("{c:.2}"))),
            format!("{:.3}", 1e3 * r.wall_per_particle()),
            opt(r.cpu_per_particle().map(|c| format!("{:.3}", 1e3 * c))),
            opt(r.cpu.map(|c| format!("{:.2}", c.load_seconds))),
            opt(r.cpu.map(|c| format!("{:.2}", c.track_seconds))),
            opt(r.cpu_track_per_particle().map(|c| format!("{:.3}", 1e3 * c))),
            r.deposited.to_string(),
            r.finished.to_string(),
            r.suspended.to_string(),
            r.lost().to_string(),
            format!("{:.4}", r.de()),
            format!("{:.4}", r.de_stderr()),
            opt(pair.map(|(p, _)| p.both.to_string())),
            opt(pair.map(|(p, _)| p.only_ours.to_string())),
            opt(pair.map(|(p, _)| p.only_peer.to_string())),
            opt(pair.map(|(p, _)| p.neither.to_string())),
            opt(pair.map(|(_, (d, _))| format!("{d:.4}"))),
            opt(pair.map(|(_, (_, s))| format!("{s:.4}"))),
        ])?;
    }
    Ok(csv)
}

/// The race as a Markdown table: per tracker, particle-steps, wall and CPU time (in total and
/// per particle; the CPU time also as loading / tracking), DE ± standard error and the paired fates against OpenFOAM.
pub fn race_markdown(rows: &[RaceRow]) -> String {
    let mut s = String::from(
        "| tracker | particle | integrator | threads | N | particle-steps | steps/particle | wall s | CPU s | wall ms/particle | CPU ms/particle | CPU s load / track | DE ± se | lost | both / ours only / OpenFOAM only / neither | paired difference |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let cpu = r.cost.cpu_seconds.map_or("n/a".into(), |c| format!("{c:.2}"));
        let cpu_pp = r.cpu_per_particle().map_or("n/a".into(), |c| format!("{:.2}", 1e3 * c));
        let split = r.cpu.map_or("n/a".into(), |c| {
            format!("{:.2} / {:.2}", c.load_seconds, c.track_seconds)
        });
        let (pairs, diff) = match r.pairing {
            Some(p) => {
                let (d, se) = p.difference();
                (
                    format!("{} / {} / {} / {}", p.both, p.only_ours, p.only_peer, p.neither),
                    format!("{d:+.3} ± {se:.3}"),
                )
            }
            None => ("(reference)".into(), String::new()),
        };
        // Writing to a String cannot fail.
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} ({}) | {:.0} | {:.2} | {cpu} | {:.2} | {cpu_pp} | {split} | {:.3} ± {:.3} | {} | {pairs} | {diff} |",
            r.tracker,
            r.particle,
            r.integrator,
            r.threads,
            r.particles,
            r.steps,
            r.steps_unit,
            r.steps as f64 / r.particles.max(1) as f64,
            r.cost.wall_seconds,
            1e3 * r.wall_per_particle(),
            r.de(),
            r.de_stderr(),
            r.lost()
        );
    }
    s
}

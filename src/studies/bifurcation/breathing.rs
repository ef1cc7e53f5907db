//! A breathing cycle in the bifurcation (issue 24, item 3): particles inhaled with a
//! sinusoidal flow rate through the transient field of `cases/bifurcation-breathing`, against
//! the steady inhalation of paper §6.4 on the same particles.
//!
//! # Physics
//! The inhalation half of a sinusoidal breath of period T (at rest, 15 breaths a minute:
//! T = 4 s) drives the parent's uniform inlet with
//! ```math
//! U_{in}(t) = U_p \sin(\omega t), \qquad \omega = 2\pi/T, \qquad 0 \le t \le T/2,
//! \qquad U_p = \tfrac{\pi}{2} U,
//! ```
//! so the mean over the inhalation is the steady case's U = 1.2425 m/s (Re = 500) and the
//! peak Reynolds number is 785. The Womersley number
//! ```math
//! \alpha = R\sqrt{\omega/\nu} = 0.97
//! ```
//! (R = 3 mm, ν = 1.491e-5 m²/s) says the viscous diffusion time R²/ν = 0.6 s is about the
//! time 1/ω = 0.64 s in which the flow rate changes: the flow is nearly quasi-steady, and the
//! convective time L/U = 0.03 s is shorter still.
//!
//! # Injection
//! The inhaled air carries a constant aerosol concentration c, so particles cross the inlet at
//! the rate c Q(t), proportional to sin ωt. A particle's injection time has the distribution
//! function F(t) = (1 − cos ωt)/2 over the inhalation and is drawn by its inverse,
//! $t = \arccos(1 - 2u)/\omega$, from a uniform u of the particle's own generator after its
//! steady draw (`Injector::injection`): particle k has the disc point, orientation and
//! shape of the steady study's particle k, and the two runs are paired particle by particle.
//! Its velocity is the steady field's at the injection point scaled by $U_{in}(t)/U$: the
//! inlet is uniform in both fields, and the particle relaxes to the transient field's velocity
//! in its response time (1.9 ms at Stk 0.4), 0.1 % of the inhalation.
//!
//! # Tracking
//! Particles are tracked through the solved inhalation, to t = T/2; the exhalation is not
//! solved, and a particle still inside at its end is suspended. The field holds two levels at
//! a time ([`TransientFlow`]): the batch runner advances every live particle to the next
//! written level, then slides the window.

use super::BifurcationError;
use super::injection::{Injection, Kind};
use super::setup::{Airway, LENGTH, NU, RADIUS, inlet_velocity};
use super::study::{DT0, MAX_STEPS, integrator};
use crate::contact::MeshBoundary;
use crate::driver::{Budget, Plan};
use crate::error::{ParamError, StepError};
use crate::flow::openfoam::{BlendedFlow, Cycle, FoamCase, FoamError, Precision, TransientFlow};
use crate::hydro::Brenner;
use crate::material::{NeoHooke, Softness};
use crate::output::{Csv, Figure, Panel, Series};
use crate::particle::Particle;
use crate::particle::State;
use crate::population::batch::{Batch, run_batch};
use crate::population::binomial::PairedFates;
use crate::population::{
    Fate, Injector, ParticleRng, ParticleSpec, RunConfig, RunOptions, RunOutput, Shard, particle_rng,
};
use rand::RngExt;
use serde::Serialize;
use std::f64::consts::PI;
use std::path::Path;

/// Period T of the breath at rest (s): 15 breaths a minute.
pub const PERIOD: f64 = 4.0;

/// Womersley number α = R√(ω/ν) of the parent at [`PERIOD`] (module docs).
pub fn womersley_number() -> f64 {
    RADIUS * (2.0 * PI / PERIOD / NU).sqrt()
}

/// How the inlet velocity changes over one inhalation, relative to the steady U.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum Waveform {
    /// The first half of a sine of this period, with peak (π/2) U (module docs).
    Sine {
        /// Period T of the breath (s).
        period: f64,
    },
    /// The steady U for this long: the steady field with particles entering uniformly in
    /// time, which must give the steady study's fates (a check of the machinery).
    Constant {
        /// Duration of the inhalation (s).
        duration: f64,
    },
}

impl Waveform {
    /// The breath at rest: a sine of period [`PERIOD`].
    pub fn rest() -> Self {
        Waveform::Sine { period: PERIOD }
    }

    /// The inhalation's duration: T/2 for a sine.
    pub fn duration(self) -> f64 {
        match self {
            Waveform::Sine { period } => 0.5 * period,
            Waveform::Constant { duration } => duration,
        }
    }

    /// U_in(t)/U over the inhalation (0 outside it).
    pub fn scale(self, t: f64) -> f64 {
        if !(0.0..=self.duration()).contains(&t) {
            return 0.0;
        }
        match self {
            Waveform::Sine { period } => 0.5 * PI * (2.0 * PI * t / period).sin(),
            Waveform::Constant { .. } => 1.0,
        }
    }

    /// The injection time of a particle whose uniform draw is `u` ∈ [0, 1): the inverse of
    /// the distribution function of times at a rate ∝ U_in(t) (module docs).
    pub fn injection_time(self, u: f64) -> f64 {
        match self {
            Waveform::Sine { period } => (1.0 - 2.0 * u).clamp(-1.0, 1.0).acos() * period / (2.0 * PI),
            Waveform::Constant { duration } => u * duration,
        }
    }
}

/// The steady study's injection ([`Injection`]) spread over an inhalation: the same particles,
/// each entering at its own time with the fluid's velocity then (module docs).
pub struct Inhaled<'a> {
    steady: Injection<'a>,
    waveform: Waveform,
}

impl<'a> Inhaled<'a> {
    /// Particles of `kind` inhaled into `airway` (whose steady field gives the injection
    /// velocity's profile) as `waveform` says.
    pub fn new(airway: &'a Airway, kind: Kind, waveform: Waveform) -> Result<Self, ParamError> {
        Ok(Self {
            steady: Injection::new(airway, kind)?,
            waveform,
        })
    }

    /// The injection time of particle `index` of a run with seed `seed` (as the runner draws it).
    pub fn injection_time(&self, seed: u64, index: u64) -> Result<f64, StepError> {
        let mut rng = particle_rng(seed, index);
        let spec = self.steady.draw(index, &mut rng)?;
        Ok(self.injection(index, &spec, &mut rng)?.t)
    }
}

impl Injector for Inhaled<'_> {
    type Law = NeoHooke;
    type Drag = Brenner;

    fn draw(&self, index: u64, rng: &mut ParticleRng) -> Result<ParticleSpec<NeoHooke>, StepError> {
        self.steady.draw(index, rng)
    }

    fn particle(&self, spec: &ParticleSpec<NeoHooke>) -> Result<Particle<Softness<NeoHooke>, Brenner>, ParamError> {
        self.steady.particle(spec)
    }

    fn injection(&self, _index: u64, spec: &ParticleSpec<NeoHooke>, rng: &mut ParticleRng) -> Result<State, StepError> {
        let t = self.waveform.injection_time(rng.random::<f64>());
        Ok(State {
            t,
            v: spec.velocity * self.waveform.scale(t),
            ..spec.start_state()
        })
    }
}

/// The transient field of one inhalation and its boundary.
#[derive(Debug)]
pub struct Breath {
    flow: TransientFlow<BlendedFlow>,
    boundary: MeshBoundary,
    waveform: Waveform,
}

impl Breath {
    /// The levels of the case in `dir` from t = 0 to the end of `waveform`'s inhalation (made
    /// by `cases/bifurcation-breathing/Allrun`), blended as the steady field is.
    pub fn open(dir: impl AsRef<Path>, waveform: Waveform) -> Result<Self, FoamError> {
        let case = FoamCase::open(dir)?;
        let end = waveform.duration();
        let times: Vec<f64> = case
            .times()
            .into_iter()
            .filter(|&t| (0.0..=end * (1.0 + 1e-9)).contains(&t))
            .collect();
        if times.len() < 2 {
            return Err(FoamError::Field {
                path: "(time directories)".into(),
                reason: format!("a breath needs at least two levels in [0, {end}], the case has {times:?}"),
            });
        }
        let flow = TransientFlow::<BlendedFlow>::open(case, &times, Cycle::Once, Precision::F64)?;
        let boundary = MeshBoundary::new(flow.mesh())?;
        Ok(Self {
            flow,
            boundary,
            waveform,
        })
    }

    /// The window ends of a run: 0, every level inside the inhalation, and its end. Not the
    /// command's equal windows ([`crate::flow::openfoam::window_ends`]) on purpose: a window
    /// ends on a level's own time, as its directory names it, so each holds exactly the two
    /// levels around it; a multiple k·Δt of the spacing differs from a level's time in the last
    /// bits, and a window ending just past a level holds a third.
    pub fn windows(&self) -> Vec<f64> {
        let end = self.waveform.duration();
        let mut w = vec![0.0];
        w.extend(
            self.flow
                .levels()
                .iter()
                .copied()
                .filter(|&t| t > 0.0 && t < end * (1.0 - 1e-9)),
        );
        w.push(end);
        w
    }

    /// The field.
    pub fn flow(&self) -> &TransientFlow<BlendedFlow> {
        &self.flow
    }

    /// The field, to slide its window.
    pub fn flow_mut(&mut self) -> &mut TransientFlow<BlendedFlow> {
        &mut self.flow
    }

    /// Wall and exits of the case.
    pub fn boundary(&self) -> &MeshBoundary {
        &self.boundary
    }

    /// The inhalation.
    pub fn waveform(&self) -> Waveform {
        self.waveform
    }
}

/// The run of `n` particles of `kind` (seed `seed`) inhaled through `breath`, injected as
/// [`Inhaled`] with the steady field of `airway`, tracked by the steady study's integrator
/// ([`integrator`]: chosen on the steady field's numbers, so both runs step alike) to the end
/// of the inhalation, window by window. With `cache` a folder, a finished run is kept there as
/// `breath-<config hash>.json` and read back instead of rerun.
pub fn run_inhaled(
    airway: &Airway,
    breath: &mut Breath,
    kind: Kind,
    n: u64,
    seed: u64,
    options: &RunOptions,
    cache: Option<&Path>,
) -> Result<RunOutput<NeoHooke>, BifurcationError> {
    let integ = integrator(airway, kind)?.integrator;
    let inhaled = Inhaled::new(airway, kind, breath.waveform)?;
    let plan = Plan::new(breath.waveform.duration(), DT0)?.with_budget(Budget {
        max_steps: MAX_STEPS,
        wall_time: None,
    });
    let batch = Batch::new(&integ, &breath.boundary, &inhaled, plan);
    let windows = breath.windows();
    let config = RunConfig {
        seed,
        particles: n,
        fingerprint: format!(
            "bifurcation breathing {kind:?}; {:?}; injection profile {}; {}; {}",
            breath.waveform,
            airway.flow().fingerprint(),
            breath.flow.fingerprint(),
            breath.boundary.fingerprint()
        ),
    };
    let file = cache.map(|dir| dir.join(format!("breath-{}.json", batch.case(&breath.flow).config_hash(&config))));
    RunOutput::read_or_run(file.as_deref(), || {
        Ok(run_batch(
            &batch,
            &mut breath.flow,
            &windows,
            &config,
            Shard::ALL,
            options,
        )?)
    })
}

/// One particle kind run steady and inhaled: the same particles, with their injection times.
#[derive(Debug)]
pub struct Paired {
    /// The particle kind.
    pub kind: Kind,
    /// The steady study's run ([`super::study::run_kind`]).
    pub steady: RunOutput<NeoHooke>,
    /// The inhaled run ([`run_inhaled`]).
    pub cyclic: RunOutput<NeoHooke>,
    /// Injection time of each particle of the inhaled run, by index.
    pub times: Vec<f64>,
}

impl Paired {
    /// Pair `steady` and `cyclic` runs of `kind` (seed `seed`, the same particles) in `airway`
    /// inhaled as `waveform`; an error if their particles differ.
    pub fn new(
        airway: &Airway,
        kind: Kind,
        waveform: Waveform,
        seed: u64,
        steady: RunOutput<NeoHooke>,
        cyclic: RunOutput<NeoHooke>,
    ) -> Result<Self, BifurcationError> {
        let same = steady.records.len() == cyclic.records.len()
            && steady
                .records
                .iter()
                .zip(&cyclic.records)
                .all(|(a, b)| a.index == b.index && a.spec == b.spec);
        if !same {
            return Err(ParamError::OutOfRange {
                name: "paired runs (the steady and inhaled runs must hold the same particles)",
                value: cyclic.records.len() as f64,
                min: steady.records.len() as f64,
                max: steady.records.len() as f64,
            }
            .into());
        }
        let inhaled = Inhaled::new(airway, kind, waveform)?;
        let times = cyclic
            .records
            .iter()
            .map(|r| inhaled.injection_time(seed, r.index))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            kind,
            steady,
            cyclic,
            times,
        })
    }

    /// Particles deposited steady but not inhaled (`.0`) and inhaled but not steady (`.1`).
    pub fn discordant(&self) -> (u64, u64) {
        let mut d = (0, 0);
        for (a, b) in self.steady.records.iter().zip(&self.cyclic.records) {
            match (deposited(&a.fate), deposited(&b.fate)) {
                (true, false) => d.0 += 1,
                (false, true) => d.1 += 1,
                _ => {}
            }
        }
        d
    }

    /// The discordant pairs, b = deposited inhaled only and c = steady only, over the particles
    /// (at least one: without any, 0 ± 0): ΔDE = DE_cyclic − DE_steady is its
    /// [`PairedFates::difference`].
    pub fn fates(&self) -> Result<PairedFates, ParamError> {
        let (lost, gained) = self.discordant();
        PairedFates::new(gained, lost, self.steady.records.len().max(1) as u64)
    }
}

fn deposited(f: &Fate) -> bool {
    matches!(f, Fate::Deposited { .. })
}

/// μ_s for the tables: `inf` for rigid, else Pa.
fn mu_s(kind: Kind) -> String {
    crate::studies::airway_tree::study::mu_s_label(kind.material)
}

/// `shape,mu_s,stk,flow,n,n_deposited,n_escaped,n_suspended,n_failed,de,de_stderr`, a row per
/// kind and flow (`steady`, `cyclic`); DE over the particles that did not fail, binomial
/// standard error ([`crate::population::binomial`]).
pub fn de_table(pairs: &[Paired]) -> Result<Csv, BifurcationError> {
    let mut csv = Csv::new(&[
        "shape",
        "mu_s",
        "stk",
        "flow",
        "n",
        "n_deposited",
        "n_escaped",
        "n_suspended",
        "n_failed",
        "de",
        "de_stderr",
    ]);
    for p in pairs {
        for (flow, out) in [("steady", &p.steady), ("cyclic", &p.cyclic)] {
            let c = out.counts();
            let n = c.total() - c.failed;
            csv.push(vec![
                p.kind.shape.label(),
                mu_s(p.kind),
                p.kind.stokes.to_string(),
                flow.into(),
                n.to_string(),
                c.deposited.to_string(),
                c.escaped.to_string(),
                c.suspended.to_string(),
                c.failed.to_string(),
                format!("{:.5}", crate::population::binomial::fraction(c.deposited, n)),
                format!("{:.5}", crate::population::binomial::stderr(c.deposited, n)),
            ])?;
        }
    }
    Ok(csv)
}

/// `shape,mu_s,stk,n,steady_only,cyclic_only,delta_de,delta_de_stderr,paired_z`: the same
/// particles steady and inhaled, ΔDE = (cyclic_only − steady_only)/n with McNemar's standard
/// error √(steady_only + cyclic_only)/n and z = ΔDE over it ([`Paired::fates`]).
pub fn paired_table(pairs: &[Paired]) -> Result<Csv, BifurcationError> {
    let mut csv = Csv::new(&[
        "shape",
        "mu_s",
        "stk",
        "n",
        "steady_only",
        "cyclic_only",
        "delta_de",
        "delta_de_stderr",
        "paired_z",
    ]);
    for p in pairs {
        let (lost, gained) = p.discordant();
        let fates = p.fates()?;
        csv.push(vec![
            p.kind.shape.label(),
            mu_s(p.kind),
            p.kind.stokes.to_string(),
            p.steady.records.len().to_string(),
            lost.to_string(),
            gained.to_string(),
            format!("{:.5}", fates.difference()),
            format!("{:.5}", fates.stderr_under_null()),
            format!("{:.2}", fates.z()),
        ])?;
    }
    Ok(csv)
}

/// The particles of `pair` whose injection time lies in bin b of `bins` equal bins of the
/// inhalation [0, `duration`]: for each bin (t_start, t_end, particles, deposited inhaled,
/// deposited steady).
pub fn by_phase(pair: &Paired, duration: f64, bins: usize) -> Vec<(f64, f64, u64, u64, u64)> {
    let mut rows: Vec<(f64, f64, u64, u64, u64)> = (0..bins)
        .map(|b| {
            let w = duration / bins as f64;
            (b as f64 * w, (b + 1) as f64 * w, 0, 0, 0)
        })
        .collect();
    for ((a, b), &t) in pair.steady.records.iter().zip(&pair.cyclic.records).zip(&pair.times) {
        if matches!(b.fate, Fate::Failed { .. }) || bins == 0 {
            continue;
        }
        let k = ((t / duration * bins as f64).floor().max(0.0) as usize).min(bins - 1);
        rows[k].2 += 1;
        rows[k].3 += u64::from(deposited(&b.fate));
        rows[k].4 += u64::from(deposited(&a.fate));
    }
    rows
}

/// `shape,mu_s,stk,t_start,t_end,u_in_over_u,n,de_cyclic,de_cyclic_stderr,de_steady,
/// de_steady_stderr`: DE by injection time in `bins` bins of the inhalation, inhaled and (the
/// same particles) steady; `u_in_over_u` is U_in/U at the bin's middle.
pub fn phase_table(pairs: &[Paired], waveform: Waveform, bins: usize) -> Result<Csv, BifurcationError> {
    let mut csv = Csv::new(&[
        "shape",
        "mu_s",
        "stk",
        "t_start",
        "t_end",
        "u_in_over_u",
        "n",
        "de_cyclic",
        "de_cyclic_stderr",
        "de_steady",
        "de_steady_stderr",
    ]);
    use crate::population::binomial::{fraction, stderr};
    for p in pairs {
        for (t0, t1, n, dc, ds) in by_phase(p, waveform.duration(), bins) {
            csv.push(vec![
                p.kind.shape.label(),
                mu_s(p.kind),
                p.kind.stokes.to_string(),
                format!("{t0:.3}"),
                format!("{t1:.3}"),
                format!("{:.4}", waveform.scale(0.5 * (t0 + t1))),
                n.to_string(),
                format!("{:.5}", fraction(dc, n)),
                format!("{:.5}", stderr(dc, n)),
                format!("{:.5}", fraction(ds, n)),
                format!("{:.5}", stderr(ds, n)),
            ])?;
        }
    }
    Ok(csv)
}

/// Particles per kind whose deposits the maps show (as [`super::figures::MAP_PARTICLES`]).
pub const MAP_PARTICLES: u64 = super::figures::MAP_PARTICLES;

/// `shape,mu_s,stk,flow,index,t_injected,t_deposited,x1,x2,x3`: the deposits of the first
/// [`MAP_PARTICLES`] particles of each kind, steady and inhaled.
pub fn map_table(pairs: &[Paired]) -> Result<Csv, BifurcationError> {
    let mut csv = Csv::new(&[
        "shape",
        "mu_s",
        "stk",
        "flow",
        "index",
        "t_injected",
        "t_deposited",
        "x1",
        "x2",
        "x3",
    ]);
    for p in pairs {
        for (flow, out) in [("steady", &p.steady), ("cyclic", &p.cyclic)] {
            for (r, t) in out.records.iter().zip(&p.times) {
                let Fate::Deposited { position, time, .. } = r.fate else {
                    continue;
                };
                if r.index >= MAP_PARTICLES {
                    continue;
                }
                let t_inj = if flow == "steady" { 0.0 } else { *t };
                csv.push(vec![
                    p.kind.shape.label(),
                    mu_s(p.kind),
                    p.kind.stokes.to_string(),
                    flow.into(),
                    r.index.to_string(),
                    format!("{t_inj:.5}"),
                    format!("{time:.5}"),
                    format!("{:.6e}", position[0]),
                    format!("{:.6e}", position[1]),
                    format!("{:.6e}", position[2]),
                ])?;
            }
        }
    }
    Ok(csv)
}

/// The pictures: for each kind, its deposits on the x₁–x₂ plane steady against inhaled (the
/// first [`MAP_PARTICLES`] particles), then a panel per Stokes number with DE against the
/// injection time, inhaled (points, ± 2σ lines) and steady on the same particles (lines).
pub fn figure(pairs: &[Paired], waveform: Waveform, bins: usize) -> Figure {
    let mut panels = Vec::new();
    for p in pairs {
        let label = format!(
            "{} {} Stk {}",
            p.kind.shape.label(),
            p.kind.material.label(),
            p.kind.stokes
        );
        let mut plane = Panel::new(format!("{label}: deposits"), "x1 [mm]", "x2 [mm]")
            .with_ranges((0.0, LENGTH * 1e3), (-14.0, 14.0));
        for (i, (flow, out)) in [("steady", &p.steady), ("cyclic", &p.cyclic)].into_iter().enumerate() {
            let pts = out
                .records
                .iter()
                .filter(|r| r.index < MAP_PARTICLES)
                .filter_map(|r| match r.fate {
                    Fate::Deposited { position, .. } => Some((position[0] * 1e3, position[1] * 1e3)),
                    _ => None,
                })
                .collect();
            plane = plane.with(Series::points(flow, pts, i));
        }
        panels.push(plane);
    }
    let mut stokes: Vec<f64> = pairs.iter().map(|p| p.kind.stokes).collect();
    stokes.dedup();
    for stk in stokes {
        let mut panel = Panel::new(format!("Stk {stk}: DE by injection time"), "t_injected [s]", "DE")
            .with_ranges((0.0, waveform.duration()), (0.0, 1.0));
        for (i, p) in pairs.iter().filter(|p| p.kind.stokes == stk).enumerate() {
            let rows = by_phase(p, waveform.duration(), bins);
            let mid = |r: &(f64, f64, u64, u64, u64)| 0.5 * (r.0 + r.1);
            let de = |k: u64, n: u64, s: f64| {
                crate::population::binomial::fraction(k, n) + s * crate::population::binomial::stderr(k, n)
            };
            let name = format!("{} {}", p.kind.shape.label(), p.kind.material.label());
            panel = panel
                .with(Series::points(
                    format!("{name} cyclic"),
                    rows.iter().map(|r| (mid(r), de(r.3, r.2, 0.0))).collect(),
                    2 * i,
                ))
                .with(Series::line(
                    format!("{name} cyclic ± 2σ"),
                    rows.iter().map(|r| (mid(r), de(r.3, r.2, 2.0))).collect(),
                    2 * i,
                ))
                .with(Series::line(
                    "",
                    rows.iter().map(|r| (mid(r), de(r.3, r.2, -2.0))).collect(),
                    2 * i,
                ))
                .with(Series::line(
                    format!("{name} steady, same particles"),
                    rows.iter().map(|r| (mid(r), de(r.4, r.2, 0.0))).collect(),
                    2 * i + 1,
                ));
        }
        panels.push(panel);
    }
    Figure::grid(panels, 2, (620, 420))
}

/// Write a quasi-steady breath into `out` (replaced): the mesh of the steady case `steady`
/// (its `constant/polyMesh`, files copied as they are) and at each of `times` its last level
/// scaled by U_in(t)/U, `waveform`'s. It is the field of the limit α → 0 at fixed Re (the
/// shape of the flow never changes, only its magnitude), the case of the snapshot test and a
/// reference for what the Reynolds number's change does.
pub fn write_quasi_steady(
    steady: &Path,
    out: &Path,
    waveform: Waveform,
    times: &[f64],
) -> Result<(), BifurcationError> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| crate::output::OutputError::Io { path, source }
    };
    let case = FoamCase::open(steady)?;
    let last = *case.times().last().ok_or_else(|| FoamError::Field {
        path: steady.display().to_string(),
        reason: "the steady case has no time directory".into(),
    })?;
    let field = case.read_field(last, "U", 3)?;
    let _ = std::fs::remove_dir_all(out);
    let mesh_dir = out.join("constant/polyMesh");
    std::fs::create_dir_all(&mesh_dir).map_err(io(&mesh_dir))?;
    let source = steady.join("constant/polyMesh");
    for entry in std::fs::read_dir(&source).map_err(io(&source))? {
        let entry = entry.map_err(io(&source))?;
        let _ = std::fs::copy(entry.path(), mesh_dir.join(entry.file_name())).map_err(io(&entry.path()))?;
    }
    let mesh = case.mesh();
    for &t in times {
        let s = waveform.scale(t);
        let mut text = String::from(
            "FoamFile { version 2.0; format ascii; class volVectorField; object U; }\ndimensions [0 1 -1 0 0 0 0];\n",
        );
        let list = |values: &[f64]| {
            let mut l = format!("nonuniform List<vector> {}\n(\n", values.len() / 3);
            for v in values.chunks(3) {
                l.push_str(&format!("({:e} {:e} {:e})\n", s * v[0], s * v[1], s * v[2]));
            }
            l.push(')');
            l
        };
        text.push_str(&format!(
            "internalField {};\nboundaryField\n{{\n",
            list(&field.internal)
        ));
        let first_boundary = mesh.n_internal_faces();
        for patch in mesh.patches() {
            let from = 3 * (patch.start - first_boundary);
            let values = &field.boundary[from..from + 3 * patch.size];
            let kind = if patch.kind == "wall" {
                "fixedValue"
            } else {
                "calculated"
            };
            text.push_str(&format!(
                "    {} {{ type {kind}; value {}; }}\n",
                patch.name,
                list(values)
            ));
        }
        text.push_str("}\n");
        let dir = out.join(format!("{t}"));
        std::fs::create_dir_all(&dir).map_err(io(&dir))?;
        crate::output::write_atomic(dir.join("U"), text.as_bytes())?;
    }
    Ok(())
}

/// The net volume flux of each open patch at every step of the case in `dir`, from its
/// `postProcessing/flowRate*/0/surfaceFieldValue.dat` (the Allrun's function objects:
/// `flowRates` the inlet, `flowRateOutlet1`, `flowRateOutlet2`), against the flux
/// prescribed by `waveform` through the inlet of `airway`'s mesh. Columns
/// `t,q_prescribed,q_inlet,q_outlet1,q_outlet2,inlet_error,imbalance`: q in m³/s, positive
/// into the airway at the inlet and out of it at the outlets; `inlet_error` =
/// (q_inlet − q_prescribed)/max q_prescribed, `imbalance` = (q_inlet − q_outlet1 − q_outlet2)/
/// max q_prescribed.
pub fn flow_rate_table(dir: &Path, airway: &Airway, waveform: Waveform) -> Result<Csv, BifurcationError> {
    let read = |name: &str| -> Result<Vec<(f64, f64)>, BifurcationError> {
        let path = dir.join(format!("postProcessing/{name}/0/surfaceFieldValue.dat"));
        let text = std::fs::read_to_string(&path).map_err(|source| crate::output::OutputError::Io {
            path: path.clone(),
            source,
        })?;
        Ok(text
            .lines()
            .filter(|l| !l.starts_with('#'))
            .filter_map(|l| {
                let mut w = l.split_whitespace().map(str::parse::<f64>);
                match (w.next(), w.next()) {
                    (Some(Ok(t)), Some(Ok(q))) => Some((t, q)),
                    _ => None,
                }
            })
            .collect())
    };
    let (inlet, out1, out2) = (read("flowRates")?, read("flowRateOutlet1")?, read("flowRateOutlet2")?);
    let mesh = airway.flow().cellwise().mesh();
    let area: f64 = mesh
        .patches()
        .iter()
        .filter(|p| p.name == "inlet")
        .flat_map(|p| p.start..p.start + p.size)
        .map(|f| mesh.face_areas()[f].norm())
        .sum();
    let q_max = inlet_velocity() * 0.5 * PI * area;
    let mut csv = Csv::new(&[
        "t",
        "q_prescribed",
        "q_inlet",
        "q_outlet1",
        "q_outlet2",
        "inlet_error",
        "imbalance",
    ]);
    for ((&(t, qi), &(t1, q1)), &(t2, q2)) in inlet.iter().zip(&out1).zip(&out2) {
        if t1 != t || t2 != t {
            continue;
        }
        let q = inlet_velocity() * waveform.scale(t) * area;
        // OpenFOAM's flux is positive out of the domain: the inlet's is negative.
        let qi = -qi;
        csv.push(vec![
            format!("{t}"),
            format!("{q:.6e}"),
            format!("{qi:.6e}"),
            format!("{q1:.6e}"),
            format!("{q2:.6e}"),
            format!("{:.3e}", (qi - q) / q_max),
            format!("{:.3e}", (qi - q1 - q2) / q_max),
        ])?;
    }
    Ok(csv)
}

/// How far level `t` of the case `a` is from the last level of the steady case `b` scaled by
/// `scale` (the same mesh): the cell velocities' relative L2 difference
/// ‖u_a − s u_b‖₂/‖s u_b‖₂, and the largest cell difference over the largest cell speed of
/// s u_b.
pub fn field_difference(a: &FoamCase, t: f64, b: &FoamCase, scale: f64) -> Result<(f64, f64), BifurcationError> {
    let last = *b.times().last().ok_or_else(|| FoamError::Field {
        path: "(steady case)".into(),
        reason: "no time directory".into(),
    })?;
    let (ua, ub) = (a.read_field(t, "U", 3)?, b.read_field(last, "U", 3)?);
    if ua.internal.len() != ub.internal.len() {
        return Err(FoamError::Mesh {
            reason: format!(
                "{} and {} cell values: not the same mesh",
                ua.internal.len(),
                ub.internal.len()
            ),
        }
        .into());
    }
    let (mut diff2, mut norm2, mut diff_max, mut speed_max) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (x, y) in ua.internal.chunks(3).zip(ub.internal.chunks(3)) {
        let d = ((x[0] - scale * y[0]).powi(2) + (x[1] - scale * y[1]).powi(2) + (x[2] - scale * y[2]).powi(2)).sqrt();
        let s = scale * (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]).sqrt();
        diff2 += d * d;
        norm2 += s * s;
        diff_max = diff_max.max(d);
        speed_max = speed_max.max(s);
    }
    Ok(((diff2 / norm2).sqrt(), diff_max / speed_max))
}

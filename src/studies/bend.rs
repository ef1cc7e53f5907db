//! Inertial deposition of spheres in a 90° bend of circular cross-section in laminar flow
//! (Re = 1000), against the measurements of Pui, Romay-Novas & Liu (Aerosol Sci. Technol. 7
//! (1987) 301–315) as their fit ([`crate::reference::pui_bend_deposition_efficiency`]).
//!
//! # Set-up
//! The OpenFOAM case of `cases/bend/Allrun` (tube radius a, curvature ratio R_o/a = 5.6, a
//! Poiseuille profile imposed on the inlet 2 D before the bend, an exit tube of 3 D; walls
//! `wall_entrance`, `wall_bend`, `wall_exit`). Rigid spheres of air-borne droplets' density
//! ([`PARTICLE_DENSITY`]) in air ([`FLUID_DENSITY`], ν of the case) are injected on the inlet
//! patch weighted by the inflow through each face (a uniformly seeded aerosol: the number
//! entering through an area is proportional to its flux), with the local fluid velocity, and
//! tracked by the `pseudorigid` command's scene machinery on the library's defaults: the
//! blended field with the second-order wall layer, Radau IIA, extent contact, no gravity
//! (settling at τ_p g during the bend's transit πR_o/(2U) ≈ 7 ms moves a sphere by at most
//! 0.06 mm = 0.023 a, at Stk = 1; the reference is inertial deposition). A sphere deposits
//! when it touches a wall and escapes through the outlet (or back through the inlet); after
//! [`RESIDENCE_TIMES`] mean residence times it is suspended.
//!
//! # Stokes number (Pui et al. 1987)
//! ```math
//! Stk = \frac{\rho_p d^2 U}{9 \mu_f D} = \frac{\tau_p U}{a}, \qquad \tau_p = \frac{\rho_p d^2}{18 \mu_f},
//! ```
//! with U the mean velocity Q/(πa²) from OpenFOAM's inlet flow rate (no slip correction C_c:
//! the spheres are continuum particles). So d = √(18 μ_f a Stk/(ρ_p U)).
//!
//! # Deposition efficiency
//! DE = n(deposited on `wall_bend`)/n(injected): the bend's wall only, as the measurement
//! counts what the bend removes. Deposits on the straight tubes are reported apart (the
//! developed entrance flow has no wall-normal velocity, so few if any deposit there). Each
//! particle deposits independently, so the count is binomial: standard error √(DE(1 − DE)/N).

use crate::error::ParamError;
use crate::material::NamedLaw;
use crate::output::plot::{Figure, Panel, Series};
use crate::output::{Csv, OutputError};
use crate::population::peer::PeerFate;
use crate::population::{Fate, Injector, ParticleRecord, ParticleSpec, RunOptions, RunOutput, Shard, particle_rng};
use crate::scene::run::Job;
use crate::scene::{Scene, SceneError};
use crate::studies::peer::{OpenFoamTracker, PeerParticle};
use crate::tensor::Vec3;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Density of the fluid (air) [kg/m³].
pub const FLUID_DENSITY: f64 = 1.2;
/// Density of the spheres [kg/m³] (oil droplets, as Pui et al.'s liquid aerosols; only Stk
/// and the size d/D enter).
pub const PARTICLE_DENSITY: f64 = 1000.0;
/// Bend angle θ (rad).
pub const BEND_ANGLE: f64 = std::f64::consts::FRAC_PI_2;
/// Tracking time in mean residence times V/Q.
pub const RESIDENCE_TIMES: f64 = 10.0;
/// The wall patch of the bend.
pub const BEND_WALL: &str = "wall_bend";
/// Local error tolerance of the scenes' integrator (`integrator.tol`: relative and absolute,
/// SI). Its effect on fates is measured by a paired run in `paper-figures/bend/NOTES.md`.
pub const TOL: f64 = 1e-5;
/// Run seed of the datasets.
pub const SEED: u64 = 1;
/// The scenes' integrator (`integrator.type`): Radau IIA(5), the library's default.
pub const INTEGRATOR: &str = "radau_iia";
/// Bulk modulus ratio λ_s/μ_s of [`Settings::shear_modulus`]'s neo-Hookean spheres: nearly
/// incompressible, the bifurcation studies' ratio.
pub const BULK_RATIO: f64 = 1e3;

/// What a study may vary for a measurement of its own error; [`Default`] is the dataset's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// `integrator.tol` (default [`TOL`]).
    pub tol: f64,
    /// Tracking time in mean residence times (default [`RESIDENCE_TIMES`]).
    pub residence_times: f64,
    /// `flow.blend` (default true: the library's default field).
    pub blend: bool,
    /// `boundary.contact_radius`: deposit when the centre comes this close to a wall (0: point
    /// contact, as OpenFOAM's parcels) instead of when the sphere's extent touches (default
    /// `None`, the library's default). A radius above the sphere's own does not work here: the
    /// patch injection moves a sphere inside by its largest semi-axis only, so it starts within
    /// the contact radius of the inlet and escapes at t = 0 (measured: 1000 of 1000 at 10 µm).
    pub contact_radius: Option<f64>,
    /// `particles.forces`: force terms beyond the paper's (default none, the dataset's).
    pub forces: &'static [&'static str],
    /// `integrator.type`, a registered integrator (default [`INTEGRATOR`]; [`integrator_name`]
    /// turns a user's name into one). It is given `tol` = [`Settings::tol`], so it must be an
    /// adaptive one (`radau_iia`, `rosenbrock_w23`, `imex_adaptive`): the scene refuses `tol`
    /// for the others.
    pub integrator: &'static str,
    /// `None`: rigid spheres (the dataset's). `Some(μ_s)`: soft ones, neo-Hookean with shear
    /// modulus μ_s (Pa) and λ_s = [`BULK_RATIO`] μ_s, starting undeformed. In the bend's
    /// scales the capillary number is Ca = μ_f (U/2a)/μ_s (1.1·10⁻² at μ_s = 1 Pa).
    pub shear_modulus: Option<f64>,
}

/// The registered integrator called `name` (or one of its aliases), by its own name: what
/// [`Settings::integrator`] takes. An unknown name is an error listing the known ones.
pub fn integrator_name(name: &str) -> Result<&'static str, ParamError> {
    Ok(crate::registry::find::<crate::integrator::registry::IntegratorRegistration>(name)?.name)
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            tol: TOL,
            residence_times: RESIDENCE_TIMES,
            blend: true,
            contact_radius: None,
            forces: &[],
            integrator: INTEGRATOR,
            shear_modulus: None,
        }
    }
}

/// Failures of a bend study.
#[derive(Debug, Error)]
pub enum BendError {
    /// The case's `bend.summary` is missing or malformed.
    #[error("{path}: {reason}")]
    Summary {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// Invalid parameters.
    #[error(transparent)]
    Param(#[from] ParamError),
    /// The scene was refused or the run failed.
    #[error(transparent)]
    Cli(#[from] SceneError),
    /// A dataset or figure could not be written.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// A particle could not be drawn.
    #[error("drawing a particle: {0}")]
    Draw(String),
}

/// A solved bend case: its folder and what `Allrun` measured (`bend.summary`).
#[derive(Debug, Clone)]
pub struct BendCase {
    /// The case folder.
    pub dir: PathBuf,
    /// Tube radius a, in m.
    pub radius: f64,
    /// Kinematic viscosity ν [m²/s].
    pub nu: f64,
    /// Mean velocity U = Q/(πa²) [m/s].
    pub mean_velocity: f64,
    /// Cells of the mesh.
    pub cells: u64,
    /// Mean residence time V/Q, in s (the tubes' volume π a² L over Q).
    pub residence_time: f64,
}

/// Straight entrance (default; `entrance_d` in `bend.summary`) and exit lengths in diameters
/// of `cases/bend`.
const ENTRANCE_D: f64 = 2.0;
const EXIT_D: f64 = 3.0;
/// Curvature ratio R_o/a of `cases/bend` (Pui et al.: 5.6–5.7).
pub const CURVATURE_RATIO: f64 = 5.6;

impl BendCase {
    /// Read `dir/bend.summary` (written by `cases/bend/Allrun`).
    pub fn open(dir: impl AsRef<Path>) -> Result<Self, BendError> {
        let dir = dir.as_ref().to_path_buf();
        let path = dir.join("bend.summary");
        let bad = |reason: String| BendError::Summary {
            path: path.clone(),
            reason,
        };
        let text = std::fs::read_to_string(&path).map_err(|e| bad(format!("cannot read: {e}")))?;
        let get = |key: &str| -> Result<f64, BendError> {
            let value = text
                .lines()
                .find_map(|l| l.strip_prefix(key).and_then(|v| v.strip_prefix('=')))
                .ok_or_else(|| bad(format!("no `{key}=`")))?;
            let x: f64 = value
                .trim()
                .parse()
                .map_err(|e| bad(format!("`{key}={}`: {e}", value.trim())))?;
            if x.is_finite() && x > 0.0 {
                Ok(x)
            } else {
                Err(bad(format!("`{key}={x}`: need a positive number")))
            }
        };
        let radius = get("radius")?;
        let nu = get("nu")?;
        let mean_velocity = get("mean_velocity")?;
        let cells = get("cells")? as u64;
        // Written since the entrance became adjustable; older summaries are the default's.
        let entrance = if text.lines().any(|l| l.starts_with("entrance_d=")) {
            get("entrance_d")?
        } else {
            ENTRANCE_D
        };
        let diameter = 2.0 * radius;
        let length = (entrance + EXIT_D) * diameter + BEND_ANGLE * CURVATURE_RATIO * radius;
        Ok(Self {
            dir,
            radius,
            nu,
            mean_velocity,
            cells,
            residence_time: length / mean_velocity,
        })
    }

    /// Reynolds number 2aU/ν.
    pub fn reynolds(&self) -> f64 {
        2.0 * self.radius * self.mean_velocity / self.nu
    }

    /// Sphere diameter of Stokes number `stokes` (> 0): d = √(18 μ_f a Stk/(ρ_p U)).
    pub fn diameter_for_stokes(&self, stokes: f64) -> Result<f64, ParamError> {
        let stk = crate::error::positive("Stokes number", stokes)?;
        let mu = FLUID_DENSITY * self.nu;
        Ok((18.0 * mu * self.radius * stk / (PARTICLE_DENSITY * self.mean_velocity)).sqrt())
    }

    /// The scene of `n` spheres of Stokes number `stokes` (module docs), as TOML in the
    /// command's key table.
    pub fn scene_text(&self, stokes: f64, n: u64, seed: u64, settings: Settings) -> Result<String, ParamError> {
        crate::error::positive("integrator.tol", settings.tol)?;
        crate::error::positive("residence times", settings.residence_times)?;
        let material = match settings.shear_modulus {
            None => "{ law = \"rigid\" }".to_string(),
            Some(mu) => {
                let mu = crate::error::positive("shear modulus", mu)?;
                format!("{{ law = \"neo_hooke\", mu = {mu:e}, lambda = {:e} }}", BULK_RATIO * mu)
            }
        };
        let r = 0.5 * self.diameter_for_stokes(stokes)?;
        let mut s = String::new();
        // Writing to a String cannot fail.
        let _ = writeln!(
            s,
            "# cases/bend: {} spheres of Stk = {stokes} (d = {:e} m)",
            if settings.shear_modulus.is_some() {
                "soft"
            } else {
                "rigid"
            },
            2.0 * r
        );
        let _ = writeln!(s, "seed = {seed}");
        let _ = writeln!(
            s,
            "[flow]\ntype = \"openfoam\"\ncase = \".\"\nblend = {}",
            settings.blend
        );
        let _ = writeln!(
            s,
            "[fluid]\nviscosity = {:e}\ndensity = {FLUID_DENSITY:e}",
            FLUID_DENSITY * self.nu
        );
        let _ = writeln!(s, "[boundary]\ntype = \"mesh\"");
        if let Some(radius) = settings.contact_radius {
            let _ = writeln!(s, "contact_radius = {radius:e}");
        }
        let _ = writeln!(s, "[particles]\ndensity = {PARTICLE_DENSITY:e}");
        if !settings.forces.is_empty() {
            let _ = writeln!(s, "forces = {:?}", settings.forces);
        }
        let _ = writeln!(
            s,
            "[particles.inject]\ncount = {n}\nsemi_axes = [{r:e}, {r:e}, {r:e}]\nfluid_velocity = true\n\
             region = {{ type = \"patch\", name = \"inlet\" }}\nmaterial = {material}"
        );
        let _ = writeln!(
            s,
            "[integrator]\ntype = \"{}\"\ntol = {:e}\ndt = 1e-6",
            settings.integrator, settings.tol
        );
        let _ = writeln!(s, "[end]\nt_end = {:e}", settings.residence_times * self.residence_time);
        let _ = writeln!(s, "[output]\nvtk = false");
        Ok(s)
    }

    /// The validated scene of [`Self::scene_text`].
    pub fn scene(&self, stokes: f64, n: u64, seed: u64, settings: Settings) -> Result<Scene, BendError> {
        let text = self.scene_text(stokes, n, seed, settings)?;
        let file = self.dir.join("bend-scene.toml").display().to_string();
        Ok(crate::scene::parse(
            &crate::scene::error::Source {
                file: &file,
                text: &text,
            },
            &self.dir,
        )?)
    }

    /// Track `n` spheres of Stokes number `stokes` with run seed `seed` (in memory, on rayon's
    /// pool): every particle's record. Sphere k is the same for any `settings` (stream k of the
    /// seed), so two settings compare particle by particle.
    pub fn run_output(
        &self,
        stokes: f64,
        n: u64,
        seed: u64,
        settings: Settings,
        options: RunOptions,
    ) -> Result<RunOutput<NamedLaw>, BendError> {
        let scene = self.scene(stokes, n, seed, settings)?;
        Ok(scene.population(&Job::Memory {
            shard: Shard::ALL,
            options,
        })?)
    }

    /// [`Self::run_output`], counted ([`BendDeposition::of`]).
    pub fn run(
        &self,
        stokes: f64,
        n: u64,
        seed: u64,
        settings: Settings,
        options: RunOptions,
    ) -> Result<BendDeposition, BendError> {
        let out = self.run_output(stokes, n, seed, settings, options)?;
        Ok(BendDeposition::of(stokes, &out))
    }

    /// Spheres 0..n of [`Self::run_output`] as the runner draws them (injection point, initial
    /// velocity): what another tracker needs to follow the same particles.
    pub fn particle_specs(&self, stokes: f64, n: u64, seed: u64) -> Result<Vec<ParticleSpec<NamedLaw>>, BendError> {
        let scene = self.scene(stokes, n, seed, Settings::default())?;
        let injector = scene.injector();
        (0..n)
            .map(|k| {
                injector
                    .draw(k, &mut particle_rng(seed, k))
                    .map_err(|e| BendError::Draw(e.to_string()))
            })
            .collect()
    }
}

impl BendCase {
    /// Spheres 0..n of Stokes number `stokes` as OpenFOAM's tracker takes them
    /// ([`Self::particle_specs`]: the same particles as [`Self::run_output`]).
    pub fn peer_particles(&self, stokes: f64, n: u64, seed: u64) -> Result<Vec<PeerParticle>, BendError> {
        let diameter = self.diameter_for_stokes(stokes)?;
        Ok(self
            .particle_specs(stokes, n, seed)?
            .iter()
            .map(|spec| PeerParticle {
                position: spec.position,
                velocity: spec.velocity,
                diameter,
                density: PARTICLE_DENSITY,
            })
            .collect())
    }

    /// OpenFOAM's tracker (the repository at `root`) on this case, as the scene runs: the
    /// same tracking time, no gravity, the scene's fluid density.
    pub fn openfoam_tracker(&self, root: &Path, settings: Settings) -> Result<OpenFoamTracker, ParamError> {
        OpenFoamTracker::new(
            root,
            settings.residence_times * self.residence_time,
            Vec3::zeros(),
            FLUID_DENSITY,
        )
    }
}

/// Whether a record deposited on the bend's wall (the DE's count), given the run's patches.
pub fn on_bend_wall<L>(record: &ParticleRecord<L>, patches: &[String]) -> bool {
    matches!(record.fate, Fate::Deposited { patch, .. } if patches.get(patch).map(String::as_str) == Some(BEND_WALL))
}

/// Whether OpenFOAM's parcel deposited on the bend's wall.
pub fn peer_on_bend_wall(fate: &PeerFate) -> bool {
    fate.fate == "deposited" && fate.patch == BEND_WALL
}

/// Fates of one Stokes number's spheres.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BendDeposition {
    /// Stokes number.
    pub stokes: f64,
    /// Spheres injected.
    pub injected: u64,
    /// Deposited on the bend's wall.
    pub bend: u64,
    /// Deposited on the straight entrance or exit tube.
    pub tubes: u64,
    /// Escaped (outlet or inlet).
    pub escaped: u64,
    /// Still inside at the end.
    pub suspended: u64,
    /// Failed (an integration error).
    pub failed: u64,
}

impl BendDeposition {
    /// Count the fates of a run of spheres of Stokes number `stokes`.
    pub fn of(stokes: f64, out: &RunOutput<NamedLaw>) -> Self {
        let mut row = Self {
            stokes,
            injected: out.records.len() as u64,
            ..Self::default()
        };
        for record in &out.records {
            match &record.fate {
                Fate::Deposited { patch, .. } => {
                    if out.patches.get(*patch).map(String::as_str) == Some(BEND_WALL) {
                        row.bend += 1;
                    } else {
                        row.tubes += 1;
                    }
                }
                Fate::Escaped { .. } => row.escaped += 1,
                Fate::Suspended => row.suspended += 1,
                Fate::Failed { .. } => row.failed += 1,
            }
        }
        row
    }

    /// DE = deposited on the bend / injected (0 if none injected).
    pub fn de(&self) -> f64 {
        crate::population::binomial::fraction(self.bend, self.injected)
    }

    /// Binomial standard error √(DE(1 − DE)/N).
    pub fn stderr(&self) -> f64 {
        crate::population::binomial::stderr(self.bend, self.injected)
    }

    /// The reference DE at this Stokes number (Pui et al. 1987, 90°).
    pub fn reference(&self) -> Result<f64, ParamError> {
        crate::reference::pui_bend_deposition_efficiency(self.stokes, BEND_ANGLE)
    }
}

/// `stk,n_injected,n_deposited,de,de_stderr,reference_de` (n_deposited: on the bend's wall).
pub fn deposition_table(rows: &[BendDeposition]) -> Result<Csv, BendError> {
    let mut csv = Csv::new(&["stk", "n_injected", "n_deposited", "de", "de_stderr", "reference_de"]);
    for r in rows {
        csv.push(vec![
            r.stokes.to_string(),
            r.injected.to_string(),
            r.bend.to_string(),
            format!("{:.5}", r.de()),
            format!("{:.5}", r.stderr()),
            format!("{:.5}", r.reference()?),
        ])?;
    }
    Ok(csv)
}

/// DE against log₁₀ Stk with ±2 standard-error bars, beside the reference curve.
pub fn deposition_figure(rows: &[BendDeposition], title: &str) -> Figure {
    let mut panel = Panel::new(title, "log10 Stk", "DE").with_ranges((-1.6, 0.1), (0.0, 1.0));
    panel = panel.with(Series::points(
        "pseudorigid (extent contact, blended field)",
        rows.iter().map(|r| (r.stokes.log10(), r.de())).collect(),
        1,
    ));
    for (i, r) in rows.iter().enumerate() {
        let lg = r.stokes.log10();
        let label = if i == 0 { "± 2 standard errors" } else { "" };
        panel = panel.with(Series::line(
            label,
            vec![(lg, r.de() - 2.0 * r.stderr()), (lg, r.de() + 2.0 * r.stderr())],
            1,
        ));
    }
    let reference: Vec<(f64, f64)> = (0..=100)
        .filter_map(|k| {
            let lg = -1.6 + 1.7 * f64::from(k) / 100.0;
            crate::reference::pui_bend_deposition_efficiency(10f64.powf(lg), BEND_ANGLE)
                .ok()
                .map(|de| (lg, de))
        })
        .collect();
    Figure::single(panel.with(Series::line(
        "Pui et al. (1987), Re = 1000, R_o/a = 5.6 (fit to the measurements)",
        reference,
        0,
    )))
}

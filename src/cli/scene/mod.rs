//! From a scene file to library objects. Every value goes through the constructor of the
//! type it becomes (`Plan::new`, `NeoHooke::new`, `Ellipsoid::new`, `Stokesian::new`, ...),
//! and a value it refuses is reported at its line and column with its dotted key.

mod carrier;
mod particles;
mod timing;

use super::error::{CliError, Source};
use super::inject::{Group, Placement, SceneInjector, Source as ParticleSource, Velocity};
use super::models::{SceneBoundary, SceneFlow, SceneTransient, TransientField};
use super::schema::*;
use crate::contact::MeshBoundary;
use crate::contact::{ContactModel, PatchRule, PipeWall, Plane, Planes};
use crate::driver::{Budget, Plan};
use crate::ellipsoid::Ellipsoid;
use crate::error::ParamError;
use crate::flow::FlowField;
use crate::flow::analytic::{LinearFlow, Poiseuille};
use crate::flow::openfoam::{BlendedFlow, Cycle, FoamCase, FoamFlow, Precision, TransientFlow};
use crate::hydro::drag::NamedDrag;
use crate::hydro::{ForceTerms, VolumetricTraction, drag, forces};
use crate::integrator::SceneIntegrator;
use crate::material::NamedLaw;
use crate::material::{self, Softness};
use crate::particle::Fluid;
use crate::population::ParticleTemplate;
use crate::registry::{Value, Values};
use crate::tensor::{Mat3, Vec3};
use nalgebra::{Rotation3, Unit};
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::Path;
use std::sync::Arc;
use toml::Spanned;

/// Particles the mesh-adequacy diagnostic ([`super::adequacy`]) re-tracks by default
/// (`output.adequacy_sample`): the paired standard error of a deposition fraction near f over
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
    /// field (`output.adequacy_sample`, [`super::adequacy`]); 0: none.
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
pub fn load(path: &Path) -> Result<Scene, CliError> {
    let text = std::fs::read_to_string(path).map_err(|source| CliError::Read {
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

/// Validate a scene's text; relative paths in it are relative to `base`.
pub fn parse(src: &Source<'_>, base: &Path) -> Result<Scene, CliError> {
    let raw: SceneFile = toml::from_str(src.text).map_err(|e| src.parse_error(&e))?;
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
    fn err(&self, span: Range<usize>, key: &str, message: impl Into<String>) -> CliError {
        self.src.error(span, key, message)
    }

    /// A library constructor's refusal, reported at `span` for `key`.
    fn param(&self, span: Range<usize>, key: &str, e: ParamError) -> CliError {
        self.err(span, key, e.to_string())
    }

    fn finite(&self, v: &Num, key: &str) -> Result<f64, CliError> {
        let x = *v.get_ref();
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.err(v.span(), key, format!("must be a finite number, got {x}")))
        }
    }

    fn positive(&self, v: &Num, key: &str) -> Result<f64, CliError> {
        let x = self.finite(v, key)?;
        if x > 0.0 {
            Ok(x)
        } else {
            Err(self.err(v.span(), key, format!("must be > 0, got {x}")))
        }
    }

    fn vec3(&self, v: &Num3, key: &str) -> Result<Vec3, CliError> {
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

    fn scene(&self, raw: SceneFile, base: &Path) -> Result<Scene, CliError> {
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
        let (plan, outputs) = self.plan(&dt, dt_max.as_ref(), &raw.end, &raw.output, particles.count())?;
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
    /// ([`super::adequacy`]), by default [`DEFAULT_SAMPLE`] on a steady
    /// OpenFOAM field and none elsewhere. A positive value is refused on an analytic flow (no
    /// mesh, no wall layer) and on a transient field (the re-track is not implemented there).
    fn adequacy_sample(&self, output: &OutputSpec, flow: &SceneFlow) -> Result<u64, CliError> {
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
    ) -> Result<(), CliError> {
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
    fn first_window(&self, field: &SceneTransient, raw: &SceneFile) -> Result<(), CliError> {
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
    ) -> Result<&'v Spanned<T>, CliError> {
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
    ) -> Result<ModelKeys, CliError> {
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
    fn model_error(&self, m: &ModelKeys, e: ParamError) -> CliError {
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
    fn table_number(&self, table: &ModelTable, prefix: &str, key: &str) -> Result<Option<Num>, CliError> {
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
    fn refuse(&self, given: &[(&str, bool)], at: Range<usize>, kind: &str) -> Result<(), CliError> {
        match given.iter().find(|(_, g)| *g) {
            Some((key, _)) => Err(self.err(at, key, format!("`{kind}` does not take `{key}`"))),
            None => Ok(()),
        }
    }
}

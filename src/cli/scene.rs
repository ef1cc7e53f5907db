//! From a scene file to library objects. Every value goes through the constructor of the
//! type it becomes (`Plan::new`, `NeoHooke::new`, `Ellipsoid::new`, `Stokesian::new`, ...),
//! and a value it refuses is reported at its line and column with its dotted key.

use super::error::{CliError, Source};
use super::inject::{Placement, SceneInjector, Source as ParticleSource, Velocity};
use super::models::{SceneBoundary, SceneDrag, SceneFlow, SceneLaw};
use super::schema::*;
use crate::contact::{ContactModel, PatchRule, PipeWall, Plane, Planes};
use crate::driver::{Budget, Plan};
use crate::ellipsoid::Ellipsoid;
use crate::error::ParamError;
use crate::flow::FlowField;
use crate::flow::analytic::{LinearFlow, Poiseuille};
use crate::flow::openfoam::{FoamCase, FoamFlow, MeshBoundary};
use crate::integrator::{ImexAdaptive, ImexPaper, Scheme, Stokesian};
use crate::material::{MooneyRivlin, NeoHooke, Softness};
use crate::particle::Fluid;
use crate::population::ParticleTemplate;
use crate::tensor::{Mat3, Vec3};
use nalgebra::{Rotation3, Unit};
use std::ops::Range;
use std::path::Path;
use toml::Spanned;

/// Output times allowed per particle: beyond this a run is a time series of one particle,
/// better written by a program than by the command.
pub const MAX_OUTPUTS: u64 = 100_000;
/// States kept in memory over all particles and output times (each state is 200 bytes, so
/// this is 400 MB).
pub const MAX_SAMPLES: u64 = 2_000_000;
/// Particles allowed in one scene (the population runner's results hold one record each).
pub const MAX_PARTICLES: u64 = 100_000_000;
/// Steps allowed per particle unless `end.max_steps` says otherwise.
pub const DEFAULT_MAX_STEPS: u64 = 10_000_000;

/// The integrators a scene can name.
#[derive(Debug, Clone, Copy)]
pub enum SceneIntegrator {
    /// The paper's fixed-step IMEX scheme.
    Imex(ImexPaper),
    /// IMEX with error control.
    ImexAdaptive(ImexAdaptive),
    /// The inertialess integrator (Rosenbrock-W or Radau IIA).
    Stokesian(Stokesian),
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
    pub template: ParticleTemplate<SceneDrag>,
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
    Builder { src }.scene(raw, base)
}

struct Builder<'a> {
    src: &'a Source<'a>,
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
        let a = *v.get_ref();
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
                radius: self.positive(r, "boundary.contact_radius")?,
            },
            None => ContactModel::Extent,
        };
        let template = self.template(&raw.fluid, &raw.particles)?;
        let particles = self.particles(&raw.particles, &template, &flow)?;
        let integrator = self.integrator(&raw.integrator)?;
        let (plan, outputs) = self.plan(&raw.integrator, &raw.end, &raw.output, particles.count())?;
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
            text: self.src.text.to_string(),
        })
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

    /// Keys given that the chosen kind does not take: `(key, given)` pairs.
    fn refuse(&self, given: &[(&str, bool)], at: Range<usize>, kind: &str) -> Result<(), CliError> {
        match given.iter().find(|(_, g)| *g) {
            Some((key, _)) => Err(self.err(at, key, format!("`{kind}` does not take `{key}`"))),
            None => Ok(()),
        }
    }

    fn flow(&self, spec: &FlowSpec, base: &Path) -> Result<SceneFlow, CliError> {
        let at = spec.kind.span();
        let rate = ("flow.rate", spec.rate.is_some());
        let pipe = [
            ("flow.radius", spec.radius.is_some()),
            ("flow.mean_velocity", spec.mean_velocity.is_some()),
        ];
        let foam = [("flow.case", spec.case.is_some()), ("flow.time", spec.time.is_some())];
        let linear = |kind: &str, make: fn(f64) -> Result<LinearFlow, ParamError>| {
            self.refuse(&[pipe[0], pipe[1], foam[0], foam[1]], at.clone(), kind)?;
            let rate = self.need(&spec.rate, at.clone(), "flow.rate", kind)?;
            let r = self.finite(rate, "flow.rate")?;
            make(r)
                .map(SceneFlow::Linear)
                .map_err(|e| self.param(rate.span(), "flow.rate", e))
        };
        match spec.kind.get_ref() {
            FlowKind::Quiescent => {
                self.refuse(&[rate, pipe[0], pipe[1], foam[0], foam[1]], at, "quiescent")?;
                Ok(SceneFlow::Quiescent)
            }
            FlowKind::Shear => linear("shear", LinearFlow::simple_shear),
            FlowKind::PlanarExtension => linear("planar_extension", LinearFlow::planar_extension),
            FlowKind::UniaxialExtension => linear("uniaxial_extension", LinearFlow::uniaxial_extension),
            FlowKind::Poiseuille => {
                self.refuse(&[rate, foam[0], foam[1]], at.clone(), "poiseuille")?;
                let radius = self.need(&spec.radius, at.clone(), "flow.radius", "poiseuille")?;
                let mean = self.need(&spec.mean_velocity, at, "flow.mean_velocity", "poiseuille")?;
                let r = self.positive(radius, "flow.radius")?;
                let u = self.finite(mean, "flow.mean_velocity")?;
                Poiseuille::new(r, u)
                    .map(SceneFlow::Poiseuille)
                    .map_err(|e| self.param(mean.span(), "flow.radius, flow.mean_velocity", e))
            }
            FlowKind::Openfoam => {
                self.refuse(&[rate, pipe[0], pipe[1]], at.clone(), "openfoam")?;
                let case = self.need(&spec.case, at, "flow.case", "openfoam")?;
                let dir = base.join(case.get_ref());
                let foam = FoamCase::open(&dir).map_err(|e| self.err(case.span(), "flow.case", e.to_string()))?;
                let t = match &spec.time {
                    Some(t) => self.finite(t, "flow.time")?,
                    None => *foam
                        .times()
                        .last()
                        .ok_or_else(|| self.err(case.span(), "flow.case", "the case has no time directories"))?,
                };
                let (span, key) = match &spec.time {
                    Some(t) => (t.span(), "flow.time"),
                    None => (case.span(), "flow.case"),
                };
                FoamFlow::read(&foam, &[t])
                    .map(|f| SceneFlow::Foam(Box::new(f)))
                    .map_err(|e| self.err(span, key, e.to_string()))
            }
        }
    }

    fn boundary(&self, spec: Option<&BoundarySpec>, flow: &SceneFlow) -> Result<SceneBoundary, CliError> {
        let Some(b) = spec else {
            return Ok(SceneBoundary::Open);
        };
        let kind = *b.kind.get_ref();
        if kind != BoundaryKind::Pipe && b.radius.is_some() {
            return Err(self.err(b.kind.span(), "boundary.radius", "only a `pipe` boundary has a radius"));
        }
        if kind != BoundaryKind::Planes && !b.walls.is_empty() {
            return Err(self.err(b.kind.span(), "boundary.walls", "only a `planes` boundary has walls"));
        }
        match kind {
            BoundaryKind::Pipe => {
                let r = b
                    .radius
                    .as_ref()
                    .ok_or_else(|| self.err(b.kind.span(), "boundary.radius", "a `pipe` boundary needs `radius`"))?;
                let radius = self.positive(r, "boundary.radius")?;
                PipeWall::new(radius)
                    .map(SceneBoundary::Pipe)
                    .map_err(|e| self.param(r.span(), "boundary.radius", e))
            }
            BoundaryKind::Planes => {
                if b.walls.is_empty() {
                    return Err(self.err(
                        b.kind.span(),
                        "boundary.walls",
                        "a `planes` boundary needs `[[boundary.walls]]`",
                    ));
                }
                let walls = b
                    .walls
                    .iter()
                    .enumerate()
                    .map(|(i, w)| {
                        let key = format!("boundary.walls[{i}]");
                        let normal = self.vec3(&w.normal, &format!("{key}.normal"))?;
                        // Finite components: the norm is 0 only for the zero vector.
                        if normal.norm() == 0.0 {
                            return Err(self.err(w.normal.span(), &format!("{key}.normal"), "must not be zero"));
                        }
                        Ok(Plane {
                            name: w.name.clone(),
                            point: self.vec3(&w.point, &format!("{key}.point"))?,
                            normal,
                            rule: match w.rule {
                                RuleSpec::Stick => PatchRule::Stick,
                                RuleSpec::Exit => PatchRule::Exit,
                            },
                        })
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                Planes::new(walls)
                    .map(SceneBoundary::Planes)
                    .map_err(|e| self.param(b.kind.span(), "boundary.walls", e))
            }
            BoundaryKind::Mesh => match flow {
                SceneFlow::Foam(f) => MeshBoundary::new(f.mesh())
                    .map(|m| SceneBoundary::Mesh(Box::new(m)))
                    .map_err(|e| self.err(b.kind.span(), "boundary.type", e.to_string())),
                _ => Err(self.err(
                    b.kind.span(),
                    "boundary.type",
                    "a `mesh` boundary needs an `openfoam` flow",
                )),
            },
        }
    }

    fn template(&self, fluid: &FluidSpec, particles: &ParticlesSpec) -> Result<ParticleTemplate<SceneDrag>, CliError> {
        let mu = self.positive(&fluid.viscosity, "fluid.viscosity")?;
        let rho_f = self.finite(&fluid.density, "fluid.density")?;
        let fluid_model =
            Fluid::new(mu, rho_f).map_err(|e| self.param(fluid.density.span(), "fluid.viscosity, fluid.density", e))?;
        let gravity = match &fluid.gravity {
            Some(g) => self.vec3(g, "fluid.gravity")?,
            None => Vec3::zeros(),
        };
        let rho_s = self.positive(&particles.density, "particles.density")?;
        let drag = match particles.drag {
            DragSpec::Brenner => SceneDrag::Brenner,
            DragSpec::StokesSphere => SceneDrag::StokesSphere,
        };
        ParticleTemplate::new(drag, fluid_model, rho_s, gravity)
            .map_err(|e| self.param(particles.density.span(), "particles.density, fluid.gravity", e))
    }

    fn material(&self, m: &MaterialSpec, key: &str) -> Result<Softness<SceneLaw>, CliError> {
        let at = m.law.span();
        let k = |name: &str| format!("{key}.{name}");
        match m.law.get_ref() {
            LawKind::Rigid => {
                let keys = [k("mu"), k("mu1"), k("mu2"), k("lambda")];
                let flags = [m.mu.is_some(), m.mu1.is_some(), m.mu2.is_some(), m.lambda.is_some()];
                let given: Vec<(&str, bool)> = keys.iter().map(String::as_str).zip(flags).collect();
                self.refuse(&given, at, "rigid")?;
                Ok(Softness::Rigid)
            }
            LawKind::NeoHooke => {
                let (k1, k2) = (k("mu1"), k("mu2"));
                self.refuse(
                    &[(&k1, m.mu1.is_some()), (&k2, m.mu2.is_some())],
                    at.clone(),
                    "neo_hooke",
                )?;
                let mu = self.need(&m.mu, at.clone(), &k("mu"), "neo_hooke")?;
                let lambda = self.need(&m.lambda, at, &k("lambda"), "neo_hooke")?;
                let (mu_v, l) = (self.positive(mu, &k("mu"))?, self.positive(lambda, &k("lambda"))?);
                NeoHooke::new(mu_v, l)
                    .map(|law| Softness::Elastic(SceneLaw::NeoHooke(law)))
                    .map_err(|e| self.param(mu.span(), &format!("{}, {}", k("mu"), k("lambda")), e))
            }
            LawKind::MooneyRivlin => {
                let k0 = k("mu");
                self.refuse(&[(&k0, m.mu.is_some())], at.clone(), "mooney_rivlin")?;
                let mu1 = self.need(&m.mu1, at.clone(), &k("mu1"), "mooney_rivlin")?;
                let mu2 = self.need(&m.mu2, at.clone(), &k("mu2"), "mooney_rivlin")?;
                let lambda = self.need(&m.lambda, at, &k("lambda"), "mooney_rivlin")?;
                let (a, b, l) = (
                    self.finite(mu1, &k("mu1"))?,
                    self.finite(mu2, &k("mu2"))?,
                    self.positive(lambda, &k("lambda"))?,
                );
                MooneyRivlin::new(a, b, l)
                    .map(|law| Softness::Elastic(SceneLaw::MooneyRivlin(law)))
                    .map_err(|e| self.param(mu1.span(), &format!("{}, {}, {}", k("mu1"), k("mu2"), k("lambda")), e))
            }
        }
    }

    fn rotation(&self, o: Option<&OrientationSpec>, key: &str) -> Result<Mat3, CliError> {
        let Some(o) = o else {
            return Ok(Mat3::identity());
        };
        let axis = self.vec3(&o.axis, &format!("{key}.axis"))?;
        let angle = self.finite(&o.angle, &format!("{key}.angle"))?;
        // Divide by the largest component first: the norm of (1e308, 1e308, 1e308) overflows.
        let scale = axis.amax();
        let axis = (scale > 0.0)
            .then(|| Unit::try_new(axis / scale, 0.0))
            .flatten()
            .ok_or_else(|| {
                self.err(
                    o.axis.span(),
                    &format!("{key}.axis"),
                    "must be a non-zero finite vector",
                )
            })?;
        Ok(Rotation3::from_axis_angle(&axis, angle).into_inner())
    }

    fn shape(&self, semi_axes: &Num3, axes: Mat3, key: &str) -> Result<Ellipsoid, CliError> {
        let r = *semi_axes.get_ref();
        for (i, v) in r.iter().enumerate() {
            if !(v.is_finite() && *v > 0.0) {
                return Err(self.err(
                    semi_axes.span(),
                    key,
                    format!("semi-axis {} must be finite and > 0, got {v}", i + 1),
                ));
            }
        }
        Ellipsoid::new(r, axes).map_err(|e| self.param(semi_axes.span(), key, e))
    }

    fn particles(
        &self,
        spec: &ParticlesSpec,
        template: &ParticleTemplate<SceneDrag>,
        flow: &SceneFlow,
    ) -> Result<ParticleSource, CliError> {
        let span = spec.density.span();
        let source = match (&spec.inject, spec.list.is_empty()) {
            (Some(_), false) => {
                return Err(self.err(
                    span,
                    "particles",
                    "give either `[[particles.list]]` or `[particles.inject]`, not both",
                ));
            }
            (None, true) => {
                return Err(self.err(
                    span,
                    "particles",
                    "give `[[particles.list]]` entries or `[particles.inject]`",
                ));
            }
            (None, false) => {
                let list = spec
                    .list
                    .iter()
                    .enumerate()
                    .map(|(i, p)| self.listed(p, &format!("particles.list[{i}]"), template, flow))
                    .collect::<Result<Vec<_>, _>>()?;
                ParticleSource::List(list)
            }
            (Some(inj), true) => self.injection(inj, template)?,
        };
        if source.count() > MAX_PARTICLES {
            return Err(self.err(
                span,
                "particles.inject.count",
                format!("at most {MAX_PARTICLES} particles"),
            ));
        }
        Ok(source)
    }

    fn listed(
        &self,
        p: &ParticleEntry,
        key: &str,
        template: &ParticleTemplate<SceneDrag>,
        flow: &SceneFlow,
    ) -> Result<Placement, CliError> {
        let axes = self.rotation(p.orientation.as_ref(), &format!("{key}.orientation"))?;
        let shape = self.shape(&p.semi_axes, axes, &format!("{key}.semi_axes"))?;
        let softness = self.material(&p.material, &format!("{key}.material"))?;
        let position = self.vec3(&p.position, &format!("{key}.position"))?;
        let velocity = match (&p.velocity, p.fluid_velocity) {
            (Some(v), true) => {
                return Err(self.err(
                    v.span(),
                    &format!("{key}.velocity"),
                    "give `velocity` or `fluid_velocity = true`, not both",
                ));
            }
            (Some(v), false) => Velocity::Given(self.vec3(v, &format!("{key}.velocity"))?),
            (None, true) => {
                flow.sample(&position, 0.0)
                    .map_err(|e| self.err(p.position.span(), &format!("{key}.position"), e.to_string()))?;
                Velocity::Fluid
            }
            (None, false) => Velocity::Given(Vec3::zeros()),
        };
        let placement = Placement {
            shape,
            softness,
            position,
            velocity,
        };
        // Build it once now, so a particle the model refuses (too slender, too heavy) is
        // reported at its entry rather than as a failed particle of the run.
        template.build(&placement.spec(Vec3::zeros())).map_err(|e| {
            self.param(
                p.semi_axes.span(),
                &format!("{key}.semi_axes, {key}.material, particles.density"),
                e,
            )
        })?;
        Ok(placement)
    }

    fn injection(&self, inj: &InjectSpec, template: &ParticleTemplate<SceneDrag>) -> Result<ParticleSource, CliError> {
        let key = "particles.inject";
        let count = *inj.count.get_ref();
        if count == 0 {
            return Err(self.err(inj.count.span(), "particles.inject.count", "must be at least 1"));
        }
        if inj.random_orientation && inj.orientation.is_some() {
            return Err(self.err(
                inj.semi_axes.span(),
                "particles.inject.orientation",
                "give `orientation` or `random_orientation = true`, not both",
            ));
        }
        let axes = self.rotation(inj.orientation.as_ref(), &format!("{key}.orientation"))?;
        let shape = self.shape(&inj.semi_axes, axes, &format!("{key}.semi_axes"))?;
        let softness = self.material(&inj.material, &format!("{key}.material"))?;
        let region = self.region(&inj.region)?;
        let placement = Placement {
            shape,
            softness,
            position: Vec3::zeros(),
            velocity: if inj.fluid_velocity {
                Velocity::Fluid
            } else {
                Velocity::Given(Vec3::zeros())
            },
        };
        template.build(&placement.spec(Vec3::zeros())).map_err(|e| {
            self.param(
                inj.semi_axes.span(),
                "particles.inject.semi_axes, particles.inject.material, particles.density",
                e,
            )
        })?;
        Ok(ParticleSource::Inject {
            count,
            region,
            random_orientation: inj.random_orientation,
            placement,
        })
    }

    fn region(&self, r: &RegionSpec) -> Result<super::inject::Region, CliError> {
        let at = r.kind.span();
        let key = "particles.inject.region";
        let k = |name: &str| format!("{key}.{name}");
        match r.kind.get_ref() {
            RegionKind::Point => {
                let (c, n, rr) = (k("centre"), k("normal"), k("radius"));
                self.refuse(
                    &[
                        (&c, r.centre.is_some()),
                        (&n, r.normal.is_some()),
                        (&rr, r.radius.is_some()),
                    ],
                    at.clone(),
                    "point",
                )?;
                let p = self.need(&r.at, at, &k("at"), "point")?;
                Ok(super::inject::Region::Point(self.vec3(p, &k("at"))?))
            }
            RegionKind::Disc => {
                let a = k("at");
                self.refuse(&[(&a, r.at.is_some())], at.clone(), "disc")?;
                let centre = self.need(&r.centre, at.clone(), &k("centre"), "disc")?;
                let normal = self.need(&r.normal, at.clone(), &k("normal"), "disc")?;
                let radius = self.need(&r.radius, at, &k("radius"), "disc")?;
                let n = self.vec3(normal, &k("normal"))?;
                if !(n.norm() > 0.0 && n.norm().is_finite()) {
                    return Err(self.err(normal.span(), &k("normal"), "must be a non-zero finite vector"));
                }
                Ok(super::inject::Region::Disc {
                    centre: self.vec3(centre, &k("centre"))?,
                    normal: n,
                    radius: self.positive(radius, &k("radius"))?,
                })
            }
        }
    }

    fn integrator(&self, spec: &IntegratorSpec) -> Result<SceneIntegrator, CliError> {
        let tol = |name: &str| match &spec.tol {
            Some(t) => Ok((self.positive(t, "integrator.tol")?, t.span())),
            None => Err(self.err(
                spec.dt.span(),
                "integrator.tol",
                format!("`{name}` needs a tolerance `tol`"),
            )),
        };
        let refuse_overdamped = |name: &str| {
            if spec.overdamped {
                Err(self.err(
                    spec.dt.span(),
                    "integrator.overdamped",
                    format!("`{name}` has an inertial barycentre only"),
                ))
            } else {
                Ok(())
            }
        };
        match spec.kind {
            IntegratorKind::Imex => {
                refuse_overdamped("imex")?;
                if let Some(t) = &spec.tol {
                    return Err(self.err(
                        t.span(),
                        "integrator.tol",
                        "`imex` is a fixed-step scheme; it takes `dt` only",
                    ));
                }
                Ok(SceneIntegrator::Imex(ImexPaper::default()))
            }
            IntegratorKind::ImexAdaptive => {
                refuse_overdamped("imex_adaptive")?;
                let (t, span) = tol("imex_adaptive")?;
                ImexAdaptive::new(t)
                    .map(SceneIntegrator::ImexAdaptive)
                    .map_err(|e| self.param(span, "integrator.tol", e))
            }
            IntegratorKind::Stokesian | IntegratorKind::StokesianRadau5 => {
                let (t, span) = tol("stokesian")?;
                let made = if spec.overdamped {
                    Stokesian::overdamped(t)
                } else {
                    Stokesian::new(t)
                };
                let scheme = if spec.kind == IntegratorKind::StokesianRadau5 {
                    Scheme::Radau5
                } else {
                    Scheme::Rosenbrock23
                };
                made.map(|s| SceneIntegrator::Stokesian(s.with_scheme(scheme)))
                    .map_err(|e| self.param(span, "integrator.tol", e))
            }
        }
    }

    fn plan(
        &self,
        integrator: &IntegratorSpec,
        end: &EndSpec,
        output: &OutputSpec,
        particles: u64,
    ) -> Result<(Plan, Vec<f64>), CliError> {
        let t_end = self.positive(&end.t_end, "end.t_end")?;
        let dt = self.positive(&integrator.dt, "integrator.dt")?;
        let outputs = match &output.every {
            None => vec![t_end],
            Some(every) => {
                let e = self.positive(every, "output.every")?;
                let n = (t_end / e).floor();
                // t_end and every are finite and > 0, so n is a number (∞ when every underflows).
                if n >= MAX_OUTPUTS as f64 {
                    return Err(self.err(
                        every.span(),
                        "output.every",
                        format!("t_end / every = {:e} output times; at most {MAX_OUTPUTS}", t_end / e),
                    ));
                }
                let mut times: Vec<f64> = (1..=n as u64)
                    .map(|k| k as f64 * e)
                    // An output within round-off of t_end would be a second frame at the same time.
                    .filter(|&t| t < t_end * (1.0 - 1e-9))
                    .collect();
                times.push(t_end);
                times
            }
        };
        // One state per particle at the start, every output time and the event.
        let samples = particles.saturating_mul(outputs.len() as u64 + 2);
        if samples > MAX_SAMPLES {
            let span = output.every.as_ref().map_or(end.t_end.span(), |e| e.span());
            return Err(self.err(
                span,
                "output.every",
                format!(
                    "{particles} particles × {} output times = {samples} states to keep; at most {MAX_SAMPLES} (write fewer outputs or split the run)",
                    outputs.len()
                ),
            ));
        }
        let mut plan = Plan::new(t_end, dt)
            .and_then(|p| p.with_outputs(&outputs))
            .map_err(|e| self.param(end.t_end.span(), "end.t_end, integrator.dt, output.every", e))?;
        if let Some(m) = &integrator.dt_max {
            let v = self.positive(m, "integrator.dt_max")?;
            plan = plan
                .with_dt_max(v)
                .map_err(|e| self.param(m.span(), "integrator.dt_max", e))?;
        }
        let max_steps = match &end.max_steps {
            Some(m) if *m.get_ref() == 0 => return Err(self.err(m.span(), "end.max_steps", "must be at least 1")),
            Some(m) => *m.get_ref(),
            None => DEFAULT_MAX_STEPS,
        };
        // No wall-time limit: it would make a particle's fate depend on the machine's load.
        let plan = plan.with_budget(Budget {
            max_steps,
            wall_time: None,
        });
        Ok((plan, outputs))
    }
}

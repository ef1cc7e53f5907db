//! One particle through the cavity: the experiment ([`Cavity`]), its outcome and the slip
//! against the fluid.

use super::*;
use crate::population::{
    Case, Fate, Fingerprint, Injector, Observer, ParticleRecord, ParticleRng, ParticleSpec, ParticleTemplate,
    RunOptions, Shard, Watch,
};

/// How a run ended, in the cavity's terms: a view of the population's [`Fate`] that
/// [`CavityRun::outcome`] gives (an escape is an exit through the lid, a deposit names its wall
/// from [`WALL_NAMES`], a failure keeps the time of its last accepted step).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum CavityFate<'a> {
    /// Left through the lid.
    Exited {
        /// Time (s).
        t: f64,
    },
    /// Stuck to a wall.
    Deposited {
        /// Time (s).
        t: f64,
        /// Wall name.
        wall: &'a str,
    },
    /// Still suspended at the end of tracking.
    Suspended,
    /// The particle's run failed (a typed step error), recorded instead of ending the study.
    Failed {
        /// Time of the last accepted step (s).
        t: f64,
        /// The error.
        reason: &'a str,
    },
}

impl CavityFate<'_> {
    /// Short label for tables: `exited`, `deposited`, `suspended` or `failed`.
    pub fn label(&self) -> &'static str {
        match self {
            CavityFate::Exited { .. } => "exited",
            CavityFate::Deposited { .. } => "deposited",
            CavityFate::Suspended => "suspended",
            CavityFate::Failed { .. } => "failed",
        }
    }

    /// Time of the exit or the deposition; `None` for a particle still suspended or failed.
    pub fn event_time(&self) -> Option<f64> {
        match self {
            CavityFate::Exited { t } | CavityFate::Deposited { t, .. } => Some(*t),
            CavityFate::Suspended | CavityFate::Failed { .. } => None,
        }
    }
}

/// A tracked particle.
#[derive(Debug, Clone)]
pub struct CavityRun {
    /// The release.
    pub release: Launch,
    /// Contact model used.
    pub contact: Contact,
    /// Shape model used (inertialess for the rigid limit whatever was asked).
    pub shape_model: ShapeModel,
    /// (t, x) samples [s, m]; a failed run's path ends at its last accepted state.
    pub path: Vec<(f64, Vec3)>,
    /// How the run ended: the population's record of it, patches indexing [`WALL_NAMES`]
    /// ([`CavityRun::outcome`] reads it in the cavity's terms).
    pub fate: Fate,
    /// Work.
    pub stats: RunStats,
    /// Validity diagnostics over the accepted steps (r₁ in m).
    pub validity: Validity,
    /// Slip relative to the fluid over the accepted steps.
    pub slip: Slip,
}

impl CavityRun {
    /// How the run ended, in the cavity's terms ([`CavityFate`]).
    pub fn outcome(&self) -> CavityFate<'_> {
        match &self.fate {
            Fate::Escaped { time, .. } => CavityFate::Exited { t: *time },
            Fate::Deposited { patch, time, .. } => CavityFate::Deposited {
                t: *time,
                wall: WALL_NAMES[*patch],
            },
            Fate::Suspended => CavityFate::Suspended,
            Fate::Failed { error } => CavityFate::Failed {
                t: self.path.last().map_or(0.0, |p| p.0),
                reason: error,
            },
        }
    }
}

/// A run serialises with its [`CavityRun::outcome`] under `outcome` in place of the
/// population's fate: the fields and values runs had when they stored the cavity's own fate.
impl Serialize for CavityRun {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        #[derive(Serialize)]
        #[serde(rename = "CavityRun")]
        struct Shim<'a> {
            release: &'a Launch,
            contact: &'a Contact,
            shape_model: &'a ShapeModel,
            path: &'a [(f64, Vec3)],
            outcome: CavityFate<'a>,
            stats: &'a RunStats,
            validity: &'a Validity,
            slip: &'a Slip,
        }
        Shim {
            release: &self.release,
            contact: &self.contact,
            shape_model: &self.shape_model,
            path: &self.path,
            outcome: self.outcome(),
            stats: &self.stats,
            validity: &self.validity,
            slip: &self.slip,
        }
        .serialize(serializer)
    }
}

/// The particle's slip |v − u(x)| relative to the undisturbed fluid at its barycentre over a
/// run's accepted steps [m/s]: the drift that the fluid-inertia force terms act on
/// (`paper-figures/fig15_fig16/NOTES.md`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, serde::Deserialize)]
pub struct Slip {
    /// Largest slip.
    pub max: f64,
    /// Median over time: each step's end-state slip weighted by the step's length, so that the
    /// short steps near walls do not outvote the rest of the path.
    pub median: f64,
}

impl Slip {
    /// From (step length, slip) samples; zeros for none.
    fn of(mut samples: Vec<(f64, f64)>) -> Self {
        samples.sort_by(|a, b| a.1.total_cmp(&b.1));
        let total: f64 = samples.iter().map(|s| s.0).sum();
        let mut seen = 0.0;
        let median = samples
            .iter()
            .find(|(dt, _)| {
                seen += dt;
                seen >= 0.5 * total
            })
            .map_or(0.0, |s| s.1);
        Self {
            max: samples.last().map_or(0.0, |s| s.1),
            median,
        }
    }
}

/// One point of [`Cavity::quasi_steady_slip`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct QuasiSteady {
    /// The quasi-steady slip |w| [m/s].
    pub slip: f64,
    /// |(∇u)u − a|/|a|: how far the blend of the cells' gradients (`grad_u`) times u is from
    /// the acceleration a along the streamline, i.e. the error of a Du/Dt built from `grad_u`
    /// (what the fluid-inertia terms used before they took [`FlowSample::convective`]).
    ///
    /// [`FlowSample::convective`]: crate::flow::FlowSample::convective
    pub acceleration_gap: f64,
}

/// How one particle is tracked through the cavity (paper §6.3): what must touch a wall, for how
/// long, at which tolerance, and how densely its path is kept.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tracking {
    /// What touches a wall: the particle's extent or its barycentre.
    pub contact: Contact,
    /// Tracking horizon t_max (s; the paper's 100 s).
    pub t_max: f64,
    /// Tolerance of the integrator ([`ShapeModel`] says which).
    pub tol: f64,
    /// Spacing of the kept path (s): the start, the first accepted step at or after each
    /// multiple of it, and the event or the end.
    pub dt_out: f64,
}

/// Why a release has no [`CavityRun`]: what the population's record says of it. A particle
/// that started and then failed has a run, whose outcome is [`CavityFate::Failed`].
///
/// The population keeps an error as displayed (its records are checkpointed as text), so the
/// variant says what happened and the message is the record's.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum MemberError {
    /// Its particle never started: drawing, building or planning the release failed.
    #[error("{error}")]
    NotStarted {
        /// The error, as displayed.
        error: String,
    },
    /// Its record's log (path, validity, slip) could not be read back: a checkpoint written by
    /// another version of the cavity's observer.
    #[error("{error}")]
    Log {
        /// The error, as displayed.
        error: String,
    },
}

/// The cavity experiment: flow field, walls, fluid and the particle model (law family and drag;
/// the paper's Neo-Hooke and Brenner by default).
#[derive(Clone)]
pub struct Cavity<'a, L = NeoHookeFactory, D = Brenner> {
    flow: VariantFlow<'a>,
    boundary: Planes,
    fluid: Fluid,
    shear_rate: f64,
    shape_model: ShapeModel,
    /// Scheme of the inertialess path.
    scheme: Scheme,
    model: ParticleModel<L, D>,
    /// Force terms beyond the paper's (none: the paper's model).
    forces: ForceTerms,
}

impl<'a> Cavity<'a> {
    /// Experiment on a loaded Re = 470 field ([`shipped_flow`]), inertialess shapes, the paper's
    /// particle model.
    pub fn new(flow: &'a BlendedFlow) -> Result<Self, StudyError> {
        let d = sym(&flow.sample(&release_point(), 0.0).map_err(StepError::from)?.grad_u);
        let shear_rate = (2.0 * d.component_mul(&d).sum()).sqrt();
        Ok(Self {
            flow: VariantFlow {
                mesh: flow,
                variant: Variant::default(),
            },
            boundary: walls(EDGE)?,
            fluid: Fluid::new(rho_fluid() * NU, rho_fluid())?,
            shear_rate,
            shape_model: ShapeModel::Inertialess,
            scheme: Scheme::Radau5,
            model: ParticleModel::default(),
            forces: ForceTerms::default(),
        })
    }
}

impl<'a, L: LawFactory, D: DragModel + Clone> Cavity<'a, L, D> {
    /// The same experiment with another particle model (law family, drag, bulk ratio).
    pub fn with_model<L2: LawFactory, D2: DragModel + Clone>(self, model: ParticleModel<L2, D2>) -> Cavity<'a, L2, D2> {
        Cavity {
            flow: self.flow,
            boundary: self.boundary,
            fluid: self.fluid,
            shear_rate: self.shear_rate,
            shape_model: self.shape_model,
            scheme: self.scheme,
            model,
            forces: self.forces,
        }
    }

    /// The same experiment with force terms beyond the paper's on the particle (e.g. the
    /// fluid-inertia terms [`fluid_inertia`]).
    pub fn with_forces(self, forces: ForceTerms) -> Self {
        Self { forces, ..self }
    }

    /// The same experiment with another scheme for the inertialess shape model (and the rigid
    /// limit, which always takes that path).
    pub fn with_scheme(self, scheme: Scheme) -> Self {
        Self { scheme, ..self }
    }

    /// The same experiment with another shape model.
    pub fn with_shape_model(self, shape_model: ShapeModel) -> Self {
        Self { shape_model, ..self }
    }

    /// The same experiment in a variant of the field. The particles keep their stiffness: Ca
    /// stays defined by the nominal field's γ̇₀ (the particle is real, the field uncertain).
    pub fn with_variant(self, variant: Variant) -> Result<Self, StudyError> {
        crate::error::positive("field scale", variant.scale)?;
        Ok(Self {
            flow: VariantFlow { variant, ..self.flow },
            ..self
        })
    }

    /// The same experiment with a neutrally buoyant particle (ρ_f = ρ_p, ν unchanged).
    pub fn neutrally_buoyant(self) -> Result<Self, StudyError> {
        Ok(Self {
            fluid: Fluid::new(RHO_PARTICLE * NU, RHO_PARTICLE)?,
            ..self
        })
    }

    /// The experiment's flow (the shipped field in its [`Variant`]) at `x`.
    pub fn sample(&self, x: &Vec3) -> Result<crate::flow::FlowSample, crate::error::FlowError> {
        self.flow.sample(x, 0.0)
    }

    /// Along `run`'s output path, the slip a Stokes sphere of the particle's volume has in
    /// quasi-steady motion (Maxey & Riley 1983 without the history force): with v̇ = a, the
    /// fluid's acceleration along the streamline (the sample's Du/Dt, the derivative of the
    /// field's u along u), the barycentre equation gives
    /// ```math
    /// ζ (u − v) = (m + C_m m_f)\,a − (C_u + C_m)\,m_f\, a − (m − m_f)\,g,\qquad ζ = 3πμ_f d_{eq},
    /// ```
    /// C_u = 1 with the undisturbed-flow force, C_m = ½ with added mass (0 without). Without the
    /// terms the inertial drift is m a/ζ; with both it is (m − m_f) a/ζ, smaller by
    /// ρ_p/|ρ_p − ρ_f| (2 000 here; zero for a neutrally buoyant particle, which then follows
    /// the fluid up to the terms of order τ² the quasi-steady balance drops). For other shapes
    /// it is an estimate.
    pub fn quasi_steady_slip(&self, run: &CavityRun) -> Result<Vec<QuasiSteady>, StudyError> {
        let names = self.forces.names();
        let c_u = if names.contains(&UndisturbedFlow::NAME) {
            1.0
        } else {
            0.0
        };
        let c_m = if names.contains(&AddedMass::NAME) { 0.5 } else { 0.0 };
        let volume = std::f64::consts::PI / 6.0 * D_EQ.powi(3);
        let (m, m_f) = (RHO_PARTICLE * volume, self.fluid.rho * volume);
        let zeta = 3.0 * std::f64::consts::PI * self.fluid.mu * D_EQ;
        let g = Vec3::new(0.0, 0.0, -9.81);
        let mut out = Vec::with_capacity(run.path.len());
        for (_, x) in &run.path {
            let s = self.flow.sample(x, 0.0).map_err(StepError::from)?;
            let a = s.material_acceleration();
            if a == Vec3::zeros() {
                continue;
            }
            let lag = (a * (m + c_m * m_f) - a * ((c_u + c_m) * m_f) - g * (m - m_f)) / zeta;
            out.push(QuasiSteady {
                slip: lag.norm(),
                acceleration_gap: (s.grad_u * s.u - a).norm() / a.norm(),
            });
        }
        Ok(out)
    }

    /// γ̇₀ = √(2 d:d) at the release point [1/s].
    pub fn release_shear_rate(&self) -> f64 {
        self.shear_rate
    }

    fn particle(&self, release: &Launch) -> Result<Particle<StudyResponse<L>, D>, StudyError> {
        let shape = release.shape.ellipsoid(D_EQ, Mat3::identity())?;
        // The inertial runs are error-controlled, so they resolve what the traction does to the
        // volume mode: the literal eq. 12 anti-damps dilation (see
        // `integrator::imex::volume_mode_floor`; at tol 1e-7 J − 1 grew from 3e-5 to 1.6), the
        // source-flow term resists it as a fluid does. Shapes are unaffected (|J − 1| ≈ 1e-4
        // at λ_s/μ_s = 1e3); the inertialess model keeps tr l_s = 0 and ignores the choice.
        // The rigid limit (Ca → 0) is a rigid particle: Jeffery rotation, no elasticity.
        let particle = self.model.particle(
            shape,
            release.softness,
            self.fluid.mu * self.shear_rate,
            self.fluid,
            RHO_PARTICLE,
        )?;
        Ok(particle
            .with_gravity(Vec3::new(0.0, 0.0, -9.81))?
            .with_volumetric(VolumetricTraction::Source)
            .with_forces(self.forces.clone())?)
    }

    /// Track `release` turned by the rotation `turn` as `tracking` says. The release's axes
    /// become turn·(e_x, e_y, e_z) and F = turn, so the stress-free shape is turned as a rigid
    /// body; `&Mat3::identity()` is the nominal release.
    ///
    /// # Errors
    /// A release that cannot be built, a turn that is not a rotation and a failed population
    /// run are errors of the call; a particle that fails on its way is a run with the outcome
    /// [`CavityFate::Failed`].
    pub fn track(&self, release: Launch, turn: &Mat3, tracking: &Tracking) -> Result<CavityRun, StudyError>
    where
        L::Law: Releasable,
    {
        // A release that cannot be built is an error of the call, not an outcome.
        self.particle(&release)?;
        self.flow.sample(&release_point(), 0.0).map_err(StepError::from)?;
        let model = self.model_of(&release);
        let jobs = [(release, *turn)];
        let options = RunOptions::default().serial().quiet();
        let run = self.run_with(model, &jobs, tracking, &options, None)?;
        run.into_iter()
            .next()
            .expect("one release gives one run")
            .map_err(|e| StudyError::Population(e.to_string()))
    }

    /// The shape model `release` is tracked with: the rigid limit has no shape dynamics and
    /// always takes the inertialess path.
    pub(super) fn model_of(&self, release: &Launch) -> ShapeModel {
        match (self.shape_model, release.softness) {
            (ShapeModel::Inertial, Deformability::Elastic { .. }) => ShapeModel::Inertial,
            _ => ShapeModel::Inertialess,
        }
    }

    /// `jobs` (all tracked with `model`) through [`Self::run_population`] with the model's
    /// integrator at the tolerance of `tracking`, checkpointed in `dir` if given (and resumed
    /// from it). A turn that is not a rotation is an error of the call.
    pub(super) fn run_with(
        &self,
        model: ShapeModel,
        jobs: &[(Launch, Mat3)],
        tracking: &Tracking,
        options: &RunOptions,
        dir: Option<&std::path::Path>,
    ) -> Result<Vec<Result<CavityRun, MemberError>>, StudyError>
    where
        L::Law: Releasable,
    {
        for (_, turn) in jobs {
            let defect = (turn.transpose() * turn - Mat3::identity()).amax();
            if defect > 1e-12 || turn.determinant() <= 0.0 {
                return Err(crate::error::ParamError::NotARotation {
                    orthogonality_defect: defect,
                    det: turn.determinant(),
                }
                .into());
            }
        }
        match model {
            ShapeModel::Inertial => {
                let integ = ImexAdaptive::new(tracking.tol)?;
                self.run_population(&integ, model, jobs, tracking, options, dir)
            }
            ShapeModel::Inertialess => {
                // Rigid releases are rigid particles (see `particle`); the integrator is the same.
                let mut integ = Stokesian::new(tracking.tol)?.with_scheme(self.scheme);
                integ.barycentre = BarycentreModel::Inertial;
                self.run_population(&integ, model, jobs, tracking, options, dir)
            }
        }
    }

    /// The cavity's releases `jobs` (release, initial rotation) as one population of the
    /// runner ([`crate::population`]): particle k is `jobs[k]`, tracked by `integ` as
    /// `tracking` says (its horizon, contact and path spacing), its fate kept as the run's
    /// [`CavityRun::fate`]. A release that could not be drawn or built is a [`MemberError`].
    fn run_population<I: TimeIntegrator + std::fmt::Debug>(
        &self,
        integ: &I,
        shape_model: ShapeModel,
        jobs: &[(Launch, Mat3)],
        tracking: &Tracking,
        options: &RunOptions,
        dir: Option<&std::path::Path>,
    ) -> Result<Vec<Result<CavityRun, MemberError>>, StudyError>
    where
        L::Law: Releasable,
    {
        let Tracking {
            contact, t_max, dt_out, ..
        } = *tracking;
        let injection = Injection { cavity: self, jobs };
        let observer = Observe { dt_out };
        // Each particle's plan is its own ([`Injection::plan`]); this one gives the time limit.
        let plan = Plan::new(t_max, t_max)?;
        let case = Case::new(integ, &self.flow, &self.boundary, &injection, plan)
            .with_contact(contact.model())
            .with_observer(&observer);
        let config = Fingerprint::new("cavity")
            .with("variant", &self.flow.variant)
            .particles(&jobs)
            .with("contact", &contact)
            .config(0, jobs.len() as u64);
        let output = match dir {
            Some(dir) => crate::population::run_in_dir(&case, &config, Shard::ALL, dir, &options.clone().resume(true))?,
            None => crate::population::run(&case, &config, Shard::ALL, options)?,
        };
        Ok(output
            .records
            .into_iter()
            .map(|record| self.cavity_run(record, jobs, contact, shape_model))
            .collect())
    }

    /// The scene's reading of a population record: its fate, the observed path, validity and
    /// slip.
    fn cavity_run(
        &self,
        record: ParticleRecord<L::Law>,
        jobs: &[(Launch, Mat3)],
        contact: Contact,
        shape_model: ShapeModel,
    ) -> Result<CavityRun, MemberError>
    where
        L::Law: Releasable,
    {
        let release = jobs[record.index as usize].0;
        if let Fate::Failed { error } = &record.fate
            && record.observed.is_null()
        {
            return Err(MemberError::NotStarted { error: error.clone() });
        }
        let log: Log =
            serde_json::from_value(record.observed).map_err(|e| MemberError::Log { error: e.to_string() })?;
        Ok(CavityRun {
            release,
            contact,
            shape_model,
            path: log.path,
            fate: record.fate,
            stats: record.stats,
            validity: log.validity,
            slip: log.slip,
        })
    }
}

/// What a law needs to be a population's ([`crate::population::Injector::Law`]).
pub trait Releasable:
    crate::material::StressLaw + Clone + PartialEq + std::fmt::Debug + Serialize + serde::de::DeserializeOwned
{
}

impl<T> Releasable for T where
    T: crate::material::StressLaw + Clone + PartialEq + std::fmt::Debug + Serialize + serde::de::DeserializeOwned
{
}

/// The cavity's releases as a population's injection: particle k is release k, at the release
/// point with the local fluid velocity, turned by its rotation (F = the rotation).
struct Injection<'c, 'a, L, D> {
    cavity: &'c Cavity<'a, L, D>,
    jobs: &'c [(Launch, Mat3)],
}

impl<L: LawFactory, D: DragModel + Clone> Injector for Injection<'_, '_, L, D>
where
    L::Law: Releasable,
{
    type Law = L::Law;
    type Drag = D;

    fn draw(&self, index: u64, _rng: &mut ParticleRng) -> Result<ParticleSpec<L::Law>, StepError> {
        let cavity = self.cavity;
        let release = self.jobs[index as usize].0;
        let x = release_point();
        Ok(ParticleSpec {
            shape: release.shape.ellipsoid(D_EQ, Mat3::identity())?,
            softness: cavity
                .model
                .response(release.softness, cavity.fluid.mu * cavity.shear_rate)?,
            density: RHO_PARTICLE,
            position: x,
            velocity: cavity.flow.sample(&x, 0.0)?.u,
        })
    }

    fn particle(&self, spec: &ParticleSpec<L::Law>) -> Result<Particle<StudyResponse<L>, D>, ParamError> {
        // As [`Cavity::particle`]: gravity, the source-flow volumetric traction, the force terms.
        ParticleTemplate::new(
            self.cavity.model.drag().clone(),
            self.cavity.fluid,
            Vec3::new(0.0, 0.0, -9.81),
        )?
        .with_volumetric(VolumetricTraction::Source)
        .with_forces(self.cavity.forces.clone())
        .build(spec)
    }

    fn start_state(&self, index: u64, spec: &ParticleSpec<L::Law>) -> State {
        State {
            f: self.jobs[index as usize].1,
            ..spec.start_state()
        }
    }

    /// No step may carry the particle further than a quarter of its smallest semi-axis
    /// (|u| ≤ U_lid): in the corners two walls are near at once, and the contact event
    /// watches only the nearest.
    fn plan(&self, _index: u64, spec: &ParticleSpec<L::Law>, plan: &Plan) -> Result<Plan, ParamError> {
        let dt_max = 0.25 * spec.shape.semi_axes().min() / LID_VELOCITY;
        Plan::new(plan.t_end(), dt_max)?.with_dt_max(dt_max)
    }
}

/// What a cavity run keeps besides its fate.
#[derive(Serialize, serde::Deserialize)]
struct Log {
    path: Vec<(f64, Vec3)>,
    validity: Validity,
    slip: Slip,
}

/// The cavity's observer: the path (the start, the first accepted step at or after each
/// multiple of `dt_out`, the event or the end), the validity monitor and the slip.
struct Observe {
    dt_out: f64,
}

impl<M: crate::material::Response, D: DragModel> Observer<Particle<M, D>, VariantFlow<'_>, Planes> for Observe {
    fn fingerprint(&self) -> String {
        format!("cavity path every {:?} s, validity, slip", self.dt_out)
    }

    fn watch<'w>(
        &'w self,
        particle: &'w Particle<M, D>,
        flow: &'w VariantFlow<'_>,
        boundary: &'w Planes,
        start: &State,
    ) -> Box<dyn Watch + 'w> {
        let mut monitor = Monitor::new(particle, flow, boundary);
        monitor.observe(start);
        Box::new(Watching {
            monitor,
            dt_out: self.dt_out,
            next_out: self.dt_out,
            path: Vec::new(),
            slips: Vec::new(),
        })
    }
}

struct Watching<'w, M, D, F> {
    monitor: Monitor<'w, M, D, F, Planes>,
    dt_out: f64,
    next_out: f64,
    path: Vec<(f64, Vec3)>,
    slips: Vec<(f64, f64)>,
}

impl<M: crate::material::Response, D: DragModel, F: FlowField> Watch for Watching<'_, M, D, F> {
    fn output(&mut self, state: &State) {
        self.path.push((state.t, state.x));
    }

    fn step(&mut self, step: &crate::driver::AcceptedStep) {
        self.monitor.observe_step(step);
        let state = step.state();
        if let Ok(fluid) = step.flow() {
            self.slips.push((step.info().dt, (state.v - fluid.u).norm()));
        }
        if state.t >= self.next_out {
            self.path.push((state.t, state.x));
            self.next_out = self.dt_out * ((state.t / self.dt_out).floor() + 1.0);
        }
    }

    fn finish(mut self: Box<Self>, fate: &Fate, end: &State) -> serde_json::Value {
        match fate {
            Fate::Suspended if self.path.last().is_none_or(|(t, _)| *t < end.t) => self.path.push((end.t, end.x)),
            Fate::Failed { .. } => self.path.push((end.t, end.x)),
            _ => {}
        }
        let log = Log {
            path: std::mem::take(&mut self.path),
            validity: self.monitor.validity(),
            slip: Slip::of(std::mem::take(&mut self.slips)),
        };
        serde_json::to_value(&log).expect("a cavity log is plain data")
    }
}

//! The TOML form of a scene, as written: every table refuses unknown keys, and every number
//! keeps its place in the file so that a bad value is reported at its line and column.
//! [`crate::scene`] turns it into library objects through their validated constructors.

use serde::Deserialize;
use toml::Spanned;

/// A number with its place in the file.
pub type Num = Spanned<f64>;
/// Three numbers with their place in the file.
pub type Num3 = Spanned<Triple>;

/// Three numbers, exactly: a longer or shorter array is an error (a fixed-size array would
/// drop the rest of `[a, b, c, d]`).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(try_from = "Vec<f64>")]
pub struct Triple(pub [f64; 3]);

impl TryFrom<Vec<f64>> for Triple {
    type Error = String;
    fn try_from(v: Vec<f64>) -> Result<Self, String> {
        <[f64; 3]>::try_from(v.as_slice())
            .map(Triple)
            .map_err(|_| format!("expected 3 numbers, got {}", v.len()))
    }
}

/// A whole scene file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Document {
    /// Run seed: particle k of an injection draws from stream k of it (default 0).
    #[serde(default)]
    pub seed: u64,
    /// The carrier flow.
    pub flow: FlowSpec,
    /// The carrier fluid.
    pub fluid: FluidSpec,
    /// Walls and exits; none: the particles run to the end time.
    pub boundary: Option<BoundarySpec>,
    /// The particles.
    pub particles: Spanned<ParticlesSpec>,
    /// The time integrator.
    pub integrator: IntegratorSpec,
    /// When each particle's run ends.
    pub end: EndSpec,
    /// What is written.
    #[serde(default)]
    pub output: OutputSpec,
}

/// `[flow]`: a kind and the keys that kind takes.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FlowSpec {
    /// Which flow.
    #[serde(rename = "type")]
    pub kind: Spanned<FlowKind>,
    /// γ̇ or ε̇ (`shear`, `planar_extension`, `uniaxial_extension`).
    pub rate: Option<Num>,
    /// Pipe radius R (`poiseuille`).
    pub radius: Option<Num>,
    /// Mean velocity Ū (`poiseuille`; the centreline velocity is 2Ū).
    pub mean_velocity: Option<Num>,
    /// Case folder, relative to the scene file (`openfoam`).
    pub case: Option<Spanned<String>>,
    /// Two to four case folders of one geometry, finest or coarsest first (`openfoam`, instead
    /// of `case`): a mesh study, run by `pseudorigid study` (`scene::study`).
    pub cases: Option<Spanned<Vec<Spanned<String>>>>,
    /// Time directories to read (`openfoam`): a time or `"latest"` (the default), a steady
    /// field; a list of times or a range `{ start, end, period }`, a transient field read
    /// window by window (`flow::openfoam::TransientFlow`).
    pub time: Option<Spanned<TimeSpec>>,
    /// How a transient field stores its levels: `"f64"` (default) or `"f32"` (half the memory,
    /// a relative error below 2⁻²⁴).
    pub precision: Option<Spanned<PrecisionSpec>>,
    /// Length of a transient field's time windows (default: the smallest spacing of its
    /// levels).
    pub window: Option<Num>,
    /// Blend the cells' linear fits into a continuous field with the no-slip wall layer
    /// (`openfoam`; default true; see `flow::openfoam::BlendedFlow`). `false` gives the cellwise
    /// field: discontinuous at faces, without the wall-normal velocity that carries slow
    /// particles to a wall, and with an O(h²) velocity on the wall itself.
    #[serde(default = "default_blend")]
    pub blend: bool,
    /// The fluid is at rest (`openfoam`; default false): a case whose U is zero in every cell is
    /// then read as still fluid (settling in a closed box, a particle thrown into still air)
    /// instead of refused as a likely initial condition.
    #[serde(default)]
    pub still: bool,
}

fn default_blend() -> bool {
    true
}

/// `flow.time`: which time directories an OpenFOAM flow reads.
#[derive(Debug, Clone)]
pub enum TimeSpec {
    /// One time: a steady field.
    One(f64),
    /// The levels of a transient field, linear in time between them.
    Many(Vec<f64>),
    /// The time directories in a range: a transient field.
    Range(TimeRange),
    /// `"latest"`: the last time directory.
    Named(String),
}

/// Read by the kind of value written, so that a bad table names its bad key (`unknown field
/// `strat``) where an untagged enum would only say that no form matched.
impl<'de> Deserialize<'de> for TimeSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        let number = |v: &toml::Value| match v {
            toml::Value::Float(x) => Some(*x),
            // TOML integers are times too (`time = 1`); beyond 2⁵³ they round, as any f64.
            toml::Value::Integer(i) => Some(*i as f64),
            _ => None,
        };
        let value = toml::Value::deserialize(d)?;
        match &value {
            toml::Value::String(name) => Ok(TimeSpec::Named(name.clone())),
            toml::Value::Array(items) => items
                .iter()
                .enumerate()
                .map(|(i, v)| number(v).ok_or_else(|| D::Error::custom(format!("time[{i}] must be a number, got {v}"))))
                .collect::<Result<_, _>>()
                .map(TimeSpec::Many),
            toml::Value::Table(_) => TimeRange::deserialize(value)
                .map(TimeSpec::Range)
                .map_err(D::Error::custom),
            v => number(v).map(TimeSpec::One).ok_or_else(|| {
                D::Error::custom(format!(
                    "expected a time, a list of times, {{ start, end, period }} or \"latest\", got {v}"
                ))
            }),
        }
    }
}

/// `flow.time = { start, end, period }`: the case's time directories in [start, end] (by
/// default its first and last), repeated with `period` if given.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeRange {
    /// First time (default: the case's first time directory).
    pub start: Option<f64>,
    /// Last time (default: the case's last time directory).
    pub end: Option<f64>,
    /// The levels repeat with this period (one period's levels in [start, end]).
    pub period: Option<f64>,
}

/// `flow.precision`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PrecisionSpec {
    /// As computed.
    F64,
    /// Rounded to f32.
    F32,
}

/// The kinds of flow.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FlowKind {
    /// u = 0.
    Quiescent,
    /// u = γ̇ x₂ e₁.
    Shear,
    /// u = ε̇ (x₁, −x₂, 0).
    PlanarExtension,
    /// u = ε̇ (x₁, −x₂/2, −x₃/2).
    UniaxialExtension,
    /// Hagen–Poiseuille pipe along e₁.
    Poiseuille,
    /// An OpenFOAM case.
    Openfoam,
}

/// `[fluid]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FluidSpec {
    /// μ_f.
    pub viscosity: Num,
    /// ρ_f.
    pub density: Num,
    /// Gravitational acceleration (default 0).
    pub gravity: Option<Num3>,
}

/// `[boundary]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundarySpec {
    /// Which boundary.
    #[serde(rename = "type")]
    pub kind: Spanned<BoundaryKind>,
    /// Pipe radius (`pipe`).
    pub radius: Option<Num>,
    /// Planar walls (`planes`).
    #[serde(default)]
    pub walls: Vec<WallSpec>,
    /// Contact distance of a point particle; absent: the particle's extent touches.
    pub contact_radius: Option<Num>,
}

/// The kinds of boundary.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BoundaryKind {
    /// The wall of the Poiseuille pipe (every contact deposits).
    Pipe,
    /// Planar walls, each with a rule.
    Planes,
    /// The patches of the OpenFOAM mesh: walls deposit, other patches let the particle exit.
    Mesh,
}

/// `[[boundary.walls]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallSpec {
    /// Name in reports.
    pub name: String,
    /// A point on the plane.
    pub point: Num3,
    /// Outward normal.
    pub normal: Num3,
    /// `stick` or `exit`.
    pub rule: RuleSpec,
}

/// What a wall does to a particle that touches it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RuleSpec {
    /// Deposit.
    Stick,
    /// Leave the domain.
    Exit,
}

/// `[particles]`: what all particles share, and either a list or injection groups.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParticlesSpec {
    /// Solid density ρ_s of every entry or group that gives none of its own.
    pub density: Option<Num>,
    /// Drag model (default `brenner`).
    pub drag: Option<Spanned<DragEntry>>,
    /// Volumetric part of the traction (default `paper`, the literal eq. 12; `source` resists
    /// dilation as a fluid does and is what error-controlled inertial runs need).
    #[serde(default)]
    pub volumetric: VolumetricSpec,
    /// Force terms beyond the paper's drag and reduced gravity, by name
    /// (`crate::hydro::forces::by_name`): `"added_mass"`, or a table
    /// `{ term = "cunningham", mean_free_path = 6.65e-8 }` for a term with parameters.
    #[serde(default)]
    pub forces: Vec<Spanned<ForceEntry>>,
    /// Explicit particles.
    #[serde(default)]
    pub list: Vec<ParticleEntry>,
    /// Random injection: one group (`[particles.inject]`) or several (`[[particles.inject]]`).
    #[serde(default)]
    pub inject: Groups,
}

/// The injection groups: a single `[particles.inject]` table or an array of
/// `[[particles.inject]]` tables, in the order written (group g's particles follow group
/// g − 1's).
#[derive(Debug, Default)]
pub struct Groups(pub Vec<InjectSpec>);

impl<'de> Deserialize<'de> for Groups {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct OneOrMany;
        impl<'de> serde::de::Visitor<'de> for OneOrMany {
            type Value = Groups;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("an injection table or an array of injection tables")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<Groups, A::Error> {
                InjectSpec::deserialize(serde::de::value::MapAccessDeserializer::new(map)).map(|g| Groups(vec![g]))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, seq: A) -> Result<Groups, A::Error> {
                Vec::deserialize(serde::de::value::SeqAccessDeserializer::new(seq)).map(Groups)
            }
        }
        d.deserialize_any(OneOrMany)
    }
}

/// One entry of `particles.forces`: a term's name, or a table with the name under `term`
/// and the term's parameters (SI units), as a drag model's are given.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub enum ForceEntry {
    /// A term without parameters.
    Name(String),
    /// A term with parameters.
    Table {
        /// The term's name.
        term: String,
        /// Its parameters.
        #[serde(flatten)]
        parameters: std::collections::BTreeMap<String, toml::Value>,
    },
}

/// Volumetric tractions by name (`crate::hydro::VolumetricTraction`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VolumetricSpec {
    /// The literal eq. 12.
    #[default]
    Paper,
    /// No viscous resistance to volume change.
    Dev,
    /// Source-flow resistance (exact for a sphere).
    Source,
}

/// `particles.drag`: a registered drag model's name, or a table with the name under `model`
/// and the model's parameters (`crate::hydro::drag::by_name`).
#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub enum DragEntry {
    /// A model without parameters.
    Name(String),
    /// A model with parameters.
    Table {
        /// The model's name.
        model: String,
        /// Its parameters.
        #[serde(flatten)]
        parameters: std::collections::BTreeMap<String, toml::Value>,
    },
}

/// A model's table as written: its name under one key (`law`, `type`) and its parameters
/// beside it, each with its place in the file. The registry of its kind decides which keys it
/// takes, so a model added in one file needs no key here.
pub type ModelTable = Spanned<std::collections::BTreeMap<String, Spanned<toml::Value>>>;

/// `[[particles.list]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParticleEntry {
    /// Solid density ρ_s of this particle (default `particles.density`).
    pub density: Option<Num>,
    /// Rest semi-axes R₁, R₂, R₃.
    pub semi_axes: Num3,
    /// Initial orientation (default: the axes along e₁, e₂, e₃).
    pub orientation: Option<OrientationSpec>,
    /// Barycentre at t = 0.
    pub position: Num3,
    /// Velocity at t = 0 (default 0, or the fluid's with `fluid_velocity`).
    pub velocity: Option<Num3>,
    /// Start with the fluid velocity at `position`.
    #[serde(default)]
    pub fluid_velocity: bool,
    /// Shape response.
    pub material: MaterialSpec,
}

/// A rotation about `axis` by `angle` (radians, right-handed).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OrientationSpec {
    /// Rotation axis (any length > 0).
    pub axis: Num3,
    /// Angle in radians.
    pub angle: Num,
}

/// Shape response: `law`, a registered law's name (`crate::material::registry`) or `rigid`,
/// and the law's parameters (`neo_hooke`: `mu`, `lambda`; `mooney_rivlin`: `mu1`, `mu2`,
/// `lambda`; `expression`: `energy`, `parameters`).
pub type MaterialSpec = ModelTable;

/// `[particles.inject]`: one injection group.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InjectSpec {
    /// Number of particles.
    pub count: Spanned<u64>,
    /// Solid density ρ_s of this group (default `particles.density`).
    pub density: Option<Num>,
    /// Where they start.
    pub region: RegionSpec,
    /// A fixed initial orientation (default: the axes along e₁, e₂, e₃).
    pub orientation: Option<OrientationSpec>,
    /// Orientations uniform on SO(3) instead (default false).
    #[serde(default)]
    pub random_orientation: bool,
    /// Start with the fluid velocity.
    #[serde(default)]
    pub fluid_velocity: bool,
    /// Rest semi-axes.
    pub semi_axes: Num3,
    /// Shape response.
    pub material: MaterialSpec,
}

/// Injection region.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegionSpec {
    /// Which region.
    #[serde(rename = "type")]
    pub kind: Spanned<RegionKind>,
    /// The point (`point`).
    pub at: Option<Num3>,
    /// Centre (`disc`).
    pub centre: Option<Num3>,
    /// Normal (`disc`).
    pub normal: Option<Num3>,
    /// Radius (`disc`).
    pub radius: Option<Num>,
    /// How points spread over the disc (`disc`): `"area"` (default) or `"poiseuille"`.
    pub weight: Option<Spanned<crate::population::sampling::DiscWeight>>,
    /// The OpenFOAM patch particles enter through (`patch`).
    pub name: Option<Spanned<String>>,
}

/// Kinds of injection region.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RegionKind {
    /// Every particle at one point.
    Point,
    /// Uniform on a disc.
    Disc,
    /// On an OpenFOAM patch, weighted by the inflow through it.
    Patch,
}

/// `[integrator]`: `type`, a registered integrator's name or alias
/// (`crate::integrator::registry`), the first step `dt` and largest step `dt_max` (the plan's),
/// and the integrator's parameters (`tol`, `overdamped`, ...).
pub type IntegratorSpec = ModelTable;

/// `[end]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EndSpec {
    /// End time of every particle's run.
    pub t_end: Num,
    /// Accepted steps allowed per particle (default 10⁷).
    pub max_steps: Option<Spanned<u64>>,
}

/// `[output]`.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Interval between output times (default: only the end of each run).
    pub every: Option<Num>,
    /// Write ParaView files (default true).
    pub vtk: Option<bool>,
    /// Particles re-tracked on the other reconstruction of an OpenFOAM field
    /// (`scene::adequacy`; default `scene::DEFAULT_SAMPLE` on a steady OpenFOAM field, 0
    /// elsewhere; 0: no re-track).
    pub adequacy_sample: Option<Spanned<u64>>,
}

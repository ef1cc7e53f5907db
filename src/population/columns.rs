//! The columns of a run's tables, defined once. A record's columns ([`record_columns`]: name,
//! description, type and how each value is read from a [`ParticleRecord`]) make `results.csv`
//! ([`super::RunOutput::table`]), `records.parquet` (the command's `scene::parquet`) and the
//! Python package's `Results.records()`; a frame's columns ([`FRAME_COLUMNS`], the particles
//! of a run at one time by [`at_time`], flagged by [`fate_code`]) make `frames.csv`,
//! `frames.parquet` and `Results.frames()`.

use super::record::{Fate, ParticleRecord};
use super::spec::ParticleSpec;
use crate::ellipsoid::PrincipalFrame;
use crate::material::{Softness, StressLaw};
use crate::output::vtk::{CloudPoint, stretch};
use crate::particle::State;

/// One particle's record as its row of a table reads it: the record, the run's patch names and
/// the ellipsoid at the end (found once for the three semi-axes).
#[derive(Debug)]
pub struct Row<'a, L> {
    /// The particle's record.
    pub record: &'a ParticleRecord<L>,
    /// The run's patch names, by patch index.
    pub patches: &'a [String],
    /// [`ParticleRecord::end_frame`].
    pub end_frame: Option<PrincipalFrame>,
}

impl<'a, L> Row<'a, L> {
    /// The row of `record` in a run with patches `patches`.
    pub fn new(record: &'a ParticleRecord<L>, patches: &'a [String]) -> Self {
        Self {
            record,
            patches,
            end_frame: record.end_frame(),
        }
    }

    fn end(&self, f: impl Fn(&State) -> f64) -> Option<f64> {
        self.record.end.as_ref().map(f)
    }

    fn spec(&self, f: impl Fn(&ParticleSpec<L>) -> f64) -> Option<f64> {
        self.record.spec.as_ref().map(f)
    }

    /// The name of the patch touched ("" for an index without a name).
    fn patch_name(&self) -> Option<&'a str> {
        let patches = self.patches;
        self.record
            .fate
            .patch()
            .map(|p| patches.get(p).map_or("", String::as_str))
    }

    /// The error of a failed particle.
    fn error(&self) -> Option<&'a str> {
        let record = self.record;
        match &record.fate {
            Fate::Failed { error } => Some(error),
            _ => None,
        }
    }
}

impl<L: StressLaw> Row<'_, L> {
    /// μ_s of an elastic particle.
    fn shear_modulus(&self) -> Option<f64> {
        match &self.record.spec.as_ref()?.softness {
            Softness::Elastic(law) => Some(law.shear_modulus()),
            Softness::Rigid => None,
        }
    }
}

/// A column's type and how a row gives its value; `None` is a value that does not exist (the
/// patch of a suspended particle, μ_s of a rigid one): an empty CSV field, a Parquet null, NaN
/// or None in Python.
pub enum ColumnValues<L> {
    /// A count, always there (index, steps): unsigned in Parquet, an int64 array in Python.
    Count(fn(&Row<'_, L>) -> u64),
    /// An integer.
    Int(fn(&Row<'_, L>) -> Option<i64>),
    /// A real number.
    Real(fn(&Row<'_, L>) -> Option<f64>),
    /// A text (in CSV with commas and line breaks replaced by spaces).
    Text(for<'a> fn(&Row<'a, L>) -> Option<&'a str>),
}

/// One column of a record's row.
pub struct Column<L> {
    /// Its name in every table.
    pub name: &'static str,
    /// What it holds.
    pub doc: &'static str,
    /// Whether `results.csv` has it (it leaves out F and the work counts besides the steps).
    pub csv: bool,
    /// Its type and values.
    pub values: ColumnValues<L>,
}

/// A column of a record's row.
const fn column<L>(name: &'static str, doc: &'static str, csv: bool, values: ColumnValues<L>) -> Column<L> {
    Column { name, doc, csv, values }
}

/// The columns of a record's row, in the order of every table: index, fate, patch and its name,
/// the end state (t, x, r₁ ≥ r₂ ≥ r₃, F), the particle's spec (injection point, rest semi-axes,
/// μ_s, ρ_s), step statistics, what the slow-manifold switch did
/// ([`crate::integrator::manifold`]) and the error of a failed particle.
///
/// The switch's columns describe every particle: a particle the slow-manifold integrator did
/// not step (another integrator, or `auto`'s full model) took 0 steps on the manifold and all
/// its `steps` with the full model, so sums over a table are the run's totals; the largest δ on
/// the manifold is empty without a step on it, and δ_max is empty where the slow-manifold
/// integrator did not step the particle.
#[rustfmt::skip]
pub fn record_columns<L: StressLaw>() -> [Column<L>; 39] {
    use ColumnValues::{Count, Int, Real, Text};
    // In every table; in all but `results.csv`.
    const ALL: bool = true;
    const NO_CSV: bool = false;
    [
        column("index", "Particle index k.", ALL, Count(|r| r.record.index)),
        column("fate", "`deposited`, `escaped`, `suspended` or `failed`.", ALL, Text(|r| Some(r.record.fate.label()))),
        column("patch", "Index of the patch touched.", ALL, Int(|r| r.record.fate.patch().map(|p| p as i64))),
        column("patch_name", "Name of the patch touched.", ALL, Text(|r| r.patch_name())),
        column("t", "Time of the end state.", ALL, Real(|r| r.end(|s| s.t))),
        column("x1", "Barycentre x₁ at the end.", ALL, Real(|r| r.end(|s| s.x[0]))),
        column("x2", "Barycentre x₂ at the end.", ALL, Real(|r| r.end(|s| s.x[1]))),
        column("x3", "Barycentre x₃ at the end.", ALL, Real(|r| r.end(|s| s.x[2]))),
        column("r1", "Largest semi-axis at the end.", ALL, Real(|r| r.end_frame.map(|f| f.r[0]))),
        column("r2", "Middle semi-axis at the end.", ALL, Real(|r| r.end_frame.map(|f| f.r[1]))),
        column("r3", "Smallest semi-axis at the end.", ALL, Real(|r| r.end_frame.map(|f| f.r[2]))),
        column("F11", "F₁₁ at the end.", NO_CSV, Real(|r| r.end(|s| s.f[(0, 0)]))),
        column("F12", "F₁₂ at the end.", NO_CSV, Real(|r| r.end(|s| s.f[(0, 1)]))),
        column("F13", "F₁₃ at the end.", NO_CSV, Real(|r| r.end(|s| s.f[(0, 2)]))),
        column("F21", "F₂₁ at the end.", NO_CSV, Real(|r| r.end(|s| s.f[(1, 0)]))),
        column("F22", "F₂₂ at the end.", NO_CSV, Real(|r| r.end(|s| s.f[(1, 1)]))),
        column("F23", "F₂₃ at the end.", NO_CSV, Real(|r| r.end(|s| s.f[(1, 2)]))),
        column("F31", "F₃₁ at the end.", NO_CSV, Real(|r| r.end(|s| s.f[(2, 0)]))),
        column("F32", "F₃₂ at the end.", NO_CSV, Real(|r| r.end(|s| s.f[(2, 1)]))),
        column("F33", "F₃₃ at the end.", NO_CSV, Real(|r| r.end(|s| s.f[(2, 2)]))),
        column("x0_1", "Injection point, x₁.", ALL, Real(|r| r.spec(|s| s.position[0]))),
        column("x0_2", "Injection point, x₂.", ALL, Real(|r| r.spec(|s| s.position[1]))),
        column("x0_3", "Injection point, x₃.", ALL, Real(|r| r.spec(|s| s.position[2]))),
        column("rest_r1", "Rest semi-axis R₁.", ALL, Real(|r| r.spec(|s| s.shape.semi_axes()[0]))),
        column("rest_r2", "Rest semi-axis R₂.", ALL, Real(|r| r.spec(|s| s.shape.semi_axes()[1]))),
        column("rest_r3", "Rest semi-axis R₃.", ALL, Real(|r| r.spec(|s| s.shape.semi_axes()[2]))),
        column("mu_s", "Shear modulus μ_s of the solid (none: rigid).", ALL, Real(|r| r.shear_modulus())),
        column("rho_s", "Density ρ_s of the solid.", ALL, Real(|r| r.spec(|s| s.density))),
        column("steps", "Accepted steps.", ALL, Count(|r| r.record.stats.steps)),
        column("rejected", "Rejected step attempts.", NO_CSV, Count(|r| r.record.stats.rejected)),
        column("rhs_evals", "Model evaluations.", NO_CSV, Count(|r| r.record.stats.rhs_evals)),
        column("jac_evals", "Jacobian evaluations.", NO_CSV, Count(|r| r.record.stats.jac_evals)),
        column("manifold_steps", "Accepted steps on the slow manifold (0 where it never ran).", NO_CSV, Count(|r| r.record.integrator.manifold.map_or(0, |m| m.manifold_steps))),
        column("full_steps", "Accepted steps of the full model: `steps` less `manifold_steps`.", NO_CSV, Count(|r| r.record.integrator.manifold.map_or(r.record.stats.steps, |m| m.full_steps))),
        column("manifold_entered", "Switches from the full model to the slow manifold.", NO_CSV, Count(|r| r.record.integrator.manifold.map_or(0, |m| m.entered.into()))),
        column("manifold_left", "Switches from the slow manifold back to the full model.", NO_CSV, Count(|r| r.record.integrator.manifold.map_or(0, |m| m.left.into()))),
        column("manifold_max_ratio", "Largest expansion ratio δ of a step on the slow manifold (none: no such step).", NO_CSV, Real(|r| r.record.integrator.manifold.filter(|m| m.manifold_steps > 0).map(|m| m.max_ratio))),
        column("manifold_delta_max", "The slow manifold's bound δ_max (none: not stepped by the slow-manifold integrator).", NO_CSV, Real(|r| r.record.integrator.manifold.map(|m| m.delta_max))),
        column("error", "Why a failed particle failed.", ALL, Text(|r| r.error())),
    ]
}

/// Flag of a particle after its run: 1 deposited, 2 escaped, 3 suspended (reached the end
/// time), 4 failed. (0 is a moving particle.)
pub fn fate_code(fate: &Fate) -> i64 {
    match fate {
        Fate::Deposited { .. } => 1,
        Fate::Escaped { .. } => 2,
        Fate::Suspended => 3,
        Fate::Failed { .. } => 4,
    }
}

/// The particles of `records` at `time`: each with a state by then at its last state at or
/// before `time`, flagged 0 while it moves and afterwards by its fate ([`fate_code`]).
pub fn at_time<L>(records: &[ParticleRecord<L>], time: f64) -> impl Iterator<Item = CloudPoint> + '_ {
    records.iter().filter_map(move |r| {
        let spec = r.spec.as_ref()?;
        let last = r.samples.last()?;
        let state: &State = r.samples.iter().rev().find(|s| s.t <= time)?;
        let flag = if time < last.t { 0 } else { fate_code(&r.fate) };
        Some(CloudPoint {
            id: r.index as i64,
            x: state.x,
            f_bar: state.f * spec.shape.shape_tensor(),
            flag,
        })
    })
}

/// Columns of a frame's row in every table of frames (`frames.csv`, `frames.parquet`, the
/// Python package's frames): frame index, time, id, the [`frame_measures`] and the flag.
pub const FRAME_COLUMNS: [&str; 19] = [
    "frame", "time", "id", "x1", "x2", "x3", "V11", "V12", "V13", "V21", "V22", "V23", "V31", "V32", "V33", "r1", "r2",
    "r3", "flag",
];

/// The names of the [`frame_measures`]: the columns of [`FRAME_COLUMNS`] between `id` and `flag`.
pub fn frame_measure_names() -> &'static [&'static str] {
    &FRAME_COLUMNS[3..FRAME_COLUMNS.len() - 1]
}

/// The measured values of a particle in a frame ([`frame_measure_names`]): its barycentre, the
/// nine components of V = √(F̄F̄ᵀ) by rows (symmetric to the last bit, so V21 = V12; kept whole,
/// as ParaView's tensor glyphs read it) and its semi-axes.
pub fn frame_measures(p: &CloudPoint) -> [f64; 15] {
    let (v, r) = stretch(&p.f_bar);
    [
        p.x[0],
        p.x[1],
        p.x[2],
        v[(0, 0)],
        v[(0, 1)],
        v[(0, 2)],
        v[(1, 0)],
        v[(1, 1)],
        v[(1, 2)],
        v[(2, 0)],
        v[(2, 1)],
        v[(2, 2)],
        r[0],
        r[1],
        r[2],
    ]
}

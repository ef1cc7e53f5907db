//! Lid-driven cube cavity: centreline profiles and extrema against a reference table.
//!
//! # Physics
//! Cube [0, L]³, lid z = L moving with speed U in +x, all other walls at rest; Re = U L/ν.
//! Standard benchmark frame (Albensoeder & Kuhlmann 2005 mapped as in
//! `reference-data/cavity_re1000_albensoeder_kuhlmann.csv`): along the vertical centreline
//! (x = y = L/2) the streamwise velocity u_x/U as a function of height z/L; along the horizontal
//! centreline (y = z = L/2) the vertical velocity u_z/U as a function of x/L. The extrema are
//! u_min (vertical line), w_min and w_max (horizontal line).
//!
//! # Scheme
//! Profiles are sampled through [`FlowField::sample`]; an extremum is the best of
//! [`EXTREMUM_SAMPLES`] equispaced samples refined by the vertex of the parabola through it and
//! its two neighbours (error O(Δs³) in position for a smooth profile, far below the mesh size).

use crate::error::FlowError;
use crate::flow::FlowField;
use crate::flow::openfoam::{FoamError, FoamFlow, cavity_block, read_vol_field};
use crate::tensor::Vec3;
use std::path::{Path, PathBuf};

pub mod report;

/// Equispaced samples along a centreline for the extremum search.
pub const EXTREMUM_SAMPLES: usize = 2001;

/// Why a reference table could not be read.
#[derive(Debug, thiserror::Error)]
pub enum TableError {
    /// The file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// File concerned.
        path: String,
        /// Underlying I/O error.
        source: std::io::Error,
    },
    /// A row does not follow `quantity,position,value`.
    #[error("{path}:{line}: {reason}")]
    Malformed {
        /// File concerned.
        path: String,
        /// 1-based line of the row.
        line: usize,
        /// What was expected.
        reason: String,
    },
}

/// Geometry and lid speed of a cube cavity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CavityCase {
    /// Edge length L.
    pub edge: f64,
    /// Lid speed U (lid moves in +x at z = L).
    pub lid_speed: f64,
}

/// A cube-cavity field shipped in `reference-data/`: simpleFoam's cell-centred `U` of one of
/// the `cases/cavity-*` cases (gzipped ASCII, 6 significant digits; provenance beside it), read
/// onto the case's uniform block rebuilt by [`cavity_block`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShippedField {
    /// Directory under `reference-data/` holding `U.gz`.
    pub dir: &'static str,
    /// Cells per edge of the uniform block.
    pub cells: usize,
    /// Edge and lid speed.
    pub case: CavityCase,
}

/// The paper's cavity (§6.3): Re = U L/ν = 470, 60³ cells (`cases/cavity-re470`).
pub const RE470: ShippedField = ShippedField {
    dir: "cavity-re470-foam",
    cells: 60,
    case: CavityCase {
        edge: 0.1,
        lid_speed: 0.0813,
    },
};

/// The same case on 12³ cells (`cases/cavity-ci`), for quick checks; not converged in h.
pub const CI: ShippedField = ShippedField {
    dir: "cavity-ci-foam",
    cells: 12,
    ..RE470
};

/// The validation case at Re = 1000, 60³ cells (`cases/cavity-re1000`).
pub const RE1000: ShippedField = ShippedField {
    dir: "cavity-re1000-foam",
    cells: 60,
    case: CavityCase {
        edge: 0.1,
        lid_speed: 0.173,
    },
};

impl ShippedField {
    /// The field's directory in this crate's `reference-data/`.
    pub fn dir(&self) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("reference-data")
            .join(self.dir)
    }

    /// The steady field, cellwise ([`FoamFlow`]; `BlendedFlow::new` makes it continuous with
    /// the no-slip wall layer).
    pub fn load(&self) -> Result<FoamFlow, FoamError> {
        let mesh = cavity_block(self.cells, self.case.edge)?;
        let u = read_vol_field(&self.dir(), "U", &mesh, 3)?;
        FoamFlow::new(mesh, vec![(0.0, u)])
    }
}

/// The two benchmark centrelines.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Centreline {
    /// x = y = L/2: u_x/U against z/L.
    Vertical,
    /// y = z = L/2: u_z/U against x/L.
    Horizontal,
}

/// The three benchmark extrema.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Extremum {
    /// Minimum of u_x/U on the vertical centreline.
    UMin,
    /// Minimum of u_z/U on the horizontal centreline.
    WMin,
    /// Maximum of u_z/U on the horizontal centreline.
    WMax,
}

impl Centreline {
    /// Both lines.
    pub const ALL: [Centreline; 2] = [Centreline::Vertical, Centreline::Horizontal];

    /// Name used in the CSV files.
    pub fn name(self) -> &'static str {
        match self {
            Centreline::Vertical => "u_vertical",
            Centreline::Horizontal => "w_horizontal",
        }
    }
}

impl Extremum {
    /// All three extrema.
    pub const ALL: [Extremum; 3] = [Extremum::UMin, Extremum::WMin, Extremum::WMax];

    /// Name used in the CSV files.
    pub fn name(self) -> &'static str {
        match self {
            Extremum::UMin => "u_min",
            Extremum::WMin => "w_min",
            Extremum::WMax => "w_max",
        }
    }

    fn line(self) -> Centreline {
        match self {
            Extremum::UMin => Centreline::Vertical,
            Extremum::WMin | Extremum::WMax => Centreline::Horizontal,
        }
    }

    /// +1 for a maximum, −1 for a minimum.
    fn sign(self) -> f64 {
        match self {
            Extremum::WMax => 1.0,
            Extremum::UMin | Extremum::WMin => -1.0,
        }
    }
}

/// A value at a normalised position s ∈ [0, 1] along a centreline.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinePoint {
    /// Normalised position (z/L or x/L).
    pub position: f64,
    /// Normalised velocity component (u_x/U or u_z/U).
    pub value: f64,
}

/// A literature table: profiles along both centrelines and the three extrema.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ReferenceTable {
    /// Vertical-centreline profile u_x/U(z/L).
    pub vertical: Vec<LinePoint>,
    /// Horizontal-centreline profile u_z/U(x/L).
    pub horizontal: Vec<LinePoint>,
    /// Extrema with their positions, in [`Extremum::ALL`] order.
    pub extrema: Vec<(Extremum, LinePoint)>,
}

impl ReferenceTable {
    /// Read `quantity,position,value` rows (`#` comments, one header line) with quantity one of
    /// `u_vertical`, `w_horizontal`, `u_min`, `w_min`, `w_max`.
    pub fn read_csv(path: &Path) -> Result<Self, TableError> {
        let text = std::fs::read_to_string(path).map_err(|source| TableError::Io {
            path: path.display().to_string(),
            source,
        })?;
        let mut table = Self::default();
        let rows = (1..)
            .zip(text.lines())
            .filter(|(_, l)| !l.trim_start().starts_with('#'));
        for (line_no, line) in rows.skip(1) {
            let malformed = |reason: String| TableError::Malformed {
                path: path.display().to_string(),
                line: line_no,
                reason,
            };
            let fields: Vec<&str> = line.split(',').map(str::trim).collect();
            let [quantity, position, value] = fields.as_slice() else {
                return Err(malformed(format!("expected 3 fields in `{line}`")));
            };
            let number = |s: &str| {
                s.parse::<f64>()
                    .map_err(|_| malformed(format!("`{s}` is not a number")))
            };
            let point = LinePoint {
                position: number(position)?,
                value: number(value)?,
            };
            match *quantity {
                "u_vertical" => table.vertical.push(point),
                "w_horizontal" => table.horizontal.push(point),
                other => match Extremum::ALL.iter().find(|e| e.name() == other) {
                    Some(&e) => table.extrema.push((e, point)),
                    None => return Err(malformed(format!("unknown quantity `{other}`"))),
                },
            }
        }
        table.extrema.sort_by_key(|(e, _)| *e as u8);
        Ok(table)
    }

    /// The profile along one centreline.
    pub fn profile(&self, line: Centreline) -> &[LinePoint] {
        match line {
            Centreline::Vertical => &self.vertical,
            Centreline::Horizontal => &self.horizontal,
        }
    }
}

impl CavityCase {
    /// Normalised velocity component at normalised position `s` along `line`.
    pub fn sample(&self, flow: &impl FlowField, line: Centreline, s: f64) -> Result<f64, FlowError> {
        let (x, component) = match line {
            Centreline::Vertical => (Vec3::new(0.5, 0.5, s), 0),
            Centreline::Horizontal => (Vec3::new(s, 0.5, 0.5), 2),
        };
        Ok(flow.sample(&(x * self.edge), 0.0)?.u[component] / self.lid_speed)
    }

    /// `n ≥ 2` equispaced samples along `line`, walls included.
    pub fn profile(&self, flow: &impl FlowField, line: Centreline, n: usize) -> Result<Vec<LinePoint>, FlowError> {
        let last = n.max(2) - 1;
        (0..=last)
            .map(|i| {
                let position = i as f64 / last as f64;
                Ok(LinePoint {
                    position,
                    value: self.sample(flow, line, position)?,
                })
            })
            .collect()
    }

    /// Position and value of an extremum (see the module's Scheme).
    pub fn extremum(&self, flow: &impl FlowField, which: Extremum) -> Result<LinePoint, FlowError> {
        let samples = self.profile(flow, which.line(), EXTREMUM_SAMPLES)?;
        let sign = which.sign();
        let best = (1..samples.len() - 1)
            .max_by(|&a, &b| (sign * samples[a].value).total_cmp(&(sign * samples[b].value)))
            .unwrap_or(1);
        let (a, b, c) = (samples[best - 1], samples[best], samples[best + 1]);
        let h = b.position - a.position;
        let curvature = a.value - 2.0 * b.value + c.value;
        if curvature.abs() <= f64::EPSILON * b.value.abs() {
            return Ok(b);
        }
        let shift = 0.5 * h * (a.value - c.value) / curvature;
        let position = b.position + shift.clamp(-h, h);
        Ok(LinePoint {
            position,
            value: self.sample(flow, which.line(), position)?,
        })
    }
}

/// One extremum, simulated against reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExtremumComparison {
    /// Which extremum.
    pub which: Extremum,
    /// Simulated value and position.
    pub simulated: LinePoint,
    /// Reference value and position.
    pub reference: LinePoint,
}

impl ExtremumComparison {
    /// Relative error of the value, (simulated − reference)/reference: negative when the
    /// simulated extremum is shallower than the reference.
    pub fn relative_error(&self) -> f64 {
        (self.simulated.value - self.reference.value) / self.reference.value
    }
}

/// Compare the three extrema of `flow` with `reference`.
pub fn compare_extrema(
    case: &CavityCase,
    flow: &impl FlowField,
    reference: &ReferenceTable,
) -> Result<Vec<ExtremumComparison>, FlowError> {
    reference
        .extrema
        .iter()
        .map(|&(which, reference)| {
            Ok(ExtremumComparison {
                which,
                simulated: case.extremum(flow, which)?,
                reference,
            })
        })
        .collect()
}

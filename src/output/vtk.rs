//! ParaView files: VTK XML PolyData (`.vtp`) and the time-series index (`.pvd`).
//!
//! A [`PolyData`] is a set of points with vertex or polyline cells and named point arrays.
//! [`particle_cloud`] builds the usual one: one point per particle at its barycentre in global
//! coordinates, with
//! - `V`: the left stretch of the total distortion, $V = \sqrt{\bar F \bar F^T}$ (F̄ = F·S,
//!   paper §5), as a symmetric 3×3 tensor of 9 components, marked as the active tensor so that
//!   ParaView's *Tensor Glyph* filter draws every particle as its current ellipsoid (a unit
//!   sphere mapped by V has the semi-axes r_a along the principal directions n_a);
//! - `r1`, `r2`, `r3`: the current semi-axes r₁ ≥ r₂ ≥ r₃ (the eigenvalues of V);
//! - `id` and `flag` (what the caller says: an outcome code, a patch number).
//!
//! [`write_pvd`] lists one file per output time with its time value, which ParaView reads as a
//! time series.
//!
//! [`PolyData::write`] writes the arrays in binary and zlib-compressed, as VTK's own XML
//! writers do by default (`compressor="vtkZLibDataCompressor"`): each array's little-endian
//! values deflated as one block in the file's `<AppendedData encoding="raw">` section, preceded
//! by the block header (block count, uncompressed size, size of the last partial block,
//! compressed size; UInt64, `header_type="UInt64"`), the `<DataArray>` elements pointing into
//! it with `format="appended"` and `offset`. A f64 takes at most 8 bytes instead of the 18–24
//! characters of its shortest decimal form, and a reader gets the values bit for bit
//! (`cases/vtk-check.py` reads the files with VTK and compares them with the CSV output).
//! [`PolyData::single_precision`] writes the floats (points included) as Float32, as
//! OpenFOAM's `foamToVTK` does by default: enough to draw (relative rounding ≤ 2⁻²⁴ ≈ 6e-8)
//! and half the size; the run's exact values are in its Parquet or CSV tables.
//! [`PolyData::to_xml`] is the same data set as ASCII XML (every float in Rust's shortest
//! round-trip form), for reading by eye. Every file is written atomically
//! ([`super::write_atomic`]). Written by hand rather than with a crate: the format needed here
//! is three XML elements, and the Rust VTK crates either lack XML writing without a large
//! dependency tree or have not been released for years.

use super::{OutputError, write_atomic};
use crate::ellipsoid::PrincipalFrame;
use crate::tensor::{Mat3, Vec3};
use std::fmt::Write as _;
use std::path::Path;
use thiserror::Error;

/// Data that cannot be written as a VTK file.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum VtkError {
    /// An array does not have `components` values per point.
    #[error("array `{name}` has {got} values, expected {expected} ({components} per point)")]
    Length {
        /// Array name.
        name: String,
        /// Values per point.
        components: usize,
        /// Values expected.
        expected: usize,
        /// Values given.
        got: usize,
    },
    /// A value is NaN or infinite (the ASCII format and its readers have no such numbers).
    #[error("array `{name}` value {index} is {value}, not finite")]
    NonFinite {
        /// Array name (`Points` for coordinates).
        name: String,
        /// Index of the value in the flat array.
        index: usize,
        /// The value.
        value: f64,
    },
    /// A cell names a point that does not exist.
    #[error("polyline {line} refers to point {point}, but there are {points} points")]
    PointIndex {
        /// Polyline number.
        line: usize,
        /// Point index in the polyline.
        point: usize,
        /// Number of points.
        points: usize,
    },
    /// A name or file name that would need escaping in XML (names are identifiers here).
    #[error("`{0}` is not a plain name (letters, digits, `_`, `-`, `.`, `/` only)")]
    Name(String),
}

/// The values of one point array.
#[derive(Debug, Clone, PartialEq)]
pub enum PointValues {
    /// 64-bit floats.
    Float64(Vec<f64>),
    /// 64-bit integers (ids, flags, patch numbers).
    Int64(Vec<i64>),
}

impl PointValues {
    fn len(&self) -> usize {
        match self {
            PointValues::Float64(v) => v.len(),
            PointValues::Int64(v) => v.len(),
        }
    }
}

/// A named point array with `components` values per point.
#[derive(Debug, Clone, PartialEq)]
pub struct DataArray {
    name: String,
    components: usize,
    values: PointValues,
}

/// Points with vertex or polyline cells and point arrays: one `.vtp` file.
#[derive(Debug, Clone, PartialEq)]
pub struct PolyData {
    points: Vec<Vec3>,
    verts: bool,
    lines: Vec<Vec<usize>>,
    arrays: Vec<DataArray>,
    active_tensors: Option<String>,
    /// Floats (and points) written as Float32 ([`PolyData::single_precision`]).
    single: bool,
}

/// Names are written into XML attributes unescaped, so only plain names are accepted.
fn plain(name: &str) -> Result<&str, VtkError> {
    let ok = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.' | '/'));
    if ok {
        Ok(name)
    } else {
        Err(VtkError::Name(name.to_string()))
    }
}

fn check_finite(name: &str, values: &[f64]) -> Result<(), VtkError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(VtkError::NonFinite {
            name: name.to_string(),
            index,
            value: values[index],
        }),
        None => Ok(()),
    }
}

/// Values that would overflow to infinity as f32 ([`PolyData::single_precision`]).
fn check_single(name: &str, values: &[f64]) -> Result<(), VtkError> {
    match values.iter().position(|v| !(*v as f32).is_finite()) {
        Some(index) => Err(VtkError::NonFinite {
            name: format!("{name} (as Float32)"),
            index,
            value: values[index],
        }),
        None => Ok(()),
    }
}

impl PolyData {
    /// Points drawn as vertices (one vertex cell per point): a particle cloud.
    pub fn vertices(points: Vec<Vec3>) -> Result<Self, VtkError> {
        for (k, p) in points.iter().enumerate() {
            check_finite("Points", p.as_slice()).map_err(|e| match e {
                VtkError::NonFinite { name, index, value } => VtkError::NonFinite {
                    name,
                    index: 3 * k + index,
                    value,
                },
                other => other,
            })?;
        }
        Ok(Self {
            points,
            verts: true,
            lines: Vec::new(),
            arrays: Vec::new(),
            active_tensors: None,
            single: false,
        })
    }

    /// Points joined by polylines, each a list of point indices (trajectories).
    pub fn polylines(points: Vec<Vec3>, lines: Vec<Vec<usize>>) -> Result<Self, VtkError> {
        let mut data = Self::vertices(points)?;
        data.verts = false;
        for (line, l) in lines.iter().enumerate() {
            if let Some(&point) = l.iter().find(|&&p| p >= data.points.len()) {
                return Err(VtkError::PointIndex {
                    line,
                    point,
                    points: data.points.len(),
                });
            }
        }
        data.lines = lines;
        Ok(data)
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// True without points.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Add a point array of `components` values per point (point-major).
    pub fn with_array(mut self, name: &str, components: usize, values: PointValues) -> Result<Self, VtkError> {
        let name = plain(name)?.to_string();
        let expected = components * self.points.len();
        if components == 0 || values.len() != expected {
            return Err(VtkError::Length {
                name,
                components,
                expected,
                got: values.len(),
            });
        }
        if let PointValues::Float64(v) = &values {
            check_finite(&name, v)?;
            if self.single {
                check_single(&name, v)?;
            }
        }
        self.arrays.push(DataArray {
            name,
            components,
            values,
        });
        Ok(self)
    }

    /// Write floats and points as Float32 (module docs). A value beyond f32's range would
    /// become infinite and is refused ([`VtkError::NonFinite`]), here for the arrays and
    /// points already present and in [`PolyData::with_array`] for later ones.
    pub fn single_precision(mut self) -> Result<Self, VtkError> {
        let coords: Vec<f64> = self.points.iter().flat_map(|p| p.iter().copied()).collect();
        check_single("Points", &coords)?;
        for a in &self.arrays {
            if let PointValues::Float64(v) = &a.values {
                check_single(&a.name, v)?;
            }
        }
        self.single = true;
        Ok(self)
    }

    /// Mark the array `name` as the active tensors (what ParaView's Tensor Glyph uses).
    pub fn with_active_tensors(mut self, name: &str) -> Result<Self, VtkError> {
        self.active_tensors = Some(plain(name)?.to_string());
        Ok(self)
    }

    /// The data set as ASCII XML (every value in the text).
    pub fn to_xml(&self) -> String {
        let mut s = String::new();
        self.render(&mut s, &mut None);
        s
    }

    /// The data set as the bytes of a binary `.vtp` file (what [`PolyData::write`] writes):
    /// XML with every array's values raw in the appended section.
    pub fn to_binary(&self) -> Vec<u8> {
        let mut s = String::new();
        let mut appended = Some(Vec::new());
        self.render(&mut s, &mut appended);
        let data = appended.unwrap_or_default();
        let mut bytes = s.into_bytes();
        bytes.reserve(data.len() + 64);
        // `_` marks the start of the raw data; the byte counts and offsets need no delimiter.
        bytes.extend_from_slice(b"<AppendedData encoding=\"raw\">\n_");
        bytes.extend_from_slice(&data);
        bytes.extend_from_slice(b"\n</AppendedData>\n</VTKFile>\n");
        bytes
    }

    /// The XML of the data set; with `appended`, every array's values go there (a UInt64 byte
    /// count, then the raw little-endian values) and the XML refers to them by offset.
    fn render(&self, s: &mut String, appended: &mut Option<Vec<u8>>) {
        let n = self.points.len();
        let n_verts = if self.verts { n } else { 0 };
        s.push_str("<?xml version=\"1.0\"?>\n");
        let compressor = if appended.is_some() {
            " compressor=\"vtkZLibDataCompressor\""
        } else {
            ""
        };
        let _ = writeln!(
            s,
            "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\"{compressor}>"
        );
        s.push_str("<PolyData>\n");
        let _ = writeln!(
            s,
            "<Piece NumberOfPoints=\"{n}\" NumberOfVerts=\"{n_verts}\" NumberOfLines=\"{}\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">",
            self.lines.len()
        );
        match &self.active_tensors {
            Some(t) => {
                let _ = writeln!(s, "<PointData Tensors=\"{t}\">");
            }
            None => s.push_str("<PointData>\n"),
        }
        for a in &self.arrays {
            write_array(s, appended, &a.name, a.components, &a.values, self.single);
        }
        s.push_str("</PointData>\n<Points>\n");
        let coords: Vec<f64> = self.points.iter().flat_map(|p| p.iter().copied()).collect();
        write_array(s, appended, "Points", 3, &PointValues::Float64(coords), self.single);
        s.push_str("</Points>\n");
        if self.verts {
            write_cells(s, appended, "Verts", (0..n).map(|p| vec![p]));
        }
        if !self.lines.is_empty() {
            write_cells(s, appended, "Lines", self.lines.iter().cloned());
        }
        s.push_str("</Piece>\n</PolyData>\n");
        if appended.is_none() {
            s.push_str("</VTKFile>\n");
        }
    }

    /// Write atomically to `path` (a `.vtp` file), binary ([`PolyData::to_binary`]).
    pub fn write(&self, path: impl AsRef<Path>) -> Result<(), OutputError> {
        write_atomic(path, &self.to_binary())
    }
}

fn write_array(
    s: &mut String,
    appended: &mut Option<Vec<u8>>,
    name: &str,
    components: usize,
    values: &PointValues,
    single: bool,
) {
    let kind = match values {
        PointValues::Float64(_) if single => "Float32",
        PointValues::Float64(_) => "Float64",
        PointValues::Int64(_) => "Int64",
    };
    let _ = write!(
        s,
        "<DataArray type=\"{kind}\" Name=\"{name}\" NumberOfComponents=\"{components}\" "
    );
    if let Some(data) = appended {
        let _ = writeln!(s, "format=\"appended\" offset=\"{}\"/>", data.len());
        let raw: Vec<u8> = match values {
            // Range checked by `check_single`; `as` rounds to nearest.
            PointValues::Float64(v) if single => v.iter().flat_map(|&x| (x as f32).to_le_bytes()).collect(),
            PointValues::Float64(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
            PointValues::Int64(v) => v.iter().flat_map(|x| x.to_le_bytes()).collect(),
        };
        append_compressed(data, &raw);
        return;
    }
    s.push_str("format=\"ascii\">");
    match values {
        // `{:?}` is the shortest representation that parses back to the same f64 (or f32).
        PointValues::Float64(v) if single => v.iter().for_each(|&x| {
            let _ = write!(s, "{:?} ", x as f32);
        }),
        PointValues::Float64(v) => v.iter().for_each(|x| {
            let _ = write!(s, "{x:?} ");
        }),
        PointValues::Int64(v) => v.iter().for_each(|x| {
            let _ = write!(s, "{x} ");
        }),
    }
    s.push_str("</DataArray>\n");
}

/// Append `raw` as one zlib block with VTK's header: block count, uncompressed block size,
/// size of the last (partial) block, compressed size of each block, UInt64 each. An empty
/// array is zero blocks.
fn append_compressed(data: &mut Vec<u8>, raw: &[u8]) {
    let blocks: u64 = if raw.is_empty() { 0 } else { 1 };
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::fast());
    // Writing to a Vec cannot fail.
    let compressed = std::io::Write::write_all(&mut z, raw)
        .and_then(|()| z.finish())
        .unwrap_or_default();
    let header = [blocks, raw.len() as u64, raw.len() as u64];
    header.iter().for_each(|h| data.extend_from_slice(&h.to_le_bytes()));
    if blocks == 1 {
        data.extend_from_slice(&(compressed.len() as u64).to_le_bytes());
        data.extend_from_slice(&compressed);
    }
}

fn write_cells(s: &mut String, appended: &mut Option<Vec<u8>>, kind: &str, cells: impl Iterator<Item = Vec<usize>>) {
    let (mut connectivity, mut offsets) = (Vec::new(), Vec::new());
    for cell in cells {
        connectivity.extend(cell.iter().map(|&p| p as i64));
        offsets.push(connectivity.len() as i64);
    }
    let _ = writeln!(s, "<{kind}>");
    write_array(s, appended, "connectivity", 1, &PointValues::Int64(connectivity), false);
    write_array(s, appended, "offsets", 1, &PointValues::Int64(offsets), false);
    let _ = writeln!(s, "</{kind}>");
}

/// One particle in a [`particle_cloud`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CloudPoint {
    /// Particle number.
    pub id: i64,
    /// Barycentre x_c (global coordinates).
    pub x: Vec3,
    /// Total distortion F̄ = F·S.
    pub f_bar: Mat3,
    /// Caller's flag (e.g. an outcome code).
    pub flag: i64,
}

/// V = sqrt(F̄F̄ᵀ) and the semi-axes r (descending) of a total distortion. V is made exactly
/// symmetric (QᵀdiagQ leaves round-off of one ulp between V_ij and V_ji).
pub fn stretch(f_bar: &Mat3) -> (Mat3, Vec3) {
    let frame = PrincipalFrame::from_total_distortion(f_bar);
    let v = frame.to_global(&Mat3::from_diagonal(&frame.r));
    (crate::tensor::sym(&v), frame.r)
}

/// Particles as vertices with the arrays `id`, `V` (active tensors), `r1`, `r2`, `r3`, `flag`.
pub fn particle_cloud(points: &[CloudPoint]) -> Result<PolyData, VtkError> {
    let (mut v, mut r) = (
        Vec::with_capacity(9 * points.len()),
        [(); 3].map(|_| Vec::with_capacity(points.len())),
    );
    for p in points {
        let (stretch, semi_axes) = stretch(&p.f_bar);
        v.extend(stretch.iter().copied()); // symmetric: row- and column-major agree
        for (a, column) in r.iter_mut().enumerate() {
            column.push(semi_axes[a]);
        }
    }
    let [r1, r2, r3] = r;
    PolyData::vertices(points.iter().map(|p| p.x).collect())?
        .with_array("id", 1, PointValues::Int64(points.iter().map(|p| p.id).collect()))?
        .with_array("V", 9, PointValues::Float64(v))?
        .with_array("r1", 1, PointValues::Float64(r1))?
        .with_array("r2", 1, PointValues::Float64(r2))?
        .with_array("r3", 1, PointValues::Float64(r3))?
        .with_array("flag", 1, PointValues::Int64(points.iter().map(|p| p.flag).collect()))?
        .with_active_tensors("V")
}

/// Write the ParaView collection `path` (`.pvd`) listing `(time, file)` pairs; files are
/// relative to the folder of `path`. Times must be finite.
pub fn write_pvd(path: impl AsRef<Path>, entries: &[(f64, String)]) -> Result<(), OutputError> {
    let mut s = String::from("<?xml version=\"1.0\"?>\n");
    s.push_str("<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n<Collection>\n");
    for (index, (t, file)) in entries.iter().enumerate() {
        if !t.is_finite() {
            return Err(VtkError::NonFinite {
                name: "timestep".into(),
                index,
                value: *t,
            }
            .into());
        }
        let file = plain(file)?;
        let _ = writeln!(s, "<DataSet timestep=\"{t:?}\" group=\"\" part=\"0\" file=\"{file}\"/>");
    }
    s.push_str("</Collection>\n</VTKFile>\n");
    write_atomic(path, s.as_bytes())
}

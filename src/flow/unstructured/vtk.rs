//! Reader for the legacy VTK files written by OpenFOAM's `foamToVTK -legacy`.
//!
//! Supported subset: `DATASET UNSTRUCTURED_GRID` in ASCII or BINARY (big-endian), `POINTS`,
//! classic `CELLS`/`CELL_TYPES` (VTK ≤ 5.0 layout), and `FIELD` arrays in `POINT_DATA` and
//! `CELL_DATA`; dataset-level `FIELD` blocks (foamToVTK's `TimeValue`) are skipped. The vtkio
//! crate (0.6.3 and 0.7.0-rc2) rejects that dataset-level block, hence this small reader.
//!
//! Header counts are untrusted: their products use checked arithmetic, and a block is
//! allocated only after the file is known to hold it (binary: n·width bytes; ASCII: at least
//! two bytes per value), so a lying header is a [`MeshError::Malformed`], never an abort.
//! Integer blocks (connectivity, cell types) must consist of integer tokens, and every
//! connectivity index must name an existing point.

use super::error::MeshError;
use crate::tensor::Vec3;
use std::collections::HashMap;
use std::path::Path;

const VTK_HEXAHEDRON: i64 = 12;

/// The parts of a legacy VTK unstructured grid that a meshed flow field needs.
#[derive(Debug, Clone, Default)]
pub struct VtkGrid {
    /// Point coordinates.
    pub points: Vec<Vec3>,
    /// Hexahedra, VTK vertex order.
    pub cells: Vec<[u32; 8]>,
    /// Point-data arrays by name: (components per point, values point-major).
    pub point_arrays: HashMap<String, (usize, Vec<f64>)>,
}

/// Read a legacy VTK unstructured grid of hexahedra.
pub fn read_legacy(path: &Path) -> Result<VtkGrid, MeshError> {
    let bytes = std::fs::read(path).map_err(|source| MeshError::Io {
        path: path.display().to_string(),
        source,
    })?;
    Parser {
        buf: &bytes,
        pos: 0,
        binary: false,
        path,
    }
    .grid()
}

#[derive(Clone, Copy, PartialEq)]
enum Section {
    Dataset,
    Points,
    Cells,
}

struct Parser<'a> {
    buf: &'a [u8],
    pos: usize,
    binary: bool,
    path: &'a Path,
}

impl<'a> Parser<'a> {
    fn err(&self, reason: impl Into<String>) -> MeshError {
        MeshError::Malformed {
            path: self.path.display().to_string(),
            format: "legacy VTK",
            offset: self.pos,
            reason: reason.into(),
        }
    }

    /// Next non-empty line, without its newline; `None` at end of file.
    fn line(&mut self) -> Option<String> {
        while self.pos < self.buf.len() {
            let end = self.buf[self.pos..]
                .iter()
                .position(|&b| b == b'\n')
                .map_or(self.buf.len(), |i| self.pos + i);
            let line = String::from_utf8_lossy(&self.buf[self.pos..end]).trim().to_string();
            self.pos = (end + 1).min(self.buf.len());
            if !line.is_empty() {
                return Some(line);
            }
        }
        None
    }

    fn grid(mut self) -> Result<VtkGrid, MeshError> {
        let version = self.line().unwrap_or_default();
        if !version.starts_with("# vtk DataFile") {
            return Err(self.err("missing `# vtk DataFile` header"));
        }
        let _title = self.line();
        self.binary = match self.line().as_deref() {
            Some("BINARY") => true,
            Some("ASCII") => false,
            other => return Err(self.err(format!("expected ASCII or BINARY, got {other:?}"))),
        };
        let mut grid = VtkGrid::default();
        let mut section = Section::Dataset;
        let mut n_points = 0;
        while let Some(line) = self.line() {
            let words: Vec<&str> = line.split_whitespace().collect();
            match words.as_slice() {
                ["DATASET", "UNSTRUCTURED_GRID"] => {}
                ["DATASET", other] => return Err(self.err(format!("unsupported dataset {other}"))),
                ["FIELD", _, n] => {
                    let n = self.count(n)?;
                    for _ in 0..n {
                        let (name, comps, tuples, values) = self.field_array()?;
                        if section == Section::Points {
                            if tuples != n_points {
                                return Err(
                                    self.err(format!("point array {name} has {tuples} tuples for {n_points} points"))
                                );
                            }
                            grid.point_arrays.insert(name, (comps, values));
                        }
                    }
                }
                ["POINTS", n, ty] => {
                    n_points = self.count(n)?;
                    let xyz = self.numbers(self.product(n_points, 3)?, ty)?;
                    grid.points = xyz.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])).collect();
                }
                ["CELLS", n, size] => {
                    let (n, size) = (self.count(n)?, self.count(size)?);
                    // Hexahedra only: each cell is its vertex count 8 and 8 indices.
                    if self.product(n, 9)? != size {
                        return Err(self.err(format!("CELLS {n} {size}: {n} hexahedra need {} integers", 9 * n)));
                    }
                    let raw = self.integers(size)?;
                    grid.cells = self.hexahedra(n, &raw)?;
                }
                ["CELL_TYPES", n] => {
                    let types = self.integers(self.count(n)?)?;
                    if let Some(cell) = types.iter().position(|&t| t != VTK_HEXAHEDRON) {
                        return Err(MeshError::UnsupportedCell {
                            cell,
                            vtk_type: types[cell],
                        });
                    }
                }
                ["POINT_DATA", _] => section = Section::Points,
                ["CELL_DATA", _] => section = Section::Cells,
                _ => return Err(self.err(format!("unsupported line `{line}`"))),
            }
        }
        let n_points = grid.points.len();
        for (cell, verts) in grid.cells.iter().enumerate() {
            if let Some(&point) = verts.iter().find(|&&p| p as usize >= n_points) {
                return Err(MeshError::BadConnectivity {
                    cell,
                    point: i64::from(point),
                    n_points,
                });
            }
        }
        Ok(grid)
    }

    fn count(&self, word: &str) -> Result<usize, MeshError> {
        word.parse()
            .map_err(|_| self.err(format!("expected a count, got `{word}`")))
    }

    /// `a · b` for header counts, an error instead of a wrap-around.
    fn product(&self, a: usize, b: usize) -> Result<usize, MeshError> {
        a.checked_mul(b)
            .ok_or_else(|| self.err(format!("{a} × {b} values overflow the address space")))
    }

    /// Fail unless `n` values of at least `min_bytes` bytes each fit in the rest of the file:
    /// every allocation is bounded by the bytes actually present, whatever a header claims.
    fn check_room(&self, n: usize, min_bytes: usize, what: &str) -> Result<(), MeshError> {
        let rest = self.buf.len() - self.pos;
        // An ASCII value is one character plus a separator, except that the last one may end
        // the file.
        if n.checked_mul(min_bytes).is_none_or(|need| need > rest + 1) {
            return Err(self.err(format!("{n} {what} declared, only {rest} bytes left")));
        }
        Ok(())
    }

    fn field_array(&mut self) -> Result<(String, usize, usize, Vec<f64>), MeshError> {
        let header = self.line().ok_or_else(|| self.err("missing FIELD array header"))?;
        let words: Vec<&str> = header.split_whitespace().collect();
        let [name, comps, tuples, ty] = words.as_slice() else {
            return Err(self.err(format!("bad FIELD array header `{header}`")));
        };
        let (comps, tuples) = (self.count(comps)?, self.count(tuples)?);
        let values = self.numbers(self.product(comps, tuples)?, ty)?;
        Ok((name.to_string(), comps, tuples, values))
    }

    fn hexahedra(&self, n: usize, raw: &[i64]) -> Result<Vec<[u32; 8]>, MeshError> {
        // `raw` was read from the file, so this capacity is bounded by the file size.
        let mut cells = Vec::with_capacity(n.min(raw.len() / 9));
        let mut rest = raw;
        for cell in 0..n {
            match rest {
                [8, v @ ..] if v.len() >= 8 => {
                    let mut verts = [0u32; 8];
                    for (slot, &p) in verts.iter_mut().zip(&v[..8]) {
                        *slot = u32::try_from(p).map_err(|_| MeshError::BadConnectivity {
                            cell,
                            point: p,
                            n_points: 0,
                        })?;
                    }
                    cells.push(verts);
                    rest = &v[8..];
                }
                [k, ..] => {
                    return Err(self.err(format!("cell {cell} has {k} vertices, expected 8")));
                }
                [] => return Err(self.err(format!("CELLS ends after {cell} of {n} cells"))),
            }
        }
        Ok(cells)
    }

    /// `n` integers (binary `int`/`long`/`vtkIdType`, or ASCII tokens that must parse as
    /// integers: `1.9` or `nan` is an error, not a silently truncated index).
    fn integers(&mut self, n: usize) -> Result<Vec<i64>, MeshError> {
        if !self.binary {
            let words = self.ascii_words(n)?;
            return words
                .into_iter()
                .map(|w| {
                    let w = String::from_utf8_lossy(w);
                    w.parse::<i64>()
                        .map_err(|_| self.err(format!("`{w}` is not an integer")))
                })
                .collect();
        }
        let block = self.binary_block(n, 4, "int")?;
        Ok(block
            .chunks_exact(4)
            .map(|c| i64::from(i32::from_be_bytes([c[0], c[1], c[2], c[3]])))
            .collect())
    }

    /// `n` numbers of VTK type `ty`, as f64 (exact for the 32-bit types used here).
    fn numbers(&mut self, n: usize, ty: &str) -> Result<Vec<f64>, MeshError> {
        let width = match ty {
            "float" | "int" => 4,
            "double" | "long" | "vtkIdType" => 8,
            _ => return Err(self.err(format!("unsupported data type `{ty}`"))),
        };
        if !self.binary {
            let words = self.ascii_words(n)?;
            return words
                .into_iter()
                .map(|w| {
                    let w = String::from_utf8_lossy(w);
                    w.parse::<f64>().map_err(|_| self.err(format!("`{w}` is not a number")))
                })
                .collect();
        }
        let block = self.binary_block(n, width, ty)?;
        let chunks = block.chunks_exact(width);
        Ok(match ty {
            "float" => chunks
                .map(|c| f64::from(f32::from_be_bytes([c[0], c[1], c[2], c[3]])))
                .collect(),
            "int" => chunks
                .map(|c| f64::from(i32::from_be_bytes([c[0], c[1], c[2], c[3]])))
                .collect(),
            "double" => chunks
                .map(|c| f64::from_be_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
                .collect(),
            _ => chunks
                .map(|c| i64::from_be_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]) as f64)
                .collect(),
        })
    }

    /// The next `n · width` bytes (checked against the end of the file before anything is
    /// allocated).
    fn binary_block(&mut self, n: usize, width: usize, ty: &str) -> Result<&'a [u8], MeshError> {
        let end = n
            .checked_mul(width)
            .and_then(|len| self.pos.checked_add(len))
            .filter(|&e| e <= self.buf.len())
            .ok_or_else(|| self.err(format!("file ends inside a block of {n} {ty}")))?;
        let block = &self.buf[self.pos..end];
        self.pos = end;
        Ok(block)
    }

    /// The next `n` whitespace-separated tokens.
    fn ascii_words(&mut self, n: usize) -> Result<Vec<&'a [u8]>, MeshError> {
        self.check_room(n, 2, "values")?;
        let buf = self.buf;
        let mut words = Vec::with_capacity(n);
        while words.len() < n {
            let start = self.pos;
            while self.pos < buf.len() && buf[self.pos].is_ascii_whitespace() {
                self.pos += 1;
            }
            let begin = self.pos;
            while self.pos < buf.len() && !buf[self.pos].is_ascii_whitespace() {
                self.pos += 1;
            }
            if begin == self.pos {
                self.pos = start;
                return Err(self.err(format!("expected {n} numbers, found {}", words.len())));
            }
            words.push(&buf[begin..self.pos]);
        }
        Ok(words)
    }
}

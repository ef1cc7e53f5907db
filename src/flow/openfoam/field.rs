//! Volume fields (`volScalarField`, `volVectorField`) in a time directory: cell values and
//! the values on every boundary face.
//!
//! A patch's face values are the stored `value` entry where the file has one (`fixedValue`,
//! `calculated`, `inletOutlet`, `pressureInletOutletVelocity`, ... all write it). Without one,
//! the value follows from the condition and the adjacent cell, as OpenFOAM evaluates it:
//! `noSlip` is zero, `zeroGradient` and `empty` repeat the cell value, `symmetry`,
//! `symmetryPlane` and `slip` remove the wall-normal component of a vector, `cyclic` and
//! `wedge` take the cells on both sides of the pair (`coupled_values`). Any other condition
//! without a stored value is an error naming it. On a patch of geometric type `empty` (a 2-D
//! case's front and back), which holds no values in OpenFOAM, the empty list solvers write
//! there (`value nonuniform 0();`) counts as no value.

use super::error::FoamError;
use super::mesh::PolyMesh;
use super::parse::{Dict, Entry, HEADER_BYTES, Limit, Numbers, Value, dictionary_file, number, read_file};
use crate::tensor::Vec3;
use std::path::Path;

/// A cell-centred field with values on the boundary faces, `comps` components per value.
#[derive(Debug, Clone, PartialEq)]
pub struct VolField {
    /// Components per value (1 scalar, 3 vector).
    pub comps: usize,
    /// `n_cells * comps` cell values.
    pub internal: Vec<f64>,
    /// `(n_faces − n_internal_faces) * comps` values, boundary faces in face order.
    pub boundary: Vec<f64>,
    /// Per patch: whether its condition prescribes the value ([`FIXED_CONDITIONS`]: a Dirichlet
    /// condition, such as a no-slip or moving wall), rather than deriving it from the cells.
    pub fixed: Vec<bool>,
}

/// Conditions that prescribe a patch's value: `noSlip`, `fixedValue` and the wall-motion
/// conditions, which store the wall's velocity.
pub const FIXED_CONDITIONS: [&str; 6] = [
    "noSlip",
    "fixedValue",
    "uniformFixedValue",
    "movingWallVelocity",
    "rotatingWallVelocity",
    "translatingWallVelocity",
];

impl VolField {
    /// Value of cell `c`.
    pub fn cell(&self, c: usize) -> &[f64] {
        &self.internal[c * self.comps..(c + 1) * self.comps]
    }

    /// Value on boundary face `b` (counted from the first boundary face).
    pub fn boundary_face(&self, b: usize) -> &[f64] {
        &self.boundary[b * self.comps..(b + 1) * self.comps]
    }

    /// A vector field given by a function, evaluated at the cell centres and the boundary face
    /// centres (analytic fields for verification and benchmarks). Every patch counts as
    /// prescribed ([`VolField::fixed`]): the function gives its values.
    pub fn from_fn(mesh: &PolyMesh, f: impl Fn(&Vec3) -> Vec3) -> Self {
        let eval = |xs: &[Vec3]| xs.iter().flat_map(|x| <[f64; 3]>::from(f(x))).collect();
        Self {
            comps: 3,
            internal: eval(mesh.cell_centres()),
            boundary: eval(&mesh.face_centres()[mesh.n_internal_faces()..]),
            fixed: vec![true; mesh.patches().len()],
        }
    }
}

/// Read the field `name` with `comps` components (1 or 3) from time directory `dir`.
pub fn read_vol_field(dir: &Path, name: &str, mesh: &PolyMesh, comps: usize) -> Result<VolField, FoamError> {
    // A value per cell and per boundary face at most, and a dictionary per patch (its type,
    // perhaps a coded condition's source: one HEADER_BYTES each).
    let n_values = mesh.n_cells() + (mesh.n_faces() - mesh.n_internal_faces());
    let patches = mesh.patches().len() as u64 * HEADER_BYTES;
    let limit = Limit::entries(
        n_values,
        comps,
        "values (cells and boundary faces)",
        patches,
        "the patches",
    );
    let (path, text) = read_file(&dir.join(name), limit)?;
    let (header, dict) = dictionary_file(&path, &text)?;
    let field_err = |reason: String| FoamError::Field {
        path: path.clone(),
        reason,
    };
    let expected_class = match comps {
        1 => "volScalarField",
        3 => "volVectorField",
        _ => return Err(field_err(format!("{comps}-component fields are not supported"))),
    };
    if header.class != expected_class {
        return Err(field_err(format!(
            "class is `{}`, expected `{expected_class}`",
            header.class
        )));
    }
    let internal = match dict.get("internalField") {
        Some((Entry::Values(v), _)) => {
            values(v, comps, mesh.n_cells()).map_err(|r| field_err(format!("internalField: {r}")))?
        }
        _ => return Err(field_err("no internalField entry".into())),
    };
    let boundary_dict = match dict.get("boundaryField") {
        Some((Entry::Dict(d), _)) => d,
        _ => return Err(field_err("no boundaryField dictionary".into())),
    };
    let n_internal = mesh.n_internal_faces();
    let mut boundary = Vec::with_capacity((mesh.n_faces() - n_internal) * comps);
    let mut fixed = Vec::with_capacity(mesh.patches().len());
    // The pairs' maps, found at the first coupled patch without stored values.
    let mut maps: Option<Vec<Option<crate::flow::Isometry>>> = None;
    for (p, patch) in mesh.patches().iter().enumerate() {
        let entry = patch_dict(boundary_dict, &patch.name)
            .ok_or_else(|| field_err(format!("boundaryField has no entry for patch `{}`", patch.name)))?;
        let kind = entry.word("type").unwrap_or("");
        fixed.push(FIXED_CONDITIONS.contains(&kind));
        let bad = |r: String| field_err(format!("patch `{}` ({kind}): {r}", patch.name));
        match entry.get("value") {
            // An `empty` patch holds no values in OpenFOAM (a 2-D case's front and back):
            // solvers write `value nonuniform 0();` on it. Its faces repeat the cell below.
            Some((Entry::Values(v), _)) if !(patch.kind == "empty" && is_empty_list(v)) => {
                boundary.extend(values(v, comps, patch.size).map_err(bad)?);
                continue;
            }
            _ => {}
        }
        let kind = if patch.kind == "empty" { "empty" } else { kind };
        if matches!(kind, "cyclic" | "wedge") && patch.kind == kind {
            maps = match maps.take() {
                Some(m) => Some(m),
                None => Some(super::images::pair_maps(mesh)?),
            };
            let map = maps
                .as_ref()
                .and_then(|m| m[p])
                .ok_or_else(|| bad("no partner patch".into()))?;
            boundary.extend(coupled_values(mesh, p, &map, &internal, comps).map_err(bad)?);
            continue;
        }
        for f in patch.start..patch.start + patch.size {
            let cell = &internal[mesh.owner(f) * comps..(mesh.owner(f) + 1) * comps];
            match kind {
                "noSlip" if comps == 3 => boundary.extend([0.0; 3]),
                "zeroGradient" | "empty" => boundary.extend_from_slice(cell),
                "symmetry" | "symmetryPlane" | "slip" if comps == 1 => boundary.extend_from_slice(cell),
                "symmetry" | "symmetryPlane" | "slip" => {
                    let n = mesh.face_areas()[f].normalize();
                    let u = Vec3::from_row_slice(cell);
                    boundary.extend((u - u.dot(&n) * n).iter());
                }
                _ => {
                    return Err(bad(
                        "no stored `value` and the condition cannot be evaluated from the cell".into(),
                    ));
                }
            }
        }
    }
    Ok(VolField {
        comps,
        internal,
        boundary,
        fixed,
    })
}

/// The values OpenFOAM's coupled conditions give on patch `p` from the cells
/// (`internal`), `map` being the patch's pair map ([`super::images::pair_maps`]):
/// - `cyclic`: the owner cell's value and the partner face's owner cell d's, mapped across the
///   pair (position $T_p^{-1}(x_{d})$, value $Q_p^T u_{d}$ with $T_p$ the patch's map),
///   interpolated linearly to the face along its normal;
/// - `wedge`: the owner cell's value rotated about the axis from the cell centre's azimuth
///   to the face centre's, exact for an axisymmetric field (scalars repeat the cell value).
fn coupled_values(
    mesh: &PolyMesh,
    p: usize,
    map: &crate::flow::Isometry,
    internal: &[f64],
    comps: usize,
) -> Result<Vec<f64>, String> {
    let patch = &mesh.patches()[p];
    let cell = |c: usize| &internal[c * comps..(c + 1) * comps];
    let mut out = Vec::with_capacity(patch.size * comps);
    if patch.kind == "wedge" {
        let (axis, _) = nalgebra::Rotation3::from_matrix_unchecked(map.q)
            .axis_angle()
            .ok_or("the wedge pair's map is not a rotation")?;
        for f in patch.start..patch.start + patch.size {
            let c = mesh.owner(f);
            let flat = |x: Vec3| {
                let r = x - map.origin;
                r - axis.into_inner() * axis.dot(&r)
            };
            let (rc, rf) = (flat(mesh.cell_centres()[c]), flat(mesh.face_centres()[f]));
            let turn = axis.dot(&rc.cross(&rf)).atan2(rc.dot(&rf));
            match comps {
                3 => {
                    let u = nalgebra::Rotation3::from_axis_angle(&axis, turn) * Vec3::from_row_slice(cell(c));
                    out.extend(u.iter());
                }
                _ => out.extend_from_slice(cell(c)),
            }
        }
        return Ok(out);
    }
    let neighbour = patch.coupling.as_ref().map(|c| c.neighbour.as_str()).unwrap_or("");
    let q = mesh
        .patches()
        .iter()
        .position(|x| x.name == neighbour)
        .ok_or_else(|| format!("partner `{neighbour}` is not in the mesh"))?;
    let partner = &mesh.patches()[q];
    if partner.size != patch.size {
        return Err(format!(
            "{} faces against its partner `{}`'s {}: a `cyclic` pair matches face by face",
            patch.size, partner.name, partner.size
        ));
    }
    // p's map takes the space beyond p onto q's side; its inverse takes the partner's cells
    // to where they neighbour p's.
    let back = map.inverse();
    for k in 0..patch.size {
        let (f, g) = (patch.start + k, partner.start + k);
        let (c, d) = (mesh.owner(f), mesh.owner(g));
        let n = mesh.face_areas()[f].normalize();
        let xf = mesh.face_centres()[f];
        let own = (xf - mesh.cell_centres()[c]).dot(&n).abs();
        let far = (xf - back.point(&mesh.cell_centres()[d])).dot(&n).abs();
        let w = if own + far > 0.0 { far / (own + far) } else { 0.5 };
        match comps {
            3 => {
                let u = Vec3::from_row_slice(cell(c)) * w + back.vector(&Vec3::from_row_slice(cell(d))) * (1.0 - w);
                out.extend(u.iter());
            }
            _ => out.extend(cell(c).iter().zip(cell(d)).map(|(a, b)| a * w + b * (1.0 - w))),
        }
    }
    Ok(out)
}

/// The face flux `phi` (a `surfaceScalarField`, m³/s, positive out of each face's owner cell,
/// so out of the domain on the boundary) on the boundary faces, in face order, from time
/// directory `dir`: `None` if the directory has no `phi` (nor `phi.gz`). A patch without a
/// stored `value` (`empty`, or a condition written without one) carries no flux.
pub fn read_boundary_flux(dir: &Path, mesh: &PolyMesh) -> Result<Option<Vec<f64>>, FoamError> {
    let name = dir.join("phi");
    let mut gz = name.as_os_str().to_owned();
    gz.push(".gz");
    if !name.is_file() && !Path::new(&gz).is_file() {
        return Ok(None);
    }
    let patches = mesh.patches().len() as u64 * HEADER_BYTES;
    let limit = Limit::entries(mesh.n_faces(), 1, "face fluxes", patches, "the patches");
    let (path, text) = read_file(&name, limit)?;
    let (header, dict) = dictionary_file(&path, &text)?;
    let field_err = |reason: String| FoamError::Field {
        path: path.clone(),
        reason,
    };
    if header.class != "surfaceScalarField" {
        return Err(field_err(format!(
            "class is `{}`, expected `surfaceScalarField`",
            header.class
        )));
    }
    let boundary_dict = match dict.get("boundaryField") {
        Some((Entry::Dict(d), _)) => d,
        _ => return Err(field_err("no boundaryField dictionary".into())),
    };
    let mut flux = Vec::with_capacity(mesh.n_faces() - mesh.n_internal_faces());
    for patch in mesh.patches() {
        match patch_dict(boundary_dict, &patch.name).and_then(|d| d.get("value")) {
            // No flux through an `empty` patch: OpenFOAM writes `value nonuniform 0();` there.
            Some((Entry::Values(v), _)) if patch.kind == "empty" && is_empty_list(v) => {
                flux.extend(std::iter::repeat_n(0.0, patch.size))
            }
            Some((Entry::Values(v), _)) => {
                flux.extend(values(v, 1, patch.size).map_err(|r| field_err(format!("patch `{}`: {r}", patch.name)))?)
            }
            _ => flux.extend(std::iter::repeat_n(0.0, patch.size)),
        }
    }
    Ok(Some(flux))
}

/// The entry of a patch, by exact name (solver-written fields name every patch; patterns
/// such as `".*"` occur only in hand-written initial conditions).
fn patch_dict<'d>(dict: &'d Dict, name: &str) -> Option<&'d Dict> {
    match dict.get(name)? {
        (Entry::Dict(d), _) => Some(d),
        _ => None,
    }
}

/// Whether a value is `nonuniform 0()`, the empty list.
fn is_empty_list(v: &[Value]) -> bool {
    matches!(v, [Value::Word(u), Value::Word(zero), Value::List(items)]
        if u == "nonuniform" && zero == "0" && items.is_empty())
}

/// `uniform v` or `nonuniform List<T> n (...)` expanded to `n * comps` finite values.
fn values(v: &[Value], comps: usize, n: usize) -> Result<Vec<f64>, String> {
    let data = match v {
        [Value::Word(u), x] if u == "uniform" => {
            let one: Vec<f64> = match x {
                Value::Word(_) if comps == 1 => number(x).into_iter().collect(),
                Value::List(items) => items.iter().filter_map(number).collect(),
                _ => Vec::new(),
            };
            let ok = one.len() == comps && matches!(x, Value::Word(_)) == (comps == 1);
            if !ok {
                return Err(format!("uniform value is not a {comps}-component number"));
            }
            one.repeat(n)
        }
        [
            Value::Word(u),
            Value::Numbers(Numbers {
                comps: c,
                count,
                data,
                offset,
            }),
        ] if u == "nonuniform" => {
            if *c != comps {
                return Err(format!("list at byte {offset} has {c} components, expected {comps}"));
            }
            if *count != n {
                return Err(format!(
                    "list at byte {offset} has {count} values for {n} cells or faces"
                ));
            }
            if data.len() == comps {
                data.repeat(n)
            } else {
                data.clone()
            }
        }
        // What OpenFOAM writes for a patch without faces (in a processor directory, a patch
        // whose faces are all in other processors).
        [Value::Word(u), Value::Word(zero), Value::List(items)]
            if u == "nonuniform" && zero == "0" && items.is_empty() =>
        {
            if n != 0 {
                return Err(format!("an empty list for {n} faces"));
            }
            Vec::new()
        }
        _ => return Err("expected `uniform <value>` or `nonuniform List<...> n (...)`".into()),
    };
    if let Some(i) = data.iter().position(|x| !x.is_finite()) {
        return Err(format!("value {} is not finite", i / comps));
    }
    Ok(data)
}

//! Test meshes: warped unit cubes of hexahedra, prisms, tetrahedra or hexahedra with a
//! refinement interface (polyhedra), assembled into OpenFOAM's face-based form and written
//! as ASCII or binary case files.

use pseudorigid::flow::openfoam::{Patch, PolyMesh, VolField};
use pseudorigid::tensor::Vec3;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;

/// Cell shapes of the generated meshes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    Hex,
    Prism,
    Tet,
    /// Left half coarse hexahedra, right half refined 2×: the coarse cells at the interface
    /// are polyhedra with nine faces.
    Poly,
}

/// A smooth warp that keeps the cube's faces planar in place: interior faces become
/// non-planar and cells skewed. Amplitude 0.04 keeps every cell star-shaped for n ≤ 8.
pub fn warp(p: Vec3) -> Vec3 {
    use std::f64::consts::PI;
    let s = (PI * p[0]).sin() * (PI * p[1]).sin() * (PI * p[2]).sin();
    p + 0.04 * s * Vec3::new(1.0, 0.6, -0.8)
}

/// Raw face-based mesh arrays.
pub struct Raw {
    pub points: Vec<Vec3>,
    pub offsets: Vec<u32>,
    pub flat: Vec<u32>,
    pub owner: Vec<u32>,
    pub neighbour: Vec<u32>,
    pub patches: Vec<Patch>,
}

impl Raw {
    pub fn mesh(&self) -> PolyMesh {
        PolyMesh::new(
            self.points.clone(),
            self.offsets.clone(),
            self.flat.clone(),
            self.owner.clone(),
            self.neighbour.clone(),
            self.patches.clone(),
        )
        .expect("generated mesh is valid")
    }
}

/// Unit cube with `n` cells per edge (`n` even for [`Shape::Poly`]).
pub fn cube(shape: Shape, n: usize) -> Raw {
    let m = if shape == Shape::Poly { 2 * n } else { n };
    let id = |i: usize, j: usize, k: usize| (i + (m + 1) * (j + (m + 1) * k)) as u32;
    let mut points = Vec::new();
    for k in 0..=m {
        for j in 0..=m {
            for i in 0..=m {
                points.push(warp(Vec3::new(i as f64, j as f64, k as f64) / m as f64));
            }
        }
    }
    let hex = |s: usize, i: usize, j: usize, k: usize| -> [u32; 8] {
        [
            id(i, j, k),
            id(i + s, j, k),
            id(i + s, j + s, k),
            id(i, j + s, k),
            id(i, j, k + s),
            id(i + s, j, k + s),
            id(i + s, j + s, k + s),
            id(i, j + s, k + s),
        ]
    };
    let mut cells: Vec<Vec<Vec<u32>>> = Vec::new();
    match shape {
        Shape::Hex => {
            for k in 0..n {
                for j in 0..n {
                    for i in 0..n {
                        cells.push(hex_faces(hex(1, i, j, k)));
                    }
                }
            }
        }
        Shape::Prism => {
            for k in 0..n {
                for j in 0..n {
                    for i in 0..n {
                        let v = hex(1, i, j, k);
                        for t in [[0, 1, 2], [0, 2, 3]] {
                            let (a, b, c) = (v[t[0]], v[t[1]], v[t[2]]);
                            let (a2, b2, c2) = (v[t[0] + 4], v[t[1] + 4], v[t[2] + 4]);
                            cells.push(vec![
                                vec![a, b, c],
                                vec![a2, b2, c2],
                                vec![a, b, b2, a2],
                                vec![b, c, c2, b2],
                                vec![c, a, a2, c2],
                            ]);
                        }
                    }
                }
            }
        }
        Shape::Tet => {
            // Kuhn triangulation: one tetrahedron per path 000 -> 111 along the axes.
            for k in 0..n {
                for j in 0..n {
                    for i in 0..n {
                        for perm in [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]] {
                            let mut c = [i, j, k];
                            let mut verts = vec![id(c[0], c[1], c[2])];
                            for d in perm {
                                c[d] += 1;
                                verts.push(id(c[0], c[1], c[2]));
                            }
                            let [a, b, c, d] = [verts[0], verts[1], verts[2], verts[3]];
                            cells.push(vec![vec![a, b, c], vec![a, b, d], vec![a, c, d], vec![b, c, d]]);
                        }
                    }
                }
            }
        }
        Shape::Poly => {
            // Coarse cells of size 2 (fine units) for x < 1/2, fine cells of size 1 beyond.
            for k in (0..m).step_by(2) {
                for j in (0..m).step_by(2) {
                    for i in (0..n).step_by(2) {
                        let mut faces = hex_faces(hex(2, i, j, k));
                        if i + 2 == n {
                            // Edges on x = 1/2 carry the fine cells' mid-edge vertices (as in
                            // snappyHexMesh's split hexahedra), so the side faces have five.
                            let on_interface = |v: u32| v as usize % (m + 1) == n;
                            for face in &mut faces {
                                let mut with_mid = Vec::new();
                                for (e, &a) in face.iter().enumerate() {
                                    let b = face[(e + 1) % face.len()];
                                    with_mid.push(a);
                                    if on_interface(a) && on_interface(b) {
                                        with_mid.push((a + b) / 2);
                                    }
                                }
                                *face = with_mid;
                            }
                            // The face at x = 1/2 meets four fine cells: split it.
                            faces.pop();
                            for (dj, dk) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                                let (j0, k0) = (j + dj, k + dk);
                                faces.push(vec![
                                    id(n, j0, k0),
                                    id(n, j0 + 1, k0),
                                    id(n, j0 + 1, k0 + 1),
                                    id(n, j0, k0 + 1),
                                ]);
                            }
                        }
                        cells.push(faces);
                    }
                }
            }
            for k in 0..m {
                for j in 0..m {
                    for i in n..m {
                        cells.push(hex_faces(hex(1, i, j, k)));
                    }
                }
            }
        }
    }
    assemble(points, &cells)
}

/// The six faces of the hexahedron with vertices `v` (blockMesh's order), each listed
/// counter-clockwise seen from outside.
fn hex_faces(v: [u32; 8]) -> Vec<Vec<u32>> {
    [
        [0, 3, 2, 1],
        [4, 5, 6, 7],
        [0, 1, 5, 4],
        [3, 7, 6, 2],
        [0, 4, 7, 3],
        [1, 2, 6, 5],
    ]
    .iter()
    .map(|f| f.iter().map(|&l| v[l]).collect())
    .collect()
}

/// An L-shaped channel along z: uniform hexahedra, `n` per unit edge (n even), filling the unit
/// cube less the block x > ½, y < ½, so the walls meet at a convex edge along (½, ½, z) (and at
/// concave ones elsewhere). Patches: `inlet` (z = 0, patch), `outlet` (z = 1, patch), `walls`
/// (wall) on every other side.
pub fn l_channel(n: usize) -> Raw {
    let id = |i: usize, j: usize, k: usize| (i + (n + 1) * (j + (n + 1) * k)) as u32;
    let mut points = Vec::new();
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                points.push(Vec3::new(i as f64, j as f64, k as f64) / n as f64);
            }
        }
    }
    let mut cells: Vec<Vec<Vec<u32>>> = Vec::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                if 2 * i >= n && 2 * j < n {
                    continue;
                }
                let v = [
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ];
                cells.push(hex_faces(v));
            }
        }
    }
    let order = [("inlet", "patch"), ("outlet", "patch"), ("walls", "wall")];
    assemble_with(points, &cells, &order, |c| {
        if c[2] < 1e-9 {
            0
        } else if c[2] > 1.0 - 1e-9 {
            1
        } else {
            2
        }
    })
}

/// Hexahedra on the grid `xs` × `ys` × `zs` (each ascending) with every point moved by `map`,
/// less the cells whose (unmapped) centre `solid` takes. `map` must keep the faces of each cell
/// planar (e.g. piecewise linear in x with a kink on a grid line). Patches: `wall` (type wall)
/// on the boundary faces whose (mapped) centre `wall` takes, `open` (type patch) on the rest.
pub fn carved_box(
    xs: &[f64],
    ys: &[f64],
    zs: &[f64],
    map: impl Fn(Vec3) -> Vec3,
    solid: impl Fn(&Vec3) -> bool,
    wall: impl Fn(&Vec3) -> bool,
) -> Raw {
    let (nx, ny) = (xs.len(), ys.len());
    let id = |i: usize, j: usize, k: usize| (i + nx * (j + ny * k)) as u32;
    let mut points = Vec::new();
    for &z in zs {
        for &y in ys {
            for &x in xs {
                points.push(map(Vec3::new(x, y, z)));
            }
        }
    }
    let mut cells: Vec<Vec<Vec<u32>>> = Vec::new();
    for k in 0..zs.len() - 1 {
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                let centre = Vec3::new(xs[i] + xs[i + 1], ys[j] + ys[j + 1], zs[k] + zs[k + 1]) * 0.5;
                if solid(&centre) {
                    continue;
                }
                cells.push(hex_faces([
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ]));
            }
        }
    }
    assemble_with(points, &cells, &[("wall", "wall"), ("open", "patch")], |c| {
        usize::from(!wall(c))
    })
}

/// Patch of a boundary face by its centre.
fn patch_name(c: &Vec3) -> &'static str {
    if c[0] < 1e-9 {
        "inlet"
    } else if c[0] > 1.0 - 1e-9 {
        "outlet"
    } else {
        "walls"
    }
}

/// Hexahedra on the tensor grid `xs` × `ys` × `zs` (each ascending), or with `prisms` each
/// hexahedron split into two triangular prisms stacked along y (triangular faces on the planes
/// y = const, as prism layers on a wall have). Patches: `wall` (type wall) on y = ys[0],
/// `open` (type patch) on the other five sides.
pub fn layered_box(xs: &[f64], ys: &[f64], zs: &[f64], prisms: bool) -> Raw {
    let (nx, ny) = (xs.len(), ys.len());
    let id = |i: usize, j: usize, k: usize| (i + nx * (j + ny * k)) as u32;
    let mut points = Vec::new();
    for &z in zs {
        for &y in ys {
            for &x in xs {
                points.push(Vec3::new(x, y, z));
            }
        }
    }
    let mut cells: Vec<Vec<Vec<u32>>> = Vec::new();
    for k in 0..zs.len() - 1 {
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                // Quads on y = ys[j] (b) and y = ys[j + 1] (t), in the same order.
                let b = [id(i, j, k), id(i + 1, j, k), id(i + 1, j, k + 1), id(i, j, k + 1)];
                let t = [
                    id(i, j + 1, k),
                    id(i + 1, j + 1, k),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ];
                let sides = |l: &[usize]| -> Vec<Vec<u32>> {
                    (0..l.len())
                        .map(|e| {
                            let (p, q) = (l[e], l[(e + 1) % l.len()]);
                            vec![b[p], b[q], t[q], t[p]]
                        })
                        .collect()
                };
                let mut prism = |l: &[usize]| {
                    let mut faces = vec![l.iter().map(|&v| b[v]).collect(), l.iter().map(|&v| t[v]).collect()];
                    faces.extend(sides(l));
                    cells.push(faces);
                };
                if prisms {
                    prism(&[0, 1, 2]);
                    prism(&[0, 2, 3]);
                } else {
                    prism(&[0, 1, 2, 3]);
                }
            }
        }
    }
    let y0 = ys[0];
    let scale = ys[ny - 1] - y0;
    assemble_with(points, &cells, &[("wall", "wall"), ("open", "patch")], |c| {
        usize::from(c[1] > y0 + 1e-9 * scale)
    })
}

/// Face-based form: faces matched by vertex set, internal faces first (by owner, then
/// neighbour), then the patches `inlet`, `outlet`, `walls`; every face oriented out of its owner.
fn assemble(points: Vec<Vec3>, cells: &[Vec<Vec<u32>>]) -> Raw {
    let order = [("inlet", "patch"), ("outlet", "patch"), ("walls", "wall")];
    assemble_with(points, cells, &order, |c| {
        order.iter().position(|&(o, _)| o == patch_name(c)).unwrap()
    })
}

/// Face-based form with the patches `patches` (name, type): boundary face centre c goes to
/// patch `patch_of(c)`.
fn assemble_with(
    points: Vec<Vec3>,
    cells: &[Vec<Vec<u32>>],
    patches: &[(&str, &str)],
    patch_of: impl Fn(&Vec3) -> usize,
) -> Raw {
    let centroid = |vs: &[u32]| vs.iter().map(|&v| points[v as usize]).sum::<Vec3>() / vs.len() as f64;
    let newell = |vs: &[u32]| {
        let mut n = Vec3::zeros();
        for (i, &a) in vs.iter().enumerate() {
            let b = vs[(i + 1) % vs.len()];
            n += points[a as usize].cross(&points[b as usize]);
        }
        n
    };
    let mut by_key: HashMap<Vec<u32>, (usize, Vec<u32>, Option<usize>)> = HashMap::new();
    for (c, faces) in cells.iter().enumerate() {
        for f in faces {
            let mut key = f.clone();
            key.sort_unstable();
            by_key
                .entry(key)
                .and_modify(|e| e.2 = Some(c))
                .or_insert((c, f.clone(), None));
        }
    }
    let cell_centre: Vec<Vec3> = cells
        .iter()
        .map(|fs| {
            let mut all: Vec<u32> = fs.iter().flatten().copied().collect();
            all.sort_unstable();
            all.dedup();
            centroid(&all)
        })
        .collect();
    let mut internal = Vec::new();
    let mut boundary: Vec<(usize, usize, Vec<u32>)> = Vec::new();
    for (_, (a, f, b)) in by_key {
        let (own, nei) = match b {
            Some(b) => (a.min(b), Some(a.max(b))),
            None => (a, None),
        };
        let mut f = f;
        if newell(&f).dot(&(centroid(&f) - cell_centre[own])) < 0.0 {
            f.reverse();
        }
        match nei {
            Some(nei) => internal.push((own, nei, f)),
            None => {
                boundary.push((patch_of(&centroid(&f)), own, f));
            }
        }
    }
    internal.sort();
    boundary.sort();
    let mut raw = Raw {
        points,
        offsets: vec![0],
        flat: Vec::new(),
        owner: Vec::new(),
        neighbour: Vec::new(),
        patches: Vec::new(),
    };
    let push = |raw: &mut Raw, own: usize, f: &[u32]| {
        raw.flat.extend_from_slice(f);
        raw.offsets.push(raw.flat.len() as u32);
        raw.owner.push(own as u32);
    };
    for (own, nei, f) in &internal {
        push(&mut raw, *own, f);
        raw.neighbour.push(*nei as u32);
    }
    for (p, (name, kind)) in patches.iter().enumerate() {
        let start = raw.owner.len();
        for (_, own, f) in boundary.iter().filter(|b| b.0 == p) {
            push(&mut raw, *own, f);
        }
        raw.patches.push(Patch {
            name: name.to_string(),
            kind: kind.to_string(),
            start,
            size: raw.owner.len() - start,
            coupling: None,
        });
    }
    raw
}

/// The field `f` sampled at the cell centres and boundary face centres of `mesh`.
pub fn sampled(mesh: &PolyMesh, f: impl Fn(&Vec3) -> Vec3) -> VolField {
    VolField::from_fn(mesh, f)
}

/// File encodings of a written case.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Format {
    Ascii,
    Binary,
    /// Binary, every file gzipped.
    BinaryGz,
}

fn header(binary: bool, class: &str, object: &str) -> String {
    format!(
        "/* test case */\nFoamFile\n{{\n    version 2.0;\n    format {};\n    class {class};\n    arch \"LSB;label=32;scalar=64\";\n    object {object};\n}}\n// * * //\n\n",
        if binary { "binary" } else { "ascii" }
    )
}

fn put(path: &Path, bytes: &[u8], gz: bool) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    if gz {
        let mut name = path.as_os_str().to_owned();
        name.push(".gz");
        let file = std::fs::File::create(name).unwrap();
        let mut enc = flate2::write::GzEncoder::new(file, flate2::Compression::default());
        enc.write_all(bytes).unwrap();
        enc.finish().unwrap();
    } else {
        std::fs::write(path, bytes).unwrap();
    }
}

fn scalars_bin(out: &mut Vec<u8>, xs: impl IntoIterator<Item = f64>) {
    for x in xs {
        out.extend_from_slice(&x.to_le_bytes());
    }
}

fn labels_bin(out: &mut Vec<u8>, xs: &[u32]) {
    for &x in xs {
        out.extend_from_slice(&(x as i32).to_le_bytes());
    }
}

fn label_list(binary: bool, object: &str, xs: &[u32]) -> Vec<u8> {
    let mut out = header(binary, "labelList", object).into_bytes();
    if binary {
        out.extend(format!("{}\n(", xs.len()).bytes());
        labels_bin(&mut out, xs);
        out.extend(b")\n");
    } else {
        let mut s = format!("{}\n(\n", xs.len());
        for x in xs {
            writeln!(s, "{x}").unwrap();
        }
        s.push_str(")\n");
        out.extend(s.bytes());
    }
    out
}

/// Vector list body `n(...)` in the file's encoding.
fn vector_list(binary: bool, vs: &[f64]) -> Vec<u8> {
    let n = vs.len() / 3;
    let mut out = Vec::new();
    if binary {
        out.extend(format!("{n}(").bytes());
        scalars_bin(&mut out, vs.iter().copied());
        out.push(b')');
    } else {
        let mut s = format!("{n}\n(\n");
        for v in vs.chunks_exact(3) {
            writeln!(s, "({} {} {})", v[0], v[1], v[2]).unwrap();
        }
        s.push(')');
        out.extend(s.bytes());
    }
    out
}

/// Write the mesh and the velocity at time directory `time` of a case in `dir`.
pub fn write_case(dir: &Path, raw: &Raw, u: &VolField, time: &str, format: Format) {
    let binary = format != Format::Ascii;
    let gz = format == Format::BinaryGz;
    let poly = dir.join("constant/polyMesh");
    let coords: Vec<f64> = raw.points.iter().flat_map(|p| [p[0], p[1], p[2]]).collect();
    let mut points = header(binary, "vectorField", "points").into_bytes();
    points.extend(vector_list(binary, &coords));
    put(&poly.join("points"), &points, gz);

    let mut faces;
    if binary {
        faces = header(true, "faceCompactList", "faces").into_bytes();
        faces.extend(format!("{}\n(", raw.offsets.len()).bytes());
        labels_bin(&mut faces, &raw.offsets);
        faces.extend(format!(")\n{}\n(", raw.flat.len()).bytes());
        labels_bin(&mut faces, &raw.flat);
        faces.extend(b")\n");
    } else {
        faces = header(false, "faceList", "faces").into_bytes();
        let mut s = format!("{}\n(\n", raw.owner.len());
        for w in raw.offsets.windows(2) {
            let f = &raw.flat[w[0] as usize..w[1] as usize];
            let labels: Vec<String> = f.iter().map(u32::to_string).collect();
            writeln!(s, "{}({})", f.len(), labels.join(" ")).unwrap();
        }
        s.push_str(")\n");
        faces.extend(s.bytes());
    }
    put(&poly.join("faces"), &faces, gz);
    put(&poly.join("owner"), &label_list(binary, "owner", &raw.owner), gz);
    put(
        &poly.join("neighbour"),
        &label_list(binary, "neighbour", &raw.neighbour),
        gz,
    );

    let mut boundary = header(binary, "polyBoundaryMesh", "boundary");
    writeln!(boundary, "{}\n(", raw.patches.len()).unwrap();
    for p in &raw.patches {
        writeln!(
            boundary,
            "    {}\n    {{\n        type {};\n        inGroups List<word> 1({});\n        nFaces {};\n        startFace {};\n    }}",
            p.name, p.kind, p.kind, p.size, p.start
        )
        .unwrap();
    }
    boundary.push_str(")\n");
    put(&poly.join("boundary"), boundary.as_bytes(), gz);
    write_field(dir, raw, u, time, format);
}

/// Write `u` as `<dir>/<time>/U` on the mesh `raw` (the mesh itself written by [`write_case`]).
pub fn write_field(dir: &Path, raw: &Raw, u: &VolField, time: &str, format: Format) {
    let binary = format != Format::Ascii;
    let gz = format == Format::BinaryGz;
    let mut field = header(binary, "volVectorField", "U").into_bytes();
    field.extend(b"dimensions [0 1 -1 0 0 0 0];\n\ninternalField nonuniform List<vector> ");
    field.extend(vector_list(binary, &u.internal));
    field.extend(b";\n\nboundaryField\n{\n");
    let n_internal = raw.neighbour.len();
    for p in &raw.patches {
        let (a, b) = (3 * (p.start - n_internal), 3 * (p.start - n_internal + p.size));
        let kind = if p.name == "walls" { "calculated" } else { "fixedValue" };
        field.extend(
            format!(
                "    {}\n    {{\n        type {kind};\n        value nonuniform List<vector> ",
                p.name
            )
            .bytes(),
        );
        field.extend(vector_list(binary, &u.boundary[a..b]));
        field.extend(b";\n    }\n");
    }
    field.extend(b"}\n");
    put(&dir.join(time).join("U"), &field, gz);
}

/// Write the mesh `raw` and `U = u(x, t)` at each of `times` into `dir` (a transient case: the
/// time directories are named by the times' shortest round-trip form).
pub fn write_levels(dir: &Path, raw: &Raw, times: &[f64], u: impl Fn(&Vec3, f64) -> Vec3) {
    let mesh = raw.mesh();
    for (i, &t) in times.iter().enumerate() {
        let field = sampled(&mesh, |x| u(x, t));
        let name = format!("{t}");
        if i == 0 {
            write_case(dir, raw, &field, &name, Format::Binary);
        } else {
            write_field(dir, raw, &field, &name, Format::Binary);
        }
    }
}

/// A circular pipe of radius `radius` along z ∈ [0, `length`] as users mesh it with blockMesh:
/// an O-grid of a square core (n × n cells, half-side 0.4 R) and four blocks of n × m cells from
/// the square to the circle, the radial cells shrinking geometrically towards the wall so that
/// the first is `grading` times thinner than the last (1: uniform); `nz` cells along the axis.
/// The wall is the polygon through the circle's points (4n facets around). Patches `inlet`
/// (z = 0, patch), `outlet` (z = L, patch), `wall` (wall).
pub fn pipe(radius: f64, length: f64, n: usize, m: usize, grading: f64, nz: usize) -> Raw {
    use std::f64::consts::FRAC_PI_2;
    let s = 0.4 * radius;
    // Section points, deduplicated by position.
    let mut section: Vec<(f64, f64)> = Vec::new();
    let mut index: HashMap<(i64, i64), usize> = HashMap::new();
    let mut point = |x: f64, y: f64| -> usize {
        let key = ((x / radius * 1e9).round() as i64, (y / radius * 1e9).round() as i64);
        *index.entry(key).or_insert_with(|| {
            section.push((x, y));
            section.len() - 1
        })
    };
    let mut quads: Vec<[usize; 4]> = Vec::new();
    let core = |i: usize, j: usize| (-s + 2.0 * s * i as f64 / n as f64, -s + 2.0 * s * j as f64 / n as f64);
    let core_ids: Vec<Vec<usize>> = (0..=n)
        .map(|i| {
            (0..=n)
                .map(|j| {
                    let (x, y) = core(i, j);
                    point(x, y)
                })
                .collect()
        })
        .collect();
    for i in 0..n {
        for j in 0..n {
            quads.push([
                core_ids[i][j],
                core_ids[i + 1][j],
                core_ids[i + 1][j + 1],
                core_ids[i][j + 1],
            ]);
        }
    }
    // Radial stations: cell k has height ∝ q^k with q^(m−1) = 1/grading.
    let q = if m > 1 {
        (1.0 / grading).powf(1.0 / (m - 1) as f64)
    } else {
        1.0
    };
    let heights: Vec<f64> = (0..m).map(|k| q.powi(k as i32)).collect();
    let total: f64 = heights.iter().sum();
    let mut stations = vec![0.0];
    for h in &heights {
        stations.push(stations.last().unwrap() + h / total);
    }
    for side in 0..4 {
        // Edge of the square from corner a to corner b (counter-clockwise), and the arc above it.
        let angle0 = -FRAC_PI_2 / 2.0 + side as f64 * FRAC_PI_2;
        let rot = |x: f64, y: f64| {
            let (c, sn) = ((side as f64 * FRAC_PI_2).cos(), (side as f64 * FRAC_PI_2).sin());
            (c * x - sn * y, sn * x + c * y)
        };
        let mut ids = vec![vec![0usize; m + 1]; n + 1];
        for (j, row) in ids.iter_mut().enumerate() {
            let (px, py) = rot(s, -s + 2.0 * s * j as f64 / n as f64);
            let theta = angle0 + FRAC_PI_2 * j as f64 / n as f64;
            let (cx, cy) = (radius * theta.cos(), radius * theta.sin());
            for (k, id) in row.iter_mut().enumerate() {
                let t = stations[k];
                *id = point(px + (cx - px) * t, py + (cy - py) * t);
            }
        }
        for j in 0..n {
            for k in 0..m {
                quads.push([ids[j][k], ids[j][k + 1], ids[j + 1][k + 1], ids[j + 1][k]]);
            }
        }
    }
    let np = section.len();
    let mut points = Vec::with_capacity(np * (nz + 1));
    for l in 0..=nz {
        let z = length * l as f64 / nz as f64;
        points.extend(section.iter().map(|&(x, y)| Vec3::new(x, y, z)));
    }
    let mut cells: Vec<Vec<Vec<u32>>> = Vec::new();
    for l in 0..nz {
        for quad in &quads {
            let b: Vec<u32> = quad.iter().map(|&p| (p + np * l) as u32).collect();
            let t: Vec<u32> = quad.iter().map(|&p| (p + np * (l + 1)) as u32).collect();
            let mut faces = vec![b.clone(), t.clone()];
            for e in 0..4 {
                let (p, r) = (e, (e + 1) % 4);
                faces.push(vec![b[p], b[r], t[r], t[p]]);
            }
            cells.push(faces);
        }
    }
    assemble_with(
        points,
        &cells,
        &[("inlet", "patch"), ("outlet", "patch"), ("wall", "wall")],
        |c| {
            if c[2] < 1e-9 * length {
                0
            } else if c[2] > length * (1.0 - 1e-9) {
                1
            } else {
                2
            }
        },
    )
}

/// A copy of the case `from`'s `subdirs` (plain files only) in a fresh directory `to`, to be
/// altered.
pub fn copy_case(from: &Path, to: &Path, subdirs: &[&str]) {
    let _ = std::fs::remove_dir_all(to);
    for sub in subdirs {
        std::fs::create_dir_all(to.join(sub)).unwrap();
        for e in std::fs::read_dir(from.join(sub)).unwrap() {
            let e = e.unwrap();
            if e.file_type().unwrap().is_file() {
                std::fs::copy(e.path(), to.join(sub).join(e.file_name())).unwrap();
            }
        }
    }
}

/// `tests/data/channel-2d`: a 2-D channel as simpleFoam wrote it.
pub fn channel_2d() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/channel-2d")
}

/// A copy of the 2-D channel's mesh and solved time in a scratch directory, to be altered.
pub fn channel_copy(name: &str) -> std::path::PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("channel_2d").join(name);
    copy_case(&channel_2d(), &dir, &["constant/polyMesh", "117"]);
    dir
}

/// The case `dir`'s `constant/polyMesh/boundary` with patch `patch`'s type set to `kind`.
pub fn retype(dir: &Path, patch: &str, kind: &str) {
    let path = dir.join("constant/polyMesh/boundary");
    let text = std::fs::read_to_string(&path).unwrap();
    let at = text.find(&format!("    {patch}\n")).unwrap();
    let ty = at + text[at..].find("type").unwrap();
    let end = ty + text[ty..].find(';').unwrap();
    std::fs::write(&path, format!("{}type {kind}{}", &text[..ty], &text[end..])).unwrap();
}

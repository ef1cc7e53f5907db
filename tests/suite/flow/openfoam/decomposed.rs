//! Decomposed cases read directly (`flow::openfoam::decomposed`): the shipped 3×3×2 cavity,
//! decomposed by OpenFOAM's `decomposePar` (`random`, 3 processors; tests/data/cavity-decomposed/README.md),
//! reads to the same mesh arrays, fields, flow samples and tracer paths, bit for bit, as its
//! undecomposed mesh and field; the layouts; and missing or inconsistent addressing as typed
//! errors. `decomposed_ci_cases` compares the cases `cases/decomposed-ci.sh` decomposes.

use super::scratch;
use pseudorigid::flow::openfoam::{BlendedFlow, FoamCase, FoamError, FoamFlow, Layout, PolyMesh};
use pseudorigid::flow::{FlowField, FlowSample};
use pseudorigid::tensor::Vec3;
use std::path::{Path, PathBuf};

fn shipped() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/cavity-decomposed")
}

const T: f64 = 127.0;

/// A copy of the shipped case in a scratch folder named after the test.
fn copy_of_shipped(name: &str) -> PathBuf {
    fn copy(from: &Path, to: &Path) {
        std::fs::create_dir_all(to).unwrap();
        for e in std::fs::read_dir(from).unwrap() {
            let e = e.unwrap();
            if e.path().is_dir() {
                copy(&e.path(), &to.join(e.file_name()));
            } else {
                std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
            }
        }
    }
    let dir = scratch(&format!("decomposed-{name}"));
    copy(&shipped(), &dir);
    dir
}

/// Every array of the two meshes, bit for bit (points and derived geometry by their f64 bits).
fn assert_same_mesh(a: &PolyMesh, b: &PolyMesh) {
    let bits = |v: &[Vec3]| {
        v.iter()
            .flat_map(|x| x.iter().map(|c| c.to_bits()))
            .collect::<Vec<u64>>()
    };
    assert_eq!(bits(a.points()), bits(b.points()));
    assert_eq!(
        (a.n_faces(), a.n_internal_faces(), a.n_cells()),
        (b.n_faces(), b.n_internal_faces(), b.n_cells())
    );
    for f in 0..a.n_faces() {
        assert_eq!(
            (a.face(f), a.owner(f), a.neighbour(f)),
            (b.face(f), b.owner(f), b.neighbour(f)),
            "face {f}"
        );
    }
    assert_eq!(a.patches(), b.patches());
    assert_eq!(bits(a.face_centres()), bits(b.face_centres()));
    assert_eq!(bits(a.face_areas()), bits(b.face_areas()));
    assert_eq!(bits(a.cell_centres()), bits(b.cell_centres()));
    let vols = |m: &PolyMesh| m.cell_volumes().iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(vols(a), vols(b));
    assert_eq!(a.content_hash(), b.content_hash());
}

fn sample_bits(s: &FlowSample) -> Vec<u64> {
    s.u.iter()
        .chain(s.grad_u.iter())
        .chain(s.du_dt.iter())
        .chain(s.convective.iter())
        .map(|c| c.to_bits())
        .collect()
}

/// Deterministic points in the box `lo..hi` (a 64-bit LCG), a margin outside it included so
/// that the errors outside the mesh are compared too.
fn box_points(n: usize, lo: Vec3, hi: Vec3) -> Vec<Vec3> {
    let mut s = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = move || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let span = hi - lo;
    (0..n)
        .map(|_| Vec3::new(next(), next(), next()).map(|c| 1.1 * c - 0.05))
        .map(|c| lo + span.component_mul(&c))
        .collect()
}

/// What two readings of one case agree on, for the report.
#[derive(Debug, Default)]
struct Agreement {
    cells: usize,
    times: usize,
    samples: usize,
    outside: usize,
    track_steps: usize,
}

/// Reads `case` as undecomposed and as decomposed and requires bitwise equality of the mesh,
/// of `U` (and `p` where present) at every time both have, of the fingerprints, and of cellwise
/// and blended samples at `n` points and `tracks` RK2 tracer paths through the blended flow.
fn compare_layouts(case: &Path, n: usize, tracks: usize) -> Agreement {
    let whole = FoamCase::open_with(case, Layout::Reconstructed).unwrap();
    let parts = FoamCase::open_with(case, Layout::Decomposed).unwrap();
    assert!(parts.is_decomposed() && !whole.is_decomposed());
    assert_same_mesh(whole.mesh(), parts.mesh());
    let times: Vec<f64> = parts
        .times()
        .into_iter()
        .filter(|t| whole.times().contains(t))
        .collect();
    assert!(!times.is_empty(), "{}: no time in both layouts", case.display());
    for &t in &times {
        assert_eq!(
            whole.read_field(t, "U", 3).unwrap(),
            parts.read_field(t, "U", 3).unwrap(),
            "U at {t}"
        );
        if whole.time_dir(t).unwrap().join("p").is_file() {
            assert_eq!(
                whole.read_field(t, "p", 1).unwrap(),
                parts.read_field(t, "p", 1).unwrap(),
                "p at {t}"
            );
        }
    }
    let last = [*times.last().unwrap()];
    let (a, b) = (
        FoamFlow::read(&whole, &last).unwrap(),
        FoamFlow::read(&parts, &last).unwrap(),
    );
    assert_eq!(a.fingerprint(), b.fingerprint());
    let (ba, bb) = (
        BlendedFlow::new(a.clone()).unwrap(),
        BlendedFlow::new(b.clone()).unwrap(),
    );
    assert_eq!(ba.fingerprint(), bb.fingerprint());
    let m = whole.mesh();
    let lo = m.points().iter().fold(Vec3::repeat(f64::INFINITY), |l, p| l.inf(p));
    let hi = m.points().iter().fold(Vec3::repeat(f64::NEG_INFINITY), |h, p| h.sup(p));
    let mut agreement = Agreement {
        cells: m.n_cells(),
        times: times.len(),
        ..Agreement::default()
    };
    let t = last[0];
    for x in box_points(n, lo, hi) {
        let pairs: [(&dyn FlowField, &dyn FlowField); 2] = [(&a, &b), (&ba, &bb)];
        for (f, g) in pairs {
            match (f.sample(&x, t), g.sample(&x, t)) {
                (Ok(s), Ok(r)) => assert_eq!(sample_bits(&s), sample_bits(&r), "at {x:?}"),
                (Err(e), Err(r)) => {
                    assert_eq!(e.to_string(), r.to_string());
                    agreement.outside += 1;
                }
                (s, r) => panic!("at {x:?}: {s:?} against {r:?}"),
            }
            agreement.samples += 1;
        }
    }
    // Tracer paths: RK2 with a step of a tenth of a cell's crossing time at the largest speed.
    let speed = (0..m.n_cells())
        .map(|c| ba.sample(&m.cell_centres()[c], t).map_or(0.0, |s| s.u.norm()))
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let h = 0.1 * (hi - lo).amin() / (m.n_cells() as f64).cbrt() / speed;
    for x0 in box_points(tracks, lo + 0.1 * (hi - lo), hi - 0.1 * (hi - lo)) {
        let (mut x, mut y) = (x0, x0);
        for _ in 0..200 {
            let (Ok(sx), Ok(sy)) = (ba.sample(&x, t), bb.sample(&y, t)) else {
                break;
            };
            let (Ok(mx), Ok(my)) = (ba.sample(&(x + 0.5 * h * sx.u), t), bb.sample(&(y + 0.5 * h * sy.u), t)) else {
                break;
            };
            x += h * mx.u;
            y += h * my.u;
            assert_eq!(sample_bits(&sx), sample_bits(&sy));
            assert_eq!(x.map(f64::to_bits), y.map(f64::to_bits), "track from {x0:?}");
            agreement.track_steps += 1;
        }
    }
    agreement
}

#[test]
fn shipped_decomposed_case_reads_as_its_undecomposed_mesh_and_field() {
    let agreement = compare_layouts(&shipped(), 2000, 20);
    assert_eq!((agreement.cells, agreement.times), (18, 1));
    assert!(
        agreement.outside > 0 && agreement.outside < agreement.samples / 2,
        "{agreement:?}"
    );
    assert!(agreement.track_steps > 1000, "{agreement:?}");
    // OpenFOAM reversed faces in every processor: the neighbour side of each of its processor
    // faces, whose vertex order the reader has turned back.
    for k in 0..3 {
        let text =
            std::fs::read_to_string(shipped().join(format!("processor{k}/constant/polyMesh/faceProcAddressing")))
                .unwrap();
        assert!(text.lines().any(|l| l.starts_with('-')), "processor{k}");
    }
}

#[test]
fn layouts_choose_where_the_mesh_and_each_time_come_from() {
    // No reconstructed mesh: `open` reads the processors.
    let dir = copy_of_shipped("no-top-mesh");
    std::fs::remove_dir_all(dir.join("constant")).unwrap();
    std::fs::remove_dir_all(dir.join("127")).unwrap();
    let case = FoamCase::open(&dir).unwrap();
    assert!(case.is_decomposed());
    assert_eq!(case.times(), vec![T]);
    let u = case.read_field(T, "U", 3).unwrap();
    let whole = FoamCase::open(shipped()).unwrap();
    assert!(!whole.is_decomposed());
    assert_eq!(u, whole.read_field(T, "U", 3).unwrap());
    let err = FoamCase::open_with(&dir, Layout::Reconstructed).unwrap_err();
    assert!(matches!(err, FoamError::Decomposed { processors: 3, .. }), "{err:?}");

    // The reconstructed mesh and a time only the processors have (a case solved in parallel):
    // `open` lists it and reads it from the processors, after checking their mesh is this one.
    let dir = copy_of_shipped("time-in-processors");
    std::fs::remove_dir_all(dir.join("127")).unwrap();
    let case = FoamCase::open(&dir).unwrap();
    assert!(!case.is_decomposed());
    assert_eq!(case.times(), vec![T]);
    assert_eq!(case.read_field(T, "U", 3).unwrap(), u);
    assert!(matches!(case.time_dir(T), Err(FoamError::Decomposed { .. })));
    assert!(matches!(
        case.read_field(1.0, "U", 3),
        Err(FoamError::NoSuchTime { .. })
    ));
    // Read as serial, the time is not there and the error says to reconstruct it.
    let serial = FoamCase::open_with(&dir, Layout::Reconstructed).unwrap();
    assert!(serial.times().is_empty());
    let err = serial.read_field(T, "U", 3).unwrap_err();
    assert!(
        matches!(err, FoamError::Decomposed { .. }) && err.to_string().contains("reconstructPar"),
        "{err}"
    );

    // Both have the time: the top level's is read, unless the processors are asked for.
    let dir = copy_of_shipped("both");
    let top = dir.join("127/U");
    let text = std::fs::read_to_string(&top).unwrap();
    std::fs::write(
        &top,
        text.replace(
            "value           uniform (0.0813 0 0)",
            "value           uniform (1 0 0)",
        ),
    )
    .unwrap();
    let lid = |case: &FoamCase| {
        let patch = &case.mesh().patches()[0];
        let u = case.read_field(T, "U", 3).unwrap();
        u.boundary_face(patch.start - case.mesh().n_internal_faces())[0]
    };
    assert_eq!(lid(&FoamCase::open(&dir).unwrap()), 1.0);
    assert_eq!(lid(&FoamCase::open_with(&dir, Layout::Decomposed).unwrap()), 0.0813);

    // A stale decomposition: the top level's mesh is another one, so a time read from the
    // processors would place values in the wrong cells; it is refused.
    let dir = copy_of_shipped("stale");
    std::fs::remove_dir_all(dir.join("127")).unwrap();
    let owner = dir.join("constant/polyMesh/owner");
    let text = std::fs::read_to_string(&owner).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    // Cells 0 and 1 renumbered: a valid mesh, but not the processors'.
    for l in lines.iter_mut() {
        *l = match l.as_str() {
            "0" => "1".into(),
            "1" => "0".into(),
            _ => l.clone(),
        };
    }
    std::fs::write(&owner, lines.join("\n")).unwrap();
    let neighbour = dir.join("constant/polyMesh/neighbour");
    let text = std::fs::read_to_string(&neighbour).unwrap();
    let swapped: Vec<String> = text
        .lines()
        .map(|l| match l {
            "0" => "1".into(),
            "1" => "0".into(),
            _ => l.to_string(),
        })
        .collect();
    std::fs::write(&neighbour, swapped.join("\n")).unwrap();
    let case = FoamCase::open(&dir).unwrap();
    let err = case.read_field(T, "U", 3).unwrap_err();
    assert!(
        matches!(&err, FoamError::Decomposition { reason, .. } if reason.contains("stale")),
        "{err}"
    );
}

#[test]
fn missing_addressing_names_reconstruct_par_mesh() {
    for file in [
        "cellProcAddressing",
        "faceProcAddressing",
        "pointProcAddressing",
        "boundaryProcAddressing",
    ] {
        let dir = copy_of_shipped(&format!("missing-{file}"));
        std::fs::remove_dir_all(dir.join("constant")).unwrap();
        std::fs::remove_file(dir.join("processor1/constant/polyMesh").join(file)).unwrap();
        let err = FoamCase::open(&dir).unwrap_err();
        match &err {
            FoamError::NoProcAddressing { path } => assert!(
                path.ends_with(&format!("processor1/constant/polyMesh/{file}")),
                "{path}"
            ),
            other => panic!("{file}: {other:?}"),
        }
        assert!(err.to_string().contains("reconstructParMesh"), "{err}");
    }
}

/// Replace the first occurrence of `from` in `file` of the case by `to`.
fn edit(dir: &Path, file: &str, from: &str, to: &str) {
    let path = dir.join(file);
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains(from), "{file} has no `{from}`");
    std::fs::write(&path, text.replacen(from, to, 1)).unwrap();
}

#[test]
fn inconsistent_decompositions_are_typed_errors() {
    let decomposition_error = |dir: &Path, what: &str| {
        let err = FoamCase::open_with(dir, Layout::Decomposed).and_then(|c| c.read_field(T, "U", 3).map(|_| c));
        match err {
            Err(FoamError::Decomposition { .. } | FoamError::Malformed { .. }) => {}
            other => panic!("{what}: {:?}", other.map(|c| c.mesh().n_cells())),
        }
    };
    let cell_list = "processor1/constant/polyMesh/cellProcAddressing";
    let face_list = "processor1/constant/polyMesh/faceProcAddressing";
    let text = |dir: &Path, file: &str| std::fs::read_to_string(dir.join(file)).unwrap();

    // A cell twice (processor 0's first cell), a cell past the cells, a list one entry short,
    // a truncated list.
    for (name, with) in [
        ("cell-twice", "5(6 5 8 11 15)"),
        ("cell-out-of-range", "5(18 5 8 11 15)"),
        ("cell-list-short", "4(5 8 11 15)"),
        ("cell-list-truncated", "5(3 5 8"),
    ] {
        let dir = copy_of_shipped(name);
        edit(&dir, cell_list, "5(3 5 8 11 15)", with);
        decomposition_error(&dir, name);
    }
    // A processor face turned (its sign flipped): its owner side listed twice or not at all.
    let dir = copy_of_shipped("face-sign");
    let body = text(&dir, face_list);
    let first = body[body.find("\n(\n").unwrap() + 3..]
        .lines()
        .next()
        .unwrap()
        .to_string();
    let reversed = body.lines().find(|l| l.starts_with('-')).unwrap().to_string();
    edit(
        &dir,
        face_list,
        &format!("\n{reversed}\n"),
        &format!("\n{}\n", &reversed[1..]),
    );
    decomposition_error(&dir, "reversed face unreversed");
    // A face label 0 (the labels are 1-based), and one past every face.
    let dir = copy_of_shipped("face-zero");
    edit(&dir, face_list, &format!("(\n{first}\n"), "(\n0\n");
    decomposition_error(&dir, "face 0");
    let dir = copy_of_shipped("face-huge");
    edit(&dir, face_list, &format!("(\n{first}\n"), "(\n-2147483647\n");
    decomposition_error(&dir, "face 2^31 - 1");
    // A processor patch mapped to a real patch, and a real patch to none.
    let dir = copy_of_shipped("patch-map");
    edit(
        &dir,
        "processor1/constant/polyMesh/boundaryProcAddressing",
        "4(0 1 -1 -1)",
        "4(0 -1 -1 -1)",
    );
    decomposition_error(&dir, "fixedWalls unmapped");
    let dir = copy_of_shipped("patch-renamed");
    edit(&dir, "processor2/constant/polyMesh/boundary", "fixedWalls", "walls");
    decomposition_error(&dir, "patch renamed in one processor");
    // A point moved in one processor only.
    let dir = copy_of_shipped("point-moved");
    edit(
        &dir,
        "processor1/constant/polyMesh/points",
        "(0 0.03333333333 0)",
        "(0 0.03333333334 0)",
    );
    decomposition_error(&dir, "point moved");
    // A missing processor in the numbering, and the collated format.
    let dir = copy_of_shipped("gap");
    std::fs::rename(dir.join("processor1"), dir.join("processor7")).unwrap();
    decomposition_error(&dir, "processor1 missing");
    let dir = copy_of_shipped("collated");
    for k in 0..3 {
        std::fs::remove_dir_all(dir.join(format!("processor{k}"))).unwrap();
    }
    std::fs::create_dir_all(dir.join("processors3/constant")).unwrap();
    let err = FoamCase::open_with(&dir, Layout::Decomposed).unwrap_err();
    assert!(err.to_string().contains("collated"), "{err}");
    // A time directory missing from one processor names the file.
    let dir = copy_of_shipped("time-missing");
    std::fs::remove_file(dir.join("processor2/127/U")).unwrap();
    let case = FoamCase::open_with(&dir, Layout::Decomposed).unwrap();
    let err = case.read_field(T, "U", 3).unwrap_err();
    assert!(
        matches!(&err, FoamError::Missing { path } if path.contains("processor2")),
        "{err}"
    );
}

/// The cases `cases/decomposed-ci.sh` prepares (a colon-separated list in
/// `PSEUDORIGID_DECOMPOSED_CASES`, each decomposed by `decomposePar` with its undecomposed mesh
/// and times kept): read both ways, compared bit for bit. Does nothing without the variable.
#[test]
fn decomposed_ci_cases() {
    let Some(cases) = std::env::var_os("PSEUDORIGID_DECOMPOSED_CASES") else {
        return;
    };
    for case in std::env::split_paths(&cases) {
        let a = compare_layouts(&case, 20_000, 50);
        println!(
            "{}: {} cells, {} time levels, {} samples equal bit for bit ({} outside the mesh, the same error), {} tracer steps equal",
            case.display(),
            a.cells,
            a.times,
            a.samples,
            a.outside,
            a.track_steps
        );
    }
}

/// A patch without faces, as a processor has a patch whose faces are all elsewhere: its value
/// is written `nonuniform 0()`, which reads as no values; the same for a patch with faces is an
/// error.
#[test]
fn patches_without_faces_read_their_empty_value_lists() {
    let dir = copy_of_shipped("empty-patch");
    edit(&dir, "constant/polyMesh/boundary", "\n2\n(", "\n3\n(");
    edit(
        &dir,
        "constant/polyMesh/boundary",
        "\n)",
        "\n    spare { type patch; nFaces 0; startFace 75; }\n)",
    );
    edit(
        &dir,
        "127/U",
        "    fixedWalls",
        "    spare { type fixedValue; value nonuniform 0(); }\n    fixedWalls",
    );
    let case = FoamCase::open_with(&dir, Layout::Reconstructed).unwrap();
    let u = case.read_field(T, "U", 3).unwrap();
    assert_eq!(u.fixed, vec![true; 3]);
    assert_eq!(u.boundary.len(), 3 * 42);
    edit(
        &dir,
        "127/U",
        "value           uniform (0.0813 0 0)",
        "value nonuniform 0()",
    );
    let err = case.read_field(T, "U", 3).unwrap_err();
    assert!(err.to_string().contains("an empty list for 9 faces"), "{err}");
}

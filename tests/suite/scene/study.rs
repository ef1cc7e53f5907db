//! `pseudorigid study` (`scene::study`, issue 58 item 1): a reduced Pich case. Point particles
//! settle out of Poiseuille flow (written exactly into the cells) in a horizontal pipe meshed
//! as three O-grids of increasing resolution, entering at the same points on every mesh; the
//! study pairs their fates across the meshes.
//! Pich's (1972) fraction at ε = 0.3 is 0.4341 (`pseudorigid::reference::pich_deposition`).

use crate::common::build;
use pseudorigid::population::Progress;
use pseudorigid::population::Shard;
use pseudorigid::population::mesh_study::MeshStudy;
use pseudorigid::scene::load_study;
use pseudorigid::scene::study::{FORMAL_ORDER, StudyOptions, run_study};
use pseudorigid::tensor::Vec3;
use std::path::Path;

/// Pich's deposited fraction ([`pseudorigid::reference::pich_deposition`]).
fn pich(epsilon: f64) -> f64 {
    pseudorigid::reference::pich_deposition(epsilon).unwrap()
}

/// 240 point particles of `studies::pich` at ε = 0.3 in the pipe R = 1, L = 4, Ū = 1 on three
/// O-grids; the study's files and numbers.
#[test]
fn reduced_pich_study() {
    let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join("reduced_pich_study");
    let _ = std::fs::remove_dir_all(&root);
    let (radius, length) = (1.0, 4.0);
    let mut cases = Vec::new();
    for (k, (n, m, nz)) in [(6, 8, 16), (4, 5, 10), (3, 4, 8)].into_iter().enumerate() {
        let raw = build::pipe(radius, length, n, m, 1.0, nz);
        let mut u = build::sampled(&raw.mesh(), |x| {
            let r2 = (x[0] * x[0] + x[1] * x[1]) / (radius * radius);
            Vec3::new(0.0, 0.0, 2.0 * (1.0 - r2).max(0.0))
        });
        let mesh = raw.mesh();
        let wall = mesh.patches().iter().find(|p| p.name == "wall").unwrap().clone();
        let first = wall.start - mesh.n_internal_faces();
        u.boundary[3 * first..3 * (first + wall.size)].fill(0.0);
        let dir = root.join(format!("pipe{k}"));
        build::write_case(&dir, &raw, &u, "0", build::Format::Ascii);
        cases.push(format!("pipe{k}"));
    }
    let scene = root.join("study.toml");
    std::fs::write(&scene, pseudorigid::studies::pich::scene(&cases, 0.3, 240, 7)).unwrap();
    let meshes = load_study(&scene).unwrap();
    assert_eq!(meshes.len(), 3);
    let out = root.join("out");
    let options = StudyOptions {
        checkpoint_every: 30.0,
        resume: false,
        progress: Progress::Quiet,
        threads: None,
        csv: false,
        formal_order: FORMAL_ORDER,
    };
    let log = run_study(&meshes, &out, Shard::ALL, &options).unwrap();
    eprintln!("{log}");
    let study: MeshStudy = serde_json::from_slice(&std::fs::read(out.join("study.json")).unwrap()).unwrap();
    assert_eq!(study.particles, 240);
    assert!(study.meshes.windows(2).all(|w| w[0].cells > w[1].cells), "finest first");
    let deposited = study.outcomes.iter().find(|o| o.outcome == "deposited:wall").unwrap();
    let escaped = study.outcomes.iter().find(|o| o.outcome == "escaped:outlet").unwrap();
    let exact = pich(0.3);
    for k in 0..3 {
        assert_eq!(
            deposited.counts[k] + escaped.counts[k],
            240,
            "mesh {k}: every particle deposits or escapes"
        );
        let se = (exact * (1.0 - exact) / 240.0).sqrt();
        assert!(
            (deposited.values[k] - exact).abs() < 3.0 * se,
            "mesh {k}: {} against Pich {exact:.4} ± {se:.4}",
            deposited.values[k]
        );
    }
    // The increments are paired, and particle k starts at the same point on every mesh (the
    // disc weighted by pipe flux, `studies::pich`): only particles whose start lies within the
    // meshes' velocity difference of the deposition boundary change fate. These meshes' flows
    // differ by a few per cent of Ū near the wall (the faceted wall's cell layer), so a few per
    // cent of the particles at most are discordant, and McNemar's error sqrt(d)/n is below
    // half the two binomial errors combined (sqrt(2 f(1 − f)/n) ≈ 0.045 here) unless more
    // than ~25 % of the particles change fate: a per-mesh injection (patch faces weighted by
    // each mesh's own flux) moves every start and fails this.
    for (k, inc) in deposited.increments.iter().enumerate() {
        let independent = deposited.stderr[k].hypot(deposited.stderr[k + 1]);
        eprintln!("increment {k}: {inc:?}, independent {independent:.4}");
        assert!(inc.paired_stderr <= 0.5 * independent, "{inc:?} against {independent}");
        let d = deposited.values[k] - deposited.values[k + 1];
        assert!((inc.difference - d).abs() < 1e-12);
    }
    assert!(!deposited.verdict.is_empty());
    // The reduced dataset, rounded: counts per mesh and the estimate where one was made.
    let rounded: String = study
        .outcomes
        .iter()
        .map(|o| {
            let e = o.estimate.as_ref();
            format!(
                "{}: counts {:?}, cells {:?}, p {}, extrapolated {}, band {}\n",
                o.outcome,
                o.counts,
                study.meshes.iter().map(|m| m.cells).collect::<Vec<_>>(),
                e.and_then(|e| e.p_apparent).map_or("-".into(), |p| format!("{p:.2}")),
                e.map_or("-".into(), |e| format!("{:.3}", e.extrapolated)),
                e.map_or("-".into(), |e| format!("{:.3}", e.band)),
            )
        })
        .collect();
    insta::assert_snapshot!(rounded);
    let csv = std::fs::read_to_string(out.join("study.csv")).unwrap();
    assert!(csv.starts_with("outcome,cells_1,count_1,value_1,stderr_1,"), "{csv}");
    assert_eq!(csv.lines().count(), 1 + study.outcomes.len());
}

/// A scene naming `flow.cases` is a study: `run` and `validate` refuse it at the key, and
/// `load_study` refuses one case, five cases, or `case` beside `cases`.
#[test]
fn cases_belong_to_a_study() {
    use pseudorigid::scene::SceneError;
    use pseudorigid::scene::error::Source;
    let text = |flow: &str| {
        format!(
            "[flow]\ntype = \"openfoam\"\n{flow}\n[fluid]\nviscosity = 1.0\ndensity = 1.0\n[boundary]\ntype = \"mesh\"\n[particles]\ndensity = 1.0\n[[particles.list]]\nsemi_axes = [0.1, 0.1, 0.1]\nposition = [0.5, 0.5, 0.5]\nmaterial = {{ law = \"rigid\" }}\n[integrator]\ntype = \"radau_iia\"\ntol = 1e-6\ndt = 1e-3\n[end]\nt_end = 1.0\n"
        )
    };
    let plain = text("cases = [\"a\", \"b\"]");
    let err = pseudorigid::scene::parse(
        &Source {
            file: "study.toml",
            text: &plain,
        },
        Path::new("."),
    )
    .unwrap_err();
    assert!(
        matches!(&err, SceneError::Invalid { key, message, .. } if key == "flow.cases" && message.contains("pseudorigid study")),
        "{err}"
    );
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cases_belong_to_a_study");
    std::fs::create_dir_all(&dir).unwrap();
    for (flow, key, says) in [
        ("cases = [\"a\"]", "flow.cases", "two to four"),
        (
            "cases = [\"a\", \"b\", \"c\", \"d\", \"e\"]",
            "flow.cases",
            "two to four",
        ),
        ("case = \"a\"\ncases = [\"a\", \"b\"]", "flow.case", "not both"),
        ("case = \"a\"", "flow.cases", "names its meshes"),
    ] {
        let path = dir.join("study.toml");
        std::fs::write(&path, text(flow)).unwrap();
        let err = load_study(&path).unwrap_err();
        assert!(
            matches!(&err, SceneError::Invalid { key: k, message, .. } if k == key && message.contains(says)),
            "{flow}: {err}"
        );
    }
}

//! The example scenes of `scenes/` through the command's library path, at reduced size, against
//! the library's own runs of the same cases. A scene's numbers are the library's f64 values
//! printed in shortest round-trip form, so the particle, flow and plan are bitwise the
//! library's, and so must be the trajectory: every comparison is exact.

mod adequacy;
mod command;
mod parse;
mod run;
mod study;
mod transient;

use crate::common::build;
use pseudorigid::material::NamedLaw;

use pseudorigid::contact::{ContactEvent, ContactModel};
use pseudorigid::driver::{Observers, Plan, Problem, integrate};
use pseudorigid::integrator::{Stokesian, TimeIntegrator};
use pseudorigid::particle::lines::material_line;
use pseudorigid::population::{Fate, RunOptions, RunOutput, Shard};
use pseudorigid::scene::SceneError;
use pseudorigid::scene::error::Source;
use pseudorigid::scene::run::Job;
use pseudorigid::scene::{Scene, parse};
use pseudorigid::studies::particles::Shape;
use pseudorigid::studies::pipe::PipeSetup;
use pseudorigid::studies::shear_regimes::{Regime, RegimeClassifier};
use pseudorigid::studies::shear_run::{oblate_fig4_run, stokesian_scaling};
use pseudorigid::studies::shear_shape::ShearShape;
use std::path::{Path, PathBuf};

/// The scene `text` parsed as the file `file` in the working directory.
fn parse_named(file: &str, text: &str) -> Result<Scene, SceneError> {
    parse(&Source { file, text }, Path::new("."))
}

fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes").join(name)
}

/// The scene `name` with each `(from, to)` text replaced (a reduced size).
fn scene(name: &str, edits: &[(&str, &str)]) -> Scene {
    let path = scene_path(name);
    let mut text = std::fs::read_to_string(&path).unwrap();
    for (from, to) in edits {
        assert!(text.contains(from), "{name} has no `{from}`");
        text = text.replace(from, to);
    }
    let file = path.display().to_string();
    parse(
        &Source {
            file: &file,
            text: &text,
        },
        path.parent().unwrap(),
    )
    .unwrap()
}

fn run(scene: &Scene, name: &str) -> RunOutput<NamedLaw> {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    let options = RunOptions::default().serial().quiet();
    scene
        .population(&Job::Run {
            shard: Shard::ALL,
            options,
            dir,
        })
        .unwrap()
}

#[test]
fn every_example_scene_validates() {
    let mut names: Vec<_> = std::fs::read_dir(scene_path(""))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    names.sort();
    assert!(names.len() >= 3, "{names:?}");
    for p in names {
        let name = p.file_name().unwrap().to_str().unwrap().to_string();
        // A scene on an OpenFOAM case needs the solved case (its Allrun); parse the rest.
        if std::fs::read_to_string(&p).unwrap().contains("\"openfoam\"") {
            continue;
        }
        let s = scene(&name, &[]);
        assert!(s.count() >= 1, "{name}");
    }
}

/// `radau_iia` and `rosenbrock_w23` pick their scheme, and the integrator's dataset name is the
/// scheme's name. Earlier scene files' names are aliases: `stokesian` (the library's
/// `Stokesian::new`) and `stokesian_radau5` read as `radau_iia`, `stokesian_rosenbrock23` as
/// `rosenbrock_w23`.
#[test]
fn scheme_names_and_their_aliases_choose_the_scheme() {
    let from = "type = \"radau_iia\"";
    assert_eq!(Stokesian::new(1e-6).unwrap().name(), "radau_iia");
    for (kind, name) in [
        ("radau_iia", "radau_iia"),
        ("rosenbrock_w23", "rosenbrock_w23"),
        ("stokesian", "radau_iia"),
        ("stokesian_radau5", "radau_iia"),
        ("stokesian_rosenbrock23", "rosenbrock_w23"),
    ] {
        let s = scene("oblate_shear.toml", &[(from, &format!("type = \"{kind}\""))]);
        assert_eq!(s.integrator.name(), name, "{kind}");
    }
}

/// `rosenbrock_w23` takes `frame = "lab"` (the default) or `"body"` (the body-frame step of
/// `integrator::body_frame`, named `rosenbrock_w23_body` in datasets); another value, or a
/// `frame` given to `radau_iia` (which steps the lab frame only), is refused with the key named.
#[test]
fn rosenbrock_takes_the_frame() {
    let from = "type = \"radau_iia\"";
    for (frame, name) in [("lab", "rosenbrock_w23"), ("body", "rosenbrock_w23_body")] {
        let s = scene(
            "oblate_shear.toml",
            &[(from, &format!("type = \"rosenbrock_w23\"\nframe = \"{frame}\""))],
        );
        assert_eq!(s.integrator.name(), name, "{frame}");
    }
    let text = std::fs::read_to_string(scene_path("oblate_shear.toml")).unwrap();
    for bad in [
        "type = \"rosenbrock_w23\"\nframe = \"sideways\"",
        "type = \"radau_iia\"\nframe = \"body\"",
    ] {
        match parse_named("edited.toml", &text.replace(from, bad)) {
            Err(e) => assert!(e.to_string().contains("frame"), "{bad}: {e}"),
            Ok(_) => panic!("{bad} accepted"),
        }
    }
}

/// `slow_manifold` is selectable by name with its `delta_max`, which must lie in (0, 1): a
/// value outside is refused with the key named (no panic, no run). Its full model takes the
/// scheme `auto` takes at the same tolerance (Radau IIA at the scene's 10⁻⁸, Rosenbrock-W 2(3)
/// at the studies' 10⁻²), as the run log says.
#[test]
fn slow_manifold_is_selectable_and_checks_delta_max() {
    let from = "type = \"radau_iia\"";
    let s = scene("oblate_shear.toml", &[(from, "type = \"slow_manifold\"")]);
    assert_eq!(s.integrator.name(), "slow_manifold");
    let log = s.integrator_log().join("\n");
    assert!(log.contains("the full model, radau_iia"), "{log}");
    let loose = scene(
        "oblate_shear.toml",
        &[(from, "type = \"slow_manifold\""), ("tol = 1e-8", "tol = 1e-2")],
    );
    let log = loose.integrator_log().join("\n");
    assert!(log.contains("the full model, rosenbrock_w23"), "{log}");
    let s = scene(
        "oblate_shear.toml",
        &[(from, "type = \"slow_manifold\"\ndelta_max = 0.05")],
    );
    assert_eq!(s.integrator.name(), "slow_manifold");
    let text = std::fs::read_to_string(scene_path("oblate_shear.toml")).unwrap();
    for bad in ["0.0", "1.5", "-0.1"] {
        let edited = text.replace(from, &format!("type = \"slow_manifold\"\ndelta_max = {bad}"));
        match parse_named("edited.toml", &edited) {
            Err(e) => assert!(e.to_string().contains("delta_max"), "{bad}: {e}"),
            Ok(_) => panic!("delta_max = {bad} accepted"),
        }
    }
}

/// The command's summary line gives the slow manifold's share of the steps and its largest δ
/// against δ_max where the run stepped a particle by it, and nothing of it otherwise: Fig. 4's
/// oblate made stiff (μ_s = 2 500, Ca = 4·10⁻⁴: δ ≈ 10⁻³ against δ_max = √10⁻³) under
/// `slow_manifold` at tol 10⁻³, and the scene's own Radau IIA, both to t = 5.
#[test]
fn the_summary_line_gives_the_slow_manifolds_share() {
    let short = ("t_end = 30.0", "t_end = 5.0");
    let stiff = scene(
        "oblate_shear.toml",
        &[
            (
                "type = \"radau_iia\"\ntol = 1e-8",
                "type = \"slow_manifold\"\ntol = 1e-3",
            ),
            ("mu = 2.5, lambda = 2500.0", "mu = 2500.0, lambda = 2.5e6"),
            short,
        ],
    );
    let summary = |s: &Scene, name: &str| {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
        let _ = std::fs::remove_dir_all(&dir);
        let options = RunOptions::default().serial().quiet();
        pseudorigid::scene::run::run(s, &dir, Shard::ALL, options, false).unwrap()
    };
    let done = summary(&stiff, "summary_slow_manifold");
    let m = done.output.integrator().manifold.unwrap();
    let steps = done.output.records[0].stats.steps;
    assert!(
        m.manifold_steps > 0 && m.manifold_steps + m.full_steps == steps,
        "{m:?}"
    );
    let share = format!(
        "; slow manifold: {} of {steps} steps ({:.1} %), largest delta {:.3e} <= delta_max = {:.3e};",
        m.manifold_steps,
        100.0 * m.manifold_steps as f64 / steps as f64,
        m.max_ratio,
        1e-3f64.sqrt()
    );
    assert!(done.summary.contains(&share), "{}", done.summary);
    let done = summary(&scene("oblate_shear.toml", &[short]), "summary_full_model");
    assert!(!done.summary.contains("slow manifold"), "{}", done.summary);
}

/// Fig. 4's oblate at Ca = 0.4: the scene's material lines at every output time equal the
/// library's `oblate_fig4_run` bitwise.
#[test]
fn oblate_shear_scene_is_the_library_fig4_run() {
    let s = scene("oblate_shear.toml", &[("t_end = 30.0", "t_end = 3.0")]);
    let out = run(&s, "cli_oblate");
    let record = &out.records[0];
    assert_eq!(record.fate, Fate::Suspended);
    let shape = record.spec.as_ref().unwrap().shape;
    // The record keeps the start state too; the library samples the output times only.
    let samples = &record.samples[1..];
    let times: Vec<f64> = samples.iter().map(|st| st.t).collect();
    assert_eq!(times, s.outputs);
    assert_eq!(times.len(), 12);
    let (library, _) = oblate_fig4_run(0.4, &times).unwrap();
    let (a, c) = ShearShape::new(Shape::Oblate(2.5)).in_plane_axes();
    for (mine, theirs) in samples.iter().zip(&library) {
        assert_eq!(material_line(&shape, &mine.f, a), theirs.xi_a, "t = {}", mine.t);
        assert_eq!(material_line(&shape, &mine.f, c), theirs.xi_c, "t = {}", mine.t);
    }
}

/// Fig. 7: the two particles either side of the prolate 2:1:1 boundary tumble and tremble as
/// the library's classifier says. The check is on the output times (every 0.1), which can
/// only miss a trembling episode shorter than 0.1: the classifier's margins at these Ca are
/// checked to be far from zero.
/// One frames schema: `frames.csv` and `frames.parquet` of a run hold the same columns
/// (`population::columns::FRAME_COLUMNS`, V by its nine components) and the same numbers.
#[cfg(feature = "parquet")]
#[test]
fn frames_csv_and_parquet_hold_one_schema() {
    use arrow_array::{Array, Float64Array, Int64Array};
    use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
    use pseudorigid::population::columns::FRAME_COLUMNS;
    let s = scene("oblate_shear.toml", &[("t_end = 30.0", "t_end = 3.0")]);
    let out = run(&s, "cli_frames_schema");
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_frames_schema_files");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("vtk")).unwrap();
    let times = s.frame_times();
    pseudorigid::scene::frames::write_run(&out, &times, true, true, &dir).unwrap();
    let text = std::fs::read_to_string(dir.join("frames.csv")).unwrap();
    let rows: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(rows[0], FRAME_COLUMNS);
    let file = std::fs::File::open(dir.join("frames.parquet")).unwrap();
    let batches: Vec<_> = ParquetRecordBatchReaderBuilder::try_new(file)
        .unwrap()
        .build()
        .unwrap()
        .map(Result::unwrap)
        .collect();
    let [table] = batches.as_slice() else {
        panic!("{} batches", batches.len())
    };
    let schema = table.schema();
    let names: Vec<&str> = schema.fields().iter().map(|f| f.name().as_str()).collect();
    assert_eq!(names, FRAME_COLUMNS);
    assert_eq!(table.num_rows(), rows.len() - 1);
    assert_eq!(table.num_rows(), times.len());
    for (c, column) in table.columns().iter().enumerate() {
        let any = column.as_any();
        for (i, row) in rows[1..].iter().enumerate() {
            let value = match (any.downcast_ref::<Int64Array>(), any.downcast_ref::<Float64Array>()) {
                (Some(ints), _) => ints.value(i).to_string(),
                (_, Some(reals)) => format!("{:?}", reals.value(i)),
                _ => panic!("column {}: {:?}", FRAME_COLUMNS[c], column.data_type()),
            };
            assert_eq!(value, row[c], "row {i}, column {}", FRAME_COLUMNS[c]);
        }
    }
}

#[test]
fn phase_boundary_scene_brackets_the_boundary() {
    let s = scene("phase_boundary.toml", &[("[output]\n", "[output]\nvtk = false\n")]);
    let out = run(&s, "cli_phase_boundary");
    let classifier = RegimeClassifier::stokesian(1e-8).unwrap();
    let shape = ShearShape::new(Shape::Prolate(2.0));
    for (record, (ca, expected)) in out
        .records
        .iter()
        .zip([(0.25, Regime::Tumbling), (0.3, Regime::Trembling)])
    {
        assert_eq!(record.fate, Fate::Suspended);
        let rest = record.spec.as_ref().unwrap().shape;
        let margin = record
            .samples
            .iter()
            .map(|st| material_line(&rest, &st.f, 0).norm() - material_line(&rest, &st.f, 1).norm())
            .fold(f64::INFINITY, f64::min);
        let regime = if margin > 0.0 {
            Regime::Tumbling
        } else {
            Regime::Trembling
        };
        assert_eq!(regime, expected, "Ca = {ca}: min (l_a − l_c) = {margin}");
        let library = classifier
            .classify_ca(&shape, ca, &stokesian_scaling(ca).unwrap())
            .unwrap();
        assert_eq!(library.regime, expected, "Ca = {ca}");
        assert!(library.margin.abs() > 0.01, "Ca = {ca}: margin {}", library.margin);
    }
}

/// The fibre of Fig. 11(b) for its first 200 time units (suspended, still far from the wall):
/// bitwise the library's Tian/Cui particle advanced by the driver with the pipe-wall contact.
#[test]
fn pipe_fibre_scene_is_the_library_tian_cui_particle() {
    let s = scene(
        "pipe_fibre.toml",
        &[
            ("t_end = 11528.5", "t_end = 200.0"),
            ("[output]\n", "[output]\nvtk = false\n"),
        ],
    );
    let out = run(&s, "cli_pipe");
    let record = &out.records[0];
    assert_eq!(record.fate, Fate::Suspended);

    let lib = PipeSetup::tian_cui(7.0, 0.25).unwrap();
    let integrator = lib.integrator(1e-7).unwrap();
    let plan = Plan::new(200.0, 1e-3).unwrap().with_outputs(&s.outputs).unwrap();
    let contact = ContactEvent::new(&lib.wall, &lib.particle, &lib.flow, ContactModel::Extent);
    let mut memory = <pseudorigid::integrator::Stokesian as TimeIntegrator>::Memory::default();
    let end = integrate(
        Problem::new(&integrator, &lib.particle, &lib.flow),
        lib.initial_state().unwrap(),
        &mut memory,
        &plan,
        &[&contact],
        Observers::none(),
    )
    .unwrap();
    assert_eq!(record.end.unwrap(), end.state);
    assert_eq!(record.stats.steps, end.stats.steps);
}

/// A case written to disk: the unit cube of warped hexahedra (patches `inlet` x = 0, `outlet`
/// x = 1, `walls`) with the velocity `u` at time 0.
fn foam_case(name: &str, u: impl Fn(&pseudorigid::tensor::Vec3) -> pseudorigid::tensor::Vec3) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    let raw = build::cube(build::Shape::Hex, 6);
    build::write_case(&dir, &raw, &build::sampled(&raw.mesh(), u), "0", build::Format::Ascii);
    dir
}

/// A rigid sphere of radius 0.05 released at x = (0.1, 0.5, 0.5) with the fluid's velocity,
/// on the OpenFOAM case `case` with its patches as the boundary, output every 0.5 to t = 2.
fn sphere_on_case_scene(case: &Path) -> String {
    format!(
        r#"[flow]
type = "openfoam"
case = "{}"
[fluid]
viscosity = 1.0
density = 1.0
[boundary]
type = "mesh"
[particles]
density = 1.0
[[particles.list]]
semi_axes = [0.05, 0.05, 0.05]
position = [0.1, 0.5, 0.5]
fluid_velocity = true
material = {{ law = "rigid" }}
[integrator]
type = "stokesian"
tol = 1e-8
dt = 1e-3
[end]
t_end = 2.0
[output]
every = 0.5
vtk = false
"#,
        case.display()
    )
}

/// A scene on an OpenFOAM case with its patches as the boundary: a sphere of radius 0.05
/// carried by the uniform flow u = e₁ from x₁ = 0.1 leaves through `outlet` when its front
/// reaches x₁ = 1, at t = 0.85. The cellwise-linear reconstruction of a uniform field is
/// uniform to round-off, so the particle moves exactly with the fluid; the event is located
/// to 1e-9 of the particle's diameter in gap, i.e. in time at unit speed.
#[test]
fn openfoam_scene_with_mesh_patches() {
    let case = foam_case("cli_foam_uniform", |_| pseudorigid::tensor::Vec3::x());
    let text = sphere_on_case_scene(&case);
    let s = parse(
        &Source {
            file: "foam.toml",
            text: &text,
        },
        Path::new("."),
    )
    .unwrap();
    let out = run(&s, "cli_foam_run");
    let record = &out.records[0];
    let Fate::Escaped { patch, time } = record.fate else {
        panic!("{:?}", record.fate);
    };
    assert_eq!(out.patches[patch], "outlet");
    assert!((time - 0.85).abs() < 1e-9, "t = {time}");
}

/// Point contact (`contact_radius = 0`) at an exit, on both reconstructions: a point tracer
/// in the solved 2-D channel leaves through `outlet`. The contact fires only after a step that
/// ends on or past the outlet's plane; the cellwise field refused every point beyond it, so
/// the steps shrank towards the plane until they underflowed and the tracer failed short of it
/// (as 197 of 200 did on OpenFOAM's pitzDaily, 5e-12 m before its outlet; issue 57 item 5). It
/// now answers just past a boundary face with the owner cell's fit, as the blend does.
#[test]
fn a_point_tracer_leaves_through_an_exit_on_either_reconstruction() {
    let text = tracer_on_case(&build::channel_2d())
        .replace("type = \"mesh\"", "type = \"mesh\"\ncontact_radius = 0.0")
        .replace("type = \"stokesian\"", "type = \"radau_iia\"\noverdamped = true")
        .replace("tol = 1e-8\ndt = 1e-4", "tol = 1e-6\ndt = 1e-6")
        // Off the cell faces y = 1 mm (the cellwise field is discontinuous across them, and a
        // tracer on one slides along it), and a bound that fails fast.
        .replace(
            "position = [1e-3, 1e-3, 0.25e-3]",
            "position = [1.3e-3, 0.8e-3, 0.25e-3]",
        )
        .replace("t_end = 1.0", "t_end = 1.0\nmax_steps = 100000");
    for blend in ["true", "false"] {
        let text = text.replace("[fluid]", &format!("blend = {blend}\n[fluid]"));
        let s = parse_named("channel.toml", &text).unwrap();
        let out = run(&s, &format!("cli_channel_point_exit_{blend}"));
        let Fate::Escaped { patch, .. } = out.records[0].fate else {
            panic!("blend = {blend}: {:?}", out.records[0].fate);
        };
        assert_eq!(out.patches[patch], "outlet");
    }
}

/// Settling in still fluid on a case whose U is zero everywhere: refused as a likely initial
/// condition unless the scene says `still = true`; with it, a rigid sphere (a = 0.05,
/// ρ_p = 2, ρ_f = 1, μ = 1, g = 1) released at rest at the centre of the cube falls onto its
/// floor when the closed form says: Stokes drag and reduced gravity give
/// z(t) = z₀ − v_t (t − τ(1 − e^{−t/τ})) with τ = 2ρ_p a²/(9μ) and v_t = τ g (1 − ρ_f/ρ_p), and
/// contact is z = a. The tolerance 10⁻⁶ of that time holds the event's location (10⁻⁹ of the
/// diameter in gap) and the integration at rtol 10⁻⁸ with a wide margin.
#[test]
fn still_fluid_is_read_when_the_scene_says_so() {
    let case = foam_case("cli_foam_still", |_| pseudorigid::tensor::Vec3::zeros());
    let scene = |still: &str| {
        format!(
            r#"[flow]
type = "openfoam"
case = "{}"
{still}
[fluid]
viscosity = 1.0
density = 1.0
gravity = [0.0, 0.0, -1.0]
[boundary]
type = "mesh"
[particles]
density = 2.0
[[particles.list]]
semi_axes = [0.05, 0.05, 0.05]
position = [0.5, 0.5, 0.5]
material = {{ law = "rigid" }}
[integrator]
type = "stokesian"
tol = 1e-8
dt = 1e-3
[end]
t_end = 2000.0
[output]
vtk = false
"#,
            case.display()
        )
    };
    let parsed = |text: &str| {
        parse(
            &Source {
                file: "still.toml",
                text,
            },
            Path::new("."),
        )
    };
    let refused = parsed(&scene("")).unwrap_err().to_string();
    assert!(refused.contains("still = true"), "{refused}");
    let s = parsed(&scene("still = true")).unwrap();
    let out = run(&s, "cli_foam_still_run");
    let Fate::Deposited { patch, time, .. } = out.records[0].fate else {
        panic!("{:?}", out.records[0].fate);
    };
    assert_eq!(out.patches[patch], "walls");
    let (a, tau) = (0.05, 2.0 * 2.0 * 0.05 * 0.05 / 9.0);
    let terminal = tau * 1.0 * (1.0 - 1.0 / 2.0);
    let fall = |t: f64| terminal * (t - tau * (1.0 - (-t / tau).exp()));
    // Bisection for fall(t) = 0.5 − a on [0, 10⁴] (fall is increasing).
    let (mut lo, mut hi) = (0.0, 1e4);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if fall(mid) < 0.5 - a { lo = mid } else { hi = mid }
    }
    assert!((time / hi - 1.0).abs() < 1e-6, "deposited at t = {time} against {hi}");
    // And a field that is not zero is refused as still.
    let moving = foam_case("cli_foam_not_still", |_| pseudorigid::tensor::Vec3::x());
    let text = scene("still = true").replace(&case.display().to_string(), &moving.display().to_string());
    let refused = parsed(&text).unwrap_err().to_string();
    assert!(refused.contains("not zero"), "{refused}");
}

/// Particles born overlapping a wall are moved off it, not deposited at birth: on the uniform
/// flow u = e₁ (walls moving with it, so the field is uniform to round-off), spheres of radius
/// 0.05 placed 0.02 into the wall y = 0, and into the corner of y = 0 and z = 0, are moved
/// to 0.05 (and 10⁻⁶ of the diameter) off each wall and carried out through `outlet` when
/// their front reaches x = 1: at t = 1 − 0.05 − 0.5 = 0.45, to the event's 10⁻⁹.
#[test]
fn particles_born_in_a_wall_are_moved_off_it() {
    let case = foam_case("cli_foam_born_in_wall", |_| pseudorigid::tensor::Vec3::x());
    let text = sphere_on_case_scene(&case).replace(
        "position = [0.1, 0.5, 0.5]",
        "position = [0.5, 0.03, 0.5]\nfluid_velocity = true\nmaterial = { law = \"rigid\" }\n\n\
         [[particles.list]]\nsemi_axes = [0.05, 0.05, 0.05]\nposition = [0.5, 0.03, 0.03]",
    );
    let s = parse(
        &Source {
            file: "born.toml",
            text: &text,
        },
        Path::new("."),
    )
    .unwrap();
    let out = run(&s, "cli_foam_born_in_wall_run");
    assert_eq!(out.records.len(), 2);
    for record in &out.records {
        let Fate::Escaped { patch, time } = record.fate else {
            panic!("particle {}: {:?}", record.index, record.fate);
        };
        assert_eq!(out.patches[patch], "outlet");
        assert!((time - 0.45).abs() < 1e-9, "particle {}: t = {time}", record.index);
    }
}

/// Every file under `dir` with its length and modification time.
fn listing(dir: &Path) -> Vec<(PathBuf, u64, std::time::SystemTime)> {
    let mut files = Vec::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let entry = entry.unwrap();
            let meta = entry.metadata().unwrap();
            if meta.is_dir() {
                todo.push(entry.path());
            } else {
                files.push((entry.path(), meta.len(), meta.modified().unwrap()));
            }
        }
    }
    files.sort();
    files
}

/// The command reads a case wherever `flow.case` points (here an absolute path outside the
/// scene's folder) and writes only under `--out`: the case and the scene's folder are
/// unchanged, file for file, after `validate` and `run`.
#[test]
fn run_writes_only_under_out() {
    let case = foam_case("cli_foam_readonly", |_| pseudorigid::tensor::Vec3::x());
    let scene_dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_readonly_scene");
    let _ = std::fs::remove_dir_all(&scene_dir);
    std::fs::create_dir_all(&scene_dir).unwrap();
    // ParaView files too: every writer the command has.
    let scene = sphere_on_case_scene(&case.canonicalize().unwrap()).replace("vtk = false", "vtk = true");
    std::fs::write(scene_dir.join("scene.toml"), scene).unwrap();
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_readonly_out");
    let _ = std::fs::remove_dir_all(&out);
    let (case_before, scene_before) = (listing(&case), listing(&scene_dir));
    for args in [vec!["validate"], vec!["run", "--quiet", "--out", out.to_str().unwrap()]] {
        let status = std::process::Command::new(env!("CARGO_BIN_EXE_pseudorigid"))
            .args(&args[..1])
            .arg(scene_dir.join("scene.toml"))
            .args(&args[1..])
            .current_dir(&scene_dir)
            .status()
            .unwrap();
        assert!(status.success(), "{args:?}");
    }
    assert!(out.join("records.parquet").is_file());
    assert_eq!(listing(&case), case_before);
    assert_eq!(listing(&scene_dir), scene_before);
}

/// The configuration hash of a scene on an OpenFOAM case covers the field as read, not only
/// the scene text: the same scene file (same case path and time) over a case whose velocity
/// was solved again differently gets another hash, so its checkpoints, shards and caches are
/// never taken for this run's; the same field read again gets the same hash; an analytic flow
/// with another rate does too (its text differs). Blended and cellwise fields differ.
#[test]
fn config_hash_covers_the_flow_field_and_boundary() {
    let text = |case: &Path, blend: bool| {
        format!(
            "[flow]\ntype = \"openfoam\"\ncase = \"{}\"\nblend = {blend}\n[fluid]\nviscosity = 1.0\ndensity = 1.0\n\
             [boundary]\ntype = \"mesh\"\n[particles]\ndensity = 1.0\n[[particles.list]]\n\
             semi_axes = [0.05, 0.05, 0.05]\nposition = [0.1, 0.5, 0.5]\nfluid_velocity = true\n\
             material = {{ law = \"rigid\" }}\n[integrator]\ntype = \"stokesian\"\ntol = 1e-8\ndt = 1e-3\n\
             [end]\nt_end = 0.1\n",
            case.display()
        )
    };
    let hash = |case: &Path, blend: bool| {
        let text = text(case, blend);
        let s = parse(
            &Source {
                file: "foam.toml",
                text: &text,
            },
            Path::new("."),
        )
        .unwrap();
        let config = s.config();
        assert!(config.fingerprint.starts_with(&text));
        run(&s, "cli_foam_hash").config_hash
    };
    use pseudorigid::tensor::Vec3;
    let case = foam_case("cli_foam_hash_case", |_| Vec3::x());
    let first = hash(&case, true);
    assert_eq!(hash(&case, true), first, "the same field read again");
    assert_ne!(hash(&case, false), first, "cellwise and blended");
    // Solved again: the same path, time and mesh, the velocity changed by 1e-300 in half the
    // cells (a change no summary statistic of the field would show).
    let again = foam_case("cli_foam_hash_case", |x| {
        Vec3::new(1.0, 0.0, if x[0] > 0.5 { 1e-300 } else { 0.0 })
    });
    assert_eq!(again, case);
    let second = hash(&case, true);
    assert_ne!(second, first, "another field under the same scene text");
    let shear = |rate: &str| {
        let s = scene(
            "shear_injection.toml",
            &[("count = 60", "count = 2"), ("rate = 1.0", rate)],
        );
        (s.config().fingerprint.clone(), run(&s, "cli_shear_hash").config_hash)
    };
    let (a, b) = (shear("rate = 1.0"), shear("rate = 2.0"));
    assert!(a.0.contains("\nflow: ") && a.0.contains("\nboundary: open"), "{}", a.0);
    assert_ne!(a.1, b.1);
}

/// `probe` on a linear field: the reconstruction is exact for linear fields, so u and ∇u come
/// back to round-off (1e-12 of |u| ~ 1); a point outside is flagged and NaN.
#[test]
fn probe_reads_a_case_back() {
    use pseudorigid::tensor::{Mat3, Vec3};
    let a = Mat3::new(0.2, 0.5, -0.1, 0.3, -0.4, 0.7, 0.6, -0.2, 0.2);
    let b = Vec3::new(1.0, -0.5, 0.25);
    let case = foam_case("cli_probe_case", move |x| b + a * x);
    let dir = case.parent().unwrap().join("cli_probe_files");
    std::fs::create_dir_all(&dir).unwrap();
    let points = dir.join("points.csv");
    std::fs::write(&points, "x,y,z\n0.3,0.4,0.5\n0.77,0.21,0.9\n1.5,0.5,0.5\n").unwrap();
    let out = dir.join("probe.csv");
    // The cellwise fits are exact for a linear field; the blended field is too away from walls,
    // but near a wall it enforces no-slip, which this field violates.
    let line = pseudorigid::cli::probe::probe(&case, "latest", &points, &out, true).unwrap();
    assert!(line.contains("2 of 3 points inside"), "{line}");
    let text = std::fs::read_to_string(&out).unwrap();
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    for row in &rows[..2] {
        let x = Vec3::new(row[0], row[1], row[2]);
        assert_eq!(row[3], 1.0);
        let u = b + a * x;
        for i in 0..3 {
            assert!(
                (row[4 + i] - u[i]).abs() < 1e-12,
                "u{i} at {x:?}: {} vs {}",
                row[4 + i],
                u[i]
            );
            for j in 0..3 {
                assert!((row[7 + 3 * i + j] - a[(i, j)]).abs() < 1e-12, "l{i}{j} at {x:?}");
            }
        }
    }
    assert_eq!(rows[2][3], 0.0);
    assert!(rows[2][4..].iter().all(|v| v.is_nan()));
}

/// The injection scene: particle k starts on the disc (radius 3 in the plane x₃ = 0) and is
/// the same particle whatever the size of the run, since it draws from stream k of the seed.
#[test]
fn injection_scene_draws_particle_k_from_its_own_stream() {
    let reduced = |count: &str| {
        scene(
            "shear_injection.toml",
            &[
                ("count = 60", count),
                ("t_end = 8.0", "t_end = 0.5"),
                ("[output]\n", "[output]\nvtk = false\n"),
            ],
        )
    };
    let six = run(&reduced("count = 6"), "cli_inject_6");
    let three = run(&reduced("count = 3"), "cli_inject_3");
    assert_eq!(six.records.len(), 6);
    assert_eq!(three.records[..], six.records[..3]);
    for r in &six.records {
        let spec = r.spec.as_ref().unwrap();
        assert!(
            spec.position.norm() <= 3.0 && spec.position[2] == 0.0,
            "{:?}",
            spec.position
        );
        assert_eq!(r.fate, Fate::Suspended);
    }
    // Different particles: distinct start points and orientations.
    assert_ne!(six.records[0].spec, six.records[1].spec);
}

/// The bifurcation scene on the shipped airway field (blended), 20 soft spheres at Stk 0.1:
/// every particle ends on a named patch of the mesh, none fails, and an escape is on an outlet
/// at the plane x₁ = L = 0.04 m (the particle's extent touches it: barycentre within a particle
/// radius, 4 µm, plus the located-event tolerance).
#[test]
fn bifurcation_scene_deposits_or_escapes_through_the_outlets() {
    use pseudorigid::contact::Boundary;
    let s = scene("bifurcation.toml", &[]);
    let out = run(&s, "cli_bifurcation");
    assert_eq!(out.records.len(), 20);
    for r in &out.records {
        let name = |patch: usize| s.boundary.patch_name(patch).to_string();
        match &r.fate {
            Fate::Escaped { patch, .. } => {
                assert!(
                    name(*patch).starts_with("outlet"),
                    "particle {} escaped through {}",
                    r.index,
                    name(*patch)
                );
                let x = r.end.unwrap().x;
                assert!(
                    (x[0] - 0.04).abs() < 1e-5,
                    "particle {} escaped at x1 = {}",
                    r.index,
                    x[0]
                );
            }
            Fate::Deposited { patch, .. } => assert_eq!(name(*patch), "wall", "particle {}", r.index),
            other => panic!("particle {}: {other:?}", r.index),
        }
    }
}

/// The OpenFOAM keys a user's own case needs, each against what it must do: `flow.time` as a
/// list or `"latest"`, an all-zero field (an unsolved `0/U`) refused at `flow.time`, an
/// injection disc that leaves the mesh refused at `particles.inject.region`, point contact
/// (`contact_radius = 0`) accepted, and `flow.blend` on by default.
#[test]
fn openfoam_scene_keys_for_a_users_case() {
    use pseudorigid::population::{Injector, particle_rng};
    use pseudorigid::scene::models::SceneFlow;
    use pseudorigid::tensor::Vec3;
    let moving = foam_case("cli_foam_keys", |x| Vec3::new(1.0 + x[1], 0.0, 0.0));
    // A second time directory with a doubled field, and an all-zero case.
    let raw = build::cube(build::Shape::Hex, 6);
    build::write_case(
        &moving,
        &raw,
        &build::sampled(&raw.mesh(), |x| Vec3::new(2.0 + 2.0 * x[1], 0.0, 0.0)),
        "1",
        build::Format::Ascii,
    );
    let still = foam_case("cli_foam_zero", |_| Vec3::zeros());
    let scene = |case: &Path, time: &str, region: &str, extra: &str| -> Result<Scene, SceneError> {
        let text = format!(
            r#"[flow]
type = "openfoam"
case = "{}"
{time}
[fluid]
viscosity = 1.0
density = 1.0
[boundary]
type = "mesh"
{extra}
[particles]
density = 1.0
[particles.inject]
count = 4000
semi_axes = [0.01, 0.01, 0.01]
fluid_velocity = true
region = {region}
material = {{ law = "rigid" }}
[integrator]
type = "stokesian"
tol = 1e-6
dt = 1e-3
[end]
t_end = 0.1
"#,
            case.display()
        );
        parse(
            &Source {
                file: "keys.toml",
                text: &text,
            },
            Path::new("."),
        )
    };
    let disc = r#"{ type = "disc", centre = [0.2, 0.5, 0.5], normal = [1.0, 0.0, 0.0], radius = 0.3 }"#;
    let key_of = |r: Result<Scene, SceneError>| match r {
        Err(SceneError::Invalid { key, message, .. }) => (key, message),
        other => panic!("expected a scene error, got {:?}", other.map(|s| s.count())),
    };
    for time in ["", "time = \"latest\"", "time = 1"] {
        let s = scene(&moving, time, disc, "contact_radius = 0.0").unwrap_or_else(|e| panic!("{time}: {e}"));
        let SceneFlow::Blended(flow) = &s.flow else {
            panic!("{time}: blend is not the default");
        };
        assert_eq!(flow.cellwise().times(), vec![1.0], "{time}");
    }
    // A list of times is a transient field (`cli::transient`), blended by default.
    let s = scene(&moving, "time = [0, 1]", disc, "contact_radius = 0.0").unwrap();
    let SceneFlow::Transient(flow) = &s.flow else {
        panic!("a list of times is not a transient field");
    };
    flow.with_field(|field| {
        assert!(matches!(field, pseudorigid::scene::models::TransientField::Blended(_)));
        assert_eq!(field.levels(), [0.0, 1.0]);
    });
    let (key, message) = key_of(scene(&moving, "time = \"first\"", disc, ""));
    assert!(key == "flow.time" && message.contains("latest"), "{key}: {message}");
    let (key, message) = key_of(scene(&still, "", disc, ""));
    assert!(
        key == "flow.case" && message.contains("zero in every cell"),
        "{key}: {message}"
    );
    let (key, message) = key_of(scene(&still, "time = 0", disc, ""));
    assert!(
        key == "flow.time" && message.contains("zero in every cell"),
        "{key}: {message}"
    );
    let wide = r#"{ type = "disc", centre = [0.2, 0.5, 0.5], normal = [1.0, 0.0, 0.0], radius = 0.6 }"#;
    let (key, message) = key_of(scene(&moving, "", wide, ""));
    assert!(
        key == "particles.inject.region" && message.contains("leaves the mesh"),
        "{key}: {message}"
    );
    // The same disc weighted by pipe flux is accepted (its weight vanishes at the rim), and
    // a particle drawn outside the unit cube fails alone with the outside-domain error, never
    // starting outside. A point at radius ρ of this disc leaves the cube where ρ > 0.5 in some
    // direction: s = ρ²/R² > 0.69, drawn with probability (1 − 0.69)² ≈ 0.09 at the worst angle,
    // so some of 4 000 fail and most start; every start lies in the cube.
    let flux_wide =
        r#"{ type = "disc", centre = [0.2, 0.5, 0.5], normal = [1.0, 0.0, 0.0], radius = 0.6, weight = "poiseuille" }"#;
    let s = scene(&moving, "", flux_wide, "").unwrap();
    let injector = s.injector();
    let (mut started, mut outside) = (0, 0);
    for k in 0..4000 {
        match injector.draw(k, &mut particle_rng(1, k)) {
            Ok(spec) => {
                assert!(
                    spec.position.iter().all(|c| (0.0..=1.0).contains(c)),
                    "{:?}",
                    spec.position
                );
                started += 1;
            }
            Err(pseudorigid::error::StepError::Flow(pseudorigid::error::FlowError::OutsideDomain { x })) => {
                assert!(
                    x.iter().any(|c| !(0.0..=1.0).contains(c)),
                    "{x:?} refused inside the cube"
                );
                outside += 1;
            }
            Err(e) => panic!("particle {k}: {e}"),
        }
    }
    assert!(started > 3000 && outside > 0, "{started} started, {outside} outside");
    for region in [
        r#"{ type = "point", at = [0.5, 0.5, 0.5], weight = "poiseuille" }"#,
        r#"{ type = "patch", name = "inlet", weight = "area" }"#,
    ] {
        let (key, message) = key_of(scene(&moving, "", region, ""));
        assert!(
            key == "particles.inject.region.weight" && message.contains("does not take"),
            "{key}: {message}"
        );
    }
    let outside = r#"{ type = "point", at = [1.5, 0.5, 0.5] }"#;
    let (key, _) = key_of(scene(&moving, "", outside, ""));
    assert_eq!(key, "particles.inject.region");
    let (key, _) = key_of(scene(&moving, "", disc, "contact_radius = -1.0"));
    assert_eq!(key, "boundary.contact_radius");
    // Injection through the inlet x₁ = 0, weighted by the inflow u₁ = 1 + x₂: the mean x₂ of
    // the particles is ∫y(1 + y)dy / ∫(1 + y)dy = 5/9 over the unit face (1/2 unweighted); the
    // standard deviation of x₂ is below 0.29, so over 4 000 particles three standard errors are
    // 0.014, and the unweighted 1/2 lies four times that away. Every particle starts 1.01 of its
    // radius inside the inlet.
    let inlet = r#"{ type = "patch", name = "inlet" }"#;
    let s = scene(&moving, "", inlet, "").unwrap();
    let injector = s.injector();
    let n = 4000u64;
    let mut mean = 0.0;
    for k in 0..n {
        let spec = injector.draw(k, &mut particle_rng(1, k)).unwrap();
        assert!((spec.position[0] - 0.0101).abs() < 1e-12, "{:?}", spec.position);
        mean += spec.position[1] / n as f64;
    }
    assert!((mean - 5.0 / 9.0).abs() < 0.014, "mean x₂ {mean}");
    // With barycentre contact at 0.05 (five radii), the particles start beyond it: 1.01 of the
    // contact radius inside the inlet, not touching it at t = 0.
    let s = scene(&moving, "", inlet, "contact_radius = 0.05").unwrap();
    let spec = s.injector().draw(0, &mut particle_rng(1, 0)).unwrap();
    assert!((spec.position[0] - 0.0505).abs() < 1e-12, "{:?}", spec.position);
    let (key, message) = key_of(scene(&moving, "", r#"{ type = "patch", name = "outflow" }"#, ""));
    assert!(
        key == "particles.inject.region.name" && message.contains("inlet"),
        "{key}: {message}"
    );
    let (key, message) = key_of(scene(&moving, "", r#"{ type = "patch", name = "outlet" }"#, ""));
    assert!(
        key == "particles.inject.region.name"
            && message.contains("no inflow through patch `outlet` (type `patch`")
            // The latest time, 1: u₁ = 2 + 2x₂ through the unit face.
            && message.contains("net flux out of the domain 3.000e0")
            && message.contains("sum(u.S), the cell fits at its faces"),
        "{key}: {message}"
    );
    // Issue 39, item 3: a wall given as the injection patch. With a flow u = (1 + x₂, 0.5, 0)
    // through the walls the fits give the face x₂ = 0 an inflow, and the particles started on
    // the wall; now the patch is refused with its type and flux (net 0: 0.5 in at x₂ = 0,
    // 0.5 out at x₂ = 1).
    let leaky = foam_case("cli_foam_leaky_wall", |x| Vec3::new(1.0 + x[1], 0.5, 0.0));
    let (key, message) = key_of(scene(&leaky, "", r#"{ type = "patch", name = "walls" }"#, ""));
    assert!(
        key == "particles.inject.region.name"
            && message.contains("patch `walls` (type `wall`")
            && message.contains("inflow 5.000e-1")
            && message.contains("no fluid enters through a wall")
            && message.contains("[\"inlet\", \"outlet\"]"),
        "{key}: {message}"
    );
    // Issue 39, item 7: a transient field whose flow starts from rest at its first time level
    // was refused for the "total weight of the triangles"; now in the user's terms.
    let resting = foam_case("cli_foam_from_rest", |_| Vec3::zeros());
    build::write_case(
        &resting,
        &raw,
        &build::sampled(&raw.mesh(), |x| Vec3::new(1.0 + x[1], 0.0, 0.0)),
        "1",
        build::Format::Ascii,
    );
    // Issue 39, item 3: where the time directory has the solver's face flux `phi`, the inlet is
    // weighted by it, not by the fits. A `phi` that lets the fluid in through the faces of
    // x₂ < 1/2 only (−1 each), while the fits say u₁ = 2 + 2x₂ over the whole face: every
    // particle starts below x₂ = 1/2 (with the fits' weights 7/12 of them start above it).
    let mesh = raw.mesh();
    let n_internal = mesh.n_internal_faces();
    let mut patches = String::new();
    for patch in mesh.patches() {
        let faces = patch.start..patch.start + patch.size;
        let values: Vec<String> = faces
            .map(|f| {
                let inflow = patch.name == "inlet" && mesh.face_centres()[f][1] < 0.5;
                (if inflow { "-1" } else { "0" }).to_string()
            })
            .collect();
        patches += &format!(
            "    {}\n    {{\n        type calculated;\n        value nonuniform List<scalar> {} ({});\n    }}\n",
            patch.name,
            values.len(),
            values.join(" ")
        );
    }
    let phi = format!(
        "FoamFile\n{{\n    version 2.0;\n    format ascii;\n    class surfaceScalarField;\n    object phi;\n}}\n\
         dimensions [0 3 -1 0 0 0 0];\ninternalField nonuniform List<scalar> {n_internal} ({});\n\
         boundaryField\n{{\n{patches}}}\n",
        vec!["0"; n_internal].join(" ")
    );
    std::fs::write(moving.join("1/phi"), &phi).unwrap();
    let s = scene(&moving, "", inlet, "").unwrap();
    let injector = s.injector();
    for k in 0..400u64 {
        let spec = injector.draw(k, &mut particle_rng(1, k)).unwrap();
        assert!(spec.position[1] < 0.5, "particle {k} at {:?}", spec.position);
    }
    let (key, message) = key_of(scene(&moving, "", r#"{ type = "patch", name = "outlet" }"#, ""));
    assert!(
        key == "particles.inject.region.name" && message.contains("the case's face flux `phi`"),
        "{key}: {message}"
    );
    std::fs::write(
        moving.join("1/phi"),
        phi.replace("surfaceScalarField", "volScalarField"),
    )
    .unwrap();
    let (key, message) = key_of(scene(&moving, "", inlet, ""));
    assert!(
        key == "flow.case" && message.contains("expected `surfaceScalarField`"),
        "{key}: {message}"
    );
    std::fs::remove_file(moving.join("1/phi")).unwrap();
    let (key, message) = key_of(scene(&resting, "time = [0, 1]", inlet, ""));
    assert!(
        key == "particles.inject.region.name"
            && message.contains("no inflow through patch `inlet` (type `patch`")
            && message.contains("at t = 0")
            && message.contains("start `flow.time` where the fluid enters")
            && !message.contains("total weight"),
        "{key}: {message}"
    );
}

/// Two injection groups with their own density settle in a quiescent fluid as Stokes' law
/// says for each: a rigid sphere of diameter d and density ρ_s under reduced gravity with
/// drag 3πμd (Brenner's resistance of a sphere) falls by
/// z(t) = v_t (t − τ(1 − e^{−t/τ})), v_t = (ρ_s − ρ_f) g d²/(18μ), τ = ρ_s d²/(18μ),
/// the closed form of m v̇ = m(1 − ρ_f/ρ_s) g − 3πμd v from rest. Group 0 (particles 0..3)
/// has ρ_s = 2000 from `particles.density`, group 1 (3..5) its own ρ_s = 3000: their terminal
/// velocities differ by a factor 2, so a particle built with the other group's density misses
/// by 50 % or more. The 10⁻⁴ tolerance is the Radau integrator's error at tol 10⁻⁸ over
/// t/τ ≈ 900 relaxation times with room to spare, far below that factor. A single
/// `[particles.inject]` table and a one-element `[[particles.inject]]` array are the same
/// scene, and a group without any density is refused at its own key.
#[test]
fn injection_groups_carry_their_own_density() {
    let (mu, rho_f, g, d) = (1e-3, 1000.0, 9.81, 10e-6);
    let text = |groups: &str, shared: &str| {
        format!(
            r#"[flow]
type = "quiescent"
[fluid]
viscosity = {mu}
density = {rho_f}
gravity = [0.0, 0.0, -{g}]
[particles]
{shared}
{groups}
[integrator]
type = "stokesian"
tol = 1e-8
dt = 1e-7
[end]
t_end = 1e-2
[output]
vtk = false
"#
        )
    };
    let group = |header: &str, count: u32, density: &str, x: f64| {
        format!(
            "{header}\ncount = {count}\n{density}\nsemi_axes = [{r}, {r}, {r}]\nregion = {{ type = \"point\", at = [{x}, 0.0, 0.0] }}\nmaterial = {{ law = \"rigid\" }}\n",
            r = d / 2.0
        )
    };
    let parse_text = |t: &str| parse_named("groups.toml", t);
    let two = format!(
        "{}{}",
        group("[[particles.inject]]", 3, "", 0.0),
        group("[[particles.inject]]", 2, "density = 3000.0", 1.0)
    );
    let s = parse_text(&text(&two, "density = 2000.0")).unwrap();
    assert_eq!(s.count(), 5);
    let out = run(&s, "cli_groups");
    let t_end = 1e-2;
    for r in &out.records {
        let spec = r.spec.as_ref().unwrap();
        let (rho_s, x0) = if r.index < 3 { (2000.0, 0.0) } else { (3000.0, 1.0) };
        assert_eq!((spec.density, spec.position[0]), (rho_s, x0), "particle {}", r.index);
        let v_t = (rho_s - rho_f) * g * d * d / (18.0 * mu);
        let tau = rho_s * d * d / (18.0 * mu);
        let fall = v_t * (t_end - tau * (1.0 - (-t_end / tau).exp()));
        let end = r.end.as_ref().unwrap();
        let z = -end.x[2];
        assert!(
            (z - fall).abs() <= 1e-4 * fall,
            "particle {} (ρ_s {rho_s}): fell {z:e}, Stokes {fall:e}",
            r.index
        );
    }
    // One group written either way is the same scene.
    let one_table = parse_text(&text(&group("[particles.inject]", 3, "", 0.0), "density = 2000.0")).unwrap();
    let one_array = parse_text(&text(&group("[[particles.inject]]", 3, "", 0.0), "density = 2000.0")).unwrap();
    assert_eq!(one_table.particles, one_array.particles);
    // No density anywhere: refused at the group's own key.
    match parse_text(&text(&two, "")) {
        Err(SceneError::Invalid { key, .. }) => assert_eq!(key, "particles.inject[0].density"),
        other => panic!("expected a scene error, got {:?}", other.map(|s| s.count())),
    }
}

/// Force terms selected in a scene file run as in the library: a 100 µm sphere at
/// ρ_p/ρ_f = 2 in water with `added_mass` and `undisturbed_flow` falls
/// z(t) = v_t(t − τ(1 − e^{−t/τ})) with τ = (ρ_p + ½ρ_f)d²/(18μ) (Maxey & Riley without the
/// history force), within 10⁻⁴ of the fall (the tolerance 10⁻⁸ on v ≈ 5·10⁻³ m/s over
/// t = 10⁻² s gives ≤ 10⁻⁸ m against a fall of 4·10⁻⁵ m); with the paper's τ = ρ_p d²/(18μ) the
/// fall differs by 4 %. A term with parameters is a table; an unknown name is refused at
/// `particles.forces[i]`, a parameter the term does not take, one of the wrong kind or a missing
/// one at `particles.forces[i].<key>`, as the other registries' are.
#[test]
fn force_terms_from_a_scene_file() {
    let (mu, rho_f, rho_p, g, d) = (1e-3, 1000.0, 2000.0, 9.81, 1e-4);
    let text = |forces: &str| {
        format!(
            r#"[flow]
type = "quiescent"
[fluid]
viscosity = {mu}
density = {rho_f}
gravity = [0.0, 0.0, -{g}]
[particles]
density = {rho_p}
forces = {forces}
[[particles.list]]
semi_axes = [{r}, {r}, {r}]
position = [0.0, 0.0, 0.0]
material = {{ law = "rigid" }}
[integrator]
type = "stokesian"
tol = 1e-8
dt = 1e-7
[end]
t_end = 1e-2
[output]
vtk = false
"#,
            r = d / 2.0
        )
    };
    let parse_text = |t: &str| parse_named("forces.toml", t);
    let s = parse_text(&text(r#"["added_mass", "undisturbed_flow"]"#)).unwrap();
    let out = run(&s, "cli_forces");
    let t_end = 1e-2;
    let v_t = (rho_p - rho_f) * g * d * d / (18.0 * mu);
    let fall = |tau: f64| v_t * (t_end - tau * (1.0 - (-t_end / tau).exp()));
    let with = fall((rho_p + 0.5 * rho_f) * d * d / (18.0 * mu));
    let paper = fall(rho_p * d * d / (18.0 * mu));
    let z = -out.records[0].end.as_ref().unwrap().x[2];
    assert!(
        (z - with).abs() <= 1e-4 * with,
        "fell {z:e}, Maxey–Riley {with:e}, paper {paper:e}"
    );
    assert!((paper - with).abs() > 0.03 * with);
    let slip = parse_text(&text(r#"[{ term = "cunningham", mean_free_path = 6.65e-8 }]"#));
    assert!(slip.is_ok(), "{:?}", slip.err());
    for (forces, key) in [
        (r#"["added_mass", "basset"]"#, "particles.forces[1]"),
        (
            r#"[{ term = "cunningham", mean_free_pth = 6.65e-8 }]"#,
            "particles.forces[0].mean_free_pth",
        ),
        (
            r#"[{ term = "cunningham", mean_free_path = "66 nm" }]"#,
            "particles.forces[0].mean_free_path",
        ),
        (r#"[{ term = "cunningham" }]"#, "particles.forces[0].mean_free_path"),
    ] {
        match parse_text(&text(forces)) {
            Err(SceneError::Invalid { key: k, .. }) => assert_eq!(k, key),
            other => panic!("{forces}: expected a scene error, got {:?}", other.map(|s| s.count())),
        }
    }
}

/// Issue 38, items 2, 5 and 6, through a scene file: a fluid of density 0 with the
/// finite-Re terms runs (every particle failed with a non-finite right-hand side at the step
/// start) and stays suspended in its quiescent fluid; two finite-Re drag corrections are
/// refused at `particles.forces` naming both, a mean free path of 10³⁰⁸ m (which set the drag
/// to 0) at the particle naming `mean_free_path`, a viscosity of 10³⁰⁸ at `fluid.viscosity`.
#[test]
fn scene_edges_of_the_force_terms_and_fluid() {
    let text = |mu: &str, rho_f: &str, forces: &str| {
        format!(
            r#"[flow]
type = "shear"
rate = 100.0
[fluid]
viscosity = {mu}
density = {rho_f}
gravity = [0.0, -9.81, 0.0]
[particles]
density = 1000.0
forces = {forces}
[[particles.list]]
semi_axes = [5e-6, 5e-6, 5e-6]
position = [0.0, 1e-4, 0.0]
fluid_velocity = true
material = {{ law = "rigid" }}
[integrator]
type = "stokesian"
tol = 1e-8
dt = 1e-6
[end]
t_end = 1e-3
[output]
vtk = false
"#
        )
    };
    let s = parse_named(
        "rho0.toml",
        &text("1.8e-5", "0.0", r#"["holzer_sommerfeld", "saffman_mei"]"#),
    )
    .unwrap();
    let out = run(&s, "cli_rho0");
    assert!(
        matches!(out.records[0].fate, Fate::Suspended),
        "{:?}",
        out.records[0].fate
    );
    for (scene, key, says) in [
        (
            text("1.8e-5", "1.2", r#"["schiller_naumann", "holzer_sommerfeld"]"#),
            "particles.forces",
            vec!["schiller_naumann", "holzer_sommerfeld"],
        ),
        (
            text("1.8e-5", "1.2", r#"[{ term = "cunningham", mean_free_path = 1e308 }]"#),
            "particles.list[0].semi_axes",
            vec!["cunningham.mean_free_path", "inf"],
        ),
        (text("1e308", "1.2", "[]"), "fluid.viscosity", vec!["mu_f"]),
    ] {
        match parse_named("edges.toml", &scene) {
            Err(SceneError::Invalid { key: k, message, .. }) => {
                assert!(k.starts_with(key), "{k}: {message}");
                for word in says {
                    assert!(message.contains(word), "{k}: `{message}` lacks `{word}`");
                }
            }
            other => panic!("{key}: expected a scene error, got {:?}", other.map(|s| s.count())),
        }
    }
}

/// The scene's numbers decide which force terms it should carry: a near-neutrally buoyant
/// sphere in water (ρ_p/ρ_f = 1.0005, the cavity's) is warned about the undisturbed-flow force
/// (ρ_f/ρ_p ≈ 100 %) and added mass (½ρ_f/ρ_p ≈ 50 %), and not once it carries them; a 1 µm
/// droplet in air (λ = μ/(0.499 ρ c̄) = 65 nm) about gas slip (C_c − 1 ≈ 17 %), and about
/// nothing else (ρ_f/ρ_p = 1.2·10⁻³ is below the 1 % threshold); a scene in nondimensional
/// units about nothing.
#[test]
fn scenes_are_warned_about_the_force_terms_their_numbers_need() {
    let text = |mu: f64, rho_f: f64, rho_p: f64, d: f64, forces: &str| {
        format!(
            "[flow]\ntype = \"quiescent\"\n[fluid]\nviscosity = {mu}\ndensity = {rho_f}\n[particles]\ndensity = {rho_p}\n{forces}\n\
             [[particles.list]]\nsemi_axes = [{r}, {r}, {r}]\nposition = [0.0, 0.0, 0.0]\nmaterial = {{ law = \"rigid\" }}\n\
             [integrator]\ntype = \"stokesian\"\ntol = 1e-6\ndt = 1e-7\n[end]\nt_end = 1e-3\n",
            r = d / 2.0
        )
    };
    let advice = |t: String| parse_named("advice.toml", &t).unwrap().force_advice();
    let cavity = advice(text(1e-3, 1000.0, 1000.5, 3e-3, ""));
    assert_eq!(cavity.len(), 2, "{cavity:?}");
    assert!(
        cavity[0].contains("`undisturbed_flow`") && cavity[1].contains("`added_mass`"),
        "{cavity:?}"
    );
    assert!(cavity[1].contains("49.98 %"), "{cavity:?}");
    let with_terms = advice(text(
        1e-3,
        1000.0,
        1000.5,
        3e-3,
        r#"forces = ["undisturbed_flow", "added_mass"]"#,
    ));
    assert!(with_terms.is_empty(), "{with_terms:?}");
    let aerosol = advice(text(1.81e-5, 1.2, 1000.0, 1e-6, ""));
    assert_eq!(aerosol.len(), 1, "{aerosol:?}");
    assert!(aerosol[0].contains("`cunningham`"), "{aerosol:?}");
    // A scene in the shear units (μ_f = 1, ρ_f = 0.1, d = 1) is not read as an SI gas: before
    // the viscosity bound it was warned about a 11 % gas slip.
    let shear_units = advice(text(1.0, 0.1, 100.0, 1.0, ""));
    assert!(shear_units.is_empty(), "{shear_units:?}");
    // The same liquid scene with an overdamped barycentre has dropped inertia, the fluid's
    // with the particle's: no fluid-inertia advice (it warned of 100 % and 50 % before).
    let overdamped = advice(text(1e-3, 1000.0, 1000.5, 3e-3, "").replace("dt = 1e-7", "dt = 1e-7\noverdamped = true"));
    assert!(overdamped.is_empty(), "{overdamped:?}");
}

/// `integrator.overdamped = true` with a fluid-inertia force term is refused where the scene
/// combines them, at `integrator.overdamped` with the term's own key (issue 38, item 1; it was
/// accepted, and its advice silenced); overdamped alone, and an inertial barycentre with the
/// terms, are still scenes.
#[test]
fn overdamped_scenes_refuse_fluid_inertia_terms() {
    let text = |forces: &str, overdamped: bool| {
        format!(
            "[flow]\ntype = \"quiescent\"\n[fluid]\nviscosity = 1e-3\ndensity = 1000.0\n[particles]\ndensity = 1000.5\n{forces}\n\
             [[particles.list]]\nsemi_axes = [5e-5, 5e-5, 5e-5]\nposition = [0.0, 0.0, 0.0]\nmaterial = {{ law = \"rigid\" }}\n\
             [integrator]\ntype = \"radau_iia\"\ntol = 1e-6\ndt = 1e-7\noverdamped = {overdamped}\n[end]\nt_end = 1e-3\n"
        )
    };
    for (forces, key, term) in [
        (
            r#"forces = ["added_mass"]"#,
            "integrator.overdamped, particles.forces[0]",
            "added_mass",
        ),
        (
            r#"forces = ["schiller_naumann", "undisturbed_flow"]"#,
            "integrator.overdamped, particles.forces[1]",
            "undisturbed_flow",
        ),
    ] {
        match parse_named("overdamped.toml", &text(forces, true)) {
            Err(SceneError::Invalid { key: k, message, .. }) => {
                assert_eq!(k, key, "{message}");
                assert!(
                    message.contains(&format!("`{term}`")) && message.contains("particle's inertia"),
                    "{message}"
                );
            }
            other => panic!("{forces}: expected a scene error, got {:?}", other.map(|s| s.count())),
        }
    }
    parse_named("overdamped.toml", &text("", true)).unwrap();
    parse_named(
        "overdamped.toml",
        &text(r#"forces = ["added_mass", "undisturbed_flow"]"#, false),
    )
    .unwrap();
}

/// An overdamped barycentre for particles the scene's numbers call inertial is warned about
/// (issue 39, item 3): in a shear of rate 1 s⁻¹, a 3 mm sphere in water has
/// St = τγ̇ = ρ_p d²/(18μ) · γ̇ = 0.5003 > 0.06, and the warning names the key, St and the
/// threshold; a 0.1 mm one (St = 5.6·10⁻⁴), the same sphere with an inertial barycentre, and
/// a quiescent fluid (no time scale: St = ∞) are not warned about. Before, nothing was said.
#[test]
fn overdamped_inertial_particles_are_warned_about() {
    let text = |flow: &str, d: f64, overdamped: bool| {
        format!(
            "[flow]\n{flow}\n[fluid]\nviscosity = 1e-3\ndensity = 1000.0\n[particles]\ndensity = 1000.5\n\
             [[particles.list]]\nsemi_axes = [{r}, {r}, {r}]\nposition = [0.0, 0.0, 0.0]\nmaterial = {{ law = \"rigid\" }}\n\
             [integrator]\ntype = \"radau_iia\"\ntol = 1e-6\ndt = 1e-7\noverdamped = {overdamped}\n[end]\nt_end = 1e-3\n",
            r = d / 2.0
        )
    };
    let shear = "type = \"shear\"\nrate = 1.0";
    let advice = |t: String| parse_named("st.toml", &t).unwrap().integrator_advice();
    let warned = advice(text(shear, 3e-3, true));
    assert_eq!(warned.len(), 1, "{warned:?}");
    assert!(
        warned[0].starts_with("particles.list[0]: `integrator.overdamped`")
            && warned[0].contains("St = 5.00")
            && warned[0].contains("> 0.06"),
        "{warned:?}"
    );
    for quiet in [
        text(shear, 1e-4, true),
        text(shear, 3e-3, false),
        text("type = \"quiescent\"", 3e-3, true),
    ] {
        let said = advice(quiet);
        assert!(said.is_empty(), "{said:?}");
    }
}

/// The run log's notes and warnings come once per set of like particles, with their count
/// (issue 39, item 3): 300 listed spheres of the cavity's liquid numbers under `type = "auto"`
/// gave 300 `auto` notes and 600 force warnings; now one note and one warning per force term,
/// naming the first entry and the 299 others.
#[test]
fn like_listed_particles_share_their_notes_and_warnings() {
    let entry = "[[particles.list]]\nsemi_axes = [1.5e-3, 1.5e-3, 1.5e-3]\nposition = [0.0, 0.0, 0.0]\nmaterial = { law = \"rigid\" }\n";
    let text = format!(
        "[flow]\ntype = \"shear\"\nrate = 1.0\n[fluid]\nviscosity = 1e-3\ndensity = 1000.0\n[particles]\ndensity = 1000.5\n{}\
         [integrator]\ntype = \"auto\"\ntol = 1e-6\ndt = 1e-7\n[end]\nt_end = 1e-3\n",
        entry.repeat(300)
    );
    let s = parse_named("many.toml", &text).unwrap();
    let log = s.integrator_log();
    assert_eq!(log.len(), 1, "{} lines, the first {:?}", log.len(), log.first());
    assert!(
        log[0].starts_with("particles.list[0] and 299 other entries: integrator auto: rigid inertialess shape"),
        "{log:?}"
    );
    let advice = s.force_advice();
    assert_eq!(
        advice.len(),
        2,
        "{} lines, the first {:?}",
        advice.len(),
        advice.first()
    );
    assert!(
        advice[0].starts_with("particles.list[0] and 299 other entries: the scene leaves out `undisturbed_flow`"),
        "{advice:?}"
    );
}

/// A law written in the scene file runs like the built-in law it writes: `yeoh_oblate.toml`
/// with c20 = 0 is Neo-Hooke with μ_s = 2 c10 = 2.5 and λ_s = 2500, the material of
/// `oblate_shear.toml`; over 2 time units of shear the two give the same F to 10⁻⁷ (the
/// integrator's tolerance is 10⁻⁸ per step; the two energies differ by round-off, which the
/// step-size controller may answer with slightly different steps). With c20 = 0.5 the Yeoh
/// solid is stiffer in stretch: its largest semi-axis grows less than Neo-Hooke's. A symbol the
/// energy does not know is refused at the material's key.
#[test]
fn a_law_written_in_the_scene_runs_like_the_built_in_law() {
    let short = [("t_end = 30.0", "t_end = 2.0"), ("every = 0.25", "every = 2.0")];
    let end = |s: &Scene, name: &str| {
        let out = run(s, name);
        let state = out.records[0].end.unwrap();
        (state.f, out.records[0].end_frame().unwrap().r[0])
    };
    let (f_nh, r_nh) = end(&scene("oblate_shear.toml", &short), "cli_law_nh");
    let mut edits = short.to_vec();
    edits.push(("c20 = 0.5", "c20 = 0.0"));
    let (f_text, _) = end(&scene("yeoh_oblate.toml", &edits), "cli_law_text");
    assert!((f_text - f_nh).amax() <= 1e-7, "{:?}", (f_text - f_nh).amax());
    let (_, r_yeoh) = end(&scene("yeoh_oblate.toml", &short), "cli_law_yeoh");
    assert!(r_yeoh < r_nh, "Yeoh r1 {r_yeoh} against Neo-Hooke {r_nh}");
    let text = std::fs::read_to_string(scene_path("yeoh_oblate.toml"))
        .unwrap()
        .replace("c20*(", "k*(");
    match parse(
        &Source {
            file: "yeoh.toml",
            text: &text,
        },
        Path::new("."),
    ) {
        Err(SceneError::Invalid { key, message, .. }) => {
            assert_eq!(key, "particles.list[0].material.energy");
            assert!(message.contains("unknown name `k`"), "{message}");
        }
        other => panic!("expected a scene error, got {:?}", other.map(|s| s.count())),
    }
}

/// `type = "auto"` chooses per injection group from the particle's numbers and says so: the
/// bifurcation scene's soft spheres at Stk = 0.1 keep their inertia (St = τγ̇ with the field's
/// mean strain rate, several U/D, is well above 0.06), spheres a quarter the size
/// (Stk = 0.006) move at the equilibrium velocity; both runs end every particle at a wall or an
/// outlet.
#[test]
fn auto_integrator_chooses_per_group_and_says_so() {
    let auto = [("type = \"radau_iia\"\ntol = 1e-5", "type = \"auto\"\ntol = 1e-2")];
    let stk = scene("bifurcation.toml", &auto);
    let log = stk.integrator_log();
    assert_eq!(log.len(), 1, "{log:?}");
    assert!(
        log[0].starts_with(
            "particles.inject[0]: integrator auto: elastic inertialess shape, inertial barycentre, rosenbrock_w23"
        ),
        "{log:?}"
    );
    let small = [
        auto[0],
        (
            "semi_axes = [4.0309733612015035e-06, 4.0309733612015035e-06, 4.0309733612015035e-06]",
            "semi_axes = [1.0077e-06, 1.0077e-06, 1.0077e-06]",
        ),
    ];
    let tracer = scene("bifurcation.toml", &small);
    let log = tracer.integrator_log();
    assert!(log[0].contains("equilibrium barycentre"), "{log:?}");
    for (s, name) in [(&stk, "cli_auto_stk"), (&tracer, "cli_auto_tracer")] {
        for r in &run(s, name).records {
            assert!(
                matches!(r.fate, Fate::Escaped { .. } | Fate::Deposited { .. }),
                "{name} particle {}: {:?}",
                r.index,
                r.fate
            );
        }
    }
    // A fixed scheme has nothing to say per particle.
    assert!(scene("bifurcation.toml", &[]).integrator_log().is_empty());
}

/// A tracer scene on the case `case` with its patches as the boundary.
fn tracer_on_case(case: &Path) -> String {
    format!(
        r#"[flow]
type = "openfoam"
case = "{}"
[fluid]
viscosity = 1e-5
density = 1.0
[boundary]
type = "mesh"
[particles]
density = 1.0
[[particles.list]]
semi_axes = [1e-6, 1e-6, 1e-6]
position = [1e-3, 1e-3, 0.25e-3]
fluid_velocity = true
material = {{ law = "rigid" }}
[integrator]
type = "stokesian"
tol = 1e-8
dt = 1e-4
[end]
t_end = 1.0
[output]
every = 0.5
vtk = false
"#,
        case.display()
    )
}

/// A 2-D case as OpenFOAM writes it is a valid scene; with a patch of a type that is not a
/// particle boundary the scene is refused at `flow.case`, the patch and its type named, before
/// its fields are read.
#[test]
fn openfoam_scene_refuses_unsupported_patch_types() {
    let text = tracer_on_case(&build::channel_2d());
    parse_named("channel.toml", &text).unwrap();
    for (patch, kind) in [
        ("walls", "cyclicACMI"),
        ("frontAndBack", "mappedPatch"),
        ("inlet", "cyclicSlip"),
    ] {
        let dir = build::channel_copy(&format!("scene_{kind}"));
        build::retype(&dir, patch, kind);
        let err = parse_named("channel.toml", &tracer_on_case(&dir)).expect_err("refused");
        let message = err.to_string();
        assert!(
            message.contains("flow.case")
                && message.contains(&format!("`{patch}`"))
                && message.contains(&format!("`{kind}`"))
                && message.contains("not supported as a particle boundary"),
            "{message}"
        );
    }
}

/// A 2-D case holds its particles in their plane, as OpenFOAM's tracker does: a prolate
/// (40 × 10 × 10 µm, ρ = 1000 kg/m³ in a gas of ν = 10⁻⁵ m²/s: τ_p ≈ 2 ms) tilted 45° out of
/// the plane and launched with 0.05 m/s out of it would leave the 0.5 mm slab by itself (the
/// launch alone carries it v τ_p ≈ 0.1 mm, the tilted drag more); held, every kept state has
/// the start's z exactly and zero out-of-plane velocity, and it leaves through the outlet.
#[test]
fn a_two_d_case_keeps_its_particles_in_the_slab() {
    let text = tracer_on_case(&build::channel_2d())
        .replace(
            "density = 1.0\n[[particles.list]]",
            "density = 1000.0\n[[particles.list]]",
        )
        .replace("semi_axes = [1e-6, 1e-6, 1e-6]", "semi_axes = [40e-6, 10e-6, 10e-6]")
        .replace(
            "fluid_velocity = true",
            "velocity = [0.05, 0.0, 0.05]\norientation = { axis = [0.0, 1.0, 0.0], angle = 0.785 }",
        )
        .replace("type = \"stokesian\"", "type = \"radau_iia\"")
        .replace("dt = 1e-4", "dt = 1e-6")
        .replace("every = 0.5", "every = 0.005");
    let s = parse_named("channel.toml", &text).unwrap();
    let out = run(&s, "cli_channel_2d_slab");
    let record = &out.records[0];
    let Fate::Escaped { patch, .. } = record.fate else {
        panic!("{:?}", record.fate);
    };
    assert_eq!(out.patches[patch], "outlet");
    assert!(record.samples.len() > 10, "{} samples", record.samples.len());
    for st in record.samples.iter().chain(record.end.as_ref()) {
        assert_eq!((st.x[2], st.v[2]), (0.25e-3, 0.0), "t = {}", st.t);
    }
    // Only the barycentre is held: the shape kept turning (its F is not the start's).
    let (start, end) = (record.samples[0].f, record.end.unwrap().f);
    assert!((end - start).norm() > 0.1, "F {start} to {end}");
}

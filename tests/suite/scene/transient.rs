//! Scene files on transient OpenFOAM fields (`flow.time` a range or a list): the fates of the
//! steady scene on a field that does not change in time, bitwise the library's batch run
//! ([`run_batch`] over a [`TransientFlow`] built here) on a field u(x) sin ωt, the closed-form
//! path through a uniform field whose magnitude is linear in time, a stopped run resumed to
//! the same records, and the typed errors of bad `time`, `precision` and `window` keys.

use super::command::{chunks, ok, pseudorigid, results};
use super::{parse_named, run};
use crate::common::build::{Shape, cube, write_levels};
use pseudorigid::contact::MeshBoundary;
use pseudorigid::driver::{Budget, Plan};
use pseudorigid::ellipsoid::Ellipsoid;
use pseudorigid::error::{ParamError, StepError};
use pseudorigid::flow::openfoam::{BlendedFlow, Cycle, FoamCase, FoamError, Precision, TransientFlow};
use pseudorigid::hydro::drag::Brenner;
use pseudorigid::integrator::Stokesian;
use pseudorigid::material::NamedLaw;
use pseudorigid::material::{NeoHooke, Softness};
use pseudorigid::particle::{Fluid, Particle};
use pseudorigid::population::batch::{Batch, run_batch};
use pseudorigid::population::{
    Fate, Fingerprint, Injector, ParticleRng, ParticleSpec, ParticleTemplate, PopulationError, RunControl, RunOptions,
    RunOutput, Shard,
};
use pseudorigid::scene::SceneError;
use pseudorigid::scene::run::Job;
use pseudorigid::scene::{DEFAULT_MAX_STEPS, Scene};
use pseudorigid::tensor::{Mat3, Vec3};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A case of `cube(Hex, 6)` in the test's scratch folder with `U = u(x, t)` at `times`.
fn transient_case(name: &str, times: &[f64], u: impl Fn(&Vec3, f64) -> Vec3) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    write_levels(&dir, &cube(Shape::Hex, 6), times, u);
    dir
}

/// Rigid spheres of radius `RADIUS` at `STARTS`, at rest, ρ_s = 2, in a fluid of μ = ρ = 1
/// with the case's patches as the boundary (walls deposit, inlet and outlet let out), the
/// overdamped Radau IIA at tol 1e-8, output every 0.25 to `t_end`; `flow` the `[flow]` keys
/// after `type` and `case`.
fn scene_text(case: &Path, flow: &str, t_end: f64) -> String {
    let list: String = STARTS
        .iter()
        .map(|p| {
            format!(
                "[[particles.list]]\nsemi_axes = [{RADIUS}, {RADIUS}, {RADIUS}]\nposition = [{}, {}, {}]\nmaterial = {{ law = \"rigid\" }}\n",
                p[0], p[1], p[2]
            )
        })
        .collect();
    format!(
        r#"[flow]
type = "openfoam"
case = "{}"
{flow}
[fluid]
viscosity = 1.0
density = 1.0
[boundary]
type = "mesh"
[particles]
density = 2.0
{list}
[integrator]
type = "stokesian"
tol = 1e-8
dt = 1e-3
overdamped = true
[end]
t_end = {t_end}
[output]
every = 0.25
vtk = false
"#,
        case.display()
    )
}

const RADIUS: f64 = 0.04;

/// Start points spread over the cube: near the inlet, the outlet, the walls and the middle.
const STARTS: [[f64; 3]; 8] = [
    [0.1, 0.5, 0.5],
    [0.5, 0.5, 0.5],
    [0.9, 0.5, 0.5],
    [0.5, 0.1, 0.5],
    [0.5, 0.9, 0.3],
    [0.3, 0.3, 0.08],
    [0.7, 0.7, 0.92],
    [0.2, 0.8, 0.6],
];

fn scene(case: &Path, flow: &str, t_end: f64) -> Scene {
    parse_named("transient.toml", &scene_text(case, flow, t_end)).unwrap_or_else(|e| panic!("{flow}: {e}"))
}

/// A flow with shear, rotation and through-flow: particles leave through the outlet, reach the
/// walls, or stay.
fn shape(x: &Vec3) -> Vec3 {
    Vec3::new(0.6 + 0.4 * x[1], 0.5 * (0.5 - x[0]), 0.3 * (x[1] - 0.5))
}

/// On a field equal in every time directory, a scene reading them as a transient field (the
/// batch runner, windows of 0.25) gives every particle the fate of the steady scene (the
/// particle-major runner), and ends where it ends to the step control's tolerance: the runs
/// differ only in the steps landing on the window ends (`population::batch`).
#[test]
fn a_field_steady_in_time_gives_the_steady_scenes_fates() {
    let times = [0.0, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5];
    let case = transient_case("cli_transient_steady", &times, |x, _| shape(x));
    let steady = run(&scene(&case, "time = 0", 1.5), "cli_transient_steady_a");
    let transient = run(
        &scene(&case, "time = { start = 0, end = 1.5 }", 1.5),
        "cli_transient_steady_b",
    );
    assert!(
        steady.records.iter().any(|r| matches!(r.fate, Fate::Deposited { .. }))
            && steady.records.iter().any(|r| matches!(r.fate, Fate::Escaped { .. })),
        "{:?}",
        steady.records.iter().map(|r| &r.fate).collect::<Vec<_>>()
    );
    for (a, b) in steady.records.iter().zip(&transient.records) {
        assert_eq!(
            std::mem::discriminant(&a.fate),
            std::mem::discriminant(&b.fate),
            "{}",
            a.index
        );
        assert_eq!(a.fate.patch(), b.fate.patch(), "particle {}", a.index);
        let (ea, eb) = (a.end.unwrap(), b.end.unwrap());
        // Positions of order 1, relative tolerance 1e-8 per step: 1e-6 covers the landing
        // steps and the located events.
        assert!(
            (ea.x - eb.x).amax() < 1e-6,
            "particle {}: {:?} {:?}",
            a.index,
            ea.x,
            eb.x
        );
        assert!((ea.t - eb.t).abs() < 1e-6, "particle {}: t {} {}", a.index, ea.t, eb.t);
    }
}

/// The library's particles of [`STARTS`], as the scene builds them (rigid spheres at rest).
struct Spheres(ParticleTemplate<Brenner>);

impl Injector for Spheres {
    type Law = NeoHooke;
    type Drag = Brenner;

    fn draw(&self, index: u64, _rng: &mut ParticleRng) -> Result<ParticleSpec<NeoHooke>, StepError> {
        Ok(ParticleSpec {
            shape: Ellipsoid::new([RADIUS; 3], Mat3::identity())?,
            softness: Softness::Rigid,
            density: 2.0,
            position: Vec3::from(STARTS[index as usize]),
            velocity: Vec3::zeros(),
        })
    }

    fn particle(&self, spec: &ParticleSpec<NeoHooke>) -> Result<Particle<Softness<NeoHooke>, Brenner>, ParamError> {
        self.0.build(spec)
    }
}

/// The library's batch run of the scene of [`scene_text`] on `case`: the field opened with
/// `times` and `cycle`, windows every `window` to `t_end`.
fn library_run(case: &Path, times: &[f64], cycle: Cycle, window: f64, t_end: f64) -> RunOutput<NeoHooke> {
    let mut flow =
        TransientFlow::<BlendedFlow>::open(FoamCase::open(case).unwrap(), times, cycle, Precision::F64).unwrap();
    let boundary = MeshBoundary::new(flow.mesh()).unwrap();
    let integrator = Stokesian::overdamped(1e-8).unwrap();
    let spheres = Spheres(ParticleTemplate::new(Brenner, Fluid::new(1.0, 1.0).unwrap(), Vec3::zeros()).unwrap());
    let outputs: Vec<f64> = (1..=(t_end / 0.25).round() as u32)
        .map(|k| f64::from(k) * 0.25)
        .collect();
    let plan = Plan::new(t_end, 1e-3)
        .and_then(|p| p.with_outputs(&outputs))
        .unwrap()
        .with_budget(Budget {
            max_steps: DEFAULT_MAX_STEPS,
            wall_time: None,
        });
    let batch = Batch::new(&integrator, &boundary, &spheres, plan).with_samples();
    let n = (t_end / window).round() as u32;
    let windows: Vec<f64> = (0..=n).map(|k| f64::from(k) * window).collect();
    let config = Fingerprint::new("transient spheres").config(0, STARTS.len() as u64);
    let quiet = RunOptions::default().quiet();
    run_batch(&batch, &mut flow, &windows, &config, Shard::ALL, &quiet).unwrap()
}

/// Fate, end state and every kept state of two runs, bit for bit.
fn assert_same_records(cli: &RunOutput<NamedLaw>, library: &RunOutput<NeoHooke>) {
    assert_eq!(cli.records.len(), library.records.len());
    for (a, b) in cli.records.iter().zip(&library.records) {
        assert_eq!(format!("{:?}", a.fate), format!("{:?}", b.fate), "particle {}", a.index);
        assert_eq!(a.end, b.end, "particle {}", a.index);
        assert_eq!(a.samples, b.samples, "particle {}", a.index);
    }
}

/// A scene on a periodic field u(x) sin ωt (period 1, eight levels, read over two periods)
/// runs as the library's [`run_batch`] on the [`TransientFlow`] opened by hand with the same
/// levels, period and windows: every record bit for bit. The same for a list of times (not
/// periodic) with the default window.
#[test]
fn a_periodic_scene_is_the_librarys_batch_run_bit_for_bit() {
    let omega = std::f64::consts::TAU;
    let times: Vec<f64> = (0..=8).map(|k| f64::from(k) * 0.125).collect();
    let case = transient_case("cli_transient_periodic", &times, |x, t| {
        shape(x) * (1.0 + (omega * t).sin())
    });
    let cli = run(
        &scene(&case, "time = { start = 0, end = 1, period = 1 }\nwindow = 0.125", 2.0),
        "cli_transient_periodic_run",
    );
    let library = library_run(&case, &times, Cycle::Periodic { period: 1.0 }, 0.125, 2.0);
    assert_same_records(&cli, &library);
    assert!(cli.records.iter().any(|r| r.fate.patch().is_some()));
    // A list of times, not periodic, with the default window (the levels' spacing 0.125).
    let list = "time = [0, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 1]";
    let cli = run(&scene(&case, list, 1.0), "cli_transient_list_run");
    let library = library_run(&case, &times, Cycle::Once, 0.125, 1.0);
    assert_same_records(&cli, &library);
}

/// u = (a + b t) e₁, uniform, written at t = 0, 0.5, …, 2 (linear in time, so interpolated
/// exactly): an overdamped sphere without gravity moves with the fluid, x₁(t) = x₁(0) + a t +
/// b t²/2. Radau IIA integrates the polynomial exactly; what remains is round-off and the
/// event-free step control, far below the tolerance 1e-8 (asserted at 1e-9 of the distance).
#[test]
fn a_uniform_field_linear_in_time_carries_a_sphere_the_closed_form_distance() {
    let (a, b) = (0.2, 0.2);
    let times = [0.0, 0.5, 1.0, 1.5, 2.0];
    let case = transient_case("cli_transient_linear", &times, |_, t| Vec3::new(a + b * t, 0.0, 0.0));
    let text = scene_text(&case, "time = { start = 0, end = 2 }\nwindow = 0.3", 2.0);
    let out = run(&parse_named("linear.toml", &text).unwrap(), "cli_transient_linear_run");
    let r = &out.records[0];
    assert_eq!(r.fate, Fate::Suspended);
    let end = r.end.unwrap();
    let distance = a * 2.0 + b * 2.0 * 2.0 / 2.0;
    assert!(
        (end.x[0] - STARTS[0][0] - distance).abs() < 1e-9 * distance,
        "travelled {} against {distance}",
        end.x[0] - STARTS[0][0]
    );
    for s in &r.samples {
        let expected = STARTS[0][0] + a * s.t + b * s.t * s.t / 2.0;
        assert!(
            (s.x[0] - expected).abs() < 1e-9,
            "t = {}: {} against {expected}",
            s.t,
            s.x[0]
        );
    }
}

/// A run stopped after its first window (a caller's Ctrl-C: [`RunControl::stop`]) has
/// checkpointed the particles finished by then and returns `Interrupted`; resumed, it gives the
/// records of an uninterrupted run, bit for bit, and reports all particles done.
#[test]
fn a_stopped_transient_run_resumes_to_the_same_records() {
    let (a, b) = (0.2, 0.2);
    let times = [0.0, 0.5, 1.0, 1.5, 2.0];
    let case = transient_case("cli_transient_resume", &times, |x, t| {
        Vec3::new(a + b * t, 0.0, 0.0) + shape(x) * 0.5
    });
    let s = scene(&case, "time = [0, 0.5, 1, 1.5, 2]\nwindow = 0.25", 2.0);
    let whole = run(&s, "cli_transient_whole");
    // Particles leave in the first window: the checkpoint holds some.
    assert!(
        whole
            .records
            .iter()
            .any(|r| matches!(r.fate, Fate::Escaped { time, .. } if time < 0.25))
    );
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_transient_stopped");
    let _ = std::fs::remove_dir_all(&dir);
    let control = Arc::new(RunControl::default());
    control.stop();
    let options = RunOptions::default().serial().quiet().with_control(control);
    let stopped = s.population(&Job::Run {
        shard: Shard::ALL,
        options,
        dir: dir.clone(),
    });
    match stopped {
        Err(SceneError::Population(PopulationError::Interrupted { done, total })) => {
            assert!(done > 0 && done < total, "{done} of {total}")
        }
        other => panic!("expected an interrupted run, got {:?}", other.map(|o| o.records.len())),
    }
    // The batch runner reports its progress to the caller's handle (Python's bar).
    let progress = Arc::new(RunControl::default());
    let resumed = s
        .population(&Job::Run {
            shard: Shard::ALL,
            options: RunOptions::default()
                .serial()
                .quiet()
                .resume(true)
                .with_control(progress.clone()),
            dir,
        })
        .unwrap();
    assert_eq!(progress.progress(), (STARTS.len() as u64, STARTS.len() as u64));
    assert_eq!(resumed.config_hash, whole.config_hash);
    assert_eq!(format!("{:?}", resumed.records), format!("{:?}", whole.records));
}

/// A time level that vanishes after the scene was validated (which reads the first window's
/// levels) fails the run at the first window that holds it (the level after a window's end is
/// held too: 1.5 for [0.75, 1]), with that window's ends and the reader's own error as the
/// source (a typed [`FoamError`], not text).
#[test]
fn a_level_missing_at_its_window_is_the_readers_typed_error() {
    let times = [0.0, 0.5, 1.0, 1.5, 2.0];
    let case = transient_case("cli_transient_vanished", &times, |x, t| shape(x) * (1.0 + t));
    let s = scene(&case, "time = [0, 0.5, 1, 1.5, 2]\nwindow = 0.25", 2.0);
    std::fs::remove_dir_all(case.join("1.5")).unwrap();
    let job = Job::Memory {
        shard: Shard::ALL,
        options: RunOptions::default().serial().quiet(),
    };
    match s.population(&job) {
        Err(SceneError::Population(e @ PopulationError::Slide { start, end, .. })) => {
            assert_eq!((start, end), (0.75, 1.0));
            let PopulationError::Slide { source, .. } = &e else {
                unreachable!()
            };
            let foam = source.downcast_ref::<FoamError>();
            assert!(
                matches!(foam, Some(FoamError::Missing { .. } | FoamError::Io { .. })),
                "{source:?}"
            );
            assert!(
                e.to_string().starts_with(&format!("time window [{start}, {end}]: ")),
                "{e}"
            );
        }
        other => panic!("expected a window error, got {:?}", other.map(|o| o.records.len())),
    }
}

/// Bad transient keys are refused at the key, with the numbers that explain why: start ≥ end,
/// a period ≤ 0, no time directory in the range, a list not ascending or naming a time the
/// case does not have, a misspelt range key, an unknown precision, a window ≤ 0 or longer than
/// the period, and `precision` or `window` on a steady field.
#[test]
fn bad_transient_keys_are_typed_errors() {
    let times = [0.0, 0.25, 0.5, 0.75, 1.0];
    let case = transient_case("cli_transient_errors", &times, |x, t| shape(x) * (1.0 + t));
    let refused = |flow: &str| match parse_named("bad.toml", &scene_text(&case, flow, 1.0)) {
        Err(SceneError::Invalid { key, message, .. }) => (key, message),
        other => panic!("{flow}: expected a scene error, got {:?}", other.map(|s| s.count())),
    };
    for (flow, key, words) in [
        (
            "time = { start = 0.5, end = 0.5 }",
            "flow.time",
            vec!["start = 0.5", "end = 0.5"],
        ),
        (
            "time = { start = 1, end = 0 }",
            "flow.time",
            vec!["start = 1", "end = 0"],
        ),
        (
            "time = { start = 0, end = 1, period = 0 }",
            "flow.time",
            vec!["period", "got 0"],
        ),
        (
            "time = { start = 0, end = 1, period = -1 }",
            "flow.time",
            vec!["got -1"],
        ),
        (
            "time = { start = 2, end = 3 }",
            "flow.time",
            vec!["0 time directories in [2, 3]", "0.75"],
        ),
        (
            "time = { start = 0.3, end = 0.4 }",
            "flow.time",
            vec!["0 time directories in [0.3, 0.4]"],
        ),
        (
            "time = [0, 0.5, 0.25]",
            "flow.time",
            vec!["time[1] = 0.5", "time[2] = 0.25"],
        ),
        ("time = [0, 0.3]", "flow.time", vec!["no time directory 0.3", "0.25"]),
        ("time = [0.5]", "flow.time", vec!["at least two"]),
        // A value no form takes is the TOML reader's error, at its dotted key.
        (
            "time = [0, 1]\nprecision = \"f16\"",
            "flow.precision",
            vec!["f16", "f32"],
        ),
        (
            "time = { strat = 0, end = 1 }",
            "flow.time",
            vec!["unknown field `strat`", "start"],
        ),
        ("time = [0, \"x\"]", "flow.time", vec!["time[1] must be a number"]),
        ("time = [0, 1]\nwindow = 0", "flow.window", vec!["got 0"]),
        (
            "time = { start = 0, end = 1, period = 1 }\nwindow = 2",
            "flow.window",
            vec!["period 1", "got 2"],
        ),
        ("time = 0.5\nprecision = \"f32\"", "flow.precision", vec!["transient"]),
        ("window = 0.1", "flow.window", vec!["transient"]),
    ] {
        let (k, message) = refused(flow);
        assert_eq!(k, key, "{flow}: {message}");
        for w in words {
            assert!(message.contains(w), "{flow}: `{message}` lacks `{w}`");
        }
    }
    // Accepted: f32 storage, a window, a range of the default ends.
    for flow in ["time = { }\nprecision = \"f32\"", "time = [0.25, 0.75]\nwindow = 0.1"] {
        let s = parse_named("good.toml", &scene_text(&case, flow, 1.0)).unwrap_or_else(|e| panic!("{flow}: {e}"));
        assert!(s.windows().is_some(), "{flow}");
    }
}

/// The command on a transient scene: two shards merged give the files of the whole run, byte
/// for byte (tables and ParaView index), and `validate` names the field's levels and windows.
#[test]
fn transient_shards_merge_to_the_whole_run_through_the_command() {
    let times = [0.0, 0.25, 0.5, 0.75, 1.0];
    let case = transient_case("cli_transient_command_case", &times, |x, t| shape(x) * (1.0 + t));
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_transient_command");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let text = scene_text(&case, "time = { start = 0, end = 1 }", 1.0).replace("vtk = false", "vtk = true");
    std::fs::write(dir.join("scene.toml"), text).unwrap();
    let command = |args: &[&str]| ok(pseudorigid(&dir, args));
    let log = command(&["validate", "scene.toml"]);
    assert!(
        log.contains("transient field, 5 levels from t = 0 to 1; 4 windows of 0.250000"),
        "{log}"
    );
    command(&["run", "scene.toml", "--out", "whole", "--quiet", "--threads", "2"]);
    for shard in ["0/2", "1/2"] {
        command(&["run", "scene.toml", "--out", "shards", "--quiet", "--shard", shard]);
    }
    command(&["merge", "scene.toml", "--out", "shards"]);
    for ((file, whole), (_, shards)) in results(&dir.join("whole")).iter().zip(&results(&dir.join("shards"))) {
        assert!(whole == shards, "{file}");
    }
}

/// The command on a transient scene killed (SIGKILL) after its first window-end checkpoint
/// and resumed writes the files of an uninterrupted run, byte for byte (issue 38, item 9): the
/// batch runner's checkpoints ([`run_batch`]) survive a kill as the particle-major runner's do
/// (`scene::run`). 4000 rigid spheres injected on a disc across the cube in the field of
/// [`a_stopped_transient_run_resumes_to_the_same_records`] at half its speed: those near the
/// outlet leave in the first window (the first chunk), 274 near the inlet are still in flight
/// at t = 2, and the whole run takes about a second on one thread (3726 escape over the 8
/// windows), so a kill polled for every 5 ms lands mid-run.
#[test]
fn a_killed_transient_run_resumes_to_the_same_files() {
    let times = [0.0, 0.5, 1.0, 1.5, 2.0];
    let case = transient_case("cli_transient_kill_case", &times, |x, t| {
        Vec3::new(0.1 + 0.1 * t, 0.0, 0.0) + shape(x) * 0.25
    });
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_transient_kill");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut text =
        scene_text(&case, "time = [0, 0.5, 1, 1.5, 2]\nwindow = 0.25", 2.0).replace("vtk = false", "vtk = true");
    let list = text.find("[[particles.list]]").unwrap()..text.find("[integrator]").unwrap();
    text.replace_range(
        list,
        &format!(
            "[particles.inject]\ncount = 4000\nsemi_axes = [{RADIUS}, {RADIUS}, {RADIUS}]\nregion = {{ type = \"disc\", centre = [0.5, 0.5, 0.5], normal = [0.0, 1.0, 0.0], radius = 0.45 }}\nmaterial = {{ law = \"rigid\" }}\n"
        ),
    );
    std::fs::write(dir.join("scene.toml"), text).unwrap();
    let command = |args: &[&str]| ok(pseudorigid(&dir, args));
    command(&["run", "scene.toml", "--out", "whole", "--quiet", "--threads", "1"]);

    let mut child = std::process::Command::new(super::command::BIN)
        .current_dir(&dir)
        .args(["run", "scene.toml", "--out", "killed", "--quiet", "--threads", "1"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let checkpoint = dir.join("killed").join("checkpoint-0000-of-0001");
    let started = std::time::Instant::now();
    // Bounded wait: the first chunk is due at the first window end, t = 0.25 of 2.
    while chunks(&checkpoint) == 0 {
        assert!(
            started.elapsed() < std::time::Duration::from_secs(120),
            "no checkpoint after 120 s"
        );
        assert!(
            child.try_wait().unwrap().is_none(),
            "the run ended before its first checkpoint"
        );
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    // `Child::kill` is SIGKILL on Unix: no handler runs, the process dies where it is.
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(
        !dir.join("killed").join("records.parquet").exists(),
        "the run finished before it was killed"
    );
    let kept = chunks(&checkpoint);

    command(&[
        "run",
        "scene.toml",
        "--out",
        "killed",
        "--quiet",
        "--threads",
        "1",
        "--resume",
    ]);
    assert!(chunks(&checkpoint) > kept, "the resumed run wrote no chunk");
    assert!(
        results(&dir.join("killed")) == results(&dir.join("whole")),
        "the resumed run's files differ"
    );
}

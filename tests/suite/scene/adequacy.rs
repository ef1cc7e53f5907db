//! The mesh-adequacy diagnostic (`scene::adequacy`, issue 39 item 2) on a box over one wall
//! whose first-cell height is chosen, in the divergence-free flow towards the wall
//! u = s (2xy, −y², 0): no-slip on y = 0, wall-normal velocity −s y², the δ² growth the wall
//! layer carries exactly (`flow::openfoam::wall_layer`: the shear γ = 2sx, c = −½ ∂γ/∂x = −s).
//! A particle's barycentre comes down the plane x = 0 as y(t) = y₀/(1 + s y₀ t) and touches the
//! wall (extent contact, radius a) at t = (1/a − 1/y₀)/s on the exact or blended field. The
//! wall cell's linear fit (the cellwise field) has u_y = −s y_c² − g (y − y_c), y_c = h/2 its
//! centre and g its least-squares slope: between the wall (g = s y_c) and the cell above
//! (g = 4 s y_c) it vanishes at some height y* ∈ [0, ¾ y_c], and a particle whose radius is
//! below y* stops there and never touches. So on a coarse first cell (h = 0.2, a = 0.02) the
//! two fields disagree about every particle; on a fine one (h = 0.015 < a) both deposit all.

use super::command::{ok, pseudorigid};
use crate::common::build;
use pseudorigid::population::{RunOptions, Shard};
use pseudorigid::scene::adequacy::{Adequacy, Skipped};
use pseudorigid::scene::error::Source;
use pseudorigid::scene::parse;
use pseudorigid::scene::run::run;
use pseudorigid::tensor::Vec3;
use std::path::{Path, PathBuf};

/// s of the flow.
const S: f64 = 10.0;
/// Sphere radius.
const A: f64 = 0.02;

/// The box x ∈ [−0.5, 0.5] (5 cells, so the particles' plane x = 0 is inside a column of cells), y ∈ `ys`, z ∈ [0, 1] (2 cells), wall at y = 0, with the
/// flow of the module docs, written to a fresh folder `name`.
fn case(name: &str, ys: &[f64]) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    let raw = build::layered_box(&[-0.5, -0.3, -0.1, 0.1, 0.3, 0.5], ys, &[0.0, 0.5, 1.0], false);
    let u = build::sampled(&raw.mesh(), |x| S * Vec3::new(2.0 * x[0] * x[1], -x[1] * x[1], 0.0));
    build::write_case(&dir, &raw, &u, "0", build::Format::Ascii);
    dir
}

/// 20 spheres of radius [`A`] (ρ_s = 2, fluid μ = 1, ρ = 1) started at rest on the disc
/// x = 0, |(y, z) − (0.5, 0.5)| < 0.2, to t = 10 (every one touches the wall on the exact
/// field by t = 4.9); `extra` is appended to `[output]`.
fn scene_text(case: &Path, extra: &str) -> String {
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
density = 2.0
[particles.inject]
count = 20
semi_axes = [{A}, {A}, {A}]
region = {{ type = "disc", centre = [0.0, 0.5, 0.5], normal = [1.0, 0.0, 0.0], radius = 0.2 }}
material = {{ law = "rigid" }}
[integrator]
type = "radau_iia"
tol = 1e-6
dt = 1e-3
overdamped = true
[end]
t_end = 10.0
[output]
vtk = false
{extra}
"#,
        case.display()
    )
}

/// The run of `scene_text(case, extra)` in `out` and its diagnostic.
fn adequacy_of(case: &Path, extra: &str, out: &str) -> Adequacy {
    let text = scene_text(case, extra);
    let scene = parse(
        &Source {
            file: "box.toml",
            text: &text,
        },
        Path::new("."),
    )
    .unwrap();
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(out);
    let _ = std::fs::remove_dir_all(&dir);
    let done = run(&scene, &dir, Shard::ALL, RunOptions::default().quiet(), false).unwrap();
    eprintln!("{}", done.adequacy.as_ref().unwrap().log());
    done.adequacy.unwrap()
}

/// The numbers by hand on the coarse box (h = 0.2): 10 wall faces of first-cell height 0.2; U
/// the largest cell-centre speed, at the top corner cells' centres x = ±0.4, y = 0.75, where
/// s(2xy, −y²) = s(±0.6, −0.5625), so U = s√(0.6² + 0.5625²); a sphere's response time with Stokes
/// drag 6πμa, τ_p = m/(6πμa) = 2ρ_s a²/(9μ). Then the warning: on the blended field every
/// particle touches the wall (the exact field's t ≤ 4.9 < t_end), on the wall cell's linear
/// fit none comes down to y = a, so all 20 pairs are discordant and the paired standard
/// error is 0.
#[test]
fn coarse_first_cell_numbers_and_warning() {
    let coarse = case("adequacy_coarse", &[0.0, 0.2, 0.5, 1.0]);
    let a = adequacy_of(&coarse, "", "adequacy_coarse_out");
    let r = a.resolution.as_ref().unwrap();
    // The heights are twice the cell centre's distance from the face: round-off of a few ulp.
    assert_eq!(r.walls.faces, 10);
    assert!(
        (r.walls.median - 0.2).abs() < 1e-15 && (r.walls.max - 0.2).abs() < 1e-15,
        "{:?}",
        r.walls
    );
    let speed = S * (0.6f64 * 0.6 + 0.5625 * 0.5625).sqrt();
    assert!((r.speed - speed).abs() < 1e-12 * speed, "{} {speed}", r.speed);
    let [p] = r.particles.as_slice() else {
        panic!("{:?}", r.particles)
    };
    let tau = 2.0 * 2.0 * A * A / 9.0;
    assert_eq!(p.key, "particles.inject[0]");
    assert_eq!(p.largest_semi_axis, A);
    assert!((p.response_time - tau).abs() < 1e-12 * tau, "{} {tau}", p.response_time);
    assert!((p.stopping_ratio - tau * speed / 0.2).abs() < 1e-12 * p.stopping_ratio);
    assert!((p.size_ratio - 0.1).abs() < 1e-15);
    assert!(p.verdict().contains("decided inside the wall layer"), "{}", p.verdict());
    let s = a.sensitivity.as_ref().unwrap();
    assert_eq!((s.run_field, s.other_field), ("blended", "cellwise"));
    assert_eq!(s.pairing.n(), 20);
    assert!(s.warning, "{s:?}");
    assert!(s.difference > 0.5, "{s:?}");
    assert!(
        a.log()
            .contains("warning: adequacy: the deposition fraction moves by 1.0000 (all 20 pairs that differ, one way)"),
        "{}",
        a.log()
    );
    let json =
        std::fs::read_to_string(Path::new(env!("CARGO_TARGET_TMPDIR")).join("adequacy_coarse_out/adequacy.json"))
            .unwrap();
    assert!(json.contains("\"warning\": true"), "{json}");
    let file: serde_json::Value = serde_json::from_str(&json).unwrap();
    let logged: Vec<&str> = file["log"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l.as_str().unwrap())
        .collect();
    assert_eq!(logged, a.log().lines().collect::<Vec<_>>());
}

/// The same particles with a first cell below their radius (h = 0.015 < a = 0.02): both fields
/// deposit them alike, no warning; the ratio says the particle spans the first cell. A first
/// sample of 5 finds no difference and cannot bound a shift of 0.01 (5 concordant pairs detect
/// only (z + 0.84)²/5 ≈ 2), so it doubles: to 10, then to all 20 unless the step budget (the
/// run's own steps) would be passed first. It always re-tracks the first particles by index,
/// and 0 re-tracks none.
#[test]
fn fine_first_cell_does_not_warn() {
    use pseudorigid::scene::adequacy::Stop;
    let fine = case("adequacy_fine", &[0.0, 0.015, 0.05, 0.12, 0.25, 0.5, 1.0]);
    let a = adequacy_of(&fine, "adequacy_sample = 5", "adequacy_fine_out");
    let s = a.sensitivity.as_ref().unwrap();
    assert!(!s.warning, "{s:?}");
    let n = s.pairing.n();
    assert!(
        s.looks >= 2 && matches!((n, s.stop), (10, Stop::Budget) | (20, Stop::AllParticles)),
        "{s:?}"
    );
    assert_eq!(s.pairing.both, n, "{s:?}");
    assert!(s.detectable > pseudorigid::scene::adequacy::RESOLVE, "{s:?}");
    assert_eq!(
        s.particles.iter().map(|p| p.index).collect::<Vec<_>>(),
        (0..n).collect::<Vec<_>>()
    );
    assert!(
        a.log()
            .contains("the smallest shift this sample detects with 80 % power is"),
        "{}",
        a.log()
    );
    assert!(a.log().contains("mesh study"), "{}", a.log());
    let p = &a.resolution.as_ref().unwrap().particles[0];
    assert!((p.size_ratio - A / 0.015).abs() < 1e-12, "{p:?}");
    assert!(!a.log().contains("warning"), "{}", a.log());
    let off = adequacy_of(&fine, "adequacy_sample = 0", "adequacy_fine_off");
    assert_eq!((off.sensitivity, off.skipped), (None, Some(Skipped::Off)));
}

/// `output.adequacy_sample` is refused, at its key, on an analytic flow; the command prints no
/// adequacy line there.
#[test]
fn adequacy_sample_on_an_analytic_flow_is_refused() {
    let text = |extra: &str| {
        format!(
            "[flow]\ntype = \"shear\"\nrate = 1.0\n[fluid]\nviscosity = 1.0\ndensity = 1.0\n[[particles.list]]\ndensity = 1.0\n\
             semi_axes = [1.0, 1.0, 1.0]\nposition = [0.0, 0.0, 0.0]\nvelocity = [0.0, 0.0, 0.0]\n\
             material = {{ law = \"rigid\" }}\n[integrator]\ntype = \"radau_iia\"\ntol = 1e-6\ndt = 1e-3\n\
             [end]\nt_end = 0.1\n[output]\nvtk = false\n{extra}\n"
        )
    };
    let parsed = |extra: &str| {
        parse(
            &Source {
                file: "shear.toml",
                text: &text(extra),
            },
            Path::new("."),
        )
    };
    match parsed("adequacy_sample = 3") {
        Err(pseudorigid::scene::SceneError::Invalid { key, message, .. }) => {
            assert_eq!(key, "output.adequacy_sample");
            assert!(message.contains("analytic flow"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(parsed("adequacy_sample = 0").unwrap().adequacy_sample, 0);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("adequacy_shear");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("scene.toml"), text("")).unwrap();
    let log = ok(pseudorigid(&dir, &["run", "scene.toml", "--out", "out", "--quiet"]));
    assert!(
        !log.contains("adequacy") && !dir.join("out/adequacy.json").exists(),
        "{log}"
    );
}

/// The sequential rule (`scene::adequacy::grow`), measured by simulation of paired fates, not
/// of particles: each of N = 10⁴ particles is discordant with probability d = 0.05, one way (b,
/// deposited by the run only) with probability (d + δ)/2 and the other with (d − δ)/2, so the
/// paired shift is δ; each costs one step, the run N steps, budget 1× (the default).
/// - δ = 0: the share of simulated runs that warn (false alarms) is at most 5 % plus three
///   Monte Carlo standard errors of 400 runs (√(0.05·0.95/400) = 0.011): Bonferroni over the
///   looks keeps the whole sequence's false-alarm rate at or below 5 %.
/// - δ = 0.01: the share that warns (the power) is at least 80 % less three standard errors
///   (0.02): the sample grows until a shift of 0.01 is detected with 80 % power or the budget
///   ends, and N = 10⁴ at d = 0.05 reaches that bound (~6 200 pairs at z = 2.69, seven looks) within it.
///
/// The seeds are fixed, so the test is deterministic; the margins hold for any seed.
#[test]
fn adequacy_rule_keeps_false_alarms_and_reaches_its_power() {
    use pseudorigid::population::particle_rng;
    use pseudorigid::scene::adequacy::{Look, Stop, grow};
    use rand::RngExt;
    let (n, d, runs) = (10_000usize, 0.05, 400u64);
    let warned = |shift: f64, seed: u64| -> f64 {
        let mut warnings = 0;
        for run in 0..runs {
            let mut rng = particle_rng(seed, run);
            let grown = grow(200, n, n as f64, |range| {
                range
                    .map(|_| {
                        let u: f64 = rng.random();
                        let look = if u < 0.5 * (d + shift) {
                            Look::Paired(true, false)
                        } else if u < d {
                            Look::Paired(false, true)
                        } else {
                            Look::Paired(false, false)
                        };
                        (look, 1)
                    })
                    .collect()
            });
            assert!(grown.steps <= n as u64 && grown.sample <= n, "{grown:?}");
            if grown.stop == Stop::Resolved {
                warnings += 1;
            }
        }
        f64::from(warnings) / runs as f64
    };
    let false_alarms = warned(0.0, 1);
    let power = warned(0.01, 2);
    eprintln!("false alarms {false_alarms}, power {power}");
    assert!(
        false_alarms <= 0.05 + 3.0 * (0.05f64 * 0.95 / runs as f64).sqrt(),
        "{false_alarms}"
    );
    assert!(power >= 0.8 - 3.0 * (0.8f64 * 0.2 / runs as f64).sqrt(), "{power}");
}

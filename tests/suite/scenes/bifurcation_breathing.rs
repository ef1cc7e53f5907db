//! A breathing cycle in the bifurcation (src/scenes/bifurcation/breathing.rs): the injection
//! times' distribution, a breath of constant flow rate against the steady study on the same
//! particles, and a reduced snapshot of the sinusoidal breath through the quasi-steady field.

use pseudorigid::population::{Fate, RunOptions, Shard};
use pseudorigid::scenes::bifurcation::breathing::{self, Breath, Paired, Waveform, de_table, paired_table};
use pseudorigid::scenes::bifurcation::{Airway, Kind, Material, figures, run_kind};
use pseudorigid::scenes::particles::Shape;
use std::path::PathBuf;
use std::sync::OnceLock;

fn airway() -> &'static Airway {
    static AIRWAY: OnceLock<Airway> = OnceLock::new();
    AIRWAY.get_or_init(|| Airway::open(Airway::shipped_dir()).expect("shipped bifurcation field"))
}

fn scratch(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name)
}

/// The injection time's distribution F(t) = (1 − cos ωt)/2 inverts the draw: F(t(u)) = u to
/// round-off (acos loses digits near u = 0 and 1, where dF/dt → 0: 1e-12 holds with room), the
/// times fill [0, T/2], and the flow rate's mean over the inhalation is the steady one (the
/// scale's mean, by 2000-point midpoint quadrature: error (π/2)·(π/2000)²/24 ≈ 1e-7).
/// α = R√(2π/(Tν)) = 0.9737 to the printed digits.
#[test]
fn injection_times_follow_the_flow_rate() {
    let w = Waveform::rest();
    let period = breathing::PERIOD;
    for k in 0..=1000 {
        let u = f64::from(k) / 1000.0;
        let t = w.injection_time(u);
        assert!((0.0..=0.5 * period).contains(&t), "u {u}: t {t}");
        let f = 0.5 * (1.0 - (2.0 * std::f64::consts::PI * t / period).cos());
        assert!((f - u).abs() <= 1e-12, "u {u}: F(t) = {f}");
    }
    let m = 2000;
    let mean = (0..m)
        .map(|k| w.scale((f64::from(k) + 0.5) / f64::from(m) * w.duration()))
        .sum::<f64>()
        / f64::from(m);
    assert!((mean - 1.0).abs() <= 1e-6, "{mean}");
    assert!((breathing::womersley_number() - 0.9737).abs() < 5e-5);
    assert_eq!(w.scale(-0.1), 0.0);
    assert_eq!(w.scale(2.1), 0.0);
}

/// A breath of constant flow rate (the steady field at every level, particles entering
/// uniformly over 0.5 s) is the steady study shifted in time: particle k injected at t₀ must
/// meet the steady particle k's fate at t₀ plus the steady fate's time, where the breath lasts
/// long enough (a steady fate after 0.5 − t₀ leaves it suspended). The runs differ only in the
/// steps cut at the window ends (every 0.1 s), by the step control's tolerance: the studies'
/// paired tolerance runs changed 1 fate in 10³ for rigid particles (`study::RTOL`), so of 120
/// rigid spheres none is expected to change and more than 1 would be a fault. Event times agree
/// to the step control's tolerance: `study::RTOL` (10⁻²) of the time tracked, at most the
/// breath's 0.5 s, so 5·10⁻³ s (measured: 2.8·10⁻⁴ s).
///
/// A consistency check of the breathing machinery (windows, injection times, paired records)
/// against the steady study, not a physics check: both runs are this code's.
#[test]
fn constant_breath_is_the_steady_study_shifted_in_time() {
    let dir = scratch("breathing-constant");
    let w = Waveform::Constant { duration: 0.5 };
    let times: Vec<f64> = (0..=5).map(|k| 0.1 * f64::from(k)).collect();
    breathing::write_quasi_steady(&Airway::shipped_dir(), &dir, w, &times).unwrap();
    let mut breath = Breath::open(&dir, w).unwrap();
    assert_eq!(breath.windows(), times);
    let kind = Kind {
        shape: Shape::Sphere,
        material: Material::Rigid,
        stokes: 0.4,
    };
    let n = 120;
    let quiet = RunOptions::default().quiet();
    let steady = run_kind(airway(), kind, n, figures::SEED, Shard::ALL, &quiet, None).unwrap();
    let cyclic = breathing::run_inhaled(airway(), &mut breath, kind, n, figures::SEED, &quiet, None).unwrap();
    let pair = Paired::new(airway(), kind, w, figures::SEED, steady, cyclic).unwrap();
    let (mut changed, mut compared, mut worst) = (0, 0, 0.0f64);
    for ((a, b), &t0) in pair.steady.records.iter().zip(&pair.cyclic.records).zip(&pair.times) {
        assert!((0.0..0.5).contains(&t0));
        let steady_end = match a.fate {
            Fate::Deposited { time, .. } | Fate::Escaped { time, .. } => time,
            ref other => panic!("particle {}: steady {other:?}", a.index),
        };
        if t0 + steady_end >= 0.5 - 1e-3 {
            // Its steady fate comes after the breath ends (or within a tolerance of it).
            continue;
        }
        compared += 1;
        match b.fate {
            Fate::Deposited { time, .. } | Fate::Escaped { time, .. } if b.fate.label() == a.fate.label() => {
                worst = worst.max((time - t0 - steady_end).abs());
            }
            _ => changed += 1,
        }
    }
    println!("constant breath: {compared} of {n} compared, {changed} fates changed, event times within {worst:.2e} s");
    assert!(compared >= 80, "{compared}");
    assert!(changed <= 1, "{changed}");
    assert!(worst <= pseudorigid::scenes::bifurcation::study::RTOL * 0.5, "{worst}");
}

/// The sinusoidal breath at reduced N through the quasi-steady field (the shipped field scaled
/// by U_in(t)/U at 11 levels, 0.2 s apart): 100 rigid and 100 soft (μ_s = 0.5 Pa) spheres at
/// Stk 0.4, steady and cyclic, their DE and paired table snapshotted. None may fail.
///
/// A regression guard (this code's own output), not a check. The transient reader's time
/// interpolation is checked against fields known in closed form in
/// `flow::openfoam::transient`; the constant breath above checks the breathing machinery
/// against the steady study, which is this code too.
#[test]
fn sinusoidal_breath_snapshot() {
    let dir = scratch("breathing-sine");
    let w = Waveform::rest();
    let times: Vec<f64> = (0..=10).map(|k| 0.2 * f64::from(k)).collect();
    breathing::write_quasi_steady(&Airway::shipped_dir(), &dir, w, &times).unwrap();
    let mut breath = Breath::open(&dir, w).unwrap();
    let quiet = RunOptions::default().quiet();
    let mut pairs = Vec::new();
    for material in [Material::Rigid, Material::ShearModulus(0.5)] {
        let kind = Kind {
            shape: Shape::Sphere,
            material,
            stokes: 0.4,
        };
        let n = 100;
        let steady = run_kind(airway(), kind, n, figures::SEED, Shard::ALL, &quiet, None).unwrap();
        let cyclic = breathing::run_inhaled(airway(), &mut breath, kind, n, figures::SEED, &quiet, None).unwrap();
        assert_eq!(cyclic.counts().failed, 0);
        pairs.push(Paired::new(airway(), kind, w, figures::SEED, steady, cyclic).unwrap());
    }
    insta::assert_snapshot!(format!(
        "{}\n{}",
        de_table(&pairs).unwrap().to_text(),
        paired_table(&pairs).unwrap().to_text()
    ));
}

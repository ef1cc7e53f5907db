//! A breathing cycle in the bifurcation (src/studies/bifurcation/breathing.rs): the injection
//! times' distribution, a breath of constant flow rate against the steady study on the same
//! particles, a slow breath against the steady field scaled to each particle's flow rate (the
//! quasi-steady limit), and a reduced snapshot of the sinusoidal breath through the
//! quasi-steady field.

use pseudorigid::population::{Fate, RunOptions};
use pseudorigid::studies::bifurcation::breathing::{self, Breath, BreathingPair, Waveform, de_table, paired_table};
use pseudorigid::studies::bifurcation::{Airway, Kind, Material, StudyRun, figures};
use pseudorigid::studies::particles::Shape;
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
/// to the step control's tolerance: each run holds the position to `study::ATOL` (10⁻⁵ m) per
/// step, so the two paths differ by at most the sum of their steps' allowances, and the event
/// (a wall reached, an outlet crossed) by that distance over the particle's speed there:
/// |Δt| ≤ (n_steady + n_cyclic)·ATOL/|v_end| per particle (local errors added without the
/// flow's amplification; measured: the largest |Δt| 6.6·10⁻⁴ s, the rigid spheres' steps set
/// by x and v alone since their orientation left the error test; a shift of the injection
/// times by one window would be 0.1 s).
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
    let steady = StudyRun::new(airway(), kind, n).run(&quiet).unwrap();
    let cyclic = breathing::run_inhaled(airway(), &mut breath, kind, n, figures::SEED, &quiet, None)
        .unwrap()
        .output;
    let pair = BreathingPair::new(airway(), kind, w, figures::SEED, steady, cyclic).unwrap();
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
                let dt = (time - t0 - steady_end).abs();
                let speed = a.end.as_ref().expect("a finished record keeps its end state").v.norm();
                let steps = (a.stats.steps + b.stats.steps) as f64;
                let allowed = steps * pseudorigid::studies::bifurcation::study::ATOL / speed;
                assert!(
                    dt <= allowed,
                    "particle {}: event times {dt:e} s apart, allowed {allowed:e} s",
                    a.index
                );
                worst = worst.max(dt);
            }
            _ => changed += 1,
        }
    }
    println!("constant breath: {compared} of {n} compared, {changed} fates changed, event times within {worst:.2e} s");
    assert!(compared >= 80, "{compared}");
    assert!(changed <= 1, "{changed}");
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
        let steady = StudyRun::new(airway(), kind, n).run(&quiet).unwrap();
        let cyclic = breathing::run_inhaled(airway(), &mut breath, kind, n, figures::SEED, &quiet, None)
            .unwrap()
            .output;
        assert_eq!(cyclic.counts().failed, 0);
        pairs.push(BreathingPair::new(airway(), kind, w, figures::SEED, steady, cyclic).unwrap());
    }
    insta::assert_snapshot!(format!(
        "{}\n{}",
        de_table(&pairs).unwrap().to_text(),
        paired_table(&pairs).unwrap().to_text()
    ));
}

/// The quasi-steady limit: a slow breath (T = 400 s, 11 levels) against, particle by particle,
/// the steady field scaled to the flow rate at its injection, s = ŝ(t₀) (ŝ the linear
/// interpolant of the levels' U_in/U, the field the breath holds), written as a steady case of
/// its own. Womersley's α does not enter: the quasi-steady field never changes its shape (the
/// solved breath at α = 0.97 departs from the steady solutions at its flow rate by about 1 %,
/// `paper-figures/airway-breathing/field_check.csv`, which this test does not cover).
/// What departs from the steady run is the change of the flow rate during a particle's stay
/// t_s (its steady event time), a Strouhal number: the field it meets stays within
/// ε = max|ŝ(t) − s|/s over [t₀, t₀ + t_s], about ωt_s cot ωt₀ ≲ 10⁻³ here (at the real
/// T = 4 s it would be 10²× larger); its injection velocity is U_in(t₀)/U times the steady
/// one, η = |U_in(t₀)/U − s|/s off (the interpolant's error, ≤ ω²Δt²/8 ≈ 1.2 % of the peak),
/// and it relaxes within its response time (1.9 ms, < 10 % of t_s). A field scaled by
/// 1 + ε shifts event times by ε t_s, so each event time, counted from t₀, agrees with the
/// steady one to (RTOL + ε + η) t_s, RTOL the step control's share (as in the constant breath
/// above); fates may change only as the step control changes them, about 1 in 10³ (RTOL's
/// docs): more than 1 of those compared is a fault. Particles injected below s = 0.5 (a
/// slow, long stay) are not compared.
#[test]
fn slow_breath_is_quasi_steady_particle_by_particle() {
    use pseudorigid::studies::bifurcation::study::RTOL;
    let period = 400.0;
    let w = Waveform::Sine { period };
    let dir = scratch("breathing-slow");
    let times: Vec<f64> = (0..=10).map(|k| 20.0 * f64::from(k)).collect();
    breathing::write_quasi_steady(&Airway::shipped_dir(), &dir, w, &times).unwrap();
    let mut breath = Breath::open(&dir, w).unwrap();
    let kind = Kind {
        shape: Shape::Sphere,
        material: Material::Rigid,
        stokes: 0.4,
    };
    // Each compared particle costs a steady case of its own (0.8 s to write and open).
    let n = 6;
    let quiet = RunOptions::default().quiet();
    let steady = StudyRun::new(airway(), kind, n).run(&quiet).unwrap();
    let cyclic = breathing::run_inhaled(airway(), &mut breath, kind, n, figures::SEED, &quiet, None)
        .unwrap()
        .output;
    let pair = BreathingPair::new(airway(), kind, w, figures::SEED, steady, cyclic).unwrap();
    // ŝ(t): the levels' scales, linearly interpolated.
    let level = |t: f64| w.scale(t);
    let s_hat = |t: f64| {
        let j = ((t / 20.0).floor() as usize).min(times.len() - 2);
        let (a, b) = (times[j], times[j + 1]);
        level(a) + (level(b) - level(a)) * (t - a) / (b - a)
    };
    let (mut compared, mut changed) = (0, 0);
    for (k, (b, &t0)) in pair.cyclic.records.iter().zip(&pair.times).enumerate() {
        let s = s_hat(t0);
        if s < 0.5 {
            continue;
        }
        // The steady field at scale s: one level at the time a sine of period 1 reaches s.
        let scaled = scratch(&format!("breathing-slow-steady-{k}"));
        let at = (2.0 * s / std::f64::consts::PI).asin() / (2.0 * std::f64::consts::PI);
        breathing::write_quasi_steady(&Airway::shipped_dir(), &scaled, Waveform::Sine { period: 1.0 }, &[at]).unwrap();
        let reference = StudyRun::new(&Airway::open(&scaled).unwrap(), kind, k as u64 + 1)
            .run(&quiet)
            .unwrap();
        let a = &reference.records[k];
        assert_eq!(a.index, b.index);
        let t_s = match a.fate {
            Fate::Deposited { time, .. } | Fate::Escaped { time, .. } => time,
            ref other => panic!("particle {k}: steady at scale {s}: {other:?}"),
        };
        let ends = [t0, t0 + t_s];
        let inner = times.iter().copied().filter(|&t| t > ends[0] && t < ends[1]);
        let eps = ends
            .into_iter()
            .chain(inner)
            .map(|t| (s_hat(t) - s).abs() / s)
            .fold(0.0, f64::max);
        let eta = (w.scale(t0) - s).abs() / s;
        compared += 1;
        match b.fate {
            Fate::Deposited { time, .. } | Fate::Escaped { time, .. } if b.fate.label() == a.fate.label() => {
                let tol = (RTOL + eps + eta) * t_s;
                assert!(
                    (time - t0 - t_s).abs() <= tol,
                    "particle {k} (t₀ {t0:.2} s, s {s:.4}): {} at {:.6} s after injection, steady {t_s:.6} s (±{tol:.2e}; ε {eps:.1e}, η {eta:.1e})",
                    b.fate.label(),
                    time - t0
                );
            }
            _ => changed += 1,
        }
        let _ = std::fs::remove_dir_all(&scaled);
    }
    println!("slow breath: {compared} of {n} compared, {changed} fates changed");
    assert!(compared >= 3, "{compared}");
    assert!(changed <= 1, "{changed}");
}

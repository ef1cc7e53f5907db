//! OpenFOAM's tracker driven from Rust and the race table (`studies::peer`): the script's
//! summary read back, the particles written, the rows' arithmetic by hand, and typed errors for
//! a broken script, a bad summary and a particle the peer lost. OpenFOAM itself runs in
//! `benches/peers/openfoam_race.sh --ci` (in `.ci/run`).
#![cfg(feature = "parallel")]

use pseudorigid::driver::RunStats;
use pseudorigid::population::peer::PeerFate;
use pseudorigid::population::{Fate, ParticleRecord, RunOutput, Shard};
use pseudorigid::studies::peer::{
    Cost, CpuSplit, Entrant, OpenFoamRun, OpenFoamTracker, PeerParticle, PeerRunError, RACE_COLUMNS, RaceRow,
    TrackerSummary, TrackerSummaryError, marginal_fit, particles_csv, race_csv, race_markdown, timed,
};
use pseudorigid::tensor::Vec3;
use std::collections::HashMap;
use std::path::Path;

/// `summary.txt` as `run.sh` writes it (values of a 200-sphere run on the CI bend).
const SUMMARY: &str = "particles=200\ndeposited=125\nescaped=56\nsuspended=19\nnot_injected=0\n\
    end_time=1.5525203431732287e-1\ntime_steps=1553\nlast_time=0.155300000001\nparcel_steps=57417\n\
    execution_seconds=0.29999999999999999\nwall_seconds=3.075\ntrack_wall_seconds=0.690\n\
    load_cpu_seconds=0.120\ntrack_cpu_seconds=0.200\ninject_cpu_seconds=0.150\n";

#[test]
fn summary_is_read_back() {
    let s = TrackerSummary::parse(SUMMARY).unwrap();
    assert_eq!(s.outer_steps, 1553);
    assert_eq!(s.parcel_steps, 57_417);
    assert_eq!(s.cpu_seconds, 0.3);
    assert_eq!(s.wall_seconds, 3.075);
    assert_eq!(s.track_wall_seconds, 0.69);
    assert_eq!(
        s.cpu,
        CpuSplit {
            load_seconds: 0.12,
            track_seconds: 0.2
        }
    );
    assert!((s.cpu.total() - 0.32).abs() < 1e-15);
    assert_eq!(s.inject_cpu_seconds, 0.15);
    // A summary of the script before parcel counts were written names what is missing.
    let old = SUMMARY.replace("parcel_steps=57417\n", "");
    let missing = TrackerSummary::parse(&old).unwrap_err();
    assert_eq!(missing, TrackerSummaryError::Missing { key: "parcel_steps" });
    assert!(missing.to_string().contains("parcel_steps"));
    let bad = SUMMARY.replace("time_steps=1553", "time_steps=many");
    let malformed = TrackerSummary::parse(&bad).unwrap_err();
    assert!(
        matches!(&malformed, TrackerSummaryError::Malformed { key: "time_steps", value, .. } if value == "many"),
        "{malformed:?}"
    );
    assert!(malformed.to_string().contains("time_steps=many"));
}

#[test]
fn particles_are_written_as_the_script_reads_them() {
    let p = |k: f64| PeerParticle {
        position: Vec3::new(k, 0.1 + k, -1e-3),
        velocity: Vec3::new(3.0, 0.0, k),
        diameter: 1.25e-5,
        density: 1000.0,
    };
    let csv = particles_csv(&[p(0.0), p(1.0)]);
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], "index,x,y,z,u,v,w,d,rho");
    assert_eq!(lines.len(), 3);
    // Shortest round-trip text: the values come back exactly.
    let row: Vec<f64> = lines[2].split(',').map(|v| v.parse().unwrap()).collect();
    assert_eq!(row, vec![1.0, 1.0, 1.1, -1e-3, 3.0, 0.0, 1.0, 1.25e-5, 1000.0]);
}

#[test]
fn tracker_refuses_bad_parameters() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    assert!(OpenFoamTracker::new(root, 0.0, Vec3::zeros(), 1.2).is_err());
    assert!(OpenFoamTracker::new(root, 1.0, Vec3::zeros(), -1.0).is_err());
    assert!(OpenFoamTracker::new(root, 1.0, Vec3::new(f64::NAN, 0.0, 0.0), 1.2).is_err());
    let t = OpenFoamTracker::new(root, 1.0, Vec3::new(9.81, 0.0, 0.0), 1.2).unwrap();
    assert!(t.script.ends_with("benches/peers/openfoam_tracker/run.sh"));
    assert_eq!(t.viscosity, None);
    for nu in [0.0, -1e-5, f64::NAN, f64::INFINITY] {
        assert!(t.clone().with_viscosity(nu).is_err(), "nu = {nu}");
    }
    assert_eq!(t.with_viscosity(1.491e-5).unwrap().viscosity, Some(1.491e-5));
}

/// A script that fails is a typed error with its status, not a panic; the particles were
/// written first.
#[test]
fn failing_script_is_an_error() {
    let work = std::env::temp_dir().join(format!("pseudorigid-failing_script_is_an_error-{}", std::process::id()));
    let mut tracker = OpenFoamTracker::new(&work, 1.0, Vec3::zeros(), 1.2).unwrap();
    tracker.script = work.join("missing.sh");
    let particle = PeerParticle {
        position: Vec3::zeros(),
        velocity: Vec3::zeros(),
        diameter: 1e-5,
        density: 1e3,
    };
    let err = tracker.run(&work, &[particle], &work.join("run")).unwrap_err();
    assert!(matches!(err, PeerRunError::Script { .. }), "{err}");
    assert!(work.join("run/particles.csv").is_file());
    std::fs::remove_dir_all(&work).unwrap();
}

fn fate(fate: &str, patch: &str) -> PeerFate {
    PeerFate {
        fate: fate.into(),
        patch: patch.into(),
        t: String::new(),
        x: Default::default(),
    }
}

fn record(index: u64, fate: Fate, steps: u64) -> ParticleRecord<()> {
    ParticleRecord {
        index,
        spec: None,
        fate,
        end: None,
        stats: RunStats {
            steps,
            rejected: 1,
            ..RunStats::default()
        },
        integrator: Default::default(),
        samples: Vec::new(),
        observed: serde_json::Value::Null,
    }
}

/// Four particles by hand: OpenFOAM deposits 0 and 1 on the wall and lost 3 (not injected);
/// ours deposits 0 and 2, leaves 1 suspended and fails on 3.
#[test]
fn race_rows_by_hand() {
    let fates: HashMap<u64, PeerFate> = [
        (0, fate("deposited", "wall")),
        (1, fate("deposited", "wall")),
        (2, fate("escaped", "outlet")),
        (3, fate("not_injected", "")),
    ]
    .into_iter()
    .collect();
    let peer = OpenFoamRun {
        fates,
        summary: TrackerSummary::parse(SUMMARY).unwrap(),
    };
    let peer_dep = |f: &PeerFate| f.fate == "deposited" && f.patch == "wall";
    let of = RaceRow::openfoam(&peer, 4, "analytical, maxCo 0.3", peer_dep);
    assert_eq!((of.deposited, of.finished, of.lost(), of.steps), (2, 3, 1, 57_417));
    assert!((of.de() - 2.0 / 3.0).abs() < 1e-15);
    assert!((of.de_stderr() - (2.0f64 / 27.0).sqrt()).abs() < 1e-15);
    assert_eq!(of.cost.wall_seconds, 0.69);

    let at_wall = Fate::Deposited {
        patch: 0,
        position: Vec3::zeros(),
        time: 0.1,
    };
    let out = RunOutput {
        format: 1,
        config_hash: String::new(),
        seed: 1,
        particles: 4,
        shard: Shard::ALL,
        patches: vec!["wall".into()],
        records: vec![
            record(0, at_wall.clone(), 10),
            record(1, Fate::Suspended, 20),
            record(2, at_wall, 30),
            record(3, Fate::Failed { error: "x".into() }, 40),
        ],
    };
    let dep = |r: &ParticleRecord<()>, patches: &[String]| matches!(r.fate, Fate::Deposited { patch, .. } if patches[patch] == "wall");
    let cost = Cost {
        wall_seconds: 2.0,
        cpu_seconds: Some(1.0),
    };
    let entrant = Entrant {
        particle: "rigid",
        integrator: "radau_iia",
        threads: 1,
        cost,
        cpu: Some(CpuSplit {
            load_seconds: 0.2,
            track_seconds: 0.8,
        }),
    };
    let ours = RaceRow::pseudorigid(entrant, &out, dep, &peer.fates, peer_dep).unwrap();
    assert_eq!(
        (ours.steps, ours.rejected, ours.deposited, ours.finished, ours.suspended),
        (100, Some(4), 2, 3, 1)
    );
    let p = ours.pairing.unwrap();
    assert_eq!((p.both, p.only_ours, p.only_peer, p.neither), (1, 1, 1, 1));
    assert_eq!(ours.wall_per_particle(), 0.5);
    assert_eq!(ours.cpu_per_particle(), Some(0.25));
    assert_eq!(ours.cpu_track_per_particle(), Some(0.2));
    assert_eq!(of.cpu_track_per_particle(), Some(0.05));

    // Every row has every column; the Markdown table one line per row under its header.
    let csv = race_csv(&[of.clone(), ours.clone()]).unwrap().to_text();
    for line in csv.lines() {
        assert_eq!(line.split(',').count(), RACE_COLUMNS.len(), "{line}");
    }
    assert_eq!(race_markdown(&[of, ours]).lines().count(), 4);

    // A particle of ours the peer has no fate for is an error.
    let mut fewer = peer.fates.clone();
    fewer.remove(&2);
    let err = RaceRow::pseudorigid(entrant, &out, dep, &fewer, peer_dep).unwrap_err();
    assert!(matches!(err, PeerRunError::Missing { index: 2 }), "{err}");
}

/// Loading then tracking: the costs add, the split keeps them apart; no CPU time in either
/// part means none in the whole and no split.
#[test]
fn costs_add_and_split() {
    let load = Cost {
        wall_seconds: 1.0,
        cpu_seconds: Some(0.5),
    };
    let track = Cost {
        wall_seconds: 3.0,
        cpu_seconds: Some(5.5),
    };
    let whole = load.then(track);
    assert_eq!((whole.wall_seconds, whole.cpu_seconds), (4.0, Some(6.0)));
    let split = CpuSplit::of(load, track).unwrap();
    assert_eq!(
        (split.load_seconds, split.track_seconds, split.total()),
        (0.5, 5.5, 6.0)
    );
    let unmeasured = Cost {
        wall_seconds: 1.0,
        cpu_seconds: None,
    };
    assert_eq!(load.then(unmeasured).cpu_seconds, None);
    assert_eq!(CpuSplit::of(unmeasured, track), None);
}

/// Points on a line give it back, whatever the weights; noise on the largest run moves the
/// intercept less than an unweighted fit would; one N, or N = 0, gives no line.
#[test]
fn marginal_fit_by_hand() {
    let line = |n: u64| 0.5 + 4e-4 * n as f64;
    let points: Vec<(u64, f64)> = [100, 10_000, 100_000].into_iter().map(|n| (n, line(n))).collect();
    let (fixed, marginal) = marginal_fit(&points).unwrap();
    assert!(
        (fixed - 0.5).abs() < 1e-9 && (marginal - 4e-4).abs() < 1e-12,
        "{fixed} {marginal}"
    );
    // Two points: the line through them. 0.6 at 100, 40.5 at 100 000 → slope 39.9/99 900.
    let (fixed, marginal) = marginal_fit(&[(100, 0.6), (100_000, 40.5)]).unwrap();
    let slope = 39.9 / 99_900.0;
    assert!((marginal - slope).abs() < 1e-12 && (fixed - (0.6 - 100.0 * slope)).abs() < 1e-9);
    // 1 % too much at 10⁵ (0.4 s): the weighted intercept moves by 0.0007 s (unweighted: 0.02 s).
    let mut noisy = points.clone();
    noisy[2].1 *= 1.01;
    let (fixed, _) = marginal_fit(&noisy).unwrap();
    assert!((fixed - 0.5).abs() < 0.002, "{fixed}");
    assert_eq!(marginal_fit(&[(1000, 1.0), (1000, 1.2)]), None);
    assert_eq!(marginal_fit(&[(0, 0.1), (1000, 1.0)]), None);
    assert_eq!(marginal_fit(&[]), None);
}

#[test]
fn timed_measures_the_work() {
    let (x, cost) = timed(|| (0..1000u64).sum::<u64>());
    assert_eq!(x, 499_500);
    assert!(cost.wall_seconds >= 0.0);
    // Linux has /proc; the CPU time of a span is never negative.
    if let Some(cpu) = cost.cpu_seconds {
        assert!(cpu >= 0.0);
    }
}

//! The time-synchronous batch runner (`population::batch`): the fates of the particle-major
//! runner on a steady field, the same records bit for bit on 1 and 2 threads, for two shard
//! layouts and across a stop and resume; its particle-steps per second against the runner's.

use super::common::{FaultySoftPipe, config, plan};
use pseudorigid::material::NeoHooke;
use pseudorigid::population::batch::{Batch, Steady, run_batch};
use pseudorigid::population::{Case, Fate, PopulationError, RunControl, RunOptions, RunOutput, Shard, run};
use std::sync::Arc;
use std::time::Instant;

fn thread_pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap()
}

/// Window ends every 10 time units over the plan's [0, 150].
fn windows() -> Vec<f64> {
    (0..=15).map(|k| 10.0 * f64::from(k)).collect()
}

/// The fate's kind and patch.
fn kind(f: &Fate) -> (&'static str, Option<usize>) {
    let name = match f {
        Fate::Deposited { .. } => "deposited",
        Fate::Escaped { .. } => "escaped",
        Fate::Suspended => "suspended",
        Fate::Failed { .. } => "failed",
    };
    (name, f.patch())
}

#[test]
fn batch_fates_are_the_runners_on_a_steady_field() {
    let FaultySoftPipe { stokes, pipe, faulty } = FaultySoftPipe::new();
    let config = config(40);
    let case = Case::new(&stokes, pipe.flow(), pipe.boundary(), &faulty, plan());
    let quiet = RunOptions::default().quiet();
    let clock = Instant::now();
    let particle_major = thread_pool(1)
        .install(|| run(&case, &config, Shard::ALL, &quiet))
        .unwrap();
    let major_time = clock.elapsed().as_secs_f64();
    let batch = Batch::new(&stokes, pipe.boundary(), &faulty, plan());
    let mut flow = Steady(pipe.flow());
    let clock = Instant::now();
    let windowed = thread_pool(1)
        .install(|| run_batch(&batch, &mut flow, &windows(), &config, Shard::ALL, &quiet))
        .unwrap();
    let batch_time = clock.elapsed().as_secs_f64();
    let counts = windowed.counts();
    assert!(counts.deposited > 0 && counts.escaped > 0 && counts.suspended > 0 && counts.failed > 0);
    let (mut steps, mut batch_steps, mut moved): (u64, u64, f64) = (0, 0, 0.0);
    for (a, b) in particle_major.records.iter().zip(&windowed.records) {
        assert_eq!(a.index, b.index);
        assert_eq!(kind(&a.fate), kind(&b.fate), "particle {}", a.index);
        if let (Fate::Deposited { position: p, .. }, Fate::Deposited { position: q, .. }) = (&a.fate, &b.fate) {
            moved = moved.max((p - q).norm());
        }
        steps += a.stats.steps;
        batch_steps += b.stats.steps;
    }
    println!(
        "steady pipe, 40 particles, 15 windows: same fates; deposits moved by at most {moved:.2e} (pipe radius 20); \
         particle-steps {steps} (runner) and {batch_steps} (batch); particle-steps/s {:.3e} (runner) and {:.3e} (batch), \
         ratio {:.2} (one thread, a shared machine)",
        steps as f64 / major_time,
        batch_steps as f64 / batch_time,
        (batch_steps as f64 / batch_time) / (steps as f64 / major_time)
    );
}

#[test]
fn batch_records_are_the_same_for_threads_shards_and_a_resume() {
    let FaultySoftPipe { stokes, pipe, faulty } = FaultySoftPipe::new();
    let config = config(31);
    let batch = Batch::new(&stokes, pipe.boundary(), &faulty, plan());
    let quiet = RunOptions::default().quiet();
    let run_with = |options: &RunOptions, shard: Shard| {
        let mut flow = Steady(pipe.flow());
        run_batch(&batch, &mut flow, &windows(), &config, shard, options)
    };
    let serial = run_with(&quiet.clone().serial(), Shard::ALL).unwrap();
    let bytes = serial.to_json().unwrap();
    for threads in [1, 2] {
        let out = thread_pool(threads).install(|| run_with(&quiet, Shard::ALL)).unwrap();
        assert!(out.to_json().unwrap() == bytes, "{threads} threads differ from serial");
    }
    for count in [2u64, 3] {
        let parts = (0..count)
            .map(|k| run_with(&quiet, format!("{k}/{count}").parse().unwrap()).unwrap())
            .collect();
        let merged = RunOutput::<NeoHooke>::merge(parts).unwrap();
        assert!(
            merged.to_json().unwrap() == bytes,
            "{count} shards differ from the whole run"
        );
    }
    // Stopped at the first window end: the records finished by then are checkpointed; the
    // resumed run equals the uninterrupted one.
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("population-batch-resume");
    let _ = std::fs::remove_dir_all(&dir);
    let control = Arc::new(RunControl::default());
    control.stop();
    let stopped = quiet
        .clone()
        .with_checkpoints(&dir, std::time::Duration::from_secs(60))
        .with_control(control);
    match run_with(&stopped, Shard::ALL) {
        Err(PopulationError::Interrupted { done, total: 31 }) => assert!(done > 0 && done < 31, "{done}"),
        other => panic!("{other:?}"),
    }
    let resumed = quiet
        .clone()
        .with_checkpoints(&dir, std::time::Duration::from_secs(60))
        .resume(true);
    assert!(run_with(&resumed, Shard::ALL).unwrap().to_json().unwrap() == bytes);
    // Another set of windows is another run: its checkpoint is refused.
    let mut flow = Steady(pipe.flow());
    assert!(matches!(
        run_batch(&batch, &mut flow, &[0.0, 75.0, 150.0], &config, Shard::ALL, &resumed),
        Err(PopulationError::ConfigMismatch { .. })
    ));
    for bad in [vec![0.0], vec![0.0, 10.0, 10.0], vec![0.0, f64::NAN]] {
        assert!(matches!(
            run_batch(&batch, &mut flow, &bad, &config, Shard::ALL, &quiet),
            Err(PopulationError::Window { .. })
        ));
    }
}

/// On a transient field the window's records are those over every level held, bit for bit:
/// Poiseuille flow whose amplitude changes as 1 + ½ sin(2πt/150), written as 11 time levels
/// on a meshed pipe (the settling pipe's, along x₁), particles of the settling pipe (feature
/// `mesh`).
#[cfg(feature = "mesh")]
#[test]
fn batch_over_a_sliding_window_is_the_batch_over_every_level() {
    use crate::common::build::{Format, pipe as pipe_mesh, sampled, write_case, write_field};
    use pseudorigid::flow::openfoam::{Cycle, FoamCase, FoamFlow, Precision, TransientFlow};
    use pseudorigid::tensor::Vec3;
    let mut raw = pipe_mesh(20.0, 200.0, 4, 3, 1.0, 20);
    // The generated pipe runs along z; a cyclic permutation turns it onto x₁.
    raw.points.iter_mut().for_each(|p| *p = Vec3::new(p[2], p[0], p[1]));
    let mesh = raw.mesh();
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("population-batch-transient");
    let _ = std::fs::remove_dir_all(&dir);
    let times: Vec<f64> = (0..=10).map(|k| 15.0 * f64::from(k)).collect();
    for (i, &t) in times.iter().enumerate() {
        let amplitude = 1.0 + 0.5 * (2.0 * std::f64::consts::PI * t / 150.0).sin();
        let u = sampled(&mesh, |x| {
            Vec3::new(2.0 * amplitude * (1.0 - (x[1] * x[1] + x[2] * x[2]) / 400.0), 0.0, 0.0)
        });
        if i == 0 {
            write_case(&dir, &raw, &u, &format!("{t}"), Format::Binary);
        } else {
            write_field(&dir, &raw, &u, &format!("{t}"), Format::Binary);
        }
    }
    let case = FoamCase::open(&dir).unwrap();
    let every = FoamFlow::read(&case, &times).unwrap();
    let mut window = TransientFlow::<FoamFlow>::open(case, &times, Cycle::Once, Precision::F64).unwrap();
    let FaultySoftPipe { stokes, pipe, faulty } = FaultySoftPipe::new();
    let batch = Batch::new(&stokes, pipe.boundary(), &faulty, plan());
    let config = config(24);
    let quiet = RunOptions::default().quiet();
    let held = run_batch(&batch, &mut Steady(&every), &windows(), &config, Shard::ALL, &quiet).unwrap();
    let slid = run_batch(&batch, &mut window, &windows(), &config, Shard::ALL, &quiet).unwrap();
    println!("transient pipe, 24 particles: {:?}", slid.counts());
    assert!(slid.counts().deposited > 0, "{:?}", slid.counts());
    assert!(slid.to_json().unwrap() == held.to_json().unwrap());
}

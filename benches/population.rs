//! Populations of independent particles.
//!
//! - `population_runner_N`: the population runner ([`pseudorigid::population::run`]) on the
//!   settling pipe (rigid spheres, overdamped barycentre: a cheap analytic case), serially and
//!   on rayon pools of 1 and 2 threads. The throughput is the run's accepted steps, so
//!   criterion's `elem/s` is particle-steps per second; the ratio serial/2 threads is the
//!   parallel speed-up. Memory per particle is printed once.
//! - `population_step_N`: N particles advanced by one step, serially and with rayon (the
//!   integrator alone, without the driver's loop).
//!
//! Set `PSEUDORIGID_POPULATION` to change N (default 1e3 for the runner, 1e5 for the step
//! benches; the CI bench uses 1e3).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use pseudorigid::driver::{Budget, Plan};
use pseudorigid::integrator::Stokesian;
use pseudorigid::population::settling_pipe::SettlingPipe;
use pseudorigid::population::{Case, Fingerprint, ParticleRecord, RunOptions, Shard, run};
use pseudorigid::prelude::*;
use rayon::prelude::*;

fn population_size(default: u64) -> u64 {
    std::env::var("PSEUDORIGID_POPULATION")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

fn runner(c: &mut Criterion) {
    let n = population_size(1_000);
    // R = 20, L = 200, Ū = 1, v_s = 0.1 (units d_eq): about half the spheres deposit, half
    // escape, after 10²–10³ steps each at tol 1e-6.
    let pipe = SettlingPipe::new(20.0, 200.0, 1.0, 0.1, 15.0).unwrap();
    let stokes = Stokesian::overdamped(1e-6).unwrap();
    let plan = Plan::new(1e4, 0.1).unwrap().with_budget(Budget {
        max_steps: 1_000_000,
        wall_time: None,
    });
    let case = Case::new(&stokes, pipe.flow(), pipe.boundary(), &pipe, plan);
    let config = Fingerprint::new("population bench").particles(&pipe).config(1, n);
    let quiet = RunOptions::default().quiet();
    let probe = run(&case, &config, Shard::ALL, &quiet).unwrap();
    let steps: u64 = probe.records.iter().map(|r| r.stats.steps).sum();
    let record = std::mem::size_of::<ParticleRecord<NeoHooke>>();
    let memory = std::mem::size_of::<<Stokesian as TimeIntegrator>::Memory>();
    eprintln!(
        "population_runner_{n}: {steps} accepted steps ({:.0} per particle), {:?}; memory per particle: \
         record {record} B kept, step memory {memory} B + state {} B while in flight",
        steps as f64 / n as f64,
        probe.counts(),
        std::mem::size_of::<State>()
    );
    let pool = |threads| rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    let (one, two) = (pool(1), pool(2));
    let mut g = c.benchmark_group(format!("population_runner_{n}"));
    g.sample_size(10);
    g.throughput(Throughput::Elements(steps));
    g.bench_function("serial", |b| {
        b.iter(|| run(&case, &config, Shard::ALL, &quiet.clone().serial()).unwrap())
    });
    g.bench_function("rayon_1", |b| {
        b.iter(|| one.install(|| run(&case, &config, Shard::ALL, &quiet).unwrap()))
    });
    g.bench_function("rayon_2", |b| {
        b.iter(|| two.install(|| run(&case, &config, Shard::ALL, &quiet).unwrap()))
    });
    g.finish();
}

fn step(c: &mut Criterion) {
    let n = population_size(100_000) as usize;
    let p = ShearScaling::new(0.4, 0.1, 1e3)
        .unwrap()
        .particle([2.0, 1.0, 1.0], Mat3::identity())
        .unwrap();
    let flow = LinearFlow::simple_shear(1.0).unwrap();
    let states: Vec<State> = (0..n)
        .map(|i| {
            let mut s = State::at_rest(Vec3::new(i as f64 * 1e-3, 0.0, 0.0));
            s.f[(0, 1)] = 0.1 * ((i % 17) as f64 / 17.0);
            s
        })
        .collect();
    let imex = ImexPaper::unguarded();
    let stokes = Stokesian::overdamped(1e-6).unwrap();
    let mut g = c.benchmark_group(format!("population_step_{n}"));
    g.sample_size(10);
    g.throughput(Throughput::Elements(n as u64));
    g.bench_function("imex_serial", |b| {
        b.iter(|| {
            states
                .iter()
                .map(|s| imex.step(&p, s, &flow, 5e-4).unwrap().0)
                .collect::<Vec<_>>()
        })
    });
    g.bench_function("imex_rayon", |b| {
        b.iter(|| {
            states
                .par_iter()
                .map(|s| imex.step(&p, s, &flow, 5e-4).unwrap().0)
                .collect::<Vec<_>>()
        })
    });
    g.bench_function("stokesian_rayon", |b| {
        b.iter(|| {
            states
                .par_iter()
                .map(|s| stokes.step(&p, s, &flow, 0.01).unwrap().0)
                .collect::<Vec<_>>()
        })
    });
    g.finish();
}

criterion_group!(benches, runner, step);
criterion_main!(benches);

//! 1e5 independent particles advanced by one step, serially and with rayon. The ratio of the
//! two is the parallel speed-up on this machine (particles share nothing, so it should approach
//! the core count). Set `PSEUDORIGID_POPULATION` to change the population (the CI bench uses 1e3).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use pseudorigid::integrator::Stokesian;
use pseudorigid::prelude::*;
use rayon::prelude::*;

fn population(c: &mut Criterion) {
    let n: usize = std::env::var("PSEUDORIGID_POPULATION")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(100_000);
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
    let mut g = c.benchmark_group(format!("population_{n}"));
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

criterion_group!(benches, population);
criterion_main!(benches);

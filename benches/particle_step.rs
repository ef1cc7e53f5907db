//! Cost of one particle-step. Criterion reports the throughput in particle-steps per second
//! (`thrpt`), for the paper's IMEX step and the inertialess Rosenbrock step.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use pseudorigid::integrator::Stokesian;
use pseudorigid::prelude::*;
use std::hint::black_box;

fn particle_and_state() -> (Particle<NeoHooke>, State) {
    let axes = Mat3::new(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0);
    let p = ShearScaling::new(0.4, 0.1, 1e3)
        .unwrap()
        .particle([2.5, 2.5, 1.0], axes)
        .unwrap();
    // A deformed, moving state so that no step is trivially at rest.
    let flow = LinearFlow::simple_shear(1.0).unwrap();
    let (s, _) = pseudorigid::driver::advance(
        &ImexPaper::default(),
        &p,
        State::at_rest(Vec3::zeros()),
        &flow,
        5e-4,
        1.0,
    )
    .unwrap();
    (p, s)
}

fn bench_steps(c: &mut Criterion) {
    let (p, s) = particle_and_state();
    let flow = LinearFlow::simple_shear(1.0).unwrap();
    let mut g = c.benchmark_group("particle_step");
    g.throughput(Throughput::Elements(1));
    g.bench_function("imex_paper", |b| {
        b.iter(|| ImexPaper::default().step(&p, black_box(&s), &flow, 5e-4).unwrap())
    });
    let unchecked = ImexPaper { check_stability: false, ..ImexPaper::default() };
    g.bench_function("imex_paper_unchecked", |b| b.iter(|| unchecked.step(&p, black_box(&s), &flow, 5e-4).unwrap()));
    g.bench_function("stokesian_rosenbrock", |b| {
        b.iter(|| {
            Stokesian::overdamped(1e-6)
                .step(&p, black_box(&s), &flow, 0.05)
                .unwrap()
        })
    });
    g.bench_function("geometry_frame_integrals_traction", |b| {
        b.iter(|| p.geometry(black_box(&s)))
    });
    g.finish();
}

criterion_group!(benches, bench_steps);
criterion_main!(benches);

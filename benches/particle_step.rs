//! Cost of one particle-step. Criterion reports the throughput in particle-steps per second
//! (`thrpt`), for the paper's IMEX step and the inertialess Rosenbrock step.

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, Throughput, criterion_group, criterion_main};
use pseudorigid::integrator::imex::StabilityGuard;
use pseudorigid::integrator::{Scheme, Stokesian, TimeIntegrator};
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

/// Steps of a running particle: the state and the integrator's step memory carry over from
/// one iteration to the next, as in a real run (geometry reuse, first-same-as-last, the cached
/// stability limit). The particle keeps tumbling in the shear flow meanwhile.
fn bench_running<I: TimeIntegrator>(g: &mut BenchmarkGroup<'_, WallTime>, name: &str, integ: &I, dt: f64) {
    let (p, s0) = particle_and_state();
    let flow = LinearFlow::simple_shear(1.0).unwrap();
    let mut s = s0;
    let mut memory = I::Memory::default();
    g.bench_function(name, |b| {
        b.iter(|| {
            let step = integ.step_with(&p, black_box(&s), &mut memory, &flow, dt).unwrap();
            s = step.state;
        })
    });
}

fn bench_steps(c: &mut Criterion) {
    let (p, s) = particle_and_state();
    let mut g = c.benchmark_group("particle_step");
    g.throughput(Throughput::Elements(1));
    bench_running(&mut g, "imex_paper", &ImexPaper::default(), 5e-4);
    bench_running(&mut g, "imex_paper_unguarded", &ImexPaper::unguarded(), 5e-4);
    let exact = ImexPaper {
        guard: StabilityGuard::Exact,
        ..ImexPaper::default()
    };
    bench_running(&mut g, "imex_paper_exact_guard", &exact, 5e-4);
    let rosenbrock = Stokesian::overdamped(1e-6).unwrap().with_scheme(Scheme::Rosenbrock23);
    bench_running(&mut g, rosenbrock.name(), &rosenbrock, 0.05);
    let radau = Stokesian::overdamped(1e-6).unwrap().with_scheme(Scheme::Radau5);
    bench_running(&mut g, radau.name(), &radau, 0.05);
    g.bench_function("geometry_frame_integrals_traction", |b| {
        b.iter(|| p.geometry(black_box(&s.f)))
    });
    g.finish();
}

criterion_group!(benches, bench_steps);
criterion_main!(benches);

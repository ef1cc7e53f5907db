//! Cost of one particle-step. Criterion reports the throughput in particle-steps per second
//! (`thrpt`), for the paper's IMEX step and the inertialess Rosenbrock step, and (group
//! `force_terms`) the IMEX step with each force term of `hydro::forces` on.

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, Throughput, criterion_group, criterion_main};
use pseudorigid::integrator::imex::StabilityGuard;
use pseudorigid::integrator::{Scheme, Stokesian, TimeIntegrator};
use pseudorigid::prelude::*;
use std::hint::black_box;

fn particle_and_state() -> (Particle<NeoHooke>, State) {
    particle_and_state_of([2.5, 2.5, 1.0])
}

fn particle_and_state_of(semi_axes: [f64; 3]) -> (Particle<NeoHooke>, State) {
    let axes = Mat3::new(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0);
    let p = ShearScaling::new(0.4, 0.1, 1e3)
        .unwrap()
        .particle(semi_axes, axes)
        .unwrap();
    // A deformed, moving state so that no step is trivially at rest.
    let flow = LinearFlow::simple_shear(1.0).unwrap();
    let (s, _) = pseudorigid::driver::advance(
        pseudorigid::driver::Problem::new(&ImexPaper::default(), &p, &flow),
        State::at_rest(Vec3::zeros()),
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
    bench_particle(g, name, integ, &p, s0, &LinearFlow::simple_shear(1.0).unwrap(), dt);
}

fn bench_particle<I: TimeIntegrator>(
    g: &mut BenchmarkGroup<'_, WallTime>,
    name: &str,
    integ: &I,
    p: &Particle<NeoHooke>,
    s0: State,
    flow: &LinearFlow,
    dt: f64,
) {
    let mut s = s0;
    let mut memory = I::Memory::default();
    g.bench_function(name, |b| {
        b.iter(|| {
            let step = integ.step_with(p, black_box(&s), &mut memory, flow, dt).unwrap();
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

/// The IMEX step with each force term on (the oblate of `bench_steps`; a sphere for the
/// sphere-only terms), beside the same particle without terms.
fn bench_force_terms(c: &mut Criterion) {
    use pseudorigid::hydro::forces::{ForceTerms, by_name};
    use pseudorigid::registry::{Value, Values};
    let mut g = c.benchmark_group("force_terms");
    g.throughput(Throughput::Elements(1));
    // Off the shear's zero line (u₀ = 0.5 e_x, v = 0 at start), so that the slip and
    // Du/Dt = (∇u)u are not zero.
    let flow = LinearFlow::new(Vec3::new(0.5, 0.0, 0.0), LinearFlow::simple_shear(1.0).unwrap().grad_u).unwrap();
    let lambda = Values::from([("mean_free_path".to_string(), Value::Number(1e-3))]);
    let none = Values::new();
    for (semi_axes, terms) in [
        ([2.5, 2.5, 1.0], vec![]),
        ([2.5, 2.5, 1.0], vec!["undisturbed_flow"]),
        ([2.5, 2.5, 1.0], vec!["added_mass"]),
        ([2.5, 2.5, 1.0], vec!["cunningham"]),
        ([2.5, 2.5, 1.0], vec!["undisturbed_flow", "added_mass"]),
        ([1.0, 1.0, 1.0], vec![]),
        ([1.0, 1.0, 1.0], vec!["schiller_naumann"]),
        ([1.0, 1.0, 1.0], vec!["saffman_mei"]),
    ] {
        let (p, s0) = particle_and_state_of(semi_axes);
        let built = terms
            .iter()
            .map(|t| by_name(t, if *t == "cunningham" { &lambda } else { &none }).unwrap())
            .collect();
        let p = p.with_forces(ForceTerms::new(built).unwrap()).unwrap();
        let shape = if semi_axes[0] == semi_axes[2] {
            "sphere"
        } else {
            "oblate"
        };
        let name = format!(
            "imex_paper_{shape}_{}",
            if terms.is_empty() {
                "none".into()
            } else {
                terms.join("+")
            }
        );
        bench_particle(&mut g, &name, &ImexPaper::default(), &p, s0, &flow, 5e-4);
    }
    g.finish();
}

criterion_group!(benches, bench_steps, bench_force_terms);
criterion_main!(benches);

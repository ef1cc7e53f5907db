//! Cost of each stage of a particle step: eigen-decomposition of F̄F̄ᵀ, Jeffery integrals,
//! traction coefficients and σ̃, the inertialess 9×9 solve, P and its tangent (closed form and
//! AD), and the explicit-stability guard.

use criterion::{Criterion, criterion_group, criterion_main};
use pseudorigid::integrator::imex::stability_limit;
use pseudorigid::material::{piola_ad, tangent_ad};
use pseudorigid::prelude::*;
use std::hint::black_box;

fn stages(c: &mut Criterion) {
    let f_bar = Mat3::new(1.2, 0.3, 0.0, -0.1, 0.9, 0.05, 0.0, 0.02, 0.7);
    let frame = PrincipalFrame::from_total_distortion(&f_bar);
    let ints = EllipsoidIntegrals::new(&frame.r);
    let traction = JefferyRoscoe::new(&frame, &ints);
    let l_f = LinearFlow::simple_shear(1.0).unwrap().grad_u;
    let l_s = Mat3::new(0.1, 0.4, 0.0, -0.3, -0.1, 0.0, 0.0, 0.0, 0.0);
    let law = NeoHooke::new(2.5, 2.5e3).unwrap();
    let mut g = c.benchmark_group("stage");
    g.bench_function("eigen_frame", |b| {
        b.iter(|| PrincipalFrame::from_total_distortion(black_box(&f_bar)))
    });
    g.bench_function("integrals_carlson", |b| {
        b.iter(|| EllipsoidIntegrals::new(black_box(&frame.r)))
    });
    g.bench_function("traction_coefficients", |b| {
        b.iter(|| JefferyRoscoe::new(black_box(&frame), &ints))
    });
    g.bench_function("sigma_tilde", |b| {
        b.iter(|| traction.sigma_tilde(black_box(&l_s), &l_f, 1.0, VolumetricTraction::Paper))
    });
    g.bench_function("inertialess_solve", |b| {
        b.iter(|| {
            traction
                .inertialess(black_box(&l_f), 1.0)
                .unwrap()
                .velocity_gradient(&Mat3::identity())
        })
    });
    g.bench_function("piola_closed_form", |b| b.iter(|| law.piola(black_box(&f_bar))));
    g.bench_function("piola_ad", |b| b.iter(|| piola_ad(&law, black_box(&f_bar))));
    g.bench_function("tangent_closed_form", |b| b.iter(|| law.tangent(black_box(&f_bar))));
    g.bench_function("tangent_ad", |b| b.iter(|| tangent_ad(&law, black_box(&f_bar))));
    let p = ShearScaling::new(0.4, 0.1, 1e3)
        .unwrap()
        .particle([2.5, 2.5, 1.0], Mat3::identity())
        .unwrap();
    let mut s = State::at_rest(Vec3::zeros());
    s.f = f_bar;
    g.bench_function("imex_stability_guard", |b| {
        b.iter(|| stability_limit(&p, black_box(&s)))
    });
    g.finish();
}

criterion_group!(benches, stages);
criterion_main!(benches);

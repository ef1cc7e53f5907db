//! The slow-manifold model (src/integrator/manifold.rs, src/particle/manifold.rs): against
//! Roscoe's steady tank-treading and against the full inertialess model on the same particle.

use pseudorigid::error::FlowError;
use pseudorigid::flow::{FlowField, FlowSample};
use pseudorigid::integrator::manifold::{Manifold, ManifoldMemory};
use pseudorigid::integrator::{Stokesian, TimeIntegrator};
use pseudorigid::particle::manifold::SlowManifold;
use pseudorigid::prelude::*;
use pseudorigid::scenes::particles::Shape;
use pseudorigid::scenes::section::ShearPlaneSection;
use pseudorigid::scenes::shear_run::unit_shear;
use pseudorigid::scenes::shear_shape::ShearShape;
use pseudorigid::scenes::tank_treading::roscoe;

fn sphere(ca: f64) -> Particle<NeoHooke> {
    ShearShape::new(Shape::Sphere)
        .particle(&ShearScaling::new(ca, 1.0, 1e3).unwrap())
        .unwrap()
}

/// Step `integ` from rest to each of `times` exactly; the states there and the memory.
fn states_at<I: TimeIntegrator, F: FlowField>(
    integ: &I,
    particle: &Particle<NeoHooke>,
    flow: &F,
    times: &[f64],
) -> (Vec<State>, I::Memory) {
    let mut memory = I::Memory::default();
    let mut state = State::at_rest(Vec3::zeros());
    let mut dt: f64 = 1e-4;
    let mut out = Vec::new();
    for &t_out in times {
        while state.t < t_out {
            let h = dt.min(t_out - state.t);
            let step = integ.step_with(particle, &state, &mut memory, flow, h).unwrap();
            dt = step.info.dt_next;
            state = step.state;
            if t_out - state.t < 1e-12 * t_out {
                state.t = t_out;
            }
        }
        out.push(state);
    }
    (out, memory)
}

/// A linear flow whose gradient turns and pulses along the path: l_f(t) = γ̇(t) Q(t) L Q(t)ᵀ
/// with L simple shear, Q a rotation about e₃ by t/2 and γ̇ = 1 + sin(t)/2; u = l_f x (the
/// particle stays at the origin). |d∇u/dt| ≈ |∇u|, so the lag behind the flow is as large as
/// the tank-treading's.
struct TurningShear;

impl FlowField for TurningShear {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        let (s, c) = (0.5 * t).sin_cos();
        let q = Mat3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0);
        let mut l = Mat3::zeros();
        l[(0, 1)] = 1.0 + 0.5 * t.sin();
        let grad = q * l * q.transpose();
        Ok(FlowSample::new(grad * x, grad, Vec3::zeros()))
    }
}

#[test]
fn explore_roscoe() {
    for ca in [0.02, 0.01, 0.005] {
        let p = sphere(ca);
        let m = SlowManifold::of(&p).unwrap().unwrap();
        let integ = Manifold::new(Stokesian::overdamped(1e-8).unwrap()).with_delta_max(0.1).unwrap();
        let (s, mem): (Vec<State>, ManifoldMemory) = states_at(&integ, &p, &unit_shear(), &[10.0]);
        let sec = ShearPlaneSection::of(&p.total_distortion(&s[0].f));
        let r = roscoe(ca).unwrap().steady;
        let d = (sec.r_long - sec.r_short) / (sec.r_long + sec.r_short);
        let full = states_at(&Stokesian::overdamped(1e-8).unwrap(), &p, &unit_shear(), &[10.0]).0;
        let secf = ShearPlaneSection::of(&p.total_distortion(&full[0].f));
        let df = (secf.r_long - secf.r_short) / (secf.r_long + secf.r_short);
        println!(
            "Ca {ca}: k = {:.4} (2/(3Ca) = {:.4}) D {d:.6e} roscoe {:.6e} full {df:.6e}; theta {:.6e} roscoe {:.6e} full {:.6e}; rvort {:.6e} {:.6e}; F diff {:.3e}; {:?}",
            m.relaxation_rate(),
            2.0 / (3.0 * ca),
            r.deformation(),
            sec.angle,
            r.theta,
            secf.angle,
            sec.r_out_of_plane, r.r_vorticity,
            (s[0].f - full[0].f).norm(),
            mem.report()
        );
        let times: Vec<f64> = (1..=20).map(|i| 0.5 * i as f64).collect();
        let flow = TurningShear;
        let (sm, mem) = states_at(&integ, &p, &flow, &times);
        let (sf, _) = states_at(&Stokesian::overdamped(1e-10).unwrap(), &p, &flow, &times);
        let err = sm.iter().zip(&sf).skip(2).map(|(a, b)| (a.f - b.f).norm()).fold(0.0, f64::max);
        let dev = sf.iter().skip(2).map(|b| (b.f * b.f.transpose() - Mat3::identity()).norm()).fold(0.0, f64::max);
        println!("  turning: max |F_m - F_full| = {err:.3e}, max |B - 1| = {dev:.3e}; {:?}", mem.report());
    }
}

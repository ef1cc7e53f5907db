//! Numerical stability on hard cases: every run either stays finite and physical or stops
//! with a typed error — never NaN, never a panic. Where a run is expected to succeed, success
//! is asserted too.
use pseudorigid::driver::{Problem, advance};
use pseudorigid::integrator::{ImexAdaptive, Stokesian};
use pseudorigid::material::{Response, Rigid};
use pseudorigid::prelude::*;

fn shear() -> LinearFlow {
    LinearFlow::simple_shear(1.0).unwrap()
}

fn particle(ratios: [f64; 3], ca: f64, rho_star: f64, bulk: f64) -> Particle<NeoHooke> {
    ShearScaling::new(ca, rho_star, bulk)
        .unwrap()
        .particle(ratios, Mat3::identity())
        .unwrap()
}

/// The rigid particle of the same shape (Ca → 0: Jeffery rotation, no elasticity).
fn rigid_particle(ratios: [f64; 3]) -> Particle<Rigid> {
    ShearScaling::new(0.1, 1.0, 1e3)
        .unwrap()
        .particle_with(ratios, Mat3::identity(), Rigid)
        .unwrap()
}

/// A physical end state: finite, det F > 0 and semi-axes within a factor 50 of d_eq.
fn assert_sane<M: Response>(p: &Particle<M>, s: &State, what: &str) {
    assert!(
        s.f.iter().chain(s.a.iter()).chain(s.x.iter()).all(|c| c.is_finite()),
        "{what}: non-finite state"
    );
    assert!(s.det_f() > 0.0, "{what}: det F = {}", s.det_f());
    let r = p.geometry(&s.f).frame.r;
    assert!(r[0] < 50.0 && r[2] > 1.0 / 50.0, "{what}: semi-axes {r:?}");
}

fn assert_typed(e: &StepError, what: &str) {
    // All StepError variants are typed; this documents which ones a hard case may produce.
    assert!(
        matches!(
            e,
            StepError::Unstable { .. }
                | StepError::NewtonNotConverged { .. }
                | StepError::Inverted { .. }
                | StepError::StepSizeUnderflow { .. }
                | StepError::VolumeModeUnresolvable { .. }
        ),
        "{what}: unexpected {e}"
    );
}

#[test]
fn extreme_aspect_ratios() {
    for ratios in [[20.0, 1.0, 1.0], [20.0, 20.0, 1.0], [1.0, 1.0, 20.0]] {
        let p = particle(ratios, 0.1, 1.0, 1e3);
        let integ = Stokesian::overdamped(1e-6).unwrap();
        let (s, _) = advance(
            Problem::new(&integ, &p, &shear()),
            State::at_rest(Vec3::zeros()),
            1e-3,
            5.0,
        )
        .unwrap_or_else(|e| panic!("{ratios:?} elastic: {e}"));
        assert_sane(&p, &s, "aspect 20");
        let rigid = rigid_particle(ratios);
        let (s, _) = advance(
            Problem::new(&integ, &rigid, &shear()),
            State::at_rest(Vec3::zeros()),
            1e-3,
            5.0,
        )
        .unwrap_or_else(|e| panic!("{ratios:?} rigid: {e}"));
        assert_sane(&p, &s, "aspect 20 rigid");
        let (s, _) = advance(
            Problem::new(&ImexAdaptive::new(1e-4).unwrap(), &p, &shear()),
            State::at_rest(Vec3::zeros()),
            1e-3,
            1.0,
        )
        .unwrap();
        assert_sane(&p, &s, "aspect 20 imex_adaptive");
    }
}

/// Ca from 1e-6 (stiff: relaxation rate 1e6 γ̇) to 3 (large deformation). The inertialess
/// integrator is L-stable, so it must succeed everywhere. The IMEX scheme at ρ* = 1, Δt = 5e-3
/// meets both stability conditions for every Ca here: Δt is below the explicit viscous limit
/// ρ*/38 of the 2:1 prolate, and λ_s Δt = (1e3/Ca)·5e-3 ≥ 5/3 > (2/3)μ_f (the volumetric
/// condition of the `paper` traction). So it must succeed too.
#[test]
fn capillary_numbers_from_1e_minus_6_to_3() {
    for ca in [1e-6, 1e-3, 0.1, 1.0, 3.0] {
        let p = particle([2.0, 1.0, 1.0], ca, 1.0, 1e3);
        let (s, _) = advance(
            Problem::new(&Stokesian::overdamped(1e-6).unwrap(), &p, &shear()),
            State::at_rest(Vec3::zeros()),
            1e-3,
            3.0,
        )
        .unwrap_or_else(|e| panic!("Ca {ca}: {e}"));
        assert_sane(&p, &s, "stokesian");
        let (s, _) = advance(
            Problem::new(&ImexPaper::default(), &p, &shear()),
            State::at_rest(Vec3::zeros()),
            5e-3,
            0.5,
        )
        .unwrap_or_else(|e| panic!("imex_paper, Ca {ca}: {e}"));
        assert_sane(&p, &s, "imex_paper");
    }
}

/// λ_s/μ_s from 10 (compressible) to 1e6 (stiff volume mode). The `paper` volumetric traction
/// anti-damps the volume mode unless λ_s Δt ≳ (2/3)μ_f: with Ca = 0.4 and Δt = 5e-4 that is
/// λ_s/μ_s ≳ 533. So the IMEX scheme must succeed from 1e3 up, and below it must not return a
/// silently wrong state: it either stops with a typed error or stays physical over t ≤ 1
/// (the anti-damped growth rate is O(1/Δt)·(1 − λ_sΔt/(2/3)μ_f), which may not show in a
/// short run). The inertialess integrator has no such condition and must succeed everywhere.
#[test]
fn bulk_ratios_from_10_to_1e6() {
    for bulk in [10.0, 1e2, 1e4, 1e6] {
        let p = particle([2.5, 2.5, 1.0], 0.4, 0.1, bulk);
        match advance(
            Problem::new(&ImexPaper::default(), &p, &shear()),
            State::at_rest(Vec3::zeros()),
            5e-4,
            1.0,
        ) {
            Ok((s, _)) => assert_sane(&p, &s, "imex_paper"),
            Err(e) if bulk < 533.0 => assert_typed(&e, "imex_paper"),
            Err(e) => panic!("imex_paper at λ_s/μ_s = {bulk} meets both stability conditions: {e}"),
        }
        let (s, _) = advance(
            Problem::new(&Stokesian::overdamped(1e-6).unwrap(), &p, &shear()),
            State::at_rest(Vec3::zeros()),
            1e-3,
            3.0,
        )
        .unwrap_or_else(|e| panic!("λ/μ {bulk}: {e}"));
        assert_sane(&p, &s, "stokesian");
    }
}

/// ρ* from 1e-4 (explicit limit Δt < ρ*/37) to 10. The adaptive IMEX caps Δt at the viscous
/// limit. With the `source` volumetric traction it must succeed everywhere. With the literal
/// `paper` traction the volume mode is anti-damped unless λ_s Δt ≳ μ_f (the explicit stability analysis of `integrator::imex`,
/// condition 2); both limits together need λ_s ρ* R² ≳ 5 μ_f², violated at ρ* = 1e-4 with
/// λ_s/μ_s = 1e4 (λ_s ρ* R² ≈ 0.6): there the run must stop with a typed error, not NaN
/// (the error control then asks for steps below the volume-mode floor).
/// The fixed-step scheme with Δt = 1e-3 must refuse ρ* < 0.037 as `Unstable`.
#[test]
fn densities_from_1e_minus_4_to_10() {
    for rho_star in [1e-4_f64, 1e-2, 1.0, 10.0] {
        let t_end = (2000.0 * rho_star / 37.0).min(1.0);
        let source = particle([2.5, 2.5, 1.0], 0.4, rho_star, 1e4).with_volumetric(VolumetricTraction::Source);
        let (s, _) = advance(
            Problem::new(&ImexAdaptive::new(1e-4).unwrap(), &source, &shear()),
            State::at_rest(Vec3::zeros()),
            1e-3,
            t_end,
        )
        .unwrap_or_else(|e| panic!("ρ* {rho_star}: {e}"));
        assert_sane(&source, &s, "imex_adaptive (source)");
        let p = particle([2.5, 2.5, 1.0], 0.4, rho_star, 1e4);
        match advance(
            Problem::new(&ImexAdaptive::new(1e-4).unwrap(), &p, &shear()),
            State::at_rest(Vec3::zeros()),
            1e-3,
            t_end,
        ) {
            Ok((s, _)) => assert_sane(&p, &s, "imex_adaptive (paper)"),
            Err(e) => {
                assert!(rho_star < 1e-3, "ρ* {rho_star}: {e}");
                assert_typed(&e, "imex_adaptive (paper)");
            }
        }
        match advance(
            Problem::new(&ImexPaper::default(), &p, &shear()),
            State::at_rest(Vec3::zeros()),
            1e-3,
            t_end,
        ) {
            Ok((s, _)) => assert_sane(&p, &s, "imex_paper"),
            Err(e) => {
                assert!(rho_star < 0.037, "ρ* {rho_star}: {e}");
                assert!(matches!(e, StepError::Unstable { .. }), "{e}");
            }
        }
    }
}

/// An exact sphere has a triply degenerate b̄ = F̄F̄ᵀ at t = 0; every integrator must start.
#[test]
fn exact_sphere_at_start() {
    let p = particle([1.0, 1.0, 1.0], 0.2, 0.1, 1e3);
    let s0 = State::at_rest(Vec3::zeros());
    let (s, _) = advance(Problem::new(&ImexPaper::default(), &p, &shear()), s0, 5e-4, 0.5).unwrap();
    assert_sane(&p, &s, "imex_paper");
    let (s, _) = advance(
        Problem::new(&ImexAdaptive::new(1e-5).unwrap(), &p, &shear()),
        s0,
        1e-3,
        0.5,
    )
    .unwrap();
    assert_sane(&p, &s, "imex_adaptive");
    let (s, _) = advance(
        Problem::new(&Stokesian::new(1e-8).unwrap(), &p, &shear()),
        s0,
        1e-3,
        0.5,
    )
    .unwrap();
    assert_sane(&p, &s, "stokesian");
    let rigid = rigid_particle([1.0, 1.0, 1.0]);
    let (s, _) = advance(
        Problem::new(&Stokesian::new(1e-8).unwrap(), &rigid, &shear()),
        s0,
        1e-3,
        0.5,
    )
    .unwrap();
    assert_sane(&p, &s, "rigid");
    // The paper's scheme integrates the elastic eq. 18: a rigid particle is a typed refusal.
    let r = advance(Problem::new(&ImexPaper::default(), &rigid, &shear()), s0, 5e-4, 0.5);
    assert!(matches!(r, Err(StepError::RigidParticle { .. })), "{r:?}");
}

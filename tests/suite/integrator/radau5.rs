//! Radau IIA (order 5) core (src/integrator/radau5.rs) on classical stiff and non-stiff test
//! problems through its public one-step interface.

use nalgebra::{SMatrix, SVector};
use pseudorigid::error::{FlowError, ParamError, StepError};
use pseudorigid::integrator::Tolerances;
use pseudorigid::integrator::radau5::{RadauDense, RadauMemory, RadauStep, step};
use std::cell::Cell;

type Rhs<const N: usize> = dyn Fn(f64, &SVector<f64, N>) -> Result<SVector<f64, N>, StepError>;
type Jac<const N: usize> = dyn Fn(f64, &SVector<f64, N>) -> Result<SMatrix<f64, N, N>, StepError>;

/// One accepted step as the run saw it.
struct Record<const N: usize> {
    t: f64,
    h: f64,
    y: SVector<f64, N>,
    dense: RadauDense<N>,
}

/// Totals of an adaptive run.
struct Run<const N: usize> {
    y: SVector<f64, N>,
    steps: Vec<Record<N>>,
    rhs_evals: u32,
    jac_evals: u32,
    lu_decomps: u32,
    newton_iters: u32,
    rejected: u32,
}

/// Integrate `(rhs, jac)` from (t0, y0) to t_end, trying h0 first, with at most `max_steps`
/// steps.
fn integrate<const N: usize>(
    (rhs, jac): (&Rhs<N>, &Jac<N>),
    t0: f64,
    y0: SVector<f64, N>,
    t_end: f64,
    h0: f64,
    tol: Tolerances,
    max_steps: usize,
) -> Result<Run<N>, StepError>
where
    nalgebra::Const<N>: nalgebra::DimMin<nalgebra::Const<N>, Output = nalgebra::Const<N>>,
{
    let mut mem = RadauMemory::<N>::default();
    let (mut t, mut y, mut h) = (t0, y0, h0);
    let mut run = Run {
        y,
        steps: Vec::new(),
        rhs_evals: 0,
        jac_evals: 0,
        lu_decomps: 0,
        newton_iters: 0,
        rejected: 0,
    };
    while t < t_end {
        assert!(run.steps.len() < max_steps, "more than {max_steps} steps, t = {t}");
        let acc: RadauStep<N> = step(t, &y, h.min(t_end - t), tol, None, &mut mem, rhs, jac)?;
        run.rhs_evals += acc.rhs_evals;
        run.jac_evals += acc.jac_evals;
        run.lu_decomps += acc.lu_decomps;
        run.newton_iters += acc.newton_iters;
        run.rejected += acc.rejected;
        run.steps.push(Record {
            t,
            h: acc.h,
            y: acc.y,
            dense: acc.dense,
        });
        t += acc.h;
        y = acc.y;
        h = acc.h_next;
    }
    run.y = y;
    Ok(run)
}

/// `n` accepted steps of the rotation problem from y = (1, 0), first step 1e-3, rtol 1e-6:
/// (t, y, proposed h) after them, with `mem` warm.
fn rotation_steps(mem: &mut RadauMemory<2>, n: usize) -> (f64, SVector<f64, 2>, f64) {
    let (mut t, mut y, mut h) = (0.0, SVector::<f64, 2>::new(1.0, 0.0), 1e-3);
    for _ in 0..n {
        let acc = step(t, &y, h, tol(1e-6, 1e-6), None, mem, rotation, rotation_jac).unwrap();
        t += acc.h;
        y = acc.y;
        h = acc.h_next;
    }
    (t, y, h)
}

fn tol(rtol: f64, atol: f64) -> Tolerances {
    Tolerances::new(rtol, atol, 1e-14).unwrap()
}

/// Van der Pol in Hairer–Wanner's scaling, ε = 1e-6 (μ = 1e3 in the unscaled form, stiffness
/// ratio 1e6): y₁' = y₂, y₂' = ((1 − y₁²)y₂ − y₁)/ε.
const VDP_EPS: f64 = 1e-6;

fn vdp(_t: f64, y: &SVector<f64, 2>) -> Result<SVector<f64, 2>, StepError> {
    Ok(SVector::<f64, 2>::new(
        y[1],
        ((1.0 - y[0] * y[0]) * y[1] - y[0]) / VDP_EPS,
    ))
}

fn vdp_jac(_t: f64, y: &SVector<f64, 2>) -> Result<SMatrix<f64, 2, 2>, StepError> {
    Ok(SMatrix::<f64, 2, 2>::new(
        0.0,
        1.0,
        (-2.0 * y[0] * y[1] - 1.0) / VDP_EPS,
        (1.0 - y[0] * y[0]) / VDP_EPS,
    ))
}

/// Robertson's chemical kinetics (Hairer & Wanner, §IV.1, eq. 1.4).
fn robertson(_t: f64, y: &SVector<f64, 3>) -> Result<SVector<f64, 3>, StepError> {
    let (a, b, c) = (0.04 * y[0], 1e4 * y[1] * y[2], 3e7 * y[1] * y[1]);
    Ok(SVector::<f64, 3>::new(-a + b, a - b - c, c))
}

fn robertson_jac(_t: f64, y: &SVector<f64, 3>) -> Result<SMatrix<f64, 3, 3>, StepError> {
    Ok(SMatrix::<f64, 3, 3>::new(
        -0.04,
        1e4 * y[2],
        1e4 * y[1],
        0.04,
        -1e4 * y[2] - 6e7 * y[1],
        -1e4 * y[1],
        0.0,
        6e7 * y[1],
        0.0,
    ))
}

/// Van der Pol at ε = 1e-6 over [0, 2] from (2, −0.66) (the classical stiff test of Hairer &
/// Wanner, Ch. IV), through the first relaxation jump at t ≈ 3/2 − ln 2 ≈ 0.81. SciPy's `solve_ivp(method="Radau")`, an independent
/// implementation of the same algorithm (with a different predictive controller, growth cap 10
/// instead of 8 and 6 Newton iterations instead of 7), takes 293 and 859 steps at
/// rtol = atol = 1e-4 and 1e-6; those controller differences change counts by tens of per
/// cent, so a factor 2 either way is a generous bound that still catches a step-size collapse
/// (which costs orders of magnitude more steps) or a broken error estimate.
/// Reference y(2) = (1.7061674375, −0.8928100166): SciPy Radau at rtol 1e-13 and LSODA at
/// 1e-12 agree to 1e-10.
#[test]
fn van_der_pol_stiff_finishes_with_sane_step_counts() {
    let exact = SVector::<f64, 2>::new(1.706_167_437_5, -0.892_810_016_6);
    for (rtol, scipy_steps) in [(1e-4, 293), (1e-6, 859)] {
        let run = integrate(
            (&vdp, &vdp_jac),
            0.0,
            SVector::<f64, 2>::new(2.0, -0.66),
            2.0,
            1e-6,
            tol(rtol, rtol),
            10_000,
        )
        .unwrap();
        let steps = run.steps.len();
        assert!(
            steps > scipy_steps / 2 && steps < 2 * scipy_steps,
            "rtol {rtol}: {steps} steps vs SciPy's {scipy_steps}"
        );
        // The Jacobian changes along the jump, so it is re-evaluated, but reused on the slow
        // arcs: fewer evaluations than steps.
        assert!(run.jac_evals > 1 && (run.jac_evals as usize) < steps);
        // The global error through a relaxation jump is not bounded by the local tolerance
        // alone; the SciPy runs above end 1.4e-6 and 1e-8 off the reference, ≤ rtol/10. Bound
        // 100·rtol: room for a different step sequence, while a lost order or a mis-resolved
        // jump (errors O(1) in y₂) fails.
        let err = (run.y - exact).amax();
        assert!(err < 100.0 * rtol, "rtol {rtol}: error {err:e}");
    }
}

/// Robertson over [0, 40] and [0, 1e11] from (1, 0, 0), rtol 1e-6, atol 1e-10 (y₂ is O(1e-5)).
/// Radau is a Runge–Kutta method, so it conserves the linear invariant y₁ + y₂ + y₃ = 1
/// exactly, also with simplified Newton (the Jacobian has zero column sums, so every Newton
/// update conserves it), up to round-off: a few ε per step over ≤ 10³ steps gives
/// |Σy − 1| ≤ 1e-12, far below any real violation (which would be of the size of atol).
/// Reference y(40) = (0.7158270687, 9.185534765e-6, 0.2841637457): SciPy Radau at rtol 1e-13
/// and LSODA at rtol 1e-12 agree to 3e-12.
/// Step count: SciPy's Radau takes 373 steps to 1e11 at these tolerances; a factor 2 bound as
/// for Van der Pol.
#[test]
fn robertson_conserves_mass_and_matches_reference() {
    let y0 = SVector::<f64, 3>::new(1.0, 0.0, 0.0);
    let run = integrate(
        (&robertson, &robertson_jac),
        0.0,
        y0,
        40.0,
        1e-6,
        tol(1e-6, 1e-10),
        10_000,
    )
    .unwrap();
    let exact = SVector::<f64, 3>::new(0.715_827_068_7, 9.185_534_765e-6, 0.284_163_745_7);
    // Global error at rtol 1e-6 over a run of ~100 steps: 10·rtol relative per component
    // (atol 1e-10 plus rtol on y₂).
    for i in 0..3 {
        let bound = 10.0 * (1e-6 * exact[i] + 1e-10);
        assert!(
            (run.y[i] - exact[i]).abs() < bound,
            "component {i}: {} vs {}",
            run.y[i],
            exact[i]
        );
    }
    for r in &run.steps {
        assert!((r.y.sum() - 1.0).abs() < 1e-12, "mass {} at t = {}", r.y.sum(), r.t);
    }

    let long = integrate(
        (&robertson, &robertson_jac),
        0.0,
        y0,
        1e11,
        1e-6,
        tol(1e-6, 1e-10),
        10_000,
    )
    .unwrap();
    let steps = long.steps.len();
    assert!(steps > 373 / 2 && steps < 2 * 373, "{steps} steps vs SciPy's 373");
    assert!((long.y.sum() - 1.0).abs() < 1e-12);
    // Late on y₁ ≈ 2.08e-8 (reference 0.2083340149701255e-7 at 1e11, problem ROBER of the
    // Bari IVP test set, Mazzia & Magherini); its accuracy is governed by atol 1e-10, so
    // ±10·atol.
    assert!((long.y[0] - 2.083_340_149_701_255e-8).abs() < 1e-9, "{}", long.y[0]);
}

/// L-stability: y' = λ(y − cos t), λ = −1e8, from y(0) = 0, far off the slow manifold
/// y_p = (λ² cos t − λ sin t)/(1 + λ²) (the transient e^{λt} is below 1e-300 after t = 1e-5).
/// Radau IIA's stability function is R(z) = (1 + 2z/5 + z²/20)/(1 − 3z/5 + 3z²/20 − z³/60)
/// = −3/z + O(z⁻²): the first step leaves |y₁ − y_p| ≈ 3/(|λ|h₁)·|y₀ − y_p(0)| (3e-7 for
/// h₁ = 0.1), whereas an A-stable method with |R(∞)| = 1 (trapezoid, Gauss) keeps an O(1)
/// transient. Bound: 3/(|λ|h₁)·(1 + 1e-3) (the O(z⁻²) term is 1e-7 relative) + 1e-8 (the
/// Newton tolerance 1e-3·1e-6 and the O(1/λ) forcing error).
/// On the manifold the problem is the algebraic equation y = cos t in the stiff limit, which
/// a stiffly accurate method satisfies at every step end independently of h; the (γ/h − J)⁻¹
/// filter makes the estimate O(1/|hλ|), so h grows by the maximum factor 8 per step:
/// 0.1·(1 + 8 + 64) > 7, so 5 steps reach t = 10. Bound ≤ 10 steps, every h after the first
/// at least the first (no collapse), and the error stays below the first step's.
#[test]
fn l_stable_on_a_very_stiff_relaxation() {
    const LAMBDA: f64 = -1e8;
    let rhs = |t: f64, y: &SVector<f64, 1>| Ok(SVector::<f64, 1>::new(LAMBDA * (y[0] - t.cos())));
    let jac = |_t: f64, _y: &SVector<f64, 1>| Ok(SMatrix::<f64, 1, 1>::new(LAMBDA));
    let slow = |t: f64| (LAMBDA * LAMBDA * t.cos() - LAMBDA * t.sin()) / (1.0 + LAMBDA * LAMBDA);
    let run = integrate(
        (&rhs, &jac),
        0.0,
        SVector::<f64, 1>::zeros(),
        10.0,
        0.1,
        tol(1e-6, 1e-6),
        10,
    )
    .unwrap();
    let first = &run.steps[0];
    let bound = 3.0 / (LAMBDA.abs() * first.h) * (1.0 + 1e-3) * slow(0.0).abs() + 1e-8;
    for r in &run.steps {
        assert!(r.h >= first.h, "h = {:e} at t = {}", r.h, r.t);
        let err = (r.y[0] - slow(r.t + r.h)).abs();
        assert!(err <= bound, "off the manifold by {err:e} at t = {}", r.t + r.h);
    }
    // A constant Jacobian: it is never re-evaluated.
    assert_eq!(run.jac_evals, 1);
}

/// Nonlinear rotation y' = 10|y|²(−y₂, y₁) from (1, 0): y = (cos 10t, sin 10t).
fn rotation(_t: f64, y: &SVector<f64, 2>) -> Result<SVector<f64, 2>, StepError> {
    Ok(SVector::<f64, 2>::new(-y[1], y[0]) * (10.0 * y.norm_squared()))
}

fn rotation_jac(_t: f64, y: &SVector<f64, 2>) -> Result<SMatrix<f64, 2, 2>, StepError> {
    let r = y.norm_squared();
    Ok(SMatrix::<f64, 2, 2>::new(
        -20.0 * y[0] * y[1],
        -10.0 * r - 20.0 * y[1] * y[1],
        10.0 * r + 20.0 * y[0] * y[0],
        20.0 * y[0] * y[1],
    ))
}

fn rotation_exact(t: f64) -> SVector<f64, 2> {
    SVector::<f64, 2>::new((10.0 * t).cos(), (10.0 * t).sin())
}

/// The interpolant inside each step is the degree-3 collocation polynomial: its error is the
/// global error at the step start plus an O(h⁴) interpolation error of the same order as the
/// controlled local estimate (≤ tol per step). So inside the steps the error may exceed the
/// largest error at the step ends by at most a few tol: bound max_inside ≤ max_ends + 10·tol.
/// The bound has teeth: linear interpolation between the step ends (error ≈ (hω)²/8 ≈ 1e-3
/// at these steps) must violate it. The dense output must also be bitwise exact at s = 0, 1.
#[test]
fn dense_output_error_is_of_the_tolerance() {
    let rtol = 1e-7;
    let run = integrate(
        (&rotation, &rotation_jac),
        0.0,
        SVector::<f64, 2>::new(1.0, 0.0),
        2.0,
        1e-3,
        tol(rtol, rtol),
        10_000,
    )
    .unwrap();
    let mut y_start = SVector::<f64, 2>::new(1.0, 0.0);
    let mut ends = 0.0_f64;
    let mut inside = 0.0_f64;
    let mut linear = 0.0_f64;
    for r in &run.steps {
        assert_eq!(r.dense.eval(0.0), y_start);
        assert_eq!(r.dense.eval(1.0), r.y);
        ends = ends.max((r.y - rotation_exact(r.t + r.h)).amax());
        for k in 1..10 {
            let s = f64::from(k) / 10.0;
            let exact = rotation_exact(r.t + s * r.h);
            inside = inside.max((r.dense.eval(s) - exact).amax());
            linear = linear.max((y_start * (1.0 - s) + r.y * s - exact).amax());
        }
        y_start = r.y;
    }
    assert!(inside <= ends + 10.0 * rtol, "inside {inside:e}, ends {ends:e}");
    assert!(linear > ends + 10.0 * rtol, "linear {linear:e}");
}

/// The reported counts equal the calls made, step by step, and the per-attempt structure holds:
/// one real + one complex LU per attempt, 3 evaluations per Newton iteration, plus the
/// evaluation at the step start and at most one filtered estimate per attempt.
#[test]
fn counters_equal_the_calls_made() {
    let rhs_calls = Cell::new(0_u32);
    let jac_calls = Cell::new(0_u32);
    let rhs = |t: f64, y: &SVector<f64, 2>| {
        rhs_calls.set(rhs_calls.get() + 1);
        vdp(t, y)
    };
    let jac = |t: f64, y: &SVector<f64, 2>| {
        jac_calls.set(jac_calls.get() + 1);
        vdp_jac(t, y)
    };
    let mut mem = RadauMemory::default();
    let (mut t, mut y, mut h) = (0.0, SVector::<f64, 2>::new(2.0, -0.66), 1e-2);
    let mut rejected = 0;
    for _ in 0..300 {
        let (r0, j0) = (rhs_calls.get(), jac_calls.get());
        let acc = step(t, &y, h, tol(1e-5, 1e-5), None, &mut mem, rhs, jac).unwrap();
        assert_eq!(acc.rhs_evals, rhs_calls.get() - r0);
        assert_eq!(acc.jac_evals, jac_calls.get() - j0);
        let attempts = acc.rejected + 1;
        assert_eq!(acc.lu_decomps, 2 * attempts);
        assert!(acc.newton_iters <= 7 * attempts);
        // The start evaluation plus three per iteration.
        assert!(acc.rhs_evals > 3 * acc.newton_iters);
        assert!(acc.rhs_evals <= 1 + 3 * acc.newton_iters + attempts);
        rejected += acc.rejected;
        t += acc.h;
        y = acc.y;
        h = acc.h_next;
    }
    // The first step from h = 1e-2 on a problem with time scale 1e-6 must be rejected: the
    // run exercises the rejection paths, not only the happy one.
    assert!(rejected > 0);
}

/// A constant-Jacobian (linear, stiff) problem: Newton converges at once, so the Jacobian
/// from the first step is reused for the whole run.
#[test]
fn jacobian_is_reused_when_newton_contracts_fast() {
    // Eigenvalues −1 ± 10i and −1e4.
    let a = SMatrix::<f64, 3, 3>::new(-1.0, 10.0, 0.0, -10.0, -1.0, 0.0, 1.0, 1.0, -1e4);
    let rhs = move |_t: f64, y: &SVector<f64, 3>| Ok(a * y);
    let jac = move |_t: f64, _y: &SVector<f64, 3>| Ok(a);
    let run = integrate(
        (&rhs, &jac),
        0.0,
        SVector::<f64, 3>::new(1.0, 0.0, 1.0),
        5.0,
        1e-4,
        tol(1e-6, 1e-6),
        10_000,
    )
    .unwrap();
    assert!(run.steps.len() > 20);
    assert_eq!(run.jac_evals, 1);
    // Newton's first iteration solves a linear collocation system exactly; the second (if
    // any) measures a round-off rate. So at most two iterations per attempt.
    let attempts = run.steps.len() as u32 + run.rejected;
    assert!(run.newton_iters <= 2 * attempts);
    assert_eq!(run.lu_decomps, 2 * attempts);
}

/// Checkpoints: the memory and the state go through JSON together, and the restored run
/// continues its history (same work, unlike a cold start) and agrees with the uninterrupted
/// run. serde_json's default float parser may be 1 ulp off the printed value,
/// but deterministically, so the restored y and the memory's end point stay equal; the
/// 1-ulp input change moves the new state by a few ulp (the step map is Lipschitz with
/// constant ~1 + h·L, hL < 1 here): bound 1e-14.
#[test]
fn memory_round_trips_through_serde() {
    let mut mem = RadauMemory::default();
    let (t, y, h) = rotation_steps(&mut mem, 5);
    let json = serde_json::to_string(&(t, y, h, &mem)).unwrap();
    type Checkpoint = (f64, SVector<f64, 2>, f64, RadauMemory<2>);
    let (t_r, y_r, h_r, mut mem_r): Checkpoint = serde_json::from_str(&json).unwrap();
    let a = step(t, &y, h, tol(1e-6, 1e-6), None, &mut mem, rotation, rotation_jac).unwrap();
    let b = step(
        t_r,
        &y_r,
        h_r,
        tol(1e-6, 1e-6),
        None,
        &mut mem_r,
        rotation,
        rotation_jac,
    )
    .unwrap();
    assert_eq!(
        (a.rhs_evals, a.jac_evals, a.newton_iters, a.rejected),
        (b.rhs_evals, b.jac_evals, b.newton_iters, b.rejected)
    );
    assert!((a.y - b.y).amax() < 1e-14, "{} vs {}", a.y, b.y);
    // h_next ∝ err^{-1/4}, and err·tol ≈ 5e-7 is the remainder of terms e·Z/h of size
    // ≈ 10·|f| ≈ 100: an ε-relative input change moves err by ≈ 2e8·ε ≈ 4e-8 relative at
    // most, h_next by a quarter of that.
    assert!((a.h_next - b.h_next).abs() < 1e-8 * a.h_next);
    // The history mattered: a cold start (no Gustafsson ratio, no extrapolated start) proposes
    // a different next step.
    let mut cold = RadauMemory::default();
    let c = step(t, &y, h, tol(1e-6, 1e-6), None, &mut cold, rotation, rotation_jac).unwrap();
    assert!(
        (c.h_next - a.h_next).abs() > 1e-6 * a.h_next,
        "{} vs {}",
        c.h_next,
        a.h_next
    );
}

/// Checkpoints and parallel drivers hold the memory beside each state: the trait set is part
/// of the interface.
#[test]
fn memory_and_dense_output_have_the_checkpoint_traits() {
    fn holdable<T: Default + Clone + Send + Sync + serde::Serialize + serde::de::DeserializeOwned>() {}
    fn dense<T: Clone + std::fmt::Debug + Send + Sync + serde::Serialize>() {}
    holdable::<RadauMemory<12>>();
    holdable::<RadauMemory<15>>();
    dense::<RadauDense<15>>();
}

/// A memory from another trajectory (or after a driver changed y) is not continued: the step
/// starts cold and is as accurate as from a fresh memory.
#[test]
fn memory_from_another_point_starts_cold() {
    let mut mem = RadauMemory::default();
    let y0 = SVector::<f64, 2>::new(1.0, 0.0);
    let first = step(0.0, &y0, 1e-2, tol(1e-8, 1e-8), None, &mut mem, rotation, rotation_jac).unwrap();
    // Restart from the exact solution at another time.
    let t1 = 0.3;
    let y1 = rotation_exact(t1);
    let with_old = step(
        t1,
        &y1,
        first.h_next,
        tol(1e-8, 1e-8),
        None,
        &mut mem,
        rotation,
        rotation_jac,
    )
    .unwrap();
    let mut fresh = RadauMemory::default();
    let with_fresh = step(
        t1,
        &y1,
        first.h_next,
        tol(1e-8, 1e-8),
        None,
        &mut fresh,
        rotation,
        rotation_jac,
    )
    .unwrap();
    // Same h accepted, both within the local tolerance of the exact solution (the Newton
    // solves differ only by the Jacobian used, to within Newton's tolerance 0.03·1e-8·… ).
    let exact = rotation_exact(t1 + with_old.h);
    assert!((with_old.y - exact).amax() < 1e-7);
    assert!((with_fresh.y - rotation_exact(t1 + with_fresh.h)).amax() < 1e-7);
}

#[test]
fn invalid_step_sizes_and_tolerances_are_typed_errors() {
    let y = SVector::<f64, 2>::new(1.0, 0.0);
    let mut mem = RadauMemory::default();
    for h in [f64::NAN, 0.0, -1.0, f64::INFINITY] {
        let e = step(0.0, &y, h, tol(1e-6, 1e-6), None, &mut mem, rotation, rotation_jac).unwrap_err();
        assert!(
            matches!(e, StepError::Param(ParamError::NotPositive { name: "h", .. })),
            "{e}"
        );
    }
    let e = step(0.0, &y, 1e-20, tol(1e-6, 1e-6), None, &mut mem, rotation, rotation_jac).unwrap_err();
    assert!(matches!(e, StepError::StepSizeUnderflow { .. }), "{e}");
    // A zero rtol cannot even be built: `Tolerances` validates itself.
    let e = Tolerances::new(0.0, 1e-6, 1e-14).unwrap_err();
    assert!(matches!(e, ParamError::NotPositive { name: "rtol", .. }), "{e}");
    let e = step(
        0.0,
        &SVector::<f64, 2>::new(f64::NAN, 0.0),
        1e-3,
        tol(1e-6, 1e-6),
        None,
        &mut mem,
        rotation,
        rotation_jac,
    )
    .unwrap_err();
    assert!(matches!(e, StepError::NonFinite { .. }), "{e}");
    let nan_jac = |_t: f64, _y: &SVector<f64, 2>| Ok(SMatrix::<f64, 2, 2>::repeat(f64::NAN));
    let e = step(0.0, &y, 1e-3, tol(1e-6, 1e-6), None, &mut mem, rotation, nan_jac).unwrap_err();
    assert!(matches!(e, StepError::NonFinite { what: "Jacobian", .. }), "{e}");
}

/// An rhs that is NaN everywhere fails at the step start; one that fails at every trial state
/// (NaN values or an inverted particle) is rejected and shrunk a bounded number of times and
/// ends in a typed underflow; any other error propagates at once. The call count proves the
/// bound: 1 start evaluation + ≤ 3 per rejected attempt (Newton stops at the first failed
/// stage) for at most 50 attempts.
#[test]
fn failing_right_hand_sides_end_in_typed_errors() {
    let y = SVector::<f64, 2>::new(1.0, 0.0);
    let jac = |_t: f64, _y: &SVector<f64, 2>| Ok(SMatrix::<f64, 2, 2>::identity());
    let mut mem = RadauMemory::default();

    let nan = |_t: f64, _y: &SVector<f64, 2>| Ok(SVector::<f64, 2>::repeat(f64::NAN));
    let e = step(0.0, &y, 1e-2, tol(1e-6, 1e-6), None, &mut mem, nan, jac).unwrap_err();
    assert!(matches!(e, StepError::NonFinite { .. }), "{e}");

    let failures: [(&str, StepError); 2] = [
        ("nan", StepError::NonFinite { what: "test", t: 0.0 }),
        ("inverted", StepError::Inverted { det_f: -1.0, t: 0.0 }),
    ];
    for (name, failure) in failures {
        let calls = Cell::new(0_u32);
        // Fine at the step start (t = 0, y) only: every stage time is later.
        let rhs = |t: f64, x: &SVector<f64, 2>| {
            calls.set(calls.get() + 1);
            if t == 0.0 && *x == y {
                Ok(SVector::<f64, 2>::new(0.0, 1.0))
            } else if name == "nan" {
                Ok(SVector::<f64, 2>::repeat(f64::NAN))
            } else {
                Err(failure.clone())
            }
        };
        let e = step(0.0, &y, 1e-2, tol(1e-6, 1e-6), None, &mut mem, rhs, jac).unwrap_err();
        assert!(matches!(e, StepError::StepSizeUnderflow { .. }), "{name}: {e}");
        assert!(calls.get() <= 1 + 3 * 50, "{name}: {} calls", calls.get());
        assert_eq!(mem, RadauMemory::default(), "{name}: memory not cold");
    }

    let outside = |t: f64, x: &SVector<f64, 2>| {
        if t == 0.0 && *x == y {
            Ok(SVector::<f64, 2>::new(0.0, 1.0))
        } else {
            Err(StepError::Flow(FlowError::OutsideDomain { x: [x[0], x[1], 0.0] }))
        }
    };
    let e = step(0.0, &y, 1e-2, tol(1e-6, 1e-6), None, &mut mem, outside, jac).unwrap_err();
    assert!(matches!(e, StepError::Flow(FlowError::OutsideDomain { .. })), "{e}");
}

/// Work counts of the stiff reference runs, snapshotted so that any change of the controller,
/// the Newton policy or the Jacobian reuse shows up in review (integer counts of deterministic
/// code; the bounds above say what is acceptable, this says what changed).
/// A regression guard, not a check.
#[test]
fn work_counts_snapshot() {
    let mut rows = vec![format!(
        "{:<12} {:>6} {:>6} {:>5} {:>6} {:>5} {:>5} {:>6}",
        "problem", "rtol", "steps", "rej", "rhs", "jac", "lu", "newton"
    )];
    let mut row = |name: &str, rtol: f64, steps: usize, r: (u32, u32, u32, u32, u32)| {
        rows.push(format!(
            "{name:<12} {rtol:>6.0e} {steps:>6} {:>5} {:>6} {:>5} {:>5} {:>6}",
            r.0, r.1, r.2, r.3, r.4
        ));
    };
    for rtol in [1e-4, 1e-6, 1e-8] {
        let run = integrate(
            (&vdp, &vdp_jac),
            0.0,
            SVector::<f64, 2>::new(2.0, -0.66),
            2.0,
            1e-6,
            tol(rtol, rtol),
            100_000,
        )
        .unwrap();
        let counts = (
            run.rejected,
            run.rhs_evals,
            run.jac_evals,
            run.lu_decomps,
            run.newton_iters,
        );
        row("vdp_1e-6", rtol, run.steps.len(), counts);
    }
    for rtol in [1e-6, 1e-8] {
        let run = integrate(
            (&robertson, &robertson_jac),
            0.0,
            SVector::<f64, 3>::new(1.0, 0.0, 0.0),
            1e11,
            1e-6,
            tol(rtol, rtol * 1e-4),
            100_000,
        )
        .unwrap();
        let counts = (
            run.rejected,
            run.rhs_evals,
            run.jac_evals,
            run.lu_decomps,
            run.newton_iters,
        );
        row("robertson", rtol, run.steps.len(), counts);
    }
    insta::assert_snapshot!(rows.join("\n"));
}

/// A driver that clips one step to hit an output time and then resumes with the step size it
/// had before must not pay for it: the tiny step's polynomial extrapolated over 1e10 of its
/// lengths amplifies the round-off ε·|Z| of its stage values by s³ = 1e30 and would be a
/// useless Newton start (6 rejections before this test existed), so the step
/// starts from Z = 0 and is accepted at the first try, like the unclipped step.
#[test]
fn resuming_after_a_clipped_step_needs_no_rejection() {
    let mut mem = RadauMemory::default();
    let (mut t, mut y, h) = rotation_steps(&mut mem, 10);
    let clipped = step(
        t,
        &y,
        h * 1e-10,
        tol(1e-6, 1e-6),
        None,
        &mut mem,
        rotation,
        rotation_jac,
    )
    .unwrap();
    t += clipped.h;
    y = clipped.y;
    let resumed = step(t, &y, h, tol(1e-6, 1e-6), None, &mut mem, rotation, rotation_jac).unwrap();
    assert_eq!(resumed.rejected, 0);
}

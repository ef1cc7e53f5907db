//! Independent reference computations used only by tests.

/// ∫₀^∞ f(λ) dλ by exp-sinh (double-exponential) quadrature, λ = exp(π/2 · sinh t), refined by
/// halving h until two successive levels agree to 1e-15 relative. Independent of Carlson's
/// duplication; integrands here are smooth on [0, ∞) and decay at least like λ^{-3/2}.
pub fn exp_sinh<F: Fn(f64) -> f64>(f: F) -> f64 {
    let half_pi = std::f64::consts::FRAC_PI_2;
    let term = |t: f64| {
        let lam = (half_pi * t.sinh()).exp();
        let w = lam * half_pi * t.cosh();
        let v = f(lam) * w;
        if v.is_finite() { v } else { 0.0 }
    };
    let t_max = 6.5;
    let mut h = 0.5;
    let mut prev = {
        let n = (t_max / h) as i64;
        h * (-n..=n).map(|i| term(i as f64 * h)).sum::<f64>()
    };
    for _ in 0..10 {
        h /= 2.0;
        let n = (t_max / h) as i64;
        // reuse: new estimate = prev/2 + h * (odd nodes)
        let odd: f64 = (-n..=n).filter(|i| i % 2 != 0).map(|i| term(i as f64 * h)).sum();
        let next = 0.5 * prev + h * odd;
        if (next - prev).abs() <= 1e-15 * next.abs() {
            return next;
        }
        prev = next;
    }
    prev
}

/// Jeffery integrals by quadrature: (χ₀, α, α', α'') for semi-axes r.
pub fn integrals_by_quadrature(r: [f64; 3]) -> (f64, [f64; 3], [f64; 3], [f64; 3]) {
    let x = r.map(|a| a * a);
    let delta = |l: f64| ((x[0] + l) * (x[1] + l) * (x[2] + l)).sqrt();
    let chi0 = exp_sinh(|l| 1.0 / delta(l));
    let alpha = [0, 1, 2].map(|i| exp_sinh(|l| 1.0 / ((x[i] + l) * delta(l))));
    let alpha_p = [0, 1, 2].map(|k| {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        exp_sinh(|l| 1.0 / ((x[i] + l) * (x[j] + l) * delta(l)))
    });
    let alpha_pp = [0, 1, 2].map(|k| {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        exp_sinh(|l| l / ((x[i] + l) * (x[j] + l) * delta(l)))
    });
    (chi0, alpha, alpha_p, alpha_pp)
}

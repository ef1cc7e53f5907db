//! Poiseuille's profile around a bend (`flow::bend_poiseuille`) against what defines it.

use pseudorigid::error::FlowError;
use pseudorigid::flow::FlowField;
use pseudorigid::flow::bend_poiseuille::BendPoiseuille;
use pseudorigid::tensor::Vec3;

/// ∇u is the derivative of u (fourth-order central differences over h = 10⁻³ a: truncation
/// h⁴|∂⁵u| is nil for the quadratic f and ~10⁻¹³ U/a for the 1/ρ of e_φ, round-off ~10⁻¹³ U/a,
/// asserted at 10⁻¹⁰ U/a), tr ∇u = 0 to round-off, |u| = 2U(1 − r²/a²) along e_φ, and the
/// convective acceleration is the centripetal −(|u|²/ρ) e_ρ; at points over the whole
/// cross-section and around the bend. A sign or an index slip is an O(U/a) miss.
#[test]
fn the_bend_poiseuille_gradient_is_the_derivative_of_its_velocity_and_traceless() {
    let (rb, a, mean) = (5.7, 1.0, 1.3);
    let field = BendPoiseuille::new(rb, a, mean).unwrap();
    let h = 1e-3 * a;
    let at = |x: Vec3| field.sample(&x, 0.0).unwrap();
    for n in 0..40 {
        let phi = 0.2 * f64::from(n);
        let (r, psi) = (0.95 * a * (f64::from(n % 7) / 6.0), 0.9 * f64::from(n));
        let rho = rb + r * psi.cos();
        let x = Vec3::new(rho * phi.cos(), rho * phi.sin(), r * psi.sin());
        let s = at(x);
        let fd = crate::common::gradient_by_differences(&field, &x, h);
        assert!(
            (s.grad_u - fd).amax() < 1e-10 * mean / a,
            "{x}: {} against {fd}",
            s.grad_u
        );
        assert!(
            s.grad_u.trace().abs() < 1e-13 * mean / a,
            "{x}: tr ∇u = {:e}",
            s.grad_u.trace()
        );
        let speed = 2.0 * mean * (1.0 - r * r / (a * a));
        let e_phi = Vec3::new(-phi.sin(), phi.cos(), 0.0);
        assert!((s.u - speed * e_phi).amax() < 1e-13 * mean, "{x}: u = {}", s.u);
        let e_rho = Vec3::new(phi.cos(), phi.sin(), 0.0);
        let centripetal = -speed * speed / rho * e_rho;
        assert!(
            (s.convective - centripetal).amax() < 1e-12 * mean * mean / a,
            "{x}: (u·∇)u = {}",
            s.convective
        );
    }
}

#[test]
fn a_bend_poiseuille_flow_ends_at_its_wall_and_checks_its_parameters() {
    let field = BendPoiseuille::new(4.0, 1.0, 1.0).unwrap();
    for outside in [
        Vec3::new(5.01, 0.0, 0.0),
        Vec3::new(2.99, 0.0, 0.0),
        Vec3::new(0.0, 4.0, 1.01),
    ] {
        assert!(matches!(
            field.sample(&outside, 0.0),
            Err(FlowError::OutsideDomain { .. })
        ));
    }
    assert_eq!(field.sample(&Vec3::new(5.0, 0.0, 0.0), 0.0).unwrap().u, Vec3::zeros());
    assert!(BendPoiseuille::new(1.0, 1.0, 1.0).is_err());
    assert!(BendPoiseuille::new(5.7, 0.0, 1.0).is_err());
    assert!(BendPoiseuille::new(5.7, 1.0, f64::NAN).is_err());
    assert!(BendPoiseuille::new(5.7, 1.0, f64::MAX).is_err());
}

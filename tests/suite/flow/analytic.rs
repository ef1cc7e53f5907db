//! Analytic fields (`flow::analytic`) against what defines them.

use pseudorigid::flow::FlowField;
use pseudorigid::flow::analytic::Cellular;
use pseudorigid::tensor::Vec3;

/// The cellular flow's ∇u is the derivative of its u (fourth-order central differences over
/// h = 10⁻³ L: truncation h⁴|∂⁵u|/30 ≈ 3·10⁻¹⁴ U/L, round-off 18·10⁻¹⁶ U/(12h) ≈ 1.5·10⁻¹³ U/L,
/// asserted at 10⁻¹¹ U/L), and u is divergence-free: tr ∇u = 0 to round-off. A sign or an index
/// slip in any entry is an O(U/L) miss.
#[test]
fn the_cellular_flow_gradient_is_the_derivative_of_its_velocity_and_traceless() {
    let field = Cellular::new(1.7, 0.3).unwrap();
    let (u, l) = (field.speed, field.length);
    let h = 1e-3 * l;
    let at = |x: Vec3| field.sample(&x, 0.0).unwrap();
    for n in 0..50 {
        let x = Vec3::new(
            0.37 * f64::from(n),
            1.0 - 0.11 * f64::from(n),
            0.05 * f64::from(n * n % 17),
        );
        let s = at(x);
        let fd = crate::common::gradient_by_differences(&field, &x, h);
        assert!((s.grad_u - fd).amax() < 1e-11 * u / l, "{x}: {} against {fd}", s.grad_u);
        assert!(
            s.grad_u.trace().abs() < 1e-14 * u / l,
            "{x}: tr ∇u = {:e}",
            s.grad_u.trace()
        );
    }
}

#[test]
fn a_cellular_flow_needs_a_finite_speed_and_a_positive_length() {
    assert!(Cellular::new(f64::NAN, 1.0).is_err());
    assert!(Cellular::new(1.0, 0.0).is_err());
    assert!(Cellular::new(1.0, -1.0).is_err());
    assert!(Cellular::new(1.0, f64::INFINITY).is_err());
}

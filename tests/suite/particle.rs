//! The particle's constant data (`particle::model`): what its constructors refuse.
use pseudorigid::error::ParamError;
use pseudorigid::particle::model::FLUID_RANGE;
use pseudorigid::prelude::*;

/// Issue 38, item 6: a fluid's viscosity and non-zero density must lie in `FLUID_RANGE`
/// (10⁻⁵⁰ to 10⁵⁰, tens of orders around any physical fluid in any units); f64::MAX was
/// accepted. The error names the parameter and carries the value and the range; the range's
/// ends, ρ_f = 0, water and air are accepted.
#[test]
fn fluid_parameters_outside_the_physical_range_are_refused() {
    let (min, max) = FLUID_RANGE;
    for (mu, rho, name) in [
        (f64::MAX, 1.0, "mu_f"),
        (1e51, 1.0, "mu_f"),
        (1e-51, 1.0, "mu_f"),
        (0.0, 1.0, "mu_f"),
        (f64::NAN, 1.0, "mu_f"),
        (1.0, f64::MAX, "rho_f"),
        (1.0, 1e-300, "rho_f"),
        (1.0, -1.0, "rho_f"),
        (1.0, f64::INFINITY, "rho_f"),
    ] {
        match Fluid::new(mu, rho) {
            Err(ParamError::OutOfRange {
                name: n,
                value,
                min: lo,
                max: hi,
            }) => {
                assert!(n.starts_with(name), "{mu:e}, {rho:e}: {n}");
                let given = if name == "mu_f" { mu } else { rho };
                assert!(value == given || value.is_nan() && given.is_nan(), "{value} vs {given}");
                assert_eq!((lo, hi), (min, max));
            }
            other => panic!("μ_f = {mu:e}, ρ_f = {rho:e}: {other:?}"),
        }
    }
    for (mu, rho) in [(min, 0.0), (max, max), (1e-3, 1000.0), (1.81e-5, 1.2), (1.0, min)] {
        assert!(Fluid::new(mu, rho).is_ok(), "μ_f = {mu:e}, ρ_f = {rho:e}");
    }
}

//! Jeffery–Roscoe traction, Brenner drag and gravity (src/hydro).

mod forces;

use crate::common;

use approx::assert_relative_eq;
use common::strategies;
use nalgebra::Matrix3;
use proptest::prelude::*;
use pseudorigid::hydro::gravity::reduced_gravity;
use pseudorigid::prelude::*;
use pseudorigid::tensor::{dev, skw, sym};

fn traction_for(r: [f64; 3], q: &Mat3) -> JefferyRoscoe {
    // F̄ = Qᵀ diag(r): principal directions are the rows of q.
    JefferyRoscoe::from_total_distortion(&(q.transpose() * Mat3::from_diagonal(&Vec3::from(r))))
}

/// Torque-free solid spin of a rigid ellipsoid (Jeffery 1922), in principal components:
/// w_s,ij = w_f,ij − ((x_i − x_j)/(x_i + x_j)) d_f,ij.
fn jeffery_spin(frame: &PrincipalFrame, l_f: &Mat3) -> Mat3 {
    let lf = frame.to_principal(l_f);
    let (d, w) = (sym(&lf), skw(&lf));
    let x = frame.r.component_mul(&frame.r);
    let ws = Mat3::from_fn(|i, j| {
        if i == j {
            0.0
        } else {
            w[(i, j)] - (x[i] - x[j]) / (x[i] + x[j]) * d[(i, j)]
        }
    });
    frame.to_global(&ws)
}

proptest! {
    /// Sphere: σ̃ = 2μ d_s + 5μ d + 3μ w exactly (Jeffery 1922, Roscoe 1967). Integrals are exact to
    /// ~1e-15 at the degenerate point, so 1e-12 of the stress scale is round-off with margin.
    #[test]
    fn sphere_stress_identity(a in 0.2f64..3.0, q in strategies::rotation(),
                              ls in strategies::traceless(1.0), lf in strategies::traceless(1.0), mu in 0.1f64..10.0) {
        let tr = traction_for([a, a, a], &q);
        let sigma = tr.sigma_tilde(&ls, &lf, mu, VolumetricTraction::Paper);
        let g = lf - ls;
        let expected = (sym(&ls) * 2.0 + dev(&sym(&g)) * 5.0 + skw(&g) * 3.0) * mu;
        let scale = expected.abs().max().max(mu);
        prop_assert!((sigma - expected).abs().max() <= 1e-12 * scale, "{sigma} vs {expected}");
    }

    /// A rigid ellipsoid spinning at Jeffery's rate feels no torque: skw σ̃ = 0. The check is
    /// independent of the s-coefficients (Jeffery's spin comes from his 1922 paper); the
    /// tolerance is round-off relative to |σ̃|.
    #[test]
    fn torque_free_at_jeffery_rate(r in strategies::semi_axes(8.0), q in strategies::rotation(), lf in strategies::traceless(1.0)) {
        let tr = traction_for(r, &q);
        let w_s = jeffery_spin(tr.frame(), &lf);
        let sigma = tr.sigma_tilde(&w_s, &lf, 1.0, VolumetricTraction::Paper);
        prop_assert!(skw(&sigma).abs().max() <= 1e-11 * sigma.abs().max().max(1.0));
    }

    /// Objectivity: rotating the particle and the flow together rotates σ̃ and K̂.
    #[test]
    fn objectivity_of_traction_and_drag(r in strategies::semi_axes(6.0), q in strategies::rotation(), rot in strategies::rotation(),
                                        ls in strategies::matrix(1.0), lf in strategies::traceless(1.0)) {
        let fbar = q.transpose() * Mat3::from_diagonal(&Vec3::from(r));
        let a = JefferyRoscoe::from_total_distortion(&fbar);
        let b = JefferyRoscoe::from_total_distortion(&(rot * fbar));
        for vol in [VolumetricTraction::Paper, VolumetricTraction::Dev, VolumetricTraction::Source] {
            let sa = a.sigma_tilde(&ls, &lf, 1.0, vol);
            let sb = b.sigma_tilde(&(rot * ls * rot.transpose()), &(rot * lf * rot.transpose()), 1.0, vol);
            prop_assert!((rot * sa * rot.transpose() - sb).abs().max() <= 1e-11 * sa.abs().max().max(1.0));
        }
        let ka = Brenner.resistance(a.frame(), &EllipsoidIntegrals::new(&a.frame().r));
        let kb = Brenner.resistance(b.frame(), &EllipsoidIntegrals::new(&b.frame().r));
        prop_assert!((rot * ka * rot.transpose() - kb).abs().max() <= 1e-12 * ka.abs().max());
    }

    /// σ̃ and K̂ ignore the sign, order and degenerate choice of eigenvectors, as long as each
    /// r_a stays paired with its n_a (eigenvector signs carry no meaning).
    #[test]
    fn invariance_under_eigenvector_choice(r in strategies::semi_axes(6.0), q in strategies::rotation(),
                                           perm in 0usize..6, signs in proptest::array::uniform3(proptest::bool::ANY),
                                           ls in strategies::matrix(1.0), lf in strategies::traceless(1.0)) {
        let base = PrincipalFrame { r: Vec3::from(r), q };
        let order = [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]][perm];
        let mut q2 = Mat3::zeros();
        let mut r2 = Vec3::zeros();
        for (a, &i) in order.iter().enumerate() {
            let s = if signs[a] { -1.0 } else { 1.0 };
            q2.set_row(a, &(q.row(i) * s));
            r2[a] = r[i];
        }
        let other = PrincipalFrame { r: r2, q: q2 };
        let (ia, ib) = (EllipsoidIntegrals::new(&base.r), EllipsoidIntegrals::new(&other.r));
        let sa = JefferyRoscoe::new(&base, &ia).sigma_tilde(&ls, &lf, 1.0, VolumetricTraction::Paper);
        let sb = JefferyRoscoe::new(&other, &ib).sigma_tilde(&ls, &lf, 1.0, VolumetricTraction::Paper);
        prop_assert!((sa - sb).abs().max() <= 1e-12 * sa.abs().max().max(1.0));
        let (ka, kb) = (Brenner.resistance(&base, &ia), Brenner.resistance(&other, &ib));
        prop_assert!((ka - kb).abs().max() <= 1e-13 * ka.abs().max());
    }

    /// For a sphere any orthonormal basis is an eigenbasis: σ̃ may not depend on which one.
    #[test]
    fn sphere_is_basis_independent(q1 in strategies::rotation(), q2 in strategies::rotation(),
                                   ls in strategies::matrix(1.0), lf in strategies::traceless(1.0)) {
        let ints = EllipsoidIntegrals::new(&Vec3::repeat(0.5));
        let s1 = JefferyRoscoe::new(&PrincipalFrame { r: Vec3::repeat(0.5), q: q1 }, &ints).sigma_tilde(&ls, &lf, 1.0, VolumetricTraction::Source);
        let s2 = JefferyRoscoe::new(&PrincipalFrame { r: Vec3::repeat(0.5), q: q2 }, &ints).sigma_tilde(&ls, &lf, 1.0, VolumetricTraction::Source);
        prop_assert!((s1 - s2).abs().max() <= 1e-12 * s1.abs().max().max(1.0));
    }

    /// The inertialess solve satisfies its defining equations: dev σ̃(l_s) = dev σ_el, tr l_s = 0.
    #[test]
    fn inertialess_solution_satisfies_balance(r in strategies::semi_axes(6.0), q in strategies::rotation(),
                                              sig in strategies::matrix(2.0), lf in strategies::traceless(1.0)) {
        let tr = traction_for(r, &q);
        let sigma_el = sym(&sig);
        let ls = tr.inertialess(&lf, 1.3).unwrap().velocity_gradient(&sigma_el);
        prop_assert!(ls.trace().abs() <= 1e-12 * ls.abs().max().max(1.0));
        let residual = dev(&tr.sigma_tilde(&ls, &lf, 1.3, VolumetricTraction::Dev)) - dev(&sigma_el);
        prop_assert!(residual.abs().max() <= 1e-11 * sigma_el.abs().max().max(1.0));
    }
}

/// A sphere's inertialess solution in closed form: with σ̃ = μ(5d + 3w + 2 dev d_s) and
/// tr l_s = 0, dev σ̃ = dev σ_el gives d_s = (5 d_f − dev σ_el/μ)/3 and w_s = w_f, in any basis.
#[test]
fn sphere_inertialess_solution_in_closed_form() {
    let q = nalgebra::Rotation3::from_euler_angles(0.3, -1.1, 2.0).into_inner();
    let tr = traction_for([0.7, 0.7, 0.7], &q);
    let lf = Mat3::new(0.2, -1.3, 0.4, 0.9, 0.5, -0.2, 0.1, 0.6, -0.7);
    let sigma_el = sym(&Mat3::new(1.5, 0.3, -0.8, 0.2, -0.4, 0.6, 0.9, 0.1, 2.2));
    let mu = 1.7;
    let ls = tr.inertialess(&lf, mu).unwrap().velocity_gradient(&sigma_el);
    let expected = (dev(&sym(&lf)) * 5.0 - dev(&sigma_el) / mu) / 3.0 + skw(&lf);
    assert!(
        (ls - expected).abs().max() <= 1e-13 * expected.abs().max(),
        "{ls} against {expected}"
    );
}

/// The normal-stress functions of a rigid-surface-free torque-free ellipsoid reproduce
/// Roscoe's I and J (Jeffery 1922, Roscoe 1967) in units abc = 1.
#[test]
fn roscoe_normal_stress_functions() {
    let r = [1.6, 0.9, 1.0 / (1.6 * 0.9)];
    let tr = traction_for(r, &Mat3::identity());
    let e = 0.7;
    let lf = Mat3::from_diagonal(&Vec3::new(e, -e, 0.0));
    let s = tr.sigma_tilde(&Mat3::zeros(), &lf, 1.0, VolumetricTraction::Paper);
    let ints = EllipsoidIntegrals::new(&Vec3::from(r));
    let app = ints.alpha_pp;
    let sig2 = app[0] * app[1] + app[1] * app[2] + app[2] * app[0];
    let (i_fn, j_fn) = (0.4 * (app[0] + app[1]) / sig2, 0.4 * (app[0] - app[1]) / sig2);
    assert_relative_eq!(s[(0, 0)] - s[(1, 1)], 10.0 * i_fn * e, max_relative = 1e-12);
    assert_relative_eq!(
        s[(0, 0)] + s[(1, 1)] - 2.0 * s[(2, 2)],
        10.0 * j_fn * e,
        max_relative = 1e-12
    );
}

/// Volumetric variants differ only in the isotropic part, by the amounts of the `VolumetricTraction` docs.
#[test]
fn volumetric_variants() {
    let tr = traction_for([1.2, 0.8, 1.0 / 0.96], &Mat3::identity());
    let ls = Mat3::identity() * 0.3; // pure expansion, tr d_s = 0.9
    let lf = Mat3::zeros();
    let p = tr.sigma_tilde(&ls, &lf, 1.0, VolumetricTraction::Paper);
    let d = tr.sigma_tilde(&ls, &lf, 1.0, VolumetricTraction::Dev);
    let s = tr.sigma_tilde(&ls, &lf, 1.0, VolumetricTraction::Source);
    assert_relative_eq!(p - d, Mat3::identity() * (2.0 / 3.0 * 0.9), epsilon = 1e-14);
    assert_relative_eq!(s - d, Mat3::identity() * (-4.0 / 3.0 * 0.9), epsilon = 1e-14);
}

fn k_principal(r: [f64; 3]) -> Vec3 {
    let frame = PrincipalFrame {
        r: Vec3::from(r),
        q: Mat3::identity(),
    };
    Brenner::k_principal(&frame, &EllipsoidIntegrals::new(&frame.r))
}

#[test]
fn drag_sphere_is_six() {
    assert_relative_eq!(k_principal([0.7, 0.7, 0.7]), Vec3::repeat(6.0), max_relative = 1e-14);
    // and StokesSphere gives 6π a for any shape of the same volume
    let frame = PrincipalFrame {
        r: Vec3::new(2.0, 1.0, 0.5),
        q: Mat3::identity(),
    };
    let k = StokesSphere.resistance(&frame, &EllipsoidIntegrals::new(&frame.r));
    assert_relative_eq!(
        k,
        Matrix3::identity() * 6.0 * std::f64::consts::PI,
        max_relative = 1e-14
    );
}

/// Brenner (1963): tables printed to 6 significant digits, so the tolerance is
/// half a unit in the last printed digit relative to the value (≤ 1e-5).
#[test]
fn drag_matches_reference_tables() {
    let table = include_str!("../../../reference-data/drag_brenner_spheroids.csv");
    let mut rows = 0;
    for line in table.lines().filter(|l| !l.starts_with('#') && !l.starts_with("shape")) {
        let c: Vec<&str> = line.split(',').collect();
        let r: Vec<f64> = c[1..4].iter().map(|v| v.parse().unwrap()).collect();
        let k = k_principal([r[0], r[1], r[2]]);
        for a in 0..3 {
            let expected: f64 = c[4 + a].parse().unwrap();
            assert_relative_eq!(k[a], expected, max_relative = 1e-5);
        }
        rows += 1;
    }
    assert!(rows >= 15, "table has {rows} rows");
}

#[test]
fn drag_closed_forms_prolate() {
    // Gallily–Cohen / Zhang et al. closed forms (Brenner 1963), independent of the integrals.
    for beta in [1.5f64, 4.0, 14.0] {
        let s = (beta * beta - 1.0).sqrt();
        let ln = (beta + s).ln();
        let kxx = 16.0 * (beta * beta - 1.0) / ((2.0 * beta * beta - 3.0) / s * ln + beta);
        let kzz = 8.0 * (beta * beta - 1.0) / ((2.0 * beta * beta - 1.0) / s * ln - beta);
        let k = k_principal([beta, 1.0, 1.0]);
        assert_relative_eq!(k[0], kzz, max_relative = 1e-12);
        assert_relative_eq!(k[1], kxx, max_relative = 1e-12);
    }
}

#[test]
fn buoyancy_factor() {
    let g = Vec3::new(0.0, 0.0, -9.81);
    assert_relative_eq!(reduced_gravity(&g, 2000.0, 1000.0, 1.0), g * 0.5);
    // ρ_t = ρ₀/J: an expanded particle is lighter
    assert_relative_eq!(reduced_gravity(&g, 2000.0, 1000.0, 2.0), Vec3::zeros());
}

#[test]
fn mean_response_time_ratio_of_spheroids() {
    use pseudorigid::hydro::drag::mean_response_time_ratio;
    // A sphere's response time is its own: the ratio is 1 up to round-off.
    assert_relative_eq!(
        mean_response_time_ratio(&Vec3::repeat(0.7)).unwrap(),
        1.0,
        max_relative = 1e-14
    );
    // Prolates λ = 2, 5, 20 of unit volume-equivalent radius: (a_eq/8)(3χ₀ + Σ x_i α_i) with the
    // integrals by adaptive quadrature (SciPy `quad`, independent of the Carlson route; its
    // error is below 1e-10, so 1e-9 relative).
    for (lambda, quadrature) in [
        (2.0, 0.957_975_925_942_851_6),
        (5.0, 0.800_167_264_606_542_2),
        (20.0, 0.501_199_955_572_886_7),
    ] {
        let c = (1.0_f64 / lambda).cbrt();
        let r = Vec3::new(lambda * c, c, c);
        assert_relative_eq!(mean_response_time_ratio(&r).unwrap(), quadrature, max_relative = 1e-9);
        // The same through the drag model's tensor in a rotated frame: 6π a_eq tr(K̂⁻¹)/3.
        let q = nalgebra::Rotation3::from_euler_angles(0.3, -1.1, 2.0).into_inner();
        let frame = PrincipalFrame { r, q };
        let k = Brenner.resistance(&frame, &EllipsoidIntegrals::new(&r));
        let mobility = k.try_inverse().unwrap().trace() / 3.0;
        assert_relative_eq!(
            mean_response_time_ratio(&r).unwrap(),
            6.0 * std::f64::consts::PI * mobility,
            max_relative = 1e-12
        );
    }
    assert!(mean_response_time_ratio(&Vec3::new(1.0, f64::NAN, 1.0)).is_err());
}

/// Reliability defect 4, traction coefficients: fed the NaN integrals of an invalid ellipsoid
/// (what `EllipsoidIntegrals::new` returns for it) or a non-finite F̄, the checked forms refuse
/// with a typed error; on a valid ellipsoid they equal the hot-path coefficients bitwise.
#[test]
fn checked_traction_coefficients_refuse_bad_input() {
    let frame = PrincipalFrame::from_total_distortion(&Mat3::identity());
    let nan_ints = EllipsoidIntegrals::new(&Vec3::new(f64::NAN, 1.0, 1.0));
    assert!(matches!(
        JefferyRoscoe::try_new(&frame, &nan_ints),
        Err(ParamError::Derived { .. })
    ));
    for f_bar in [
        Mat3::identity() * f64::NAN,
        Mat3::identity() * f64::INFINITY,
        Mat3::zeros(),
    ] {
        assert!(JefferyRoscoe::try_from_total_distortion(&f_bar).is_err(), "{f_bar}");
    }
    let f_bar = Mat3::from_diagonal(&Vec3::new(2.0, 1.0, 0.5));
    assert_eq!(
        JefferyRoscoe::try_from_total_distortion(&f_bar).unwrap(),
        JefferyRoscoe::from_total_distortion(&f_bar)
    );
}

//! The one shape-family type ([`Shape`]) and its placements: every scene builds, bit for bit,
//! the semi-axes, orientation, labels and d_eq that its own shape type built before the types
//! were merged (the shear scenes' `(flow, gradient, vorticity)` ratios, the real-flow scenes'
//! body ratios, the pipe's λ₁, λ₂ and r₃). The expected values are the old code's arithmetic
//! written out on literal ratios, so any change of ratio order, scaling or placement that moves
//! a dataset by one ulp fails here.

use pseudorigid::ellipsoid::Ellipsoid;
use pseudorigid::particle::ShearScaling;
use pseudorigid::studies::particles::Shape;
use pseudorigid::studies::pipe::{PipeParticleData, PipeSetup};
use pseudorigid::studies::shear_shape::ShearShape;
use pseudorigid::tensor::Mat3;

/// The old scaling to d_eq, `Ellipsoid::with_volume_diameter` as it read when each scene
/// called it with its own ratios: cube roots first, one common factor.
fn old_semi_axes(ratios: [f64; 3], d_eq: f64) -> [f64; 3] {
    let scale = 0.5 * d_eq / (ratios[0].cbrt() * ratios[1].cbrt() * ratios[2].cbrt());
    ratios.map(|r| r * scale)
}

fn bits(v: [f64; 3]) -> [u64; 3] {
    v.map(f64::to_bits)
}

fn semi_axes(e: &Ellipsoid) -> [f64; 3] {
    e.semi_axes().into()
}

/// Fig. 7 aspect ratios, the work-precision Jeffery prolate (5) and the Fig. 4 oblate (2.5).
const SHEAR_ASPECTS: [f64; 10] = [1.25, 1.5, 1.75, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0];

/// Fig. 8 sections: (ω₁, ω₂) = (0.5, 0.1 … 1) and (0.1 … 0.9, 0.5).
fn fig8_triaxials() -> Vec<(f64, f64)> {
    let tenths = |from: u32, to: u32| (from..=to).map(|i| f64::from(i) / 10.0);
    tenths(1, 10)
        .map(|w2| (0.5, w2))
        .chain(tenths(1, 9).map(|w1| (w1, 0.5)))
        .collect()
}

/// The shear placements give the old `ShearShape` ratios (the phase-map columns) and the old
/// particle: semi-axes bit for bit, axes the identity.
#[test]
fn shear_placement_builds_the_old_particles() {
    let scaling = ShearScaling::new(0.4, 1.0, 1e3).unwrap();
    let mut cases: Vec<(Shape, [f64; 3])> = vec![(Shape::Sphere, [1.0, 1.0, 1.0])];
    for l in SHEAR_ASPECTS {
        cases.push((Shape::Prolate(l), [l, 1.0, 1.0]));
        cases.push((Shape::Oblate(l), [l, 1.0, l]));
    }
    for (omega1, omega2) in fig8_triaxials() {
        cases.push((Shape::Triaxial { omega1, omega2 }, [1.0, omega1, omega2]));
    }
    for (shape, old_ratios) in cases {
        let placed = ShearShape::new(shape);
        assert_eq!(bits(placed.ratios()), bits(old_ratios), "{shape:?}");
        let particle = placed.particle(&scaling).unwrap();
        assert_eq!(
            bits(semi_axes(particle.shape())),
            bits(old_semi_axes(old_ratios, 1.0)),
            "{shape:?}"
        );
        assert_eq!(particle.shape().axes(), Mat3::identity(), "{shape:?}");
    }
    // The Fig. 4 oblate: 2.5 along flow and vorticity, the short axis along the gradient.
    let oblate = ShearShape::new(Shape::Oblate(2.5));
    assert_eq!(oblate.in_plane_axes(), (0, 1));
    assert_eq!(oblate.in_plane_aspect(), 2.5);
}

/// The real-flow scenes (cavity d_eq = 3 mm, bifurcation at its Stokes-number d_eq) give the
/// old body ratios and semi-axes, and the old dataset labels.
#[test]
fn real_flow_shapes_build_the_old_ellipsoids() {
    let turn = nalgebra::Rotation3::from_euler_angles(0.3, -0.7, 1.1).into_inner();
    for d_eq in [3e-3, 4.7e-6] {
        for l in [1.0, 2.0, 5.0, 8.0, 20.0] {
            for (shape, old_ratios) in [(Shape::Prolate(l), [l, 1.0, 1.0]), (Shape::Oblate(l), [l, l, 1.0])] {
                assert_eq!(bits(shape.ratios()), bits(old_ratios));
                let e = shape.ellipsoid(d_eq, turn).unwrap();
                assert_eq!(bits(semi_axes(&e)), bits(old_semi_axes(old_ratios, d_eq)), "{shape:?}");
                assert_eq!(e.axes(), turn);
            }
        }
    }
    assert_eq!(Shape::Prolate(1.0).label(), "prolate_1");
    assert_eq!(Shape::Prolate(5.0).label(), "prolate_5");
    assert_eq!(Shape::Oblate(8.0).label(), "oblate_8");
    assert_eq!(Shape::Prolate(3.5).label(), "prolate_3.5");
    assert_eq!(Shape::Sphere.label(), "sphere");
    let triaxial = Shape::Triaxial {
        omega1: 0.5,
        omega2: 0.2,
    };
    assert_eq!(triaxial.label(), "triaxial_0.5_0.2");
}

/// The pipe's Tian/Cui prolates (λ₁ = 3.5, 7, 14): the old d_eq = 2 r₃ (λ₁λ₂)^{1/3} with
/// λ₂ = 1, and the old particle, ratios (λ₁, λ₂, 1) scaled to d_eq = 1 along the global axes.
#[test]
fn pipe_prolates_build_the_old_particles() {
    for l in [3.5, 7.0, 14.0] {
        let data = PipeParticleData::tian_cui(Shape::Prolate(l));
        let old_d_eq = 2.0 * 0.5e-6 * (l * 1.0).cbrt();
        assert_eq!(data.d_eq().unwrap().to_bits(), old_d_eq.to_bits(), "λ₁ = {l}");
        assert_eq!(data.lambda1().to_bits(), l.to_bits());
        let scene = PipeSetup::tian_cui(l, 0.25).unwrap();
        assert_eq!(scene.length_unit.to_bits(), old_d_eq.to_bits());
        let shape = scene.particle.shape();
        assert_eq!(bits(semi_axes(shape)), bits(old_semi_axes([l, 1.0, 1.0], 1.0)));
        assert_eq!(shape.axes(), Mat3::identity());
    }
}

/// d_eq from the smallest semi-axis is the volume-equivalent diameter of the semi-axes it
/// implies, for every family: 2 (R₁R₂R₃)^{1/3} with R_a = ρ_a r_min/ρ_min, to a few ulps
/// (three cube roots, a product and a quotient, each correctly rounded or within 1 ulp).
#[test]
fn volume_diameter_from_the_smallest_semi_axis() {
    let r_min = 0.5e-6;
    let shapes = [
        Shape::Sphere,
        Shape::Prolate(14.0),
        Shape::Oblate(2.5),
        Shape::Triaxial {
            omega1: 0.3,
            omega2: 0.5,
        },
    ];
    for shape in shapes {
        let ratios = shape.ratios();
        let min = ratios.iter().copied().fold(f64::INFINITY, f64::min);
        let radii = ratios.map(|r| r * r_min / min);
        let expected = 2.0 * (radii[0] * radii[1] * radii[2]).cbrt();
        let d_eq = shape.volume_diameter(r_min).unwrap();
        assert!(
            (d_eq - expected).abs() <= 8.0 * f64::EPSILON * expected,
            "{shape:?}: {d_eq} vs {expected}"
        );
        let e = shape.ellipsoid(d_eq, Mat3::identity()).unwrap();
        let smallest = e.semi_axes().min();
        assert!(
            (smallest - r_min).abs() <= 8.0 * f64::EPSILON * r_min,
            "{shape:?}: {smallest}"
        );
    }
    assert!(Shape::Prolate(-2.0).volume_diameter(r_min).is_err());
    assert!(Shape::Oblate(f64::NAN).volume_diameter(r_min).is_err());
    assert!(Shape::Sphere.volume_diameter(0.0).is_err());
    assert!(Shape::Prolate(1e300).volume_diameter(1e300).is_err());
}

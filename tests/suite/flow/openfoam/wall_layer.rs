//! The wall layer (`flow::openfoam::wall_layer`) against exact fields: linear fields with any
//! wall velocity, Hiemenz's gradient at half the first cell, Taylor–Couette at a rotating wall.

use super::{Layering, points, stagnation_box};
use crate::common::build;
use pseudorigid::flow::FlowField;
use pseudorigid::flow::openfoam::{BlendedFlow, FoamFlow, PolyMesh};
use pseudorigid::scenes::stagnation::half_cell_errors;
use pseudorigid::tensor::{Mat3, Vec3};

/// Least-squares slope of ln e against ln h.
fn slope(rows: &[(f64, f64)]) -> f64 {
    let n = rows.len() as f64;
    let (mx, my) = rows
        .iter()
        .fold((0.0, 0.0), |(a, b), (h, e)| (a + h.ln() / n, b + e.ln() / n));
    let sxy: f64 = rows.iter().map(|(h, e)| (h.ln() - mx) * (e.ln() - my)).sum();
    let sxx: f64 = rows.iter().map(|(h, _)| (h.ln() - mx).powi(2)).sum();
    sxy / sxx
}

/// The box meshes of the near-wall tests: blockMesh layerings built here (hexahedra and prisms)
/// and the shipped snappyHexMesh meshes, all with the wall y = 0.
fn wall_meshes() -> Vec<(String, PolyMesh)> {
    let mut meshes = Vec::new();
    for layering in [Layering::Uniform, Layering::Graded, Layering::Layers(5)] {
        for prisms in [false, true] {
            let mesh = stagnation_box(layering, 0, prisms).cellwise.mesh().clone();
            meshes.push((format!("{layering:?} prisms {prisms}"), mesh));
        }
    }
    for n in [0, 2, 5] {
        let mesh = stagnation_box(Layering::Snapped(n), 0, false).cellwise.mesh().clone();
        meshes.push((format!("snapped, {n} layers"), mesh));
    }
    meshes
}

/// A divergence-free linear field u = c + Bx (tr B = 0) imposed on the cells and every patch:
/// the wall y = 0 then moves with c + B(x, 0, z), through itself (u_y ≠ 0) and with a surface
/// divergence (B_xx + B_zz = −3), as a transpiring, deforming or verification wall does. The
/// default field reproduces it to round-off within two cells of the wall and everywhere else:
/// the wall fit takes the wall velocity's surface gradient W from the neighbouring wall faces
/// (exact for a linear wall velocity on a flat wall), the normal derivative of u_n from
/// continuity (−tr W, exact for a divergence-free field) and the shear from the wall cell and
/// the cell above it (exact for a linear profile). Bound: |u| ≤ 6 here and the fits divide by
/// cell heights down to 2e-3 of the box, so round-off of 1e-15 relative grows to ~1e-12; the
/// issue's target, 1e-9 of the largest |u| and |∇u|, is the bound (measured: 7e-16 and
/// 6e-14). Before the wall velocity's gradient entered the fit the uniform box missed by
/// |Δu| = 0.28 and |Δ∇u| = 4.0, the largest |∇u| itself (the test fails so).
#[test]
fn linear_fields_are_exact_at_moving_walls() {
    let c = Vec3::new(0.3, -1.2, 0.7);
    let b = Mat3::new(1.0, -2.0, 0.5, 0.25, 3.0, -1.5, -0.75, 2.0, -4.0);
    assert_eq!(b.trace(), 0.0);
    let exact = |x: &Vec3| c + b * x;
    for (name, mesh) in wall_meshes() {
        let cells = FoamFlow::new(mesh.clone(), vec![(0.0, build::sampled(&mesh, exact))]).unwrap();
        assert!(!cells.walls().is_empty(), "{name}: no wall faces");
        let blend = BlendedFlow::new(cells).unwrap();
        let first = 0.05;
        let mut pts: Vec<Vec3> = points(600, 0.0, 1.0, 37)
            .into_iter()
            .map(|p| Vec3::new(p[0] - 0.5, 2.0 * first * p[1] * p[1], 0.25 * p[2]))
            .collect();
        pts.extend(points(200, 0.0, 1.0, 41).into_iter().map(|p| Vec3::new(p[0] - 0.5, 0.4 * p[1], 0.25 * p[2])));
        let (mut eu, mut eg) = (0.0f64, 0.0f64);
        for x in &pts {
            let s = blend.sample(x, 0.0).unwrap();
            eu = eu.max((s.u - exact(x)).amax());
            eg = eg.max((s.grad_u - b).amax());
        }
        eprintln!("{name}: linear field, |Δu| {eu:.2e}, |Δ∇u| {eg:.2e}");
        assert!(eu < 1e-9 * 6.0 && eg < 1e-9 * 4.0, "{name}: {eu:e} {eg:e}");
    }
}

/// Hiemenz flow at half the first cell's height over the wall: u and ∇u relative to the exact
/// field's maxima on the uniform, 2- and 5-layer blockMesh boxes refined twice
/// (`paper-figures/near-wall/gradient_order.csv` holds the snappyHexMesh meshes). The wall fit
/// takes the shear γ from the quadratic profile through the wall, the wall cell and the cell
/// above, so γ is second order and ∇u = γ + 2δq + … with q first order at δ = O(h): second
/// order. Bound 1.8, the target (a fitted order over three levels; the coarse level
/// has δ₁/ℓ up to 0.5 and the next term moves the order by about 0.1; measured 1.98–2.09).
/// With the cell gradient's normal derivative in γ the order of ∇u was 1.05 on the uniform
/// box (the test fails so).
#[test]
fn hiemenz_gradient_at_half_the_first_cell_converges_at_second_order() {
    for layering in [Layering::Uniform, Layering::Layers(2), Layering::Layers(5)] {
        let (mut u, mut grad) = (Vec::new(), Vec::new());
        for refine in 0..3 {
            let flow = stagnation_box(layering, refine, false);
            let (eu, eg) = half_cell_errors(&flow.blended, flow.first_cell).unwrap();
            eprintln!("{layering:?} refine {refine}: first cell {:.3e}, u {eu:.3e}, ∇u {eg:.3e}", flow.first_cell);
            u.push((flow.first_cell, eu));
            grad.push((flow.first_cell, eg));
        }
        let (pu, pg) = (slope(&u), slope(&grad));
        eprintln!("{layering:?}: fitted order u {pu:.2}, ∇u {pg:.2}");
        assert!(pu >= 1.8 && pg >= 1.8, "{layering:?}: orders {pu:.2}, {pg:.2}");
    }
}

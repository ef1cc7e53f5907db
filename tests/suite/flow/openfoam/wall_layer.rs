//! The wall layer (`flow::openfoam::wall_layer`) against exact fields: linear fields with any
//! wall velocity, Hiemenz's gradient at half the first cell, Taylor–Couette at a rotating wall.

use super::{Layering, points, stagnation_box};
use crate::common::build;
use pseudorigid::flow::FlowField;
use pseudorigid::flow::openfoam::{BlendedFlow, FoamFlow, PolyMesh};
use pseudorigid::studies::couette::exact as couette;
use pseudorigid::studies::stagnation::half_cell_errors;
use pseudorigid::tensor::{Mat3, Vec3};

/// Observed order of (h, e) rows ([`crate::common::observed_order`]).
fn slope(rows: &[(f64, f64)]) -> f64 {
    let (h, e): (Vec<f64>, Vec<f64>) = rows.iter().copied().unzip();
    crate::common::observed_order(&h, &e)
}

/// The box meshes of the near-wall tests: blockMesh layerings built here (hexahedra and prisms)
/// and the shipped snappyHexMesh meshes, all with the wall y = 0.
/// (name, mesh, first cell's height).
fn wall_meshes() -> Vec<(String, PolyMesh, f64)> {
    let mut meshes = Vec::new();
    for layering in [Layering::Uniform, Layering::Graded, Layering::Layers(5)] {
        for prisms in [false, true] {
            let flow = stagnation_box(layering, 0, prisms);
            meshes.push((
                format!("{layering:?} prisms {prisms}"),
                flow.cellwise.mesh().clone(),
                flow.first_cell,
            ));
        }
    }
    for n in [0, 2, 5] {
        let flow = stagnation_box(Layering::Snapped(n), 0, false);
        meshes.push((
            format!("snapped, {n} layers"),
            flow.cellwise.mesh().clone(),
            flow.first_cell,
        ));
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
    for (name, mesh, _) in wall_meshes() {
        let cells = FoamFlow::new(mesh.clone(), vec![(0.0, build::sampled(&mesh, exact))]).unwrap();
        assert!(!cells.walls().is_empty(), "{name}: no wall faces");
        let cells_named = cells.strained_walls();
        let blend = BlendedFlow::new(cells).unwrap();
        let first = 0.05;
        let mut pts: Vec<Vec3> = points(600, 0.0, 1.0, 37)
            .into_iter()
            .map(|p| Vec3::new(p[0] - 0.5, 2.0 * first * p[1] * p[1], 0.25 * p[2]))
            .collect();
        pts.extend(
            points(200, 0.0, 1.0, 41)
                .into_iter()
                .map(|p| Vec3::new(p[0] - 0.5, 0.4 * p[1], 0.25 * p[2])),
        );
        let (mut eu, mut eg) = (0.0f64, 0.0f64);
        for x in &pts {
            let s = blend.sample(x, 0.0).unwrap();
            eu = eu.max((s.u - exact(x)).amax());
            eg = eg.max((s.grad_u - b).amax());
        }
        eprintln!("{name}: linear field, |Δu| {eu:.2e}, |Δ∇u| {eg:.2e}");
        assert!(
            cells_named.is_empty(),
            "{name}: flat walls named strained: {cells_named:?}"
        );
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
            eprintln!(
                "{layering:?} refine {refine}: first cell {:.3e}, u {eu:.3e}, ∇u {eg:.3e}",
                flow.first_cell
            );
            u.push((flow.first_cell, eu));
            grad.push((flow.first_cell, eg));
        }
        let (pu, pg) = (slope(&u), slope(&grad));
        eprintln!("{layering:?}: fitted order u {pu:.2}, ∇u {pg:.2}");
        assert!(pu >= 1.8 && pg >= 1.8, "{layering:?}: orders {pu:.2}, {pg:.2}");
    }
}

/// The quarter annulus θ ∈ [0, π/2], r ∈ [1, 2] as blockMesh makes it with arc edges:
/// `8 · 2^level` cells in θ and in r (uniform, or with `layers` prism layers of expansion 1.2
/// in the first core cell) and two of depth 2^−level/8 in z, hexahedra similar under
/// refinement; the inner cylinder is the `wall` patch, the other sides `open` (type patch).
/// Returns the mesh and its first cell's height.
fn quarter_annulus(level: u32, layers: usize) -> (PolyMesh, f64) {
    let n = 8usize << level;
    let thetas: Vec<f64> = (0..=n)
        .map(|i| std::f64::consts::FRAC_PI_2 * i as f64 / n as f64)
        .collect();
    let core = 1.0 / n as f64;
    let mut radii = vec![1.0];
    if layers > 0 {
        let first = core * 0.2 / (1.2f64.powi(layers as i32) - 1.0);
        for i in 0..layers {
            radii.push(radii[i] + first * 1.2f64.powi(i as i32));
        }
        let scale = core / (radii[layers] - 1.0);
        radii.iter_mut().for_each(|r| *r = 1.0 + (*r - 1.0) * scale);
    }
    // The layers fill the first core cell; the core cells follow.
    let from = if layers > 0 { 2 } else { 1 };
    radii.extend((from..n).map(|i| 1.0 + i as f64 * core));
    radii.push(2.0);
    let depth = 0.125 / (1u32 << level) as f64;
    let mut raw = build::layered_box(&thetas, &radii, &[0.0, depth, 2.0 * depth], false);
    // (θ, r, z) → (r sin θ, r cos θ, z): orientation-preserving (Jacobian r > 0).
    for p in &mut raw.points {
        *p = Vec3::new(p[1] * p[0].sin(), p[1] * p[0].cos(), p[2]);
    }
    (raw.mesh(), radii[1] - 1.0)
}

/// Largest |u| and |∇u| errors of `flow` at half the first cell's height over the inner
/// cylinder (r = 1 + δ₁/2, θ ∈ [0.1, 0.9] π/2, in the lower cells), relative to the exact field's
/// largest |u| (1) and |∇u| (5/3 on the inner wall, `studies::couette::GRAD_MAX`).
fn couette_half_cell(flow: &dyn FlowField, first: f64) -> (f64, f64) {
    let r = 1.0 + 0.5 * first;
    (0..60)
        .map(|i| {
            let theta = std::f64::consts::FRAC_PI_2 * (0.1 + 0.8 * (i as f64 + 0.5) / 60.0);
            let x = Vec3::new(r * theta.sin(), r * theta.cos(), 0.005);
            let (s, (u, g)) = (flow.sample(&x, 0.0).unwrap(), couette(&x));
            ((s.u - u).amax(), (s.grad_u - g).amax() / (5.0 / 3.0))
        })
        .fold((0.0f64, 0.0f64), |(a, b), (u, g)| (a.max(u), b.max(g)))
}

/// Taylor–Couette at the rotating inner cylinder, exact field on cells and patches, uniform
/// cells and 2 and 5 layers (levels 1–3: the coarsest quarter annulus, 8 cells over 90°, is
/// pre-asymptotic). The fit extends the wall's rigid rotation exactly (its normal derivative m
/// from W), and ∇u takes the wall's turning (the shape operator K: D's normal row −(Kγ)ᵀ and
/// the shear part's growth with the distance from the curved wall, `wall_layer` module docs),
/// so u and ∇u at half the first cell's height converge at second order (fitted order ≥ 1.8
/// for both, as for Hiemenz), and ∇u is below the cellwise fits' error at every level.
///
/// Before the wall's motion entered the fit ∇u missed by 0.30 of its largest value at every
/// level (order −0.05) and u converged at first order, 14× worse than the cellwise fits at
/// level 3. Before the turning entered ∇u, ∇u converged at first order (0.054, 0.028, 0.014 of
/// its largest value without layers, about half of the dropped term's κ|γ_s|h/2; order 0.96).
/// The test fails so.
#[test]
fn taylor_couette_at_a_rotating_wall() {
    for layers in [0, 2, 5] {
        let (mut u, mut grad) = (Vec::new(), Vec::new());
        for level in 1..=3 {
            let (mesh, first) = quarter_annulus(level, layers);
            let cells = FoamFlow::new(mesh.clone(), vec![(0.0, build::sampled(&mesh, |x| couette(x).0))]).unwrap();
            let blend = BlendedFlow::new(cells.clone()).unwrap();
            let (eu, eg) = couette_half_cell(&blend, first);
            let (cu, cg) = couette_half_cell(&cells, first);
            eprintln!(
                "{layers} layers, level {level}: first cell {first:.3e}, u {eu:.3e}, ∇u {eg:.3e} (cellwise {cu:.3e}, {cg:.3e})"
            );
            assert!(eg < cg, "{layers} layers, level {level}: ∇u {eg:e}, cellwise {cg:e}");
            u.push((first, eu));
            grad.push((first, eg));
        }
        let (pu, pg) = (slope(&u), slope(&grad));
        eprintln!("{layers} layers: fitted order u {pu:.2}, ∇u {pg:.2}");
        assert!(pu >= 1.8 && pg >= 1.8, "{layers} layers: orders {pu:.2}, {pg:.2}");
    }
}

/// A curved wall at rest carries no flow into its faces. On a flat no-slip face, continuity
/// gives ∂u_n/∂n = −∇ₛ·u_t = 0, so the velocity towards the face grows as δ² whatever the data
/// in the cells; the fit's u is the flat-face expansion, which keeps that on a faceted curved
/// wall too. The wall's turning (−Kγ·r_t, the normal part of the shear's surface gradient)
/// belongs in ∇u only: in u it was a normal velocity −δ Kγ·r_t on a face still no-slip, a sink
/// on half of every face (on the 90° bend it carried spheres' centres onto the wall; the test
/// fails so, |u·n|/(δ|∇u|max) = 2–4·10⁻² here). Circular Couette flow with the inner cylinder
/// r = 1 (the quarter annulus' wall, level 1, 16 faces over 90°) at rest and the outer one
/// turning, u_θ = (4/3)(r − 1/r), on the cells and the open patch, the inner faces at rest
/// (shear 8/3 there, |∇u|max); each inner face approached along its normal from a point
/// half-way and nine tenths of the way from its centre to a vertex. Bound 10⁻⁶ at δ = 10⁻⁸ h,
/// as for the duct's edges: a term C δ² with C of the field's second derivatives (≤ 10 here)
/// gives at most 10⁻⁸ · 0.06 · 10/(8/3) ≈ 2·10⁻⁹.
#[test]
fn a_curved_wall_at_rest_draws_no_flow_into_its_faces() {
    let (mesh, _) = quarter_annulus(1, 0);
    let resting = |x: &Vec3| {
        let r2 = x[0] * x[0] + x[1] * x[1];
        if r2 < 1.001 {
            Vec3::zeros()
        } else {
            Vec3::new(-x[1], x[0], 0.0) * (4.0 / 3.0 * (1.0 - 1.0 / r2))
        }
    };
    let cells = FoamFlow::new(mesh.clone(), vec![(0.0, build::sampled(&mesh, resting))]).unwrap();
    let blend = BlendedFlow::new(cells).unwrap();
    let n = 16usize;
    let (h, largest_shear) = (1.0 / n as f64, 8.0 / 3.0);
    let z = 0.5 * 0.125 / 2.0;
    let on_wall = |theta: f64| Vec3::new(theta.sin(), theta.cos(), z);
    let mut worst = 0.0f64;
    for i in [1usize, 5, 8, 12, 14] {
        let (a, b) = (
            std::f64::consts::FRAC_PI_2 * i as f64 / n as f64,
            std::f64::consts::FRAC_PI_2 * (i + 1) as f64 / n as f64,
        );
        let (va, vb) = (on_wall(a), on_wall(b));
        let centre = (va + vb) * 0.5;
        let inward = Vec3::new(centre[0], centre[1], 0.0).normalize();
        for (toward, fraction) in [(va, 0.5), (vb, 0.9)] {
            let foot = centre + (toward - centre) * fraction;
            let ratios: Vec<f64> = [1e-2, 1e-4, 1e-6, 1e-8]
                .iter()
                .map(|&f| {
                    let delta = f * h;
                    let u = blend.sample(&(foot + inward * delta), 0.0).unwrap().u;
                    u.dot(&inward).abs() / (delta * largest_shear)
                })
                .collect();
            let shown: Vec<String> = ratios.iter().map(|r| format!("{r:.2e}")).collect();
            eprintln!(
                "inner face {i}, {fraction} of the way to a vertex: |u·n|/(δ|∇u|max) at δ/h = 1e-2 … 1e-8: {shown:?}"
            );
            worst = worst.max(ratios[3]);
        }
    }
    assert!(worst < 1e-6, "largest |u·n|/(δ|∇u|max) at δ = 1e-8 h: {worst:e}");
}

/// The snappyHexMesh annuli shipped in `tests/data/couette-snappy` (`cases/taylor-couette`,
/// coarse level: 96 faces around the inner cylinder, 0, 2 and 5 layers on both cylinders).
fn snapped_annulus(layers: usize) -> PolyMesh {
    let case = format!(
        "{}/tests/data/couette-snappy/layers{layers}",
        env!("CARGO_MANIFEST_DIR")
    );
    PolyMesh::read(case.as_ref()).unwrap()
}

/// Both cylinders of a snapped annulus turning with the fluid as one rigid body, u = Ω e_z × x
/// on cells and patches: the wall fits extend each wall's rigid motion exactly (W to round-off
/// once the off-plane offsets are iterated out, m = Ω × n), so the default field is exact
/// everywhere, walls included, though the walls are faceted and curved. Bound as for the flat
/// walls: 1e-9 of |u| ≤ 2 and |∇u| = 1 (measured 4e-16 and 1e-14). With the off-plane
/// offsets left in W the error is O(κh): |Δu| 3.3e-3, |Δ∇u| 3.8e-2 without layers (the test
/// fails so).
#[test]
fn a_rigidly_rotating_snapped_annulus_is_exact() {
    let rotation = |x: &Vec3| Vec3::new(-x[1], x[0], 0.0);
    for layers in [0, 2, 5] {
        let mesh = snapped_annulus(layers);
        let cells = FoamFlow::new(mesh.clone(), vec![(0.0, build::sampled(&mesh, rotation))]).unwrap();
        let blend = BlendedFlow::new(cells).unwrap();
        let (mut eu, mut eg) = (0.0f64, 0.0f64);
        for p in points(2000, 0.0, 1.0, 47) {
            let (r, theta) = (1.0 + 0.3 * p[0] * p[0], std::f64::consts::TAU * p[1]);
            let x = Vec3::new(r * theta.cos(), r * theta.sin(), 0.25 * p[2]);
            let s = blend.sample(&x, 0.0).unwrap();
            eu = eu.max((s.u - rotation(&x)).amax());
            eg = eg.max((s.grad_u - Mat3::new(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0)).amax());
        }
        eprintln!("snapped annulus, {layers} layers: rigid rotation |Δu| {eu:.2e}, |Δ∇u| {eg:.2e}");
        assert!(eu < 2e-9 && eg < 1e-9, "{layers} layers: {eu:e} {eg:e}");
    }
}

/// The exact circular Couette flow in the shipped snapped annuli (`studies::couette`, level 0,
/// 0/2/5 layers): the wall layer replaces the cellwise fits within two cells of the wall, so its
/// largest ∇u error against the exact solution must be no larger than theirs at every height
/// from 0.1 to 2 first-cell heights over the rotating cylinder (the largest over 60 points
/// each; issue 37). No tolerance: the claim is an inequality, and it holds by a factor
/// 1.1–10 (printed). It is asserted on levels 1–2 by `examples/near_wall_hiemenz`.
#[test]
fn snapped_couette_wall_layer_is_no_worse_than_the_cellwise_fits() {
    use pseudorigid::studies::couette::{CouetteAnnulus, blend_against_cellwise};
    for layers in [0, 2, 5] {
        let annulus = CouetteAnnulus::new(snapped_annulus(layers)).unwrap();
        for band in blend_against_cellwise(&annulus).unwrap() {
            eprintln!("{layers} layers, {band:?}");
            assert!(band.blended <= band.cellwise, "{layers} layers: {band:?}");
        }
    }
}

/// A square duct (the unit cube's walls y, z ∈ {0, 1}, 8 hexahedra per edge, h = 1/8) carrying
/// an axial flow and a secondary swirl that vanish on every wall,
/// u = (16 y(1−y) z(1−z), ∂ψ/∂z, −∂ψ/∂y) with ψ = 16 y²(1−y)² z²(1−z)² (divergence-free),
/// imposed on the cells and the patches. Exactly, the velocity towards a wall grows as the
/// square of the distance from it, so next to an edge |u_y| + |u_z| = O(δ²) along the diagonal
/// y = z = δ. The wall fit of a face on y = 0 takes its shear from the wall cell's value, whose
/// z-component is the swirl's (5.6·10⁻³ at the corner cell's centre): unprojected, that shear
/// carried fluid through the wall z = 0 linearly in δ next to the edge, where the blend weighs
/// both walls' faces alike, and (|u_y| + |u_z|)/δ stayed at 5·10⁻² of the largest shear
/// |∇u|max = 4 down to δ = 10⁻⁸ h (a sink that draws tracers into the edge; the test fails so).
/// With the shear projected on the edge's direction the ratio falls as δ: bound 10⁻⁶ at
/// δ = 10⁻⁸ h, where a normal velocity C δ² with C of the size of the field's second
/// derivatives (|∇²u| ≤ 10², so C/|∇u|max ≤ 25) gives at most 3·10⁻⁸ (measured: 3·10⁻¹³,
/// falling tenfold per decade of δ).
#[test]
fn duct_edges_carry_no_flow_into_the_walls() {
    let psi_y = |y: f64, z: f64| 32.0 * y * (1.0 - y) * (1.0 - 2.0 * y) * (z * (1.0 - z)).powi(2);
    let psi_z = |y: f64, z: f64| 32.0 * z * (1.0 - z) * (1.0 - 2.0 * z) * (y * (1.0 - y)).powi(2);
    let exact = |x: &Vec3| {
        let (y, z) = (x[1], x[2]);
        Vec3::new(16.0 * y * (1.0 - y) * z * (1.0 - z), psi_z(y, z), -psi_y(y, z))
    };
    let mesh = build::cube(build::Shape::Hex, 8).mesh();
    let cells = FoamFlow::new(mesh.clone(), vec![(0.0, build::sampled(&mesh, exact))]).unwrap();
    let blend = BlendedFlow::new(cells).unwrap();
    let (h, largest_shear) = (1.0 / 8.0, 4.0);
    for x in [0.3, 0.5, 0.77] {
        // The four edges of the duct, approached along their diagonals.
        for (corner, inward) in [
            (Vec3::new(x, 0.0, 0.0), Vec3::new(0.0, 1.0, 1.0)),
            (Vec3::new(x, 1.0, 0.0), Vec3::new(0.0, -1.0, 1.0)),
            (Vec3::new(x, 0.0, 1.0), Vec3::new(0.0, 1.0, -1.0)),
            (Vec3::new(x, 1.0, 1.0), Vec3::new(0.0, -1.0, -1.0)),
        ] {
            let ratios: Vec<f64> = [1e-2, 1e-4, 1e-6, 1e-8]
                .iter()
                .map(|&fraction| {
                    let delta = fraction * h;
                    let u = blend.sample(&(corner + inward * delta), 0.0).unwrap().u;
                    (u[1].abs() + u[2].abs()) / (delta * largest_shear)
                })
                .collect();
            let shown: Vec<String> = ratios.iter().map(|r| format!("{r:.2e}")).collect();
            eprintln!("edge at {corner:?}: (|u_y| + |u_z|)/(δ |∇u|max) at δ/h = 1e-2 … 1e-8: {shown:?}");
            assert!(ratios[3] < 1e-6, "edge at {corner:?}: {ratios:?}");
        }
    }
}

/// Around the convex edge of an L-shaped channel (8 cells per unit, the edge along (½, ½, z)),
/// a wall face's weight fades out behind its plane (`flow::openfoam::blend`, Convex edges). The
/// fade's gradient must enter the weights' gradients, or the convective acceleration the
/// fluid-inertia terms use is no longer the derivative of the blended u along u. Checked
/// against the central difference of u over ±h along u, h = 10⁻⁶ of the distance r to the
/// edge, at points whose direction from the edge lies in the fade (c from −0.48 to −0.29; also
/// −0.71 and −0.09, where H is 0 and 1), with a smooth field that moves the
/// walls (so every fit carries shear and wall motion). The difference's truncation is about
/// (h/r)²/6 ≈ 10⁻¹³ and its round-off ε|u|/h ≈ 10⁻⁹ of |u|²/r; the bound 10⁻⁶ of
/// |(u·∇)u| + |u|²/r is a thousand times that, and the fade's term ω H'∇c is of the size of
/// (u·∇)u itself here: measured 1.7·10⁻¹⁰; without the fade's term the test fails (0.28 at
/// r = 0.02, 61°).
#[test]
fn convective_acceleration_is_the_derivative_of_u_at_a_convex_edge() {
    let exact = |x: &Vec3| {
        Vec3::new(
            (2.0 * x[1]).sin() + 0.3 * x[2],
            0.5 * (3.0 * x[0]).cos(),
            1.0 + x[0] * x[1] + 0.2 * x[0] * x[0],
        )
    };
    let mesh = build::l_channel(8).mesh();
    let cells = FoamFlow::new(mesh.clone(), vec![(0.0, build::sampled(&mesh, exact))]).unwrap();
    let blend = BlendedFlow::new(cells).unwrap();
    let mut worst: f64 = 0.0;
    for r in [0.02, 0.05] {
        for degrees in [45.0_f64, 61.0, 64.0, 67.0, 70.0, 73.0, 85.0] {
            let (s, c) = degrees.to_radians().sin_cos();
            // At `degrees` from the wall y = ½ (x > ½) around the edge: 90° − `degrees` past the
            // plane of the face x = ½ (inward normal −x), whose cosine c = −cos(`degrees`).
            let x = Vec3::new(0.5 + r * c, 0.5 + r * s, 0.5);
            let sample = blend.sample(&x, 0.0).unwrap();
            let speed = sample.u.norm();
            let along = sample.u / speed;
            let h = 1e-6 * r;
            let ahead = blend.sample(&(x + along * h), 0.0).unwrap().u;
            let behind = blend.sample(&(x - along * h), 0.0).unwrap().u;
            let difference = (ahead - behind) * (speed / (2.0 * h));
            let scale = sample.convective.norm() + speed * speed / r;
            let error = (sample.convective - difference).norm() / scale;
            worst = worst.max(error);
            assert!(
                error < 1e-6,
                "r {r}, {degrees}°: (u·∇)u {:?}, difference {difference:?}",
                sample.convective
            );
        }
    }
    eprintln!("convex edge: largest |(u·∇)u − difference| / scale {worst:.2e}");
}

/// The convex fade's cosines measured against others (`flow::openfoam::blend`, Convex edges)
/// at the convex edge of the L-shaped channel (16 cells per unit, h = 1/16, the edge along
/// (½, ½, z)), in the field that flows along a convex edge with no slip on both its faces:
/// u = r^{2/3} sin(2θ/3) ẑ, θ measured from the wall y = ½ (x > ½) through the fluid to the
/// wall x = ½ (y < ½) at 3π/2. It is harmonic and divergence-free, the leading term of a duct's
/// Poiseuille flow at a re-entrant edge, whose shear r^{−1/3} grows towards the edge: there the
/// faces next to the edge carry the largest shear, which their fits reverse behind their planes
/// (the failure the fade exists for). Sampled at cell centres and boundary faces (the far walls
/// then move along z), so every error is the blend's. Errors |u − u_exact|/r^{2/3} (the field's
/// size on the circle) on rings r = 0.1 … 1.3 h about the edge at z = ½, θ = 1° … 269°.
///
/// The bound: the blend is a weighted mean of fits, and a fade that keeps the fits valid in
/// front of their faces and drops the reversed ones should leave the blend no worse near the
/// edge than the cellwise-linear field it smooths (the containing cell's fit, [`FoamFlow`]),
/// whose own error there is that of one linear fit of r^{2/3} at the distance of its cell's
/// centre: the shipped fade's largest error must lie below the cellwise field's largest error
/// on the same points, over all of them and over those behind a face's plane. Printed besides:
/// full weight to 7° and none beyond 15° behind a face's plane, the shipped 14.5°/30°, 25°/45°,
/// and no fade; the shipped fade must lower the rms error behind the planes below no fade's
/// (a comparison, no tolerance).
#[test]
fn convex_fade_is_measured_against_an_exact_field_at_a_convex_edge() {
    let angle = |x: &Vec3| {
        let theta = (x[1] - 0.5).atan2(x[0] - 0.5);
        // The solid quadrant is −π/2 < θ < 0: points below it (x < ½, y < ½) continue past π.
        if theta < -std::f64::consts::FRAC_PI_4 {
            theta + 2.0 * std::f64::consts::PI
        } else {
            theta
        }
    };
    let exact = |x: &Vec3| {
        let r = (x[0] - 0.5).hypot(x[1] - 0.5);
        Vec3::new(0.0, 0.0, r.powf(2.0 / 3.0) * (2.0 * angle(x) / 3.0).sin())
    };
    let n = 16;
    let h = 1.0 / n as f64;
    let mesh = build::l_channel(n).mesh();
    let cells = FoamFlow::new(mesh.clone(), vec![(0.0, build::sampled(&mesh, exact))]).unwrap();
    let shipped = BlendedFlow::new(cells.clone()).unwrap();
    let behind = |full: f64, none: f64| Some((-none.to_radians().sin(), -full.to_radians().sin()));
    let variants = [
        ("7°/15°", behind(7.0, 15.0)),
        ("14.5°/30° (shipped)", None),
        ("25°/45°", behind(25.0, 45.0)),
        ("no fade", None),
    ];
    let mut points = Vec::new();
    for fraction in [0.1, 0.3, 0.6, 0.9, 1.3] {
        for degrees in (1..270).step_by(2) {
            let (s, c) = (degrees as f64).to_radians().sin_cos();
            points.push(Vec3::new(0.5 + fraction * h * c, 0.5 + fraction * h * s, 0.5));
        }
    }
    // Largest and rms error over all points, then over those behind a face's plane (θ < π/2
    // behind the faces on x = ½, θ > π behind those on y = ½), where the fade acts.
    let errors = |field: &dyn FlowField| -> [f64; 4] {
        let (mut all, mut behind) = (Vec::new(), Vec::new());
        for x in &points {
            let r = (x[0] - 0.5).hypot(x[1] - 0.5);
            let e = (field.sample(x, 0.0).unwrap().u - exact(x)).norm() / r.powf(2.0 / 3.0);
            all.push(e);
            if !(std::f64::consts::FRAC_PI_2..=std::f64::consts::PI).contains(&angle(x)) {
                behind.push(e);
            }
        }
        let rms = |e: &[f64]| (e.iter().map(|e| e * e).sum::<f64>() / e.len() as f64).sqrt();
        let largest = |e: &[f64]| e.iter().copied().fold(0.0, f64::max);
        [largest(&all), rms(&all), largest(&behind), rms(&behind)]
    };
    let cellwise = errors(&cells);
    eprintln!("convex edge, u = r^(2/3) sin(2θ/3) ẑ, h = 1/{n}: |u − u_exact|/r^(2/3), largest and rms, all / behind");
    let show = |name: &str, e: &[f64; 4]| {
        eprintln!("  {name:<22} {:.3} {:.3} / {:.3} {:.3}", e[0], e[1], e[2], e[3]);
    };
    show("cellwise-linear", &cellwise);
    let mut measured = Vec::new();
    for (name, fade) in variants {
        let blend = match name {
            "14.5°/30° (shipped)" => shipped.clone(),
            _ => BlendedFlow::new(cells.clone()).unwrap().with_convex_fade(fade).unwrap(),
        };
        let e = errors(&blend);
        show(name, &e);
        measured.push(e);
    }
    let (shipped, unfaded) = (measured[1], measured[3]);
    assert!(
        shipped[0] < cellwise[0] && shipped[2] < cellwise[2],
        "shipped fade {shipped:?} against the cellwise field {cellwise:?}"
    );
    // The fade acts where it should: behind the planes it lowers the blend's rms error.
    assert!(
        shipped[3] < unfaded[3],
        "shipped fade {shipped:?} against none {unfaded:?}"
    );
}

/// The blend's largest errors (u, ∇u) against the linear field `u = c + Bx` at half the first
/// cell over the wall faces of each patch, and the patches `strained_walls` names, for that
/// field imposed on the cells and every patch of the snapped sphere (box walls snapped to a
/// surface, within 0.5° of their planes, and the sphere; issue 57 item 4).
fn strained(c: Vec3, b: Mat3) -> (Vec<(String, f64, f64)>, Vec<String>) {
    let mesh = super::snappy(20).mesh().clone();
    let exact = |x: &Vec3| c + b * x;
    let cells = FoamFlow::new(mesh.clone(), vec![(0.0, build::sampled(&mesh, exact))]).unwrap();
    let named = cells.strained_walls().into_iter().map(|w| w.patch).collect();
    let walls = cells.walls().to_vec();
    let blend = BlendedFlow::new(cells).unwrap();
    let layer = blend.cellwise().wall_layer();
    let errors = (mesh.patches().iter().filter(|p| p.kind == "wall"))
        .map(|patch| {
            let (mut eu, mut eg) = (0.0f64, 0.0f64);
            for (k, &f) in walls.iter().enumerate() {
                if (patch.start..patch.start + patch.size).contains(&(f as usize)) {
                    let x = mesh.face_centres()[f as usize] + layer.normal(k) * (0.5 * layer.depth(k));
                    let s = blend.sample(&x, 0.0).unwrap();
                    eu = eu.max((s.u - exact(&x)).amax());
                    eg = eg.max((s.grad_u - b).amax());
                }
            }
            (patch.name.clone(), eu, eg)
        })
        .collect();
    (errors, named)
}

/// The wall layer extends a wall's velocity exactly where the wall is flat or moves rigidly,
/// and not where a curved wall's velocity strains along it (module docs of `wall_layer`, *What
/// is exact*): the patches where it misses, and only those, are named for the run's warning
/// (the flat walls of [`linear_fields_are_exact_at_moving_walls`] are named by none). On the
/// snapped sphere (n = 20) with a linear field on every patch: a rigid motion V + Ω × x is
/// exact at half the first cell of every wall face (bound 1e-9 of |u|, |∇u| ≤ 4, as the
/// flat-wall test's round-off argument) and nothing is named; a straining field c + Bx
/// (tr B = 0) misses by more than 1e-7 (a hundred times round-off) at both the sphere and the
/// snapped box walls (measured 3.2e-4 and 1.4e-4 in u, 0.30 and 0.026 in ∇u), and both are
/// named.
#[test]
fn a_curved_wall_whose_velocity_strains_is_named_and_a_rigid_one_is_not() {
    let (v, omega) = (Vec3::new(0.2, -0.1, 0.3), Vec3::new(1.5, -0.5, 2.0));
    let (errors, named) = strained(v, omega.cross_matrix());
    eprintln!("rigid motion: (patch, |Δu|, |Δ∇u|) {errors:?}, named {named:?}");
    for (patch, eu, eg) in &errors {
        assert!(*eu < 1e-9 * 4.0 && *eg < 1e-9 * 4.0, "rigid, {patch}: {eu:e} {eg:e}");
    }
    assert!(named.is_empty(), "rigid: {named:?}");
    let (c, b) = super::linear_a();
    let (errors, named) = strained(c, b);
    eprintln!("linear c + Bx: (patch, |Δu|, |Δ∇u|) {errors:?}, named {named:?}");
    let missed: Vec<String> = (errors.iter().filter(|(_, eu, eg)| eu.max(*eg) > 1e-7))
        .map(|e| e.0.clone())
        .collect();
    assert_eq!(missed, ["walls", "sphere"], "{errors:?}");
    assert_eq!(named, missed);
}

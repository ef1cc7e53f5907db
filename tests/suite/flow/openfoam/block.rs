//! The shipped cube-cavity fields through the OpenFOAM reader: simpleFoam's own `U`
//! (`reference-data/cavity-*-foam/U.gz`) on the uniform block rebuilt by
//! `flow::openfoam::cavity_block`, checked against blockMesh's mesh, against the physics of a
//! lid-driven cavity, and at Re = 1000 against Albensoeder & Kuhlmann (2005).

use crate::common;

use pseudorigid::flow::FlowField;
use pseudorigid::flow::openfoam::{BlendedFlow, FoamError, PolyMesh, cavity_block};
use pseudorigid::studies::cavity_benchmark::{CI, Centreline, RE470, RE1000, ShippedField};
use pseudorigid::tensor::Vec3;

/// The builder is blockMesh's mesh: `tests/data/cavity-ci-blockmesh` is what blockMesh made of
/// `cases/cavity-ci` (12³, L = 0.1 m), written as ASCII with 6 significant digits. Topology
/// (face vertex lists, owners, neighbours, patches) must be identical; points agree to the
/// file's rounding, half a unit in the 6th digit of coordinates ≤ 0.1 m: 5e-8 m.
#[test]
fn cavity_block_is_blockmesh_s_mesh() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/cavity-ci-blockmesh");
    let theirs = PolyMesh::read(&dir).unwrap();
    let ours = cavity_block(CI.cells, CI.case.edge).unwrap();
    assert_eq!(ours.n_cells(), theirs.n_cells());
    assert_eq!(ours.n_faces(), theirs.n_faces());
    assert_eq!(ours.n_internal_faces(), theirs.n_internal_faces());
    assert_eq!(ours.patches(), theirs.patches());
    for f in 0..ours.n_faces() {
        assert_eq!(ours.face(f), theirs.face(f), "face {f}");
        assert_eq!(ours.owner(f), theirs.owner(f), "owner of face {f}");
        assert_eq!(ours.neighbour(f), theirs.neighbour(f), "neighbour of face {f}");
    }
    let gap = ours
        .points()
        .iter()
        .zip(theirs.points())
        .map(|(a, b)| (a - b).amax())
        .fold(0.0, f64::max);
    assert!(gap <= 5e-8, "points differ by {gap} m");
}

/// Bad sizes are typed errors, not panics or meshes.
#[test]
fn cavity_block_refuses_bad_sizes() {
    for (cells, edge) in [
        (0, 0.1),
        (4, 0.0),
        (4, -1.0),
        (4, f64::NAN),
        (4, f64::INFINITY),
        (1 << 12, 0.1),
    ] {
        assert!(
            matches!(cavity_block(cells, edge), Err(FoamError::Mesh { .. })),
            "{cells} cells, edge {edge}"
        );
    }
}

/// RMS of tr ∇u over RMS of |∇u| (Frobenius) on a lattice of n³ points filling the cube
/// [lo, hi]³ (in units of L).
fn divergence_ratio(flow: &impl FlowField, edge: f64, n: usize, lo: f64, hi: f64) -> f64 {
    let (mut tr2, mut g2) = (0.0, 0.0);
    let s = |i: usize| lo + (hi - lo) * (i as f64 + 0.5) / n as f64;
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let g = flow.sample(&(Vec3::new(s(i), s(j), s(k)) * edge), 0.0).unwrap().grad_u;
                tr2 += g.trace().powi(2);
                g2 += g.norm_squared();
            }
        }
    }
    (tr2 / g2).sqrt()
}

/// Checks lid, walls, vortex sense and symmetry of a shipped Re = 470 field as the cavity scene
/// reads it (blended, with the no-slip wall layer); returns h/L and the divergence ratios
/// (whole cube, core [0.1, 0.9]³).
fn physical_facts(field: &ShippedField) -> (f64, f64, f64) {
    let flow = BlendedFlow::new(field.load().unwrap()).unwrap();
    let (edge, lid) = (field.case.edge, field.case.lid_speed);
    // On a wall the wall layer's weight is infinite (capped at 1e24 against O(1) cell
    // weights): u is the wall's velocity to 1e-24 relative, far below 1e-12.
    for (x, y) in [(0.5, 0.5), (0.2, 0.8), (0.9, 0.1)] {
        let u = flow.sample(&(Vec3::new(x, y, 1.0) * edge), 0.0).unwrap().u;
        assert!((u - Vec3::new(lid, 0.0, 0.0)).amax() < 1e-12 * lid, "lid {u:?}");
    }
    for x in [
        Vec3::new(0.5, 0.5, 0.0),
        Vec3::new(0.0, 0.3, 0.6),
        Vec3::new(1.0, 0.7, 0.4),
        Vec3::new(0.4, 0.0, 0.8),
        Vec3::new(0.6, 1.0, 0.2),
    ] {
        let u = flow.sample(&(x * edge), 0.0).unwrap().u;
        assert!(u.amax() < 1e-12 * lid, "wall {x:?}: {u:?}");
    }
    // Primary vortex: backflow in the lower half, upflow near x = 0, downflow near x = L.
    let case = field.case;
    assert!(case.sample(&flow, Centreline::Vertical, 0.25).unwrap() < -0.05);
    assert!(case.sample(&flow, Centreline::Horizontal, 0.15).unwrap() > 0.05);
    assert!(case.sample(&flow, Centreline::Horizontal, 0.85).unwrap() < -0.05);
    // Mirror symmetry about y = L/2 (symmetric mesh, converged steady solution): the cell
    // values are symmetric to the solver's convergence and the file's 6 digits (1e-5 U), and
    // the reconstruction is symmetric on a symmetric mesh.
    for x in [Vec3::new(0.3, 0.2, 0.7), Vec3::new(0.8, 0.35, 0.3)] {
        let m = Vec3::new(x[0], 1.0 - x[1], x[2]);
        let (a, b) = (
            flow.sample(&(x * edge), 0.0).unwrap().u,
            flow.sample(&(m * edge), 0.0).unwrap().u,
        );
        assert!((a - Vec3::new(b[0], -b[1], b[2])).amax() < 1e-4 * lid, "{a:?} vs {b:?}");
    }
    let ratio = divergence_ratio(&flow, edge, 20, 0.0, 1.0);
    let core = divergence_ratio(&flow, edge, 20, 0.1, 0.9);
    let h = 1.0 / field.cells as f64;
    eprintln!("h/L = {h:.4}, rms tr∇u / rms |∇u|: {ratio:.3e} (cube), {core:.3e} (core)");
    (h, ratio, core)
}

/// Both shipped Re = 470 fields (60³ and the 12³ CI field, same case and solver) are lid
/// driven cavities, and the divergence of the reconstructed gradient falls at the rates the
/// discretisation predicts. The solver's flux divergence vanishes to its tolerance; the trace
/// of a cell's least-squares gradient of the cell-centred velocities differs from it by the
/// O(h²) truncation error where the flow is smooth, so away from the walls the ratio to |∇u|
/// must fall at least by (h₁₂/h₆₀)² = 25 from 12³ to 60³. Over the whole cube the lid edges,
/// where u jumps from U to 0, keep an O(1) ratio in a layer one cell thick, whose share of
/// the mean square is O(h/L): the rms falls at least like (h/L)^½, by √5. (Measured: core
/// 9.2e-2 → 2.6e-4, cube 0.25 → 3.3e-2.)
#[test]
fn re470_fields_are_lid_driven_cavities_converging_at_the_argued_rates() {
    let (h_fine, cube_fine, core_fine) = physical_facts(&RE470);
    let (h_coarse, cube_coarse, core_coarse) = physical_facts(&CI);
    let refinement = h_coarse / h_fine;
    assert!((refinement - 5.0).abs() < 1e-9, "refinement {refinement}");
    assert!(
        core_coarse / core_fine >= refinement.powi(2),
        "core divergence ratio {core_coarse:.3e} → {core_fine:.3e}: slower than second order"
    );
    assert!(
        cube_coarse / cube_fine >= refinement.sqrt(),
        "cube divergence ratio {cube_coarse:.3e} → {cube_fine:.3e}: slower than order ½"
    );
}

/// The extrema lie within 5 % of the spectral reference (`common::cavity_re1000_extrema`): a
/// uniform 60³ finite-volume grid is expected 2–5 % shallow (Ben Beya & Lili: 1–2 % at
/// 48³–64³ with a finer scheme, 5 % at 32³). The cellwise reconstruction adds an O(h²)
/// interpolation error, 0.3 % of U for h = L/60 and the curvature of these profiles, well
/// inside the bound.
/// The 5 % bound is the check; the snapshot of the extrema is a regression guard.
#[test]
fn re1000_extrema_through_the_openfoam_reader() {
    let flow = RE1000.load().unwrap();
    let text = common::cavity_re1000_extrema(&flow);
    // Rounded to 3 decimals (the shipped U has 6 significant digits).
    insta::assert_snapshot!(text);
}

//! Meshed flow fields (src/flow/unstructured): location, interpolation, readers, and the
//! shipped cavity field. Everything here runs without OpenFOAM.

use proptest::prelude::*;
use pseudorigid::error::FlowError;
use pseudorigid::flow::FlowField;
use pseudorigid::flow::unstructured::{HexMesh, MeshError, MeshedFlow, compact, vtk};
use pseudorigid::tensor::{Mat3, Vec3};
use std::path::PathBuf;

/// Structured n³ grid on [0, 1]³ (VTK hex order); interior points displaced by up to
/// `distortion`·h so that cells are general (non-affine) trilinear hexahedra.
fn grid_mesh(n: usize, distortion: f64) -> HexMesh {
    let h = 1.0 / n as f64;
    let id = |i: usize, j: usize, k: usize| (i + (n + 1) * (j + (n + 1) * k)) as u32;
    let mut points = Vec::new();
    for k in 0..=n {
        for j in 0..=n {
            for i in 0..=n {
                let mut p = Vec3::new(i as f64, j as f64, k as f64) * h;
                if [i, j, k].iter().all(|&c| c > 0 && c < n) {
                    let phase = (7 * i + 13 * j + 29 * k) as f64;
                    p += Vec3::new(phase.sin(), (1.3 * phase).cos(), (0.7 * phase).sin()) * (distortion * h);
                }
                points.push(p);
            }
        }
    }
    let mut cells = Vec::new();
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                cells.push([
                    id(i, j, k),
                    id(i + 1, j, k),
                    id(i + 1, j + 1, k),
                    id(i, j + 1, k),
                    id(i, j, k + 1),
                    id(i + 1, j, k + 1),
                    id(i + 1, j + 1, k + 1),
                    id(i, j + 1, k + 1),
                ]);
            }
        }
    }
    HexMesh::new(points, cells).expect("generated mesh is valid")
}

fn linear_gradient() -> Mat3 {
    Mat3::new(0.3, -1.2, 0.5, 0.7, 0.1, -0.4, -0.9, 0.6, -0.4)
}

/// The exactly linear field u = u₀ + L x sampled at the mesh points.
fn linear_flow(mesh: HexMesh) -> MeshedFlow {
    let (u0, l) = (Vec3::new(0.2, -0.1, 0.05), linear_gradient());
    let u = mesh.points().iter().map(|p| u0 + l * p).collect();
    let g = vec![l; mesh.points().len()];
    MeshedFlow::new(mesh, u, g).expect("consistent point data")
}

proptest! {
    /// Trilinear interpolation on trilinear cells is exact for linear fields: round-off only.
    #[test]
    fn linear_field_is_reproduced_on_distorted_cells(x in prop::array::uniform3(0.0..=1.0f64)) {
        let flow = linear_flow(grid_mesh(5, 0.2));
        let x = Vec3::from(x);
        let s = flow.sample(&x, 0.0).expect("inside the unit cube");
        let exact = Vec3::new(0.2, -0.1, 0.05) + linear_gradient() * x;
        prop_assert!((s.u - exact).amax() < 1e-13, "u error {}", (s.u - exact).amax());
        prop_assert!((s.grad_u - linear_gradient()).amax() < 1e-13);
    }
}

#[test]
fn located_cell_contains_the_point() {
    let flow = linear_flow(grid_mesh(6, 0.25));
    for k in 0..50 {
        let t = k as f64 * 0.618_033_988_75;
        let x = Vec3::new(t.fract(), (2.0 * t).fract(), (3.0 * t).fract());
        let loc = flow.locate(&x).expect("inside");
        let p = flow.mesh().cell_points(loc.cell);
        let (back, _) = pseudorigid::flow::unstructured::hex::map(&p, &loc.xi);
        assert!((back - x).amax() < 1e-13);
    }
}

#[test]
fn outside_points_are_typed_errors() {
    let flow = linear_flow(grid_mesh(4, 0.2));
    for x in [
        Vec3::new(1.0 + 1e-6, 0.5, 0.5),
        Vec3::new(0.5, -1e-6, 0.5),
        Vec3::new(0.5, 0.5, 3.0),
        Vec3::new(-2.0, -2.0, -2.0),
    ] {
        assert_eq!(
            flow.sample(&x, 0.0),
            Err(FlowError::OutsideDomain { x: [x[0], x[1], x[2]] })
        );
    }
    let nan = Vec3::new(f64::NAN, 0.5, 0.5);
    assert!(matches!(flow.sample(&nan, 0.0), Err(FlowError::NonFiniteQuery { .. })));
    // Points on the boundary (and on shared faces) are inside.
    assert!(flow.sample(&Vec3::new(1.0, 0.0, 0.25), 0.0).is_ok());
}

#[test]
fn inconsistent_point_data_is_rejected() {
    let mesh = grid_mesh(2, 0.0);
    let n = mesh.points().len();
    let err = MeshedFlow::new(mesh, vec![Vec3::zeros(); n - 1], vec![Mat3::zeros(); n]);
    assert!(matches!(err, Err(MeshError::MissingArray { .. })));
}

fn temp_path(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("pseudorigid-{}-{name}", std::process::id()))
}

#[test]
fn compact_form_round_trips_to_f32_precision() {
    let flow = linear_flow(grid_mesh(4, 0.0));
    let path = temp_path("roundtrip.prf");
    compact::write(&flow, &path, compact::FULL_PRECISION).expect("rectilinear mesh");
    let back = MeshedFlow::load(&path).expect("compact file");
    std::fs::remove_file(&path).ok();
    for x in [Vec3::new(0.1, 0.7, 0.33), Vec3::new(1.0, 1.0, 1.0)] {
        let (a, b) = (flow.sample(&x, 0.0).unwrap(), back.sample(&x, 0.0).unwrap());
        // f32 storage: relative rounding 2⁻²⁴ ≈ 6e-8 of values of order 1.
        assert!((a.u - b.u).amax() < 3e-7);
        assert!((a.grad_u - b.grad_u).amax() < 3e-7);
    }
    // Rounded to 12 mantissa bits: relative error ≤ 2⁻¹³ at the points, zeros exact.
    compact::write(&flow, &path, 12).expect("rectilinear mesh");
    let rounded = MeshedFlow::load(&path).expect("compact file");
    std::fs::remove_file(&path).ok();
    for x in flow.mesh().points() {
        let (a, b) = (flow.sample(x, 0.0).unwrap(), rounded.sample(x, 0.0).unwrap());
        for (p, q) in a.u.iter().chain(a.grad_u.iter()).zip(b.u.iter().chain(b.grad_u.iter())) {
            assert!((p - q).abs() <= 2f64.powi(-13) * p.abs() + 1e-12, "{p} vs {q}");
        }
    }
    let distorted = linear_flow(grid_mesh(4, 0.2));
    assert!(matches!(
        compact::write(&distorted, &temp_path("distorted.prf"), 12),
        Err(MeshError::NotRectilinear { .. })
    ));
}

/// A legacy VTK file as foamToVTK writes it (dataset-level TimeValue FIELD, cell and point
/// FIELD arrays), for a single unit cube holding the linear field.
fn legacy_vtk(binary: bool) -> Vec<u8> {
    let corners = pseudorigid::flow::unstructured::hex::CORNERS;
    let l = linear_gradient();
    let mut out = Vec::new();
    let block = |out: &mut Vec<u8>, ty: &str, values: &[f64]| {
        if binary {
            for &v in values {
                match ty {
                    "int" => out.extend((v as i32).to_be_bytes()),
                    _ => out.extend((v as f32).to_be_bytes()),
                }
            }
            out.push(b'\n');
        } else {
            let words: Vec<String> = values.iter().map(|v| format!("{v}")).collect();
            out.extend(words.join(" ").bytes());
            out.push(b'\n');
        }
    };
    let mode = if binary { "BINARY" } else { "ASCII" };
    out.extend(format!("# vtk DataFile Version 2.0\ncube\n{mode}\nDATASET UNSTRUCTURED_GRID\nFIELD FieldData 1\nTimeValue 1 1 float\n").bytes());
    block(&mut out, "float", &[42.0]);
    out.extend(b"POINTS 8 float\n");
    let points: Vec<f64> = corners.iter().flatten().copied().collect();
    block(&mut out, "float", &points);
    out.extend(b"CELLS 1 9\n");
    block(&mut out, "int", &[8.0, 0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);
    out.extend(b"CELL_TYPES 1\n");
    block(&mut out, "int", &[12.0]);
    out.extend(b"CELL_DATA 1\nFIELD attributes 1\nU 3 1 float\n");
    block(&mut out, "float", &[0.0, 0.0, 0.0]);
    out.extend(b"POINT_DATA 8\nFIELD attributes 2\nU 3 8 float\n");
    let u: Vec<f64> = corners
        .iter()
        .flat_map(|c| (l * Vec3::from(*c)).iter().copied().collect::<Vec<_>>())
        .collect();
    block(&mut out, "float", &u);
    // OpenFOAM writes grad(U) as T_ij = ∂_i U_j row-major: T = Lᵀ, whose row-major order
    // is the column-major order nalgebra iterates L in.
    out.extend(b"grad(U) 9 8 float\n");
    let t: Vec<f64> = (0..8).flat_map(|_| l.iter().copied().collect::<Vec<_>>()).collect();
    block(&mut out, "float", &t);
    out
}

#[test]
fn legacy_vtk_ascii_and_binary_are_read() {
    for binary in [false, true] {
        let path = temp_path(if binary { "bin.vtk" } else { "ascii.vtk" });
        std::fs::write(&path, legacy_vtk(binary)).unwrap();
        let grid = vtk::read_legacy(&path).expect("foamToVTK-style file");
        assert_eq!((grid.points.len(), grid.cells.len()), (8, 1));
        let flow = MeshedFlow::load(&path).expect("U and grad(U) present");
        std::fs::remove_file(&path).ok();
        let x = Vec3::new(0.25, 0.5, 0.75);
        let s = flow.sample(&x, 0.0).unwrap();
        assert!((s.u - linear_gradient() * x).amax() < 1e-6);
        // f32 file values; the transpose convention is what is checked here.
        assert!((s.grad_u - linear_gradient()).amax() < 1e-6);
    }
}

#[test]
fn truncated_vtk_is_malformed_not_a_panic() {
    let mut bytes = legacy_vtk(true);
    bytes.truncate(bytes.len() / 2);
    let path = temp_path("truncated.vtk");
    std::fs::write(&path, bytes).unwrap();
    let err = MeshedFlow::load(&path);
    std::fs::remove_file(&path).ok();
    assert!(matches!(err, Err(MeshError::Malformed { .. })));
}

/// The shipped OpenFOAM fields (reference-data/*.prf, provenance next to them).
mod shipped {
    use super::*;
    use pseudorigid::scenes::cavity_benchmark::{CavityCase, Centreline};

    const EDGE: f64 = 0.1;
    const LID: f64 = 0.0813;

    fn load(name: &str) -> MeshedFlow {
        let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("reference-data")
            .join(name);
        MeshedFlow::load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    }

    /// RMS of tr ∇u over RMS of |∇u| (Frobenius) on a lattice of n³ points filling the cube
    /// [lo, hi]³ (in units of L).
    fn divergence_ratio(flow: &MeshedFlow, n: usize, lo: f64, hi: f64) -> f64 {
        let (mut tr2, mut g2) = (0.0, 0.0);
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    let s = |i: usize| lo + (hi - lo) * (i as f64 + 0.5) / n as f64;
                    let x = Vec3::new(s(i), s(j), s(k)) * EDGE;
                    let g = flow.sample(&x, 0.0).unwrap().grad_u;
                    tr2 += g.trace().powi(2);
                    g2 += g.norm_squared();
                }
            }
        }
        (tr2 / g2).sqrt()
    }

    /// Checks lid, walls, vortex sense and symmetry; returns h/L and the divergence ratios
    /// (whole cube, core [0.1, 0.9]³).
    fn physical_facts(flow: &MeshedFlow) -> (f64, f64, f64) {
        let h = EDGE / (flow.mesh().cells().len() as f64).cbrt();
        // Lid: u = (U, 0, 0) on the lid away from its edges (12 mantissa bits: 1.2e-4 relative).
        for (x, y) in [(0.5, 0.5), (0.2, 0.8), (0.9, 0.1)] {
            let u = flow.sample(&(Vec3::new(x, y, 1.0) * EDGE), 0.0).unwrap().u;
            assert!((u - Vec3::new(LID, 0.0, 0.0)).amax() < 2e-4 * LID, "lid {u:?}");
        }
        // No-slip: the wall point values are exactly zero; the walls sit at f32 coordinates
        // (0.1 → 0.1 + 1.5e-9), so a query on the f64 wall plane picks up ~1e-8 of a cell.
        for x in [
            Vec3::new(0.5, 0.5, 0.0),
            Vec3::new(0.0, 0.3, 0.6),
            Vec3::new(1.0, 0.7, 0.4),
            Vec3::new(0.4, 0.0, 0.8),
            Vec3::new(0.6, 1.0, 0.2),
        ] {
            let u = flow.sample(&(x * EDGE), 0.0).unwrap().u;
            assert!(u.amax() < 1e-6 * LID, "wall {x:?}: {u:?}");
        }
        // Primary vortex: backflow in the lower half, upflow near x = 0, downflow near x = L.
        let case = CavityCase {
            edge: EDGE,
            lid_speed: LID,
        };
        assert!(case.sample(flow, Centreline::Vertical, 0.25).unwrap() < -0.05);
        assert!(case.sample(flow, Centreline::Horizontal, 0.15).unwrap() > 0.05);
        assert!(case.sample(flow, Centreline::Horizontal, 0.85).unwrap() < -0.05);
        // Mirror symmetry about y = L/2 (symmetric mesh, converged steady solution).
        for x in [Vec3::new(0.3, 0.2, 0.7), Vec3::new(0.8, 0.35, 0.3)] {
            let m = Vec3::new(x[0], 1.0 - x[1], x[2]);
            let (a, b) = (
                flow.sample(&(x * EDGE), 0.0).unwrap().u,
                flow.sample(&(m * EDGE), 0.0).unwrap().u,
            );
            assert!((a - Vec3::new(b[0], -b[1], b[2])).amax() < 1e-4 * LID, "{a:?} vs {b:?}");
        }
        let ratio = divergence_ratio(flow, 20, 0.0, 1.0);
        let core = divergence_ratio(flow, 20, 0.1, 0.9);
        eprintln!(
            "h/L = {:.4}, rms tr∇u / rms |∇u|: {ratio:.3e} (cube), {core:.3e} (core)",
            h / EDGE
        );
        (h / EDGE, ratio, core)
    }

    /// Both shipped Re = 470 fields (60³ and the 12³ CI field, same case and solver) are lid
    /// driven cavities, and their divergence error falls at the rates the discretisation
    /// predicts. tr ∇u of the Gauss-linear gradient is the divergence of linearly interpolated
    /// face velocities; it differs from the conservative flux divergence (zero to the solver
    /// tolerance, 1e-8) by the Rhie–Chow pressure term, O(h²) where the flow is smooth: away
    /// from the walls the ratio to |∇u| must fall at least by (h₁₂/h₆₀)² = 25 from 12³ to 60³.
    /// Over the whole cube the lid edges, where u jumps from U to 0, keep an O(1) ratio in a
    /// layer one cell thick, whose share of the mean square is O(h/L): the rms falls at least
    /// like (h/L)^½, by √5. (Measured: core 3.9e-2 → 3.0e-4, cube 3.9e-2 → 1.4e-2.)
    #[test]
    fn re470_fields_are_lid_driven_cavities_converging_at_the_argued_rates() {
        let (h_fine, cube_fine, core_fine) = physical_facts(&load("cavity_re470.prf"));
        let (h_coarse, cube_coarse, core_coarse) = physical_facts(&load("cavity_ci.prf"));
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
}

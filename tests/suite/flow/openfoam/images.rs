//! Patches particles pass through (src/flow/openfoam/images.rs, the driver's crossings) on
//! meshes OpenFOAM's blockMesh wrote (`tests/data/coupled-*`), against closed forms: a periodic
//! plane Poiseuille channel (translational `cyclic`), a swirling flow in a 90° sector
//! (rotational `cyclicAMI`) and in a 5° wedge (`wedge`), both periodic along the axis, and a
//! sphere settling onto a `symmetryPlane`.

use crate::common::build::copy_case;
use pseudorigid::contact::{ContactEvent, ContactModel, MeshBoundary};
use pseudorigid::driver::{Plan, Problem, Stop, until_event};
use pseudorigid::ellipsoid::Ellipsoid;
use pseudorigid::flow::openfoam::{BlendedFlow, FoamCase, FoamFlow, PolyMesh, check_particle_patches};
use pseudorigid::flow::{FlowField, Isometry};
use pseudorigid::material::Rigid;
use pseudorigid::particle::{Fluid, Particle, State};
use pseudorigid::tensor::{Mat3, Vec3};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// How a test writes a patch's entry in `0/U`: its condition with the exact field's values at
/// the face centres, or the condition alone (as OpenFOAM writes `cyclic`, `wedge`,
/// `symmetryPlane` and `noSlip`).
enum Entry {
    Value(&'static str),
    Bare(&'static str),
}

/// A copy of the fixture `tests/data/<fixture>` with `0/U` = u written in ASCII, each patch's
/// entry as `entry` says.
fn case(name: &str, fixture: &str, u: impl Fn(&Vec3) -> Vec3, entry: impl Fn(&str) -> Entry) -> PathBuf {
    let from = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(fixture);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("images").join(name);
    copy_case(&from, &dir, &["constant/polyMesh", "system"]);
    let mesh = PolyMesh::read(&dir).unwrap();
    let list = |xs: &[Vec3]| {
        let mut s = format!("nonuniform List<vector> {}(", xs.len());
        for x in xs {
            let v = u(x);
            write!(s, "({:e} {:e} {:e}) ", v[0], v[1], v[2]).unwrap();
        }
        s + ")"
    };
    let mut text = String::from(
        "FoamFile { version 2.0; format ascii; class volVectorField; object U; }\n\
         dimensions [0 1 -1 0 0 0 0];\n",
    );
    writeln!(text, "internalField {};\nboundaryField\n{{", list(mesh.cell_centres())).unwrap();
    for p in mesh.patches() {
        match entry(&p.name) {
            Entry::Value(kind) => {
                let faces = &mesh.face_centres()[p.start..p.start + p.size];
                writeln!(text, "    {} {{ type {kind}; value {}; }}", p.name, list(faces)).unwrap();
            }
            Entry::Bare(kind) => writeln!(text, "    {} {{ type {kind}; }}", p.name).unwrap(),
        }
    }
    text.push_str("}\n");
    std::fs::create_dir_all(dir.join("0")).unwrap();
    std::fs::write(dir.join("0/U"), text).unwrap();
    dir
}

/// The blended field (the default) of `dir`'s time 0, and its mesh boundary.
fn field(dir: &Path) -> (BlendedFlow, MeshBoundary) {
    let foam = FoamCase::open(dir).unwrap();
    check_particle_patches(foam.mesh()).unwrap();
    let boundary = MeshBoundary::new(foam.mesh()).unwrap();
    let cells = FoamFlow::read(&foam, &[0.0]).unwrap();
    (BlendedFlow::new(cells).unwrap(), boundary)
}

/// A point tracer: a rigid sphere of radius `a` without inertia (overdamped Stokesian), which
/// moves with the sampled fluid velocity, from `x0` to `t_end` or its first wall contact,
/// Radau IIA at `tol`.
fn trace(flow: &BlendedFlow, boundary: &MeshBoundary, x0: Vec3, t_end: f64, tol: f64) -> (State, Stop) {
    let shape = Ellipsoid::new([1e-4; 3], Mat3::identity()).unwrap();
    let particle = Particle::new(shape, Rigid, Fluid::new(1e-3, 1e3).unwrap(), 1e3).unwrap();
    let integrator = pseudorigid::integrator::Stokesian::overdamped(tol).unwrap();
    let contact = ContactEvent::new(boundary, &particle, flow, ContactModel::Extent);
    let plan = Plan::new(t_end, 1e-4).unwrap();
    let out = until_event(
        Problem::new(&integrator, &particle, flow),
        State::at_rest(x0),
        &plan,
        &[&contact],
    )
    .unwrap();
    (out.state, out.stop)
}

/// Tracers in a plane Poiseuille channel, u = U 4y(H − y)/H² e_x (U = 1, H = 0.2), periodic in
/// x (L = 1, `cyclic` left and right, written without values as OpenFOAM writes them), between
/// `symmetryPlane`s in z: after 100 flow-throughs every tracer is inside, at its height and
/// depth, and back at its start x to 10⁻⁶ of its travel. The closed form is that of the field the
/// tracer sees: a flow-through takes $T = \int_0^L dx/u_h(x, y_0)$, $u_h$ the sampled field,
/// by Simpson's rule on 4 000 intervals (the blend is smooth: its error is far below 10⁻⁹), so
/// after 100 T the tracer is where it started. Near the walls $u_h$ varies along x by a few
/// 10⁻⁴ near the pair, where the wall layer's fits do not see across it (module docs of
/// `images`); the field's own error against the profile, quadratic where the reconstruction is
/// linear, is bounded by ½|u''|Δy² = U/16 on Δy = H/8.
#[test]
fn tracers_in_a_periodic_poiseuille_channel_advance_with_the_profile() {
    let (h, big_u) = (0.2, 1.0);
    let profile = |x: &Vec3| Vec3::new(big_u * 4.0 * x[1] * (h - x[1]) / (h * h), 0.0, 0.0);
    let dir = case("poiseuille", "coupled-box", profile, |name| match name {
        "walls" => Entry::Bare("noSlip"),
        "left" | "right" => Entry::Bare("cyclic"),
        _ => Entry::Bare("symmetryPlane"),
    });
    let (flow, boundary) = field(&dir);
    for y0 in [0.03, 0.1, 0.155] {
        let x0 = Vec3::new(0.3, y0, 0.05);
        let n = 4000;
        let slowness = |i: usize| {
            let x = Vec3::new(i as f64 / n as f64, y0, 0.05);
            let u = flow.sample(&x, 0.0).unwrap().u[0];
            assert!((u - profile(&x)[0]).abs() <= big_u / 16.0, "u_h = {u} at {x:?}");
            1.0 / u
        };
        let simpson: f64 = (0..=n)
            .map(|i| {
                slowness(i)
                    * if i == 0 || i == n {
                        1.0
                    } else if i % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    }
            })
            .sum();
        let period = simpson / (3.0 * n as f64);
        let (end, stop) = trace(&flow, &boundary, x0, 100.0 * period, 1e-10);
        assert_eq!(stop, Stop::EndTime, "y0 = {y0}");
        let miss = (end.x[0] - x0[0] + 0.5).rem_euclid(1.0) - 0.5;
        assert!(
            miss.abs() <= 1e-6 * 100.0,
            "y0 = {y0}: x = {} after 100 periods",
            end.x[0]
        );
        assert!(
            (end.x[1] - y0).abs() <= 1e-12 && (end.x[2] - 0.05).abs() <= 1e-12,
            "{:?}",
            end.x
        );
        assert!((0.0..=1.0).contains(&end.x[0]), "outside: {:?}", end.x);
    }
}

/// The swirl u = Ω e_z × x + W e_z (Ω = 1, W = 0.1): linear, so the reconstruction is exact
/// and a tracer's path is the helix r = r₀, φ = φ₀ + Ωt, z = z₀ + Wt, seen in the domain
/// with φ wrapped into the mesh's sector and z into [0, 0.5].
fn swirl(x: &Vec3) -> Vec3 {
    Vec3::new(-x[1], x[0], 0.1)
}

/// (r, φ, z) of the closed-form helix from `x0` after t, φ wrapped into [lo, lo + width).
fn helix(x0: &Vec3, t: f64, lo: f64, width: f64) -> (f64, f64, f64) {
    let r = x0.xy().norm();
    let phi = (x0[1].atan2(x0[0]) + t - lo).rem_euclid(width) + lo;
    (r, phi, (x0[2] + 0.1 * t).rem_euclid(0.5))
}

/// The tracer's (r, φ, z) against the helix: r (its angular momentum per unit mass Ωr²) to
/// `rel` of r₀, φ to `rel` rad and z to 10⁻⁷. On the sector `rel` = 10⁻⁷: Radau IIA at
/// rtol 10⁻¹⁰ over a few hundred steps accumulates at most a few 10⁻⁸, each crossing is
/// located to 10⁻⁹ of the step's travel and mapped by an exact rotation or translation.
fn assert_on_helix(end: &State, x0: &Vec3, t: f64, lo: f64, width: f64, rel: f64) {
    let (r, phi, z) = helix(x0, t, lo, width);
    let (r_h, phi_h) = (end.x.xy().norm(), end.x[1].atan2(end.x[0]));
    assert!((r_h - r).abs() <= rel * r, "r = {r_h} against {r}");
    assert!((phi_h - phi).abs() <= rel, "phi = {phi_h} against {phi}");
    assert!((end.x[2] - z).abs() <= 1e-7, "z = {} against {z}", end.x[2]);
}

/// Tracers in a 90° sector of the swirl (`cyclicAMI` sides with a rotational transform, as
/// OpenFOAM's pipeCyclic tutorial has them, values stored as OpenFOAM writes them; `cyclic`
/// ends): two turns, eight crossings of the sides and two or three of the ends, on the helix.
#[test]
fn tracers_in_a_rotational_sector_keep_their_angular_momentum() {
    let dir = case("sector", "coupled-sector", swirl, |name| match name {
        "bottom" | "top" => Entry::Bare("cyclic"),
        "side1" | "side2" => Entry::Value("cyclicAMI"),
        _ => Entry::Value("fixedValue"),
    });
    let (flow, boundary) = field(&dir);
    let t = 4.0 * std::f64::consts::PI;
    for (r0, phi0) in [(0.75, 0.3), (0.6, 1.2), (0.9, 0.05)] {
        let x0 = Vec3::new(r0 * f64::cos(phi0), r0 * f64::sin(phi0), 0.25);
        let (end, stop) = trace(&flow, &boundary, x0, t, 1e-10);
        assert_eq!(stop, Stop::EndTime);
        assert_on_helix(&end, &x0, t, 0.0, std::f64::consts::FRAC_PI_2, 1e-7);
    }
}

/// The same swirl on an axisymmetric 5° wedge (`wedge` front and back, written without values
/// as OpenFOAM writes them; `cyclic` ends): a tracer crossing the wedge 11 times in one radian
/// is rotated back each time and stays on the helix, as on the 3-D sector, to the wedge
/// condition's own error: its face value is the cell's rotated onto the face (as OpenFOAM's
/// `wedge` condition evaluates it), whose centre lies off the rotated cell centre by up to
/// r(1/cos α − 1) ≈ rα²/2 (α = 2.5° the half angle), a relative velocity error α²/2 = 9.5·10⁻⁴
/// at the faces; over Ωt = 1 the path moves at most α²/2 of r and of a radian off the helix.
#[test]
fn tracers_in_a_wedge_are_rotated_back_onto_the_helix() {
    let dir = case("wedge", "coupled-wedge", swirl, |name| match name {
        "bottom" | "top" => Entry::Bare("cyclic"),
        "front" | "back" => Entry::Bare("wedge"),
        _ => Entry::Value("fixedValue"),
    });
    let (flow, boundary) = field(&dir);
    let half = 2.5f64.to_radians();
    for r0 in [0.3, 0.6, 0.85] {
        let x0 = Vec3::new(r0, 0.0, 0.25);
        let (end, stop) = trace(&flow, &boundary, x0, 1.0, 1e-10);
        assert_eq!(stop, Stop::EndTime);
        assert_on_helix(&end, &x0, 1.0, -half, 2.0 * half, half * half / 2.0);
    }
}

/// A rigid sphere (a = 2 mm, ρ_p = 2 000, ρ_f = 1 000 kg/m³, μ = 0.01 Pa s, g = 1 m/s² towards
/// the `symmetryPlane` z = 0) released at rest at z₀ = 0.05 in still fluid: it is reflected
/// each time its barycentre reaches the plane, never deposited. Between crossings the closed
/// form with Stokes drag and reduced gravity holds, w(t) = −v_t + (w_k + v_t)e^{−(t−t_k)/τ},
/// τ = 2ρ_p a²/(9μ), v_t = τg(1 − ρ_f/ρ_p); at a crossing w changes sign. After 2 s (the first
/// crossing near 0.7 s, then bounces) z and w match the piecewise closed form to 10⁻⁷ m and
/// 10⁻⁶ m/s: the crossings are located to 10⁻⁹ of a step's travel and the steps integrated at
/// rtol 10⁻¹⁰; the drag damps what an error at one crossing carries to the next.
#[test]
fn a_sphere_settling_onto_a_symmetry_plane_is_reflected() {
    let dir = case(
        "settling",
        "coupled-box",
        |_| Vec3::zeros(),
        |name| match name {
            "walls" => Entry::Bare("noSlip"),
            "left" | "right" => Entry::Bare("cyclic"),
            _ => Entry::Bare("symmetryPlane"),
        },
    );
    let (flow, boundary) = field(&dir);
    let (a, rho_p, rho_f, mu, g) = (2e-3, 2000.0, 1000.0, 0.01, 1.0);
    let shape = Ellipsoid::new([a; 3], Mat3::identity()).unwrap();
    let particle = Particle::new(shape, Rigid, Fluid::new(mu, rho_f).unwrap(), rho_p)
        .unwrap()
        .with_gravity(Vec3::new(0.0, 0.0, -g))
        .unwrap();
    let integrator = pseudorigid::integrator::Stokesian::new(1e-10).unwrap();
    let contact = ContactEvent::new(&boundary, &particle, &flow, ContactModel::Extent);
    let t_end = 2.0;
    let out = until_event(
        Problem::new(&integrator, &particle, &flow),
        State::at_rest(Vec3::new(0.5, 0.1, 0.05)),
        &Plan::new(t_end, 1e-4).unwrap(),
        &[&contact],
    )
    .unwrap();
    assert_eq!(out.stop, Stop::EndTime, "{:?}", out.state.x);
    // The piecewise closed form.
    let tau = 2.0 * rho_p * a * a / (9.0 * mu);
    let v_t = tau * g * (1.0 - rho_f / rho_p);
    let z_at = |zk: f64, wk: f64, s: f64| zk - v_t * s + tau * (wk + v_t) * (1.0 - (-s / tau).exp());
    let w_at = |wk: f64, s: f64| -v_t + (wk + v_t) * (-s / tau).exp();
    let (mut tk, mut zk, mut wk, mut bounces) = (0.0, 0.05, 0.0, 0);
    loop {
        // The next crossing: z decreases through 0 after its top; bisect on a bracket.
        let (mut lo, mut hi) = (0.0, t_end - tk);
        if z_at(zk, wk, hi) > 0.0 {
            break;
        }
        if wk > 0.0 {
            lo = tau * (1.0 + wk / v_t).ln();
        }
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if z_at(zk, wk, mid) > 0.0 { lo = mid } else { hi = mid }
        }
        (tk, zk, wk, bounces) = (tk + hi, 0.0, -w_at(wk, hi), bounces + 1);
    }
    assert!(bounces >= 2, "{bounces} crossings");
    let (z, w) = (z_at(zk, wk, t_end - tk), w_at(wk, t_end - tk));
    assert!(
        (out.state.x[2] - z).abs() <= 1e-7,
        "z = {} against {z} after {bounces} crossings",
        out.state.x[2]
    );
    assert!((out.state.v[2] - w).abs() <= 1e-6, "w = {} against {w}", out.state.v[2]);
}

/// The mirror image of a soft particle's state (module docs of `pseudorigid::flow::image`):
/// det F > 0, the same stretches (singular values of F), the barycentre and its velocity
/// mirrored, the deformed ellipsoid $F B_0 F^T$ (B₀ = R₀ diag(r²) R₀ᵀ, a rest shape tilted out
/// of every coordinate plane) the mirror image of the original's, and mirroring twice gives the
/// state back. With P = diag(1, 1, −1) in place of the rest shape's own principal reflection the
/// ellipsoid check fails by O(1) for this tilt.
#[test]
fn a_mirrored_state_keeps_its_shape_and_orientation_sense() {
    let mirror = Isometry::reflection(Vec3::new(0.0, 0.0, 0.1), &Vec3::new(0.0, 0.6, 0.8));
    let f = Mat3::new(1.3, 0.2, -0.1, 0.05, 0.8, 0.3, -0.2, 0.1, 0.95);
    let rest = *nalgebra::Rotation3::from_euler_angles(0.3, -0.5, 0.7).matrix();
    let b0 = rest * Mat3::from_diagonal(&Vec3::new(9.0, 4.0, 1.0)) * rest.transpose();
    let s = State {
        t: 1.0,
        x: Vec3::new(0.2, 0.3, 0.4),
        v: Vec3::new(1.0, -2.0, 0.5),
        f,
        a: Mat3::new(0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9),
    };
    let m = s.mapped(&mirror, &rest);
    assert!(m.f.determinant() > 0.0 && (m.f.determinant() - f.determinant()).abs() <= 1e-14);
    let (sv, svm) = (f.singular_values(), m.f.singular_values());
    assert!((sv - svm).norm() <= 1e-14, "{sv} {svm}");
    let shape = |f: &Mat3| f * b0 * f.transpose();
    let mirrored = mirror.q * shape(&f) * mirror.q.transpose();
    assert!(
        (shape(&m.f) - mirrored).amax() <= 1e-13,
        "{} against {mirrored}",
        shape(&m.f)
    );
    let n = Vec3::new(0.0, 0.6, 0.8);
    assert!(((m.x - s.x).cross(&n)).norm() <= 1e-15, "moved along the normal only");
    assert!(
        ((m.x + s.x) * 0.5 - Vec3::new(0.0, 0.0, 0.1)).dot(&n).abs() <= 1e-15,
        "midpoint on the plane"
    );
    let back = m.mapped(&mirror, &rest);
    assert!((back.x - s.x).norm() <= 1e-15 && (back.f - s.f).norm() <= 1e-14 && (back.a - s.a).norm() <= 1e-14);
}

/// A mirrored pair in the whole box moves as one particle in the half box (issue 57, item 1):
/// `coupled-box-full` is `coupled-box` joined to its mirror image about z = 0, where the half box
/// has its `symmetryPlane`. In the linear shear u = (y, 0, 0) (exact on both meshes, walls y = 0
/// at rest and y = 0.2 sliding) a rigid prolate (4 × 2 × 2 mm, ρ_p = 2ρ_f, τ_p ≈ 0.18 s), its rest
/// shape tilted out of every coordinate plane, is thrown at the plane z = 0 from z = 0.02 at
/// 0.5 m/s and crosses it; in the whole box its mirror twin starts at z = −0.02 thrown the other
/// way. After 1 s the two whole-box states are each other's mirror images, and the half-box
/// particle, reflected at the plane, is the one of them above it: barycentre to 1e-7 m, its
/// velocity to 1e-6 m/s, the deformed ellipsoid F B₀ Fᵀ to 1e-6 of its size (the steps at rtol 1e-10 and the crossing located to 1e-9 of a step's travel; the
/// fields agree to round-off, both exact for a linear field).
#[test]
fn a_mirrored_pair_in_the_whole_box_moves_as_one_in_the_half() {
    let entry = |name: &str| match name {
        "walls" => Entry::Value("fixedValue"),
        "left" | "right" => Entry::Bare("cyclic"),
        _ => Entry::Bare("symmetryPlane"),
    };
    let shear = |x: &Vec3| Vec3::new(x[1], 0.0, 0.0);
    let half = case("pair-half", "coupled-box", shear, entry);
    let whole = case("pair-whole", "coupled-box-full", shear, entry);
    let mirror = Isometry::reflection(Vec3::zeros(), &Vec3::z());
    let rest = *nalgebra::Rotation3::from_euler_angles(0.3, -0.5, 0.7).matrix();
    let twin_rest = mirror.q * rest * Mat3::from_diagonal(&Vec3::new(1.0, 1.0, -1.0));
    let run = |dir: &Path, axes: Mat3, x0: Vec3, v0: Vec3| {
        let (flow, boundary) = field(dir);
        let shape = Ellipsoid::new([4e-3, 2e-3, 2e-3], axes).unwrap();
        let particle = Particle::new(shape, Rigid, Fluid::new(0.01, 1000.0).unwrap(), 2000.0).unwrap();
        let integrator = pseudorigid::integrator::Stokesian::new(1e-10).unwrap();
        let contact = ContactEvent::new(&boundary, &particle, &flow, ContactModel::Extent);
        let start = State {
            v: v0,
            ..State::at_rest(x0)
        };
        let out = until_event(
            Problem::new(&integrator, &particle, &flow),
            start,
            &Plan::new(1.0, 1e-4).unwrap(),
            &[&contact],
        )
        .unwrap();
        assert_eq!(out.stop, Stop::EndTime, "{:?}", out.state.x);
        out.state
    };
    let (x0, v0) = (Vec3::new(0.3, 0.1, 0.02), Vec3::new(0.0, 0.0, -0.5));
    let one = run(&half, rest, x0, v0);
    let a = run(&whole, rest, x0, v0);
    let b = run(&whole, twin_rest, mirror.point(&x0), mirror.q * v0);
    assert!(
        a.x[2] < 0.0 && b.x[2] > 0.0 && one.x[2] > 0.0,
        "no crossing: {} {} {}",
        a.x,
        b.x,
        one.x
    );
    // The deformed ellipsoids F B₀ Fᵀ (each with its own rest shape B₀) and the barycentres'
    // positions and velocities.
    let b0 = |axes: &Mat3| axes * Mat3::from_diagonal(&Vec3::new(16e-6, 4e-6, 4e-6)) * axes.transpose();
    let (b0_a, b0_b) = (b0(&rest), b0(&twin_rest));
    let close = |p: &State, p_b0: &Mat3, q: &State, q_b0: &Mat3, what: &str| {
        let (sp, sq) = (p.f * p_b0 * p.f.transpose(), q.f * q_b0 * q.f.transpose());
        assert!(
            (p.x - q.x).amax() <= 1e-7 && (p.v - q.v).amax() <= 1e-6 && (sp - sq).amax() <= 1e-6 * 16e-6,
            "{what}: x {} against {}, v {} against {}, F B₀ Fᵀ {sp} against {sq}",
            p.x,
            q.x,
            p.v,
            q.v
        );
    };
    let a_mirrored = a.mapped(&mirror, &rest);
    close(&b, &b0_b, &a_mirrored, &b0_a, "the whole box's pair");
    close(&one, &b0_a, &b, &b0_b, "the half box against the twin above the plane");
}

/// A decomposed case's cyclic faces across processors and the cyclic types not handled are
/// refused by name, with what to do for the first.
#[test]
fn unhandled_coupled_types_are_refused_by_name() {
    for (kind, hint) in [
        ("processorCyclic", "reconstructPar"),
        ("cyclicACMI", ""),
        ("cyclicSlip", ""),
    ] {
        let dir = case(kind, "coupled-box", |_| Vec3::zeros(), |_| Entry::Bare("zeroGradient"));
        crate::common::build::retype(&dir, "left", kind);
        let mesh = PolyMesh::read(&dir).unwrap();
        let e = check_particle_patches(&mesh).unwrap_err().to_string();
        assert!(e.contains("`left`") && e.contains(kind) && e.contains(hint), "{e}");
    }
}

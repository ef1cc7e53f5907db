//! Contact with mesh walls (src/contact/mesh.rs, src/contact/event.rs) against exact geometry:
//! a 90° step (a convex edge and a concave corner) and a wall kinked by 5° (the edge of a faceted
//! cylinder), meshed with 0.5 mm hexahedra. Every expected answer below is computed from the
//! geometry alone: the distance to the wall set, the closed-form section of an ellipsoid by a
//! plane, the point where a straight flight first comes within a radius of the wall.

use crate::common::build::{carved_box, pipe};
use pseudorigid::contact::{Boundary, ContactEvent, ContactModel, Extent, MeshBoundary, PatchRule};
use pseudorigid::driver::{Plan, Problem, Stop, until_event};
use pseudorigid::ellipsoid::{Ellipsoid, PrincipalFrame};
use pseudorigid::flow::analytic::Quiescent;
use pseudorigid::integrator::Stokesian;
use pseudorigid::material::Rigid;
use pseudorigid::particle::{Fluid, Particle, State};
use pseudorigid::tensor::{Mat3, Vec3};

const MM: f64 = 1e-3;

/// Grid lines every 0.5 mm from `lo` to `hi` (mm).
fn lines(lo: f64, hi: f64) -> Vec<f64> {
    let n = ((hi - lo) / 0.5).round() as usize;
    (0..=n).map(|i| (lo + 0.5 * i as f64) * MM).collect()
}

/// A 5 mm step along z: plateau y = 0 (x < 0), vertical face x = 0 (−5 mm < y < 0), floor
/// y = −5 mm (x > 0); the convex edge is the z axis, the concave corner the line
/// (0, −5 mm, z). Open (exit) faces on the box's other sides, at least 2.5 mm from the edge.
fn step() -> MeshBoundary {
    let on = |a: f64, b: f64| (a - b).abs() < 1e-9 * MM;
    let raw = carved_box(
        &lines(-5.0, 5.0),
        &lines(-5.0, 5.0),
        &lines(-2.5, 2.5),
        |p| p,
        |c| c[0] < 0.0 && c[1] < 0.0,
        |c| (on(c[1], 0.0) && c[0] < 0.0) || (on(c[0], 0.0) && c[1] < 0.0) || (on(c[1], -5.0 * MM) && c[0] > 0.0),
    );
    MeshBoundary::new(&raw.mesh()).unwrap()
}

/// Distance from x (in the fluid, within 2 mm of the edge) to the step's walls.
fn step_distance(x: &Vec3) -> f64 {
    let plateau = if x[0] <= 0.0 { x[1].abs() } else { x[0].hypot(x[1]) };
    let vertical = if x[1] <= 0.0 { x[0].abs() } else { x[0].hypot(x[1]) };
    let floor = if x[0] >= 0.0 {
        (x[1] + 5.0 * MM).abs()
    } else {
        x[0].hypot(x[1] + 5.0 * MM)
    };
    plateau.min(vertical).min(floor)
}

/// The wall's drop beyond the kink of [`kinked`].
const KINK: f64 = 5.0 * std::f64::consts::PI / 180.0;

/// A wall y = 0 for x < 0 that turns down by 5° at the z axis (y = −x tan 5° for x > 0): the
/// convex edge between two facets of a faceted cylinder of 72 sides. The fluid above it up to
/// y = 5 mm; open faces elsewhere.
fn kinked() -> MeshBoundary {
    let height = 5.0 * MM;
    let drop = |x: f64| -KINK.tan() * x.max(0.0);
    let raw = carved_box(
        &lines(-5.0, 5.0),
        &lines(0.0, 5.0),
        &lines(-2.5, 2.5),
        |p| Vec3::new(p[0], p[1] + drop(p[0]) * (1.0 - p[1] / height), p[2]),
        |_| false,
        |c| (c[1] - drop(c[0])).abs() < 1e-9 * MM,
    );
    MeshBoundary::new(&raw.mesh()).unwrap()
}

/// A point and a sphere of radius 10 µm: the gap is the distance to the walls less the radius,
/// to rounding (1e-12 mm), on a grid about the step's convex edge — also over the edge, where the
/// planes of the plateau and of the vertical face both cut through the fluid. The gap was the
/// plane gap of the face nearest to the support point there: points 16–172 µm above the corner
/// of OpenFOAM's pitzDaily step were recorded deposited on the vertical face's plane.
#[test]
fn step_gap_of_points_and_spheres_is_their_distance_to_the_walls() {
    let boundary = step();
    for radius in [0.0, 10e-6] {
        for i in -40..=40 {
            for j in -40..=40 {
                let x = Vec3::new(i as f64 * 25e-6, j as f64 * 25e-6, 0.3 * MM);
                if x[0] < 0.0 && x[1] < 0.0 {
                    continue;
                }
                let exact = step_distance(&x) - radius;
                let gap = boundary.nearest(&x, &Extent::Point { radius }).gap;
                assert!(
                    (gap - exact).abs() <= 1e-15,
                    "radius {radius}: at {x:?} gap {gap} against the distance {exact}"
                );
            }
        }
    }
}

/// The smallest value of coordinate `along` over the section of the ellipsoid c + L·u (|u| ≤ 1)
/// by the plane x[`across`] = 0, or `None` where the plane misses it: with l_p, l_o the rows of L,
/// the section is l_p·u = −c_p, and the minimum of l_o·u there is
/// β l_o·l̂_p − |l_o⊥| √(1 − β²), β = −c_p/|l_p|.
fn section_minimum(c: &Vec3, l: &Mat3, across: usize, along: usize) -> Option<f64> {
    let (lp, lo) = (l.row(across).transpose(), l.row(along).transpose());
    let beta = -c[across] / lp.norm();
    if beta.abs() > 1.0 {
        return None;
    }
    let unit = lp / lp.norm();
    let perpendicular = lo - unit * lo.dot(&unit);
    Some(c[along] + beta * lo.dot(&unit) - perpendicular.norm() * (1.0 - beta * beta).sqrt())
}

/// Ellipsoids of every orientation about the step's edge: the gap is ≤ 0 exactly where the
/// ellipsoid meets the plateau or the vertical face (the closed-form section), and never more
/// than the distance from the centre to the walls less r₃ (an upper bound of the true gap: the
/// ellipsoid holds the ball of radius r₃). Cases within 1e-9 of the semi-axes of touching are
/// left out (rounding decides them).
#[test]
fn step_gap_of_ellipsoids_is_negative_exactly_where_they_touch() {
    let boundary = step();
    // A fixed linear congruential sequence in [0, 1): the cases are the same on every run.
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    let mut uniform = move || {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut touching, mut apart) = (0, 0);
    for _ in 0..20_000 {
        let r = Vec3::new(5.0 + 35.0 * uniform(), 5.0 + 35.0 * uniform(), 5.0 + 35.0 * uniform()) * 1e-6;
        let axis = Vec3::new(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5).normalize();
        let q = *nalgebra::Rotation3::from_scaled_axis(axis * std::f64::consts::PI * uniform()).matrix();
        let c = Vec3::new(120e-6 * (uniform() - 0.5), 120e-6 * (uniform() - 0.5), 0.0);
        if c[0] < 0.0 && c[1] < 0.0 {
            continue;
        }
        // x = c + Qᵀ diag(r) u: L = Qᵀ diag(r).
        let l = q.transpose() * Mat3::from_diagonal(&r);
        let plateau = section_minimum(&c, &l, 1, 0);
        let vertical = section_minimum(&c, &l, 0, 1);
        let margin = [plateau, vertical].into_iter().flatten().fold(f64::INFINITY, f64::min);
        if margin.abs() < 1e-9 * r.min() {
            continue;
        }
        // A convex body from a point of the fluid into the solid quadrant crosses its rim.
        let touches = margin <= 0.0;
        let frame = PrincipalFrame { r, q };
        let gap = boundary.nearest(&c, &Extent::Ellipsoid(frame)).gap;
        assert_eq!(
            gap <= 0.0,
            touches,
            "semi-axes {r:?}, Q {q:?}, centre {c:?}: gap {gap}, section {margin}"
        );
        assert!(
            gap <= step_distance(&c) - r.min() + 1e-15,
            "{gap} above the ball's gap at {c:?}"
        );
        if touches {
            touching += 1;
        } else {
            apart += 1;
        }
    }
    assert!(touching > 1000 && apart > 1000, "{touching} touching, {apart} apart");
}

/// Where a sphere of radius `a` flying along x₀ + s·u first comes within `a` of the walls
/// (`distance`), by bisection on s over [0, `reach`] after a scan at steps of a/1000; `None` if
/// it never does.
fn first_touch(x0: &Vec3, u: &Vec3, a: f64, reach: f64, distance: impl Fn(&Vec3) -> f64) -> Option<Vec3> {
    let step = a / 1000.0;
    let n = (reach / step).ceil() as usize;
    let inside = |s: f64| distance(&(x0 + u * s)) <= a;
    let k = (1..=n).find(|&k| inside(k as f64 * step))?;
    let (mut lo, mut hi) = ((k - 1) as f64 * step, k as f64 * step);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if inside(mid) { hi = mid } else { lo = mid }
    }
    Some(x0 + u * hi)
}

/// A rigid sphere (a = 10 µm, 1 000 kg/m³) launched at `speed` along `u` from `start` in still
/// air, drag only, Radau IIA at tol 1e-8: where it deposits, or `None` if it does not.
fn flight(boundary: &MeshBoundary, start: Vec3, u: Vec3, speed: f64) -> Option<Vec3> {
    let a = 10e-6;
    // Five relaxation times ρ_p d²/(18 μ) = 1.2 ms: the sphere has stopped or left.
    let plan = Plan::new(6e-3, 1e-7).unwrap();
    launch(boundary, a, ContactModel::Extent, &plan, start, u * speed).map(|(x, _)| x)
}

/// A rigid sphere of radius `a` (1 000 kg/m³) in still air, drag only, Radau IIA at tol 1e-8,
/// started at `start` with velocity `v` and tracked by `plan` until contact by `model`: where it
/// deposits and on which patch, or `None` if it does not.
fn launch(
    boundary: &MeshBoundary,
    a: f64,
    model: ContactModel,
    plan: &Plan,
    start: Vec3,
    v: Vec3,
) -> Option<(Vec3, String)> {
    let shape = Ellipsoid::new([a; 3], Mat3::identity()).unwrap();
    let particle = Particle::new(shape, Rigid, Fluid::new(1.8e-5, 1.2).unwrap(), 1000.0).unwrap();
    let integrator = Stokesian::new(1e-8).unwrap();
    let contact = ContactEvent::new(boundary, &particle, &Quiescent, model);
    let mut state = State::at_rest(start);
    state.v = v;
    let out = until_event(
        Problem::new(&integrator, &particle, &Quiescent),
        state,
        plan,
        &[&contact],
    )
    .unwrap();
    let patch = contact.nearest(&out.state).patch;
    (out.stop == Stop::Event { index: 0 } && boundary.rule(patch) == PatchRule::Stick)
        .then(|| (out.state.x, boundary.patch_name(patch).to_string()))
}

/// The tolerance of a deposit's position: the event is located to |g| ≤ 10⁻⁹ of the diameter
/// (2·10⁻¹⁴ m) and the path is straight (drag along the velocity in still fluid) to Radau's
/// tolerance 10⁻⁸ of a (10⁻¹³ m); along a path meeting the wall at 5° a gap error δg moves the
/// point by δg / sin 5° ≈ 11 δg. 10⁻⁹ m (10⁻⁴ a) holds both with a margin of 10³.
const WHERE: f64 = 1e-9;

/// Spheres aimed downwards past a convex edge (5° past the step's 90° one, 2.5° past the kinked
/// wall's 5° one) at perpendicular distance d from it: deposited if and only if d < a, at the point where
/// the straight line first comes within a of the walls, at every speed from 0.1 to 30 m/s.
/// Before the room stopped at a face's open edges, the spheres at d = 0.8a–0.95a passed through
/// the step's edge at 1–10 m/s (suspended: the contact was mid-step, the step's end over the
/// drop).
#[test]
fn grazing_flights_past_convex_edges_deposit_if_and_only_if_they_touch() {
    let a = 10e-6;
    let step = step();
    let kink = kinked();
    let kink_distance = |x: &Vec3| {
        // The plateau y = 0 (x ≤ 0) and the facet beyond, along t = (cos 5°, −sin 5°).
        let t = Vec3::new(KINK.cos(), -KINK.sin(), 0.0);
        let plateau = if x[0] <= 0.0 { x[1].abs() } else { x[0].hypot(x[1]) };
        let along = x.dot(&t);
        let facet = if along >= 0.0 {
            (x - t * along).norm()
        } else {
            x[0].hypot(x[1])
        };
        plateau.min(facet)
    };
    let mut failures = Vec::new();
    // Aimed 5° down past the step, 2.5° past the kink (so that the path leaves the facet).
    for (name, boundary, distance, down) in [
        (
            "90° step",
            &step,
            &step_distance as &dyn Fn(&Vec3) -> f64,
            5.0_f64.to_radians(),
        ),
        (
            "5° kink",
            &kink,
            &kink_distance as &dyn Fn(&Vec3) -> f64,
            2.5_f64.to_radians(),
        ),
    ] {
        let u = Vec3::new(down.cos(), -down.sin(), 0.0);
        // The line's nearest point to the edge (the z axis) lies d along the normal to u.
        let normal = Vec3::new(down.sin(), down.cos(), 0.0);
        for d in [0.5, 0.8, 0.9, 0.95, 0.99, 1.01, 1.05, 1.5, 2.0] {
            // Start 100 µm before the nearest point: every speed below reaches it (the
            // stopping distance is 123 µm at 0.1 m/s).
            let start = normal * (d * a) - u * 100e-6;
            let exact = first_touch(&start, &u, a, 300e-6, distance);
            assert_eq!(exact.is_some(), d < 1.0, "{name}: d = {d} a");
            for speed in [0.1, 0.3, 1.0, 3.0, 10.0, 30.0] {
                let got = flight(boundary, start, u, speed);
                let ok = match (got, exact) {
                    (Some(g), Some(e)) => (g - e).norm() <= WHERE,
                    (None, None) => true,
                    _ => false,
                };
                if !ok {
                    failures.push(format!("{name}, d = {d} a, {speed} m/s: {got:?} against {exact:?}"));
                }
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Spheres flown into the step's concave corner (the vertical face meeting the floor) from
/// several directions deposit where the line first comes within a of either wall.
#[test]
fn flights_into_a_concave_corner_deposit_where_they_first_touch() {
    let a = 10e-6;
    let step = step();
    let corner = Vec3::new(0.0, -5.0 * MM, 0.0);
    for degrees in [190.0, 200.0, 225.0, 250.0, 260.0_f64] {
        let u = Vec3::new(degrees.to_radians().cos(), degrees.to_radians().sin(), 0.0);
        // Aimed 3a beside the corner's bisector point, from 150 µm away.
        let target = corner + Vec3::new(3.0 * a, 3.0 * a, 0.0);
        let start = target - u * 150e-6;
        let exact = first_touch(&start, &u, a, 300e-6, step_distance).unwrap();
        for speed in [0.3, 3.0, 30.0] {
            let got =
                flight(&step, start, u, speed).unwrap_or_else(|| panic!("{degrees}°, {speed} m/s: not deposited"));
            assert!(
                (got - exact).norm() <= WHERE,
                "{degrees}°, {speed} m/s: at {got:?} against {exact:?}"
            );
        }
    }
}

/// A point particle (contact radius 0) flying straight down (−y) at 1 m/s through still fluid
/// from (x, −0.5, z) towards the bottom of a pipe of radius 1 along z meshed as a 16-sided
/// polygon (`build::pipe`, 4 × 4 × 4 cells over a length of 2), whose vertex line (0, −1, z)
/// lies below the start: where it deposits and on which patch, or `None`. The sphere
/// (a = 10 mm, 1 000 kg/m³ in air) relaxes over ρ_p d²/(18 μ) ≈ 1.2·10³ s, so its path is
/// straight and its speed 1 m/s to 10⁻⁴ over the 0.5 it flies.
fn point_drop(boundary: &MeshBoundary, x: f64, z: f64) -> Option<(Vec3, String)> {
    let plan = Plan::new(1.0, 1e-4).unwrap();
    let model = ContactModel::Barycentre { radius: 0.0 };
    launch(
        boundary,
        0.01,
        model,
        &plan,
        Vec3::new(x, -0.5, z),
        Vec3::new(0.0, -1.0, 0.0),
    )
}

/// Point particles falling onto or beside a vertex line of a faceted pipe wall, where the
/// fluid's side is convex (inner angle 157.5°), deposit on the wall where their path crosses it,
/// y = −1 + |x| tan 11.25°. A step ends up to the slack (5 mm, half the rest radius) past the
/// wall; within |x| < 5 mm · tan 11.25° of the vertex line that end lies beyond both faces'
/// planes in the wedge that projects into neither face, and the gap there was the (positive)
/// distance to the edge: the particles passed through the wall and flew on outside the mesh
/// (module docs of `contact::mesh`, Rims). The event is located to |g| ≤ 10⁻⁹ of the diameter
/// (2·10⁻¹¹) on a path crossing the wall at 78.75° or more, and the path is straight, so the
/// deposit lies within 10⁻¹⁰ of the crossing; 10⁻⁸ holds it with a margin of 10².
#[test]
fn point_particles_falling_onto_a_wall_edge_deposit_on_the_wall() {
    let boundary = MeshBoundary::new(&pipe(1.0, 2.0, 4, 4, 1.0, 4).mesh()).unwrap();
    let slope = 11.25_f64.to_radians().tan();
    let mut failures = Vec::new();
    // z = 1 lies on a ring of the wall's vertices (four faces meet at (0, −1, 1)); z = 0.8 on
    // the edge between two faces.
    for z in [0.8, 1.0] {
        for x in [0.0_f64, 1e-12, -1e-9, 1e-6, -1e-5, 1e-4, -1e-4, 4e-4, -1e-3, 3e-3] {
            let crossing = Vec3::new(x, -1.0 + x.abs() * slope, z);
            match point_drop(&boundary, x, z) {
                Some((at, patch)) if patch == "wall" && (at - crossing).norm() <= 1e-8 => {}
                got => failures.push(format!("x = {x:e}, z = {z}: {got:?} against {crossing:?}")),
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

//! Point location + interpolation on a snappyHexMesh mesh, with and without a hint, and the
//! cost of reading a case.
//!
//! The mesh is the shipped `reference-data/snappy-sphere/n40` (14 k cells) unless
//! `PSEUDORIGID_OPENFOAM_CASE` names another case directory (e.g. the same case meshed with
//! `cases/snappy-test/Allmesh 80 DIR`, 1e5 cells). The field is analytic (written onto the
//! cell and face centres), so no time directory is needed.
//! Queries: 1000 points spread over the mesh; "hint" starts each search from the cell of a
//! point 0.3 cell sizes away (a particle's previous position), "no_hint" from nothing.
//!
//! Group `blended_sample`: one sample of the blended field ([`BlendedFlow`]) on the airway
//! bifurcation (`reference-data/bifurcation`, prism layers on its walls): "cells" at 1000
//! points 0.3 cell sizes from cell centres spread over the mesh, "near_wall" at 1000 points a
//! quarter of the way from wall faces spread over the walls to their cells' centres (in the
//! first prism layer, where the supports are finest).
//!
//! Group `tabulated_sample`: one sample of the same field tabulated on an octree
//! ([`OctreeFlow`], leaves sized by the mesh) with trilinear and with tricubic Hermite leaves,
//! at the "cells" points of `blended_sample` (those in wall leaves or next to them pay the
//! blend too).
//!
//! Group `tracked_rigid_step`: Fig. 18's tracked particle-step on the blended bifurcation field:
//! rigid λ = 20 prolates at Stk 0.1, the studies' integrator (Rosenbrock-W 2(3) at rtol 10⁻²),
//! contact rule and seed, the first 20 particles run to their fates on one thread; the
//! throughput is in accepted particle-steps (each with its contact event and driver work).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use pseudorigid::flow::FlowField;
use pseudorigid::flow::openfoam::octree::{Interpolant, Options};
use pseudorigid::flow::openfoam::{BlendedFlow, FoamCase, FoamFlow, OctreeFlow, VolField};
use pseudorigid::population::RunOptions;
use pseudorigid::studies::bifurcation::{Airway, Kind, Material, StudyRun};
use pseudorigid::studies::cavity::Shape;
use pseudorigid::tensor::Vec3;
use std::hint::black_box;

fn case_dir() -> String {
    std::env::var("PSEUDORIGID_OPENFOAM_CASE")
        .unwrap_or_else(|_| format!("{}/reference-data/snappy-sphere/n40", env!("CARGO_MANIFEST_DIR")))
}

fn openfoam(c: &mut Criterion) {
    let dir = case_dir();
    let case = FoamCase::open(&dir).expect("readable case");
    let mesh = case.mesh().clone();
    let field = VolField::from_fn(&mesh, |x| Vec3::new(x[1] * x[2], x[0].sin(), x[0] * x[1]));
    let flow = FoamFlow::new(mesh.clone(), vec![(0.0, field)]).expect("valid field");
    let n_cells = mesh.n_cells();
    let h = (mesh.cell_volumes().iter().sum::<f64>() / n_cells as f64).cbrt();

    // Cell centres spread over the mesh, each with the cell of a point 0.3 h away as hint.
    let step = Vec3::new(0.3, -0.2, 0.15).normalize() * 0.3 * h;
    let queries: Vec<(Vec3, usize)> = (0..1000)
        .map(|k| mesh.cell_centres()[k * n_cells / 1000])
        .filter_map(|x| {
            let previous = flow.locate(&(x - step), None).ok()?;
            Some((x, previous))
        })
        .collect();

    let mut g = c.benchmark_group(format!("openfoam_{n_cells}_cells"));
    g.throughput(Throughput::Elements(queries.len() as u64));
    g.bench_function("locate_interpolate_hint", |b| {
        b.iter(|| {
            for (x, hint) in &queries {
                black_box(flow.sample_from(black_box(x), 0.0, Some(*hint)).ok());
            }
        })
    });
    g.bench_function("locate_interpolate_no_hint", |b| {
        b.iter(|| {
            for (x, _) in &queries {
                black_box(flow.sample_from(black_box(x), 0.0, None).ok());
            }
        })
    });
    g.finish();

    let mut g = c.benchmark_group("openfoam_read");
    g.sample_size(10);
    g.bench_function("mesh_and_locator", |b| {
        b.iter(|| {
            let case = FoamCase::open(black_box(&dir)).expect("readable case");
            let field = VolField::from_fn(case.mesh(), |x| *x);
            FoamFlow::new(case.mesh().clone(), vec![(0.0, field)]).expect("valid field")
        })
    });
    g.finish();
}

fn blended(c: &mut Criterion) {
    let dir = format!("{}/reference-data/bifurcation", env!("CARGO_MANIFEST_DIR"));
    let case = FoamCase::open(&dir).expect("readable case");
    let last = *case.times().last().expect("a time directory");
    let flow = BlendedFlow::new(FoamFlow::read(&case, &[last]).expect("readable field")).expect("blendable");
    let mesh = flow.cellwise().mesh();
    let n_cells = mesh.n_cells();
    let h = (mesh.cell_volumes().iter().sum::<f64>() / n_cells as f64).cbrt();
    let step = Vec3::new(0.3, -0.2, 0.15).normalize() * 0.3 * h;
    let cells: Vec<Vec3> = (0..1000)
        .map(|k| mesh.cell_centres()[k * n_cells / 1000] + step)
        .collect();
    let walls = flow.cellwise().walls();
    let near_wall: Vec<Vec3> = (0..1000)
        .map(|k| {
            let f = walls[k * walls.len() / 1000] as usize;
            let (q, c) = (mesh.face_centres()[f], mesh.cell_centres()[mesh.owner(f)]);
            q + 0.25 * (c - q)
        })
        .collect();
    let mut g = c.benchmark_group("blended_sample");
    g.throughput(Throughput::Elements(1000));
    for (name, points) in [("cells", &cells), ("near_wall", &near_wall)] {
        g.bench_function(name, |b| {
            b.iter(|| {
                for x in points {
                    black_box(flow.sample(black_box(x), 0.0).ok());
                }
            })
        });
    }
    g.finish();
    let mut g = c.benchmark_group("tabulated_sample");
    g.throughput(Throughput::Elements(1000));
    for (name, interpolant) in [("trilinear", Interpolant::Trilinear), ("hermite", Interpolant::Hermite)] {
        let options = Options {
            u_tolerance: f64::INFINITY,
            gradient_tolerance: f64::INFINITY,
            interpolant,
            ..Options::default()
        };
        let table = OctreeFlow::with_options(flow.clone(), options).expect("a table");
        g.bench_function(name, |b| {
            b.iter(|| {
                for x in &cells {
                    black_box(table.sample(black_box(x), 0.0).ok());
                }
            })
        });
    }
    g.finish();
}

fn tracked_rigid_step(c: &mut Criterion) {
    let airway = Airway::open(Airway::shipped_dir()).expect("the shipped airway");
    let kind = Kind {
        shape: Shape::Prolate(20.0),
        material: Material::Rigid,
        stokes: 0.1,
    };
    let quiet = RunOptions::default().quiet();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a thread pool");
    let run = || pool.install(|| StudyRun::new(&airway, kind, 20).run(&quiet).expect("the study runs"));
    // The same particles every iteration: their steps, counted once, are the throughput.
    let steps: u64 = run().records.iter().map(|r| r.stats.steps).sum();
    let mut g = c.benchmark_group("tracked_rigid_step");
    g.throughput(Throughput::Elements(steps));
    g.sample_size(10);
    g.bench_function("fig18_stk0.1", |b| b.iter(|| black_box(run())));
    g.finish();
}

criterion_group!(benches, blended, tracked_rigid_step, openfoam);
criterion_main!(benches);

//! The airway bifurcation's field tabulated for tracking (`flow::openfoam::octree`): the
//! table's size and build time, its differences from the blend at points spread over the
//! mesh and next to every wall patch, and the time of a sample of each.
//!
//! With `cellular` for the case, the shipped mesh carries the exact cellular flow
//! (`flow::analytic::Cellular`, U = 1 m/s, L = 1.5 mm) in its cells and on every patch
//! instead of the solved field, and the blend and the table are both compared with the exact
//! u and ∇u (median, 90th and 99th percentiles and largest error over the spread points).
//!
//! ```text
//! cargo run --release --example octree_field [-- CASE_DIR|- [U_TOL GRAD_TOL LEAVES_PER_CELL WALL_LEAF INTERPOLANT]]
//! ```
//! (`-`: the shipped field; defaults 1e-4, 1e-3, 12, 2, trilinear,
//! `flow::openfoam::octree::Options`; INTERPOLANT `trilinear` or `hermite`).

use pseudorigid::flow::FlowField;
use pseudorigid::flow::analytic::Cellular;
use pseudorigid::flow::openfoam::octree::Options;
use pseudorigid::flow::openfoam::{BlendedFlow, FoamCase, FoamFlow, OctreeFlow, VolField};
use pseudorigid::studies::bifurcation::Airway;
use pseudorigid::tensor::Vec3;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let first = std::env::args().nth(1);
    let exact = (first.as_deref() == Some("cellular"))
        .then(|| Cellular::new(1.0, 1.5e-3))
        .transpose()?;
    let dir = first
        .filter(|a| a != "-" && a != "cellular")
        .map_or_else(Airway::shipped_dir, Into::into);
    let case = FoamCase::open(&dir)?;
    let last = *case.times().last().ok_or("no time directory")?;
    let cells = match &exact {
        Some(field) => {
            let values = VolField::from_fn(case.mesh(), |x| field.sample(x, 0.0).map_or(Vec3::zeros(), |s| s.u));
            FoamFlow::new(case.mesh().clone(), vec![(0.0, values)])?
        }
        None => FoamFlow::read(&case, &[last])?,
    };
    let blend = BlendedFlow::new(cells)?;
    let start = Instant::now();
    let tol = |i: usize, default: f64| std::env::args().nth(i).and_then(|a| a.parse().ok()).unwrap_or(default);
    let options = Options {
        u_tolerance: tol(2, 1e-4),
        gradient_tolerance: tol(3, 1e-3),
        leaves_per_cell: tol(4, 12.0) as usize,
        wall_leaf: tol(5, 2.0),
        interpolant: std::env::args().nth(6).as_deref().unwrap_or("trilinear").parse()?,
        ..Options::default()
    };
    let table = OctreeFlow::with_options(blend, options)?;
    let built = start.elapsed().as_secs_f64();
    let r = table.report();
    println!("{r:?}");
    println!("built in {built:.1} s; {:.0} bytes per cell", r.bytes_per_cell());
    let mut census = std::collections::BTreeMap::new();
    for leaf in table.leaves() {
        *census
            .entry((format!("{:.1} µm", leaf.edge * 1e6), leaf.tabulated))
            .or_insert(0usize) += 1;
    }
    println!("leaves by edge and tabulated: {census:?}");
    let points = table.check_points(20_000, 1, &[0.1, 0.25, 0.5], 1);
    let spread = table.misses(points.spread.iter().copied());
    let wall = table.misses(points.near_wall.iter().map(|p| p.0));
    println!("spread {spread:?}\nnear wall {wall:?}");
    let against = |name: &str, field: &dyn FlowField, reference: &dyn FlowField| {
        let (mut du, mut dg): (Vec<f64>, Vec<f64>) = points
            .spread
            .iter()
            .filter_map(|x| Some((field.sample(x, 0.0).ok()?, reference.sample(x, 0.0).ok()?)))
            .map(|(a, b)| {
                (
                    (a.u - b.u).norm() / r.u_max,
                    (a.grad_u - b.grad_u).norm() / r.gradient_max,
                )
            })
            .unzip();
        let quantiles = |v: &mut Vec<f64>| {
            v.sort_by(f64::total_cmp);
            [0.5, 0.9, 0.99, 1.0]
                .map(|q| {
                    format!(
                        "{:.2e}",
                        v.get(((v.len() as f64 - 1.0) * q) as usize)
                            .copied()
                            .unwrap_or(f64::NAN)
                    )
                })
                .join(", ")
        };
        println!(
            "{name} at {} spread points, relative to the maxima (50 %, 90 %, 99 %, max): u {}, ∇u {}",
            du.len(),
            quantiles(&mut du),
            quantiles(&mut dg)
        );
    };
    against("table − blend", &table, table.blended());
    if let Some(field) = &exact {
        against("blend − exact", table.blended(), field);
        against("table − exact", &table, field);
    }
    // The blend's own scale: its difference from the cells' linear fits it blends.
    let (mut du, mut dg) = (0.0f64, 0.0f64);
    for x in &points.spread {
        if let (Ok(b), Ok(c)) = (
            table.blended().sample(x, 0.0),
            table.blended().cellwise().sample(x, 0.0),
        ) {
            du = du.max((b.u - c.u).norm() / r.u_max);
            dg = dg.max((b.grad_u - c.grad_u).norm() / r.gradient_max);
        }
    }
    println!("blend against the cellwise fits at the spread points: u {du:.2e}, ∇u {dg:.2e} (relative to the maxima)");
    let tabulated: Vec<_> = points
        .spread
        .iter()
        .copied()
        .filter(|x| table.is_tabulated(x))
        .collect();
    println!(
        "tabulated alone at {} of {} spread points",
        tabulated.len(),
        points.spread.len()
    );
    for (name, field) in [
        ("blend", table.blended() as &dyn FlowField),
        ("octree", &table as &dyn FlowField),
    ] {
        let start = Instant::now();
        let mut sum = 0.0;
        for _ in 0..5 {
            for x in &tabulated {
                sum += field.sample(x, 0.0).map_or(0.0, |s| s.u[0]);
            }
        }
        let per = start.elapsed().as_secs_f64() / (5 * tabulated.len()) as f64;
        println!("{name}: {:.0} ns per sample ({sum:.3e})", per * 1e9);
    }
    Ok(())
}

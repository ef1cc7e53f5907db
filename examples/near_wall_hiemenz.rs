//! Hiemenz stagnation flow on snappyHexMesh meshes under refinement (issue 25, deliverable 2):
//! the exact field written into the meshes of `cases/stagnation`, the wall layer against it.
//!
//! ```text
//! for n in 0 2 5; do for k in 0 1 2 3; do cases/stagnation/Allmesh $n $k MESHES/layers$n/level$k; done; done
//! cargo run --release --example near_wall_hiemenz -- MESHES [OUT_DIR]
//! ```
//! (`cases/stagnation-ci.sh` does both.) Reads every `MESHES/layers{0,2,5}/level{0,1,...}`
//! there is, writes `hiemenz_snappy.csv` and `hiemenz_snappy.svg` to OUT_DIR (default
//! `paper-figures/near-wall`) and fails unless, on every mesh, the blended normal velocity is
//! within 10 % of the exact one in the first cell and v/δ² within 10 % of continuity's
//! coefficient (the issue's targets; the arguments are in `tests/suite/flow/openfoam/mod.rs`), and the
//! observed order of the wall-layer |u| error, fitted over all levels (at least three), is
//! 2 ± 0.3: the error is C δ₁² (1 + O(δ₁/ℓ)) with δ₁/ℓ up to 0.45 on the coarse level, so the
//! next term may move the observed order by a few tenths; the lower bound 1.7 is that of the
//! other convergence tests (`tests/suite/flow/openfoam/mod.rs`). The step-to-step orders are printed
//! and written, not asserted: the snapped meshes are similar under refinement only nearly
//! (`studies::stagnation::fitted_order`), and they move by ±0.2. It also writes
//! `gradient_order.csv` (u and ∇u at half the first cell's height, relative to the exact
//! field's maxima) and fails unless the fitted order of that ∇u error is at least 1.8 on every
//! layering (issue 37: the wall fit's shear is second order, `flow::openfoam::wall_layer`).
//! Beside each measured v/δ² it prints the ratio the three-point profile's truncation and the
//! exact profile's δ³ term predict (`studies::stagnation::predicted_coefficient_ratio`; printed,
//! not asserted here: the suite asserts the remainder below ε/4 on the level-0 meshes).
//! With COUETTE_MESHES (`cases/taylor-couette/Allmesh` meshes under
//! `COUETTE_MESHES/layers{0,2,5}/level{0,1,...}`) it adds the Taylor–Couette rows at the rotating
//! cylinder (`studies::couette`) and fails unless their u error's fitted order is at least 1.8
//! and, on every annulus, the blended field's largest ∇u error is no larger than the cellwise
//! fits' at each height of `couette::BAND` (0.1 to 2 first-cell heights over the inner
//! cylinder, 60 points each; issue 37).

use pseudorigid::studies::couette::{self, CouetteAnnulus};
use pseudorigid::studies::stagnation::{
    Measure, OrderRow, StagnationBox, WallLayerRow, fitted_order, gradient_order_table, observed_order,
    order_row_slope, predicted_coefficient_ratio, wall_layer_figure, wall_layer_table,
};
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let usage = "usage: near_wall_hiemenz MESHES [OUT_DIR [COUETTE_MESHES]]";
    let meshes = PathBuf::from(args.next().ok_or(usage)?);
    let out = args.next().map_or_else(
        || pseudorigid::output::paper_figure_path("near-wall", ""),
        PathBuf::from,
    );
    let couette_meshes = args.next().map(PathBuf::from);
    let (mut rows, mut predicted) = (Vec::new(), Vec::new());
    for layers in [0, 2, 5] {
        for level in 0.. {
            let case = meshes.join(format!("layers{layers}/level{level}"));
            if !case.exists() {
                break;
            }
            let flow = StagnationBox::read(&case)?;
            rows.push(WallLayerRow::measure(layers, level, &flow)?);
            predicted.push(predicted_coefficient_ratio(&flow, flow.first_cell / 100.0));
        }
    }
    if rows.is_empty() {
        return Err(format!("no meshes under {}", meshes.display()).into());
    }
    std::fs::create_dir_all(&out)?;
    wall_layer_table(&rows, 4)?.write(out.join("hiemenz_snappy.csv"))?;
    wall_layer_figure(&rows).write(out.join("hiemenz_snappy.svg"))?;
    let mut orders: Vec<OrderRow> = rows.iter().map(OrderRow::from).collect();
    let mut failures = Vec::new();
    if let Some(dir) = &couette_meshes {
        for layers in [0, 2, 5] {
            for level in 0.. {
                let case = dir.join(format!("layers{layers}/level{level}"));
                if !case.exists() {
                    break;
                }
                let annulus = CouetteAnnulus::read(&case)?;
                let row = couette::order_row(layers, level, &annulus)?;
                // The wall layer replaces the cellwise fits within two cells of the wall: its
                // largest ∇u error must be no larger than theirs at any height there.
                for band in couette::blend_against_cellwise(&annulus)? {
                    if band.blended > band.cellwise {
                        failures.push(format!(
                            "Taylor–Couette, {layers} layers, level {level}: ∇u error at {} δ₁ {:.4} > cellwise {:.4}",
                            band.fraction, band.blended, band.cellwise
                        ));
                    }
                }
                let parts = couette::component_errors_at(&annulus.blended, 0.5 * annulus.first_cell)?;
                println!(
                    "Taylor–Couette, {layers} layers, level {level}: first cell {:.3e}, u {:.3e}, ∇u {:.3e} (shear {:.3e}, stretch {:.3e})",
                    row.first_cell_height, row.u_rel_err, row.grad_rel_err, parts.shear, parts.stretch
                );
                orders.push(row);
            }
        }
    }
    gradient_order_table(&orders, 4)?.write(out.join("gradient_order.csv"))?;
    println!(
        "layers level  cells  first cell  |Δu_n|/|u_n| at 0.1 0.25 0.5 0.75 of it   (v/δ²)/c (the profile's truncation)   max|Δu|    order"
    );
    for (i, (r, p)) in rows.iter().zip(&predicted).enumerate() {
        let order = observed_order(&rows, i, Measure::Velocity);
        let p = p.map_or_else(|| "-".into(), |(lo, hi)| format!("{lo:.4}–{hi:.4}"));
        println!(
            "{:6} {:5} {:6}  {:.3e}   {:.4} {:.4} {:.4} {:.4}   {:.4} ({p})   {:.3e}  {}",
            r.layers,
            r.level,
            r.cells,
            r.first_cell,
            r.normal_error[0],
            r.normal_error[1],
            r.normal_error[2],
            r.normal_error[3],
            r.coefficient_ratio,
            r.velocity_error,
            order.map_or_else(String::new, |p| format!("{p:.2}"))
        );
        if r.normal_error.iter().any(|&e| e > 0.10) || (r.coefficient_ratio - 1.0).abs() > 0.10 {
            failures.push(format!("{} layers, level {}: beyond 10 %", r.layers, r.level));
        }
    }
    for layers in [0, 2, 5] {
        let levels = rows.iter().filter(|r| r.layers == layers).count();
        let fit = |m| fitted_order(&rows, layers, m).map_or_else(|| "-".into(), |p| format!("{p:.2}"));
        println!(
            "{layers} layers: order over {levels} levels: |u| {}, |∇u| {}, |∇u| at half the first cell {}",
            fit(Measure::Velocity),
            fit(Measure::Gradient),
            fit(Measure::HalfCellGradient)
        );
        match fitted_order(&rows, layers, Measure::HalfCellGradient) {
            Some(p) if levels >= 3 && p >= 1.8 => {}
            p => failures.push(format!(
                "{layers} layers: ∇u order at half the first cell {p:?} over {levels} levels"
            )),
        }
        match fitted_order(&rows, layers, Measure::Velocity) {
            Some(p) if levels >= 3 && (p - 2.0).abs() <= 0.3 => {}
            p => failures.push(format!("{layers} layers: order {p:?} over {levels} levels")),
        }
    }
    if couette_meshes.is_some() {
        for layers in [0, 2, 5] {
            let fit = |gradient| order_row_slope(&orders, "taylor_couette", layers, gradient);
            println!(
                "Taylor–Couette, {layers} layers: fitted order u {:?}, ∇u {:?}",
                fit(false),
                fit(true)
            );
            // u second order (bound 1.8). ∇u is not asserted: the wall fit carries the wall's
            // turning (`flow::openfoam::wall_layer`, Curved walls; second order on built
            // annuli), but on these snapped annuli the largest error at half the first cell
            // falls at first order (paper-figures/near-wall/NOTES.md).
            match fit(false) {
                Some(p) if p >= 1.8 => {}
                p => failures.push(format!("Taylor–Couette, {layers} layers: u order {p:?}")),
            }
        }
    }
    println!("wrote {}", out.join("hiemenz_snappy.csv").display());
    if failures.is_empty() {
        Ok(())
    } else {
        Err(failures.join("; ").into())
    }
}

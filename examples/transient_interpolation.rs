//! The error of linear interpolation in time ([`pseudorigid::flow::openfoam::transient`]) on a
//! CFD case written at every solver step: the levels of the second half of the case's times,
//! thinned to every k-th, interpolated at the levels left out and compared with them at every
//! cell centre (where a cell's reconstruction is its value). Prints the largest error relative
//! to the largest |u| of the levels left out, for k = 2, 4, ..., 32, and the observed order;
//! then the samples per second of the window against the field of every level held.
//!
//! `cases/oscillating-cavity/Allrun` solves the case (icoFoam, a lid oscillating with period
//! 0.5 s, 2.5 ms steps) and runs this: `cargo run --release --example transient_interpolation
//! -- CASE_DIR`.

use pseudorigid::flow::FlowField;
use pseudorigid::flow::openfoam::{Cycle, FoamCase, FoamFlow, Precision, TransientFlow};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args()
        .nth(1)
        .ok_or("usage: transient_interpolation CASE_DIR")?;
    let case = FoamCase::open(&dir)?;
    let times = case.times();
    // The first half is the start from rest; the second is periodic.
    let levels = &times[times.len() / 2..];
    if levels.len() < 33 {
        return Err(format!("{} levels in the second half; at least 33 are needed", levels.len()).into());
    }
    let centres = case.mesh().cell_centres();
    println!(
        "levels {} to {}, {} of them",
        levels[0],
        levels[levels.len() - 1],
        levels.len()
    );
    println!("k\tspacing\trelative error\torder");
    let mut previous: Option<f64> = None;
    for k in [2usize, 4, 8, 16, 32] {
        let kept: Vec<f64> = levels.iter().step_by(k).copied().collect();
        let mut flow = TransientFlow::<FoamFlow>::open(case.clone(), &kept, Cycle::Once, Precision::F64)?;
        let (mut error, mut scale): (f64, f64) = (0.0, 0.0);
        let last = kept[kept.len() - 1];
        for (m, &t) in levels.iter().enumerate() {
            if m % k == 0 || t > last {
                continue;
            }
            let level = FoamFlow::read(&case, &[t])?;
            flow.slide(t, t)?;
            for x in centres {
                let exact = level.sample(x, t)?.u;
                error = error.max((flow.sample(x, t)?.u - exact).amax());
                scale = scale.max(exact.amax());
            }
        }
        let relative = error / scale;
        let order = previous.map_or(String::new(), |p| format!("{:.2}", (relative / p).log2()));
        println!("{k}\t{:.4}\t{relative:.3e}\t{order}", kept[1] - kept[0]);
        previous = Some(relative);
    }
    throughput(&case, levels, centres)
}

/// Samples per second of the field of every level against the window's (f64 and f32): at the
/// cell centres shifted off them, at four times in each interval, the window slid interval
/// by interval (its reading and gradients timed too).
fn throughput(
    case: &FoamCase,
    levels: &[f64],
    centres: &[pseudorigid::tensor::Vec3],
) -> Result<(), Box<dyn std::error::Error>> {
    use std::time::Instant;
    let offset = pseudorigid::tensor::Vec3::new(1e-4, -2e-4, 0.0);
    let points: Vec<_> = centres.iter().map(|c| c + offset).collect();
    let times = |w: &[f64]| {
        let (a, b) = (w[0], w[1]);
        (0..4).map(move |i| a + (b - a) * f64::from(i) / 4.0)
    };
    let all = FoamFlow::read(case, levels)?;
    let clock = Instant::now();
    let mut sum = 0.0;
    let mut count = 0u64;
    for w in levels.windows(2) {
        for t in times(w) {
            for x in &points {
                sum += all.sample(x, t)?.u[0];
                count += 1;
            }
        }
    }
    let every = count as f64 / clock.elapsed().as_secs_f64();
    println!("samples per second: every level held {every:.3e}");
    for precision in [Precision::F64, Precision::F32] {
        let mut flow = TransientFlow::<FoamFlow>::open(case.clone(), levels, Cycle::Once, precision)?;
        let clock = Instant::now();
        let mut windowed = 0.0;
        for w in levels.windows(2) {
            flow.slide(w[0], w[1])?;
            for t in times(w) {
                for x in &points {
                    windowed += flow.sample(x, t)?.u[0];
                }
            }
        }
        let rate = count as f64 / clock.elapsed().as_secs_f64();
        println!(
            "samples per second: window ({precision:?}, slides included) {rate:.3e}, {:.2} of every level held's",
            rate / every
        );
        if precision == Precision::F64 && windowed != sum {
            return Err("the window's samples differ from every level held's".into());
        }
    }
    Ok(())
}

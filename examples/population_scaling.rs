//! Run time of the population runner against N and threads, on the settling pipe (rigid
//! spheres, overdamped barycentre, tol 1e-6: the runner bench's case).
//!
//! ```text
//! cargo run --release --example population_scaling -- 1000:1,2 10000:1,2 100000:2
//! ```
//! Each argument is `N:threads,threads,...`. Prints, per run: N, threads, wall time,
//! particles/s, particle-steps/s, fates, and the resident memory the run's records added per
//! particle (from /proc/self/status where it exists).

use pseudorigid::driver::{Budget, Plan};
use pseudorigid::integrator::Stokesian;
use pseudorigid::population::settling_pipe::SettlingPipe;
use pseudorigid::population::{Case, RunConfig, RunOptions, Shard, run};
use std::time::Instant;

/// Resident set size in bytes (Linux), if known.
fn rss() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let args = if args.is_empty() {
        vec!["1000:1,2".to_string()]
    } else {
        args
    };
    let pipe = SettlingPipe::new(20.0, 200.0, 1.0, 0.1, 15.0)?;
    let stokes = Stokesian::overdamped(1e-6)?;
    let plan = Plan::new(1e4, 0.1)?.with_budget(Budget {
        max_steps: 1_000_000,
        wall_time: None,
    });
    let case = Case::new(&stokes, pipe.flow(), pipe.boundary(), &pipe, plan);
    println!("n,threads,wall_s,particles_per_s,steps_per_s,deposited,escaped,suspended,failed,rss_bytes_per_particle");
    for arg in &args {
        let (n, threads) = arg.split_once(':').ok_or("argument must be N:threads,...")?;
        let n: u64 = n.parse()?;
        for threads in threads.split(',') {
            let threads: usize = threads.parse()?;
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build()?;
            let config = RunConfig {
                seed: 1,
                particles: n,
                fingerprint: pipe.fingerprint(),
            };
            let before = rss();
            let start = Instant::now();
            let out = pool.install(|| run(&case, &config, Shard::ALL, &RunOptions::default().quiet()))?;
            let wall = start.elapsed().as_secs_f64();
            let per_particle = match (before, rss()) {
                (Some(a), Some(b)) => format!("{:.0}", (b - a) / n as f64),
                _ => String::new(),
            };
            let steps: u64 = out.records.iter().map(|r| r.stats.steps).sum();
            let c = out.counts();
            println!(
                "{n},{threads},{wall:.2},{:.0},{:.0},{},{},{},{},{per_particle}",
                n as f64 / wall,
                steps as f64 / wall,
                c.deposited,
                c.escaped,
                c.suspended,
                c.failed
            );
            drop(out);
        }
    }
    Ok(())
}

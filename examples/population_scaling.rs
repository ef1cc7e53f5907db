//! Run time of the population runner against N and threads, on the settling pipe (rigid
//! spheres, overdamped barycentre, tol 1e-6: the runner bench's case) or, with
//! `--bifurcation STK`, on the airway bifurcation (rigid spheres at that Stokes number, or
//! prolates with `--prolate LAMBDA`, Neo-Hookean with `--mu-s PA` (shear modulus, Pa) instead of
//! rigid, the shipped field and the studies' integrator: the case of Figs 17–23).
//!
//! ```text
//! cargo run --release --example population_scaling -- 1000:1,2 10000:1,2 100000:2
//! cargo run --release --example population_scaling -- --bifurcation 0.005 1000:1,2 10000:1,2 100000:2
//! cargo run --release --example population_scaling -- --bifurcation 0.005 --prolate 20 10000:1,2 100000:2
//! ```
//! Each `N:threads,threads,...` argument runs N particles on each thread count. Prints, per
//! run: N, threads, wall time, the
//! process's CPU time, particles/s, particle-steps/s, fates, and the resident memory the run's
//! records added per particle (from /proc/self where it exists). On a shared machine the wall
//! time of a 2-thread run says little about the speed-up (the second core may be busy); the
//! CPU time does not depend on the load: equal CPU time for 1 and 2 threads means the runner
//! adds no parallel overhead, and the speed-up on an idle machine is the thread count times
//! the load balance.
//!
//! `--records PATH` writes each run's records (fates, end states, work counts) as JSON to
//! PATH.N.T (N particles, T threads): two builds whose files are byte for byte the same gave
//! the same results (`sha256sum`). `--pair PATH` pairs each run's fates particle by particle
//! with the records PATH.N.T of an earlier run (another build) and prints the deposits of
//! either only and the paired difference of the deposited fractions with its standard error
//! (`population::binomial::Pairing`).

use pseudorigid::driver::{Budget, Plan};
use pseudorigid::integrator::Stokesian;
use pseudorigid::material::NeoHooke;
use pseudorigid::population::binomial::Pairing;
use pseudorigid::population::progress::{process_cpu_seconds, process_resident_bytes};
use pseudorigid::population::settling_pipe::SettlingPipe;
use pseudorigid::population::{Case, Fingerprint, ParticleRecord, RunOptions, RunOutput, Shard, run};
use pseudorigid::studies::bifurcation::{Airway, Kind, Material, study};
use pseudorigid::studies::cavity::Shape;
use std::time::Instant;

/// One timed run of N particles; its records are dropped before the next.
type Runner<'a> = Box<dyn Fn(u64) -> Result<RunOutput<NeoHooke>, String> + Sync + 'a>;

/// The value after `flag` in `args` (both removed), `None` if `flag` is absent.
fn take_option(args: &mut Vec<String>, flag: &str, what: &str) -> Result<Option<String>, String> {
    let Some(i) = args.iter().position(|a| a == flag) else {
        return Ok(None);
    };
    let value = args.get(i + 1).ok_or(format!("{flag} needs {what}"))?.clone();
    args.drain(i..i + 2);
    Ok(Some(value))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let bifurcation: Option<f64> = take_option(&mut args, "--bifurcation", "a Stokes number")?
        .map(|v| v.parse())
        .transpose()?;
    let prolate: f64 = match take_option(&mut args, "--prolate", "an aspect ratio")? {
        Some(v) => v.parse()?,
        None => 1.0,
    };
    let material = match take_option(&mut args, "--mu-s", "a shear modulus (Pa)")? {
        Some(v) => Material::ShearModulus(v.parse()?),
        None => Material::Rigid,
    };
    let records = take_option(&mut args, "--records", "a path")?;
    let pair = take_option(&mut args, "--pair", "a path")?;
    if args.is_empty() {
        args.push("1000:1,2".to_string());
    }
    let pipe = SettlingPipe::new(20.0, 200.0, 1.0, 0.1, 15.0)?;
    let stokes = Stokesian::overdamped(1e-6)?;
    let plan = Plan::new(1e4, 0.1)?.with_budget(Budget {
        max_steps: 1_000_000,
        wall_time: None,
    });
    let case = Case::new(&stokes, pipe.flow(), pipe.boundary(), &pipe, plan);
    let airway = match bifurcation {
        Some(_) => Some(Airway::open(Airway::shipped_dir())?),
        None => None,
    };
    let runner: Runner = match (&airway, bifurcation) {
        (Some(airway), Some(stk)) => {
            let kind = Kind {
                shape: Shape::Prolate(prolate),
                material,
                stokes: stk,
            };
            let quiet = RunOptions::default().quiet();
            Box::new(move |n| {
                study::StudyRun::new(airway, kind, n)
                    .run(&quiet)
                    .map_err(|e| e.to_string())
            })
        }
        _ => Box::new(|n| {
            let config = Fingerprint::new("population_scaling").particles(&pipe).config(1, n);
            run(&case, &config, Shard::ALL, &RunOptions::default().quiet()).map_err(|e| e.to_string())
        }),
    };
    println!(
        "n,threads,wall_s,cpu_s,particles_per_s,steps_per_s,deposited,escaped,suspended,failed,rss_bytes_per_particle"
    );
    for arg in &args {
        let (n, threads) = arg.split_once(':').ok_or("argument must be N:threads,...")?;
        let n: u64 = n.parse()?;
        for threads in threads.split(',') {
            let threads: usize = threads.parse()?;
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build()?;
            let before = process_resident_bytes();
            let cpu_before = process_cpu_seconds();
            let start = Instant::now();
            let out = pool.install(|| runner(n))?;
            let wall = start.elapsed().as_secs_f64();
            let cpu = match (cpu_before, process_cpu_seconds()) {
                (Some(a), Some(b)) => format!("{:.2}", b - a),
                _ => String::new(),
            };
            let per_particle = match (before, process_resident_bytes()) {
                (Some(a), Some(b)) => format!("{:.0}", (b - a) / n as f64),
                _ => String::new(),
            };
            let steps: u64 = out.records.iter().map(|r| r.stats.steps).sum();
            let c = out.counts();
            println!(
                "{n},{threads},{wall:.2},{cpu},{:.0},{:.0},{},{},{},{},{per_particle}",
                n as f64 / wall,
                steps as f64 / wall,
                c.deposited,
                c.escaped,
                c.suspended,
                c.failed
            );
            if let Some(path) = &records {
                std::fs::write(format!("{path}.{n}.{threads}"), serde_json::to_vec(&out.records)?)?;
            }
            if let Some(path) = &pair {
                let earlier: Vec<ParticleRecord<NeoHooke>> =
                    serde_json::from_slice(&std::fs::read(format!("{path}.{n}.{threads}"))?)?;
                let paired = Pairing::of_records(&earlier, &out.records)?.fates_or_zero();
                println!(
                    "paired with {path}: deposited by it only {}, by this run only {}, difference {:+.2e} ± {:.2e}",
                    paired.first_only(),
                    paired.second_only(),
                    paired.difference(),
                    paired.stderr()
                );
            }
            drop(out);
        }
    }
    Ok(())
}

//! The evidence behind the studies' barycentre choice
//! ([`pseudorigid::integrator::choice::EQUILIBRIUM_STOKES`]): the same rigid λ = 20 prolates
//! (Fig. 18's particles, the datasets' seed) through the airway bifurcation with the inertial
//! barycentre and with the equilibrium velocity, at the studies' tolerances and scheme, paired
//! particle by particle.
//!
//! ```text
//! cargo run --release --example barycentre_choice -- [N] [STK...]    # default 4000; 0.005 … 0.1
//! ```
//! Writes `paper-figures/fig18/barycentre_choice.csv` with columns
//! `stk,n,deposited_inertial,deposited_equilibrium,lost,gained,steps_inertial,steps_equilibrium,cpu_ratio`:
//! deposits of each model, the particles only the inertial run deposits (`lost`) and only the
//! equilibrium run deposits (`gained`), the accepted steps of each run, and the CPU time of the
//! inertial run over the equilibrium run's (both measured in this process, one after the other).

use pseudorigid::integrator::BarycentreModel;
use pseudorigid::output::Csv;
use pseudorigid::population::RunOptions;
use pseudorigid::population::binomial::Pairing;
use pseudorigid::population::progress::process_cpu_seconds;
use pseudorigid::studies::bifurcation::{Airway, Kind, Material, study};
use pseudorigid::studies::cavity::Shape;
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let n: u64 = args.first().map_or(Ok(4000), |a| a.parse())?;
    let stokes: Vec<f64> = if args.len() > 1 {
        args[1..].iter().map(|a| a.parse()).collect::<Result<_, _>>()?
    } else {
        vec![0.005, 0.01, 0.02, 0.04, 0.06, 0.1]
    };
    let airway = Airway::open(Airway::shipped_dir())?;
    let mut csv = Csv::new(&[
        "stk",
        "n",
        "deposited_inertial",
        "deposited_equilibrium",
        "lost",
        "gained",
        "steps_inertial",
        "steps_equilibrium",
        "cpu_ratio",
    ]);
    for stk in stokes {
        let kind = Kind {
            shape: Shape::Prolate(20.0),
            material: Material::Rigid,
            stokes: stk,
        };
        let choice = study::integrator(&airway, kind)?;
        eprintln!("Stk {stk}: {}", choice.reason);
        let chosen = choice.integrator.full();
        let mut runs = Vec::new();
        for barycentre in [BarycentreModel::Inertial, BarycentreModel::Equilibrium] {
            let integ = pseudorigid::integrator::Stokesian { barycentre, ..chosen };
            let cpu = process_cpu_seconds();
            let out = study::StudyRun::new(&airway, kind, n)
                .integrator(integ)
                .run(&RunOptions::default().quiet())?;
            let cpu = process_cpu_seconds().zip(cpu).map(|(b, a)| b - a);
            let steps: u64 = out.records.iter().map(|r| r.stats.steps).sum();
            runs.push((out, steps, cpu));
        }
        let pairing = Pairing::of_records(&runs[0].0.records, &runs[1].0.records)?;
        let (lost, gained) = (pairing.only_ours, pairing.only_peer);
        let cpu_ratio = match (runs[0].2, runs[1].2) {
            (Some(a), Some(b)) if b > 0.0 => format!("{:.2}", a / b),
            _ => String::new(),
        };
        let row = vec![
            stk.to_string(),
            n.to_string(),
            runs[0].0.counts().deposited.to_string(),
            runs[1].0.counts().deposited.to_string(),
            lost.to_string(),
            gained.to_string(),
            runs[0].1.to_string(),
            runs[1].1.to_string(),
            cpu_ratio,
        ];
        println!("{}", row.join(","));
        csv.push(row)?;
    }
    csv.write(Path::new("paper-figures/fig18/barycentre_choice.csv"))?;
    Ok(())
}

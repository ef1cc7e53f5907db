//! Which inertialess scheme each scene should use: wall time and error of Radau IIA(5) and the
//! Rosenbrock-W 2(3) pair on one representative particle per scene that runs `Stokesian`, at
//! the scene's tolerance and one decade tighter, against a Radau run four decades tighter.
//!
//! - pipe (Figs 11, 12): λ₁ = 3.5, Ca = 0.25 to deposition at rtol = atol = 1e-7; error in
//!   the deposition distance (d_eq);
//! - pipe (Fig. 10): λ₁ = 14, Ca = 0.05 over 0.5 s at 1e-7; error in the final direction
//!   cosines of l_a;
//! - cavity, inertialess path: a rigid λ₁ = 2 prolate (Fig. 14, 5 s at 1e-7) and a soft λ₁ = 2
//!   prolate at Ca = 0.25 (Figs 15, 16 inertialess, 100 s at 1e-6); error in the last position
//!   (m);
//! - bifurcation: particle 0 of the soft spheres at Stk = 0.4 (rtol 1e-3, atol 1e-6 with the
//!   study's step cap); error in the end position (m).
//!
//! Wall time is the least of three runs (the machine is shared). Prints a Markdown table.
//!
//! Run: `cargo run --release --example scheme_choice`

use pseudorigid::integrator::{Scheme, Stokesian, Tolerances};
use pseudorigid::population::{Case, Fingerprint, RunOptions, Shard, run};
use pseudorigid::studies::bifurcation::{Airway, Injection, Kind, Material, figures, study};
use pseudorigid::studies::cavity::{Cavity, Contact, Launch, Shape, Tracking};
use pseudorigid::studies::pipe::{Deformability, PipeCase, sample_orientation, track_to_deposition};
use pseudorigid::tensor::Mat3;
use std::error::Error;
use std::time::Instant;

/// What one run reports: the compared quantity and, where the scene counts them, its
/// accepted and rejected steps.
struct Outcome {
    quantity: Vec<f64>,
    steps: Option<(u64, u64)>,
}

type Measure<'a> = Box<dyn Fn(Scheme, f64) -> Result<Outcome, Box<dyn Error>> + 'a>;

/// The least wall time of three runs and the run's result.
fn timed(f: &dyn Fn() -> Result<Outcome, Box<dyn Error>>) -> Result<(f64, Outcome), Box<dyn Error>> {
    let start = Instant::now();
    let out = f()?;
    let mut best = start.elapsed().as_secs_f64();
    for _ in 1..3 {
        let start = Instant::now();
        f()?;
        best = best.min(start.elapsed().as_secs_f64());
    }
    Ok((best, out))
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>().sqrt()
}

fn main() -> Result<(), Box<dyn Error>> {
    let cavity_flow = pseudorigid::studies::cavity::shipped_flow()?;
    let airway = Airway::open(Airway::shipped_dir())?;
    let rosenbrock = Cavity::new(&cavity_flow)?.with_scheme(Scheme::Rosenbrock23);
    let radau = Cavity::new(&cavity_flow)?.with_scheme(Scheme::Radau5);
    let cavity = |scheme| if scheme == Scheme::Radau5 { &radau } else { &rosenbrock };
    let mut cases: Vec<(&str, f64, Measure<'_>)> = Vec::new();

    cases.push((
        "pipe fig11 λ3.5 Ca0.25",
        1e-7,
        Box::new(|scheme, tol| {
            let case = PipeCase { lambda1: 3.5, ca: 0.25 };
            let scene = case.setup()?;
            let t_max = 50.0 * scene.sphere_settling_time();
            let run = track_to_deposition(&scene, &scene.integrator(tol)?.with_scheme(scheme), 1e-3, t_max, t_max)?;
            Ok(Outcome {
                quantity: vec![run.distance()],
                steps: Some((run.steps, run.rejected)),
            })
        }),
    ));
    cases.push((
        "pipe fig10 λ14 Ca0.05",
        1e-7,
        Box::new(|scheme, tol| {
            let case = PipeCase {
                lambda1: 14.0,
                ca: 0.05,
            };
            let scene = case.setup()?;
            let t_end = 0.5 / scene.time_unit;
            let samples = sample_orientation(&scene, &scene.integrator(tol)?.with_scheme(scheme), &[t_end], 1e-3)?;
            let c = samples.last().ok_or("no sample")?.xi_a.normalize();
            Ok(Outcome {
                quantity: vec![c[0], c[1], c[2]],
                steps: None,
            })
        }),
    ));
    cases.push((
        "cavity fig14 rigid λ2",
        1e-7,
        Box::new(|scheme, tol| {
            let release = Launch {
                shape: Shape::Prolate(2.0),
                softness: Deformability::Rigid,
            };
            let run = cavity(scheme).track(
                release,
                &Mat3::identity(),
                &Tracking {
                    contact: Contact::Extent,
                    t_max: 5.0,
                    tol,
                    dt_out: 5.0,
                },
            )?;
            let x = run.path.last().ok_or("no path")?.1;
            Ok(Outcome {
                quantity: vec![x[0], x[1], x[2]],
                steps: Some((run.stats.steps, run.stats.rejected)),
            })
        }),
    ));
    cases.push((
        "cavity soft λ2 Ca0.25",
        1e-6,
        Box::new(|scheme, tol| {
            let release = Launch {
                shape: Shape::Prolate(2.0),
                softness: Deformability::Elastic { ca: 0.25 },
            };
            let run = cavity(scheme).track(
                release,
                &Mat3::identity(),
                &Tracking {
                    contact: Contact::Barycentre,
                    t_max: 100.0,
                    tol,
                    dt_out: 100.0,
                },
            )?;
            let x = run.path.last().ok_or("no path")?.1;
            Ok(Outcome {
                quantity: vec![x[0], x[1], x[2]],
                steps: Some((run.stats.steps, run.stats.rejected)),
            })
        }),
    ));
    let airway = &airway;
    cases.push((
        "bifurcation Stk0.4 soft sphere",
        study::RTOL,
        Box::new(move |scheme, rtol| {
            let kind = Kind {
                shape: Shape::Prolate(1.0),
                material: Material::ShearModulus(0.5),
                stokes: 0.4,
            };
            let injection = Injection::new(airway, kind)?;
            let integ = Stokesian {
                tol: Tolerances::new(rtol, rtol * study::ATOL / study::RTOL, 1e-14)?,
                ..study::integrator(airway, kind)?.integrator.full()
            }
            .with_scheme(scheme);
            let case = Case::new(
                &integ,
                airway.flow(),
                airway.boundary(),
                &injection,
                study::plan(airway)?,
            );
            let config = Fingerprint::new("scheme_choice").config(figures::SEED, 1);
            let out = run(&case, &config, Shard::ALL, &RunOptions::default().quiet())?;
            let r = &out.records[0];
            let x = r.end.ok_or("no end state")?.x;
            Ok(Outcome {
                quantity: vec![x[0], x[1], x[2]],
                steps: Some((r.stats.steps, r.stats.rejected)),
            })
        }),
    ));

    println!("| scene, particle | tol | scheme | wall [s] | steps | rejected | error |");
    println!("|---|---|---|---|---|---|---|");
    for (name, tol, measure) in &cases {
        let reference = measure(Scheme::Radau5, tol * 1e-4)?;
        for t in [*tol, 0.1 * tol] {
            for scheme in [Scheme::Rosenbrock23, Scheme::Radau5] {
                let (wall, out) = timed(&|| measure(scheme, t))?;
                let err = distance(&out.quantity, &reference.quantity);
                let (steps, rej) = out
                    .steps
                    .map_or(("–".into(), "–".into()), |(a, r)| (a.to_string(), r.to_string()));
                println!("| {name} | {t:e} | {scheme:?} | {wall:.3} | {steps} | {rej} | {err:.2e} |");
            }
        }
    }
    Ok(())
}

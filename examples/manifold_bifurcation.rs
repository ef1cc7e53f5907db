//! Issue 36: soft spheres in the airway bifurcation at Stk 0.1, μ_s = 0.5, 5, 50, 500 Pa and
//! rigid, each run by the studies' integrator (the full inertialess model,
//! `study::integrator`, its Rosenbrock-W step in the lab and in the body frame,
//! `integrator::body_frame`) and by the slow-manifold model over each (`integrator::manifold`),
//! on the same particles (same seed). Prints steps, CPU time, fates, and both models' errors against
//! a reference (the full model by Radau IIA at rtol 10⁻⁶): fates paired, and the shape
//! B = F Fᵀ and barycentre along the path at 39 common output times.
//!
//! ```text
//! cargo run --release --example manifold_bifurcation -- [N] [SEED] [MU_S,MU_S,...]
//! ```
//! The shear moduli default to 0.5,5,50,500 (Pa).
//! `PSEUDORIGID_DELTA_MAX` sets δ_max (default √rtol). One thread (CPU time is the process's, measured around each run, after an untimed warm-up
//! run that fills the mesh's clearance grid).

use pseudorigid::driver::Plan;
use pseudorigid::error::ParamError;
use pseudorigid::error::StepError;
use pseudorigid::flow::FlowField;
use pseudorigid::hydro::DragModel;
use pseudorigid::integrator::manifold::{Manifold, ManifoldMemory};
use pseudorigid::integrator::{BarycentreModel, IntegratorReport, Step, TimeIntegrator};
use pseudorigid::integrator::{Frame, Scheme, Stepper, Stokesian, Tolerances};
use pseudorigid::material::Response;
use pseudorigid::material::{NeoHooke, Softness};
use pseudorigid::particle::{Particle, State};
use pseudorigid::population::progress::process_cpu_seconds;
use pseudorigid::population::{Case, Fate, Fingerprint, RunOptions, RunOutput, Shard, paired, run};
use pseudorigid::studies::bifurcation::{Airway, Injection, Kind, Material, study};
use pseudorigid::studies::particles::Shape;
use pseudorigid::tensor::Mat3;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

fn run_with<I>(
    airway: &Airway,
    kind: Kind,
    integ: &I,
    n: u64,
    seed: u64,
    times: &[f64],
) -> Result<(RunOutput<NeoHooke>, f64), Box<dyn std::error::Error>>
where
    I: Stepper<Softness<NeoHooke>, pseudorigid::hydro::Brenner> + std::fmt::Debug,
{
    let injection = Injection::new(airway, kind)?;
    let plan: Plan = study::plan(airway)?.with_outputs(times)?;
    let case = Case::new(integ, airway.flow(), airway.boundary(), &injection, plan).with_samples();
    let config = Fingerprint::new("manifold_bifurcation")
        .particles(&kind)
        .config(seed, n);
    let before = process_cpu_seconds().unwrap_or(f64::NAN);
    let out = run(&case, &config, Shard::ALL, &RunOptions::default().serial())?;
    Ok((out, process_cpu_seconds().unwrap_or(f64::NAN) - before))
}

fn fate_code(f: &Fate) -> &'static str {
    match f {
        Fate::Deposited { .. } => "deposited",
        Fate::Escaped { .. } => "escaped",
        _ => "other",
    }
}

fn summary(name: &str, out: &RunOutput<NeoHooke>, cpu: f64) -> (u64, f64) {
    let steps: u64 = out.records.iter().map(|r| r.stats.steps).sum();
    let rejected: u64 = out.records.iter().map(|r| r.stats.rejected).sum();
    let dep = out.records.iter().filter(|r| fate_code(&r.fate) == "deposited").count();
    let esc = out.records.iter().filter(|r| fate_code(&r.fate) == "escaped").count();
    let other = out.records.len() - dep - esc;
    println!(
        "  {name:>8}: {steps:>8} steps ({rejected} rejected), {cpu:7.2} s CPU, deposited {dep}, escaped {esc}, other {other}"
    );
    (steps, cpu)
}

/// The switch's counts summed over a run: [`Manifold`] with every step's change of its
/// per-particle [`pseudorigid::integrator::manifold::ManifoldReport`] added up.
#[derive(Debug, Default)]
struct Tally {
    manifold_steps: AtomicU64,
    full_steps: AtomicU64,
    entered: AtomicU64,
    left: AtomicU64,
    manifold_rejected: AtomicU64,
    full_rejected: AtomicU64,
    exit_rejected: AtomicU64,
}

#[derive(Debug, Clone)]
struct Tallied(Manifold, Arc<Tally>);

impl TimeIntegrator for Tallied {
    type Memory = ManifoldMemory;

    fn name(&self) -> &'static str {
        self.0.name()
    }

    fn barycentre(&self) -> BarycentreModel {
        self.0.barycentre()
    }

    fn report(&self, memory: &ManifoldMemory) -> IntegratorReport {
        self.0.report(memory)
    }

    fn step_with<M: Response, D: DragModel, F: FlowField + ?Sized>(
        &self,
        particle: &Particle<M, D>,
        state: &State,
        memory: &mut ManifoldMemory,
        flow: &F,
        dt: f64,
    ) -> Result<Step, StepError> {
        let before = self.0.manifold_report(memory);
        let step = self.0.step_with(particle, state, memory, flow, dt)?;
        let after = self.0.manifold_report(memory);
        let t = &self.1;
        t.manifold_steps
            .fetch_add(after.manifold_steps - before.manifold_steps, Ordering::Relaxed);
        t.full_steps
            .fetch_add(after.full_steps - before.full_steps, Ordering::Relaxed);
        t.entered
            .fetch_add(u64::from(after.entered - before.entered), Ordering::Relaxed);
        t.left.fetch_add(u64::from(after.left - before.left), Ordering::Relaxed);
        let rejected = u64::from(step.info.rejected);
        if after.left > before.left {
            t.exit_rejected.fetch_add(rejected, Ordering::Relaxed);
        } else if after.full_steps > before.full_steps {
            t.full_rejected.fetch_add(rejected, Ordering::Relaxed);
        } else {
            t.manifold_rejected.fetch_add(rejected, Ordering::Relaxed);
        }
        Ok(step)
    }
}

/// Paired comparison of `run` against `reference`: fates changed, and |B − B_ref| (max,
/// median) and |x − x_ref| (max) over the common samples.
fn compare(run: &RunOutput<NeoHooke>, reference: &RunOutput<NeoHooke>) -> Result<(usize, f64, f64, f64), ParamError> {
    let mut changed = 0;
    let mut db = Vec::new();
    let mut dx: f64 = 0.0;
    for (a, b) in paired(&reference.records, &run.records)? {
        if fate_code(&a.fate) != fate_code(&b.fate) {
            changed += 1;
        }
        for (p, q) in a.samples.iter().zip(&b.samples) {
            if p.t != q.t {
                break;
            }
            db.push((p.f * p.f.transpose() - q.f * q.f.transpose()).norm());
            dx = dx.max((p.x - q.x).norm());
        }
    }
    db.sort_by(f64::total_cmp);
    Ok((
        changed,
        db.last().copied().unwrap_or(0.0),
        db.get(db.len() / 2).copied().unwrap_or(0.0),
        dx,
    ))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let n: u64 = args.next().map_or(Ok(200), |a| a.parse())?;
    let seed: u64 = args.next().map_or(Ok(7), |a| a.parse())?;
    let moduli: Vec<f64> = match args.next() {
        Some(list) => list.split(',').map(str::parse).collect::<Result<_, _>>()?,
        None => vec![0.5, 5.0, 50.0, 500.0],
    };
    let airway = Airway::open(Airway::shipped_dir())?;
    let t_end = airway.tracking_time();
    let times: Vec<f64> = (1..40).map(|i| t_end * i as f64 / 40.0).collect();
    let rigid = Kind {
        shape: Shape::Sphere,
        material: Material::Rigid,
        stokes: 0.1,
    };
    println!("N = {n} spheres at Stk 0.1, seed {seed}");
    let full = study::integrator(&airway, rigid)?.integrator.full();
    // The first run pays the one-off fill of the mesh's clearance grid: warm up, untimed.
    let _ = run_with(&airway, rigid, &full, n.min(50), seed + 1, &times)?;
    let (out, cpu) = run_with(&airway, rigid, &full, n, seed, &times)?;
    println!("rigid");
    let (rigid_steps, rigid_cpu) = summary("full", &out, cpu);
    println!(
        "material,model,steps,cpu_s,steps_over_rigid,cpu_over_rigid,fates_changed_vs_ref,max_dB_vs_ref,median_dB_vs_ref,max_dx_vs_ref_m,ref_max_B_minus_1"
    );
    let mut rows = Vec::new();
    for mu_s in moduli {
        let kind = Kind {
            material: Material::ShearModulus(mu_s),
            ..rigid
        };
        let choice = study::integrator(&airway, kind)?;
        println!(
            "mu_s = {mu_s} Pa (Ca = {:.3e}): {}",
            kind.material.capillary_number(),
            choice.reason
        );
        let chosen: Stokesian = choice.integrator.full();
        let reference = Stokesian {
            tol: Tolerances::new(1e-6, 1e-8, 1e-14)?,
            scheme: Scheme::Radau5,
            ..chosen
        };
        let (or, _) = run_with(&airway, kind, &reference, n, seed, &times)?;
        let (sr, _) = summary("ref", &or, f64::NAN);
        let b_dev = or
            .records
            .iter()
            .flat_map(|r| {
                r.samples
                    .iter()
                    .map(|s| (s.f * s.f.transpose() - Mat3::identity()).norm())
            })
            .fold(0.0, f64::max);
        for frame in [Frame::Lab, Frame::Body] {
            let full = chosen.with_frame(frame);
            let tally = Arc::new(Tally::default());
            let manifold = match std::env::var("PSEUDORIGID_DELTA_MAX") {
                Ok(d) => Manifold::new(full)?.with_delta_max(d.parse()?)?,
                Err(_) => Manifold::new(full)?,
            };
            let reduced = Tallied(manifold, tally.clone());
            let (of, cf) = run_with(&airway, kind, &full, n, seed, &times)?;
            let (sf, _) = summary(frame.name(), &of, cf);
            let (om, cm) = run_with(&airway, kind, &reduced, n, seed, &times)?;
            let (sm, _) = summary("manifold", &om, cm);
            let on = tally.manifold_steps.load(Ordering::Relaxed);
            let off = tally.full_steps.load(Ordering::Relaxed);
            println!(
                "  switch: {on} steps on the manifold, {off} full ({:.1} % on), {} entries, {} exits (discarded steps); rejected attempts: {} on the manifold, {} full, {} in the full steps that follow an exit",
                100.0 * on as f64 / (on + off).max(1) as f64,
                tally.entered.load(Ordering::Relaxed),
                tally.left.load(Ordering::Relaxed),
                tally.manifold_rejected.load(Ordering::Relaxed),
                tally.full_rejected.load(Ordering::Relaxed),
                tally.exit_rejected.load(Ordering::Relaxed)
            );
            let full_name = format!("full {}", frame.name());
            let manifold_name = format!("manifold {}", frame.name());
            for (model, out, steps, cpu) in [(&full_name, &of, sf, cf), (&manifold_name, &om, sm, cm)] {
                let (changed, max_db, median_db, dx) = compare(out, &or)?;
                println!(
                    "  {model} against the reference ({sr} steps): {changed} of {n} fates changed; |B - B_ref| max {max_db:.3e}, median {median_db:.3e}; |x - x_ref| max {dx:.3e} m; reference max |B - 1| {b_dev:.3e}"
                );
                rows.push(format!(
                    "{mu_s},{model},{steps},{cpu:.2},{:.3},{:.3},{changed},{max_db:.3e},{median_db:.3e},{dx:.3e},{b_dev:.3e}",
                    steps as f64 / rigid_steps as f64,
                    cpu / rigid_cpu,
                ));
            }
        }
    }
    // The rigid run again, last: its CPU time against the first one's is the spread of the
    // measurement (cache, the shared machine).
    let rigid_full = study::integrator(&airway, rigid)?.integrator.full();
    let (again, cpu_again) = run_with(&airway, rigid, &rigid_full, n, seed, &times)?;
    println!("rigid again");
    summary("full", &again, cpu_again);
    println!(
        "material,model,steps,cpu_s,steps_over_rigid,cpu_over_rigid,fates_changed_vs_ref,max_dB_vs_ref,median_dB_vs_ref,max_dx_vs_ref_m,ref_max_B_minus_1"
    );
    println!("rigid,full,{rigid_steps},{rigid_cpu:.2},1,1,0,0,0,0,0");
    println!(
        "rigid (again),full,{rigid_steps},{cpu_again:.2},1,{:.3},0,0,0,0,0",
        cpu_again / rigid_cpu
    );
    for r in rows {
        println!("{r}");
    }
    Ok(())
}

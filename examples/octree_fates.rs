//! Fates on the tabulated field (`flow::openfoam::octree`) against the blend it tabulates: the
//! same rigid λ = 20 prolates of Fig. 18 (the datasets' seed) through the airway bifurcation,
//! at the studies' integrator, tolerances and contact rule, paired particle by particle. The
//! evidence behind the module docs' "Fates" table: whether a table fast enough to pay for
//! itself keeps Fig. 18's deposition.
//!
//! ```text
//! cargo run --release --example octree_fates -- [N STK U_TOL LEAVES_PER_CELL INTERPOLANT KIND WALL_LEAF [FINE_CASE]]
//! # defaults 4000 0.5 inf 12 trilinear prolate 2
//! ```
//! `KIND` `prolate` (Fig. 18's rigid λ = 20 prolates) or `sphere:MU_S` (Neo-Hookean spheres of
//! shear modulus MU_S Pa, Figs 19–23; `sphere:rigid` rigid ones).
//! `U_TOL` the table's tolerance of u against the blend relative to |u|max (`inf`: leaves sized
//! by the mesh alone); the tolerance of ∇u is infinite; `INTERPOLANT` `trilinear` or `hermite`;
//! `WALL_LEAF` the wall leaves' edge over the wall cell's height ([`Options`]).
//! `FINE_CASE` (optional) a finer solution of the same airway (`cases/bifurcation/Allrun
//! 0.2e-3 DIR`): the same particles are tracked on its blend as well and both fields of the
//! shipped mesh are paired against it, so the table's shift from the blend can be set beside
//! the blend's own change under mesh refinement.
//! One thread per run, so the times compare.

use pseudorigid::flow::FlowField;
use pseudorigid::flow::openfoam::OctreeFlow;
use pseudorigid::flow::openfoam::octree::Options;
use pseudorigid::material::NeoHooke;
use pseudorigid::population::peer::Pairing;
use pseudorigid::population::{Case, Fate, Fingerprint, ParticleRecord, RunConfig, RunOptions, Shard, run};
use pseudorigid::studies::bifurcation::{Airway, Injection, Kind, Material, figures, study};
use pseudorigid::studies::cavity::Shape;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: &str| args.get(i).map_or(default.to_string(), Clone::clone);
    let n: u64 = arg(0, "4000").parse()?;
    let stokes: f64 = arg(1, "0.5").parse()?;
    let options = Options {
        u_tolerance: arg(2, "inf").parse()?,
        gradient_tolerance: f64::INFINITY,
        leaves_per_cell: arg(3, "12").parse()?,
        interpolant: arg(4, "trilinear").parse()?,
        wall_leaf: arg(6, "2").parse()?,
        ..Options::default()
    };
    let airway = Airway::open(Airway::shipped_dir())?;
    let start = Instant::now();
    let table = OctreeFlow::with_options(airway.flow().clone(), options)?;
    let r = table.report();
    println!(
        "table: built in {:.1} s, {:.0} bytes per cell, {} tabulated leaves, {} wall leaves, {} left to the blend; \
         largest miss at the midpoints u {:.2e}, ∇u {:.2e} (of the maxima)",
        start.elapsed().as_secs_f64(),
        r.bytes_per_cell(),
        r.table_leaves,
        r.wall_leaves,
        r.unconverged,
        r.u_miss,
        r.gradient_miss
    );
    let kind = match arg(5, "prolate").as_str() {
        "prolate" => Kind {
            shape: Shape::Prolate(20.0),
            material: Material::Rigid,
            stokes,
        },
        sphere => {
            let modulus = sphere.strip_prefix("sphere:").ok_or("KIND: prolate or sphere:MU_S")?;
            Kind {
                shape: Shape::Sphere,
                material: match modulus {
                    "rigid" => Material::Rigid,
                    mu_s => Material::ShearModulus(mu_s.parse()?),
                },
                stokes,
            }
        }
    };
    let config = Fingerprint::new("octree_fates").config(figures::SEED, n);
    let blend = fates(&airway, airway.flow(), kind, &config, "blend")?;
    let tabulated = fates(&airway, &table, kind, &config, "table")?;
    paired(&tabulated, &blend, "DE table − blend")?;
    if let Some(dir) = args.get(7) {
        let fine = Airway::open(dir)?;
        let finer = fates(&fine, fine.flow(), kind, &config, &format!("blend of {dir}"))?;
        paired(&blend, &finer, "DE blend − fine blend")?;
        paired(&tabulated, &finer, "DE table − fine blend")?;
    }
    Ok(())
}

/// The records of the particles of `config` on `field` in `airway` (the studies' integrator,
/// injection, contact and plan, one thread), with the run's time, steps and deposits printed.
fn fates(
    airway: &Airway,
    field: &dyn FlowField,
    kind: Kind,
    config: &RunConfig,
    name: &str,
) -> Result<Vec<ParticleRecord<NeoHooke>>, Box<dyn std::error::Error>> {
    let integ = study::integrator(airway, kind)?.integrator;
    let injection = Injection::new(airway, kind)?;
    let case = Case::new(&integ, field, airway.boundary(), &injection, study::plan(airway)?);
    let start = Instant::now();
    let out = run(&case, config, Shard::ALL, &RunOptions::default().serial().quiet())?;
    let steps: u64 = out.records.iter().map(|r| r.stats.steps).sum();
    println!(
        "{name}: {:.1} s, {steps} steps, {} of {} deposited",
        start.elapsed().as_secs_f64(),
        out.records
            .iter()
            .filter(|r| matches!(r.fate, Fate::Deposited { .. }))
            .count(),
        config.particles
    );
    Ok(out.records)
}

/// The paired difference of DE, `ours` − `reference`, over the same particles (McNemar's
/// standard error), printed with the counts deposited by one only.
fn paired(
    ours: &[ParticleRecord<NeoHooke>],
    reference: &[ParticleRecord<NeoHooke>],
    label: &str,
) -> Result<(), Box<dyn std::error::Error>> {
    let pairing = Pairing::of_records(ours, reference)?;
    let (difference, se) = pairing.difference();
    println!(
        "paired: {label} {difference:+.4} ± {se:.4} ({} / {} deposited by one only)",
        pairing.only_ours, pairing.only_peer
    );
    Ok(())
}

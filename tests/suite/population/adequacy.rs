//! The mesh-adequacy diagnostic from Rust, without a scene (`population::adequacy`): the coarse
//! box of `scene::adequacy`'s tests (first-cell height 0.2, flow u = s (2xy, −y², 0) towards
//! the wall y = 0), 20 rigid spheres of radius 0.02 at rest on the line x = 0, z = 0.5. On the
//! blended field every one comes down to the wall; the wall cell's linear fit stops them above
//! it (that module's docs), so the re-track on the cellwise field deposits none.

use crate::common::build;
use pseudorigid::contact::MeshBoundary;
use pseudorigid::driver::Plan;
use pseudorigid::ellipsoid::Ellipsoid;
use pseudorigid::error::{ParamError, StepError};
use pseudorigid::flow::openfoam::{BlendedFlow, FoamCase, FoamFlow};
use pseudorigid::hydro::drag::Brenner;
use pseudorigid::integrator::Stokesian;
use pseudorigid::material::{NeoHooke, Softness};
use pseudorigid::particle::{Fluid, Particle};
use pseudorigid::population::adequacy::{Reconstruction, Resolution, Stop, sensitivity};
use pseudorigid::population::{
    Case, Fate, Fingerprint, Injector, ParticleRng, ParticleSpec, ParticleTemplate, RunOptions, Shard, run,
};
use pseudorigid::tensor::{Mat3, Vec3};
use std::path::Path;

/// s of the flow.
const S: f64 = 10.0;
/// Sphere radius.
const A: f64 = 0.02;
/// Spheres.
const N: u64 = 20;

/// Sphere k at rest at (0, 0.35 + 0.015 k, 0.5), ρ_s = 2.
struct Line(ParticleTemplate<Brenner>);

impl Injector for Line {
    type Law = NeoHooke;
    type Drag = Brenner;

    fn draw(&self, index: u64, _rng: &mut ParticleRng) -> Result<ParticleSpec<NeoHooke>, StepError> {
        Ok(ParticleSpec {
            shape: Ellipsoid::new([A; 3], Mat3::identity())?,
            softness: Softness::Rigid,
            density: 2.0,
            position: Vec3::new(0.0, 0.35 + 0.015 * index as f64, 0.5),
            velocity: Vec3::zeros(),
        })
    }

    fn particle(&self, spec: &ParticleSpec<NeoHooke>) -> Result<Particle<Softness<NeoHooke>, Brenner>, ParamError> {
        self.0.build(spec)
    }
}

/// The ratios and the re-track of a run on the blended field, from the library's parts: every
/// pair discordant one way (deposited on the blended field only), so a warning at the first
/// look; the first-cell height and a sphere's response time τ_p = 2ρ_s a²/(9μ) by hand.
#[test]
fn retrack_without_a_scene_warns_on_the_coarse_box() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("population_adequacy_coarse");
    let _ = std::fs::remove_dir_all(&dir);
    let raw = build::layered_box(
        &[-0.5, -0.3, -0.1, 0.1, 0.3, 0.5],
        &[0.0, 0.2, 0.5, 1.0],
        &[0.0, 0.5, 1.0],
        false,
    );
    let u = build::sampled(&raw.mesh(), |x| S * Vec3::new(2.0 * x[0] * x[1], -x[1] * x[1], 0.0));
    build::write_case(&dir, &raw, &u, "0", build::Format::Ascii);
    let foam = FoamCase::open(&dir).unwrap();
    let boundary = MeshBoundary::new(foam.mesh()).unwrap();
    let blended = BlendedFlow::new(FoamFlow::read(&foam, &[0.0]).unwrap()).unwrap();
    let line = Line(ParticleTemplate::new(Brenner, Fluid::new(1.0, 1.0).unwrap(), Vec3::zeros()).unwrap());
    let integrator = Stokesian::overdamped(1e-6).unwrap();
    let case = Case::new(&integrator, &blended, &boundary, &line, Plan::new(10.0, 1e-3).unwrap());
    let config = Fingerprint::new("blended line").config(0, N);
    let out = run(&case, &config, Shard::ALL, &RunOptions::default().quiet()).unwrap();
    assert!(out.records.iter().all(|r| matches!(r.fate, Fate::Deposited { .. })));

    let particle = line
        .particle(&line.draw(0, &mut pseudorigid::population::particle_rng(0, 0)).unwrap())
        .unwrap();
    let r = Resolution::of(blended.cellwise(), [("line".to_string(), &particle)]).unwrap();
    assert!((r.walls.median - 0.2).abs() < 1e-15, "{:?}", r.walls);
    let tau = 2.0 * 2.0 * A * A / 9.0;
    let [p] = r.particles.as_slice() else {
        panic!("{:?}", r.particles)
    };
    assert!((p.response_time - tau).abs() < 1e-12 * tau, "{} {tau}", p.response_time);
    assert_eq!(p.size_ratio, A / r.walls.median);

    let s = sensitivity(&case, config.seed, Reconstruction::Blended(&blended), &out.records, N).unwrap();
    assert_eq!((s.run_field, s.other_field), ("blended", "cellwise"));
    assert_eq!(
        (s.pairing.only_ours, s.pairing.only_peer, s.pairing.both),
        (N, 0, 0),
        "{s:?}"
    );
    assert_eq!(
        (s.looks, s.stop, s.warning, s.difference),
        (1, Stop::Resolved, true, 1.0)
    );
    assert_eq!(s.particles.len(), N as usize);
}

//! Injection times (`Injector::injection`): without them a run's records are those of the code
//! before they existed, bit for bit; with them every particle starts at its own time, in the
//! batch runner's window that contains it, with the particle-major runner's fate.

use super::common::{Faulty, FaultySoftPipe, config, integrator, plan, soft_pipe};
use proptest::prelude::*;
use pseudorigid::error::{FlowError, ParamError, StepError};
use pseudorigid::flow::{FlowField, FlowSample};
use pseudorigid::material::{NeoHooke, Softness};
use pseudorigid::particle::{Particle, State};
use pseudorigid::population::batch::{Batch, Sliding, Steady, run_batch};
use pseudorigid::population::{Fate, Injector, ParticleRng, ParticleSpec, RunOptions, Shard, particle_rng, run};
use pseudorigid::prelude::Brenner;
use pseudorigid::tensor::Vec3;
use rand::RngExt;

fn thread_pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap()
}

/// FNV-1a (64 bit) of `bytes`: a short, stable digest of a run's records to pin in a snapshot.
fn fnv1a(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// The settling pipe's mixed population (40 particles, 4 of them failing to draw) through the
/// particle-major runner and the batch runner (15 windows), on one thread, its records'
/// digests pinned: the default injection draws nothing and starts at t = 0, so any change of a
/// bit of any record (a draw consumed, a start moved) fails here. When `Injector::injection`
/// came in, the digests of the whole outputs (records and configuration hash) were those of
/// the code before it (commit 0362386) bit for bit; since the integrator's error norm
/// (`integrator::ErrorNorm`) entered the integrator's `Debug` text, and with it the
/// configuration hash, only the records are digested (that change keeps them bit for bit).
/// A regression guard by design, not a check.
#[test]
fn records_without_injection_times_are_those_before_them() {
    let FaultySoftPipe { stokes, pipe, faulty } = FaultySoftPipe::new();
    let config = config(40);
    let quiet = RunOptions::default().quiet();
    let case = pseudorigid::population::Case::new(&stokes, pipe.flow(), pipe.boundary(), &faulty, plan());
    let major = thread_pool(1)
        .install(|| run(&case, &config, Shard::ALL, &quiet))
        .unwrap();
    let batch = Batch::new(&stokes, pipe.boundary(), &faulty, plan());
    let windows: Vec<f64> = (0..=15).map(|k| 10.0 * f64::from(k)).collect();
    let windowed = thread_pool(1)
        .install(|| run_batch(&batch, &mut Steady(pipe.flow()), &windows, &config, Shard::ALL, &quiet))
        .unwrap();
    let records = |out: &pseudorigid::population::RunOutput<pseudorigid::material::NeoHooke>| {
        fnv1a(&serde_json::to_vec(&out.records).unwrap())
    };
    insta::assert_snapshot!(format!(
        "particle-major {}\nbatch {}",
        records(&major),
        records(&windowed)
    ));
}

/// The settling pipe's particles injected at times uniform in [0, `latest`), drawn from each
/// particle's generator after its spec.
struct Timed {
    inner: Faulty,
    latest: f64,
}

impl Injector for Timed {
    type Law = NeoHooke;
    type Drag = Brenner;

    fn draw(&self, index: u64, rng: &mut ParticleRng) -> Result<ParticleSpec<NeoHooke>, StepError> {
        self.inner.draw(index, rng)
    }

    fn particle(&self, spec: &ParticleSpec<NeoHooke>) -> Result<Particle<Softness<NeoHooke>, Brenner>, ParamError> {
        self.inner.particle(spec)
    }

    fn injection(&self, _index: u64, spec: &ParticleSpec<NeoHooke>, rng: &mut ParticleRng) -> Result<State, StepError> {
        Ok(State {
            t: self.latest * rng.random::<f64>(),
            ..spec.start_state()
        })
    }
}

/// A steady flow that answers only the times of the window it was slid to: a particle started
/// in a window before the one holding its injection time, or after it, would sample a time
/// outside it and fail.
struct Strict<'f, F> {
    inner: &'f F,
    window: (f64, f64),
}

impl<F: FlowField> FlowField for Strict<'_, F> {
    fn sample(&self, x: &Vec3, t: f64) -> Result<FlowSample, FlowError> {
        let (start, end) = self.window;
        if t < start || t > end {
            return Err(FlowError::OutsideTimeWindow { t, start, end });
        }
        self.inner.sample(x, t)
    }

    fn strain_rate(&self) -> Option<f64> {
        self.inner.strain_rate()
    }
}

impl<F: FlowField> Sliding for Strict<'_, F> {
    type Error = std::convert::Infallible;

    fn slide(&mut self, start: f64, end: f64) -> Result<(), Self::Error> {
        self.window = (start, end);
        Ok(())
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(6))]

    /// Any window layout over [0, 150] and injection times spread over [0, latest): every
    /// particle's first state is at its own injection time (drawn again here from its seed,
    /// after its spec), no particle fails but those the injector fails on purpose (k ≡ 5 mod 11:
    /// a particle started outside its window would sample the strict flow out of its window and
    /// fail), and each has the fate the particle-major runner gives it on the same steady field
    /// (the cuts change only the landing steps, by the step control's tolerance).
    #[test]
    fn particles_start_in_the_window_of_their_injection_time(
        cuts in proptest::collection::btree_set(1u32..150, 1..12),
        latest in 1.0..140.0f64,
    ) {
        let (stokes, pipe) = (integrator(), soft_pipe());
        let timed = Timed { inner: Faulty { inner: pipe.clone(), delay: None }, latest };
        let config = config(12);
        let quiet = RunOptions::default().quiet();
        let mut windows = vec![0.0];
        windows.extend(cuts.iter().map(|&c| f64::from(c)));
        windows.push(150.0);
        let batch = Batch::new(&stokes, pipe.boundary(), &timed, plan()).with_samples();
        let mut strict = Strict { inner: pipe.flow(), window: (0.0, 0.0) };
        let windowed = run_batch(&batch, &mut strict, &windows, &config, Shard::ALL, &quiet).unwrap();
        let case = pseudorigid::population::Case::new(&stokes, pipe.flow(), pipe.boundary(), &timed, plan());
        let major = run(&case, &config, Shard::ALL, &quiet).unwrap();
        for (a, b) in major.records.iter().zip(&windowed.records) {
            let k = b.index;
            if k % 11 == 5 {
                prop_assert!(matches!(b.fate, Fate::Failed { .. }), "particle {} should fail to draw", k);
                continue;
            }
            prop_assert!(!matches!(b.fate, Fate::Failed { .. }), "particle {k}: {:?}", b.fate);
            let mut rng = particle_rng(config.seed, k);
            let spec = timed.draw(k, &mut rng).unwrap();
            let t0 = timed.injection(k, &spec, &mut rng).unwrap().t;
            prop_assert!(t0 > 0.0 && t0 < latest);
            prop_assert_eq!(b.samples[0].t, t0, "particle {}", k);
            prop_assert_eq!(a.fate.label(), b.fate.label(), "particle {}", k);
        }
    }
}

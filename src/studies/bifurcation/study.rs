//! Deposition studies: populations of one particle kind, their deposition efficiency with its
//! binomial error, and the paper's figures' datasets.
//!
//! # Statistics
//! Each particle deposits independently with probability p, so the deposited count of n
//! particles is binomial and DE = n_dep/n estimates p with standard error
//! $\sqrt{DE(1 − DE)/n}$. Failed particles (an integration error) are left out of n and reported.

use super::BifurcationError;
use super::injection::{Injection, Kind};
use super::setup::{Airway, zhang_reference};
use crate::contact::MeshBoundary;
use crate::driver::{Budget, Plan};
use crate::error::ParamError;
use crate::flow::openfoam::BlendedFlow;
use crate::hydro::ForceTerms;
use crate::integrator::choice::{self, Choice, Chosen, ParticleNumbers};
use crate::integrator::{ErrorNorm, Tolerances};
use crate::material::NeoHooke;
use crate::output::Csv;
use crate::population::Injector;
use crate::population::{
    Case, CaseObserver, Computed, Fate, FateCounts, Fingerprint, RunOptions, RunOutput, Shard, run,
};
use serde::Serialize;
use std::path::Path;

/// Relative error tolerance of the integrator (absolute: [`ATOL`], SI units), under the
/// frame-independent error norm [`NORM`]. What a DE needs is that the integration error
/// changes few particles' fates, and fewer than the binomial error does. Checked by paired runs
/// (the same particles at two tolerances), 2 000 particles per kind against Radau IIA at rtol
/// 10⁻⁵, atol 10⁻⁸ ([`super::error_norm`], `paper-figures/work-precision/error_norm.csv`):
///
/// | kind | tensor 10⁻³ | tensor 3·10⁻³ | componentwise 10⁻² (before) |
/// |---|---|---|---|
/// | rigid λ = 20, Stk 0.01 | 0 | 0 | 0 |
/// | rigid λ = 20, Stk 0.2 | 1 | 2 | 1 |
/// | rigid λ = 20, Stk 0.5 | 1 | 9 (all deposited) | 0 |
/// | soft sphere μ_s = 1 Pa, Stk 0.1 | 0 | 0 | 0 |
/// | soft prolate λ₁ = 5, μ_s = 0.5 Pa, Stk 0.4 | 1 | 4 | 1 |
///
/// (fates changed). At 3·10⁻³ the long prolates' orientation is loose enough to bias
/// deposition at Stk 0.5 (9 of 2 000, all towards deposition: +0.0045 in DE, three binomial
/// errors at N = 10⁵), so the studies take 10⁻³, which changes as few fates as the
/// componentwise norm at 10⁻² did, for 1.0–1.21× less CPU time. About 1 fate in 10³ moves with
/// the tolerance, in either direction, against a binomial error of DE of 1.4·10⁻³–10⁻² at
/// N = 10⁴–10⁵; deposits that agree lie within 5 µm (median) of the reference's, and the
/// histograms' 0.8 mm bins are 30× the 90 % deposit shift.
pub const RTOL: f64 = 1e-3;
/// The studies' error norm: δF, δx and δv each by its Frobenius or Euclidean norm
/// ([`ErrorNorm::Tensor`]), so the steps do not depend on how the lab axes lie against the
/// particle. The componentwise norm held F's near-zero entries to [`ATOL`] alone, which set
/// two thirds of the rejected steps ([`super::error_norm`]).
pub const NORM: ErrorNorm = ErrorNorm::Tensor;
/// Absolute tolerance (SI): 10⁻⁵ m on positions (a particle radius), 10⁻⁵ m/s on velocities
/// (10⁻⁵ of the inlet speed), 10⁻⁵ on F. 10⁻⁴ changed 1 of 200 rigid λ = 20 fates at Stk = 0.5
/// and moved deposits by up to 5 mm; see [`RTOL`].
pub const ATOL: f64 = 1e-5;
/// Run seed of every dataset (particle k of every kind is drawn from stream k of it).
pub const SEED: u64 = 2024;
/// First step (s) (the integrator adapts it at once).
pub const DT0: f64 = 1e-6;
/// Accepted steps allowed per particle (10⁶: a particle that needs more is stuck, not slow).
pub const MAX_STEPS: u64 = 1_000_000;

/// The integrator of the studies for particles of `kind` in `airway`, chosen by
/// [`crate::integrator::choice`] at rtol [`RTOL`], atol [`ATOL`], error norm [`NORM`]: an
/// inertialess shape, the Rosenbrock-W 2(3) pair (at these loose tolerances, where wall
/// contacts and the mesh field set the steps, it costs half of Radau IIA's time), and the
/// equilibrium barycentre for
/// tracer-like particles (St ≤ [`crate::integrator::choice::EQUILIBRIUM_STOKES`]: Stk ≤ 0.022
/// for rigid λ = 20 prolates; 2.4–4.3× fewer steps, fates paired with the inertial barycentre in
/// `examples/barycentre_choice.rs`), the inertial one above.
pub fn integrator(airway: &Airway, kind: Kind) -> Result<Choice, BifurcationError> {
    let injection = Injection::new(airway, kind)?;
    let particle = injection.particle(&injection.particle_spec(0, 0)?)?;
    let numbers = ParticleNumbers::of(&particle, airway.flow())?;
    let choice = choice::choose(numbers, Tolerances::new(RTOL, ATOL, 1e-14)?)?;
    Ok(Choice {
        integrator: choice.integrator.with_norm(NORM),
        ..choice
    })
}

/// Track particles until contact, exit or [`Airway::tracking_time`]. Steps follow the error
/// control and the contact event's cap, which on the mesh's walls bounds the distance
/// travelled in any direction by the gap to the nearest face
/// ([`crate::contact::Approach::AnyDirection`]): no fixed step length is needed at the carina.
pub fn plan(airway: &Airway) -> Result<Plan, ParamError> {
    Ok(Plan::new(airway.tracking_time(), DT0)?.with_budget(Budget {
        max_steps: MAX_STEPS,
        wall_time: None,
    }))
}

/// The observer of a study's particles ([`StudyRun::observer`]).
pub type StudyObserver<'a> = CaseObserver<'a, Injection<'a>, BlendedFlow, MeshBoundary>;

/// One run of the study: `n` particles of one [`Kind`] through an [`Airway`], built up from
/// the paper's model and the study's choices and then run ([`Self::run`]), the one way every
/// bifurcation and airway-tree dataset is made:
///
/// ```no_run
/// # use pseudorigid::studies::bifurcation::{Airway, Kind, Material, StudyRun};
/// # use pseudorigid::studies::particles::Shape;
/// # use pseudorigid::population::RunOptions;
/// # fn go(airway: &Airway) -> Result<(), Box<dyn std::error::Error>> {
/// let kind = Kind { shape: Shape::Prolate(20.0), material: Material::Rigid, stokes: 0.1 };
/// let out = StudyRun::new(airway, kind, 1000).seed(7).run(&RunOptions::default())?;
/// # Ok(()) }
/// ```
///
/// Defaults: run seed [`SEED`] (the datasets'), the whole run
/// ([`Shard::ALL`]), no force term beyond the paper's drag and gravity, the study's integrator
/// ([`integrator`]), no observer, no cache. Everything set here enters the configuration hash
/// of a cached run, so a run is never read back for other settings.
#[derive(Clone)]
pub struct StudyRun<'a, 'o> {
    airway: &'a Airway,
    kind: Kind,
    n: u64,
    seed: u64,
    shard: Shard,
    forces: ForceTerms,
    integrator: Option<Chosen>,
    observer: Option<&'o StudyObserver<'a>>,
    cache: Option<&'o Path>,
}

impl<'a, 'o> StudyRun<'a, 'o> {
    /// `n` particles of `kind` through `airway`, with the defaults above.
    pub fn new(airway: &'a Airway, kind: Kind, n: u64) -> Self {
        Self {
            airway,
            kind,
            n,
            seed: SEED,
            shard: Shard::ALL,
            forces: ForceTerms::default(),
            integrator: None,
            observer: None,
            cache: None,
        }
    }

    /// Run seed: particle k draws from stream k of it.
    pub fn seed(self, seed: u64) -> Self {
        Self { seed, ..self }
    }

    /// Only shard `shard` of the run (a cluster's job array; `population::merge` joins them).
    pub fn shard(self, shard: Shard) -> Self {
        Self { shard, ..self }
    }

    /// Force terms beyond the paper's on every particle.
    pub fn forces(self, forces: &ForceTerms) -> Self {
        Self {
            forces: forces.clone(),
            ..self
        }
    }

    /// The integrator `integ` instead of the study's choice (paired comparisons of
    /// integrators and models).
    pub fn integrator(self, integ: impl Into<Chosen>) -> Self {
        Self {
            integrator: Some(integ.into()),
            ..self
        }
    }

    /// Each particle's run watched by `observer` (its summary in the records' `observed`; its
    /// fingerprint enters the configuration hash). The fates are those of the unobserved run:
    /// an observer only reads what it is shown.
    pub fn observer<'p>(self, observer: &'p StudyObserver<'a>) -> StudyRun<'a, 'p>
    where
        'o: 'p,
    {
        StudyRun {
            observer: Some(observer),
            ..self
        }
    }

    /// Keep the finished run in the folder `dir` as `<config hash>-<shard>.json` and read it
    /// back instead of running it again (the hash covers everything that determines the
    /// results).
    pub fn cache<'p>(self, dir: &'p Path) -> StudyRun<'a, 'p>
    where
        'o: 'p,
    {
        StudyRun {
            cache: Some(dir),
            ..self
        }
    }

    /// The airway it runs through.
    pub fn airway(&self) -> &'a Airway {
        self.airway
    }

    /// The particle kind.
    pub fn kind(&self) -> Kind {
        self.kind
    }

    /// Run it (or read it from the cache) as `options` say.
    pub fn run(&self, options: &RunOptions) -> Result<RunOutput<NeoHooke>, BifurcationError> {
        Ok(self.run_timed(options)?.output)
    }

    /// [`Self::run`] with the wall time the run took to compute (kept beside a cached run:
    /// [`RunOutput::read_or_run`]).
    pub fn run_timed(&self, options: &RunOptions) -> Result<Computed<NeoHooke>, BifurcationError> {
        let (airway, kind, forces) = (self.airway, self.kind, &self.forces);
        let integ = match &self.integrator {
            Some(integ) => *integ,
            None => integrator(airway, kind)?.integrator,
        };
        let injection = Injection::new(airway, kind)?.with_forces(forces.clone());
        let plan = plan(airway)?;
        let case = Case::new(&integ, airway.flow(), airway.boundary(), &injection, plan);
        let case = match self.observer {
            Some(observer) => case.with_observer(observer),
            None => case,
        };
        let config = Fingerprint::new("bifurcation")
            .particles(&kind)
            .with("residence time", &airway.mean_residence_time())
            .with("cells", &airway.flow().cellwise().mesh().n_cells())
            .with("blend radius", &airway.flow().radius())
            .flow(airway.flow())
            .boundary(airway.boundary())
            .with("forces", forces)
            .config(self.seed, self.n);
        let shard = self.shard;
        let file = self
            .cache
            .map(|dir| dir.join(format!("{}-{shard}.json", case.config_hash(&config)).replace('/', "of")));
        RunOutput::read_or_run(file.as_deref(), || Ok(run(&case, &config, shard, options)?))
    }
}

/// Deposition efficiency of one particle kind.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Efficiency {
    /// The particle kind.
    pub kind: Kind,
    /// Fates.
    pub counts: FateCounts,
}

impl Efficiency {
    /// Count the fates of a run of `kind`.
    pub fn of(kind: Kind, output: &RunOutput<NeoHooke>) -> Self {
        Self {
            kind,
            counts: output.counts(),
        }
    }

    /// Particles that finished (deposited, escaped or suspended).
    pub fn finished(&self) -> u64 {
        self.counts.total() - self.counts.failed
    }

    /// DE = n_dep/n over the finished particles (0 if none).
    pub fn de(&self) -> f64 {
        crate::population::binomial::fraction(self.counts.deposited, self.finished())
    }

    /// Binomial standard error √(DE(1 − DE)/n).
    pub fn stderr(&self) -> f64 {
        crate::population::binomial::stderr(self.counts.deposited, self.finished())
    }
}

/// `shape,ca,stk,n_injected,n_deposited,n_escaped,n_suspended,de,de_stderr`: n_injected
/// counts every particle, failed ones included (none in the shipped datasets; DE leaves them
/// out).
pub fn efficiency_table(rows: &[Efficiency]) -> Result<Csv, crate::output::OutputError> {
    let mut csv = Csv::new(&EFFICIENCY_COLUMNS);
    for r in rows {
        csv.push(efficiency_fields(r))?;
    }
    Ok(csv)
}

/// The columns of [`efficiency_table`].
const EFFICIENCY_COLUMNS: [&str; 9] = [
    "shape",
    "ca",
    "stk",
    "n_injected",
    "n_deposited",
    "n_escaped",
    "n_suspended",
    "de",
    "de_stderr",
];

/// A row of [`efficiency_table`].
fn efficiency_fields(r: &Efficiency) -> Vec<String> {
    vec![
        r.kind.shape.label(),
        format!("{:.4e}", r.kind.material.capillary_number()),
        r.kind.stokes.to_string(),
        r.counts.total().to_string(),
        r.counts.deposited.to_string(),
        r.counts.escaped.to_string(),
        r.counts.suspended.to_string(),
        format!("{:.5}", r.de()),
        format!("{:.5}", r.stderr()),
    ]
}

/// [`efficiency_table`] with the band of a mesh study: `de_extrapolated,gci,p`, the
/// `deposited` outcome's extrapolated fraction, its GCI in DE's units and the apparent order
/// (three-grid procedure, [`crate::population::gci`]) of the study in `studies` of the row's
/// kind; empty where there is none or the procedure stands behind no bar
/// ([`crate::population::mesh_study::OutcomeStudy::error_bar`]: its verdict is in the study's
/// own table).
pub fn banded_efficiency_table(
    rows: &[Efficiency],
    studies: &[(Kind, crate::population::mesh_study::MeshStudy)],
) -> Result<Csv, crate::output::OutputError> {
    let mut header = EFFICIENCY_COLUMNS.to_vec();
    header.extend(["de_extrapolated", "gci", "p"]);
    let mut csv = Csv::new(&header);
    for r in rows {
        let bar = studies
            .iter()
            .find(|(k, _)| *k == r.kind)
            .and_then(|(_, s)| s.outcome("deposited")?.error_bar());
        let mut fields = efficiency_fields(r);
        fields.extend([
            bar.map_or(String::new(), |e| format!("{:.5}", e.extrapolated)),
            bar.map_or(String::new(), |e| format!("{:.5}", e.band)),
            bar.and_then(|e| e.p_apparent)
                .map_or(String::new(), |p| format!("{p:.2}")),
        ]);
        csv.push(fields)?;
    }
    Ok(csv)
}

/// DE beside the correlation at the Stokes number the particles' drag implies: Stk from d_eq
/// (paper eq. 25) times the orientation-averaged response-time ratio
/// ([`crate::hydro::drag::mean_response_time_ratio`]), the correlation being for spheres.
/// Columns `shape,stk,response_time_ratio,stk_effective,de,de_stderr,zhang_at_stk,
/// zhang_at_stk_effective`.
pub fn effective_stokes_table(rows: &[Efficiency]) -> Result<Csv, BifurcationError> {
    let mut csv = Csv::new(&[
        "shape",
        "stk",
        "response_time_ratio",
        "stk_effective",
        "de",
        "de_stderr",
        "zhang_at_stk",
        "zhang_at_stk_effective",
    ]);
    for r in rows {
        let ratio = crate::hydro::drag::mean_response_time_ratio(&crate::tensor::Vec3::from(r.kind.shape.ratios()))?;
        let effective = r.kind.stokes * ratio;
        csv.push(vec![
            r.kind.shape.label(),
            r.kind.stokes.to_string(),
            format!("{ratio:.5}"),
            format!("{effective:.5}"),
            format!("{:.5}", r.de()),
            format!("{:.5}", r.stderr()),
            format!("{:.5}", zhang_reference(r.kind.stokes)?),
            format!("{:.5}", zhang_reference(effective)?),
        ])?;
    }
    Ok(csv)
}

/// The deposited particles of a run: (index, barycentre x, time).
pub fn deposits(output: &RunOutput<NeoHooke>) -> impl Iterator<Item = (u64, crate::tensor::Vec3, f64)> + '_ {
    output.records.iter().filter_map(|r| match r.fate {
        Fate::Deposited { position, time, .. } => Some((r.index, position, time)),
        _ => None,
    })
}

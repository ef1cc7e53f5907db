//! Drug release at a critical stretch in the tree (issue 24, item 5): runs of a soft kind
//! watched by the release observer ([`crate::population::release`]), where (generation, point)
//! and when each particle first reaches each threshold, the released fractions per generation
//! against the threshold, the release map and the picture.
//!
//! # Statistics
//! For a threshold s and a generation g, n_rel,g counts the particles whose first crossing of
//! s lies in generation g (its barycentre classified by [`Tree::classify`]: a G-g tube or the
//! bifurcation zone at its end, as for deposition), and
//! ```math
//! f_g = \frac{n_{rel,g}}{N}, \qquad \sigma_g = \sqrt{\frac{f_g (1 - f_g)}{N}},
//! ```
//! with N the finished particles of the run (failed ones are left out, as in
//! [`super::study`]): f_g is the share of the dose released in generation g, and the f_g of one
//! threshold add up to the fraction released anywhere in the tree. Each particle releases in at
//! most one generation per threshold, so n_rel,g is binomial with N trials and the error is
//! the binomial one. A crossing after the particle's deposit is not a release (the watch stops
//! at the run's end); a particle that escapes through an outlet may have released before.

use super::study::mu_s_label;
use super::tree::{Location, Tree};
use super::{AirwayTree, AirwayTreeError};
use crate::material::NeoHooke;
use crate::output::vtk::PointValues;
use crate::output::{Csv, Figure, Panel, PolyData, Series, VtkError};
use crate::particle::release::{ReleaseCriterion, ReleaseThresholds};
use crate::population::release::{Crossing, ReleaseObserver, Released};
use crate::population::{Computed, Fate, RunOptions, RunOutput, SummaryError};
use crate::studies::bifurcation::Kind;
use crate::studies::bifurcation::StudyRun;
use crate::tensor::Vec3;

/// Thresholds of the largest principal stretch λ₁ scanned by the study: from barely deformed
/// (1.01) past the rupture stretch of a brittle alginate gel (about 1.2, Sun et al., Nature 489
/// (2012) 133–136; [`crate::particle::release`]) to 2.
pub const STRETCH_LEVELS: [f64; 8] = [1.01, 1.02, 1.05, 1.1, 1.2, 1.3, 1.5, 2.0];

/// The study's thresholds: [`STRETCH_LEVELS`] of λ₁.
pub fn stretch_thresholds() -> ReleaseThresholds {
    ReleaseThresholds::new(ReleaseCriterion::PrincipalStretch, STRETCH_LEVELS.to_vec())
        .expect("the study's levels are increasing and above 1")
}

/// `run` (through the tree's airway: [`AirwayTree::study`]) watched by [`ReleaseObserver`] at
/// `thresholds`: the tree study's run ([`super::track`]) with another observer, hence the
/// same fates particle by particle. A cached run is keyed by the configuration hash, which
/// covers the observer. The run comes back with its computation's wall time ([`Computed`]).
pub fn track<'a>(
    tree: &'a AirwayTree,
    run: StudyRun<'a, '_>,
    thresholds: &ReleaseThresholds,
    options: &RunOptions,
) -> Result<Computed<NeoHooke>, AirwayTreeError> {
    if !std::ptr::eq(run.airway(), tree.airway()) {
        return Err(AirwayTreeError::OtherAirway);
    }
    let observer = ReleaseObserver::new(thresholds.clone());
    Ok(run.observer(&observer).run_timed(options)?)
}

/// One particle's first crossing of one threshold, placed in the tree.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReleaseEvent {
    /// Particle index.
    pub index: u64,
    /// The threshold.
    pub threshold: f64,
    /// Time, point and criterion of the crossing.
    pub crossing: Crossing,
    /// Where in the tree.
    pub location: Location,
}

/// What the finished particles of a run did: their number and every release event.
#[derive(Debug, Clone, PartialEq)]
pub struct ReleaseResults {
    /// The criterion and its levels.
    pub thresholds: ReleaseThresholds,
    /// Finished (not failed) particles, N.
    pub n: u64,
    /// Every first crossing of every threshold, by particle then threshold.
    pub events: Vec<ReleaseEvent>,
    /// The largest criterion value of each finished particle (its peak).
    pub peaks: Vec<f64>,
}

impl ReleaseResults {
    /// The releases of `output`, run with [`ReleaseObserver`] at `thresholds`.
    pub fn of(
        tree: &Tree,
        thresholds: &ReleaseThresholds,
        output: &RunOutput<NeoHooke>,
    ) -> Result<Self, AirwayTreeError> {
        let mut events = Vec::new();
        let mut peaks = Vec::new();
        for record in &output.records {
            if matches!(record.fate, Fate::Failed { .. }) {
                continue;
            }
            let released: Released = record.summary()?;
            if released.crossings.len() != thresholds.levels().len() {
                return Err(SummaryError {
                    index: record.index,
                    summary: "release",
                    reason: format!(
                        "{} crossings kept, {} thresholds asked",
                        released.crossings.len(),
                        thresholds.levels().len()
                    ),
                }
                .into());
            }
            peaks.push(released.peak.value);
            for (&threshold, crossing) in thresholds.levels().iter().zip(released.crossings) {
                if let Some(crossing) = crossing {
                    events.push(ReleaseEvent {
                        index: record.index,
                        threshold,
                        crossing,
                        location: tree.classify(&Vec3::from(crossing.x))?,
                    });
                }
            }
        }
        Ok(Self {
            thresholds: thresholds.clone(),
            n: peaks.len() as u64,
            events,
            peaks,
        })
    }

    /// Released counts per threshold and generation of `tree` (thresholds outer).
    pub fn by_generation(&self, tree: &Tree) -> Vec<ReleaseCounts> {
        let mut rows = Vec::new();
        for &threshold in self.thresholds.levels() {
            for generation in tree.generations() {
                let released = self
                    .events
                    .iter()
                    .filter(|e| e.threshold == threshold && e.location.generation == generation)
                    .count() as u64;
                rows.push(ReleaseCounts {
                    threshold,
                    generation,
                    released,
                    n: self.n,
                });
            }
        }
        rows
    }

    /// Release times at `threshold`: (count, mean, standard error of the mean, median); `None`
    /// if no particle released.
    pub fn times(&self, threshold: f64) -> Option<TimeSummary> {
        let mut t: Vec<f64> = self
            .events
            .iter()
            .filter(|e| e.threshold == threshold)
            .map(|e| e.crossing.t)
            .collect();
        if t.is_empty() {
            return None;
        }
        t.sort_by(f64::total_cmp);
        let n = t.len() as f64;
        let mean = t.iter().sum::<f64>() / n;
        let var = if t.len() > 1 {
            t.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)
        } else {
            0.0
        };
        let mid = t.len() / 2;
        let median = if t.len() % 2 == 1 {
            t[mid]
        } else {
            0.5 * (t[mid - 1] + t[mid])
        };
        Some(TimeSummary {
            count: t.len() as u64,
            mean,
            stderr: (var / n).sqrt(),
            median,
        })
    }
}

/// Release times at one threshold.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeSummary {
    /// Particles released.
    pub count: u64,
    /// Mean release time.
    pub mean: f64,
    /// Its standard error, s/√count.
    pub stderr: f64,
    /// Median release time.
    pub median: f64,
}

/// Particles releasing at one threshold in one generation, out of N.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReleaseCounts {
    /// The threshold.
    pub threshold: f64,
    /// The generation.
    pub generation: u8,
    /// Particles whose first crossing lies in the generation.
    pub released: u64,
    /// Finished particles of the run.
    pub n: u64,
}

impl ReleaseCounts {
    /// f_g = n_rel,g/N (0 if N = 0).
    pub fn fraction(&self) -> f64 {
        crate::population::binomial::fraction(self.released, self.n)
    }

    /// Binomial standard error √(f(1 − f)/N) (0 if N = 0).
    pub fn stderr(&self) -> f64 {
        crate::population::binomial::stderr(self.released, self.n)
    }
}

/// `shape,mu_s,stk,threshold,generation,n_released,fraction,fraction_stderr` (issue 24).
pub fn release_table(rows: &[(Kind, Vec<ReleaseCounts>)]) -> Result<Csv, AirwayTreeError> {
    let mut csv = Csv::new(&[
        "shape",
        "mu_s",
        "stk",
        "threshold",
        "generation",
        "n_released",
        "fraction",
        "fraction_stderr",
    ]);
    for (kind, counts) in rows {
        for c in counts {
            csv.push(vec![
                kind.shape.label(),
                mu_s_label(kind.material),
                kind.stokes.to_string(),
                c.threshold.to_string(),
                c.generation.to_string(),
                c.released.to_string(),
                format!("{:.5}", c.fraction()),
                format!("{:.5}", c.stderr()),
            ])?;
        }
    }
    Ok(csv)
}

/// `shape,mu_s,stk,threshold,n,n_released,fraction,fraction_stderr,t_mean,t_stderr,t_median,
/// zone_share`: the released fraction over the whole tree, the release times (s) per
/// threshold, and the share of the releases that lie in a bifurcation zone (a carina region)
/// rather than a tube proper.
pub fn release_times_table(rows: &[(Kind, ReleaseResults)]) -> Result<Csv, AirwayTreeError> {
    let mut csv = Csv::new(&[
        "shape",
        "mu_s",
        "stk",
        "threshold",
        "n",
        "n_released",
        "fraction",
        "fraction_stderr",
        "t_mean",
        "t_stderr",
        "t_median",
        "zone_share",
    ]);
    for (kind, releases) in rows {
        for &threshold in releases.thresholds.levels() {
            let times = releases.times(threshold);
            let whole = ReleaseCounts {
                threshold,
                generation: 0,
                released: times.map_or(0, |t| t.count),
                n: releases.n,
            };
            let time = |f: fn(&TimeSummary) -> f64| times.as_ref().map_or(String::new(), |t| format!("{:.5}", f(t)));
            csv.push(vec![
                kind.shape.label(),
                mu_s_label(kind.material),
                kind.stokes.to_string(),
                threshold.to_string(),
                releases.n.to_string(),
                whole.released.to_string(),
                format!("{:.5}", whole.fraction()),
                format!("{:.5}", whole.stderr()),
                time(|t| t.mean),
                time(|t| t.stderr),
                time(|t| t.median),
                zone_share(releases, threshold).map_or(String::new(), |z| format!("{z:.5}")),
            ])?;
        }
    }
    Ok(csv)
}

/// The share of the releases at `threshold` located in a bifurcation zone; `None` if none.
fn zone_share(releases: &ReleaseResults, threshold: f64) -> Option<f64> {
    let at: Vec<&ReleaseEvent> = releases.events.iter().filter(|e| e.threshold == threshold).collect();
    let zones = at
        .iter()
        .filter(|e| e.location.part == super::tree::Part::Bifurcation)
        .count();
    (!at.is_empty()).then(|| zones as f64 / at.len() as f64)
}

/// Released fraction against the threshold, one panel per generation of `tree`, one series
/// per kind with f ± 2σ as lines; a last panel for the whole tree.
pub fn release_figure(tree: &Tree, rows: &[(Kind, ReleaseResults)], title: &str) -> Figure {
    let mut panels = Vec::new();
    let whole = |releases: &ReleaseResults, threshold: f64| ReleaseCounts {
        threshold,
        generation: 0,
        released: releases.times(threshold).map_or(0, |t| t.count),
        n: releases.n,
    };
    let generations: Vec<Option<u8>> = tree.generations().map(Some).chain([None]).collect();
    for generation in generations {
        let name = generation.map_or("whole tree".to_string(), |g| format!("G{g}"));
        let mut panel = Panel::new(
            format!("{title}: released in {name}"),
            "threshold of the largest stretch",
            "fraction of all particles",
        );
        for (i, (kind, releases)) in rows.iter().enumerate() {
            let counts: Vec<ReleaseCounts> = match generation {
                Some(g) => releases
                    .by_generation(tree)
                    .into_iter()
                    .filter(|c| c.generation == g)
                    .collect(),
                None => releases
                    .thresholds
                    .levels()
                    .iter()
                    .map(|&s| whole(releases, s))
                    .collect(),
            };
            let pts = |k: f64| -> Vec<(f64, f64)> {
                counts
                    .iter()
                    .map(|c| (c.threshold, c.fraction() + k * c.stderr()))
                    .collect()
            };
            let key = format!(
                "{} mu_s={} Stk={}",
                kind.shape.label(),
                mu_s_label(kind.material),
                kind.stokes
            );
            panel = panel
                .with(Series::points(key.clone(), pts(0.0), i + 1))
                .with(Series::line(format!("{key} ± 2σ"), pts(2.0), i + 1))
                .with(Series::line("", pts(-2.0), i + 1));
        }
        panels.push(panel);
    }
    Figure::grid(panels, 3, (560, 420))
}

/// Per kind: a number for the map's `kind` array, and its releases.
type Map<'r> = [(Kind, &'r ReleaseResults)];

/// The release map for ParaView: one vertex per release event of the particles with index
/// below `particles` (the same particles in every kind; a map of every particle of a large
/// run is tens of megabytes) at its barycentre, with point arrays `time`, `threshold`,
/// `stretch` (λ₁ there), `generation`, `tube`, `zone` (1 in a bifurcation zone), `particle`
/// (index) and `kind` (position in `rows`).
pub fn release_map(rows: &Map<'_>, particles: u64) -> Result<PolyData, VtkError> {
    let events: Vec<(usize, &ReleaseEvent)> = rows
        .iter()
        .enumerate()
        .flat_map(|(k, (_, r))| r.events.iter().map(move |e| (k, e)))
        .filter(|(_, e)| e.index < particles)
        .collect();
    let f = |g: fn(&ReleaseEvent) -> f64| PointValues::Float64(events.iter().map(|(_, e)| g(e)).collect());
    let i = |g: fn(usize, &ReleaseEvent) -> i64| PointValues::Int64(events.iter().map(|(k, e)| g(*k, e)).collect());
    let map = PolyData::vertices(events.iter().map(|(_, e)| Vec3::from(e.crossing.x)).collect())?
        .with_array("time", 1, f(|e| e.crossing.t))?
        .with_array("threshold", 1, f(|e| e.threshold))?
        .with_array("stretch", 1, f(|e| e.crossing.stretch))?
        .with_array("generation", 1, i(|_, e| i64::from(e.location.generation)))?
        .with_array("tube", 1, i(|_, e| e.location.tube as i64))?
        .with_array(
            "zone",
            1,
            i(|_, e| i64::from(e.location.part == super::tree::Part::Bifurcation)),
        )?
        .with_array("particle", 1, i(|_, e| e.index as i64))?
        .with_array("kind", 1, i(|k, _| k as i64))?;
    Ok(map)
}

/// The release map as a Parquet table: `shape`, `mu_s` (null for rigid), `stk`, `threshold`,
/// `particle`, `t`, `x1`–`x3`, `value` (the criterion), `stretch`, `generation`, `tube`,
/// `zone`, one row per release event of the particles with index below `particles` (as
/// [`release_map`]).
#[cfg(feature = "parquet")]
pub fn write_release_parquet(rows: &Map<'_>, particles: u64, path: &std::path::Path) -> Result<(), AirwayTreeError> {
    use crate::output::parquet::Table;
    use crate::studies::bifurcation::Material;
    let events: Vec<(&Kind, &ReleaseEvent)> = rows
        .iter()
        .flat_map(|(k, r)| r.events.iter().map(move |e| (k, e)))
        .filter(|(_, e)| e.index < particles)
        .collect();
    let mut t = Table::default();
    t.text("shape", events.iter().map(|(k, _)| Some(k.shape.label())).collect());
    t.f64_or_null(
        "mu_s",
        events
            .iter()
            .map(|(k, _)| match k.material {
                Material::Rigid => None,
                Material::ShearModulus(mu) => Some(mu),
            })
            .collect(),
    );
    t.f64("stk", events.iter().map(|(k, _)| k.stokes).collect());
    t.f64("threshold", events.iter().map(|(_, e)| e.threshold).collect());
    t.u64("particle", events.iter().map(|(_, e)| e.index).collect());
    t.f64_measured("t", events.iter().map(|(_, e)| e.crossing.t).collect());
    for a in 0..3 {
        t.f64_measured(
            &format!("x{}", a + 1),
            events.iter().map(|(_, e)| e.crossing.x[a]).collect(),
        );
    }
    t.f64_measured("value", events.iter().map(|(_, e)| e.crossing.value).collect());
    t.f64_measured("stretch", events.iter().map(|(_, e)| e.crossing.stretch).collect());
    t.i64(
        "generation",
        events.iter().map(|(_, e)| i64::from(e.location.generation)).collect(),
    );
    t.i64("tube", events.iter().map(|(_, e)| e.location.tube as i64).collect());
    t.i64(
        "zone",
        events
            .iter()
            .map(|(_, e)| i64::from(e.location.part == super::tree::Part::Bifurcation))
            .collect(),
    );
    Ok(t.write(path)?)
}

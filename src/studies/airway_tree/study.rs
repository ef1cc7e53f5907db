//! The per-generation deposition study: runs of one particle kind through the tree with the
//! [`Generations`] observer, their counts per generation, rigid against soft on the same
//! particles, the datasets and the picture.
//!
//! # Statistics
//! Per generation g, DE_g = n_dep,g/n_ent,g with the binomial error of the module docs
//! ([`super`]). Failed particles are left out of every count and reported by the run.
//!
//! Rigid and soft runs of a kind use the same seed, so particle k starts at the same point
//! with the same orientation (and, the shape being the same, the same fluid velocity) in
//! both: the pairs differ only by the material. For a generation, let b (c) count the
//! particles the reference (soft) run deposits in g and the other does not deposit in g; the
//! change of the fraction of all N particles deposited in g, (c − b)/N, then has McNemar's
//! standard error √(b + c)/N, far below the unpaired error when few particles change. The
//! change of DE_g itself is reported with the unpaired error √(σ_ref² + σ_soft²), an upper
//! bound for positively correlated runs.

use super::observe::{Generations, Reached};
use super::tree::Tree;
use super::{AirwayTree, AirwayTreeError};
use crate::material::NeoHooke;
use crate::output::{Csv, Figure, Panel, Series};
use crate::population::binomial::{PairedFates, Pairing};
use crate::population::{Computed, Fate, ParticleRecord, RunOptions, RunOutput};
use crate::studies::bifurcation::injection::Material;
use crate::studies::bifurcation::{BifurcationError, Kind, StudyRun};
use std::path::PathBuf;

/// `run` (through the tree's airway: [`AirwayTree::study`]) with each particle watched by
/// [`Generations`]: the bifurcation's study ([`crate::studies::bifurcation::study`]:
/// integrator, tolerances, plan) in the tree's flow. A cached run is keyed by the
/// configuration hash, which covers the tree and the observer; the run comes back with its
/// computation's wall time ([`Computed`]).
pub fn track<'a>(
    tree: &'a AirwayTree,
    run: StudyRun<'a, '_>,
    options: &RunOptions,
) -> Result<Computed<NeoHooke>, AirwayTreeError> {
    if !std::ptr::eq(run.airway(), tree.airway()) {
        return Err(AirwayTreeError::OtherAirway);
    }
    let observer = Generations::new(tree.tree());
    Ok(run.observer(&observer).run_timed(options)?)
}

/// Where one finished particle went: the deepest generation it entered and the generation it
/// deposited in (`None`: escaped or suspended).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TreeFate {
    /// Deepest generation entered.
    pub deepest: u8,
    /// Generation of the deposit.
    pub deposited: Option<u8>,
}

/// The outcome of a record; `None` for a failed particle. The deposit's generation is that of
/// its barycentre at contact ([`Tree::classify`]); a particle entered every generation up to
/// its deposit's (so `deepest` is at least that, whatever the observer saw).
pub fn tree_fate(tree: &Tree, record: &ParticleRecord<NeoHooke>) -> Result<Option<TreeFate>, AirwayTreeError> {
    let deposited = match &record.fate {
        Fate::Failed { .. } => return Ok(None),
        Fate::Deposited { position, .. } => Some(tree.classify(position)?.generation),
        Fate::Escaped { .. } | Fate::Suspended => None,
    };
    let reached: Reached = record.summary()?;
    Ok(Some(TreeFate {
        deepest: reached.generation.max(deposited.unwrap_or(0)),
        deposited,
    }))
}

/// Particles that entered and deposited in one generation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GenerationCounts {
    /// The generation.
    pub generation: u8,
    /// Particles that entered it.
    pub entered: u64,
    /// Particles deposited in it (its tubes and the bifurcation zones at their ends).
    pub deposited: u64,
}

impl GenerationCounts {
    /// DE_g = n_dep/n_ent (0 if none entered).
    pub fn de(&self) -> f64 {
        crate::population::binomial::fraction(self.deposited, self.entered)
    }

    /// Binomial standard error √(DE(1 − DE)/n_ent) (0 if none entered).
    pub fn stderr(&self) -> f64 {
        crate::population::binomial::stderr(self.deposited, self.entered)
    }
}

/// Counts of every generation of `tree` over the finished particles of `output`.
pub fn by_generation(tree: &Tree, output: &RunOutput<NeoHooke>) -> Result<Vec<GenerationCounts>, AirwayTreeError> {
    let mut outcomes = Vec::with_capacity(output.records.len());
    for record in &output.records {
        outcomes.extend(tree_fate(tree, record)?);
    }
    Ok(count(tree, outcomes))
}

/// Counts of every generation of `tree` over some particles' outcomes: a particle entered
/// every generation up to its deepest.
pub fn count(tree: &Tree, outcomes: impl IntoIterator<Item = TreeFate>) -> Vec<GenerationCounts> {
    let mut rows: Vec<GenerationCounts> = tree
        .generations()
        .map(|generation| GenerationCounts {
            generation,
            entered: 0,
            deposited: 0,
        })
        .collect();
    for o in outcomes {
        for row in &mut rows {
            if row.generation <= o.deepest {
                row.entered += 1;
            }
            if o.deposited == Some(row.generation) {
                row.deposited += 1;
            }
        }
    }
    rows
}

/// One generation of a reference run against a soft run of the same particles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairedGeneration {
    /// The reference run's counts.
    pub reference: GenerationCounts,
    /// The soft run's counts.
    pub soft: GenerationCounts,
    /// The particles finished in both runs, paired: deposited in this generation by the soft
    /// run (first) and by the reference run (second).
    pub pairing: Pairing,
}

impl PairedGeneration {
    /// Particles finished in both runs.
    pub fn n(&self) -> u64 {
        self.pairing.n()
    }

    /// Deposited in this generation by the reference run only.
    pub fn reference_only(&self) -> u64 {
        self.pairing.only_peer
    }

    /// Deposited in this generation by the soft run only.
    pub fn soft_only(&self) -> u64 {
        self.pairing.only_ours
    }

    /// The generation's discordant pairs: b = deposited in it by the soft run only, c = by the
    /// reference run only, over the n pairs (without pairs, 0 ± 0). Its
    /// [`PairedFates::difference`] is the change of the fraction of all particles deposited in
    /// the generation, soft − reference; the tables give it McNemar's standard error
    /// [`PairedFates::stderr_under_null`].
    pub fn fates(&self) -> PairedFates {
        self.pairing.fates_or_zero()
    }

    /// DE_soft − DE_reference.
    pub fn delta_de(&self) -> f64 {
        self.soft.de() - self.reference.de()
    }

    /// Unpaired standard error of [`Self::delta_de`] (an upper bound for paired runs).
    pub fn delta_de_stderr(&self) -> f64 {
        self.soft.stderr().hypot(self.reference.stderr())
    }
}

/// The runs `reference` and `soft` of the same particles, generation by generation.
pub fn paired(
    tree: &Tree,
    reference: &RunOutput<NeoHooke>,
    soft: &RunOutput<NeoHooke>,
) -> Result<Vec<PairedGeneration>, AirwayTreeError> {
    let (ra, rb) = (by_generation(tree, reference)?, by_generation(tree, soft)?);
    let mut rows: Vec<PairedGeneration> = ra
        .into_iter()
        .zip(rb)
        .map(|(reference, soft)| PairedGeneration {
            reference,
            soft,
            pairing: Pairing::default(),
        })
        .collect();
    let pairs = crate::population::paired(&reference.records, &soft.records).map_err(BifurcationError::from)?;
    for (a, b) in pairs {
        let (Some(oa), Some(ob)) = (tree_fate(tree, a)?, tree_fate(tree, b)?) else {
            continue;
        };
        for row in &mut rows {
            let g = Some(row.reference.generation);
            row.pairing.add(ob.deposited == g, oa.deposited == g);
        }
    }
    Ok(rows)
}

/// μ_s of a material for the tables: `inf` for rigid, else the shear modulus in Pa.
pub fn mu_s_label(material: Material) -> String {
    match material {
        Material::Rigid => "inf".into(),
        Material::ShearModulus(mu_s) => mu_s.to_string(),
    }
}

/// `shape,mu_s,stk,generation,n_entered,n_deposited,de,de_stderr` (issue 24).
pub fn de_table(rows: &[(Kind, Vec<GenerationCounts>)]) -> Result<Csv, AirwayTreeError> {
    let mut csv = Csv::new(&[
        "shape",
        "mu_s",
        "stk",
        "generation",
        "n_entered",
        "n_deposited",
        "de",
        "de_stderr",
    ]);
    for (kind, counts) in rows {
        for c in counts {
            csv.push(vec![
                kind.shape.label(),
                mu_s_label(kind.material),
                kind.stokes.to_string(),
                c.generation.to_string(),
                c.entered.to_string(),
                c.deposited.to_string(),
                format!("{:.5}", c.de()),
                format!("{:.5}", c.stderr()),
            ])?;
        }
    }
    Ok(csv)
}

/// `shape,stk,reference,soft,generation,n,reference_only,soft_only,delta_fraction,
/// delta_fraction_stderr,de_reference,de_soft,delta_de,delta_de_stderr` (μ_s labels as in
/// [`de_table`]; [`PairedGeneration`]): `delta_fraction` ± `delta_fraction_stderr` is
/// [`PairedGeneration::fates`]' difference with McNemar's standard error under no effect,
/// √(soft_only + reference_only)/n ([`PairedFates::stderr_under_null`]).
pub fn paired_table(rows: &[(Kind, Kind, Vec<PairedGeneration>)]) -> Result<Csv, AirwayTreeError> {
    let mut csv = Csv::new(&[
        "shape",
        "stk",
        "reference",
        "soft",
        "generation",
        "n",
        "reference_only",
        "soft_only",
        "delta_fraction",
        "delta_fraction_stderr",
        "de_reference",
        "de_soft",
        "delta_de",
        "delta_de_stderr",
    ]);
    for (reference, soft, gens) in rows {
        for p in gens {
            let fates = p.fates();
            csv.push(vec![
                reference.shape.label(),
                reference.stokes.to_string(),
                mu_s_label(reference.material),
                mu_s_label(soft.material),
                p.reference.generation.to_string(),
                p.n().to_string(),
                p.reference_only().to_string(),
                p.soft_only().to_string(),
                format!("{:.5}", fates.difference()),
                format!("{:.5}", fates.stderr_under_null()),
                format!("{:.5}", p.reference.de()),
                format!("{:.5}", p.soft.de()),
                format!("{:.5}", p.delta_de()),
                format!("{:.5}", p.delta_de_stderr()),
            ])?;
        }
    }
    Ok(csv)
}

/// DE_g against the generation, one panel per Stokes number, one series per (shape, μ_s)
/// with DE ± 2 standard errors as lines.
pub fn de_figure(rows: &[(Kind, Vec<GenerationCounts>)], title: &str) -> Figure {
    let mut stokes: Vec<f64> = Vec::new();
    for (kind, _) in rows {
        if !stokes.contains(&kind.stokes) {
            stokes.push(kind.stokes);
        }
    }
    let panels: Vec<Panel> = stokes
        .iter()
        .map(|&stk| {
            let mut panel = Panel::new(
                format!("{title}, Stk = {stk}"),
                "generation",
                "DE of the particles entering",
            );
            let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
            let mut top: f64 = 0.0;
            for (i, (kind, counts)) in rows.iter().filter(|(k, _)| k.stokes == stk).enumerate() {
                let pts = |s: f64| -> Vec<(f64, f64)> {
                    counts
                        .iter()
                        .map(|c| (f64::from(c.generation), c.de() + s * c.stderr()))
                        .collect()
                };
                for c in counts {
                    lo = lo.min(f64::from(c.generation));
                    hi = hi.max(f64::from(c.generation));
                    top = top.max(c.de() + 2.0 * c.stderr());
                }
                let key = format!("{} mu_s={}", kind.shape.label(), mu_s_label(kind.material));
                panel = panel
                    .with(Series::points(key.clone(), pts(0.0), i + 1))
                    .with(Series::line(format!("{key} ± 2σ"), pts(2.0), i + 1))
                    .with(Series::line("", pts(-2.0), i + 1));
            }
            if lo <= hi {
                panel = panel.with_ranges((lo - 0.3, hi + 0.3), (0.0, (1.1 * top).max(1e-3)));
            }
            panel
        })
        .collect();
    let columns = panels.len().max(1);
    Figure::grid(panels, columns, (640, 480))
}

/// The folder where finished tree runs are kept between examples (created if missing):
/// `PSEUDORIGID_TREE_CACHE`, else `target/airway-tree-runs` in the crate.
pub fn cache_dir() -> Result<PathBuf, crate::output::OutputError> {
    crate::studies::cache_folder("PSEUDORIGID_TREE_CACHE", "airway-tree-runs")
}

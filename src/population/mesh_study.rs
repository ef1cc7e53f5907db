//! A mesh study of a population: the same particles (the same seed, so particle k draws the
//! same shape, orientation and injection on every mesh) run on two to four solutions of one
//! geometry, every outcome's fraction on each mesh, its sampling errors, and the discretisation
//! error of the finest value by the three-grid procedure ([`super::gci`]).
//!
//! # Outcomes
//! Every fate a particle can meet is an outcome: `deposited` and `deposited:<wall patch>`,
//! `escaped` and `escaped:<outlet>`, `suspended`, `failed`. Patches are matched by name, so
//! meshes whose patches are numbered differently pair correctly.
//!
//! # Two kinds of error
//! A fraction f = k/n on one mesh has the binomial standard error $\sqrt{f(1-f)/n}$
//! ([`super::binomial`]). The increment between two meshes is a paired difference: each
//! particle has a fate on both, and only the discordant ones move it, so its standard error
//! is McNemar's ([`super::binomial::PairedFates`]), far below the two binomial errors combined.
//! The order p is read from the ratio of two increments: an increment within two of its paired
//! standard errors is sampling noise, and so is any p read from it. The verdict says so
//! before it quotes p, the extrapolated value or the GCI.
//!
//! # Which meshes
//! Meshes are sorted finest first by cell count. Celik et al.'s procedure takes three: with
//! four, the three finest give the estimate and the coarsest one's value and increment are
//! reported beside it; with two, the formal order is assumed and F_s = 3.

use super::binomial::{Pairing, fraction, stderr};
use super::gci::{Convergence, GciError, GridConvergence};
use super::{Fate, RunOutput};
use crate::output::{Csv, OutputError};
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;
use thiserror::Error;

/// The formal order assumed for the chain (a second-order finite-volume solution, linear
/// reconstruction between cells) unless a study says otherwise.
pub const FORMAL_ORDER: f64 = 2.0;
/// An increment is resolved when it exceeds this many paired standard errors.
pub const RESOLVED_SE: f64 = 2.0;
/// An apparent order within this of the formal order reads as asymptotic (the acceptance of
/// issue 58's verification target; Celik et al. ask for "reasonably close" to formal).
pub const ASYMPTOTIC_ORDER_SLACK: f64 = 0.5;

/// Why the runs cannot make a study.
#[derive(Debug, Error)]
pub enum MeshStudyError {
    /// Two to four meshes are needed.
    #[error("{meshes} meshes: a mesh study takes two to four")]
    Meshes {
        /// How many were given.
        meshes: usize,
    },
    /// The runs are not of the same particles.
    #[error(
        "mesh {label} holds {found} records of {particles} particles, mesh {first} {expected} of {first_particles}: a study pairs the same particles (whole runs of one seed)"
    )]
    Unpaired {
        /// The mesh that differs.
        label: String,
        /// Its records.
        found: usize,
        /// Its run's particles.
        particles: u64,
        /// The finest mesh.
        first: String,
        /// Its records.
        expected: usize,
        /// Its run's particles.
        first_particles: u64,
    },
    /// Particle indices or seeds differ between two meshes.
    #[error("mesh {label}: {what} differs from mesh {first}'s")]
    Mismatch {
        /// The mesh that differs.
        label: String,
        /// The finest mesh.
        first: String,
        /// What differs (seed, particle index k).
        what: String,
    },
    /// Two meshes with the same number of cells: no refinement ratio.
    #[error("meshes {a} and {b} both have {cells} cells: no refinement between them")]
    SameCells {
        /// One mesh.
        a: String,
        /// The other.
        b: String,
        /// Their cells.
        cells: u64,
    },
}

/// One mesh's run: a label (the case folder), its cells and its records.
#[derive(Debug)]
pub struct MeshRun<'a, L> {
    /// How the mesh is named in the tables.
    pub label: &'a str,
    /// Cells of the mesh.
    pub cells: u64,
    /// The whole run on it.
    pub output: &'a RunOutput<L>,
}

/// A mesh of the study, finest first.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Mesh {
    /// Its label.
    pub label: String,
    /// Its cells.
    pub cells: u64,
}

/// The change of an outcome's fraction from one mesh to the next finer one, paired.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Increment {
    /// Fraction on the finer mesh minus that on the coarser (ε of Celik et al. with the sign
    /// of fine − coarse: ε₂₁ = φ₂ − φ₁ is minus this for the pair 1–2).
    pub difference: f64,
    /// McNemar's standard error of the difference.
    pub paired_stderr: f64,
    /// Particles with the outcome on the finer mesh only.
    pub finer_only: u64,
    /// Particles with the outcome on the coarser mesh only.
    pub coarser_only: u64,
}

impl Increment {
    /// Whether the difference exceeds [`RESOLVED_SE`] paired standard errors.
    pub fn resolved(&self) -> bool {
        self.difference.abs() > RESOLVED_SE * self.paired_stderr
    }
}

/// One outcome across the meshes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OutcomeStudy {
    /// `deposited`, `deposited:<patch>`, `escaped`, `escaped:<patch>`, `suspended`, `failed`.
    pub outcome: String,
    /// Particles with it, per mesh (finest first).
    pub counts: Vec<u64>,
    /// Its fraction per mesh.
    pub values: Vec<f64>,
    /// Binomial standard error of each fraction.
    pub stderr: Vec<f64>,
    /// Increments from each mesh to the next finer one: `[0]` meshes 2 → 1, `[1]` 3 → 2, ...
    pub increments: Vec<Increment>,
    /// The estimate from the two or three finest meshes, if the procedure gave one.
    pub estimate: Option<GridConvergence>,
    /// Why not, if it did not.
    pub no_estimate: Option<String>,
    /// What the numbers say, in words.
    pub verdict: String,
}

impl OutcomeStudy {
    /// The estimate as an error bar: only where the procedure stands behind it
    /// ([`GridConvergence::holds`]: monotone on three meshes, or two with the assumed order)
    /// and every increment it read is resolved by the sample (beyond [`RESOLVED_SE`] paired
    /// standard errors). Elsewhere the verdict says why there is none.
    pub fn error_bar(&self) -> Option<&GridConvergence> {
        let used = self.values.len().min(3).saturating_sub(1);
        let resolved = self
            .increments
            .get(..used)
            .is_some_and(|i| i.iter().all(Increment::resolved));
        self.estimate.as_ref().filter(|e| e.holds() && resolved)
    }
}

/// A mesh study of one population (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MeshStudy {
    /// Particles of every run.
    pub particles: u64,
    /// Dimension d of h = (V/N)^{1/d}.
    pub dimension: u32,
    /// The formal order of the chain (solver and reconstruction), capping the order used.
    pub formal_order: f64,
    /// The meshes, finest first.
    pub meshes: Vec<Mesh>,
    /// Every outcome any mesh saw.
    pub outcomes: Vec<OutcomeStudy>,
}

/// The outcomes `fate` counts for: its class, and its class with the patch's name.
fn outcomes_of<L>(fate: &Fate, output: &RunOutput<L>) -> Vec<String> {
    let class = fate.label().to_string();
    match fate.patch() {
        Some(p) => {
            let name = output.patches.get(p).map_or_else(|| format!("patch{p}"), Clone::clone);
            vec![format!("{class}:{name}"), class]
        }
        None => vec![class],
    }
}

impl MeshStudy {
    /// The study of `runs` (any order; sorted finest first) in `dimension` dimensions with the
    /// chain's formal order `formal_order`.
    pub fn new<L>(runs: &[MeshRun<'_, L>], dimension: u32, formal_order: f64) -> Result<Self, MeshStudyError> {
        if !(2..=4).contains(&runs.len()) {
            return Err(MeshStudyError::Meshes { meshes: runs.len() });
        }
        let mut runs: Vec<&MeshRun<'_, L>> = runs.iter().collect();
        runs.sort_by_key(|r| std::cmp::Reverse(r.cells));
        let first = runs[0];
        for w in runs.windows(2) {
            if w[0].cells == w[1].cells {
                return Err(MeshStudyError::SameCells {
                    a: w[0].label.into(),
                    b: w[1].label.into(),
                    cells: w[0].cells,
                });
            }
        }
        for run in &runs[1..] {
            let (a, b) = (first.output, run.output);
            if a.records.len() != b.records.len() || a.particles != b.particles {
                return Err(MeshStudyError::Unpaired {
                    label: run.label.into(),
                    found: b.records.len(),
                    particles: b.particles,
                    first: first.label.into(),
                    expected: a.records.len(),
                    first_particles: a.particles,
                });
            }
            let mismatch = |what: String| MeshStudyError::Mismatch {
                label: run.label.into(),
                first: first.label.into(),
                what,
            };
            if a.seed != b.seed {
                return Err(mismatch(format!("seed {} (finest: {})", b.seed, a.seed)));
            }
            if let Some((x, y)) = a.records.iter().zip(&b.records).find(|(x, y)| x.index != y.index) {
                return Err(mismatch(format!("particle index {} (finest: {})", y.index, x.index)));
            }
        }
        // Per mesh, per particle, the outcomes it counts for.
        let per_mesh: Vec<Vec<Vec<String>>> = runs
            .iter()
            .map(|r| {
                r.output
                    .records
                    .iter()
                    .map(|rec| outcomes_of(&rec.fate, r.output))
                    .collect()
            })
            .collect();
        let names: BTreeSet<&String> = per_mesh.iter().flatten().flatten().collect();
        let n = first.output.records.len() as u64;
        let cells: Vec<f64> = runs.iter().map(|r| r.cells as f64).collect();
        let outcomes = names
            .into_iter()
            .map(|name| {
                let has: Vec<Vec<bool>> = per_mesh
                    .iter()
                    .map(|mesh| mesh.iter().map(|o| o.contains(name)).collect())
                    .collect();
                outcome(name, &has, n, &cells, dimension, formal_order)
            })
            .collect();
        Ok(Self {
            particles: n,
            dimension,
            formal_order,
            meshes: runs
                .iter()
                .map(|r| Mesh {
                    label: r.label.into(),
                    cells: r.cells,
                })
                .collect(),
            outcomes,
        })
    }

    /// The study of the outcome named `name` (`deposited`, `escaped:outlet1`, ...), if any
    /// mesh saw it.
    pub fn outcome(&self, name: &str) -> Option<&OutcomeStudy> {
        self.outcomes.iter().find(|o| o.outcome == name)
    }

    /// One row per outcome: `outcome`, per mesh k (1 finest) `cells_k`, `count_k`, `value_k`,
    /// `stderr_k`, per increment `diff_k(k+1)` (finer − coarser) and `paired_se_k(k+1)`, then
    /// `r21`, `r32`, `p`, `order_used`, `extrapolated`, `gci` (the band in the fraction's
    /// units), `gci_relative` (Celik's GCI_fine²¹), `convergence` and `verdict`; empty where
    /// the procedure gave no number.
    pub fn csv(&self) -> Result<Csv, OutputError> {
        Self::table(&[("", self)], None, None)
    }

    /// Several studies of the same meshes in one table: the rows of [`Self::csv`], each led by
    /// a column `key` holding its study's label (none if `key` is `None`), and only the
    /// outcome named `only` if given. Studies of different mesh counts do not fit one header
    /// (an [`OutputError`] naming the row).
    pub fn table(studies: &[(&str, &Self)], key: Option<&str>, only: Option<&str>) -> Result<Csv, OutputError> {
        let m = studies.first().map_or(0, |(_, s)| s.meshes.len());
        let mut header: Vec<String> = key.into_iter().map(String::from).collect();
        header.push("outcome".into());
        for k in 1..=m {
            header.extend(["cells", "count", "value", "stderr"].map(|c| format!("{c}_{k}")));
        }
        for k in 1..m {
            header.extend([format!("diff_{k}{}", k + 1), format!("paired_se_{k}{}", k + 1)]);
        }
        header.extend(
            [
                "r21",
                "r32",
                "p",
                "order_used",
                "extrapolated",
                "gci",
                "gci_relative",
                "convergence",
                "verdict",
            ]
            .map(String::from),
        );
        let mut csv = Csv::new(&header.iter().map(String::as_str).collect::<Vec<_>>());
        for (label, study) in studies {
            for o in study
                .outcomes
                .iter()
                .filter(|o| only.is_none_or(|name| o.outcome == name))
            {
                let mut row: Vec<String> = key.map(|_| (*label).to_string()).into_iter().collect();
                row.extend(study.row(o));
                csv.push(row)?;
            }
        }
        Ok(csv)
    }

    /// The fields of `o`'s row in [`Self::csv`].
    fn row(&self, o: &OutcomeStudy) -> Vec<String> {
        let opt = |v: Option<f64>| v.map_or(String::new(), |x| x.to_string());
        let mut row = vec![o.outcome.clone()];
        for (k, mesh) in self.meshes.iter().enumerate() {
            row.extend([
                mesh.cells.to_string(),
                o.counts[k].to_string(),
                o.values[k].to_string(),
                o.stderr[k].to_string(),
            ]);
        }
        for inc in &o.increments {
            row.extend([inc.difference.to_string(), inc.paired_stderr.to_string()]);
        }
        let e = o.estimate.as_ref();
        row.extend([
            opt(e.map(|e| e.r21)),
            opt(e.and_then(|e| e.r32)),
            opt(e.and_then(|e| e.p_apparent)),
            opt(e.map(|e| e.order_used)),
            opt(e.map(|e| e.extrapolated)),
            opt(e.map(|e| e.band)),
            opt(e.and_then(|e| e.gci_fine)),
            e.map_or(String::new(), |e| {
                serde_json::to_value(e.convergence)
                    .ok()
                    .and_then(|v| v.as_str().map(String::from))
                    .unwrap_or_default()
            }),
            o.verdict.clone(),
        ]);
        row
    }
}

/// The study of one outcome: `has[mesh][particle]`, meshes finest first with `cells`.
fn outcome(name: &str, has: &[Vec<bool>], n: u64, cells: &[f64], dimension: u32, formal: f64) -> OutcomeStudy {
    let counts: Vec<u64> = has.iter().map(|h| h.iter().filter(|&&x| x).count() as u64).collect();
    let values: Vec<f64> = counts.iter().map(|&k| fraction(k, n)).collect();
    let increments: Vec<Increment> = has
        .windows(2)
        .map(|w| {
            let pairing: Pairing = w[0].iter().copied().zip(w[1].iter().copied()).collect();
            let (finer_only, coarser_only) = (pairing.only_ours, pairing.only_peer);
            let paired = pairing.fates_or_zero();
            Increment {
                difference: paired.difference(),
                paired_stderr: paired.stderr(),
                finer_only,
                coarser_only,
            }
        })
        .collect();
    let used = values.len().min(3);
    let estimate = GridConvergence::from_cells(&values[..used], &cells[..used], dimension, formal);
    let verdict = verdict(&values, &increments[..used - 1], &estimate, formal);
    let (estimate, no_estimate) = match estimate {
        Ok(e) => (Some(e), None),
        Err(e) => (None, Some(e.to_string())),
    };
    OutcomeStudy {
        outcome: name.to_string(),
        stderr: counts.iter().map(|&k| stderr(k, n)).collect(),
        counts,
        values,
        increments,
        estimate,
        no_estimate,
        verdict,
    }
}

/// What the numbers of one outcome say (module docs, *Two kinds of error*): `increments` are
/// those the estimate used (finest first).
fn verdict(
    values: &[f64],
    increments: &[Increment],
    estimate: &Result<GridConvergence, GciError>,
    formal: f64,
) -> String {
    let e = match estimate {
        Ok(e) => e,
        Err(err) => return format!("no estimate: {err}"),
    };
    let listed: Vec<String> = increments
        .iter()
        .map(|i| format!("{:+.4} ± {:.4}", i.difference, i.paired_stderr))
        .collect();
    let increments_text = format!("increments (finer − coarser, ± paired se) {}", listed.join(", "));
    if increments.iter().all(|i| !i.resolved()) {
        return format!(
            "no mesh effect resolved: {increments_text} all within {RESOLVED_SE} paired se; the finest value {:.4} stands, its mesh error below this sample's resolution",
            values[0]
        );
    }
    if increments.iter().any(|i| !i.resolved()) {
        return format!(
            "order not resolved: {increments_text}, one within {RESOLVED_SE} paired se, so p is sampling noise; more particles or a wider refinement are needed (extrapolation {:.4} ± {:.4} is not an error bar)",
            e.extrapolated, e.band
        );
    }
    let estimate_text = format!(
        "extrapolated {:.4} ± {:.4} (GCI, F_s = {})",
        e.extrapolated, e.band, e.safety
    );
    match (e.convergence, e.p_apparent) {
        (Convergence::Assumed, _) => {
            format!("two meshes: formal order {formal} assumed; {increments_text}; {estimate_text}")
        }
        (Convergence::Monotone, Some(p)) if (p - formal).abs() <= ASYMPTOTIC_ORDER_SLACK => format!(
            "monotone, asymptotic: p = {p:.2} within {ASYMPTOTIC_ORDER_SLACK} of the formal {formal}; {increments_text}; {estimate_text}"
        ),
        (Convergence::Monotone, Some(p)) => format!(
            "monotone but pre-asymptotic: p = {p:.2} differs from the formal {formal} by more than {ASYMPTOTIC_ORDER_SLACK} (order used {:.2}); {increments_text}; {estimate_text}, a rough bar",
            e.order_used
        ),
        (Convergence::Oscillatory, _) => format!(
            "oscillatory: {increments_text}; no extrapolation holds, the values span {:.4}–{:.4}",
            values.iter().copied().fold(f64::INFINITY, f64::min),
            values.iter().copied().fold(f64::NEG_INFINITY, f64::max)
        ),
        (Convergence::Divergent, _) => format!(
            "increments grow under refinement: {increments_text}; not in the asymptotic range, a finer mesh is needed"
        ),
        (Convergence::Flat | Convergence::Monotone, _) => {
            format!("the two finest meshes agree exactly: {increments_text}")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `n` particles, the first `k[m]` of which have the outcome on mesh m (nested sets: every
    /// discordant particle moves the fraction the same way, so each increment's paired se is
    /// small against it).
    fn nested(k: &[usize], n: usize) -> Vec<Vec<bool>> {
        k.iter().map(|&k| (0..n).map(|i| i < k).collect()).collect()
    }

    /// Cells 8000, 1000, 125 in 3-D: r = 2 for both pairs. Fractions 0.10, 0.12, 0.16 (finest
    /// first): ε₃₂/ε₂₁ = 2 = r^p, so p = 1 exactly, monotone; capped at the formal 2 it stays
    /// 1, and Richardson's extrapolation is φ₁ + (φ₁ − φ₂)/(r^p − 1) = 0.08 with the band
    /// F_s |φ₁ − φ₂|/(r^p − 1) = 1.25 × 0.02 = 0.025 (Celik et al. 2008, eqs. 4 and 7).
    #[test]
    fn a_resolved_monotone_outcome_has_richardsons_bar() {
        let cells = [8000.0, 1000.0, 125.0];
        let o = outcome(
            "deposited",
            &nested(&[1000, 1200, 1600], 10_000),
            10_000,
            &cells,
            3,
            FORMAL_ORDER,
        );
        let bar = o.error_bar().expect("resolved and monotone");
        assert!((bar.p_apparent.unwrap() - 1.0).abs() < 1e-9, "{bar:?}");
        assert!((bar.extrapolated - 0.08).abs() < 1e-12, "{bar:?}");
        assert!((bar.band - 0.025).abs() < 1e-12, "{bar:?}");
    }

    /// The same values on 100 particles are not resolved by the sample (the 2 → 1 increment is
    /// 2 particles: 0.02 against a paired se of √(2 − 0.04)/100 = 0.014, 1.4 se), an
    /// oscillating sequence holds no bar (Celik et al.: no extrapolation), and neither has one.
    #[test]
    fn unresolved_or_oscillating_outcomes_have_no_bar() {
        let cells = [8000.0, 1000.0, 125.0];
        let small = outcome("deposited", &nested(&[10, 12, 16], 100), 100, &cells, 3, FORMAL_ORDER);
        assert!(small.estimate.is_some() && small.error_bar().is_none(), "{small:?}");
        let wavy = outcome(
            "deposited",
            &nested(&[1000, 1400, 1100], 10_000),
            10_000,
            &cells,
            3,
            FORMAL_ORDER,
        );
        assert_eq!(wavy.estimate.map(|e| e.convergence), Some(Convergence::Oscillatory));
        assert!(wavy.error_bar().is_none());
    }
}

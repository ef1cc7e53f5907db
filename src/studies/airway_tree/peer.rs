//! The tree against another tracker on the same particles (issue 37, item 4): the fates
//! OpenFOAM's kinematic cloud gives the particles of a [`super::track`] run
//! ([`crate::studies::peer`], `benches/peers/openfoam_tracker`), compared generation by
//! generation and particle by particle (`examples/openfoam_peer.rs --tree`).
//!
//! # Where a peer's particle went
//! The peer reports each particle's fate and, when it left the mesh, the patch and the point
//! where its barycentre met it; it keeps no path. So:
//! - a **deposit** counts for the generation of that point ([`Tree::classify`], the rule of our
//!   deposits), and the particle entered every generation down to it;
//! - an **escape** through a tube's outlet patch entered every generation down to that tube's;
//!   through any other patch (the inlet) only the first;
//! - a suspended or uninjected particle has no outcome and is left out.
//!
//! Our outcomes ([`TreeFate`], from the generation observer) use the path: a particle that
//! crossed into generation g + 1 and then deposited upstream, in g, entered g + 1 by ours and
//! not by the peer's rule. [`PeerComparison::returned`] counts such particles of ours, so the
//! difference the two rules can make is measured, not assumed.
//!
//! # Statistics
//! Per generation g the pairs are the particles both trackers finished and both saw enter g
//! (n_ent,g). With b (c) those of them deposited in g by us (by the peer) only,
//! ```math
//! DE_{ours} - DE_{peer} = \frac{b - c}{n_{ent,g}}, \qquad
//! \sigma = \frac{\sqrt{b + c - (b - c)^2/n_{ent,g}}}{n_{ent,g}}
//! ```
//! (McNemar's paired standard error, [`Pairing::difference`]). A particle one tracker deposits
//! upstream of g and the other lets into g is a discordant pair of the upstream generation and
//! absent from g's pairs; each tracker's own counts over its own finished particles
//! ([`PeerComparison::ours`], [`PeerComparison::peer`]) show what that leaves out.

use super::AirwayTreeError;
use super::study::{GenerationCounts, TreeFate, count, tree_fate};
use super::tree::Tree;
use crate::material::NeoHooke;
use crate::output::{Csv, Figure, Panel, Series};
use crate::population::RunOutput;
use crate::population::binomial::fraction;
use crate::population::peer::{Pairing, PeerFate, paired_with_peer};
use crate::tensor::Vec3;
use std::collections::HashMap;

/// Where the peer's particle `index` went (module docs); `None` if it has no outcome
/// (suspended or never injected).
pub fn peer_tree_fate(tree: &Tree, index: u64, fate: &PeerFate) -> Result<Option<TreeFate>, AirwayTreeError> {
    let bad = |reason: String| AirwayTreeError::Peer { index, reason };
    match fate.fate.as_str() {
        "deposited" => {
            let mut x = Vec3::zeros();
            for (c, text) in x.iter_mut().zip(&fate.x) {
                *c = text
                    .parse()
                    .map_err(|e| bad(format!("deposit point {:?}: {e}", fate.x)))?;
            }
            let generation = tree.classify(&x)?.generation;
            Ok(Some(TreeFate {
                deepest: generation,
                deposited: Some(generation),
            }))
        }
        "escaped" => {
            let deepest = tree
                .tubes()
                .iter()
                .find(|t| t.outlet.as_deref() == Some(fate.patch.as_str()))
                .map_or(tree.first_generation(), |t| t.generation);
            Ok(Some(TreeFate {
                deepest,
                deposited: None,
            }))
        }
        "suspended" | "not_injected" => Ok(None),
        other => Err(bad(format!("unknown fate `{other}`"))),
    }
}

/// One generation's pairs: the particles both trackers finished and saw enter it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PeerGeneration {
    /// The generation.
    pub generation: u8,
    /// Deposited in it by both, by us only, by the peer only, by neither.
    pub pairing: Pairing,
}

impl PeerGeneration {
    /// n_ent,g: the pairs.
    pub fn entered(&self) -> u64 {
        self.pairing.n()
    }

    /// Our DE_g over the pairs.
    pub fn de_ours(&self) -> f64 {
        fraction(self.pairing.both + self.pairing.only_ours, self.entered())
    }

    /// The peer's DE_g over the pairs.
    pub fn de_peer(&self) -> f64 {
        fraction(self.pairing.both + self.pairing.only_peer, self.entered())
    }

    /// DE_ours − DE_peer and its paired standard error (module docs).
    pub fn difference(&self) -> (f64, f64) {
        self.pairing.difference()
    }

    /// Whether |DE_ours − DE_peer| ≤ `sigmas` σ + `slack`; false without pairs.
    pub fn agrees(&self, sigmas: f64, slack: f64) -> bool {
        let (d, se) = self.difference();
        self.entered() > 0 && d.abs() <= sigmas * se + slack
    }
}

/// Our run against the peer's fates of the same particles.
#[derive(Debug, Clone, PartialEq)]
pub struct PeerComparison {
    /// Per generation, the pairs (first generation first).
    pub generations: Vec<PeerGeneration>,
    /// Our counts over our finished particles ([`super::by_generation`]).
    pub ours: Vec<GenerationCounts>,
    /// The peer's counts over its particles with an outcome.
    pub peer: Vec<GenerationCounts>,
    /// Particles finished by one tracker only (failed in ours, or suspended or uninjected in
    /// the peer): in neither tracker's pairs.
    pub unpaired: u64,
    /// Our deposited particles whose path entered a deeper generation than their deposit's
    /// (module docs).
    pub returned: u64,
}

/// Pair our run `ours` with the peer's fates `peer` of the same particles (every particle of
/// ours must have one), generation by generation (module docs).
pub fn against_peer(
    tree: &Tree,
    ours: &RunOutput<NeoHooke>,
    peer: &HashMap<u64, PeerFate>,
) -> Result<PeerComparison, AirwayTreeError> {
    let mut generations: Vec<PeerGeneration> = tree
        .generations()
        .map(|generation| PeerGeneration {
            generation,
            pairing: Pairing::default(),
        })
        .collect();
    let (mut our_outcomes, mut peer_outcomes) = (Vec::new(), Vec::new());
    let (mut unpaired, mut returned) = (0, 0);
    let pairs = paired_with_peer(&ours.records, peer).map_err(|e| AirwayTreeError::Peer {
        index: e.index,
        reason: "missing from the peer's fates".into(),
    })?;
    for (record, fate) in pairs {
        let (a, b) = (tree_fate(tree, record)?, peer_tree_fate(tree, record.index, fate)?);
        our_outcomes.extend(a);
        peer_outcomes.extend(b);
        let (Some(a), Some(b)) = (a, b) else {
            unpaired += u64::from(a.is_some() || b.is_some());
            continue;
        };
        returned += u64::from(a.deposited.is_some_and(|g| a.deepest > g));
        for row in &mut generations {
            let g = row.generation;
            if a.deepest >= g && b.deepest >= g {
                row.pairing.add(a.deposited == Some(g), b.deposited == Some(g));
            }
        }
    }
    Ok(PeerComparison {
        generations,
        ours: count(tree, our_outcomes),
        peer: count(tree, peer_outcomes),
        unpaired,
        returned,
    })
}

/// `generation,n_entered,de_ours,de_openfoam,se_combined,only_ours,only_openfoam` (issue 37):
/// per generation the pairs, both DEs over them, the paired standard error of their
/// difference and the discordant particles ([`PeerGeneration`]).
pub fn openfoam_table(rows: &[PeerGeneration]) -> Result<Csv, AirwayTreeError> {
    let mut csv = Csv::new(&[
        "generation",
        "n_entered",
        "de_ours",
        "de_openfoam",
        "se_combined",
        "only_ours",
        "only_openfoam",
    ]);
    for r in rows {
        csv.push(vec![
            r.generation.to_string(),
            r.entered().to_string(),
            format!("{:.5}", r.de_ours()),
            format!("{:.5}", r.de_peer()),
            format!("{:.5}", r.difference().1),
            r.pairing.only_ours.to_string(),
            r.pairing.only_peer.to_string(),
        ])?;
    }
    Ok(csv)
}

/// DE_g of both trackers against the generation on the same particles, with the band
/// DE_peer ± (`sigmas` σ + `slack`) that ours must lie in.
pub fn openfoam_figure(rows: &[PeerGeneration], title: &str, sigmas: f64, slack: f64) -> Figure {
    let g = |r: &PeerGeneration| f64::from(r.generation);
    let band = |s: f64| -> Vec<(f64, f64)> {
        rows.iter()
            .map(|r| (g(r), r.de_peer() + s * (sigmas * r.difference().1 + slack)))
            .collect()
    };
    let top = band(1.0).iter().map(|p| p.1).fold(0.0, f64::max);
    let (lo, hi) = rows.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
        (lo.min(g(r)), hi.max(g(r)))
    });
    let mut panel = Panel::new(title, "generation", "DE of the particles entering")
        .with(Series::points(
            "OpenFOAM's tracker",
            rows.iter().map(|r| (g(r), r.de_peer())).collect(),
            1,
        ))
        .with(Series::line(
            format!("OpenFOAM ± ({sigmas} se + {slack})"),
            band(1.0),
            1,
        ))
        .with(Series::line("", band(-1.0), 1))
        .with(Series::points(
            "pseudorigid",
            rows.iter().map(|r| (g(r), r.de_ours())).collect(),
            2,
        ));
    if lo <= hi {
        panel = panel.with_ranges((lo - 0.3, hi + 0.3), (0.0, (1.1 * top).max(1e-3)));
    }
    Figure::single(panel)
}

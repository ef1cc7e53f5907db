//! The tree's centrelines and the generation classifier.
//!
//! `cases/airway-tree/geometry.py` writes `centrelines.json` beside the surface it meshes: each
//! tube's centreline segment (from its start, the inlet plane or its parent's branch point, to
//! its own branch point or outlet cap), its radius, its generation, and the distance along its
//! axis where it begins as a tube of its own (its *entry*); each bifurcation's branch point and
//! rounded carina apex. This module reads that file; nothing here re-derives the geometry.
//!
//! # The classification rule
//! A point belongs to the tube whose centreline segment is nearest (Euclidean distance to the
//! segment, its axial coordinate clamped to the segment; ties to the first tube in the file's
//! depth-first order). If that tube is a daughter (generation g + 1 > 3) and the point's axial
//! coordinate t along it, measured from the branch point, is below the tube's entry
//! ```math
//! t_{entry} = (x_{apex} - x_B)\cdot d + R_d ,
//! ```
//! the point lies in the *bifurcation zone* of its parent, generation g: the joint, the outer
//! bend and the carina up to one daughter radius R_d past the rounded apex, measured along the
//! daughter's axis d. So a deposit on the carina of generation g's bifurcation counts as
//! generation g, and a particle *enters* generation g + 1 when it crosses the plane normal to
//! d at t_entry (the inlet plane of the G-(g+1) tube). The G3 tube begins at the inlet plane
//! (entry 0). Generation g of a deposit is then "tube g or the bifurcation at its end"; the
//! eight G6 tubes end at the outlets and have no bifurcation zone.
//!
//! The rule needs only the centrelines, so it holds for any point, inside the mesh or not; on
//! the wall the nearest centreline is that of the tube the wall belongs to wherever the wall is
//! closer to its own axis than to any other (everywhere but within the joints, where the
//! parent's and the daughters' segments meet and either answer gives generation g).

use crate::tensor::Vec3;
use serde::Deserialize;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Failures reading or using a tree description.
#[derive(Debug, Error)]
pub enum TreeError {
    /// The file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// The file is not a tree description.
    #[error("{path}: {source}")]
    Json {
        /// The file.
        path: PathBuf,
        /// The error.
        source: serde_json::Error,
    },
    /// The description is inconsistent.
    #[error("tree description: {reason}")]
    Invalid {
        /// What is wrong, with the numbers.
        reason: String,
    },
    /// A point to classify is not finite.
    #[error("cannot classify the point {x:?}: not finite")]
    NonFinite {
        /// The point.
        x: [f64; 3],
    },
}

/// One tube of the tree.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct Tube {
    /// Index in the file (depth-first order; the G3 tube is 0).
    pub id: usize,
    /// Weibel generation (3 for the first tube).
    pub generation: u8,
    /// The parent tube (`None` for the first).
    pub parent: Option<usize>,
    /// Start of the centreline (m): the inlet plane's centre, or the parent's branch point.
    pub start: [f64; 3],
    /// End of the centreline (m): its branch point, or the centre of its outlet cap.
    pub end: [f64; 3],
    /// Radius (m) past the taper.
    pub radius: f64,
    /// Radius at the start (the parent's; the taper's start).
    pub start_radius: f64,
    /// Where along its axis, from its start, it begins as a tube of its own (m; module docs).
    pub entry: f64,
    /// Its outlet patch, for the last generation.
    pub outlet: Option<String>,
}

impl Tube {
    fn start(&self) -> Vec3 {
        Vec3::from(self.start)
    }

    /// Length of the centreline (m).
    pub fn length(&self) -> f64 {
        (Vec3::from(self.end) - self.start()).norm()
    }

    /// Unit axis, start to end.
    pub fn direction(&self) -> Vec3 {
        (Vec3::from(self.end) - self.start()) / self.length()
    }

    /// The point at axial coordinate `t` (m) on the centreline.
    pub fn point(&self, t: f64) -> Vec3 {
        self.start() + t * self.direction()
    }
}

/// One bifurcation: the end of a tube of generation g that splits into two of generation g + 1.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct Bifurcation {
    /// Generation of the parent tube.
    pub generation: u8,
    /// The parent tube.
    pub tube: usize,
    /// Branch point (m): where the parent's centreline ends and the daughters' begin.
    pub branch_point: [f64; 3],
    /// Unit normal of the bifurcation plane, within it (the daughters go along
    /// cos θ e ± sin θ n).
    pub normal: [f64; 3],
    /// The rounded carina apex (m), on the parent's axis.
    pub apex: [f64; 3],
    /// Its radius of curvature in the bifurcation plane (m).
    pub apex_radius: f64,
}

/// Where a point lies: a tube, or the bifurcation zone at a tube's end.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Part {
    /// Inside the tube proper (past its entry).
    Tube,
    /// In the bifurcation zone at the tube's end (joint, outer bend, carina).
    Bifurcation,
}

/// The classification of a point ([`Tree::classify`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Location {
    /// The generation the point counts for: the tube's, or the parent's in a bifurcation zone.
    pub generation: u8,
    /// Tube or bifurcation zone.
    pub part: Part,
    /// The tube (for a bifurcation zone: the parent tube, whose end it is).
    pub tube: usize,
}

#[derive(Deserialize)]
struct File {
    variant: String,
    tubes: Vec<Tube>,
    bifurcations: Vec<Bifurcation>,
}

/// The tree of `cases/airway-tree` (module docs): its tubes and bifurcations.
#[derive(Debug, Clone, PartialEq)]
pub struct Tree {
    variant: String,
    tubes: Vec<Tube>,
    bifurcations: Vec<Bifurcation>,
}

fn invalid(reason: String) -> TreeError {
    TreeError::Invalid { reason }
}

impl Tree {
    /// Read `centrelines.json` (written by `cases/airway-tree/geometry.py`).
    pub fn read(path: impl AsRef<Path>) -> Result<Self, TreeError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|source| TreeError::Io {
            path: path.into(),
            source,
        })?;
        let file: File = serde_json::from_str(&text).map_err(|source| TreeError::Json {
            path: path.into(),
            source,
        })?;
        Self::new(file.variant, file.tubes, file.bifurcations)
    }

    /// A tree from its parts, checked: tubes indexed by `id` in order, parents before children,
    /// each daughter one generation below its parent and starting at its end, finite positive
    /// lengths and radii, entries within the tube, every non-terminal tube with a bifurcation.
    pub fn new(variant: String, tubes: Vec<Tube>, bifurcations: Vec<Bifurcation>) -> Result<Self, TreeError> {
        if tubes.is_empty() {
            return Err(invalid("no tubes".into()));
        }
        for (i, t) in tubes.iter().enumerate() {
            let finite = t.start.iter().chain(&t.end).all(|c| c.is_finite());
            let length = t.length();
            // Comparisons with NaN are false, so a NaN length or radius fails here too.
            let ok = t.id == i && finite && length > 0.0 && t.radius > 0.0 && t.start_radius >= t.radius;
            if !ok {
                return Err(invalid(format!(
                    "tube {i}: id {}, start {:?}, end {:?}, length {length:e}, radius {:e}, start radius {:e}",
                    t.id, t.start, t.end, t.radius, t.start_radius
                )));
            }
            if !(0.0..length).contains(&t.entry) {
                return Err(invalid(format!(
                    "tube {i}: entry {:e} outside [0, {length:e})",
                    t.entry
                )));
            }
            match t.parent {
                None if i != 0 => return Err(invalid(format!("tube {i} has no parent"))),
                Some(p) if p >= i => return Err(invalid(format!("tube {i}: parent {p} comes after it"))),
                Some(p) => {
                    let parent = &tubes[p];
                    let gap = (Vec3::from(parent.end) - t.start()).norm();
                    if t.generation != parent.generation + 1 || gap > 1e-9 * parent.length() {
                        return Err(invalid(format!(
                            "tube {i}: generation {} under parent {p} of generation {}, {gap:e} m from its end",
                            t.generation, parent.generation
                        )));
                    }
                }
                None => {}
            }
        }
        for (k, b) in bifurcations.iter().enumerate() {
            let ok = tubes.get(b.tube).is_some_and(|t| t.generation == b.generation);
            if !ok {
                return Err(invalid(format!(
                    "bifurcation {k}: tube {} of generation {}",
                    b.tube, b.generation
                )));
            }
        }
        for t in &tubes {
            let children = tubes.iter().filter(|c| c.parent == Some(t.id)).count();
            let has_bifurcation = bifurcations.iter().any(|b| b.tube == t.id);
            if !((children == 0 && !has_bifurcation) || (children == 2 && has_bifurcation)) {
                return Err(invalid(format!(
                    "tube {}: {children} daughters, bifurcation listed: {has_bifurcation}",
                    t.id
                )));
            }
        }
        Ok(Self {
            variant,
            tubes,
            bifurcations,
        })
    }

    /// `planar` or `rotated`.
    pub fn variant(&self) -> &str {
        &self.variant
    }

    /// The tubes, depth-first (the G3 tube first).
    pub fn tubes(&self) -> &[Tube] {
        &self.tubes
    }

    /// The bifurcations.
    pub fn bifurcations(&self) -> &[Bifurcation] {
        &self.bifurcations
    }

    /// The first generation (the inlet tube's).
    pub fn first_generation(&self) -> u8 {
        self.tubes[0].generation
    }

    /// The last generation (the outlet tubes').
    pub fn last_generation(&self) -> u8 {
        self.tubes
            .iter()
            .map(|t| t.generation)
            .max()
            .unwrap_or(self.tubes[0].generation)
    }

    /// Generations first to last.
    pub fn generations(&self) -> std::ops::RangeInclusive<u8> {
        self.first_generation()..=self.last_generation()
    }

    /// The generation, tube or bifurcation zone of point `x` (module docs: nearest centreline
    /// segment, then the zone rule).
    pub fn classify(&self, x: &Vec3) -> Result<Location, TreeError> {
        if !x.iter().all(|c| c.is_finite()) {
            return Err(TreeError::NonFinite { x: [x[0], x[1], x[2]] });
        }
        let mut best: Option<(f64, usize, f64)> = None;
        for (i, tube) in self.tubes.iter().enumerate() {
            let t = (x - tube.start()).dot(&tube.direction());
            let distance = (x - tube.point(t.clamp(0.0, tube.length()))).norm();
            if best.is_none_or(|(d, _, _)| distance < d) {
                best = Some((distance, i, t));
            }
        }
        let (_, i, t) = best.expect("a tree has at least one tube (Tree::new)");
        let tube = &self.tubes[i];
        Ok(match tube.parent {
            Some(parent) if t < tube.entry => Location {
                generation: tube.generation - 1,
                part: Part::Bifurcation,
                tube: parent,
            },
            _ => Location {
                generation: tube.generation,
                part: Part::Tube,
                tube: i,
            },
        })
    }

    /// What the classification depends on, for the configuration hash of observed runs.
    pub fn fingerprint(&self) -> String {
        let tubes: Vec<String> = self
            .tubes
            .iter()
            .map(|t| format!("{}:{:?}-{:?} entry {:e}", t.generation, t.start, t.end, t.entry))
            .collect();
        format!("tree {} [{}]", self.variant, tubes.join("; "))
    }
}

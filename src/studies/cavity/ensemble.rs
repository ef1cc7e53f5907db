//! Ensembles over orientations and field variants, and their outcome fractions.

use super::*;

/// Initial orientations of an ensemble: the identity (the nominal release) and `count − 1`
/// rotations that carry the shape's symmetry axis (e_x for prolates, e_z for oblates) to
/// directions spread evenly over a hemisphere (a Fibonacci lattice; axis and −axis give the
/// same ellipsoid), each by the smallest rotation. A triaxial shape has no symmetry axis: its
/// first axis r₁ is spread, and the rotation about it is the smallest one, not sampled; a
/// sphere looks the same in every orientation.
pub fn orientations(shape: Shape, count: usize) -> Vec<Mat3> {
    let axis = match shape {
        Shape::Oblate(_) => Vec3::z(),
        Shape::Sphere | Shape::Prolate(_) | Shape::Triaxial { .. } => Vec3::x(),
    };
    let others = count.saturating_sub(1);
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut out = Vec::with_capacity(count);
    if count > 0 {
        out.push(Mat3::identity());
    }
    for k in 0..others {
        let z = 1.0 - (k as f64 + 0.5) / others as f64;
        let rho = (1.0 - z * z).sqrt();
        let phi = golden * k as f64;
        let target = Vec3::new(rho * phi.cos(), rho * phi.sin(), z);
        let turn = nalgebra::Rotation3::rotation_between(&axis, &target)
            .unwrap_or_else(|| nalgebra::Rotation3::from_axis_angle(&Vec3::y_axis(), std::f64::consts::PI));
        out.push(turn.into_inner());
    }
    out
}

/// One ensemble member: the variant and orientation it was run in, and its run (or the error
/// that stopped it).
#[derive(Debug, Clone)]
pub struct Member {
    /// Field variant.
    pub variant: Variant,
    /// Index into [`orientations`] (0: nominal).
    pub orientation: usize,
    /// The run, or why there is none.
    pub run: Result<CavityRun, MemberError>,
}

/// Events (exit or deposition) after this time (s) are flagged as sensitive to the paper's
/// 100 s tracking horizon.
pub const LATE_EVENT: f64 = 95.0;

/// Outcome fractions per (shape, Ca) over the members given:
/// `shape,ca,shape_model,runs,failed,exited,deposited,suspended,late_events,deposit_walls,
/// nominal_outcome` where the fractions are of the runs that finished, `late_events` the
/// fraction of them with an event after [`LATE_EVENT`], `deposit_walls` the walls hit with
/// counts (`x1:5;bottom:2`) and `nominal_outcome` the outcome of the nominal member
/// (orientation 0, lid +x, scale 1) if it was run.
pub fn outcome_fraction_table(members: &[Member]) -> Result<crate::output::Csv, crate::output::OutputError> {
    let mut csv = crate::output::Csv::new(&[
        "shape",
        "ca",
        "shape_model",
        "runs",
        "failed",
        "exited",
        "deposited",
        "suspended",
        "late_events",
        "deposit_walls",
        "nominal_outcome",
    ]);
    let mut keys: Vec<(String, Option<f64>)> = Vec::new();
    let key = |m: &Member| -> Option<(String, Option<f64>)> {
        m.run.as_ref().ok().map(|r| (r.release.shape.label(), r.release.ca()))
    };
    for m in members {
        if let Some(k) = key(m)
            && !keys.contains(&k)
        {
            keys.push(k);
        }
    }
    for (shape, ca) in keys {
        let group: Vec<&Member> = members
            .iter()
            .filter(|m| key(m).as_ref() == Some(&(shape.clone(), ca)))
            .collect();
        // A run that failed as a particle (`CavityFate::Failed`) counts as failed, like one whose
        // set-up failed; the fractions are over the runs that finished.
        let runs: Vec<&CavityRun> = group
            .iter()
            .filter_map(|m| m.run.as_ref().ok())
            .filter(|r| !matches!(r.outcome(), CavityFate::Failed { .. }))
            .collect();
        let n = runs.len() as f64;
        // No finished run (every member failed): the fractions are empty cells, not 0/0.
        let frac = |f: &dyn Fn(&CavityRun) -> bool| match runs.is_empty() {
            true => String::new(),
            false => format!("{:.3}", runs.iter().filter(|r| f(r)).count() as f64 / n),
        };
        let mut walls: Vec<(&str, usize)> = Vec::new();
        for r in &runs {
            if let CavityFate::Deposited { wall, .. } = r.outcome() {
                match walls.iter_mut().find(|(w, _)| *w == wall) {
                    Some((_, c)) => *c += 1,
                    None => walls.push((wall, 1)),
                }
            }
        }
        let nominal = group
            .iter()
            .find(|m| m.orientation == 0 && m.variant == Variant::default())
            .and_then(|m| m.run.as_ref().ok())
            .map(|r| outcome_label(r.outcome()))
            .unwrap_or_default();
        let shape_model = group
            .iter()
            .find_map(|m| m.run.as_ref().ok())
            .map(|r| r.shape_model.label())
            .unwrap_or_default();
        csv.push(vec![
            shape,
            ca.map(|c| c.to_string()).unwrap_or_default(),
            shape_model.into(),
            group.len().to_string(),
            (group.len() - runs.len()).to_string(),
            frac(&|r| matches!(r.outcome(), CavityFate::Exited { .. })),
            frac(&|r| matches!(r.outcome(), CavityFate::Deposited { .. })),
            frac(&|r| matches!(r.outcome(), CavityFate::Suspended)),
            frac(&|r| r.outcome().event_time().is_some_and(|t| t > LATE_EVENT)),
            walls
                .iter()
                .map(|(w, c)| format!("{w}:{c}"))
                .collect::<Vec<_>>()
                .join(";"),
            nominal,
        ])?;
    }
    Ok(csv)
}

/// Per-member table: `mirrored,scale,orientation,error` followed by the [`outcome_table`]
/// columns (empty on error).
pub fn member_table(members: &[Member]) -> Result<crate::output::Csv, crate::output::OutputError> {
    let mut header = vec!["mirrored", "scale", "orientation", "error"];
    let inner = outcome_header();
    header.extend(&inner);
    let mut csv = crate::output::Csv::new(&header);
    let limits = Thresholds::default();
    for m in members {
        let mut cells = vec![
            m.variant.mirrored.to_string(),
            m.variant.scale.to_string(),
            m.orientation.to_string(),
        ];
        match &m.run {
            Ok(run) => {
                cells.push(String::new());
                cells.extend(outcome_cells(run, &limits));
            }
            Err(e) => {
                cells.push(e.to_string().replace([',', '"', '\n'], " "));
                cells.extend(inner.iter().map(|_| String::new()));
            }
        }
        csv.push(cells)?;
    }
    Ok(csv)
}

/// The label of `outcome`, a deposit with its wall (`deposited:x1`).
fn outcome_label(outcome: CavityFate<'_>) -> String {
    match outcome {
        CavityFate::Deposited { wall, .. } => format!("deposited:{wall}"),
        other => other.label().into(),
    }
}

/// An ensemble over the set-up's uncertainties (paper §6.3): every release in every field
/// variant and in `orientations` initial orientations ([`orientations`]), tracked for `t_max`
/// seconds at tolerance `tol` with barycentre contact, the path kept at the end only.
///
/// [`Ensemble::run`] runs it in a [`Cavity`] (its particle model, shape model, scheme and force
/// terms; its own variant is replaced by each of `variants`).
#[derive(Debug, Clone, PartialEq)]
pub struct Ensemble {
    /// The releases (shape, softness).
    pub releases: Vec<Launch>,
    /// The field variants, each one run of every release.
    pub variants: Vec<Variant>,
    /// Initial orientations per release (1: the nominal release only).
    pub orientations: usize,
    /// Tracking horizon t_max (s).
    pub t_max: f64,
    /// Tolerance of the integrator.
    pub tol: f64,
    /// Where to checkpoint: each population (variant `i`, shape model `m`) runs in
    /// `checkpoints/variant-<i>-<m>` ([`crate::population::run_in_dir`]) and resumes from what
    /// is there, so a killed ensemble continues where it stopped and gives the same members.
    /// `None`: in memory.
    pub checkpoints: Option<std::path::PathBuf>,
}

impl Ensemble {
    /// Run the ensemble in `cavity`. Each variant's releases are one population of the runner
    /// per shape model ([`crate::population`]; particle k is the k-th (release, orientation)
    /// pair of that model, in the order given, and its fate is read as a [`CavityFate`]), so
    /// they run in parallel and a failed particle is kept as its outcome. A member whose
    /// release could not be built is kept as its [`MemberError`], so one failure does not hide
    /// the rest of the ensemble.
    ///
    /// # Errors
    /// A variant the field cannot take, a failed population run or its checkpoints.
    pub fn run<L, D>(&self, cavity: &Cavity<'_, L, D>) -> Result<Vec<Member>, StudyError>
    where
        L: LawFactory + Clone,
        L::Law: Releasable,
        D: DragModel + Clone,
    {
        let options = crate::population::RunOptions::default().quiet();
        let tracking = Tracking {
            contact: Contact::Barycentre,
            t_max: self.t_max,
            tol: self.tol,
            dt_out: self.t_max,
        };
        let mut members = Vec::new();
        for (i, variant) in self.variants.iter().enumerate() {
            let cavity = cavity.clone().with_variant(*variant)?;
            // (release, orientation index, turn) in the ensemble's order.
            let jobs: Vec<(Launch, usize, Mat3)> = self
                .releases
                .iter()
                .flat_map(|r| {
                    orientations(r.shape, self.orientations)
                        .into_iter()
                        .enumerate()
                        .map(move |(k, turn)| (*r, k, turn))
                })
                .collect();
            let mut runs: Vec<Option<Result<CavityRun, MemberError>>> = vec![None; jobs.len()];
            for model in [ShapeModel::Inertialess, ShapeModel::Inertial] {
                let mine: Vec<usize> = (0..jobs.len())
                    .filter(|&j| cavity.model_of(&jobs[j].0) == model)
                    .collect();
                if mine.is_empty() {
                    continue;
                }
                let pairs: Vec<(Launch, Mat3)> = mine.iter().map(|&j| (jobs[j].0, jobs[j].2)).collect();
                let folder = self
                    .checkpoints
                    .as_ref()
                    .map(|d| d.join(format!("variant-{i}-{}", model.label())));
                let out = cavity.run_with(model, &pairs, &tracking, &options, folder.as_deref())?;
                for (j, run) in mine.into_iter().zip(out) {
                    runs[j] = Some(run);
                }
            }
            members.extend(jobs.iter().zip(runs).map(|((_, k, _), run)| Member {
                variant: *variant,
                orientation: *k,
                run: run.expect("every member belongs to one shape model"),
            }));
        }
        Ok(members)
    }
}

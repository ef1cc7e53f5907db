//! The transient field of one inhalation ([`Breath`], module docs of [`super`]: Tracking) and
//! its checks: the quasi-steady breath written from the steady case, the flow rates the solver
//! passed, and a level's distance from the scaled steady field.

use super::Waveform;
use crate::contact::MeshBoundary;
use crate::flow::openfoam::{BlendedFlow, Cycle, FoamCase, FoamError, Precision, TransientFlow};
use crate::output::Csv;
use crate::studies::bifurcation::BifurcationError;
use crate::studies::bifurcation::setup::{Airway, inlet_velocity};
use std::f64::consts::PI;
use std::path::Path;

/// The transient field of one inhalation and its boundary.
#[derive(Debug)]
pub struct Breath {
    pub(super) flow: TransientFlow<BlendedFlow>,
    pub(super) boundary: MeshBoundary,
    pub(super) waveform: Waveform,
}

impl Breath {
    /// The levels of the case in `dir` from t = 0 to the end of `waveform`'s inhalation (made
    /// by `cases/bifurcation-breathing/Allrun`), blended as the steady field is.
    pub fn open(dir: impl AsRef<Path>, waveform: Waveform) -> Result<Self, FoamError> {
        let case = FoamCase::open(dir)?;
        let end = waveform.duration();
        let times: Vec<f64> = case
            .times()
            .into_iter()
            .filter(|&t| (0.0..=end * (1.0 + 1e-9)).contains(&t))
            .collect();
        if times.len() < 2 {
            return Err(FoamError::Field {
                path: "(time directories)".into(),
                reason: format!("a breath needs at least two levels in [0, {end}], the case has {times:?}"),
            });
        }
        let flow = TransientFlow::<BlendedFlow>::open(case, &times, Cycle::Once, Precision::F64)?;
        let boundary = MeshBoundary::new(flow.mesh())?;
        Ok(Self {
            flow,
            boundary,
            waveform,
        })
    }

    /// The window ends of a run: 0, every level inside the inhalation, and its end. Not the
    /// command's equal windows ([`crate::flow::openfoam::window_ends`]) on purpose: a window
    /// ends on a level's own time, as its directory names it, so each holds exactly the two
    /// levels around it; a multiple k·Δt of the spacing differs from a level's time in the last
    /// bits, and a window ending just past a level holds a third.
    pub fn windows(&self) -> Vec<f64> {
        let end = self.waveform.duration();
        let mut w = vec![0.0];
        w.extend(
            self.flow
                .levels()
                .iter()
                .copied()
                .filter(|&t| t > 0.0 && t < end * (1.0 - 1e-9)),
        );
        w.push(end);
        w
    }

    /// The field.
    pub fn flow(&self) -> &TransientFlow<BlendedFlow> {
        &self.flow
    }

    /// The field, to slide its window.
    pub fn flow_mut(&mut self) -> &mut TransientFlow<BlendedFlow> {
        &mut self.flow
    }

    /// Wall and exits of the case.
    pub fn boundary(&self) -> &MeshBoundary {
        &self.boundary
    }

    /// The inhalation.
    pub fn waveform(&self) -> Waveform {
        self.waveform
    }
}

/// Write a quasi-steady breath into `out` (replaced): the mesh of the steady case `steady`
/// (its `constant/polyMesh`, files copied as they are) and at each of `times` its last level
/// scaled by U_in(t)/U, `waveform`'s. It is the field of the limit α → 0 at fixed Re (the
/// shape of the flow never changes, only its magnitude), the case of the snapshot test and a
/// reference for what the Reynolds number's change does.
pub fn write_quasi_steady(
    steady: &Path,
    out: &Path,
    waveform: Waveform,
    times: &[f64],
) -> Result<(), BifurcationError> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| crate::output::OutputError::Io { path, source }
    };
    let case = FoamCase::open(steady)?;
    let last = *case.times().last().ok_or_else(|| FoamError::Field {
        path: steady.display().to_string(),
        reason: "the steady case has no time directory".into(),
    })?;
    let field = case.read_field(last, "U", 3)?;
    let _ = std::fs::remove_dir_all(out);
    let mesh_dir = out.join("constant/polyMesh");
    std::fs::create_dir_all(&mesh_dir).map_err(io(&mesh_dir))?;
    let source = steady.join("constant/polyMesh");
    for entry in std::fs::read_dir(&source).map_err(io(&source))? {
        let entry = entry.map_err(io(&source))?;
        let _ = std::fs::copy(entry.path(), mesh_dir.join(entry.file_name())).map_err(io(&entry.path()))?;
    }
    let mesh = case.mesh();
    for &t in times {
        let s = waveform.scale(t);
        let mut text = String::from(
            "FoamFile { version 2.0; format ascii; class volVectorField; object U; }\ndimensions [0 1 -1 0 0 0 0];\n",
        );
        let list = |values: &[f64]| {
            let mut l = format!("nonuniform List<vector> {}\n(\n", values.len() / 3);
            for v in values.chunks(3) {
                l.push_str(&format!("({:e} {:e} {:e})\n", s * v[0], s * v[1], s * v[2]));
            }
            l.push(')');
            l
        };
        text.push_str(&format!(
            "internalField {};\nboundaryField\n{{\n",
            list(&field.internal)
        ));
        let first_boundary = mesh.n_internal_faces();
        for patch in mesh.patches() {
            let from = 3 * (patch.start - first_boundary);
            let values = &field.boundary[from..from + 3 * patch.size];
            let kind = if patch.kind == "wall" {
                "fixedValue"
            } else {
                "calculated"
            };
            text.push_str(&format!(
                "    {} {{ type {kind}; value {}; }}\n",
                patch.name,
                list(values)
            ));
        }
        text.push_str("}\n");
        let dir = out.join(format!("{t}"));
        std::fs::create_dir_all(&dir).map_err(io(&dir))?;
        crate::output::write_atomic(dir.join("U"), text.as_bytes())?;
    }
    Ok(())
}

/// The net volume flux of each open patch at every step of the case in `dir`, from its
/// `postProcessing/flowRate*/0/surfaceFieldValue.dat` (the Allrun's function objects:
/// `flowRates` the inlet, `flowRateOutlet1`, `flowRateOutlet2`), against the flux
/// prescribed by `waveform` through the inlet of `airway`'s mesh. Columns
/// `t,q_prescribed,q_inlet,q_outlet1,q_outlet2,inlet_error,imbalance`: q in m³/s, positive
/// into the airway at the inlet and out of it at the outlets; `inlet_error` =
/// (q_inlet − q_prescribed)/max q_prescribed, `imbalance` = (q_inlet − q_outlet1 − q_outlet2)/
/// max q_prescribed.
pub fn flow_rate_table(dir: &Path, airway: &Airway, waveform: Waveform) -> Result<Csv, BifurcationError> {
    let read = |name: &str| -> Result<Vec<(f64, f64)>, BifurcationError> {
        let path = dir.join(format!("postProcessing/{name}/0/surfaceFieldValue.dat"));
        let text = std::fs::read_to_string(&path).map_err(|source| crate::output::OutputError::Io {
            path: path.clone(),
            source,
        })?;
        Ok(text
            .lines()
            .filter(|l| !l.starts_with('#'))
            .filter_map(|l| {
                let mut w = l.split_whitespace().map(str::parse::<f64>);
                match (w.next(), w.next()) {
                    (Some(Ok(t)), Some(Ok(q))) => Some((t, q)),
                    _ => None,
                }
            })
            .collect())
    };
    let (inlet, out1, out2) = (read("flowRates")?, read("flowRateOutlet1")?, read("flowRateOutlet2")?);
    let mesh = airway.flow().cellwise().mesh();
    let area: f64 = mesh
        .patches()
        .iter()
        .filter(|p| p.name == "inlet")
        .flat_map(|p| p.start..p.start + p.size)
        .map(|f| mesh.face_areas()[f].norm())
        .sum();
    let q_max = inlet_velocity() * 0.5 * PI * area;
    let mut csv = Csv::new(&[
        "t",
        "q_prescribed",
        "q_inlet",
        "q_outlet1",
        "q_outlet2",
        "inlet_error",
        "imbalance",
    ]);
    for ((&(t, qi), &(t1, q1)), &(t2, q2)) in inlet.iter().zip(&out1).zip(&out2) {
        if t1 != t || t2 != t {
            continue;
        }
        let q = inlet_velocity() * waveform.scale(t) * area;
        // OpenFOAM's flux is positive out of the domain: the inlet's is negative.
        let qi = -qi;
        csv.push(vec![
            format!("{t}"),
            format!("{q:.6e}"),
            format!("{qi:.6e}"),
            format!("{q1:.6e}"),
            format!("{q2:.6e}"),
            format!("{:.3e}", (qi - q) / q_max),
            format!("{:.3e}", (qi - q1 - q2) / q_max),
        ])?;
    }
    Ok(csv)
}

/// How far level `t` of the case `a` is from the last level of the steady case `b` scaled by
/// `scale` (the same mesh): the cell velocities' relative L2 difference
/// ‖u_a − s u_b‖₂/‖s u_b‖₂, and the largest cell difference over the largest cell speed of
/// s u_b.
pub fn field_difference(a: &FoamCase, t: f64, b: &FoamCase, scale: f64) -> Result<(f64, f64), BifurcationError> {
    let last = *b.times().last().ok_or_else(|| FoamError::Field {
        path: "(steady case)".into(),
        reason: "no time directory".into(),
    })?;
    let (ua, ub) = (a.read_field(t, "U", 3)?, b.read_field(last, "U", 3)?);
    if ua.internal.len() != ub.internal.len() {
        return Err(FoamError::Mesh {
            reason: format!(
                "{} and {} cell values: not the same mesh",
                ua.internal.len(),
                ub.internal.len()
            ),
        }
        .into());
    }
    let (mut diff2, mut norm2, mut diff_max, mut speed_max) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (x, y) in ua.internal.chunks(3).zip(ub.internal.chunks(3)) {
        let d = ((x[0] - scale * y[0]).powi(2) + (x[1] - scale * y[1]).powi(2) + (x[2] - scale * y[2]).powi(2)).sqrt();
        let s = scale * (y[0] * y[0] + y[1] * y[1] + y[2] * y[2]).sqrt();
        diff2 += d * d;
        norm2 += s * s;
        diff_max = diff_max.max(d);
        speed_max = speed_max.max(s);
    }
    Ok(((diff2 / norm2).sqrt(), diff_max / speed_max))
}

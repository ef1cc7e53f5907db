//! `[flow]` and `[boundary]`: the carrier flow and what the particles can touch.
use super::*;

impl Builder<'_> {
    pub(super) fn flow(&self, spec: &FlowSpec, base: &Path) -> Result<SceneFlow, SceneError> {
        let at = spec.kind.span();
        // A study's scenes are built one case at a time (`load_study`), with `cases` cleared.
        if let Some(cases) = &spec.cases {
            return Err(self.err(
                cases.span(),
                "flow.cases",
                format!(
                    "names a mesh study of {} cases: run it with `pseudorigid study` (or give one `flow.case`)",
                    cases.get_ref().len()
                ),
            ));
        }
        let rate = ("flow.rate", spec.rate.is_some());
        let pipe = [
            ("flow.radius", spec.radius.is_some()),
            ("flow.mean_velocity", spec.mean_velocity.is_some()),
        ];
        let foam = [
            ("flow.case", spec.case.is_some()),
            ("flow.time", spec.time.is_some()),
            ("flow.precision", spec.precision.is_some()),
            ("flow.window", spec.window.is_some()),
            ("flow.still", spec.still),
        ];
        let linear = |kind: &str, make: fn(f64) -> Result<LinearFlow, ParamError>| {
            self.refuse(
                &[pipe[0], pipe[1], foam[0], foam[1], foam[2], foam[3], foam[4]],
                at.clone(),
                kind,
            )?;
            let rate = self.need(&spec.rate, at.clone(), "flow.rate", kind)?;
            let r = self.finite(rate, "flow.rate")?;
            make(r)
                .map(SceneFlow::Linear)
                .map_err(|e| self.param(rate.span(), "flow.rate", e))
        };
        match spec.kind.get_ref() {
            FlowKind::Quiescent => {
                self.refuse(
                    &[rate, pipe[0], pipe[1], foam[0], foam[1], foam[2], foam[3], foam[4]],
                    at,
                    "quiescent",
                )?;
                Ok(SceneFlow::Quiescent)
            }
            FlowKind::Shear => linear("shear", LinearFlow::simple_shear),
            FlowKind::PlanarExtension => linear("planar_extension", LinearFlow::planar_extension),
            FlowKind::UniaxialExtension => linear("uniaxial_extension", LinearFlow::uniaxial_extension),
            FlowKind::Poiseuille => {
                self.refuse(
                    &[rate, foam[0], foam[1], foam[2], foam[3], foam[4]],
                    at.clone(),
                    "poiseuille",
                )?;
                let radius = self.need(&spec.radius, at.clone(), "flow.radius", "poiseuille")?;
                let mean = self.need(&spec.mean_velocity, at, "flow.mean_velocity", "poiseuille")?;
                let r = self.positive(radius, "flow.radius")?;
                let u = self.finite(mean, "flow.mean_velocity")?;
                Poiseuille::new(r, u)
                    .map(SceneFlow::Poiseuille)
                    .map_err(|e| self.param(mean.span(), "flow.radius, flow.mean_velocity", e))
            }
            FlowKind::Openfoam => {
                self.refuse(&[rate, pipe[0], pipe[1]], at.clone(), "openfoam")?;
                let case = self.need(&spec.case, at, "flow.case", "openfoam")?;
                let dir = base.join(case.get_ref());
                let foam = FoamCase::open(&dir).map_err(|e| self.err(case.span(), "flow.case", e.to_string()))?;
                // Before any field is read: a cyclic or wedge patch's field has no value to read.
                check_particle_patches(foam.mesh()).map_err(|e| self.err(case.span(), "flow.case", e.to_string()))?;
                let latest = || {
                    foam.times()
                        .last()
                        .copied()
                        .ok_or_else(|| self.err(case.span(), "flow.case", "the case has no time directories"))
                };
                if let Some(t) = &spec.time
                    && matches!(t.get_ref(), TimeSpec::Many(_) | TimeSpec::Range(_))
                {
                    return self.transient(spec, t, foam);
                }
                let steady = "is for a transient field: `flow.time` a list of times or `{ start, end, period }`";
                if let Some(p) = &spec.precision {
                    return Err(self.err(p.span(), "flow.precision", steady));
                }
                if let Some(w) = &spec.window {
                    return Err(self.err(w.span(), "flow.window", steady));
                }
                let (times, span, key) = match &spec.time {
                    None => (vec![latest()?], case.span(), "flow.case"),
                    Some(t) => {
                        let times = match t.get_ref() {
                            TimeSpec::One(t) => vec![*t],
                            TimeSpec::Many(_) | TimeSpec::Range(_) => unreachable!("read as a transient field above"),
                            TimeSpec::Named(name) if name == "latest" => vec![latest()?],
                            TimeSpec::Named(name) => {
                                return Err(self.err(
                                    t.span(),
                                    "flow.time",
                                    format!("expected a time, a list of times or \"latest\", got \"{name}\""),
                                ));
                            }
                        };
                        if times.is_empty() || times.iter().any(|t| !t.is_finite()) {
                            return Err(self.err(
                                t.span(),
                                "flow.time",
                                format!("times must be finite and at least one, got {times:?}"),
                            ));
                        }
                        (times, t.span(), "flow.time")
                    }
                };
                let cells = FoamFlow::read(&foam, &times).map_err(|e| self.err(span.clone(), key, e.to_string()))?;
                let flux = foam
                    .read_boundary_flux(times[0])
                    .map_err(|e| self.err(span.clone(), key, e.to_string()))?;
                if let Some(flux) = flux {
                    // Built once per scene: the cell is empty here.
                    let _ = self.boundary_flux.set(flux);
                }
                if cells.is_zero() != spec.still {
                    let message = if spec.still {
                        format!("`flow.still = true` but U is not zero in every cell at t = {times:?}")
                    } else {
                        format!(
                            "U is zero in every cell at t = {times:?} (an initial condition? for still fluid say \
                             `still = true`); the case has times {:?}",
                            foam.times()
                        )
                    };
                    return Err(self.err(span, key, message));
                }
                match spec.blend {
                    true => BlendedFlow::new(cells).map(|b| SceneFlow::Blended(Box::new(b))),
                    false => Ok(SceneFlow::Foam(Box::new(cells))),
                }
                .map_err(|e| self.err(span, key, e.to_string()))
            }
        }
    }

    /// A transient field (`flow.time` a list or a range): the levels read window by window,
    /// repeated with `period` if given, stored in `flow.precision`, run in windows of
    /// `flow.window` (default: the smallest spacing of the levels, the wrap of a periodic
    /// field's included, so a window holds at most three levels).
    fn transient(&self, spec: &FlowSpec, time: &Spanned<TimeSpec>, foam: FoamCase) -> Result<SceneFlow, SceneError> {
        let (at, key) = (time.span(), "flow.time");
        if spec.still {
            return Err(self.err(at, "flow.still", "is for a steady field: a transient one is not still"));
        }
        let case_times = foam.times();
        let err = |message: String| self.err(at.clone(), key, message);
        let (levels, cycle) = match time.get_ref() {
            TimeSpec::Many(ts) => {
                if ts.len() < 2 {
                    return Err(err(format!(
                        "a list of times is a transient field and needs at least two, got {ts:?} (one time: `time = t`)"
                    )));
                }
                if let Some(t) = ts.iter().find(|t| !t.is_finite()) {
                    return Err(err(format!("times must be finite, got {t}")));
                }
                if let Some(i) = ts.windows(2).position(|w| w[0] >= w[1]) {
                    return Err(err(format!(
                        "times must be ascending: time[{i}] = {} is followed by time[{}] = {}",
                        ts[i],
                        i + 1,
                        ts[i + 1]
                    )));
                }
                if let Some(t) = ts.iter().find(|&&t| foam.time_dir(t).is_err()) {
                    return Err(err(format!(
                        "the case has no time directory {t}; its times are {}",
                        listed(&case_times)
                    )));
                }
                (ts.clone(), Cycle::Once)
            }
            TimeSpec::Range(range) => {
                let (Some(&first), Some(&last)) = (case_times.first(), case_times.last()) else {
                    return Err(err("the case has no time directories".into()));
                };
                let (start, end) = (range.start.unwrap_or(first), range.end.unwrap_or(last));
                if !(start.is_finite() && end.is_finite() && start < end) {
                    return Err(err(format!(
                        "needs finite start < end, got start = {start}, end = {end}"
                    )));
                }
                let cycle = match range.period {
                    None => Cycle::Once,
                    Some(period) if period.is_finite() && period > 0.0 => Cycle::Periodic { period },
                    Some(period) => return Err(err(format!("period must be > 0 and finite, got {period}"))),
                };
                // Within a relative 1e-9 of the ends, as the reader matches time directories.
                let slack = |t: f64| 1e-9 * t.abs().max(1.0);
                let levels: Vec<f64> = case_times
                    .iter()
                    .copied()
                    .filter(|&t| t >= start - slack(start) && t <= end + slack(end))
                    .collect();
                if levels.len() < 2 {
                    return Err(err(format!(
                        "{} time directories in [{start}, {end}]; a transient field needs at least two (the case's times are {})",
                        levels.len(),
                        listed(&case_times)
                    )));
                }
                (levels, cycle)
            }
            TimeSpec::One(_) | TimeSpec::Named(_) => unreachable!("a steady field"),
        };
        let precision = match spec.precision.as_ref().map(|p| *p.get_ref()) {
            Some(PrecisionSpec::F32) => Precision::F32,
            Some(PrecisionSpec::F64) | None => Precision::F64,
        };
        let field = match spec.blend {
            true => TransientFlow::open(foam, &levels, cycle, precision).map(|f| TransientField::Blended(Box::new(f))),
            false => {
                TransientFlow::open(foam, &levels, cycle, precision).map(|f| TransientField::Cellwise(Box::new(f)))
            }
        }
        .map_err(|e| err(e.to_string()))?;
        // The levels as read: a periodic field drops a level at the first's time plus a period.
        let read = field.levels();
        let mut spacings: Vec<f64> = read.windows(2).map(|w| w[1] - w[0]).collect();
        if let Cycle::Periodic { period } = cycle {
            spacings.push(read[0] + period - read[read.len() - 1]);
        }
        let spacing = spacings.into_iter().fold(f64::INFINITY, f64::min);
        let window = match &spec.window {
            None => spacing,
            Some(w) => {
                let w_len = self.positive(w, "flow.window")?;
                if let Cycle::Periodic { period } = cycle
                    && w_len > period
                {
                    return Err(self.err(
                        w.span(),
                        "flow.window",
                        format!("must be at most the period {period}, got {w_len}"),
                    ));
                }
                w_len
            }
        };
        Ok(SceneFlow::Transient(Arc::new(SceneTransient::new(field, window))))
    }

    pub(super) fn boundary(&self, spec: Option<&BoundarySpec>, flow: &SceneFlow) -> Result<SceneBoundary, SceneError> {
        let Some(b) = spec else {
            return Ok(SceneBoundary::Open(crate::contact::Unbounded));
        };
        let kind = *b.kind.get_ref();
        if kind != BoundaryKind::Pipe && b.radius.is_some() {
            return Err(self.err(b.kind.span(), "boundary.radius", "only a `pipe` boundary has a radius"));
        }
        if kind != BoundaryKind::Planes && !b.walls.is_empty() {
            return Err(self.err(b.kind.span(), "boundary.walls", "only a `planes` boundary has walls"));
        }
        match kind {
            BoundaryKind::Pipe => {
                let r = b
                    .radius
                    .as_ref()
                    .ok_or_else(|| self.err(b.kind.span(), "boundary.radius", "a `pipe` boundary needs `radius`"))?;
                let radius = self.positive(r, "boundary.radius")?;
                PipeWall::new(radius)
                    .map(SceneBoundary::Pipe)
                    .map_err(|e| self.param(r.span(), "boundary.radius", e))
            }
            BoundaryKind::Planes => {
                if b.walls.is_empty() {
                    return Err(self.err(
                        b.kind.span(),
                        "boundary.walls",
                        "a `planes` boundary needs `[[boundary.walls]]`",
                    ));
                }
                let walls = b
                    .walls
                    .iter()
                    .enumerate()
                    .map(|(i, w)| {
                        let key = format!("boundary.walls[{i}]");
                        let normal = self.vec3(&w.normal, &format!("{key}.normal"))?;
                        // Finite components: the norm is 0 only for the zero vector.
                        if normal.norm() == 0.0 {
                            return Err(self.err(w.normal.span(), &format!("{key}.normal"), "must not be zero"));
                        }
                        Ok(Plane {
                            name: w.name.clone(),
                            point: self.vec3(&w.point, &format!("{key}.point"))?,
                            normal,
                            rule: match w.rule {
                                RuleSpec::Stick => PatchRule::Stick,
                                RuleSpec::Exit => PatchRule::Exit,
                            },
                        })
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                Planes::new(walls)
                    .map(SceneBoundary::Planes)
                    .map_err(|e| self.param(b.kind.span(), "boundary.walls", e))
            }
            BoundaryKind::Mesh => match flow {
                SceneFlow::Foam(f) => MeshBoundary::new(f.mesh())
                    .map(|m| SceneBoundary::Mesh(Box::new(m)))
                    .map_err(|e| self.err(b.kind.span(), "boundary.type", e.to_string())),
                SceneFlow::Blended(f) => MeshBoundary::new(f.cellwise().mesh())
                    .map(|m| SceneBoundary::Mesh(Box::new(m)))
                    .map_err(|e| self.err(b.kind.span(), "boundary.type", e.to_string())),
                SceneFlow::Transient(f) => f
                    .with_field(|field| MeshBoundary::new(field.cellwise().mesh()))
                    .map(|m| SceneBoundary::Mesh(Box::new(m)))
                    .map_err(|e| self.err(b.kind.span(), "boundary.type", e.to_string())),
                _ => Err(self.err(
                    b.kind.span(),
                    "boundary.type",
                    "a `mesh` boundary needs an `openfoam` flow",
                )),
            },
        }
    }
}

/// Times as an error lists them: all of up to eight, else the first three, the last two and
/// how many.
fn listed(times: &[f64]) -> String {
    if times.len() <= 8 {
        return format!("{times:?}");
    }
    let n = times.len();
    format!(
        "[{}, {}, {}, …, {}, {}] ({n} times)",
        times[0],
        times[1],
        times[2],
        times[n - 2],
        times[n - 1]
    )
}

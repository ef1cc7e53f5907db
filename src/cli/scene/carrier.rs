//! `[flow]` and `[boundary]`: the carrier flow and what the particles can touch.
use super::*;

impl Builder<'_> {
    pub(super) fn flow(&self, spec: &FlowSpec, base: &Path) -> Result<SceneFlow, CliError> {
        let at = spec.kind.span();
        let rate = ("flow.rate", spec.rate.is_some());
        let pipe = [
            ("flow.radius", spec.radius.is_some()),
            ("flow.mean_velocity", spec.mean_velocity.is_some()),
        ];
        let foam = [("flow.case", spec.case.is_some()), ("flow.time", spec.time.is_some())];
        let linear = |kind: &str, make: fn(f64) -> Result<LinearFlow, ParamError>| {
            self.refuse(&[pipe[0], pipe[1], foam[0], foam[1]], at.clone(), kind)?;
            let rate = self.need(&spec.rate, at.clone(), "flow.rate", kind)?;
            let r = self.finite(rate, "flow.rate")?;
            make(r)
                .map(SceneFlow::Linear)
                .map_err(|e| self.param(rate.span(), "flow.rate", e))
        };
        match spec.kind.get_ref() {
            FlowKind::Quiescent => {
                self.refuse(&[rate, pipe[0], pipe[1], foam[0], foam[1]], at, "quiescent")?;
                Ok(SceneFlow::Quiescent)
            }
            FlowKind::Shear => linear("shear", LinearFlow::simple_shear),
            FlowKind::PlanarExtension => linear("planar_extension", LinearFlow::planar_extension),
            FlowKind::UniaxialExtension => linear("uniaxial_extension", LinearFlow::uniaxial_extension),
            FlowKind::Poiseuille => {
                self.refuse(&[rate, foam[0], foam[1]], at.clone(), "poiseuille")?;
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
                let latest = || {
                    foam.times()
                        .last()
                        .copied()
                        .ok_or_else(|| self.err(case.span(), "flow.case", "the case has no time directories"))
                };
                let (times, span, key) = match &spec.time {
                    None => (vec![latest()?], case.span(), "flow.case"),
                    Some(t) => {
                        let times = match t.get_ref() {
                            TimeSpec::One(t) => vec![*t],
                            TimeSpec::Many(ts) => ts.clone(),
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
                if cells.is_zero() {
                    return Err(self.err(
                        span,
                        key,
                        format!(
                            "U is zero in every cell at t = {times:?} (an initial condition?); the case has times {:?}",
                            foam.times()
                        ),
                    ));
                }
                match spec.blend {
                    true => BlendedFlow::new(cells).map(|b| SceneFlow::Blended(Box::new(b))),
                    false => Ok(SceneFlow::Foam(Box::new(cells))),
                }
                .map_err(|e| self.err(span, key, e.to_string()))
            }
        }
    }

    pub(super) fn boundary(&self, spec: Option<&BoundarySpec>, flow: &SceneFlow) -> Result<SceneBoundary, CliError> {
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
                _ => Err(self.err(
                    b.kind.span(),
                    "boundary.type",
                    "a `mesh` boundary needs an `openfoam` flow",
                )),
            },
        }
    }
}

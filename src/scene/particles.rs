//! `[fluid]` and `[particles]`: what the particles share, their shapes, laws and starts.
use super::*;
use crate::population::sampling::{DiscWeight, WeightedTriangles};

/// Points on an injection disc's rim checked to lie in the mesh.
const RIM_POINTS: usize = 64;

impl Builder<'_> {
    pub(super) fn template(
        &self,
        fluid: &FluidSpec,
        particles: &ParticlesSpec,
        forces: ForceTerms,
    ) -> Result<ParticleTemplate<NamedDrag>, SceneError> {
        let mu = self.positive(&fluid.viscosity, "fluid.viscosity")?;
        let rho_f = self.finite(&fluid.density, "fluid.density")?;
        let fluid_model = Fluid::new(mu, rho_f).map_err(|e| match e.key() {
            Some(k) if k.starts_with("mu_f") => self.param(fluid.viscosity.span(), "fluid.viscosity", e),
            _ => self.param(fluid.density.span(), "fluid.density", e),
        })?;
        let gravity = match &fluid.gravity {
            Some(g) => self.vec3(g, "fluid.gravity")?,
            None => Vec3::zeros(),
        };
        let drag = self.drag(particles.drag.as_ref())?;
        let volumetric = match particles.volumetric {
            VolumetricSpec::Paper => VolumetricTraction::Paper,
            VolumetricSpec::Dev => VolumetricTraction::Dev,
            VolumetricSpec::Source => VolumetricTraction::Source,
        };
        let at = fluid.gravity.as_ref().map_or(fluid.viscosity.span(), Spanned::span);
        let template = ParticleTemplate::new(drag, fluid_model, gravity)
            .map(|t| t.with_volumetric(volumetric))
            .map_err(|e| self.param(at, "fluid.gravity", e))?;
        Ok(template.with_forces(forces))
    }

    /// `particles.drag` through the registry of drag models (default `brenner`, the paper's).
    fn drag(&self, entry: Option<&Spanned<DragEntry>>) -> Result<NamedDrag, SceneError> {
        let Some(entry) = entry else {
            return drag::by_name("brenner", &Values::new()).map_err(|e| self.param(0..0, "particles.drag", e));
        };
        let (name, values) = match entry.get_ref() {
            DragEntry::Name(name) => (name, Values::new()),
            DragEntry::Table { model, parameters } => {
                let mut values = Values::new();
                for (k, v) in parameters {
                    let value = to_value(v)
                        .ok_or_else(|| self.err(entry.span(), &format!("particles.drag.{k}"), VALUE_KINDS))?;
                    values.insert(k.clone(), value);
                }
                (model, values)
            }
        };
        drag::by_name(name, &values).map_err(|e| {
            let key = match e.key() {
                Some(k) => format!("particles.drag.{k}"),
                None => "particles.drag".to_string(),
            };
            self.param(entry.span(), &key, e)
        })
    }

    /// `particles.forces`: each entry through the registry of force terms; a refusal that
    /// names a parameter is reported at `particles.forces[i].<key>`.
    pub(super) fn forces(&self, entries: &[Spanned<ForceEntry>]) -> Result<ForceTerms, SceneError> {
        let mut terms = Vec::with_capacity(entries.len());
        for (i, entry) in entries.iter().enumerate() {
            let key = format!("particles.forces[{i}]");
            let (name, values) = match entry.get_ref() {
                ForceEntry::Name(name) => (name, Values::new()),
                ForceEntry::Table { term, parameters } => {
                    let mut values = Values::new();
                    for (k, v) in parameters {
                        let value =
                            to_value(v).ok_or_else(|| self.err(entry.span(), &format!("{key}.{k}"), VALUE_KINDS))?;
                        values.insert(k.clone(), value);
                    }
                    (term, values)
                }
            };
            terms.push(forces::by_name(name, &values).map_err(|e| {
                let key = match e.key() {
                    Some(k) => format!("{key}.{k}"),
                    None => key.clone(),
                };
                self.param(entry.span(), &key, e)
            })?);
        }
        ForceTerms::new(terms)
            .map_err(|e| self.param(entries.last().map_or(0..0, Spanned::span), "particles.forces", e))
    }

    /// The solid density of an entry or group: its own `density` (`key`), else
    /// `particles.density`; `at` is where the entry or group is written.
    fn density(&self, own: Option<&Num>, shared: Option<&Num>, key: &str, at: Range<usize>) -> Result<f64, SceneError> {
        match (own, shared) {
            (Some(v), _) => self.positive(v, key),
            (None, Some(v)) => self.positive(v, "particles.density"),
            (None, None) => Err(self.err(at, key, format!("give `{key}` or `particles.density`"))),
        }
    }

    /// `material`: the response by name through the registry of laws.
    fn material(&self, m: &MaterialSpec, key: &str) -> Result<Softness<NamedLaw>, SceneError> {
        let keys = self.model_keys(m, key, "law", &[])?;
        material::registry::response(&keys.name, &keys.values).map_err(|e| self.model_error(&keys, e))
    }

    fn rotation(&self, o: Option<&OrientationSpec>, key: &str) -> Result<Mat3, SceneError> {
        let Some(o) = o else {
            return Ok(Mat3::identity());
        };
        let axis = self.vec3(&o.axis, &format!("{key}.axis"))?;
        let angle = self.finite(&o.angle, &format!("{key}.angle"))?;
        // Divide by the largest component first: the norm of (1e308, 1e308, 1e308) overflows.
        let scale = axis.amax();
        let axis = (scale > 0.0)
            .then(|| Unit::try_new(axis / scale, 0.0))
            .flatten()
            .ok_or_else(|| {
                self.err(
                    o.axis.span(),
                    &format!("{key}.axis"),
                    "must be a non-zero finite vector",
                )
            })?;
        Ok(Rotation3::from_axis_angle(&axis, angle).into_inner())
    }

    fn shape(&self, semi_axes: &Num3, axes: Mat3, key: &str) -> Result<Ellipsoid, SceneError> {
        let r = semi_axes.get_ref().0;
        for (i, v) in r.iter().enumerate() {
            if !(v.is_finite() && *v > 0.0) {
                return Err(self.err(
                    semi_axes.span(),
                    key,
                    format!("semi-axis {} must be finite and > 0, got {v}", i + 1),
                ));
            }
        }
        Ellipsoid::new(r, axes).map_err(|e| self.param(semi_axes.span(), key, e))
    }

    pub(super) fn particles(
        &self,
        spanned: &Spanned<ParticlesSpec>,
        template: &ParticleTemplate<NamedDrag>,
        flow: &SceneFlow,
        contact_radius: f64,
    ) -> Result<ParticleSource, SceneError> {
        let (spec, span) = (spanned.get_ref(), spanned.span());
        let shared = spec.density.as_ref();
        let source = match (spec.inject.0.is_empty(), spec.list.is_empty()) {
            (false, false) => {
                return Err(self.err(
                    span,
                    "particles",
                    "give either `[[particles.list]]` or `[particles.inject]`, not both",
                ));
            }
            (true, true) => {
                return Err(self.err(
                    span,
                    "particles",
                    "give `[[particles.list]]` entries or `[particles.inject]`",
                ));
            }
            (true, false) => {
                let list = spec
                    .list
                    .iter()
                    .enumerate()
                    .map(|(i, p)| self.listed(p, &format!("particles.list[{i}]"), shared, template, flow))
                    .collect::<Result<Vec<_>, _>>()?;
                ParticleSource::List(list)
            }
            (false, true) => {
                let groups = &spec.inject.0;
                // A single `[particles.inject]` keeps its plain key in messages.
                let key = |g: usize| match groups.len() {
                    1 => "particles.inject".to_string(),
                    _ => format!("particles.inject[{g}]"),
                };
                ParticleSource::Inject(
                    groups
                        .iter()
                        .enumerate()
                        .map(|(g, inj)| self.injection(inj, &key(g), shared, template, flow, contact_radius))
                        .collect::<Result<Vec<_>, _>>()?,
                )
            }
        };
        if source.count() > MAX_PARTICLES {
            return Err(self.err(
                span,
                "particles.inject.count",
                format!("at most {MAX_PARTICLES} particles in all"),
            ));
        }
        Ok(source)
    }

    fn listed(
        &self,
        p: &ParticleEntry,
        key: &str,
        shared: Option<&Num>,
        template: &ParticleTemplate<NamedDrag>,
        flow: &SceneFlow,
    ) -> Result<Placement, SceneError> {
        let density = self.density(
            p.density.as_ref(),
            shared,
            &format!("{key}.density"),
            p.semi_axes.span(),
        )?;
        let axes = self.rotation(p.orientation.as_ref(), &format!("{key}.orientation"))?;
        let shape = self.shape(&p.semi_axes, axes, &format!("{key}.semi_axes"))?;
        let softness = self.material(&p.material, &format!("{key}.material"))?;
        let position = self.vec3(&p.position, &format!("{key}.position"))?;
        let velocity = match (&p.velocity, p.fluid_velocity) {
            (Some(v), true) => {
                return Err(self.err(
                    v.span(),
                    &format!("{key}.velocity"),
                    "give `velocity` or `fluid_velocity = true`, not both",
                ));
            }
            (Some(v), false) => Velocity::Given(self.vec3(v, &format!("{key}.velocity"))?),
            (None, true) => {
                flow.sample(&position, 0.0).map_err(|e| {
                    // The domain is the flow's: name the keys that set it, which may be the
                    // ones written wrong (a pipe of radius 1e-320).
                    let domain = match flow {
                        SceneFlow::Poiseuille(_) => "; the pipe's `flow.radius` sets the domain",
                        SceneFlow::Foam(_) | SceneFlow::Blended(_) | SceneFlow::Transient(_) => {
                            "; the mesh of `flow.case` sets the domain"
                        }
                        SceneFlow::Quiescent | SceneFlow::Linear(_) => "",
                    };
                    self.err(p.position.span(), &format!("{key}.position"), format!("{e}{domain}"))
                })?;
                Velocity::Fluid
            }
            (None, false) => Velocity::Given(Vec3::zeros()),
        };
        let placement = Placement {
            shape,
            softness,
            density,
            position,
            velocity,
        };
        // Build it once now, so a particle the model refuses (too slender, too heavy) is
        // reported at its entry rather than as a failed particle of the run.
        template
            .build(&placement.spec(Vec3::zeros()))
            .map_err(|e| self.param(p.semi_axes.span(), &self.built_from(key, &p.material), e))?;
        Ok(placement)
    }

    /// The keys a particle of entry or group `key` is built from, as a refusal names them: its
    /// shape, density and the material's given parameters, and the fluid's viscosity (the
    /// rest-state rates combine them).
    fn built_from(&self, key: &str, m: &MaterialSpec) -> String {
        let material: Vec<String> = m
            .get_ref()
            .keys()
            .filter(|name| *name != "law")
            .map(|name| format!("{key}.material.{name}"))
            .collect();
        let material = if material.is_empty() {
            format!("{key}.material")
        } else {
            material.join(", ")
        };
        format!("{key}.semi_axes, {key}.density, {material}, fluid.viscosity")
    }

    fn injection(
        &self,
        inj: &InjectSpec,
        key: &str,
        shared: Option<&Num>,
        template: &ParticleTemplate<NamedDrag>,
        flow: &SceneFlow,
        contact_radius: f64,
    ) -> Result<Group, SceneError> {
        let count = *inj.count.get_ref();
        if count == 0 {
            return Err(self.err(inj.count.span(), &format!("{key}.count"), "must be at least 1"));
        }
        if inj.random_orientation && inj.orientation.is_some() {
            return Err(self.err(
                inj.semi_axes.span(),
                &format!("{key}.orientation"),
                "give `orientation` or `random_orientation = true`, not both",
            ));
        }
        let density = self.density(
            inj.density.as_ref(),
            shared,
            &format!("{key}.density"),
            inj.count.span(),
        )?;
        let axes = self.rotation(inj.orientation.as_ref(), &format!("{key}.orientation"))?;
        let shape = self.shape(&inj.semi_axes, axes, &format!("{key}.semi_axes"))?;
        let softness = self.material(&inj.material, &format!("{key}.material"))?;
        let key_region = format!("{key}.region");
        // A particle touches at its largest semi-axis, or at the contact radius of barycentre
        // contact if that is larger.
        let extent = shape.semi_axes().iter().copied().fold(contact_radius, f64::max);
        let region = self.region(&inj.region, &key_region, flow, extent)?;
        self.region_in_mesh(&region, &key_region, inj.region.kind.span(), flow)?;
        let placement = Placement {
            shape,
            softness,
            density,
            position: Vec3::zeros(),
            velocity: if inj.fluid_velocity {
                Velocity::Fluid
            } else {
                Velocity::Given(Vec3::zeros())
            },
        };
        template
            .build(&placement.spec(Vec3::zeros()))
            .map_err(|e| self.param(inj.semi_axes.span(), &self.built_from(key, &inj.material), e))?;
        Ok(Group {
            count,
            region,
            random_orientation: inj.random_orientation,
            placement,
        })
    }

    /// On an OpenFOAM flow, every point of the injection region lies in a cell: the point, or
    /// the disc's centre and, weighted by area, 64 points on its rim (a disc whose rim stays
    /// inside a convex cross-section lies inside). A disc weighted by pipe flux needs only its
    /// centre inside: its weight vanishes at the rim, and a particle drawn outside the mesh
    /// fails alone rather than starting outside.
    fn region_in_mesh(
        &self,
        region: &crate::scene::inject::Region,
        key: &str,
        span: Range<usize>,
        flow: &SceneFlow,
    ) -> Result<(), SceneError> {
        flow.with_cellwise(|cells| match cells {
            Some(cells) => self.points_in_mesh(region, key, span, cells),
            None => Ok(()),
        })
    }

    /// [`Self::region_in_mesh`] on the cellwise field `cells`.
    fn points_in_mesh(
        &self,
        region: &crate::scene::inject::Region,
        key: &str,
        span: Range<usize>,
        cells: &FoamFlow,
    ) -> Result<(), SceneError> {
        let points: Vec<Vec3> = match region {
            crate::scene::inject::Region::Point(p) => vec![*p],
            // Inside by construction (the patch's faces moved inwards).
            crate::scene::inject::Region::Patch(_) => return Ok(()),
            // Pipe flux vanishes at the rim, which a faceted wall cuts: the centre must lie
            // inside, and a particle drawn outside fails alone (`Region::Disc`).
            &crate::scene::inject::Region::Disc {
                centre,
                weight: DiscWeight::Poiseuille,
                ..
            } => vec![centre],
            &crate::scene::inject::Region::Disc {
                centre,
                normal,
                radius,
                weight: DiscWeight::Area,
            } => {
                let n = normal.normalize();
                let helper = if n[0].abs() < 0.9 { Vec3::x() } else { Vec3::y() };
                let e1 = n.cross(&helper).normalize();
                let e2 = n.cross(&e1);
                let mut pts = vec![centre];
                pts.extend((0..RIM_POINTS).map(|i| {
                    let a = std::f64::consts::TAU * i as f64 / RIM_POINTS as f64;
                    centre + (e1 * a.cos() + e2 * a.sin()) * radius
                }));
                pts
            }
        };
        for p in points {
            if let Err(e) = cells.locate(&p, None) {
                return Err(self.err(
                    span,
                    key,
                    format!("the injection region leaves the mesh at {:?}: {e}", [p[0], p[1], p[2]]),
                ));
            }
        }
        Ok(())
    }

    fn region(
        &self,
        r: &RegionSpec,
        key: &str,
        flow: &SceneFlow,
        extent: f64,
    ) -> Result<crate::scene::inject::Region, SceneError> {
        let at = r.kind.span();
        let k = |name: &str| format!("{key}.{name}");
        match r.kind.get_ref() {
            RegionKind::Point => {
                let (c, n, rr, nm, w) = (k("centre"), k("normal"), k("radius"), k("name"), k("weight"));
                self.refuse(
                    &[
                        (&c, r.centre.is_some()),
                        (&n, r.normal.is_some()),
                        (&rr, r.radius.is_some()),
                        (&nm, r.name.is_some()),
                        (&w, r.weight.is_some()),
                    ],
                    at.clone(),
                    "point",
                )?;
                let p = self.need(&r.at, at, &k("at"), "point")?;
                Ok(crate::scene::inject::Region::Point(self.vec3(p, &k("at"))?))
            }
            RegionKind::Disc => {
                let (a, nm) = (k("at"), k("name"));
                self.refuse(&[(&a, r.at.is_some()), (&nm, r.name.is_some())], at.clone(), "disc")?;
                let centre = self.need(&r.centre, at.clone(), &k("centre"), "disc")?;
                let normal = self.need(&r.normal, at.clone(), &k("normal"), "disc")?;
                let radius = self.need(&r.radius, at, &k("radius"), "disc")?;
                let n = self.vec3(normal, &k("normal"))?;
                if !(n.norm() > 0.0 && n.norm().is_finite()) {
                    return Err(self.err(normal.span(), &k("normal"), "must be a non-zero finite vector"));
                }
                Ok(crate::scene::inject::Region::Disc {
                    centre: self.vec3(centre, &k("centre"))?,
                    normal: n,
                    radius: self.positive(radius, &k("radius"))?,
                    weight: r.weight.as_ref().map_or(DiscWeight::Area, |w| *w.get_ref()),
                })
            }
            RegionKind::Patch => {
                let (a, c, n, rr, w) = (k("at"), k("centre"), k("normal"), k("radius"), k("weight"));
                self.refuse(
                    &[
                        (&a, r.at.is_some()),
                        (&c, r.centre.is_some()),
                        (&n, r.normal.is_some()),
                        (&rr, r.radius.is_some()),
                        (&w, r.weight.is_some()),
                    ],
                    at.clone(),
                    "patch",
                )?;
                let name = self.need(&r.name, at, &k("name"), "patch")?;
                self.patch_region(name, &k("name"), flow, extent)
            }
        }
    }

    /// The inflow through patch `name` as weighted triangles: each face's fan of triangles
    /// around its centre, weighted by the face's inflow (below; at the first time level) times
    /// the triangle's share of the face's area, moved
    /// inside along the face normal by 1.01 `extent` (the particle's largest semi-axis, or the
    /// contact radius of barycentre contact if larger), so a
    /// particle does not start touching the patch it enters through (at least 10⁻⁶ of the
    /// face's size for point particles).
    ///
    /// The face's inflow is the case's own face flux −`phi` where the steady field's time
    /// directory has `phi` (the solver's conservative flux: the injection then splits as the
    /// solver's flow does), else −u·S of the cell fit (a transient field, a decomposed case,
    /// a field written without `phi`).
    ///
    /// Refused, naming the patch, its type and its flux: a patch of
    /// type `wall`, which no fluid crosses (a cell fit's round-off or a non-zero wall velocity
    /// gives some of its faces an inflow, and particles would start on the wall), and a patch
    /// with no inflow at the field's first time (an outlet; on a transient field, an inlet
    /// whose flow starts from rest).
    fn patch_region(
        &self,
        name: &Spanned<String>,
        key: &str,
        flow: &SceneFlow,
        extent: f64,
    ) -> Result<crate::scene::inject::Region, SceneError> {
        let transient = matches!(flow, SceneFlow::Transient(_));
        flow.with_cellwise(|cells| match cells {
            Some(cells) => self.patch_triangles(name, key, cells, extent, transient),
            None => Err(self.err(name.span(), key, "a `patch` region needs an `openfoam` flow")),
        })
    }

    /// [`Self::patch_region`] on the cellwise field `cells` (of a transient field if
    /// `transient`).
    fn patch_triangles(
        &self,
        name: &Spanned<String>,
        key: &str,
        cells: &FoamFlow,
        extent: f64,
        transient: bool,
    ) -> Result<crate::scene::inject::Region, SceneError> {
        let mesh = cells.mesh();
        let Some(patch) = mesh.patches().iter().find(|p| p.name == *name.get_ref()) else {
            let names: Vec<&str> = mesh.patches().iter().map(|p| p.name.as_str()).collect();
            return Err(self.err(
                name.span(),
                key,
                format!("no patch `{}`; the mesh has {names:?}", name.get_ref()),
            ));
        };
        let t = cells.times()[0];
        let phi = self.boundary_flux.get().filter(|_| !transient);
        let (mut triangles, mut net, mut inflow_total) = (Vec::new(), 0.0, 0.0);
        for f in patch.start..patch.start + patch.size {
            let (area, centre) = (mesh.face_areas()[f], mesh.face_centres()[f]);
            let size = area.norm();
            let flux = match phi {
                Some(phi) => phi[f - mesh.n_internal_faces()],
                None => cells.sample_cell(mesh.owner(f), &centre, t).u.dot(&area),
            };
            let inflow = (-flux).max(0.0);
            net += flux;
            inflow_total += inflow;
            let inward = -area / size * (1.01 * extent).max(1e-6 * size.sqrt());
            let poly = mesh.face(f);
            for (i, &v) in poly.iter().enumerate() {
                let (a, b) = (
                    mesh.points()[v as usize],
                    mesh.points()[poly[(i + 1) % poly.len()] as usize],
                );
                let share = (a - centre).cross(&(b - centre)).norm() / 2.0 / size;
                triangles.push(([centre + inward, a + inward, b + inward], inflow * share));
            }
        }
        let source = match phi {
            Some(_) => "the case's face flux `phi`",
            None => "sum(u.S), the cell fits at its faces",
        };
        let what = format!(
            "patch `{}` (type `{}`, {} faces): net flux out of the domain {net:.3e}, inflow {inflow_total:.3e} ({source} \
             at t = {t})",
            patch.name, patch.kind, patch.size
        );
        let open = || -> Vec<&str> {
            mesh.patches()
                .iter()
                .filter(|p| p.kind != "wall")
                .map(|p| p.name.as_str())
                .collect()
        };
        if patch.kind == "wall" {
            return Err(self.err(
                name.span(),
                key,
                format!(
                    "{what}: no fluid enters through a wall, and the particles would start on it; name a patch the \
                     fluid enters through (the mesh's patches that are not walls: {:?})",
                    open()
                ),
            ));
        }
        if inflow_total <= 0.0 {
            let start = if transient {
                "; a transient field is injected into at its first time level, where this flow has not started: \
                 start `flow.time` where the fluid enters, or inject from a disc or a point"
            } else {
                ""
            };
            return Err(self.err(
                name.span(),
                key,
                format!("no inflow through {what}: particles are drawn where the fluid enters{start}"),
            ));
        }
        WeightedTriangles::new(triangles)
            .map(crate::scene::inject::Region::Patch)
            .map_err(|e| self.err(name.span(), key, format!("{what}: {e}")))
    }
}

//! One particle through the cavity: the experiment ([`Cavity`]), its outcome and the slip
//! against the fluid.

use super::*;

/// How a run ended.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum Outcome {
    /// Left through the lid.
    Exited {
        /// Time (s).
        t: f64,
    },
    /// Stuck to a wall.
    Deposited {
        /// Time (s).
        t: f64,
        /// Wall name.
        wall: String,
    },
    /// Still suspended at the end of tracking.
    Suspended,
    /// The particle's run failed (a typed step error), recorded instead of ending the study.
    Failed {
        /// Time of the last accepted step (s).
        t: f64,
        /// The error.
        reason: String,
    },
}

/// A tracked particle.
#[derive(Debug, Clone, Serialize)]
pub struct CavityRun {
    /// The release.
    pub release: Release,
    /// Contact model used.
    pub contact: Contact,
    /// Shape model used (inertialess for the rigid limit whatever was asked).
    pub shape_model: ShapeModel,
    /// (t, x) samples [s, m].
    pub path: Vec<(f64, Vec3)>,
    /// Outcome.
    pub outcome: Outcome,
    /// Work.
    pub stats: RunStats,
    /// Validity diagnostics over the accepted steps (r₁ in m).
    pub validity: Validity,
    /// Slip relative to the fluid over the accepted steps.
    pub slip: Slip,
}

/// The particle's slip |v − u(x)| relative to the undisturbed fluid at its barycentre over a
/// run's accepted steps [m/s]: the drift that the fluid-inertia force terms act on
/// (`paper-figures/fig15_fig16/NOTES.md`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Slip {
    /// Largest slip.
    pub max: f64,
    /// Median over time: each step's end-state slip weighted by the step's length, so that the
    /// short steps near walls do not outvote the rest of the path.
    pub median: f64,
}

impl Slip {
    /// From (step length, slip) samples; zeros for none.
    fn of(mut samples: Vec<(f64, f64)>) -> Self {
        samples.sort_by(|a, b| a.1.total_cmp(&b.1));
        let total: f64 = samples.iter().map(|s| s.0).sum();
        let mut seen = 0.0;
        let median = samples
            .iter()
            .find(|(dt, _)| {
                seen += dt;
                seen >= 0.5 * total
            })
            .map_or(0.0, |s| s.1);
        Self {
            max: samples.last().map_or(0.0, |s| s.1),
            median,
        }
    }
}

/// One point of [`Cavity::quasi_steady_slip`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct QuasiSteady {
    /// The quasi-steady slip |w| [m/s].
    pub slip: f64,
    /// |(∇u)u − a|/|a|: how far the blend of the cells' gradients (`grad_u`) times u is from
    /// the acceleration a along the streamline, i.e. the error of a Du/Dt built from `grad_u`
    /// (what the fluid-inertia terms used before they took [`FlowSample::convective`]).
    ///
    /// [`FlowSample::convective`]: crate::flow::FlowSample::convective
    pub acceleration_gap: f64,
}

/// The cavity experiment: flow field, walls, fluid and the particle model (law family and drag;
/// the paper's Neo-Hooke and Brenner by default).
pub struct Cavity<'a, L = NeoHookeLaw, D = Brenner> {
    flow: VariantFlow<'a>,
    boundary: Planes,
    fluid: Fluid,
    shear_rate: f64,
    shape_model: ShapeModel,
    /// Scheme of the inertialess path.
    scheme: Scheme,
    model: ParticleModel<L, D>,
    /// Force terms beyond the paper's (none: the paper's model).
    forces: ForceTerms,
}

impl<'a> Cavity<'a> {
    /// Experiment on a loaded Re = 470 field ([`shipped_flow`]), inertialess shapes, the paper's
    /// particle model.
    pub fn new(flow: &'a BlendedFlow) -> Result<Self, SceneError> {
        let d = sym(&flow.sample(&release_point(), 0.0).map_err(StepError::from)?.grad_u);
        let shear_rate = (2.0 * d.component_mul(&d).sum()).sqrt();
        Ok(Self {
            flow: VariantFlow {
                mesh: flow,
                variant: Variant::default(),
            },
            boundary: Planes::cavity(EDGE)?,
            fluid: Fluid::new(rho_fluid() * NU, rho_fluid())?,
            shear_rate,
            shape_model: ShapeModel::Inertialess,
            scheme: Scheme::Radau5,
            model: ParticleModel::default(),
            forces: ForceTerms::default(),
        })
    }
}

impl<'a, L: LawFactory, D: DragModel + Clone> Cavity<'a, L, D> {
    /// The same experiment with another particle model (law family, drag, bulk ratio).
    pub fn with_model<L2: LawFactory, D2: DragModel + Clone>(self, model: ParticleModel<L2, D2>) -> Cavity<'a, L2, D2> {
        Cavity {
            flow: self.flow,
            boundary: self.boundary,
            fluid: self.fluid,
            shear_rate: self.shear_rate,
            shape_model: self.shape_model,
            scheme: self.scheme,
            model,
            forces: self.forces,
        }
    }

    /// The same experiment with force terms beyond the paper's on the particle (e.g. the
    /// fluid-inertia terms [`fluid_inertia`]).
    pub fn with_forces(self, forces: ForceTerms) -> Self {
        Self { forces, ..self }
    }

    /// The same experiment with another scheme for the inertialess shape model (and the rigid
    /// limit, which always takes that path).
    pub fn with_scheme(self, scheme: Scheme) -> Self {
        Self { scheme, ..self }
    }

    /// The same experiment with another shape model.
    pub fn with_shape_model(self, shape_model: ShapeModel) -> Self {
        Self { shape_model, ..self }
    }

    /// The same experiment in a variant of the field. The particles keep their stiffness: Ca
    /// stays defined by the nominal field's γ̇₀ (the particle is real, the field uncertain).
    pub fn with_variant(self, variant: Variant) -> Result<Self, SceneError> {
        crate::error::positive("field scale", variant.scale)?;
        Ok(Self {
            flow: VariantFlow { variant, ..self.flow },
            ..self
        })
    }

    /// The same experiment with a neutrally buoyant particle (ρ_f = ρ_p, ν unchanged).
    pub fn neutrally_buoyant(self) -> Result<Self, SceneError> {
        Ok(Self {
            fluid: Fluid::new(RHO_PARTICLE * NU, RHO_PARTICLE)?,
            ..self
        })
    }

    /// The experiment's flow (the shipped field in its [`Variant`]) at `x`.
    pub fn sample(&self, x: &Vec3) -> Result<crate::flow::FlowSample, crate::error::FlowError> {
        self.flow.sample(x, 0.0)
    }

    /// Along `run`'s output path, the slip a Stokes sphere of the particle's volume has in
    /// quasi-steady motion (Maxey & Riley 1983 without the history force): with v̇ = a, the
    /// fluid's acceleration along the streamline (the sample's Du/Dt, the derivative of the
    /// field's u along u), the barycentre equation gives
    /// ```math
    /// ζ (u − v) = (m + C_m m_f)\,a − (C_u + C_m)\,m_f\, a − (m − m_f)\,g,\qquad ζ = 3πμ_f d_{eq},
    /// ```
    /// C_u = 1 with the undisturbed-flow force, C_m = ½ with added mass (0 without). Without the
    /// terms the inertial drift is m a/ζ; with both it is (m − m_f) a/ζ, smaller by
    /// ρ_p/|ρ_p − ρ_f| (2 000 here; zero for a neutrally buoyant particle, which then follows
    /// the fluid up to the terms of order τ² the quasi-steady balance drops). For other shapes
    /// it is an estimate.
    pub fn quasi_steady_slip(&self, run: &CavityRun) -> Result<Vec<QuasiSteady>, SceneError> {
        let names = self.forces.names();
        let c_u = if names.contains(&UndisturbedFlow::NAME) {
            1.0
        } else {
            0.0
        };
        let c_m = if names.contains(&AddedMass::NAME) { 0.5 } else { 0.0 };
        let volume = std::f64::consts::PI / 6.0 * D_EQ.powi(3);
        let (m, m_f) = (RHO_PARTICLE * volume, self.fluid.rho * volume);
        let zeta = 3.0 * std::f64::consts::PI * self.fluid.mu * D_EQ;
        let g = Vec3::new(0.0, 0.0, -9.81);
        let mut out = Vec::with_capacity(run.path.len());
        for (_, x) in &run.path {
            let s = self.flow.sample(x, 0.0).map_err(StepError::from)?;
            let a = s.material_acceleration();
            if a == Vec3::zeros() {
                continue;
            }
            let lag = (a * (m + c_m * m_f) - a * ((c_u + c_m) * m_f) - g * (m - m_f)) / zeta;
            out.push(QuasiSteady {
                slip: lag.norm(),
                acceleration_gap: (s.grad_u * s.u - a).norm() / a.norm(),
            });
        }
        Ok(out)
    }

    /// γ̇₀ = √(2 d:d) at the release point [1/s].
    pub fn release_shear_rate(&self) -> f64 {
        self.shear_rate
    }

    fn particle(&self, release: &Release) -> Result<Particle<SceneResponse<L>, D>, SceneError> {
        let shape = release.shape.ellipsoid(D_EQ, Mat3::identity())?;
        // The inertial runs are error-controlled, so they resolve what the traction does to the
        // volume mode: the literal eq. 12 anti-damps dilation (see
        // `integrator::imex::volume_mode_floor`; at tol 1e-7 J − 1 grew from 3e-5 to 1.6), the
        // source-flow term resists it as a fluid does. Shapes are unaffected (|J − 1| ≈ 1e-4
        // at λ_s/μ_s = 1e3); the inertialess model keeps tr l_s = 0 and ignores the choice.
        // The rigid limit (Ca → 0) is a rigid particle: Jeffery rotation, no elasticity.
        let particle = self.model.particle(
            shape,
            release.softness,
            self.fluid.mu * self.shear_rate,
            self.fluid,
            RHO_PARTICLE,
        )?;
        Ok(particle
            .with_gravity(Vec3::new(0.0, 0.0, -9.81))?
            .with_volumetric(VolumetricTraction::Source)
            .with_forces(self.forces.clone())?)
    }

    /// Track `release` for `t_max` seconds with tolerance `tol`, sampling every `dt_out`;
    /// `contact` decides what must touch a wall.
    pub fn track(
        &self,
        release: Release,
        contact_model: Contact,
        t_max: f64,
        tol: f64,
        dt_out: f64,
    ) -> Result<CavityRun, SceneError> {
        self.track_oriented(release, contact_model, &Mat3::identity(), t_max, tol, dt_out)
    }

    /// [`Self::track`] with the release turned by the rotation `turn` (its axes become
    /// turn·(e_x, e_y, e_z)); F = turn, so the stress-free shape is turned as a rigid body.
    pub fn track_oriented(
        &self,
        release: Release,
        contact_model: Contact,
        turn: &Mat3,
        t_max: f64,
        tol: f64,
        dt_out: f64,
    ) -> Result<CavityRun, SceneError> {
        let model = match (self.shape_model, release.softness) {
            (ShapeModel::Inertial, Deformability::Elastic { .. }) => ShapeModel::Inertial,
            _ => ShapeModel::Inertialess,
        };
        match model {
            ShapeModel::Inertial => {
                let integ = ImexAdaptive::new(tol)?;
                self.track_with(&integ, model, release, contact_model, turn, t_max, dt_out)
            }
            ShapeModel::Inertialess => {
                // Rigid releases are rigid particles (see `particle`); the integrator is the same.
                let mut integ = Stokesian::new(tol)?.with_scheme(self.scheme);
                integ.barycentre = BarycentreModel::Inertial;
                self.track_with(&integ, model, release, contact_model, turn, t_max, dt_out)
            }
        }
    }

    #[allow(clippy::too_many_arguments)] // the release, its integrator and the run's limits
    fn track_with<I: TimeIntegrator>(
        &self,
        integ: &I,
        shape_model: ShapeModel,
        release: Release,
        contact_model: Contact,
        turn: &Mat3,
        t_max: f64,
        dt_out: f64,
    ) -> Result<CavityRun, SceneError> {
        let defect = (turn.transpose() * turn - Mat3::identity()).amax();
        if defect > 1e-12 || turn.determinant() <= 0.0 {
            return Err(crate::error::ParamError::NotARotation {
                orthogonality_defect: defect,
                det: turn.determinant(),
            }
            .into());
        }
        let p = self.particle(&release)?;
        let mut s0 = State::at_rest(release_point());
        s0.f = *turn;
        s0.v = self.flow.sample(&s0.x, 0.0).map_err(StepError::from)?.u;
        let model = match contact_model {
            Contact::Extent => ContactModel::Extent,
            Contact::Barycentre => ContactModel::Barycentre {
                radius: BARYCENTRE_CONTACT_DISTANCE,
            },
        };
        let contact = ContactEvent::new(&self.boundary, &p, &self.flow, model);
        let mut monitor = Monitor::new(&p, &self.flow, &self.boundary);
        monitor.observe(&s0);
        // No step may carry the particle further than a quarter of its smallest semi-axis
        // (|u| ≤ U_lid): in the corners two walls are near at once, and the contact event
        // watches only the nearest.
        let dt_max = 0.25 * p.shape().semi_axes().min() / LID_VELOCITY;
        let plan = Plan::new(t_max, dt_max)?.with_dt_max(dt_max)?;
        let path = std::cell::RefCell::new(Vec::new());
        let mut slips = Vec::new();
        let mut next_out = dt_out;
        let mut memory = Default::default();
        let end = match integrate(
            integ,
            &p,
            &self.flow,
            s0,
            &mut memory,
            &plan,
            &[&contact],
            |s| path.borrow_mut().push((s.t, s.x)),
            |step| {
                monitor.observe(&step.state);
                if let Ok(fluid) = self.flow.sample(&step.state.x, step.state.t) {
                    slips.push((step.info.dt, (step.state.v - fluid.u).norm()));
                }
                if step.state.t >= next_out {
                    path.borrow_mut().push((step.state.t, step.state.x));
                    next_out = dt_out * ((step.state.t / dt_out).floor() + 1.0);
                }
            },
        ) {
            Ok(end) => end,
            Err(failure) => {
                // A failed particle is an outcome of the study, as in the population runner.
                let mut path = path.into_inner();
                path.push((failure.state.t, failure.state.x));
                return Ok(CavityRun {
                    release,
                    contact: contact_model,
                    shape_model,
                    path,
                    outcome: Outcome::Failed {
                        t: failure.state.t,
                        reason: failure.error.to_string(),
                    },
                    stats: failure.stats,
                    validity: monitor.validity(),
                    slip: Slip::of(slips),
                });
            }
        };
        let outcome = match end.stop {
            Stop::Event { .. } => {
                let near = contact.nearest(&end.state);
                match self.boundary.rule(near.patch) {
                    PatchRule::Exit => Outcome::Exited { t: end.state.t },
                    PatchRule::Stick => Outcome::Deposited {
                        t: end.state.t,
                        wall: self.boundary.patch_name(near.patch).to_string(),
                    },
                }
            }
            Stop::EndTime => {
                let mut path = path.borrow_mut();
                if path.last().is_none_or(|(t, _)| *t < end.state.t) {
                    path.push((end.state.t, end.state.x));
                }
                Outcome::Suspended
            }
        };
        let path = path.into_inner();
        let stats = end.stats;
        Ok(CavityRun {
            release,
            contact: contact_model,
            shape_model,
            path,
            outcome,
            stats,
            validity: monitor.validity(),
            slip: Slip::of(slips),
        })
    }
}

//! Validity diagnostics of a run: how far a particle strays from the assumptions of the model.
//!
//! # What the model assumes (paper §2–§4)
//! The pseudo-rigid particle sees the carrier flow through u and ∇u at its barycentre and the
//! Jeffery–Roscoe traction and Brenner's drag (eqs. 12, 14), which are Stokes-flow solutions for
//! an ellipsoid alone in an unbounded linear flow. That requires
//! - creeping flow at the particle scale: the shear Reynolds number Re_γ = γ̇ d²/ν and the slip
//!   Reynolds number Re_s = |u − v| d/ν small (d = d_eq, γ̇ = √(2 d:d) of the flow);
//! - a particle small against the distance to the nearest wall (no wall interaction);
//! - a particle small against the length over which the flow changes (u linear across it).
//!
//! # Thresholds ([`Thresholds::default`]) and their argument
//! - Re_s ≤ 0.1: Oseen's first inertial correction of the drag is (3/16) Re_s, 2 % at 0.1.
//! - Re_γ ≤ 0.1: the inertial drift of Jeffery orbits and the Saffman lift grow as Re_γ and
//!   Re_γ^{1/2} (Einarsson et al. 2015; Saffman 1965); at 0.1 the orbit drift per period is a few
//!   per cent of the Jeffery dynamics.
//! - r₁/ℓ_w ≤ 0.1, ℓ_w the barycentre's distance to the nearest boundary: the wall correction of
//!   the drag of a sphere of radius a at distance ℓ is (9/16) a/ℓ (Lorentz/Faxén), 5.6 % at 0.1.
//! - r₁/ℓ_u ≤ 0.1, ℓ_u = |u|/|∇u| (Frobenius norm): the velocity changes across the particle by
//!   r₁|∇u| against |u|. This is a crude scale: at a stagnation point or vortex centre |u| → 0
//!   and the ratio diverges although ∇u may be uniform; the flag says "look", not "wrong".
//!
//! Every quantity is a maximum over the states observed (the driver's accepted steps).
//!
//! # Force terms the run leaves out ([`Omitted`])
//! The paper's barycentre has Stokes drag and reduced gravity only; [`crate::hydro::forces`]
//! has the terms beyond it. Every registered term with an estimate
//! ([`crate::hydro::forces::Omission`]) that the particle does not carry is estimated from the
//! run's numbers, as the relative change it would make to the slip u − v, the drag or the
//! response time, and flagged above [`Thresholds::omitted_term`] (1 %). The monitor iterates
//! the registry; each estimate and its argument are in the term's file:
//! [`undisturbed`](crate::hydro::forces::undisturbed) (the quasi-steady slip),
//! [`added_mass`](crate::hydro::forces::added_mass) (the response time, from the rest shape),
//! [`schiller_naumann`](crate::hydro::forces::schiller_naumann) (the finite-Re drag, for a
//! particle with no finite-Re correction), [`saffman_mei`](crate::hydro::forces::saffman_mei)
//! (the shear lift over the drag) and [`cunningham`](crate::hydro::forces::cunningham) (gas slip,
//! from d_eq and the fluid).
//!
//! # The slow manifold ([`Validity::integrator`])
//! A stiff elastic particle stepped by the slow-manifold model ([`crate::integrator::manifold`])
//! has its shape slaved to the local flow where the expansion ratio δ (the flow's rates over
//! the particle's elastic relaxation rate) is at most δ_max = √rtol; its dropped terms are
//! O(δ²), the full model's own tolerance at δ_max. The diagnostics state the largest δ of an
//! accepted step on the manifold against δ_max, so a user sees how close to its bound the
//! reduced model ran, and flag `manifold_ratio` if it ever ran above it, which the switch
//! excludes (it discards such a step and takes it again with the full model): the flag
//! checks that invariant. The monitor sees the accepted steps, not the integrator's step
//! memory, so the caller that ran the particle adds the integrator's report
//! ([`Validity::with_integrator`]).
//!
//! # Unbounded linear flows
//! In the shear scenes ([`Monitor::in_linear_flow`]) there is no wall and u is exactly linear
//! across a particle of any size, so both length-scale ratios are 0 by construction; the
//! Reynolds numbers are those of the particle's fluid (in the shear units μ_f = 1, ρ_f = ρ*,
//! so Re_γ = ρ*: for inertialess runs ρ* is a placeholder of a model that assumes Re → 0, and
//! the scenes report their inertialess runs with [`Validity::inertialess`]).

use crate::contact::{Boundary, Extent, Unbounded};
use crate::driver::AcceptedStep;
use crate::flow::FlowField;
use crate::flow::FlowSample;
use crate::flow::analytic::LinearFlow;
use crate::hydro::DragModel;
use crate::hydro::forces::omission::{self, Observed, Rest, Size, StateEstimate};
use crate::integrator::IntegratorReport;
use crate::material::Response;
use crate::particle::{Particle, State};
use crate::tensor::sym;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// Limits beyond which a [`Validity`] quantity is flagged (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Thresholds {
    /// Largest shear Reynolds number γ̇ d²/ν.
    pub re_shear: f64,
    /// Largest slip Reynolds number |u − v| d/ν.
    pub re_slip: f64,
    /// Largest r₁ over the barycentre's distance to the nearest boundary.
    pub r1_over_wall_distance: f64,
    /// Largest r₁ over the flow length scale |u|/|∇u|.
    pub r1_over_flow_scale: f64,
    /// Largest size of a force term left out ([`Omitted`]).
    pub omitted_term: f64,
}

impl Default for Thresholds {
    fn default() -> Self {
        Self {
            re_shear: 0.1,
            re_slip: 0.1,
            r1_over_wall_distance: 0.1,
            r1_over_flow_scale: 0.1,
            omitted_term: 0.01,
        }
    }
}

/// Sizes of the force terms a run left out (module docs), each the largest over the run, by
/// term name in the order of [`crate::hydro::forces::Omission::order`]; zero for the terms the
/// particle carries. In JSON, an object from term name to size, read back in the monitor's
/// order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Omitted(Vec<(String, f64)>);

impl Omitted {
    /// The terms and their sizes, by the names of [`crate::hydro::forces::by_name`].
    pub fn sizes(&self) -> impl Iterator<Item = (&str, f64)> {
        self.0.iter().map(|(name, size)| (name.as_str(), *size))
    }

    /// The size of the term `name`, if estimated.
    pub fn size(&self, name: &str) -> Option<f64> {
        self.sizes().find(|(n, _)| *n == name).map(|(_, size)| size)
    }

    /// The larger of the two sizes of each term; a term estimated in one only keeps its size.
    fn max(mut self, other: &Self) -> Self {
        for (name, size) in other.sizes() {
            match self.0.iter_mut().find(|(n, _)| n == name) {
                Some((_, mine)) => *mine = mine.max(size),
                None => self.0.push((name.to_string(), size)),
            }
        }
        self
    }

    /// The same terms, each of size 0.
    fn zeroed(mut self) -> Self {
        self.0.iter_mut().for_each(|(_, size)| *size = 0.0);
        self
    }
}

impl Serialize for Omitted {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_map(self.sizes().map(|(name, size)| (name, Extended(size))))
    }
}

impl<'de> Deserialize<'de> for Omitted {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Sizes;
        impl<'de> serde::de::Visitor<'de> for Sizes {
            type Value = Omitted;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a table of force-term names and sizes")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<Omitted, A::Error> {
                let mut sizes = Vec::new();
                while let Some((name, Extended(size))) = map.next_entry::<String, Extended>()? {
                    sizes.push((name, size));
                }
                // In the monitor's order, whatever the text's (a `serde_json::Value` sorts its
                // keys by name); names no term registers here go last, by name.
                let order = omission::estimated();
                sizes.sort_by_cached_key(|(name, _)| {
                    let rank = order.iter().position(|(term, _)| term.name == name);
                    (rank.unwrap_or(order.len()), name.clone())
                });
                Ok(Omitted(sizes))
            }
        }
        d.deserialize_map(Sizes)
    }
}

/// An f64 that keeps its infinities in JSON ([`extended`]).
#[derive(Serialize, Deserialize)]
struct Extended(#[serde(with = "extended")] f64);

/// The particle's numbers as the estimates of omitted terms take them.
fn rest<M: Response, D: DragModel>(particle: &Particle<M, D>) -> Rest {
    let fluid = particle.fluid();
    let semi_axes = particle.shape().semi_axes();
    Rest {
        semi_axes,
        d_eq: 2.0 * semi_axes.product().cbrt(),
        mu_f: fluid.mu,
        rho_f: fluid.rho,
        nu: fluid.mu / fluid.rho,
        rho_p: particle.rho_solid(),
        mass: particle.mass(),
        volume0: particle.volume0(),
        gravity: *particle.gravity(),
    }
}

/// The sizes of the terms of a particle that do not change during a run
/// ([`Size::Constant`]: added mass from its rest shape and densities, gas slip from its size
/// and fluid); zero for the terms it carries and for those estimated state by state.
pub fn omitted_constants<M: Response, D: DragModel>(particle: &Particle<M, D>) -> Omitted {
    omitted_from_rest(particle, |size| match size {
        Size::Constant(size) => Some(*size),
        _ => None,
    })
}

/// What a scene can say of the terms a particle leaves out before any run: the constant sizes
/// of [`omitted_constants`] and, for the terms estimated state by state, the bound each
/// registration gives from the particle alone ([`Size::PerStateBounded`]: the undisturbed-flow
/// force's density ratio ρ_f/ρ_p); zero for the terms the particle carries and for those with
/// neither. The validity monitor does not take these bounds: it observes the run.
pub fn omitted_before_run<M: Response, D: DragModel>(particle: &Particle<M, D>) -> Omitted {
    omitted_from_rest(particle, Size::before_run)
}

/// Each registered estimate's size from the particle alone, by the estimate `pick` takes of
/// it; zero for the terms the particle carries and where `pick` takes none.
fn omitted_from_rest<M: Response, D: DragModel>(
    particle: &Particle<M, D>,
    pick: impl Fn(&Size) -> Option<fn(&Rest) -> f64>,
) -> Omitted {
    let rest = rest(particle);
    Omitted(
        omission::estimated()
            .into_iter()
            .map(|(term, o)| {
                let size = match pick(&o.size) {
                    Some(size) if !term.carried(particle.forces()) => size(&rest),
                    _ => 0.0,
                };
                (term.name.to_string(), size)
            })
            .collect(),
    )
}

/// Maxima over a run (0 before any state is observed).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Validity {
    /// max γ̇ d_eq²/ν.
    #[serde(with = "extended")]
    pub max_re_shear: f64,
    /// max |u − v| d_eq/ν.
    #[serde(with = "extended")]
    pub max_re_slip: f64,
    /// max r₁ (units of the run).
    #[serde(with = "extended")]
    pub max_r1: f64,
    /// max r₁/ℓ_w (ℓ_w: barycentre distance to the nearest boundary; ∞ on or beyond it).
    #[serde(with = "extended")]
    pub max_r1_over_wall_distance: f64,
    /// max r₁|∇u|/|u| (∞ where u = 0 and ∇u ≠ 0).
    #[serde(with = "extended")]
    pub max_r1_over_flow_scale: f64,
    /// States observed.
    pub states: u64,
    /// States at which the flow could not be sampled (left out of the maxima).
    pub unsampled: u64,
    /// Sizes of the force terms the run left out.
    pub omitted: Omitted,
    /// What the integrator did (module docs): the slow-manifold switch's steps, switches, the
    /// largest δ on the manifold and δ_max, where the slow-manifold integrator stepped the
    /// particle. Not among the CSV cells ([`Self::COLUMNS`]), only in the flags; in the JSON
    /// under its earlier name `manifold`, absent where empty.
    #[serde(rename = "manifold", default, skip_serializing_if = "IntegratorReport::is_empty")]
    pub integrator: IntegratorReport,
}

impl Validity {
    /// The same maxima for a run of the inertialess model, which assumes creeping flow: both
    /// Reynolds numbers are 0 by the model's assumption, not by measurement, and so is every
    /// fluid-inertia term (its fluid density is a placeholder).
    pub fn inertialess(self) -> Self {
        Self {
            max_re_shear: 0.0,
            max_re_slip: 0.0,
            omitted: self.omitted.zeroed(),
            ..self
        }
    }

    /// The same with the integrator's `report` of the run
    /// ([`crate::integrator::TimeIntegrator::report`] of its step memory).
    pub fn with_integrator(self, report: IntegratorReport) -> Self {
        Self {
            integrator: report,
            ..self
        }
    }

    /// The maxima over two runs (e.g. the two runs bracketing a phase boundary); the
    /// integrator reports combined ([`IntegratorReport::combine`]).
    pub fn combine(self, other: Self) -> Self {
        Self {
            max_re_shear: self.max_re_shear.max(other.max_re_shear),
            max_re_slip: self.max_re_slip.max(other.max_re_slip),
            max_r1: self.max_r1.max(other.max_r1),
            max_r1_over_wall_distance: self.max_r1_over_wall_distance.max(other.max_r1_over_wall_distance),
            max_r1_over_flow_scale: self.max_r1_over_flow_scale.max(other.max_r1_over_flow_scale),
            states: self.states + other.states,
            unsampled: self.unsampled + other.unsampled,
            omitted: self.omitted.max(&other.omitted),
            integrator: self.integrator.combine(other.integrator),
        }
    }

    /// Names of the thresholds crossed, in the order of [`Thresholds`]' fields, then
    /// `omits_<term>` for every force term left out whose size crosses
    /// [`Thresholds::omitted_term`], then the integrator's own bounds crossed
    /// ([`IntegratorReport::flags`]: `manifold_ratio` if an accepted step on the slow manifold
    /// ran above its own bound δ_max; module docs).
    pub fn flags(&self, limits: &Thresholds) -> Vec<String> {
        let omitted = self
            .omitted
            .sizes()
            .filter(|(_, size)| !(*size <= limits.omitted_term))
            .map(|(name, _)| format!("omits_{name}"));
        [
            ("re_shear", self.max_re_shear > limits.re_shear),
            ("re_slip", self.max_re_slip > limits.re_slip),
            (
                "r1_over_wall_distance",
                self.max_r1_over_wall_distance > limits.r1_over_wall_distance,
            ),
            (
                "r1_over_flow_scale",
                self.max_r1_over_flow_scale > limits.r1_over_flow_scale,
            ),
        ]
        .into_iter()
        .filter(|(_, crossed)| *crossed)
        .map(|(name, _)| name.to_string())
        .chain(omitted)
        .chain(self.integrator.flags().map(str::to_string))
        .collect()
    }

    /// [`Self::flags`] joined by `;` (empty if none), for a CSV cell.
    pub fn flag_text(&self, limits: &Thresholds) -> String {
        self.flags(limits).join(";")
    }

    /// CSV header of [`Self::cells`].
    pub const COLUMNS: [&'static str; 6] = [
        "max_re_shear",
        "max_re_slip",
        "max_r1",
        "max_r1_over_wall_distance",
        "max_r1_over_flow_scale",
        "validity_flags",
    ];

    /// The maxima and the flags as CSV cells in [`Self::COLUMNS`] order (4 significant digits).
    pub fn cells(&self, limits: &Thresholds) -> Vec<String> {
        let g = |v: f64| format!("{v:.4e}");
        vec![
            g(self.max_re_shear),
            g(self.max_re_slip),
            g(self.max_r1),
            g(self.max_r1_over_wall_distance),
            g(self.max_r1_over_flow_scale),
            self.flag_text(limits),
        ]
    }
}

/// Watches one particle in one flow and boundary; feed it from the driver's `on_step`
/// ([`Monitor::observe_step`]).
pub struct Monitor<'a, M, D, F: ?Sized, B: ?Sized> {
    particle: &'a Particle<M, D>,
    flow: &'a F,
    boundary: &'a B,
    /// The flow is homogeneous (linear in x): r₁/ℓ_u is 0 whatever the particle's size.
    linear: bool,
    /// The particle's numbers for the estimates of omitted terms.
    rest: Rest,
    /// The estimates taken state by state, each with its place in `validity.omitted`: the
    /// registered [`Size::PerState`] estimates of the terms the particle does not carry.
    per_state: Vec<(usize, StateEstimate)>,
    validity: Validity,
}

impl<'a, M, D> Monitor<'a, M, D, LinearFlow, Unbounded>
where
    M: Response,
    D: DragModel,
{
    /// A monitor for an unbounded linear flow (see the module docs).
    pub fn in_linear_flow(particle: &'a Particle<M, D>, flow: &'a LinearFlow) -> Self {
        Self {
            linear: true,
            ..Monitor::new(particle, flow, &Unbounded)
        }
    }
}

impl<'a, M, D, F, B> Monitor<'a, M, D, F, B>
where
    M: Response,
    D: DragModel,
    F: FlowField + ?Sized,
    B: Boundary + ?Sized,
{
    /// A monitor with nothing observed yet; d_eq from the rest shape, ν = μ_f/ρ_f.
    pub fn new(particle: &'a Particle<M, D>, flow: &'a F, boundary: &'a B) -> Self {
        let rest = rest(particle);
        // omitted_constants lists the same estimates in the same order: index i is term i.
        let per_state = omission::estimated()
            .into_iter()
            .enumerate()
            .filter_map(|(i, (term, o))| match o.size {
                _ if term.carried(particle.forces()) => None,
                size => size.per_state().map(|at| (i, at)),
            })
            .collect();
        Self {
            particle,
            flow,
            boundary,
            linear: false,
            rest,
            per_state,
            validity: Validity {
                omitted: omitted_constants(particle),
                ..Validity::default()
            },
        }
    }

    /// Take `state` into the maxima, sampling the flow and building the frame there.
    pub fn observe(&mut self, state: &State) {
        let sample = self.flow.sample(&state.x, state.t);
        let r1 = self.particle.frame(&state.f).r[0];
        self.take(state, sample.as_ref().ok(), r1);
    }

    /// Take the end state of an accepted step into the maxima, with the frame and flow sample
    /// the driver shows ([`AcceptedStep`]): the same maxima as [`Self::observe`] of its state,
    /// without a second sample or frame.
    ///
    /// The distance to the nearest boundary is still this monitor's own query: ℓ_w is the
    /// barycentre's distance, a point query, while the contact event measures the gap of the
    /// particle's extent, and far from mesh walls asks for no gap at all but a lower bound of
    /// the distance to every face ([`crate::contact::ContactEvent`]). That bound cannot stand in
    /// for ℓ_w: over a ridge the point gap is the distance to the plane of the nearest face,
    /// which lies below the distance to the face, so a maximum skipped on the bound could differ
    /// from the one queried.
    pub fn observe_step(&mut self, step: &AcceptedStep) {
        self.take(step.state(), step.flow().ok(), step.frame().r[0]);
    }

    /// Take `state` into the maxima, with the flow `sample` there (`None`: unsampled) and its
    /// longest semi-axis `r1`.
    fn take(&mut self, state: &State, sample: Option<&FlowSample>, r1: f64) {
        let v = &mut self.validity;
        v.states += 1;
        let Some(sample) = sample else {
            v.unsampled += 1;
            return;
        };
        let d = sym(&sample.grad_u);
        let shear_rate = (2.0 * d.component_mul(&d).sum()).sqrt();
        let wall = self.boundary.nearest(&state.x, &Extent::Point { radius: 0.0 }).gap;
        let ratio = |num: f64, den: f64| if den > 0.0 { num / den } else { f64::INFINITY };
        let re_shear = shear_rate * self.rest.d_eq * self.rest.d_eq / self.rest.nu;
        let re_slip = (sample.u - state.v).norm() * self.rest.d_eq / self.rest.nu;
        v.max_re_shear = v.max_re_shear.max(re_shear);
        v.max_re_slip = v.max_re_slip.max(re_slip);
        v.max_r1 = v.max_r1.max(r1);
        v.max_r1_over_wall_distance = v.max_r1_over_wall_distance.max(ratio(r1, wall));
        let grad = sample.grad_u.norm();
        if grad > 0.0 && !self.linear {
            v.max_r1_over_flow_scale = v.max_r1_over_flow_scale.max(ratio(r1 * grad, sample.u.norm()));
        }
        self.estimate_omitted(state, sample, re_slip);
    }

    /// The state-dependent sizes of the terms left out (module docs).
    fn estimate_omitted(&mut self, state: &State, sample: &FlowSample, re_slip: f64) {
        let at = Observed {
            det_f: state.det_f(),
            flow: sample,
            re_slip,
        };
        let sizes = &mut self.validity.omitted.0;
        for &(i, size) in &self.per_state {
            sizes[i].1 = sizes[i].1.max(size(&self.rest, &at));
        }
    }

    /// The maxima so far.
    pub fn validity(&self) -> Validity {
        self.validity.clone()
    }
}

/// f64 in JSON with its infinities: a maximum such as r₁/ℓ_w is ∞ on a wall, which JSON
/// numbers cannot hold (serde_json writes it as null); non-finite values are written as the
/// strings `inf`, `-inf` and `NaN`, so a record of a run keeps them
/// ([`crate::population::observe`]).
mod extended {
    use serde::{Deserialize, Deserializer, Serializer};

    pub(super) fn serialize<S: Serializer>(value: &f64, s: S) -> Result<S::Ok, S::Error> {
        match value {
            v if v.is_finite() => s.serialize_f64(*v),
            v if v.is_nan() => s.serialize_str("NaN"),
            v if *v > 0.0 => s.serialize_str("inf"),
            _ => s.serialize_str("-inf"),
        }
    }

    pub(super) fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Value {
            Number(f64),
            Text(String),
        }
        match Value::deserialize(d)? {
            Value::Number(v) => Ok(v),
            Value::Text(t) => match t.as_str() {
                "inf" => Ok(f64::INFINITY),
                "-inf" => Ok(f64::NEG_INFINITY),
                "NaN" => Ok(f64::NAN),
                _ => Err(serde::de::Error::custom(format!("`{t}` is not a number"))),
            },
        }
    }
}

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
//! has the terms beyond it. For each term the particle does not carry, the monitor estimates
//! its size from the run's numbers, as the relative change it would make to the slip u − v
//! (or to the response time), and flags it above [`Thresholds::omitted_term`] (1 %):
//! - undisturbed flow: in quasi-steady slip (v̇ ≈ Du/Dt) the drag balances
//!   m Du/Dt − (m − m_f) g without the term and (m − m_f)(Du/Dt − g) with it (added mass
//!   cancels there), so omitting it changes the slip by m_f|Du/Dt| / |(m − m_f)(Du/Dt − g)| —
//!   about ρ_f/(ρ_p − ρ_f) where the flow's acceleration dominates gravity (2 000 for the
//!   cavity's particle), ρ_f/ρ_p·|Du/Dt|/g where gravity dominates;
//! - added mass: the response time m/(c μ_f K) grows by M_a/m, at most (ρ_f/ρ_p) max k_i with
//!   Lamb's coefficients of the rest shape (½ ρ_f/ρ_p for a sphere);
//! - finite-Re drag (neither `schiller_naumann` nor `holzer_sommerfeld` on): Schiller–Naumann's
//!   0.15 Re_s^{0.687} with the slip Reynolds number;
//! - shear lift: the lift of [`SaffmanMei`] over the Stokes drag,
//!   1.615 d²√(ρ_f μ_f |ω|)|w| C / (3π μ_f d |w|) = 0.171 Re_ω^{1/2} C with Re_ω = |ω| d²/ν and
//!   the term's own C = [`SaffmanMei::lift_ratio`]`(Re_s, Re_ω)`: McLaughlin's J*(ε) where the
//!   slip competes with the shear (ε = Re_ω^{1/2}/Re_s of order 1 or smaller), Mei's decay at
//!   larger Re_s, Saffman's C = 1 as the slip vanishes (ε → ∞). Saffman's limit alone
//!   overstated the lift 1.4× at ε = 1 and 19× at ε = 0.3;
//! - gas slip: Cunningham's C_c − 1 at d_eq for a gas in SI units (ρ_f < [`GAS_DENSITY`] and
//!   μ_f < [`GAS_VISCOSITY`]; a scene in shear units is not read as a gas), with the mean free
//!   path λ = μ_f/(0.499 ρ_f c̄) of kinetic theory and air's mean molecular speed c̄ = 463 m/s at
//!   20 °C (the run's gas is assumed to be air-like; 66 nm for air at 1 atm).
//!
//! # Unbounded linear flows
//! In the shear scenes ([`Monitor::in_linear_flow`]) there is no wall and u is exactly linear
//! across a particle of any size, so both length-scale ratios are 0 by construction; the
//! Reynolds numbers are those of the particle's fluid (in the shear units μ_f = 1, ρ_f = ρ*,
//! so Re_γ = ρ*: for inertialess runs ρ* is a placeholder of a model that assumes Re → 0, and
//! the scenes report their inertialess runs with [`Validity::inertialess`]).

use crate::contact::{Boundary, Extent, Unbounded};
use crate::ellipsoid::EllipsoidIntegrals;
use crate::flow::FlowField;
use crate::flow::analytic::LinearFlow;
use crate::hydro::DragModel;
use crate::hydro::forces::{
    AddedMass, Cunningham, HolzerSommerfeld, SaffmanMei, SchillerNaumann, UndisturbedFlow, added_mass,
    saffman_mei::vorticity,
};
use crate::material::Response;
use crate::particle::{Particle, State};
use crate::tensor::sym;
use serde::{Deserialize, Serialize};

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

/// Fluids lighter than this (kg/m³) are gases for the slip estimate: gases at ordinary
/// pressures are below 10, liquids above 500.
pub const GAS_DENSITY: f64 = 10.0;

/// Fluids more viscous than this (Pa s) are not gases for the slip estimate: gases are
/// 1–3·10⁻⁵ Pa s, liquids 2·10⁻⁴ and up, and a scene in nondimensional units (μ_f = 1 in the
/// shear scenes) is not read as SI.
pub const GAS_VISCOSITY: f64 = 1e-4;

/// Mean molecular speed of air at 20 °C, c̄ = √(8RT/(πM)) (m/s), for the mean free path of a gas.
pub const AIR_MOLECULAR_SPEED: f64 = 463.0;

/// Sizes of the force terms a run left out (module docs), each the largest over the run; zero
/// for the terms the particle carries.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Omitted {
    /// Undisturbed-flow force: relative change of the quasi-steady slip.
    #[serde(with = "extended")]
    pub undisturbed_flow: f64,
    /// Added mass: relative change of the response time.
    #[serde(with = "extended")]
    pub added_mass: f64,
    /// Finite-Re drag: relative change of the drag.
    #[serde(with = "extended")]
    pub schiller_naumann: f64,
    /// Shear lift over the drag.
    #[serde(with = "extended")]
    pub saffman_mei: f64,
    /// Gas slip: C_c − 1.
    #[serde(with = "extended")]
    pub cunningham: f64,
}

impl Omitted {
    /// The terms and their sizes, by the names of [`crate::hydro::forces::by_name`].
    pub fn sizes(&self) -> [(&'static str, f64); 5] {
        [
            (UndisturbedFlow::NAME, self.undisturbed_flow),
            (AddedMass::NAME, self.added_mass),
            (SchillerNaumann::NAME, self.schiller_naumann),
            (SaffmanMei::NAME, self.saffman_mei),
            (Cunningham::NAME, self.cunningham),
        ]
    }

    fn max(self, other: Self) -> Self {
        Self {
            undisturbed_flow: self.undisturbed_flow.max(other.undisturbed_flow),
            added_mass: self.added_mass.max(other.added_mass),
            schiller_naumann: self.schiller_naumann.max(other.schiller_naumann),
            saffman_mei: self.saffman_mei.max(other.saffman_mei),
            cunningham: self.cunningham.max(other.cunningham),
        }
    }
}

/// The sizes of the terms of a particle that do not change during a run: added mass from its
/// rest shape and densities, gas slip from its size and fluid (module docs); zero for the terms
/// it carries.
pub fn omitted_constants<M: Response, D: DragModel>(particle: &Particle<M, D>) -> Omitted {
    let on = particle.forces().names();
    let off = |name: &str| !on.contains(&name);
    let fluid = particle.fluid();
    let semi_axes = particle.shape().semi_axes();
    let d_eq = 2.0 * semi_axes.product().cbrt();
    let k_max = EllipsoidIntegrals::try_new(&semi_axes).map_or(f64::NAN, |ints| added_mass::coefficients(&ints).max());
    let gas = fluid.rho > 0.0 && fluid.rho < GAS_DENSITY && fluid.mu < GAS_VISCOSITY;
    let slip = || {
        let lambda = fluid.mu / (0.499 * fluid.rho * AIR_MOLECULAR_SPEED);
        Cunningham::new(lambda).map_or(0.0, |c| c.correction(d_eq) - 1.0)
    };
    Omitted {
        added_mass: if off(AddedMass::NAME) {
            fluid.rho / particle.rho_solid() * k_max
        } else {
            0.0
        },
        cunningham: if off(Cunningham::NAME) && gas { slip() } else { 0.0 },
        ..Omitted::default()
    }
}

/// Maxima over a run (0 before any state is observed).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
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
}

impl Validity {
    /// The same maxima for a run of the inertialess model, which assumes creeping flow: both
    /// Reynolds numbers are 0 by the model's assumption, not by measurement, and so is every
    /// fluid-inertia term (its fluid density is a placeholder).
    pub fn inertialess(self) -> Self {
        Self {
            max_re_shear: 0.0,
            max_re_slip: 0.0,
            omitted: Omitted::default(),
            ..self
        }
    }

    /// The maxima over two runs (e.g. the two runs bracketing a phase boundary).
    pub fn combine(self, other: Self) -> Self {
        Self {
            max_re_shear: self.max_re_shear.max(other.max_re_shear),
            max_re_slip: self.max_re_slip.max(other.max_re_slip),
            max_r1: self.max_r1.max(other.max_r1),
            max_r1_over_wall_distance: self.max_r1_over_wall_distance.max(other.max_r1_over_wall_distance),
            max_r1_over_flow_scale: self.max_r1_over_flow_scale.max(other.max_r1_over_flow_scale),
            states: self.states + other.states,
            unsampled: self.unsampled + other.unsampled,
            omitted: self.omitted.max(other.omitted),
        }
    }

    /// Names of the thresholds crossed, in the order of [`Thresholds`]' fields, then
    /// `omits_<term>` for every force term left out whose size crosses
    /// [`Thresholds::omitted_term`].
    pub fn flags(&self, limits: &Thresholds) -> Vec<String> {
        let omitted = self
            .omitted
            .sizes()
            .into_iter()
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

/// Watches one particle in one flow and boundary; feed it from the driver's `on_step`.
pub struct Monitor<'a, M, D, F: ?Sized, B: ?Sized> {
    particle: &'a Particle<M, D>,
    flow: &'a F,
    boundary: &'a B,
    d_eq: f64,
    nu: f64,
    /// The flow is homogeneous (linear in x): r₁/ℓ_u is 0 whatever the particle's size.
    linear: bool,
    /// Which of the estimated terms the particle carries (no estimate then).
    carries: Carries,
    validity: Validity,
}

/// The state-dependent terms a particle carries.
#[derive(Debug, Clone, Copy)]
struct Carries {
    undisturbed_flow: bool,
    schiller_naumann: bool,
    saffman_mei: bool,
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
        let fluid = particle.fluid();
        let on = particle.forces().names();
        Self {
            particle,
            flow,
            boundary,
            d_eq: 2.0 * particle.shape().semi_axes().product().cbrt(),
            nu: fluid.mu / fluid.rho,
            linear: false,
            carries: Carries {
                undisturbed_flow: on.contains(&UndisturbedFlow::NAME),
                schiller_naumann: on.contains(&SchillerNaumann::NAME) || on.contains(&HolzerSommerfeld::NAME),
                saffman_mei: on.contains(&SaffmanMei::NAME),
            },
            validity: Validity {
                omitted: omitted_constants(particle),
                ..Validity::default()
            },
        }
    }

    /// Take `state` into the maxima.
    pub fn observe(&mut self, state: &State) {
        let v = &mut self.validity;
        v.states += 1;
        let Ok(sample) = self.flow.sample(&state.x, state.t) else {
            v.unsampled += 1;
            return;
        };
        let r1 = self.particle.frame(&state.f).r[0];
        let d = sym(&sample.grad_u);
        let shear_rate = (2.0 * d.component_mul(&d).sum()).sqrt();
        let wall = self.boundary.nearest(&state.x, &Extent::Point { radius: 0.0 }).gap;
        let ratio = |num: f64, den: f64| if den > 0.0 { num / den } else { f64::INFINITY };
        let re_shear = shear_rate * self.d_eq * self.d_eq / self.nu;
        let re_slip = (sample.u - state.v).norm() * self.d_eq / self.nu;
        v.max_re_shear = v.max_re_shear.max(re_shear);
        v.max_re_slip = v.max_re_slip.max(re_slip);
        v.max_r1 = v.max_r1.max(r1);
        v.max_r1_over_wall_distance = v.max_r1_over_wall_distance.max(ratio(r1, wall));
        let grad = sample.grad_u.norm();
        if grad > 0.0 && !self.linear {
            v.max_r1_over_flow_scale = v.max_r1_over_flow_scale.max(ratio(r1 * grad, sample.u.norm()));
        }
        self.estimate_omitted(state, &sample, re_slip);
    }

    /// The state-dependent sizes of the terms left out (module docs).
    fn estimate_omitted(&mut self, state: &State, sample: &crate::flow::FlowSample, re_slip: f64) {
        let p = self.particle;
        let o = &mut self.validity.omitted;
        if !self.carries.undisturbed_flow {
            let m_f = p.fluid().rho * p.volume0() * state.det_f();
            let du_dt = sample.material_acceleration();
            let driving = (du_dt - p.gravity()) * (p.mass() - m_f);
            let ratio = match (m_f * du_dt.norm(), driving.norm()) {
                (0.0, _) => 0.0,
                (num, den) if den > 0.0 => num / den,
                _ => f64::INFINITY,
            };
            o.undisturbed_flow = o.undisturbed_flow.max(ratio);
        }
        if !self.carries.schiller_naumann {
            o.schiller_naumann = o.schiller_naumann.max(SchillerNaumann::factor(re_slip) - 1.0);
        }
        if !self.carries.saffman_mei {
            let re_omega = vorticity(&sample.grad_u).norm() * self.d_eq * self.d_eq / self.nu;
            let lift =
                1.615 / (3.0 * std::f64::consts::PI) * re_omega.sqrt() * SaffmanMei::lift_ratio(re_slip, re_omega);
            o.saffman_mei = o.saffman_mei.max(lift);
        }
    }

    /// The maxima so far.
    pub fn validity(&self) -> Validity {
        self.validity
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

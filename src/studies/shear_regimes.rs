//! Tumbling (TU) / trembling (TR) classification in simple shear (paper §6.1).
//!
//! # Criterion (paper §6.1)
//! l_a and l_c are the lengths of the material lines through the points A and C initially on
//! the in-shear-plane semi-axes, A on the longer one. The particle **trembles** if l_c > l_a
//! at any time and **tumbles** otherwise. We also return the margin m = min_t (l_a − l_c):
//! m > 0 is TU, m < 0 is TR, and |m| says how far the shape is from the boundary.
//!
//! # Horizon and dense checking (paper §6.1)
//! The motion is quasi-periodic with a shape period of about half a Jeffery period π(r + 1/r)
//! (r the in-plane aspect ratio; ≈ 10 for the oblate 2.5 at Ca 0.4–0.5, where the minimum of
//! l_a − l_c falls at t̂ ≈ 3.5 and recurs every period to within ~1e-3). For elongated shapes
//! the minima drift slowly from period to period: next to the boundary the oblate 5
//! (Ca = 0.9715) reaches its smallest l_a − l_c only after ≈ 5.1 half periods (t̂ ≈ 83) and
//! the triaxial (1, 0.1, 0.5) (Ca = 1.617) after ≈ 3.7 (t̂ ≈ 117); with 3.5 half periods both
//! boundaries came out one ΔCa = 0.001 step too high, while 7, 10 and 20 half periods give
//! identical minima. The default horizon is therefore T = max(30, 8 π(r + 1/r)).
//! Every accepted step is checked, and inside each step l_a − l_c is evaluated at `substeps`
//! interior points of the step's dense output (the driver's cubic Hermite interpolant of F,
//! [`crate::integrator::Dense`]), on which ξ = FΞ is linear. Wherever a sample undercuts the
//! Every local minimum of the samples is refined by a golden-section search on the dense
//! output between its neighbouring samples. Sampling a smooth minimum at spacing δ alone would miss it by up
//! to ½|m″|(δ/2)² (≈ 2.5e-5 at the step ends of a Rosenbrock run at rtol 1e-6, more with
//! Radau's longer steps); after refinement what remains is the interpolant's error, O(h⁴)
//! and below the integration tolerance, so the margin is resolved well below the
//! 1e-5 – 1e-4 margins met next to the boundary at ΔCa ≤ 1e-4 (sensitivity ≈ 0.6 ΔCa).
//! The integrator is Radau IIA(5) ([`Scheme::Radau5`]): at rtol 1e-7 it gives the same
//! Fig. 7/8 brackets as the Rosenbrock 2(3) pair at ΔCa ≤ 1e-3 and the same brackets as
//! itself at 1e-8 at ΔCa ≤ 1e-4, in about half the time.

use super::StudyError;
use super::shear_run::unit_shear;
use super::shear_shape::ShearShape;
use crate::diagnostics::{Monitor, Validity};
use crate::driver::{Observers, Plan, Problem, RunStats, integrate};
use crate::integrator::Dense;
use crate::integrator::{Scheme, Stokesian, TimeIntegrator};
use crate::material::{LawFactory, NeoHookeFactory};
use crate::particle::{ShearScaling, State};
use crate::tensor::Vec3;
use serde::{Deserialize, Serialize};

/// Dynamic regime of a soft ellipsoid in shear.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Regime {
    /// l_a > l_c at all times.
    Tumbling,
    /// l_c > l_a at some time.
    Trembling,
}

/// Result of one classification run.
#[derive(Debug, Clone, PartialEq)]
pub struct Classification {
    /// TU or TR.
    pub regime: Regime,
    /// min_t (l_a − l_c) over the horizon.
    pub margin: f64,
    /// Time of that minimum.
    pub t_margin: f64,
    /// First time with l_c > l_a (TR only).
    pub first_trembling: Option<f64>,
    /// Horizon used.
    pub horizon: f64,
    /// Work of the run.
    pub stats: RunStats,
    /// Validity diagnostics over the accepted steps, as measured (r₁ in d_eq).
    pub validity: Validity,
}

/// The TU/TR classifier: an integrator, the particles' law, the horizon and checking density.
#[derive(Debug, Clone, Copy)]
pub struct RegimeClassifier<I, L = NeoHookeFactory> {
    /// Time integrator.
    pub integrator: I,
    /// Builds each particle's law from μ_s = 1/Ca and λ_s = (λ_s/μ_s)/Ca.
    pub law: L,
    /// First step (adaptive) or the fixed step.
    pub dt0: f64,
    /// Minimum horizon t̂.
    pub t_min: f64,
    /// Horizon in half Jeffery periods of the in-plane aspect ratio.
    pub periods: f64,
    /// Hermite check points inside each accepted step.
    pub substeps: usize,
}

impl RegimeClassifier<Stokesian> {
    /// Inertialess classifier with rtol = atol = `tol`, horizon max(30, 8 half periods).
    pub fn stokesian(tol: f64) -> Result<Self, crate::error::ParamError> {
        Ok(Self::new(Stokesian::overdamped(tol)?.with_scheme(Scheme::Radau5), 1e-3))
    }
}

impl<I: TimeIntegrator> RegimeClassifier<I> {
    /// Classifier with the default horizon and 4 check points per step.
    pub fn new(integrator: I, dt0: f64) -> Self {
        Self {
            integrator,
            law: NeoHookeFactory,
            dt0,
            t_min: 30.0,
            periods: 8.0,
            substeps: 4,
        }
    }

    /// The same classifier for particles of another law.
    pub fn with_law<L: LawFactory>(self, law: L) -> RegimeClassifier<I, L> {
        RegimeClassifier {
            integrator: self.integrator,
            law,
            dt0: self.dt0,
            t_min: self.t_min,
            periods: self.periods,
            substeps: self.substeps,
        }
    }
}

impl<I: TimeIntegrator, L: LawFactory> RegimeClassifier<I, L> {
    /// Horizon for `shape`.
    pub fn horizon(&self, shape: &ShearShape) -> f64 {
        self.t_min.max(self.periods * shape.rigid_shape_period())
    }

    /// Classify `shape` at the groups `scaling` (Ca, ρ*, λ_s/μ_s).
    pub fn classify(&self, shape: &ShearShape, scaling: &ShearScaling) -> Result<Classification, StudyError> {
        let mu_s = 1.0 / scaling.ca();
        let law = self.law.law(mu_s, scaling.bulk_ratio() * mu_s)?;
        let particle = shape.particle_with(scaling, law)?;
        let (a, c) = shape.in_plane_axes();
        let (xi_a0, xi_c0) = (particle.shape().axis_point(a), particle.shape().axis_point(c));
        let horizon = self.horizon(shape);
        let start = State::at_rest(Vec3::zeros());
        let mut track = MarginTracker::new(&start, xi_a0, xi_c0);
        let mut memory = I::Memory::default();
        let flow = unit_shear();
        let mut monitor = Monitor::in_linear_flow(&particle, &flow);
        monitor.observe(&start);
        let stats = integrate(
            Problem::new(&self.integrator, &particle, &flow),
            start,
            &mut memory,
            &Plan::new(horizon, self.dt0)?,
            &[],
            Observers::none().with_on_step(|step| {
                track.step(step.dense(), self.substeps);
                monitor.observe_step(step);
            }),
        )?
        .stats;
        Ok(Classification {
            regime: if track.first_trembling.is_some() {
                Regime::Trembling
            } else {
                Regime::Tumbling
            },
            margin: track.margin,
            t_margin: track.t_margin,
            first_trembling: track.first_trembling,
            horizon,
            stats,
            validity: monitor.validity(),
        })
    }

    /// Classify at capillary number `ca` (inertia and bulk modulus as in `base`).
    pub fn classify_ca(&self, shape: &ShearShape, ca: f64, base: &ShearScaling) -> Result<Classification, StudyError> {
        self.classify(shape, &ShearScaling::new(ca, base.rho_star(), base.bulk_ratio())?)
    }
}

/// Running minimum of l_a − l_c over accepted steps and their dense output.
struct MarginTracker {
    xi0: (Vec3, Vec3),
    margin: f64,
    t_margin: f64,
    first_trembling: Option<f64>,
    /// The last two samples (t, m), for bracketing local minima.
    last: [(f64, f64); 2],
    /// Dense output of the previous step (a bracket can straddle two steps).
    previous: Option<Dense>,
}

impl MarginTracker {
    fn new(s: &State, xi_a0: Vec3, xi_c0: Vec3) -> Self {
        let mut t = Self {
            xi0: (xi_a0, xi_c0),
            margin: f64::INFINITY,
            t_margin: s.t,
            first_trembling: None,
            last: [(s.t, f64::INFINITY); 2],
            previous: None,
        };
        t.record(s);
        t.last[1] = (s.t, t.margin);
        t
    }

    fn record(&mut self, s: &State) {
        let m = self.margin_at(s);
        if m < self.margin {
            self.margin = m;
            self.t_margin = s.t;
        }
        if m < 0.0 && self.first_trembling.is_none() {
            self.first_trembling = Some(s.t);
        }
    }

    /// Check `substeps` interior points and the end of one step; every local minimum of the
    /// samples (a sample lower than both neighbours) is refined on the dense output.
    fn step(&mut self, dense: &Dense, substeps: usize) {
        let (t0, t1) = (dense.t_start(), dense.t_end());
        for i in 1..=substeps + 1 {
            let s = dense.state_at(t0 + (t1 - t0) * i as f64 / (substeps + 1) as f64);
            self.record(&s);
            let m = self.margin_at(&s);
            let [(ta, ma), (tb, mb)] = self.last;
            if mb < ma && mb <= m {
                self.refine(dense, ta, s.t);
            }
            self.last = [(tb, mb), (s.t, m)];
        }
        self.previous = Some(*dense);
    }

    /// The interpolated state at `t`, from this step's or the previous step's dense output.
    fn state_at(&self, dense: &Dense, t: f64) -> State {
        match &self.previous {
            Some(p) if t < dense.t_start() => p.state_at(t),
            _ => dense.state_at(t),
        }
    }

    /// Golden-section search for the minimum of l_a − l_c in the bracket [a, b]: 40 sections
    /// shrink it by 0.618⁴⁰ ≈ 4e-9, so what remains is the interpolant's own error (O(h⁴),
    /// below the integration tolerance).
    fn refine(&mut self, dense: &Dense, mut a: f64, mut b: f64) {
        const INV_PHI: f64 = 0.618_033_988_749_894_8;
        let mut c = b - INV_PHI * (b - a);
        let mut d = a + INV_PHI * (b - a);
        let mut fc = self.margin_at(&self.state_at(dense, c));
        let mut fd = self.margin_at(&self.state_at(dense, d));
        for _ in 0..40 {
            if fc < fd {
                (b, d, fd) = (d, c, fc);
                c = b - INV_PHI * (b - a);
                fc = self.margin_at(&self.state_at(dense, c));
            } else {
                (a, c, fc) = (c, d, fd);
                d = a + INV_PHI * (b - a);
                fd = self.margin_at(&self.state_at(dense, d));
            }
        }
        let best = self.state_at(dense, if fc < fd { c } else { d });
        self.record(&best);
    }

    fn margin_at(&self, s: &State) -> f64 {
        (s.f * self.xi0.0).norm() - (s.f * self.xi0.1).norm()
    }
}

//! Tumbling (TU) / trembling (TR) classification in simple shear (paper §6.1).
//!
//! # Criterion (paper §6.1)
//! l_a and l_c are the lengths of the material lines through the points A and C initially on
//! the in-shear-plane semi-axes, A on the longer one. The particle **trembles** if l_c > l_a
//! at any time and **tumbles** otherwise. We also return the margin m = min_t (l_a − l_c):
//! m > 0 is TU, m < 0 is TR, and |m| says how far the shape is from the boundary.
//!
//! # Horizon and dense checking (physics.md §9.9)
//! The motion is quasi-periodic with a shape period of about half a Jeffery period π(r + 1/r)
//! (r the in-plane aspect ratio; ≈ 10 for the oblate 2.5 at Ca 0.4–0.5, where the minimum of
//! l_a − l_c falls at t̂ ≈ 3.5 and recurs every period to within ~1e-3). For elongated shapes
//! the minima drift slowly from period to period: next to the boundary the oblate 5
//! (Ca = 0.9715) reaches its smallest l_a − l_c only after ≈ 5.1 half periods (t̂ ≈ 83) and
//! the triaxial (1, 0.1, 0.5) (Ca = 1.617) after ≈ 3.7 (t̂ ≈ 117); with 3.5 half periods both
//! boundaries came out one ΔCa = 0.001 step too high, while 7, 10 and 20 half periods give
//! identical minima. The default horizon is therefore T = max(30, 8 π(r + 1/r)).
//! Every accepted step is checked, and inside each step l_a − l_c is evaluated at `substeps`
//! interior points of the cubic Hermite interpolant of ξ = FΞ built from (F, Ḟ) at both ends.
//! Sampling a smooth minimum at spacing δ misses it by ≤ ½|m''|(δ/2)²: ≈ 2.5e-5 with step ends
//! only (h ≈ 0.027 at rtol 1e-6, tested), 25× less with the default 4 interior points, below
//! the 1e-5–1e-4 margins met next to the boundary. (The first step starts from rest,
//! Ḟ(0) = 0, which only affects the interpolant over the initial 1e-3.)

use super::SceneError;
use super::shear_run::unit_shear;
use super::shear_shape::ShearShape;
use crate::driver::{RunStats, run};
use crate::integrator::{Stokesian, TimeIntegrator};
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
#[derive(Debug, Clone, Copy, PartialEq)]
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
}

/// The TU/TR classifier: an integrator plus the horizon and checking density.
#[derive(Debug, Clone, Copy)]
pub struct RegimeClassifier<I> {
    /// Time integrator.
    pub integrator: I,
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
    pub fn stokesian(tol: f64) -> Self {
        Self::new(Stokesian::overdamped(tol), 1e-3)
    }
}

impl<I: TimeIntegrator> RegimeClassifier<I> {
    /// Classifier with the default horizon and 4 check points per step.
    pub fn new(integrator: I, dt0: f64) -> Self {
        Self {
            integrator,
            dt0,
            t_min: 30.0,
            periods: 8.0,
            substeps: 4,
        }
    }

    /// Horizon for `shape`.
    pub fn horizon(&self, shape: &ShearShape) -> f64 {
        self.t_min.max(self.periods * shape.rigid_shape_period())
    }

    /// Classify `shape` at the groups `scaling` (Ca, ρ*, λ_s/μ_s).
    pub fn classify(&self, shape: &ShearShape, scaling: &ShearScaling) -> Result<Classification, SceneError> {
        let particle = shape.particle(scaling)?;
        let (a, c) = shape.in_plane_axes();
        let (xi_a0, xi_c0) = (particle.shape().axis_point(a), particle.shape().axis_point(c));
        let horizon = self.horizon(shape);
        let start = State::at_rest(Vec3::zeros());
        let mut track = MarginTracker::new(&start, xi_a0, xi_c0);
        let (_, stats) = run(
            &self.integrator,
            &particle,
            start,
            &unit_shear(),
            self.dt0,
            &[horizon],
            |_| {},
            |s, _| track.step(s, self.substeps),
        )?;
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
        })
    }

    /// Classify at capillary number `ca` (inertia and bulk modulus as in `base`).
    pub fn classify_ca(&self, shape: &ShearShape, ca: f64, base: &ShearScaling) -> Result<Classification, SceneError> {
        self.classify(shape, &ShearScaling::new(ca, base.rho_star(), base.bulk_ratio())?)
    }
}

/// Running minimum of l_a − l_c over accepted steps and their Hermite interpolants.
struct MarginTracker {
    xi0: (Vec3, Vec3),
    prev: (f64, [Vec3; 4]),
    margin: f64,
    t_margin: f64,
    first_trembling: Option<f64>,
}

impl MarginTracker {
    fn new(s: &State, xi_a0: Vec3, xi_c0: Vec3) -> Self {
        let mut t = Self {
            xi0: (xi_a0, xi_c0),
            prev: (s.t, [Vec3::zeros(); 4]),
            margin: f64::INFINITY,
            t_margin: s.t,
            first_trembling: None,
        };
        t.prev.1 = t.lines(s);
        t.record(s.t, t.prev.1[0].norm() - t.prev.1[1].norm());
        t
    }

    /// (ξ_a, ξ_c, ξ̇_a, ξ̇_c) of a state.
    fn lines(&self, s: &State) -> [Vec3; 4] {
        [s.f * self.xi0.0, s.f * self.xi0.1, s.a * self.xi0.0, s.a * self.xi0.1]
    }

    fn record(&mut self, t: f64, m: f64) {
        if m < self.margin {
            self.margin = m;
            self.t_margin = t;
        }
        if m < 0.0 && self.first_trembling.is_none() {
            self.first_trembling = Some(t);
        }
    }

    fn step(&mut self, s: &State, substeps: usize) {
        let (t0, p) = self.prev;
        let q = self.lines(s);
        let h = s.t - t0;
        for i in 1..=substeps {
            let u = i as f64 / (substeps + 1) as f64;
            let (h00, h10) = (2.0 * u.powi(3) - 3.0 * u * u + 1.0, u.powi(3) - 2.0 * u * u + u);
            let (h01, h11) = (-2.0 * u.powi(3) + 3.0 * u * u, u.powi(3) - u * u);
            let xa = p[0] * h00 + p[2] * (h * h10) + q[0] * h01 + q[2] * (h * h11);
            let xc = p[1] * h00 + p[3] * (h * h10) + q[1] * h01 + q[3] * (h * h11);
            self.record(t0 + u * h, xa.norm() - xc.norm());
        }
        self.record(s.t, q[0].norm() - q[1].norm());
        self.prev = (s.t, q);
    }
}

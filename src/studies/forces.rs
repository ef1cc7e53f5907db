//! The force terms' verification datasets (`paper-figures/forces/`): Lamb's added-mass
//! coefficients of spheroids and a triaxial ellipsoid, and a sphere settling from rest with
//! fluid inertia, each beside its closed form.
//!
//! # Physics
//! - Added mass: k_i = A_i/(2 − A_i) with A_i = r₁r₂r₃ α_i ([`crate::hydro::forces::added_mass`]);
//!   the dataset lists what the code computes, and the tests compare it with Lamb's spheroid
//!   closed forms and with the integral by quadrature.
//! - Settling: a sphere of diameter d released at rest in quiescent fluid under gravity g, with
//!   added mass and the undisturbed-flow force on, obeys
//!   (m + ½ m_f) v̇ = (m − m_f) g − 3π μ d v, so
//!   ```math
//!   v(t) = v_t\big(1 - e^{-t/\tau}\big),\qquad v_t = \frac{(\rho_p - \rho_f)\,g\,d^2}{18\mu},\qquad
//!   \tau = \frac{(\rho_p + \tfrac12\rho_f)\,d^2}{18\mu}
//!   ```
//!   (Maxey & Riley 1983 without the history force; the paper's model has τ with ρ_p alone).
//!   At ρ_p/ρ_f = 1.0005 the added mass makes τ 1.5× longer, at 0.1 (a light sphere that
//!   rises) 6× longer.

use crate::driver::{Problem, advance};
use crate::ellipsoid::{Ellipsoid, EllipsoidIntegrals};
use crate::error::{ParamError, StepError};
use crate::flow::analytic::Quiescent;
use crate::hydro::Brenner;
use crate::hydro::forces::{AddedMass, ForceTerms, UndisturbedFlow, added_mass};
use crate::integrator::Stokesian;
use crate::material::Rigid;
use crate::output::OutputError;
use crate::output::csv::Csv;
use crate::output::plot::{Figure, Panel, Series};
use crate::particle::{Fluid, Particle, State};
use crate::tensor::{Mat3, Vec3};
use std::sync::Arc;

/// Column names of `added_mass.csv`.
pub const ADDED_MASS_COLUMNS: [&str; 5] = ["a1", "a2", "a3", "axis", "k"];
/// Column names of `settling.csv`.
pub const SETTLING_COLUMNS: [&str; 8] = ["rho_p", "rho_f", "d", "mu", "g", "t", "v_numeric", "v_exact"];

/// Semi-axes of the added-mass dataset: spheroids of aspect ratio 1, 2, 5, 10, prolate
/// (r, 1, 1) and oblate (1, 1, 1/r), and the 3:2:1 ellipsoid.
pub fn added_mass_shapes() -> Vec<Vec3> {
    let mut shapes = vec![Vec3::new(1.0, 1.0, 1.0)];
    for r in [2.0, 5.0, 10.0] {
        shapes.push(Vec3::new(r, 1.0, 1.0));
        shapes.push(Vec3::new(1.0, 1.0, 1.0 / r));
    }
    shapes.push(Vec3::new(3.0, 2.0, 1.0));
    shapes
}

/// One row of `added_mass.csv`: k for translation along semi-axis `axis` (1, 2 or 3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AddedMassRow {
    /// Semi-axes a₁, a₂, a₃.
    pub semi_axes: Vec3,
    /// Axis of translation, 1-based.
    pub axis: usize,
    /// Lamb's coefficient k.
    pub k: f64,
}

/// The added-mass dataset: every shape of [`added_mass_shapes`], all three axes.
pub fn added_mass_table() -> Result<Vec<AddedMassRow>, ParamError> {
    let mut rows = Vec::new();
    for semi_axes in added_mass_shapes() {
        let k = added_mass::coefficients(&EllipsoidIntegrals::try_new(&semi_axes)?);
        rows.extend((0..3).map(|i| AddedMassRow {
            semi_axes,
            axis: i + 1,
            k: k[i],
        }));
    }
    Ok(rows)
}

/// `added_mass.csv`.
pub fn added_mass_csv(rows: &[AddedMassRow]) -> Result<Csv, OutputError> {
    let mut csv = Csv::new(&ADDED_MASS_COLUMNS);
    for r in rows {
        csv.push_numbers(&[r.semi_axes[0], r.semi_axes[1], r.semi_axes[2], r.axis as f64, r.k])?;
    }
    Ok(csv)
}

/// k against the aspect ratio along the symmetry axis and across it, prolate and oblate.
pub fn added_mass_figure(rows: &[AddedMassRow]) -> Figure {
    let series = |label: &str, color: usize, pick: &dyn Fn(&AddedMassRow) -> Option<f64>| {
        let points = rows.iter().filter_map(|r| pick(r).map(|x| (x.log10(), r.k))).collect();
        Series::points(label, points, color)
    };
    // Prolate (r, 1, 1) and oblate (1, 1, 1/r); the sphere is both, the 3:2:1 neither.
    let prolate = |r: &AddedMassRow| r.semi_axes[1] == 1.0 && r.semi_axes[2] == 1.0;
    let oblate = |r: &AddedMassRow| r.semi_axes[0] == 1.0 && r.semi_axes[1] == 1.0;
    let ratio = |r: &AddedMassRow| r.semi_axes[0] / r.semi_axes[2];
    let panel = Panel::new("Added mass of spheroids (Lamb §114–115)", "log10 aspect ratio", "k")
        .with(series("prolate, along the axis", 0, &|r| {
            (prolate(r) && r.axis == 1).then(|| ratio(r))
        }))
        .with(series("prolate, across", 1, &|r| {
            (prolate(r) && r.axis == 2).then(|| ratio(r))
        }))
        .with(series("oblate, along the axis", 2, &|r| {
            (oblate(r) && r.axis == 3).then(|| ratio(r))
        }))
        .with(series("oblate, across", 3, &|r| {
            (oblate(r) && r.axis == 1).then(|| ratio(r))
        }));
    Figure::single(panel)
}

/// One settling case: densities, diameter, viscosity and gravity (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SettlingCase {
    /// Particle density ρ_p.
    pub rho_p: f64,
    /// Fluid density ρ_f.
    pub rho_f: f64,
    /// Diameter d.
    pub d: f64,
    /// Viscosity μ.
    pub mu: f64,
    /// Gravity g (along −z).
    pub g: f64,
}

impl SettlingCase {
    /// The dataset's cases, ρ_p/ρ_f = 1000, 2, 1.0005 and 0.1: a 10 µm droplet in air, and
    /// 100 µm spheres in water.
    pub fn dataset() -> [Self; 4] {
        let water = |ratio: f64| Self {
            rho_p: 1000.0 * ratio,
            rho_f: 1000.0,
            d: 1e-4,
            mu: 1e-3,
            g: 9.81,
        };
        [
            Self {
                rho_p: 1200.0,
                rho_f: 1.2,
                d: 1e-5,
                mu: 1.8e-5,
                g: 9.81,
            },
            water(2.0),
            water(1.0005),
            water(0.1),
        ]
    }

    /// Terminal velocity v_t = (ρ_p − ρ_f) g d²/(18μ) (along gravity; negative: rising).
    pub fn terminal_velocity(&self) -> f64 {
        (self.rho_p - self.rho_f) * self.g * self.d * self.d / (18.0 * self.mu)
    }

    /// Response time with added mass, τ = (ρ_p + ½ρ_f) d²/(18μ).
    pub fn response_time(&self) -> f64 {
        (self.rho_p + 0.5 * self.rho_f) * self.d * self.d / (18.0 * self.mu)
    }

    /// v(t) = v_t(1 − e^{−t/τ}) (module docs).
    pub fn exact(&self, t: f64) -> f64 {
        self.terminal_velocity() * -(-t / self.response_time()).exp_m1()
    }

    /// The rigid sphere with added mass and the undisturbed-flow force.
    pub fn particle(&self) -> Result<Particle<Rigid>, ParamError> {
        let r = 0.5 * self.d;
        let forces = ForceTerms::new(vec![Arc::new(AddedMass), Arc::new(UndisturbedFlow)])?;
        Particle::with_drag(
            Ellipsoid::new([r, r, r], Mat3::identity())?,
            Rigid,
            Brenner,
            Fluid::new(self.mu, self.rho_f)?,
            self.rho_p,
        )?
        .with_gravity(Vec3::new(0.0, 0.0, -self.g))?
        .with_forces(forces)
    }
}

/// One row of `settling.csv`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SettlingRow {
    /// The case.
    pub case: SettlingCase,
    /// Time t.
    pub t: f64,
    /// Velocity along gravity, integrated.
    pub v_numeric: f64,
    /// Velocity along gravity, exact.
    pub v_exact: f64,
}

/// `samples` + 1 equally spaced times over 6τ of `case`, integrated by Radau IIA with an
/// inertial barycentre at tolerance `tol`, from one sample time to the next.
pub fn settle(case: &SettlingCase, samples: usize, tol: f64) -> Result<Vec<SettlingRow>, StepError> {
    let particle = case.particle()?;
    let integrator = Stokesian::new(tol)?;
    let dt = 6.0 * case.response_time() / samples as f64;
    let mut state = State::at_rest(Vec3::zeros());
    let mut rows = Vec::with_capacity(samples + 1);
    for k in 0..=samples {
        let t = dt * k as f64;
        if k > 0 {
            state = advance(Problem::new(&integrator, &particle, &Quiescent), state, 0.01 * dt, t)?.0;
        }
        rows.push(SettlingRow {
            case: *case,
            t,
            v_numeric: state.v.dot(&-Vec3::z()),
            v_exact: case.exact(t),
        });
    }
    Ok(rows)
}

/// `settling.csv`.
pub fn settling_csv(rows: &[SettlingRow]) -> Result<Csv, OutputError> {
    let mut csv = Csv::new(&SETTLING_COLUMNS);
    for r in rows {
        let c = r.case;
        csv.push_numbers(&[c.rho_p, c.rho_f, c.d, c.mu, c.g, r.t, r.v_numeric, r.v_exact])?;
    }
    Ok(csv)
}

/// v/v_t against t/τ for each case: integrated (points) over exact (lines).
pub fn settling_figure(rows: &[SettlingRow]) -> Figure {
    let mut panel = Panel::new(
        "Settling from rest with added mass and the undisturbed-flow force",
        "t / tau, tau = (rho_p + rho_f/2) d^2 / (18 mu)",
        "v / v_t",
    );
    for (color, case) in SettlingCase::dataset().iter().enumerate() {
        let of_case: Vec<&SettlingRow> = rows.iter().filter(|r| r.case == *case).collect();
        let scaled = |v: f64, t: f64| (t / case.response_time(), v / case.terminal_velocity());
        let label = format!("rho_p/rho_f = {}", case.rho_p / case.rho_f);
        panel = panel
            .with(Series::points(
                label,
                of_case.iter().map(|r| scaled(r.v_numeric, r.t)).collect(),
                color,
            ))
            .with(Series::line(
                "",
                of_case.iter().map(|r| scaled(r.v_exact, r.t)).collect(),
                color,
            ));
    }
    Figure::single(panel)
}

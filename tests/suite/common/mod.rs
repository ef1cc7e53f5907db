//! Shared test helpers: proptest strategies, independent reference computations and (feature
//! `mesh`) generated OpenFOAM cases (`build`).

#[cfg(feature = "mesh")]
pub mod build;
pub mod reference;
pub mod strategies;

/// Observed order of convergence: the least-squares slope of ln e against ln h (h the step,
/// cell size or tolerance, e the error at it).
pub fn observed_order(h: &[f64], e: &[f64]) -> f64 {
    let n = h.len() as f64;
    let (mx, my) = h
        .iter()
        .zip(e)
        .fold((0.0, 0.0), |(a, b), (h, e)| (a + h.ln() / n, b + e.ln() / n));
    let sxy: f64 = h.iter().zip(e).map(|(h, e)| (h.ln() - mx) * (e.ln() - my)).sum();
    let sxx: f64 = h.iter().map(|h| (h.ln() - mx).powi(2)).sum();
    sxy / sxx
}

/// `x` rounded to `digits` significant digits, as text: stable across machines for snapshots.
pub fn sig(x: f64, digits: i32) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let decimals = (digits - 1 - x.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{x:.decimals$}");
    if s.starts_with("-") && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// The Re = 1000 cavity benchmark on `flow`: the three centreline extrema against Albensoeder &
/// Kuhlmann (2005), each within 5 % (a uniform 60³ finite-volume grid is expected 2–5 % shallow:
/// Ben Beya & Lili, 1–2 % at 48³–64³ with a finer scheme, 5 % at 32³), as a table rounded to 3
/// decimals for a snapshot.
#[cfg(feature = "mesh")]
pub fn cavity_re1000_extrema(flow: &impl pseudorigid::flow::FlowField) -> String {
    use pseudorigid::studies::cavity_benchmark::{CavityCase, ReferenceTable, compare_extrema};
    let case = CavityCase {
        edge: 0.1,
        lid_speed: 0.173,
    };
    let root = env!("CARGO_MANIFEST_DIR");
    let table =
        ReferenceTable::read_csv(format!("{root}/reference-data/cavity_re1000_albensoeder_kuhlmann.csv").as_ref())
            .unwrap();
    let rows = compare_extrema(&case, flow, &table).unwrap();
    assert_eq!(rows.len(), 3);
    let mut text = String::from("extremum,simulated,position,reference,error_percent\n");
    for r in &rows {
        assert!(
            r.relative_error().abs() <= 0.05,
            "{}: {:+.2} %",
            r.which.name(),
            100.0 * r.relative_error()
        );
        text.push_str(&format!(
            "{},{:.3},{:.3},{:.3},{:.1}\n",
            r.which.name(),
            r.simulated.value,
            r.simulated.position,
            r.reference.value,
            100.0 * r.relative_error()
        ));
    }
    text
}

/// The one record of a one-particle shard, which must have ended at a boundary (deposited or
/// escaped), not failed or stayed inside; `what` names the particle in the failure message
/// (the meshed scenes' tests use it).
#[cfg(all(feature = "mesh", feature = "parallel"))]
pub fn assert_single_run_ends<L>(out: &pseudorigid::population::RunOutput<L>, what: &str) {
    use pseudorigid::population::Fate;
    let [record] = out.records.as_slice() else {
        panic!("{what}: one particle per shard, got {}", out.records.len())
    };
    assert!(
        matches!(record.fate, Fate::Escaped { .. } | Fate::Deposited { .. }),
        "{what}: {:?}",
        record.fate
    );
}

/// A rigid sphere of Stokes response time τ = 2ρr²/(9μ) (its mass over 6πμr) and density ρ in
/// a fluid of viscosity μ without density.
pub fn heavy_sphere(tau: f64, mu: f64, rho: f64) -> pseudorigid::particle::Particle<pseudorigid::material::Rigid> {
    use pseudorigid::prelude::*;
    let r = (4.5 * mu * tau / rho).sqrt();
    Particle::new(
        Ellipsoid::aligned([r; 3]).unwrap(),
        pseudorigid::material::Rigid,
        Fluid::new(mu, 0.0).unwrap(),
        rho,
    )
    .unwrap()
}

/// A fibre-reinforced Neo-Hookean solid (a hydrogel with aligned fibres): W = W_NH + (k/2)(I₄ − 1)²
/// with I₄ = e₁·C e₁ = |F e₁|², the stretch of the fibre that lies along e₁ at rest. Not
/// isotropic: it keeps `Hyperelastic::is_isotropic`'s default.
pub struct Fibred {
    /// The matrix.
    pub matrix: pseudorigid::material::NeoHooke,
    /// The fibre stiffness k.
    pub k: f64,
}

impl pseudorigid::material::Hyperelastic for Fibred {
    fn energy<S: pseudorigid::tensor::Scalar>(&self, f: &nalgebra::Matrix3<S>) -> S {
        let i4 = f[(0, 0)] * f[(0, 0)] + f[(1, 0)] * f[(1, 0)] + f[(2, 0)] * f[(2, 0)];
        self.matrix.energy(f) + (i4 - 1.0) * (i4 - 1.0) * (0.5 * self.k)
    }
    fn shear_modulus(&self) -> f64 {
        self.matrix.shear_modulus()
    }
    fn lame_lambda(&self) -> f64 {
        self.matrix.lame_lambda()
    }
}

/// ∇u of `flow` at x by fourth-order central differences over h (column j the derivative along
/// e_j): truncation h⁴|∂⁵u|/30, round-off about 18 ε |u| / (12 h). The analytic fields' tests
/// check their ∇u against it.
pub fn gradient_by_differences<F: pseudorigid::flow::FlowField + ?Sized>(
    flow: &F,
    x: &pseudorigid::tensor::Vec3,
    h: f64,
) -> pseudorigid::tensor::Mat3 {
    use pseudorigid::tensor::{Mat3, Vec3};
    let at = |y: Vec3| flow.sample(&y, 0.0).unwrap().u;
    let mut fd = Mat3::zeros();
    for j in 0..3 {
        let e = Vec3::ith(j, h);
        let d = (at(x - 2.0 * e) - 8.0 * at(x - e) + 8.0 * at(x + e) - at(x + 2.0 * e)) / (12.0 * h);
        fd.set_column(j, &d);
    }
    fd
}

//! The discretisation error of a quantity computed on two or three meshes: Richardson
//! extrapolation and Roache's grid convergence index (GCI) by the three-grid procedure of
//! Celik, Ghia, Roache, Freitas, Coleman and Raad (2008, "Procedure for estimation and reporting
//! of uncertainty due to discretization in CFD applications", J. Fluids Eng. 130, 078001).
//!
//! # The procedure
//! A mesh of N cells filling a volume V (an area in 2-D, d = 2) has the representative size
//! $h = (V/N)^{1/d}$ (Celik et al., eq. 1), so two meshes of the same domain have the
//! refinement ratio $r = h_{coarse}/h_{fine} = (N_{fine}/N_{coarse})^{1/d}$, whatever V is.
//! With φ₁, φ₂, φ₃ the values on the fine, medium and coarse meshes, $r_{21} = h_2/h_1$,
//! $r_{32} = h_3/h_2$, $\varepsilon_{21} = \varphi_2 - \varphi_1$ and
//! $\varepsilon_{32} = \varphi_3 - \varphi_2$, the apparent order p solves (eqs. 3a–c)
//! ```math
//! p = \frac{1}{\ln r_{21}}\left|\ln\left|\frac{\varepsilon_{32}}{\varepsilon_{21}}\right| + q(p)\right|,
//! \qquad q(p) = \ln\frac{r_{21}^p - s}{r_{32}^p - s}, \qquad
//! s = \operatorname{sgn}\frac{\varepsilon_{32}}{\varepsilon_{21}},
//! ```
//! solved by fixed-point iteration from q = 0 (q vanishes for equal ratios, and p is then
//! explicit). s < 0, increments of alternating sign, is *oscillatory* convergence (Celik et
//! al., below eq. 3c), reported as such. The extrapolated value, the approximate and the
//! extrapolated relative errors and the fine-grid convergence index are (eqs. 4–7)
//! ```math
//! \varphi_{ext}^{21} = \frac{r_{21}^p\varphi_1 - \varphi_2}{r_{21}^p - 1}, \quad
//! e_a^{21} = \left|\frac{\varphi_1 - \varphi_2}{\varphi_1}\right|, \quad
//! e_{ext}^{21} = \left|\frac{\varphi_{ext}^{21} - \varphi_1}{\varphi_{ext}^{21}}\right|, \quad
//! GCI_{fine}^{21} = \frac{F_s\, e_a^{21}}{r_{21}^p - 1},
//! ```
//! with the safety factor F_s = 1.25 for three meshes (Roache 1997, Annu. Rev. Fluid Mech.
//! 29:123). [`GridConvergence::band`] is the same index in the quantity's units,
//! $F_s|\varphi_1 - \varphi_2|/(r_{21}^p - 1)$: a deposited fraction near zero has a
//! meaningless relative error, but its absolute band is what a reader compares.
//!
//! # Bounds on p
//! An apparent order above the scheme's formal order promises more than the scheme can give
//! (an increment that happens to be small); Roache (1998, *Verification and Validation in
//! Computational Science and Engineering*, §5.10) and ASME V&V 20-2009 cap the order used in
//! the index at the formal one, and so does [`GridConvergence::order_used`]. The extrapolated
//! value and the index use that capped order; the apparent order is reported as computed. With
//! two meshes no order can be observed: the formal order is used with F_s = 3 (Roache 1997).
//! The procedure does not hold where the increments grow under refinement
//! (|ε₂₁| > |ε₃₂| at equal ratios: p < 0 before the absolute value of eq. 3a takes its sign
//! away) or vanish: [`Convergence`] names these cases and the index is then not an error bar.
//!
//! # Checked
//! Against Table 1 of Celik et al. (2008), all three columns (monotone with p = 1.53 and
//! p = 0.75, oscillatory with p = 1.51): `reference-data/celik2008_gci_table1.csv`, and
//! exactly on manufactured sequences φ(h) = φ₀ + C hᵖ (tests/suite/population/gci.rs).

use thiserror::Error;

/// Safety factor of the index with three or more meshes (Roache 1997; Celik et al. 2008).
pub const SAFETY_THREE_MESHES: f64 = 1.25;
/// Safety factor of the index with two meshes and an assumed order (Roache 1997).
pub const SAFETY_TWO_MESHES: f64 = 3.0;
/// Largest change of p between fixed-point iterates accepted as converged.
const P_TOLERANCE: f64 = 1e-12;
/// Fixed-point iterations allowed.
const P_ITERATIONS: usize = 200;

/// Why no estimate could be made.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum GciError {
    /// Meshes not given finest first, or a refinement ratio not above one.
    #[error("refinement ratio r{pair} = {ratio} must be > 1 (meshes finest first, cells {cells:?})")]
    Ratio {
        /// The pair, `21` or `32`.
        pair: &'static str,
        /// Its ratio.
        ratio: f64,
        /// The cell counts as given.
        cells: Vec<f64>,
    },
    /// Two or three meshes are needed.
    #[error("{meshes} meshes given: the procedure takes two or three")]
    Meshes {
        /// How many were given.
        meshes: usize,
    },
    /// A value or a formal order that is not finite, or a dimension other than 1, 2 or 3.
    #[error("`{name}` must be finite{extra}, got {value}")]
    Input {
        /// Which input.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What else it must be.
        extra: &'static str,
    },
    /// The fixed-point iteration for p did not settle.
    #[error("apparent order not converged after {iterations} iterations: p = {p}, last change {change:e}")]
    NotConverged {
        /// Iterations taken.
        iterations: usize,
        /// The last iterate.
        p: f64,
        /// Its change from the one before.
        change: f64,
    },
}

/// How the values approach their limit, read from the increments.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Convergence {
    /// Increments of one sign, shrinking under refinement.
    Monotone,
    /// Increments of alternating sign (s < 0 in eq. 3c).
    Oscillatory,
    /// Increments of one sign, growing under refinement (ε₂₁ larger than the ratios allow for
    /// any p > 0): not yet in the asymptotic range; p is only formally defined.
    Divergent,
    /// The fine pair agrees exactly (ε₂₁ = 0): no order can be read; the band is zero.
    Flat,
    /// Two meshes: the formal order is assumed, nothing is observed.
    Assumed,
}

/// The estimate of one quantity on two or three meshes (module docs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GridConvergence {
    /// r₂₁ = h₂/h₁.
    pub r21: f64,
    /// r₃₂ = h₃/h₂ (None with two meshes).
    pub r32: Option<f64>,
    /// The apparent order of eq. 3a (None with two meshes or a flat fine pair).
    pub p_apparent: Option<f64>,
    /// The order used for the extrapolation and the index: the apparent one capped at the
    /// formal one, or the formal one with two meshes or a flat fine pair.
    pub order_used: f64,
    /// φ_ext²¹ (eq. 4) with [`Self::order_used`].
    pub extrapolated: f64,
    /// e_a²¹ (eq. 5): relative change from the medium to the fine mesh (None where φ₁ = 0,
    /// an outcome no particle met on the finest mesh).
    pub e_a: Option<f64>,
    /// e_ext²¹ (eq. 6): relative distance of the fine value from the extrapolated one (None
    /// where φ_ext = 0).
    pub e_ext: Option<f64>,
    /// GCI_fine²¹ (eq. 7), relative to φ₁ (None where φ₁ = 0; [`Self::band`] is then the bar).
    pub gci_fine: Option<f64>,
    /// The same index in the quantity's units: F_s |φ₁ − φ₂| / (r₂₁^p − 1).
    pub band: f64,
    /// F_s: 1.25 with three meshes, 3 with two.
    pub safety: f64,
    /// How the increments behave.
    pub convergence: Convergence,
}

/// r = (N_fine/N_coarse)^{1/d}: the ratio of the representative sizes h = (V/N)^{1/d} of two
/// meshes of the same domain in d dimensions (Celik et al. 2008, eq. 1).
pub fn refinement_ratio(cells_fine: f64, cells_coarse: f64, dimension: u32) -> f64 {
    (cells_fine / cells_coarse).powf(1.0 / f64::from(dimension))
}

impl GridConvergence {
    /// The estimate from `values` (finest first: φ₁, φ₂ and, with three meshes, φ₃) on meshes
    /// of `cells` cells (finest first) in `dimension` dimensions, the scheme's formal order
    /// `formal` capping the order used (module docs).
    pub fn from_cells(values: &[f64], cells: &[f64], dimension: u32, formal: f64) -> Result<Self, GciError> {
        if !(1..=3).contains(&dimension) {
            return Err(GciError::Input {
                name: "dimension",
                value: f64::from(dimension),
                extra: " and 1, 2 or 3",
            });
        }
        if cells.len() != values.len() || !(2..=3).contains(&cells.len()) {
            return Err(GciError::Meshes {
                meshes: cells.len().max(values.len()),
            });
        }
        let ratios: Vec<f64> = cells
            .windows(2)
            .map(|w| refinement_ratio(w[0], w[1], dimension))
            .collect();
        for (&ratio, pair) in ratios.iter().zip(["21", "32"]) {
            if !(ratio > 1.0 && ratio.is_finite()) {
                return Err(GciError::Ratio {
                    pair,
                    ratio,
                    cells: cells.to_vec(),
                });
            }
        }
        Self::from_ratios(values, &ratios, formal)
    }

    /// The estimate from `values` (finest first) and the refinement ratios r₂₁ (and r₃₂),
    /// each > 1.
    pub fn from_ratios(values: &[f64], ratios: &[f64], formal: f64) -> Result<Self, GciError> {
        for &v in values {
            if !v.is_finite() {
                return Err(GciError::Input {
                    name: "value",
                    value: v,
                    extra: "",
                });
            }
        }
        if !(formal > 0.0 && formal.is_finite()) {
            return Err(GciError::Input {
                name: "formal order",
                value: formal,
                extra: " and > 0",
            });
        }
        for (&ratio, pair) in ratios.iter().zip(["21", "32"]) {
            if !(ratio > 1.0 && ratio.is_finite()) {
                return Err(GciError::Ratio {
                    pair,
                    ratio,
                    cells: Vec::new(),
                });
            }
        }
        match (values, ratios) {
            ([phi1, phi2], [r21]) => Ok(Self::assemble(
                *phi1,
                *phi2,
                *r21,
                None,
                None,
                formal,
                SAFETY_TWO_MESHES,
                Convergence::Assumed,
            )),
            ([phi1, phi2, phi3], [r21, r32]) => Self::three(*phi1, *phi2, *phi3, *r21, *r32, formal),
            _ => Err(GciError::Meshes {
                meshes: values.len().max(ratios.len() + 1),
            }),
        }
    }

    fn three(phi1: f64, phi2: f64, phi3: f64, r21: f64, r32: f64, formal: f64) -> Result<Self, GciError> {
        let (e21, e32) = (phi2 - phi1, phi3 - phi2);
        if e21 == 0.0 {
            return Ok(Self::assemble(
                phi1,
                phi2,
                r21,
                Some(r32),
                None,
                formal,
                SAFETY_THREE_MESHES,
                Convergence::Flat,
            ));
        }
        let s = if e32 / e21 < 0.0 { -1.0 } else { 1.0 };
        // ε₃₂ = 0 with ε₂₁ ≠ 0: the coarse pair agrees and the fine pair does not; ln 0 would
        // send p to infinity. The smallest positive increment stands in (p is then large, and
        // capped at the formal order; the increments grow, reported as divergent).
        let ratio = (e32 / e21).abs().max(f64::MIN_POSITIVE);
        let (ln_ratio, ln_r21) = (ratio.ln(), r21.ln());
        let q = |p: f64| ((r21.powf(p) - s) / (r32.powf(p) - s)).ln();
        let mut p = ln_ratio.abs() / ln_r21;
        let mut change = f64::INFINITY;
        let mut iterations = 0;
        while iterations < P_ITERATIONS && change > P_TOLERANCE * p.max(1.0) {
            let next = (ln_ratio + q(p)).abs() / ln_r21;
            change = (next - p).abs();
            p = next;
            iterations += 1;
        }
        if change > P_TOLERANCE * p.max(1.0) || !p.is_finite() {
            return Err(GciError::NotConverged { iterations, p, change });
        }
        // Without the absolute value of eq. 3a, p would be negative: |ε₂₁| exceeds what any
        // positive order gives from ε₃₂ at these ratios.
        let convergence = if s < 0.0 {
            Convergence::Oscillatory
        } else if ln_ratio + q(p) < 0.0 {
            Convergence::Divergent
        } else {
            Convergence::Monotone
        };
        Ok(Self::assemble(
            phi1,
            phi2,
            r21,
            Some(r32),
            Some(p),
            formal,
            SAFETY_THREE_MESHES,
            convergence,
        ))
    }

    /// Eqs. 4–7 with the order `p_apparent` capped at `formal` (or `formal` without one).
    #[allow(clippy::too_many_arguments)]
    fn assemble(
        phi1: f64,
        phi2: f64,
        r21: f64,
        r32: Option<f64>,
        p_apparent: Option<f64>,
        formal: f64,
        safety: f64,
        convergence: Convergence,
    ) -> Self {
        let order_used = p_apparent.map_or(formal, |p| p.min(formal));
        let gain = r21.powf(order_used) - 1.0;
        let extrapolated = (r21.powf(order_used) * phi1 - phi2) / gain;
        let band = safety * (phi1 - phi2).abs() / gain;
        let relative = |x: f64, of: f64| (of != 0.0).then(|| (x / of).abs());
        let e_a = relative(phi1 - phi2, phi1);
        Self {
            r21,
            r32,
            p_apparent,
            order_used,
            extrapolated,
            e_a,
            e_ext: relative(extrapolated - phi1, extrapolated),
            gci_fine: e_a.map(|e| safety * e / gain),
            band,
            safety,
            convergence,
        }
    }

    /// Whether the band is an error bar: monotone convergence with three meshes, or two
    /// meshes with the assumed order (F_s = 3). Oscillatory, divergent and flat sequences give
    /// numbers but no bar the procedure stands behind.
    pub fn holds(&self) -> bool {
        matches!(self.convergence, Convergence::Monotone | Convergence::Assumed)
    }
}

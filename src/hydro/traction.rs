//! Jeffery–Roscoe traction stress σ̃.
//!
//! # Physics (paper eq. 12; closed form from Jeffery 1922 and Roscoe 1967)
//! σ̃ := (1/vol B_t) ∫ t ⊗ ξ da is the first moment of the fluid traction on an ellipsoid whose
//! surface moves affinely with l_s in the undisturbed linear flow l_f. In the principal frame,
//! with g = l_f − l_s, d = dev sym g, w = skw g, d_s = sym l_s and
//! Σ″ = α″₁α″₂ + α″₂α″₃ + α″₃α″₁:
//!
//! ```math
//! \tilde\sigma = -\bar p\,\mathbf 1 + \mu_f\,\big[\,s(d, w) + 2 d_s\,\big]
//! ```
//! with, off the diagonal (i ≠ j, either order, k the third index),
//! ```math
//! s_{ij} = \frac{4}{abc}\Big\{\frac{d_{ij}}{\alpha'_k (x_i+x_j)}
//!   + \frac{x_j[(x_i+x_j) w_{ij} - (x_i-x_j) d_{ij}]}{(x_i+x_j)(x_i\alpha_i + x_j\alpha_j)}\Big\},
//! ```
//! on the diagonal and for the mean normal stress
//! ```math
//! s_{ii} = \frac{4}{3abc}\,\frac{2\alpha''_i d_{ii} - \alpha''_j d_{jj} - \alpha''_k d_{kk}}{\Sigma''},
//! \qquad
//! \bar p = \frac{2\mu_f}{3\Sigma''}\sum_i \alpha''_i(2\alpha_i-\alpha_j-\alpha_k)\, d_{ii}.
//! ```
//!
//! Global components σ̃ = Qᵀ σ̃′ Q. Checked limits (tests): the sphere gives
//! σ̃ = 2μd_s + 5μd + 3μw; a torque-free ellipsoid spins at Jeffery's rate.
//!
//! The formula covers incompressible surface motion only. The volumetric part of the "2 d_s"
//! term is a modelling choice ([`VolumetricTraction`]). Derivation, checks and the three
//! volumetric readings: [`crate::theory::traction`].

use crate::ellipsoid::{EllipsoidIntegrals, PrincipalFrame};
use crate::error::ParamError;
use crate::tensor::{Mat3, dev, skw, sym};
use serde::{Deserialize, Serialize};

/// Treatment of the volumetric part tr d_s, about which Jeffery–Roscoe is silent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum VolumetricTraction {
    /// Literal eq. 12: 2μ d_s. Adds +(2/3)μ tr(d_s) 1, which anti-damps volume changes.
    #[default]
    Paper,
    /// 2μ dev d_s: no viscous resistance to volume change.
    Dev,
    /// 2μ dev d_s − (4/3)μ tr(d_s) 1: the source-flow value, exact for a sphere.
    Source,
}

/// Shape coefficients of σ̃ for one principal frame; σ̃ is affine in (l_f, l_s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JefferyRoscoe {
    frame: PrincipalFrame,
    /// Coefficient of d_ij in s_ij for the ordered pair (i, j).
    c_d: Mat3,
    /// Coefficient of w_ij in s_ij.
    c_w: Mat3,
    /// s_ii = Σ_m c_diag[(i, m)] d_mm.
    c_diag: Mat3,
    /// p̄/μ_f = Σ_i c_p[i] d_ii.
    c_p: [f64; 3],
}

impl JefferyRoscoe {
    /// Coefficients for the ellipsoid with principal frame `frame` and integrals `ints`.
    ///
    /// Precondition: finite integrals of a finite frame; otherwise the coefficients hold NaN or
    /// ∞, promptly (the hot path, [preconditions](crate::error#preconditions)).
    /// [`Self::try_new`] checks.
    pub fn new(frame: &PrincipalFrame, ints: &EllipsoidIntegrals) -> Self {
        let (x, a, ap, app, abc) = (ints.x, ints.alpha, ints.alpha_p, ints.alpha_pp, ints.abc);
        let mut c_d = Mat3::zeros();
        let mut c_w = Mat3::zeros();
        for i in 0..3 {
            for j in 0..3 {
                if i == j {
                    continue;
                }
                let k = 3 - i - j;
                let sum = x[i] + x[j];
                let xa = x[i] * a[i] + x[j] * a[j];
                c_d[(i, j)] = 4.0 / (abc * ap[k] * sum) - 4.0 * x[j] * (x[i] - x[j]) / (abc * sum * xa);
                c_w[(i, j)] = 4.0 * x[j] / (abc * xa);
            }
        }
        let sigma2 = app[0] * app[1] + app[1] * app[2] + app[2] * app[0];
        let c = 4.0 / (3.0 * abc * sigma2);
        let mut c_diag = Mat3::zeros();
        let mut c_p = [0.0; 3];
        for i in 0..3 {
            for m in 0..3 {
                c_diag[(i, m)] = if i == m { 2.0 * app[m] * c } else { -app[m] * c };
            }
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            c_p[i] = 2.0 / (3.0 * sigma2) * app[i] * (2.0 * a[i] - a[j] - a[k]);
        }
        Self {
            frame: *frame,
            c_d,
            c_w,
            c_diag,
            c_p,
        }
    }

    /// The coefficients of the same ellipsoid in `frame`, a frame with this one's semi-axes
    /// (this frame turned, [`PrincipalFrame::turned`]): they depend on the semi-axes only, so
    /// only the frame changes. Taking the turned frame rather than the rotation lets a caller
    /// that turns the frame anyway ([`crate::particle::Geometry::turned`]) turn it once.
    pub fn in_frame(&self, frame: PrincipalFrame) -> Self {
        Self { frame, ..*self }
    }

    /// Coefficients for `frame` and `ints`, or the first that is not finite (an ellipsoid too
    /// slender for f64, or non-finite input).
    pub fn try_new(frame: &PrincipalFrame, ints: &EllipsoidIntegrals) -> Result<Self, ParamError> {
        let coefficients = Self::new(frame, ints);
        match coefficients.first_non_finite() {
            Some(value) => Err(ParamError::Derived {
                name: "Jeffery–Roscoe traction coefficient",
                value,
                inputs: frame.r.iter().copied().collect(),
            }),
            None => Ok(coefficients),
        }
    }

    /// Coefficients straight from the total distortion F̄ = F·S (precondition: F̄ finite and
    /// non-singular, as for [`PrincipalFrame::from_total_distortion`]).
    pub fn from_total_distortion(f_bar: &Mat3) -> Self {
        let frame = PrincipalFrame::from_total_distortion(f_bar);
        Self::new(&frame, &EllipsoidIntegrals::new(&frame.r))
    }

    /// Coefficients from the total distortion F̄ = F·S, or why they do not exist: a frame,
    /// integrals or coefficients that are not finite.
    pub fn try_from_total_distortion(f_bar: &Mat3) -> Result<Self, ParamError> {
        let frame = PrincipalFrame::try_from_total_distortion(f_bar)?;
        Self::try_new(&frame, &EllipsoidIntegrals::try_new(&frame.r)?)
    }

    /// Whether every coefficient is finite (false for an ellipsoid too slender for f64).
    pub fn is_finite(&self) -> bool {
        self.first_non_finite().is_none()
    }

    fn first_non_finite(&self) -> Option<f64> {
        [self.c_d, self.c_w, self.c_diag]
            .iter()
            .flat_map(|m| m.iter())
            .chain(&self.c_p)
            .find(|c| !c.is_finite())
            .copied()
    }

    /// The principal frame the coefficients belong to.
    pub fn frame(&self) -> &PrincipalFrame {
        &self.frame
    }

    /// σ̃′/μ_f in the principal frame for principal components `lf` of l_f and `ls` of l_s.
    pub fn sigma_principal(&self, lf: &Mat3, ls: &Mat3, vol: VolumetricTraction) -> Mat3 {
        let g = lf - ls;
        let d = dev(&sym(&g));
        let w = skw(&g);
        let ds = sym(ls);
        let tr_ds = ds.trace();
        let mut s = Mat3::zeros();
        let mut p = 0.0;
        for i in 0..3 {
            for j in 0..3 {
                s[(i, j)] = if i == j {
                    (0..3).map(|m| self.c_diag[(i, m)] * d[(m, m)]).sum()
                } else {
                    self.c_d[(i, j)] * d[(i, j)] + self.c_w[(i, j)] * w[(i, j)]
                };
            }
            p += self.c_p[i] * d[(i, i)];
        }
        let viscous = match vol {
            VolumetricTraction::Paper => ds * 2.0,
            VolumetricTraction::Dev => dev(&ds) * 2.0,
            VolumetricTraction::Source => dev(&ds) * 2.0 - Mat3::identity() * (4.0 / 3.0 * tr_ds),
        };
        s + viscous - Mat3::identity() * p
    }

    /// σ̃ in global components for the solid velocity gradient `l_s` and fluid gradient `l_f`.
    pub fn sigma_tilde(&self, l_s: &Mat3, l_f: &Mat3, mu_f: f64, vol: VolumetricTraction) -> Mat3 {
        let sp = self.sigma_principal(&self.frame.to_principal(l_f), &self.frame.to_principal(l_s), vol);
        self.frame.to_global(&sp) * mu_f
    }

    /// Linear solver for the inertialess shape dynamics in flow `l_f` (paper eq. 18 with Θ → 0).
    pub fn inertialess(&self, l_f: &Mat3, mu_f: f64) -> Option<InertialessSolver> {
        InertialessSolver::new(self, l_f, mu_f)
    }
}

/// The inertialess (Θ → 0) balance P̃ = P, i.e. σ̃(l_s) = σ_el, for an incompressible particle:
/// dev σ̃(l_s) = dev σ_el with tr l_s = 0 (paper eq. 18 with Θ → 0).
///
/// σ̃ is affine in l_s, and in the principal frame its linear part decouples (module docs: s_ij
/// depends on d_ij and w_ij, s_ii on the diagonal of d): the nine equations are one 3×3 system
/// for the diagonal of l_s (the deviatoric normal stresses of rows 1 and 2, and tr l_s = 0 in
/// place of row 3) and three 2×2 systems for the pairs (l_ij, l_ji). The part of σ̃′/μ_f linear
/// in l_s (g = l_f − l_s contributes −l_s) is, for a pair i < j,
/// ```math
/// \begin{pmatrix}\tilde\sigma'_{ij}\\ \tilde\sigma'_{ji}\end{pmatrix} / \mu_f =
/// \begin{pmatrix} 1 - \tfrac12 (c^d_{ij} + c^w_{ij}) & 1 - \tfrac12 (c^d_{ij} - c^w_{ij})\\
///  1 - \tfrac12 (c^d_{ji} - c^w_{ji}) & 1 - \tfrac12 (c^d_{ji} + c^w_{ji})\end{pmatrix}
/// \begin{pmatrix} l_{ij}\\ l_{ji}\end{pmatrix},
/// ```
/// and on the diagonal $\tilde\sigma^{\prime}_{ii}/\mu_f = \sum_m K_{im} l_{mm} - \bar p/\mu_f$ with
/// $K_{im} = -c^{\mathrm{diag}}_{im} + \tfrac13 \sum_k c^{\mathrm{diag}}_{ik} + 2\delta_{im} - \tfrac23$
/// (the viscous 2 dev d_s; p̄ drops out of dev). Four small solves replace the 9×9 operator
/// probed column by column and its LU (a quarter of a soft particle's model evaluation). Tested
/// against the defining equations through σ̃ itself (random ellipsoids with axis ratios up to
/// 36) and the sphere's closed form.
#[derive(Debug, Clone)]
pub struct InertialessSolver {
    q: Mat3,
    /// Inverse of the diagonal block: (l_00, l_11, l_22) from (dev σ̃′_00, dev σ̃′_11, tr l_s).
    diagonal: nalgebra::Matrix3<f64>,
    /// Inverses of the pairs' blocks: (l_ij, l_ji) from (σ̃′_ij, σ̃′_ji), for [`PAIRS`].
    pairs: [nalgebra::Matrix2<f64>; 3],
    base: Mat3,
    mu_f: f64,
}

/// The off-diagonal pairs (i, j), i < j.
const PAIRS: [(usize, usize); 3] = [(0, 1), (0, 2), (1, 2)];

impl InertialessSolver {
    fn new(traction: &JefferyRoscoe, l_f: &Mat3, mu_f: f64) -> Option<Self> {
        let frame = traction.frame();
        let lf = frame.to_principal(l_f);
        // The volumetric variant is irrelevant once tr l_s = 0 and dev is taken.
        let base = dev(&traction.sigma_principal(&lf, &Mat3::zeros(), VolumetricTraction::Dev));
        let (c_d, c_w, c_diag) = (&traction.c_d, &traction.c_w, &traction.c_diag);
        let k = Mat3::from_fn(|i, m| {
            let mean: f64 = (0..3).map(|l| c_diag[(i, l)]).sum::<f64>() / 3.0;
            -c_diag[(i, m)] + mean + if i == m { 2.0 } else { 0.0 } - 2.0 / 3.0
        });
        let diagonal = Mat3::from_fn(|i, m| {
            if i == 2 {
                1.0
            } else {
                k[(i, m)] - (0..3).map(|l| k[(l, m)]).sum::<f64>() / 3.0
            }
        })
        .try_inverse()?;
        let pair = |(i, j): (usize, usize)| {
            nalgebra::Matrix2::new(
                1.0 - 0.5 * (c_d[(i, j)] + c_w[(i, j)]),
                1.0 - 0.5 * (c_d[(i, j)] - c_w[(i, j)]),
                1.0 - 0.5 * (c_d[(j, i)] - c_w[(j, i)]),
                1.0 - 0.5 * (c_d[(j, i)] + c_w[(j, i)]),
            )
            .try_inverse()
        };
        let pairs = [pair(PAIRS[0])?, pair(PAIRS[1])?, pair(PAIRS[2])?];
        let finite = diagonal
            .iter()
            .chain(pairs.iter().flat_map(|p| p.iter()))
            .all(|v| v.is_finite());
        finite.then_some(Self {
            q: frame.q,
            diagonal,
            pairs,
            base,
            mu_f,
        })
    }

    /// l_s (global components) for the elastic Cauchy stress σ_el (global components).
    pub fn velocity_gradient(&self, sigma_el: &Mat3) -> Mat3 {
        let target = dev(&(self.q * sigma_el * self.q.transpose())) / self.mu_f - self.base;
        self.solve(target)
    }

    /// The linear part: δl_s for a stress perturbation δσ_el (used by Jacobians).
    pub fn velocity_gradient_increment(&self, d_sigma_el: &Mat3) -> Mat3 {
        self.solve(dev(&(self.q * d_sigma_el * self.q.transpose())) / self.mu_f)
    }

    /// l_s (principal components turned back to global) with dev σ̃′(l_s) − (its value at
    /// l_s = 0) = `rhs` and tr l_s = 0 (the (2, 2) entry of `rhs` is not used).
    fn solve(&self, rhs: Mat3) -> Mat3 {
        let diagonal = self.diagonal * nalgebra::Vector3::new(rhs[(0, 0)], rhs[(1, 1)], 0.0);
        let mut ls = Mat3::from_diagonal(&diagonal);
        for (&(i, j), inverse) in PAIRS.iter().zip(&self.pairs) {
            let pair = inverse * nalgebra::Vector2::new(rhs[(i, j)], rhs[(j, i)]);
            ls[(i, j)] = pair[0];
            ls[(j, i)] = pair[1];
        }
        self.q.transpose() * ls * self.q
    }
}

/// Jeffery's (1922) torque-free spin of a rigid ellipsoid in the flow gradient `l_f`: the skew
/// l_s with skw σ̃ = 0 and d_s = 0. In the principal frame
/// $w_{s,ij} = w_{f,ij} - \frac{x_i - x_j}{x_i + x_j}\\, d_{f,ij}$ with x_i = r_i².
pub fn jeffery_spin(frame: &PrincipalFrame, l_f: &Mat3) -> Mat3 {
    let lf = frame.to_principal(l_f);
    let x = frame.r.component_mul(&frame.r);
    let ws = Mat3::from_fn(|i, j| {
        if i == j {
            0.0
        } else {
            0.5 * (lf[(i, j)] - lf[(j, i)]) - (x[i] - x[j]) / (x[i] + x[j]) * 0.5 * (lf[(i, j)] + lf[(j, i)])
        }
    });
    frame.to_global(&ws)
}

//! Small-tensor vocabulary shared by every model: 3×3 matrices and 3-vectors, generic over the
//! scalar so that the same code runs on `f64` and on num-dual numbers (for P = ∂W/∂F and the
//! Newton Jacobians).
//!
//! Conventions: `Mat3` stores coefficients in the fixed inertial frame E_A (the paper's iFoR).
//! A 3×3 tensor is flattened to a 9-vector column-major (nalgebra's storage order), so
//! `vec9(F)[i + 3 j] = F_ij`.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};
use num_dual::DualNum;

/// 3×3 matrix of scalars `S` (default `f64`).
pub type Mat3<S = f64> = Matrix3<S>;
/// 3-vector of scalars `S` (default `f64`).
pub type Vec3<S = f64> = Vector3<S>;
/// A 3×3 tensor flattened column-major.
pub type Vec9<S = f64> = SVector<S, 9>;
/// A linear map between flattened 3×3 tensors, e.g. a tangent ∂P/∂F.
pub type Mat9 = SMatrix<f64, 9, 9>;

/// Scalars the models are generic over: `f64` and the num-dual numbers built on it.
pub trait Scalar: DualNum<Primitive = f64> + Copy + Send + Sync {}
impl<T: DualNum<Primitive = f64> + Copy + Send + Sync> Scalar for T {}

/// det A by cofactors (generic: nalgebra's `determinant` needs a `ComplexField`).
pub fn det3<S: Scalar>(a: &Mat3<S>) -> S {
    a[(0, 0)] * (a[(1, 1)] * a[(2, 2)] - a[(1, 2)] * a[(2, 1)])
        - a[(0, 1)] * (a[(1, 0)] * a[(2, 2)] - a[(1, 2)] * a[(2, 0)])
        + a[(0, 2)] * (a[(1, 0)] * a[(2, 1)] - a[(1, 1)] * a[(2, 0)])
}

/// Cofactor matrix cof A = det A · A⁻ᵀ (defined also for singular A).
pub fn cofactor<S: Scalar>(a: &Mat3<S>) -> Mat3<S> {
    let c = |i0: usize, i1: usize, j0: usize, j1: usize| a[(i0, j0)] * a[(i1, j1)] - a[(i0, j1)] * a[(i1, j0)];
    Mat3::new(
        c(1, 2, 1, 2),
        -c(1, 2, 0, 2),
        c(1, 2, 0, 1),
        -c(0, 2, 1, 2),
        c(0, 2, 0, 2),
        -c(0, 2, 0, 1),
        c(0, 1, 1, 2),
        -c(0, 1, 0, 2),
        c(0, 1, 0, 1),
    )
}

/// A⁻ᵀ = cof A / det A. The caller guarantees det A ≠ 0 (det F > 0 is checked upstream).
pub fn inv_transpose<S: Scalar>(a: &Mat3<S>) -> Mat3<S> {
    cofactor(a) / det3(a)
}

/// Symmetric part, sym A = (A + Aᵀ)/2.
pub fn sym<S: Scalar>(a: &Mat3<S>) -> Mat3<S> {
    (a + a.transpose()) * S::from(0.5)
}

/// Skew part, skw A = (A − Aᵀ)/2.
pub fn skw<S: Scalar>(a: &Mat3<S>) -> Mat3<S> {
    (a - a.transpose()) * S::from(0.5)
}

/// Deviatoric part, dev A = A − (tr A / 3) 1.
pub fn dev<S: Scalar>(a: &Mat3<S>) -> Mat3<S> {
    a - Mat3::identity() * (a.trace() / S::from(3.0))
}

/// Flatten column-major: `vec9(A)[i + 3 j] = A_ij`.
pub fn vec9<S: Scalar>(a: &Mat3<S>) -> Vec9<S> {
    Vec9::from_column_slice(a.as_slice())
}

/// Inverse of [`vec9`].
pub fn mat3<S: Scalar>(v: &Vec9<S>) -> Mat3<S> {
    Mat3::from_column_slice(v.as_slice())
}

/// Lift an `f64` matrix into any scalar type (constants inside AD-evaluated expressions).
pub fn lift<S: Scalar>(a: &Mat3) -> Mat3<S> {
    a.map(S::from)
}

/// Iterations of [`nearest_rotation`]'s Newton method before it falls back to the SVD. From
/// F with singular values in [σ_min, σ_max] the unscaled iteration needs about
/// log₂(σ_max/σ_min) steps to reach the quadratic regime, and then about five more: 64 covers
/// every non-singular F whose singular values f64 can hold a quotient of.
const POLAR_ITERATIONS: usize = 64;

/// The nearest rotation to `f` (det F > 0): the orthogonal polar factor R of F = R U.
///
/// Newton's iteration for the polar factor (Higham 1986, *SIAM J. Sci. Stat. Comput.* 7),
/// ```math
/// X_0 = F, \qquad X_{k+1} = \tfrac12\left(X_k + X_k^{-T}\right),
/// ```
/// converges quadratically to R from any non-singular F: a rigid particle's F, a rotation up
/// to the step's error ε, takes about log₂ log₂(1/u) − log₂ log₂(1/ε) + 1 ≈ 3 steps (one 3×3
/// inverse each), where the SVD costs an order of magnitude more. It stops one step after the
/// change falls below 10⁻⁹ (the next is then at round-off, ≈ 10⁻¹⁸ before rounding). An F for
/// which it does not settle within 64 steps (`POLAR_ITERATIONS`; singular, or not finite) goes to the
/// SVD's U Vᵀ, and `f` itself is returned when the SVD does not give both factors.
pub fn nearest_rotation(f: &Mat3) -> Mat3 {
    let mut x = *f;
    let mut settled = false;
    for _ in 0..POLAR_ITERATIONS {
        let Some(inv) = x.try_inverse() else { break };
        let next = (x + inv.transpose()) * 0.5;
        let change = (next - x).abs().max();
        x = next;
        if settled {
            return x;
        }
        if !change.is_finite() {
            break;
        }
        settled = change <= 1e-9;
    }
    let svd = f.svd(true, true);
    match (svd.u, svd.v_t) {
        (Some(u), Some(v_t)) => u * v_t,
        _ => *f,
    }
}

/// `true` when every coefficient is finite.
pub fn all_finite<const R: usize, const C: usize>(a: &SMatrix<f64, R, C>) -> bool {
    a.iter().all(|x| x.is_finite())
}

/// Largest of `values` (0 for none), NaN if any is NaN. `fold(0.0, f64::max)` would drop a NaN
/// (IEEE `maxNum` returns the other operand) and report a poisoned error norm as small.
pub fn max_or_nan(values: impl IntoIterator<Item = f64>) -> f64 {
    values.into_iter().fold(
        0.0,
        |m: f64, v| if m.is_nan() || v.is_nan() { f64::NAN } else { m.max(v) },
    )
}

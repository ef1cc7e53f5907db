//! Tricubic Hermite interpolation on a cube (Lekien & Marsden 2005), C¹ across cubes that
//! share their corners' data.
//!
//! # Interpolant
//! Each corner k of a cube of edge E carries, per component, the eight derivatives
//! $\partial^m f$ with $m \in \lbrace 0, 1 \rbrace^3$ (f, f_x, f_y, f_xy, f_z, f_xz, f_yz, f_xyz: bit 0 of m
//! is x, bit 1 y, bit 2 z), in physical units. Inside the cube, with ξ = (x − x₁)/E ∈ [0, 1]³,
//! ```math
//! f(\xi) = \sum_{k} \sum_{m} E^{|m|}\,(\partial^m f)_k \prod_{a=1}^{3} h_{k_a m_a}(\xi_a),
//! ```
//! with the cubic Hermite basis on [0, 1]: $h_{00} = 2t^3 − 3t^2 + 1$ (value at 0),
//! $h_{10} = −2t^3 + 3t^2$ (value at 1), $h_{01} = t^3 − 2t^2 + t$ (slope at 0),
//! $h_{11} = t^3 − t^2$ (slope at 1). This is Lekien & Marsden's 64 coefficients per component
//! written in the basis of the data instead of monomials: the same polynomial space (cubic in
//! each coordinate), no 64 × 64 solve.
//! - *Exact* for every polynomial of degree at most 3 in each coordinate whose derivatives the
//!   corners hold (tested).
//! - *C¹*: on a face, f and ∂f/∂n are bicubic Hermite interpolants of the face's four corners'
//!   data alone, so two cubes with the same corner data there agree with their normal
//!   derivative. A smaller cube on part of a larger one's face agrees with it when its
//!   corners on that face carry the larger cube's interpolant and its derivatives (the face's
//!   bicubic space restricted to a sub-rectangle is the sub-rectangle's bicubic space).
//!
//! The functions are the crate's own: their callers (the octree table) hand each corner's 24
//! numbers; the module is public for this description of the table's interpolant.

use crate::tensor::{Mat3, Vec3};

/// Derivatives per corner and component: $\partial^m f$, m's bits x, y, z.
pub(crate) const QUANTITIES: usize = 8;

/// The cubic Hermite basis at t: `value[end][order]` and its t-derivative `slope[end][order]`
/// (end 0 or 1 of [0, 1]; order 0 the value's function, 1 the slope's).
fn basis(t: f64) -> Basis {
    let (t2, t3) = (t * t, t * t * t);
    (
        [
            [2.0 * t3 - 3.0 * t2 + 1.0, t3 - 2.0 * t2 + t],
            [-2.0 * t3 + 3.0 * t2, t3 - t2],
        ],
        [
            [6.0 * t2 - 6.0 * t, 3.0 * t2 - 4.0 * t + 1.0],
            [-6.0 * t2 + 6.0 * t, 3.0 * t2 - 2.0 * t],
        ],
    )
}

/// One axis's basis: `[end][order]` values and their derivatives.
type Basis = ([[f64; 2]; 2], [[f64; 2]; 2]);

/// Per axis: the basis at ξ_a, its slope functions times E (the data are physical
/// derivatives) and, for a derivative along the axis, divided by E.
fn axes(xi: &[f64; 3], edge: f64) -> [Basis; 3] {
    std::array::from_fn(|a| {
        let (mut v, mut d) = basis(xi[a]);
        // The slope functions' derivatives need both factors, E and 1/E: they cancel.
        for end in 0..2 {
            v[end][1] *= edge;
            d[end][0] /= edge;
        }
        (v, d)
    })
}

/// The derivative $\partial^d f$ (d's bits x, y, z) of the interpolant at ξ in a cube of edge
/// `edge`, for three components: `corner(k)` is corner k's data (k's bits the x, y, z ends),
/// component c's derivatives at `c * QUANTITIES..`.
pub(crate) fn derivative<'a>(corner: impl Fn(usize) -> &'a [f64], xi: &[f64; 3], edge: f64, d: usize) -> [f64; 3] {
    let ax = axes(xi, edge);
    let mut out = [0.0; 3];
    for k in 0..8 {
        let data = corner(k);
        for m in 0..QUANTITIES {
            let w: f64 = (0..3)
                .map(|a| {
                    let (v, s) = &ax[a];
                    let table = if (d >> a) & 1 == 1 { s } else { v };
                    table[(k >> a) & 1][(m >> a) & 1]
                })
                .product();
            for (c, o) in out.iter_mut().enumerate() {
                *o += w * data[c * QUANTITIES + m];
            }
        }
    }
    out
}

/// The interpolant u at ξ and its gradient ∇u (∂u_i/∂x_j), three components (as
/// [`derivative`], the four derivatives in one pass), contracted one axis at a time: z first
/// (a corner and the one above it, the four (m_x, m_y) quantities side by side), then y, then
/// x: about 190 multiply-adds per component.
pub(crate) fn value_and_gradient<'a>(corner: impl Fn(usize) -> &'a [f64], xi: &[f64; 3], edge: f64) -> (Vec3, Mat3) {
    let [(xv, xd), (yv, yd), (zv, zd)] = axes(xi, edge);
    let mut u = [0.0; 3];
    let mut g = [[0.0; 3]; 3];
    // The four (kx, ky) columns of corners: k = kx + 2ky below, k + 4 above.
    let columns: [(&[f64], &[f64]); 4] = std::array::from_fn(|k| (corner(k), corner(k + 4)));
    for c in 0..3 {
        let q = c * QUANTITIES;
        // a[k][m0], az[k][m0]: along z, for column k and m0 = mx + 2my.
        let mut a = [[0.0; 4]; 4];
        let mut az = [[0.0; 4]; 4];
        for (k, (lo, hi)) in columns.iter().enumerate() {
            let (lo, hi) = (&lo[q..q + QUANTITIES], &hi[q..q + QUANTITIES]);
            for m0 in 0..4 {
                a[k][m0] = zv[0][0] * lo[m0] + zv[0][1] * lo[m0 + 4] + zv[1][0] * hi[m0] + zv[1][1] * hi[m0 + 4];
                az[k][m0] = zd[0][0] * lo[m0] + zd[0][1] * lo[m0 + 4] + zd[1][0] * hi[m0] + zd[1][1] * hi[m0 + 4];
            }
        }
        // Along y: for kx and mx, the value, its y- and its z-derivative.
        let mut b = [[0.0; 2]; 2];
        let mut by = [[0.0; 2]; 2];
        let mut bz = [[0.0; 2]; 2];
        for kx in 0..2 {
            for mx in 0..2 {
                for ky in 0..2 {
                    for my in 0..2 {
                        let (k, m0) = (kx + 2 * ky, mx + 2 * my);
                        b[kx][mx] += yv[ky][my] * a[k][m0];
                        by[kx][mx] += yd[ky][my] * a[k][m0];
                        bz[kx][mx] += yv[ky][my] * az[k][m0];
                    }
                }
            }
        }
        // Along x.
        for kx in 0..2 {
            for mx in 0..2 {
                u[c] += xv[kx][mx] * b[kx][mx];
                g[c][0] += xd[kx][mx] * b[kx][mx];
                g[c][1] += xv[kx][mx] * by[kx][mx];
                g[c][2] += xv[kx][mx] * bz[kx][mx];
            }
        }
    }
    (
        Vec3::new(u[0], u[1], u[2]),
        Mat3::new(
            g[0][0], g[0][1], g[0][2], g[1][0], g[1][1], g[1][2], g[2][0], g[2][1], g[2][2],
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A polynomial cubic in each coordinate, with cross terms up to x³y³z³'s lower corner,
    /// and its derivatives ∂^m: the interpolant must reproduce it (and its derivatives) to
    /// round-off anywhere in a cube, from its corners' derivatives alone.
    fn poly(x: &Vec3, m: usize, c: usize) -> f64 {
        // f = Π_a p_a(x_a) + q(x) with p_a cubic, q = x y z (c + 1) + y² z.
        let coef = [[0.3, -1.2, 0.7, 0.25], [1.1, 0.4, -0.6, 0.9], [-0.5, 0.8, 0.2, -0.35]];
        let p = |a: usize, order: usize| {
            let t = x[a];
            let k = &coef[(a + c) % 3];
            if order == 0 {
                k[0] + k[1] * t + k[2] * t * t + k[3] * t * t * t
            } else {
                k[1] + 2.0 * k[2] * t + 3.0 * k[3] * t * t
            }
        };
        let product: f64 = (0..3).map(|a| p(a, (m >> a) & 1)).product();
        let s = (c + 1) as f64;
        let (x0, y, z) = (x[0], x[1], x[2]);
        let q = match m {
            0 => s * x0 * y * z + y * y * z,
            1 => s * y * z,
            2 => s * x0 * z + 2.0 * y * z,
            3 => s * z,
            4 => s * x0 * y + y * y,
            5 => s * y,
            6 => s * x0 + 2.0 * y,
            _ => s,
        };
        product + q
    }

    #[test]
    fn a_tricubic_polynomial_and_its_derivatives_are_reproduced() {
        let lower = Vec3::new(-0.3, 0.2, 1.1);
        let edge = 0.7;
        let corner_of =
            |k: usize| lower + Vec3::new((k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64) * edge;
        let data: Vec<Vec<f64>> = (0..8)
            .map(|k| {
                let x = corner_of(k);
                (0..3 * QUANTITIES)
                    .map(|i| poly(&x, i % QUANTITIES, i / QUANTITIES))
                    .collect()
            })
            .collect();
        let mut worst = 0.0f64;
        for n in 0..125 {
            let xi = [
                f64::from(n % 5) / 4.0,
                f64::from(n / 5 % 5) / 4.0,
                f64::from(n / 25) / 4.0,
            ];
            let x = lower + Vec3::new(xi[0], xi[1], xi[2]) * edge;
            let (u, g) = value_and_gradient(|k| &data[k], &xi, edge);
            for c in 0..3 {
                worst = worst.max((u[c] - poly(&x, 0, c)).abs());
                for b in 0..3 {
                    worst = worst.max((g[(c, b)] - poly(&x, 1 << b, c)).abs());
                }
            }
            for d in 0..QUANTITIES {
                let v = derivative(|k| &data[k], &xi, edge, d);
                for (c, vc) in v.iter().enumerate() {
                    worst = worst.max((vc - poly(&x, d, c)).abs());
                }
            }
        }
        // |f| and its derivatives are O(10) here; round-off of 64-term sums is ~1e-14.
        assert!(worst < 1e-12, "{worst:e}");
    }

    /// Two cubes side by side with one copy of the shared corners' data: value and normal
    /// derivative agree on the shared face for arbitrary (non-polynomial) data.
    #[test]
    fn neighbours_sharing_corner_data_join_with_their_first_derivatives() {
        let edge = 0.5;
        // Node data on a 3 × 2 × 2 lattice, pseudo-random.
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let nodes: Vec<Vec<f64>> = (0..12).map(|_| (0..3 * QUANTITIES).map(|_| next()).collect()).collect();
        let node = |i: usize, j: usize, k: usize| &nodes[i + 3 * (j + 2 * k)];
        let left = |k: usize| node(k & 1, (k >> 1) & 1, (k >> 2) & 1).as_slice();
        let right = |k: usize| node((k & 1) + 1, (k >> 1) & 1, (k >> 2) & 1).as_slice();
        let mut worst = 0.0f64;
        for n in 0..25 {
            let (s, t) = (f64::from(n % 5) / 4.0, f64::from(n / 5) / 4.0);
            let (ua, ga) = value_and_gradient(left, &[1.0, s, t], edge);
            let (ub, gb) = value_and_gradient(right, &[0.0, s, t], edge);
            worst = worst.max((ua - ub).amax()).max((ga - gb).amax());
        }
        assert!(worst < 1e-13, "{worst:e}");
    }
}

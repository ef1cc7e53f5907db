#!/usr/bin/env python3
"""Inertialess pseudo-rigid shape dynamics in NumPy/SciPy: an independent peer of pseudorigid.

Written from the paper (Wedel et al., "ellipsoidal soft micro-particles", Sec. 2-5) and the
Jeffery (1922) / Roscoe (1967) traction of an ellipsoid, not from the Rust code, so that
agreement between the two is evidence for both.

Physics (units: mu_f = 1, shear rate = 1, volume-equivalent diameter d_eq = 1):
  * F_bar = F S with S = diag(r_f, r_g, r_v), r_f r_g r_v = 1/8 (initial axes = identity);
    the current semi-axes are r_a = sqrt(eig(F_bar F_bar^T)), the principal directions n_a
    its eigenvectors, Q = [n_a . E_B].
  * Neo-Hooke (paper eq. 9): P = mu_s (F - F^-T) + lambda_s ln J F^-T, Cauchy stress
    sigma_el = P F^T / J, mu_s = 1/Ca, lambda_s = bulk_ratio mu_s.
  * Inertialess limit of eq. (18): Theta -> 0 gives P_tilde = P, i.e. sigma_tilde(l_s) =
    sigma_el(F). For an incompressible surface motion (tr l_s = 0) the mean normal stress of the
    traction is a Lagrange multiplier, so the balance is dev sigma_tilde(l_s) = dev sigma_el(F)
    together with tr l_s = 0: nine linear equations for the nine components of l_s.
  * sigma_tilde (paper eq. 12 structure, Jeffery-Roscoe) in the principal frame with
    g = l_f - l_s, d = dev sym g, w = skw g, d_s = sym l_s:
        sigma_tilde = -p 1 + s(d, w) + 2 d_s,
        s_ij = (4/abc) { d_ij / [a'_k (x_i + x_j)]
                         + x_j [(x_i + x_j) w_ij - (x_i - x_j) d_ij] / [(x_i + x_j)(x_i a_i + x_j a_j)] },
        s_ii = 4/(3 abc) (2 a''_i d_ii - a''_j d_jj - a''_k d_kk) / (a''_1 a''_2 + a''_2 a''_3 + a''_3 a''_1),
    with x_i = r_i^2 and Jeffery's integrals a_i, a'_k, a''_k (Carlson R_D, scipy.special.elliprd).
    The pressure p drops out of the deviatoric balance.
  * Shape ODE: dF/dt = l_s F, F(0) = 1, simple shear u = (y, 0, 0), l_f = e_1 (x) e_2.

Prints one JSON line with the solver statistics and F(t_end) (row-major), plus F at the output
times t = 1, 2, ..., t_end ("f_samples"), taken from the solver's dense output.
"""

import argparse
import json
import sys
import time

import numpy as np
from scipy.integrate import BDF, DOP853, LSODA, RK45, Radau, solve_ivp
from scipy.special import elliprd

# Off-diagonal index pairs (i, j) and the third index k (0-based).
_I = np.array([0, 1, 1, 2, 2, 0])
_J = np.array([1, 0, 2, 1, 0, 2])
_K = 3 - _I - _J
# Pairs (i, j) -> third index k for the three unordered pairs, indexed by k.
_PAIR_I = np.array([1, 2, 0])
_PAIR_J = np.array([2, 0, 1])
# Degenerate-pair threshold: below it the difference quotient for a'_k loses more digits
# (~1e-16 / 1e-5) than the O(delta^2) = 1e-10 error of the confluent evaluation.
_DEGENERATE = 1e-5


def jeffery_integrals(x):
    """Jeffery's integrals for squared semi-axes x (..., 3).

    Returns (abc, alpha, alpha1, alpha2) with alpha_i = int dl / ((x_i + l) Delta),
    alpha1[k] = a'_k = int dl / ((x_i + l)(x_j + l) Delta), alpha2[k] = a''_k = int l dl / (...),
    for the pair (i, j) complementary to k, Delta = sqrt(prod (x_m + l)).
    """
    abc = np.sqrt(np.prod(x, axis=-1))
    x1, x2, x3 = x[..., 0], x[..., 1], x[..., 2]
    alpha = (2.0 / 3.0) * np.stack([elliprd(x2, x3, x1), elliprd(x3, x1, x2), elliprd(x1, x2, x3)], axis=-1)
    xi, xj, xk = x[..., _PAIR_I], x[..., _PAIR_J], x[..., [0, 1, 2]]
    ai, aj = alpha[..., _PAIR_I], alpha[..., _PAIR_J]
    diff = xi - xj
    degenerate = np.abs(diff) <= _DEGENERATE * np.maximum(xi, xj)
    with np.errstate(divide="ignore", invalid="ignore"):
        alpha1 = np.where(degenerate, 0.0, (aj - ai) / np.where(degenerate, 1.0, diff))
    if np.any(degenerate):
        alpha1 = np.where(degenerate, _confluent_alpha1(0.5 * (xi + xj), xk), alpha1)
    alpha2 = ai - xj * alpha1
    return abc, alpha, alpha1, alpha2


def _confluent_alpha1(m, xk):
    """a' of the pair of equal squared semi-axes m in the spheroid (m, m, xk).

    From beta_i = int dl / ((x_i + l)^2 Delta) = a'_(ij) when x_i = x_j and the identity
    3 beta_i + a'_(ij) + a'_(ik) = 2 / (abc x_i): a'_(ij) = (2 / (abc m) - a'_(ik)) / 4.
    When xk is also close to m the sphere value 2 / (5 s^(5/2)) is used, with the mean
    s = (6 m + xk) / 7 weighted by how the integrand's exponents see each axis.
    """
    abc = m * np.sqrt(xk)
    a_m = (2.0 / 3.0) * elliprd(m, xk, m)
    a_k = (2.0 / 3.0) * elliprd(m, m, xk)
    near = np.abs(m - xk) <= _DEGENERATE * np.maximum(m, xk)
    with np.errstate(divide="ignore", invalid="ignore"):
        a_ik = np.where(near, 0.0, (a_k - a_m) / np.where(near, 1.0, m - xk))
    spheroid = (2.0 / (abc * m) - a_ik) / 4.0
    s = (6.0 * m + xk) / 7.0
    return np.where(near, 2.0 / (5.0 * s**2.5), spheroid)


def traction_s(g, geo):
    """Deviatoric part of sigma_tilde(l_s) without the 2 d_s term: s(dev sym g, skw g).

    g (..., 3, 3) in the principal frame; geo = (x, abc, alpha, alpha1, alpha2), each
    broadcastable against g's leading axes.
    """
    x, abc, alpha, alpha1, alpha2 = geo
    sym = 0.5 * (g + np.swapaxes(g, -1, -2))
    tr = np.trace(sym, axis1=-2, axis2=-1)
    d = sym - (tr / 3.0)[..., None, None] * np.eye(3)
    w = 0.5 * (g - np.swapaxes(g, -1, -2))
    s = np.zeros_like(g)
    xi, xj = x[..., _I], x[..., _J]
    a1k, a2k = alpha1[..., _K], alpha2[..., _K]
    xa = 2.0 * xi * xj * a1k + (xi + xj) * a2k  # = x_i a_i + x_j a_j
    dij, wij = d[..., _I, _J], w[..., _I, _J]
    s[..., _I, _J] = (4.0 / abc[..., None]) * (
        dij / (a1k * (xi + xj)) + xj * ((xi + xj) * wij - (xi - xj) * dij) / ((xi + xj) * xa)
    )
    sig2 = alpha2[..., 0] * alpha2[..., 1] + alpha2[..., 1] * alpha2[..., 2] + alpha2[..., 2] * alpha2[..., 0]
    ddiag = np.diagonal(d, axis1=-2, axis2=-1)
    weighted = alpha2 * ddiag
    diag = (4.0 / (3.0 * abc * sig2))[..., None] * (3.0 * weighted - weighted.sum(axis=-1, keepdims=True))
    s[..., [0, 1, 2], [0, 1, 2]] = diag
    return s


def _dev(a):
    return a - (np.trace(a, axis1=-2, axis2=-1) / 3.0)[..., None, None] * np.eye(3)


# Basis E_m of 3x3 matrices, m = 3 a + b (row-major), as the columns of the 9x9 system.
_BASIS = np.eye(9).reshape(9, 3, 3)
_SYM_BASIS = 0.5 * (_BASIS + np.swapaxes(_BASIS, -1, -2))
_TRACE_ROW = np.eye(3).reshape(9)


class Model:
    """The inertialess right-hand side dF/dt = l_s(F) F, batched over states."""

    def __init__(self, semi_axes, ca, bulk_ratio):
        r = np.asarray(semi_axes, dtype=float)
        r = r * (0.125 / np.prod(r)) ** (1.0 / 3.0)
        self.shape = np.diag(r)
        self.mu_s = 1.0 / ca
        self.lambda_s = bulk_ratio * self.mu_s
        self.l_f = np.zeros((3, 3))
        self.l_f[0, 1] = 1.0
        self.evals = 0

    def rate(self, f):
        """l_s for a batch of F (k, 3, 3)."""
        fbar = f @ self.shape
        x, v = np.linalg.eigh(fbar @ np.swapaxes(fbar, -1, -2))
        q = np.swapaxes(v, -1, -2)  # rows n_a
        qt = v
        abc, alpha, alpha1, alpha2 = jeffery_integrals(x)
        j = np.linalg.det(f)
        # dev sigma_el = (mu_s / J) dev(F F^T); the ln J term is isotropic.
        sig_el = (self.mu_s / j)[:, None, None] * _dev(f @ np.swapaxes(f, -1, -2))
        sig_el_p = q @ sig_el @ qt
        lf_p = q @ self.l_f @ qt
        # Affine map u -> dev sigma_tilde(l_s' = u) - dev sigma_el', u in the principal frame:
        # constant part at u = 0 and the columns of the linear part on the basis E_m.
        geo = (x, abc, alpha, alpha1, alpha2)
        const = traction_s(lf_p, geo) - sig_el_p
        geo_b = tuple(a[:, None, ...] for a in geo)
        cols = traction_s(np.broadcast_to(-_BASIS, (len(f), 9, 3, 3)), geo_b) + 2.0 * _dev(_SYM_BASIS)[None]
        mat = cols.reshape(-1, 9, 9).swapaxes(-1, -2)
        rhs = -const.reshape(-1, 9)
        # The deviatoric rows sum to zero on the diagonal: replace the (3,3) row by tr l_s = 0.
        mat[:, 8, :] = _TRACE_ROW
        rhs[:, 8] = 0.0
        u = np.linalg.solve(mat, rhs[..., None])[..., 0].reshape(-1, 3, 3)
        return qt @ u @ q

    def __call__(self, _t, y):
        """solve_ivp right-hand side; y is (9,) or (9, k) when vectorized."""
        batch = y.reshape(9, -1).T.reshape(-1, 3, 3)
        self.evals += batch.shape[0]
        df = self.rate(batch) @ batch
        return df.reshape(-1, 9).T.reshape(y.shape)


METHODS = {"Radau": Radau, "LSODA": LSODA, "BDF": BDF, "DOP853": DOP853, "RK45": RK45}


def counting(method):
    """`method` with a count of accepted steps (solve_ivp calls `step` once per accepted step)."""

    class Counted(method):
        steps = 0

        def step(self):
            message = super().step()
            if self.status != "failed":
                Counted.steps += 1
            return message

    return Counted


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n", 1)[0])
    p.add_argument("--axes", default="2.5,1,2.5", help="semi-axes along flow,gradient,vorticity")
    p.add_argument("--ca", type=float, default=0.4)
    p.add_argument("--bulk-ratio", type=float, default=1000.0)
    p.add_argument("--t-end", type=float, default=30.0)
    p.add_argument("--method", default="Radau", choices=sorted(METHODS))
    p.add_argument("--rtol", type=float, default=1e-6)
    p.add_argument("--atol", type=float, default=None, help="defaults to rtol")
    p.add_argument(
        "--reference",
        action="store_true",
        help="high-accuracy run: --method at rtol = atol = 1e-13 (overrides --rtol/--atol)",
    )
    p.add_argument(
        "--no-vectorized",
        action="store_true",
        help="evaluate the finite-difference Jacobian column by column (Radau/BDF only)",
    )
    return p.parse_args(argv)


def main(argv):
    args = parse_args(argv)
    axes = [float(a) for a in args.axes.split(",")]
    if len(axes) != 3 or min(axes) <= 0.0 or not np.all(np.isfinite(axes)):
        raise SystemExit(f"--axes needs three positive numbers, got {args.axes!r}")
    if not (args.ca > 0.0 and args.bulk_ratio > 0.0 and args.t_end > 0.0):
        raise SystemExit(f"need Ca, bulk ratio, t_end > 0, got {args.ca}, {args.bulk_ratio}, {args.t_end}")
    rtol = 1e-13 if args.reference else args.rtol
    atol = 1e-13 if args.reference else (args.atol if args.atol is not None else rtol)
    model = Model(axes, args.ca, args.bulk_ratio)
    samples = np.arange(1.0, np.floor(args.t_end) + 1.0)
    samples = samples[samples < args.t_end]
    t_eval = np.append(samples, args.t_end)
    vectorized = args.method in ("Radau", "BDF") and not args.no_vectorized
    counted = counting(METHODS[args.method])
    start = time.perf_counter()
    sol = solve_ivp(
        model,
        (0.0, args.t_end),
        np.eye(3).reshape(9),
        method=counted,
        t_eval=t_eval,
        rtol=rtol,
        atol=atol,
        vectorized=vectorized,
    )
    wall = time.perf_counter() - start
    if not sol.success:
        print(json.dumps({"error": sol.message, "method": args.method, "rtol": rtol}))
        return 1
    f = sol.y.T
    print(
        json.dumps(
            {
                "method": args.method,
                "rtol": rtol,
                "atol": atol,
                "steps": counted.steps,
                "rhs_evals": model.evals,
                "nfev": int(sol.nfev),
                "jac_evals": int(sol.njev),
                "lu": int(sol.nlu),
                "wall_s": wall,
                "t_samples": t_eval.tolist(),
                "f_samples": [row.tolist() for row in f],
                "f_end": f[-1].tolist(),
            }
        )
    )
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

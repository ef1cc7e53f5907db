#!/usr/bin/env python3
"""Checks of the SciPy peer against closed forms, independent of the Rust library.

Run: python3 benches/peers/test_inertialess.py  (plain asserts; pytest also collects it)
"""

import os
import sys

import numpy as np
from scipy.integrate import quad, solve_ivp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import inertialess as peer  # noqa: E402


def quadrature_integrals(x):
    """Jeffery's integrals by adaptive quadrature on lambda in [0, inf)."""
    delta = lambda l: np.sqrt(np.prod(x + l))  # noqa: E731
    alpha = [quad(lambda l, i=i: 1.0 / ((x[i] + l) * delta(l)), 0, np.inf, epsabs=0, epsrel=1e-13)[0] for i in range(3)]
    alpha1 = []
    for k in range(3):
        i, j = [m for m in range(3) if m != k]
        alpha1.append(quad(lambda l: 1.0 / ((x[i] + l) * (x[j] + l) * delta(l)), 0, np.inf, epsabs=0, epsrel=1e-13)[0])
    return np.array(alpha), np.array(alpha1)


def test_integrals_match_quadrature_and_sphere():
    # Carlson R_D is accurate to round-off; quadrature to its requested 1e-13 relative, so 1e-10
    # leaves room for the O(delta^2) = 1e-12 confluent branch at delta ~ 1e-6.
    for x in ([4.0, 1.0, 0.25], [1.0, 1.0 + 1e-6, 2.0], [25.0, 1.0, 1.0], [1.0, 1.0, 1.0]):
        x = np.array(x)
        abc, alpha, alpha1, _ = peer.jeffery_integrals(x[None])
        qa, qa1 = quadrature_integrals(x)
        assert np.allclose(alpha[0], qa, rtol=1e-10, atol=0), (x, alpha, qa)
        assert np.allclose(alpha1[0], qa1, rtol=1e-10, atol=0), (x, alpha1, qa1)
        # identity abc (alpha_1 + alpha_2 + alpha_3) = 2, exact up to round-off
        assert abs(abc[0] * alpha[0].sum() - 2.0) < 1e-13
    # sphere of radius a: alpha = 2/(3 a^3), alpha' = 2/(5 a^5), alpha'' = 4/(15 a^3)
    a = 0.5
    _, alpha, alpha1, alpha2 = peer.jeffery_integrals(np.full((1, 3), a * a))
    assert np.allclose(alpha, 2 / (3 * a**3), rtol=1e-14)
    assert np.allclose(alpha1, 2 / (5 * a**5), rtol=1e-14)
    assert np.allclose(alpha2, 4 / (15 * a**3), rtol=1e-14)


def test_sphere_traction():
    # Sphere: s(d, w) = 5 d + 3 w (stresslet (20/3) pi mu a^3 E, torque 8 pi mu a^3 (omega_f - omega_s)).
    a = 0.5
    x = np.full((1, 3), a * a)
    geo = (x,) + peer.jeffery_integrals(x)
    g = np.random.default_rng(1).normal(size=(1, 3, 3))
    d = 0.5 * (g + g.transpose(0, 2, 1))
    d -= np.trace(d[0]) / 3 * np.eye(3)
    w = 0.5 * (g - g.transpose(0, 2, 1))
    assert np.allclose(peer.traction_s(g, geo), 5 * d + 3 * w, rtol=0, atol=1e-12)


def test_rigid_prolate_follows_jeffery_orbit():
    # Quasi-rigid prolate r = 3 (Ca = 1e-5, flow-aligned at t = 0) over t = 6, through the fast
    # flip (the angle turns by ~2 rad): the long axis follows tan phi = r tan(t r / (r^2 + 1))
    # up to the elastic deviation, first order in Ca (~ Ca t = 6e-5), and the solver's 1e-9. The
    # bound 1e-3 is well above both; a wrong skew (rotation) part of the traction misses by O(1).
    r, ca = 3.0, 1e-5
    model = peer.Model([r, 1.0, 1.0], ca, 1000.0)
    t = 6.0
    sol = solve_ivp(model, (0, t), np.eye(3).reshape(9), method="Radau", rtol=1e-9, atol=1e-9)
    f = sol.y[:, -1].reshape(3, 3)
    axis = f @ np.array([1.0, 0.0, 0.0])
    phi_num = np.arctan2(axis[0], axis[1])  # from the gradient axis towards the flow
    # Jeffery's angle from the gradient axis for an orbit that starts flow-aligned (phi = pi/2)
    t0 = (r * r + 1) / r * np.pi / 2
    phi = np.arctan2(r * np.sin((t0 + t) * r / (r * r + 1)), np.cos((t0 + t) * r / (r * r + 1)))
    d = (phi_num - phi + np.pi / 2) % np.pi - np.pi / 2
    assert abs(d) < 1e-3, (phi_num, phi)


def test_volume_is_preserved():
    # tr l_s = 0 makes det F = 1 exactly for the flow; the solver keeps it to its tolerance.
    model = peer.Model([2.5, 1.0, 2.5], 0.4, 1000.0)
    sol = solve_ivp(model, (0, 5), np.eye(3).reshape(9), method="Radau", rtol=1e-10, atol=1e-10)
    assert abs(np.linalg.det(sol.y[:, -1].reshape(3, 3)) - 1.0) < 1e-8


if __name__ == "__main__":
    for name, fn in sorted(globals().items()):
        if name.startswith("test_") and callable(fn):
            fn()
            print(f"ok {name}")

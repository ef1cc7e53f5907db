"""One particle from a notebook, and the OpenFOAM probe."""

from __future__ import annotations

import math
import subprocess

import numpy as np
import pytest

import pseudorigid as pr


def test_rigid_prolate_returns_after_one_jeffery_period():
    """A rigid prolate of aspect ratio λ in unit shear, its axis in the shear plane, rotates with
    Jeffery's period T = 2π(λ + 1/λ); at t = T its F is the identity again. The integrator's
    tolerance 1e-10 per step, over the ~10³ steps of one period, leaves an error far below
    the 1e-6 asserted; a wrong spin rate of even 1e-5 relative gives |F - 1| ~ 2π·1e-5 > 1e-6."""
    lam = 2.0
    period = 2 * math.pi * (lam + 1 / lam)
    out = pr.integrate(
        {"type": "shear", "rate": 1.0},
        [lam, 1.0, 1.0],
        t_end=period,
        every=period / 8,
        integrator={"type": "stokesian", "tol": 1e-10, "dt": 1e-4, "overdamped": True},
    )
    assert out["fate"] == "suspended"
    assert out["t"][-1] == period and out["t"].shape == (9,)
    assert out["F"].shape == (9, 3, 3) and out["x"].shape == (9, 3)
    np.testing.assert_allclose(out["F"][-1], np.eye(3), atol=1e-6)
    # Half-way the axis has turned by π: F = diag(-1, -1, 1).
    np.testing.assert_allclose(out["F"][4], np.diag([-1.0, -1.0, 1.0]), atol=1e-6)
    # Rigid: the semi-axes never change; det F = 1.
    np.testing.assert_allclose(out["r"], np.tile([lam, 1.0, 1.0], (9, 1)), rtol=1e-12)
    np.testing.assert_allclose(np.linalg.det(out["F"]), 1.0, atol=1e-12)


def test_integrate_keeps_a_trajectory_by_default():
    """Without ``every`` the particle's states are kept every t_end/100: 101 of them, evenly
    spaced (before, only the start and the end)."""
    out = pr.integrate({"type": "shear", "rate": 1.0}, [2.0, 1.0, 1.0], t_end=2.0)
    assert out["t"].shape == (101,)
    np.testing.assert_allclose(np.diff(out["t"]), 0.02, rtol=1e-9)


def test_bad_particle_input_raises():
    with pytest.raises(pr.SceneError):
        pr.integrate({"type": "shear", "rate": 1.0}, [1.0, math.nan, 1.0], t_end=1.0)
    with pytest.raises(pr.SceneError):
        pr.integrate({"type": "vortex"}, [1.0, 1.0, 1.0], t_end=1.0)


def test_failed_step_raises_step_error():
    """A one-step budget cannot reach t_end: the particle fails and integrate raises."""
    with pytest.raises(pr.StepError):
        pr.integrate(
            {"type": "shear", "rate": 1.0},
            [2.0, 1.0, 1.0],
            material={"law": "neo_hooke", "mu": 2.5, "lambda": 2500.0},
            t_end=10.0,
            max_steps=1,
        )


@pytest.mark.parametrize("cellwise", [False, True])
def test_foam_flow_equals_the_probe_command(tmp_path, root, cli, cellwise):
    case = root / "reference-data" / "bifurcation"
    flow = pr.FoamFlow(case, cellwise=cellwise)
    assert flow.time == 190.0 and flow.cells > 0
    # Along the inlet's axis into the airway, and one point far outside.
    pts = np.array([[2e-4 + 1e-3 * k, 1e-4, -2e-4] for k in range(20)] + [[1.0, 1.0, 1.0]])
    u, grad, inside = flow.sample(pts)
    assert u.shape == (21, 3) and grad.shape == (21, 3, 3) and inside.dtype == bool
    assert inside[:3].all() and not inside[-1] and np.isnan(u[-1]).all()
    (tmp_path / "p.csv").write_text("x,y,z\n" + "\n".join(",".join(repr(float(c)) for c in p) for p in pts))
    command = [str(cli), "probe", str(case), "latest", str(tmp_path / "p.csv"), str(tmp_path / "o.csv")]
    subprocess.run(command + (["--cellwise"] if cellwise else []), check=True)
    table = np.genfromtxt(tmp_path / "o.csv", delimiter=",", names=True)
    np.testing.assert_array_equal(table["inside"] == 1, inside)
    for i in range(3):
        np.testing.assert_array_equal(table[f"u{i + 1}"], u[:, i])
        for j in range(3):
            np.testing.assert_array_equal(table[f"l{i + 1}{j + 1}"], grad[:, i, j])
    with pytest.raises(pr.ParameterError):
        flow.sample(np.zeros((2, 2)))
    with pytest.raises(pr.ParameterError):
        flow.sample(np.array([[0.0, math.nan, 0.0]]))

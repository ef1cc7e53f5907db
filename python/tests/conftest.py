"""Shared fixtures: the repository, the `pseudorigid` command, a small shipped scene."""

from __future__ import annotations

import os
import pathlib
import subprocess

import pytest

import pseudorigid as pr

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def root() -> pathlib.Path:
    return ROOT


@pytest.fixture(scope="session")
def cli() -> pathlib.Path:
    """The command as the README builds it (`cargo build --release`; a no-op when up to date),
    or $PSEUDORIGID_CLI. Its default features include `parquet`, as the package's do, so its
    runs write the same files as the package's."""
    given = os.environ.get("PSEUDORIGID_CLI")
    if given:
        return pathlib.Path(given)
    subprocess.run(["cargo", "build", "--release", "--bin", "pseudorigid"], cwd=ROOT, check=True)
    # Where cargo put it: $CARGO_TARGET_DIR if set (as for `cargo build`), else target/.
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    return (target if target.is_absolute() else ROOT / target) / "release" / "pseudorigid"


@pytest.fixture()
def small_scene() -> dict:
    """scenes/shear_injection.toml with 12 particles to t = 2 (about 0.1 s of work)."""
    d = pr.Scene.from_toml(ROOT / "scenes" / "shear_injection.toml").to_dict()
    d["particles"]["inject"]["count"] = 12
    d["end"]["t_end"] = 2.0
    return d

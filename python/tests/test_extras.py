"""Optional dependencies (issue 39, item 4): numpy is the only requirement, so a missing pandas
or tqdm must say which extra installs it rather than fail with a bare import error (pandas) or
draw nothing without a word (tqdm)."""

from __future__ import annotations

import sys

import numpy as np
import pytest

import pseudorigid as pr


def test_to_pandas_without_pandas_names_the_extra(monkeypatch):
    # None in sys.modules makes `import pandas` fail as if it were not installed.
    monkeypatch.setitem(sys.modules, "pandas", None)
    table = pr.Table(a=np.arange(3.0))
    with pytest.raises(ModuleNotFoundError, match=r"pseudorigid\[pandas\]") as refused:
        table.to_pandas()
    assert refused.value.name == "pandas"


def test_progress_without_tqdm_warns_and_runs(monkeypatch, small_scene):
    monkeypatch.setitem(sys.modules, "tqdm", None)
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)
    with pytest.warns(RuntimeWarning, match=r"pseudorigid\[progress\]"):
        results = pr.run_in_memory(pr.Scene.from_dict(small_scene), threads=1, progress=True)
    assert len(results) == small_scene["particles"]["inject"]["count"]

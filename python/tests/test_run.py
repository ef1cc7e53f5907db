"""The Python run is the command's run: the same files, byte for byte."""

from __future__ import annotations

import _thread
import copy
import csv
import gzip
import json
import math
import pathlib
import signal
import subprocess
import warnings

import numpy as np
import pytest

import pseudorigid as pr

# The runner's own checkpoint chunks hold records in the order the workers finished them, which
# differs between any two parallel runs (of the command too); every result file is compared.
def result_files(out: pathlib.Path) -> list:
    return sorted(
        p.relative_to(out).as_posix()
        for p in out.rglob("*")
        if p.is_file() and not p.relative_to(out).as_posix().startswith("checkpoint-")
    )


PARQUET = {"records.parquet", "frames.parquet"}


def assert_same_files(cli: pathlib.Path, py: pathlib.Path) -> None:
    """The command's run and the Python run hold the same files, byte for byte, Parquet tables
    included (both are built with the feature `parquet`, the command's default)."""
    files = result_files(cli)
    mine = set(result_files(py))
    assert set(files) == mine, mine ^ set(files)
    if (py / "results.csv").exists():
        assert PARQUET <= mine
    assert "results.csv" in files or any(f.startswith("results-") for f in files)
    assert not any(f.endswith(".json") for f in mine), "records are written once: the checkpoint"
    for f in files:
        assert (cli / f).read_bytes() == (py / f).read_bytes(), f


def cli_run(cli, scene_file, out, *extra):
    subprocess.run([str(cli), "run", str(scene_file), "--out", str(out), "--quiet", *extra], check=True)


def test_run_equals_cli_byte_for_byte(tmp_path, cli, small_scene):
    scene = pr.Scene.from_dict(small_scene)
    # The command reads the same TOML text, so the runs share their configuration hash.
    (tmp_path / "scene.toml").write_text(scene.to_toml())
    cli_run(cli, tmp_path / "scene.toml", tmp_path / "cli", "--csv")
    calls = []
    results = pr.run(scene, tmp_path / "py", threads=2, progress=lambda d, t: calls.append((d, t)), csv=True)
    assert_same_files(tmp_path / "cli", tmp_path / "py")
    assert (tmp_path / "py" / "vtk" / "trajectories.vtp").exists()
    assert calls[-1] == (12, 12)
    assert len(results) == 12 and results.counts()["suspended"] == 12


def test_shipped_scene_file_equals_cli(tmp_path, cli, root):
    scene_file = root / "scenes" / "oblate_shear.toml"
    cli_run(cli, scene_file, tmp_path / "cli", "--csv")
    pr.run(pr.Scene.from_toml(scene_file), tmp_path / "py", csv=True)
    assert_same_files(tmp_path / "cli", tmp_path / "py")


def test_adequacy_is_the_commands_file(tmp_path, cli, root, small_scene):
    """On an OpenFOAM field `run` returns the command's `adequacy.json` (the same run through
    the binding) and raises its warning lines; a run on an analytic flow has none, and
    removes an earlier run's file from its folder."""
    scene_file = root / "scenes" / "bifurcation.toml"
    cli_run(cli, scene_file, tmp_path / "cli")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        results = pr.run(pr.Scene.from_toml(scene_file), tmp_path / "py")
    expected = json.loads((tmp_path / "cli" / "adequacy.json").read_text())
    assert results.adequacy == expected
    pairing = expected["sensitivity"]["pairing"]
    assert sum(pairing.values()) == 20 and len(expected["sensitivity"]["particles"]) == 20
    assert expected["resolution"]["walls"]["faces"] > 0
    assert any(line.startswith("note: adequacy: the first 20 particles re-tracked") for line in expected["log"])
    warned = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]
    assert warned == [line[len("warning: ") :] for line in expected["log"] if line.startswith("warning: ")]
    # The library's diagnostic from Python, of the run read back: the command's file.
    with warnings.catch_warnings(record=True) as again:
        warnings.simplefilter("always")
        assert pr.adequacy(scene_file, pr.load_results(tmp_path / "py")) == expected
    assert [str(w.message) for w in again if issubclass(w.category, RuntimeWarning)] == warned
    (tmp_path / "shear").mkdir()
    (tmp_path / "shear" / "adequacy.json").write_text(json.dumps(expected))
    assert pr.run(pr.Scene.from_dict(small_scene), tmp_path / "shear").adequacy is None
    assert pr.adequacy(small_scene, pr.run_in_memory(small_scene)) is None
    assert not (tmp_path / "shear" / "adequacy.json").exists()


def test_shard_equals_cli_shard(tmp_path, cli, small_scene):
    scene = pr.Scene.from_dict(small_scene)
    (tmp_path / "scene.toml").write_text(scene.to_toml())
    cli_run(cli, tmp_path / "scene.toml", tmp_path / "cli", "--shard", "1/3", "--csv")
    results = pr.run(scene, tmp_path / "py", shard=(1, 3), threads=1, csv=True)
    assert_same_files(tmp_path / "cli", tmp_path / "py")
    assert list(results.records()["index"]) == [1, 4, 7, 10]


def test_interrupted_run_resumes_to_the_cli_files(tmp_path, cli, root):
    """Ctrl-C (a SIGINT seen between polls) stops the run; resume gives the command's files."""
    d = pr.Scene.from_toml(root / "scenes" / "shear_injection.toml").to_dict()
    scene = pr.Scene.from_dict(d)
    (tmp_path / "scene.toml").write_text(scene.to_toml())
    seen = []

    def interrupt(done, total):
        seen.append((done, total))
        _thread.interrupt_main()  # what Ctrl-C does: the signal is checked after this call

    # A shell starts background jobs with SIGINT ignored, and `interrupt_main` does nothing
    # for an ignored signal: install Python's own handler, as an interactive session has it.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            # One thread: 60 particles take about a second, the first poll comes after 0.1 s.
            pr.run(scene, tmp_path / "py", threads=1, checkpoint_every=0.05, progress=interrupt)
    finally:
        signal.signal(signal.SIGINT, previous)
    done, total = seen[0]
    assert total == 60 and done < total
    assert not (tmp_path / "py" / "records.parquet").exists()
    pr.run(scene, tmp_path / "py", resume=True, csv=True)
    cli_run(cli, tmp_path / "scene.toml", tmp_path / "cli", "--csv")
    assert_same_files(tmp_path / "cli", tmp_path / "py")


def test_progress_callback_error_stops_the_run(tmp_path, small_scene):
    def boom(done, total):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        pr.run(pr.Scene.from_dict(small_scene), tmp_path / "py", progress=boom)
    # The output folder holds the interrupted run's checkpoint: a fresh run refuses it.
    with pytest.raises(pr.PopulationError, match="resume"):
        pr.run(pr.Scene.from_dict(small_scene), tmp_path / "py")


def read_csv(path: pathlib.Path) -> dict:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return {name: [r[i] for r in rows[1:]] for i, name in enumerate(rows[0])}


def floats(values) -> np.ndarray:
    return np.array([float(v) if v != "" else np.nan for v in values])


def test_columns_equal_the_csv_files(tmp_path, small_scene):
    """records() and frames() hold exactly the numbers of results.csv and frames.csv (written
    with shortest round-trip formatting, so parsing them back is exact)."""
    scene = pr.Scene.from_dict(small_scene)
    results = pr.run(scene, tmp_path, csv=True)
    rec = results.records()
    table = read_csv(tmp_path / "results.csv")
    assert list(rec["index"]) == [int(i) for i in table["index"]]
    assert list(rec["fate"]) == table["fate"]
    for c in ["t", "x1", "x2", "x3", "r1", "r2", "r3", "x0_1", "rest_r1", "mu_s"]:
        np.testing.assert_array_equal(rec[c], floats(table[c]), err_msg=c)
    frames = results.frames()
    ftable = read_csv(tmp_path / "frames.csv")
    assert len(frames) == len(ftable["id"]) == 12 * len(scene.frame_times)
    # One schema: the frames hold exactly the columns of frames.csv, in its order.
    assert list(frames.columns) == list(ftable)
    for c in ["time", "x1", "x2", "x3", "V11", "V12", "V21", "V23", "V32", "V33", "r1", "r2", "r3"]:
        np.testing.assert_array_equal(frames[c], floats(ftable[c]), err_msg=c)
    for c in ["frame", "id", "flag"]:
        np.testing.assert_array_equal(frames[c], [int(v) for v in ftable[c]], err_msg=c)
    # The same records in memory and from the files.
    mem = pr.run_in_memory(scene).records()
    for c in rec:
        np.testing.assert_array_equal(mem[c], rec[c], err_msg=c)
    pd = pytest.importorskip("pandas")
    df = rec.to_pandas()
    assert isinstance(df, pd.DataFrame) and df.shape == (12, len(rec.columns))


def test_records_carry_the_slow_manifold_switch(small_scene):
    """The particles made stiff (mu_s = 2 500, Ca = 4e-4) under `slow_manifold` at tol 1e-3
    step on the slow manifold: for each, manifold_steps + full_steps = steps and the largest
    delta on it is at most delta_max = sqrt(tol). Under the scene's own integrator no particle
    has a step on it, all its steps are the full model's and the delta columns are NaN."""
    stiff = copy.deepcopy(small_scene)
    stiff["particles"]["inject"]["material"] = {"law": "neo_hooke", "mu": 2500.0, "lambda": 2.5e6}
    stiff["integrator"] = {"type": "slow_manifold", "tol": 1e-3, "dt": 1e-3, "overdamped": True}
    rec = pr.run_in_memory(stiff).records()
    assert (rec["manifold_steps"] > 0).all(), rec["manifold_steps"]
    np.testing.assert_array_equal(rec["manifold_steps"] + rec["full_steps"], rec["steps"])
    np.testing.assert_array_equal(rec["manifold_delta_max"], np.full(12, math.sqrt(1e-3)))
    assert (rec["manifold_max_ratio"] <= rec["manifold_delta_max"]).all(), rec["manifold_max_ratio"]
    full = pr.run_in_memory(small_scene).records()
    assert (full["manifold_steps"] == 0).all()
    np.testing.assert_array_equal(full["full_steps"], full["steps"])
    assert np.isnan(full["manifold_max_ratio"]).all() and np.isnan(full["manifold_delta_max"]).all()


def test_edited_checkpoint_chunk_is_refused(tmp_path, small_scene):
    """A digit changed in a checkpoint chunk (valid JSON still) stops the resume with a
    PopulationError naming the chunk, instead of resuming into different results."""
    scene = pr.Scene.from_dict(small_scene)
    pr.run(scene, tmp_path)
    chunk = next((tmp_path / "checkpoint-0000-of-0001").glob("chunk-*.json.gz"))
    text = gzip.decompress(chunk.read_bytes()).decode()
    at = text.index('"steps":') + len('"steps":')
    digit = "1" if text[at] == "9" else str(int(text[at]) + 1)
    chunk.write_bytes(gzip.compress((text[:at] + digit + text[at + 1 :]).encode()))
    with pytest.raises(pr.PopulationError, match="checksum") as info:
        pr.run(scene, tmp_path, resume=True)
    assert str(chunk) in str(info.value)
    chunk.write_bytes(gzip.compress(text.encode()))
    assert len(pr.run(scene, tmp_path, resume=True)) == 12


def bits(values) -> np.ndarray:
    """The f64 bit patterns (null read back as NaN, as the columns hold it)."""
    return np.array([np.nan if v is None else v for v in values], dtype=np.float64).view(np.int64)


def test_parquet_tables_hold_the_records_bit_for_bit(tmp_path, small_scene):
    pq = pytest.importorskip("pyarrow.parquet")
    results = pr.run(pr.Scene.from_dict(small_scene), tmp_path)
    rec = results.records()
    table = pq.read_table(tmp_path / "records.parquet").to_pydict()
    assert table["index"] == list(rec["index"]) and table["fate"] == list(rec["fate"])
    floats = [c for c in rec if rec[c].dtype == np.float64]
    assert {"t", "x1", "r3", "F23", "x0_2", "rest_r1", "mu_s"} <= set(floats)
    for c in floats:
        np.testing.assert_array_equal(bits(table[c]), rec[c].view(np.int64), err_msg=c)
    for c in ["steps", "rejected", "rhs_evals", "jac_evals"]:
        assert table[c] == list(rec[c]), c
    assert table["patch"] == [None] * 12 and table["error"] == [None] * 12
    # The same columns in the same order, and the same nulls (None in the integer and text
    # columns; NaN, checked above through the bits, in the float columns).
    assert rec.columns == list(table.keys())
    for c in ["patch", "patch_name", "error"]:
        assert list(rec[c]) == table[c], c
    frames = results.frames()
    ft = pq.read_table(tmp_path / "frames.parquet").to_pydict()
    assert frames.columns == list(ft.keys())
    assert len(ft["id"]) == len(frames)
    for c in ["frame", "id", "flag"]:
        assert ft[c] == list(frames[c]), c
    for c in ["time", "x1", "x2", "x3", "V11", "V12", "V13", "V22", "V23", "V33", "r1", "r2", "r3"]:
        np.testing.assert_array_equal(bits(ft[c]), frames[c].view(np.int64), err_msg=c)


def test_run_returns_what_its_checkpoint_holds(tmp_path, small_scene):
    """`run` hands back the records it wrote instead of reading them back: they equal what
    `load_results` reads from the checkpoint, bit for bit, records, frames and trajectories."""
    scene = pr.Scene.from_dict(small_scene)
    ran = pr.run(scene, tmp_path, threads=2)
    loaded = pr.load_results(tmp_path, scene)
    a, b = ran.records(), loaded.records()
    assert list(a) == list(b)
    for c in a:
        if a[c].dtype == np.float64:
            np.testing.assert_array_equal(a[c].view(np.int64), b[c].view(np.int64), err_msg=c)
        else:
            assert list(a[c]) == list(b[c]), c
    fa, fb = ran.frames(), loaded.frames()
    for c in fa:
        assert np.array_equal(np.asarray(fa[c]), np.asarray(fb[c])), c
    np.testing.assert_array_equal(ran.trajectory(3)["F"], loaded.trajectory(3)["F"])


def test_parquet_shards_read_as_one_dataset(tmp_path, small_scene):
    """Three shards' tables, read as one folder each, are the whole run's tables (sorted by
    particle, and by frame and particle)."""
    pq = pytest.importorskip("pyarrow.parquet")
    scene = pr.Scene.from_dict(small_scene)
    for k in range(3):
        pr.run(scene, tmp_path / "shards", shard=(k, 3))
    whole = pr.run(scene, tmp_path / "whole")
    records = pq.read_table(tmp_path / "shards" / "records").sort_by("index")
    assert records.equals(pq.read_table(tmp_path / "whole" / "records.parquet"))
    frames = pq.read_table(tmp_path / "shards" / "frames").sort_by([("frame", "ascending"), ("id", "ascending")])
    assert frames.equals(pq.read_table(tmp_path / "whole" / "frames.parquet"))
    assert frames.num_rows == len(whole.frames())


def test_results_are_written_once(tmp_path, small_scene):
    """Without csv=True a run writes its records once as a table (Parquet) beside the
    checkpoint, and no JSON outside it; a sharded folder loads as the merged run."""
    scene = pr.Scene.from_dict(small_scene)
    whole = pr.run(scene, tmp_path / "whole")
    top = {p.name for p in (tmp_path / "whole").iterdir() if p.is_file()}
    assert top == {"records.parquet", "frames.parquet", "particles.pvd"}, top
    for k in range(2):
        pr.run(scene, tmp_path / "shards", shard=(k, 2))
    merged = pr.load_results(tmp_path / "shards", scene)
    for c, values in whole.records().items():
        np.testing.assert_array_equal(merged.records()[c], values, err_msg=c)
    assert merged.config_hash == whole.config_hash

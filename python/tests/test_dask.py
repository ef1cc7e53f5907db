"""The Dask recipe: a (Ca, shape) sweep and a sharded run on a LocalCluster of two worker
processes gather into the DataFrames of single-process runs, value for value."""

from __future__ import annotations

import pytest

import pseudorigid as pr

distributed = pytest.importorskip("dask.distributed")
pd = pytest.importorskip("pandas")
prd = pytest.importorskip("pseudorigid.dask")


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    )
    with distributed.Client(cluster) as c:
        yield c
    cluster.close()


def sweep(small_scene):
    """(Ca, shape): two capillary numbers (μ_s = 1/Ca) by an oblate and a prolate, 4 particles
    each to t = 1."""
    small_scene["particles"]["inject"]["count"] = 4
    small_scene["end"]["t_end"] = 1.0
    shapes = {"oblate": [0.6786044041487266, 0.27144176165949063, 0.6786044041487266], "prolate": [1.0, 0.5, 0.5]}
    return [
        (
            {"Ca": ca, "shape": shape},
            prd.with_values(
                small_scene,
                {
                    "particles.inject.material.mu": 1.0 / ca,
                    "particles.inject.material.lambda": 1000.0 / ca,
                    "particles.inject.semi_axes": axes,
                },
            ),
        )
        for ca in (0.2, 0.4)
        for shape, axes in shapes.items()
    ]


def test_sweep_gathers_the_single_process_records(client, small_scene):
    cases = sweep(small_scene)
    df = prd.run_cases(cases, client, threads=1)
    # Every case ran on a worker process, not here.
    assert len({w for w in client.scheduler_info()["workers"]}) == 2
    expected = pd.concat(
        [prd.run_case(labels, scene, threads=2) for labels, scene in cases], ignore_index=True
    )
    pd.testing.assert_frame_equal(df, expected, check_exact=True)
    assert list(df.columns[:2]) == ["Ca", "shape"] and len(df) == 16
    # The parameters took effect: the prolate cases' rest semi-axes, the moduli 1/Ca.
    assert set(df.loc[df["shape"] == "prolate", "rest_r1"]) == {1.0}
    assert set(df["mu_s"]) == {5.0, 2.5}


def test_shards_gather_the_whole_run(client, small_scene, tmp_path):
    scene = pr.Scene.from_dict(small_scene)
    df = prd.run_shards(scene, tmp_path / "shards", 3, client, threads=1)
    whole = pr.run_in_memory(scene).records().to_pandas()
    pd.testing.assert_frame_equal(df, whole, check_exact=True)
    # The shards' files are there too: the merged checkpoints are the same run.
    assert pr.load_results(tmp_path / "shards").config_hash == pr.run_in_memory(scene).config_hash


def test_bad_thread_count_is_a_parameter_error(client, small_scene):
    with pytest.raises(pr.ParameterError, match="threads"):
        prd.run_cases([({}, small_scene)], client, threads=0)

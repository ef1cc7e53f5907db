"""Parameter sweeps and sharded runs on a Dask cluster (``dask.distributed``).

Dask is the scheduler: this module only maps pseudorigid's units of work onto its tasks.
Each task is one case of a sweep (a scene, e.g. one (Stk, Ca, shape) point) or one shard
``k/n`` of a scene, run by the Rust library on ``threads`` threads of its own (rayon); the
results come back as pandas DataFrames and are gathered into one.

>>> from dask.distributed import Client, LocalCluster
>>> import pseudorigid as pr, pseudorigid.dask as prd
>>> base = pr.Scene.from_toml("scenes/shear_injection.toml").to_dict()
>>> cases = [({"Ca": ca}, prd.with_values(base, {"particles.inject.material.mu": 1 / ca}))
...          for ca in (0.1, 0.2, 0.4)]
>>> with Client(LocalCluster(n_workers=2, threads_per_worker=1)) as client:
...     df = prd.run_cases(cases, client, threads=1)   # one row per particle, plus a column Ca

Choose ``threads`` and the workers' ``threads_per_worker`` together: a worker runs up to
``threads_per_worker`` tasks at once, each on ``threads`` cores, so give each worker process
``threads_per_worker * threads`` cores (on Slurm: ``cores`` of ``SLURMCluster``; see
``python/README.md``). A case's records do not depend on ``threads`` (each particle's record
is a pure function of the scene, the seed and its index), so the gathered table equals a
single-process run's.
"""

from __future__ import annotations

import copy
import os
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

from . import Scene, run, run_in_memory
from .errors import ParameterError

SceneLike = Union[Scene, Mapping[str, Any]]

__all__ = ["with_values", "run_case", "run_cases", "run_shard", "run_shards"]


def with_values(scene: SceneLike, values: Mapping[str, Any]) -> Dict[str, Any]:
    """A copy of ``scene`` (as a dict) with each dotted key of ``values`` set, e.g.
    ``{"particles.inject.material.mu": 2.5, "particles.density": 10.0}``. Missing tables are
    created; the result is validated when the case runs (:meth:`Scene.from_dict`)."""
    d = copy.deepcopy(_as_dict(scene))
    for key, value in values.items():
        *path, last = key.split(".")
        node = d
        for part in path:
            child = node.setdefault(part, {})
            if not isinstance(child, dict):
                raise ParameterError(f"{key}: `{part}` is not a table")
            node = child
        node[last] = value
    return d


def _as_dict(scene: SceneLike) -> Dict[str, Any]:
    # A dict travels to the workers as plain data (Scene objects live in Rust memory).
    if isinstance(scene, Scene):
        return scene.to_dict()
    if isinstance(scene, Mapping):
        return dict(scene)
    raise ParameterError(f"scene must be a Scene or a dict, got {type(scene).__name__}")


def run_case(labels: Mapping[str, Any], scene: Mapping[str, Any], threads: int = 1) -> Any:
    """One task: run ``scene`` in memory on ``threads`` threads; its records as a pandas
    DataFrame with a column per label (the case's parameters) in front."""
    df = run_in_memory(Scene.from_dict(dict(scene)), threads=threads).records().to_pandas()
    for position, (name, value) in enumerate(labels.items()):
        df.insert(position, name, [value] * len(df))
    return df


def _check_threads(threads: int) -> int:
    if not isinstance(threads, int) or isinstance(threads, bool) or threads < 1:
        raise ParameterError(f"threads must be an integer >= 1, got {threads!r}")
    return threads


def run_cases(
    cases: Iterable[Tuple[Mapping[str, Any], SceneLike]],
    client: Any,
    *,
    threads: int = 1,
    resources: Optional[Mapping[str, float]] = None,
) -> Any:
    """Run every ``(labels, scene)`` of ``cases`` as one Dask task on ``client`` (a
    ``dask.distributed.Client``), each on ``threads`` threads (``resources``: passed to
    ``client.submit``, e.g. ``{"cores": threads}`` on workers started with that resource).
    Returns one pandas DataFrame: the cases' records in the order of ``cases``, with the
    labels as columns."""
    import pandas as pd

    threads = _check_threads(threads)
    futures: List[Any] = []
    for k, (labels, scene) in enumerate(cases):
        futures.append(
            client.submit(
                run_case,
                dict(labels),
                _as_dict(scene),
                threads,
                key=f"pseudorigid-case-{k}-{os.getpid()}-{id(futures)}",
                pure=False,
                resources=dict(resources) if resources else None,
            )
        )
    frames: List[Any] = client.gather(futures)
    if not frames:
        return pd.DataFrame()
    return pd.concat(frames, ignore_index=True)


def run_shard(scene: Mapping[str, Any], out: str, shard: Tuple[int, int], threads: int = 1) -> Any:
    """One task: shard ``k/n`` of ``scene`` into the output folder ``out`` (its checkpoint and
    Parquet parts, as ``pseudorigid run --shard k/n``); its records as a pandas DataFrame."""
    return run(Scene.from_dict(dict(scene)), out, shard=shard, threads=threads).records().to_pandas()


def run_shards(
    scene: SceneLike,
    out: Union[str, "os.PathLike[str]"],
    n: int,
    client: Any,
    *,
    threads: int = 1,
    resources: Optional[Mapping[str, float]] = None,
) -> Any:
    """Run ``scene`` as ``n`` shards on ``client``, each a task on ``threads`` threads writing
    into ``out`` (a folder every worker sees: on a cluster, a shared file system). Returns the
    whole run's records as one pandas DataFrame sorted by particle index, equal to the
    unsharded run's. ``out/records/`` and ``out/frames/`` read as Parquet datasets, and
    ``pseudorigid merge`` (or :func:`pseudorigid.load_results`) joins the checkpoints."""
    threads = _check_threads(threads)
    if not isinstance(n, int) or n < 1:
        raise ParameterError(f"n must be an integer >= 1, got {n!r}")
    d, folder = _as_dict(scene), os.fspath(out)
    futures = [
        client.submit(
            run_shard,
            d,
            folder,
            (k, n),
            threads,
            key=f"pseudorigid-shard-{k}-of-{n}-{os.getpid()}-{id(d)}",
            pure=False,
            resources=dict(resources) if resources else None,
        )
        for k in range(n)
    ]
    frames: Sequence[Any] = client.gather(futures)
    import pandas as pd

    return pd.concat(frames).sort_values("index", kind="stable").reset_index(drop=True)


"""pseudorigid from Python: soft ellipsoidal micro-particles in viscous flow (pseudo-rigid
bodies, Wedel et al.).

>>> import pseudorigid as pr
>>> scene = pr.Scene.from_toml("scenes/shear_injection.toml")
>>> results = pr.run(scene, out="shear-out", progress=True)   # the command's `run`
>>> df = results.records().to_pandas()                        # one row per particle

The Rust library does the work: scenes are validated by the same code as the
``pseudorigid`` command's, and :func:`run` writes bitwise the files of
``pseudorigid run SCENE --out DIR``.
"""

from __future__ import annotations

import json
import math
import os
import warnings
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from .errors import (
    FlowError,
    MeshError,
    ParameterError,
    PopulationError,
    PseudorigidError,
    SceneError,
    StudyError,
    StepError,
)

__version__: str = _native.__version__

Scene = _native.Scene
FoamFlow = _native.FoamFlow

__all__ = [
    "Scene",
    "FoamFlow",
    "Table",
    "Results",
    "run",
    "run_in_memory",
    "load_results",
    "adequacy",
    "integrate",
    "PseudorigidError",
    "ParameterError",
    "SceneError",
    "StudyError",
    "StepError",
    "FlowError",
    "MeshError",
    "PopulationError",
]

PathLike = Union[str, "os.PathLike[str]"]
Progress = Union[None, bool, Callable[[int, int], Any]]


class Table(Dict[str, Any]):
    """Columns by name: NumPy arrays of equal length (strings as object arrays)."""

    def __len__(self) -> int:
        # Number of rows, not of columns: a table reads like a data frame.
        for v in self.values():
            return len(v)
        return 0

    @property
    def columns(self) -> List[str]:
        return list(self.keys())

    def to_pandas(self) -> "Any":
        """A pandas DataFrame of the columns (needs pandas: the ``pandas`` extra)."""
        pd = _optional("pandas", "to_pandas()")
        return pd.DataFrame({k: v for k, v in self.items()})

    def to_polars(self) -> "Any":
        """A polars DataFrame of the columns (needs polars: the ``polars`` extra)."""
        pl = _optional("polars", "to_polars()")
        return pl.DataFrame({k: v for k, v in self.items()})


def _optional(module: str, needed_by: str) -> "Any":
    """The optional dependency ``module`` (also the name of the extra that installs it), or a
    ``ModuleNotFoundError`` that says which extra to install: numpy is the package's only
    requirement, so a plain ``pip install ./python`` has no pandas."""
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError as e:
        raise ModuleNotFoundError(
            f"{needed_by} needs {module}, which is not installed: pip install 'pseudorigid[{module}]' "
            f"(from the repository: pip install './python[{module}]'), or pip install {module}",
            name=module,
        ) from e


def _table(columns: Mapping[str, Any]) -> Table:
    out = Table()
    for k, v in columns.items():
        out[k] = v if isinstance(v, np.ndarray) else np.asarray(v, dtype=object)
    return out


class Results:
    """The records of a run: :meth:`records` (one row per particle), :meth:`frames` (a long
    table, one row per particle per output time) and :meth:`trajectory` (one particle)."""

    def __init__(self, native: "_native.Results", adequacy: Optional[Dict[str, Any]] = None) -> None:
        self._native = native
        self._adequacy = adequacy

    def __len__(self) -> int:
        return len(self._native)

    def __repr__(self) -> str:
        return f"Results({len(self)} particles, {self.counts()})"

    @property
    def adequacy(self) -> Optional[Dict[str, Any]]:
        """The mesh-adequacy diagnostic of a whole :func:`run` on an OpenFOAM field, as in its
        ``adequacy.json``: ``resolution`` (the first-cell height 2ρ at the walls against each
        group's largest semi-axis and stopping distance), ``sensitivity`` (the first
        ``output.adequacy_sample`` particles re-tracked on the other reconstruction of the
        field, paired with the run), ``skipped`` and ``log`` (the command's lines). None for a
        run in memory (:func:`adequacy` computes it), a shard (``merge`` re-tracks) or an
        analytic flow."""
        return self._adequacy

    @property
    def config_hash(self) -> str:
        return self._native.config_hash

    @property
    def patches(self) -> List[str]:
        return self._native.patches

    def counts(self) -> Dict[str, int]:
        """Particles per fate: deposited, escaped, suspended, failed."""
        return dict(self._native.counts())

    def records(self) -> Table:
        """One row per particle: the columns of ``records.parquet`` in its order (those of
        ``results.csv`` plus the end state's F, ``F11`` .. ``F33``, step statistics and the
        slow-manifold switch's: ``manifold_steps``, ``full_steps``, ``manifold_entered``,
        ``manifold_left``, ``manifold_max_ratio``, ``manifold_delta_max``). Where the file has
        a null, a float column holds NaN (the slow manifold's δ columns of a particle it did
        not step) and ``patch``, ``patch_name`` and ``error`` hold None."""
        return _table(self._native.records())

    def frames(self) -> Table:
        """Every particle at every frame time (0 and the output times): the columns of
        ``frames.csv`` and ``frames.parquet`` in their order (V by its nine components)."""
        return _table(self._native.frames())

    def trajectory(self, index: int = 0) -> Dict[str, Any]:
        """Kept states of particle ``index``: ``t``, ``x``, ``v``, ``r`` (r1 >= r2 >= r3),
        ``F``, ``axes`` and its ``fate``."""
        return self._native.trajectory(index)


def _callback(progress: Progress, total_hint: int) -> Tuple[Optional[Callable[[int, int], Any]], Any]:
    """A ``(done, total)`` callback for ``progress``: a callable as is, ``True`` a tqdm bar."""
    if progress is None or progress is False:
        return None, None
    if progress is True:
        try:
            from tqdm.auto import tqdm
        except ImportError:  # no bar without tqdm; the run is the same, and the user is told
            warnings.warn(
                "progress=True draws a tqdm bar, and tqdm is not installed: pip install 'pseudorigid[progress]' "
                "(from the repository: pip install './python[progress]'); running without a bar",
                RuntimeWarning,
                # Through _callback and run/run_in_memory to the caller's line.
                stacklevel=3,
            )
            return None, None
        bar = tqdm(total=total_hint, unit="particle")

        def update(done: int, total: int) -> None:
            bar.total = total
            bar.n = done
            bar.refresh()

        return update, bar
    if callable(progress):
        return progress, None
    raise ParameterError(f"progress must be None, a bool or a callable (done, total), got {type(progress).__name__}")


def _scene(scene: Union["Scene", PathLike, Mapping[str, Any]]) -> "Scene":
    if isinstance(scene, _native.Scene):
        return scene
    if isinstance(scene, Mapping):
        return Scene.from_dict(dict(scene))
    if isinstance(scene, (str, os.PathLike)):
        return Scene.from_toml(os.fspath(scene))
    raise ParameterError(f"scene must be a Scene, a path or a dict, got {type(scene).__name__}")


def run(
    scene: Union["Scene", PathLike, Mapping[str, Any]],
    out: PathLike,
    *,
    threads: Optional[int] = None,
    shard: Optional[Tuple[int, int]] = None,
    resume: bool = False,
    checkpoint_every: float = 60.0,
    progress: Progress = None,
    csv: bool = False,
) -> Results:
    """The command's ``run``: bitwise the files of ``pseudorigid run SCENE --out OUT`` (with
    ``--shard k/n``, ``--resume``, ``--threads``, ``--csv``). Records are written once: the
    checkpoint (sealed JSON, for resume and merge) and ``records.parquet`` /
    ``frames.parquet`` (a shard: ``records/`` and ``frames/``); CSV tables only with
    ``csv=True``. The GIL is released while Rust works;
    Ctrl-C stops the run after the particles in flight (they are checkpointed, and
    ``resume=True`` continues). ``progress``: ``True`` for a tqdm bar, or a callable
    ``(done, total)``. Returns the run's (or the shard's) results: the records just written,
    which :func:`load_results` would read back from the checkpoint."""
    s = _scene(scene)
    callback, bar = _callback(progress, s.count)
    try:
        _, results = _native.run(
            s,
            os.fspath(out),
            threads=threads,
            shard=shard,
            resume=resume,
            checkpoint_every=checkpoint_every,
            progress=callback,
            csv=csv,
        )
    finally:
        if bar is not None:
            bar.close()
    return Results(results, _adequacy(out, shard))


def _adequacy(out: PathLike, shard: Optional[Tuple[int, int]]) -> Optional[Dict[str, Any]]:
    """A whole run's ``adequacy.json`` (None for a shard or without one), its warning lines
    raised as :class:`RuntimeWarning` at the caller's line, as the command prints them."""
    path = os.path.join(os.fspath(out), "adequacy.json")
    if shard is not None or not os.path.exists(path):
        return None
    with open(path, encoding="utf-8") as f:
        found: Dict[str, Any] = json.load(f)
    # Through _warn, _adequacy and run to the caller's line.
    return _warn(found, stacklevel=4)


def _warn(diagnostic: Dict[str, Any], stacklevel: int) -> Dict[str, Any]:
    """`diagnostic`, its ``warning:`` lines raised as :class:`RuntimeWarning`."""
    for line in diagnostic.get("log", []):
        if line.startswith("warning: "):
            warnings.warn(line[len("warning: ") :], RuntimeWarning, stacklevel=stacklevel)
    return diagnostic


def adequacy(scene: Union["Scene", PathLike, Mapping[str, Any]], results: Results) -> Optional[Dict[str, Any]]:
    """The mesh-adequacy diagnostic of ``scene``'s whole run ``results`` (a
    :func:`run_in_memory`, or one read back by :func:`load_results`), computed by the library
    as the command computes its ``adequacy.json``: the same dict as :attr:`Results.adequacy`
    of a :func:`run` into a folder, its warning lines raised as :class:`RuntimeWarning`. The
    first ``output.adequacy_sample`` particles are re-tracked. None on an analytic flow."""
    text = _native.adequacy(_scene(scene), results._native)
    if text is None:
        return None
    # Through _warn and adequacy to the caller's line.
    return _warn(json.loads(text), stacklevel=3)


def run_in_memory(
    scene: Union["Scene", PathLike, Mapping[str, Any]],
    *,
    threads: Optional[int] = None,
    shard: Optional[Tuple[int, int]] = None,
    progress: Progress = None,
) -> Results:
    """Run a scene without writing files (the same records as :func:`run`)."""
    s = _scene(scene)
    callback, bar = _callback(progress, s.count)
    try:
        return Results(_native.run_in_memory(s, threads=threads, shard=shard, progress=callback))
    finally:
        if bar is not None:
            bar.close()


def load_results(out: PathLike, scene: Optional["Scene"] = None, *, shard: Optional[Tuple[int, int]] = None) -> Results:
    """The results in output folder ``out``, read from its checkpoint: shard ``(k, n)``'s,
    or without ``shard`` the whole run's, or else the merge of every shard's checkpoint in
    ``out``. Every chunk's checksum is verified. Frames need the ``scene`` (its output
    times)."""
    return Results(_native.load_results(os.fspath(out), scene, shard))


def integrate(
    flow: Mapping[str, Any],
    semi_axes: Sequence[float],
    *,
    material: Optional[Mapping[str, Any]] = None,
    t_end: float,
    every: Optional[float] = None,
    position: Sequence[float] = (0.0, 0.0, 0.0),
    orientation: Optional[Mapping[str, Any]] = None,
    velocity: Optional[Sequence[float]] = None,
    fluid: Optional[Mapping[str, Any]] = None,
    density: float = 1.0,
    integrator: Optional[Mapping[str, Any]] = None,
    boundary: Optional[Mapping[str, Any]] = None,
    max_steps: Optional[int] = None,
    base: Optional[PathLike] = None,
) -> Dict[str, Any]:
    """Integrate one particle and return its states as arrays: ``t`` (n), ``x``, ``v``,
    ``r`` (n x 3), ``F``, ``axes`` (n x 3 x 3), its ``fate`` and ``error``. The states are
    kept every ``every`` (default ``t_end / 100``: 101 states) and at the end.

    ``flow`` is a scene's ``[flow]`` table (``{"type": "shear", "rate": 1.0}``, or
    ``{"type": "openfoam", "case": "path"}``); ``material`` a scene material
    (``{"law": "neo_hooke", "mu": 2.5, "lambda": 2500.0}``; default rigid). The scene goes
    through the same validation as a file; a failed step raises :class:`StepError`.
    """
    particle: Dict[str, Any] = {
        "semi_axes": [float(a) for a in semi_axes],
        "position": [float(c) for c in position],
        "material": dict(material) if material is not None else {"law": "rigid"},
    }
    if orientation is not None:
        particle["orientation"] = dict(orientation)
    if velocity is not None:
        particle["velocity"] = [float(c) for c in velocity]
    d: Dict[str, Any] = {
        "flow": dict(flow),
        "fluid": dict(fluid) if fluid is not None else {"viscosity": 1.0, "density": 1.0},
        "particles": {"density": density, "list": [particle]},
        "integrator": dict(integrator)
        if integrator is not None
        else {"type": "radau_iia", "tol": 1e-8, "dt": 1e-3, "overdamped": True},
        "end": {"t_end": t_end},
        "output": {"vtk": False},
    }
    if every is None and math.isfinite(t_end) and t_end > 0.0:
        # A trajectory to plot: 100 intervals (without `every` the run keeps only its ends).
        every = t_end / 100.0
    if every is not None:
        d["output"]["every"] = every
    if max_steps is not None:
        d["end"]["max_steps"] = max_steps
    if boundary is not None:
        d["boundary"] = dict(boundary)
    scene = Scene.from_dict(d, None if base is None else os.fspath(base))
    out = Results(_native.run_in_memory(scene, threads=1)).trajectory(0)
    if out["fate"] == "failed":
        raise StepError(out["error"])
    return out

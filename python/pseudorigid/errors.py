"""Exceptions of pseudorigid, mirroring the library's typed errors.

Every error the package raises on purpose is a :class:`PseudorigidError`, except missing
files, which raise the built-in :class:`FileNotFoundError`, and other I/O failures
(:class:`OSError`).
"""

from __future__ import annotations

from typing import Optional

__all__ = [
    "PseudorigidError",
    "ParameterError",
    "SceneError",
    "StudyError",
    "StepError",
    "FlowError",
    "MeshError",
    "PopulationError",
]


class PseudorigidError(Exception):
    """Base class of pseudorigid's errors."""


class ParameterError(PseudorigidError, ValueError):
    """A parameter outside its domain (the library's ``ParamError``), or a bad argument."""


class SceneError(PseudorigidError, ValueError):
    """A scene that does not validate (the library's ``scene::SceneError::Invalid``).

    ``file``, ``line`` and ``column`` locate the value in the TOML text (for a scene given as a
    dict: in the TOML text of :meth:`pseudorigid.Scene.to_toml`, file ``<dict>``); ``key`` is
    its dotted path, e.g. ``particles.inject.material.mu``; ``reason`` says what was expected.
    """

    file: Optional[str] = None
    line: Optional[int] = None
    column: Optional[int] = None
    key: Optional[str] = None
    reason: Optional[str] = None


#: The earlier name of :class:`SceneError` (in the library, ``StudyError`` is a study's
#: failure, not a scene's); kept so that ``except pseudorigid.StudyError`` still catches it.
StudyError = SceneError


class StepError(PseudorigidError, ArithmeticError):
    """A particle's integration failed (Newton, det F <= 0, non-finite state, budget, ...)."""


class FlowError(PseudorigidError, ValueError):
    """A flow could not be sampled (a point outside the domain, a failed reconstruction)."""


class MeshError(PseudorigidError, ValueError):
    """An OpenFOAM case that cannot be read or is inconsistent."""


class PopulationError(PseudorigidError, RuntimeError):
    """A population run, its checkpoint, shard files or their merge failed."""

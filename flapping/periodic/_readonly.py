"""Package-internal: read-only result arrays.

Every result dataclass of :mod:`flapping.periodic` calls :func:`freeze` in ``__post_init__``:
its arrays come back with ``writeable=False``, so that an analysis of a result is an analysis of
what was solved (``orbit.x0[:] = 1`` would otherwise move a later Floquet analysis onto a point of
no orbit). An array the result does not own (a view, which may share memory with the caller's
input or a solver's cache) is copied first; the copy is small beside the integration behind it.
"""

from __future__ import annotations

import functools
from dataclasses import fields
from typing import Any

import numpy as np

__all__ = ["freeze", "readonly"]


def readonly(a: np.ndarray) -> np.ndarray:
    """``a`` (a copy of it if it is a view) with ``writeable=False``."""
    if not a.flags.owndata:
        a = a.copy()
    a.flags.writeable = False
    return a


def freeze(obj: Any) -> None:
    """Make every ndarray field of the dataclass ``obj`` (and in tuples of arrays) read-only."""
    cls: Any = type(obj)  # a dataclass type is hashable (mypy reads the instance's __hash__)
    for name in _field_names(cls):
        value = getattr(obj, name)
        if value is None:
            continue
        if isinstance(value, np.ndarray):
            object.__setattr__(obj, name, readonly(value))
        elif isinstance(value, tuple) and value and all(isinstance(v, np.ndarray)
                                                       for v in value):
            object.__setattr__(obj, name, tuple(readonly(v) for v in value))


@functools.lru_cache(maxsize=64)
def _field_names(cls: type) -> tuple[str, ...]:
    # listed once per class: results are built at every point of a sweep
    return tuple(f.name for f in fields(cls))

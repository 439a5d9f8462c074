"""Deprecated module paths: thin modules that forward to the layers' modules and warn.

Each deprecated path (``flapping/stability.py``, ...) is a module of three statements: it warns
when imported, and its module-level ``__getattr__`` (PEP 562) hands out every attribute of the
module that holds the code, warning each time, so that ``import flapping.stability`` and ``from
flapping.stability import hover_stability`` both work and both name the path to import from.
"""

from __future__ import annotations

import importlib
import warnings
from typing import Any

#: Each deprecated module path, and the module that holds its code.
MOVED_MODULES = {
    "flapping.stability": "flapping.hover.stability",
    "flapping.hover_branch": "flapping.hover.branch",
    "flapping.sweep": "flapping.studies.sweep",
    "flapping.atlas": "flapping.studies.atlas",
    "flapping.control": "flapping.studies.control",
}


def warn_import(old: str) -> None:
    """Warn that the deprecated module ``old`` is imported (call it from that module's body)."""
    # stacklevel 3: this function, the old module's body, then (past the import machinery's
    # frames, which warnings skips) the line that imported it.
    warnings.warn(f"{old} is deprecated: import from {MOVED_MODULES[old]}", DeprecationWarning,
                  stacklevel=3)


def forward(old: str, name: str) -> Any:
    """The attribute ``name`` of the module behind ``old``, with a DeprecationWarning.

    Parameters
    ----------
    old : str
        The deprecated module path, a key of :data:`MOVED_MODULES`.
    name : str
        The attribute asked of the deprecated module.

    Returns
    -------
    object
        The attribute of the module behind ``old`` itself (same object, same patch target).

    Raises
    ------
    AttributeError
        If that module has no such attribute.
    """
    new = MOVED_MODULES[old]
    if name.startswith("__") and name.endswith("__") and name != "__all__":
        raise AttributeError(f"module {old!r} has no attribute {name!r}")  # import machinery
    warnings.warn(f"{old}.{name} is deprecated: import {name} from {new}", DeprecationWarning,
                  stacklevel=3)
    return getattr(importlib.import_module(new), name)


def names(old: str) -> list[str]:
    """The names the deprecated module ``old`` forwards (for ``dir()``)."""
    return dir(importlib.import_module(MOVED_MODULES[old]))

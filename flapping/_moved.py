"""The module paths that moved into the layers, kept importable by thin forwarding modules.

Each old path (``flapping/stability.py``, ...) is a module of three lines: it warns when
imported, and its module-level ``__getattr__`` (PEP 562) hands out every attribute of the new
module, warning each time, so that ``import flapping.stability`` and ``from flapping.stability
import hover_stability`` both work and both say where the name lives now.
"""

from __future__ import annotations

import importlib
import warnings
from typing import Any

#: Each old module path, and the module that holds its code.
MOVED_MODULES = {
    "flapping.stability": "flapping.hover.stability",
    "flapping.hover_branch": "flapping.hover.branch",
    "flapping.sweep": "flapping.studies.sweep",
    "flapping.atlas": "flapping.studies.atlas",
    "flapping.control": "flapping.studies.control",
}


def warn_import(old: str) -> None:
    """Warn that module ``old`` is imported by its old path (call it from that module's body)."""
    # stacklevel 3: this function, the old module's body, then (past the import machinery's
    # frames, which warnings skips) the line that imported it.
    warnings.warn(f"{old} is deprecated: import from {MOVED_MODULES[old]}", DeprecationWarning,
                  stacklevel=3)


def forward(old: str, name: str) -> Any:
    """The attribute ``name`` of the module that replaced ``old``, with a DeprecationWarning.

    Parameters
    ----------
    old : str
        The old module path, a key of :data:`MOVED_MODULES`.
    name : str
        The attribute asked of the old module.

    Returns
    -------
    object
        The new module's attribute itself (same object, so the same patch target).

    Raises
    ------
    AttributeError
        If the new module has no such attribute.
    """
    new = MOVED_MODULES[old]
    if name.startswith("__") and name.endswith("__") and name != "__all__":
        raise AttributeError(f"module {old!r} has no attribute {name!r}")  # import machinery
    warnings.warn(f"{old}.{name} is deprecated: import {name} from {new}", DeprecationWarning,
                  stacklevel=3)
    return getattr(importlib.import_module(new), name)


def names(old: str) -> list[str]:
    """The names the old module ``old`` forwards (for ``dir()``): the new module's."""
    return dir(importlib.import_module(MOVED_MODULES[old]))

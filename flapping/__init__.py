"""flapping: stability of hovering flapping-wing insects and MAVs.

Reproduces and extends Elsadek, El-Bayoumi & Taha, "Stability Analysis of Longitudinal Dynamics of
Hovering Flapping MAVs/Insects". Layers, each importing only the ones before it:

- :mod:`flapping.model`: the insect (morphology -> kinematics -> aerodynamics -> derivation /
  derivatives -> dynamics);
- :mod:`flapping.periodic`: periodic orbits, flows, Floquet multipliers and continuation of any
  ``f(t, x)`` (imports nothing of the insect: reusable on its own);
- :mod:`flapping.fast`: the compiled hover kernel (numba, generated from the model's SymPy code);
- :mod:`flapping.hover`: the application joining them: the hover problem, its orbit, stability
  and branches;
- :mod:`flapping.studies`: studies built on the hover orbit: sweeps, the species atlas,
  stabilisation and feedback;
- :mod:`flapping.book`: the book's figures, tables and the paper's printed numbers (not
  re-exported).

Importing the package does no work beyond definitions. The command line is :mod:`flapping.cli`
(``flapping --help``).
"""

import importlib
import importlib.abc
import importlib.machinery
import importlib.util
import sys
import types
from typing import Any

from flapping.errors import ConvergenceError, HoverDriftWarning
from flapping.hover import HoverOrbit, HoverProblem, find_hover_orbit
from flapping.hover.stability import HoverStability, hover_stability
from flapping.model.morphology import Insect, hawkmoth
from flapping.periodic.floquet import monodromy
from flapping.periodic.shooting import find_periodic_orbit
from flapping.studies.sweep import sweep_hover

__all__ = [
    "ConvergenceError",
    "HoverDriftWarning",
    "HoverOrbit",
    "HoverProblem",
    "HoverStability",
    "Insect",
    "find_hover_orbit",
    "find_periodic_orbit",
    "hawkmoth",
    "hover_stability",
    "monodromy",
    "sweep_hover",
]
__version__ = "0.2.0"

#: Module paths of version 0.2 that moved into the layers, and where they live now: importing an
#: old path gives the very module object of the new one (same functions, same patch targets).
MOVED_MODULES = {
    "flapping.stability": "flapping.hover.stability",
    "flapping.hover_branch": "flapping.hover.branch",
    "flapping.sweep": "flapping.studies.sweep",
    "flapping.atlas": "flapping.studies.atlas",
    "flapping.control": "flapping.studies.control",
}


class _MovedModuleFinder(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Resolves an old module path to its new module, when (and only when) it is imported."""

    def find_spec(self, fullname: str, path: Any = None,
                  target: Any = None) -> importlib.machinery.ModuleSpec | None:
        if fullname not in MOVED_MODULES:
            return None
        return importlib.util.spec_from_loader(fullname, self)

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> types.ModuleType:
        return importlib.import_module(MOVED_MODULES[spec.name])

    def exec_module(self, module: types.ModuleType) -> None:
        pass  # the new module ran when it was imported; the old name is bound to it


if not any(isinstance(f, _MovedModuleFinder) for f in sys.meta_path):
    sys.meta_path.append(_MovedModuleFinder())

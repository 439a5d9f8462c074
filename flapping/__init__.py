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
  stabilisation and feedback.

The names in ``__all__`` are the main entry points, imported from their layers when first used
(PEP 562): ``import flapping`` alone loads NumPy and the exceptions, not the solvers, so the
command line and scripts that need one layer do not pay for the others. The subpackages load the
same way (``flapping.hover`` after ``import flapping``). The command line is :mod:`flapping.cli`
(``flapping --help``).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from flapping._moved import MOVED_MODULES as MOVED_MODULES  # deprecated paths: forwarders

if TYPE_CHECKING:  # what mypy and editors see; at run time __getattr__ imports on first use
    from flapping.backends import Adaptive, Compiled, FixedStep
    from flapping.errors import ConvergenceError, HoverDriftWarning
    from flapping.hover import HoverOrbit, HoverProblem, find_hover_orbit
    from flapping.hover.stability import HoverStability, hover_stability
    from flapping.model.morphology import Insect, hawkmoth
    from flapping.periodic.floquet import monodromy
    from flapping.periodic.shooting import find_periodic_orbit
    from flapping.results import Status
    from flapping.studies.sweep import sweep_hover

__all__ = [
    "Adaptive",
    "Compiled",
    "ConvergenceError",
    "FixedStep",
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
    "Status",
    "sweep_hover",
]
__version__ = "0.2.0"

#: Where each name of ``__all__`` is defined: the module :func:`__getattr__` imports it from.
_ENTRY_POINTS = {
    "Adaptive": "flapping.backends",
    "Compiled": "flapping.backends",
    "FixedStep": "flapping.backends",
    "Status": "flapping.results",
    "ConvergenceError": "flapping.errors",
    "HoverDriftWarning": "flapping.errors",
    "HoverOrbit": "flapping.hover",
    "HoverProblem": "flapping.hover",
    "HoverStability": "flapping.hover.stability",
    "Insect": "flapping.model.morphology",
    "find_hover_orbit": "flapping.hover",
    "find_periodic_orbit": "flapping.periodic.shooting",
    "hawkmoth": "flapping.model.morphology",
    "hover_stability": "flapping.hover.stability",
    "monodromy": "flapping.periodic.floquet",
    "sweep_hover": "flapping.studies.sweep",
}

#: The subpackages and modules reachable as attributes of the package without importing them
#: first (``flapping.hover.find_hover_orbit`` after ``import flapping``).
_SUBMODULES = frozenset({"backends", "cli", "errors", "fast", "hover", "model", "peers",
                         "periodic", "results", "studies"})


def __getattr__(name: str) -> Any:
    """Import an entry point or a subpackage of :mod:`flapping` on first use (PEP 562).

    Parameters
    ----------
    name : str
        A name of ``__all__`` or of a subpackage.

    Returns
    -------
    object
        The object the name stands for; it is then bound in the package, so this runs once.

    Raises
    ------
    AttributeError
        For any other name.
    """
    if name in _ENTRY_POINTS:
        value = getattr(importlib.import_module(_ENTRY_POINTS[name]), name)
    elif name in _SUBMODULES:
        value = importlib.import_module(f"{__name__}.{name}")
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    """The package's names, the ones not imported yet included (for ``dir()`` and completion)."""
    return sorted(set(globals()) | set(__all__) | _SUBMODULES)

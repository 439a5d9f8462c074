"""flapping: stability of hovering flapping-wing insects and MAVs.

Reproduces and extends Elsadek, El-Bayoumi & Taha, "Stability Analysis of Longitudinal Dynamics of
Hovering Flapping MAVs/Insects". Layers, each importing only the ones before it:

- :mod:`flapping.model`: the insect (morphology -> kinematics -> aerodynamics -> derivation /
  derivatives -> dynamics);
- :mod:`flapping.periodic`: periodic orbits, flows and Floquet multipliers of any ``f(t, x)``
  (imports nothing of the insect: reusable on its own);
- :mod:`flapping.hover` and :mod:`flapping.stability`: the application joining the two (the hover
  orbit and its stability);
- :mod:`flapping.book`: the book's figures, tables and the paper's printed numbers (not
  re-exported).

Importing the package does no work beyond definitions. The command line is
:mod:`flapping.__main__` (``flapping --help``).
"""

from flapping.errors import ConvergenceError, HoverDriftWarning
from flapping.hover import HoverOrbit, find_hover_orbit
from flapping.model.morphology import Insect, hawkmoth
from flapping.periodic.floquet import monodromy
from flapping.periodic.shooting import find_periodic_orbit
from flapping.stability import HoverStability, hover_stability

__all__ = [
    "ConvergenceError",
    "HoverDriftWarning",
    "HoverOrbit",
    "HoverStability",
    "Insect",
    "find_hover_orbit",
    "find_periodic_orbit",
    "hawkmoth",
    "hover_stability",
    "monodromy",
]
__version__ = "0.2.0"

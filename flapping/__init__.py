"""flapping: stability of hovering flapping-wing insects and MAVs.

Reproduces and extends Elsadek, El-Bayoumi & Taha, "Stability Analysis of Longitudinal Dynamics of
Hovering Flapping MAVs/Insects". The modules follow the method, and data flows one way:

``morphology`` -> ``kinematics`` -> ``aerodynamics`` -> ``derivation`` (SymPy, generates the
code of) ``stability_derivatives`` -> ``dynamics`` -> ``integrate`` / ``shooting`` / ``floquet``
(general tools, validated on ``testproblems``) -> ``hover`` (the orbit) -> ``stability``; the
paper's printed numbers are in ``paper``, the book's figures in ``plotting``.

Importing the package does no work beyond definitions (the SymPy derivation lives in
:mod:`flapping.derivation` and runs only when called).
"""

from flapping.errors import ConvergenceError
from flapping.morphology import Insect, hawkmoth

__all__ = ["ConvergenceError", "Insect", "hawkmoth"]
__version__ = "0.1.0"

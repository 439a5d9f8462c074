"""The insect model: everything about the flapping insect, nothing about solvers.

Data flows one way through the modules:
``morphology`` (:class:`Insect`) -> ``kinematics`` (stroke angle, rate, sign) -> ``aerodynamics``
(blade-element loads, nonlinear in the body states; the trim of eq. 40) -> ``derivation`` (SymPy:
the stability derivatives, generated into ``_derivatives_generated``) -> ``derivatives`` (the
time-periodic stability derivatives X0..Mq(t)) -> ``dynamics`` (eq. 2/29 as ``rhs(t, x)`` and
``jac(t, x)``).

SI units and radians throughout; degrees and millimetres only at the edges (tables, CLI).
"""

from flapping.model.morphology import Insect, hawkmoth

__all__ = ["Insect", "hawkmoth"]

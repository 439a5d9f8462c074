"""The insect model: everything about the flapping insect, nothing about solvers.

Modules, each importing only the ones before it:
``kinematics`` (stroke angle, rate and sign of eq. 39; the accepted ranges of the stroke amplitude
and of alpha_m) -> ``morphology`` (:class:`Insect`) -> ``presets`` (species from the
literature, each number with its source) and ``insect_file`` (an insect from a TOML or JSON file)
-> ``aerodynamics`` (blade-element loads,
nonlinear in the body states; the trim of eq. 40; the K constants of the linearised loads) ->
``derivation`` (SymPy, at derive time only: the stability derivatives, generated into
``_derivatives_generated``) -> ``derivatives`` (the time-periodic stability derivatives
X0..Mq(t), from the generated code) -> ``sixdof_derivation`` (SymPy: the insect in six degrees of
freedom, strip kinematics, load assembly and equations of motion: the package's one derivation
of the mechanics) -> ``inertia_derivation`` (its planar case, with and without wing mass,
generated into ``_inertia_generated``, which every planar path runs) / ``inertia`` (the wings'
inertial loads, planar) -> ``dynamics`` (eq. 2/29 as ``rhs(t, x)`` and ``jac(t, x)``) ->
``_sixdof_generated`` and ``_sixdof_jacobian_generated`` (the Jacobians of the blade-element
loads' geometry and section law, for the compiled six-degree-of-freedom path) -> ``sixdof``
(:class:`~flapping.model.sixdof.SixDofDynamics`).

Conventions: SI units and radians throughout; degrees and millimetres only at the edges (tables,
CLI). Public functions and constructors check their arguments once, through
:mod:`flapping._validation` (one accepted range per quantity, messages naming the argument and
the range), and convert numbers to float64 on entry (bools and strings refused); the functions
that run inside integrations (``rhs``, ``jac``, the kinematic formulas) trust their inputs.
Finite differences go through :mod:`flapping._numdiff`.
"""

from flapping.model.morphology import Insect, hawkmoth

__all__ = ["Insect", "hawkmoth"]

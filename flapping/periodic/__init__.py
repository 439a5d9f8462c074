"""General periodic-orbit tools for any ``f(t, x)``: no insect inside.

- :mod:`~flapping.periodic.integrate`: flows and variational flows (state-transition matrices),
  piecewise-smooth right-hand sides restarted at breakpoints;
- :mod:`~flapping.periodic.shooting`: periodic orbits by the optimized (Levenberg-Marquardt)
  shooting method;
- :mod:`~flapping.periodic.floquet`: monodromy matrices and Floquet multipliers;
- :mod:`~flapping.periodic.testproblems`: Lorenz, Roessler and a forced oscillator.

This subpackage imports nothing from :mod:`flapping.model`; other projects can reuse it alone.
"""

from flapping.periodic.floquet import monodromy
from flapping.periodic.shooting import find_periodic_orbit

__all__ = ["find_periodic_orbit", "monodromy"]

"""General periodic-orbit tools for any ``f(t, x)``: no insect inside.

- :mod:`~flapping.periodic.integrate`: flows and variational flows (state-transition matrices),
  piecewise-smooth right-hand sides restarted at breakpoints;
- :mod:`~flapping.periodic.rk4`: the paper's fixed-step RK4 as a scipy ``OdeSolver``;
- :mod:`~flapping.periodic.shooting`: periodic orbits by the optimized (Levenberg-Marquardt)
  shooting method;
- :mod:`~flapping.periodic.fixedstep`: periodic orbits of forced systems by Newton's method on a
  fixed-step 8th-order period map, with Richardson error estimates (smooth residual, exact
  Jacobian of the discrete map);
- :mod:`~flapping.periodic.floquet`: monodromy matrices and Floquet multipliers;
- :mod:`~flapping.periodic.continuation`: branches of orbits as a parameter changes
  (pseudo-arclength), with folds, period doublings and Neimark-Sacker points located;
- :mod:`~flapping.periodic.bifurcation_curves`: curves of those bifurcations in two parameters
  (:func:`continue_bifurcation`), with their codimension-two points;
- :mod:`~flapping.periodic.testproblems`: Lorenz, Roessler and a forced oscillator;
- :mod:`~flapping.periodic.settings`: :class:`SolverSettings`, the options shared by shooting,
  Floquet analysis and continuation (``settings=``), and the checks and caps of those options.

Conventions, the same in every module: time along the last axis (as ``solve_ivp``'s ``y``);
counters ``nfev``, ``njev``, ``nit`` as scipy names them; ``rtol``, ``atol``, ``method``,
``rk4_steps`` and ``max_steps`` wherever something is integrated; arguments checked once, at the
public functions, numbers converted to float64 and bools or strings refused. Every integration
checks that ``fun`` and ``jac`` return finite values and has a step budget, so a NaN or a stiff
problem fails with a message instead of hanging. Result arrays are read-only
(``writeable=False``).

This subpackage imports nothing from :mod:`flapping.model`; other projects can reuse it alone.
(``_segments``, ``_problem``, ``_fixedmap``, ``_tableau``, ``_branchflow``, ``_bifurcation``,
``_branchplot`` and ``_defining`` are package-internal modules: the integration driver, the
shooting problem, the fixed-step period map, the DOP853 coefficients, the continuation's shooting
map, its bifurcation tests, its plot, and the defining systems of bifurcation curves.)
"""

from flapping.periodic.bifurcation_curves import BifurcationCurve, continue_bifurcation
from flapping.periodic.continuation import Bifurcation, Branch, continue_orbit
from flapping.periodic.fixedstep import FixedStepOrbit, find_periodic_orbit_fixed_step
from flapping.periodic.floquet import Monodromy, monodromy
from flapping.periodic.integrate import FlowResult, VariationalFlow, flow, variational_flow
from flapping.periodic.rk4 import RK4
from flapping.periodic.settings import SolverSettings
from flapping.periodic.shooting import PeriodicOrbit, find_periodic_orbit

__all__ = [
    "find_periodic_orbit", "PeriodicOrbit", "monodromy", "Monodromy", "flow", "FlowResult",
    "variational_flow", "VariationalFlow", "RK4", "continue_orbit", "Branch", "Bifurcation",
    "SolverSettings", "find_periodic_orbit_fixed_step", "FixedStepOrbit",
    "continue_bifurcation", "BifurcationCurve",
]

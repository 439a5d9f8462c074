"""The hover application: the insect model joined to the periodic-orbit tools.

- :mod:`flapping.hover._schema`: the one schema of an orbit and of its stability, whatever the
  degrees of freedom;
- :mod:`flapping.hover.problem`: :class:`HoverProblem`, the hover problem of one insect (its
  right-hand sides, Jacobians and trim sensitivities, the kernel's packing), and
  :func:`~flapping.hover.problem.choose_backend`, the one function that decides which backend
  runs;
- :mod:`flapping.hover.orbit`: :func:`find_hover_orbit` and :class:`HoverOrbit`, the orbit at a
  prescribed amplitude (:func:`forced_orbit`), the paper's own hover condition
  (:func:`paper_hover_problem`) and the force budget;
- :mod:`flapping.hover.sixdof`: hover and its eight multipliers in six degrees of freedom;
- :mod:`flapping.hover.stability`: the orbit's Floquet multipliers, the averaged system,
  perturbation growth and the sensitivity to the modelling choices
  (:func:`~flapping.hover.stability.hover_stability`);
- :mod:`flapping.hover.compiled_path`, :mod:`~flapping.hover.fixed_step_path`,
  :mod:`~flapping.hover.adaptive_path` (peers): each backend's strategy, the code of its path;
- :mod:`flapping.hover.branch`: the orbit followed in an insect parameter
  (:func:`~flapping.hover.branch.continue_hover`).

Each module imports only the ones before it in this list.
"""

from flapping.hover.orbit import (
    ANALYSIS_ATOL,
    ANALYSIS_RTOL,
    HALF_PERIOD_SYMMETRY,
    HOVER_SPEED_ATOL,
    HOVER_SPEED_RTOL,
    HoverOrbit,
    HoverStatus,
    find_hover_orbit,
    force_budget,
    forced_orbit,
    paper_hover_problem,
    use_kernel,
)
from flapping.hover.problem import BACKENDS, DEFAULT_BACKEND, TRIMS, HoverProblem, choose_backend

# Each path's strategy registers itself with its backend class (flapping.backends), and the
# six-degree-of-freedom solve with find_hover_orbit (dof=6): modules above orbit and problem.
from flapping.hover import sixdof  # noqa: E402, F401  isort: skip
from flapping.hover import adaptive_path, compiled_path, fixed_step_path  # noqa: E402, F401  isort: skip

__all__ = [
    "ANALYSIS_ATOL",
    "ANALYSIS_RTOL",
    "BACKENDS",
    "DEFAULT_BACKEND",
    "HALF_PERIOD_SYMMETRY",
    "HOVER_SPEED_ATOL",
    "HOVER_SPEED_RTOL",
    "TRIMS",
    "HoverOrbit",
    "HoverProblem",
    "HoverStatus",
    "choose_backend",
    "find_hover_orbit",
    "force_budget",
    "forced_orbit",
    "paper_hover_problem",
    "use_kernel",
]

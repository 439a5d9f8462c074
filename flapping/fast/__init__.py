"""flapping.fast: the compiled hover kernel (numba), for sweeps of thousands of orbits.

:func:`solve_hover` finds the hover orbit of eq. (29)'s linear model and its Floquet multipliers
in about half a millisecond, with an error estimate and an automatic step count, and
:func:`orbit_quadrature` gives the cycle-averaged Jacobian and mean velocities along it in one
compiled call (:mod:`flapping.fast.kernel`). The sweeps over insect parameters built on it are in
:mod:`flapping.studies.sweep`; :func:`flapping.hover.find_hover_orbit` can use it as its backend.

Importing this package does not import numba: the kernel is compiled (or loaded from numba's
on-disk cache) the first time it runs, in the process, or ahead of use by :func:`warm_up`
(``python -m flapping compile``); every numba module here follows the same policy
(:mod:`flapping.fast._jit`, with ``FLAPPING_FIRST_CALL`` and ``NUMBA_CACHE_DIR``). numba is the
optional ``fast`` extra (``pip install flapping[fast]``); :func:`numba_available` says whether it
is installed.
"""

from flapping.fast.kernel import (
    AMPLITUDE_TOL_DEG,
    AMPLITUDE_TOL_FLOOR_DEG,
    MULTIPLIER_TOL,
    MULTIPLIER_TOL_FLOOR,
    SUPPORTED_FIELDS,
    HoverSolution,
    KernelCompileWarning,
    KernelProblem,
    OrbitQuadrature,
    monodromy_at,
    numba_available,
    orbit_quadrature,
    sample_orbit,
    solve_hover,
)
from flapping.fast.warm import WarmUp, warm_up

__all__ = [
    "AMPLITUDE_TOL_DEG",
    "AMPLITUDE_TOL_FLOOR_DEG",
    "MULTIPLIER_TOL",
    "MULTIPLIER_TOL_FLOOR",
    "SUPPORTED_FIELDS",
    "HoverSolution",
    "KernelCompileWarning",
    "KernelProblem",
    "OrbitQuadrature",
    "monodromy_at",
    "numba_available",
    "orbit_quadrature",
    "sample_orbit",
    "solve_hover",
    "WarmUp",
    "warm_up",
]

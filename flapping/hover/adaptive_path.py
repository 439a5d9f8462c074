"""The adaptive path (:class:`flapping.backends.Adaptive`): Levenberg-Marquardt shooting on
scipy's adaptive integrators, as in the paper (the reference and the cross-check).

Its strategy: :func:`check` (an explicit method), :func:`solve` and :func:`analyse` (the
monodromy's variational integration at the analysis tolerances).
"""

from __future__ import annotations

import functools
import math
import sys
import time

import numpy as np

from flapping.backends import Adaptive, register
from flapping.hover.orbit import (
    HoverOrbit,
    _AdaptiveSamples,
    _checked_trims,
    _model_at,
    _orbit_of,
    explicit_method,
)
from flapping.hover.problem import HoverProblem
from flapping.hover.stability import HoverStability, _averaged_jacobian, _stability
from flapping.periodic.floquet import monodromy
from flapping.periodic.shooting import find_periodic_orbit

__all__ = ["analyse", "check", "solve"]


def check(path: Adaptive, problem: HoverProblem) -> None:
    """The adaptive path applies to every hover problem (its method is checked when it runs)."""


def solve(path: Adaptive, problem: HoverProblem, guess: np.ndarray, x0: np.ndarray,
          n_samples: int) -> HoverOrbit:
    """find_hover_orbit on the adaptive path."""
    return _adaptive_orbit(problem, path, guess, x0, n_samples, time.perf_counter())


def analyse(path: Adaptive, orbit: HoverOrbit, problem: HoverProblem, n_average: int,
            rtol: float, atol: float) -> HoverStability:
    """hover_stability on the adaptive path: the monodromy at ``path``'s analysis tolerances."""
    explicit_method(path)
    model = orbit.model
    rhs, jac = model.segment_functions()
    rtol, atol = path.analysis_rtol, path.analysis_atol
    mon = monodromy(rhs, orbit.x0, orbit.period, jac=jac, breakpoints=model.breakpoints,
                    method=path.method, rtol=rtol, atol=atol, rk4_steps=path.rk4_steps,
                    max_steps=path.max_steps)
    # Multipliers from the monodromy's product-QR iteration (accurate even when small).
    values = np.asarray(mon.multipliers, dtype=complex)
    # the averaged Jacobian on first use (the multipliers do not need it)
    averaged = functools.partial(_averaged_jacobian, orbit, n_average, rtol, atol)
    return _stability(orbit, mon.matrix, values, mon.det, mon.liouville_det, averaged,
                      mon.trace_integral, math.nan)


def _adaptive_orbit(problem: HoverProblem, path: Adaptive, guess: np.ndarray, x0: np.ndarray,
                    n_samples: int, started: float) -> HoverOrbit:
    """find_hover_orbit on the scipy path: LM shooting with the trims free."""
    explicit_method(path)
    rhs, jac, pjac = problem.fields()
    extra = problem.n_conditions
    jacobian = path.jacobian or ("variational" if problem.aerodynamics == "linear"
                                 else "finite-difference")
    result = find_periodic_orbit(
        rhs, np.concatenate([x0, np.zeros(extra)]), problem.period, autonomous=False, jac=jac,
        param_jac=pjac, free_params=list(guess), fixed=tuple(range(4, 4 + extra)),
        breakpoints=problem.model.breakpoints, method=path.method, jacobian=jacobian,
        rtol=path.rtol, atol=path.atol, tol=path.tol, rk4_steps=path.rk4_steps,
        max_steps=path.max_steps, max_nfev=path.max_nfev)
    trims = _checked_trims(problem, result)
    model = _model_at(problem, trims)
    return _orbit_of(problem, result, trims, model, path, started, shooting=result,
                     samples=_AdaptiveSamples(model, np.array(result.x0[:4], dtype=float),
                                              n_samples, path.method, path.rtol, path.atol),
                     njev=int(result.njev))


register(Adaptive.name, sys.modules[__name__])  # this module is the path's strategy

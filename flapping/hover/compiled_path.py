"""The compiled path (:class:`flapping.backends.Compiled`): the numba hover kernel of
:mod:`flapping.fast.kernel` (eq. 29's linear loads, one trim).

Its strategy: :func:`check` (where the kernel applies), :func:`solve` (the orbit, its monodromy
and mean velocities from the kernel's Newton solve) and :func:`analyse` (the multipliers from
that solve's last integration, the averaged Jacobian by the kernel's quadrature).
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np

from flapping.backends import Compiled, register
from flapping.fast import kernel as _kernel
from flapping.hover.orbit import HoverOrbit, _KernelSamples
from flapping.hover.problem import HoverProblem
from flapping.hover.stability import (
    HoverStability,
    _averaged_jacobian,
    _kernel_problem,
    _stability,
)
from flapping.results import Stats

__all__ = ["analyse", "check", "solve"]


def check(path: Compiled, problem: HoverProblem) -> None:
    """Refuse the compiled path where the kernel does not apply, or without numba."""
    why_not = problem._kernel_refusal()
    if why_not:
        raise ValueError(f"backend='compiled' does not apply: {why_not}; use "
                         "backend='adaptive' (or 'auto', which falls back)")
    if not _kernel.numba_available():
        raise ImportError("backend='compiled' needs numba: pip install flapping[fast]")


def solve(path: Compiled, problem: HoverProblem, guess: np.ndarray, x0: np.ndarray,
          n_samples: int) -> HoverOrbit:
    """find_hover_orbit on the compiled kernel."""
    return _kernel_orbit(problem, path, float(guess[0]), x0, n_samples, time.perf_counter())


def analyse(path: Compiled, orbit: HoverOrbit, problem: HoverProblem, n_average: int,
            rtol: float, atol: float) -> HoverStability:
    """hover_stability on the compiled kernel."""
    matrix, values, det, liouville, trace, error = _kernel_monodromy(orbit)
    averaged = _averaged_jacobian(orbit, n_average, rtol, atol, compiled=True)
    return _stability(orbit, matrix, values, det, liouville, averaged, trace, error)


def _kernel_orbit(problem: HoverProblem, path: Compiled, amplitude: float, x0: np.ndarray,
                  n_samples: int, started: float) -> HoverOrbit:
    """find_hover_orbit on the compiled kernel: the orbit, its monodromy, its mean velocities."""
    kp = problem.kernel_problem
    # x0 (state_guess) and the amplitude (problem.guess) are checked already
    options = _kernel.checked_options(n_steps=path.n_steps,
                                      amplitude_tol_deg=path.amplitude_tol_deg,
                                      multiplier_tol=path.multiplier_tol)
    sol = _kernel.solve_checked(kp, np.append(x0, amplitude), *options)
    x_start = sol.x0  # read-only already
    return HoverOrbit(problem, x_start, sol.amplitude, problem.insect.stroke_mean, sol.z_drift,
                      "compiled", sol.nit, sol.nfev, sol.residual_norm, kernel=sol,
                      mean_velocity=sol.mean_velocity,
                      samples=_KernelSamples(kp, x_start, sol.amplitude, n_samples),
                      solver=path, stats=Stats(sol.nit, sol.nfev, 0,
                                               time.perf_counter() - started),
                      amplitude_error=sol.amplitude_error, x0_error=sol.x0_error,
                      multiplier_error=sol.multiplier_error)


def _kernel_monodromy(orbit: HoverOrbit
                      ) -> tuple[np.ndarray, np.ndarray, float, float, float, float]:
    """(M, multipliers, det M, exp(int trace J), int trace J, multiplier error) from the
    compiled kernel."""
    sol = orbit.kernel
    if (isinstance(sol, _kernel.HoverSolution) and np.array_equal(sol.x0, orbit.x0)
            and sol.amplitude == orbit.amplitude):
        # the last Newton integration's
        matrix, trace, error = sol.monodromy, sol.trace_integral, sol.multiplier_error
    else:
        matrix, trace, error, _ = _kernel.monodromy_at(_kernel_problem(orbit), orbit.x0,
                                                       orbit.amplitude)
    values = np.linalg.eigvals(matrix).astype(complex)
    values = values[np.argsort(-np.abs(values), kind="stable")]
    log_det = float(np.sum(np.log(np.abs(values))))
    det = float(np.linalg.det(matrix)) if abs(log_det) < 700 else math.copysign(
        math.inf if log_det > 0 else 0.0, float(np.prod(np.sign(values.real))))
    liouville = math.exp(trace) if trace < 700 else math.inf
    return matrix, values, det, liouville, trace, float(error)


register(Compiled.name, sys.modules[__name__])  # this module is the path's strategy

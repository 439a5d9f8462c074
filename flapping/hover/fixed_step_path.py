"""The fixed-step path (:class:`flapping.backends.FixedStep`): Newton on the graded fixed-step
period map (any loads model), with Richardson error estimates
(:mod:`flapping.periodic.fixedstep`).

Its strategy: :func:`check` (it applies to every hover problem), :func:`solve` and
:func:`analyse` (the monodromy at n and 2n steps per half-stroke).
"""

from __future__ import annotations

import functools
import sys
import time

import numpy as np

from flapping.backends import Adaptive, FixedStep, register
from flapping.hover.orbit import (
    HoverOrbit,
    _AdaptiveSamples,
    _checked_trims,
    _model_at,
    _orbit_of,
)
from flapping.hover.problem import TRIMS, HoverProblem
from flapping.hover.stability import _LAZY, HoverStability, _averaged_jacobian, _stability
from flapping.model.dynamics import LongitudinalDynamics
from flapping.periodic._readonly import readonly
from flapping.periodic.fixedstep import (
    FixedStepOrbit,
    find_periodic_orbit_fixed_step,
    fixed_step_flow,
    fixed_step_monodromy,
)

__all__ = ["analyse", "check", "solve"]


def check(path: FixedStep, problem: HoverProblem) -> None:
    """The fixed-step path applies to every hover problem."""


def solve(path: FixedStep, problem: HoverProblem, guess: np.ndarray, x0: np.ndarray,
          n_samples: int) -> HoverOrbit:
    """find_hover_orbit on the fixed-step path."""
    return _fixed_step_orbit(problem, path, guess, x0, n_samples, time.perf_counter())


def analyse(path: FixedStep, orbit: HoverOrbit, problem: HoverProblem, n_average: int,
            rtol: float, atol: float) -> HoverStability:
    """hover_stability on the fixed-step path."""
    return _fixed_step_stability(orbit, problem, path, n_average, rtol, atol)


def _fixed_step_orbit(problem: HoverProblem, path: FixedStep, guess: np.ndarray,
                      x0: np.ndarray, n_samples: int, started: float) -> HoverOrbit:
    """find_hover_orbit on the fixed-step path: Newton on the graded fixed-step period map."""
    funs, switches = problem.graded_fields()
    extra = problem.n_conditions
    result = find_periodic_orbit_fixed_step(
        funs, np.concatenate([x0, np.zeros(extra)]), 2.0, free_params=list(guess),
        fixed=tuple(range(4, 4 + extra)), breakpoints=(0.5,), switches=switches,
        **path.fixed_step_options())
    trims = _checked_trims(problem, result)
    model = _model_at(problem, trims)
    x_start = np.array(result.x0[:4], dtype=float)
    # The samples are a by-product, integrated on first use at the adaptive path's tolerances.
    samples = _AdaptiveSamples(model, x_start, n_samples, "DOP853", Adaptive.rtol, Adaptive.atol)
    error = np.asarray(result.unknowns_error)
    return _orbit_of(problem, result, trims, model, path, started, fixed_step=result,
                     samples=samples,
                     mean_velocity=readonly(_fixed_step_mean_velocity(problem, model, result,
                                                                      trims)),
                     njev=int(result.njev), amplitude_error=float(error[4]),
                     x0_error=float(np.max(error[:4])),
                     multiplier_error=float(result.multiplier_error))


def _fixed_step_mean_velocity(problem: HoverProblem, model: LongitudinalDynamics,
                              solved: FixedStepOrbit, trims: list[float]) -> np.ndarray:
    """(forward, climb) cycle means of a fixed-step orbit: x_e(T) / T and -z(T) / T on the solve's
    mesh (the two-trim field carries x_e), instead of sampling the orbit adaptively."""
    full = problem
    if problem.n_conditions == 1:  # the two-trim field carries x_e; on the problem's own model
        full = HoverProblem(problem.insect, problem.aerodynamics, problem.alpha_m, TRIMS[1],
                            trim_check=False)
        full.__dict__["model"] = problem.model  # the cached_property's slot (of_model's models)
    funs, switches = full.graded_fields()
    phi_bar = trims[1] if len(trims) == 2 else problem.insect.stroke_mean
    end = fixed_step_flow(funs, np.concatenate([solved.x0[:4], [0.0, 0.0]]), 2.0,
                          n_steps=solved.n_steps, free_params=[trims[0], phi_bar],
                          breakpoints=(0.5,), switches=switches)
    return np.array([end[5], -end[4]]) / problem.period


def _fixed_step_stability(orbit: HoverOrbit, problem: HoverProblem, path: FixedStep,
                          n_average: int, rtol: float, atol: float) -> HoverStability:
    """The analysis on the fixed-step path: the monodromy at n and 2n steps per half-stroke."""
    params = np.array([orbit.amplitude, orbit.stroke_mean][: problem.n_conditions])
    y0 = np.concatenate([orbit.x0, np.zeros(problem.n_conditions)])
    funs, switches = problem.graded_fields()
    solved = orbit.fixed_step
    n = path.n_steps if solved is None else solved.n_steps

    def physical(n_steps: int, difference_scale: float = 1.0) -> np.ndarray:
        # The augmented state's monodromy is block-triangular (z and x_e do not feed back):
        # the (u, w, q, theta) block holds the multipliers.
        if (solved is not None and n_steps == solved.n_steps and difference_scale == 1.0
                and solved.params is not None and np.array_equal(solved.x0, y0)
                and np.array_equal(solved.params, params)):
            full = solved.monodromy  # the solve's last pass, at these unknowns
        else:
            full = fixed_step_monodromy(funs, y0, 2.0, n_steps=n_steps, free_params=params,
                                        breakpoints=(0.5,), switches=switches,
                                        difference_scale=difference_scale)
        return np.array(full[:4, :4])

    coarse, matrix = physical(n), physical(2 * n)
    values = _sorted_eigenvalues(matrix)

    def change(other: np.ndarray) -> float:
        # each multiplier's nearest one of the other matrix
        gaps = np.abs(_sorted_eigenvalues(other)[:, None] - values[None, :])
        return float(np.max(np.min(gaps, axis=0)))

    # The mesh's error (n against 2n steps) and, where the monodromy is a central difference of
    # the map (the switches make it one), the quotient's own: the same mesh at twice the step.
    # The compiled loads showed why both count: their rounding moved the multipliers by 6e-10
    # while n -> 2n changed them by 1.4e-10.
    error = change(coarse)
    if any(switches):
        error += change(physical(2 * n, difference_scale=2.0))
    error *= _FIXED_STEP_SAFETY
    det = float(np.linalg.det(matrix))
    # The averaged Jacobian on first use (most of this analysis's time, which the multipliers do
    # not need), and with it int_0^T trace J dt by its Gauss rule and exp of that (the loads'
    # kinks limit it: Liouville's check measured 4e-7 on the small-angle hawkmoth, 5e-10 on the
    # linear loads).
    averaged = functools.partial(_averaged_jacobian, orbit, n_average, rtol, atol)
    return _stability(orbit, matrix, values, det, _LAZY, averaged, _LAZY, error)


#: Safety factor of the fixed-step analysis's multiplier error estimate (as the fixed-step
#: solve's Richardson estimates, :mod:`flapping.periodic.fixedstep`): the change from n to 2n
#: steps is one sample of the monodromy's rounding noise, which may happen to be small.
_FIXED_STEP_SAFETY = 2.0


def _sorted_eigenvalues(matrix: np.ndarray) -> np.ndarray:
    """Eigenvalues as complex, by descending modulus."""
    values = np.linalg.eigvals(matrix).astype(complex)
    return values[np.argsort(-np.abs(values), kind="stable")]


register(FixedStep.name, sys.modules[__name__])  # this module is the path's strategy

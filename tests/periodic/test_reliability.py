"""Bad input and silent nonsense in flapping.periodic (issue 17, item 5): each test is a
reproducer that failed before its fix, written for the class of inputs rather than the instance.

- work caps: a size argument beyond :data:`flapping.periodic.settings.CAPS` is a ValueError that
  names the argument and the cap (``n_points=10**6`` ran for ever);
- unbounded integrations: a span whose restart grid alone exceeds ``max_steps`` fails at once,
  and a step budget that runs out in ``monodromy`` is a ConvergenceError carrying the data;
- closure: ``monodromy`` of a point on no orbit warns (it returned multipliers silently);
- aliasing: an autonomous orbit found at a multiple of its period, or residual points at one
  phase, warn;
- tolerances: an ``rtol`` below 100 eps is raised to it with a warning (as solve_ivp does);
- results are read-only, and the caller's arrays are not frozen with them.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import fields

import numpy as np
import pytest

from flapping.errors import (
    AliasedPeriodWarning,
    ClosureWarning,
    ConvergenceError,
    ToleranceWarning,
)
from flapping.periodic.continuation import continue_orbit
from flapping.periodic.floquet import CLOSURE_TOL, monodromy
from flapping.periodic.integrate import flow, variational_flow
from flapping.periodic.settings import CAPS, RTOL_FLOOR
from flapping.periodic.shooting import find_periodic_orbit
from flapping.periodic.testproblems import rossler, rossler_jac

GUESS, T_GUESS = [0.0, -6.8, 0.03], 5.9  # Roessler period-1 orbit near x = 0 (c = 5.7)


def hopf(t, x, p):
    r2 = x[0] ** 2 + x[1] ** 2
    return np.array([p * x[0] - x[1] - x[0] * r2, x[0] + p * x[1] - x[1] * r2])


@pytest.fixture(scope="module")
def orbit():
    return find_periodic_orbit(rossler, GUESS, T_GUESS, fixed=[0], jac=rossler_jac)


@pytest.fixture(scope="module")
def mon(orbit):
    return monodromy(rossler, orbit.x0, orbit.period, jac=rossler_jac)


# ---- work caps ------------------------------------------------------------------------------

SHOOTING_SIZES = [("n_points", 10**6), ("segments", 10**6), ("rk4_steps", 2**40),
                  ("max_steps", 10**12), ("max_nfev", 10**9)]


@pytest.mark.parametrize(("name", "value"), SHOOTING_SIZES)
def test_shooting_size_beyond_its_cap_is_refused_at_once(name, value):
    # n_points = 10**6 ran for ever (an O(n_points^2) lookup of the residual times)
    start = time.perf_counter()
    with pytest.raises(ValueError, match=rf"`{name}` must be an integer in \[1, {CAPS[name]}\]"):
        find_periodic_orbit(rossler, GUESS, T_GUESS, fixed=[0], **{name: value})
    assert time.perf_counter() - start < 1.0


def test_largest_accepted_n_points_returns():
    # at the cap the call finishes: the residual times are looked up in O(m log m)
    with pytest.raises(ConvergenceError) as info:  # three residuals are not enough to converge
        find_periodic_orbit(rossler, GUESS, T_GUESS, jac=rossler_jac, n_points=CAPS["n_points"],
                            max_nfev=3)
    assert info.value.result.residual.size == 3 * CAPS["n_points"]


def test_monodromy_and_continuation_sizes_are_capped():
    with pytest.raises(ValueError, match=rf"`n_sub` must be an integer in \[1, {CAPS['n_sub']}\]"):
        monodromy(rossler, GUESS, T_GUESS, n_sub=10**7)
    for name, value in (("max_points", 10**9), ("max_newton", 10**6), ("segments", 10**5)):
        with pytest.raises(ValueError, match=rf"`{name}` must be an integer in \[\d+, {CAPS[name]}\]"):
            continue_orbit(hopf, [1.0, 0.0], 6.0, 1.0, 0.5, **{name: value})


def test_span_of_a_trillion_periods_fails_at_once_not_after_building_its_grid():
    start = time.perf_counter()
    out = flow(lambda t, x: -x, (0.0, 1e12), [1.0], period=1.0, breakpoints=(0.5,))
    var = variational_flow(lambda t, x: -x, None, (0.0, 1e12), [1.0], period=1.0,
                           breakpoints=(0.5,))
    assert time.perf_counter() - start < 1.0
    assert not out.success and "step budget" in out.message
    assert not var.success and "step budget" in var.message


def test_monodromy_out_of_steps_is_a_convergence_error_with_the_data():
    with pytest.raises(ConvergenceError, match="step budget") as info:
        monodromy(rossler, GUESS, T_GUESS, jac=rossler_jac, max_steps=5)
    assert info.value.x is not None and info.value.x.shape == (3,)
    assert info.value.result is not None and not info.value.result.success


# ---- closure --------------------------------------------------------------------------------

def test_monodromy_of_a_point_on_no_orbit_warns_and_reports_the_closure():
    # was: multipliers returned silently for a closure error of 31.8
    with pytest.warns(ClosureWarning, match="on no periodic orbit"):
        off = monodromy(rossler, [1.0, 2.0, 3.0], 5.0, jac=rossler_jac)
    assert off.relative_closure_error > CLOSURE_TOL
    assert off.relative_closure_error == pytest.approx(
        off.closure_error / max(1.0, math.sqrt(14.0)), rel=1e-12)


def test_monodromy_on_the_orbit_is_silent_and_closes_to_the_solve(mon):
    # the orbit closes to the shooting tol (1e-10) plus DOP853's error at rtol 1e-12
    assert mon.relative_closure_error <= 1e-9


# ---- aliasing -------------------------------------------------------------------------------

def test_autonomous_solve_at_twice_the_period_warns(orbit):
    with pytest.warns(AliasedPeriodWarning, match=r"T / 2"):
        twice = find_periodic_orbit(rossler, orbit.x0, 2 * orbit.period, fixed=[0],
                                    jac=rossler_jac)
    assert twice.period == pytest.approx(2 * orbit.period, rel=1e-9)


def test_solve_at_the_minimal_period_is_silent():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        find_periodic_orbit(rossler, GUESS, T_GUESS, fixed=[0], jac=rossler_jac)


def test_residual_points_at_one_phase_warn():
    # delta = 1/2: blocks k = 0 and k = 2 sample the same phase
    with pytest.warns(AliasedPeriodWarning, match="aliased sampling"), \
            pytest.raises(ConvergenceError):  # two evaluations: the warning comes first
        find_periodic_orbit(rossler, GUESS, T_GUESS, jac=rossler_jac, n_points=3, delta=0.5,
                            max_nfev=2)


# ---- tolerances -----------------------------------------------------------------------------

@pytest.mark.parametrize("call", [
    lambda r: flow(lambda t, x: -x, (0.0, 1.0), [1.0], rtol=r),
    lambda r: monodromy(lambda t, x: -x, [0.0], 1.0, rtol=r),
    lambda r: find_periodic_orbit(lambda t, x: -x + math.cos(t), [0.5], 2 * math.pi,
                                  autonomous=False, rtol=r),
])
def test_rtol_below_float64_is_raised_to_the_floor_with_a_warning(call):
    with pytest.warns(ToleranceWarning, match="raised to"):
        low = call(1e-20)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        floor = call(RTOL_FLOOR)
    for f in fields(low):
        a, b = getattr(low, f.name), getattr(floor, f.name)
        if isinstance(a, np.ndarray):
            np.testing.assert_array_equal(a, b)  # the same integration, bit for bit


@pytest.mark.parametrize("bad", [0.0, -1e-9, math.nan, "1e-9", True])
def test_non_positive_or_non_numeric_tolerances_are_refused(bad):
    with pytest.raises(ValueError, match="`atol`"):
        flow(lambda t, x: -x, (0.0, 1.0), [1.0], atol=bad)
    with pytest.raises(ValueError, match="`rtol`"):
        monodromy(lambda t, x: -x, [0.0], 1.0, rtol=bad)


# ---- read-only results ----------------------------------------------------------------------

def _arrays(result):
    return {f.name: getattr(result, f.name) for f in fields(result)
            if isinstance(getattr(result, f.name), np.ndarray)}


def _assert_read_only(result):
    arrays = _arrays(result)
    assert arrays
    for name, a in arrays.items():
        with pytest.raises(ValueError, match="read-only"):
            a[...] = 0  # an analysis of a result must be an analysis of what was solved
        assert not a.flags.writeable, name


def test_shooting_and_floquet_results_are_read_only(orbit, mon):
    _assert_read_only(orbit)
    _assert_read_only(mon)
    with pytest.raises(ValueError, match="read-only"):
        orbit.x0[:] = 1  # the example


def test_integration_results_are_read_only():
    _assert_read_only(flow(lambda t, x: -x, (0.0, 1.0), [1.0]))
    _assert_read_only(variational_flow(lambda t, x, p: -p * x, None, (0.0, 1.0), [1.0],
                                       trace=True, params=[1.0]))


def test_branch_is_read_only():
    # the bifurcations of a branch: tests/periodic/test_continuation.py (Duffing's folds)
    _assert_read_only(continue_orbit(hopf, [1.0, 0.0], 6.0, 1.0, 0.8, ds=0.1, ds_max=0.1))


def test_the_callers_arrays_are_not_frozen():
    x0 = np.array(GUESS)
    find_periodic_orbit(rossler, x0, T_GUESS, fixed=[0], jac=rossler_jac)
    assert x0.flags.writeable and list(x0) == GUESS

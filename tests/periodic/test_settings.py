"""flapping.periodic.settings: one SolverSettings accepted by shooting, Floquet analysis and
continuation, with the functions' defaults unchanged and explicit keywords winning."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import flapping.periodic
from flapping.errors import ToleranceWarning
from flapping.periodic import SolverSettings
from flapping.periodic.continuation import continue_orbit
from flapping.periodic.floquet import monodromy
from flapping.periodic.settings import (
    CAPS,
    RESIDUAL_CEILING,
    RTOL_CEILING,
    RTOL_FLOOR,
    check_times,
)
from flapping.periodic.shooting import find_periodic_orbit
from flapping.periodic.testproblems import rossler, rossler_jac

GUESS, T_GUESS = [0.0, -6.8, 0.03], 5.9


def hopf(t, x, p):
    r2 = x[0] ** 2 + x[1] ** 2
    return np.array([p * x[0] - x[1] - x[0] * r2, x[0] + p * x[1] - x[1] * r2])


def test_exported_frozen_and_neutral_by_default():
    assert flapping.periodic.SolverSettings is SolverSettings
    s = SolverSettings()
    assert all(getattr(s, f.name) is None for f in dataclasses.fields(s))
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.rtol = 1e-9  # type: ignore[misc]


def test_empty_settings_change_nothing():
    plain = find_periodic_orbit(rossler, GUESS, T_GUESS, fixed=[0], jac=rossler_jac)
    same = find_periodic_orbit(rossler, GUESS, T_GUESS, fixed=[0], jac=rossler_jac,
                               settings=SolverSettings())
    assert plain.period == same.period and plain.nfev == same.nfev


def test_settings_equal_keywords_and_keywords_win():
    loose = SolverSettings(rtol=1e-8, atol=1e-8, tol=1e-6)
    by_settings = find_periodic_orbit(rossler, GUESS, T_GUESS, fixed=[0], jac=rossler_jac,
                                      settings=loose)
    by_keywords = find_periodic_orbit(rossler, GUESS, T_GUESS, fixed=[0], jac=rossler_jac,
                                      rtol=1e-8, atol=1e-8, tol=1e-6)
    assert by_settings.period == by_keywords.period and by_settings.nfev == by_keywords.nfev
    overridden = find_periodic_orbit(rossler, GUESS, T_GUESS, fixed=[0], jac=rossler_jac,
                                     settings=loose, rtol=1e-11, atol=1e-12, tol=1e-10)
    default = find_periodic_orbit(rossler, GUESS, T_GUESS, fixed=[0], jac=rossler_jac)
    assert overridden.period == default.period and overridden.nfev == default.nfev


def test_monodromy_and_continuation_take_the_same_object():
    s = SolverSettings(rtol=1e-9, atol=1e-9, max_newton=4)
    orbit = find_periodic_orbit(rossler, GUESS, T_GUESS, fixed=[0], jac=rossler_jac)
    a = monodromy(rossler, orbit.x0, orbit.period, jac=rossler_jac, settings=s)
    b = monodromy(rossler, orbit.x0, orbit.period, jac=rossler_jac, rtol=1e-9, atol=1e-9)
    np.testing.assert_array_equal(a.matrix, b.matrix)
    c = continue_orbit(hopf, [1.0, 0.0], 6.0, 1.0, 0.8, settings=s, ds=0.1)
    d = continue_orbit(hopf, [1.0, 0.0], 6.0, 1.0, 0.8, rtol=1e-9, atol=1e-9, max_newton=4,
                       ds=0.1)
    np.testing.assert_array_equal(c.period, d.period)


def test_not_a_settings_object_is_refused():
    with pytest.raises(ValueError, match="`settings` must be a SolverSettings"):
        monodromy(rossler, GUESS, T_GUESS, settings={"rtol": 1e-9})


@given(st.sampled_from(["rtol", "atol", "tol"]),
       st.one_of(st.floats(max_value=0.0), st.just(math.inf), st.just(math.nan),
                 st.text(max_size=3), st.booleans()))
def test_bad_tolerance_field_is_named(name, value):
    with pytest.raises(ValueError, match=f"`{name}`"):
        SolverSettings(**{name: value})


@given(st.sampled_from(["rk4_steps", "max_steps", "max_nfev", "max_newton"]),
       st.one_of(st.integers(max_value=0), st.integers(min_value=1).map(lambda k: k + 10**7 * 500),
                 st.floats(), st.booleans()))
def test_bad_size_field_is_named_with_its_cap(name, value):
    with pytest.raises(ValueError, match=rf"`{name}` must be an integer in \[1, {CAPS[name]}\]"):
        SolverSettings(**{name: value})


def test_rtol_below_the_floor_is_raised_once_with_a_warning():
    with pytest.warns(ToleranceWarning):
        s = SolverSettings(rtol=1e-30)
    assert s.rtol == RTOL_FLOOR


def test_unknown_method_is_named():
    with pytest.raises(ValueError, match="`method` must be one of"):
        SolverSettings(method="Euler")


# ---- tolerance ceilings (issue 26, item 6): a tolerance too loose to mean anything -------------

X_AB, T_AB = np.array([-13.763610682134, -19.578751942452, 27.0]), 1.5586522107162


def lorenz_p(t, x, rho):
    from flapping.periodic.testproblems import lorenz

    return lorenz(t, x, 10.0, rho)


@given(st.floats(min_value=RTOL_CEILING, max_value=1e300, exclude_min=True))
def test_rtol_above_the_ceiling_is_refused_with_the_range(rtol):
    # scipy takes any rtol; rtol = 1 or 1e300 used to "succeed" with no correct digit
    with pytest.raises(ValueError, match=r"`rtol` must be a real number in \(0, 0\.001\]"):
        SolverSettings(rtol=rtol)


def test_rtol_at_the_ceiling_is_scipys_default_and_accepted():
    assert RTOL_CEILING == 1e-3
    assert SolverSettings(rtol=1e-3).rtol == 1e-3


@pytest.mark.parametrize("call", [
    lambda: flapping.periodic.flow(lambda t, x: -x, (0.0, 1.0), [1.0], rtol=1.0),
    lambda: flapping.periodic.variational_flow(lambda t, x: -x, None, (0.0, 1.0), [1.0],
                                               rtol=1e300),
    lambda: find_periodic_orbit(rossler, GUESS, T_GUESS, rtol=1.0),
    lambda: monodromy(rossler, GUESS, T_GUESS, rtol=1.0),
    lambda: continue_orbit(hopf, [0.3, 0.0], 6.28, 0.1, 0.2, rtol=1.0),
    lambda: continue_orbit(hopf, [0.3, 0.0], 6.28, 0.1, 0.2, locate_rtol=0.5),
], ids=["flow", "variational_flow", "find_periodic_orbit", "monodromy", "continue_orbit",
        "continue_orbit locate_rtol"])
def test_every_rtol_of_the_layer_has_the_ceiling(call):
    with pytest.raises(ValueError, match=r"rtol` must be a real number in \(0, 0\.001\]"):
        call()


@pytest.mark.parametrize("call", [
    lambda: flapping.periodic.flow(lambda t, x: -x, (0.0, 1.0), [1.0], atol=1e300),
    lambda: find_periodic_orbit(rossler, GUESS, T_GUESS, atol=1e300),
    lambda: monodromy(rossler, GUESS, T_GUESS, atol=1.0),
    lambda: continue_orbit(hopf, [0.3, 0.0], 6.28, 0.1, 0.2, atol=1.0),
    lambda: continue_orbit(hopf, [0.3, 0.0], 6.28, 0.1, 0.2, locate_atol=1.0),
], ids=["flow", "find_periodic_orbit", "monodromy", "continue_orbit", "locate_atol"])
def test_an_atol_that_switches_the_error_control_off_is_refused(call):
    # atol = 1e300 used to make flow "succeed" in one step, and shooting blow up
    with pytest.raises(ValueError, match=r"atol` must be at most 0\.01 \* max\(1, \|x0\|\)"):
        call()


def test_the_atol_ceiling_scales_with_the_state():
    # the same atol is coarse for a state of size 1 and fine for one of size 1e4
    big = np.array([1e4])
    assert flapping.periodic.flow(lambda t, x: -x, (0.0, 1.0), big, atol=1.0).success
    with pytest.raises(ValueError, match=r"`atol` must be at most .* = 0\.01 "):
        flapping.periodic.flow(lambda t, x: -x, (0.0, 1.0), [1.0], atol=1.0)


def test_the_residual_ceiling_is_the_closure_monodromy_accepts():
    from flapping.periodic.floquet import CLOSURE_TOL

    assert RESIDUAL_CEILING == CLOSURE_TOL


@pytest.mark.parametrize("tol", [1e6, 1.0, 1e-3])
def test_a_shooting_tol_that_accepts_non_solutions_is_refused(tol):
    # |x0| = 36: the ceiling is 3.6e-5. tol = 1e6 used to return success=True at the guess.
    with pytest.raises(ValueError, match=r"`tol` must be at most 1e-06 \* max\(1, \|x0\|\) = "
                                         r"3\.61e-05"):
        find_periodic_orbit(lorenz_p, X_AB, T_AB, fixed=[2], args=(28.0,), tol=tol)


def test_a_shooting_tol_given_through_settings_meets_the_same_ceiling():
    with pytest.raises(ValueError, match=r"`tol` must be at most"):
        find_periodic_orbit(lorenz_p, X_AB, T_AB, fixed=[2], args=(28.0,),
                            settings=SolverSettings(tol=1e6))


def test_a_shooting_tol_at_its_ceiling_is_accepted_and_met():
    tol = RESIDUAL_CEILING * float(np.linalg.norm(X_AB))
    orbit = find_periodic_orbit(lorenz_p, X_AB, T_AB, fixed=[2], args=(28.0,), tol=tol)
    assert orbit.success and orbit.residual_norm <= tol


@pytest.mark.parametrize(("name", "value"), [("tol", 1e6), ("tol", 1.0), ("tol", 2e-6),
                                              ("locate_tol", 1.0), ("switch_amplitude", 2.0)])
def test_continuation_tolerances_have_a_sane_range(name, value):
    # tol = 1e6 used to "reach p_end" through points on no orbit
    with pytest.raises(ValueError, match=rf"`{name}` must be a real number in \(0, "):
        continue_orbit(hopf, [0.3, 0.0], 6.28, 0.1, 0.2, **{name: value})


@pytest.mark.parametrize(("name", "value"), [("xtol", 1e6), ("ftol", 1.0)])
def test_levenberg_marquardts_tolerances_have_a_ceiling(name, value):
    with pytest.raises(ValueError, match=rf"`{name}` must be a real number in \[2\.22045e-16, "
                                         rf"0\.01\]"):
        find_periodic_orbit(rossler, GUESS, T_GUESS, **{name: value})


def test_check_times_accepts_the_edges_and_an_empty_grid():
    np.testing.assert_array_equal(check_times("t_eval", [0.0, 1.0], 0.0, 1.0), [0.0, 1.0])
    np.testing.assert_array_equal(check_times("t_eval", [1.0, 1.0, 0.0], 1.0, 0.0),
                                  [1.0, 1.0, 0.0])  # repeated times: harmless (solve_ivp refuses)
    assert check_times("t_eval", [], 0.0, 1.0).size == 0

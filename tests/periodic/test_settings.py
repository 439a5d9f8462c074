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
from flapping.periodic.settings import CAPS, RTOL_FLOOR
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

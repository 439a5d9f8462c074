"""SolverSettings in the hover layer: find_hover_orbit, hover_stability, continue_hover and
sweep_hover take ``settings=`` with the precedence of flapping.periodic (an explicit keyword wins,
even one equal to the default), and an empty or absent settings object changes nothing."""

from __future__ import annotations

import inspect

import numpy as np
import pytest

import flapping
from flapping.backends import Adaptive
from flapping.hover import ANALYSIS_ATOL, ANALYSIS_RTOL, find_hover_orbit
from flapping.hover.branch import continue_hover
from flapping.hover.stability import hover_stability
from flapping.periodic import SolverSettings

LOOSE = SolverSettings(rtol=1e-8, atol=1e-9, tol=1e-7)


@pytest.fixture(scope="module")
def insect():
    return flapping.hawkmoth()


@pytest.fixture(scope="module")
def adaptive(insect):
    return find_hover_orbit(insect, backend="adaptive")


def _same_orbit(a, b) -> bool:
    return (np.array_equal(a.x0, b.x0) and a.amplitude == b.amplitude and a.nfev == b.nfev
            and a.backend == b.backend)


def test_the_signatures_hold_no_default_number_the_backend_objects_do():
    # One place for every default: the backend objects' fields. The hover layer's signatures
    # say None for a tolerance (the object's field then applies).
    for function in (find_hover_orbit, hover_stability):
        parameters = inspect.signature(function).parameters
        for name in ("method", "rtol", "atol"):
            assert parameters[name].default is None, (function, name)
    assert inspect.signature(find_hover_orbit).parameters["tol"].default is None
    assert (Adaptive.rtol, Adaptive.atol, Adaptive.tol) == (1e-11, 1e-12, 1e-10)
    assert Adaptive.analysis_rtol == ANALYSIS_RTOL and Adaptive.analysis_atol == ANALYSIS_ATOL


def test_the_default_solve_is_the_default_object_s(insect, adaptive):
    assert _same_orbit(adaptive, find_hover_orbit(insect, backend=Adaptive()))
    explicit = Adaptive(rtol=1e-11, atol=1e-12, tol=1e-10)
    assert _same_orbit(adaptive, find_hover_orbit(insect, backend=explicit))


def test_empty_settings_change_nothing(insect, adaptive):
    same = find_hover_orbit(insect, backend="adaptive", settings=SolverSettings())
    assert _same_orbit(adaptive, same)
    plain, empty = hover_stability(adaptive), hover_stability(adaptive, settings=SolverSettings())
    assert np.array_equal(plain.monodromy, empty.monodromy)
    assert np.array_equal(plain.averaged_jacobian, empty.averaged_jacobian)


def test_find_hover_orbit_settings_equal_keywords_and_keywords_win(insect, adaptive):
    by_settings = find_hover_orbit(insect, backend="adaptive", settings=LOOSE)
    by_keywords = find_hover_orbit(insect, backend="adaptive", rtol=1e-8, atol=1e-9, tol=1e-7)
    assert _same_orbit(by_settings, by_keywords)
    assert not _same_orbit(by_settings, adaptive)  # the settings reached the solve
    # Keywords equal to the defaults, given explicitly, win over the settings.
    overridden = find_hover_orbit(insect, backend="adaptive", settings=LOOSE, rtol=1e-11,
                                  atol=1e-12, tol=1e-10)
    assert _same_orbit(overridden, adaptive)


def test_a_settings_method_selects_the_adaptive_path_as_the_keyword_does(insect):
    by_settings = find_hover_orbit(insect, settings=SolverSettings(method="RK45"))
    by_keyword = find_hover_orbit(insect, method="RK45")
    assert by_settings.backend == "adaptive" and _same_orbit(by_settings, by_keyword)


def test_hover_stability_settings_equal_keywords_and_keywords_win(adaptive):
    rk4 = SolverSettings(method="RK4", rk4_steps=256)
    by_settings = hover_stability(adaptive, backend="adaptive", settings=rk4)
    by_keywords = hover_stability(adaptive, backend="adaptive", method="RK4", rk4_steps=256)
    assert np.array_equal(by_settings.monodromy, by_keywords.monodromy)
    reference = hover_stability(adaptive)
    assert not np.array_equal(by_settings.monodromy, reference.monodromy)
    overridden = hover_stability(adaptive, settings=rk4, method="DOP853", rk4_steps=1024)
    assert np.array_equal(overridden.monodromy, reference.monodromy)
    assert np.array_equal(overridden.averaged_jacobian, reference.averaged_jacobian)


def test_settings_of_the_wrong_type_are_refused(adaptive, insect):
    with pytest.raises(ValueError, match="settings"):
        find_hover_orbit(insect, settings={"rtol": 1e-9})
    with pytest.raises(ValueError, match="settings"):
        hover_stability(adaptive, settings={"rtol": 1e-9})


def test_continue_hover_settings_replace_its_defaults_and_keywords_win(insect):
    end = insect.frequency * 1.01
    common = {"ds": 0.2, "ds_max": 0.2, "max_points": 3}
    plain = continue_hover(insect, "frequency", end, **common)
    empty = continue_hover(insect, "frequency", end, settings=SolverSettings(), **common)
    assert np.array_equal(plain.x0, empty.x0) and np.array_equal(plain.p, empty.p)
    by_settings = continue_hover(insect, "frequency", end, settings=SolverSettings(rtol=1e-11),
                                 **common)
    by_keyword = continue_hover(insect, "frequency", end, rtol=1e-11, **common)
    assert np.array_equal(by_settings.x0, by_keyword.x0)
    assert np.array_equal(by_settings.multipliers, by_keyword.multipliers)
    assert not np.array_equal(by_settings.x0, plain.x0)
    overridden = continue_hover(insect, "frequency", end, settings=SolverSettings(rtol=1e-11),
                                rtol=1e-10, **common)
    assert np.array_equal(overridden.x0, plain.x0)


def test_sweep_passes_its_settings_to_every_point(insect):
    pytest.importorskip("pandas")
    pytest.importorskip("tqdm")
    from flapping.studies.sweep import sweep_hover

    grid = {"frequency": [insect.frequency]}
    table = sweep_hover(insect, grid, progress=False, settings=SolverSettings(method="RK45"))
    orbit = find_hover_orbit(insect, method="RK45")
    row = table.iloc[0]
    assert row["backend"] == "adaptive" and row["amplitude_deg"] == orbit.amplitude_deg
    assert row["mu1_real"] == hover_stability(orbit, method="RK45").multipliers[0].real
    with pytest.raises(ValueError, match="settings"):
        sweep_hover(insect, grid, progress=False, settings={"method": "RK45"})

"""Each backend a strategy (flapping.backends + flapping.hover.*_path): the object that holds a
path's options also runs it; no other code asks which class it is."""

from __future__ import annotations

import math
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import flapping
from flapping.backends import (
    COMPILED_AMPLITUDE_TOL_FLOOR_DEG,
    COMPILED_MULTIPLIER_TOL_FLOOR,
    COMPILED_STEPS_RANGE,
    Adaptive,
    Compiled,
    FixedStep,
    OptionWarning,
)
from flapping.fast import kernel
from flapping.hover import HoverProblem, find_hover_orbit
from flapping.hover.problem import state_guess
from flapping.hover.stability import hover_stability

PACKAGE = Path(flapping.__file__).parent
#: The strategies: the backend classes and each path's module.
STRATEGIES = {"backends.py", "hover/compiled_path.py", "hover/fixed_step_path.py",
              "hover/adaptive_path.py"}
DISPATCH = re.compile(r"isinstance\([^)]*\b(Compiled|FixedStep|Adaptive|Backend)\b")


def test_no_backend_isinstance_outside_the_strategies():
    # Reproducer (issue 35): 15 isinstance dispatches in 7 files decided what runs.
    found = [f"{path.relative_to(PACKAGE)}:{i}"
             for path in PACKAGE.rglob("*.py")
             if str(path.relative_to(PACKAGE)) not in STRATEGIES
             and "peers" not in path.parts  # FWUAV's own analysis: not a hover path
             for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
             if DISPATCH.search(line)]
    assert not found, found


@pytest.fixture(scope="module")
def moth():
    return flapping.hawkmoth()


@pytest.mark.parametrize("backend", [Compiled(), FixedStep(), Adaptive()])
def test_each_object_solves_and_analyses_on_its_own_path(moth, backend):
    problem = HoverProblem(moth)
    orbit = backend.solve(problem, problem.guess(None), state_guess(None), 64)
    assert orbit.backend == backend.name and orbit.solver == backend
    stability = backend.analyse(orbit, problem, 64, Adaptive.analysis_rtol,
                                Adaptive.analysis_atol)
    reference = hover_stability(find_hover_orbit(moth))
    # The three paths agree to their error estimates (1e-8 and below on the linear loads).
    np.testing.assert_allclose(stability.multipliers, reference.multipliers, atol=1e-7)


def test_a_six_dof_orbit_takes_the_same_objects(moth):
    # Reproducer: hover_stability(orbit6, backend=Compiled()) was refused while "compiled"
    # worked.
    orbit = find_hover_orbit(moth, dof=6, aerodynamics="linear")
    by_object = hover_stability(orbit, backend=Compiled())
    by_name = hover_stability(orbit, backend="compiled")
    np.testing.assert_array_equal(by_object.multipliers, by_name.multipliers)
    with pytest.raises(ValueError, match="six-degree-of-freedom"):
        hover_stability(orbit, backend=FixedStep())


@pytest.mark.parametrize("options", [
    {"rtol": -1.0}, {"rtol": 0.0}, {"rtol": math.nan}, {"rtol": 1e6}, {"rtol": "tight"},
    {"atol": -1.0}, {"atol": math.inf}, {"n_average": -1}, {"rk4_steps": -5},
    {"settings": "default"}, {"method": "RK23"}])
def test_a_six_dof_analysis_refuses_what_every_path_refuses(moth, options):
    # Reproducer: hover_stability on a six-dof orbit ignored these with no warning.
    orbit = find_hover_orbit(moth, dof=6, aerodynamics="linear")
    with pytest.raises(ValueError, match=next(iter(options))):
        hover_stability(orbit, **options)


def test_a_six_dof_analysis_warns_about_an_option_it_does_not_use(moth):
    orbit = find_hover_orbit(moth, dof=6, aerodynamics="linear")
    with pytest.warns(OptionWarning, match="rk4_steps"):
        hover_stability(orbit, rk4_steps=100)
    with pytest.warns(OptionWarning, match="analysis_rtol"):  # the compiled path runs
        hover_stability(orbit, rtol=1e-10)


def test_the_compiled_options_are_refused_where_the_kernel_refuses_them():
    # Reproducer: Compiled(n_steps=2000) was built and refused by the solve ("[4, 1024]").
    assert COMPILED_STEPS_RANGE == (kernel._MIN_STEPS, kernel._MAX_STEPS)
    assert COMPILED_AMPLITUDE_TOL_FLOOR_DEG == kernel.AMPLITUDE_TOL_FLOOR_DEG
    assert COMPILED_MULTIPLIER_TOL_FLOOR == kernel.MULTIPLIER_TOL_FLOOR
    for bad in ({"n_steps": 2000}, {"n_steps": 3}, {"amplitude_tol_deg": 1e-12},
                {"multiplier_tol": 1e-13}):
        with pytest.raises(ValueError, match=next(iter(bad))):
            Compiled(**bad)
    edge = Compiled(n_steps=1024, amplitude_tol_deg=1e-11, multiplier_tol=1e-12)
    assert kernel.checked_options(edge.n_steps, edge.amplitude_tol_deg, edge.multiplier_tol)


def test_the_keyword_routes_warn_and_forward_to_the_object(moth):
    with pytest.warns(DeprecationWarning, match="backend=Compiled"):
        routed = find_hover_orbit(moth, kernel_options={"n_steps": 16})
    direct = find_hover_orbit(moth, backend=Compiled(n_steps=16))
    assert routed.solver == direct.solver and routed.amplitude == direct.amplitude
    with pytest.warns(DeprecationWarning, match="backend=Adaptive"):
        flat = find_hover_orbit(moth, backend="adaptive", rtol=1e-10)
    assert flat.solver == Adaptive(rtol=1e-10)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the one route warns about nothing
        find_hover_orbit(moth, backend=Adaptive(rtol=1e-10))

"""How a solve runs (flapping.backends) and what it reports (flapping.results): the backend
objects, the one function that chooses among them, the one status table."""

from __future__ import annotations

import ast
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

import flapping
from flapping.backends import (
    AUTO,
    BACKEND_NAMES,
    Adaptive,
    Compiled,
    FixedStep,
    OptionWarning,
    as_backend,
)
from flapping.errors import ConvergenceError, DomainError, ToleranceWarning
from flapping.hover import HoverProblem, choose_backend, find_hover_orbit
from flapping.hover.stability import hover_stability
from flapping.results import MESSAGES, Status, status_of

PACKAGE = Path(flapping.__file__).parent


def test_the_string_forms_are_the_objects_with_their_defaults():
    assert as_backend("compiled") == Compiled()
    assert as_backend("fixed-step") == FixedStep()
    assert as_backend("adaptive") == Adaptive()
    assert as_backend("auto") == AUTO
    assert as_backend(Adaptive) == Adaptive()
    custom = FixedStep(n_steps=32)
    assert as_backend(custom) is custom
    assert BACKEND_NAMES == ("auto", "compiled", "fixed-step", "adaptive")


@pytest.mark.parametrize("bad", ["fast", "", None, 3, Status.SUCCESS, ["auto"]])
def test_an_unknown_backend_names_the_accepted_forms(bad):
    with pytest.raises(ValueError, match="`backend` must be one of"):
        as_backend(bad)


@pytest.mark.parametrize(("kind", "name", "value"), [
    (Adaptive, "rtol", 1.0), (Adaptive, "rtol", 1e300), (Adaptive, "rtol", math.nan),
    (Adaptive, "atol", 0.0), (Adaptive, "atol", -1e-9), (Adaptive, "tol", 1e6),
    (Adaptive, "analysis_rtol", 0.5), (Adaptive, "method", "Euler"),
    (Adaptive, "jacobian", "analytic"), (Adaptive, "rk4_steps", 0), (Adaptive, "max_steps", 10**9),
    (Compiled, "amplitude_tol_deg", 1.0), (Compiled, "multiplier_tol", -1.0),
    (Compiled, "n_steps", 10**6), (Compiled, "n_steps", 2.5),
    (FixedStep, "n_steps", 1), (FixedStep, "error_tol", 0.0), (FixedStep, "tol", math.inf),
    (FixedStep, "multiplier_tol", 2.0), (FixedStep, "max_nfev", 0),
])
def test_every_option_is_checked_when_the_object_is_built(kind, name, value):
    with pytest.raises(ValueError, match=f"`{name}`"):
        kind(**{name: value})


def test_an_absurd_tolerance_is_refused_on_every_path_whether_or_not_it_runs():
    # Reproducer: find_hover_orbit(h, rtol=1.0) ran the compiled path and ignored it in silence.
    insect = flapping.hawkmoth()
    for rtol in (1.0, 1e300):
        with pytest.raises(ValueError, match="`rtol`"):
            find_hover_orbit(insect, rtol=rtol)
        with pytest.raises(ValueError, match="`rtol`"):
            find_hover_orbit(insect, backend="compiled", rtol=rtol)


def test_an_rtol_below_float64_is_raised_to_the_floor_with_a_warning():
    with pytest.warns(ToleranceWarning, match="raised to"):
        path = Adaptive(rtol=1e-20)
    assert path.rtol == pytest.approx(100 * np.finfo(float).eps)


def test_an_unknown_option_names_the_path_and_its_options():
    with pytest.raises(ValueError, match="no option rtol.*amplitude_tol_deg"):
        Compiled().with_options(rtol=1e-9)
    with pytest.raises(ValueError, match="`kernel_options` accepts"):
        find_hover_orbit(flapping.hawkmoth(), kernel_options={"steps": 8})


def test_auto_chooses_the_fastest_path_that_applies():
    moth = flapping.hawkmoth()
    assert isinstance(choose_backend(HoverProblem(moth)), Compiled)
    assert isinstance(choose_backend(HoverProblem(moth, "small-angle")), FixedStep)
    assert isinstance(choose_backend(HoverProblem(moth, "exact")), FixedStep)
    two = HoverProblem(moth, trims=("amplitude", "stroke_mean"))
    assert isinstance(choose_backend(two), Adaptive)
    # an orbit already solved is analysed on its own path
    solved = FixedStep(n_steps=16)
    assert choose_backend(HoverProblem(moth), solved=solved) is solved
    # a name is that path, checked to apply
    with pytest.raises(ValueError, match="does not apply"):
        choose_backend(HoverProblem(moth, "exact"), "compiled")
    with pytest.raises(ValueError, match="does not apply"):
        choose_backend(two, Compiled())


def test_an_option_of_a_path_that_does_not_run_warns():
    moth = flapping.hawkmoth()
    with pytest.warns(OptionWarning, match="rtol=1e-10 does not apply to the compiled path"):
        orbit = find_hover_orbit(moth, rtol=1e-10)
    assert orbit.backend == "compiled"
    with pytest.warns(OptionWarning, match="amplitude_tol_deg"):
        find_hover_orbit(moth, backend="adaptive", kernel_options={"amplitude_tol_deg": 1e-8})
    with pytest.warns(OptionWarning, match="rtol"):
        hover_stability(orbit, rtol=1e-10)
    with warnings.catch_warnings():
        warnings.simplefilter("error", OptionWarning)
        find_hover_orbit(moth)  # nothing given, nothing to warn about
        find_hover_orbit(moth, kernel_options={"n_steps": 16})


def test_another_method_chooses_the_adaptive_path_as_before():
    orbit = find_hover_orbit(flapping.hawkmoth(), method="RK45")
    assert orbit.backend == "adaptive" and isinstance(orbit.solver, Adaptive)
    assert orbit.solver.method == "RK45"


def test_an_implicit_method_is_refused_on_the_hover_path():
    # Reproducer: method="Radau" on the adaptive hover ran for hours.
    with pytest.raises(ValueError, match="not stiff"):
        find_hover_orbit(flapping.hawkmoth(), method="Radau")


def test_one_function_decides_the_path():
    # The decision's ingredients (the kernel's refusal, whether numba is there) are read in
    # flapping.hover.problem.choose_backend only (and in the kernel itself).
    readers = []
    for path in PACKAGE.rglob("*.py"):
        if "fast" in path.relative_to(PACKAGE).parts:
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.Attribute) and node.attr in ("numba_available",
                                                                   "_kernel_refusal"):
                readers.append(f"{path.relative_to(PACKAGE)}:{node.lineno}")
    # ... and in the compiled path's own check of where it applies (its strategy module).
    assert readers and all(r.startswith(("hover/problem.py", "hover/compiled_path.py"))
                           for r in readers), readers


def test_status_reads_as_a_word_and_has_one_message_each():
    assert str(Status.SUCCESS) == "success" and str(Status.SINGULAR) == "singular"
    assert f"{Status.MAX_ITERATIONS}" == "max_iterations"
    assert set(MESSAGES) == set(Status) and all(MESSAGES.values())
    assert Status.SUCCESS.success and not Status.SINGULAR.success


def test_a_failure_s_status_comes_from_its_error():
    assert status_of(DomainError("out")) is Status.LEFT_DOMAIN
    assert status_of(ValueError("bad")) is Status.INVALID_INPUT
    assert status_of(np.linalg.LinAlgError("singular")) is Status.SINGULAR
    assert status_of(FloatingPointError("nan")) is Status.NON_FINITE
    assert status_of(ConvergenceError("no")) is Status.FAILED
    error = ConvergenceError("no")
    error.status = Status.MAX_ITERATIONS
    assert status_of(error) is Status.MAX_ITERATIONS


def test_the_hover_status_prints_as_a_word():
    # Reproducer: print(orbit.status) printed 0.
    orbit = find_hover_orbit(flapping.hawkmoth())
    assert str(orbit.status) == "hover" and f"{orbit.status}" == "hover"
    assert str(orbit.solve_status) == "success"


@pytest.mark.parametrize("backend", ["compiled", "adaptive"])
def test_every_path_reports_the_same_fields(backend):
    orbit = find_hover_orbit(flapping.hawkmoth(), backend=backend)
    assert orbit.stats is not None and orbit.stats.nit == orbit.nit >= 1
    assert orbit.stats.nfev == orbit.nfev > 0 and orbit.stats.time > 0
    assert orbit.solver is not None and orbit.solver.name == orbit.backend
    errors = (orbit.amplitude_error, orbit.x0_error, orbit.multiplier_error)
    if backend == "compiled":
        assert all(0 <= e < 1e-8 for e in errors)
    else:  # the adaptive path has no estimate, and says so with NaN
        assert all(math.isnan(e) for e in errors)


def test_a_fixed_step_orbit_reports_its_estimates_and_is_analysed_on_its_path():
    orbit = find_hover_orbit(flapping.hawkmoth(), aerodynamics="small-angle")
    assert orbit.backend == "fixed-step" and isinstance(orbit.solver, FixedStep)
    assert orbit.fixed_step is not None
    assert orbit.amplitude_error == float(orbit.fixed_step.unknowns_error[4]) < 1e-9
    stability = hover_stability(orbit)
    assert math.isfinite(stability.multiplier_error) and stability.multiplier_error < 1e-7


def test_an_orbit_is_not_changed_after_construction():
    orbit = find_hover_orbit(flapping.hawkmoth(), backend="adaptive")
    with pytest.raises(AttributeError):
        orbit.samples = None  # type: ignore[misc]
    source = (PACKAGE / "hover" / "orbit.py").read_text(encoding="utf-8")
    assert 'object.__setattr__(orbit' not in source


@pytest.mark.parametrize("aerodynamics", ["linear", "small-angle"])
def test_the_monodromy_has_one_type_whatever_the_path(aerodynamics):
    from flapping.results import Floquet

    orbit = find_hover_orbit(flapping.hawkmoth(), aerodynamics=aerodynamics)
    stability = hover_stability(orbit)
    solved, analysed = orbit.floquet, stability.floquet
    assert isinstance(solved, Floquet) and isinstance(analysed, Floquet)
    assert solved.matrix.shape == analysed.matrix.shape == (4, 4)
    assert not analysed.multipliers.flags.writeable
    # the solve's last integration and the analysis agree within their error estimates
    gap = np.max(np.abs(solved.multipliers - analysed.multipliers))
    assert gap <= solved.multiplier_error + analysed.multiplier_error + 1e-12
    assert analysed.is_stable == stability.is_stable
    np.testing.assert_array_equal(analysed.exponents, stability.exponents)
    if aerodynamics == "linear":  # the kernel integrates trace J: Liouville holds to rounding
        assert analysed.liouville_error < 1e-9
    adaptive = hover_stability(find_hover_orbit(flapping.hawkmoth(), backend="adaptive"))
    assert find_hover_orbit(flapping.hawkmoth(), backend="adaptive").floquet is None
    assert adaptive.floquet.liouville_error < 1e-9


def test_the_kernel_s_codes_are_the_one_table_s():
    from flapping.fast import _compiled

    codes = {"CONVERGED": Status.SUCCESS, "MAX_ITERATIONS": Status.MAX_ITERATIONS,
             "AMPLITUDE_OUT_OF_RANGE": Status.LEFT_DOMAIN, "NOT_FINITE": Status.NON_FINITE,
             "SINGULAR": Status.SINGULAR}
    for name, status in codes.items():
        assert getattr(_compiled, name) == status.code, name
        assert Status(getattr(_compiled, name)) is status, name


def test_a_failed_kernel_solve_carries_its_status(monkeypatch):
    # No refinement allowed from 4 steps: the tolerances cannot be met. The error says so with
    # the one table's status, which a sweep row reports as its word.
    from flapping.fast import kernel

    monkeypatch.setattr(kernel, "_MAX_REFINEMENTS", 0)
    with pytest.raises(ConvergenceError) as info:
        kernel.solve_hover(flapping.hawkmoth(), n_steps=4, amplitude_tol_deg=1e-11,
                           multiplier_tol=1e-12)
    assert info.value.status is Status.TOLERANCE_NOT_MET
    assert status_of(info.value) is Status.TOLERANCE_NOT_MET


def test_the_adaptive_shooting_reports_the_one_table_s_status():
    from flapping.periodic.shooting import find_periodic_orbit
    from flapping.periodic.testproblems import lorenz, lorenz_jac

    orbit = find_periodic_orbit(lorenz, [-13.76, -19.58, 27.0], 1.56, jac=lorenz_jac, fixed=[2])
    assert orbit.status is Status.SUCCESS and orbit.success
    with pytest.raises(ConvergenceError) as info:  # two evaluations cannot converge
        find_periodic_orbit(lorenz, [-13.76, -19.58, 27.0], 1.56, jac=lorenz_jac, fixed=[2],
                            max_nfev=2)
    assert info.value.status in (Status.MAX_EVALUATIONS, Status.RESIDUAL_ABOVE_TOL)
    assert info.value.result.status is info.value.status

"""One hover problem behind every path: HoverProblem, HoverOrbit whatever the backend, sweeps."""

import math
import warnings

import numpy as np
import pytest

from flapping import hawkmoth
from flapping.errors import HoverDriftWarning
from flapping.fast import kernel
from flapping.hover import (
    DEFAULT_BACKEND,
    HOVER_SPEED_RTOL,
    HoverOrbit,
    HoverProblem,
    HoverStatus,
    find_hover_orbit,
    forced_orbit,
)
from flapping.hover.branch import HoverFields
from flapping.hover.stability import hover_stability
from flapping.model.dynamics import LongitudinalDynamics

needs_numba = pytest.mark.skipif(not kernel.numba_available(), reason="needs numba")


@pytest.fixture(scope="module")
def moth():
    return hawkmoth()


@pytest.fixture(scope="module")
def both(moth):
    """The hover orbit and its stability on each backend."""
    adaptive = find_hover_orbit(moth, backend="adaptive")
    out = {"adaptive": (adaptive, hover_stability(adaptive))}
    if kernel.numba_available():
        compiled = find_hover_orbit(moth, backend="compiled")
        out["compiled"] = (compiled, hover_stability(compiled))
    return out


# --------------------------------------------------------------------------- the problem
def test_the_default_backend_is_the_fast_one():
    assert DEFAULT_BACKEND == "auto"


@needs_numba
@pytest.mark.parametrize(("options", "expected"), [
    ({}, "compiled"),
    ({"aerodynamics": "exact"}, "fixed-step"),
    ({"trims": ("amplitude", "stroke_mean")}, "adaptive"),
])
def test_auto_runs_the_kernel_only_where_it_applies_and_fixed_step_for_blade_elements(moth, options, expected):
    assert HoverProblem(moth, **options).backend("auto") == expected


@pytest.mark.parametrize("options", [{"aerodynamics": "small-angle"},
                                     {"trims": ("amplitude", "stroke_mean")}])
def test_compiled_says_why_it_does_not_apply(moth, options):
    with pytest.raises(ValueError, match="backend='compiled' does not apply"):
        HoverProblem(moth, **options).backend("compiled")


def test_a_problem_refuses_an_insect_that_cannot_trim(moth):
    with pytest.raises(ValueError, match="cannot hover"):
        HoverProblem(moth, alpha_m=math.radians(1.0))


def test_a_model_has_a_problem_without_the_trim_check(moth):
    # alpha_m = 0.02 rad needs a stroke beyond 90 deg (eq. 40): no hover problem, but a model at
    # a prescribed amplitude still has one (forced_orbit's), built by the one constructor.
    with pytest.raises(ValueError, match="cannot hover"):
        HoverProblem(moth, alpha_m=0.02)
    unchecked = HoverProblem(moth, alpha_m=0.02, trim_check=False)
    model = LongitudinalDynamics(moth, amplitude=1.0, alpha_m=0.02)
    problem = HoverProblem.of_model(model)
    assert problem.model is model and problem.trims == ("amplitude",)
    assert (problem.insect, problem.aerodynamics, problem.alpha_m) == (
        unchecked.insect, unchecked.aerodynamics, unchecked.alpha_m)
    y, trims = np.array([0.1, -0.2, 3.0, 0.05, 0.0]), np.array([1.0])
    for f, g in zip(problem.fields()[0], unchecked.fields()[0], strict=True):
        np.testing.assert_array_equal(f(1e-3, y, trims), g(1e-3, y, trims))
    assert problem.backend("auto") in ("compiled", "adaptive")
    with pytest.raises(ValueError, match="trim_check"):
        HoverProblem(moth, trim_check=0)


def test_a_problem_given_to_find_hover_orbit_keeps_its_own_options(moth):
    with pytest.raises(ValueError, match="the problem's own"):
        find_hover_orbit(HoverProblem(moth), aerodynamics="exact")


@pytest.mark.parametrize("trims", [("amplitude",), ("amplitude", "stroke_mean")])
def test_the_fields_jacobian_is_the_derivative_of_the_rhs(moth, trims):
    # Central differences of the augmented right-hand side, in the state and in the trims.
    problem = HoverProblem(moth.with_(hinge_offset=1e-3), trims=trims)
    rhs, jac, pjac = problem.fields()
    n = 4 + problem.n_conditions
    y = np.array([0.1, -0.05, 1.5, 0.2] + [0.0] * problem.n_conditions)
    p = problem.guess()
    for k, t in ((0, 0.1 * problem.period), (1, 0.7 * problem.period)):
        J = jac[k](t, y, p)
        P = pjac[k](t, y, p)
        for j in range(n):
            h = 1e-6 * max(1.0, abs(y[j]))
            e = np.zeros(n)
            e[j] = h
            fd = (rhs[k](t, y + e, p) - rhs[k](t, y - e, p)) / (2 * h)
            np.testing.assert_allclose(J[:, j], fd, rtol=1e-6, atol=1e-6)
        for j in range(len(p)):
            e = np.zeros(len(p))
            e[j] = 1e-7
            fd = (rhs[k](t, y, p + e) - rhs[k](t, y, p - e)) / 2e-7
            np.testing.assert_allclose(P[:, j], fd, rtol=1e-5, atol=1e-5)


def test_the_branch_fields_are_the_problem_fields(moth):
    # hover_branch asks the problem of each parameter value; the same numbers as find_hover_orbit's.
    fields = HoverFields(moth, "frequency")
    rhs = HoverProblem(moth.with_(frequency=27.0)).fields()[0]
    y, t = np.array([0.1, 0.0, 1.0, 0.1, 0.0]), 0.004
    for k in range(2):
        np.testing.assert_array_equal(fields.funs[k](t, y, 27.0, np.array([1.0])),
                                      rhs[k](t, y, np.array([1.0])))


# --------------------------------------------------------------------------- one result type
@needs_numba
def test_both_backends_give_the_same_orbit_and_multipliers(both):
    (a, sa), (c, sc) = both["adaptive"], both["compiled"]
    assert (a.backend, c.backend) == ("adaptive", "compiled")
    # The kernel meets Phi to 1e-9 deg and the multipliers to 1e-8 (its error estimates).
    assert abs(a.amplitude_deg - c.amplitude_deg) < 1e-8
    np.testing.assert_allclose(c.x0, a.x0, atol=1e-8)
    np.testing.assert_allclose(sc.multipliers, sa.multipliers, atol=1e-7)
    # The averaged Jacobian: Gauss quadrature on both paths, to the orbit's accuracy.
    np.testing.assert_allclose(sc.averaged_jacobian, sa.averaged_jacobian, rtol=1e-7, atol=1e-7)
    for orbit in (a, c):
        assert orbit.status == HoverStatus.HOVER and orbit.is_hover
        assert orbit.nit > 0 and orbit.nfev > 0 and orbit.residual_norm < 1e-9


@needs_numba
def test_the_compiled_orbit_samples_agree_with_the_adaptive_ones(both):
    a, c = both["adaptive"][0], both["compiled"][0]
    np.testing.assert_array_equal(c.t, a.t)
    np.testing.assert_allclose(c.x, a.x, atol=1e-8)


@pytest.mark.parametrize("backend", ["adaptive", "compiled"])
def test_result_arrays_are_read_only(both, backend):
    if backend not in both:
        pytest.skip("needs numba")
    orbit, stab = both[backend]
    for array in (orbit.x0, orbit.t, orbit.x, stab.monodromy, stab.multipliers,
                  stab.eigenvectors, stab.averaged_jacobian):
        with pytest.raises(ValueError, match="read-only"):
            array[0] = 1.0


@needs_numba
def test_auto_analyses_an_orbit_on_the_path_that_solved_it(both):
    a, sa = both["adaptive"]
    # The adaptive path's Liouville check is at rounding level (5e-14); the kernel's ~1e-11.
    assert sa.liouville_error < 1e-12
    assert hover_stability(a, backend="compiled").liouville_error > sa.liouville_error


# --------------------------------------------------------------------------- drift and status
def test_a_drifting_orbit_is_not_hover_and_says_why(moth):
    with pytest.warns(HoverDriftWarning):
        orbit = find_hover_orbit(moth.with_(hinge_offset=1e-3))
    assert orbit.status == HoverStatus.DRIFTING and not orbit.is_hover
    speed = orbit.mean_inertial_velocity["forward"]
    assert abs(speed) > 1e3 * HOVER_SPEED_RTOL * orbit.wingtip_speed
    assert "stroke_mean" in orbit.message


def test_a_forced_orbit_away_from_hover_climbs_or_sinks(moth):
    orbit = forced_orbit(moth, math.radians(70.0))
    assert orbit.status == HoverStatus.CLIMBING and orbit.trims == ()
    assert orbit.mean_inertial_velocity["climb"] > 0  # more stroke than hover needs: climbs


def test_two_trims_make_the_offset_insect_hover(moth):
    with warnings.catch_warnings():
        warnings.simplefilter("error", HoverDriftWarning)
        orbit = find_hover_orbit(moth.with_(hinge_offset=1e-3),
                                 trims=("amplitude", "stroke_mean"))
    assert orbit.is_hover and orbit.backend == "adaptive" and orbit.stroke_mean != 0.0


def test_hover_orbit_is_the_package_result_type(both):
    assert all(isinstance(orbit, HoverOrbit) for orbit, _ in both.values())


# --------------------------------------------------------------------------- sweeps
@pytest.mark.parametrize("backend", ["adaptive", "auto"])
def test_a_sweep_never_calls_a_drifting_orbit_a_converged_hover(moth, backend):
    pytest.importorskip("pandas")
    from flapping.studies.sweep import sweep_hover

    table = sweep_hover(moth, {"hinge_offset": [0.0, 1e-3]}, progress=False, backend=backend)
    centred, offset = table.iloc[0], table.iloc[1]
    assert centred.converged and centred.status == HoverStatus.HOVER
    assert not offset.converged and offset.status == HoverStatus.DRIFTING
    assert offset.forward_speed > 0.1 and "forwards" in offset.message  # ~0.44 m/s
    assert abs(centred.forward_speed) < 1e-6

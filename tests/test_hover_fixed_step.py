"""The fixed-step path of the blade-element hover orbit (``backend="fixed-step"``).

Newton on a fixed-step DOP853 period map on a time mesh graded towards the stroke reversals,
with the loads' kinks as switching functions: it converges to the integration floor where the
adaptive path's Levenberg-Marquardt stalls at its integration noise (~3e-8 at hinge heights of
10, 15, 17-20 and 22 mm for the hawkmoth), and it estimates its own error.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from flapping import hawkmoth
from flapping.backends import OptionWarning
from flapping.errors import ConvergenceError, HoverDriftWarning
from flapping.hover import HoverProblem, find_hover_orbit
from flapping.hover.problem import grading, grading_derivative
from flapping.hover.stability import hover_stability
from flapping.model.presets import preset
from flapping.periodic._fixedmap import PeriodMap

TOL = 1e-10


def _check(orbit, tol=TOL):
    fs = orbit.fixed_step
    assert orbit.backend == "fixed-step" and fs is not None and fs.success
    assert orbit.residual_norm < tol
    assert np.all(fs.unknowns_error <= TOL * np.maximum(1.0, np.abs(fs.unknowns)))
    assert 0.0 < orbit.amplitude <= math.pi / 2


@pytest.fixture(scope="module")
def continuation():
    """The small-angle orbit continued in hinge height, warm-started, on the fixed-step path."""
    orbits = {}
    x0 = amplitude = None
    n_steps = 64
    for h_mm in (0, 5, 10, 15, 17, 20, 22, 25, 30, 35):
        orbit = find_hover_orbit(hawkmoth(hinge_height=h_mm * 1e-3), aerodynamics="small-angle",
                                 x0_guess=x0, amplitude_guess=amplitude,
                                 fixed_step_options={"n_steps": n_steps})
        orbits[h_mm] = orbit
        x0, amplitude = orbit.x0, orbit.amplitude
        n_steps = orbit.fixed_step.n_steps
    return orbits


def test_auto_chooses_the_fixed_step_path_for_the_blade_element_models():
    for aerodynamics in ("small-angle", "exact"):
        problem = HoverProblem(hawkmoth(), aerodynamics)
        assert problem.backend() == "fixed-step"
        assert problem.backend("auto", adaptive_options=True) == "adaptive"
        assert problem.backend("adaptive") == "adaptive"
    assert HoverProblem(hawkmoth(), "linear").backend("fixed-step") == "fixed-step"


def test_the_hinge_height_continuation_converges_at_every_height(continuation):
    # 10, 15, 17, 20 and 22 mm are where the adaptive path's LM stalled at ~3e-8.
    for orbit in continuation.values():
        _check(orbit)
    amplitudes = [o.amplitude for o in continuation.values()]
    assert np.all(np.diff(amplitudes) < 0)  # a smooth branch: Phi falls with the hinge height


def test_two_trims_converge_at_a_height_where_lm_stalled(continuation):
    guess = continuation[20]
    orbit = find_hover_orbit(hawkmoth(hinge_height=20e-3), aerodynamics="small-angle",
                             trims=("amplitude", "stroke_mean"), x0_guess=guess.x0,
                             amplitude_guess=guess.amplitude)
    _check(orbit)
    assert orbit.is_hover


def test_agrees_with_the_adaptive_path_where_both_converge(continuation):
    new = continuation[0]
    old = find_hover_orbit(hawkmoth(), aerodynamics="small-angle", backend="adaptive")
    assert abs(new.amplitude - old.amplitude) < 1e-10  # measured 7e-13 rad
    assert np.max(np.abs(new.x0 - old.x0)) < 1e-9  # measured 3.9e-11
    # The fixed-step monodromy (augmented state: its trivial multiplier 1 is the descent z)
    # against the adaptive analysis of the adaptive orbit.
    mu_new = np.sort(np.abs(new.fixed_step.multipliers))
    mu_new = np.delete(mu_new, np.argmin(np.abs(mu_new - 1.0)))
    mu_old = np.sort(np.abs(hover_stability(old).multipliers))
    assert np.max(np.abs(mu_new - mu_old)) < 1e-8  # measured 1.9e-10
    # The adaptive analysis of the two orbits (measured 2.2e-10).
    mu_analysed = np.sort(np.abs(hover_stability(new, backend="adaptive").multipliers))
    assert np.max(np.abs(mu_analysed - mu_old)) < 1e-8


def test_the_error_estimate_is_honest_under_refinement(continuation):
    # At 24, 32 and 48 steps per half-stroke (no refinement: error_tol 1e-2), the error of the
    # unknowns against a tight solve (128 steps, error_tol 1e-12) falls at order ~8, and the
    # Richardson estimate bounds it (max over the unknowns, each relative to max(1, |z_i|)) within
    # a small factor (measured 2-6.5 from 20 steps on; at 16 steps, where the coarse level has 8,
    # it falls 2 % short: not yet asymptotic).
    start = continuation[10]
    insect = start.problem.insect

    def solve(n, tol):
        return find_hover_orbit(insect, aerodynamics="small-angle", x0_guess=start.x0,
                                amplitude_guess=start.amplitude,
                                fixed_step_options={"n_steps": n, "error_tol": tol}).fixed_step

    tight = solve(128, 1e-12)
    scale = np.maximum(1.0, np.abs(tight.unknowns))
    steps, errors = (24, 32, 48), []
    for n in steps:
        fs = solve(n, 1e-2)
        assert fs.n_steps == n
        actual = float(np.max(np.abs(fs.unknowns - tight.unknowns) / scale))
        estimate = float(np.max(fs.unknowns_error / scale))
        assert actual <= estimate < 20.0 * actual, (n, actual, estimate)
        errors.append(actual)
    orders = np.log(np.array(errors[:-1]) / np.array(errors[1:])) / np.log(
        np.array(steps[1:]) / np.array(steps[:-1]))
    assert np.all(orders >= 6.0), (errors, orders)


def test_the_graded_mesh_restores_the_order_of_the_period_map():
    # Errors of x(T) at 16, 32, 64 steps per half-stroke against 512: observed order >= 6
    # (a uniform mesh gives 1-4 on these loads).
    problem = HoverProblem(hawkmoth(hinge_height=10e-3), "small-angle")
    funs, switches = problem.graded_fields()
    pmap = PeriodMap(funs, [None, None], [None, None], (), 2.0, (0.5,), True, 10**9, switches)
    x, p = np.array([[0.02, -0.05, 0.3, 0.01, 0.0]]), problem.guess()[None, :]
    reference = pmap.flow(x, p, 512)[0]
    errors = [float(np.max(np.abs(pmap.flow(x, p, n)[0] - reference))) for n in (16, 32, 64)]
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(orders >= 6.0), (errors, orders)
    assert errors[-1] < 1e-10


def test_the_grading_maps_each_half_stroke_onto_itself():
    s = np.linspace(0.0, 1.0, 101)
    g = np.array([grading(v) for v in s])
    assert g[0] == 0.0 and abs(g[-1] - 1.0) < 1e-15 and np.all(np.diff(g) > 0)
    # g' is the derivative of g (central differences) and vanishes at the reversals.
    h = 1e-6
    for v in (0.1, 0.37, 0.5, 0.9):
        assert abs((grading(v + h) - grading(v - h)) / (2 * h) - grading_derivative(v)) < 1e-8
    assert grading_derivative(0.0) == 0.0 and grading_derivative(1.0) < 1e-60


def test_the_monarch_small_angle_orbit_converges():
    orbit = find_hover_orbit(preset("monarch"), aerodynamics="small-angle")
    _check(orbit)


def test_the_measured_monarch_two_trim_orbit_from_its_default_guess():
    # Newton's first step from the default guess (Phi 34.8 deg, phi_bar 0) asks for Phi = 98.7
    # deg, which the model refuses: the halved steps reach the orbit that the homotopy from the
    # paper's monarch finds (a second route)
    from flapping.studies.atlas import hover_by_homotopy

    insect = preset("monarch", geometry="source")
    options = {"aerodynamics": "small-angle", "trims": ("amplitude", "stroke_mean"),
               "backend": "fixed-step"}
    orbit = find_hover_orbit(insect, **options)
    _check(orbit)
    assert orbit.is_hover
    route = hover_by_homotopy(insect, preset("monarch"), **options).orbit
    assert abs(orbit.amplitude - route.amplitude) < 1e-10
    assert abs(orbit.stroke_mean - route.stroke_mean) < 1e-10
    np.testing.assert_allclose(orbit.x0, route.x0, rtol=0, atol=1e-10)


def test_mean_velocities_come_from_the_solves_mesh():
    # x_e(T) / T and -z(T) / T on the fixed-step mesh; the adaptive samples' means (a second
    # route) agree to their own accuracy, and the drift is what the hinge offset makes
    with pytest.warns(HoverDriftWarning):
        orbit = find_hover_orbit(hawkmoth().with_(hinge_offset=1e-3), aerodynamics="small-angle")
    v = orbit.mean_inertial_velocity
    assert orbit.mean_velocity is not None and not orbit.mean_velocity.flags.writeable
    u, w, _, theta = orbit.x[:, :-1]
    assert abs(v["forward"] - np.mean(u * np.cos(theta) + w * np.sin(theta))) < 1e-8
    assert abs(v["climb"] - np.mean(u * np.sin(theta) - w * np.cos(theta))) < 1e-8
    assert abs(v["climb"]) < 1e-12 < 0.1 < v["forward"]


def test_mean_velocities_use_the_problems_own_model():
    # a model given through HoverProblem.of_model (here 3 span nodes) is the field the mean
    # velocities integrate too: the climb is the solve's own z drift, not another model's
    from flapping.model.dynamics import LongitudinalDynamics

    model = LongitudinalDynamics(hawkmoth(), aerodynamics="exact", n_nodes=3)
    orbit = find_hover_orbit(HoverProblem.of_model(model), backend="fixed-step")
    assert abs(orbit.mean_inertial_velocity["climb"]) < 1e-12


def test_bad_options_are_value_errors_naming_them():
    insect = hawkmoth()
    with pytest.raises(ValueError, match="fixed_step_options"):
        find_hover_orbit(insect, aerodynamics="small-angle", fixed_step_options={"steps": 8})
    with pytest.raises(ValueError, match="error_tol"):
        find_hover_orbit(insect, aerodynamics="small-angle", fixed_step_options={"error_tol": 0})
    # an option of a path that does not run is not dropped in silence
    with pytest.warns(OptionWarning, match="n_steps=8 does not apply to the adaptive path"):
        find_hover_orbit(insect, backend="adaptive", fixed_step_options={"n_steps": 8})


def test_non_convergence_is_a_convergence_error_with_residual_and_iterations():
    with pytest.raises(ConvergenceError) as info:
        find_hover_orbit(hawkmoth(), aerodynamics="small-angle", backend="fixed-step",
                         fixed_step_options={"max_nfev": 2000})
    assert info.value.residual is not None or info.value.iterations is not None
    assert info.value.iterations is not None


def test_on_the_linear_loads_it_agrees_with_the_adaptive_path():
    # No kinks there: the graded mesh alone, against the adaptive reference (measured 3e-12).
    new = find_hover_orbit(hawkmoth(), backend="fixed-step")
    old = find_hover_orbit(hawkmoth(), backend="adaptive")
    _check(new)
    assert abs(new.amplitude - old.amplitude) < 1e-11
    assert np.max(np.abs(new.x0 - old.x0)) < 1e-10

"""Floquet stability of the hover orbit (flapping.hover.stability)."""

import dataclasses
import inspect
import math
import warnings

import numpy as np
import pytest

import flapping
from flapping.errors import HoverDriftWarning
from flapping.hover import ANALYSIS_ATOL, ANALYSIS_RTOL, find_hover_orbit
from flapping.hover.stability import (
    PERTURBATION_ATOL,
    hover_stability,
    mode_response,
    perturbation_growth,
    simulate_perturbation,
)


@pytest.fixture(scope="module")
def stability(orbit):
    return hover_stability(orbit)


def test_liouville(stability):
    # det M from the multipliers' product against exp(int trace J): both from integrations at
    # rtol 1e-12 over one period, so they agree to ~1e-11; 1e-9 is the requirement.
    assert stability.liouville_error < 1e-9


def test_multipliers_rk4_agree_with_dop853(orbit, stability):
    rk4 = hover_stability(orbit, method="RK4")
    # RK4 at 2^-10 of a period: global error ~ (h * |lambda|)^4 is far below 1e-6 here.
    np.testing.assert_allclose(np.sort_complex(rk4.multipliers), np.sort_complex(stability.multipliers),
                               rtol=1e-6, atol=1e-8)


def test_hover_is_unstable_and_nonlinear_growth_matches_multiplier(stability):
    assert not stability.is_stable
    growth = perturbation_growth(stability, epsilon=1e-8, n_periods=30)
    assert growth.growth_per_cycle == pytest.approx(abs(stability.multipliers[0]), rel=2e-3)


def test_averaged_jacobian_has_the_trace_of_liouville(stability):
    # trace of the averaged Jacobian times T is the integral of trace J: a consistency check of
    # the quadrature against the monodromy's determinant.
    T = stability.orbit.period
    assert math.exp(np.trace(stability.averaged_jacobian) * T) == pytest.approx(stability.det, rel=1e-9)


def test_hinge_offset_sign_mirrors_the_orbit(insect):
    # Reflecting the body fore-aft (x_h -> -x_h) must give the same amplitude and multipliers,
    # and the opposite horizontal drift.
    from flapping.hover.stability import hover_sensitivity

    # The rows report the drift (mean_forward_velocity, is_hover), so the sweep does not warn.
    with warnings.catch_warnings():
        warnings.simplefilter("error", HoverDriftWarning)
        ahead, behind = hover_sensitivity(insect, {"+": {"hinge_offset": 1e-3},
                                                   "-": {"hinge_offset": -1e-3}})
    assert not ahead.is_hover and not behind.is_hover
    assert ahead.amplitude_deg == pytest.approx(behind.amplitude_deg, rel=1e-9)
    np.testing.assert_allclose(np.abs(ahead.multipliers), np.abs(behind.multipliers), rtol=1e-8)
    assert ahead.mean_forward_velocity == pytest.approx(-behind.mean_forward_velocity, rel=1e-6)
    assert abs(ahead.mean_forward_velocity) > 1e-3


def test_mode_response_grows_by_its_multiplier_each_period(stability):
    from flapping.hover.stability import mode_response

    t, delta = mode_response(stability, n_periods=2, samples_per_period=8)
    mu = stability.multipliers[0].real
    np.testing.assert_allclose(delta[:, 8], mu * delta[:, 0], atol=1e-9)
    np.testing.assert_allclose(delta[:, 16], mu**2 * delta[:, 0], atol=1e-9)
    assert stability.averaged_eigenvalues.dtype == complex
    with pytest.raises(ValueError, match="n_periods"):
        mode_response(stability, n_periods=0)


def test_speed_pitch_cubic_root_is_an_averaged_eigenvalue(stability):
    from flapping.hover.stability import speed_pitch_cubic

    cubic = speed_pitch_cubic(stability.averaged_jacobian)
    # With x_h = 0 the averaged w-equation decouples, so the cubic's roots are three of the four
    # averaged eigenvalues.
    for root in cubic.roots:
        assert np.min(np.abs(stability.averaged_eigenvalues - root)) < 1e-9 * abs(root)
    assert cubic.coefficients[-1] < 0  # g Mu < 0: a positive real root
    flipped = speed_pitch_cubic(stability.averaged_jacobian, flip_mu=True)
    assert flipped.coefficients[-1] == pytest.approx(-cubic.coefficients[-1])


def test_simulated_perturbation_starts_on_the_orbit_plus_epsilon(orbit):
    from flapping.hover.stability import simulate_perturbation

    t, xp, xo = simulate_perturbation(orbit, 1e-4, n_periods=2, samples_per_period=8)
    assert np.linalg.norm(xp[:, 0] - xo[:, 0]) == pytest.approx(1e-4)
    np.testing.assert_allclose(xo[:, 8], orbit.x0, atol=1e-8)
    with pytest.raises(ValueError, match="epsilon"):
        simulate_perturbation(orbit, -1.0)


def test_perturbation_growth_validates_its_arguments(stability):
    with pytest.raises(ValueError, match="epsilon"):
        perturbation_growth(stability, epsilon=0.0)
    with pytest.raises(ValueError, match="epsilon"):
        perturbation_growth(stability, epsilon=10.0)
    with pytest.raises(ValueError, match="n_periods"):
        perturbation_growth(stability, epsilon=1e-8, n_periods=0)


def test_default_tolerances_are_the_ones_results_were_computed_with():
    # The analysis tolerances (rtol 1e-12; atol 1e-12, or 1e-14 for the perturbed simulations)
    # live in one place, the Adaptive backend's fields and PERTURBATION_ATOL; the signatures say
    # None, and a call without them is the call with them.
    assert (ANALYSIS_RTOL, ANALYSIS_ATOL, PERTURBATION_ATOL) == (1e-12, 1e-12, 1e-14)
    from flapping.hover import force_budget

    for function in (hover_stability, mode_response, perturbation_growth, simulate_perturbation,
                     force_budget):
        parameters = inspect.signature(function).parameters
        assert (parameters["rtol"].default, parameters["atol"].default) == (None, None), function
    adaptive = find_hover_orbit(flapping.hawkmoth(), backend="adaptive")
    explicit = hover_stability(adaptive, rtol=1e-12, atol=1e-12)
    assert np.array_equal(hover_stability(adaptive).monodromy, explicit.monodromy)
    assert force_budget(adaptive, 64) == force_budget(adaptive, 64, rtol=1e-12, atol=1e-12)


def test_tolerances_reach_the_integrations(stability):
    # A looser tolerance moves each result, by about its own size: the option is used.
    _, delta = mode_response(stability, n_periods=1, samples_per_period=8)
    _, loose = mode_response(stability, n_periods=1, samples_per_period=8, rtol=1e-7, atol=1e-9)
    error = np.abs(loose - delta).max()
    assert 0.0 < error < 1e-4
    t, xp, _ = simulate_perturbation(stability.orbit, 1e-6, n_periods=1, samples_per_period=4)
    _, xp_loose, _ = simulate_perturbation(stability.orbit, 1e-6, n_periods=1, samples_per_period=4,
                                           rtol=1e-7, atol=1e-9)
    assert 0.0 < np.abs(xp_loose - xp).max() < 1e-4 * np.abs(xp).max()
    loose_avg = hover_stability(stability.orbit, rtol=1e-7, atol=1e-9).averaged_jacobian
    assert 0.0 < np.abs(loose_avg - stability.averaged_jacobian).max() < 1e-3 * np.abs(
        stability.averaged_jacobian).max()


@pytest.mark.parametrize("call, name", [
    (lambda s: hover_stability(s.orbit, rtol=-1.0), "rtol"),
    (lambda s: hover_stability(s.orbit, atol=float("nan")), "atol"),
    (lambda s: hover_stability(s, n_average=8), "orbit"),
    (lambda s: hover_stability(s.orbit, n_average=0), "n_average"),
    (lambda s: mode_response(s, mode=4), "mode"),
    (lambda s: mode_response(s, samples_per_period=True), "samples_per_period"),
    (lambda s: perturbation_growth(s, epsilon="1e-8"), "epsilon"),
    (lambda s: perturbation_growth(s, epsilon=1e-8, direction=[0, 0, 0, 0]), "direction"),
    (lambda s: simulate_perturbation(s.orbit, 1e-6, samples_per_period=0), "samples_per_period"),
    (lambda s: simulate_perturbation(s.orbit, 1e-6, direction=[1.0, 2.0]), "direction"),
])
def test_bad_arguments_are_refused_by_name(stability, call, name):
    with pytest.raises(ValueError, match=name):
        call(stability)


def test_a_multiplier_below_the_smallest_float_is_handled():
    # Reproducer (issue 7): enormous rotational damping (the mu1 = mu2 = 1e6; here
    # 7.5e4, just enough, as the stiff system costs time in proportion) damps one mode beyond
    # 1e-323 in a period, so its multiplier is 0 in floating point, det M and exp(int tr J)
    # underflow to 0, and liouville_error divided 0 by 0 (ZeroDivisionError); its exponent was
    # -inf + nan i. Now: exponent -inf (real), the others finite, the Liouville check NaN
    # (impossible in floating point, not passed), the trace integral finite.
    orbit = find_hover_orbit(flapping.hawkmoth(mu1=7.5e4, mu2=7.5e4))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # the monodromy's own log(0)
        stab = hover_stability(orbit)
    assert stab.multipliers[-1] == 0.0
    assert stab.exponents[-1] == complex(-math.inf, 0.0)
    assert np.all(np.isfinite(stab.exponents[:-1]))
    assert not np.any(np.isnan(stab.exponents.imag))
    assert stab.det == 0.0 and stab.liouville_det == 0.0
    assert math.isfinite(stab.trace_integral) and stab.trace_integral < -700
    assert math.isnan(stab.liouville_error)


def test_liouville_error_of_values_beyond_the_float_range(stability):
    # det M and exp(int tr J) overflow (or underflow) while the multipliers and the trace
    # integral are finite: the relative error is formed from the logarithms instead, and equals
    # the one of the same quantities scaled into range.
    scale = 200.0  # every multiplier times e^200: det and exp(trace) times e^800, beyond 1e308
    mu = stability.multipliers * math.exp(scale)
    big = dataclasses.replace(stability, multipliers=mu, det=math.inf, liouville_det=math.inf,
                              trace_integral=stability.trace_integral + 4 * scale)
    assert big.liouville_error == pytest.approx(stability.liouville_error, rel=1e-2, abs=1e-12)
    tiny = dataclasses.replace(stability, multipliers=stability.multipliers * math.exp(-scale),
                               det=0.0, liouville_det=0.0,
                               trace_integral=stability.trace_integral - 4 * scale)
    assert tiny.liouville_error == pytest.approx(stability.liouville_error, rel=1e-2, abs=1e-12)
    # A real disagreement stays visible: exp(int tr J) off by a factor e.
    off = dataclasses.replace(big, trace_integral=big.trace_integral + 1.0)
    assert off.liouville_error == pytest.approx(1 - math.exp(-1.0), rel=1e-9)
    # Beyond any float: infinite, not an OverflowError.
    assert dataclasses.replace(big, trace_integral=big.trace_integral - 2000.0).liouville_error \
        == math.inf
    # And in range, the formula is the one it always was.
    assert stability.liouville_error == abs(stability.det - stability.liouville_det) / abs(
        stability.liouville_det)

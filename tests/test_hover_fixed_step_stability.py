"""hover_stability on the fixed-step path: the monodromy at n and 2n steps per half-stroke, with
the change as the error estimate of the multipliers (HoverStability.multiplier_error); under
"auto" a fixed-step orbit is analysed there too, the adaptive reference a keyword away."""

from __future__ import annotations

import math

import numpy as np
import pytest

from flapping import hawkmoth
from flapping.hover import find_hover_orbit, forced_orbit
from flapping.hover.stability import hover_stability


def _gap(a: np.ndarray, b: np.ndarray) -> float:
    """Largest distance from a multiplier of ``a`` to the nearest of ``b``."""
    return float(np.max(np.min(np.abs(np.asarray(a)[:, None] - np.asarray(b)[None, :]), axis=1)))


@pytest.fixture(scope="module")
def linear():
    return find_hover_orbit(hawkmoth(), backend="adaptive")


@pytest.fixture(scope="module")
def small_angle():
    return find_hover_orbit(hawkmoth(), aerodynamics="small-angle")


def test_the_estimate_bounds_the_difference_to_the_adaptive_analysis_on_the_linear_loads(linear):
    # The adaptive analysis of the linear loads is converged far below the fixed-step one's
    # error (rtol 1e-12 against 1e-13: ~1e-13 apart), so it is the exact answer here.
    fixed = hover_stability(linear, backend="fixed-step")
    adaptive = hover_stability(linear, backend="adaptive")
    assert 0.0 < fixed.multiplier_error < math.inf
    assert _gap(fixed.multipliers, adaptive.multipliers) <= fixed.multiplier_error
    assert fixed.multipliers.shape == (4,) and fixed.monodromy.shape == (4, 4)
    assert fixed.orbit is linear and fixed.det == pytest.approx(np.prod(fixed.multipliers).real)
    # Liouville: det M against exp(int trace J), an independent check of the monodromy
    assert fixed.liouville_error < 10 * fixed.multiplier_error
    np.testing.assert_array_equal(fixed.averaged_jacobian, adaptive.averaged_jacobian)


def test_a_forced_orbit_is_analysed_on_the_fixed_step_path_too():
    insect = hawkmoth()
    orbit = forced_orbit(insect, 0.9 * insect.stroke_amplitude)
    fixed = hover_stability(orbit, backend="fixed-step")
    adaptive = hover_stability(orbit, backend="adaptive")
    assert _gap(fixed.multipliers, adaptive.multipliers) <= fixed.multiplier_error


def test_the_adaptive_analysis_has_no_estimate_and_the_kernel_reports_its_own(linear):
    assert math.isnan(hover_stability(linear).multiplier_error)
    compiled = find_hover_orbit(hawkmoth())
    if compiled.kernel is None:
        pytest.skip("needs numba")
    stability = hover_stability(compiled)
    assert stability.multiplier_error == compiled.kernel.multiplier_error > 0.0


@pytest.mark.slow  # ~25 s on CI: the adaptive analysis of the blade-element loads at rtol 1e-13
def test_the_estimate_bounds_the_difference_to_a_tight_adaptive_analysis(small_angle):
    assert small_angle.backend == "fixed-step"
    fixed = hover_stability(small_angle, backend="fixed-step")
    tight = hover_stability(small_angle, backend="adaptive", rtol=1e-13, atol=1e-13)
    looser = hover_stability(small_angle, backend="adaptive", rtol=1e-12, atol=1e-12)
    assert 0.0 < fixed.multiplier_error < math.inf
    # The adaptive reference is not exact on these loads either: its multipliers move by
    # ~4e-10 from rtol 1e-12 to 1e-13 (measured), the size of the gap itself. The gap must lie
    # within the two estimates together.
    reference_error = _gap(looser.multipliers, tight.multipliers)
    assert _gap(fixed.multipliers, tight.multipliers) <= fixed.multiplier_error + reference_error
    # and the estimate is not vacuous: it claims more than the rtol-1e-11 analysis delivers.
    # (Measured: 5.3e-10 against that analysis's 2.7e-8 on one machine, 3.3e-9 on an AVX-512
    # one, where the n -> 2n change is 1.6e-9 and the actual gap 3.0e-10: the compiled loads'
    # rounding, hence the estimate, depends on the CPU's instruction set.)
    coarse = hover_stability(small_angle, backend="adaptive", rtol=1e-11, atol=1e-11)
    assert fixed.multiplier_error < _gap(coarse.multipliers, tight.multipliers)
    # "auto" analyses the fixed-step orbit on its own path, with its estimate
    default = hover_stability(small_angle)
    np.testing.assert_array_equal(default.monodromy, fixed.monodromy)
    assert default.multiplier_error == fixed.multiplier_error


def test_auto_analyses_a_fixed_step_orbit_on_its_path_unless_adaptive_options_are_given(
        small_angle):
    default = hover_stability(small_angle)
    assert 0.0 < default.multiplier_error < math.inf  # the fixed-step estimate
    rk4 = hover_stability(small_angle, method="RK4", rk4_steps=2048)
    assert math.isnan(rk4.multiplier_error)  # an adaptive-path option: the adaptive path


def _eager(stability, *, gauss_trace: bool):
    """The analysis with its averaged quantities computed up front, as before they were lazy."""
    from flapping.hover import ANALYSIS_ATOL, ANALYSIS_RTOL
    from flapping.hover.stability import _averaged_jacobian, _stability

    orbit = stability.orbit
    averaged = _averaged_jacobian(orbit, 64, ANALYSIS_RTOL, ANALYSIS_ATOL)
    if gauss_trace:  # the fixed-step path's int trace J dt: the averaged Jacobian's Gauss rule
        trace = float(np.trace(averaged)) * orbit.period
        liouville = math.exp(trace) if trace < 700 else math.inf
    else:
        trace, liouville = stability.trace_integral, stability.liouville_det
    return _stability(orbit, stability.monodromy, stability.multipliers, stability.det,
                      liouville, averaged, trace, stability.multiplier_error)


_AVERAGED = ("averaged_jacobian", "averaged_eigenvalues", "trace_integral", "liouville_det")


@pytest.mark.parametrize(("backend", "lazy"), [
    ("fixed-step", _AVERAGED), ("adaptive", _AVERAGED[:2])])
def test_the_averaged_quantities_are_computed_on_first_use_and_equal_the_eager_ones(
        linear, backend, lazy):
    import copy
    import dataclasses
    import pickle

    stability = hover_stability(linear, backend=backend)
    assert all(name not in vars(stability) for name in lazy)  # not computed by the analysis
    # first use through each way a result is read: a copy, a pickle, a replace, the object
    copies = [copy.deepcopy(hover_stability(linear, backend=backend)),
              pickle.loads(pickle.dumps(hover_stability(linear, backend=backend))),
              dataclasses.replace(hover_stability(linear, backend=backend),
                                  multiplier_error=stability.multiplier_error)]
    trace_first = stability.trace_integral  # the class default must not shadow the lazy value
    eager = _eager(stability, gauss_trace=backend == "fixed-step")
    assert trace_first == eager.trace_integral
    for result in [stability, *copies]:
        for name in _AVERAGED:
            np.testing.assert_array_equal(getattr(result, name), getattr(eager, name))
        assert result.liouville_error == eager.liouville_error
    assert not stability.averaged_jacobian.flags.writeable
    assert not stability.averaged_eigenvalues.flags.writeable
    with pytest.raises(dataclasses.FrozenInstanceError):
        stability.averaged_jacobian = eager.averaged_jacobian  # type: ignore[misc]
    assert stability.averaged_jacobian is stability.averaged_jacobian  # computed once


def test_a_lazy_field_needs_a_way_to_compute_it(linear):
    import dataclasses

    from flapping.hover.stability import _LAZY

    stability = hover_stability(linear, backend="adaptive")
    with pytest.raises(ValueError, match="averaged_jacobian"):
        dataclasses.replace(stability, averaged_jacobian=_LAZY, _averaged=None)

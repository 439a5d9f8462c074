"""Exceptions and warnings shared by the solvers (flapping.errors)."""

from types import SimpleNamespace

import numpy as np
import pytest

from flapping.errors import ConvergenceError, HoverDriftWarning, require_success


def test_require_success_passes_a_successful_result_through():
    result = SimpleNamespace(success=True, message="ok")
    assert require_success(result, "anything") is result


def test_require_success_raises_naming_what_failed_and_why():
    result = SimpleNamespace(success=False, message="Required step size is less than spacing")
    with pytest.raises(ConvergenceError, match="the averaged Jacobian.*step size") as error:
        require_success(result, "the averaged Jacobian")
    assert error.value.result is result


def test_convergence_error_carries_its_diagnostics():
    error = ConvergenceError("no orbit", x=[1, 2], residual=1e-3, iterations=7)
    assert "1.000e-03" in str(error) and "7 iterations" in str(error)
    assert error.x.dtype == np.float64 and error.iterations == 7


def test_hover_drift_warning_is_a_user_warning():
    # So that `-W error::UserWarning` and warnings filters on UserWarning catch it.
    assert issubclass(HoverDriftWarning, UserWarning)


# ---- where a failure happened, as attributes (issue 26, item 6) ---------------------------------


def test_a_convergence_error_without_a_place_has_none():
    error = ConvergenceError("no luck", residual=1.0, iterations=3)
    assert error.t is None and error.state is None and error.source is None


def test_a_convergence_error_keeps_where_the_integration_stopped_as_floats():
    state = [1, 2]
    error = ConvergenceError("blew up", t=1, state=state, source="state")
    assert error.t == 1.0 and isinstance(error.t, float) and error.source == "state"
    assert error.state.dtype == float and error.state.tolist() == [1.0, 2.0]
    state[0] = 99  # a copy: the caller's list may change
    assert error.state[0] == 1.0


def test_a_non_finite_error_is_a_valueerror_with_its_attributes():
    from flapping.errors import NonFiniteError

    error = NonFiniteError("`fun` returned NaN", source="fun", t=0.5, state=[1.0],
                           value=[np.nan])
    assert isinstance(error, ValueError)
    assert (error.source, error.t, error.state.tolist()) == ("fun", 0.5, [1.0])
    assert np.isnan(error.value).all()


def test_require_success_carries_where_a_flow_stopped():
    from flapping.periodic.integrate import flow

    failed = flow(lambda t, x: x**2, (0.0, 2.0), [1.0])  # blows up at t = 1
    with pytest.raises(ConvergenceError) as error:
        require_success(failed, "the test flow")
    assert error.value.source == "step budget"
    assert error.value.t == pytest.approx(1.0, abs=1e-3)
    assert error.value.state.shape == (1,)


def test_require_success_of_a_result_without_failure_has_no_place():
    with pytest.raises(ConvergenceError) as error:
        require_success(SimpleNamespace(success=False, message="no"), "x")
    assert error.value.t is None

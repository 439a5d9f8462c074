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

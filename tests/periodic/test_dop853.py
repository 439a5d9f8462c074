"""flapping.periodic._dop853.LeanDOP853: scipy's DOP853 with a leaner step must be the same
method, bit for bit: the same steps and the same values (the same floating-point operations in
the same order), forwards, backwards and in its dense output."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import DOP853, solve_ivp

from flapping.periodic._dop853 import LeanDOP853
from flapping.periodic.testproblems import lorenz, rossler


@pytest.mark.parametrize(("fun", "x0", "t1"), [
    (rossler, [0.0, -6.8, 0.03], 5.9),
    (lorenz, [-13.76, -19.58, 27.0], 1.56),
    (lambda t, x: np.array([x[1], -x[0] - 0.1 * x[1] + np.cos(t)]), [1.0, 0.0], 20.0),
])
@pytest.mark.parametrize("tol", [1e-6, 1e-10, 1e-13])
def test_same_steps_and_values_as_scipy_to_rounding(fun, x0, t1, tol):
    ref = solve_ivp(fun, (0.0, t1), x0, method=DOP853, rtol=tol, atol=tol)
    lean = solve_ivp(fun, (0.0, t1), x0, method=LeanDOP853, rtol=tol, atol=tol)
    assert lean.success and lean.t.size == ref.t.size and lean.nfev == ref.nfev
    np.testing.assert_array_equal(lean.t, ref.t)  # the same operations in the same order
    np.testing.assert_array_equal(lean.y, ref.y)


def test_backward_and_dense_output_as_scipy():
    ref = solve_ivp(rossler, (5.0, 0.0), [1.0, -6.0, 0.1], method=DOP853, rtol=1e-10,
                    atol=1e-10, dense_output=True)
    lean = solve_ivp(rossler, (5.0, 0.0), [1.0, -6.0, 0.1], method=LeanDOP853, rtol=1e-10,
                     atol=1e-10, dense_output=True)
    assert lean.t.size == ref.t.size
    np.testing.assert_array_equal(lean.sol(2.5), ref.sol(2.5))

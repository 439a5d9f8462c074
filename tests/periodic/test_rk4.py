"""The fixed-step RK4 solver (flapping.periodic.rk4) as a scipy OdeSolver."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from flapping.periodic.integrate import flow
from flapping.periodic.rk4 import RK4
from flapping.periodic.testproblems import lorenz

X_AB = np.array([-13.763610682134, -19.578751942452, 27.0])
T_AB = 1.5586522107162


def test_solve_ivp_with_rk4_is_the_flow_with_method_rk4():
    # Same scheme, same grid, same arithmetic: identical to the last bit.
    ours = flow(lorenz, (0.0, T_AB), X_AB, method="RK4", period=T_AB)
    scipy_way = solve_ivp(lorenz, (0.0, T_AB), X_AB, method=RK4, step=T_AB / 1024)
    np.testing.assert_array_equal(scipy_way.y, ours.x)
    assert scipy_way.nfev == ours.nfev == 4 * 1024


def test_rk4_global_error_falls_as_h_to_the_fourth():
    # x' = -x over [0, 1]: halving the step divides the error by 2^4 = 16 (15-17 allowed).
    errors = [abs(solve_ivp(lambda t, y: -y, (0.0, 1.0), [1.0], method=RK4, step=h).y[0, -1]
                  - math.exp(-1.0)) for h in (0.1, 0.05)]
    assert 15.0 < errors[0] / errors[1] < 17.0


def test_last_step_is_shortened_to_end_at_t_bound():
    res = solve_ivp(lambda t, y: -y, (0.0, 1.0), [1.0], method=RK4, step=0.3)
    np.testing.assert_allclose(res.t, [0.0, 0.3, 0.6, 0.9, 1.0], rtol=0, atol=1e-15)
    assert res.t[-1] == 1.0


def test_dense_output_interpolates_the_steps_to_fourth_order():
    # Cubic Hermite on each step: exact at the steps, error O(h^4) between (h = 0.01: < 1e-9).
    res = solve_ivp(lambda t, y: -y, (0.0, 1.0), [1.0], method=RK4, step=0.01, dense_output=True)
    np.testing.assert_array_equal(res.sol(res.t[3]), res.y[:, 3])
    t = np.linspace(0.0, 1.0, 333)
    np.testing.assert_allclose(res.sol(t)[0], np.exp(-t), rtol=0, atol=1e-9)


def test_backward_integration_returns_to_the_start():
    fwd = solve_ivp(lambda t, y: -y, (0.0, 1.0), [1.0], method=RK4, step=1e-3)
    back = solve_ivp(lambda t, y: -y, (1.0, 0.0), fwd.y[:, -1], method=RK4, step=1e-3)
    assert abs(back.y[0, -1] - 1.0) < 1e-12  # local errors h^5 ~ 1e-15 per step, 1000 steps


def test_tolerances_are_ignored_with_a_warning():
    with pytest.warns(UserWarning, match="ignores the options"):
        solve_ivp(lambda t, y: -y, (0.0, 1.0), [1.0], method=RK4, step=0.1, rtol=1e-3)


@pytest.mark.parametrize("step", [0.0, -0.1, math.nan, math.inf])
def test_bad_step_is_a_valueerror(step):
    with pytest.raises(ValueError, match="`step`"):
        solve_ivp(lambda t, y: -y, (0.0, 1.0), [1.0], method=RK4, step=step)

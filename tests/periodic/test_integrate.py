"""Segment-aware integration (flapping.periodic.integrate): each test states one property that must hold."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from flapping.periodic.integrate import flow, variational_flow
from flapping.periodic.testproblems import lorenz, lorenz_jac

# Viswanath's orbit AB of the Lorenz system (a convenient, bounded, chaotic test trajectory).
X_AB = np.array([-13.763610682134, -19.578751942452, 27.0])
T_AB = 1.5586522107162


def square_wave_rhs(a, T):
    """x' = -a x + s(t), s = +1 on [0, T/2], -1 on [T/2, T]: one callable per closed half-period.

    Each callable asserts that it is only ever evaluated on its own closed segment.
    """
    calls = {"first": [], "second": []}

    def first(t, x):
        phase = t / T - math.floor(t / T + 1e-12)
        assert phase <= 0.5 + 1e-12, f"segment-0 callable evaluated at phase {phase}"
        calls["first"].append(t)
        return -a * x + 1.0

    def second(t, x):
        phase = t / T - math.floor(t / T)
        assert phase >= 0.5 - 1e-12 or phase <= 1e-12, f"segment-1 callable evaluated at phase {phase}"
        calls["second"].append(t)
        return -a * x - 1.0

    return [first, second], calls


def square_wave_exact(t, x0, a, T):
    """Closed-form solution of the square-wave problem, piece by piece."""
    x, s = x0, 0.0
    while s < t - 1e-15:
        half = math.floor(2 * s / T + 1e-12)
        end = min(t, (half + 1) * T / 2)
        sign = 1.0 if half % 2 == 0 else -1.0
        x = sign / a + (x - sign / a) * math.exp(-a * (end - s))
        s = end
    return x


def test_linear_decay_matches_exponential():
    # x' = -x: DOP853 at rtol 1e-11 must give exp(-t) to ~1e-11 (10x margin for the global error).
    r = flow(lambda t, x: -x, (0.0, 3.0), [1.0], t_eval=[1.0, 2.0, 3.0])
    np.testing.assert_allclose(r.x[0], np.exp(-r.t), rtol=1e-10)
    assert r.success and r.nfev > 0


@pytest.mark.parametrize("method", ["DOP853", "RK4"])
def test_segment_callables_respected_at_segment_ends(method):
    # A right-hand side that jumps at t = T/2: each half-period's callable is used on its closed
    # segment only (asserted inside), and the solution matches the closed form. DOP853 to 1e-10;
    # RK4 at 2^-10 of T = 2 has local error h^5 ~ 1e-14 for this smooth-per-segment problem.
    a, T = 1.3, 2.0
    funs, calls = square_wave_rhs(a, T)
    r = flow(funs, (0.0, 2.5 * T), [0.2], breakpoints=(0.5,), period=T, method=method,
             t_eval=[0.5 * T, T, 1.75 * T, 2.5 * T])
    exact = [square_wave_exact(t, 0.2, a, T) for t in r.t]
    np.testing.assert_allclose(r.x[0], exact, rtol=0, atol=1e-10)
    assert any(abs(t - T / 2) < 1e-12 for t in calls["first"])  # used at its closing end
    assert any(abs(t - T / 2) < 1e-12 for t in calls["second"])  # and the other at its opening


def test_rk4_counts_four_evaluations_per_step():
    # Classical RK4: exactly 4 right-hand-side evaluations per step, 1024 steps per period.
    r = flow(lorenz, (0.0, T_AB), X_AB, method="RK4", period=T_AB)
    assert r.nfev == 4 * 1024
    assert len(r.t) == 1025


def test_rk4_is_fourth_order_and_agrees_with_dop853_to_its_accuracy():
    # RK4 at 2^-10 of the period differs from DOP853 (1e-12) by its own truncation error, which
    # Richardson extrapolation estimates as |x_h - x_{h/2}| * 16/15; halving h divides it by ~16.
    ref = flow(lorenz, (0.0, T_AB), X_AB, rtol=1e-13, atol=1e-13).x[:, -1]
    x1 = flow(lorenz, (0.0, T_AB), X_AB, method="RK4", period=T_AB, rk4_steps=1024).x[:, -1]
    x2 = flow(lorenz, (0.0, T_AB), X_AB, method="RK4", period=T_AB, rk4_steps=2048).x[:, -1]
    e1, e2 = np.linalg.norm(x1 - ref), np.linalg.norm(x2 - ref)
    assert 12.0 < e1 / e2 < 20.0  # order 4: ratio 16
    assert e1 <= 2.0 * (16.0 / 15.0) * np.linalg.norm(x1 - x2)


def test_rk4_breakpoint_off_grid_is_rejected():
    with pytest.raises(ValueError, match="step boundary"):
        flow(lambda t, x: -x, (0.0, 1.0), [1.0], method="RK4", period=1.0, breakpoints=(0.3,))


def test_dense_output_is_continuous_across_breakpoints():
    # The piecewise interpolant agrees with the restart states at the breakpoint (1e-10).
    a, T = 0.7, 1.0
    funs, _ = square_wave_rhs(a, T)
    r = flow(funs, (0.0, 2.0), [0.0], breakpoints=(0.5,), period=T, dense_output=True)
    for t in (0.5, 1.0, 1.5):
        assert abs(r.sol(t)[0] - square_wave_exact(t, 0.0, a, T)) < 1e-10
        assert abs(r.sol(t - 1e-9)[0] - r.sol(t + 1e-9)[0]) < 1e-8


def test_backward_integration_returns_to_start():
    fwd = flow(lorenz, (0.0, 0.5), X_AB)
    back = flow(lorenz, (0.5, 0.0), fwd.x[:, -1])
    np.testing.assert_allclose(back.x[:, -1], X_AB, atol=1e-8)  # Lorenz expands errors ~e^{0.9*0.5}


def test_variational_stm_matches_finite_differences_of_the_flow():
    # Phi(T) from the variational equations vs central differences of the flow (step 1e-5:
    # truncation ~ 1e-10 |x'''|, rounding ~ 1e-12 / 1e-5): agree to 1e-6 relative.
    var = variational_flow(lorenz, lorenz_jac, (0.0, T_AB), X_AB)
    h = 1e-5
    fd = np.empty((3, 3))
    for j in range(3):
        e = np.zeros(3)
        e[j] = h
        fd[:, j] = (flow(lorenz, (0.0, T_AB), X_AB + e).x[:, -1]
                    - flow(lorenz, (0.0, T_AB), X_AB - e).x[:, -1]) / (2 * h)
    np.testing.assert_allclose(var.stm_end, fd, rtol=1e-6, atol=1e-6 * np.abs(fd).max())


def test_fd_jacobian_variational_matches_analytic():
    # jac=None (central differences per evaluation, error ~eps^(2/3)) vs the analytic Jacobian.
    a = variational_flow(lorenz, lorenz_jac, (0.0, T_AB), X_AB)
    b = variational_flow(lorenz, None, (0.0, T_AB), X_AB)
    np.testing.assert_allclose(b.stm_end, a.stm_end, rtol=1e-7, atol=1e-7 * np.abs(a.stm_end).max())
    assert b.nfev > 6 * a.nfev / 2  # 2n = 6 extra evaluations per call are counted


def test_parameter_sensitivity_matches_finite_differences():
    # dx(T)/drho from the sensitivity equation vs central differences of the flow in rho.
    def f(t, x, p):
        return lorenz(t, x, 10.0, p[0], 8.0 / 3.0)

    def fj(t, x, p):
        return lorenz_jac(t, x, 10.0, p[0], 8.0 / 3.0)

    var = variational_flow(f, fj, (0.0, 0.5), X_AB, params=[28.0])
    h = 1e-5
    plus = flow(lambda t, x: f(t, x, [28.0 + h]), (0.0, 0.5), X_AB).x[:, -1]
    minus = flow(lambda t, x: f(t, x, [28.0 - h]), (0.0, 0.5), X_AB).x[:, -1]
    np.testing.assert_allclose(var.sensitivity_end[:, 0], (plus - minus) / (2 * h), rtol=1e-6)


def test_trace_integral_of_lorenz_is_exact():
    # trace J = -(sigma + 1 + beta) is constant on Lorenz: the quadrature state is exact.
    var = variational_flow(lorenz, lorenz_jac, (0.0, T_AB), X_AB, trace=True)
    assert abs(var.trace_integral[-1] + (10 + 1 + 8 / 3) * T_AB) < 1e-12 * 13.7 * T_AB


def test_wrong_output_shape_names_fun():
    with pytest.raises(ValueError, match="`fun` must return an array of shape"):
        flow(lambda t, x: np.zeros(2), (0.0, 1.0), [1.0, 2.0, 3.0])


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(breakpoints=(0.5,)), "give `period`"),
        (dict(breakpoints=(1.2,), period=1.0), r"open interval \(0, 1\)"),
        (dict(breakpoints=(0.6, 0.4), period=1.0), "strictly increasing"),
        (dict(method="Euler"), "`method` must be"),
        (dict(rtol=-1.0), "`rtol`"),
        (dict(rk4_steps=0, method="RK4"), "`rk4_steps`"),
    ],
)
def test_bad_arguments_raise_valueerror(kwargs, match):
    with pytest.raises(ValueError, match=match):
        flow(lambda t, x: -x, (0.0, 1.0), [1.0], **kwargs)


def test_sequence_length_must_match_segments():
    with pytest.raises(ValueError, match="one callable per segment"):
        flow([lambda t, x: -x], (0.0, 1.0), [1.0], breakpoints=(0.5,), period=1.0)


@settings(max_examples=40, deadline=None)
@given(st.one_of(st.floats(max_value=0.0), st.just(math.inf), st.just(math.nan)))
def test_non_positive_or_non_finite_period_is_rejected(period):
    with pytest.raises(ValueError, match=r"`period` must be a real number in \(0, inf\)"):
        flow(lambda t, x: -x, (0.0, 1.0), [1.0], period=period)


# ---- no hangs: non-finite values, step budgets -------------------------------------------------


def nan_rhs(t, x):
    return np.full(2, np.nan)


@pytest.mark.parametrize("integrate", [
    lambda: flow(nan_rhs, (0.0, 1.0), [1.0, 1.0]),
    lambda: variational_flow(nan_rhs, None, (0.0, 1.0), [1.0, 1.0]),
    lambda: flow(nan_rhs, (0.0, 1.0), [1.0, 1.0], method="RK4"),
])
def test_nan_from_fun_is_a_valueerror_naming_fun(integrate):
    # Used to hang: solve_ivp fed NaN shrinks its step forever.
    with pytest.raises(ValueError, match="`fun` returned a non-finite value at t = 0.0"):
        integrate()


def test_nan_from_jac_is_a_valueerror_naming_jac():
    with pytest.raises(ValueError, match="`jac` returned a non-finite value"):
        variational_flow(lambda t, x: -x, lambda t, x: np.full((2, 2), np.nan), (0.0, 1.0),
                         [1.0, 1.0])


def test_nan_midway_names_the_time_and_state():
    def f(t, x):
        return -x if t < 0.5 else np.full(1, np.inf)

    with pytest.raises(ValueError, match=r"`fun` returned a non-finite value at t = 0\.5"):
        flow(f, (0.0, 1.0), [1.0], method="RK4", rk4_steps=4)


def stiff(t, x):
    return -1e9 * (x - np.cos(t))


def test_stiff_problem_with_an_explicit_method_fails_early_with_advice():
    # DOP853 needs steps ~3e-9 (its stability limit) to cross 2 pi: ~1e9 steps, hours. The step
    # guard stops after 100 steps whose size cannot reach the end within max_steps.
    res = flow(stiff, (0.0, 2 * math.pi), [1.0])
    assert not res.success
    assert "method='Radau'" in res.message and "max_steps" in res.message
    assert res.nfev <= 12 * 150  # DOP853: 12 evaluations per step, ~100 steps taken


def test_stiff_problem_with_the_advised_method_succeeds():
    # Radau follows the slow manifold x = cos t (up to 1e-9 sin t).
    res = flow(stiff, (0.0, 2 * math.pi), [1.0], method="Radau", rtol=1e-8, atol=1e-10)
    assert res.success and abs(res.x[0, -1] - 1.0) < 1e-7


def test_step_budget_is_a_hard_limit():
    res = flow(lorenz, (0.0, 100.0), X_AB, max_steps=50)
    assert not res.success and "max_steps = 50" in res.message
    # 51 accepted steps of 12 evaluations, plus the rejected ones (fewer than the accepted here)
    assert res.nfev <= 2 * 12 * 51


def test_finite_time_blow_up_fails_instead_of_hanging():
    # x' = x^2, x(0) = 1 blows up at t = 1: the step shrinks towards the singularity.
    res = flow(lambda t, x: x**2, (0.0, 2.0), [1.0])
    assert not res.success and res.nfev < 12 * 10**4


@pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning",
                            "ignore:invalid value encountered:RuntimeWarning")
def test_overflowing_state_fails_with_a_message():
    # x' = 50 x from 1 over [0, 20]: the state leaves the float range (exp(1000)).
    res = flow(lambda t, x: 50.0 * x, (0.0, 20.0), [1.0], rtol=1e-6)
    assert not res.success and "non-finite" in res.message


# ---- conventions -------------------------------------------------------------------------------


def test_time_is_the_last_axis_of_every_result():
    def f(t, x, p):
        return lorenz(t, x, 10.0, p[0], 8.0 / 3.0)

    t_out = [0.1, 0.2, 0.3, 0.4]
    var = variational_flow(f, None, (0.0, 0.4), X_AB, params=[28.0], t_out=t_out, trace=True)
    assert var.x.shape == (3, 4) and var.stm.shape == (3, 3, 4)
    assert var.sensitivity.shape == (3, 1, 4) and var.trace_integral.shape == (4,)
    np.testing.assert_array_equal(var.x_end, var.x[:, -1])
    np.testing.assert_array_equal(var.stm_end, var.stm[:, :, -1])
    np.testing.assert_array_equal(var.sensitivity_end, var.sensitivity[:, :, -1])
    res = flow(lambda t, x, p: f(t, x, [28.0]), (0.0, 0.4), X_AB, t_eval=t_out, args=(None,))
    assert res.x.shape == (3, 4)
    np.testing.assert_allclose(res.x, var.x, rtol=1e-9)  # two integrations, rtol 1e-11


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(period=True), "`period`"),
        (dict(rtol="1e-8"), "`rtol`"),
        (dict(atol=False), "`atol`"),
        (dict(rk4_steps=1024.0, method="RK4"), "`rk4_steps`"),
        (dict(max_steps=0), "`max_steps`"),
        (dict(x0=[True]), "`x0`"),
        (dict(x0=["1.0"]), "`x0`"),
        (dict(t_span=("0", 1.0)), "`t_span"),
    ],
)
def test_bools_and_strings_are_refused(kwargs, match):
    call = dict(t_span=(0.0, 1.0), x0=[1.0])
    call.update(kwargs)
    with pytest.raises(ValueError, match=match):
        flow(lambda t, x: -x, call.pop("t_span"), call.pop("x0"), **call)


def test_numpy_scalars_are_converted_to_float64():
    res = flow(lambda t, x: -x, (np.float32(0.0), np.int64(1)), np.array([1.0], np.float32),
               rtol=np.float32(1e-10), period=np.float32(1.0))
    assert res.x.dtype == np.float64 and abs(res.x[0, -1] - math.exp(-1.0)) < 1e-9


def test_method_may_be_an_ode_solver_class():
    from flapping.periodic.rk4 import RK4

    a = flow(lorenz, (0.0, T_AB), X_AB, method="RK4", period=T_AB)
    b = flow(lorenz, (0.0, T_AB), X_AB, method=RK4, period=T_AB)
    np.testing.assert_array_equal(a.x, b.x)


# ---- t_eval: every bad value answered (issue 26, item 6) ----------------------------------------


@pytest.mark.parametrize(("t_span", "t_eval", "message"), [
    ((0.0, 1.0), [0.0, math.nan, 1.0], "`t_eval` must be finite"),  # was success=True, NaN rows
    ((0.0, 1.0), [0.0, math.inf], "`t_eval` must be finite"),
    ((0.0, 1.0), [0.5, 0.1, 1.0], r"`t_eval` must be sorted increasing.*0\.5 before 0\.1"),
    ((1.0, 0.0), [0.0, 0.5, 1.0], r"`t_eval` must be sorted decreasing \(t1 < t0\)"),
    ((0.0, 1.0), [0.0, 2.0], r"`t_eval` must lie within t_span \[0\.0, 1\.0\]"),
    ((0.0, 1.0), ["a", "b"], "`t_eval` must be an array of real numbers"),
    ((0.0, 1.0), [0.1 + 1j], "`t_eval` must be an array of real numbers"),
    ((0.0, 1.0), [[0.0, 1.0]], "`t_eval` must be a 1-D array"),
])
def test_a_bad_t_eval_is_a_valueerror_naming_it(t_span, t_eval, message):
    with pytest.raises(ValueError, match=message):
        flow(lambda t, x: -x, t_span, [1.0], t_eval=t_eval)


def test_t_eval_beyond_its_cap_is_refused_at_once():
    # 1e7 points used to run for minutes (one dense-output evaluation each, in Python)
    from flapping.periodic.settings import CAPS

    too_many = np.linspace(0.0, 1.0, CAPS["t_eval"] + 1)
    with pytest.raises(ValueError, match=rf"`t_eval` must have at most {CAPS['t_eval']} points"):
        flow(lambda t, x: -x, (0.0, 1.0), [1.0], t_eval=too_many)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(0.0, 1.0), min_size=1, max_size=20), st.integers(0, 19),
       st.sampled_from([math.nan, math.inf, -math.inf]))
def test_any_non_finite_time_in_t_eval_is_refused(times, where, bad):
    times = sorted(times)
    times.insert(where % (len(times) + 1), bad)
    with pytest.raises(ValueError, match="`t_eval` must be finite"):
        flow(lambda t, x: -x, (0.0, 1.0), [1.0], t_eval=times)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(0.0, 1.0), min_size=1, max_size=20), st.booleans())
def test_any_sorted_t_eval_within_the_span_is_answered_at_those_times(times, backwards):
    times = sorted(times, reverse=backwards)
    t_span = (1.0, 0.0) if backwards else (0.0, 1.0)
    res = flow(lambda t, x: -x, t_span, [1.0], t_eval=times, rtol=1e-10, atol=1e-12)
    assert res.success
    np.testing.assert_array_equal(res.t, times)
    x0 = 1.0  # x(t) = x(t0) exp(-(t - t0))
    np.testing.assert_allclose(res.x[0], x0 * np.exp(-(np.array(times) - t_span[0])),
                               rtol=1e-8)


# ---- blow-ups carry where they happened --------------------------------------------------------


def test_a_non_finite_value_of_fun_carries_time_state_and_source():
    from flapping.errors import NonFiniteError

    def f(t, x):
        return -x if t < 0.5 else np.full(1, np.nan)

    with pytest.raises(NonFiniteError) as error:
        flow(f, (0.0, 1.0), [1.0])
    exc = error.value
    assert isinstance(exc, ValueError)  # a bad value of the user's callable
    assert exc.source == "fun" and exc.t >= 0.5
    assert exc.state.shape == (1,) and 0.0 < exc.state[0] < 1.0  # x(t) = exp(-t), t ~ 0.5
    assert np.isnan(exc.value).all()


def test_a_field_that_overflows_with_its_solution_says_it_is_blowing_up():
    from flapping.errors import NonFiniteError

    # x' = x**4 from 1e10: a trial stage reaches a finite, huge state where x**4 overflows
    with pytest.raises(NonFiniteError, match="the solution is blowing up") as error:
        flow(lambda t, x: x * x * x * x, (0.0, 1.0), [1e10])
    assert error.value.source == "fun" and error.value.state[0] > 1e100


def test_a_failed_flow_says_where_it_stopped():
    # x' = x^2, x(0) = 1 blows up at t = 1: the step budget stops it there, and says so
    res = flow(lambda t, x: x**2, (0.0, 2.0), [1.0])
    assert not res.success
    assert res.failure is not None and res.failure.source == "step budget"
    assert res.failure.t == pytest.approx(1.0, abs=1e-3)
    assert res.failure.state[0] > 1e3


def test_a_successful_flow_has_no_failure():
    assert flow(lambda t, x: -x, (0.0, 1.0), [1.0]).failure is None


def test_a_failed_variational_flow_says_where_it_stopped_in_the_state_alone():
    var = variational_flow(lambda t, x: x**2, None, (0.0, 2.0), [1.0])
    assert not var.success
    assert var.failure is not None and var.failure.state.shape == (1,)  # not the matrices
    assert var.failure.t == pytest.approx(1.0, abs=1e-3)


def test_rk4_breakpoints_off_the_grid_name_breakpoints_and_rk4_steps():
    with pytest.raises(ValueError, match=r"`breakpoints` must fall on a step boundary.*"
                                         r"breakpoint 0\.3 does not: choose `rk4_steps`"):
        flow(lambda t, x: -x, (0.0, 1.0), [1.0], method="RK4", period=1.0, breakpoints=[0.3],
             rk4_steps=4)


def test_more_output_times_than_the_step_budget_are_refused_at_once():
    # each output time is a restart: 10**7 of them used to take a minute before failing
    with pytest.raises(ValueError, match=r"`t_out` has 100001 times, more than max_steps"):
        variational_flow(lambda t, x: -x, None, (0.0, 1.0), [1.0],
                         t_out=np.linspace(0.0, 1.0, 100_001))


@pytest.mark.parametrize(("t_out", "message"), [([math.nan], "`t_out` must be finite"),
                                                ([0.5, 2.0], r"within t_span .* got 2\.0"),
                                                ([[0.5]], "`t_out` must be a 1-D")])
def test_bad_output_times_are_named(t_out, message):
    with pytest.raises(ValueError, match=message):
        variational_flow(lambda t, x: -x, None, (0.0, 1.0), [1.0], t_out=t_out)


def test_output_times_in_any_order_are_reported_in_that_order():
    var = variational_flow(lambda t, x: -x, None, (0.0, 1.0), [1.0], t_out=[1.0, 0.5],
                           rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(var.x[0], np.exp([-1.0, -0.5]), rtol=1e-9)

"""A user's ODE mistakes answered at the first call (flapping.periodic._checks), at every entry.

Each mistake used to reach Python or NumPy internals (an IndexError from inside the field, a
TypeError about positional arguments, a string that "could not convert to float") or, worse,
nothing: a complex field lost its imaginary part with a warning and the solve "succeeded".
Every test states what the answer must name: the argument (``fun``, ``jac``, ``x0``, ``args``)
and what was expected against what came.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from flapping.periodic.continuation import continue_orbit
from flapping.periodic.fixedstep import (
    find_periodic_orbit_fixed_step,
    fixed_step_flow,
    fixed_step_monodromy,
)
from flapping.periodic.floquet import monodromy
from flapping.periodic.integrate import flow, variational_flow
from flapping.periodic.shooting import find_periodic_orbit
from flapping.periodic.testproblems import (
    forced_oscillator,
    forced_oscillator_orbit,
    lorenz,
    rossler,
)

X_AB = np.array([-13.763610682134, -19.578751942452, 27.0])
T_AB = 1.5586522107162
FORCING = (0.1, 1.0, 2.0, 1.0)  # zeta, omega0, omega, amplitude
X_FO = forced_oscillator_orbit(*FORCING)[0]
T_FO = 2 * math.pi / FORCING[2]


def unpacking_lorenz(t, u):
    """Lorenz written as users write it: unpacking the state (a 2-vector cannot unpack)."""
    x, y, z = u
    return np.array([10 * (y - x), x * (28 - z) - y, x * y - 8 / 3 * z])


def oscillator(t, x):
    return forced_oscillator(t, x, *FORCING)


# Each public entry point as fun -> call, with the right x0 and period for fun's system.
def _lorenz_entries(fun, x0=X_AB, jac=None, args=(), fixed=(2,)):
    return {
        "flow": lambda: flow(fun, (0.0, 0.1), x0, args=args),
        "variational_flow": lambda: variational_flow(fun, jac, (0.0, 0.1), x0, args=args),
        "find_periodic_orbit": lambda: find_periodic_orbit(fun, x0, T_AB, jac=jac, fixed=fixed,
                                                           args=args),
        "multiple shooting": lambda: find_periodic_orbit(fun, x0, T_AB, jac=jac, fixed=fixed,
                                                         segments=3, args=args),
        "monodromy": lambda: monodromy(fun, x0, T_AB, jac=jac, args=args),
    }


def _oscillator_entries(fun, x0=X_FO, jac=None, args=()):
    return {
        "find_periodic_orbit_fixed_step": lambda: find_periodic_orbit_fixed_step(
            fun, x0, T_FO, jac=jac, args=args),
        "fixed_step_monodromy": lambda: fixed_step_monodromy(fun, x0, T_FO, n_steps=16,
                                                             jac=jac, args=args),
        "fixed_step_flow": lambda: fixed_step_flow(fun, x0, T_FO, n_steps=16, args=args),
    }


def _entries(lorenz_fun, oscillator_fun, **kw):
    return [*_lorenz_entries(lorenz_fun, **kw).items(),
            *_oscillator_entries(oscillator_fun, **kw).items()]


def _ids(cases):
    return [name for name, _ in cases]


# ---- x0 of the wrong length: named as x0, not blamed on the field -----------------------------

X0_SHORT = [*_lorenz_entries(unpacking_lorenz, x0=X_AB[:2], fixed=()).items(),
            *_oscillator_entries(oscillator, x0=[0.1, 0.2, 0.3]).items()]


@pytest.mark.parametrize("call", [c for _, c in X0_SHORT], ids=_ids(X0_SHORT))
def test_x0_of_the_wrong_length_is_named(call):
    # Used to be "not enough values to unpack" (ValueError from inside the field) or "`fun`
    # must return an array of shape (3,), got shape (2,)": the field blamed for x0's length.
    with pytest.raises(ValueError, match=r"`x0`.*length") as error:
        call()
    assert "`fun`" in str(error.value)


def test_x0_too_short_for_an_indexing_field_is_named_too():
    # lorenz indexes x[2]: an IndexError inside the field becomes a ValueError naming x0
    with pytest.raises(ValueError, match=r"`fun` raised IndexError.*`x0` of length 2"):
        find_periodic_orbit(lorenz, X_AB[:2], T_AB)


def test_continuation_names_x0_of_the_wrong_length():
    with pytest.raises(ValueError, match=r"`x0` of length 2"):
        continue_orbit(lambda t, x, c: rossler(t, x, c=c), [4.6, 0.0], 5.7, 2.5, 2.6)


# ---- args that do not fit fun's signature: named as args, with the signature ------------------

ARGS = [*_lorenz_entries(lorenz, args=(1.0, 2.0, 3.0, 4.0)).items(),
        *_oscillator_entries(forced_oscillator, args=(1.0, 2.0)).items()]


@pytest.mark.parametrize("call", [c for _, c in ARGS], ids=_ids(ARGS))
def test_args_that_do_not_fit_the_signature_are_named(call):
    # Used to be Python's "lorenz() takes from 2 to 5 positional arguments but 6 were given"
    with pytest.raises(TypeError, match=r"`fun` cannot be called as fun\(t, x, \*args\) with "
                                        r"`args` = .*its signature is (lorenz|forced_osc)"):
        call()


def test_args_as_a_bare_number_is_named():
    with pytest.raises(ValueError, match=r"`args` must be a tuple.*got 5 \(int\)"):
        flow(lambda t, x, a: -a * x, (0.0, 1.0), [1.0], args=5)


def test_continuation_names_a_field_without_the_parameter():
    with pytest.raises(TypeError, match=r"`fun` cannot be called as fun\(t, x, p\) with the "
                                        r"parameter p0"):
        continue_orbit(lambda t, x: -x, [1.0, 0.0, 0.0], 5.7, 2.5, 2.6)


# ---- what fun returns: None, strings, complex, booleans, ragged lists, wrong shapes -----------

BAD_VALUES = {
    "None": (lambda t, x: None, TypeError, r"`fun` returned None .*missing `return`"),
    "a string": (lambda t, x: "abc", TypeError, r"`fun` returned 'abc' \(str\)"),
    "complex": (lambda t, x: -x + 1j * x, TypeError, r"`fun` returned complex values"),
    "booleans": (lambda t, x: x > 0, TypeError, r"`fun` returned .*\(dtype bool\)"),
    "ragged": (lambda t, x: [x, 1.0], TypeError, r"not an array of numbers"),
    "2-D": (lambda t, x: -x[:, None], ValueError, r"`fun` must return an array of shape"),
}


@pytest.mark.parametrize("name", list(BAD_VALUES))
@pytest.mark.parametrize("entry", ["flow", "variational_flow", "find_periodic_orbit",
                                   "monodromy", "find_periodic_orbit_fixed_step"])
def test_a_bad_value_of_fun_is_named_at_the_first_call(name, entry):
    # A complex field used to "succeed" (NumPy dropped the imaginary part with a warning);
    # a string reached float(): "could not convert string to float".
    fun, kind, message = BAD_VALUES[name]
    calls = dict(_entries(fun, fun))
    with pytest.raises(kind, match=message):
        calls[entry]()


def test_a_list_is_a_valid_value_of_fun():
    # the edge case that must keep working: solve_ivp accepts lists too
    res = flow(lambda t, x: [-v for v in x], (0.0, 1.0), [1.0, 2.0], rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(res.x_end, np.array([1.0, 2.0]) * math.exp(-1.0), rtol=1e-9)


# ---- jac of the wrong shape or type ------------------------------------------------------------

BAD_JACS = {
    "wrong shape": (lambda t, x: np.eye(2), ValueError,
                    r"`jac` must return an array of shape \(3, 3\), got shape \(2, 2\)"),
    "None": (lambda t, x: None, TypeError, r"`jac` returned None"),
    "complex": (lambda t, x: np.eye(3) * (1 + 1j), TypeError, r"`jac` returned complex"),
}


@pytest.mark.parametrize("name", list(BAD_JACS))
@pytest.mark.parametrize("entry", ["variational_flow", "find_periodic_orbit",
                                   "multiple shooting", "monodromy"])
def test_a_bad_jacobian_is_named_at_the_first_call(name, entry):
    # A complex jac used to end in "Levenberg-Marquardt stopped ... residual norm 2e-05": a
    # convergence failure for a typing mistake.
    jac, kind, message = BAD_JACS[name]
    with pytest.raises(kind, match=message) as error:
        _lorenz_entries(lorenz, jac=jac)[entry]()
    assert "`x0` has the wrong length" not in str(error.value)  # fun accepted x0: jac's fault


def test_continuation_names_a_bad_jacobian():
    with pytest.raises(TypeError, match=r"`jac` returned None at its first call, jac\(t, x, p\)"):
        continue_orbit(lambda t, x, c: rossler(t, x, c=c), [4.58, 0.0, 1.53], 5.749, 2.5, 2.6,
                       jac=lambda t, x, c: None)


def test_a_wrong_length_of_fun_hints_at_x0():
    with pytest.raises(ValueError, match=r"if the system has 2 states, `x0` has the wrong "
                                         r"length \(3, expected 2\)"):
        find_periodic_orbit_fixed_step(oscillator, [0.1, 0.2, 0.3], T_FO)


# ---- the user's own exceptions keep their type, with where they were raised --------------------


def test_an_exception_of_the_user_keeps_its_type_and_says_where():
    def broken(t, x):
        raise RuntimeError("user bug")

    with pytest.raises(RuntimeError, match="user bug") as error:
        find_periodic_orbit(broken, X_AB, T_AB)
    assert any("raised by `fun` at its first call" in note for note in error.value.__notes__)


# ---- the probe changes nothing of a good solve ---------------------------------------------------


@settings(max_examples=25, deadline=None)
@given(st.integers(min_value=1, max_value=6))
def test_any_number_of_args_that_fits_is_accepted(k):
    # a field taking k extra coefficients, given k of them: no false alarm from the check
    def fun(t, x, *coefficients):
        assert len(coefficients) == k
        return -sum(coefficients) * x

    res = flow(fun, (0.0, 1.0), [1.0], args=tuple(1.0 / k for _ in range(k)), rtol=1e-10,
               atol=1e-12)
    assert res.success
    assert res.x_end[0] == pytest.approx(math.exp(-1.0), rel=1e-9)


@settings(max_examples=25, deadline=None)
@given(st.integers(min_value=1, max_value=8), st.integers(min_value=1, max_value=8))
def test_a_field_of_another_size_than_x0_is_always_named(n_field, n_x0):
    # property: whenever the field's size differs from x0's, the answer names x0's length
    def fun(t, x):
        return np.zeros(n_field)

    if n_field == n_x0:
        assert flow(fun, (0.0, 1.0), np.ones(n_x0)).success
    else:
        with pytest.raises(ValueError, match=rf"`x0` has the wrong length \({n_x0}, "
                                             rf"expected {n_field}\)"):
            flow(fun, (0.0, 1.0), np.ones(n_x0))


# ---- round two of bad inputs: every segment, every flag, every user callable ----------------


def _half(sign):
    return lambda t, x: -x + sign


def test_a_later_segment_callable_is_checked_too_at_its_own_time():
    # the second half-period's callable returned complex values, and flow "succeeded" (NumPy
    # dropped the imaginary part); it is probed at the start of its own segment, t = 0.5
    with pytest.raises(TypeError, match=r"`fun` returned complex values .*t = 0\.5"):
        flow([_half(1.0), lambda t, x: -x + 1j], (0.0, 1.0), [1.0, 2.0], period=1.0,
             breakpoints=[0.5])


def test_a_later_segment_of_another_length_is_its_own_mistake_not_x0s():
    with pytest.raises(ValueError, match=r"got shape \(1,\) at its first call") as error:
        flow([_half(1.0), lambda t, x: -x[:1]], (0.0, 1.0), [1.0, 2.0], period=1.0,
             breakpoints=[0.5])
    assert "`x0` has the wrong length" not in str(error.value)  # segment 0 accepted x0


def test_each_segment_callable_is_probed_only_on_its_own_closed_segment():
    # the probe must keep the contract of the segmented integration (module notes)
    seen = {0: [], 1: []}

    def on(k, lo, hi):
        def f(t, x):
            phase = t - math.floor(t)
            at_period_end = k == 1 and phase < 1e-12  # phase 0 is phase 1 of the period before
            assert lo - 1e-12 <= phase <= hi + 1e-12 or at_period_end, (k, t)
            seen[k].append(t)
            return -x
        return f

    assert flow([on(0, 0.0, 0.5), on(1, 0.5, 1.0)], (0.25, 2.75), [1.0], period=1.0,
                breakpoints=[0.5]).success
    assert seen[0] and seen[1]


def test_trace_must_be_a_flag():
    # trace="no" used to be truthy and silently integrate the trace
    with pytest.raises(ValueError, match=r"`trace` must be True or False"):
        variational_flow(lorenz, None, (0.0, 0.1), X_AB, trace="no")


def test_an_error_inside_extra_residual_says_where():
    with pytest.raises(ZeroDivisionError) as error:
        find_periodic_orbit(lorenz, X_AB, T_AB, extra_residual=lambda x, T, p: 1 / 0)
    assert any("raised by `extra_residual`" in note for note in error.value.__notes__)


def _forced(t, x, p):
    return oscillator(t, x)


def test_a_period_function_that_raises_says_where():
    with pytest.raises(ZeroDivisionError) as error:
        continue_orbit(_forced, X_FO, lambda p: 1 / 0, 0.0, 0.1, autonomous=False)
    assert any("raised by `period` at its first call" in note for note in error.value.__notes__)


def test_a_period_function_returning_none_is_named():
    with pytest.raises(TypeError, match=r"`period\(p\)` must return a number .*got None"):
        continue_orbit(_forced, X_FO, lambda p: None, 0.0, 0.1, autonomous=False)

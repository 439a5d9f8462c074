"""flapping.periodic.fixedstep: Newton on a fixed-step DOP853 period map.

Each test states a property that can fail: the exact orbit and multipliers of the forced
oscillator, the formula's order 8 by refinement, the error estimate bounding the actual error,
breakpoints restarting the formula (order kept across a jump), free parameters with held
components, and the refusals (autonomous systems, bad arguments, the work cap).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from flapping.errors import ConvergenceError, DomainError
from flapping.periodic.fixedstep import FixedStepOrbit, find_periodic_orbit_fixed_step
from flapping.periodic.testproblems import (
    forced_oscillator,
    forced_oscillator_jac,
    forced_oscillator_orbit,
    lorenz,
)
from flapping.results import Status

ZETA, OMEGA0, OMEGA, AMPLITUDE = 0.1, 1.0, 2.0, 1.0
ARGS = (ZETA, OMEGA0, OMEGA, AMPLITUDE)
PERIOD = 2.0 * math.pi / OMEGA
X0, MULTIPLIERS = forced_oscillator_orbit(*ARGS)


def _square_wave(k):
    """x' = -x + 1 on the first half-period, -x - 1 on the second (a jump at T/2)."""
    s = 1.0 if k == 0 else -1.0
    return lambda t, x: np.array([-x[0] + s])


@pytest.mark.parametrize("jac", [None, forced_oscillator_jac], ids=["differenced", "variational"])
def test_forced_oscillator_orbit_and_multipliers_are_exact_to_the_tolerance(jac):
    orbit = find_periodic_orbit_fixed_step(forced_oscillator, [0.3, 0.1], PERIOD, args=ARGS,
                                           jac=jac)
    assert orbit.success and orbit.status is Status.SUCCESS and str(orbit.status) == "success"
    assert orbit.jacobian == ("finite-difference" if jac is None else "variational")
    # error_tol 1e-10 on the unknowns (Richardson, with a factor 2 of safety)
    np.testing.assert_allclose(orbit.x0, X0, rtol=0, atol=1e-10)
    assert np.all(np.abs(orbit.x0 - X0) <= orbit.x0_error)  # the estimate bounds the error
    # multipliers: the variational monodromy is exact to the formula's error; central
    # differences of the map add their rounding floor, eps / eps^(1/3) ~ 4e-11
    np.testing.assert_allclose(orbit.multipliers, MULTIPLIERS, rtol=0,
                               atol=1e-12 if jac is not None else 2e-10)
    assert orbit.residual_norm < 1e-14


def test_order_eight_by_refinement():
    errors = []
    for n in (4, 8, 16):
        orbit = find_periodic_orbit_fixed_step(forced_oscillator, X0, PERIOD, args=ARGS,
                                               jac=forced_oscillator_jac, n_steps=n,
                                               error_tol=1e-2)
        assert orbit.n_steps == n  # a loose tolerance keeps the first step count
        errors.append(float(np.max(np.abs(orbit.x0 - X0))))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all((orders > 7.5) & (orders < 8.5)), orders


def test_breakpoints_restart_the_formula_across_a_jump():
    # periodic solution x0 = -tanh(T/4) (closed form of the two exponential halves)
    T = 2.0
    exact = -math.tanh(T / 4.0)
    errors = []
    for n in (2, 4, 8):
        orbit = find_periodic_orbit_fixed_step([_square_wave(0), _square_wave(1)], [0.0], T,
                                               breakpoints=[0.5], n_steps=n, error_tol=1e-2)
        errors.append(abs(orbit.x0[0] - exact))
    assert errors[-1] < 1e-12
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(orders > 7.5), orders  # a step across the jump would be first order


def test_free_parameter_with_a_held_component():
    # hold y(0) at twice the orbit's value: the forcing amplitude must double (linearity)
    def fun(t, x, p):
        return forced_oscillator(t, x, ZETA, OMEGA0, OMEGA, p)

    orbit = find_periodic_orbit_fixed_step(fun, [2.0 * X0[0], 0.0], PERIOD, free_params=[0.5],
                                           fixed=[0])
    assert orbit.x0[0] == 2.0 * X0[0]
    assert orbit.params is not None and orbit.params_error is not None
    assert abs(orbit.params[0] - 2.0 * AMPLITUDE) < 1e-10
    np.testing.assert_allclose(orbit.x0, 2.0 * X0, rtol=0, atol=1e-10)
    assert orbit.sensitivity is not None and orbit.sensitivity.shape == (2, 1)


def test_result_arrays_are_read_only():
    orbit = find_periodic_orbit_fixed_step(forced_oscillator, X0, PERIOD, args=ARGS)
    assert isinstance(orbit, FixedStepOrbit)
    for a in (orbit.x0, orbit.monodromy, orbit.multipliers, orbit.residual, orbit.unknowns):
        assert not a.flags.writeable


def test_autonomous_systems_are_refused():
    with pytest.raises(ValueError, match="autonomous"):
        find_periodic_orbit_fixed_step(lorenz, [1.0, 1.0, 1.0], 1.5, autonomous=True)


@pytest.mark.parametrize("kwargs, name", [
    ({"n_steps": 1}, "n_steps"), ({"n_steps": 10**6}, "n_steps"),
    ({"error_tol": 1e-16}, "error_tol"), ({"multiplier_tol": 0.0}, "multiplier_tol"),
    ({"max_nfev": 10**9}, "max_nfev"), ({"fixed": [5]}, "fixed"), ({"tol": -1.0}, "tol"),
])
def test_bad_arguments_are_named(kwargs, name):
    with pytest.raises(ValueError, match=name):
        find_periodic_orbit_fixed_step(forced_oscillator, X0, PERIOD, args=ARGS, **kwargs)


def test_wrong_shape_of_fun_is_a_value_error():
    with pytest.raises(ValueError, match="shape"):
        find_periodic_orbit_fixed_step(lambda t, x: np.zeros(3), [0.0, 0.0], 1.0)


def test_the_work_cap_ends_the_solve_with_its_diagnostics():
    with pytest.raises(ConvergenceError, match="cap") as info:
        find_periodic_orbit_fixed_step(forced_oscillator, [0.3, 0.1], PERIOD, args=ARGS,
                                       max_nfev=500)
    assert info.value.result.status is Status.MAX_EVALUATIONS and not info.value.result.success


def test_a_diverging_iteration_fails_cleanly():
    # x' = x^2 + cos t blows up within a period from this guess
    with pytest.raises(ConvergenceError) as info:
        find_periodic_orbit_fixed_step(lambda t, x: np.array([x[0] ** 2 + 10.0]), [1e3], 10.0,
                                       n_steps=4)
    assert info.value.result.status in (Status.MAX_ITERATIONS, Status.LEFT_DOMAIN,
                                        Status.NON_FINITE)


def _kinked(t, x):
    """x' = cos t - x - |x|/2: continuous, with a kink where the orbit crosses x = 0."""
    return np.array([math.cos(t) - x[0] - 0.5 * abs(x[0])])


def test_switches_restore_the_order_across_a_state_dependent_kink():
    def crossing(t, x):
        return x[0]

    reference = find_periodic_orbit_fixed_step(_kinked, [0.0], 2.0 * math.pi, switches=[crossing],
                                               n_steps=256, error_tol=1e-2).x0[0]

    def error(n, switches):
        orbit = find_periodic_orbit_fixed_step(_kinked, [0.0], 2.0 * math.pi, n_steps=n,
                                               switches=switches, error_tol=1e-2)
        return abs(orbit.x0[0] - reference)

    marked = [error(n, [crossing]) for n in (8, 16)]
    unmarked = [error(n, []) for n in (8, 16)]
    assert marked[1] < 1e-9 and math.log2(marked[0] / marked[1]) > 6.0  # measured 6.8
    assert unmarked[1] > 1e-5  # the kink left unmarked: first order (measured 4e-5)
    orbit = find_periodic_orbit_fixed_step(_kinked, [0.0], 2.0 * math.pi, switches=[crossing],
                                           jac=lambda t, x: np.array([[-1.0]]))
    assert orbit.jacobian == "finite-difference"  # jac is one-sided on the switch: not used


@pytest.mark.xfail(strict=True, reason="known limitation: across a split kink the observed order "
                   "is 5-7, not 8, so the order-8 Richardson estimate is low (1.6e-10 actual at "
                   "error_tol 1e-10); needs an observed-order estimate (three step counts)")
def test_the_error_estimate_holds_with_switches():
    def crossing(t, x):
        return x[0]

    reference = find_periodic_orbit_fixed_step(_kinked, [0.0], 2.0 * math.pi, switches=[crossing],
                                               n_steps=256, error_tol=1e-2).x0[0]
    orbit = find_periodic_orbit_fixed_step(_kinked, [0.0], 2.0 * math.pi, switches=[crossing])
    assert abs(orbit.x0[0] - reference) <= orbit.x0_error[0]


def test_fixed_step_monodromy_is_the_solves_derivative_and_converges_at_order_8():
    from flapping.periodic.fixedstep import fixed_step_monodromy

    orbit = find_periodic_orbit_fixed_step(forced_oscillator, [0.3, 0.1], PERIOD, args=ARGS,
                                           jac=forced_oscillator_jac)
    same = fixed_step_monodromy(forced_oscillator, orbit.x0, PERIOD, n_steps=orbit.n_steps,
                                args=ARGS, jac=forced_oscillator_jac)
    np.testing.assert_array_equal(same, orbit.monodromy)
    assert not same.flags.writeable
    # the forced oscillator's monodromy is exp(A T): the multipliers' error falls as n^-8
    errors = []
    for n in (4, 8):
        M = fixed_step_monodromy(forced_oscillator, X0, PERIOD, n_steps=n, args=ARGS,
                                 jac=forced_oscillator_jac)
        mu = np.linalg.eigvals(M)
        errors.append(max(np.min(np.abs(mu[:, None] - MULTIPLIERS[None, :]), axis=1)))
    assert 2.0 ** 8 / 2 < errors[0] / errors[1] < 2.0 ** 8 * 2
    with pytest.raises(ValueError, match="n_steps"):
        fixed_step_monodromy(forced_oscillator, X0, PERIOD, n_steps=1, args=ARGS)


def _exp_forced(p_max):
    """The forced oscillator with amplitude exp(p), a model defined for p <= p_max only."""
    def fun(t, x, p):
        if p[0] > p_max:
            raise DomainError(f"p = {p[0]} > {p_max}")
        return forced_oscillator(t, x, ZETA, OMEGA0, OMEGA, math.exp(p[0]))
    return fun


def test_a_step_the_model_refuses_is_halved():
    # holding y(0) at twice the orbit's value needs exp(p) = 2; Newton from p = -3 steps to
    # p ~ 36, which this model refuses: the halved step (p ~ 1.9) is accepted, then it converges
    orbit = find_periodic_orbit_fixed_step(_exp_forced(5.0), [2.0 * X0[0], 0.0], PERIOD,
                                           free_params=[-3.0], fixed=[0])
    assert orbit.params is not None and abs(orbit.params[0] - math.log(2.0)) < 1e-10
    np.testing.assert_allclose(orbit.x0, 2.0 * X0, rtol=0, atol=1e-10)


def test_a_refusal_that_halving_cannot_clear_ends_the_solve():
    with pytest.raises(DomainError, match="p = "):
        find_periodic_orbit_fixed_step(_exp_forced(-2.9999), [2.0 * X0[0], 0.0], PERIOD,
                                       free_params=[-3.0], fixed=[0])


def test_the_flow_is_the_solves_map():
    from flapping.periodic.fixedstep import fixed_step_flow

    orbit = find_periodic_orbit_fixed_step(forced_oscillator, [0.3, 0.1], PERIOD, args=ARGS)
    end = fixed_step_flow(forced_oscillator, orbit.x0, PERIOD, n_steps=orbit.n_steps,
                          args=ARGS)
    np.testing.assert_allclose(end, orbit.x0, rtol=0, atol=1e-12)  # periodic on its own mesh
    assert not end.flags.writeable
    with pytest.raises(ValueError, match="n_steps"):
        fixed_step_flow(forced_oscillator, orbit.x0, PERIOD, n_steps=1, args=ARGS)


# --------------------------------------------------------------------------- a compiled map
def _forced(t, x, p):
    """x' = -x + p cos t: the periodic orbit is x = p (cos t + sin t) / 2, so x(0) = p / 2."""
    return np.array([-x[0] + p[0] * math.cos(t)])


def _kink(t, x, p):
    return x[0]


class _Offer:
    """A CompiledMap that integrates by the Python map itself and counts its calls (the
    protocol is what is tested, not a compiler)."""

    def __init__(self, funs, switches):
        from flapping.periodic._fixedmap import PeriodMap

        self.funs, self.switches, self.calls = tuple(funs), tuple(map(tuple, switches)), 0
        self.reference = PeriodMap(self.funs, (None,), (None,), (), 2.0 * math.pi, (), True,
                                   10**8, self.switches)
        self.reference.compiled = None  # it would find this offer on the callables

    def flow(self, X, P, n, nodes):
        self.calls += 1
        before = self.reference.nfev
        return self.reference.flow(X, P, n), self.reference.nfev - before


def _offered(switches=((_kink,),)):
    from flapping.periodic._fixedmap import COMPILED_MAP

    def fun(t, x, p):
        return _forced(t, x, p)

    offer = _Offer([fun], switches)
    setattr(fun, COMPILED_MAP, offer)
    return fun, offer


def test_an_offered_compiled_map_integrates_the_solve():
    fun, offer = _offered()
    orbit = find_periodic_orbit_fixed_step(fun, [0.25], 2.0 * math.pi, free_params=[0.0],
                                           fixed=[0], switches=[_kink])
    assert offer.calls > 0 and orbit.nfev == offer.reference.nfev  # every evaluation by it
    assert orbit.params is not None and abs(orbit.params[0] - 0.5) < 1e-10


def test_an_offer_for_other_switches_or_conventions_is_not_used():
    from flapping.periodic._fixedmap import PeriodMap

    fun, offer = _offered()
    # another switching function than the offer locates: the Python map runs
    find_periodic_orbit_fixed_step(fun, [0.25], 2.0 * math.pi, free_params=[0.0], fixed=[0],
                                   switches=[lambda t, x, p: x[0]])
    assert offer.calls == 0
    # extra arguments, or no parameters: not the offer's calling convention
    for args, has_params in (((1.0,), True), ((), False)):
        pmap = PeriodMap((fun,), (None,), (None,), args, 1.0, (), has_params, 10, ((_kink,),))
        assert pmap.compiled is None
    assert PeriodMap((fun,), (None,), (None,), (), 1.0, (), True, 10,
                     ((_kink,),)).compiled is offer


def test_the_work_cap_counts_an_offered_maps_evaluations():
    fun, offer = _offered()
    with pytest.raises(ConvergenceError, match="cap") as info:
        find_periodic_orbit_fixed_step(fun, [0.25], 2.0 * math.pi, free_params=[0.0],
                                       fixed=[0], switches=[_kink], max_nfev=2000)
    assert offer.calls > 0 and info.value.result.status is Status.MAX_EVALUATIONS


# ---- tolerance ceilings at the entry (issue 26, item 6) -----------------------------------------


@pytest.mark.parametrize(("name", "value", "message"), [
    ("error_tol", 1e6, r"`error_tol` must be a real number in \[1e-13, 0\.01\]"),
    ("multiplier_tol", 1e6, r"`multiplier_tol` must be a real number in \[1e-13, 0\.01\]"),
    ("tol", 1e6, r"`tol` must be at most 1e-06 \* max\(1, \|x0\|\)"),
])
def test_a_tolerance_too_loose_to_mean_anything_is_refused(name, value, message):
    # each used to return success=True ("converged") at 16 steps, whatever the accuracy
    with pytest.raises(ValueError, match=message):
        find_periodic_orbit_fixed_step(forced_oscillator, X0, PERIOD, args=ARGS,
                                       **{name: value})


def test_the_loosest_error_tol_is_accepted():
    orbit = find_periodic_orbit_fixed_step(forced_oscillator, [0.3, 0.1], PERIOD, args=ARGS,
                                           error_tol=1e-2)
    assert orbit.success

"""The primer's toy systems: the multiplier of x' = a(t) x, Kapitza's pendulum, averaging error."""

import math

import numpy as np

from flapping.periodic.floquet import monodromy
from flapping.periodic.integrate import flow
from flapping_book.primer import (
    KapitzaPendulum,
    averaging_error,
    floquet_versus_averaging,
    scalar_system,
)


def test_scalar_multiplier_is_exp_of_the_integrated_rate():
    a0, a1, T = 0.3, 4.0, 0.5
    fun, exact = scalar_system(a0, a1, T)
    mon = monodromy(fun, [1.0], T)
    assert math.isclose(mon.multipliers[0].real, math.exp(a0 * T), rel_tol=1e-9)  # rtol 1e-12 run
    path = flow(fun, (0.0, 3 * T), [1.0], t_eval=np.linspace(0, 3 * T, 7))
    assert np.allclose(path.x[0], exact(path.t, 1.0), rtol=1e-8)


def test_kapitza_upright_stable_by_floquet_unstable_by_first_order_averaging():
    pendulum = KapitzaPendulum()
    assert pendulum.kapitza_number > 1
    result = floquet_versus_averaging(pendulum)
    assert result.floquet_stable and not result.averaging_stable
    # Liouville: det = exp(-c T) exactly for this system (trace A = -c).
    assert math.isclose(result.monodromy_det, math.exp(-pendulum.damping_per_s * pendulum.period),
                        rel_tol=1e-9)


def test_kapitza_below_the_criterion_falls():
    pendulum = KapitzaPendulum(amplitude_m=0.01)
    assert pendulum.kapitza_number < 1
    assert not floquet_versus_averaging(pendulum).floquet_stable


def test_averaging_error_shrinks_like_the_period_squared():
    gaps = averaging_error([[-1.0, 1.0], [0.0, -2.0]], [[0.0, 3.0], [-3.0, 0.0]],
                           [0.4, 0.2, 0.1])
    ratios = gaps[:-1] / gaps[1:]
    assert np.all(ratios > 3.5) and np.all(ratios < 4.5)   # second order: 4 per halving


def test_floquet_factorisation_periodic_factor_and_exponents():
    from flapping_book.primer import floquet_factorisation

    pendulum = KapitzaPendulum()
    fact = floquet_factorisation(pendulum.rhs, [0.0, 0.0], pendulum.period,
                                 jac=pendulum.jacobian, periods=2, samples_per_period=8)
    assert np.allclose(fact.P[..., 0], np.eye(2))
    assert fact.periodicity_error() < 1e-8                   # P(t + T) = P(t)
    mu = floquet_versus_averaging(pendulum).multipliers
    expected = np.log(mu) / pendulum.period
    for part in (np.real, np.imag):   # the pair in either order (equal real parts)
        assert np.allclose(np.sort(part(fact.exponents())), np.sort(part(expected)), atol=1e-8)
    # Psi(t) = P(t) exp(B t) at every sample, by construction and at t = T by the logarithm
    import scipy.linalg
    k = 8
    assert np.allclose(fact.stm[..., k], fact.P[..., k] @ scipy.linalg.expm(fact.B * fact.times[k]))


def test_read_multiplier_positive_negative_complex():
    import pytest

    from flapping_book.primer import read_multiplier

    T = 0.5
    pos = read_multiplier(math.e, T)
    assert pos.kind == "positive" and pos.turn_per_period == 0 and pos.periods_per_turn == math.inf
    assert math.isclose(pos.exponent.real, 1 / T) and pos.exponent.imag == 0
    neg = read_multiplier(-2.0, T)
    assert neg.kind == "negative" and neg.turn_per_period == 0.5 and neg.periods_per_turn == 2
    assert math.isclose(neg.exponent.real, math.log(2) / T)
    assert math.isclose(neg.exponent.imag, math.pi / T)
    # every branch is a logarithm of the same multiplier
    assert np.allclose(np.exp(neg.branches(T) * T), -2.0)
    rot = read_multiplier(0.5 * np.exp(1j * math.pi / 3), T)
    assert rot.kind == "complex" and math.isclose(rot.turn_per_period, 1 / 6)
    assert math.isclose(rot.growth_per_period, math.log(0.5))
    assert read_multiplier(complex(-3.0, 1e-15), T).kind == "negative"   # round-off ignored
    with pytest.raises(ValueError):
        read_multiplier(0.0, T)


def test_linearisation_error_shrinks_with_the_disturbance():
    from flapping_book.primer import linearisation_error

    pendulum = KapitzaPendulum()
    errors = linearisation_error(pendulum.rhs, [0.0, 0.0], pendulum.period, [1.0, 0.0],
                                 [0.1, 0.05, 0.025], jac=pendulum.jacobian)
    ratios = errors[:-1] / errors[1:]
    assert np.all(ratios > 3.5) and np.all(ratios < 4.5)   # sin x: cubic, error/eps ~ eps^2
    # a linear system is its own linearisation
    fun, _ = scalar_system(0.2, 1.0, 1.0)
    assert np.all(linearisation_error(fun, [0.0], 1.0, [1.0], [1.0, 0.1]) < 1e-9)

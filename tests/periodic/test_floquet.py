"""Floquet analysis (flapping.periodic.floquet): Liouville, the trivial multiplier, independent methods."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from flapping.errors import ConvergenceError
from flapping.periodic.floquet import (
    FloquetAccuracyWarning,
    floquet_exponents,
    floquet_multipliers,
    monodromy,
    nontrivial_multipliers,
    trivial_multiplier,
)
from flapping.periodic.integrate import flow
from flapping.periodic.shooting import find_periodic_orbit
from flapping.periodic.testproblems import lorenz, lorenz_jac, rossler, rossler_jac

SIGMA, BETA = 10.0, 8.0 / 3.0


@pytest.fixture(scope="module")
def orbit_ab():
    return find_periodic_orbit(lorenz, [-13.8, -19.6, 27.0], 1.56, fixed=[2], jac=lorenz_jac)


@pytest.fixture(scope="module")
def mon_ab(orbit_ab):
    return monodromy(lorenz, orbit_ab.x0, orbit_ab.period, jac=lorenz_jac)


def test_lorenz_multipliers_trivial_expanding_contracting(mon_ab):
    # One multiplier is 1 (flow direction): within 1e-8 (integration at 1e-12 over an orbit whose
    # largest multiplier is ~5: errors ~1e-11). One expands, one contracts.
    mu = mon_ab.multipliers
    i = trivial_multiplier(mon_ab)
    assert abs(mu[i] - 1.0) <= 1e-8
    others = np.abs(nontrivial_multipliers(mon_ab))
    assert others[0] > 1.0 > others[1] > 0.0
    assert np.all(np.abs(mu.imag) == 0.0)


def test_lorenz_det_matches_liouville(orbit_ab, mon_ab):
    # det M (product of well-conditioned factors) vs exp(int trace J) = exp(-(sigma+1+beta) T):
    # 1e-9 relative (each factor keeps ~1e-12 / cond; det M ~ 5.6e-10 is tiny, so a plain
    # det(eig) would fail this by orders of magnitude).
    exact = math.exp(-(SIGMA + 1.0 + BETA) * orbit_ab.period)
    assert abs(mon_ab.liouville_det / exact - 1.0) <= 1e-12  # the trace is constant: exact
    assert mon_ab.liouville_error <= 1e-9
    assert abs(mon_ab.det / exact - 1.0) <= 1e-9
    # the small multiplier, from the periodic QR, is consistent with det / (mu_e * 1)
    mu = mon_ab.multipliers.real
    assert abs(mu[0] * mu[1] * mu[2] / exact - 1.0) <= 1e-9


def test_variational_monodromy_matches_finite_differences_of_the_flow(orbit_ab, mon_ab):
    # Central differences of the one-period flow (h = 1e-6; truncation ~h^2 |d3x|, rounding
    # ~1e-12/h): the large entries agree to ~1e-6 relative.
    h = 1e-6
    x0, T = orbit_ab.x0, orbit_ab.period
    fd = np.empty((3, 3))
    for j in range(3):
        e = np.zeros(3)
        e[j] = h
        xp = flow(lorenz, (0.0, T), x0 + e, rtol=1e-12, atol=1e-12).x[:, -1]
        xm = flow(lorenz, (0.0, T), x0 - e, rtol=1e-12, atol=1e-12).x[:, -1]
        fd[:, j] = (xp - xm) / (2 * h)
    np.testing.assert_allclose(mon_ab.matrix, fd, atol=1e-5 * np.abs(fd).max())


def test_finite_difference_jacobian_gives_the_same_multipliers(orbit_ab, mon_ab):
    # jac=None: central differences inside the variational equations (error ~eps^(2/3)).
    fd = monodromy(lorenz, orbit_ab.x0, orbit_ab.period)
    np.testing.assert_allclose(fd.multipliers[:2], mon_ab.multipliers[:2], rtol=1e-8)
    assert fd.liouville_error <= 1e-9


def test_roessler_expanding_multiplier_matches_chaosbook():
    # ChaosBook: the period-1 orbit (a = b = 0.2, c = 5.7) has Lambda_e = -2.40395 (6 digits).
    orbit = find_periodic_orbit(rossler, [0.0, -6.8, 0.03], 5.9, fixed=[0], jac=rossler_jac)
    mon = monodromy(rossler, orbit.x0, orbit.period, jac=rossler_jac)
    assert abs(mon.multipliers[0].real + 2.40395) <= 5e-6
    assert abs(mon.multipliers[trivial_multiplier(mon)] - 1.0) <= 1e-8
    assert mon.liouville_error <= 1e-9


def test_segmented_monodromy_of_jumping_rhs():
    # x' = -a x + s(t) with s jumping at T/2: M = exp(-a T) exactly, whatever the forcing.
    # Relative 1e-10: the finite-difference Jacobian (jac=None) has relative error ~eps^(2/3)
    # ~ 4e-11 and DOP853 at rtol 1e-12 accumulates ~1e-11 over the period's steps.
    # Started on the periodic solution, x0 = -c / (1 + E) with E = exp(-a T / 2) and
    # c = (1 - E) / a (from x(T) = x0), so that no ClosureWarning is due.
    a, T = 1.3, 2.0
    funs = [lambda t, x: -a * x + 1.0, lambda t, x: -a * x - 1.0]
    E = math.exp(-a * T / 2)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mon = monodromy(funs, [-(1 - E) / a / (1 + E)], T, breakpoints=(0.5,))
    assert abs(mon.multipliers[0] / math.exp(-a * T) - 1.0) <= 1e-10
    assert mon.liouville_error <= 1e-10


def test_rk4_monodromy_agrees_to_rk4_accuracy(orbit_ab, mon_ab):
    # RK4 at 2^-10 of the period: multipliers agree to its truncation error (~1e-7 here).
    rk4 = monodromy(lorenz, orbit_ab.x0, orbit_ab.period, jac=lorenz_jac, method="RK4")
    np.testing.assert_allclose(rk4.multipliers[:2], mon_ab.multipliers[:2], rtol=1e-6)


def test_tiny_multiplier_from_eig_warns():
    with pytest.warns(FloquetAccuracyWarning):
        floquet_multipliers(np.diag([2.0, 1e-20]))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mu = floquet_multipliers(np.diag([0.5, 2.0, -1.0]))
    np.testing.assert_array_equal(mu, [2.0, -1.0, 0.5])  # sorted by modulus, descending


def test_exponents_are_log_over_period():
    mu = np.array([math.e**2, -1.0])
    ex = floquet_exponents(mu, 2.0)
    assert ex[0] == pytest.approx(1.0)
    assert ex[1] == pytest.approx(1j * math.pi / 2.0)
    with pytest.raises(ValueError, match="`period`"):
        floquet_exponents(mu, 0.0)


def test_bad_arguments():
    with pytest.raises(ValueError, match="`matrix`"):
        floquet_multipliers(np.ones((2, 3)))
    with pytest.raises(ValueError, match="`n_sub`"):
        monodromy(lorenz, [1.0, 1.0, 1.0], 1.0, n_sub=0)
    with pytest.raises(ValueError, match="`period`"):
        monodromy(lorenz, [1.0, 1.0, 1.0], -1.0)


# ---- no hangs, no overflow errors -------------------------------------------------------------


def test_nan_from_fun_is_a_valueerror_not_a_hang():
    # The reproducer of issue 7: hung forever before.
    with pytest.raises(ValueError, match="`fun` returned a non-finite value"):
        monodromy(lambda t, x: np.full(2, np.nan), [1.0, 1.0], 1.0)


def test_nan_from_jac_is_a_valueerror_naming_jac():
    with pytest.raises(ValueError, match="`jac` returned a non-finite value"):
        monodromy(lambda t, x: -x, [1.0, 1.0], 1.0, jac=lambda t, x: np.full((2, 2), np.nan))


def test_stiff_monodromy_fails_early_with_advice():
    with pytest.raises(ConvergenceError, match="method='Radau'"):
        monodromy(lambda t, x: -1e9 * (x - np.cos(t)), [1.0], 2 * math.pi)


def test_overflowing_multiplier_is_inf_with_a_warning_and_a_finite_exponent():
    # x' = 50 x over T = 20 at the equilibrium x = 0: M = exp(1000) overflows float64. It raised
    # OverflowError; now the multiplier and det M are inf (with a warning), while the exponent
    # and Liouville's log keep the value: 50 and 1000 (relative 1e-12: rtol 1e-12, constant J).
    with pytest.warns(RuntimeWarning, match="overflow"):
        mon = monodromy(lambda t, x: 50.0 * x, [0.0], 20.0)
    assert mon.multipliers[0] == math.inf and mon.det == math.inf
    assert mon.liouville_det == math.inf
    assert abs(mon.exponents[0].real / 50.0 - 1.0) <= 1e-12
    assert abs(mon.trace_integral / 1000.0 - 1.0) <= 1e-12
    assert mon.liouville_error <= 1e-9  # from the logarithms


def test_exponent_of_a_zero_multiplier_is_minus_inf_without_warnings():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ex = floquet_exponents([0.0, 1.0, 0j, -1.0], 2.0)
    assert ex[0] == complex(-math.inf, 0.0) and ex[2] == complex(-math.inf, 0.0)
    assert ex[1] == 0.0 and ex[3] == pytest.approx(1j * math.pi / 2.0)


def test_factors_are_time_last_and_multiply_to_the_matrix(mon_ab):
    F = mon_ab.factors
    assert F.shape[:2] == (3, 3) and F.shape[2] >= 4
    M = np.eye(3)
    for k in range(F.shape[2]):
        M = F[:, :, k] @ M
    np.testing.assert_array_equal(M, mon_ab.matrix)


@pytest.mark.parametrize("kwargs, match", [
    (dict(period=True), "`period`"),
    (dict(n_sub=2.0), "`n_sub`"),
    (dict(max_cond=1.0), "`max_cond`"),
    (dict(rtol="1e-8"), "`rtol`"),
])
def test_bools_strings_and_bad_numbers_are_refused(kwargs, match):
    call = dict(period=1.0)
    call.update(kwargs)
    with pytest.raises(ValueError, match=match):
        monodromy(lorenz, [1.0, 1.0, 1.0], call.pop("period"), **call)


# ---- bad inputs and blow-ups (issue 26, item 6) -------------------------------------------------


def test_a_blow_up_in_monodromy_carries_time_state_and_source():
    # x' = x^2 blows up at t = 1, inside the period 2: where, as attributes
    with pytest.raises(ConvergenceError, match="could not be integrated") as error:
        monodromy(lambda t, x: x**2, [1.0], 2.0)
    exc = error.value
    assert exc.source in ("step budget", "integrator", "state")
    assert exc.t == pytest.approx(1.0, abs=1e-3)
    assert exc.state.shape == (1,) and exc.state[0] > 1e3


@pytest.mark.parametrize("multipliers", [[math.nan], [1.0, complex(math.nan, 0.0)], ["a"]])
def test_floquet_exponents_refuse_multipliers_that_are_not_numbers(multipliers):
    # [nan] used to return [nan+nanj]
    with pytest.raises(ValueError, match="`multipliers` must"):
        floquet_exponents(multipliers, 1.0)


def test_no_multipliers_have_no_trivial_one():
    # used to be numpy's "attempt to get argmin of an empty sequence"
    with pytest.raises(ValueError, match="`multipliers` must not be empty"):
        nontrivial_multipliers([])


def test_an_infinite_multiplier_keeps_its_infinite_exponent():
    # the edge case that must keep working: an overflowed |mu| is a number, not a mistake
    assert floquet_exponents([math.inf], 2.0)[0].real == math.inf

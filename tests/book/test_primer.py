"""The primer's toy systems: the multiplier of x' = a(t) x, Kapitza's pendulum, averaging error."""

import math

import numpy as np

from flapping.book.primer import (
    KapitzaPendulum,
    averaging_error,
    floquet_versus_averaging,
    scalar_system,
)
from flapping.periodic.floquet import monodromy
from flapping.periodic.integrate import flow


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

"""FWUAV's hover orbits and Floquet exponents (flapping.peers.fwuav.floquet) against FWUAV's
stored exponents (sim_QS_x_hover_conv_rate.mat, fdcl-gwu/FWUAV @ 1a25d41)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from flapping.errors import ConvergenceError
from flapping.peers.fwuav import FwuavHover, fwuav_procedure, hover_floquet

# FWUAV's exponents (1/s), typed from its data file, not from our code:
# conv_rate_<insect> = [0, 0, 0, longitudinal 1, longitudinal 2, lateral]
FWUAV = {"hawkmoth": (-1.7755204381, -4.6284423025, -1.4813366750),
         "bumblebee": (-1.5289432328, -2.8919659432, -2.0118769537),
         "fruit_fly": (-3.9368558007, -7.0358838946, -4.6478546990)}


@pytest.mark.parametrize("name", sorted(FWUAV))
def test_the_exponents_match_fwuavs_within_two_percent(name):
    r = hover_floquet(name)
    ours = np.concatenate([r.longitudinal.real, [r.lateral.real]])
    np.testing.assert_allclose(ours, FWUAV[name], rtol=0.02)
    assert np.all(np.abs(r.longitudinal.imag) < 1e-12)


@pytest.mark.parametrize("name", sorted(FWUAV))
def test_six_exponents_three_zero_sorted_by_real_part(name):
    r = hover_floquet(name)
    assert r.exponents.shape == (6,)
    assert np.all(np.diff(r.exponents.real) <= 0)
    assert np.abs(r.exponents[:3]).max() < 1e-8
    assert np.all(r.exponents[3:].real < -0.5)  # hover is stable in this model
    np.testing.assert_allclose(np.sort(r.exponents[3:].real),
                               np.sort([*r.longitudinal.real, r.lateral.real]), rtol=1e-9)
    np.testing.assert_allclose(r.multipliers, np.exp(r.exponents * r.period), rtol=1e-12)


def test_the_orbit_is_periodic():
    r = hover_floquet("fruit_fly")
    model = FwuavHover("fruit_fly")
    sol = solve_ivp(model.velocity_rhs, (0.0, r.period), r.x0[3:6], method="DOP853",
                    rtol=1e-12, atol=1e-14)
    gap = np.abs(sol.y[:, -1] - r.x0[3:6]).max()
    assert gap < 1e-8 * np.abs(r.x0[3:6]).max()
    assert r.residual_norm < 1e-10
    # the velocity moves: a flapping orbit, not an equilibrium
    assert np.ptp(sol.y, axis=1).max() > 0.1 * np.abs(r.x0[3:6]).max()
    # FWUAV's optimiser held the mean velocity near zero; the drift it left is reported
    assert np.abs(r.mean_velocity).max() < 1e-3


def test_the_orbit_starts_near_fwuavs_stored_velocity():
    r = hover_floquet("hawkmoth")
    fwuav_x_dot0 = np.array([-0.11981422138550234, 0.0, 0.006147654793844691])
    assert np.abs(r.x0[3:6] - fwuav_x_dot0).max() < 1e-3


@pytest.mark.parametrize("kwargs, word", [({"rtol": 0.1}, "rtol"), ({"rtol": True}, "rtol"),
                                          ({"n_strips": 0}, "n_strips"),
                                          ({"quadrature": "trapezoid"}, "quadrature")])
def test_bad_arguments_are_value_errors_naming_them(kwargs, word):
    with pytest.raises(ValueError, match=word):
        hover_floquet("hawkmoth", **kwargs)


def test_an_unknown_insect_is_a_value_error():
    with pytest.raises(ValueError, match="name"):
        hover_floquet("locust")


def test_fwuavs_procedure_converges_onto_our_exponents_when_refined():
    r = hover_floquet("fruit_fly")
    ours = np.array([*r.longitudinal.real, r.lateral.real])
    loose = fwuav_procedure("fruit_fly", rtol=1e-6)
    tight = fwuav_procedure("fruit_fly", rtol=1e-10, start=r.x0[3:6])
    np.testing.assert_allclose(loose, FWUAV["fruit_fly"], rtol=0.02)  # FWUAV's own setting
    assert np.abs(tight - ours).max() < 1e-3 * np.abs(loose - ours).max()
    np.testing.assert_allclose(tight, ours, rtol=1e-5)


def test_the_monarch_is_refused_with_a_convergence_error_saying_why():
    with pytest.raises(ConvergenceError, match="stroke reversal"):
        hover_floquet("monarch")


def test_the_hawkmoths_exponents_are_the_ones_computed_before_the_speed_up():
    # Computed on 2026-12-03 before the model's evaluation was made faster (same equations; the
    # faster code gives them to the bit). Tolerance: the method's accuracy at the default
    # rtol = 1e-11, measured against rtol = 1e-12: 4e-10 relative (rtol 1e-10: 3e-8). A change
    # of the arithmetic's order moves them by ~1e-13; a change of the integration would not pass.
    r = hover_floquet("hawkmoth")
    np.testing.assert_allclose(r.longitudinal.real, [-1.7758957011796377, -4.630048434248125],
                               rtol=1e-9)
    assert r.lateral.real == pytest.approx(-1.482035276245892, rel=1e-9)
    np.testing.assert_allclose(r.x0[3:6], [-0.11980044476313688, 0.0, 0.006140098680065467],
                               rtol=0, atol=1e-12)


def test_the_backend_argument_is_the_package_s():
    from flapping.backends import Adaptive
    from flapping.peers.fwuav import hover_floquet

    assert hover_floquet("hawkmoth", backend=Adaptive(rtol=1e-11)) is hover_floquet("hawkmoth")
    with pytest.raises(ValueError, match="adaptive path only"):
        hover_floquet("hawkmoth", backend="compiled")

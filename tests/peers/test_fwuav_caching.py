"""The FWUAV models remember what depends on the time alone (the prescribed motion, the bodies'
rates and positions) and the motion at the last attitude: a model reused across instants,
states and attitudes in any order gives, bit for bit, what a fresh model gives at each call.
These caches carry the chapter "A second model" (its central-difference Jacobians evaluate the
right-hand side 8 or 18 times at one instant), so a stale entry would move its numbers."""

from __future__ import annotations

import numpy as np
import pytest

from flapping._numdiff import central_jacobian
from flapping.peers.fwuav import FwuavAttitudeFree, FwuavPitchFree
from flapping.peers.fwuav.attitude import _reduced, _Retrimmed


def _points(period: float, n: int = 6) -> list[tuple[float, np.ndarray]]:
    """Instants revisited out of order, with states that differ in pitch, rate and velocity."""
    rng = np.random.default_rng(7)
    ts = rng.uniform(0.0, period, n)
    order = [0, 1, 0, 2, 2, 1, 3, 4, 3, 5]  # back to an earlier instant, twice in a row
    return [(float(ts[i]), np.array([0.3, 0.1, -0.2, 2.0]) + 0.05 * rng.standard_normal(4))
            for i in order]


@pytest.mark.parametrize("body_rate_term", ["fwuav", "rotated"])
def test_a_reused_pitch_free_model_equals_a_fresh_one(body_rate_term: str) -> None:
    reused = FwuavPitchFree("hawkmoth", body_rate_term=body_rate_term)
    fun, jac = _reduced(reused)
    for t, y in _points(reused.period):
        fresh = FwuavPitchFree("hawkmoth", body_rate_term=body_rate_term)
        f_fresh, j_fresh = _reduced(fresh)
        np.testing.assert_array_equal(fun(t, y), f_fresh(t, y))
        np.testing.assert_array_equal(jac(t, y), _reduced(
            FwuavPitchFree("hawkmoth", body_rate_term=body_rate_term))[1](t, y))
        x6 = np.concatenate([[0.0, 0.0], y])
        np.testing.assert_array_equal(np.concatenate(reused.momentum(t, x6)),
                                      np.concatenate(fresh.momentum(t, x6)))


def test_the_held_pitch_model_is_not_served_the_free_ones_terms() -> None:
    held = FwuavPitchFree("hawkmoth", pitch="prescribed")
    free = FwuavPitchFree("hawkmoth")
    for t, y in _points(held.period, n=6)[:4]:
        x6 = np.concatenate([[0.0, 0.0], y])
        free.rhs(t, x6)
        np.testing.assert_array_equal(
            held.rhs(t, x6), FwuavPitchFree("hawkmoth", pitch="prescribed").rhs(t, x6))


def test_the_trim_jacobian_skips_only_the_zero_position_columns() -> None:
    system = _Retrimmed("hawkmoth", "fwuav", ("phi_m", "phi_0"))
    k = system.base.kinematics
    values = np.array([k.phi_m * 1.01, k.phi_0 + 0.01])
    for t, y in _points(1.0 / k.f)[:4]:
        x6 = np.concatenate([[0.01, -0.02], y])
        model = system.model(values)
        full = central_jacobian(lambda z, t=t, model=model: model.rhs(t, z), x6)
        assert np.all(full[:, :2] == 0.0)  # the position enters nothing
        np.testing.assert_array_equal(system.jac(t, x6, values), full)


@pytest.mark.parametrize("body_rate_term", ["fwuav", "rotated"])
def test_a_reused_attitude_free_model_equals_a_fresh_one(body_rate_term: str) -> None:
    reused = FwuavAttitudeFree("hawkmoth", body_rate_term=body_rate_term)
    rng = np.random.default_rng(3)
    for t, y in _points(reused.period):
        state = FwuavAttitudeFree.from_planar(y)
        state[12:] += 0.05 * rng.standard_normal(6)  # off the plane: roll, yaw, sideslip
        fresh = FwuavAttitudeFree("hawkmoth", body_rate_term=body_rate_term)
        np.testing.assert_array_equal(reused.rhs(t, state), fresh.rhs(t, state))
        np.testing.assert_array_equal(
            reused.local_jacobian(t, state),
            FwuavAttitudeFree("hawkmoth", body_rate_term=body_rate_term).local_jacobian(t, state))


def test_both_wings_strip_jacobians_at_once_equal_each_wings() -> None:
    from flapping.peers.fwuav import species
    from flapping.peers.fwuav.model import _strip_jacobian, _strip_jacobians

    sp = species("bumblebee")
    rng = np.random.default_rng(5)
    U = rng.standard_normal((3, 2, 50))
    U[1] = 0.0  # no spanwise component
    U[:, 1, 7] = 0.0  # a strip at rest on the second wing only
    weights = rng.uniform(1e-6, 1e-5, 50)
    both = _strip_jacobians(sp, U, weights)
    for w in range(2):
        np.testing.assert_array_equal(both[w], _strip_jacobian(sp, U[:, w], weights))

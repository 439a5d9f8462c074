"""Numeric stability derivatives X0(t) ... Mq(t) of eq. (29) (flapping.model.derivatives)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import flapping
from flapping.model import aerodynamics, derivatives
from flapping.model.derivatives import NAMES, stability_derivatives


@pytest.fixture(scope="module")
def moth():
    return flapping.hawkmoth()


def test_cycle_mean_of_z0_balances_weight_at_trim(moth):
    t = np.linspace(0.0, moth.period, 2048, endpoint=False)
    mean_z0 = stability_derivatives(moth, t).cycle_mean()["Z0"]
    assert mean_z0 / moth.mass == pytest.approx(-moth.gravity, rel=1e-12)


def test_averaged_jacobian_carries_gravity_and_the_pitch_kinematics(moth):
    t = np.linspace(0.0, moth.period, 64, endpoint=False)
    d = stability_derivatives(moth, t)
    J = d.averaged_jacobian(moth.gravity)
    means = d.cycle_mean()
    np.testing.assert_array_equal(J[3], [0.0, 0.0, 1.0, 0.0])   # theta' = q
    assert J[0, 3] == -moth.gravity
    assert J[2, 2] == means["Mq"]


def test_constants_are_those_of_the_aerodynamics_module():
    # aero_constants moved below the derivation; this module re-exports the same objects.
    assert derivatives.aero_constants is aerodynamics.aero_constants
    assert derivatives.AeroConstants is aerodynamics.AeroConstants


def test_shape_follows_t(moth):
    t = np.linspace(0.0, moth.period, 12).reshape(3, 4)
    d = stability_derivatives(moth, t)
    assert all(getattr(d, name).shape == (3, 4) for name in NAMES)


@pytest.mark.parametrize("bad", [float("nan"), -3.0, 2.0, 0.0, math.pi / 2, True, "0.3"])
def test_stability_derivatives_reject_bad_alpha_m(moth, bad):
    # True was accepted as 1 rad; 0 and pi/2 are outside the model's one range (0, pi/2).
    with pytest.raises(ValueError, match="alpha_m"):
        stability_derivatives(moth, [0.0], alpha_m=bad)


@pytest.mark.parametrize("kwargs, name", [
    (dict(amplitude=2.0), "amplitude"),
    (dict(t=[0.0, math.nan]), "t"),
    (dict(insect="hawkmoth"), "insect"),
])
def test_other_bad_arguments_are_named(moth, kwargs, name):
    args = dict(insect=moth, t=[0.0]) | kwargs
    with pytest.raises(ValueError, match=f"`{name}`"):
        stability_derivatives(args.pop("insect"), args.pop("t"), **args)


def test_numpy_scalar_arguments_give_the_float64_numbers(moth):
    # np.float32 alpha_m was refused; a float32 mass leaked into the derivatives as float32.
    t = np.linspace(0.0, moth.period, 16)
    alpha, amplitude, mass = np.float32(0.3), np.float32(1.0), np.float32(1.648e-3)
    ref = stability_derivatives(moth.with_(mass=float(mass)), t, alpha_m=float(alpha),
                                amplitude=float(amplitude))
    got = stability_derivatives(moth.with_(mass=mass), t, alpha_m=alpha, amplitude=amplitude)
    assert type(got.alpha_m) is float and type(got.amplitude) is float
    for name in NAMES:
        value = getattr(got, name)
        assert value.dtype == np.float64
        np.testing.assert_array_equal(value, getattr(ref, name))

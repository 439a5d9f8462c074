"""Wing kinematics (flapping.model.kinematics): the stroke of eq. (39), the pitch of eq. (11), and
the one accepted range of each kinematic parameter (stroke amplitude, alpha_m)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import flapping
from flapping.model.kinematics import (
    check_alpha_m,
    check_amplitude,
    flapping_angle,
    flapping_rate,
    geometric_pitch,
    reversed_flow_fraction,
    segment_stroke_sign,
    stroke_sign,
    stroke_sign_scalar,
)

F = 26.3  # Hz, the hawkmoth's


# ----------------------------------------------------------------------------- the stroke
def test_flapping_rate_is_the_derivative_of_the_angle():
    # Central differences of eq. (39): truncation (2 pi f h)^2 / 6 ~ 1e-10 relative at h = 1e-7 T.
    t = np.linspace(0.0, 1.0 / F, 37)
    h = 1e-7 / F
    fd = (flapping_angle(t + h, 1.0, F) - flapping_angle(t - h, 1.0, F)) / (2 * h)
    np.testing.assert_allclose(flapping_rate(t, 1.0, F), fd, rtol=0, atol=1e-7 * 2 * math.pi * F)


def test_backward_stroke_first_then_forward():
    t = np.array([0.1, 0.4, 0.6, 0.9]) / F
    np.testing.assert_array_equal(stroke_sign(t, F), [-1.0, -1.0, 1.0, 1.0])
    np.testing.assert_array_equal(np.sign(flapping_rate(t, 1.0, F)), [-1.0, -1.0, 1.0, 1.0])
    assert [segment_stroke_sign(k) for k in range(4)] == [-1.0, 1.0, -1.0, 1.0]


@settings(max_examples=200, deadline=None)
@given(k=st.integers(-10_000, 10_000), half=st.booleans(), jitter=st.floats(-1e-15, 1e-15))
def test_scalar_and_array_stroke_signs_agree_at_reversal(k, half, jitter):
    # t * f rounds near reversal (here by a few ulps, |k| jitter < 1e-11 in phase): both versions
    # snap onto the half-stroke that starts there.
    t = (k + 0.5 * half) / F * (1.0 + jitter)
    assert stroke_sign_scalar(t, F) == float(stroke_sign(t, F))
    assert stroke_sign_scalar(t, F) == (1.0 if half else -1.0)


def test_geometric_pitch_flips_at_reversal():
    # eq. (11): alpha_m on the forward stroke, pi - alpha_m on the backward one.
    np.testing.assert_array_equal(geometric_pitch(0.3, np.array([1.0, -1.0])),
                                  [0.3, math.pi - 0.3])


def test_reversed_flow_fraction_grows_with_speed_and_vanishes_at_rest():
    h = flapping.hawkmoth()
    r = h.r2 * h.semi_span
    fracs = [reversed_flow_fraction(r, u, h.stroke_amplitude, h.frequency) for u in (0.0, 0.1, 0.5)]
    assert fracs[0] == 0.0 < fracs[1] < fracs[2] < 0.5


@pytest.mark.parametrize("kwargs, name", [
    (dict(radius=-0.01), "radius"),
    (dict(amplitude=2.0), "amplitude"),
    (dict(frequency=0.0), "frequency"),
    (dict(n_samples=True), "n_samples"),
    (dict(u="0.1"), "u"),
])
def test_reversed_flow_fraction_names_its_bad_argument(kwargs, name):
    args = dict(radius=0.02, u=0.1, amplitude=1.0, frequency=F, n_samples=100) | kwargs
    with pytest.raises(ValueError, match=f"`{name}`"):
        reversed_flow_fraction(**args)


# ----------------------------------------------------------------------------- accepted ranges
@settings(max_examples=200, deadline=None)
@given(value=st.floats(allow_nan=True, allow_infinity=True))
def test_amplitude_range_is_zero_excluded_to_ninety_degrees(value):
    inside = 0.0 < value <= math.pi / 2
    if inside:
        assert check_amplitude(value) == value
    else:
        with pytest.raises(ValueError, match=r"`amplitude` must be .*\(0, pi/2\] rad"):
            check_amplitude(value)


@settings(max_examples=200, deadline=None)
@given(value=st.floats(allow_nan=True, allow_infinity=True))
def test_alpha_m_range_is_the_open_quarter_turn(value):
    # Open at both ends: there sin(2 alpha_m) = 0, the wing makes no LEV lift and cannot trim.
    if 0.0 < value < math.pi / 2:
        assert check_alpha_m(value) == value
    else:
        with pytest.raises(ValueError, match=r"`alpha_m` must be .*\(0, pi/2\) rad"):
            check_alpha_m(value)


@pytest.mark.parametrize("check", [check_amplitude, check_alpha_m])
@pytest.mark.parametrize("value", [np.float32(0.5), np.float16(0.5), np.array(0.5), np.int64(1)])
def test_numpy_scalars_become_python_floats(check, value):
    out = check(value)
    assert type(out) is float
    assert out == float(value)


@pytest.mark.parametrize("check", [check_amplitude, check_alpha_m])
@pytest.mark.parametrize("value", [True, np.bool_(True), "0.5", None, 0.5j, [0.5]])
def test_non_numbers_are_refused(check, value):
    # True used to pass as 1 rad.
    with pytest.raises(ValueError, match="must be a real number"):
        check(value)


def test_the_message_names_the_caller_s_argument():
    with pytest.raises(ValueError, match="`stroke_amplitude`"):
        check_amplitude(3.0, "stroke_amplitude")

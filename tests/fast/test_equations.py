"""The kernel's hand-written equations of motion against LongitudinalDynamics (the reference).

``plain_rhs`` (eq. 2 with eq. 29's loads, and the descent rate z'), and inside
``variational_rhs`` the Jacobian (eqs. 44-47, with the z row) and the sensitivity to the stroke
amplitude Phi, at random states, phases of both half-strokes and insects. Both sides evaluate the
same generated derivatives in float64 in a different order, so they agree to rounding: 1e-12 of
the largest term of each quantity (the terms reach ~10^3 |result| where gravity and the
aerodynamic accelerations cancel, hence a scale from the terms rather than from the result).
"""

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import flapping
from flapping.model.dynamics import LongitudinalDynamics, inertial_velocity, inertial_velocity_jac

pytest.importorskip("numba")
from flapping.fast import kernel  # noqa: E402

RTOL = 1e-12

insects = st.builds(
    flapping.hawkmoth,
    hinge_offset=st.floats(-3e-3, 3e-3),
    hinge_height=st.floats(0.0, 10e-3),
    mass=st.floats(1.2e-3, 1.9e-3),
    frequency=st.floats(20.0, 34.0),
)
# Both half-strokes, not at stroke reversal (t = T/2), where the half-stroke of t is ambiguous and
# the loads vanish to rounding (phi_dot = -omega Phi sin(pi) ~ 1e-16): a sign of noise.
phases = st.one_of(st.floats(0.0, 0.499), st.floats(0.501, 0.999))
states = st.tuples(st.floats(-3, 3), st.floats(-3, 3), st.floats(-30, 30), st.floats(-1.5, 1.5))


def _kernel_fields(problem, t, x, amplitude, sign):
    """(f (5,), J (5, 4), df/dPhi (5,), trace J) from the compiled right-hand sides."""
    kc = kernel.load()
    d, out = np.empty(24), np.empty(5)
    kc.plain_rhs(t, np.append(x, 0.0), amplitude, sign, problem.k, problem.p, d, out)
    y = np.zeros(kc.N_VAR)
    y[:4] = x
    y[5:25] = np.vstack([np.eye(4), np.zeros((1, 4))]).ravel()  # Y = [I; 0], s = 0
    var = np.empty(kc.N_VAR)
    kc.variational_rhs(t, y, amplitude, sign, problem.k, problem.p, d, var)
    # The two right-hand sides share the formulas (their derivatives are generated separately).
    _close(var[:5], out, np.abs(out).max())
    return out, var[5:25].reshape(5, 4), var[25:30], var[30]


def _close(actual, expected, scale):
    np.testing.assert_allclose(actual, expected, rtol=0, atol=RTOL * scale)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(insect=insects, x=states, amplitude=st.floats(0.3, 1.5), phase=phases)
def test_kernel_equations_equal_longitudinal_dynamics(insect, x, amplitude, phase):
    try:
        model = LongitudinalDynamics(insect, amplitude, aerodynamics="linear")
    except ValueError:  # too heavy to trim at this frequency (eq. 40): no model to compare
        assume(False)
    problem = kernel.KernelProblem.of(insect)
    assert problem.alpha_m == model.alpha_m
    t = phase * insect.period
    sign = -1.0 if phase < 0.5 else 1.0  # backward stroke first (eq. 11)
    x = np.array(x)
    f, J, dphi, trace = _kernel_fields(problem, t, x, amplitude, sign)
    g = insect.gravity
    terms = max(g, abs(x[2] * x[0]), abs(x[2] * x[1]), *np.abs(model.rhs(t, x)))
    _close(f[:4], model.rhs(t, x), terms)
    _close(f[4], inertial_velocity(x[0], x[1], x[3])[1], np.abs(x[:2]).sum())
    jac = model.jac(t, x)
    _close(J[:4], jac, np.abs(jac).max())
    _close(J[4], inertial_velocity_jac(x[0], x[1], x[3])[1], np.abs(x[:2]).sum() + 1.0)
    _close(trace, np.trace(jac), np.abs(np.diag(jac)).sum())
    sens = model.amplitude_jac(t, x)[:, 0]
    _close(dphi[:4], sens, np.abs(sens).max())
    assert dphi[4] == 0.0  # z' does not depend on Phi


def test_the_half_stroke_sign_matters():
    # The check above can fail: the wrong half-stroke's sign gives different loads.
    insect = flapping.hawkmoth()
    model = LongitudinalDynamics(insect, aerodynamics="linear")
    problem = kernel.KernelProblem.of(insect)
    x, t = np.array([0.3, -0.2, 1.0, 0.1]), 0.25 * insect.period
    f, _, _, _ = _kernel_fields(problem, t, x, insect.stroke_amplitude, +1.0)
    assert not np.allclose(f[:4], model.rhs(t, x), rtol=1e-6, atol=0)
    assert math.isfinite(f[0])

"""Equations of motion: Jacobian, validation, and consistency between the aerodynamic models."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import flapping
from flapping.model.aerodynamics import BladeElementModel
from flapping.model.derivatives import stability_derivatives
from flapping.model.dynamics import LongitudinalDynamics


@pytest.fixture(scope="module")
def insect():
    return flapping.hawkmoth(hinge_offset=1e-3)


@pytest.mark.parametrize("aerodynamics", ["linear", "small-angle", "exact"])
def test_jacobian_matches_finite_differences_of_rhs(insect, aerodynamics):
    model = LongitudinalDynamics(insect, aerodynamics=aerodynamics)
    rng = np.random.default_rng(1)
    for _ in range(5):
        t = rng.uniform(0.05, 0.45) * insect.period
        x = rng.normal(scale=[0.2, 0.2, 2.0, 0.3])
        J = model.jac(t, x)
        h = 1e-6
        fd = np.column_stack([(model.rhs(t, x + h * e) - model.rhs(t, x - h * e)) / (2 * h)
                              for e in np.eye(4)])
        np.testing.assert_allclose(J, fd, rtol=1e-5, atol=1e-6 * np.abs(fd).max())


def test_linear_and_blade_element_models_agree_to_second_order(insect):
    lin = LongitudinalDynamics(insect, aerodynamics="linear")
    ble = LongitudinalDynamics(insect, aerodynamics="small-angle")
    t = 0.21 * insect.period
    direction = np.array([0.2, 0.3, -1.5, 0.1])
    diffs = [np.abs(lin.rhs(t, e * direction) - ble.rhs(t, e * direction)).max()
             for e in (4e-3, 2e-3)]
    assert diffs[0] / diffs[1] == pytest.approx(4.0, rel=0.1)


def test_rhs_at_rest_is_gravity_plus_aerodynamic_forcing(insect):
    model = LongitudinalDynamics(insect)
    t = 0.1 * insect.period
    d = model.derivatives(t)
    f = model.rhs(t, np.zeros(4))
    np.testing.assert_allclose(f, [d[0] / insect.mass, insect.gravity + d[1] / insect.mass,
                                   d[2] / insect.pitch_inertia, 0.0])


def test_segment_functions_use_their_own_stroke_sign(insect):
    model = LongitudinalDynamics(insect, aerodynamics="exact")
    rhs, _ = model.segment_functions()
    x = np.array([0.5, 0.0, 0.0, 0.0])  # forward speed: U != 0 at reversal
    t_rev = 0.5 * insect.period
    left, right = rhs[0](t_rev, x), rhs[1](t_rev, x)
    # The wing pitch flips at reversal: with u != 0 the loads jump there.
    assert np.abs(left - right).max() > 1e-3
    # ... and segment 0 is the left limit: continuous with the backward stroke just before.
    np.testing.assert_allclose(left, model.rhs(t_rev * (1 - 1e-7), x), rtol=1e-4)


@pytest.mark.parametrize("kwargs, match", [
    (dict(amplitude=2.0), "amplitude"),
    (dict(amplitude=-0.1), "amplitude"),
    (dict(amplitude=float("nan")), "amplitude"),
    (dict(aerodynamics="quasi"), "aerodynamics"),
    (dict(alpha_m=2.0), "alpha_m"),
    (dict(alpha_m=True), "alpha_m"),
    (dict(amplitude="1.0"), "amplitude"),
    (dict(n_nodes=1), "n_nodes"),
    (dict(n_nodes=32.0), "n_nodes"),
])
def test_bad_arguments_raise(insect, kwargs, match):
    with pytest.raises(ValueError, match=match):
        LongitudinalDynamics(insect, **kwargs)


def test_too_heavy_insect_cannot_trim():
    heavy = flapping.hawkmoth(mass=0.05)
    with pytest.raises(ValueError, match="weight"):
        LongitudinalDynamics(heavy)


# ----------------------------------------------------------------------------- one range, float64
@settings(max_examples=60, deadline=None)
@given(alpha_m=st.one_of(st.sampled_from([0.0, math.pi / 2, -0.0, 1e-300, math.pi / 2 - 1e-15]),
                         st.floats(-1.0, 2.0)))
def test_alpha_m_range_is_the_same_for_every_model_that_takes_it(insect, alpha_m):
    # BladeElementModel accepted [0, pi/2], LongitudinalDynamics (0, pi/2): now all (0, pi/2).
    def accepts(build):
        try:
            build()
        except ValueError as error:
            assert "`alpha_m`" in str(error)
            return False
        return True

    verdicts = {
        "blade": accepts(lambda: BladeElementModel(insect, alpha_m, n_nodes=4)),
        "dynamics": accepts(lambda: LongitudinalDynamics(insect, alpha_m=alpha_m)),
        "derivatives": accepts(lambda: stability_derivatives(insect, [0.0], alpha_m=alpha_m)),
    }
    assert set(verdicts.values()) == {0.0 < alpha_m < math.pi / 2}, verdicts


@pytest.mark.parametrize("aerodynamics", ["linear", "small-angle"])
@pytest.mark.parametrize("overrides", [
    dict(mass=np.float32(1.648e-3)),               # the reproducer (hover failed after 107 s)
    dict(frequency=np.int64(26), pitch_inertia=np.float32(2.08e-7)),
])
def test_numpy_scalar_insect_gives_the_float64_equations_of_motion(overrides, aerodynamics):
    # The float32 mass leaked into the derivatives; every field is now a float on entry, so the
    # model is the one of the float64 values: rhs and jac identical, bit for bit.
    as_float = flapping.hawkmoth(**{k: float(v) for k, v in overrides.items()})
    as_numpy = flapping.hawkmoth(**overrides)
    a = LongitudinalDynamics(as_float, aerodynamics=aerodynamics)
    b = LongitudinalDynamics(as_numpy, aerodynamics=aerodynamics, amplitude=np.float32(1.0),
                             n_nodes=np.int64(32))
    a = a.with_amplitude(float(np.float32(1.0)))
    assert type(b.alpha_m) is float and type(b.amplitude) is float and type(b.n_nodes) is int
    x = np.array([0.1, -0.05, 0.7, 0.02])
    for t in np.linspace(0.0, as_float.period, 7):
        for method in ("rhs", "jac", "amplitude_jac"):
            fa, fb = getattr(a, method)(t, x), getattr(b, method)(t, x)
            assert fb.dtype == np.float64
            np.testing.assert_array_equal(fb, fa)


def test_blade_element_jacobian_uses_the_documented_steps(insect):
    # Central differences of the loads with steps 1e-6 max(1, |x_j|), divided by 2 h: the values
    # the book's blade-element results were computed with.
    model = LongitudinalDynamics(insect, aerodynamics="exact")
    t, x = 0.3 * insect.period, np.array([0.4, -2.0, 3.0, 0.1])
    u, w, q, _ = x
    rigid_body = np.array([[0.0, -q, -w], [q, 0.0, u], [0.0, 0.0, 0.0]])   # eq. (2)
    scale = np.array([insect.mass, insect.mass, insect.pitch_inertia])
    J = model.jac(t, x)
    for j in range(3):
        h = 1e-6 * max(1.0, abs(x[j]))
        xp, xm = x[:3].copy(), x[:3].copy()
        xp[j] += h
        xm[j] -= h
        column = (model.loads(t, xp) - model.loads(t, xm)) * (1.0 / scale) / (2.0 * h)
        # Bit for bit up to the one rounding of adding the rigid-body terms back.
        np.testing.assert_allclose(J[:3, j] - rigid_body[:, j], column, rtol=0,
                                   atol=np.spacing(np.abs(rigid_body[:, j]).max()))


def test_amplitude_jacobian_of_the_blade_element_model(insect):
    model = LongitudinalDynamics(insect, aerodynamics="small-angle")
    t, x = 0.2 * insect.period, np.array([0.1, 0.2, -1.0, 0.0])
    h = 1e-7 * model.amplitude
    expected = (model.rhs(t, x, amplitude=model.amplitude + h)
                - model.rhs(t, x, amplitude=model.amplitude - h)) / (2.0 * h)
    np.testing.assert_array_equal(model.amplitude_jac(t, x)[:, 0], expected)


# --------------------------------------------------------------- hinge height and mean stroke
@pytest.mark.parametrize("aerodynamics", ["linear", "small-angle"])
def test_parameter_jacobians_match_finite_differences_with_a_mean_stroke(aerodynamics):
    # phi = phi_bar + Phi cos(2 pi f t): the amplitude derivative is no longer the Euler operator
    # alone, and the mean-stroke derivative is d/dphi. Central differences (step 1e-5 rad,
    # truncation ~1e-10 relative) of the right-hand side check both.
    insect = flapping.hawkmoth(hinge_height=5e-3, stroke_mean=0.2)
    model = LongitudinalDynamics(insect, aerodynamics=aerodynamics)
    x = np.array([0.2, -0.1, 3.0, 0.05])
    h = 1e-5
    for t in np.array([0.07, 0.31, 0.62, 0.88]) * insect.period:
        fd_amp = (model.with_amplitude(model.amplitude + h).rhs(t, x)
                  - model.with_amplitude(model.amplitude - h).rhs(t, x)) / (2 * h)
        fd_mean = (model.with_stroke_mean(0.2 + h).rhs(t, x)
                   - model.with_stroke_mean(0.2 - h).rhs(t, x)) / (2 * h)
        scale = np.abs(fd_amp).max()
        np.testing.assert_allclose(model.amplitude_jac(t, x)[:, 0], fd_amp, atol=1e-7 * scale)
        np.testing.assert_allclose(model.stroke_mean_jac(t, x)[:, 0], fd_mean,
                                   atol=1e-7 * np.abs(fd_mean).max())


def test_hinge_height_moment_is_the_forward_force_times_the_arm():
    # At q = 0 the hinge height only moves the forces' point of action: M(h) = M(0) - h X.
    insect = flapping.hawkmoth()
    high = insect.with_(hinge_height=7e-3)
    for aero in ("linear", "small-angle", "exact"):
        low_m = LongitudinalDynamics(insect, aerodynamics=aero)
        high_m = LongitudinalDynamics(high, alpha_m=low_m.alpha_m, aerodynamics=aero)
        for t in np.array([0.1, 0.4, 0.7]) * insect.period:
            X, Z, M = low_m.loads(t, [0.3, -0.2, 0.0])
            Xh, Zh, Mh = high_m.loads(t, [0.3, -0.2, 0.0])
            np.testing.assert_allclose([Xh, Zh, Mh], [X, Z, M - 7e-3 * X],
                                       rtol=1e-12, atol=1e-12 * abs(M))


def test_inertial_velocity_turns_the_body_velocity_and_its_jacobian_matches_differences():
    from flapping._numdiff import central_jacobian
    from flapping.model.dynamics import inertial_velocity, inertial_velocity_jac

    assert inertial_velocity(1.0, 0.0, 0.0) == (1.0, 0.0)
    forward, down = inertial_velocity(0.0, 1.0, math.pi / 2)  # nose up 90 deg: body z points forward
    assert forward == pytest.approx(1.0) and down == pytest.approx(0.0, abs=1e-15)
    x = np.array([0.3, -0.2, 5.0, 0.4])
    numeric = central_jacobian(lambda y: np.array(inertial_velocity(y[0], y[1], y[3])), x)
    np.testing.assert_allclose(inertial_velocity_jac(0.3, -0.2, 0.4), numeric, atol=1e-9)

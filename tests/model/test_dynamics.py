"""Equations of motion: Jacobian, validation, and consistency between the aerodynamic models."""

import numpy as np
import pytest

import flapping
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
])
def test_bad_arguments_raise(insect, kwargs, match):
    with pytest.raises(ValueError, match=match):
        LongitudinalDynamics(insect, **kwargs)


def test_too_heavy_insect_cannot_trim():
    heavy = flapping.hawkmoth(mass=0.05)
    with pytest.raises(ValueError, match="weight"):
        LongitudinalDynamics(heavy)


def test_reversed_flow_fraction_grows_with_speed_and_vanishes_at_rest():
    from flapping.model.kinematics import reversed_flow_fraction

    h = flapping.hawkmoth()
    r = h.r2 * h.semi_span
    fracs = [reversed_flow_fraction(r, u, h.stroke_amplitude, h.frequency) for u in (0.0, 0.1, 0.5)]
    assert fracs[0] == 0.0 < fracs[1] < fracs[2] < 0.5


def test_root_singular_planform_needs_no_damping_integral_without_damping():
    # p < 3/4 makes I_04 (rotational damping) diverge: allowed without damping, refused with it.
    r1, r2 = 0.3, 0.4  # beta shape p ~ 0.6
    light = flapping.hawkmoth(r1=r1, r2=r2, mu1=0.0, mu2=0.0)
    assert flapping.model.morphology.beta_shape_parameters(r1, r2)[0] < 0.75
    from flapping.model.derivatives import aero_constants

    assert aero_constants(light).Knu == 0.0
    with pytest.raises(ValueError, match="mu1 = mu2 = 0"):
        aero_constants(flapping.hawkmoth(r1=r1, r2=r2))


def test_stability_derivatives_reject_bad_alpha_m():
    from flapping.model.derivatives import stability_derivatives

    h = flapping.hawkmoth()
    for bad in (float("nan"), -3.0, 2.0):
        with pytest.raises(ValueError, match="alpha_m"):
            stability_derivatives(h, [0.0], alpha_m=bad)

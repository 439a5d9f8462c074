"""Wings of mass: the generated equations against laws that do not use them.

With no air and no gravity the insect (body and wings) is a free system: its linear momentum and its
angular momentum about a fixed point stay constant, whatever the wings do. The momenta are computed
here from point masses placed by hand (two per wing, matching the wing's mass moments), not from
the mass matrix of :mod:`flapping.model.inertia`, so the check is independent of the derivation.
"""

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import flapping
from flapping import hawkmoth
from flapping.model import inertia_derivation
from flapping.model.dynamics import LongitudinalDynamics, inertial_velocity
from flapping.model.inertia import WingInertia, stroke_phase

GENERATED = Path(flapping.__file__).parent / "model" / "_inertia_generated.py"
MOTH = hawkmoth(wing_mass=4.7e-5, hinge_offset=2e-3, hinge_height=4e-3, stroke_mean=0.1)


def test_the_generated_code_is_what_the_derivation_prints():
    assert GENERATED.read_text() == inertia_derivation.generate_source()


def _free(insect):
    """The insect's wing inertia with gravity off (air is switched off by passing no loads)."""
    k = WingInertia.of(insect).constants
    return WingInertia(k[:-1] + (0.0,))


def _integrate(insect, x0, periods=3.0):
    inertia = _free(insect)
    amplitude = insect.stroke_amplitude

    def f(t, y):
        acc = inertia.accelerations(stroke_phase(insect, t, amplitude), y[:4], (0.0, 0.0, 0.0))
        return [*acc, y[2], *inertial_velocity(y[0], y[1], y[3])]

    t = np.linspace(0.0, periods * insect.period, 301)
    sol = solve_ivp(f, (0.0, t[-1]), [*x0, 0.0, 0.0], t_eval=t, rtol=1e-12, atol=1e-14,
                    method="DOP853")
    return sol.t, sol.y


def _particles(insect):
    """(mass, span position) of two equal point masses per wing with the wing's m, A1/2, A2/2."""
    a1, a2 = insect.wing_mass_moments
    mean = a1 / (2.0 * insect.wing_mass)
    spread = math.sqrt(a2 / (2.0 * insect.wing_mass) - mean**2)
    return [(insect.wing_mass / 2.0, mean - spread), (insect.wing_mass / 2.0, mean + spread)]


def _momenta(insect, t, y):
    """Linear momentum (forward, down) and angular momentum about the inertial origin."""
    u, w, q, theta, xe, ze = y
    c, s = math.cos(theta), math.sin(theta)
    m_body = insect.mass - 2.0 * insect.wing_mass
    points = [(m_body, 0.0, 0.0, 0.0, 0.0)]  # mass, body-axis x, z and their rates
    phi, phi_dot, _ = stroke_phase(insect, t, insect.stroke_amplitude)
    for mass, rho in _particles(insect):
        x = insect.hinge_offset + rho * math.sin(phi)
        points += [(mass, x, -insect.hinge_height, rho * math.cos(phi) * phi_dot, 0.0)] * 2
    p = np.zeros(2)
    h = insect.pitch_inertia * q
    for mass, x, z, x_rate, z_rate in points:
        vx, vz = u + q * z + x_rate, w - q * x + z_rate   # V + omega x r + r_dot, body axes
        v = np.array([vx * c + vz * s, -vx * s + vz * c])
        r = np.array([xe + x * c + z * s, ze - x * s + z * c])
        p += mass * v
        h += mass * (r[1] * v[0] - r[0] * v[1])
    return p, h


@pytest.mark.parametrize("insect", [MOTH, hawkmoth(wing_mass=4.7e-5)], ids=["off-CG", "at-CG"])
def test_without_air_and_gravity_both_momenta_are_conserved(insect):
    t, y = _integrate(insect, [0.3, -0.1, 2.0, 0.2])
    momenta = [_momenta(insect, ti, yi) for ti, yi in zip(t, y.T, strict=True)]
    p = np.array([m[0] for m in momenta])
    h = np.array([m[1] for m in momenta])
    # rtol 1e-12 over three wingbeats: the momenta drift by ~1e-11 of their size at most.
    assert np.max(np.abs(p - p[0])) < 1e-9 * np.max(np.abs(p))
    assert np.max(np.abs(h - h[0])) < 1e-9 * np.max(np.abs(h))


def test_the_body_recoils_exactly_as_the_wings_momentum_demands():
    # Hinge at the centre of gravity, from rest: no pitch, and m u + A1 cos(phi) phi_dot = const.
    insect = hawkmoth(wing_mass=4.7e-5)
    t, y = _integrate(insect, [0.0, 0.0, 0.0, 0.0])
    a1, _ = insect.wing_mass_moments
    wings = np.array([a1 * math.cos(p[0]) * p[1] for p in
                      (stroke_phase(insect, ti, insect.stroke_amplitude) for ti in t)])
    assert np.max(np.abs(y[2])) < 1e-12
    np.testing.assert_allclose(insect.mass * y[0] + wings, wings[0], atol=1e-12 * np.max(wings))
    omega = 2.0 * math.pi * insect.frequency
    # The momentum argument's amplitude, A1 Phi omega / m: 0.24 m/s for the hawkmoth.
    assert np.ptp(y[0]) / 2.0 == pytest.approx(a1 * insect.stroke_amplitude * omega / insect.mass,
                                               rel=1e-6)


def test_massless_wings_through_the_generated_equations_give_eq_2():
    # The generated path with m_w = 0 against the paper's eq. (2), to rounding.
    model = LongitudinalDynamics(hawkmoth(hinge_height=4e-3, hinge_offset=2e-3))
    massless = WingInertia.of(hawkmoth(wing_mass=1e-9, hinge_height=4e-3, hinge_offset=2e-3))
    k = list(massless.constants)
    k[2:5] = [0.0, 0.0, 0.0]
    inertia = WingInertia(tuple(k))
    rng = np.random.default_rng(1)
    for _ in range(20):
        t, x = rng.uniform(0, model.period), rng.normal(size=4) * [0.5, 0.5, 5.0, 0.5]
        loads = model.loads(t, x)
        acc = inertia.accelerations(stroke_phase(model.insect, t, model.amplitude), x, loads)
        np.testing.assert_allclose(acc, model.rhs(t, x)[:3], rtol=1e-13, atol=1e-12)


@pytest.mark.parametrize("aerodynamics", ["linear", "small-angle"])
def test_jacobian_and_stroke_sensitivities_match_finite_differences(aerodynamics):
    model = LongitudinalDynamics(MOTH, aerodynamics=aerodynamics)
    t, x, h = 0.0123, np.array([0.1, -0.2, 0.5, 0.3]), 1e-6
    fd = np.array([(model.rhs(t, x + e * h) - model.rhs(t, x - e * h)) / (2 * h)
                   for e in np.eye(4)]).T
    # Central differences: error ~h^2 |f'''| and rounding ~eps |f| / h: 1e-8 relative is ample.
    np.testing.assert_allclose(model.jac(t, x), fd, rtol=1e-7, atol=1e-8 * np.abs(fd).max())
    amp = model.amplitude
    fd_amp = (model.rhs(t, x, amplitude=amp + h) - model.rhs(t, x, amplitude=amp - h)) / (2 * h)
    np.testing.assert_allclose(model.amplitude_jac(t, x)[:, 0], fd_amp, rtol=1e-7, atol=1e-6)
    bar = MOTH.stroke_mean
    fd_bar = (model.with_stroke_mean(bar + h).rhs(t, x)
              - model.with_stroke_mean(bar - h).rhs(t, x)) / (2 * h)
    np.testing.assert_allclose(model.stroke_mean_jac(t, x)[:, 0], fd_bar, rtol=1e-7, atol=1e-6)


def test_zero_wing_mass_leaves_the_paper_model_untouched():
    plain, zero = hawkmoth(hinge_height=3e-3), hawkmoth(hinge_height=3e-3, wing_mass=0.0)
    a, b = LongitudinalDynamics(plain), LongitudinalDynamics(zero)
    x = np.array([0.1, -0.2, 0.5, 0.3])
    assert np.array_equal(a.rhs(0.01, x), b.rhs(0.01, x))
    assert np.array_equal(a.jac(0.01, x), b.jac(0.01, x))


@pytest.mark.parametrize(("changes", "match"), [
    ({"wing_mass": -1e-6}, "wing_mass"),
    ({"wing_mass": 1e-3}, "below half of `mass`"),
    ({"wing_mass": 1e-5, "wing_mass_r1": 0.6, "wing_mass_r2": 0.5}, "must not exceed"),
    ({"wing_mass": 1e-5, "wing_mass_r1": 0.0}, "wing_mass_r1"),
    ({"wing_mass": 1e-5, "wing_mass_r2": 1.5}, "wing_mass_r2"),
])
def test_bad_wing_mass_is_refused_by_name(changes, match):
    with pytest.raises(ValueError, match=match):
        hawkmoth(**changes)


def test_default_mass_radii_are_the_areas():
    moth = hawkmoth(wing_mass=4.7e-5)
    assert moth.wing_mass_radii == (moth.r1, moth.r2)
    a1, a2 = moth.wing_mass_moments
    assert a1 == pytest.approx(2 * 4.7e-5 * moth.r1 * moth.semi_span)
    assert a2 == pytest.approx(2 * 4.7e-5 * (moth.r2 * moth.semi_span) ** 2)

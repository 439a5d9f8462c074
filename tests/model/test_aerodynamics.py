"""Tests of the nonlinear blade-element model (flapping.model.aerodynamics), paper Sec. II, eqs. (3)-(23).

Each test states one property that must hold; tolerances are set by the method's accuracy.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import integrate

from flapping.model.aerodynamics import (
    VARIANTS,
    BladeElementModel,
    aero_constants,
    section_loads,
    span_quadrature,
    trim_angle_of_attack,
    wing_loads,
)
from flapping.model.kinematics import flapping_angle, flapping_rate, stroke_sign
from flapping.model.morphology import hawkmoth

# Roundoff of a sum of O(100) terms of mixed sign, relative to the largest load: the accuracy of a
# quadrature that is exact for the integrand.
ROUNDOFF = 1e-12


@pytest.fixture(scope="module")
def moth():
    return hawkmoth()


@pytest.fixture(scope="module")
def alpha_trim(moth):
    return trim_angle_of_attack(moth)


def phase_grid(insect, n=4096):
    """Uniform phases over one period: the trapezoidal rule on it is spectrally accurate for
    smooth periodic integrands and exact for trigonometric polynomials of degree < n."""
    return np.arange(n) * insect.period / n


def kinematics_at(insect, t):
    a, f = insect.stroke_amplitude, insect.frequency
    return float(flapping_angle(t, a, f)), float(flapping_rate(t, a, f)), float(stroke_sign(t, f))


# ----------------------------------------------------------------------------- span quadrature
@pytest.mark.parametrize("n", range(5))
@pytest.mark.parametrize("m", range(4))
def test_quadrature_reproduces_closed_form_span_integrals(moth, m, n):
    # Gauss-Jacobi with weight c^n integrates r^m exactly (m < 2 n_nodes): only rounding remains.
    quad = span_quadrature(moth, 8)
    assert quad.integrate(n, quad.nodes[n] ** m) == pytest.approx(
        moth.span_integral(m, n), rel=1e-12)


def test_quadrature_rules_are_cached_per_shape(moth):
    assert span_quadrature(moth, 16) is span_quadrature(hawkmoth(mass=2e-3), 16)
    assert span_quadrature(moth, 16) is not span_quadrature(moth, 17)


def reference_loads(insect, alpha_m, t, state, variant):
    """(X, Z, M) by adaptive quadrature of section_loads over the span (independent of the
    Gauss-Jacobi rules): r = R v**g removes the root singularity of c(r)**4; the kink of |U| at
    U = 0 is passed to QUADPACK as a break point."""
    phi, phi_dot, s = kinematics_at(insect, t)
    R = insect.semi_span
    g = 1.0 / (1.0 + 4.0 * (insect.beta_p - 1.0))
    kink = -state[0] * math.cos(phi) / phi_dot
    points = [(kink / R) ** (1.0 / g)] if 0.0 < kink < R else None

    def integrand(v, i):
        r = R * v**g
        load = section_loads(r, insect.chord(r), phi, phi_dot, s, *state, alpha_m, insect,
                             variant=variant)[i]
        return 2.0 * load * R * g * v ** (g - 1.0)

    return np.array([integrate.quad(integrand, 0.0, 1.0, args=(i,), points=points, limit=400,
                                    epsabs=0.0, epsrel=1e-13)[0] for i in range(3)])


STATES = [  # (t/T, (u, w, q)): mid-stroke, U changing sign in span, near reversal, fast descent
    (0.30, (0.4, -0.3, 20.0)),
    (0.70, (0.4, 0.1, -10.0)),
    (0.47, (-0.5, 0.2, 5.0)),
    (0.03, (2.0, 0.2, 5.0)),
    (0.80, (-3.0, 1.5, -30.0)),
]


@pytest.mark.parametrize("phase, state", STATES)
def test_small_angle_span_integral_is_exact_at_any_state(phase, state):
    # The small-angle integrand is polynomial in r apart from the kink of |U|, handled in closed
    # form: even 4 nodes must agree with adaptive quadrature to its tolerance (1e-13 asked; 1e-11
    # allowed for QUADPACK's own error on the singular, kinked integrand).
    insect = hawkmoth(hinge_offset=2e-3)
    alpha_m = trim_angle_of_attack(insect)
    t = phase * insect.period
    reference = reference_loads(insect, alpha_m, t, state, "small-angle")
    for n_nodes in (4, 32):
        loads = BladeElementModel(insect, alpha_m, variant="small-angle", n_nodes=n_nodes).loads(
            t, *state)
        np.testing.assert_allclose(loads, reference, rtol=0, atol=1e-11 * np.abs(reference).max())


@pytest.mark.parametrize("phase, state", STATES)
def test_exact_variant_quadrature_converges(phase, state):
    # The exact integrand is smooth but steep near U = 0 (scale |w_eff/phi_dot|): the error must
    # fall as n_nodes grows, and 128 nodes must reach the adaptive reference.
    insect = hawkmoth(hinge_offset=2e-3)
    alpha_m = trim_angle_of_attack(insect)
    t = phase * insect.period
    reference = reference_loads(insect, alpha_m, t, state, "exact")
    scale = np.abs(reference).max()
    errors = [np.abs(BladeElementModel(insect, alpha_m, variant="exact", n_nodes=n).loads(
        t, *state) - reference).max() / scale for n in (4, 16, 64, 128)]
    assert errors[-1] < 1e-9
    for coarse, fine in zip(errors, errors[1:], strict=False):     # monotone until rounding (1e-12) is reached
        assert fine <= max(coarse, 1e-12)
    assert errors[2] < max(1e-2 * errors[0], 1e-12)


# ----------------------------------------------------------------------------- trim, eq. (40)
def test_hawkmoth_trim_angle(moth, alpha_trim):
    # eq. (40) with A from eq. (4) (pair aspect ratio 2R^2/S = 5.68 -> A = 2.225).
    assert moth.lift_slope == pytest.approx(2.22497, rel=1e-5)
    ratio = moth.weight * moth.period**2 / (
        math.pi**2 * moth.air_density * moth.lift_slope * moth.stroke_amplitude**2
        * moth.span_integral(2, 1))
    assert math.sin(2.0 * alpha_trim) == pytest.approx(ratio, rel=1e-14)
    assert 0.0 < alpha_trim <= math.pi / 4


@pytest.mark.parametrize("variant", VARIANTS)
def test_mean_vertical_force_at_trim_equals_weight(moth, alpha_trim, variant):
    # At zero state both variants give Z = -K21 phi_dot^2 sin(2 alpha_m); its mean over the
    # 4096-point grid is exact (trigonometric polynomial), the span quadrature exact: rounding only.
    model = BladeElementModel(moth, alpha_trim, variant=variant)
    loads = model.loads(phase_grid(moth), 0.0, 0.0, 0.0)
    assert loads[1].mean() == pytest.approx(-moth.weight, rel=ROUNDOFF)


@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("hinge_offset", [0.0, 3e-3, -2e-3])
def test_mean_horizontal_force_and_moment_at_zero_state(variant, hinge_offset):
    # Fore-aft symmetry of the stroke: at zero state the second half-stroke is the mirror image
    # x -> -x of the first (phi -> -phi, phi_dot -> -phi_dot, alpha_g -> pi - alpha_g), so
    # X(t + T/2) = -X(t) and the moment about the hinge line flips too: mean X = 0 and
    # mean M = -x_h mean Z = x_h m g (only the lift acting a distance x_h ahead of the CG remains).
    insect = hawkmoth(hinge_offset=hinge_offset)
    alpha_m = trim_angle_of_attack(insect)
    loads = BladeElementModel(insect, alpha_m, variant=variant).loads(phase_grid(insect), 0.0,
                                                                      0.0, 0.0)
    scale = np.abs(loads).max(axis=1)
    assert abs(loads[0].mean()) < ROUNDOFF * scale[0]
    assert loads[2].mean() == pytest.approx(hinge_offset * insect.weight,
                                            abs=ROUNDOFF * scale[2])
    assert abs(np.abs(loads[0]).mean()) > 0.01 * insect.weight   # X itself is not zero


# ----------------------------------------------------------------------------- symmetries
@settings(max_examples=40, deadline=None)
@given(phase=st.floats(0.01, 0.49), u=st.floats(-2, 2), w=st.floats(-2, 2),
       q=st.floats(-40, 40), variant=st.sampled_from(VARIANTS))
def test_fore_aft_mirror_symmetry(phase, u, w, q, variant):
    # With the CG under the hinge line (x_h = 0), reflecting x -> -x maps the motion at t with
    # state (u, w, q) onto the motion at t + T/2 with (-u, w, -q): phi, phi_dot, U, Omega and
    # Gamma change sign, w_eff = w - q r sin(phi) does not, alpha_g -> pi - alpha_g. Hence
    # (X, Z, M)(t + T/2; -u, w, -q) = (-X, Z, -M)(t; u, w, q), exactly (same span nodes).
    insect = hawkmoth()
    model = BladeElementModel(insect, trim_angle_of_attack(insect), variant=variant)
    t = phase * insect.period
    first = model.loads(t, u, w, q)
    second = model.loads(t + 0.5 * insect.period, -u, w, -q)
    scale = np.abs(first).max() + 1e-30
    np.testing.assert_allclose(second, first * np.array([-1.0, 1.0, -1.0]), rtol=0,
                               atol=1e-11 * scale)


@pytest.mark.parametrize("variant", VARIANTS)
def test_mirror_symmetry_with_hinge_offset(variant):
    # With x_h != 0 and q = 0, the mirror keeps w_eff = w: Z is unchanged, X flips, and the
    # moments about the hinge line flip, so M(t) + M(t + T/2; -u) = -2 x_h Z (the lift's arm x_h).
    x_h = 4e-3
    insect = hawkmoth(hinge_offset=x_h)
    model = BladeElementModel(insect, trim_angle_of_attack(insect), variant=variant)
    t = 0.2 * insect.period
    first = model.loads(t, 0.7, -0.4, 0.0)
    second = model.loads(t + 0.5 * insect.period, -0.7, -0.4, 0.0)
    assert second[0] == pytest.approx(-first[0], rel=1e-12)
    assert second[1] == pytest.approx(first[1], rel=1e-12)
    assert first[2] + second[2] == pytest.approx(-2.0 * x_h * first[1], rel=1e-10)


# ----------------------------------------------------------------------------- variants
@pytest.mark.parametrize("s, sign_u", [(1, 1), (-1, -1), (1, -1), (-1, 1)])
def test_exact_and_small_angle_differ_at_second_order(moth, alpha_trim, s, sign_u):
    # Section loads with w_eff/|U| = eps: exact - small-angle = O(eps^2), so halving eps divides
    # the difference by 4 (to O(eps)), and it is small next to the first-order term. Holds on
    # both strokes and also where U opposes the stroke (s != sign U, near reversal with u != 0).
    r, chord, phi = 0.03, moth.chord(0.03), 0.4
    u, q = 0.3 * sign_u, 15.0
    phi_dot = (sign_u * 5.0 - u * math.cos(phi)) / r          # U = 5 sign_u m/s
    U = r * phi_dot + u * math.cos(phi)
    differences = []
    for eps in (2e-2, 1e-2, 5e-3):
        w = eps * abs(U) + q * (r * math.sin(phi) + moth.hinge_offset)    # w_eff = eps |U|
        exact, small = (np.array(section_loads(r, chord, phi, phi_dot, s, u, w, q, alpha_trim,
                                               moth, variant=v)) for v in ("exact", "small-angle"))
        differences.append(exact - small)
        first_order = np.array(section_loads(r, chord, phi, phi_dot, s, u, w, q, alpha_trim, moth,
                                             variant="small-angle")) - np.array(section_loads(
            r, chord, phi, phi_dot, s, u, w - eps * abs(U), q, alpha_trim, moth,
            variant="small-angle"))
        assert np.all(np.abs(exact - small) < 0.05 * np.abs(first_order))
    ratios = np.array(differences[:-1]) / np.array(differences[1:])
    np.testing.assert_allclose(ratios, 4.0, rtol=0.05)


def test_variants_coincide_without_induced_flow(moth, alpha_trim):
    # With w_eff = 0 everywhere (w = q = 0) the inflow angle is exactly 0 or pi: identical loads.
    t = phase_grid(moth, 64)
    small = BladeElementModel(moth, alpha_trim, variant="small-angle").loads(t, 0.6, 0.0, 0.0)
    exact = BladeElementModel(moth, alpha_trim, variant="exact", n_nodes=128).loads(t, 0.6, 0.0,
                                                                                  0.0)
    # The exact variant integrates the kink of |U| by plain quadrature: ~1e-7 at 128 nodes.
    np.testing.assert_allclose(exact, small, rtol=0, atol=1e-6 * np.abs(small).max())


@pytest.mark.parametrize("variant", VARIANTS)
def test_zero_state_derivatives_match_paper_closed_forms(moth, alpha_trim, variant):
    # First-order terms of eqs. (25)-(26) integrated: X_u = -2 rho A sin^2(alpha_m) cos^2(phi)
    # |phi_dot| I11 and Z_w = -rho A cos^2(alpha_m) |phi_dot| I11. Central differences with h =
    # 1e-5 m/s: truncation O(h^2) ~ 1e-10 relative.
    t = 0.3 * moth.period
    phi, phi_dot, _ = kinematics_at(moth, t)
    model = BladeElementModel(moth, alpha_trim, variant=variant)
    h = 1e-5
    x_u = (model.loads(t, h, 0.0, 0.0)[0] - model.loads(t, -h, 0.0, 0.0)[0]) / (2 * h)
    z_w = (model.loads(t, 0.0, h, 0.0)[1] - model.loads(t, 0.0, -h, 0.0)[1]) / (2 * h)
    rho_a_i11 = moth.air_density * moth.lift_slope * moth.span_integral(1, 1) * abs(phi_dot)
    assert x_u == pytest.approx(-2 * rho_a_i11 * math.sin(alpha_trim) ** 2 * math.cos(phi) ** 2,
                                rel=1e-7)
    assert z_w == pytest.approx(-rho_a_i11 * math.cos(alpha_trim) ** 2, rel=1e-7)


# ----------------------------------------------------------------------------- moment
@pytest.mark.parametrize("variant", VARIANTS)
@pytest.mark.parametrize("q", [-25.0, -3.0, 3.0, 25.0])
def test_rotational_damping_torque_opposes_pitch_rate(variant, q):
    # Berman & Wang: M_damping = 2 int tau cos(phi) dr = -(pi/16) rho I04 (mu1 f + mu2 |Omega|)
    # Omega cos(phi), Omega = q cos(phi): the difference between mu = 0.2 and mu = 0 must equal it
    # and have the sign of -q.
    insect = hawkmoth()
    undamped = insect.with_(mu1=0.0, mu2=0.0)
    alpha_m = trim_angle_of_attack(insect)
    t = 0.15 * insect.period
    phi, _, _ = kinematics_at(insect, t)
    state = (0.2, -0.1, q)
    damping = (BladeElementModel(insect, alpha_m, variant=variant).loads(t, *state)[2]
               - BladeElementModel(undamped, alpha_m, variant=variant).loads(t, *state)[2])
    omega = q * math.cos(phi)
    expected = -(math.pi / 16) * insect.air_density * insect.span_integral(0, 4) * (
        insect.mu1 * insect.frequency + insect.mu2 * abs(omega)) * omega * math.cos(phi)
    assert math.copysign(1.0, damping) == -math.copysign(1.0, q)
    assert damping == pytest.approx(expected, rel=1e-9)


@pytest.mark.parametrize("variant", VARIANTS)
def test_cycle_mean_pitch_damping_is_negative(moth, alpha_trim, variant):
    # The mean of dM/dq over a cycle at zero state is negative (aerodynamic and rotational
    # damping); a sign error in w_eff, x_cp or tau would flip or spoil it.
    model = BladeElementModel(moth, alpha_trim, variant=variant)
    t = phase_grid(moth, 256)
    h = 1e-4
    m_q = (model.loads(t, 0.0, 0.0, h)[2] - model.loads(t, 0.0, 0.0, -h)[2]) / (2 * h)
    assert m_q.mean() < 0.0


def test_section_loads_at_zero_state_by_hand(moth, alpha_trim):
    # Forward stroke, u = w = q = 0 (eqs. 18-19 with w_eff = 0, Omega = 0): F_z = -rho A c U^2
    # sin(2 alpha_m)/2, F_x = -rho A c U^2 sin^2(alpha_m) cos(phi), both acting at the centre of
    # pressure x_cp = x_h + r sin(phi) - x_hat c cos(alpha_m) cos(phi), z_cp = x_hat c
    # sin(alpha_m), so M' = z_cp F_x - x_cp F_z (eqs. 20-23).
    r, c, phi, phi_dot = 0.025, 0.02, 0.5, 150.0
    fx, fz, m = section_loads(r, c, phi, phi_dot, 1, 0.0, 0.0, 0.0, alpha_trim, moth)
    x_cp = moth.hinge_offset + r * math.sin(phi) - moth.center_of_pressure * c * math.cos(
        alpha_trim) * math.cos(phi)
    z_cp = moth.center_of_pressure * c * math.sin(alpha_trim)
    assert float(m) == pytest.approx(z_cp * float(fx) - x_cp * float(fz), rel=1e-14)
    U = r * phi_dot
    rho_a_c = moth.air_density * moth.lift_slope * c
    assert float(fz) == pytest.approx(-0.5 * rho_a_c * U**2 * math.sin(2 * alpha_trim), rel=1e-14)
    assert float(fx) == pytest.approx(-rho_a_c * U**2 * math.sin(alpha_trim) ** 2 * math.cos(phi),
                                      rel=1e-14)


# ----------------------------------------------------------------------------- API consistency
@pytest.mark.parametrize("variant", VARIANTS)
def test_wing_loads_matches_model_and_array_evaluation(moth, alpha_trim, variant):
    model = BladeElementModel(moth, alpha_trim, variant=variant)
    t = np.array([0.001, 0.013, 0.021, 0.034])
    state = (0.3, -0.2, 7.0)
    batch = model.loads(t, *state)
    assert batch.shape == (3, 4)
    for k, tk in enumerate(t):
        one = wing_loads(float(tk), state + (1.0,), moth, alpha_trim, variant=variant)
        np.testing.assert_array_equal(one, batch[:, k])
        np.testing.assert_array_equal(one, model.loads(float(tk), *state))


def test_stroke_sign_override_at_reversal(moth, alpha_trim):
    # At t = T/2 phi_dot = 0 and the stroke sign from t is +1 (the forward stroke starts); the
    # override selects the left limit. With u != 0 (w = q = 0) the wing moves at U = u cos(phi)
    # pitched alpha_m or pi - alpha_m: the lift -rho A c U|U| sin(2 alpha_g)/2 flips sign with s,
    # the drag (sin^2 alpha_g) does not. The default equals the explicit forward sign.
    t = 0.5 * moth.period
    state = (0.5, 0.0, 0.0)
    forward = wing_loads(t, state, moth, alpha_trim, stroke_sign=1.0)
    backward = wing_loads(t, state, moth, alpha_trim, stroke_sign=-1.0)
    np.testing.assert_array_equal(wing_loads(t, state, moth, alpha_trim), forward)
    assert forward[1] == pytest.approx(-backward[1], rel=1e-12)
    assert forward[0] == pytest.approx(backward[0], rel=1e-12)
    # U > 0 with s = +1 is a forward stroke (lift up, Z < 0); with s = -1 the wing moves
    # trailing edge first and its lift points down.
    assert forward[1] < 0.0 < backward[1]
    assert stroke_sign(t, moth.frequency) == 1.0


def test_default_stroke_sign_agrees_with_kinematics(moth, alpha_trim):
    model = BladeElementModel(moth, alpha_trim)
    t = phase_grid(moth, 37) + 0.3 * moth.period
    signs = stroke_sign(t, moth.frequency)
    np.testing.assert_array_equal(model.loads(t, 0.4, 0.2, 3.0),
                                  model.loads(t, 0.4, 0.2, 3.0, s=signs))


# ----------------------------------------------------------------------------- validation
def test_trim_raises_for_a_body_too_heavy_for_its_wings():
    heavy = hawkmoth(mass=20e-3)
    with pytest.raises(ValueError, match=r"weight .* exceeds the largest mean lift"):
        trim_angle_of_attack(heavy)
    # ... or for the hawkmoth at a small amplitude: max mean lift scales as Phi^2.
    with pytest.raises(ValueError, match="sin\\(2 alpha_m\\)"):
        trim_angle_of_attack(hawkmoth(), amplitude=math.radians(15))


@pytest.mark.parametrize("amplitude", [0.0, -0.1, math.pi / 2 + 1e-9, math.nan, math.inf])
def test_trim_rejects_bad_amplitude(moth, amplitude):
    with pytest.raises(ValueError, match="amplitude"):
        trim_angle_of_attack(moth, amplitude)


def test_trim_at_larger_amplitude_is_smaller(moth, alpha_trim):
    # sin(2 alpha_m) scales as 1/Phi^2.
    alpha = trim_angle_of_attack(moth, amplitude=math.pi / 2)
    assert math.sin(2 * alpha) == pytest.approx(
        math.sin(2 * alpha_trim) * (moth.stroke_amplitude / (math.pi / 2)) ** 2, rel=1e-14)


@pytest.mark.parametrize("variant", ["linear", "Exact", "", None])
def test_unknown_variant_is_named(moth, alpha_trim, variant):
    with pytest.raises(ValueError, match=repr(variant).replace("(", r"\(")):
        wing_loads(0.01, (0, 0, 0), moth, alpha_trim, variant=variant)


@pytest.mark.parametrize("n_nodes", [1, 0, -3, 2.5, True])
def test_bad_node_count(moth, alpha_trim, n_nodes):
    with pytest.raises(ValueError, match="n_nodes"):
        wing_loads(0.01, (0, 0, 0), moth, alpha_trim, n_nodes=n_nodes)


@settings(max_examples=30, deadline=None)
@given(index=st.integers(0, 4), bad=st.sampled_from([math.nan, math.inf, -math.inf]))
def test_non_finite_time_or_state_raises(index, bad):
    insect = hawkmoth()
    alpha_m = trim_angle_of_attack(insect)
    values = [0.01, 0.1, 0.2, 3.0, 0.05]        # t, u, w, q, theta
    values[index] = bad
    with pytest.raises(ValueError, match="finite"):
        wing_loads(values[0], tuple(values[1:]), insect, alpha_m)
    if index < 4:   # the array path validates too
        with pytest.raises(ValueError, match="finite"):
            BladeElementModel(insect, alpha_m).loads(*(np.array([v, v]) for v in values[:4]))


@pytest.mark.parametrize("kwargs, match", [
    (dict(stroke_sign=0.0), "stroke sign"),
    (dict(stroke_sign=2.0), "stroke sign"),
    (dict(amplitude=2.0), "amplitude"),
])
def test_other_bad_inputs(moth, alpha_trim, kwargs, match):
    with pytest.raises(ValueError, match=match):
        wing_loads(0.01, (0, 0, 0), moth, alpha_trim, **kwargs)


@pytest.mark.parametrize("alpha_m", [-0.1, 2.0, math.nan, 0.0, math.pi / 2, True, "0.3"])
def test_bad_alpha_m(moth, alpha_m):
    # 0 and pi/2 were accepted here but refused by LongitudinalDynamics: one range now, (0, pi/2).
    with pytest.raises(ValueError, match=r"`alpha_m` must be .*\(0, pi/2\) rad"):
        BladeElementModel(moth, alpha_m)
    with pytest.raises(ValueError, match="`alpha_m`"):
        section_loads(0.01, 0.01, 0.0, 100.0, 1.0, 0.0, 0.0, 0.0, alpha_m, moth)


def test_wing_loads_refuses_a_bool_alpha_m_even_when_a_model_is_cached(moth):
    # The model cache is keyed on its arguments and True == 1.0: validation comes first.
    wing_loads(0.01, (0.0, 0.0, 0.0), moth, 1.0)
    with pytest.raises(ValueError, match="`alpha_m`"):
        wing_loads(0.01, (0.0, 0.0, 0.0), moth, True)


def test_numpy_integer_node_count_is_accepted(moth, alpha_trim):
    model = BladeElementModel(moth, alpha_trim, n_nodes=np.int64(12))
    assert type(model.n_nodes) is int and model.n_nodes == 12
    np.testing.assert_array_equal(model.loads(0.003, 0.1, 0.2, 3.0),
                                  BladeElementModel(moth, alpha_trim, n_nodes=12).loads(
                                      0.003, 0.1, 0.2, 3.0))
    assert span_quadrature(moth, np.int32(12)) is span_quadrature(moth, 12)
    with pytest.raises(ValueError, match="`n_nodes`"):
        span_quadrature(moth, 12.0)


def test_numpy_scalar_arguments_give_the_float64_loads(moth, alpha_trim):
    t, state = np.float32(0.004), (0.1, -0.2, 3.0)
    ref = wing_loads(float(t), state, moth, alpha_trim, amplitude=1.0)
    got = wing_loads(t, (np.float64(0.1), np.float64(-0.2), np.int64(3)), moth,
                     np.float64(alpha_trim), amplitude=np.float32(1.0))
    assert got.dtype == np.float64
    np.testing.assert_array_equal(got, ref)
    model = BladeElementModel(moth, np.float32(0.3), amplitude=np.int64(1))
    assert type(model.alpha_m) is float and type(model.amplitude) is float
    assert model == BladeElementModel(moth, float(np.float32(0.3)), amplitude=1.0)


@pytest.mark.parametrize("kwargs, name", [
    (dict(insect="hawkmoth"), "insect"),
    (dict(variant=("exact",)), "variant"),
    (dict(amplitude=True), "amplitude"),
])
def test_model_arguments_are_named(moth, alpha_trim, kwargs, name):
    args = dict(insect=moth, alpha_m=alpha_trim) | kwargs
    with pytest.raises(ValueError, match=f"`{name}`"):
        BladeElementModel(**args)


@pytest.mark.parametrize("name, value", [("r", math.nan), ("phi_dot", "1"), ("q", [True])])
def test_section_loads_name_the_bad_input(moth, alpha_trim, name, value):
    args = dict(r=0.01, chord=0.01, phi=0.0, phi_dot=100.0, s=1.0, u=0.0, w=0.0, q=0.0) | {
        name: value}
    with pytest.raises(ValueError, match=f"`{name}`"):
        section_loads(*args.values(), alpha_trim, moth)


def test_bad_state_length(moth, alpha_trim):
    with pytest.raises(ValueError, match="state"):
        wing_loads(0.01, (0.0, 0.0), moth, alpha_trim)


def test_divergent_planform_is_rejected():
    # r1 = 0.35, r2 = 0.45 gives p = 0.645 < 2/3: c(r)^3 and c(r)^4 ~ r^(n(p-1)) are not
    # integrable at the root, so the moment of the rotational lift about the centre of pressure
    # and the damping torque of eq. (23) are infinite; without those terms the model is finite.
    insect = hawkmoth(r1=0.35, r2=0.45)
    assert 3 * (insect.beta_p - 1) <= -1 < 2 * (insect.beta_p - 1)
    with pytest.raises(ValueError, match="diverges"):
        BladeElementModel(insect, 0.3)
    BladeElementModel(insect.with_(mu1=0.0, mu2=0.0, center_of_pressure=0.0), 0.3)


def test_scalar_and_array_loads_agree_at_stroke_reversal():
    # The scalar fast path and the array path must pick the same half-stroke at reversal times,
    # where t * f rounds either side of the half-integer.
    import flapping
    from flapping.model.aerodynamics import BladeElementModel, trim_angle_of_attack

    insect = flapping.hawkmoth()
    model = BladeElementModel(insect, trim_angle_of_attack(insect), variant="exact")
    for k in range(-50, 50):
        for t in (k / insect.frequency, (k + 0.5) / insect.frequency):
            scalar = model.loads(float(t), 0.3, 0.1, 0.5)
            array = model.loads(np.array(t), 0.3, 0.1, 0.5)
            np.testing.assert_array_equal(scalar, np.asarray(array).reshape(3))


# ----------------------------------------------------------------------------- linearised loads
def test_k_constants_use_the_closed_form_span_integrals(moth):
    c = aero_constants(moth)
    assert c.K[(2, 1)] == pytest.approx(
        0.5 * moth.air_density * moth.lift_slope * 2 * moth.wing_area
        * moth.semi_span**2 * moth.r2**2, rel=1e-12)
    assert c.Knu == pytest.approx(math.pi / 16 * moth.air_density * moth.span_integral(0, 4))


def test_root_singular_planform_needs_no_damping_integral_without_damping():
    # p < 3/4 makes I_04 (rotational damping) diverge: allowed without damping, refused with it.
    r1, r2 = 0.3, 0.4  # beta shape p ~ 0.6
    light = hawkmoth(r1=r1, r2=r2, mu1=0.0, mu2=0.0)
    assert light.beta_p < 0.75
    assert aero_constants(light).Knu == 0.0
    with pytest.raises(ValueError, match="mu1 = mu2 = 0"):
        aero_constants(hawkmoth(r1=r1, r2=r2))


def test_linear_load_constants_are_the_span_integrals_exactly():
    # The span table is cached per planform: each constant must still be rho A I_mn / 2 and
    # rho pi (3/4 - x0_hat) I_mn to the last bit, for an insect that shares the planform.
    from flapping.model.aerodynamics import aero_constants

    insect = hawkmoth().with_(frequency=31.0, air_density=1.1, pitch_axis=0.1)
    c = aero_constants(insect)
    rho, A, kappa = insect.air_density, insect.lift_slope, 0.75 - insect.pitch_axis
    expected = {(m, n): insect.span_integral(m, n) for m in range(4) for n in range(1, 5)
                if m + 1 + n * (insect.beta_p - 1.0) > 0}
    assert list(c.K) == list(expected)
    assert all(c.K[k] == 0.5 * rho * A * v for k, v in expected.items())
    assert all(c.Krot[k] == rho * math.pi * kappa * v for k, v in expected.items())
    assert c.Knu == math.pi / 16.0 * rho * expected[(0, 4)] and c.f == 31.0

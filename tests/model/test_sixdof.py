"""The insect in six degrees of freedom (flapping.model.sixdof and its SymPy derivation).

Checked against what does not share its code: the planar model (hand-written equations and its
own inertia derivation), an independent NumPy reconstruction of the strip geometry and load
assembly (vectors and cross products strip by strip), mirror symmetry, and Newton-Euler for the
momenta of a body carrying point-mass wings (finite differences in time).
"""

import math
from pathlib import Path

import numpy as np
import pytest

import flapping
from flapping.model import sixdof_derivation
from flapping.model.aerodynamics import _lev_coefficients, span_quadrature
from flapping.model.dynamics import LongitudinalDynamics
from flapping.model.sixdof import LATERAL, LONGITUDINAL, SixDofDynamics, body_inertia

GENERATED = Path(sixdof_derivation.__file__).with_name("_sixdof_generated.py")
LATERAL_INERTIA = dict(roll_inertia=1.6e-8, yaw_inertia=2.1e-7, roll_yaw_product=3e-9)
GEOMETRIES = {
    "paper": {},
    "hinge": dict(hinge_offset=2e-3, hinge_height=3e-3, stroke_mean=0.1),
    "wings": dict(wing_mass=4.7e-5, hinge_offset=1e-3, hinge_height=-2e-3),
}


def moth(**changes):
    return flapping.hawkmoth().with_(**{**LATERAL_INERTIA, **changes})


def test_the_generated_code_is_what_the_derivation_prints():
    assert GENERATED.read_text() == sixdof_derivation.generate_source()


def test_the_generated_jacobians_are_what_the_derivation_prints():
    assert (GENERATED.with_name("_sixdof_jacobian_generated.py").read_text()
            == sixdof_derivation.generate_jacobian_source())


@pytest.mark.parametrize("variant", ["small-angle", "exact"])
def test_the_generated_section_law_is_the_models(variant):
    """The SymPy section law (for its derivatives) against aerodynamics._lev_coefficients, and
    its derivatives against central differences of that law."""
    from flapping.model import _sixdof_jacobian_generated as jac

    law = jac.section_small_angle if variant == "small-angle" else jac.section_exact
    rng = np.random.default_rng(11)
    out = np.empty(6)
    for _ in range(20):
        U, W = rng.normal(size=2) * 3.0
        s, am = rng.choice([-1.0, 1.0]), rng.uniform(0.2, 1.3)
        consts = (s * math.sin(2 * am), math.cos(2 * am), math.sin(am) ** 2, math.cos(am) ** 2)
        sigma = math.copysign(1.0, U)
        law(U, W, sigma, *consts, 1e-300, out)
        a, b = _lev_coefficients(np.array([U]), np.array([W]), *consts, variant)
        np.testing.assert_allclose(out[:2], [a[0], b[0]], rtol=1e-13, atol=1e-15)
        h = 1e-6
        for k, (dU, dW) in enumerate(((h, 0.0), (0.0, h))):
            plus = _lev_coefficients(np.array([U + dU]), np.array([W + dW]), *consts, variant)
            minus = _lev_coefficients(np.array([U - dU]), np.array([W - dW]), *consts, variant)
            numeric = [(plus[i][0] - minus[i][0]) / (2 * h) for i in range(2)]
            # central differences: truncation ~h^2, rounding ~1e-16/h relative
            np.testing.assert_allclose([out[2 + k], out[4 + k]], numeric, rtol=1e-8,
                                       atol=1e-8 * (U * U + W * W))


@pytest.mark.parametrize("aerodynamics", ["small-angle", "exact"])
@pytest.mark.parametrize("geometry", list(GEOMETRIES))
def test_the_plane_of_symmetry_is_the_planar_model(geometry, aerodynamics):
    insect = moth(**GEOMETRIES[geometry])
    six = SixDofDynamics(insect, aerodynamics=aerodynamics)
    four = LongitudinalDynamics(insect, aerodynamics=aerodynamics)
    rng = np.random.default_rng(7)
    for _ in range(12):
        t = rng.uniform(0.0, insect.period)
        x4 = rng.normal(size=4) * [0.5, 0.5, 5.0, 0.3]
        x8 = np.zeros(8)
        x8[list(LONGITUDINAL)] = x4
        f8, f4 = six.rhs(t, x8), four.rhs(t, x4)
        np.testing.assert_allclose(f8[list(LONGITUDINAL)], f4, rtol=1e-12, atol=1e-12)
        assert np.all(f8[list(LATERAL)] == 0.0)


def test_a_mirrored_state_gives_mirrored_loads():
    model = SixDofDynamics(moth(hinge_offset=1e-3, hinge_height=2e-3))
    mirror = np.array([1, -1, 1, -1, 1, -1, -1, 1.0])  # v, p, r, roll change sign
    rng = np.random.default_rng(3)
    for _ in range(10):
        t = rng.uniform(0.0, model.period)
        x = rng.normal(size=8) * 0.3
        loads, mirrored = model.loads(t, x), model.loads(t, mirror * x)
        # X, Z, M keep their values; Y, L, N change sign.
        np.testing.assert_allclose(mirrored, np.array([1, -1, 1, -1, 1, -1]) * loads,
                                   rtol=1e-12, atol=1e-14)


def _reference_loads(insect, alpha_m, t, x, s, n_nodes=32):
    """(X, Y, Z, L, M, N) strip by strip with vectors, the exact section law of the package."""
    amplitude, f = insect.stroke_amplitude, insect.frequency
    phi = insect.stroke_mean + amplitude * math.cos(2 * math.pi * f * t)
    phi_dot = -2 * math.pi * f * amplitude * math.sin(2 * math.pi * f * t)
    V, Omega = np.array(x[:3]), np.array(x[3:6])
    rho, quad = insect.air_density, span_quadrature(insect, n_nodes)
    kappa = math.pi * (0.75 - insect.pitch_axis)
    x_hat, mu1f, mu2 = insect.center_of_pressure, insect.mu1 * f, insect.mu2
    cos_ag, sin_am = s * math.cos(alpha_m), math.sin(alpha_m)
    force, moment = np.zeros(3), np.zeros(3)
    n = np.array([0.0, 0.0, 1.0])
    for side in (1, -1):
        e = np.array([math.sin(phi), side * math.cos(phi), 0.0])
        tk = np.array([math.cos(phi), -side * math.sin(phi), 0.0])
        hinge = np.array([insect.hinge_offset, 0.0, -insect.hinge_height])
        omega_k = side * Omega @ e
        for power in (1, 2, 3, 4):
            nodes, weights = quad.nodes[power], 0.5 * quad.weights[power]  # one wing
            for r, weight in zip(nodes, weights, strict=True):
                r_s = hinge + r * e
                v_s = V + np.cross(Omega, r_s) + r * phi_dot * tk
                U, W = v_s @ tk, v_s @ n
                a, b = _lev_coefficients(U, W, s * math.sin(2 * alpha_m),
                                         math.cos(2 * alpha_m), sin_am**2,
                                         math.cos(alpha_m)**2, "exact")
                lev = rho * insect.lift_slope * (a * tk + b * n)   # per chord
                rot = rho * kappa * omega_k * (W * tk - U * n)      # per chord^2
                d = x_hat * (-cos_ag * tk + sin_am * n)             # per chord
                tau = -(math.pi / 16) * rho * (mu1f + mu2 * abs(omega_k)) * omega_k  # per c^4
                # The chord's powers: c (LEV force), c^2 (rotational force; LEV at d),
                # c^3 (rotational at d), c^4 (damping torque).
                f_w = {1: lev, 2: rot}.get(power, np.zeros(3))
                m_w = {1: np.cross(r_s, lev), 2: np.cross(r_s, rot) + np.cross(d, lev),
                       3: np.cross(d, rot), 4: side * tau * e}[power]
                force += weight * f_w
                moment += weight * m_w
    return np.concatenate([force, moment])


@pytest.mark.parametrize("geometry", list(GEOMETRIES)[:2])
def test_loads_agree_with_a_strip_by_strip_reconstruction(geometry):
    insect = moth(**GEOMETRIES[geometry])
    model = SixDofDynamics(insect, aerodynamics="exact")
    rng = np.random.default_rng(11)
    for _ in range(6):
        t = rng.uniform(0.0, insect.period)
        x = rng.normal(size=8) * [0.5, 0.5, 0.5, 3.0, 3.0, 3.0, 0.2, 0.2]
        s = 1.0 if rng.uniform() < 0.5 else -1.0
        ours = model.loads(t, x, s)
        reference = _reference_loads(insect, model.alpha_m, t, x, s)
        scale = np.array([1, 1, 1, insect.semi_span, insect.semi_span, insect.semi_span])
        np.testing.assert_allclose(ours / scale, reference / scale, rtol=0,
                                   atol=1e-12 * np.max(np.abs(reference / scale)))


def _point_masses(insect):
    """Two point masses per wing with its mass and first two spanwise moments about the hinge."""
    m_w = insect.wing_mass
    s1, s2 = (a / 2 for a in insect.wing_mass_moments)
    mean, var = s1 / m_w, s2 / m_w - (s1 / m_w) ** 2
    spread = math.sqrt(var)
    return [(m_w / 2, mean - spread), (m_w / 2, mean + spread)]


def test_wing_inertia_obeys_newton_euler_for_point_mass_wings():
    insect = moth(wing_mass=4.7e-5, hinge_offset=1.5e-3, hinge_height=2e-3)
    model = SixDofDynamics(insect)
    i_x, i_y, i_z, i_xz = body_inertia(insect)
    inertia = np.array([[i_x, 0, -i_xz], [0, i_y, 0], [-i_xz, 0, i_z]])
    masses = _point_masses(insect)
    m_body = insect.mass - 2 * insect.wing_mass
    rng = np.random.default_rng(5)
    t0, x0 = 0.3 * insect.period, rng.normal(size=8) * [0.3, 0.3, 0.3, 2, 2, 2, 0.2, 0.2]
    loads = np.zeros(6)  # air off: gravity and inertia only
    xdot = np.linalg.solve(np.array(model_gen(model).mass_matrix(phi_at(model, t0)[0],
                                                                  model._k)).reshape(6, 6),
                           loads + np.array(model_gen(model).forcing(*phi_at(model, t0), *x0,
                                                                     model._k)))

    def momenta(h):
        V = x0[:3] + h * xdot[:3]
        Omega = x0[3:6] + h * xdot[3:]
        phi, phi_dot, _ = phi_at(model, t0 + h)
        P, H = m_body * V, inertia @ Omega
        for side in (1, -1):
            e = np.array([math.sin(phi), side * math.cos(phi), 0.0])
            tk = np.array([math.cos(phi), -side * math.sin(phi), 0.0])
            for m, r in masses:
                pos = np.array([insect.hinge_offset, 0, -insect.hinge_height]) + r * e
                vel = V + np.cross(Omega, pos) + r * phi_dot * tk
                P, H = P + m * vel, H + m * np.cross(pos, vel)
        return P, H

    h = 1e-6 * insect.period
    (P_plus, H_plus), (P_minus, H_minus) = momenta(h), momenta(-h)
    P0, H0 = momenta(0.0)
    V0, Omega0 = x0[:3], x0[3:6]
    roll, theta = x0[6], x0[7]
    g = insect.gravity * np.array([-math.sin(theta), math.sin(roll) * math.cos(theta),
                                   math.cos(roll) * math.cos(theta)])
    phi0 = phi_at(model, t0)[0]
    weight_moment = np.zeros(3)
    for side in (1, -1):
        e = np.array([math.sin(phi0), side * math.cos(phi0), 0.0])
        for m, r in masses:
            pos = np.array([insect.hinge_offset, 0, -insect.hinge_height]) + r * e
            weight_moment += m * np.cross(pos, g)
    # Body-axis Newton-Euler about the body's centre of gravity O (moving at V):
    # dP/dt + Omega x P = m g; dH_O/dt + Omega x H_O + V x P = sum r x m g.
    dP = (P_plus - P_minus) / (2 * h) + np.cross(Omega0, P0) - insect.mass * g
    dH = (H_plus - H_minus) / (2 * h) + np.cross(Omega0, H0) + np.cross(V0, P0) - weight_moment
    assert np.max(np.abs(dP)) < 1e-6 * insect.weight
    assert np.max(np.abs(dH)) < 1e-6 * insect.weight * insect.semi_span


def model_gen(model):
    from flapping.model import _sixdof_generated
    return _sixdof_generated


def phi_at(model, t):
    return model._stroke(t, model.amplitude)


def test_an_insect_without_lateral_inertia_is_refused_by_name():
    with pytest.raises(ValueError, match="roll_inertia"):
        SixDofDynamics(flapping.hawkmoth(roll_inertia=None))


def test_an_unknown_aerodynamic_model_is_refused_in_six_dof():
    # The linear loads (eq. 29) are derived in six dof now (tests/model/test_sixdof_linear.py).
    with pytest.raises(ValueError, match="aerodynamics"):
        SixDofDynamics(moth(), aerodynamics="quasi-steady")


def test_bad_states_are_refused():
    model = SixDofDynamics(moth())
    with pytest.raises(ValueError, match="8 states"):
        model.rhs(0.0, np.zeros(4))
    with pytest.raises(ValueError, match="`s`"):
        model.rhs(0.0, np.zeros(8), s=0.5)


def test_a_non_positive_definite_inertia_tensor_is_refused():
    with pytest.raises(ValueError, match="positive definite"):
        moth(roll_yaw_product=1e-7)

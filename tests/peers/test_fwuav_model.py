"""FWUAV's prescribed-attitude hover model (flapping.peers.fwuav.model) against FWUAV itself.

The reference accelerations are FWUAV's own: ``X_dot`` computed by its ``eom_QS_x.m`` and stored
in ``matlab/sim_data/other_insects/sim_QS_x_hover_<insect>.mat`` (fdcl-gwu/FWUAV @ 1a25d41),
at the stored time ``t(k)`` and state ``X(k, :)`` (MATLAB's 1-based k in the comments).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from flapping.peers.fwuav import SPECIES, FwuavHover, Motion, prescribed_motion, wing_angles
from flapping.peers.fwuav.data import species
from flapping.peers.fwuav.model import _wing

# (insect, t [s], X = (x, x_dot) [m, m/s], FWUAV's x_ddot [m/s^2])
FWUAV_ACCELERATIONS = [
    ("hawkmoth", 0.0, (0.0, 0.0, 0.0, -0.11981422138550234, 3.95256743308817e-19,
                       0.006147654793844691),
     (8.869940948333841, -1.778358008191674e-16, 8.893018632938402)),  # hawk k=1
    ("hawkmoth", 0.021531865992401342,
     (0.0010698113693214154, 3.214643697400295e-20, 0.00024960137074320774, 0.03505512629234311,
      2.828084682734946e-18, 0.020785008505760698),
     (-28.923159118643756, -3.2894483388516515e-16, -13.738460344908637)),  # hawk k=218
    ("bumblebee", 0.021329060475750807,
     (4.218913443244719e-05, 2.206351912897268e-20, 8.785619047591029e-05, 0.09426629582769025,
      2.1110269466049606e-18, 0.026884793854960072),
     (-82.72708477033977, -2.710505431213761e-16, -63.45620946563434)),  # bumb k=902
    ("fruit_fly", 0.005258733083772328,
     (-0.000127306097764971, 2.7208416161956113e-22, -1.6308790558710953e-06, 0.1584344390642467,
      1.8611467763790362e-19, 0.05781828658012752),
     (192.58560596386855, -3.561472081825536e-17, 9.347473075067613)),  # fruit k=501
    ("monarch", 0.08522452396452841,
     (2.4501579250345648e-05, -3.717290555103413e-19, 4.649530611003732e-06, -0.30720518553230297,
      -6.933770459815024e-18, -0.055823397814252426),
     (3.1617764907175365, 5.5437757487294586e-17, 18.376040955498713)),  # mona k=334
]


@pytest.mark.parametrize("name, t, X, expected", FWUAV_ACCELERATIONS)
def test_the_acceleration_is_fwuavs_at_its_stored_instants(name, t, X, expected):
    ours = FwuavHover(name).rhs(t, np.array(X))
    np.testing.assert_allclose(ours[0:3], X[3:6], rtol=0, atol=0)
    np.testing.assert_allclose(ours[3:6], expected, rtol=0, atol=1e-12 * np.abs(expected).max())


def _rx(a):
    return np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])


def _ry(a):
    return np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])


def _rz(a):
    return np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])


def _right_wing_force_by_hand(name, t, v):
    """FWUAV's right-wing force (QS_model.tex eqs. for U_R, dL, dD), one strip at a time, with
    the wing's angular velocity from FWUAV's T_R matrix (wing_attitude.m)."""
    sp = species(name)
    k, m = sp.kinematics, sp.morphology
    (phi, theta, psi), (dphi, dtheta, dpsi) = wing_angles(k, t)[0], wing_angles(k, t)[1]
    w = 2 * math.pi * k.f
    th_B = k.theta_B_m * math.cos(w * t + k.theta_B_a) + k.theta_B_0
    W = np.array([0.0, -k.theta_B_m * w * math.sin(w * t + k.theta_B_a), 0.0])
    R = _ry(th_B)
    Q = _ry(k.beta) @ _rx(phi) @ _rz(-psi) @ _ry(theta)
    T_R = np.array([[math.cos(psi) * math.cos(theta), 0, math.sin(theta)],
                    [math.sin(psi), 1, 0],
                    [math.cos(psi) * math.sin(theta), 0, -math.cos(theta)]])
    Om = T_R @ np.array([dphi, dtheta, dpsi])
    e2 = np.array([0.0, 1.0, 0.0])
    rs = np.linspace(0, m.span, 50)
    F = np.zeros(3)
    for r in rs:
        c = np.polyval(m.chord_poly, r / m.scale) * m.scale
        U = (np.eye(3) - np.outer(e2, e2)) @ Q.T @ (R.T @ v + np.cross(W, m.mu_R)) \
            + r * np.cross(Q @ W + Om, e2)
        speed = np.linalg.norm(U)
        alpha = math.acos(abs(U[0]) / speed)
        C_L = m.C_T * math.sin(2 * alpha)
        C_D = m.C_D_0 * math.cos(alpha) ** 2 + m.C_D_pi2 * math.sin(alpha) ** 2
        L = 0.5 * m.rho * C_L * np.sign(U[0] * U[2]) * np.cross(e2, U) * speed
        D = -0.5 * m.rho * C_D * speed * U
        F += (L + D) * c * (rs[1] - rs[0])
    return R @ Q @ F


@pytest.mark.parametrize("name, t", [("hawkmoth", 0.0037), ("bumblebee", 0.0011),
                                     ("fruit_fly", 0.0023)])
def test_the_right_wing_force_is_the_hand_computed_strip_sum(name, t):
    model = FwuavHover(name)
    v = np.array([0.3, -0.2, 0.1])
    motion = prescribed_motion(model.species, t)
    left_mirror = prescribed_motion(model.species, t)
    both = model.aerodynamic_force(motion, v)
    right = _right_wing_force_by_hand(name, t, v)
    assert np.abs(right).max() > 1e-3 * model.mass * 9.81  # a force, not a zero
    # the left wing is the right one's mirror image for a symmetric velocity (v_2 = 0)
    sym = np.array([0.3, 0.0, 0.1])
    both_sym = model.aerodynamic_force(left_mirror, sym)
    right_sym = _right_wing_force_by_hand(name, t, sym)
    np.testing.assert_allclose(both_sym, 2 * right_sym * [1, 0, 1], rtol=1e-12,
                               atol=1e-12 * np.abs(right_sym).max())
    assert abs(both[1]) > 0  # the lateral velocity breaks the symmetry: a side force


def test_wing_angular_velocity_and_acceleration_are_the_derivatives_of_the_attitude():
    sp = SPECIES["hawkmoth"]
    t, h = 0.0071, 1e-6
    now, plus, minus = (prescribed_motion(sp, s) for s in (t, t + h, t - h))
    for Q, Qp, Qm, Om, side in ((now.Q_R, plus.Q_R, minus.Q_R, now.Om_R, "R"),
                                (now.Q_L, plus.Q_L, minus.Q_L, now.Om_L, "L")):
        hat = Q.T @ (Qp - Qm) / (2 * h)
        np.testing.assert_allclose([hat[2, 1], hat[0, 2], hat[1, 0]], Om, rtol=1e-6,
                                   err_msg=side)
    for sign, plus_Om, minus_Om in ((1.0, plus.Om_R, minus.Om_R), (-1.0, plus.Om_L, minus.Om_L)):
        numeric = (plus_Om - minus_Om) / (2 * h)
        _, _, dOm = _wing(sp.kinematics.beta, wing_angles(sp.kinematics, t), sign)
        np.testing.assert_allclose(dOm, numeric, rtol=0, atol=1e-6 * np.abs(numeric).max())
    angles = [wing_angles(sp.kinematics, s) for s in (t - h, t, t + h)]
    np.testing.assert_allclose(angles[1][1], (angles[2][0] - angles[0][0]) / (2 * h), rtol=1e-6)
    np.testing.assert_allclose(angles[1][2], (angles[2][1] - angles[0][1]) / (2 * h), rtol=1e-5,
                               atol=1e-3)
    # the body's pitch rate
    dR = now.R.T @ (plus.R - minus.R) / (2 * h)
    np.testing.assert_allclose(dR[0, 2], now.W[1], rtol=1e-6)


def test_momentum_is_conserved_without_aerodynamics_and_gravity():
    model = FwuavHover("hawkmoth", aerodynamics=False, gravity=False)
    x0 = np.array([0.0, 0.0, 0.0, 0.2, -0.1, 0.05])
    sol = solve_ivp(model.rhs, (0.0, 1.5 * model.period), x0, method="DOP853", rtol=1e-11,
                    atol=1e-13, dense_output=True)
    p = np.array([model.momentum(t, sol.sol(t)) for t in np.linspace(0, sol.t[-1], 25)])
    scale = model.mass * 0.2
    assert np.ptp(p, axis=0).max() < 1e-8 * scale
    # ...while the thorax's own momentum is not: the appendages move it
    v = np.array([sol.sol(t)[3:6] for t in np.linspace(0, sol.t[-1], 25)])
    assert np.ptp(v, axis=0).max() * model.mass > 1e-3 * scale


def test_gravity_alone_changes_the_momentum_by_m_g_t():
    model = FwuavHover("bumblebee", aerodynamics=False)
    x0 = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
    T = model.period
    sol = solve_ivp(model.rhs, (0.0, T), x0, method="DOP853", rtol=1e-11, atol=1e-14)
    dp = model.momentum(T, sol.y[:, -1]) - model.momentum(0.0, x0)
    np.testing.assert_allclose(dp, [0, 0, model.mass * 9.81 * T], rtol=1e-7,
                               atol=1e-9 * model.mass * 9.81 * T)


@pytest.mark.parametrize("name", ["hawkmoth", "fruit_fly", "monarch"])
def test_the_velocity_jacobian_is_the_derivative_of_the_right_hand_side(name):
    model = FwuavHover(name)
    v = np.array([-0.12, 0.03, 0.01])
    h = 1e-6
    for t in (0.0, 0.3 * model.period, 0.77 * model.period):
        fd = np.column_stack([(model.velocity_rhs(t, v + h * e) - model.velocity_rhs(t, v - h * e))
                              / (2 * h) for e in np.eye(3)])
        np.testing.assert_allclose(model.velocity_jacobian(t, v), fd, rtol=0,
                                   atol=1e-6 * np.abs(fd).max())


def test_fwuavs_span_sum_is_the_converged_integral_to_a_fraction_of_a_percent():
    v = np.array([-0.1, 0.0, 0.0])
    motion = prescribed_motion(SPECIES["hawkmoth"], 0.004)
    forces = [FwuavHover("hawkmoth", quadrature="gauss", n_strips=n).aerodynamic_force(motion, v)
              for n in (40, 80)]
    fwuav = FwuavHover("hawkmoth").aerodynamic_force(motion, v)
    assert np.abs(forces[1] - forces[0]).max() < 1e-6 * np.abs(forces[1]).max()
    gap = np.abs(fwuav - forces[1]).max() / np.abs(forces[1]).max()
    assert 1e-5 < gap < 5e-3  # 50 equally weighted points: a small, non-zero quadrature error


@pytest.mark.parametrize("kwargs, word", [({"n_strips": 1}, "n_strips"),
                                          ({"quadrature": "simpson"}, "quadrature"),
                                          ({"body_rate_term": "x"}, "body_rate_term")])
def test_bad_options_are_value_errors_naming_them(kwargs, word):
    with pytest.raises(ValueError, match=word):
        FwuavHover("hawkmoth", **kwargs)


def test_an_unknown_insect_is_a_value_error_listing_the_four():
    with pytest.raises(ValueError, match="hawkmoth, bumblebee, fruit_fly, monarch"):
        FwuavHover("dragonfly")


def test_the_body_rate_term_changes_the_force_only_through_the_body_rate():
    fwuav, rotated = FwuavHover("fruit_fly"), FwuavHover("fruit_fly", body_rate_term="rotated")
    v = np.array([-0.15, 0.0, -0.08])
    t = 0.0013
    motion = prescribed_motion(fwuav.species, t)
    assert abs(motion.W[1]) > 1.0  # the thorax pitches (rad/s)
    a, b = fwuav.aerodynamic_force(motion, v), rotated.aerodynamic_force(motion, v)
    assert np.abs(a - b).max() > 1e-3 * np.abs(a).max()
    still = Motion(**{**vars(motion), "W": np.zeros(3)})
    np.testing.assert_allclose(fwuav.aerodynamic_force(still, v),
                               rotated.aerodynamic_force(still, v), rtol=1e-13)


def test_the_jacobian_at_the_right_hand_sides_instant_reuses_its_wing_frames(monkeypatch):
    # The integrators ask for f(t, x) and J(t, x) at the same instants: the wing frames (two
    # thirds of the strip velocities' work, four cross products) are computed once for both.
    import flapping.peers.fwuav.model as fw

    model = FwuavHover("hawkmoth")
    t, x = 0.3 * model.period, np.array([0.0, 0.0, 0.0, -0.12, 0.0, 0.006])
    model.rhs(t, x)
    calls = []
    monkeypatch.setattr(fw, "_cross", lambda a, b: calls.append(1) or np.cross(a, b))
    model.jac(t, x)
    assert calls == []
    model.jac(t + 1e-5, x)  # another instant: new frames
    assert calls


@pytest.mark.parametrize("name", ["hawkmoth", "monarch"])
def test_remembered_frames_give_a_fresh_models_numbers(name):
    # The frames are remembered per motion, the velocity enters afresh: after a call at another
    # state (and at another instant) the same instant gives the fresh model's numbers, to the bit.
    used, fresh = FwuavHover(name), FwuavHover(name)
    t = 0.41 * used.period
    x1, x2 = np.array([0, 0, 0, -0.12, 0.01, 0.006]), np.array([0, 0, 0, 0.2, -0.03, -0.1])
    used.rhs(0.1 * used.period, x2)
    used.rhs(t, x1)
    used.jac(t, x1)
    np.testing.assert_array_equal(used.rhs(t, x2), fresh.rhs(t, x2))
    np.testing.assert_array_equal(used.jac(t, x2), FwuavHover(name).jac(t, x2))


def test_a_strip_at_rest_adds_no_force_and_no_jacobian():
    # The masked branch of the strip sums (a strip of zero velocity has no angle of attack):
    # its force and Jacobian are those of the other strips alone.
    from flapping.peers.fwuav.model import _strip_forces, _strip_jacobian

    sp = species("hawkmoth")
    U = np.array([[0.0, -1.2, 2.0, 0.7], [0.0, 0.0, 0.0, 0.0], [0.0, 0.4, -0.3, 1.1]])
    w = np.array([3e-4, 2e-4, 1e-4, 2.5e-4])
    np.testing.assert_allclose(_strip_forces(sp, U, w), _strip_forces(sp, U[:, 1:], w[1:]),
                               rtol=1e-15, atol=0)
    np.testing.assert_allclose(_strip_jacobian(sp, U, w), _strip_jacobian(sp, U[:, 1:], w[1:]),
                               rtol=1e-15, atol=0)
    assert np.all(np.isfinite(_strip_jacobian(sp, U, w)))

"""FWUAV's attitude-free hover in 3-D (flapping.peers.fwuav.attitude3d)."""

from __future__ import annotations

import dataclasses
from functools import lru_cache

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from flapping.peers.fwuav.attitude import FwuavPitchFree, _reduced, pitch_free_floquet
from flapping.peers.fwuav.attitude3d import (
    LATERAL,
    LONGITUDINAL,
    FwuavAttitudeFree,
    _expm_hat,
    _variational,
    attitude_free_floquet,
)
from flapping.peers.fwuav.model import _strip_forces

# A planar state near the hawkmoth's pitch-free orbit, (theta, v_1, v_3, q), and a stretch of
# an eighth of a wingbeat: the properties below hold on any planar motion, periodic or not.
PLANAR = np.array([1.09, -0.11, 0.17, 0.3])
LON, LAT = list(LONGITUDINAL), list(LATERAL)


@lru_cache(maxsize=2)
def _stretch(body_rate_term: str
             ) -> tuple[FwuavAttitudeFree, float, np.ndarray, float, np.ndarray]:
    """The 3-D transition matrix of ``(xi, v, W)`` over ``T / 8`` from ``PLANAR`` (rtol 1e-10),
    ``int trace A dt`` and the final ``(R, v, W)``."""
    model = FwuavAttitudeFree("hawkmoth", body_rate_term=body_rate_term)
    span = model.period / 8
    end, M, trace, _ = _variational(model, model.from_planar(PLANAR), span, 1e-10)
    return model, span, M, trace, end


@pytest.mark.parametrize("body_rate_term", ["fwuav", "rotated"])
@pytest.mark.parametrize("name", ["hawkmoth", "fruit_fly"])
def test_planar_restriction_is_the_pitch_free_model(name: str, body_rate_term: str) -> None:
    """In the plane of symmetry the 3-D equations (one 6 x 6 linear solve) give
    FwuavPitchFree.rhs (three residual evaluations and a 3 x 3 solve) and no lateral
    acceleration."""
    planar = FwuavPitchFree(name, body_rate_term=body_rate_term)
    model = FwuavAttitudeFree(name, body_rate_term=body_rate_term)
    for t in np.linspace(0.0, planar.period, 7):
        y = np.array([0.001, 0.002, 1.05, 0.1, -0.2, 3.0])
        state = model.from_planar(y)
        expected = planar.rhs(t, y)
        f = model.rhs(t, state)
        got = np.array([f[0], f[2], state[16], f[12], f[14], f[16]])
        np.testing.assert_allclose(got, expected, rtol=1e-10, atol=1e-10 * np.abs(expected).max())
        assert np.abs(f[[1, 13, 15, 17]]).max() <= 1e-12 * np.abs(f).max()


def test_aerodynamic_loads_are_the_strip_points_kinematics() -> None:
    """Off the plane (roll, yaw, sideslip), with ``Q^T W`` (the exact rotation of the body rate
    into the wing frame), the force and moment are the sums over strip points ``p = mu +
    Q (+/- r e2)`` of the force at each point's own velocity ``Q^T (R^T v + W x p) + Om x
    (p - mu)`` and of ``p x Q dF``: a per-point computation against the vectorised one."""
    model = FwuavAttitudeFree("hawkmoth", body_rate_term="rotated")
    R = _expm_hat(np.array([0.2, 1.0, -0.3]))
    v, W = np.array([0.3, -0.4, 0.2]), np.array([4.0, -2.0, 3.0])
    t = 0.3 * model.period
    motion, _ = model._prescribed(t)
    frame = dataclasses.replace(motion, R=R, W=W)
    F, M = model._aerodynamics(frame, v)
    hover, sp = model.planar.hover, model.species
    F_ref, M_ref = np.zeros(3), np.zeros(3)
    project = np.diag([1.0, 0.0, 1.0])
    for Q, Om, sign in ((motion.Q_R, motion.Om_R, 1.0), (motion.Q_L, motion.Om_L, -1.0)):
        mu = np.array(sp.morphology.mu_R) * np.array([1.0, sign, 1.0])
        for r, w in zip(hover.r, hover.weights, strict=True):
            arm = sign * r * np.array([0.0, 1.0, 0.0])
            p = mu + Q @ arm
            U = project @ (Q.T @ (R.T @ v + np.cross(W, p)) + np.cross(Om, arm))
            dF = _strip_forces(sp, U[:, None], np.array([w]))
            F_ref += R @ Q @ dF
            M_ref += np.cross(p, Q @ dF)
    np.testing.assert_allclose(F, F_ref, rtol=1e-12, atol=1e-12 * np.abs(F_ref).max())
    np.testing.assert_allclose(M, M_ref, rtol=1e-12, atol=1e-12 * np.abs(M_ref).max())


def test_conserves_momentum_in_3d_without_external_loads() -> None:
    """No aerodynamics, no gravity, a thorax rolling and yawing: linear and angular momentum of
    the four bodies are constant (fails if an inertia, the locked-inertia matrix or a coupling
    term of the 6 x 6 system is wrong)."""
    model = FwuavAttitudeFree("hawkmoth", aerodynamics=False, gravity=False)
    y0 = model.from_planar([0.001, 0.002, 1.0, 0.1, -0.2, 3.0])
    y0[3:12] = (y0[3:12].reshape(3, 3) @ _expm_hat(np.array([0.3, 0.0, -0.2]))).ravel()
    y0[12:15] += [0.0, 0.05, 0.0]
    y0[15:18] += [2.0, 0.0, -1.5]
    sol = solve_ivp(model.rhs, (0.0, 0.6 * model.period), y0, method="DOP853", rtol=1e-11,
                    atol=1e-13)
    P0, H0 = model.momentum(0.0, y0)
    P1, H1 = model.momentum(sol.t[-1], sol.y[:, -1])
    assert np.abs(sol.y[[15, 17], -1] - y0[[15, 17]]).max() > 0.1  # roll and yaw rates moved
    np.testing.assert_allclose(P1, P0, atol=1e-9 * np.abs(P0).max())
    np.testing.assert_allclose(H1, H0, atol=1e-8 * np.abs(H0).max())


def test_jacobian_decouples_in_the_plane_only() -> None:
    """Mirror symmetry: at a planar state the longitudinal-lateral blocks of the local Jacobian
    vanish (to the central differences' rounding); off the plane they do not."""
    model = FwuavAttitudeFree("hawkmoth")
    state = model.from_planar(PLANAR)
    A = model.local_jacobian(0.004, state)
    scale = np.abs(A).max()
    assert np.abs(A[np.ix_(LON, LAT)]).max() < 1e-8 * scale
    assert np.abs(A[np.ix_(LAT, LON)]).max() < 1e-8 * scale
    rolled = state.copy()
    rolled[15] = 5.0  # a roll rate
    B = model.local_jacobian(0.004, rolled)
    assert np.abs(B[np.ix_(LON, LAT)]).max() > 1e-3 * scale


@pytest.mark.parametrize("body_rate_term", ["fwuav", "rotated"])
def test_transition_matrix_blocks(body_rate_term: str) -> None:
    """Over T/8 from a planar state: the longitudinal block of the 3-D transition matrix is
    the pitch-free model's (its own variational equations, 4 states) and the coupling blocks
    vanish. Tolerance: both integrated at rtol 1e-10 with central-difference Jacobians."""
    model, span, M, _, _ = _stretch(body_rate_term)
    fun, jac = _reduced(FwuavPitchFree("hawkmoth", body_rate_term=body_rate_term))

    def variational(t: float, y: np.ndarray) -> np.ndarray:
        return np.concatenate([fun(t, y[:4]), (jac(t, y[:4]) @ y[4:].reshape(4, 4)).ravel()])

    sol = solve_ivp(variational, (0.0, span), np.concatenate([PLANAR, np.eye(4).ravel()]),
                    method="DOP853", rtol=1e-10, atol=1e-11)
    M_planar = sol.y[4:, -1].reshape(4, 4)
    np.testing.assert_allclose(M[np.ix_(LON, LON)], M_planar, atol=1e-7 * np.abs(M).max())
    assert np.abs(M[np.ix_(LON, LAT)]).max() < 1e-8 * np.abs(M).max()
    assert np.abs(M[np.ix_(LAT, LON)]).max() < 1e-8 * np.abs(M).max()


def _so3_log(R: np.ndarray) -> np.ndarray:
    return Rotation.from_matrix(R).as_rotvec()


def test_transition_matrix_is_the_flows_derivative_and_liouville() -> None:
    """The variational equations in exponential coordinates (with ``xi' = -W x xi + dW``) give
    the derivative of the nonlinear 3-D flow (central differences of 18 integrations, no
    Jacobian), and det M = exp(int trace A) (Liouville). Dropping ``-W x xi`` would change M by
    about ``|W| T / 8`` (~1e-2 here), four orders above the tolerance."""
    model, span, M, trace, _ = _stretch("fwuav")
    state0 = model.from_planar(PLANAR)

    def end(z: np.ndarray) -> np.ndarray:
        y = state0.copy()
        y[3:12] = (state0[3:12].reshape(3, 3) @ _expm_hat(z[:3])).ravel()
        y[12:18] += z[3:]
        return solve_ivp(model.rhs, (0.0, span), y, method="DOP853", rtol=1e-12,
                         atol=1e-14).y[:, -1]

    ref = end(np.zeros(9))
    R_ref = ref[3:12].reshape(3, 3)
    h = 1e-5
    cols = []
    for e in np.eye(9):
        plus, minus = end(h * e), end(-h * e)
        d = np.concatenate([_so3_log(R_ref.T @ plus[3:12].reshape(3, 3))
                            - _so3_log(R_ref.T @ minus[3:12].reshape(3, 3)),
                            plus[12:18] - minus[12:18]])
        cols.append(d / (2 * h))
    M_fd = np.column_stack(cols)
    np.testing.assert_allclose(M, M_fd, atol=1e-6 * np.abs(M).max())
    assert abs(np.linalg.det(M) / np.exp(trace) - 1.0) < 1e-8
    assert abs(np.linalg.det(M_fd) / np.exp(trace) - 1.0) < 1e-6


@pytest.mark.parametrize("body_rate_term", ["fwuav", "rotated"])
def test_yaw_about_gravity_is_carried_along(body_rate_term: str) -> None:
    """Nothing depends on the heading: a yaw ``eps`` about ``e3`` of the whole motion is the
    perturbation ``(xi, v, W) = eps (R^T e3, e3 x v, 0)``, and the transition matrix carries it
    from the start's to the end's (a lateral check of the aerodynamic and gravity terms; on the
    periodic orbit it is the neutral multiplier one)."""
    model, _, M, _, end = _stretch(body_rate_term)
    start = model.from_planar(PLANAR)

    def yaw(y: np.ndarray) -> np.ndarray:
        R, v = y[0:9].reshape(3, 3), y[9:12]
        return np.concatenate([R[2], np.cross([0.0, 0.0, 1.0], v), np.zeros(3)])

    np.testing.assert_allclose(M @ yaw(start[3:]), yaw(end), atol=1e-7)
    assert np.abs(yaw(end) - yaw(start[3:])).max() > 1e-4  # the motion did change them


def test_bad_arguments_are_named() -> None:
    with pytest.raises(ValueError, match="rtol"):
        attitude_free_floquet("hawkmoth", rtol=1e-3)
    with pytest.raises(ValueError, match="insect"):
        attitude_free_floquet("monarch")
    with pytest.raises(ValueError, match="body_rate_term"):
        attitude_free_floquet("hawkmoth", body_rate_term="both")
    with pytest.raises(ValueError, match="y0"):
        attitude_free_floquet("hawkmoth", y0=PLANAR)
    planar = FwuavPitchFree("hawkmoth")
    with pytest.raises(ValueError, match="y0"):
        attitude_free_floquet(planar)
    with pytest.raises(ValueError, match="y0"):
        attitude_free_floquet(planar, y0=np.zeros(6))
    with pytest.raises(ValueError, match="period"):
        attitude_free_floquet(planar, y0=PLANAR, period=-1.0)
    with pytest.raises(ValueError, match="model"):
        attitude_free_floquet(3.0)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="pitch"):
        FwuavAttitudeFree(FwuavPitchFree("hawkmoth", pitch="prescribed"))
    with pytest.raises(ValueError, match="body_rate_term"):  # a model's own term applies
        FwuavAttitudeFree(FwuavPitchFree("hawkmoth"), body_rate_term="rotated")
    with pytest.raises(ValueError, match="y"):
        FwuavAttitudeFree.from_planar(np.zeros(5))


@pytest.mark.slow  # ~6 min per form on two shared cores: the planar shooting dominates
@pytest.mark.parametrize("body_rate_term", ["fwuav", "rotated"])
def test_hawkmoth_longitudinal_block_is_the_pitch_free_result(body_rate_term: str) -> None:
    """About the periodic pitch-free orbit: the 3-D monodromy's longitudinal block has the
    pitch-free multipliers (two integrations of different equations), the coupling blocks
    vanish, the orbit closes in 3-D, Liouville holds, and one lateral multiplier is the
    neutral yaw about gravity (exactly one in exact arithmetic)."""
    planar = pitch_free_floquet("hawkmoth", body_rate_term=body_rate_term)
    result = attitude_free_floquet("hawkmoth", body_rate_term=body_rate_term)
    np.testing.assert_allclose(result.longitudinal, planar.multipliers, atol=1e-6)
    assert result.coupling < 1e-8
    assert result.closure < 1e-6
    assert result.liouville_error < 1e-6
    assert np.abs(result.lateral - 1.0).min() < 1e-6

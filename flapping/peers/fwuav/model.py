"""FWUAV's hover model with the attitudes prescribed: the translation of the thorax.

FWUAV (fdcl-gwu/FWUAV, ``doc/QS_model.tex``) models an insect as four rigid bodies: thorax
(position ``x`` and attitude ``R`` in an inertial frame with ``e3`` down), two wings (attitudes
``Q_R``, ``Q_L`` relative to the thorax, roots at ``mu_R``, ``mu_L`` in the thorax frame) and an
abdomen (``Q_A``, joint at ``mu_A``). In the hover runs stored in its repository the thorax
attitude, the wing angles and the abdomen angle are prescribed functions of time; only ``x`` is
free, and the state is ``(x, x')`` (six components).

Equation of motion. The system's momentum is ``m x' + sum_i m_i s_i'``, where ``m`` is the total
mass and ``s_i = R (mu_i + Q_i nu_i)`` the prescribed position of the centre of mass of body
``i`` (wings, abdomen) relative to the thorax's. Newton's law for the whole system gives::

    m x'' = F_aero + m g e3 - sum_i m_i s_i'',

with ``s_i'' = R (W^2 p_i + W' ^ p_i + 2 W ^ p_i' + p_i'')``, ``p_i = mu_i + Q_i nu_i``,
``p_i' = Q_i (Om_i ^ nu_i)``, ``p_i'' = Q_i (Om_i ^ (Om_i ^ nu_i) + Om_i' ^ nu_i)`` (``W``
thorax and ``Om_i`` relative angular velocities in the body frames). It is the first block of
FWUAV's Euler-Lagrange equations with the rotational unknowns given: their ``JJ_12 xi_2' +
LL_12 xi_2`` term is ``sum_i m_i s_i''`` minus its ``x''``-independent part, term by term.

Aerodynamics (Sane & Dickinson's translational quasi-steady model, FWUAV's span integration):
each wing is cut into strips at ``r_k`` along its span with chord ``c(r_k)``; the strip velocity
in the wing frame, its component along the span removed, is::

    U_k = P Q^T (R^T x' + W ^ mu) +/- r_k (Q W + Om) ^ e2,      P = I - e2 e2^T

(``+`` right wing, ``-`` left; ``Q W`` as FWUAV's code and its ``doc/QS_model.tex`` write it,
where the rotation of ``W`` into the wing frame would be ``Q^T W``: see ``body_rate_term``). The
angle of attack is ``a = acos(|U_1| / |U|)`` and the strip force::

    dF = 1/2 rho c dr [C_L(a) sgn(U_1 U_3) (e2 ^ U) |U| - C_D(a) |U| U],

summed as FWUAV sums it: ``N = 50`` equally spaced ``r_k`` from root to tip, every one weighted by
``dr = l / (N - 1)`` (``quadrature="fwuav"``). ``quadrature="gauss"`` integrates the same force
with Gauss-Legendre points instead, for the converged span integral. FWUAV's rotational force is
zero in this model; so is every aerodynamic load on the thorax and abdomen.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

import flapping._validation as check
from flapping._numdiff import central_jacobian
from flapping.peers.fwuav.data import Kinematics, Species, species

__all__ = ["Motion", "FwuavHover", "prescribed_motion", "wing_angles", "QUADRATURES",
           "BODY_RATE_TERMS"]

#: Span quadratures: FWUAV's equally weighted points, or Gauss-Legendre.
QUADRATURES = ("fwuav", "gauss")
#: The body-rate term of the strip velocity: FWUAV's ``Q W`` or the rotated ``Q^T W``.
BODY_RATE_TERMS = ("fwuav", "rotated")

_E1, _E2, _E3 = np.eye(3)
_PROJECT = np.diag([1.0, 0.0, 1.0])  # removes the spanwise component


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a x b`` of two 3-vectors, in Python floats (``np.cross`` costs ~20 us a call; unpacking
    the arrays into NumPy scalars ~4 us; through ``tolist`` ~1 us, the same float64 products)."""
    a0, a1, a2 = a.tolist()
    b0, b1, b2 = b.tolist()
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


def _rot(axis: int, angle: float) -> np.ndarray:
    """Rotation ``exp(angle hat(e_axis))`` (built whole: ``np.eye`` and item assignments cost
    twice as much, and the prescribed motion builds ten a call)."""
    c, s = math.cos(angle), math.sin(angle)
    if axis == 0:
        return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    if axis == 1:
        return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def wing_angles(k: Kinematics, t: float) -> np.ndarray:
    """Flapping, pitch and deviation angles and their first two derivatives at ``t``.

    Parameters
    ----------
    k : Kinematics
        FWUAV's hover kinematics.
    t : float
        Time (s).

    Returns
    -------
    ndarray, shape (3, 3)
        Rows ``(phi, theta, psi)`` (rad), ``(phi', theta', psi')`` (rad/s) and the second
        derivatives (rad/s^2).
    """
    w = 2.0 * math.pi * k.f
    A, a = k.phi_m / math.asin(k.phi_K), k.phi_K
    cw, sw = math.cos(w * t), math.sin(w * t)
    root = math.sqrt(1.0 - a * a * cw * cw)
    phi = (A * math.asin(a * cw) + k.phi_0, -A * a * w * sw / root,
           A * a * w * w * cw * (a * a - 1.0) / root**3)
    B, C = k.theta_m / math.tanh(k.theta_C), k.theta_C
    arg = w * t + k.theta_a
    th = math.tanh(C * math.sin(arg))
    sech2 = 1.0 - th * th
    theta = (B * th + k.theta_0, B * C * w * math.cos(arg) * sech2,
             -B * C * w * w * sech2 * (math.sin(arg) + 2.0 * C * math.cos(arg) ** 2 * th))
    wp = k.psi_N * w
    cp, sp = math.cos(wp * t + k.psi_a), math.sin(wp * t + k.psi_a)
    psi = (k.psi_m * cp + k.psi_0, -k.psi_m * wp * sp, -k.psi_m * wp * wp * cp)
    return np.array([phi, theta, psi]).T


def _sinusoid(amplitude: float, mean: float, phase: float, w: float, t: float
              ) -> tuple[float, float, float]:
    c, s = math.cos(w * t + phase), math.sin(w * t + phase)
    return amplitude * c + mean, -amplitude * w * s, -amplitude * w * w * c


def _wing(beta: float, angles: np.ndarray, sign: float
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Attitude, angular velocity and acceleration (wing frame) of one wing.

    ``Q = Ry(beta) Rx(sign phi) Rz(-sign psi) Ry(theta)``: ``sign = +1`` right, ``-1`` left.
    """
    (phi, theta, psi), (dphi, dtheta, dpsi), (ddphi, ddtheta, ddpsi) = angles
    Ry_t = _rot(1, theta)
    Rz_p = _rot(2, -sign * psi)
    Q = _rot(1, beta) @ _rot(0, sign * phi) @ Rz_p @ Ry_t
    a = Ry_t.T @ Rz_p.T @ _E1 * sign          # d Om / d phi'
    b = -sign * (Ry_t.T @ _E3)                # d Om / d psi'
    Om = a * dphi + b * dpsi + _E2 * dtheta
    # time derivatives of a and b: Ry(theta)^T turns at -theta' e2, Rz(-sign psi)^T at sign psi' e3
    da = -dtheta * _cross(_E2, a) + dpsi * (Ry_t.T @ _cross(_E3, Rz_p.T @ _E1))
    db = -dtheta * _cross(_E2, b)
    dOm = a * ddphi + b * ddpsi + _E2 * ddtheta + da * dphi + db * dpsi
    return Q, Om, dOm


@dataclass(frozen=True)
class Motion:
    """The prescribed motion at one instant (FWUAV's frames; SI units).

    Attributes
    ----------
    R : ndarray, shape (3, 3)
        Thorax attitude (body to inertial).
    W, W_dot : ndarray, shape (3,)
        Thorax angular velocity and acceleration, body frame.
    Q_R, Q_L, Q_A : ndarray, shape (3, 3)
        Right wing, left wing and abdomen attitudes relative to the thorax.
    Om_R, Om_L : ndarray, shape (3,)
        Wing angular velocities relative to the thorax, in their own frames.
    inertial_load : ndarray, shape (3,)
        ``sum_i m_i s_i''`` (N), inertial frame: what the appendages' motion takes from the
        thorax's translation.
    appendage_momentum : ndarray, shape (3,)
        ``sum_i m_i s_i'`` (kg m/s), inertial frame.
    """

    R: np.ndarray
    W: np.ndarray
    W_dot: np.ndarray
    Q_R: np.ndarray
    Q_L: np.ndarray
    Q_A: np.ndarray
    Om_R: np.ndarray
    Om_L: np.ndarray
    inertial_load: np.ndarray
    appendage_momentum: np.ndarray


def _appendage(m: float, R: np.ndarray, W: np.ndarray, dW: np.ndarray, mu: np.ndarray,
               Q: np.ndarray, Om: np.ndarray, dOm: np.ndarray, nu: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
    """``m s'`` and ``m s''`` of a body at ``s = R (mu + Q nu)`` (inertial frame)."""
    p = mu + Q @ nu
    dp = Q @ _cross(Om, nu)
    ddp = Q @ (_cross(Om, _cross(Om, nu)) + _cross(dOm, nu))
    ds = R @ (_cross(W, p) + dp)
    dds = R @ (_cross(W, _cross(W, p)) + _cross(dW, p) + 2.0 * _cross(W, dp) + ddp)
    return m * ds, m * dds


def prescribed_motion(sp: Species, t: float) -> Motion:
    """The attitudes, rates and appendage loads FWUAV prescribes at time ``t``.

    Parameters
    ----------
    sp : Species
        The insect.
    t : float
        Time (s).

    Returns
    -------
    Motion
    """
    k, m = sp.kinematics, sp.morphology
    w = 2.0 * math.pi * k.f
    th_B, dth_B, ddth_B = _sinusoid(k.theta_B_m, k.theta_B_0, k.theta_B_a, w, t)
    th_A, dth_A, ddth_A = _sinusoid(k.theta_A_m, k.theta_A_0, k.theta_A_a, w, t)
    R, W, dW = _rot(1, th_B), dth_B * _E2, ddth_B * _E2
    angles = wing_angles(k, t)
    Q_R, Om_R, dOm_R = _wing(k.beta, angles, 1.0)
    Q_L, Om_L, dOm_L = _wing(k.beta, angles, -1.0)
    Q_A = _rot(1, th_A)
    mu_R, nu_R = np.array(m.mu_R), np.array(m.nu_R)
    mirror = np.array([1.0, -1.0, 1.0])
    parts = [
        _appendage(m.m_wing, R, W, dW, mu_R, Q_R, Om_R, dOm_R, nu_R),
        _appendage(m.m_wing, R, W, dW, mu_R * mirror, Q_L, Om_L, dOm_L, nu_R * mirror),
        _appendage(m.m_A, R, W, dW, np.array(m.mu_A), Q_A, dth_A * _E2, ddth_A * _E2,
                   np.array(m.nu_A)),
    ]
    return Motion(R=R, W=W, W_dot=dW, Q_R=Q_R, Q_L=Q_L, Q_A=Q_A, Om_R=Om_R, Om_L=Om_L,
                  inertial_load=parts[0][1] + parts[1][1] + parts[2][1],
                  appendage_momentum=parts[0][0] + parts[1][0] + parts[2][0])


def _coefficients(sp: Species, cos_a: np.ndarray, sin_a: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Lift and drag coefficients at the angles of attack with these cosines and sines."""
    m = sp.morphology
    if m.coefficients == "monarch":
        alpha = np.degrees(np.arctan2(sin_a, cos_a))
        return (0.225 + 1.58 * np.sin(np.radians(2.13 * alpha - 7.2)),
                1.92 - 1.55 * np.cos(np.radians(2.04 * alpha - 9.82)))
    assert m.C_T is not None and m.C_D_0 is not None and m.C_D_pi2 is not None
    return 2.0 * m.C_T * sin_a * cos_a, m.C_D_0 * cos_a**2 + m.C_D_pi2 * sin_a**2


def _strip_forces(sp: Species, U: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Sum over strips of ``1/2 rho c dr [C_L sgn(U1 U3) (e2 x U)|U| - C_D |U| U]`` (wing frame).

    ``U`` has shape (3, N) (no spanwise component); ``weights`` is ``c dr`` per strip.
    """
    speed = np.sqrt(U[0] ** 2 + U[2] ** 2)
    still = not speed.all()  # a strip at rest (rare: the masks cost a third of the call)
    safe = np.where(speed > 0.0, speed, 1.0) if still else speed
    cos_a = np.abs(U[0]) / safe
    sin_a = np.abs(U[2]) / safe
    C_L, C_D = _coefficients(sp, cos_a, sin_a)
    if still:
        C_L = np.where(speed > 0.0, C_L, 0.0)
    e2_x_U = np.array([U[2], np.zeros_like(U[0]), -U[0]])
    density = 0.5 * sp.morphology.rho * weights * speed
    return (e2_x_U * (C_L * np.sign(U[0] * U[2])) - U * C_D) @ density


def _strip_jacobian(sp: Species, U: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """``d(sum of strip forces)/dU`` (3x3, wing frame) for Sane & Dickinson's coefficients.

    With ``U = (a, 0, b)``, ``s = |U|``: lift ``rho w C_T (a b / s) (b, 0, -a)`` and drag
    ``-rho w / 2 (C_D_0 a^2 + C_D_pi2 b^2) / s (a, 0, b)`` per strip of weight ``w = c dr``.
    """
    m = sp.morphology
    assert m.C_T is not None and m.C_D_0 is not None and m.C_D_pi2 is not None
    a, b = U[0], U[2]
    s = np.sqrt(a * a + b * b)
    kl, kd = m.rho * weights * m.C_T, 0.5 * m.rho * weights
    if not s.all():  # a strip at rest (rare: the masks cost a fifth of the call) adds nothing
        live = s > 0.0
        s = np.where(live, s, 1.0)
        kl, kd = np.where(live, kl, 0.0), np.where(live, kd, 0.0)
    h, h_a, h_b = a * b / s, (b / s) ** 3, (a / s) ** 3
    q = (m.C_D_0 * a * a + m.C_D_pi2 * b * b) / s
    q_a = 2.0 * m.C_D_0 * a / s - q * a / s**2
    q_b = 2.0 * m.C_D_pi2 * b / s - q * b / s**2
    G = np.zeros((3, 3))
    G[0, 0] = (kl * h_a * b - kd * (q_a * a + q)).sum()
    G[0, 2] = (kl * (h_b * b + h) - kd * q_b * a).sum()
    G[2, 0] = (-kl * (h_a * a + h) - kd * q_a * b).sum()
    G[2, 2] = (-kl * h_b * a - kd * (q_b * b + q)).sum()
    return G


def _strip_jacobians(sp: Species, U: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """:func:`_strip_jacobian` of several wings at once: ``U`` (3, n, N), ``weights`` (N,);
    returns (n, 3, 3). The same operations, element by element, and each wing's sums over its
    own row, so each matrix equals :func:`_strip_jacobian`'s bit for bit; one pass over both
    wings halves the NumPy calls, which dominate at FWUAV's 50 strips."""
    m = sp.morphology
    assert m.C_T is not None and m.C_D_0 is not None and m.C_D_pi2 is not None
    a, b = U[0], U[2]
    s = np.sqrt(a * a + b * b)
    kl = np.broadcast_to(m.rho * weights * m.C_T, s.shape)
    kd = np.broadcast_to(0.5 * m.rho * weights, s.shape)
    if not s.all():  # a strip at rest adds nothing
        live = s > 0.0
        s = np.where(live, s, 1.0)
        kl, kd = np.where(live, kl, 0.0), np.where(live, kd, 0.0)
    h, h_a, h_b = a * b / s, (b / s) ** 3, (a / s) ** 3
    q = (m.C_D_0 * a * a + m.C_D_pi2 * b * b) / s
    q_a = 2.0 * m.C_D_0 * a / s - q * a / s**2
    q_b = 2.0 * m.C_D_pi2 * b / s - q * b / s**2
    G = np.zeros((a.shape[0], 3, 3))
    G[:, 0, 0] = (kl * h_a * b - kd * (q_a * a + q)).sum(axis=-1)
    G[:, 0, 2] = (kl * (h_b * b + h) - kd * q_b * a).sum(axis=-1)
    G[:, 2, 0] = (-kl * (h_a * a + h) - kd * q_a * b).sum(axis=-1)
    G[:, 2, 2] = (-kl * h_b * a - kd * (q_b * b + q)).sum(axis=-1)
    return G


#: Per wing, from the motion alone: R Q, dU/dv, P Q^T (W x mu), the spin term (3, N).
_Frames = tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]


class FwuavHover:
    """FWUAV's prescribed-attitude hover: ``x' = v``, ``m v' = F_aero + m g e3 - sum m_i s_i''``.

    Parameters
    ----------
    insect : str or Species
        ``hawkmoth``, ``bumblebee``, ``fruit_fly``, ``monarch`` or a :class:`Species`.
    aerodynamics, gravity : bool, optional
        Switch the aerodynamic force and gravity off (for the momentum check); default on.
    n_strips : int, optional
        Span points per wing, in [2, 10000] (FWUAV: 50).
    quadrature : {"fwuav", "gauss"}, optional
        FWUAV's equally weighted points (default) or Gauss-Legendre points on the span.
    body_rate_term : {"fwuav", "rotated"}, optional
        ``Q W`` in the strip velocity as FWUAV (default), or ``Q^T W``.

    Notes
    -----
    State ``(x, v)``: thorax position (m) and velocity (m/s), inertial frame, ``e3`` down.
    """

    def __init__(self, insect: str | Species, *, aerodynamics: bool = True, gravity: bool = True,
                 n_strips: int = 50, quadrature: str = "fwuav",
                 body_rate_term: str = "fwuav") -> None:
        self.species = insect if isinstance(insect, Species) else species(insect)
        self.aerodynamics = bool(aerodynamics)
        self.gravity = bool(gravity)
        self.n_strips = check.integer("n_strips", n_strips, low=2, high=10_000)
        self.quadrature = check.choice("quadrature", quadrature, QUADRATURES)
        self.body_rate_term = check.choice("body_rate_term", body_rate_term, BODY_RATE_TERMS)
        m = self.species.morphology
        if self.quadrature == "fwuav":
            r = np.linspace(0.0, m.span, self.n_strips)
            dr = np.full(self.n_strips, r[1] - r[0])
        else:
            nodes, w = np.polynomial.legendre.leggauss(self.n_strips)
            r, dr = 0.5 * m.span * (nodes + 1.0), 0.5 * m.span * w
        chord = np.polyval(np.array(m.chord_poly), r / m.scale) * m.scale
        self.r = r
        self.weights = chord * dr
        self.mass = m.mass
        self.period = 1.0 / self.species.kinematics.f
        self._last: tuple[float, Motion] | None = None
        self._frames: tuple[Motion, list[_Frames]] | None = None

    def _wing_frames(self, motion: Motion) -> list[_Frames]:
        """Per wing, what the strip velocities take from the motion alone: ``R Q`` (wing to
        inertial), ``P Q^T R^T`` (dU/dv), ``P Q^T (W x mu)`` and the spin term (3, N).

        Remembered for the last motion: the right-hand side and the Jacobian at one instant
        share it (it is two thirds of the work of the strip velocities).
        """
        if self._frames is not None and self._frames[0] is motion:
            return self._frames[1]
        m = self.species.morphology
        out: list[_Frames] = []
        for Q, Om, mu, sign in ((motion.Q_R, motion.Om_R, np.array(m.mu_R), 1.0),
                                (motion.Q_L, motion.Om_L, np.array(m.mu_R) * [1, -1, 1], -1.0)):
            W_w = Q @ motion.W if self.body_rate_term == "fwuav" else Q.T @ motion.W
            spin = sign * _cross(W_w + Om, _E2)
            out.append((motion.R @ Q, _PROJECT @ Q.T @ motion.R.T,
                        _PROJECT @ (Q.T @ _cross(motion.W, mu)),
                        spin[:, None] * self.r[None, :]))
        self._frames = (motion, out)
        return out

    def _strip_velocities(self, motion: Motion, v: np.ndarray
                          ) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """Per wing: ``R Q`` (wing to inertial), ``P Q^T R^T`` (dU/dv) and the strip ``U``."""
        return [(RQ, dU_dv, (dU_dv @ v + offset)[:, None] + spin)
                for RQ, dU_dv, offset, spin in self._wing_frames(motion)]

    def aerodynamic_force(self, motion: Motion, v: np.ndarray) -> np.ndarray:
        """The wings' quasi-steady force at thorax velocity ``v``.

        Parameters
        ----------
        motion : Motion
            The prescribed motion at the instant (:func:`prescribed_motion`).
        v : ndarray, shape (3,)
            Thorax velocity (m/s), inertial frame.

        Returns
        -------
        ndarray, shape (3,)
            Force (N), inertial frame.
        """
        return sum((RQ @ _strip_forces(self.species, U, self.weights)
                    for RQ, _, U in self._strip_velocities(motion, v)), np.zeros(3))

    def aerodynamic_jacobian(self, motion: Motion, v: np.ndarray) -> np.ndarray:
        """``dF_aero / dv`` (N s/m): analytic for Sane & Dickinson's coefficients, else central
        differences (the monarch's fitted curves)."""
        if self.species.morphology.coefficients != "sane-dickinson":
            return central_jacobian(lambda u: self.aerodynamic_force(motion, u), v)
        wings = self._strip_velocities(motion, v)
        G = _strip_jacobians(self.species, np.stack([U for _, _, U in wings], axis=1),
                             self.weights)
        return sum((RQ @ G_w @ dU_dv for (RQ, dU_dv, _), G_w in zip(wings, G, strict=True)),
                   np.zeros((3, 3)))

    def _motion(self, t: float) -> Motion:
        """The prescribed motion at ``t``, remembered for the next call at the same ``t`` (the
        integrators ask for the right-hand side and the Jacobian at the same instants)."""
        if self._last is None or self._last[0] != t:
            self._last = (t, prescribed_motion(self.species, t))
        return self._last[1]

    def loads(self, t: float, x: Any) -> dict[str, np.ndarray]:
        """The three loads on the insect's translation at time ``t`` and state ``x``.

        Parameters
        ----------
        t : float
            Time (s).
        x : array_like, shape (6,)
            Position (m) and velocity (m/s), inertial frame.

        Returns
        -------
        dict
            ``"aerodynamic"``, ``"gravity"`` and ``"inertial"`` (``-sum m_i s_i''``), each a
            force (N, inertial frame) of shape (3,); their sum is ``m x''``.
        """
        motion = self._motion(float(t))
        v = np.asarray(x, dtype=float)[3:6]
        aero = self.aerodynamic_force(motion, v) if self.aerodynamics else np.zeros(3)
        gravity = (self.mass * self.species.morphology.g * _E3 if self.gravity
                   else np.zeros(3))
        return {"aerodynamic": aero, "gravity": gravity, "inertial": -motion.inertial_load}

    def rhs(self, t: float, x: np.ndarray) -> np.ndarray:
        """The right-hand side ``(x', v')`` (m/s, m/s^2) at time ``t`` (s) and state ``x``.

        Parameters
        ----------
        t : float
            Time (s).
        x : ndarray, shape (6,)
            Position (m) and velocity (m/s).

        Returns
        -------
        ndarray, shape (6,)
        """
        f = self.loads(t, x)
        return np.concatenate([x[3:6], (f["aerodynamic"] + f["gravity"] + f["inertial"])
                               / self.mass])

    def velocity_rhs(self, t: float, v: np.ndarray) -> np.ndarray:
        """``v'`` alone: the velocity subsystem (position enters nothing)."""
        return self.rhs(t, np.concatenate([np.zeros(3), v]))[3:6]

    def velocity_jacobian(self, t: float, v: np.ndarray) -> np.ndarray:
        """``d v' / d v`` (1/s): the aerodynamic force's derivative over the mass."""
        if not self.aerodynamics:
            return np.zeros((3, 3))
        motion = self._motion(float(t))
        return self.aerodynamic_jacobian(motion, np.asarray(v, dtype=float)) / self.mass

    def jac(self, t: float, x: np.ndarray) -> np.ndarray:
        """``d(x', v')/d(x, v)``: position columns zero, ``dx'/dv = I``."""
        J = np.zeros((6, 6))
        J[0:3, 3:6] = np.eye(3)
        J[3:6, 3:6] = self.velocity_jacobian(t, x[3:6])
        return J

    def momentum(self, t: float, x: Any) -> np.ndarray:
        """Linear momentum of the whole insect, ``m v + sum_i m_i s_i'``.

        Parameters
        ----------
        t : float
            Time (s).
        x : array_like, shape (6,)
            Position (m) and velocity (m/s).

        Returns
        -------
        ndarray, shape (3,)
            Momentum (kg m/s), inertial frame; constant without aerodynamics and gravity.
        """
        motion = prescribed_motion(self.species, float(t))
        return self.mass * np.asarray(x, dtype=float)[3:6] + motion.appendage_momentum

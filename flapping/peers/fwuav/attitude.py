"""FWUAV's hover with the thorax pitch free: the planar reduction of its attitude-free model.

FWUAV's attitude-free hover (``floquet_stability.m``, ``eom_hover_xR`` with ``n = 12``: position,
attitude, velocity and angular velocity of the thorax) lets the thorax rotate under the
aerodynamic and inertial moments while the wing and abdomen angles relative to the thorax stay
prescribed. With both wings moving as mirror images, the plane of symmetry is invariant: a
motion that starts in it (no sideslip, roll or yaw) stays in it, and the longitudinal block of
the twelve Floquet exponents is that of the planar system with the state::

    (x_1, x_3, theta, v_1, v_3, q)

(thorax position in the plane, thorax pitch with ``R = exp(theta hat e2)``, velocity, pitch rate
``q``; inertial frame, ``e3`` down). This module solves that system; the lateral block (sideslip,
roll, yaw) is not computed.

Equations (Newton and Euler for the four bodies, with the relative motion prescribed). With
``p_i`` the position of body ``i``'s centre of mass relative to the thorax's (thorax frame),
``a`` the thorax acceleration and ``W = q e2``::

    m a + sum_i m_i R s_i = F_aero + m g e3,
    sum_i (R p_i) x m_i (a + R s_i) + R (J_B W' + W x J_B W)
        + sum_i R Q_i (J_i w_i' + w_i x J_i w_i) = M_aero + sum_i (R p_i) x m_i g e3,

where ``s_i = W x (W x p_i) + W' x p_i + 2 W x p_i' + p_i''``, ``w_i = Q_i^T W + Om_i`` is the
angular velocity of body ``i`` in its own frame (``w_i' = Q_i^T W' - Om_i x Q_i^T W + Om_i'``),
``J_i`` its inertia about its centre of mass (FWUAV stores the wings' and abdomen's about their
joints: we shift them), and ``M_aero`` the moment about the thorax's centre of mass of the strip
forces, each applied at its strip's point ``mu + Q (+/- r e2)`` on the span axis (as FWUAV's
``wing_QS_aerodynamics.m`` does: its wing moment is ``sum r e2 x dF``). The equations are linear
in ``(a, q')``; we take the ``e1``, ``e3`` force and the ``e2`` moment components. The strip
forces are :class:`~flapping.peers.fwuav.model.FwuavHover`'s at the free attitude and rate.

With ``pitch="prescribed"`` the pitch follows FWUAV's sinusoid and only the force equation is
solved: :class:`FwuavHover`'s model, which the tests check.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np

import flapping._validation as check
from flapping._numdiff import central_jacobian
from flapping.errors import ConvergenceError, require_success
from flapping.peers.fwuav.data import Species, species
from flapping.peers.fwuav.model import (
    FwuavHover,
    Motion,
    _cross,
    _rot,
    _sinusoid,
    _strip_forces,
    _wing,
    prescribed_motion,
    wing_angles,
)
from flapping.periodic.floquet import monodromy
from flapping.periodic.integrate import flow
from flapping.periodic.shooting import find_periodic_orbit

__all__ = ["FwuavPitchFree", "PitchFreeFloquet", "pitch_free_floquet", "pitch_free_model",
           "PITCH_MODES", "TRIM_PARAMETERS", "DEFAULT_TRIM"]

#: How the thorax pitch moves: free (a state) or FWUAV's prescribed sinusoid.
PITCH_MODES = ("free", "prescribed")
#: FWUAV's kinematic parameters a pitch-free trim may adjust (rad; all are among the 21 that
#: FWUAV's ``sim_QS_x_hover.m`` optimises): stroke-plane angle, stroke amplitude, mean stroke
#: angle.
TRIM_PARAMETERS = ("beta", "phi_m", "phi_0")
#: The pair ``trim=True`` adjusts: the stroke amplitude ``phi_m`` (the wing speed, hence the
#: vertical force, grows with it) and the mean stroke angle ``phi_0`` (it moves the wings' centre
#: of pressure fore and aft of the centre of mass: the pitch moment, hence the pitch the thorax
#: settles at, hence the tilt of the mean force and the horizontal drift).
DEFAULT_TRIM = ("phi_m", "phi_0")
#: Where a trimmed parameter still describes a wingbeat (rad): a stroke plane within a right
#: angle of the thorax's, an amplitude below a quarter turn, a mean stroke angle that keeps the
#: stroke within +-90 deg.
_TRIM_BOUNDS = {"beta": (-math.pi / 2, math.pi / 2), "phi_m": (0.0, math.pi / 2),
                "phi_0": (-math.pi / 2, math.pi / 2)}

_E2, _E3 = np.eye(3)[1], np.eye(3)[2]
#: Per body (right wing, left wing, abdomen): attitude, angular velocity, its derivative.
_Rates = tuple[tuple[np.ndarray, np.ndarray, np.ndarray], ...]
#: Per body: ``p_i``, ``p_i'``, ``p_i''`` (thorax frame).
_Geometry = tuple[tuple[np.ndarray, np.ndarray, np.ndarray], ...]


def _shift_to_centre(J: np.ndarray, m: float, nu: np.ndarray) -> np.ndarray:
    """Inertia about the centre of mass from the inertia about a point ``nu`` away from it."""
    return J - m * (float(nu @ nu) * np.eye(3) - np.outer(nu, nu))


class FwuavPitchFree:
    """FWUAV's four-body hover in the plane of symmetry, the thorax pitch free.

    Parameters
    ----------
    insect : str or Species
        ``hawkmoth``, ``bumblebee``, ``fruit_fly`` (Sane & Dickinson's coefficients).
    pitch : {"free", "prescribed"}, optional
        The pitch a state (default) or FWUAV's prescribed sinusoid.
    body_rate_term : {"fwuav", "rotated"}, optional
        The body-rate term of the strip velocity: FWUAV's ``Q W`` (default) or ``Q^T W``.
    n_strips : int, optional
        Span points per wing, in [2, 10000] (FWUAV: 50).
    aerodynamics, gravity : bool, optional
        Switch the aerodynamic loads and gravity off (for the momentum check); default on.

    Notes
    -----
    State ``(x_1, x_3, theta, v_1, v_3, q)``: m, m, rad, m/s, m/s, rad/s; ``e3`` down, ``theta``
    the thorax pitch (FWUAV's ``theta_B``, nose up positive about ``e2``).
    """

    def __init__(self, insect: str | Species, *, pitch: str = "free",
                 body_rate_term: str = "fwuav", n_strips: int = 50, aerodynamics: bool = True,
                 gravity: bool = True) -> None:
        self.species = insect if isinstance(insect, Species) else species(insect)
        if self.species.morphology.coefficients != "sane-dickinson":
            raise ValueError(f"`insect` must have Sane & Dickinson's coefficients (hawkmoth, "
                             f"bumblebee, fruit_fly); got {self.species.name!r}")
        self.pitch = check.choice("pitch", pitch, PITCH_MODES)
        self.hover = FwuavHover(self.species, n_strips=n_strips, body_rate_term=body_rate_term)
        self.aerodynamics, self.gravity = bool(aerodynamics), bool(gravity)
        m = self.species.morphology
        self.mass = m.mass
        self.period = 1.0 / self.species.kinematics.f
        mirror = np.array([1.0, -1.0, 1.0])
        nu_R, nu_A = np.array(m.nu_R), np.array(m.nu_A)
        J_R = np.array(m.J_R).reshape(3, 3)
        J_L = J_R * np.outer(mirror, mirror)
        # (mass, joint, centre of mass from the joint, inertia about the centre of mass)
        self._bodies = (
            (m.m_wing, np.array(m.mu_R), nu_R, _shift_to_centre(J_R, m.m_wing, nu_R)),
            (m.m_wing, np.array(m.mu_R) * mirror, nu_R * mirror,
             _shift_to_centre(J_L, m.m_wing, nu_R * mirror)),
            (m.m_A, np.array(m.mu_A), nu_A,
             _shift_to_centre(np.array(m.J_A).reshape(3, 3), m.m_A, nu_A)),
        )
        self._J_B = np.array(m.J_B).reshape(3, 3)
        # The prescribed motion and rates at the last instant, and the motion at the last
        # (instant, pitch, pitch rate): a central-difference Jacobian evaluates the right-hand
        # side 8 times at one instant, 4 of them at one attitude. The same values, computed once.
        self._at: tuple[float, Motion, _Rates, tuple[_Geometry, np.ndarray]] | None = None
        self._posed: tuple[tuple[float, float, float], Motion] | None = None
        self._spun: tuple[Motion, Any] | None = None

    def _prescribed_pitch(self, t: float) -> tuple[float, float, float]:
        k = self.species.kinematics
        return _sinusoid(k.theta_B_m, k.theta_B_0, k.theta_B_a, 2.0 * math.pi * k.f, t)

    def _aerodynamics(self, motion: Motion, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Force (inertial) and moment about the thorax's centre of mass (thorax frame)."""
        h = self.hover
        force, moment = np.zeros(3), np.zeros(3)
        mu = np.array(self.species.morphology.mu_R)
        for (RQ, _, U), Q, sign in zip(h._strip_velocities(motion, v), (motion.Q_R, motion.Q_L),
                                       (1.0, -1.0), strict=True):
            F = _strip_forces(self.species, U, h.weights)          # wing frame
            rF = _strip_forces(self.species, U, h.weights * h.r)   # sum r_k dF_k (linear in w)
            joint = mu * np.array([1.0, sign, 1.0])
            force += RQ @ F
            moment += _cross(joint, Q @ F) + Q @ (sign * _cross(_E2, rF))
        return force, moment

    def _geometry(self, rates: _Rates) -> tuple[_Geometry, np.ndarray]:
        """Per body ``p_i``, ``p_i'``, ``p_i''`` (thorax frame), and ``sum m_i p_i``: they depend
        on the prescribed relative motion alone, hence on the time alone."""
        out, first = [], np.zeros(3)
        for (mi, mu, nu, _), (Q, Om, dOm) in zip(self._bodies, rates, strict=True):
            p = mu + Q @ nu
            dp = Q @ _cross(Om, nu)
            ddp = Q @ (_cross(Om, _cross(Om, nu)) + _cross(dOm, nu))
            out.append((p, dp, ddp))
            first += mi * p
        return tuple(out), first

    def _parts(self, motion: Motion, rates: _Rates, theta_ddot: float,
               geometry: tuple[_Geometry, np.ndarray] | None = None
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Inertial force ``sum m_i R s_i`` (inertial frame, without ``a``), the inertial moment
        (thorax frame, without the ``a`` terms) and ``sum m_i p_i`` (thorax frame), at pitch
        acceleration ``theta_ddot`` (``geometry``: :meth:`_geometry` of ``rates``, if known)."""
        dW = theta_ddot * _E2
        positions, first = self._geometry(rates) if geometry is None else geometry
        gyro, spins = self._spins(motion, rates, positions)
        force, moment = np.zeros(3), self._J_B @ dW + gyro
        for (mi, _, _, J), (Q, _, dOm), (p, _, ddp), (centripetal, coriolis, QtW_x, spin) in zip(
                self._bodies, rates, positions, spins, strict=True):
            s = centripetal + _cross(dW, p) + coriolis + ddp
            force += mi * s
            dwi = Q.T @ dW - QtW_x + dOm
            moment += mi * _cross(p, s) + Q @ (J @ dwi + spin)
        return motion.R @ force, moment, first

    def _spins(self, motion: Motion, rates: _Rates, positions: _Geometry
               ) -> tuple[np.ndarray, tuple[tuple[np.ndarray, ...], ...]]:
        """The terms of :meth:`_parts` that the pitch acceleration leaves alone: ``W x J_B W``
        and per body ``W x (W x p_i)``, ``2 W x p_i'``, ``Om_i x Q_i^T W``, ``w_i x J_i w_i``;
        remembered for the last motion (the four residuals of one right-hand side share it)."""
        if self._spun is not None and self._spun[0] is motion:
            return self._spun[1]
        W = motion.W
        out = []
        for (_, _, _, J), (Q, Om, _), (p, dp, _) in zip(self._bodies, rates, positions,
                                                        strict=True):
            wi = Q.T @ W + Om
            out.append((_cross(W, _cross(W, p)), 2.0 * _cross(W, dp), _cross(Om, Q.T @ W),
                        _cross(wi, J @ wi)))
        terms = (_cross(W, self._J_B @ W), tuple(out))
        self._spun = (motion, terms)
        return terms

    def _rates(self, t: float, motion: Motion) -> _Rates:
        """Per body: attitude, angular velocity and acceleration relative to the thorax."""
        k = self.species.kinematics
        angles = wing_angles(k, t)
        _, dth_A, ddth_A = _sinusoid(k.theta_A_m, k.theta_A_0, k.theta_A_a,
                                     2.0 * math.pi * k.f, t)
        return ((motion.Q_R, motion.Om_R, _wing(k.beta, angles, 1.0)[2]),
                (motion.Q_L, motion.Om_L, _wing(k.beta, angles, -1.0)[2]),
                (motion.Q_A, dth_A * _E2, ddth_A * _E2))

    def _prescribed(self, t: float) -> tuple[Motion, _Rates]:
        """The prescribed motion and the bodies' rates at ``t``, remembered for the last ``t``
        (they depend on the time alone)."""
        if self._at is None or self._at[0] != t:
            base = prescribed_motion(self.species, t)
            rates = self._rates(t, base)
            self._at = (t, base, rates, self._geometry(rates))
        return self._at[1], self._at[2]

    def _geometry_at(self, t: float) -> tuple[_Geometry, np.ndarray]:
        """:meth:`_geometry` at ``t`` (remembered with the prescribed motion)."""
        self._prescribed(t)
        assert self._at is not None
        return self._at[3]

    def _motion(self, t: float, theta: float, q: float) -> Motion:
        key = (t, theta, q)
        if self._posed is None or self._posed[0] != key:
            base, _ = self._prescribed(t)
            # one object per attitude: the wings' frames are remembered per motion object
            self._posed = (key, dataclasses.replace(base, R=_rot(1, theta), W=q * _E2))
        return self._posed[1]

    def accelerations(self, t: float, state: np.ndarray) -> tuple[np.ndarray, float]:
        """Thorax acceleration (inertial, m/s^2) and pitch acceleration (rad/s^2).

        Parameters
        ----------
        t : float
            Time (s).
        state : ndarray, shape (6,)
            ``(x_1, x_3, theta, v_1, v_3, q)``.

        Returns
        -------
        a : ndarray, shape (3,)
            Thorax acceleration; ``a_2 = 0`` by symmetry.
        theta_ddot : float
            Pitch acceleration (the prescribed one with ``pitch="prescribed"``).
        """
        t = float(t)
        state = np.asarray(state, dtype=float)
        if self.pitch == "prescribed":
            theta, q, prescribed = self._prescribed_pitch(t)
        else:
            theta, q = float(state[2]), float(state[5])
        motion = self._motion(t, theta, q)
        _, rates = self._prescribed(t)
        v = np.array([state[3], 0.0, state[4]])
        F, M = self._aerodynamics(motion, v) if self.aerodynamics else (np.zeros(3), np.zeros(3))
        m, g = self.mass, self.species.morphology.g * self.gravity
        R = motion.R

        # three of the four residuals of the free pitch share the inertial terms at dd = 0
        geometry = self._geometry_at(t)
        at_rest = self._parts(motion, rates, 0.0, geometry) if self.pitch == "free" else None

        def residual(a: np.ndarray, dd: float) -> np.ndarray:
            f_in, m_in, first = (at_rest if dd == 0.0 and at_rest is not None
                                 else self._parts(motion, rates, dd, geometry))
            force = m * a + f_in - F - m * g * _E3
            # moment about the thorax centre of mass, thorax frame
            moment = _cross(first, R.T @ a - g * (R.T @ _E3)) + m_in - M
            return np.array([force[0], force[2], moment[1]])

        if self.pitch == "prescribed":
            base = residual(np.zeros(3), prescribed)
            A = np.array([[m, 0.0], [0.0, m]])
            a13 = np.linalg.solve(A, -base[:2])
            return np.array([a13[0], 0.0, a13[1]]), prescribed
        base = residual(np.zeros(3), 0.0)
        cols = [residual(np.array([1.0, 0.0, 0.0]), 0.0) - base,
                residual(np.array([0.0, 0.0, 1.0]), 0.0) - base,
                residual(np.zeros(3), 1.0) - base]
        z = np.linalg.solve(np.column_stack(cols), -base)
        return np.array([z[0], 0.0, z[1]]), float(z[2])

    def rhs(self, t: float, state: np.ndarray) -> np.ndarray:
        """``d/dt (x_1, x_3, theta, v_1, v_3, q)`` at time ``t`` (s)."""
        a, dd = self.accelerations(t, state)
        if self.pitch == "prescribed":
            _, q, _ = self._prescribed_pitch(float(t))
        else:
            q = float(state[5])
        return np.array([state[3], state[4], q, a[0], a[2], dd])

    def jac(self, t: float, state: np.ndarray) -> np.ndarray:
        """Central-difference Jacobian of :meth:`rhs` (6x6)."""
        return central_jacobian(lambda y: self.rhs(t, y), np.asarray(state, dtype=float))

    def momentum(self, t: float, state: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Linear momentum and angular momentum about the inertial origin of the four bodies.

        Parameters
        ----------
        t : float
            Time (s).
        state : ndarray, shape (6,)
            ``(x_1, x_3, theta, v_1, v_3, q)``.

        Returns
        -------
        P : ndarray, shape (3,)
            Linear momentum (kg m/s), inertial frame.
        H : ndarray, shape (3,)
            Angular momentum about the origin (kg m^2/s), inertial frame; both are constant
            without aerodynamics and gravity.
        """
        t = float(t)
        state = np.asarray(state, dtype=float)
        if self.pitch == "prescribed":
            theta, q, _ = self._prescribed_pitch(t)
        else:
            theta, q = float(state[2]), float(state[5])
        motion = self._motion(t, theta, q)
        x, v = np.array([state[0], 0.0, state[1]]), np.array([state[3], 0.0, state[4]])
        return self._momentum(x, v, motion.R, motion.W, self._rates(t, motion))

    def _momentum(self, x: np.ndarray, v: np.ndarray, R: np.ndarray, W: np.ndarray,
                  rates: _Rates) -> tuple[np.ndarray, np.ndarray]:
        """Linear and angular momentum (about the origin) of the four bodies at any thorax
        position ``x``, velocity ``v``, attitude ``R`` and angular velocity ``W`` (3-D: the
        attitude-free model shares it)."""
        m_B = self.species.morphology.m_B
        P, H = m_B * v, _cross(x, m_B * v) + R @ (self._J_B @ W)
        for (mi, mu, nu, J), (Q, Om, _) in zip(self._bodies, rates, strict=True):
            p = mu + Q @ nu
            vi = v + R @ (_cross(W, p) + Q @ _cross(Om, nu))
            P = P + mi * vi
            H = H + _cross(x + R @ p, mi * vi) + R @ Q @ (J @ (Q.T @ W + Om))
        return P, H


@dataclass(frozen=True)
class PitchFreeFloquet:
    """The periodic orbit of FWUAV's pitch-free hover and its Floquet multipliers.

    Attributes
    ----------
    name : str
        The insect.
    body_rate_term : str
        ``"fwuav"`` (``Q W``) or ``"rotated"`` (``Q^T W``).
    y0 : ndarray, shape (4,)
        ``(theta, v_1, v_3, q)`` at ``t = 0`` on the orbit (rad, m/s, m/s, rad/s).
    period : float
        ``1 / f`` (s).
    multipliers : ndarray, shape (4,), complex
        Floquet multipliers of ``(theta, v_1, v_3, q)``, by modulus, descending (the two of the
        position, exactly one, are left out).
    exponents : ndarray, shape (4,), complex
        ``log(multipliers) / period`` (1/s), same order.
    mean_pitch : float
        Mean thorax pitch over the orbit (rad).
    pitch_amplitude : float
        Half the peak-to-peak thorax pitch on the orbit (rad).
    mean_velocity : ndarray, shape (2,)
        Mean ``(v_1, v_3)`` over the orbit (m/s): its drift.
    residual_norm : float
        Shooting residual.
    liouville_error : float
        Relative mismatch of ``det M`` and ``exp(int trace J)``.
    monodromy : ndarray, shape (4, 4)
    trim_parameters : tuple of str
        The kinematic parameters adjusted for a pitch-free hover (empty: FWUAV's kinematics).
    trim_values : tuple of float
        Their trimmed values (rad), same order.
    trim_nfev : int
        Residual evaluations of the trim (0 without one).
    """

    name: str
    body_rate_term: str
    y0: np.ndarray
    period: float
    multipliers: np.ndarray
    exponents: np.ndarray
    mean_pitch: float
    pitch_amplitude: float
    mean_velocity: np.ndarray
    residual_norm: float
    liouville_error: float
    monodromy: np.ndarray = field(repr=False)
    trim_parameters: tuple[str, ...] = ()
    trim_values: tuple[float, ...] = ()
    trim_nfev: int = 0


def _reduced(model: FwuavPitchFree) -> tuple[Callable[[float, np.ndarray], np.ndarray],
                                             Callable[[float, np.ndarray], np.ndarray]]:
    """Right-hand side of ``(theta, v_1, v_3, q)`` (the position enters nothing) and its
    central-difference Jacobian."""

    def fun(t: float, y: np.ndarray) -> np.ndarray:
        return model.rhs(t, np.concatenate([[0.0, 0.0], y]))[2:]

    def jac(t: float, y: np.ndarray) -> np.ndarray:
        return central_jacobian(lambda z: fun(t, z), np.asarray(y, dtype=float))

    return fun, jac


def _floquet(model: FwuavPitchFree, name: str, body_rate_term: str, y0: np.ndarray,
             residual_norm: float, rtol: float, trim_parameters: tuple[str, ...] = (),
             trim_values: tuple[float, ...] = (), trim_nfev: int = 0) -> PitchFreeFloquet:
    """Orbit statistics and Floquet multipliers of the closed orbit through ``y0``."""
    fun, jac = _reduced(model)
    T = model.period
    path = require_success(flow(fun, (0.0, T), y0, rtol=rtol, atol=rtol * 0.1,
                                t_eval=np.linspace(0.0, T, 201)),
                           "the pitch-free orbit over one period")
    mono = monodromy(fun, y0, T, jac=jac, rtol=rtol, atol=rtol * 0.1)
    order = np.argsort(-np.abs(mono.multipliers), kind="stable")
    pitch = path.x[0, :-1]
    return PitchFreeFloquet(
        name=name, body_rate_term=body_rate_term, y0=y0, period=T,
        multipliers=mono.multipliers[order], exponents=mono.exponents[order],
        mean_pitch=float(pitch.mean()), pitch_amplitude=float(np.ptp(pitch) / 2.0),
        mean_velocity=path.x[1:3, :-1].mean(axis=1), residual_norm=float(residual_norm),
        liouville_error=float(mono.liouville_error), monodromy=mono.matrix,
        trim_parameters=trim_parameters, trim_values=trim_values, trim_nfev=trim_nfev)


def _start(model: FwuavPitchFree) -> np.ndarray:
    """FWUAV's pitch, velocity and pitch rate at the start of its wingbeat."""
    theta, q, _ = model._prescribed_pitch(0.0)
    v = model.species.velocity_guess
    return np.array([theta, v[0], v[2], q])


@lru_cache(maxsize=8)
def _pitch_free(name: str, body_rate_term: str, rtol: float) -> PitchFreeFloquet:
    model = FwuavPitchFree(name, body_rate_term=body_rate_term)
    fun, jac = _reduced(model)
    orbit = find_periodic_orbit(fun, _start(model), model.period, autonomous=False, jac=jac,
                                rtol=rtol, atol=rtol * 0.1, tol=min(1e3 * rtol, 1e-6))
    return _floquet(model, name, body_rate_term, orbit.x0, orbit.residual_norm, rtol)


class _Retrimmed:
    """The six-state right-hand side ``(x_1, x_3, theta, v_1, v_3, q)`` as a function of the
    trimmed kinematic parameters (the last argument), one model per parameter set."""

    def __init__(self, name: str, body_rate_term: str, parameters: tuple[str, ...]) -> None:
        self.base = species(name)
        self.body_rate_term, self.parameters = body_rate_term, parameters
        self._models: dict[tuple[float, ...], FwuavPitchFree] = {}

    def model(self, values: np.ndarray) -> FwuavPitchFree:
        key = tuple(float(v) for v in values)
        if key not in self._models:
            if len(self._models) > 16:  # the shooting asks for a few sets at a time
                self._models.clear()
            changes: dict[str, Any] = dict(zip(self.parameters, key, strict=True))
            k = dataclasses.replace(self.base.kinematics, **changes)
            self._models[key] = FwuavPitchFree(dataclasses.replace(self.base, kinematics=k),
                                               body_rate_term=self.body_rate_term)
        return self._models[key]

    def fun(self, t: float, x: np.ndarray, values: np.ndarray) -> np.ndarray:
        return self.model(values).rhs(t, x)

    def jac(self, t: float, x: np.ndarray, values: np.ndarray) -> np.ndarray:
        """Central differences in ``(theta, v_1, v_3, q)``; the position's two columns are
        zero (it enters nothing), so they are not differenced."""
        model = self.model(values)
        x = np.asarray(x, dtype=float)
        J = np.zeros((6, 6))
        J[:, 2:] = central_jacobian(lambda z: model.rhs(t, np.concatenate([x[:2], z])), x[2:])
        return J


def _check_trim(trim: object) -> tuple[str, ...]:
    """``()`` for no trim, else the two parameter names."""
    if trim is False:
        return ()
    if trim is True:
        return DEFAULT_TRIM
    if (isinstance(trim, (tuple, list)) and len(trim) == 2 and len(set(trim)) == 2
            and all(isinstance(p, str) and p in TRIM_PARAMETERS for p in trim)):
        return tuple(trim)
    raise ValueError(f"`trim` must be True, False or two different names among "
                     f"{', '.join(TRIM_PARAMETERS)}; got {trim!r}")


@lru_cache(maxsize=8)
def _trimmed(name: str, body_rate_term: str, rtol: float, parameters: tuple[str, ...]
             ) -> PitchFreeFloquet:
    system = _Retrimmed(name, body_rate_term, parameters)
    k = system.base.kinematics
    start = np.concatenate([[0.0, 0.0], _start(system.model(np.array(
        [getattr(k, p) for p in parameters])))])
    guess = np.array([getattr(k, p) for p in parameters])
    tol = min(1e3 * rtol, 1e-6)
    try:
        orbit = find_periodic_orbit(system.fun, start, 1.0 / k.f, autonomous=False,
                                    jac=system.jac, free_params=guess, fixed=(0, 1), rtol=rtol,
                                    atol=rtol * 0.1, tol=tol, max_nfev=60)
    except ConvergenceError as error:
        raise ConvergenceError(
            f"no pitch-free hover of the {name} by adjusting {', '.join(parameters)}: "
            f"{error}", x=error.x, residual=error.residual, iterations=error.iterations,
            result=error.result) from error
    assert orbit.params is not None
    values = orbit.params
    for p, value in zip(parameters, values.tolist(), strict=True):
        low, high = _TRIM_BOUNDS[p]
        if not low < value < high:
            raise ConvergenceError(f"the trimmed {p} = {value:.4g} rad is outside ({low:.4g}, "
                                   f"{high:.4g})", x=orbit.unknowns, residual=orbit.residual_norm,
                                   iterations=orbit.nit, result=orbit)
    return _floquet(system.model(values), name, body_rate_term, orbit.x0[2:],
                    orbit.residual_norm, rtol, trim_parameters=parameters,
                    trim_values=tuple(float(v) for v in values), trim_nfev=int(orbit.nfev))


def pitch_free_floquet(name: str, *, body_rate_term: str = "fwuav", rtol: float = 1e-9,
                       trim: bool | tuple[str, str] = False) -> PitchFreeFloquet:
    """FWUAV's hover with the thorax pitch free: periodic orbit and Floquet multipliers.

    Without ``trim``, the orbit flown by FWUAV's kinematics (optimised by FWUAV with the pitch
    prescribed): with the pitch free it is no hover, it sinks and drifts (``mean_velocity``).
    With ``trim``, two of FWUAV's kinematic parameters are adjusted together with the orbit's
    initial state so that the orbit is periodic and its mean velocity zero in both components:
    six conditions (four of periodicity, two of a closed position) on six unknowns (the state
    and the two parameters), solved by our shooting
    (:func:`~flapping.periodic.shooting.find_periodic_orbit`, the position a state held at zero
    at the start, the two parameters free).
    The default pair is the stroke amplitude ``phi_m``, which sets the wing speed and hence the
    vertical force, and the mean stroke angle ``phi_0``, which moves the wings' centre of
    pressure fore and aft of the centre of mass, hence the pitch moment, the pitch the thorax
    settles at and the tilt of the mean force (the horizontal drift).

    Parameters
    ----------
    name : str
        ``hawkmoth``, ``bumblebee`` or ``fruit_fly``.
    body_rate_term : {"fwuav", "rotated"}, optional
        The body-rate term of the strip velocity (FWUAV's ``Q W`` by default).
    rtol : float, optional
        Relative tolerance of every integration, in [1e-12, 1e-6] (absolute ``rtol / 10``;
        shooting residual ``min(1000 rtol, 1e-6)``, in rad, m/s, rad/s and, with ``trim``, m
        of position after one period).
    trim : bool or tuple of two str, optional
        ``False`` (default): FWUAV's kinematics. ``True``: re-trimmed for a pitch-free hover
        by adjusting :data:`DEFAULT_TRIM`; or two different names among
        :data:`TRIM_PARAMETERS`.

    Returns
    -------
    PitchFreeFloquet
        Cached per argument set; with ``trim``, ``trim_parameters`` and ``trim_values`` say
        what was adjusted, and ``residual_norm`` is that of the six conditions.

    Raises
    ------
    ValueError
        For an unknown name or an argument out of range.
    ConvergenceError
        If the shooting (or the trim) does not converge or an integration fails; it carries
        the last iterate, its residual norm and the iteration count.
    """
    FwuavPitchFree(name, body_rate_term=body_rate_term)  # checks both
    # any real type (float32, int, 0-d array) is accepted and converted to float
    rtol = check.real("rtol", rtol, low=1e-12, high=1e-6)
    parameters = _check_trim(trim)
    if parameters:
        return _trimmed(name, body_rate_term, float(rtol), parameters)
    return _pitch_free(name, body_rate_term, float(rtol))


def pitch_free_model(result: PitchFreeFloquet) -> FwuavPitchFree:
    """The pitch-free model whose orbit ``result`` is: FWUAV's kinematics, or the re-trimmed ones.

    Parameters
    ----------
    result : PitchFreeFloquet
        From :func:`pitch_free_floquet` (with or without ``trim``).

    Returns
    -------
    FwuavPitchFree
        The model with ``result.trim_values`` in place of FWUAV's values of
        ``result.trim_parameters``; ``result.y0`` lies on its periodic orbit (e.g. for
        :func:`~flapping.peers.fwuav.attitude3d.attitude_free_floquet`).

    Raises
    ------
    ValueError
        If ``result`` is not a :class:`PitchFreeFloquet`.
    """
    check.instance("result", result, PitchFreeFloquet)
    base = species(result.name)
    changes: dict[str, Any] = dict(zip(result.trim_parameters, result.trim_values, strict=True))
    kinematics = dataclasses.replace(base.kinematics, **changes)
    return FwuavPitchFree(dataclasses.replace(base, kinematics=kinematics),
                          body_rate_term=result.body_rate_term)

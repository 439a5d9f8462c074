"""FWUAV's attitude-free hover in 3-D: the thorax attitude free, and its lateral Floquet block.

FWUAV's attitude-free hover (``floquet_stability.m`` with ``eom_hover_xR``, ``n = 12``) frees
the thorax's position ``x``, attitude ``R`` in SO(3), velocity ``v`` and body angular velocity
``W``; the wing and abdomen angles relative to the thorax stay prescribed. The planar,
pitch-free reduction is :class:`~flapping.peers.fwuav.attitude.FwuavPitchFree`; this module
solves the full system and computes all its Floquet multipliers about the planar periodic orbit.

Equations. Newton and Euler for the four bodies, as in
:mod:`flapping.peers.fwuav.attitude`, now with ``W`` and ``W'`` any 3-vectors. They are
linear in the thorax acceleration ``a`` (inertial frame) and ``W'`` (thorax frame)::

    [ m I      -R S^ ] [ a  ]   [ F + m g e3 - R sum_i m_i c_i                           ]
    [ S^ R^T   J_loc ] [ W' ] = [ M + S x g R^T e3 - W x J_B W
                                      - sum_i (m_i p_i x c_i + Q_i (J_i e_i + w_i x J_i w_i)) ]

with ``S = sum_i m_i p_i`` (first moment of the appendages about the thorax's centre of mass),
``J_loc = J_B + sum_i (Q_i J_i Q_i^T + m_i (|p_i|^2 I - p_i p_i^T))`` (the locked inertia),
``c_i = W x (W x p_i) + 2 W x p_i' + p_i''``, ``w_i = Q_i^T W + Om_i``,
``e_i = -Om_i x Q_i^T W + Om_i'``, and ``F``, ``M`` the strip forces and their moment about the
thorax's centre of mass at the free ``R``, ``v``, ``W`` (both forms of the body-rate term of the
strip velocity, as :class:`~flapping.peers.fwuav.model.FwuavHover`). The kinematics:
``x' = v``, ``R' = R W^``. The state is FWUAV's ``X`` with ``R`` stored row by row::

    (x (3), R.ravel() (9), v (3), W (3))                          18 entries

Linearisation: exponential coordinates. A perturbation of the attitude is ``R = R_o exp(xi^)``
about the orbit's ``R_o(t)`` (FWUAV's ``R*expmhat(dR)``), so the perturbation
``(dx, xi, dv, dW)`` lives in a linear space R^12 and obeys::

    dx' = dv,    xi' = -W_o x xi + dW,    (dv', dW') = d(a, W')/d(xi, dv, dW) (xi, dv, dW)

(the middle one as in FWUAV's ``eom_hover_xR``: ``d_mat(4:6) = -hat(W)*dR + dW``). We take
these rather than Euler angles because they have no singular attitude and because the planar
orbit's pitch perturbation is exactly ``xi_2`` (``R_o = exp(theta e2^)``), its roll and yaw
``xi_1`` and ``xi_3``, so the blocks of the monodromy are directly the longitudinal
``(xi_2, v_1, v_3, W_2)`` (the pitch-free model's ``(theta, v_1, v_3, q)``) and the lateral
``(xi_1, xi_3, v_2, W_1, W_3)``. The derivative of ``(a, W')`` is taken by central differences
(FWUAV: forward differences of its ``eom_QS_xR`` with ``epsilon = 1e-8``) at every evaluation,
integrated with the orbit (reference and the 9 x 9 transition matrix of ``(xi, v, W)``; the
position enters nothing, so its three multipliers are exactly one and left out).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

import flapping._validation as check
from flapping._numdiff import central_jacobian
from flapping.errors import ClosureWarning, ConvergenceError
from flapping.peers.fwuav.attitude import FwuavPitchFree, pitch_free_floquet
from flapping.peers.fwuav.data import Species
from flapping.peers.fwuav.model import Motion, _cross, _rot, prescribed_motion
from flapping.periodic.floquet import CLOSURE_TOL

__all__ = ["FwuavAttitudeFree", "AttitudeFreeFloquet", "attitude_free_floquet",
           "LONGITUDINAL", "LATERAL", "Y0_LIMITS", "MAX_NFEV"]

#: Indices of the longitudinal ``(xi_2, v_1, v_3, W_2)`` and lateral ``(xi_1, xi_3, v_2, W_1,
#: W_3)`` perturbations in ``(xi, v, W)`` (9 entries).
LONGITUDINAL = (1, 3, 5, 7)
LATERAL = (0, 2, 4, 6, 8)

_E3 = np.eye(3)[2]


def _hat(w: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def _expm_hat(xi: np.ndarray) -> np.ndarray:
    """``exp(xi^)`` by Rodrigues' formula (series below 1e-8 rad)."""
    angle = math.sqrt(float(xi @ xi))
    K = _hat(xi)
    if angle < 1e-8:
        return np.eye(3) + K + 0.5 * K @ K
    return (np.eye(3) + math.sin(angle) / angle * K
            + (1.0 - math.cos(angle)) / angle**2 * K @ K)


class FwuavAttitudeFree:
    """FWUAV's four-body hover with the thorax attitude free in 3-D (``eom_hover_xR``).

    Parameters
    ----------
    insect : str, Species or FwuavPitchFree
        ``hawkmoth``, ``bumblebee``, ``fruit_fly`` (Sane & Dickinson's coefficients), or a
        pitch-free model whose insect, strips, body-rate term and switches are taken (so a model
        built with other options, e.g. a trim, is extended to 3-D as it is).
    body_rate_term : {"fwuav", "rotated"}, optional
        The body-rate term of the strip velocity: FWUAV's ``Q W`` (default) or ``Q^T W``.
    n_strips : int, optional
        Span points per wing, in [2, 10000] (FWUAV: 50).
    aerodynamics, gravity : bool, optional
        Switch the aerodynamic loads and gravity off (for the momentum check); default on.
        With a model for ``insect``, these four must stay at their defaults (the model's own
        apply).

    Notes
    -----
    State ``(x, R.ravel(), v, W)`` (18 entries): m, -, m/s, rad/s; inertial frame with ``e3``
    down, ``W`` in the thorax frame.
    """

    def __init__(self, insect: str | Species | FwuavPitchFree, *, body_rate_term: str = "fwuav",
                 n_strips: int = 50, aerodynamics: bool = True, gravity: bool = True) -> None:
        if isinstance(insect, FwuavPitchFree):
            given = {"body_rate_term": (body_rate_term, "fwuav"), "n_strips": (n_strips, 50),
                     "aerodynamics": (aerodynamics, True), "gravity": (gravity, True)}
            changed = [k for k, (value, default) in given.items() if value != default]
            if changed:
                raise ValueError(f"{', '.join(f'`{k}`' for k in changed)} must be left at the "
                                 "default when `insect` is a model (the model's own are used)")
            if insect.pitch != "free":
                raise ValueError("`insect` must be a pitch-free model (pitch='free'); got "
                                 f"pitch={insect.pitch!r}")
            self.planar = insect
        else:
            self.planar = FwuavPitchFree(insect, body_rate_term=body_rate_term, n_strips=n_strips,
                                         aerodynamics=aerodynamics, gravity=gravity)
        self.species = self.planar.species
        self.mass = self.planar.mass
        self.period = self.planar.period
        self.body_rate_term = self.planar.hover.body_rate_term
        self._kinematics: tuple[float, Motion, Any, Any] | None = None

    def _prescribed(self, t: float) -> tuple[Motion, Any]:
        """The prescribed relative motion at ``t`` (remembered: the Jacobian's evaluations share
        it)."""
        if self._kinematics is None or self._kinematics[0] != t:
            motion = prescribed_motion(self.species, t)
            rates = self.planar._rates(t, motion)
            self._kinematics = (t, motion, rates, self._locked(rates))
        return self._kinematics[1], self._kinematics[2]

    def _locked(self, rates: Any) -> tuple[tuple[tuple[np.ndarray, ...], ...], np.ndarray,
                                           np.ndarray]:
        """Per body ``p_i``, ``p_i'``, ``p_i''``; ``S`` and ``J_loc``: the parts of the
        accelerations that depend on the time alone (a central-difference Jacobian evaluates
        them 18 times at one instant)."""
        planar = self.planar
        S = np.zeros(3)
        J_loc = planar._J_B.copy()
        positions = []
        for (mi, mu, nu, J), (Q, Om, dOm) in zip(planar._bodies, rates, strict=True):
            p = mu + Q @ nu
            dp = Q @ _cross(Om, nu)
            ddp = Q @ (_cross(Om, _cross(Om, nu)) + _cross(dOm, nu))
            positions.append((p, dp, ddp))
            S += mi * p
            J_loc += Q @ J @ Q.T + mi * (float(p @ p) * np.eye(3) - np.outer(p, p))
        return tuple(positions), S, J_loc

    def _aerodynamics(self, motion: Motion, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Force (inertial) and moment about the thorax's centre of mass (thorax frame): the
        planar model's strip sums, which hold at any attitude (the motion carries it)."""
        return self.planar._aerodynamics(motion, v)

    def accelerations(self, t: float, R: np.ndarray, v: np.ndarray, W: np.ndarray
                      ) -> tuple[np.ndarray, np.ndarray]:
        """Thorax acceleration (inertial, m/s^2) and angular acceleration (thorax frame, rad/s^2).

        Parameters
        ----------
        t : float
            Time (s).
        R : ndarray, shape (3, 3)
            Thorax attitude (thorax to inertial).
        v : ndarray, shape (3,)
            Thorax velocity (m/s), inertial frame.
        W : ndarray, shape (3,)
            Thorax angular velocity (rad/s), thorax frame.

        Returns
        -------
        a, W_dot : ndarray, shape (3,)
        """
        base, rates = self._prescribed(float(t))
        motion = Motion(R=R, W=W, W_dot=np.zeros(3), Q_R=base.Q_R, Q_L=base.Q_L, Q_A=base.Q_A,
                        Om_R=base.Om_R, Om_L=base.Om_L, inertial_load=base.inertial_load,
                        appendage_momentum=base.appendage_momentum)
        planar = self.planar
        if planar.aerodynamics:
            F, M = self._aerodynamics(motion, v)
        else:
            F, M = np.zeros(3), np.zeros(3)
        m, g = self.mass, self.species.morphology.g * planar.gravity
        J_B = planar._J_B
        assert self._kinematics is not None
        positions, S, J_loc = self._kinematics[3]
        force = np.zeros(3)
        moment = M - _cross(W, J_B @ W)
        for (mi, _, _, J), (Q, Om, dOm), (p, dp, ddp) in zip(planar._bodies, rates, positions,
                                                             strict=True):
            c = _cross(W, _cross(W, p)) + 2.0 * _cross(W, dp) + ddp
            QtW = Q.T @ W
            wi = QtW + Om
            e = -_cross(Om, QtW) + dOm
            force -= mi * c
            moment -= mi * _cross(p, c) + Q @ (J @ e + _cross(wi, J @ wi))
        gb = g * R[2]  # g R^T e3
        K = np.zeros((6, 6))
        K[:3, :3] = m * np.eye(3)
        K[:3, 3:] = -R @ _hat(S)
        K[3:, :3] = _hat(S) @ R.T
        K[3:, 3:] = J_loc
        b = np.concatenate([F + m * g * _E3 + R @ force, moment + _cross(S, gb)])
        z = np.linalg.solve(K, b)
        return z[:3], z[3:]

    def rhs(self, t: float, state: np.ndarray) -> np.ndarray:
        """``d/dt (x, R.ravel(), v, W)`` at time ``t`` (s): ``(v, (R W^).ravel(), a, W')``."""
        R = state[3:12].reshape(3, 3)
        v, W = state[12:15], state[15:18]
        a, dW = self.accelerations(t, R, v, W)
        return np.concatenate([v, (R @ _hat(W)).ravel(), a, dW])

    def local_jacobian(self, t: float, state: np.ndarray) -> np.ndarray:
        """Jacobian of ``(xi, v, W)``'s right-hand side at ``xi = 0`` (9 x 9, exponential
        coordinates ``R exp(xi^)``; see the module notes), by central differences."""
        R = state[3:12].reshape(3, 3)
        v, W = state[12:15], state[15:18]

        def acc(z: np.ndarray) -> np.ndarray:
            a, dW = self.accelerations(t, R @ _expm_hat(z[:3]), v + z[3:6], W + z[6:])
            return np.concatenate([a, dW])

        A = np.zeros((9, 9))
        A[:3, :3] = -_hat(W)
        A[:3, 6:] = np.eye(3)
        A[3:, :] = central_jacobian(acc, np.zeros(9))
        return A

    @staticmethod
    def from_planar(y: Any) -> np.ndarray:
        """The 18-entry state of a planar one.

        Parameters
        ----------
        y : array_like, shape (6,) or (4,)
            ``(x_1, x_3, theta, v_1, v_3, q)`` of
            :class:`~flapping.peers.fwuav.attitude.FwuavPitchFree`, or ``(theta, v_1, v_3, q)``
            (position zero).

        Returns
        -------
        ndarray, shape (18,)
        """
        y = check.vector("y", y)
        if y.size == 4:
            y = np.concatenate([[0.0, 0.0], y])
        elif y.size != 6:
            raise ValueError(f"`y` must have shape (4,) or (6,); got shape {y.shape}")
        return np.concatenate([[y[0], 0.0, y[1]], _rot(1, y[2]).ravel(), [y[3], 0.0, y[4]],
                               [0.0, y[5], 0.0]])

    def momentum(self, t: float, state: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Linear momentum and angular momentum about the inertial origin of the four bodies.

        Parameters
        ----------
        t : float
            Time (s).
        state : ndarray, shape (18,)
            ``(x, R.ravel(), v, W)``.

        Returns
        -------
        P : ndarray, shape (3,)
            Linear momentum (kg m/s), inertial frame.
        H : ndarray, shape (3,)
            Angular momentum about the origin (kg m^2/s), inertial frame; both are constant
            without aerodynamics and gravity.
        """
        state = np.asarray(state, dtype=float)
        _, rates = self._prescribed(float(t))
        x, R = state[0:3], state[3:12].reshape(3, 3)
        return self.planar._momentum(x, state[12:15], R, state[15:18], rates)


@dataclass(frozen=True)
class AttitudeFreeFloquet:
    """Floquet multipliers of FWUAV's attitude-free hover about the planar periodic orbit.

    Attributes
    ----------
    name : str
        The insect.
    body_rate_term : str
        ``"fwuav"`` (``Q W``) or ``"rotated"`` (``Q^T W``).
    y0 : ndarray, shape (4,)
        The planar orbit's ``(theta, v_1, v_3, q)`` at ``t = 0``.
    period : float
        Period (s).
    monodromy : ndarray, shape (9, 9)
        Monodromy of ``(xi, v, W)`` (exponential coordinates of the attitude).
    longitudinal : ndarray, shape (4,), complex
        Multipliers of the ``(xi_2, v_1, v_3, W_2)`` block, by modulus, descending.
    lateral : ndarray, shape (5,), complex
        Multipliers of the ``(xi_1, xi_3, v_2, W_1, W_3)`` block, by modulus, descending (one of
        them the neutral yaw about gravity, exactly one in exact arithmetic).
    multipliers : ndarray, shape (9,), complex
        Eigenvalues of the whole monodromy, by modulus, descending (the position's three,
        exactly one, left out).
    coupling : float
        Largest entry of the longitudinal-lateral blocks over the largest of the monodromy: zero
        by the mirror symmetry.
    closure : float
        ``max |y(T) - y(0)|`` of the reference orbit integrated in 3-D (the 15 entries of ``R``,
        ``v``, ``W``).
    liouville_error : float
        ``|det M / exp(int_0^T trace A dt) - 1|``.
    nfev : int
        Evaluations of the variational right-hand side.
    """

    name: str
    body_rate_term: str
    y0: np.ndarray
    period: float
    monodromy: np.ndarray = field(repr=False)
    longitudinal: np.ndarray
    lateral: np.ndarray
    multipliers: np.ndarray
    coupling: float
    closure: float
    liouville_error: float
    nfev: int

    def exponents(self, which: str = "lateral") -> np.ndarray:
        """``log(mu) / period`` (1/s) of the ``"lateral"``, ``"longitudinal"`` or ``"all"``
        multipliers, in their order."""
        which = check.choice("which", which, ("lateral", "longitudinal", "all"))
        mu = {"lateral": self.lateral, "longitudinal": self.longitudinal,
              "all": self.multipliers}[which]
        return np.log(mu.astype(complex)) / self.period


def _by_modulus(mu: np.ndarray) -> np.ndarray:
    mu = np.asarray(mu, dtype=complex)
    out = mu[np.lexsort((-mu.imag, -np.abs(mu)))]
    out.flags.writeable = False
    return out


#: Bounds of ``y0`` = (theta, v_1, v_3, q) of :func:`attitude_free_floquet` with a model: any
#: attitude, 10 m/s (a hovering insect's orbit moves at centimetres a second; the presets' at
#: t = 0 are below 0.2 m/s) and 100 rad/s (their pitch rates are below 1 rad/s). From
#: ``[1e6] * 4`` the integration never returned; from these bounds it takes ~1200 evaluations
#: (~14 s, against ~480 on the hawkmoth's orbit).
Y0_LIMITS: tuple[tuple[str, float, str], ...] = (
    ("theta", math.pi, "rad"), ("v_1", 10.0, "m/s"), ("v_3", 10.0, "m/s"), ("q", 100.0, "rad/s"))

#: Most evaluations of the variational right-hand side one period may take (400 times the
#: hawkmoth's orbit's): beyond, the integration is stuck and is stopped with an error.
MAX_NFEV = 200_000


def _variational(model: FwuavAttitudeFree, state0: np.ndarray, period: float, rtol: float
                 ) -> tuple[np.ndarray, np.ndarray, float, int]:
    """Reference orbit (R, v, W) and transition matrix of ``(xi, v, W)`` over ``[0, period]``;
    returns the final reference (15), ``M`` (9 x 9), ``int trace A`` and the evaluation count."""

    calls = [0]

    def fun(t: float, y: np.ndarray) -> np.ndarray:
        calls[0] += 1
        if calls[0] > MAX_NFEV:  # bounded: a state the step size collapses at never returns
            raise ConvergenceError(
                f"the attitude-free variational equations took more than {MAX_NFEV} "
                f"evaluations (reached t = {t:.6g} of {period:.6g} s): the integration is "
                "stuck; is y0 on the orbit?")
        state = np.concatenate([np.zeros(3), y[:15]])
        f = model.rhs(t, state)
        A = model.local_jacobian(t, state)
        Phi = y[15:96].reshape(9, 9)
        return np.concatenate([f[3:], (A @ Phi).ravel(), [np.trace(A)]])

    y0 = np.concatenate([state0[3:], np.eye(9).ravel(), [0.0]])
    sol = solve_ivp(fun, (0.0, period), y0, method="DOP853", rtol=rtol, atol=rtol * 0.1)
    if not sol.success:
        raise ConvergenceError(f"the attitude-free variational equations failed: {sol.message}",
                               result=sol)
    end = sol.y[:, -1]
    return end[:15], end[15:96].reshape(9, 9), float(end[96]), int(sol.nfev)


def attitude_free_floquet(model: str | FwuavPitchFree, y0: Any = None, period: Any = None, *,
                          body_rate_term: str = "fwuav", rtol: float = 1e-8
                          ) -> AttitudeFreeFloquet:
    """Floquet multipliers of FWUAV's attitude-free hover (all twelve perturbations of
    ``eom_hover_xR``) about a planar periodic orbit.

    Parameters
    ----------
    model : str or FwuavPitchFree
        An insect name (``hawkmoth``, ``bumblebee``, ``fruit_fly``): the orbit is then
        :func:`~flapping.peers.fwuav.attitude.pitch_free_floquet`'s; or a pitch-free model
        (e.g. a trimmed one), whose periodic orbit ``y0`` must be given.
    y0 : array_like, shape (4,), optional
        ``(theta, v_1, v_3, q)`` at ``t = 0`` on the model's periodic orbit (rad, m/s, m/s,
        rad/s), within :data:`Y0_LIMITS`; required with a model, not allowed with a name.
    period : float, optional
        The orbit's period (s), in (0, 1]; default the model's wingbeat period.
    body_rate_term : {"fwuav", "rotated"}, optional
        With a name: the body-rate term of the strip velocity. Ignored with a model.
    rtol : float, optional
        Relative tolerance of the integration, in [1e-12, 1e-6] (absolute ``rtol / 10``; the
        orbit from :func:`~flapping.peers.fwuav.attitude.pitch_free_floquet` at its default
        tolerance).

    Returns
    -------
    AttitudeFreeFloquet
        Cached per argument set when ``model`` is a name.

    Raises
    ------
    ValueError
        For an unknown name or an argument out of range.
    ConvergenceError
        If an integration fails or is stuck (more than :data:`MAX_NFEV` evaluations), or, with
        a name, the planar shooting does not converge.

    Warns
    -----
    ClosureWarning
        If the reference orbit from ``y0`` does not close after ``period``: ``y0`` is on no
        periodic orbit, and the multipliers are not an orbit's.
    """
    # any real type (float32, int, 0-d array) is accepted and converted to float
    rtol = check.real("rtol", rtol, low=1e-12, high=1e-6)
    if isinstance(model, str):
        if y0 is not None or period is not None:
            raise ValueError("`y0` and `period` are taken from pitch_free_floquet when `model` "
                             "is a name; pass a FwuavPitchFree model to give them")
        FwuavPitchFree(model, body_rate_term=body_rate_term)  # checks both
        return _named(model, body_rate_term, float(rtol))
    if not isinstance(model, FwuavPitchFree):
        raise ValueError("`model` must be an insect name or a FwuavPitchFree model; got "
                         f"{type(model).__name__}")
    if y0 is None:
        raise ValueError("`y0` (the planar orbit's (theta, v_1, v_3, q) at t = 0) is required "
                         "with a model")
    y0 = check.components("y0", y0, Y0_LIMITS)
    T = model.period if period is None else check.real("period", period, low=0.0, high=1.0,
                                                       low_open=True, unit="s")
    return _floquet(FwuavAttitudeFree(model), y0, T, float(rtol))


@lru_cache(maxsize=8)
def _named(name: str, body_rate_term: str, rtol: float) -> AttitudeFreeFloquet:
    orbit = pitch_free_floquet(name, body_rate_term=body_rate_term)
    model = FwuavPitchFree(name, body_rate_term=body_rate_term)
    return _floquet(FwuavAttitudeFree(model), orbit.y0, orbit.period, rtol)


def _warn_if_open(end: np.ndarray, start: np.ndarray, rtol: float) -> None:
    """A :class:`~flapping.errors.ClosureWarning` if the reference does not close: ``y0`` is on
    no orbit of the period, and the multipliers are a transition matrix's.

    The relative closure ``max |y(T) - y(0)| / max(1, max |y(0)|)`` against the package's
    :data:`~flapping.periodic.floquet.CLOSURE_TOL`, or 100 rtol where the integration's own
    error may reach it (the hawkmoth's orbit closes to 4e-8 at rtol 1e-8).
    """
    size = max(1.0, float(np.abs(start).max()))
    closure = float(np.abs(end - start).max()) / size
    tol = max(CLOSURE_TOL, 100.0 * rtol)
    if closure > tol:
        warnings.warn(f"the reference orbit does not close: relative closure {closure:.3g} > "
                      f"{tol:.1g}; `y0` is on no periodic orbit of this period, and the "
                      "multipliers are those of a transition matrix, not an orbit's",
                      ClosureWarning, stacklevel=4)


def _floquet(model: FwuavAttitudeFree, y0: np.ndarray, period: float, rtol: float
             ) -> AttitudeFreeFloquet:
    state0 = FwuavAttitudeFree.from_planar(y0)
    end, M, trace, nfev = _variational(model, state0, period, rtol)
    lon, lat = list(LONGITUDINAL), list(LATERAL)
    coupling = max(np.abs(M[np.ix_(lon, lat)]).max(), np.abs(M[np.ix_(lat, lon)]).max())
    liouville = abs(np.linalg.det(M) / math.exp(trace) - 1.0)
    _warn_if_open(end, state0[3:], rtol)
    M.flags.writeable = False
    y0 = y0.copy()
    y0.flags.writeable = False
    return AttitudeFreeFloquet(
        name=model.species.name, body_rate_term=model.body_rate_term, y0=y0, period=period,
        monodromy=M, longitudinal=_by_modulus(np.linalg.eigvals(M[np.ix_(lon, lon)])),
        lateral=_by_modulus(np.linalg.eigvals(M[np.ix_(lat, lat)])),
        multipliers=_by_modulus(np.linalg.eigvals(M)),
        coupling=float(coupling / np.abs(M).max()),
        closure=float(np.abs(end - state0[3:]).max()), liouville_error=float(liouville),
        nfev=nfev)

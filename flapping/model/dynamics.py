"""Longitudinal equations of motion of a hovering flapping insect (eqs. 2, 28, 29).

State x = (u, w, q, theta): body-axis velocities [m/s] (x forward, z down), pitch rate [rad/s] and
pitch angle [rad], nose-up positive. Rigid body, wing inertia neglected (eq. 2):

    u' = -q w - g sin(theta) + X/m
    w' =  q u + g cos(theta) + Z/m
    q' =  M / I_y
    theta' = q

These equations, and those with the wings' mass, are not written here: they are the planar case
of the six-degree-of-freedom derivation (:mod:`flapping.model.sixdof_derivation`), restricted in
:mod:`flapping.model.inertia_derivation` and printed into ``_inertia_generated`` (``rigid_rates``,
``rigid_state_jac``; ``mass_matrix``, ``forcing`` with wing mass), which every planar path runs.

The aerodynamic loads (X, Z, M) come from one of three models:

``"linear"``
    the paper's eq. (29): X = X0(t) + m (Xu u + Xw w + Xq q), etc., with the stability derivatives
    derived in :mod:`flapping.model.derivation` (first order in the states);
``"small-angle"``
    the blade-element loads of eqs. (13)-(23), nonlinear in the states (small induced angle);
``"exact"``
    the blade-element loads with the exact inflow angle and speed.

Two extensions of the paper's model (what could make hover stable), both 0 by default so that
every number of the paper's model is unchanged: the hinge height ``insect.hinge_height`` above
the centre of gravity (the section's forward velocity feels u - q h_w, the forces act h_w
higher), and the mean stroke angle ``insect.stroke_mean``, phi = phi_bar + Phi cos(2 pi f t);
:meth:`LongitudinalDynamics.stroke_mean_jac` is the sensitivity to phi_bar.

The right-hand side is smooth within each half-stroke only (the wing pitch flips at reversal,
eq. 11), so :meth:`LongitudinalDynamics.segment_functions` returns one callable per half-stroke for
integrators that restart at :data:`~flapping.model.kinematics.HALF_STROKE_BREAKPOINTS`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal, NamedTuple

import numpy as np

import flapping._numdiff as _numdiff
import flapping._validation as _validation
from flapping.model import _derivatives_generated as _gen
from flapping.model import _inertia_generated as _mechanics
from flapping.model.aerodynamics import (
    AeroConstants,
    BladeElementModel,
    aero_constants,
    check_nodes,
    trim_angle_of_attack,
)
from flapping.model.inertia import (
    WingInertia,
    _stroke_phase,
    stroke_phase_amplitude_derivative,
)
from flapping.model.kinematics import (
    HALF_STROKE_BREAKPOINTS,
    _stroke_sign,
    check_alpha_m,
    check_amplitude,
    segment_stroke_sign,
)
from flapping.model.morphology import Insect

__all__ = ["STATE_NAMES", "AERODYNAMIC_MODELS", "LongitudinalDynamics", "UncheckedCalls",
           "inertial_velocity",
           "inertial_velocity_jac"]

#: Names of the state components, in order.
STATE_NAMES: tuple[str, ...] = ("u", "w", "q", "theta")
AerodynamicModel = Literal["linear", "small-angle", "exact"]

#: Aerodynamic models accepted by :class:`LongitudinalDynamics`.
AERODYNAMIC_MODELS: tuple[AerodynamicModel, ...] = ("linear", "small-angle", "exact")

#: Central-difference steps of the blade-element Jacobians: 1e-6 max(1, |x_j|) for the states
#: (near eps**(1/3) for unit-size states: accurate to ~1e-10) and 1e-7 Phi for the amplitude.
_STATE_STEP = 1e-6
_AMPLITUDE_STEP = 1e-7

#: Blade-element models kept per LongitudinalDynamics at amplitudes other than its own.
_MAX_BLADES = 8


def _check_call(t: Any, x: Any, n: int, stroke: Any, amplitude: Any) -> None:
    """The public calls' argument check: a finite time, ``n`` (0, 3 or 4) finite state entries, a
    stroke sign of +1 or -1 (or None) and a finite amplitude (or None), else a ValueError naming
    the argument.

    The common case costs one sum and one ``isfinite`` (~0.3 us); the solvers skip even that
    (they call the unchecked implementations). A sum that overflows with finite terms passes on
    to the full check, which then finds nothing to refuse.
    """
    try:  # arithmetic, not float(): float("0.1") would let a string through; unrolled: fast
        if n == 4:
            total = t + 0.0 + x[0] + x[1] + x[2] + x[3]
        elif n == 3:
            total = t + 0.0 + x[0] + x[1] + x[2]
        else:
            total = t + 0.0
        ok = (math.isfinite(total) and (amplitude is None or math.isfinite(amplitude))
              and (stroke is None or stroke == 1.0 or stroke == -1.0))
    except (TypeError, ValueError, IndexError, KeyError):
        ok = False
    if not ok:
        _refuse_call(t, x, n, stroke, amplitude)


def _refuse_call(t: Any, x: Any, n: int, stroke: Any, amplitude: Any) -> None:
    """:func:`_check_call`'s slow path: the first bad argument, named (returns if none is)."""
    _validation.real("t", t)
    if n:
        state = _validation.array("x", x)
        if state.ndim != 1 or state.size < n:
            raise ValueError(f"`x` must be a 1-D array of at least {n} numbers (the state "
                             f"{', '.join(STATE_NAMES[:n])}); got shape {state.shape}")
    if stroke is not None and _validation.real("stroke", stroke) not in (1.0, -1.0):
        raise ValueError(f"`stroke` must be +1 (forward), -1 (backward) or None; got {stroke!r}")
    if amplitude is not None:
        _validation.real("amplitude", amplitude)


def _check_velocity_args(u: Any, w: Any, theta: Any) -> None:
    """u, w, theta of :func:`inertial_velocity` finite, else a ValueError naming the first bad."""
    try:
        if math.isfinite(u + w + theta):
            return
    except TypeError:
        pass
    for name, value in (("u", u), ("w", w), ("theta", theta)):
        _validation.real(name, value)


def inertial_velocity(u: float, w: float, theta: float) -> tuple[float, float]:
    """Velocity of the centre of gravity in inertial axes: (forward, down) [m/s].

    The body velocity (u, w) turned by the pitch angle: forward = u cos(theta) + w sin(theta),
    down = -u sin(theta) + w cos(theta) (z down, theta nose up). Integrated beside the states,
    it gives the position: the hover condition holds the descent over a period at zero.

    Parameters
    ----------
    u, w : float
        Body-axis velocities [m/s].
    theta : float
        Pitch angle [rad].

    Returns
    -------
    tuple of 2 floats

    Raises
    ------
    ValueError
        If an argument is not a finite real number (named in the message).
    """
    _check_velocity_args(u, w, theta)
    rates = _mechanics.rigid_rates(u, w, 0.0, theta, 0.0)
    return rates[5], rates[4]


def inertial_velocity_jac(u: float, w: float, theta: float) -> np.ndarray:
    """Jacobian of :func:`inertial_velocity` in the state (u, w, q, theta), shape (2, 4).

    Parameters
    ----------
    u, w : float
        Body-axis velocities [m/s].
    theta : float
        Pitch angle [rad].

    Returns
    -------
    ndarray, shape (2, 4)
        Rows forward and down.

    Raises
    ------
    ValueError
        If an argument is not a finite real number (named in the message).
    """
    _check_velocity_args(u, w, theta)
    jac = np.reshape(_mechanics.rigid_state_jac(u, w, 0.0, theta, 0.0), (6, 4))
    return np.array(jac[[5, 4]], dtype=float)


class UncheckedCalls(NamedTuple):
    """A model's calls without the argument check of the public methods, for solvers that make
    their own arguments and call them millions of times (:attr:`LongitudinalDynamics.unchecked`).

    Same signatures and results as :meth:`LongitudinalDynamics.rhs`, ``jac``, ``loads``,
    ``amplitude_jac``, ``stroke_mean_jac`` and ``derivatives`` on valid arguments; on a
    non-finite state they return what the arithmetic gives (an integrator reports the overflow),
    where the public methods raise ValueError (the blade-element models' loads,
    :meth:`~flapping.model.aerodynamics.BladeElementModel.loads`, keep their own check).
    """

    rhs: Callable[..., np.ndarray]
    jac: Callable[..., np.ndarray]
    loads: Callable[..., np.ndarray]
    amplitude_jac: Callable[..., np.ndarray]
    stroke_mean_jac: Callable[..., np.ndarray]
    derivatives: Callable[..., tuple[float, ...]]


@dataclass(frozen=True, init=False)
class LongitudinalDynamics:
    """Longitudinal flight dynamics of a flapping insect in the calling convention of ``solve_ivp``.

    Parameters
    ----------
    insect : Insect
        Morphology and constants.
    amplitude : float, optional
        Stroke amplitude Phi [rad], in (0, pi/2]; default ``insect.stroke_amplitude``.
    alpha_m : float, optional
        Mean geometric angle of attack [rad], in (0, pi/2); default the trim of eq. (40) at the
        insect's nominal stroke amplitude.
    aerodynamics : {"linear", "small-angle", "exact"}
        Which aerodynamic model gives the loads (see the module docstring).
    n_nodes : int
        Span quadrature nodes for the blade-element models, in [2, 4096]
        (:data:`~flapping.model.aerodynamics.MAX_NODES`).

    Attributes
    ----------
    insect, amplitude, alpha_m, aerodynamics, n_nodes
        The arguments, validated (amplitude and alpha_m as floats, defaults filled in).
    unchecked : UncheckedCalls
        :meth:`rhs`, :meth:`jac`, :meth:`loads`, :meth:`amplitude_jac`,
        :meth:`stroke_mean_jac` and :meth:`derivatives` without their argument check: the
        solvers' entry (as :meth:`segment_functions`).

    Raises
    ------
    ValueError
        If an argument is outside its range (the message names it and the range), or, with
        ``alpha_m=None``, if the insect is too heavy to trim (eq. 40).

    Examples
    --------
    >>> from scipy.integrate import solve_ivp
    >>> model = LongitudinalDynamics(hawkmoth())                       # doctest: +SKIP
    >>> sol = solve_ivp(model.rhs, (0, model.period), [0, 0, 0, 0], jac=model.jac)  # doctest: +SKIP
    """

    insect: Insect
    amplitude: float
    alpha_m: float
    aerodynamics: str
    n_nodes: int
    _constants: AeroConstants = field(init=False, repr=False, compare=False)
    _blade: BladeElementModel | None = field(init=False, repr=False, compare=False)
    # The wings' inertia (None for massless wings: then eq. 2 exactly as the paper writes it).
    _inertia: WingInertia | None = field(init=False, repr=False, compare=False)
    # Last (t, amplitude) -> derivatives: rhs and jac are called at the same t by integrators of
    # the variational equations, and the derivatives are most of the cost of either.
    _cache: list[Any] = field(init=False, repr=False, compare=False)
    # Blade-element models at other amplitudes (shooting with Phi free evaluates a few of them
    # over and over; building one costs ~25 load evaluations). Bounded: oldest dropped first.
    _blades: dict[float, BladeElementModel] = field(init=False, repr=False, compare=False)
    # The calls without their argument check, for solvers (documented in the class's Attributes).
    unchecked: UncheckedCalls = field(init=False, repr=False, compare=False)

    def __init__(self, insect: Insect, amplitude: float | None = None,
                 alpha_m: float | None = None, aerodynamics: str = "linear",
                 n_nodes: int = 32) -> None:
        _validation.instance("insect", insect, Insect)
        amplitude = check_amplitude(insect.stroke_amplitude if amplitude is None else amplitude)
        if alpha_m is None:
            alpha_m = trim_angle_of_attack(insect, insect.stroke_amplitude)
        alpha_m = check_alpha_m(alpha_m)
        aerodynamics = _validation.choice("aerodynamics", aerodynamics, AERODYNAMIC_MODELS)
        n_nodes = check_nodes(n_nodes)
        blade = None
        if aerodynamics != "linear":
            blade = BladeElementModel(insect, alpha_m, amplitude, aerodynamics, n_nodes)
        values = dict(insect=insect, amplitude=amplitude, alpha_m=alpha_m,
                      aerodynamics=aerodynamics, n_nodes=n_nodes,
                      _constants=aero_constants(insect), _blade=blade, _cache=[None], _blades={},
                      _inertia=WingInertia.of(insect))
        for name, value in values.items():
            object.__setattr__(self, name, value)
        object.__setattr__(self, "unchecked", UncheckedCalls(
            self._rhs, self._jac, self._loads, self._amplitude_jac, self._stroke_mean_jac,
            self._derivatives))

    # ---------------------------------------------------------------- basics
    @property
    def period(self) -> float:
        """Flapping period T [s]."""
        return self.insect.period

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """Stroke reversals as fractions of the period, where the right-hand side is not smooth."""
        return HALF_STROKE_BREAKPOINTS

    def with_amplitude(self, amplitude: float) -> LongitudinalDynamics:
        """The same model at another stroke amplitude (alpha_m kept).

        Raises
        ------
        ValueError
            If amplitude is outside (0, pi/2].
        """
        return LongitudinalDynamics(self.insect, amplitude, self.alpha_m, self.aerodynamics,
                                    self.n_nodes)

    def with_stroke_mean(self, stroke_mean: float) -> LongitudinalDynamics:
        """The same model with another mean stroke angle phi_bar [rad] (amplitude, alpha_m kept).

        Raises
        ------
        ValueError
            If stroke_mean is outside (-pi/2, pi/2).
        """
        return LongitudinalDynamics(self.insect.with_(stroke_mean=stroke_mean), self.amplitude,
                                    self.alpha_m, self.aerodynamics, self.n_nodes)

    # ---------------------------------------------------------------- loads
    def _derivatives(self, t: float, amplitude: float | None = None) -> tuple[float, ...]:
        """:meth:`derivatives` without its argument check (the solvers' entry: they
        call it millions of times, with arguments they made)."""
        return self._derivatives_with_amplitude(t, amplitude)[:12]

    def _amplitude_derivatives(self, t: float,
                               amplitude: float | None = None) -> tuple[float, ...]:
        """:meth:`amplitude_derivatives` without its argument check (the solvers' entry: they
        call it millions of times, with arguments they made)."""
        amplitude = self.amplitude if amplitude is None else amplitude
        return tuple(v / amplitude for v in self._derivatives_with_amplitude(t, amplitude)[12:])

    def _stroke(self, t: float, amplitude: float) -> tuple[float, float]:
        """phi and phi_dot of eq. (39) at time t, with the mean stroke angle phi_bar."""
        phi, phi_dot, _ = _stroke_phase(self.insect, t, amplitude)
        return phi, phi_dot

    def _derivatives_with_amplitude(self, t: float, amplitude: float | None) -> tuple[float, ...]:
        amplitude = self.amplitude if amplitude is None else float(amplitude)
        key = (float(t), amplitude)
        cached = self._cache[0]  # (key, values), read and written as one object
        if cached is not None and cached[0] == key:
            return cached[1]
        phi, phidot = self._stroke(t, amplitude)
        phi_bar = self.insect.stroke_mean
        values = _gen.stability_derivatives_scalar_with_amplitude(
            phi, phidot, abs(phidot), self.alpha_m, self._constants)
        if phi_bar != 0.0:
            # The generated Phi d/dPhi is the Euler operator, exact at phi_bar = 0 only: with
            # phi = phi_bar + Phi cos, Phi d/dPhi = Euler - phi_bar d/dphi.
            dphi = _gen.stability_derivatives_scalar_phi_derivative(
                phi, phidot, abs(phidot), self.alpha_m, self._constants)
            values = values[:12] + tuple(e - phi_bar * d
                                         for e, d in zip(values[12:], dphi, strict=True))
        self._cache[0] = (key, values)
        return values

    def _stroke_mean_derivatives(self, t: float,
                                 amplitude: float | None = None) -> tuple[float, ...]:
        """:meth:`stroke_mean_derivatives` without its argument check (the solvers' entry: they
        call it millions of times, with arguments they made)."""
        amplitude = self.amplitude if amplitude is None else float(amplitude)
        phi, phidot = self._stroke(t, amplitude)
        return tuple(_gen.stability_derivatives_scalar_phi_derivative(
            phi, phidot, abs(phidot), self.alpha_m, self._constants))

    def _loads(self, t: float, x: Sequence[float] | np.ndarray, stroke: float | None = None,
               amplitude: float | None = None) -> np.ndarray:
        """:meth:`loads` without its argument check (the solvers' entry: they
        call it millions of times, with arguments they made)."""
        u, w, q = float(x[0]), float(x[1]), float(x[2])
        if self.aerodynamics == "linear":
            c = self._constants
            ax, az, aq = self._eq29_accelerations(self._derivatives(t, amplitude), u, w, q)
            return np.array([c.m * ax, c.m * az, c.Iy * aq])
        blade = self._blade_at(amplitude)
        s = float(_stroke_sign(t, self.insect.frequency)) if stroke is None else stroke
        return np.asarray(blade.loads(t, u, w, q, s), dtype=float)

    def _eq29_accelerations(self, d: Sequence[float], u: float, w: float,
                            q: float) -> tuple[float, float, float]:
        """Loads of eq. (29) per unit mass / pitch inertia: X0/m + Xu u + Xw w + Xq q, etc."""
        c = self._constants
        return (d[0] / c.m + d[3] * u + d[4] * w + d[5] * q,
                d[1] / c.m + d[6] * u + d[7] * w + d[8] * q,
                d[2] / c.Iy + d[9] * u + d[10] * w + d[11] * q)

    def _blade_at(self, amplitude: float | None) -> BladeElementModel:
        assert self._blade is not None, "only the blade-element models have a BladeElementModel"
        if amplitude is None or amplitude == self.amplitude:
            return self._blade
        amplitude = float(amplitude)
        blade = self._blades.get(amplitude)
        if blade is None:
            if len(self._blades) >= _MAX_BLADES:
                del self._blades[next(iter(self._blades))]
            blade = BladeElementModel(self.insect, self.alpha_m, amplitude, self.aerodynamics,
                                      self.n_nodes)
            self._blades[amplitude] = blade
        return blade

    # ---------------------------------------------------------------- vector field
    def _rhs(self, t: float, x: Sequence[float] | np.ndarray, stroke: float | None = None,
             amplitude: float | None = None) -> np.ndarray:
        """:meth:`rhs` without its argument check (the solvers' entry: they
        call it millions of times, with arguments they made)."""
        u, w, q, theta = float(x[0]), float(x[1]), float(x[2]), float(x[3])
        g, c = self.insect.gravity, self._constants
        X, Z, M = self._loads(t, x, stroke, amplitude)
        if self._inertia is not None:
            acc = self._inertia._accelerations(self._phase(t, amplitude), (u, w, q, theta),
                                              (X, Z, M))
            return np.array([acc[0], acc[1], acc[2], q])
        # The generated eq. (2) at zero load, plus the loads over diag(m, m, I_y).
        rates = _mechanics.rigid_rates(u, w, q, theta, g)
        return np.array([rates[0] + X / c.m, rates[1] + Z / c.m, rates[2] + M / c.Iy, rates[3]])

    def _jac(self, t: float, x: Sequence[float] | np.ndarray, stroke: float | None = None,
             amplitude: float | None = None) -> np.ndarray:
        """:meth:`jac` without its argument check (the solvers' entry: they
        call it millions of times, with arguments they made)."""
        u, w, q, theta = float(x[0]), float(x[1]), float(x[2]), float(x[3])
        g, c = self.insect.gravity, self._constants
        if self.aerodynamics == "linear":
            d = self._derivatives(t, amplitude)
            aero = np.array([[d[3], d[4], d[5]], [d[6], d[7], d[8]], [d[9], d[10], d[11]]])
        else:
            # The blade-element loads have no closed-form derivative (span quadrature of |U|
            # and atan2): central differences of the loads (see _STATE_STEP).
            # Scaled to per unit mass / inertia before the division by 2 h, as always done.
            state = np.array([u, w, q])
            h = _STATE_STEP * np.maximum(1.0, np.abs(state))
            diff = _numdiff.central_differences(
                lambda y: self._loads(t, y, stroke, amplitude), state, step=h)
            aero = diff * np.array([[1.0 / c.m], [1.0 / c.m], [1.0 / c.Iy]]) / (2.0 * h)
        J = np.zeros((4, 4))
        if self._inertia is not None:
            loads_jac = np.zeros((3, 4))
            loads_jac[:, :3] = aero * np.array([[c.m], [c.m], [c.Iy]])
            J[:3, :] = self._inertia._state_jac(self._phase(t, amplitude), (u, w, q, theta),
                                               loads_jac)
            J[3, 2] = 1.0
            return J
        J[:, :] = np.reshape(_mechanics.rigid_state_jac(u, w, q, theta, g), (6, 4))[:4]
        J[:3, :3] += aero
        return J

    def _amplitude_jac(self, t: float, x: Sequence[float] | np.ndarray,
                       stroke: float | None = None, amplitude: float | None = None) -> np.ndarray:
        """:meth:`amplitude_jac` without its argument check (the solvers' entry: they
        call it millions of times, with arguments they made)."""
        amplitude = self.amplitude if amplitude is None else float(amplitude)
        if self.aerodynamics == "linear":
            u, w, q = float(x[0]), float(x[1]), float(x[2])
            # eq. (29) is linear in the derivatives, so d/dPhi applies it to their d/dPhi.
            acc = self._eq29_accelerations(self._amplitude_derivatives(t, amplitude), u, w, q)
            if self._inertia is not None:
                dphase = stroke_phase_amplitude_derivative(self.insect, t)
                return self._inertia_sensitivity(t, x, amplitude, acc, dphase)
            return np.array([[acc[0]], [acc[1]], [acc[2]], [0.0]])
        return _numdiff.central_jacobian_nominal(
            lambda p: self._rhs(t, x, stroke, p[0]), np.array([amplitude]),
            step=_AMPLITUDE_STEP * amplitude)

    def _stroke_mean_jac(self, t: float, x: Sequence[float] | np.ndarray,
                         stroke: float | None = None, amplitude: float | None = None) -> np.ndarray:
        """:meth:`stroke_mean_jac` without its argument check (the solvers' entry: they
        call it millions of times, with arguments they made)."""
        if self.aerodynamics == "linear":
            u, w, q = float(x[0]), float(x[1]), float(x[2])
            acc = self._eq29_accelerations(self._stroke_mean_derivatives(t, amplitude), u, w, q)
            if self._inertia is not None:
                return self._inertia_sensitivity(t, x, amplitude, acc, (1.0, 0.0, 0.0))
            return np.array([[acc[0]], [acc[1]], [acc[2]], [0.0]])
        phi_bar = self.insect.stroke_mean
        return _numdiff.central_jacobian_nominal(
            lambda p: self.with_stroke_mean(p[0])._rhs(t, x, stroke, amplitude),
            np.array([phi_bar]), step=_AMPLITUDE_STEP)

    # ---------------------------------------------------------------- the public calls
    def derivatives(self, t: float, amplitude: float | None = None) -> tuple[float, ...]:
        """(X0, Z0, M0, Xu, ..., Mq) at time t (scalar), normalised as in eq. (29).

        Parameters
        ----------
        t : float
            Time [s].
        amplitude : float, optional
            Stroke amplitude [rad]; default the model's.

        Returns
        -------
        tuple of 12 floats
            In the order of :data:`flapping.model.derivatives.NAMES`.

        Raises
        ------
        ValueError
            If ``t`` or ``amplitude`` is not a finite real number (named in the message).
        """
        _check_call(t, None, 0, None, amplitude)
        return self._derivatives(t, amplitude)

    def amplitude_derivatives(self, t: float, amplitude: float | None = None) -> tuple[float, ...]:
        """d/dPhi of (X0, Z0, M0, Xu, ..., Mq) at time t (from the generated code).

        Parameters
        ----------
        t : float
            Time [s].
        amplitude : float, optional
            Stroke amplitude Phi [rad]; default the model's.

        Returns
        -------
        tuple of 12 floats
            The derivatives of :meth:`derivatives` with respect to Phi [per rad].

        Raises
        ------
        ValueError
            If ``t`` or ``amplitude`` is not a finite real number (named in the message).
        """
        _check_call(t, None, 0, None, amplitude)
        return self._amplitude_derivatives(t, amplitude)

    def stroke_mean_derivatives(self, t: float,
                                amplitude: float | None = None) -> tuple[float, ...]:
        """d/dphi_bar of (X0, Z0, M0, Xu, ..., Mq) at time t (from the generated code).

        Parameters
        ----------
        t : float
            Time [s].
        amplitude : float, optional
            Stroke amplitude Phi [rad]; default the model's.

        Returns
        -------
        tuple of 12 floats
            The derivatives of :meth:`derivatives` with respect to the mean stroke angle [per rad]
            (d/dphi_bar = d/dphi, since phi = phi_bar + Phi cos(2 pi f t)).

        Raises
        ------
        ValueError
            If ``t`` or ``amplitude`` is not a finite real number (named in the message).
        """
        _check_call(t, None, 0, None, amplitude)
        return self._stroke_mean_derivatives(t, amplitude)

    def loads(self, t: float, x: Sequence[float] | np.ndarray, stroke: float | None = None,
              amplitude: float | None = None) -> np.ndarray:
        """Aerodynamic loads of both wings at time t and state x.

        Parameters
        ----------
        t : float
            Time [s].
        x : array_like
            State (u, w, q[, theta]) [m/s, m/s, rad/s, rad]; theta does not enter the loads.
        stroke : {+1, -1}, optional
            Overrides the half-stroke found from t; matters only for the blade-element models at
            stroke reversal.
        amplitude : float, optional
            Stroke amplitude [rad]; default the model's.

        Returns
        -------
        numpy.ndarray
            (X, Z, M) [N, N, N m] in body axes (eq. 29 for ``"linear"``, eqs. 13-23 otherwise).

        Raises
        ------
        ValueError
            If ``t``, an entry of ``x`` or ``amplitude`` is not a finite real number, ``x`` has
            fewer than 3 entries, or ``stroke`` is not +1, -1 or None (the message names the
            argument). Checked here, at the public call; the solvers call the unchecked
            implementation (:meth:`segment_functions`).
        """
        _check_call(t, x, 3, stroke, amplitude)
        return self._loads(t, x, stroke, amplitude)

    def rhs(self, t: float, x: Sequence[float] | np.ndarray, stroke: float | None = None,
            amplitude: float | None = None) -> np.ndarray:
        """Right-hand side dx/dt of eq. (2) with the model's loads (eq. 29 for ``"linear"``).

        Parameters
        ----------
        t : float
            Time [s].
        x : array_like, shape (4,)
            State (u, w, q, theta) [m/s, m/s, rad/s, rad].
        stroke : {+1, -1}, optional
            Half-stroke override (see :meth:`loads`).
        amplitude : float, optional
            Stroke amplitude [rad]; default the model's.

        Returns
        -------
        numpy.ndarray, shape (4,)
            (u', w', q', theta') [m/s^2, m/s^2, rad/s^2, rad/s].

        Raises
        ------
        ValueError
            If ``t``, an entry of ``x`` or ``amplitude`` is not a finite real number, ``x`` has
            fewer than 4 entries, or ``stroke`` is not +1, -1 or None (the message names the
            argument). Checked here, at the public call; the solvers call the unchecked
            implementation (:meth:`segment_functions`).
        """
        _check_call(t, x, 4, stroke, amplitude)
        return self._rhs(t, x, stroke, amplitude)

    def jac(self, t: float, x: Sequence[float] | np.ndarray, stroke: float | None = None,
            amplitude: float | None = None) -> np.ndarray:
        """Jacobian d(dx/dt)/dx of :meth:`rhs` (eqs. 44-47).

        Analytic for ``"linear"``; for the blade-element models, central differences of the loads.

        Parameters
        ----------
        t, x, stroke, amplitude
            As for :meth:`rhs`.

        Returns
        -------
        numpy.ndarray, shape (4, 4)

        Raises
        ------
        ValueError
            If ``t``, an entry of ``x`` or ``amplitude`` is not a finite real number, ``x`` has
            fewer than 4 entries, or ``stroke`` is not +1, -1 or None (the message names the
            argument). Checked here, at the public call; the solvers call the unchecked
            implementation (:meth:`segment_functions`).
        """
        _check_call(t, x, 4, stroke, amplitude)
        return self._jac(t, x, stroke, amplitude)

    def amplitude_jac(self, t: float, x: Sequence[float] | np.ndarray, stroke: float | None = None,
                      amplitude: float | None = None) -> np.ndarray:
        """d(dx/dt)/dPhi, the sensitivity of :meth:`rhs` to the stroke amplitude of eq. (39).

        Analytic for ``"linear"`` (eq. 29 applied to the amplitude derivatives of the stability
        derivatives); central differences with step 1e-7 Phi otherwise.

        Parameters
        ----------
        t, x, stroke, amplitude
            As for :meth:`rhs`.

        Returns
        -------
        numpy.ndarray, shape (4, 1)

        Raises
        ------
        ValueError
            If ``t``, an entry of ``x`` or ``amplitude`` is not a finite real number, ``x`` has
            fewer than 4 entries, or ``stroke`` is not +1, -1 or None (the message names the
            argument). Checked here, at the public call; the solvers call the unchecked
            implementation (:meth:`segment_functions`).
        """
        _check_call(t, x, 4, stroke, amplitude)
        return self._amplitude_jac(t, x, stroke, amplitude)

    def stroke_mean_jac(self, t: float, x: Sequence[float] | np.ndarray,
                        stroke: float | None = None, amplitude: float | None = None) -> np.ndarray:
        """d(dx/dt)/dphi_bar, the sensitivity of :meth:`rhs` to the mean stroke angle.

        Analytic for ``"linear"`` (eq. 29 applied to :meth:`stroke_mean_derivatives`); central
        differences with step 1e-7 rad otherwise (two blade-element models per call: slow).

        Parameters
        ----------
        t, x, stroke, amplitude
            As for :meth:`rhs`.

        Returns
        -------
        numpy.ndarray, shape (4, 1)

        Raises
        ------
        ValueError
            If ``t``, an entry of ``x`` or ``amplitude`` is not a finite real number, ``x`` has
            fewer than 4 entries, or ``stroke`` is not +1, -1 or None (the message names the
            argument). Checked here, at the public call; the solvers call the unchecked
            implementation (:meth:`segment_functions`).
        """
        _check_call(t, x, 4, stroke, amplitude)
        return self._stroke_mean_jac(t, x, stroke, amplitude)

    def _phase(self, t: float, amplitude: float | None) -> tuple[float, float, float]:
        """(phi, phi_dot, phi_ddot) at t, for the wings' inertia."""
        return _stroke_phase(self.insect, t, self.amplitude if amplitude is None else amplitude)

    def _inertia_sensitivity(self, t: float, x: Sequence[float] | np.ndarray,
                             amplitude: float | None, dacc: Sequence[float],
                             dphase: Sequence[float]) -> np.ndarray:
        """The body's accelerations' derivative in a stroke parameter, wings of mass: the
        linear loads' derivative ``dacc`` (per unit mass / inertia, eq. 29) through the mass
        matrix, plus the wings' inertial terms' (``dphase``: how phi, phi_dot, phi_ddot move)."""
        assert self._inertia is not None
        c = self._constants
        dloads = (c.m * dacc[0], c.m * dacc[1], c.Iy * dacc[2])
        loads = self._loads(t, x, None, amplitude)
        state = tuple(float(v) for v in x[:4])
        dacc_total = self._inertia._stroke_jac(self._phase(t, amplitude), state, loads, dphase,
                                              dloads)
        return np.array([[dacc_total[0]], [dacc_total[1]], [dacc_total[2]], [0.0]])

    def segment_functions(self) -> tuple[list[Callable[..., np.ndarray]],
                                         list[Callable[..., np.ndarray]]]:
        """Per-half-stroke right-hand sides and Jacobians, smooth on each closed half-stroke.

        Returns
        -------
        rhs_list, jac_list : list of callable
            ``f(t, x)`` and ``J(t, x)`` per segment: element k is used on segment k of the period
            split at :attr:`breakpoints` (k = 0: backward stroke, k = 1: forward stroke, eq. 11).
        """
        rhs, jac = [], []
        for k in range(len(self.breakpoints) + 1):
            s = segment_stroke_sign(k)
            rhs.append(lambda t, x, _s=s: self._rhs(t, x, _s))
            jac.append(lambda t, x, _s=s: self._jac(t, x, _s))
        return rhs, jac

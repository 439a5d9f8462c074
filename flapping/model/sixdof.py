"""The insect in six degrees of freedom: (u, v, w, p, q, r, roll, theta).

Every formula of geometry and mechanics comes from :mod:`flapping.model.sixdof_derivation` (SymPy,
printed into ``_sixdof_generated.py``): the strip speeds of each wing, the assembly of the wings'
loads about the centre of gravity, and the equations of motion of the body with its two wings
(wing mass included through the mass matrix). What is left here is the section law, which is the
planar model's own (:meth:`flapping.model.aerodynamics.BladeElementModel.wing_resultants`, applied
to each wing), and the bookkeeping.

State x = (u, v, w) [m/s] (x forward, y right, z down), (p, q, r) [rad/s] (roll, pitch, yaw rates),
roll and theta [rad] (3-2-1 Euler angles). Heading and position do not feed back into the loads
or the body's motion, so they are not states. With the lateral states zero and both wings
flapping alike, the motion stays in the plane of symmetry (the planar model of
:class:`~flapping.model.dynamics.LongitudinalDynamics`).

Aerodynamic models: ``"small-angle"`` and ``"exact"``, the blade-element loads of the planar model;
``"linear"``, the paper's linear loads (eq. 29) in six degrees of freedom: the constant loads and
their derivatives in (u, v, w, p, q, r) at the zero state, derived by
:mod:`flapping.model.sixdof_linear_derivation` (printed into ``_sixdof_linear_generated.py``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

import flapping._validation as _validation
from flapping.model import _sixdof_generated, _sixdof_linear_generated
from flapping.model.aerodynamics import (
    BladeElementModel,
    aero_constants,
    check_nodes,
    trim_angle_of_attack,
)
from flapping.model.kinematics import (
    HALF_STROKE_BREAKPOINTS,
    check_alpha_m,
    check_amplitude,
    segment_stroke_sign,
)
from flapping.model.morphology import Insect

__all__ = ["SIXDOF_STATE_NAMES", "SIXDOF_AERODYNAMIC_MODELS", "LONGITUDINAL", "LATERAL",
           "SixDofDynamics", "body_inertia", "linear_constants"]

#: Names of the state components, in order.
SIXDOF_STATE_NAMES: tuple[str, ...] = ("u", "v", "w", "p", "q", "r", "roll", "theta")
#: Aerodynamic models of :class:`SixDofDynamics`.
SIXDOF_AERODYNAMIC_MODELS: tuple[str, ...] = ("small-angle", "exact", "linear")
#: Indices of the longitudinal states (u, w, q, theta) in the eight-state vector.
LONGITUDINAL: tuple[int, ...] = (0, 2, 4, 7)
#: Indices of the lateral states (v, p, r, roll) in the eight-state vector.
LATERAL: tuple[int, ...] = (1, 3, 5, 6)

# The generated functions take their arguments spread from tuples (their signatures are long).
_gen: Any = _sixdof_generated
_lin: Any = _sixdof_linear_generated


def linear_constants(insect: Insect) -> np.ndarray:
    """The constants array ``k`` of the generated linear loads (their ``CONSTANTS``, SI).

    Parameters
    ----------
    insect : Insect

    Returns
    -------
    numpy.ndarray
        float64, in the order of ``_sixdof_linear_generated.CONSTANTS``.
    """
    c = aero_constants(insect)
    plain = {"FREQUENCY": c.f, "H_W": c.h_w, "K_NU": c.Knu, "MU1": c.mu1, "X_H": c.x_h,
             "X_HAT": c.x_hat}
    values = []
    for name in _lin.CONSTANTS:
        if name in plain:
            values.append(plain[name])
        else:  # K_mn or KROT_mn
            table = c.Krot if name.startswith("KROT_") else c.K
            values.append(table[(int(name[-2]), int(name[-1]))])
    return np.array(values, dtype=float)


def body_inertia(insect: Insect) -> tuple[float, float, float, float]:
    """(I_x, I_y, I_z, I_xz) of the body [kg m^2], or a ValueError naming the missing field.

    Parameters
    ----------
    insect : Insect
        Must carry ``roll_inertia``, ``yaw_inertia`` and ``roll_yaw_product``.

    Raises
    ------
    ValueError
        If one of them is None (the planar model does not need them; six degrees of freedom
        do).
    """
    _validation.instance("insect", insect, Insect)
    missing = [name for name in ("roll_inertia", "yaw_inertia", "roll_yaw_product")
               if getattr(insect, name) is None]
    if missing:
        raise ValueError(
            f"six degrees of freedom need the body's {', '.join(f'`{n}`' for n in missing)} "
            f"[kg m^2]; {insect.name} has none: give them with insect.with_(roll_inertia=..., "
            "yaw_inertia=..., roll_yaw_product=...) (the presets carry sourced values)")
    assert insect.roll_inertia is not None and insect.yaw_inertia is not None
    assert insect.roll_yaw_product is not None
    return (insect.roll_inertia, insect.pitch_inertia, insect.yaw_inertia,
            insect.roll_yaw_product)


class SixDofDynamics:
    """Flight dynamics of a flapping insect in six degrees of freedom (``solve_ivp`` convention).

    Parameters
    ----------
    insect : Insect
        Morphology and constants, with the body's roll and yaw inertia (:func:`body_inertia`).
    amplitude : float, optional
        Stroke amplitude Phi [rad], in (0, pi/2]; default ``insect.stroke_amplitude``.
    alpha_m : float, optional
        Mean geometric angle of attack [rad], in (0, pi/2); default the trim of eq. (40) at the
        insect's nominal amplitude (as the planar model).
    aerodynamics : {"small-angle", "exact", "linear"}
        The blade-element loads, or the paper's linear loads (eq. 29) in six degrees of freedom
        (:data:`SIXDOF_AERODYNAMIC_MODELS`).
    n_nodes : int
        Span quadrature nodes, in [2, 4096].

    Raises
    ------
    ValueError
        If an argument is outside its range, or the insect lacks its roll or yaw inertia.
    """

    def __init__(self, insect: Insect, amplitude: float | None = None,
                 alpha_m: float | None = None, aerodynamics: str = "small-angle",
                 n_nodes: int = 32) -> None:
        inertia = body_inertia(insect)
        self.insect = insect
        self.amplitude = check_amplitude(insect.stroke_amplitude if amplitude is None
                                         else amplitude)
        if alpha_m is None:
            alpha_m = trim_angle_of_attack(insect, insect.stroke_amplitude)
        self.alpha_m = check_alpha_m(alpha_m)
        self.aerodynamics = _validation.choice("aerodynamics", aerodynamics,
                                               SIXDOF_AERODYNAMIC_MODELS)
        self.n_nodes = check_nodes(n_nodes)
        if self.aerodynamics == "linear":
            self._blade: BladeElementModel | None = None
            self._linear_k = linear_constants(insect)
        else:
            self._blade = BladeElementModel(insect, self.alpha_m, self.amplitude,
                                            self.aerodynamics, self.n_nodes)
        a1, a2 = insect.wing_mass_moments
        # The constants k of the generated functions (sixdof_derivation.CONSTANT_NAMES); the
        # wing roots sit on the plane of symmetry (y_w = 0), as in the planar model.
        self._k = (insect.mass, *inertia, insect.wing_mass, a1, a2, insect.hinge_offset, 0.0,
                   insect.hinge_height, insect.gravity)
        # Massless wings: the mass matrix is constant (diag(m, m, m, inertia tensor)).
        self._inverse = (np.linalg.inv(np.array(_gen.mass_matrix(0.0, self._k)).reshape(6, 6))
                         if insect.wing_mass == 0.0 else None)

    @property
    def period(self) -> float:
        """Flapping period T [s]."""
        return self.insect.period

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """Stroke reversals as fractions of the period (the right-hand side is not smooth there)."""
        return HALF_STROKE_BREAKPOINTS

    def with_amplitude(self, amplitude: float) -> SixDofDynamics:
        """The same model at another stroke amplitude (alpha_m kept)."""
        return SixDofDynamics(self.insect, amplitude, self.alpha_m, self.aerodynamics,
                              self.n_nodes)

    def _stroke(self, t: float, amplitude: float) -> tuple[float, float, float]:
        """(phi, phi_dot, phi_ddot) at t: phi = phi_bar + Phi cos(2 pi f t)."""
        omega = 2.0 * math.pi * self.insect.frequency
        c, s = math.cos(omega * t), math.sin(omega * t)
        return (self.insect.stroke_mean + amplitude * c, -omega * amplitude * s,
                -omega * omega * amplitude * c)

    def _loads(self, t: float, x: Sequence[float], s: float,
               amplitude: float) -> tuple[float, ...]:
        phi, phi_dot, _ = self._stroke(t, amplitude)
        if self._blade is None:  # eq. (29): constant loads + derivatives times (u ... r)
            out = np.empty(len(_lin.OUTPUT_NAMES))
            _lin.linear_loads(phi, phi_dot, abs(phi_dot), self.alpha_m, self._linear_k, out)
            return tuple((out[:6] + out[6:].reshape(6, 6) @ np.asarray(x[:6])).tolist())
        kin = _gen.strip_kinematics(phi, phi_dot, *x, self._k)
        right = self._blade.wing_resultants(kin[0], kin[1], kin[2], kin[3], kin[4], s)
        left = self._blade.wing_resultants(kin[5], kin[6], kin[7], kin[8], kin[9], s)
        return _gen.wing_loads(phi, s, self.alpha_m, self.insect.center_of_pressure, *right,
                               *left, self._k)

    def linear_loads(self, t: float, amplitude: float | None = None) -> tuple[np.ndarray,
                                                                              np.ndarray]:
        """The paper's linear loads (eq. 29) in six degrees of freedom at time t.

        Parameters
        ----------
        t : float
            Time [s].
        amplitude : float, optional
            Stroke amplitude [rad]; default the model's.

        Returns
        -------
        loads0 : numpy.ndarray, shape (6,)
            (X0, Y0, Z0, L0, M0, N0) [N, N m]: the loads at the zero state.
        derivatives : numpy.ndarray, shape (6, 6)
            d(X, Y, Z, L, M, N)/d(u, v, w, p, q, r) (dimensional; for every aerodynamic model
            of this instance, the derivatives of the small-angle loads at the zero state).
        """
        t = _validation.real("t", t)
        amplitude = self.amplitude if amplitude is None else check_amplitude(amplitude)
        phi, phi_dot, _ = self._stroke(t, amplitude)
        k = self._linear_k if self._blade is None else linear_constants(self.insect)
        out = np.empty(len(_lin.OUTPUT_NAMES))
        _lin.linear_loads(phi, phi_dot, abs(phi_dot), self.alpha_m, k, out)
        return out[:6], out[6:].reshape(6, 6)

    def loads(self, t: float, x: Sequence[float] | np.ndarray, s: float | None = None,
              amplitude: float | None = None) -> np.ndarray:
        """Aerodynamic loads (X, Y, Z, L, M, N) of both wings about the centre of gravity.

        Parameters
        ----------
        t : float
            Time [s].
        x : sequence of 8 floats
            The state (:data:`SIXDOF_STATE_NAMES`).
        s : {+1, -1}, optional
            Stroke sign; default the sign of phi_dot(t) (:meth:`segment_functions` fixes it per
            half-stroke).
        amplitude : float, optional
            Stroke amplitude [rad]; default the model's.

        Returns
        -------
        numpy.ndarray
            Forces [N] and moments [N m] in body axes.
        """
        t, x, s, amplitude = self._checked(t, x, s, amplitude)
        return np.array(self._loads(t, x, s, amplitude))

    def _rhs(self, t: float, x: Sequence[float], s: float, amplitude: float) -> np.ndarray:
        phi, phi_dot, phi_ddot = self._stroke(t, amplitude)
        loads = self._loads(t, x, s, amplitude)
        forcing = _gen.forcing(phi, phi_dot, phi_ddot, *x, self._k)
        out = np.empty(8)
        if self._inverse is not None:
            out[:6] = self._inverse @ np.add(loads, forcing)
        else:
            a = np.array(_gen.mass_matrix(phi, self._k)).reshape(6, 6)
            out[:6] = np.linalg.solve(a, np.add(loads, forcing))
        out[6:] = _gen.euler_rates(*x)
        return out

    def rhs(self, t: float, x: Sequence[float] | np.ndarray, s: float | None = None,
            amplitude: float | None = None) -> np.ndarray:
        """dx/dt of the eight states (arguments as :meth:`loads`)."""
        t, x, s, amplitude = self._checked(t, x, s, amplitude)
        return self._rhs(t, x, s, amplitude)

    def _checked(self, t: Any, x: Any, s: Any, amplitude: Any) -> tuple[float, list[float],
                                                                        float, float]:
        t = _validation.real("t", t)
        x = _validation.array("x", x)
        if x.shape != (8,):
            raise ValueError(f"`x` must hold the 8 states {SIXDOF_STATE_NAMES}; got shape "
                             f"{x.shape}")
        amplitude = self.amplitude if amplitude is None else check_amplitude(amplitude)
        if s is None:
            s = 1.0 if self._stroke(t, amplitude)[1] > 0.0 else -1.0
        elif s not in (1, -1):
            raise ValueError(f"`s` must be +1 or -1 (the stroke sign); got {s!r}")
        return t, x.tolist(), float(s), amplitude

    def segment_functions(self) -> list[Callable[..., np.ndarray]]:
        """One right-hand side ``f(t, x, amplitude)`` per half-stroke (stroke sign fixed), for
        integrators that restart at :attr:`breakpoints` (the solvers' entry: unchecked)."""
        def field(sign: float) -> Callable[..., np.ndarray]:
            def f(t: float, x: Any, amplitude: float) -> np.ndarray:
                return self._rhs(t, list(x), sign, amplitude)
            return f

        return [field(segment_stroke_sign(k)) for k in range(len(self.breakpoints) + 1)]

"""The wings' inertial loads on the body: accelerations of the body with wings of mass.

With massless wings (the paper's eq. 2, ``insect.wing_mass = 0``) the body's accelerations are the
loads over the mass and inertia. With wings of mass m_w flapping on a prescribed stroke phi(t), the
body and wings obey (derived in :mod:`flapping.model.inertia_derivation`, generated into
``_inertia_generated``)

    A(phi) (u_dot, w_dot, q_dot) = (X, Z, M) + F(phi, phi_dot, phi_ddot, u, w, q, theta),

A the mass matrix of body and wings about the body's centre of gravity (it couples the three
accelerations through the wings' first mass moment), F gravity, the body's rotation terms and the
wings' reaction to their own acceleration. :class:`WingInertia` solves this 3 x 3 system and gives
its derivatives in the states (for Jacobians) and in the stroke (for the sensitivities to the
stroke amplitude and mean stroke angle).

Layering: imports morphology and the generated code only.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

import flapping._validation as _validation
from flapping.model import _inertia_generated as _gen
from flapping.model.morphology import Insect

__all__ = ["WingInertia", "stroke_phase"]


def stroke_phase(insect: Insect, t: float, amplitude: float) -> tuple[float, float, float]:
    """(phi, phi_dot, phi_ddot) [rad, rad/s, rad/s^2] of phi = phi_bar + Phi cos(2 pi f t) at t.

    Parameters
    ----------
    insect : Insect
        Its frequency and mean stroke angle.
    t : float
        Time [s].
    amplitude : float
        Stroke amplitude Phi [rad].

    Returns
    -------
    tuple of 3 floats

    Raises
    ------
    ValueError
        If ``insect`` is not an Insect, or ``t`` or ``amplitude`` is not a finite real number
        (the dynamics call the unchecked :func:`_stroke_phase` inside integrations).
    """
    _validation.instance("insect", insect, Insect)
    return _stroke_phase(insect, _validation.real("t", t),
                         _validation.real("amplitude", amplitude))


def _stroke_phase(insect: Insect, t: float, amplitude: float) -> tuple[float, float, float]:
    """:func:`stroke_phase` of trusted arguments (inside right-hand sides)."""
    omega = 2.0 * math.pi * insect.frequency
    c, s = math.cos(omega * t), math.sin(omega * t)
    return (insect.stroke_mean + amplitude * c, -omega * amplitude * s,
            -omega * omega * amplitude * c)


def stroke_phase_amplitude_derivative(insect: Insect, t: float) -> tuple[float, float, float]:
    """d/dPhi of :func:`stroke_phase` (independent of Phi)."""
    omega = 2.0 * math.pi * insect.frequency
    c, s = math.cos(omega * t), math.sin(omega * t)
    return c, -omega * s, -omega * omega * c


@dataclass(frozen=True)
class WingInertia:
    """The body's accelerations with wings of mass (see the module docstring).

    Parameters
    ----------
    constants : tuple of 8 floats
        (m, I_b, m_w, A1, A2, x_h, h_w, g) in the order of
        :data:`~flapping.model.inertia_derivation.CONSTANT_NAMES`: total mass [kg], the body's
        pitch inertia about its centre of gravity [kg m^2], one wing's mass [kg], the pair's first
        and second spanwise mass moments about the hinge [kg m, kg m^2], the hinge ahead of and
        above the centre of gravity [m], gravity [m/s^2].
    """

    constants: tuple[float, ...]

    @classmethod
    def of(cls, insect: Insect) -> WingInertia | None:
        """The wing inertia of an insect; None if its wings are massless (``wing_mass = 0``)."""
        if insect.wing_mass == 0.0:
            return None
        a1, a2 = insect.wing_mass_moments
        return cls((insect.mass, insect.pitch_inertia, insect.wing_mass, a1, a2,
                    insect.hinge_offset, insect.hinge_height, insect.gravity))

    def _mass_matrix(self, phi: float) -> np.ndarray:
        return np.array(_gen.mass_matrix(phi, self.constants), dtype=float).reshape(3, 3)

    def _accelerations(self, phase: Sequence[float], x: Sequence[float],
                      loads: Sequence[float] | np.ndarray) -> np.ndarray:
        """:meth:`accelerations` of trusted arguments (inside right-hand sides)."""
        forcing = _gen.forcing(phase[0], phase[1], phase[2], x[0], x[1], x[2], x[3], self.constants)
        rhs = np.asarray(loads, dtype=float) + np.array(forcing, dtype=float)
        return np.linalg.solve(self._mass_matrix(phase[0]), rhs)

    def _state_jac(self, phase: Sequence[float], x: Sequence[float],
                  loads_jac: np.ndarray) -> np.ndarray:
        """:meth:`state_jac` of trusted arguments (inside right-hand sides)."""
        values = _gen.forcing_state_jac(phase[0], phase[1], phase[2], x[0], x[1], x[2], x[3],
                                        self.constants)
        forcing = np.array(values, dtype=float).reshape(3, 4)
        return np.linalg.solve(self._mass_matrix(phase[0]), loads_jac + forcing)

    def _stroke_jac(self, phase: Sequence[float], x: Sequence[float],
                   loads: Sequence[float] | np.ndarray,
                   dphase: Sequence[float], dloads: Sequence[float]) -> np.ndarray:
        """:meth:`stroke_jac` of trusted arguments (inside right-hand sides)."""
        k = self.constants
        a = self._mass_matrix(phase[0])
        acc = self._accelerations(phase, x, loads)
        values = _gen.forcing_kinematic_jac(phase[0], phase[1], phase[2], x[0], x[1], x[2], x[3],
                                            k)
        dforcing = np.array(values, dtype=float).reshape(3, 3) @ np.asarray(dphase, dtype=float)
        da = np.array(_gen.mass_matrix_phi_jac(phase[0], k), dtype=float).reshape(3, 3)
        db = np.asarray(dloads, dtype=float) + dforcing
        return np.linalg.solve(a, db - da @ acc * dphase[0])

    def accelerations(self, phase: Sequence[float], x: Sequence[float],
                      loads: Sequence[float] | np.ndarray) -> np.ndarray:
        """(u_dot, w_dot, q_dot) = A^-1 (loads + F).

        Parameters
        ----------
        phase : (phi, phi_dot, phi_ddot)
            The stroke at this instant (:func:`stroke_phase`).
        x : array_like
            State (u, w, q, theta).
        loads : array_like
            Aerodynamic (X, Z, M) about the body's centre of gravity [N, N, N m].

        Returns
        -------
        numpy.ndarray, shape (3,)

        Raises
        ------
        ValueError
            If an entry of ``phase``, ``x`` (its first four) or ``loads`` is not a finite real
            number, or one is missing (the message names the argument). The dynamics call the
            unchecked implementation inside integrations.
        """
        _check_arrays(("phase", phase, 3), ("x", x, 4), ("loads", loads, 3))
        return self._accelerations(phase, x, loads)

    def state_jac(self, phase: Sequence[float], x: Sequence[float],
                  loads_jac: np.ndarray) -> np.ndarray:
        """d(u_dot, w_dot, q_dot)/d(u, w, q, theta), shape (3, 4).

        Parameters
        ----------
        phase, x
            As for :meth:`accelerations`.
        loads_jac : ndarray, shape (3, 4)
            d(X, Z, M)/d(u, w, q, theta) [N per unit state].

        Raises
        ------
        ValueError
            If an entry of ``phase``, ``x`` (its first four) or ``loads_jac`` is not a finite real
            number, or one is missing (the message names the argument). The dynamics call the
            unchecked implementation inside integrations.
        """
        _check_arrays(("phase", phase, 3), ("x", x, 4), ("loads_jac", loads_jac, None))
        return self._state_jac(phase, x, loads_jac)

    def stroke_jac(self, phase: Sequence[float], x: Sequence[float],
                   loads: Sequence[float] | np.ndarray,
                   dphase: Sequence[float], dloads: Sequence[float]) -> np.ndarray:
        """d(u_dot, w_dot, q_dot)/dp for a parameter p of the stroke, shape (3,).

        d(A^-1 b)/dp = A^-1 (db/dp - dA/dp A^-1 b), with b = loads + F.

        Parameters
        ----------
        phase, x, loads
            As for :meth:`accelerations`.
        dphase : (dphi/dp, dphi_dot/dp, dphi_ddot/dp)
            How the stroke moves with p (e.g. (1, 0, 0) for the mean stroke angle).
        dloads : array_like
            d(X, Z, M)/dp [N per unit p].

        Raises
        ------
        ValueError
            If an entry of ``phase``, ``x``, ``loads``, ``dphase`` or ``dloads`` is not a finite
            real number, or one is missing (the message names the argument). The dynamics call
            the unchecked implementation inside integrations.
        """
        _check_arrays(("phase", phase, 3), ("x", x, 4), ("loads", loads, 3), ("dphase", dphase, 3),
                      ("dloads", dloads, 3))
        return self._stroke_jac(phase, x, loads, dphase, dloads)


def _check_arrays(*arguments: tuple[str, object, int | None]) -> None:
    """Each (name, value, size): ``value`` finite, with at least ``size`` entries (any shape if
    size is None), else a ValueError naming it."""
    for name, value, size in arguments:
        array = _validation.array(name, value)
        if size is not None and (array.ndim != 1 or array.size < size):
            raise ValueError(f"`{name}` must be a 1-D array of at least {size} numbers; got "
                             f"shape {array.shape}")

"""Numeric time-periodic stability derivatives X0(t) ... Mq(t) of eq. (29).

The formulas are the ones derived symbolically in :mod:`flapping.model.derivation`, used through the
generated module ``flapping.model._derivatives_generated`` (plain NumPy / math code, no SymPy at run
time). Normalisation as in eq. (29): X0, Z0 [N], M0 [N m]; Xu, Xw, Zu, Zw [1/s]; Xq, Zq [m/(s rad)];
Mu, Mw [1/(m s)]; Mq [1/s] -- forces divided by the mass, moments by the pitch inertia.

The constants they take, :class:`AeroConstants` from :func:`aero_constants`, are defined in
:mod:`flapping.model.aerodynamics` (below the derivation, which evaluates with them too) and
re-exported here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

import flapping._validation as _validation
from flapping.model import _derivatives_generated as _gen
from flapping.model.aerodynamics import AeroConstants, aero_constants, trim_angle_of_attack
from flapping.model.kinematics import check_alpha_m, check_amplitude, flapping_angle, flapping_rate
from flapping.model.morphology import Insect

__all__ = ["NAMES", "AeroConstants", "aero_constants", "StabilityDerivatives",
           "stability_derivatives"]

#: Names of the derivatives, in order.
NAMES: tuple[str, ...] = tuple(_gen.NAMES)


@dataclass(frozen=True)
class StabilityDerivatives:
    """Stability derivatives sampled at times ``t`` (result of :func:`stability_derivatives`).

    Attributes
    ----------
    t : ndarray
        Times [s].
    alpha_m, amplitude : float
        Mean geometric angle of attack and stroke amplitude [rad] they were evaluated at.
    X0, Z0, M0 : ndarray
        Zero-state loads [N, N, N m], the shape of ``t``.
    Xu, Xw, Xq, Zu, Zw, Zq, Mu, Mw, Mq : ndarray
        Derivatives normalised as in eq. (29) (forces per unit mass, moment per unit I_y).
    """

    t: np.ndarray
    alpha_m: float
    amplitude: float
    X0: np.ndarray
    Z0: np.ndarray
    M0: np.ndarray
    Xu: np.ndarray
    Xw: np.ndarray
    Xq: np.ndarray
    Zu: np.ndarray
    Zw: np.ndarray
    Zq: np.ndarray
    Mu: np.ndarray
    Mw: np.ndarray
    Mq: np.ndarray

    def as_dict(self) -> dict[str, np.ndarray]:
        """The twelve derivatives by name."""
        return {name: getattr(self, name) for name in NAMES}

    def averaged_jacobian(self, gravity: float) -> np.ndarray:
        """Jacobian of the first-order averaged system at the zero state, (u, w, q, theta).

        The periodic coefficients of eq. (29) replaced by their means over the samples (a cycle
        average on a uniform one-period grid); at trim the zero state is the averaged system's
        equilibrium, and this 4x4 matrix its linearisation (gravity enters through -g theta).

        Parameters
        ----------
        gravity : float
            g [m/s^2], >= 0.

        Returns
        -------
        numpy.ndarray, shape (4, 4)
        """
        gravity = _validation.nonnegative("gravity", gravity, unit="m/s^2")
        m = self.cycle_mean()
        return np.array([
            [m["Xu"], m["Xw"], m["Xq"], -gravity],
            [m["Zu"], m["Zw"], m["Zq"], 0.0],
            [m["Mu"], m["Mw"], m["Mq"], 0.0],
            [0.0, 0.0, 1.0, 0.0],
        ])

    def cycle_mean(self) -> dict[str, float]:
        """Means over the samples (a cycle average when ``t`` is a uniform grid over one period)."""
        return {name: float(np.mean(getattr(self, name))) for name in NAMES}


def stability_derivatives(
    insect: Insect,
    t: ArrayLike,
    *,
    alpha_m: float | None = None,
    amplitude: float | None = None,
) -> StabilityDerivatives:
    """Evaluate X0(t) ... Mq(t) of eq. (29) for ``insect``.

    Parameters
    ----------
    insect : Insect
        Morphology and aerodynamic constants.
    t : array_like
        Times [s].
    alpha_m : float, optional
        Mean geometric angle of attack [rad], in (0, pi/2); default: the trim of eq. (40) at the
        insect's nominal ``stroke_amplitude`` (the paper fixes alpha_m there and then frees Phi).
    amplitude : float, optional
        Stroke amplitude Phi [rad], in (0, pi/2]; default ``insect.stroke_amplitude``.

    Returns
    -------
    StabilityDerivatives
        The twelve derivatives sampled at ``t``.

    Raises
    ------
    ValueError
        If an argument is outside its range (the message names it), t is empty or not finite,
        or the insect cannot trim (eq. 40) when alpha_m is not given.
    """
    _validation.instance("insect", insect, Insect)
    amplitude = check_amplitude(insect.stroke_amplitude if amplitude is None else amplitude)
    if alpha_m is None:
        alpha_m = trim_angle_of_attack(insect, insect.stroke_amplitude)
    alpha_m = check_alpha_m(alpha_m)
    t = _validation.array("t", t)
    if t.size == 0:  # the cycle means of an empty sample are NaN, not an answer
        raise ValueError("`t` must hold at least one time; got an empty array")
    phi = flapping_angle(t, amplitude, insect.frequency)
    if insect.stroke_mean != 0.0:  # phi = phi_bar + Phi cos(2 pi f t); phi_bar = 0 adds nothing
        phi = phi + insect.stroke_mean
    phidot = flapping_rate(t, amplitude, insect.frequency)
    values = _gen.stability_derivatives(phi, phidot, np.abs(phidot), alpha_m,
                                        aero_constants(insect))
    arrays = [np.broadcast_to(np.asarray(v, dtype=float), t.shape).copy() for v in values]
    return StabilityDerivatives(t, alpha_m, amplitude, *arrays)

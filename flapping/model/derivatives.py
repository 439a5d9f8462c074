"""Numeric time-periodic stability derivatives X0(t) ... Mq(t) of eq. (29).

The formulas are the ones derived symbolically in :mod:`flapping.model.derivation`, used through the
generated module ``flapping.model._derivatives_generated`` (plain NumPy / math code, no SymPy at run
time). Normalisation as in eq. (29): X0, Z0 [N], M0 [N m]; Xu, Xw, Zu, Zw [1/s]; Xq, Zq [m/(s rad)];
Mu, Mw [1/(m s)]; Mq [1/s] -- forces divided by the mass, moments by the pitch inertia.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from flapping.model import _derivatives_generated as _gen
from flapping.model.aerodynamics import trim_angle_of_attack
from flapping.model.kinematics import check_amplitude, flapping_angle, flapping_rate
from flapping.model.morphology import Insect

__all__ = ["NAMES", "AeroConstants", "aero_constants", "StabilityDerivatives", "stability_derivatives"]

#: Names of the derivatives, in order.
NAMES: tuple[str, ...] = tuple(_gen.NAMES)


@dataclass(frozen=True)
class AeroConstants:
    """The constants of the linearised loads (after eq. 29), SI units.

    Attributes
    ----------
    K : dict
        K[(m, n)] = rho A I_mn / 2.
    Krot : dict
        Krot[(m, n)] = rho pi (3/4 - x0_hat) I_mn.
    Knu : float
        (pi/16) rho I_04.
    x_hat, x_h, mu1, f, m, Iy : float
        Centre of pressure (fraction of chord), hinge offset [m], damping coefficient, flapping
        frequency [Hz], mass [kg], pitch inertia [kg m^2].
    """

    K: dict
    Krot: dict
    Knu: float
    x_hat: float
    x_h: float
    mu1: float
    f: float
    m: float
    Iy: float


def aero_constants(insect: Insect) -> AeroConstants:
    """The constants K_mn, Krot_mn and K_nu of the linearised loads (after eq. 29).

    Parameters
    ----------
    insect : Insect
        Morphology; the span integrals I_mn come from its closed form (beta functions).

    Returns
    -------
    AeroConstants
        K[(m, n)] = rho A I_mn / 2 and Krot[(m, n)] = rho pi (3/4 - x0_hat) I_mn for m = 0..3,
        n = 1..4 where I_mn converges; K_nu = (pi/16) rho I_04; and the insect's x_hat, x_h,
        mu1, f, m, I_y.

    Raises
    ------
    ValueError
        If the rotational damping is on (mu1 or mu2 > 0) but I_04 diverges for this planform.
    """
    rho, A = insect.air_density, insect.lift_slope
    kappa = 0.75 - insect.pitch_axis
    I = {(m, n): insect.span_integral(m, n) for m in range(4) for n in range(1, 5)
         if (m + 1 + n * (insect.beta_p - 1.0)) > 0}
    if (0, 4) in I:
        knu = math.pi / 16.0 * rho * I[(0, 4)]
    elif insect.mu1 == 0.0 and insect.mu2 == 0.0:
        knu = 0.0  # no rotational damping: its diverging span integral is never needed
    else:
        raise ValueError(
            f"the rotational damping needs I_04 = 2 int c^4 dr, which diverges for this planform "
            f"(r1={insect.r1!r}, r2={insect.r2!r}: beta shape p={insect.beta_p:.4g} <= 3/4); "
            "choose r1, r2 with p > 3/4 or set mu1 = mu2 = 0"
        )
    return AeroConstants(
        K={k: 0.5 * rho * A * v for k, v in I.items()},
        Krot={k: rho * math.pi * kappa * v for k, v in I.items()},
        Knu=knu,
        x_hat=insect.center_of_pressure,
        x_h=insect.hinge_offset,
        mu1=insect.mu1,
        f=insect.frequency,
        m=insect.mass,
        Iy=insect.pitch_inertia,
    )


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
        """
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
    t,
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
        Mean geometric angle of attack [rad]; default: the trim of eq. (40) at the insect's
        nominal ``stroke_amplitude`` (the paper fixes alpha_m there and then frees Phi).
    amplitude : float, optional
        Stroke amplitude Phi [rad]; default ``insect.stroke_amplitude``.

    Returns
    -------
    StabilityDerivatives
    """
    amplitude = check_amplitude(insect.stroke_amplitude if amplitude is None else amplitude)
    if alpha_m is None:
        alpha_m = trim_angle_of_attack(insect, insect.stroke_amplitude)
    elif not (isinstance(alpha_m, (int, float)) and math.isfinite(alpha_m)
              and 0.0 < alpha_m < math.pi / 2):
        raise ValueError(f"alpha_m must be a number in (0, pi/2) rad; got {alpha_m!r}")
    t = np.asarray(t, dtype=float)
    if not np.all(np.isfinite(t)):
        raise ValueError("t must be finite")
    phi = flapping_angle(t, amplitude, insect.frequency)
    phidot = flapping_rate(t, amplitude, insect.frequency)
    values = _gen.stability_derivatives(phi, phidot, np.abs(phidot), alpha_m, aero_constants(insect))
    arrays = [np.broadcast_to(np.asarray(v, dtype=float), t.shape).copy() for v in values]
    return StabilityDerivatives(t, float(alpha_m), amplitude, *arrays)

"""The toy systems of the Floquet primer (``book/primer_floquet.md``), before the insect.

* A scalar periodic system ``x' = a(t) x`` with ``a(t) = a0 + a1 cos(2 pi t / T)``: its multiplier
  is ``exp(int_0^T a dt) = exp(a0 T)``, whatever ``a1`` (:func:`scalar_system`).
* The inverted pendulum on a vertically vibrated pivot (Kapitza's pendulum,
  :class:`KapitzaPendulum`): upright, it falls without the vibration, and first-order averaging of
  the linearised equations (the mean of the periodic Jacobian) says it still falls; Floquet theory
  (:func:`flapping.periodic.monodromy`) says it stays up when ``a^2 omega^2 > 2 g l``, the
  criterion that second-order averaging recovers.
* :func:`averaging_error`: for a periodic forcing of fixed size, the gap between the Floquet
  exponents and the eigenvalues of the averaged matrix shrinks as the period goes to zero.

Everything is computed with :mod:`flapping.periodic`, as for the insect.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from flapping.periodic.floquet import monodromy

__all__ = [
    "scalar_system",
    "KapitzaPendulum",
    "FloquetVersusAveraging",
    "floquet_versus_averaging",
    "averaging_error",
]


def scalar_system(a0: float, a1: float, period: float
                  ) -> tuple[Callable[..., np.ndarray], Callable[..., np.ndarray]]:
    """``x' = (a0 + a1 cos(2 pi t / T)) x`` as ``(fun, exact)``.

    Parameters
    ----------
    a0, a1 : float
        Mean and amplitude of the rate a(t) [1/s].
    period : float
        T [s].

    Returns
    -------
    fun : callable
        ``fun(t, x)``, for :func:`flapping.periodic.flow` (x of shape (1,)).
    exact : callable
        ``exact(t, x0)``: the solution ``x0 exp(a0 t + a1 T / (2 pi) sin(2 pi t / T))``.
    """
    omega = 2.0 * math.pi / period

    def fun(t, x):
        return (a0 + a1 * math.cos(omega * t)) * np.asarray(x, dtype=float)

    def exact(t, x0):
        t = np.asarray(t, dtype=float)
        return x0 * np.exp(a0 * t + a1 / omega * np.sin(omega * t))

    return fun, exact


@dataclass(frozen=True)
class KapitzaPendulum:
    """An inverted pendulum whose pivot is shaken vertically, ``y_p = a cos(omega t)``.

    With the angle ``x`` from the upright (rad) and the state ``(x, x')``::

        x'' = (g / l) (1 + (a omega^2 / g) cos(omega t)) sin x - c x'

    Attributes
    ----------
    length_m : float
        Pendulum length l [m].
    amplitude_m : float
        Pivot amplitude a [m].
    frequency_hz : float
        Pivot frequency f [Hz]; omega = 2 pi f.
    damping_per_s : float
        Viscous damping c [1/s].
    gravity : float
        g [m/s^2].
    """

    length_m: float = 0.2
    amplitude_m: float = 0.02
    frequency_hz: float = 25.0
    damping_per_s: float = 0.5
    gravity: float = 9.81

    @property
    def omega(self) -> float:
        """Angular frequency of the pivot [rad/s]."""
        return 2.0 * math.pi * self.frequency_hz

    @property
    def period(self) -> float:
        """Period of the pivot's motion T [s]."""
        return 1.0 / self.frequency_hz

    def _gain(self, t: float) -> float:
        return self.gravity / self.length_m * (
            1.0 + self.amplitude_m * self.omega**2 / self.gravity * math.cos(self.omega * t))

    def rhs(self, t: float, x: Any) -> np.ndarray:
        """The nonlinear equations of motion, ``(x, x')' = (x', gain(t) sin x - c x')``."""
        return np.array([x[1], self._gain(t) * math.sin(x[0]) - self.damping_per_s * x[1]])

    def jacobian(self, t: float, x: Any) -> np.ndarray:
        """``d rhs / dx``; about the upright (x = 0) it is the linearised system's matrix A(t)."""
        return np.array([[0.0, 1.0], [self._gain(t) * math.cos(x[0]), -self.damping_per_s]])

    def averaged_matrix(self) -> np.ndarray:
        """The mean of A(t) over a period: first-order averaging about the upright."""
        return np.array([[0.0, 1.0], [self.gravity / self.length_m, -self.damping_per_s]])

    @property
    def kapitza_number(self) -> float:
        """``a^2 omega^2 / (2 g l)``: above one the upright is stable (second-order averaging)."""
        return (self.amplitude_m * self.omega) ** 2 / (2.0 * self.gravity * self.length_m)


@dataclass(frozen=True)
class FloquetVersusAveraging:
    """The stability of a periodic linear system by Floquet theory and by first-order averaging.

    Attributes
    ----------
    multipliers : ndarray
        Floquet multipliers (eigenvalues of the monodromy matrix), by decreasing modulus.
    exponents : ndarray
        Floquet exponents ``log(mu) / T`` [1/s] (real parts).
    averaged_eigenvalues : ndarray
        Eigenvalues of the averaged matrix [1/s], by decreasing real part.
    monodromy_det : float
        ``det`` of the monodromy matrix (Liouville's check: ``exp(int trace A)``).
    liouville_error : float
        Relative difference between the two.
    """

    multipliers: np.ndarray
    exponents: np.ndarray
    averaged_eigenvalues: np.ndarray
    monodromy_det: float
    liouville_error: float

    @property
    def floquet_stable(self) -> bool:
        """Every multiplier inside the unit circle."""
        return bool(np.all(np.abs(self.multipliers) < 1.0))

    @property
    def averaging_stable(self) -> bool:
        """Every eigenvalue of the averaged matrix in the left half-plane."""
        return bool(np.all(self.averaged_eigenvalues.real < 0.0))


def floquet_versus_averaging(pendulum: KapitzaPendulum) -> FloquetVersusAveraging:
    """Floquet multipliers of the upright pendulum against the averaged system's eigenvalues.

    Parameters
    ----------
    pendulum : KapitzaPendulum

    Returns
    -------
    FloquetVersusAveraging
    """
    mon = monodromy(pendulum.rhs, np.zeros(2), pendulum.period, jac=pendulum.jacobian)
    averaged = np.linalg.eigvals(pendulum.averaged_matrix())
    return FloquetVersusAveraging(
        multipliers=mon.multipliers,
        exponents=np.log(np.abs(mon.multipliers)) / pendulum.period,
        averaged_eigenvalues=averaged[np.argsort(-averaged.real)],
        monodromy_det=float(mon.det),
        liouville_error=float(mon.liouville_error),
    )


def averaging_error(a0: Any, a1: Any, periods: Sequence[float]) -> np.ndarray:
    """Largest gap between Floquet exponents and averaged eigenvalues, for each period.

    The system is ``x' = (A0 + A1 cos(2 pi t / T)) x``: forcing of fixed size, faster and faster.

    Parameters
    ----------
    a0, a1 : array_like, shape (n, n)
        Mean and amplitude of the periodic matrix [1/s].
    periods : sequence of float
        Periods T [s].

    Returns
    -------
    ndarray
        For each T, ``max |Re lambda_k - Re lambda_bar_k|`` [1/s], both sorted by real part.
    """
    a0 = np.asarray(a0, dtype=float)
    a1 = np.asarray(a1, dtype=float)
    averaged = np.sort(np.linalg.eigvals(a0).real)
    gaps = []
    for period in periods:
        omega = 2.0 * math.pi / period

        def fun(t, x, omega=omega):
            return (a0 + a1 * math.cos(omega * t)) @ x

        def jac(t, x, omega=omega):
            return a0 + a1 * math.cos(omega * t)

        mon = monodromy(fun, np.zeros(len(a0)), period, jac=jac)
        exponents = np.sort(np.log(np.abs(mon.multipliers)) / period)
        gaps.append(float(np.max(np.abs(exponents - averaged))))
    return np.array(gaps)

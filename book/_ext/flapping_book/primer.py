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
* :func:`floquet_factorisation`: Floquet's theorem made concrete, ``Psi(t) = P(t) exp(B t)`` with
  ``B = log(Psi(T)) / T`` and ``P`` periodic.
* :func:`read_multiplier`: what a multiplier's logarithm says, for positive, negative and complex
  multipliers (growth per period, turn per period, the branch of the logarithm).
* :func:`linearisation_error`: the stroboscopic map of the nonlinear flow against its
  linearisation ``Psi(T)``, for shrinking disturbances.

Everything is computed with :mod:`flapping.periodic`, as for the insect.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.linalg

from flapping.periodic.floquet import floquet_exponents, monodromy
from flapping.periodic.integrate import flow, variational_flow

__all__ = [
    "scalar_system",
    "KapitzaPendulum",
    "FloquetVersusAveraging",
    "floquet_versus_averaging",
    "averaging_error",
    "FloquetFactorisation",
    "floquet_factorisation",
    "MultiplierReading",
    "read_multiplier",
    "linearisation_error",
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


@dataclass(frozen=True)
class FloquetFactorisation:
    """Floquet's theorem for one linear periodic system: ``Psi(t) = P(t) exp(B t)``.

    Attributes
    ----------
    times : ndarray, shape (m,)
        Times t [s] at which ``Psi`` and ``P`` are given (from 0 to ``periods`` periods).
    stm : ndarray, shape (n, n, m)
        State-transition matrices ``Psi(t)`` from the variational equations.
    B : ndarray, shape (n, n), complex
        ``log(Psi(T)) / T`` (principal matrix logarithm); complex when a multiplier is negative.
    P : ndarray, shape (n, n, m), complex
        ``Psi(t) exp(-B t)``: T-periodic, ``P(0) = P(T) = I``.
    period : float
        T [s].
    """

    times: np.ndarray
    stm: np.ndarray
    B: np.ndarray
    P: np.ndarray
    period: float

    def periodicity_error(self) -> float:
        """``max |P(t + T) - P(t)|`` over the sampled times one period apart (0 if none)."""
        shift = {round(t / self.period, 9): k for k, t in enumerate(self.times)}
        errors = [float(np.max(np.abs(self.P[..., shift[key + 1.0]] - self.P[..., k])))
                  for key, k in shift.items() if key + 1.0 in shift]
        return max(errors, default=0.0)

    def exponents(self) -> np.ndarray:
        """Eigenvalues of ``B``, sorted by decreasing real part: the Floquet exponents [1/s]."""
        eig = np.linalg.eigvals(self.B)
        return eig[np.argsort(-eig.real, kind="stable")]


def floquet_factorisation(fun: Callable[..., Any], x0: Any, period: float, *,
                          jac: Callable[..., Any] | None = None, periods: int = 2,
                          samples_per_period: int = 16, args: tuple = ()
                          ) -> FloquetFactorisation:
    """Split the state-transition matrix along a periodic orbit as ``P(t) exp(B t)``.

    Parameters
    ----------
    fun : callable
        ``fun(t, x, *args)``, T-periodic in t; ``x0`` must start a T-periodic solution (for a
        linear system, ``x0 = 0``).
    x0 : array_like, shape (n,)
        Start of the periodic orbit.
    period : float
        T [s].
    jac : callable, optional
        ``d fun / dx``; default finite differences (see
        :func:`flapping.periodic.integrate.variational_flow`).
    periods : int
        Number of periods sampled (at least 1; 2 lets :meth:`FloquetFactorisation.periodicity_error`
        compare P one period apart at every sample).
    samples_per_period : int
        Samples per period.
    args : tuple
        Extra arguments of ``fun`` and ``jac``.

    Returns
    -------
    FloquetFactorisation
    """
    if periods < 1 or samples_per_period < 1:
        raise ValueError("periods and samples_per_period must be >= 1; "
                         f"got {periods!r}, {samples_per_period!r}")
    times = np.linspace(0.0, periods * period, periods * samples_per_period + 1)
    var = variational_flow(fun, jac, (0.0, times[-1]), x0, t_out=times, args=args)
    stm = var.stm
    k_period = samples_per_period          # index of t = T
    B = scipy.linalg.logm(stm[..., k_period]) / period
    P = np.stack([stm[..., k] @ scipy.linalg.expm(-B * t) for k, t in enumerate(times)], axis=-1)
    return FloquetFactorisation(times=times, stm=stm, B=np.asarray(B, dtype=complex),
                                P=P, period=float(period))


@dataclass(frozen=True)
class MultiplierReading:
    """What the logarithm of one Floquet multiplier ``mu = exp(lambda T)`` says.

    Attributes
    ----------
    multiplier : complex
        mu.
    exponent : complex
        ``log(mu) / T`` on the principal branch [1/s]; the imaginary part is defined only up to
        multiples of ``2 pi / T``, the real part is not ambiguous.
    growth_per_period : float
        ``ln |mu|``: e-folds of growth (negative: decay) per period.
    turn_per_period : float
        ``arg(mu) / (2 pi)`` in (-1/2, 1/2]: the fraction of a turn the disturbance makes per
        period in the plane of its (complex) eigenvector; 1/2 for a negative multiplier.
    kind : str
        ``"positive"``, ``"negative"`` or ``"complex"``.
    """

    multiplier: complex
    exponent: complex
    growth_per_period: float
    turn_per_period: float
    kind: str

    @property
    def periods_per_turn(self) -> float:
        """Periods for one full turn, ``1 / |turn_per_period|`` (2 for a negative multiplier,
        infinite for a positive one)."""
        return math.inf if self.turn_per_period == 0 else 1.0 / abs(self.turn_per_period)

    def branches(self, period: float, ks: Sequence[int] = (-1, 0, 1)) -> np.ndarray:
        """Other logarithms of the same multiplier: ``exponent + 2 pi i k / T`` [1/s]."""
        return np.array([self.exponent + 2j * math.pi * k / period for k in ks])


def read_multiplier(mu: complex, period: float, *, imag_tol: float = 1e-12) -> MultiplierReading:
    """Read one multiplier as growth and turn per period (its logarithm, on every branch).

    Parameters
    ----------
    mu : complex
        A nonzero Floquet multiplier.
    period : float
        T [s].
    imag_tol : float
        An imaginary part below ``imag_tol * |mu|`` counts as zero (numerical round-off).

    Returns
    -------
    MultiplierReading

    Raises
    ------
    ValueError
        For a zero multiplier (no logarithm).
    """
    mu = complex(mu)
    if mu == 0:
        raise ValueError("a zero multiplier has no logarithm")
    if abs(mu.imag) <= imag_tol * abs(mu):
        mu = complex(mu.real, 0.0)
    kind = "complex" if mu.imag != 0 else ("negative" if mu.real < 0 else "positive")
    exponent = complex(floquet_exponents([mu], period)[0])
    turn = math.atan2(mu.imag, mu.real) / (2.0 * math.pi)
    if kind == "negative":
        turn = 0.5                           # atan2(-0.0, -1) would give -1/2
    return MultiplierReading(multiplier=mu, exponent=exponent, growth_per_period=math.log(abs(mu)),
                             turn_per_period=turn, kind=kind)


def linearisation_error(fun: Callable[..., Any], x0: Any, period: float, direction: Any,
                        sizes: Sequence[float], *, jac: Callable[..., Any] | None = None,
                        args: tuple = (), rtol: float = 1e-12, atol: float = 1e-14
                        ) -> np.ndarray:
    """How far the nonlinear one-period map departs from its linearisation ``Psi(T)``.

    For each size eps, the disturbance ``d = eps v / |v|`` is carried one period by the full
    equations and by the monodromy matrix; returns ``|x(T; x0 + d) - x(T; x0) - Psi(T) d| / eps``,
    which shrinks like eps for a smooth right-hand side (like eps**2 when its second derivatives
    vanish at the orbit, as for ``sin x`` about ``x = 0``).

    Parameters
    ----------
    fun : callable
        ``fun(t, x, *args)``.
    x0 : array_like, shape (n,)
        Start of the (periodic) reference solution.
    period : float
        T [s].
    direction : array_like, shape (n,)
        Direction v of the disturbance (normalised here).
    sizes : sequence of float
        Sizes eps > 0.
    jac : callable, optional
        ``d fun / dx`` for the monodromy matrix.
    args : tuple
        Extra arguments of ``fun`` and ``jac``.
    rtol, atol : float
        Integration tolerances (tight: the differences are small).

    Returns
    -------
    ndarray, shape (len(sizes),)
    """
    x0 = np.asarray(x0, dtype=float)
    v = np.asarray(direction, dtype=float)
    v = v / np.linalg.norm(v)
    var = variational_flow(fun, jac, (0.0, period), x0, args=args, rtol=rtol, atol=atol)
    base, M = var.x[:, -1], var.stm[..., -1]
    errors = []
    for eps in sizes:
        if not eps > 0:
            raise ValueError(f"sizes must be > 0; got {eps!r}")
        moved = flow(fun, (0.0, period), x0 + eps * v, args=args, rtol=rtol, atol=atol).x_end
        errors.append(float(np.linalg.norm(moved - base - M @ (eps * v)) / eps))
    return np.array(errors)

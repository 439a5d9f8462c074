"""What every solve reports: one status enumeration with one message table, its statistics, and
the one type of a monodromy with its Floquet multipliers (:class:`Floquet`).

After scipy's integer ``status`` beside ``message`` and diffrax's ``RESULTS``: the compiled
kernel, the fixed-step solver, the adaptive shooting and the sweeps' rows all report a
:class:`Status` from this one table, so a batch can record a failure row by row and a single
call can raise. ``str(status)`` reads as a word (``"success"``, ``"singular"``), and
``status.message`` says what it means.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["MESSAGES", "Floquet", "Status", "Stats", "status_of"]


class Status(enum.IntEnum):
    """The outcome of a solve (one table for every path; :attr:`message` says it in words)."""

    SUCCESS = 0
    MAX_ITERATIONS = 1
    LEFT_DOMAIN = 2
    NON_FINITE = 3
    SINGULAR = 4
    TOLERANCE_NOT_MET = 5
    MAX_EVALUATIONS = 6
    RESIDUAL_ABOVE_TOL = 7
    INTEGRATION_FAILED = 8
    INVALID_INPUT = 9
    INTERRUPTED = 10
    FAILED = 11

    def __str__(self) -> str:
        return self.name.lower()

    @property
    def message(self) -> str:
        """What the status means, in words."""
        return MESSAGES[self]

    @property
    def success(self) -> bool:
        """True for :attr:`SUCCESS`."""
        return self is Status.SUCCESS


#: The one message table.
MESSAGES: dict[Status, str] = {
    Status.SUCCESS: "converged: the residual and the error estimates within their tolerances",
    Status.MAX_ITERATIONS: "Newton's method reached its iteration cap",
    Status.LEFT_DOMAIN: "an iterate left the unknowns' domain (a stroke amplitude outside "
                        "(0, 90] deg or a mean stroke angle outside (-90, 90) deg)",
    Status.NON_FINITE: "the integration produced a non-finite value",
    Status.SINGULAR: "the Jacobian of the periodicity residual is singular",
    Status.TOLERANCE_NOT_MET: "the error tolerances were not met with the largest step count",
    Status.MAX_EVALUATIONS: "the solve reached its cap on evaluations of the right-hand side "
                            "(`max_nfev`)",
    Status.RESIDUAL_ABOVE_TOL: "Newton's method stopped with a residual norm above `tol`",
    Status.INTEGRATION_FAILED: "an integration failed (step size below its floor or step "
                               "budget exhausted)",
    Status.INVALID_INPUT: "the input was refused (a parameter outside its range)",
    Status.INTERRUPTED: "interrupted (Ctrl-C)",
    Status.FAILED: "the solve did not converge (its message says why)",
}


def status_of(error: BaseException) -> Status:
    """The :class:`Status` of a solve that raised ``error``.

    A :class:`~flapping.errors.ConvergenceError` carries its own (``error.status``); otherwise:
    a :class:`~flapping.errors.DomainError` left the domain, a ValueError is refused input, a
    LinAlgError a singular matrix, an ArithmeticError a non-finite value, KeyboardInterrupt an
    interruption.
    """
    from flapping.errors import DomainError  # errors imports nothing of this module's users

    status = getattr(error, "status", None)
    if isinstance(status, Status):
        return status
    if isinstance(error, DomainError):
        return Status.LEFT_DOMAIN
    if isinstance(error, KeyboardInterrupt):
        return Status.INTERRUPTED
    if isinstance(error, np.linalg.LinAlgError):  # a ValueError: before that test
        return Status.SINGULAR
    if isinstance(error, ValueError):
        return Status.INVALID_INPUT
    if isinstance(error, ArithmeticError):
        return Status.NON_FINITE
    return Status.FAILED


@dataclass(frozen=True)
class Stats:
    """The work a solve did (scipy's counter names).

    Attributes
    ----------
    nit : int
        Newton (or Levenberg-Marquardt) iterations.
    nfev : int
        Evaluations of the right-hand side (or of the residual, on the adaptive path).
    njev : int
        Evaluations of the residual's Jacobian (0 where it is not counted apart).
    time : float
        Wall-clock time of the solve [s].
    """

    nit: int
    nfev: int
    njev: int = 0
    time: float = 0.0


@dataclass(frozen=True, eq=False)
class Floquet:
    """A monodromy matrix and its Floquet multipliers: the one type every path reports them in.

    Attributes
    ----------
    matrix : ndarray, shape (n, n)
        The monodromy (state-transition matrix over one period), read-only.
    multipliers : ndarray, complex, shape (n,)
        Its eigenvalues, sorted by modulus (descending), read-only.
    period : float
        T [s].
    multiplier_error : float
        Estimated largest absolute error of a multiplier (NaN where the path has no estimate).
    trace_integral : float
        int_0^T trace J dt along the orbit (NaN where the path did not integrate it).
    """

    matrix: Any
    multipliers: Any
    period: float
    multiplier_error: float = math.nan
    trace_integral: float = math.nan

    @classmethod
    def of_matrix(cls, matrix: Any, period: float, *, multiplier_error: float = math.nan,
                  trace_integral: float = math.nan, multipliers: Any = None) -> Floquet:
        """The Floquet data of a monodromy matrix (its eigenvalues unless ``multipliers`` are
        given, e.g. from a product-QR iteration that is accurate when they are small)."""
        m = np.array(matrix, dtype=float)
        mu = np.linalg.eigvals(m) if multipliers is None else np.asarray(multipliers)
        mu = mu.astype(complex)[np.argsort(-np.abs(mu), kind="stable")]
        m.flags.writeable = False
        mu.flags.writeable = False
        return cls(m, mu, float(period), float(multiplier_error), float(trace_integral))

    @property
    def exponents(self) -> Any:
        """Floquet exponents log(mu) / T [1/s]
        (:func:`flapping.periodic.floquet.floquet_exponents`: principal branch, -inf for 0)."""
        from flapping.periodic.floquet import floquet_exponents  # that layer imports this one

        return floquet_exponents(self.multipliers, self.period)

    @property
    def max_modulus(self) -> float:
        """Largest modulus of a multiplier."""
        return float(abs(self.multipliers[0]))

    @property
    def is_stable(self) -> bool:
        """True if every multiplier lies inside the unit circle."""
        return self.max_modulus < 1.0

    @property
    def det(self) -> float:
        """det of the monodromy."""
        return float(np.linalg.det(self.matrix))

    @property
    def liouville_error(self) -> float:
        """``abs(det M / exp(int trace J) - 1)`` from the logarithms (NaN without the trace
        integral, or for a multiplier that is 0 or infinite in floating point)."""
        modulus = np.abs(self.multipliers)
        if not (math.isfinite(self.trace_integral) and np.all(np.isfinite(modulus))
                and np.all(modulus > 0.0)):
            return math.nan
        log_ratio = float(np.sum(np.log(modulus))) - self.trace_integral
        return math.inf if log_ratio > 700.0 else abs(math.expm1(log_ratio))

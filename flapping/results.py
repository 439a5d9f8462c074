"""What every solve reports: one status enumeration with one message table, its statistics, and
the one type of a monodromy with its Floquet multipliers (:class:`Floquet`).

After scipy's integer ``status`` beside ``message`` and diffrax's ``RESULTS``: the compiled
kernel, the fixed-step solver, the adaptive shooting and the sweeps' rows all report a
:class:`Status` from this one table, so a batch can record a failure row by row and a single
call can raise. A status is a word (a :class:`enum.StrEnum`): ``str(status)``, its JSON and
its value are ``"success"``, ``"singular"``..., it equals that word and nothing else (not an
integer, not a member of another enumeration), and ``status.message`` says what it means.

What a *returned* orbit is (hover, drifting, climbing) is another question with its own words,
:class:`HoverStatus`; the two tables share no word, so a sweep's one ``status`` column holds
either (:data:`STATUS_WORDS`).
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from flapping.errors import DomainError

__all__ = ["MESSAGES", "STATUS_WORDS", "Floquet", "HoverStatus", "Status", "Stats", "exponents_of",
           "status_of"]


class _Word(enum.StrEnum):
    """A status that is a word: it prints, compares and serialises as its value, so it equals
    its word and no member of another table (the tables share no word)."""

    def __repr__(self) -> str:
        return f"{type(self).__name__}.{self.name}"


class Status(_Word):
    """The outcome of a solve (one table for every path; :attr:`message` says it in words).

    :attr:`code` is the member's integer code, the one the compiled kernel returns (scipy's
    integer ``status``); ``Status(code)`` looks a member up by it.
    """

    SUCCESS = "success"
    MAX_ITERATIONS = "max_iterations"
    LEFT_DOMAIN = "left_domain"
    NON_FINITE = "non_finite"
    SINGULAR = "singular"
    TOLERANCE_NOT_MET = "tolerance_not_met"
    MAX_EVALUATIONS = "max_evaluations"
    RESIDUAL_ABOVE_TOL = "residual_above_tol"
    INTEGRATION_FAILED = "integration_failed"
    INVALID_INPUT = "invalid_input"
    INTERRUPTED = "interrupted"
    FAILED = "failed"

    @classmethod
    def _missing_(cls, value: object) -> Status | None:
        # The compiled kernel returns an integer code (numba has no enumerations of words).
        if isinstance(value, int | np.integer) and not isinstance(value, bool):
            members = list(cls)
            if 0 <= int(value) < len(members):
                return members[int(value)]
        return None

    @property
    def code(self) -> int:
        """The integer code (the order of the table: ``SUCCESS`` is 0)."""
        return list(type(self)).index(self)

    @property
    def message(self) -> str:
        """What the status means, in words."""
        return MESSAGES[self]

    @property
    def success(self) -> bool:
        """True for :attr:`SUCCESS`."""
        return self is Status.SUCCESS


class HoverStatus(_Word):
    """What a solved orbit is (a failed solve raises :class:`~flapping.errors.ConvergenceError`).

    ``HOVER``: periodic and in place on average. ``DRIFTING``: periodic, holds its altitude, but
    flies horizontally (a hinge off the centre of gravity with the amplitude as the only trim).
    ``CLIMBING``: periodic but climbs or sinks (an orbit forced away from the hover amplitude).
    """

    HOVER = "hover"
    DRIFTING = "drifting"
    CLIMBING = "climbing"


#: Every status word: what a sweep row's one ``status`` column can hold (the orbit's
#: :class:`HoverStatus` where a point solved, the solve's :class:`Status` where it failed).
STATUS_WORDS: frozenset[str] = frozenset(map(str, [*HoverStatus, *Status]))
assert len(STATUS_WORDS) == len(HoverStatus) + len(Status), "the two tables share a word"


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


def exponents_of(multipliers: np.ndarray, period: float) -> np.ndarray:
    """Floquet exponents ``log(mu) / T`` of checked multipliers (complex, no NaN) and period
    (> 0): principal branch; a zero multiplier gives ``-inf`` (real part; imaginary part its
    argument over T), an infinite one ``+inf``."""
    mu = np.asarray(multipliers, dtype=complex)
    with np.errstate(divide="ignore", invalid="ignore"):
        exponents = np.asarray(np.log(mu) / period)
        bad = ~np.isfinite(exponents)
        if np.any(bad):  # log(0) = -inf and log(inf) = inf: real and imaginary parts apart
            exponents[bad] = np.log(np.abs(mu[bad])) / period + 1j * (np.angle(mu[bad]) / period)
    return exponents


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
        """Floquet exponents log(mu) / T [1/s] (principal branch, -inf for 0; as
        :func:`flapping.periodic.floquet.floquet_exponents`, which checks its input and
        calls :func:`exponents_of`)."""
        return exponents_of(self.multipliers, self.period)

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

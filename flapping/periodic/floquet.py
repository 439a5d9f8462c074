"""Floquet analysis of a periodic orbit: monodromy matrix, multipliers, exponents (eqs. 42-49, 67).

The monodromy matrix ``M = Phi(T, 0)`` is the state-transition matrix over one period, integrated
from the variational equations ``Phi' = J(t, x(t)) Phi`` along the orbit. Its eigenvalues are the
Floquet multipliers ``mu`` (eq. 67); the exponents are ``log(mu) / T``. An orbit is asymptotically
stable when every multiplier (but the trivial one, ``mu = 1``, of an autonomous orbit) lies inside
the unit circle.

Accuracy. ``M`` of a dissipative orbit is nearly singular: on the Lorenz orbit AB its smallest
multiplier is ~1e-10 against ~5 for the largest. ``eig(M)`` then returns the small multipliers
with an absolute error of about ``tol * |M|``, i.e. with few or no correct digits, and ``det(M)``
is just as wrong. We therefore integrate ``M`` as a product of ``n_sub`` well-conditioned factors
``M = Phi_K ... Phi_1`` (the period split into equal sub-intervals, breakpoints respected) and
compute

* ``det M = prod det Phi_i`` (each factor's determinant is accurate to its relative tolerance), and
* the multipliers by the periodic QR (orthogonal) iteration on the factors, which converges to
  the periodic Schur form when the multipliers have distinct moduli and then gives even tiny
  multipliers to nearly full relative accuracy (as in the QR method for Lyapunov exponents);
  with complex pairs or equal moduli we fall back to ``eig(M)``.

Liouville's formula ``det M = exp(int_0^T trace J dt)`` checks both, with the trace integrated as
an extra quadrature state along the orbit.

Overflow. A strongly unstable orbit can have multipliers beyond the float range (``x' = 50 x``
over ``T = 20``: ``exp(1000)``). The factors stay finite; their product, ``det M``, Liouville's
``exp(trace_integral)`` and the large multipliers are then reported as ``inf`` with a
``RuntimeWarning`` (no ``OverflowError``), while ``trace_integral`` and the exponents, computed
from the logarithms of the periodic QR, stay finite. A zero multiplier has the exponent
``-inf``.

Conventions as in :mod:`flapping.periodic.integrate` (time along the last axis: the factors are
``(n, n, K)``; ``nfev``/``njev``; ``rtol``/``atol``/``max_steps``; arguments checked once).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.integrate import OdeSolver

import flapping._validation as check
from flapping.errors import ClosureWarning, ConvergenceError
from flapping.periodic import _segments as seg
from flapping.periodic import settings as opt
from flapping.periodic._checks import first_call
from flapping.periodic._readonly import freeze
from flapping.results import Floquet, exponents_of

__all__ = [
    "DEFAULTS",
    "FloquetAccuracyWarning",
    "Monodromy",
    "monodromy",
    "floquet_multipliers",
    "floquet_exponents",
    "trivial_multiplier",
    "nontrivial_multipliers",
    "CLOSURE_TOL",
    "TRIVIAL_TOL",
]

_EPS = np.finfo(float).eps

#: Relative closure error ``|x(T) - x(0)| / max(1, |x(0)|)`` above which :func:`monodromy`
#: warns that its point is on no periodic orbit. A shooting solution closes to its ``tol``
#: (1e-10) plus the integration error (~1e-10 relative); 1e-6 leaves four orders for
#: orbits found at looser tolerances or by RK4, while a point off the orbit by a
#: millionth of its size already has multipliers wrong in the sixth digit.
CLOSURE_TOL = 1e-6


class FloquetAccuracyWarning(UserWarning):
    """A multiplier is below machine epsilon times the largest: it carries no correct digits."""


@dataclass(frozen=True)
class Monodromy:
    """Monodromy matrix of a periodic orbit and what follows from it.

    Attributes
    ----------
    matrix : ndarray, shape (n, n)
        ``M = Phi(T, 0)`` (product of the sub-interval factors).
    multipliers : ndarray, shape (n,), complex
        Floquet multipliers (eq. 67), sorted by modulus, descending.
    exponents : ndarray, shape (n,), complex
        ``log(mu) / T`` (principal branch).
    det : float
        ``det M`` as the product of the factors' determinants.
    trace_integral : float
        ``int_0^T trace J dt``, integrated along the orbit.
    liouville_det : float
        ``exp(trace_integral)``, Liouville's prediction of ``det M`` (``inf`` on overflow).
    liouville_error : float
        ``|det - liouville_det| / |liouville_det|`` (from the logarithms when either value
        overflows or underflows).
    x_end : ndarray, shape (n,)
        State after one period (closure check: equals ``x0`` on a periodic orbit).
    closure_error : float
        ``|x_end - x0|`` (Euclidean).
    relative_closure_error : float
        ``|x_end - x0| / max(1, |x0|)``: above :data:`CLOSURE_TOL` the point is on no periodic
        orbit of this period and a :class:`~flapping.errors.ClosureWarning` was issued.
    period : float
        The period used.
    factors : ndarray, shape (n, n, K)
        Sub-interval state-transition matrices in time order (time along the last axis),
        ``M = factors[..., -1] @ ... @ factors[..., 0]``.
    multiplier_method : str
        ``"periodic-qr"`` or ``"eig"`` (fallback: complex pair or equal moduli).
    nfev : int
        Right-hand-side evaluations (including finite-difference Jacobians).
    njev : int
        Analytic Jacobian evaluations.
    """

    matrix: np.ndarray
    multipliers: np.ndarray
    exponents: np.ndarray
    det: float
    trace_integral: float
    liouville_det: float
    liouville_error: float
    x_end: np.ndarray
    closure_error: float
    period: float
    factors: np.ndarray
    multiplier_method: str
    nfev: int
    njev: int
    relative_closure_error: float = math.nan

    def __post_init__(self) -> None:
        freeze(self)

    @property
    def floquet(self) -> Floquet:
        """The monodromy and its multipliers as the package's one type
        (:class:`flapping.results.Floquet`), with the trace integral."""
        return Floquet.of_matrix(self.matrix, self.period, multipliers=self.multipliers,
                                 trace_integral=self.trace_integral)


def _sort_by_modulus(mu: np.ndarray) -> np.ndarray:
    # Ties in modulus (complex pairs) are ordered by argument so that the order is reproducible.
    order = np.lexsort((-np.angle(mu), -np.abs(mu)))
    return mu[order]


def _warn_if_inaccurate(mu: np.ndarray, stacklevel: int = 3) -> None:
    mods = np.abs(mu)
    if mods.size and np.any(mods < _EPS * mods.max()):
        warnings.warn(
            f"{int(np.sum(mods < _EPS * mods.max()))} Floquet multiplier(s) below machine epsilon "
            f"times the largest ({mods.max():.3e}): eig(M) gives them no correct digits",
            FloquetAccuracyWarning,
            stacklevel=stacklevel,
        )


def floquet_multipliers(matrix: Any) -> np.ndarray:
    """Eigenvalues of a monodromy matrix, sorted by modulus (descending), eq. (67).

    Parameters
    ----------
    matrix : array_like, shape (n, n)
        Monodromy matrix.

    Returns
    -------
    ndarray, complex
        The multipliers.

    Raises
    ------
    ValueError
        If ``matrix`` is not a finite square matrix.

    Warns
    -----
    FloquetAccuracyWarning
        When a multiplier's modulus is below machine epsilon times the largest.
    """
    M = check.matrix("matrix", matrix, square=True)
    if np.iscomplexobj(M):
        raise ValueError("`matrix` must be a real square matrix (a monodromy matrix)")
    if M.size == 0:
        raise ValueError("`matrix` must be a finite square matrix; got shape (0, 0)")
    mu = _sort_by_modulus(np.linalg.eigvals(M).astype(complex))
    _warn_if_inaccurate(mu)
    return mu


def floquet_exponents(multipliers: Any, period: float) -> np.ndarray:
    """Floquet exponents ``log(mu) / T`` (principal branch of the complex logarithm).

    Parameters
    ----------
    multipliers : array_like
        Floquet multipliers.
    period : float
        Period ``T`` > 0.

    Returns
    -------
    ndarray, complex
        Exponents; the real parts are the orbit's Lyapunov exponents. A zero multiplier gives
        ``-inf`` (real part; imaginary part its argument over T), an infinite one ``+inf``.

    Raises
    ------
    ValueError
        For a non-positive period, or multipliers that are not numbers or are NaN.
    """
    T = check.positive("period", period)
    return exponents_of(_multipliers_array(multipliers), T)


def _multipliers_array(value: Any) -> np.ndarray:
    """Multipliers as a complex array (any shape); NaN and non-numbers refused, naming
    ``multipliers`` (an infinite multiplier is a legitimate overflow of ``|mu|``)."""
    if type(value) is np.ndarray and value.dtype == complex:  # the continuation's, every point
        if np.isnan(value).any():
            raise ValueError(f"`multipliers` must not be NaN; got {value!r}")
        return value
    try:
        mu = np.asarray(value)
    except ValueError:
        raise ValueError(f"`multipliers` must be an array of numbers; got {value!r}") from None
    if mu.dtype.kind not in "iufc":
        raise ValueError(f"`multipliers` must be an array of numbers; got {value!r} "
                         f"(dtype {mu.dtype})")
    mu = mu.astype(complex)
    if np.isnan(mu).any():
        raise ValueError(f"`multipliers` must not be NaN; got {value!r}")
    return mu


def trivial_multiplier(multipliers: Any) -> int:
    """Index of the multiplier closest to 1 (the trivial one of an autonomous orbit).

    Parameters
    ----------
    multipliers : array_like or Monodromy
        Multipliers, or a :class:`Monodromy`.

    Returns
    -------
    int
        Index into ``multipliers``.

    Raises
    ------
    ValueError
        For empty multipliers, NaN, or values that are not numbers.
    """
    mu = (multipliers.multipliers if isinstance(multipliers, Monodromy)
          else _multipliers_array(multipliers))
    return _trivial_index(mu)


def _trivial_index(mu: np.ndarray) -> int:
    """:func:`trivial_multiplier` of a checked complex array."""
    if mu.size == 0:
        raise ValueError("`multipliers` must not be empty")
    return int(np.argmin(np.abs(mu - 1.0)))


#: Largest ``|mu - 1|`` of the multiplier :func:`nontrivial_multipliers` drops as the trivial one.
#: The trivial multiplier of an autonomous orbit is 1 up to the monodromy's error: the closure
#: (below :data:`CLOSURE_TOL`, 1e-6, on an orbit) times the eigenvalue's condition; the book's
#: orbits give 1 within ~1e-8. 1e-3 leaves that three orders or more, while a set with no
#: multiplier near 1 (``[5.0]``: a forced orbit's, or a point on no orbit) has no trivial one
#: to drop.
TRIVIAL_TOL = 1e-3


def nontrivial_multipliers(multipliers: Any, *, tol: float = TRIVIAL_TOL) -> np.ndarray:
    """The multipliers without the trivial one (closest to 1), in the same order.

    The trivial multiplier is the 1 of an autonomous orbit (the flow's direction, eq. 47's
    neutral perturbation along the orbit); it is dropped only if it is there, within ``tol``.

    Parameters
    ----------
    multipliers : array_like or Monodromy
        Multipliers, or a :class:`Monodromy`.
    tol : float
        Largest ``|mu - 1|`` of a trivial multiplier, in (0, 1] (default :data:`TRIVIAL_TOL`).

    Returns
    -------
    ndarray, complex
        The ``n - 1`` others.

    Raises
    ------
    ValueError
        For empty multipliers, NaN, or values that are not numbers; or if no multiplier lies
        within ``tol`` of 1 (a forced orbit has no trivial multiplier: use all of them).
    """
    tol = check.real("tol", tol, low=0.0, high=1.0, low_open=True)
    mu = (multipliers.multipliers if isinstance(multipliers, Monodromy)
          else _multipliers_array(multipliers))
    i = _trivial_index(mu)
    distance = float(abs(mu.flat[i] - 1.0))
    if not distance <= tol:
        raise ValueError(
            f"`multipliers` have no trivial multiplier: the closest to 1, {complex(mu.flat[i])}, "
            f"is {distance:.3g} from it (a trivial one lies within `tol` = {tol:g}). An "
            "autonomous orbit has one; a forced orbit's multipliers, or a point on no orbit's, "
            "have none to drop")
    return np.delete(mu, i)


def _periodic_qr(factors: Sequence[np.ndarray], M: np.ndarray,
                 max_sweeps: int = 200) -> tuple[np.ndarray, np.ndarray] | None:
    """Multipliers from the periodic QR (orthogonal) iteration on ``M = F_K ... F_1``.

    Returns the real multipliers sorted by modulus and the logarithms of their moduli (finite
    even when the multipliers overflow), or None when the iteration does not reach the
    periodic Schur form (complex pair, equal moduli). Started from an orthonormal basis of
    the eigenvectors of ``M`` (sorted by modulus) so that it usually converges in a sweep or
    two: the dominant directions of ``M`` are accurate even when its small eigenvalues are not;
    from the identity when ``M`` overflowed.
    """
    n = M.shape[0]
    if np.all(np.isfinite(M)):
        lam, vec = np.linalg.eig(M)
        if np.any(np.abs(lam.imag) > 0):
            return None
        Q, _ = np.linalg.qr(vec[:, np.argsort(-np.abs(lam))].real)
    else:
        Q = np.eye(n)
    for _ in range(max_sweeps):
        Q_start = Q
        log_diag = np.zeros(n)
        for F in factors:
            Q, R = np.linalg.qr(F @ Q)
            d = np.diag(R).copy()
            if np.any(d == 0.0):
                return None
            Q = Q * np.sign(d)  # make diag(R) positive: the QR factors are then unique
            log_diag += np.log(np.abs(d))
        C = Q_start.T @ Q  # M Q_start = Q R  =>  Q_start^T M Q_start = C R
        if np.max(np.abs(np.tril(C, -1))) < 64 * _EPS * n:
            with np.errstate(over="ignore"):
                mu = np.sign(np.diag(C)) * np.exp(log_diag)
            key = np.abs(mu) if np.all(np.isfinite(mu)) else log_diag
            order = np.argsort(-key, kind="stable")
            return mu[order], log_diag[order]
    return None


def _check_monodromy(x0: Any, period: Any, method: Any, rtol: Any, atol: Any, rk4_steps: Any,
                     max_steps: Any, breakpoints: Any, n_sub: Any, max_cond: Any
                     ) -> tuple[np.ndarray, float, seg.Settings, tuple[float, ...], int, float,
                                float | None]:
    """Arguments of :func:`monodromy`, checked: ``(x0, T, settings, breakpoints, n_sub,
    max_cond, h)``."""
    x = check.vector("x0", x0)
    T = check.positive("period", period)
    settings = seg.check_settings(method, rtol, atol, rk4_steps, max_steps)
    opt.check_scaled("atol", settings.atol, x, opt.TOL_CEILING)
    b = seg.check_breakpoints(breakpoints)
    n_sub = opt.capped("n_sub", n_sub)
    if not (isinstance(max_cond, (float, np.floating)) and max_cond == math.inf):
        max_cond = check.real("max_cond", max_cond, low=1.0, low_open=True)
    if settings.fixed_step and settings.rk4_steps % n_sub:
        raise ValueError(f"with method='RK4', `rk4_steps` ({settings.rk4_steps}) must be a "
                         f"multiple of `n_sub` ({n_sub})")
    h = seg.fixed_step(settings, 0.0, T, T, b)
    return x, T, settings, b, n_sub, float(max_cond), h


@dataclass
class _Factors:
    """The sub-interval factors of M in time order, with the trace integral and the counts."""

    matrices: list[np.ndarray]
    trace_integral: float
    x_end: np.ndarray
    nfev: int
    njev: int


def _factorise(funs: Sequence[Callable[..., Any]], jacs: Sequence[Callable[..., Any] | None],
               x: np.ndarray, T: float, *, args: tuple[Any, ...], settings: seg.Settings,
               h: float | None, breakpoints: tuple[float, ...], n_sub: int,
               max_cond: float) -> _Factors:
    """Sub-intervals integrated in time order from ``Phi = I``; one whose factor is
    ill-conditioned (cond > max_cond) is bisected and redone, so that every factor keeps nearly
    all its digits."""
    pending = [(T * k / n_sub, T * (k + 1) / n_sub) for k in range(n_sub)]
    out = _Factors([], 0.0, x, 0, 0)
    h_rk4 = T / settings.rk4_steps
    pjacs = (None,) * len(funs)
    while pending:
        a, b = pending.pop(0)
        var = seg.variational(funs, jacs, pjacs, float(a), float(b), out.x_end, args=args,
                              params=None, trace=True, settings=settings, h=h, period=T,
                              breakpoints=breakpoints, t_out=(float(b),))
        out.nfev += var.nfev
        out.njev += var.njev
        if not var.success:
            where = var.failure
            raise ConvergenceError(
                f"the orbit could not be integrated over [{a:.6g}, {b:.6g}]: {var.message}",
                x=out.x_end, iterations=out.nfev + var.nfev, result=var,
                t=None if where is None else where.t,
                state=None if where is None else where.state,
                source=None if where is None else where.source)
        F = var.stm_end
        steps = round((b - a) / h_rk4)
        splittable = (b - a) > T * 2.0**-12 and (not settings.fixed_step or steps % 2 == 0)
        if splittable and np.linalg.cond(F) > max_cond:
            m = a + 0.5 * (b - a)
            pending[:0] = [(a, m), (m, b)]
            continue
        out.matrices.append(F)
        assert var.trace_integral is not None
        out.trace_integral += float(var.trace_integral[-1])
        out.x_end = var.x_end
    return out


def _exp_or_inf(value: float) -> float:
    """``exp(value)``, ``inf`` instead of OverflowError."""
    try:
        return math.exp(value)
    except OverflowError:
        return math.inf


def _determinants(factors: Sequence[np.ndarray], trace_integral: float
                  ) -> tuple[float, float, float]:
    """``det M`` (product of the factors'), Liouville's ``exp(trace)``, and their relative
    difference (from the logarithms when either is not a normal float)."""
    signs_logs = [np.linalg.slogdet(F) for F in factors]
    sign = float(np.prod([s for s, _ in signs_logs]))
    log_det = float(sum(l for _, l in signs_logs))
    det = sign * _exp_or_inf(log_det)
    liouville = _exp_or_inf(trace_integral)
    if math.isfinite(det) and math.isfinite(liouville) and liouville:
        error = abs(det - liouville) / abs(liouville)
    else:
        error = abs(math.expm1(min(log_det - trace_integral, 700.0))) if sign > 0 else math.inf
    if not (math.isfinite(det) and math.isfinite(liouville)):
        warnings.warn(
            f"monodromy: det M = exp({log_det:.6g}) and/or Liouville's exp({trace_integral:.6g}) "
            "overflow float64: reported as inf (trace_integral and the exponents keep the "
            "logarithms)", RuntimeWarning, stacklevel=3)
    return det, liouville, error


def _multipliers(factors: Sequence[np.ndarray], M: np.ndarray, T: float
                 ) -> tuple[np.ndarray, np.ndarray, str]:
    """Multipliers, exponents and how the multipliers were computed."""
    qr = _periodic_qr(factors, M)
    if qr is not None:
        mu, log_abs = qr[0].astype(complex), qr[1]
        exponents = floquet_exponents(mu, T)
        big = ~np.isfinite(mu)
        exponents[big] = log_abs[big] / T + 1j * (np.angle(mu[big]) / T)
        return mu, exponents, "periodic-qr"
    if not np.all(np.isfinite(M)):
        raise ConvergenceError(
            "the monodromy matrix overflows float64 and the periodic QR iteration on its "
            "factors did not converge (complex pair or equal moduli): integrate over a "
            "shorter span or rescale the problem")
    mu = _sort_by_modulus(np.linalg.eigvals(M).astype(complex))
    _warn_if_inaccurate(mu, stacklevel=4)
    return mu, floquet_exponents(mu, T), "eig"


def monodromy(
    fun: Callable[..., Any] | Sequence[Callable[..., Any]],
    x0: Any,
    period: float,
    *,
    jac: Callable[..., Any] | Sequence[Callable[..., Any]] | None = None,
    breakpoints: Sequence[float] = (),
    method: str | type[OdeSolver] | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    rk4_steps: int | None = None,
    max_steps: int | None = None,
    n_sub: int = 4,
    max_cond: float = 100.0,
    args: tuple[Any, ...] = (),
    settings: opt.SolverSettings | None = None,
) -> Monodromy:
    """Monodromy matrix, Floquet multipliers and Liouville check of a periodic orbit (eqs. 42-49).

    Parameters
    ----------
    fun : callable or sequence of callables
        Right-hand side ``fun(t, x, *args)`` (one per segment with breakpoints, see
        :mod:`flapping.periodic.integrate`). Parameters found by shooting go at the end of ``args``.
    x0 : array_like, shape (n,)
        A point of the orbit at ``t = 0``.
    period : float
        Period ``T``.
    jac : callable or sequence of callables, optional
        Analytic ``df/dx(t, x, *args)``; default central finite differences of ``fun`` at every
        evaluation (relative error ~ eps**(2/3) in the variational equations).
    breakpoints, method, rtol, atol, rk4_steps, max_steps
        As in :func:`flapping.periodic.integrate.flow` (``max_steps``: per sub-interval);
        defaults ``"DOP853"``, 1e-12, 1e-12, 1024, 100 000.
    n_sub : int, optional
        Initial number of equal sub-intervals of the period, each integrated from ``Phi = I``
        (see the module notes); with RK4, ``rk4_steps`` must be a multiple of it.
    max_cond : float, optional
        A sub-interval whose state-transition matrix has a condition number above this is
        bisected (down to ``2**-12`` of the period): each factor then loses at most
        ``log10(max_cond)`` digits to the integration error, and so do ``det M`` and the small
        multipliers. ``math.inf`` keeps the ``n_sub`` equal pieces.
    args : tuple, optional
        Extra arguments of ``fun`` and ``jac``.
    settings : SolverSettings, optional
        ``method``, ``rtol``, ``atol``, ``rk4_steps`` and ``max_steps`` as one object
        (:mod:`flapping.periodic.settings`); a keyword given explicitly overrides its field.

    Returns
    -------
    Monodromy
        Matrix, multipliers, exponents, determinant and Liouville check, closure, evaluation counts.

    Raises
    ------
    ValueError
        For a bad argument (``rtol`` in (0, 1e-3], ``atol`` at most ``1e-2 max(1, |x0|)``),
        ``fun``/``jac`` returning a wrong shape, or raising a ValueError or IndexError at the
        first call (naming ``x0`` and ``args``).
    NonFiniteError
        A ValueError: ``fun`` or ``jac`` returned NaN or infinity at a finite state (with
        ``t``, ``state``, ``source``, ``value``).
    TypeError
        ``args`` does not fit the signature of ``fun`` or ``jac``, or either returned None, a
        string, or complex or boolean values (checked at the first call).
    ConvergenceError
        If the orbit could not be integrated (the integrator gave up, the step budget ran out:
        the message suggests what to try, or the state overflowed); carries the state at the
        start of the failing sub-interval (``x``), the failed integration (``result``), and
        where it stopped: ``t``, ``state`` and ``source``.

    Warns
    -----
    ClosureWarning
        When ``|x(T) - x0| / max(1, |x0|)`` exceeds :data:`CLOSURE_TOL` (1e-6): ``x0`` is on no
        orbit of period ``T``, and the matrix is a transition matrix, not a monodromy matrix.
    FloquetAccuracyWarning
        When the multipliers come from ``eig(M)`` and one is below eps times the largest.
    RuntimeWarning
        When ``det M`` or Liouville's ``exp(trace_integral)`` overflows (reported as inf).
    """
    o = opt.resolve(settings, DEFAULTS, method=method, rtol=rtol, atol=atol,
                    rk4_steps=rk4_steps, max_steps=max_steps)
    x, T, integration, breakpoints, n_sub, max_cond, h = _check_monodromy(
        x0, period, o["method"], o["rtol"], o["atol"], o["rk4_steps"], o["max_steps"],
        breakpoints, n_sub, max_cond)
    n_seg = len(breakpoints) + 1
    funs = seg.segment_callables(fun, n_seg, "fun")
    jacs = (None,) * n_seg if jac is None else seg.segment_callables(jac, n_seg, "jac")
    args = check.call_args(args)
    given = f"`args` = {check._show(args)}"
    # the first callables once each at (0, x0), checked (not counted: a check, not a step)
    first_call(funs[0], "fun", 0.0, x, args, (x.size,), call="fun(t, x, *args)", given=given)
    if jacs[0] is not None:
        first_call(jacs[0], "jac", 0.0, x, args, (x.size, x.size), call="jac(t, x, *args)",
                   given=given)
    parts = _factorise(funs, jacs, x, T, args=args, settings=integration, h=h,
                       breakpoints=breakpoints, n_sub=n_sub, max_cond=max_cond)
    M = np.eye(x.size)
    with np.errstate(over="ignore", invalid="ignore"):
        for F in parts.matrices:
            M = F @ M
    det, liouville, error = _determinants(parts.matrices, parts.trace_integral)
    mu, exponents, how = _multipliers(parts.matrices, M, T)
    closure = float(np.linalg.norm(parts.x_end - x))
    relative = _warn_if_open(closure, x, T)
    return Monodromy(
        matrix=M, multipliers=mu, exponents=exponents, det=det,
        trace_integral=parts.trace_integral, liouville_det=liouville, liouville_error=error,
        x_end=parts.x_end, closure_error=closure, period=T,
        factors=np.stack(parts.matrices, axis=-1), multiplier_method=how, nfev=parts.nfev,
        njev=parts.njev, relative_closure_error=relative,
    )


#: What a call uses for each :class:`~flapping.periodic.settings.SolverSettings` field it
#: reads when neither the keyword nor ``settings`` gives it (the signature shows None).
DEFAULTS: dict[str, Any] = {"method": "DOP853", "rtol": opt.MONODROMY_RTOL,
                             "atol": opt.MONODROMY_ATOL, "rk4_steps": 1024,
                             "max_steps": None}


def _warn_if_open(closure: float, x: np.ndarray, T: float) -> float:
    """The relative closure error; a ClosureWarning above :data:`CLOSURE_TOL`."""
    relative = closure / max(1.0, float(np.linalg.norm(x)))
    if relative > CLOSURE_TOL:
        warnings.warn(
            f"monodromy: x0 is on no periodic orbit of period T = {T:.10g}: |x(T) - x0| = "
            f"{closure:.3e} ({relative:.1e} relative > CLOSURE_TOL = {CLOSURE_TOL:g}); the "
            f"multipliers are those of a transition matrix, not of an orbit (find the orbit "
            f"first with find_periodic_orbit)", ClosureWarning, stacklevel=3)
    return relative

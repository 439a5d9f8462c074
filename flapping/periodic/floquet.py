"""Floquet analysis of a periodic orbit: monodromy matrix, multipliers, exponents (eqs. 42-49, 67).

The monodromy matrix ``M = Phi(T, 0)`` is the state-transition matrix over one period, integrated
from the variational equations ``Phi' = J(t, x(t)) Phi`` along the orbit. Its eigenvalues are the
Floquet multipliers ``mu`` (eq. 67); the exponents are ``log(mu) / T``. An orbit is asymptotically
stable when every multiplier (but the trivial one, ``mu = 1``, of an autonomous orbit) lies inside
the unit circle.

Accuracy. ``M`` of a dissipative orbit is nearly singular: on the Lorenz orbit AB its smallest
multiplier is ~1e-10 against ~5 for the largest. ``eig(M)`` then returns the small multipliers
with an absolute error ~``tol * |M|``, i.e. with few or no correct digits, and ``det(M)`` is just
as wrong. We therefore integrate ``M`` as a product of ``n_sub`` well-conditioned factors
``M = Phi_K ... Phi_1`` (the period split into equal sub-intervals, breakpoints respected) and
compute

* ``det M = prod det Phi_i`` (each factor's determinant is accurate to its relative tolerance), and
* the multipliers by the periodic QR (orthogonal) iteration on the factors, which converges to
  the periodic Schur form when the multipliers have distinct moduli and then gives even tiny
  multipliers to nearly full relative accuracy (as in the QR method for Lyapunov exponents);
  with complex pairs or equal moduli we fall back to ``eig(M)``.

Liouville's formula ``det M = exp(int_0^T trace J dt)`` checks both, with the trace integrated as
an extra quadrature state along the orbit.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from flapping.errors import ConvergenceError
from flapping.periodic.integrate import (
    _check_breakpoints,
    _check_method,
    _check_period,
    _check_rk4_steps,
    _check_state,
    _check_tolerances,
    variational_flow,
)

__all__ = [
    "FloquetAccuracyWarning",
    "Monodromy",
    "monodromy",
    "floquet_multipliers",
    "floquet_exponents",
    "trivial_multiplier",
    "nontrivial_multipliers",
]

_EPS = np.finfo(float).eps


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
        ``exp(trace_integral)``, Liouville's prediction of ``det M``.
    liouville_error : float
        ``|det - liouville_det| / |liouville_det|``.
    x_end : ndarray, shape (n,)
        State after one period (closure check: equals ``x0`` on a periodic orbit).
    closure_error : float
        ``|x_end - x0|`` (Euclidean).
    period : float
        The period used.
    factors : ndarray, shape (K, n, n)
        Sub-interval state-transition matrices, ``M = factors[-1] @ ... @ factors[0]``.
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


def floquet_multipliers(matrix) -> np.ndarray:
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
    M = np.asarray(matrix, dtype=float)
    if M.ndim != 2 or M.shape[0] != M.shape[1] or M.size == 0 or not np.all(np.isfinite(M)):
        raise ValueError(f"`matrix` must be a finite square matrix, got shape {M.shape}")
    mu = _sort_by_modulus(np.linalg.eigvals(M).astype(complex))
    _warn_if_inaccurate(mu)
    return mu


def floquet_exponents(multipliers, period: float) -> np.ndarray:
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
        Exponents; the real parts are the orbit's Lyapunov exponents.

    Raises
    ------
    ValueError
        For a non-positive period.
    """
    T = _check_period(period)
    mu = np.asarray(multipliers, dtype=complex)
    with np.errstate(divide="ignore"):
        return np.log(mu) / T


def trivial_multiplier(multipliers) -> int:
    """Index of the multiplier closest to 1 (the trivial one of an autonomous orbit).

    Parameters
    ----------
    multipliers : array_like or Monodromy
        Multipliers, or a :class:`Monodromy`.

    Returns
    -------
    int
        Index into ``multipliers``.
    """
    mu = multipliers.multipliers if isinstance(multipliers, Monodromy) else np.asarray(multipliers)
    return int(np.argmin(np.abs(np.asarray(mu, dtype=complex) - 1.0)))


def nontrivial_multipliers(multipliers) -> np.ndarray:
    """The multipliers without the trivial one (closest to 1), in the same order."""
    mu = multipliers.multipliers if isinstance(multipliers, Monodromy) else np.asarray(multipliers)
    return np.delete(np.asarray(mu, dtype=complex), trivial_multiplier(mu))


def _periodic_qr(factors: np.ndarray, M: np.ndarray, max_sweeps: int = 200):
    """Multipliers from the periodic QR (orthogonal) iteration on ``M = F_K ... F_1``.

    Returns the real multipliers sorted by modulus, or None when the iteration does not reach
    the periodic Schur form (complex pair, equal moduli). Started from an orthonormal basis of
    the eigenvectors of ``M`` (sorted by modulus) so that it usually converges in a sweep or two:
    the dominant directions of ``M`` are accurate even when its small eigenvalues are not.
    """
    n = M.shape[0]
    lam, vec = np.linalg.eig(M)
    if np.any(np.abs(lam.imag) > 0):
        return None
    order = np.argsort(-np.abs(lam))
    Q, _ = np.linalg.qr(vec[:, order].real)
    for _ in range(max_sweeps):
        Q_start = Q
        log_diag = np.zeros(n)
        for F in factors:
            Q, R = np.linalg.qr(F @ Q)
            d = np.diag(R).copy()
            if np.any(d == 0.0):
                return None
            s = np.sign(d)
            Q = Q * s  # make diag(R) positive: the QR factors are then unique
            log_diag += np.log(np.abs(d))
        C = Q_start.T @ Q  # M Q_start = Q R  =>  Q_start^T M Q_start = C R
        if np.max(np.abs(np.tril(C, -1))) < 64 * _EPS * n:
            signs = np.sign(np.diag(C))
            mu = signs * np.exp(log_diag)
            return mu[np.argsort(-np.abs(mu), kind="stable")]
    return None


def monodromy(
    fun: Callable | Sequence[Callable],
    x0,
    period: float,
    *,
    jac: Callable | Sequence[Callable] | None = None,
    breakpoints: Sequence[float] = (),
    method: str = "DOP853",
    rtol: float = 1e-12,
    atol: float = 1e-12,
    rk4_steps: int = 1024,
    n_sub: int = 4,
    max_cond: float = 100.0,
    args: tuple = (),
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
    breakpoints, method, rtol, atol, rk4_steps
        As in :func:`flapping.periodic.integrate.flow`.
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

    Returns
    -------
    Monodromy
        Matrix, multipliers, exponents, determinant and Liouville check, closure, evaluation counts.

    Raises
    ------
    ValueError
        For a bad argument.

    Warns
    -----
    FloquetAccuracyWarning
        When the multipliers come from ``eig(M)`` and one is below eps times the largest.
    """
    x = _check_state(x0)
    T = _check_period(period)
    method = _check_method(method)
    _check_tolerances(rtol, atol)
    rk4_steps = _check_rk4_steps(rk4_steps)
    breakpoints = _check_breakpoints(breakpoints)
    if isinstance(n_sub, bool) or int(n_sub) != n_sub or n_sub < 1:
        raise ValueError(f"`n_sub` must be a positive integer, got {n_sub!r}")
    n_sub = int(n_sub)
    if not (max_cond > 1.0):
        raise ValueError(f"`max_cond` must be > 1, got {max_cond!r}")
    if method == "RK4" and rk4_steps % n_sub:
        raise ValueError(f"with method='RK4', `rk4_steps` ({rk4_steps}) must be a multiple of `n_sub` ({n_sub})")
    # Sub-intervals, integrated in time order from Phi = I; one whose factor is ill-conditioned
    # (cond > max_cond) is bisected and redone, so that every factor keeps nearly all its digits.
    h_rk4 = T / rk4_steps
    pending = [(T * k / n_sub, T * (k + 1) / n_sub) for k in range(n_sub)]
    factors, trace_total, nfev, njev = [], 0.0, 0, 0
    xi = x
    while pending:
        a, b = pending.pop(0)
        var = variational_flow(fun, jac, (float(a), float(b)), xi, breakpoints=breakpoints,
                               period=T, method=method, rtol=rtol, atol=atol,
                               rk4_steps=rk4_steps, trace=True, args=args)
        nfev += var.nfev
        njev += var.njev
        if not var.success:
            raise ConvergenceError(
                f"the orbit could not be integrated over [{a:.6g}, {b:.6g}]: {var.message}")
        F = var.stm_end
        steps = round((b - a) / h_rk4)
        splittable = (b - a) > T * 2.0**-12 and (method != "RK4" or steps % 2 == 0)
        if splittable and np.linalg.cond(F) > max_cond:
            m = a + 0.5 * (b - a)
            pending[:0] = [(a, m), (m, b)]
            continue
        factors.append(F)
        trace_total += float(var.trace_integral[-1])
        xi = var.x_end
    factors = np.array(factors)
    M = np.eye(x.size)
    for F in factors:
        M = F @ M
    signs_logs = [np.linalg.slogdet(F) for F in factors]
    det = float(np.prod([s for s, _ in signs_logs]) * math.exp(sum(l for _, l in signs_logs)))
    mu = _periodic_qr(factors, M)
    if mu is not None:
        mu = mu.astype(complex)
        how = "periodic-qr"
    else:
        mu = _sort_by_modulus(np.linalg.eigvals(M).astype(complex))
        _warn_if_inaccurate(mu)
        how = "eig"
    liouville = math.exp(trace_total)
    return Monodromy(
        matrix=M, multipliers=mu, exponents=floquet_exponents(mu, T), det=det,
        trace_integral=trace_total, liouville_det=liouville,
        liouville_error=abs(det - liouville) / abs(liouville) if liouville else math.inf,
        x_end=xi, closure_error=float(np.linalg.norm(xi - x)), period=T, factors=factors,
        multiplier_method=how, nfev=nfev, njev=njev,
    )

"""Finite-difference Jacobians, in one place.

Used where no analytic Jacobian exists: the blade-element loads (their span quadrature has no
closed-form derivative), user right-hand sides given without ``jac``, and extra residuals of the
shooting problem. Central differences throughout: a state-transition matrix inherits the
Jacobian's relative error, and forward differences (error ~ eps**(1/2) ~ 1e-8) would cap the
Floquet multipliers and Liouville's check at eight digits; central ones reach ~eps**(2/3) ~ 4e-11.
We write this by hand because ``scipy.optimize.approx_fprime`` is forward-only and
``scipy.differentiate.jacobian`` adapts its step with many more evaluations than a shooting
iteration can afford.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

__all__ = ["central_jacobian", "central_step", "central_jacobian_nominal", "forward_jacobian",
           "central_differences"]

_EPS = float(np.finfo(float).eps)


def central_step(x: np.ndarray, relative: float = _EPS ** (1.0 / 3.0)) -> np.ndarray:
    """Steps ``relative * max(1, |x_j|)``: the optimum of central differences for O(1) curvature."""
    return relative * np.maximum(1.0, np.abs(x))


def _differences(
    f: Callable[[np.ndarray], np.ndarray], x: np.ndarray, h: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Undivided central differences (m, n) and the representable spans ``x_j+ - x_j-`` (n,)."""
    columns, spans = [], []
    for j in range(x.size):
        xp, xm = x.copy(), x.copy()
        xp[j] += h[j]
        xm[j] -= h[j]
        columns.append(np.asarray(f(xp)) - np.asarray(f(xm)))
        spans.append(xp[j] - xm[j])
    return np.stack(columns, axis=-1), np.array(spans)


def central_jacobian(
    f: Callable[[np.ndarray], np.ndarray],
    x: np.ndarray,
    step: np.ndarray | float | None = None,
) -> np.ndarray:
    """Central-difference Jacobian ``df/dx`` (shape ``(m, n)``) of ``f: R^n -> R^m`` at ``x``.

    Parameters
    ----------
    f : callable
        ``f(x) -> array of shape (m,)``.
    x : ndarray, shape (n,)
        Where to differentiate.
    step : float or ndarray, optional
        Absolute steps per component; default :func:`central_step`. ``2 n`` evaluations of ``f``.
    """
    x = np.asarray(x, dtype=float)
    h = central_step(x) if step is None else np.broadcast_to(np.asarray(step, float), x.shape)
    diff, spans = _differences(f, x, h)
    return diff / spans  # the representable span, not 2h: removes the rounding of x +- h


def central_differences(
    f: Callable[[np.ndarray], np.ndarray],
    x: np.ndarray,
    step: np.ndarray | float,
) -> np.ndarray:
    """The undivided central differences ``f(x + h_j e_j) - f(x - h_j e_j)``, shape ``(m, n)``.

    For callers that scale the differences before dividing by ``2 h_j`` (as the insect model's
    Jacobian, which divides the loads by the mass): scaling first and dividing last is the
    order of operations those callers' values are computed in, bit for bit.

    Parameters
    ----------
    f : callable
        ``f(x) -> array of shape (m,)``.
    x : ndarray, shape (n,)
        Where to differentiate.
    step : float or ndarray
        Absolute steps ``h_j`` per component. ``2 n`` evaluations of ``f``.

    Returns
    -------
    ndarray, shape (m, n)
        Column j is the difference across component j.
    """
    x = np.asarray(x, dtype=float)
    return _differences(f, x, np.broadcast_to(np.asarray(step, float), x.shape))[0]


def central_jacobian_nominal(
    f: Callable[[np.ndarray], np.ndarray],
    x: np.ndarray,
    step: np.ndarray | float,
) -> np.ndarray:
    """Central differences ``(f(x + h_j e_j) - f(x - h_j e_j)) / (2 h_j)``, shape ``(m, n)``.

    As :func:`central_jacobian` with given steps, but divided by the nominal ``2 h_j`` rather
    than the representable difference of the two points. The insect model's amplitude
    derivative (:meth:`flapping.model.dynamics.LongitudinalDynamics.amplitude_jac`) divides this
    way, and every number derived from it depends on that order of operations, bit for bit.

    Parameters
    ----------
    f : callable
        ``f(x) -> array of shape (m,)``.
    x : ndarray, shape (n,)
        Where to differentiate.
    step : float or ndarray
        Absolute steps ``h_j`` per component. ``2 n`` evaluations of ``f``.

    Returns
    -------
    ndarray, shape (m, n)
    """
    h = np.broadcast_to(np.asarray(step, float), np.shape(x))
    return central_differences(f, x, h) / (2.0 * h)


def forward_jacobian(
    f: Callable[[np.ndarray], np.ndarray],
    x: np.ndarray,
    fx: np.ndarray,
) -> np.ndarray:
    """Forward-difference Jacobian with MINPACK ``lmdif``'s steps ``sqrt(eps) |x_j|``.

    The paper's Jacobian of the shooting residual (each column one more shooting integration,
    so one evaluation per column rather than two); step ``sqrt(eps)`` where ``x_j = 0``.

    Parameters
    ----------
    f : callable
        ``f(x) -> array of shape (m,)``.
    x : ndarray, shape (n,)
        Where to differentiate.
    fx : ndarray, shape (m,)
        ``f(x)``, already known.

    Returns
    -------
    ndarray, shape (m, n)
    """
    x = np.asarray(x, dtype=float)
    J = np.empty((np.asarray(fx).size, x.size))
    for j in range(x.size):
        h = _EPS ** 0.5 * abs(x[j]) or _EPS ** 0.5
        xp = x.copy()
        xp[j] += h
        # divide by the representable step, not h: removes the rounding of x + h
        J[:, j] = (np.asarray(f(xp)) - fx) / (xp[j] - x[j])
    return J

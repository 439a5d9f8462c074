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

__all__ = ["central_jacobian", "central_step"]

_EPS = float(np.finfo(float).eps)


def central_step(x: np.ndarray, relative: float = _EPS ** (1.0 / 3.0)) -> np.ndarray:
    """Steps ``relative * max(1, |x_j|)``: the optimum of central differences for O(1) curvature."""
    return relative * np.maximum(1.0, np.abs(x))


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
    columns = []
    for j in range(x.size):
        xp, xm = x.copy(), x.copy()
        xp[j] += h[j]
        xm[j] -= h[j]
        # divide by the representable difference, not 2h: removes the rounding of x +- h
        columns.append((np.asarray(f(xp)) - np.asarray(f(xm))) / (xp[j] - xm[j]))
    return np.stack(columns, axis=-1)

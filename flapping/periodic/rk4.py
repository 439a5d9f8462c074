"""The classical fixed-step fourth-order Runge-Kutta scheme as a :class:`scipy.integrate.OdeSolver`.

The paper integrates with RK4 at a step of ``2**-10`` of the period (Sec. III.A); scipy has no
fixed-step method, so :class:`RK4` adds one that :func:`scipy.integrate.solve_ivp` accepts::

    solve_ivp(fun, (0.0, 1.0), y0, method=RK4, step=2.0**-10, dense_output=True)

The steps lie on the grid ``t0 + k * step`` (computed from ``t0``, so the grid does not drift);
the last step is shortened to end exactly at ``t_bound`` when the span is not a multiple of the
step. Four evaluations of ``fun`` per step. The dense output is the cubic Hermite interpolant of
the step's end values and slopes (fourth order, like the scheme); the end slope is the next
step's first stage, so dense output costs one extra evaluation per integration, not per step.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from typing import Any

import numpy as np
from scipy.integrate import DenseOutput, OdeSolver
from scipy.interpolate import CubicHermiteSpline

__all__ = ["RK4"]


class RK4(OdeSolver):
    """Classical fourth-order Runge-Kutta with a fixed step (no error control).

    Parameters
    ----------
    fun : callable
        Right-hand side ``fun(t, y) -> (n,)``.
    t0 : float
        Initial time.
    y0 : array_like, shape (n,)
        Initial state.
    t_bound : float
        End time (may be below ``t0``: backward integration).
    step : float, optional
        Step size ``h > 0``; default ``|t_bound - t0| / 1024`` (the paper's ``2**-10``).
    vectorized : bool, optional
        Passed to :class:`~scipy.integrate.OdeSolver` (only the single-point form is used).
    **extraneous
        Options of the adaptive methods (``rtol``, ``atol``, ``first_step``, ...) are ignored
        with a warning, as scipy's own solvers do with options they do not use.

    Raises
    ------
    ValueError
        If ``step`` is not a positive finite number.
    """

    # attributes of OdeSolver that this class reads and writes (scipy ships no type hints)
    t: float
    t_old: float | None
    t_bound: float
    y: np.ndarray

    def __init__(
        self,
        fun: Callable[[float, np.ndarray], Any],
        t0: float,
        y0: Any,
        t_bound: float,
        step: float | None = None,
        vectorized: bool = False,
        **extraneous: Any,
    ) -> None:
        if extraneous:
            warnings.warn(f"the fixed-step RK4 ignores the options {sorted(extraneous)}",
                          stacklevel=2)
        super().__init__(fun, t0, y0, t_bound, vectorized)
        span = t_bound - t0
        h = abs(span) / 1024 if step is None else step
        if not (isinstance(h, (int, float)) and math.isfinite(h) and h > 0):
            if span == 0.0 and step is None:
                h = 1.0
            else:
                raise ValueError(f"`step` must be a positive finite number; got {step!r}")
        self.h_abs = float(h)
        self._t_start = t0
        # m steps, n_full of them of length h (the last one is shorter when h does not divide
        # the span); tolerance 1e-9 h: a span that is a multiple of h up to rounding is one.
        self._m = max(1, math.ceil(abs(span) / h - 1e-9))
        self._n_full = self._m if abs(abs(span) - self._m * h) <= 1e-9 * h else self._m - 1
        self._signed_step = math.copysign(self.h_abs, span) if span else self.h_abs
        self._i = 0
        self._k_next: np.ndarray | None = None  # slope at (t, y), when dense output asked for it
        self._k_old: np.ndarray | None = None
        self.y_old: np.ndarray | None = None

    def _step_impl(self) -> tuple[bool, str | None]:
        t, y, i, dt_full = self.t, self.y, self._i, self._signed_step
        dt = dt_full if i < self._n_full else (self.t_bound - t)
        k1 = self.fun(t, y) if self._k_next is None else self._k_next
        half = 0.5 * dt
        k2 = self.fun(t + half, y + half * k1)
        k3 = self.fun(t + half, y + half * k2)
        # t0 + (i + 1) h rather than t + h: no drift of the grid over many steps
        t_next = self.t_bound if i == self._m - 1 else self._t_start + (i + 1) * dt_full
        k4 = self.fun(t_next, y + dt * k3)
        self.y_old, self._k_old, self._k_next = y, k1, None
        self.y = y + (dt / 6.0) * (k1 + 2.0 * (k2 + k3) + k4)
        self.t = t_next
        self._i = i + 1
        return True, None

    def _dense_output_impl(self) -> DenseOutput:
        if self._k_next is None:
            self._k_next = self.fun(self.t, self.y)  # reused as the next step's first stage
        assert self.t_old is not None and self.y_old is not None and self._k_old is not None
        return _HermiteDenseOutput(self.t_old, self.t, self.y_old, self.y, self._k_old,
                                   self._k_next)


class _HermiteDenseOutput(DenseOutput):
    """Cubic Hermite interpolant on one step (values and slopes at both ends)."""

    def __init__(self, t_old: float, t: float, y_old: np.ndarray, y: np.ndarray,
                 k_old: np.ndarray, k: np.ndarray) -> None:
        super().__init__(t_old, t)
        if t >= t_old:
            self._spline = CubicHermiteSpline([t_old, t], np.array([y_old, y]),
                                              np.array([k_old, k]), axis=0)
        else:  # backward step: the spline wants increasing abscissae
            self._spline = CubicHermiteSpline([t, t_old], np.array([y, y_old]),
                                              np.array([k, k_old]), axis=0)

    def _call_impl(self, t: np.ndarray) -> np.ndarray:
        return np.asarray(self._spline(t), dtype=float).T

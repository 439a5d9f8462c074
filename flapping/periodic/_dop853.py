"""Package-internal: scipy's DOP853 with a leaner step, for the continuation's many integrations.

:class:`LeanDOP853` is :class:`scipy.integrate.DOP853` (same tableau, initial step, error
estimate and step-size control, same accept/reject rule) with ``_step_impl`` rewritten to
spend less Python per step: Python floats for the stage times and the step control, the
tableau rows sliced once, no ``nextafter``/``norm`` wrappers on NumPy scalars. A continuation of
a small system integrates tens of thousands of steps whose stages each cost a few microseconds
of user code, so scipy's per-step bookkeeping was a large part of its time.

The floating-point operations are scipy's, in scipy's order (the same ``np.dot`` calls on the
same operands): the steps and values are bit for bit those of scipy's DOP853
(``tests/periodic/test_dop853.py``). Another summation order would not do: the error estimate
is a sum of stage values that cancel, so reordering it moves the step sizes by ~1e-6.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from scipy.integrate import DOP853

__all__ = ["LeanDOP853"]

_SAFETY, _MIN_FACTOR, _MAX_FACTOR = 0.9, 0.2, 10.0  # scipy.integrate._ivp.rk's constants


class LeanDOP853(DOP853):
    """DOP853 with a lean step (module notes); constructor and attributes as scipy's."""

    # attributes of scipy's solver that the step reads and writes (scipy ships no type hints)
    t: float
    y: np.ndarray
    f: np.ndarray
    h_abs: float
    h_previous: float | None
    y_old: np.ndarray | None
    status: str
    t_old: float | None

    def __init__(self, fun: Any, t0: float, y0: Any, t_bound: float, **options: Any) -> None:
        super().__init__(fun, t0, y0, t_bound, **options)
        K = self.K  # scipy allocates the stages once and writes them in place
        # per stage: the view K[:s].T, the tableau row and the node, built once per solver
        self._plan = [(K[:s].T, self.A[s, :s], float(self.C[s]))
                      for s in range(1, self.n_stages)]
        self._KB, self._KT = K[:-1].T, K.T
        self._n = float(self.n)

    def _stages(self, t: float, y: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
        """The Runge-Kutta stages into ``self.K``; the new state and its slope.

        ``y + dot(K[:s].T, a) * h`` as scipy writes it, with the scaling and the addition
        (which commutes exactly) done in place on the product: the same numbers, two
        temporaries fewer. Each stage state is a new array, as scipy's: ``fun`` may keep it.
        """
        K, fun, dot = self.K, self.fun, np.dot
        K[0] = self.f
        for s, (KT, a, c) in enumerate(self._plan, start=1):
            x = dot(KT, a)
            x *= h
            x += y
            K[s] = fun(t + c * h, x)
        y_new = y + h * dot(self._KB, self.B)
        f_new = fun(t + h, y_new)
        K[-1] = f_new
        return y_new, f_new

    def step(self) -> str | None:
        """One step: scipy's ``OdeSolver.step`` for a running, non-empty solver."""
        if self.status != "running" or self.n == 0 or self.t == self.t_bound:
            return super().step()  # scipy's errors and corner cases
        t = self.t
        success, message = self._step_impl()
        if not success:
            self.status = "failed"
        else:
            self.t_old = t
            if self.direction * (self.t - self.t_bound) >= 0:
                self.status = "finished"
        return message

    def _error_norm(self, h: float, scale: np.ndarray) -> float:
        """DOP853's error norm, as scipy's ``_estimate_error_norm`` computes it.

        The estimate is a sum of large stage values that cancel: another summation order
        (``E @ K`` for ``K.T @ E``) moves it by ~1e-4 relative and the step sizes with it, so
        the sums are scipy's own (``norm(x)**2`` is ``sqrt(x @ x)**2`` in NumPy).
        """
        K = self._KT
        err5, err3 = np.dot(K, self.E5) / scale, np.dot(K, self.E3) / scale
        e5, e3 = math.sqrt(err5.dot(err5)) ** 2, math.sqrt(err3.dot(err3)) ** 2
        if e5 == 0.0 and e3 == 0.0:
            return 0.0
        return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * self._n)

    def _step_impl(self) -> tuple[bool, str | None]:
        t, y, direction = float(self.t), self.y, float(self.direction)
        min_step = 10 * abs(math.nextafter(t, direction * math.inf) - t)
        h_abs = float(self.h_abs)
        h_abs = self.max_step if h_abs > self.max_step else max(h_abs, min_step)
        rejected, exponent = False, self.error_exponent
        while True:
            if h_abs < min_step:
                return False, self.TOO_SMALL_STEP
            t_new = t + h_abs * direction
            if direction * (t_new - self.t_bound) > 0:
                t_new = float(self.t_bound)
            h = t_new - t
            h_abs = abs(h)
            y_new, f_new = self._stages(t, y, h)
            scale = self.atol + np.maximum(np.abs(y), np.abs(y_new)) * self.rtol
            error = self._error_norm(h, scale)
            if error < 1:
                factor = _MAX_FACTOR if error == 0 else min(_MAX_FACTOR,
                                                             _SAFETY * error ** exponent)
                h_abs *= min(1.0, factor) if rejected else factor
                break
            h_abs *= max(_MIN_FACTOR, _SAFETY * error ** exponent)
            rejected = True
        self.h_previous, self.y_old = h, y
        self.t, self.y, self.h_abs, self.f = t_new, y_new, h_abs, f_new
        return True, None

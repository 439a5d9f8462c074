"""Segment-aware integration of ODEs and of their variational equations.

Two public functions:

* :func:`flow` integrates ``x' = f(t, x)`` like :func:`scipy.integrate.solve_ivp`, but restarts the
  integrator at *breakpoints* repeated periodically in time, and accepts one right-hand side per
  segment of the period. A flapping insect's right-hand side jumps at stroke reversal (the wing
  pitch switches, eq. 11); an adaptive integrator stepping across such a jump loses its order and
  its error estimate, and a single callable evaluated *at* the jump returns the value of one side
  only. Integrating each segment with its own callable, closed at both ends, is exact.
* :func:`variational_flow` integrates the state together with the variational equations
  ``Phi' = J Phi`` (the state-transition matrix, eqs. 42-49 of the paper) and, optionally,
  the parameter sensitivities ``S' = J S + df/dp`` and the quadrature ``int trace J dt``
  (Liouville's formula). These feed the Jacobian of the shooting residual (eq. 38) and the
  monodromy matrix of Floquet theory.

Besides scipy's methods (``"DOP853"``, ``"RK45"``, ``"Radau"``, ...), ``method="RK4"`` is the classical
fixed-step fourth-order Runge-Kutta scheme the paper uses (step ``period / 1024``, i.e. ``2**-10``
of a period). It is written by hand because ``solve_ivp`` has no fixed-step method.

Time grid
---------
With ``period`` ``T`` and ``breakpoints`` ``(b_1, ..., b_m)`` (fractions of the period in (0, 1),
increasing), segment ``k`` of period ``j`` is ``[(j + b_k) T, (j + b_{k+1}) T]`` with ``b_0 = 0`` and
``b_{m+1} = 1``; a sequence ``fun`` has ``m + 1`` callables, the ``k``-th used on segment ``k`` of every
period, including at its two end points.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicHermiteSpline

__all__ = ["FlowResult", "VariationalFlow", "flow", "variational_flow", "SCIPY_METHODS"]

#: Methods handed to :func:`scipy.integrate.solve_ivp`; ``"RK4"`` is ours.
SCIPY_METHODS: tuple[str, ...] = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")

_EPS = np.finfo(float).eps


# --------------------------------------------------------------------------------------------
# Results
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class FlowResult:
    """Result of :func:`flow`.

    Attributes
    ----------
    t : ndarray, shape (m,)
        Output times: ``t_eval`` if given, else every step the integrator took (segment ends
        included once).
    x : ndarray, shape (n, m)
        States at ``t``.
    nfev : int
        Number of right-hand-side evaluations (all segments together).
    success : bool
        Whether every segment was integrated to its end.
    message : str
        The integrator's message (of the first failing segment, if any).
    sol : callable or None
        ``sol(t)`` interpolates the solution (``dense_output=True``): scipy's dense output per
        segment, cubic Hermite for RK4 (fourth order, like the scheme).
    """

    t: np.ndarray
    x: np.ndarray
    nfev: int
    success: bool
    message: str
    sol: Callable[[Any], np.ndarray] | None = None


@dataclass(frozen=True)
class VariationalFlow:
    """Result of :func:`variational_flow`.

    Attributes
    ----------
    t : ndarray, shape (m,)
        Output times (``t_out``, in the order given; default ``(t1,)``).
    x : ndarray, shape (m, n)
        States at ``t``.
    stm : ndarray, shape (m, n, n)
        State-transition matrices ``Phi(t, t0) = dx(t)/dx(t0)``.
    sensitivity : ndarray, shape (m, n, n_p) or None
        ``dx(t)/dp`` for the parameters ``params`` (``None`` without parameters).
    trace_integral : ndarray, shape (m,) or None
        ``int_{t0}^{t} trace J(s, x(s)) ds`` (``trace=True`` only).
    nfev : int
        Right-hand-side evaluations, including those spent on finite-difference Jacobians.
    njev : int
        Analytic Jacobian evaluations (``jac`` and ``param_jac`` calls).
    success : bool
        Whether the integration reached ``t1``.
    message : str
        The integrator's message.
    """

    t: np.ndarray
    x: np.ndarray
    stm: np.ndarray
    sensitivity: np.ndarray | None
    trace_integral: np.ndarray | None
    nfev: int
    njev: int
    success: bool
    message: str

    @property
    def x_end(self) -> np.ndarray:
        """State at the last output time."""
        return self.x[-1]

    @property
    def stm_end(self) -> np.ndarray:
        """State-transition matrix at the last output time."""
        return self.stm[-1]


# --------------------------------------------------------------------------------------------
# Argument checking (public boundary)
# --------------------------------------------------------------------------------------------


class _Counter:
    """Mutable evaluation counter shared by the wrapped callables of all segments."""

    __slots__ = ("n",)

    def __init__(self) -> None:
        self.n = 0


class _Counted:
    """Wrap ``fun(t, x, *args)``: count calls and check the output shape once per call.

    The shape check costs a tuple comparison; it turns a wrong-shaped right-hand side into a
    ValueError that names the culprit instead of a broadcasting error deep inside scipy.
    """

    __slots__ = ("fun", "args", "shape", "counter", "name")

    def __init__(self, fun, args, shape, counter, name):
        self.fun = fun
        self.args = args
        self.shape = shape
        self.counter = counter
        self.name = name

    def __call__(self, t, x):
        self.counter.n += 1
        out = np.asarray(self.fun(t, x, *self.args), dtype=float)
        if out.shape != self.shape:
            raise ValueError(
                f"`{self.name}` must return an array of shape {self.shape}, got shape {out.shape}"
            )
        return out


def _check_state(x0, name: str = "x0") -> np.ndarray:
    x = np.array(x0, dtype=float)
    if x.ndim != 1 or x.size == 0:
        raise ValueError(f"`{name}` must be a non-empty 1-D array, got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValueError(f"`{name}` must be finite, got {x}")
    return x


def _check_period(period, name: str = "period") -> float:
    try:
        value = float(period)
    except (TypeError, ValueError):
        raise ValueError(f"`{name}` must be a positive finite number, got {period!r}") from None
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"`{name}` must be a positive finite number, got {period!r}")
    return value


def _check_breakpoints(breakpoints) -> tuple[float, ...]:
    try:
        b = tuple(float(v) for v in breakpoints)
    except (TypeError, ValueError):
        raise ValueError(
            f"`breakpoints` must be a sequence of numbers in (0, 1), got {breakpoints!r}"
        ) from None
    for v in b:
        if not (0.0 < v < 1.0):
            raise ValueError(f"`breakpoints` must lie in the open interval (0, 1), got {b}")
    if any(b2 <= b1 for b1, b2 in zip(b, b[1:])):
        raise ValueError(f"`breakpoints` must be strictly increasing, got {b}")
    return b


def _check_method(method) -> str:
    if method == "RK4" or method in SCIPY_METHODS:
        return method
    raise ValueError(f"`method` must be 'RK4' or one of {SCIPY_METHODS}, got {method!r}")


def _check_tolerances(rtol, atol) -> None:
    if not (np.isscalar(rtol) and math.isfinite(rtol) and rtol > 0):
        raise ValueError(f"`rtol` must be a positive finite number, got {rtol!r}")
    atol_arr = np.asarray(atol, dtype=float)
    if not (np.all(np.isfinite(atol_arr)) and np.all(atol_arr > 0)):
        raise ValueError(f"`atol` must be positive and finite, got {atol!r}")


def _check_rk4_steps(rk4_steps) -> int:
    if isinstance(rk4_steps, bool) or int(rk4_steps) != rk4_steps or rk4_steps < 1:
        raise ValueError(f"`rk4_steps` must be a positive integer, got {rk4_steps!r}")
    return int(rk4_steps)


def _check_span(t_span) -> tuple[float, float]:
    try:
        t0, t1 = (float(v) for v in t_span)
    except (TypeError, ValueError):
        raise ValueError(f"`t_span` must be a pair (t0, t1) of finite numbers, got {t_span!r}") from None
    if not (math.isfinite(t0) and math.isfinite(t1)):
        raise ValueError(f"`t_span` must be a pair (t0, t1) of finite numbers, got {t_span!r}")
    return t0, t1


def _check_integration(t_span, x0, method, rtol, atol, rk4_steps, period, breakpoints):
    """The argument checks shared by :func:`flow` and :func:`variational_flow`.

    Returns ``(t0, t1, x0, method, period, breakpoints, h)`` with ``h`` the RK4 step (or None).
    """
    t0, t1 = _check_span(t_span)
    x0 = _check_state(x0)
    method = _check_method(method)
    _check_tolerances(rtol, atol)
    rk4_steps = _check_rk4_steps(rk4_steps)
    if period is not None:
        period = _check_period(period)
    breakpoints = _check_breakpoints(breakpoints)
    h = _check_grid(t0, t1, period, breakpoints, method, rk4_steps)
    return t0, t1, x0, method, period, breakpoints, h


def _segment_callables(fun, n_segments: int, name: str) -> tuple[Callable, ...]:
    """One callable per segment of the period: a callable is repeated, a sequence is checked."""
    if callable(fun):
        return (fun,) * n_segments
    try:
        funs = tuple(fun)
    except TypeError:
        raise ValueError(f"`{name}` must be a callable or a sequence of callables") from None
    if len(funs) != n_segments or not all(callable(f) for f in funs):
        raise ValueError(
            f"`{name}` as a sequence needs one callable per segment: len(breakpoints) + 1 = "
            f"{n_segments} callables, got {len(funs)} item(s)"
        )
    return funs


def _check_grid(t0, t1, period, breakpoints, method, rk4_steps) -> float | None:
    """Validate period/breakpoints; return the RK4 step (None for adaptive methods)."""
    if breakpoints and period is None:
        raise ValueError("`breakpoints` are fractions of `period`: give `period` as well")
    if method != "RK4":
        return None
    if period is not None:
        h = period / rk4_steps
        for b in breakpoints:
            if abs(b * rk4_steps - round(b * rk4_steps)) > 1e-9:
                raise ValueError(
                    f"with method='RK4' every breakpoint must fall on a step boundary "
                    f"(a multiple of 1/rk4_steps = 1/{rk4_steps}); breakpoint {b} does not"
                )
        return h
    return abs(t1 - t0) / rk4_steps if t1 != t0 else 1.0


# --------------------------------------------------------------------------------------------
# Segment bookkeeping
# --------------------------------------------------------------------------------------------


def _nodes(t0, t1, period, breakpoints, extra_times=()):
    """Restart times from t0 to t1 (in the integration direction) and the segment of each piece.

    Breakpoint times within a few ulps of another node are merged into it, so that a span that
    starts "at" a breakpoint computed by a different formula does not produce a sliver segment.
    """
    lo, hi = min(t0, t1), max(t0, t1)
    scale = max(abs(t0), abs(t1), period or 0.0, 1e-300)
    tol = 64 * _EPS * scale
    times = [t0, t1]
    if breakpoints:
        fractions = (0.0,) + tuple(breakpoints)
        for j in range(math.floor(lo / period) - 1, math.ceil(hi / period) + 2):
            for b in fractions:
                times.append((j + b) * period)
    times.extend(extra_times)
    inside = sorted(t for t in times if lo + tol < t < hi - tol)
    nodes = [lo]
    for t in inside:
        if t - nodes[-1] > tol:
            nodes.append(t)
    if hi - nodes[-1] > tol or len(nodes) == 1:
        nodes.append(hi)
    else:
        nodes[-1] = hi
    nodes = np.array(nodes)
    if t1 < t0:
        nodes = nodes[::-1]
    if breakpoints:
        mids = 0.5 * (nodes[:-1] + nodes[1:])
        phase = np.mod(mids / period, 1.0)
        segments = np.searchsorted(np.asarray(breakpoints), phase, side="right")
    else:
        segments = np.zeros(len(nodes) - 1, dtype=int)
    return nodes, segments


def _rk4_piece(f, a, b, y, h, record):
    """Classical RK4 from a to b with the step h (b - a a multiple of h, last step clipped).

    Written by hand because solve_ivp has no fixed-step method; the paper's scheme.
    Returns (y(b), ts, ys, slopes) where ts/ys/slopes are filled only when ``record``.
    """
    span = b - a
    m = max(1, math.ceil(abs(span) / h - 1e-9))
    n_full = m if abs(abs(span) - m * h) <= 1e-9 * h else m - 1
    step = math.copysign(h, span)
    ts, ys, ks = [], [], []
    t = a
    for i in range(m):
        dt = step if i < n_full else (b - t)
        k1 = f(t, y)
        if record:
            ts.append(t)
            ys.append(y)
            ks.append(k1)
        half = 0.5 * dt
        k2 = f(t + half, y + half * k1)
        k3 = f(t + half, y + half * k2)
        t_next = b if i == m - 1 else a + (i + 1) * step  # no drift of the grid
        k4 = f(t_next, y + dt * k3)
        y = y + (dt / 6.0) * (k1 + 2.0 * (k2 + k3) + k4)
        t = t_next
    return y, ts, ys, ks


def _on_grid(t, t0, h) -> bool:
    q = (t - t0) / h
    return abs(q - round(q)) <= 1e-7


def _propagate(funs, t0, t1, y0, *, period, breakpoints, method, rtol, atol, rk4_h,
               t_out=(), t_eval=None, dense=False, record_steps=False):
    """Integrate over the pieces between restart nodes; the workhorse of this module.

    Returns dict with: ``y_out`` (states at t_out, list), ``t``/``y`` (steps or t_eval),
    ``sol`` (piecewise interpolant), ``success``, ``message``.
    """
    t_out = [float(t) for t in t_out]
    nodes, segments = _nodes(t0, t1, period, breakpoints, t_out)
    if method == "RK4":
        for t in list(nodes) + t_out:
            if not _on_grid(t, t0, rk4_h) and t != t1:
                raise ValueError(
                    f"with method='RK4' breakpoints and output times must fall on the step grid "
                    f"t0 + k h (h = {rk4_h:.6g}); time {t:.17g} does not"
                )
    y = np.asarray(y0, dtype=float)
    need_steps = record_steps or t_eval is not None or dense
    t_eval_arr = None if t_eval is None else np.asarray(t_eval, dtype=float)
    out_t, out_y, pieces = [], [], []
    # Each output time was merged into a node by _nodes; remember which one.
    out_index = [int(np.argmin(np.abs(nodes - t))) for t in t_out]
    node_state = [None] * len(nodes)
    node_state[0] = y
    success, message = True, "The solver successfully reached the end of the integration interval."
    first_step = None
    for i_node, (a, b, seg) in enumerate(zip(nodes[:-1], nodes[1:], segments)):
        f = funs[seg]
        if method == "RK4":
            y_new, ts, ys, ks = _rk4_piece(f, a, b, y, rk4_h, need_steps)
            if need_steps:
                ts.append(b)
                ys.append(y_new)
                if dense or t_eval is not None:
                    ks.append(f(b, y_new))  # end slope of this piece, from its own callable
                    pieces.append(("rk4", a, b, CubicHermiteSpline(ts, np.array(ys), np.array(ks), axis=0)))
                if t_eval is None:
                    out_t.extend(ts if not out_t else ts[1:])
                    out_y.extend(ys if not out_y else ys[1:])
            y = y_new
        else:
            if first_step is not None:
                first_step = min(first_step, abs(b - a))
            res = solve_ivp(f, (a, b), y, method=method, rtol=rtol, atol=atol,
                            dense_output=dense or t_eval is not None,
                            first_step=first_step)
            if not res.success:
                success, message = False, f"segment [{a:.6g}, {b:.6g}]: {res.message}"
                break
            if len(res.t) >= 2:
                # Carry the step size across the restart: saves the initial-step search and the
                # ramp-up, the main cost of restarting at every breakpoint.
                first_step = abs(res.t[-1] - res.t[-2]) if len(res.t) > 2 else abs(res.t[-1] - res.t[0])
            if dense or t_eval is not None:
                pieces.append(("ivp", a, b, res.sol))
            if t_eval is None and need_steps:
                out_t.extend(res.t if not out_t else res.t[1:])
                out_y.extend(res.y.T if not out_y else res.y.T[1:])
            y = res.y[:, -1]
        node_state[i_node + 1] = y
    y_out = [node_state[i] for i in out_index]
    sol = _PiecewiseSolution(pieces) if pieces else None
    if t_eval is not None and success:
        out_t = list(t_eval_arr)
        out_y = [sol(t) for t in t_eval_arr] if len(t_eval_arr) else []
    return {
        "y_out": y_out, "t": np.array(out_t), "y": np.array(out_y), "sol": sol,
        "success": success, "message": message, "y_end": y,
    }


class _PiecewiseSolution:
    """Dispatch ``sol(t)`` to the interpolant of the piece containing t (first match wins)."""

    def __init__(self, pieces):
        self.pieces = pieces
        ends = [max(a, b) for _, a, b, _ in pieces]
        starts = [min(a, b) for _, a, b, _ in pieces]
        order = np.argsort(starts)
        self.starts = np.asarray(starts)[order]
        self.ends = np.asarray(ends)[order]
        self.interps = [pieces[i][3] for i in order]

    def _one(self, t):
        i = int(np.clip(np.searchsorted(self.starts, t, side="right") - 1, 0, len(self.starts) - 1))
        return np.asarray(self.interps[i](t), dtype=float)

    def __call__(self, t):
        t = np.asarray(t, dtype=float)
        if t.ndim == 0:
            return self._one(float(t))
        return np.stack([self._one(float(s)) for s in t], axis=-1)


# --------------------------------------------------------------------------------------------
# Public API
# --------------------------------------------------------------------------------------------


def flow(
    fun: Callable | Sequence[Callable],
    t_span: tuple[float, float],
    x0,
    *,
    breakpoints: Sequence[float] = (),
    period: float | None = None,
    method: str = "DOP853",
    rtol: float = 1e-11,
    atol: float = 1e-12,
    rk4_steps: int = 1024,
    t_eval=None,
    dense_output: bool = False,
    args: tuple = (),
) -> FlowResult:
    """Integrate ``x' = fun(t, x, *args)``, restarting at periodic breakpoints.

    The state equation (30) of the paper, integrated segment by segment so that a right-hand
    side that jumps at stroke reversal is never stepped across.

    Parameters
    ----------
    fun : callable or sequence of callables
        ``fun(t, x, *args) -> (n,)`` (solve_ivp convention), or one such callable per segment of
        the period (``len(breakpoints) + 1`` of them), each smooth on its *closed* segment and
        evaluated only there.
    t_span : (float, float)
        Start and end times; ``t1 < t0`` integrates backwards.
    x0 : array_like, shape (n,)
        Initial state.
    breakpoints : sequence of float, optional
        Fractions of ``period`` in (0, 1), strictly increasing, at which the integrator restarts in
        every period (period boundaries ``j T`` are restart times too when breakpoints are given).
    period : float, optional
        Period ``T`` of the breakpoints and the RK4 step ``T / rk4_steps``. Required with
        breakpoints.
    method : str, optional
        ``"DOP853"`` (default), any other :func:`~scipy.integrate.solve_ivp` method, or ``"RK4"``
        (classical fixed step ``period / rk4_steps``, or ``(t1 - t0) / rk4_steps`` without period;
        breakpoints must then fall on step boundaries).
    rtol, atol : float, optional
        Tolerances of the adaptive methods (ignored by RK4).
    rk4_steps : int, optional
        RK4 steps per period; 1024 (``2**-10`` of a period) is the paper's choice (Sec. III.A).
    t_eval : array_like, optional
        Times at which to report the solution (interpolated by the dense output).
    dense_output : bool, optional
        Return a callable ``sol``.
    args : tuple, optional
        Extra arguments of ``fun``.

    Returns
    -------
    FlowResult
        Times, states (shape (n, m)), number of right-hand-side evaluations, success flag.

    Raises
    ------
    ValueError
        For a bad argument (message names it and the accepted range), a wrong-shaped ``fun``
        output, or RK4 breakpoints off the step grid.
    """
    t0, t1, x0, method, period, breakpoints, h = _check_integration(
        t_span, x0, method, rtol, atol, rk4_steps, period, breakpoints)
    counter = _Counter()
    funs = tuple(
        _Counted(f, tuple(args), x0.shape, counter, "fun")
        for f in _segment_callables(fun, len(breakpoints) + 1, "fun")
    )
    if t_eval is not None:
        t_eval = np.asarray(t_eval, dtype=float)
        if t_eval.ndim != 1 or np.any(t_eval < min(t0, t1)) or np.any(t_eval > max(t0, t1)):
            raise ValueError("`t_eval` must be a 1-D array of times within `t_span`")
    if t1 == t0:
        return FlowResult(np.array([t0]), x0[:, None], 0, True, "empty interval", None)
    out = _propagate(funs, t0, t1, x0, period=period, breakpoints=breakpoints, method=method,
                     rtol=rtol, atol=atol, rk4_h=h, t_eval=t_eval, dense=dense_output,
                     record_steps=True)
    x = out["y"].T if out["y"].size else np.empty((x0.size, 0))
    return FlowResult(out["t"], x, counter.n, out["success"], out["message"],
                      out["sol"] if dense_output else None)


def _fd_jacobian(f, t, x, fx=None):
    """Central-difference Jacobian of f(t, .) at x: 2n evaluations, error ~ eps**(2/3).

    Central rather than forward differences because the state-transition matrix inherits the
    Jacobian's relative error; forward differences (eps**(1/2) ~ 1e-8) would cap the Floquet
    multipliers and Liouville's check at eight digits.
    """
    n = x.size
    J = np.empty((n, n))
    hs = _EPS ** (1.0 / 3.0) * np.maximum(1.0, np.abs(x))
    for j in range(n):
        xp = x.copy()
        xm = x.copy()
        xp[j] += hs[j]
        xm[j] -= hs[j]
        J[:, j] = (f(t, xp) - f(t, xm)) / (xp[j] - xm[j])
    return J


class _FunP:
    """``fun(t, x, *args, p)`` seen as ``g(t, x)`` for fixed p, and as a function of p."""

    __slots__ = ("fun", "args", "p", "shape", "counter")

    def __init__(self, fun, args, p, shape, counter):
        self.fun, self.args, self.p, self.shape, self.counter = fun, args, p, shape, counter

    def __call__(self, t, x):
        return self.at(t, x, self.p)

    def at(self, t, x, p):
        self.counter.n += 1
        out = np.asarray(self.fun(t, x, *self.args, p), dtype=float)
        if out.shape != self.shape:
            raise ValueError(f"`fun` must return an array of shape {self.shape}, got shape {out.shape}")
        return out


def _variational_rhs(f, jac, pjac, n, n_p, trace, jcounter):
    """Right-hand side of (x, Phi, S, int tr J): the variational bookkeeping solve_ivp lacks.

    ``f`` is a counted g(t, x) (a :class:`_FunP` when there are parameters); ``jac`` and
    ``pjac`` are user callables already bound to args/p, or None for finite differences.
    """
    nn = n * n
    i_s = n + nn
    i_tr = i_s + n * n_p

    def rhs(t, y):
        x = y[:n]
        fx = f(t, x)
        if jac is None:
            J = _fd_jacobian(f, t, x)
        else:
            jcounter.n += 1
            J = np.asarray(jac(t, x), dtype=float)
            if J.shape != (n, n):
                raise ValueError(f"`jac` must return an array of shape {(n, n)}, got shape {J.shape}")
        out = np.empty_like(y)
        out[:n] = fx
        out[n:i_s] = (J @ y[n:i_s].reshape(n, n)).ravel()
        if n_p:
            if pjac is None:
                # Central differences in p: 2 n_p extra evaluations per call.
                p = f.p
                dfdp = np.empty((n, n_p))
                hs = _EPS ** (1.0 / 3.0) * np.maximum(1.0, np.abs(p))
                for j in range(n_p):
                    pp = p.copy()
                    pm = p.copy()
                    pp[j] += hs[j]
                    pm[j] -= hs[j]
                    dfdp[:, j] = (f.at(t, x, pp) - f.at(t, x, pm)) / (pp[j] - pm[j])
            else:
                jcounter.n += 1
                dfdp = np.asarray(pjac(t, x), dtype=float).reshape(n, n_p)
            out[i_s:i_tr] = (J @ y[i_s:i_tr].reshape(n, n_p) + dfdp).ravel()
        if trace:
            out[i_tr] = np.trace(J)
        return out

    return rhs


def _failed_variational(t_out, n, n_p, trace, nfev, njev, message):
    nan = np.full(len(t_out), np.nan)
    return VariationalFlow(np.array(t_out), np.full((len(t_out), n), np.nan),
                           np.full((len(t_out), n, n), np.nan),
                           np.full((len(t_out), n, n_p), np.nan) if n_p else None,
                           nan if trace else None, nfev, njev, False, message)


def variational_flow(
    fun: Callable | Sequence[Callable],
    jac: Callable | Sequence[Callable] | None,
    t_span: tuple[float, float],
    x0,
    *,
    breakpoints: Sequence[float] = (),
    period: float | None = None,
    method: str = "DOP853",
    rtol: float = 1e-11,
    atol: float = 1e-12,
    stm_atol: float | None = None,
    rk4_steps: int = 1024,
    t_out=None,
    params=None,
    param_jac: Callable | Sequence[Callable] | None = None,
    trace: bool = False,
    args: tuple = (),
) -> VariationalFlow:
    """Integrate the state with its variational equations (paper eqs. 42-49).

    Integrates ``x' = f``, ``Phi' = J Phi`` (``Phi(t0) = I``), and with parameters
    ``S' = J S + df/dp`` (``S(t0) = 0``), plus ``int trace J dt`` as an extra quadrature state.
    The extended system is integrated as one ODE with the same segments and error control
    (``method="RK4"`` then gives the exact derivative of the discrete RK4 map, because RK methods
    commute with linearisation).

    Parameters
    ----------
    fun : callable or sequence of callables
        ``fun(t, x, *args)`` or, with ``params``, ``fun(t, x, *args, p)``; a sequence gives one
        callable per segment (see :func:`flow`).
    jac : callable, sequence of callables, or None
        Analytic Jacobian ``df/dx``, same signature and segment convention as ``fun``. ``None``:
        central finite differences of ``fun`` at every right-hand-side evaluation, i.e. the
        variational equation with a finite-difference Jacobian (``2 n`` extra evaluations per
        call, relative error ~ eps**(2/3)); *not* differences of the flow.
    t_span : (float, float)
        Start and end times.
    x0 : array_like, shape (n,)
        Initial state.
    breakpoints, period, method, rtol, atol, rk4_steps, args
        As in :func:`flow`.
    stm_atol : float, optional
        Absolute tolerance for the matrix (and sensitivity) components; default ``atol``. A large
        value takes them out of the step-size control (the step is then set by the state alone):
        cheaper, and enough where the matrix only steers a Newton iteration.
    t_out : sequence of float, optional
        Times (within ``t_span``) at which to report; default ``(t1,)``. The integrator restarts
        at each (so RK4 needs them on its grid).
    params : array_like, optional
        Parameters ``p``, passed as the last argument of ``fun``, ``jac``, ``param_jac``; their
        sensitivities are integrated.
    param_jac : callable or sequence of callables, optional
        ``df/dp``, shape (n, n_p); default central finite differences of ``fun`` in ``p``.
    trace : bool, optional
        Also integrate ``int trace J dt`` (Liouville's formula).

    Returns
    -------
    VariationalFlow
        States, state-transition matrices, sensitivities, trace integrals at ``t_out``, and
        evaluation counts.

    Raises
    ------
    ValueError
        For a bad argument, or ``fun``/``jac`` returning the wrong shape.
    """
    t0, t1, x0, method, period, breakpoints, h = _check_integration(
        t_span, x0, method, rtol, atol, rk4_steps, period, breakpoints)
    n = x0.size
    n_seg = len(breakpoints) + 1
    funs = _segment_callables(fun, n_seg, "fun")
    jacs = (None,) * n_seg if jac is None else _segment_callables(jac, n_seg, "jac")
    args = tuple(args)
    if params is not None:
        p = np.atleast_1d(np.array(params, dtype=float))
        if p.ndim != 1 or not np.all(np.isfinite(p)):
            raise ValueError(f"`params` must be a finite 1-D array, got {params!r}")
        n_p = p.size
        pjacs = (None,) * n_seg if param_jac is None else _segment_callables(param_jac, n_seg, "param_jac")
    else:
        p, n_p, pjacs = None, 0, (None,) * n_seg
    t_out = (t1,) if t_out is None else tuple(float(t) for t in t_out)
    for t in t_out:
        if not (min(t0, t1) <= t <= max(t0, t1)):
            raise ValueError(f"`t_out` times must lie within t_span {t_span}, got {t}")
    counter, jcounter = _Counter(), _Counter()
    rhss = []
    for f, J, PJ in zip(funs, jacs, pjacs):
        extra = args if p is None else args + (p,)
        g = _FunP(f, args, p, x0.shape, counter) if p is not None else _Counted(f, args, x0.shape, counter, "fun")
        Jb = None if J is None else (lambda t, x, J=J, extra=extra: J(t, x, *extra))
        PJb = None if PJ is None else (lambda t, x, PJ=PJ, extra=extra: PJ(t, x, *extra))
        rhss.append(_variational_rhs(g, Jb, PJb, n, n_p, trace, jcounter))
    y0 = np.concatenate([x0, np.eye(n).ravel(), np.zeros(n * n_p), np.zeros(1 if trace else 0)])
    if stm_atol is not None:
        atol = np.concatenate([np.full(n, atol, dtype=float) if np.ndim(atol) == 0 else np.asarray(atol, float),
                               np.full(y0.size - n, float(stm_atol))])
    ys = []
    success, message = True, "empty interval"
    if t1 != t0:
        out = _propagate(tuple(rhss), t0, t1, y0, period=period, breakpoints=breakpoints,
                         method=method, rtol=rtol, atol=atol, rk4_h=h, t_out=t_out)
        success, message = out["success"], out["message"]
        if not success:
            return _failed_variational(t_out, n, n_p, trace, counter.n, jcounter.n, message)
        ys = out["y_out"]
    else:
        ys = [y0 for _ in t_out]
    Y = np.array(ys)
    nn = n * n
    return VariationalFlow(
        t=np.array(t_out),
        x=Y[:, :n].copy(),
        stm=Y[:, n:n + nn].reshape(-1, n, n).copy(),
        sensitivity=Y[:, n + nn:n + nn + n * n_p].reshape(-1, n, n_p).copy() if n_p else None,
        trace_integral=Y[:, -1].copy() if trace else None,
        nfev=counter.n,
        njev=jcounter.n,
        success=success,
        message=message,
    )

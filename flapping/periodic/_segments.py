"""Package-internal integration machinery shared by integrate, shooting and floquet.

The public functions of :mod:`flapping.periodic` check their arguments once and then call into
this module, which trusts its inputs. It holds:

* :class:`Settings` and the checks of the integration options (method, tolerances, RK4 step,
  step budget, breakpoints), used by every public function that integrates;
* :class:`Checked`, the wrapper of every user callable: it counts evaluations and refuses a wrong
  shape or a non-finite value (``solve_ivp`` fed NaN shrinks its step forever);
* :func:`restart_nodes` (the restart times of a segmented period) and :func:`propagate`, the
  driver that integrates piece by piece with any :class:`scipy.integrate.OdeSolver`, under a
  step budget (:class:`StepGuard`) so that a stiff or blowing-up problem fails with advice
  instead of running for hours;
* :func:`variational`, the state with its variational equations, and the result classes
  :class:`FlowResult` and :class:`VariationalFlow` (re-exported by
  :mod:`flapping.periodic.integrate`).

Conventions of :mod:`flapping.periodic` (all modules):

* time along the last axis, as ``solve_ivp``'s ``y``: states ``(n, m)``, matrices ``(n, n, m)``,
  sensitivities ``(n, n_p, m)``; ``*_end`` properties give the last time;
* counters as scipy names them: ``nfev`` (evaluations of ``fun``, including those spent on
  finite differences), ``njev`` (evaluations of ``jac`` and ``param_jac``), ``nit`` (iterations);
* ``rtol``, ``atol``, ``method``, ``rk4_steps`` and ``max_steps`` wherever something is integrated;
* numbers converted to float64 on entry; bools and strings refused (:mod:`flapping._validation`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.integrate import BDF, DOP853, LSODA, RK23, RK45, OdeSolution, OdeSolver

import flapping._validation as check
from flapping._numdiff import central_jacobian
from flapping.periodic import settings as opt
from flapping.periodic._readonly import freeze
from flapping.periodic.rk4 import RK4
from flapping.periodic.settings import MAX_STEPS, METHODS

#: Consecutive steps whose size, kept up, would exceed the budget before the early failure.
_STREAK = 100

_EPS = float(np.finfo(float).eps)


# --------------------------------------------------------------------------------------------
# Settings and their checks (called at the public boundary only)
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Settings:
    """Checked integration settings.

    Attributes
    ----------
    method : str
        Name of the method (``"RK4"`` or a scipy name; the class name for an OdeSolver class).
    solver : type
        The :class:`~scipy.integrate.OdeSolver` subclass.
    rtol : float
        Relative tolerance (adaptive methods).
    atol : float or ndarray
        Absolute tolerance (adaptive methods).
    rk4_steps : int
        Fixed steps per period (RK4).
    max_steps : int
        Step budget of one integration call.
    """

    method: str
    solver: type[OdeSolver]
    rtol: float
    atol: float | np.ndarray
    rk4_steps: int
    max_steps: int

    @property
    def fixed_step(self) -> bool:
        """Whether the method takes fixed steps (RK4): breakpoints must then be on its grid."""
        return issubclass(self.solver, RK4)


def check_settings(method: Any, rtol: Any, atol: Any, rk4_steps: Any,
                   max_steps: Any) -> Settings:
    """Check the integration options shared by every public function that integrates.

    The checks themselves live in :mod:`flapping.periodic.settings` (tolerance floors, caps).

    Raises
    ------
    ValueError
        Naming the first bad option and its accepted values.
    """
    checked = opt.check_method(method)
    if isinstance(checked, type):
        name, solver = ("RK4" if issubclass(checked, RK4) else checked.__name__), checked
    else:
        name, solver = checked, METHODS[checked]
    return Settings(name, solver, opt.check_rtol("rtol", rtol), opt.check_atol("atol", atol),
                    opt.capped("rk4_steps", rk4_steps),
                    opt.capped("max_steps", MAX_STEPS if max_steps is None else max_steps))


def check_breakpoints(breakpoints: Any) -> tuple[float, ...]:
    """Fractions of the period in (0, 1), strictly increasing, as floats."""
    try:
        items = list(breakpoints)
    except TypeError:
        raise ValueError(f"`breakpoints` must be a sequence of numbers in (0, 1); "
                         f"got {breakpoints!r}") from None
    b = tuple(check.real("breakpoints", v) for v in items)
    for v in b:
        if not 0.0 < v < 1.0:
            raise ValueError(f"`breakpoints` must lie in the open interval (0, 1); got {b}")
    if any(b2 <= b1 for b1, b2 in zip(b, b[1:], strict=False)):
        raise ValueError(f"`breakpoints` must be strictly increasing; got {b}")
    return b


def check_span(t_span: Any) -> tuple[float, float]:
    """``(t0, t1)`` as two finite floats."""
    try:
        t0, t1 = t_span
    except (TypeError, ValueError):
        raise ValueError(f"`t_span` must be a pair (t0, t1) of finite numbers; "
                         f"got {t_span!r}") from None
    return check.real("t_span[0]", t0), check.real("t_span[1]", t1)


def segment_callables(fun: Any, n_segments: int, name: str) -> tuple[Callable[..., Any], ...]:
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
            f"{n_segments} callables, got {len(funs)} item(s)")
    return funs


def fixed_step(settings: Settings, t0: float, t1: float, period: float | None,
               breakpoints: tuple[float, ...]) -> float | None:
    """The RK4 step (``period / rk4_steps``, else ``|t1 - t0| / rk4_steps``); None if adaptive.

    Raises
    ------
    ValueError
        If breakpoints come without a period, or (RK4) fall off the step grid.
    """
    if breakpoints and period is None:
        raise ValueError("`breakpoints` are fractions of `period`: give `period` as well")
    if not settings.fixed_step:
        return None
    steps = settings.rk4_steps
    if period is None:
        return abs(t1 - t0) / steps if t1 != t0 else 1.0
    for b in breakpoints:
        if abs(b * steps - round(b * steps)) > 1e-9:
            raise ValueError(
                f"with method='RK4' every one of `breakpoints` must fall on a step boundary (a "
                f"multiple of 1/rk4_steps = 1/{steps}); breakpoint {b} does not: choose "
                f"`rk4_steps` accordingly")
    return period / steps


def solver_options(settings: Settings, h: float | None, atol: Any = None) -> dict[str, Any]:
    """Keyword options of the solver: the step for RK4, the tolerances otherwise."""
    if settings.fixed_step:
        return {"step": h}
    return {"rtol": settings.rtol, "atol": settings.atol if atol is None else atol}


# --------------------------------------------------------------------------------------------
# Checked user callables
# --------------------------------------------------------------------------------------------


class Counter:
    """Mutable evaluation counter shared by the wrapped callables of all segments."""

    __slots__ = ("n",)

    def __init__(self) -> None:
        self.n = 0


class Diverged(Exception):
    """The state itself became non-finite (the solution overflowed): not the callable's fault.

    ``t`` and ``state``: where (None when the raiser does not know).
    """

    def __init__(self, message: str, t: float | None = None, state: Any = None) -> None:
        super().__init__(message)
        self.t, self.state = t, state


@dataclass(frozen=True)
class Failure:
    """Where an integration stopped without reaching its end.

    Attributes
    ----------
    t : float
        The time reached.
    state : ndarray
        The state there (of the user's system: the variational matrices are left out).
    source : str
        Why: ``"state"`` (the solution overflowed), ``"step budget"`` (``max_steps`` ran out, or
        the step size foretold it) or ``"integrator"`` (the solver gave up, e.g. a step below
        rounding).
    """

    t: float
    state: np.ndarray
    source: str

    def __post_init__(self) -> None:
        freeze(self)


class Checked:
    """``fun(t, x, *args[, params])`` seen as ``g(t, x)``: counted, shape- and finiteness-checked.

    ``params`` (the free parameters, or None) is appended to the arguments; :meth:`at` evaluates at
    another ``params`` (finite differences in the parameters). A wrong shape is a ValueError naming
    the callable; so is a non-finite value at a finite state (a NaN would make the adaptive
    integrator shrink its step forever); a non-finite *state* raises :class:`Diverged`.
    """

    __slots__ = ("fun", "args", "params", "shape", "counter", "name", "reshape", "extra")

    def __init__(self, fun: Callable[..., Any], args: tuple[Any, ...], params: np.ndarray | None,
                 shape: tuple[int, ...], counter: Counter, name: str = "fun",
                 reshape: bool = False) -> None:
        self.fun, self.args, self.params, self.shape = fun, args, params, shape
        self.counter, self.name, self.reshape = counter, name, reshape
        self.extra = args if params is None else args + (params,)

    def __call__(self, t: float, x: np.ndarray) -> np.ndarray:
        self.counter.n += 1
        out = np.asarray(self.fun(t, x, *self.extra), dtype=float)
        if out.ndim == 1 and out.shape == self.shape and math.isfinite(out.dot(out)):
            return out  # the common case, kept short: this runs at every evaluation
        return self._checked(out, t, x)

    def at(self, t: float, x: np.ndarray, params: np.ndarray | None) -> np.ndarray:
        """Evaluate at the parameters ``params``."""
        self.counter.n += 1
        extra = self.args if params is None else self.args + (params,)
        return self._checked(np.asarray(self.fun(t, x, *extra), dtype=float), t, x)

    def _checked(self, out: np.ndarray, t: float, x: np.ndarray) -> np.ndarray:
        if out.shape != self.shape:
            if not (self.reshape and out.size == math.prod(self.shape)):
                raise ValueError(f"`{self.name}` must return an array of shape {self.shape}, "
                                 f"got shape {out.shape}")
            out = out.reshape(self.shape)
        # v.v is finite iff every entry is (or it overflowed, |v| > 1e154: then look closer);
        # five times cheaper than isfinite().all() on small arrays, checked at every evaluation
        flat = out.reshape(-1)
        if not math.isfinite(flat.dot(flat)) and not np.isfinite(out).all():
            if not np.isfinite(x).all():
                raise Diverged(f"the state became non-finite at t = {float(t)!r} (the solution "
                               f"overflowed)", float(t), x)
            check.finite_output(self.name, out, float(t), x)
        return out


# --------------------------------------------------------------------------------------------
# Restart grid and the piecewise solution
# --------------------------------------------------------------------------------------------


def restart_nodes(t0: float, t1: float, period: float | None, breakpoints: tuple[float, ...],
                  extra_times: Sequence[float] = ()) -> tuple[np.ndarray, np.ndarray]:
    """Restart times from t0 to t1 (in the integration direction) and the segment of each piece.

    Breakpoint times within a few ulps of another node are merged into it, so that a span that
    starts "at" a breakpoint computed by a different formula does not produce a sliver segment.
    """
    lo, hi = min(t0, t1), max(t0, t1)
    scale = max(abs(t0), abs(t1), period or 0.0, 1e-300)
    tol = 64 * _EPS * scale
    times = [t0, t1]
    if breakpoints:
        assert period is not None
        fractions = (0.0,) + tuple(breakpoints)
        for j in range(math.floor(lo / period) - 1, math.ceil(hi / period) + 2):
            times.extend((j + b) * period for b in fractions)
    times.extend(extra_times)
    inside = sorted(t for t in times if lo + tol < t < hi - tol)
    kept = [lo]
    for t in inside:
        if t - kept[-1] > tol:
            kept.append(t)
    if hi - kept[-1] > tol or len(kept) == 1:
        kept.append(hi)
    else:
        kept[-1] = hi
    nodes = np.array(kept)
    if t1 < t0:
        nodes = nodes[::-1]
    if breakpoints:
        assert period is not None
        phase = np.mod(0.5 * (nodes[:-1] + nodes[1:]) / period, 1.0)
        segments = np.searchsorted(np.asarray(breakpoints), phase, side="right")
    else:
        segments = np.zeros(len(nodes) - 1, dtype=int)
    return nodes, segments


class Piecewise:
    """``sol(t)``: the dense output of the piece containing t (of the later piece at a node)."""

    def __init__(self, pieces: list[tuple[float, float, OdeSolution]]) -> None:
        starts = [min(a, b) for a, b, _ in pieces]
        order = np.argsort(starts)
        self.starts = np.asarray(starts)[order]
        self.interps = [pieces[i][2] for i in order]

    def _one(self, t: float) -> np.ndarray:
        i = int(np.clip(np.searchsorted(self.starts, t, side="right") - 1, 0,
                        len(self.starts) - 1))
        return np.asarray(self.interps[i](t), dtype=float)

    def __call__(self, t: Any) -> np.ndarray:
        """States at ``t`` (scalar: shape (n,); array of m times: shape (n, m))."""
        t = np.asarray(t, dtype=float)
        if t.ndim == 0:
            return self._one(float(t))
        return np.stack([self._one(float(s)) for s in t], axis=-1)


# --------------------------------------------------------------------------------------------
# The driver
# --------------------------------------------------------------------------------------------


class StepGuard:
    """Step budget of one integration call: a hard limit and an early stiffness alarm.

    The call fails when its steps exceed ``max_steps``, or earlier when, for ``_STREAK``
    consecutive steps, the current step size would need more than the budget to reach the end:
    the signature of an explicit method on a stiff problem (or of a finite-time blow-up).
    """

    def __init__(self, max_steps: int, t_end: float, method: str) -> None:
        self.max_steps, self.t_end, self.method = max_steps, t_end, method
        self.steps = 0
        self.streak = 0

    def failure(self, solver: OdeSolver) -> str | None:
        """None while within budget, else the failure message with advice."""
        self.steps += 1
        h = abs(solver.t - solver.t_old)
        projected = self.steps + (abs(self.t_end - solver.t) / h if h > 0 else math.inf)
        self.streak = self.streak + 1 if projected > self.max_steps else 0
        if self.steps <= self.max_steps and self.streak < _STREAK:
            return None
        advice = ("the problem is probably stiff (use an implicit method, method='Radau' or "
                  "'BDF') or its solution blows up in finite time"
                  if self.method not in ("Radau", "BDF", "LSODA")
                  else "the solution may blow up in finite time, or the tolerances be too tight")
        return (f"step budget exceeded: at t = {solver.t:.6g} the step is {h:.3g}, so "
                f"reaching t = {self.t_end:.6g} needs about {projected:.3g} steps, more than "
                f"max_steps = {self.max_steps} ({self.steps} taken with {self.method}); "
                f"{advice}, or raise `max_steps` if the steps are genuinely needed")


#: Solvers whose steps only call ``solver.fun`` (explicit Runge-Kutta, and our RK4).
_DIRECT: tuple[type[OdeSolver], ...] = (RK23, RK45, DOP853, RK4)


@dataclass
class Piece:
    """One integrated piece: the steps (when recorded), the dense output, how it ended."""

    ts: list[float]
    ys: list[np.ndarray]
    sol: OdeSolution | None
    y_end: np.ndarray
    message: str | None  # None: success
    failure: Failure | None = None


def solve_piece(fun: Callable[[float, np.ndarray], np.ndarray], a: float, b: float,
                y: np.ndarray, solver_class: type[OdeSolver], options: dict[str, Any],
                dense: bool, guard: StepGuard) -> Piece:
    """Integrate one smooth piece with ``solver_class``: ``solve_ivp``'s loop, under ``guard``.

    The same solver calls as :func:`scipy.integrate.solve_ivp` (hence the same numbers), with
    the step budget checked after each step and a non-finite state reported as a failure.
    """
    solver = solver_class(fun, a, y, b, vectorized=False, **options)
    if issubclass(solver_class, _DIRECT):
        # Explicit Runge-Kutta steps call solver.fun, scipy's counting wrapper around
        # np.asarray(fun(t, y)): two Python frames per stage that change nothing here (every
        # callable given to propagate returns a float64 array, and we count evaluations
        # ourselves), 5-8 % of a continuation. Same numbers, bit for bit.
        solver.fun = fun
    ts, ys, interpolants = [a], [y], []
    try:
        while solver.status == "running":
            message = solver.step()
            if solver.status == "failed":
                return Piece(ts, ys, None, solver.y, f"segment [{a:.6g}, {b:.6g}]: {message}",
                             Failure(float(solver.t), np.array(solver.y), "integrator"))
            if dense:
                interpolants.append(solver.dense_output())
            ts.append(solver.t)
            ys.append(solver.y)
            failure = guard.failure(solver)
            if failure is not None:
                return Piece(ts, ys, None, solver.y, failure,
                             Failure(float(solver.t), np.array(solver.y), "step budget"))
    except Diverged as exc:
        where = Failure(float(ts[-1] if exc.t is None else exc.t),
                        np.array(ys[-1] if exc.state is None else exc.state, dtype=float), "state")
        return Piece(ts, ys, None, ys[-1], f"segment [{a:.6g}, {b:.6g}]: {exc}", where)
    sol = None
    if dense:  # RK4: at a step time, the later step's interpolant (exact there)
        sol = OdeSolution(ts, interpolants, alt_segment=solver_class in (BDF, LSODA, RK4))
    return Piece(ts, ys, sol, solver.y, None)


@dataclass
class Propagation:
    """Result of :func:`propagate` (time-first lists; the public functions transpose)."""

    y_out: list[np.ndarray]
    t: np.ndarray
    y: np.ndarray
    sol: Piecewise | None
    success: bool
    message: str
    y_end: np.ndarray
    failure: Failure | None = None


def propagate(funs: Sequence[Callable[[float, np.ndarray], np.ndarray]], t0: float, t1: float,
              y0: np.ndarray, *, period: float | None, breakpoints: tuple[float, ...],
              settings: Settings, h: float | None, t_out: Sequence[float] = (),
              t_eval: np.ndarray | None = None, dense: bool = False, record_steps: bool = False,
              atol: Any = None) -> Propagation:
    """Integrate ``y' = funs[segment](t, y)`` from t0 to t1, restarting at every node.

    ``t_out``: times whose states are returned in ``y_out`` (restart nodes, hence exact);
    ``t_eval``: times sampled from the dense output; ``record_steps``: return every step.
    ``atol`` overrides ``settings.atol`` (the variational system's longer vector).
    """
    t_out = [float(t) for t in t_out]
    too_many = _too_many_pieces(t0, t1, period, breakpoints, len(t_out), settings.max_steps)
    if too_many:
        y = np.asarray(y0, dtype=float)
        return Propagation([y for _ in t_out], np.empty(0), np.empty((0, y.size)), None, False,
                           too_many, y)
    nodes, segments = restart_nodes(t0, t1, period, breakpoints, t_out)
    if h is not None:
        _check_on_grid(list(nodes) + t_out, t0, t1, h)
    y = np.asarray(y0, dtype=float)
    need_steps, want_sol = record_steps or t_eval is not None or dense, dense or t_eval is not None
    out_t: list[float] = []
    out_y: list[np.ndarray] = []
    pieces: list[tuple[float, float, OdeSolution]] = []
    out_index = _nearest(nodes, t_out)  # t_out were merged into nodes
    node_state: list[np.ndarray] = [y]
    success, message = True, "The solver successfully reached the end of the integration interval."
    options = solver_options(settings, h, atol)
    guard = StepGuard(settings.max_steps, t1, settings.method)
    first_step = None
    failure = None
    for a, b, seg in zip(nodes[:-1], nodes[1:], segments, strict=True):
        if first_step is not None:
            options["first_step"] = min(first_step, abs(b - a))
        piece = solve_piece(funs[seg], float(a), float(b), y, settings.solver, options, want_sol,
                            guard)
        if piece.message is not None:
            success, message, failure = False, piece.message, piece.failure
            break
        if not settings.fixed_step and len(piece.ts) >= 2:
            # Carry the step size across the restart: saves the initial-step search and the
            # ramp-up, the main cost of restarting at every breakpoint.
            first_step = abs(piece.ts[-1] - piece.ts[-2]) if len(piece.ts) > 2 else abs(b - a)
        if want_sol and piece.sol is not None:
            pieces.append((float(a), float(b), piece.sol))
        if t_eval is None and need_steps:
            out_t.extend(piece.ts if not out_t else piece.ts[1:])
            out_y.extend(piece.ys if not out_y else piece.ys[1:])
        y = piece.y_end
        node_state.append(y)
    sol = Piecewise(pieces) if pieces else None
    if t_eval is not None and success and sol is not None:
        out_t, out_y = list(t_eval), [sol(t) for t in t_eval]
    return Propagation([node_state[i] if i < len(node_state) else y for i in out_index],
                       np.array(out_t), np.array(out_y), sol, success, message, y, failure)


def _too_many_pieces(t0: float, t1: float, period: float | None, breakpoints: tuple[float, ...],
                     n_out: int, max_steps: int) -> str:
    """Why the restart grid alone would exceed the step budget (each piece takes a step), or ''.

    Counted before the grid is built: a span of 10**12 periods must fail at once, not after
    building 10**12 restart times.
    """
    periods = abs(t1 - t0) / period + 2.0 if breakpoints and period else 0.0
    pieces = periods * (len(breakpoints) + 1) + n_out + 1
    if pieces <= max_steps:
        return ""
    return (f"step budget exceeded before the first step: the span [{t0:.6g}, {t1:.6g}] needs "
            f"about {pieces:.3g} restarts (breakpoints and output times), more than max_steps = "
            f"{max_steps}; shorten the span or raise `max_steps`")


def _nearest(nodes: np.ndarray, times: Sequence[float]) -> list[int]:
    """Index of the node nearest each time (nodes monotonic): O(m log n), not O(m n)."""
    if not times:
        return []
    ascending = nodes[-1] >= nodes[0]
    grid = nodes if ascending else nodes[::-1]
    t = np.asarray(times)
    hi = np.clip(np.searchsorted(grid, t), 1, grid.size - 1)
    lo = hi - 1
    idx = np.where(np.abs(grid[lo] - t) <= np.abs(grid[hi] - t), lo, hi)
    return [int(i) if ascending else int(grid.size - 1 - i) for i in idx]


def _check_on_grid(times: Sequence[float], t0: float, t1: float, h: float) -> None:
    for t in times:
        q = (t - t0) / h
        if abs(q - round(q)) > 1e-7 and t != t1:
            raise ValueError(
                f"with method='RK4' breakpoints and output times must fall on the step grid "
                f"t0 + k h (h = {h:.6g}); time {t:.17g} does not")


# --------------------------------------------------------------------------------------------
# Results and the variational equations
# --------------------------------------------------------------------------------------------


@dataclass(frozen=True)
class FlowResult:
    """Result of :func:`flapping.periodic.integrate.flow`.

    Attributes
    ----------
    t : ndarray, shape (m,)
        Output times: ``t_eval`` if given, else every step the integrator took (segment ends
        included once).
    x : ndarray, shape (n, m)
        States at ``t`` (time along the last axis, as ``solve_ivp``'s ``y``).
    nfev : int
        Number of right-hand-side evaluations (all segments together).
    success : bool
        Whether every segment was integrated to its end.
    message : str
        The integrator's message (of the first failing segment, if any).
    sol : callable or None
        ``sol(t)`` interpolates the solution (``dense_output=True``): each method's dense
        output per segment (cubic Hermite for RK4, fourth order like the scheme).
    failure : Failure or None
        Where a failed integration stopped (``t``, ``state``, ``source``); None on success.
    """

    t: np.ndarray
    x: np.ndarray
    nfev: int
    success: bool
    message: str
    sol: Callable[[Any], np.ndarray] | None = None
    failure: Failure | None = None

    def __post_init__(self) -> None:
        freeze(self)

    @property
    def x_end(self) -> np.ndarray:
        """State at the last output time."""
        return self.x[:, -1]


@dataclass(frozen=True)
class VariationalFlow:
    """Result of :func:`flapping.periodic.integrate.variational_flow` (time along the last axis).

    Attributes
    ----------
    t : ndarray, shape (m,)
        Output times (``t_out``, in the order given; default ``(t1,)``).
    x : ndarray, shape (n, m)
        States at ``t``.
    stm : ndarray, shape (n, n, m)
        State-transition matrices ``Phi(t, t0) = dx(t)/dx(t0)``.
    sensitivity : ndarray, shape (n, n_p, m) or None
        ``dx(t)/dparams`` for the parameters ``params`` (``None`` without parameters).
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
    failure : Failure or None
        Where a failed integration stopped (``t``, the state ``x`` there, ``source``); None on
        success.
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
    failure: Failure | None = None

    def __post_init__(self) -> None:
        freeze(self)

    @property
    def x_end(self) -> np.ndarray:
        """State at the last output time, shape (n,)."""
        return self.x[:, -1]

    @property
    def stm_end(self) -> np.ndarray:
        """State-transition matrix at the last output time, shape (n, n)."""
        return self.stm[:, :, -1]

    @property
    def sensitivity_end(self) -> np.ndarray | None:
        """Parameter sensitivity at the last output time, shape (n, n_p), or None."""
        return None if self.sensitivity is None else self.sensitivity[:, :, -1]


class VariationalRHS:
    """Right-hand side of ``(x, Phi, S, int tr J)``: the variational bookkeeping solve_ivp lacks.

    ``f`` is a :class:`Checked` ``g(t, x)``; ``jac`` and ``pjac`` are Checked too, or None for
    central finite differences (:func:`flapping._numdiff.central_jacobian`) of ``f`` in x or params.
    """

    def __init__(self, f: Checked, jac: Checked | None, pjac: Checked | None, n: int, n_p: int,
                 trace: bool) -> None:
        self.f, self.jac, self.pjac, self.n, self.n_p, self.trace = f, jac, pjac, n, n_p, trace

    def __call__(self, t: float, y: np.ndarray) -> np.ndarray:
        n, n_p, f = self.n, self.n_p, self.f
        i_s = n + n * n
        i_tr = i_s + n * n_p
        x = y[:n]
        fx = f(t, x)
        J = central_jacobian(lambda z: f(t, z), x) if self.jac is None else self.jac(t, x)
        out = np.empty_like(y)
        out[:n] = fx
        out[n:i_s] = (J @ y[n:i_s].reshape(n, n)).ravel()
        if n_p:
            params = f.params
            assert params is not None
            dfdp = (central_jacobian(lambda v: f.at(t, x, v), params) if self.pjac is None
                    else self.pjac(t, x))
            out[i_s:i_tr] = (J @ y[i_s:i_tr].reshape(n, n_p) + dfdp).ravel()
        if self.trace:
            out[i_tr] = np.trace(J)
        return out


def variational(funs: Sequence[Callable[..., Any]], jacs: Sequence[Callable[..., Any] | None],
                pjacs: Sequence[Callable[..., Any] | None], t0: float, t1: float, x0: np.ndarray,
                *, args: tuple[Any, ...], params: np.ndarray | None, trace: bool,
                settings: Settings, h: float | None, period: float | None,
                breakpoints: tuple[float, ...], t_out: Sequence[float],
                stm_atol: float | None = None) -> VariationalFlow:
    """State, state-transition matrix, sensitivities, trace integral at ``t_out`` (trusted inputs).

    ``funs``, ``jacs``, ``pjacs``: the user's callables, one per segment (None entries: finite
    differences). See :func:`flapping.periodic.integrate.variational_flow`.
    """
    n = x0.size
    n_p = 0 if params is None else params.size
    counter, jcounter = Counter(), Counter()
    rhss = [VariationalRHS(
        Checked(f, args, params, (n,), counter),
        None if J is None else Checked(J, args, params, (n, n), jcounter, "jac"),
        None if P is None else Checked(P, args, params, (n, n_p), jcounter, "param_jac", True),
        n, n_p, trace) for f, J, P in zip(funs, jacs, pjacs, strict=True)]
    y0 = np.concatenate([x0, np.eye(n).ravel(), np.zeros(n * n_p), np.zeros(1 if trace else 0)])
    atol = None
    if stm_atol is not None:
        atol = np.concatenate([np.full(n, settings.atol, dtype=float)
                               if np.ndim(settings.atol) == 0 else settings.atol,
                               np.full(y0.size - n, float(stm_atol))])
    ys, success, message, failure = [y0 for _ in t_out], True, "empty interval", None
    if t1 != t0:
        out = propagate(rhss, t0, t1, y0, period=period, breakpoints=breakpoints,
                        settings=settings, h=h, t_out=t_out, atol=atol)
        success, message, ys = out.success, out.message, out.y_out
        if out.failure is not None:  # the user's state, without the matrices
            failure = Failure(out.failure.t, out.failure.state[:n], out.failure.source)
    Y = np.array(ys).T if success else np.full((y0.size, len(t_out)), np.nan)
    nn = n * n
    return VariationalFlow(
        t=np.array(t_out, dtype=float), x=Y[:n].copy(),
        stm=Y[n:n + nn].reshape(n, n, -1).copy(),
        sensitivity=Y[n + nn:n + nn + n * n_p].reshape(n, n_p, -1).copy() if n_p else None,
        trace_integral=Y[-1].copy() if trace else None,
        nfev=counter.n, njev=jcounter.n, success=success, message=message, failure=failure)

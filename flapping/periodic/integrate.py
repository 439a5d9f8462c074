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
  the parameter sensitivities ``S' = J S + df/dparams`` and the quadrature ``int trace J dt``
  (Liouville's formula). These feed the Jacobian of the shooting residual (eq. 38) and the
  monodromy matrix of Floquet theory.

Besides scipy's methods (``"DOP853"``, ``"RK45"``, ``"Radau"``, ...), ``method="RK4"`` is the
classical fixed-step fourth-order Runge-Kutta scheme the paper uses (step ``period / 1024``, i.e.
``2**-10`` of a period): :class:`flapping.periodic.rk4.RK4`, an
:class:`~scipy.integrate.OdeSolver` that ``solve_ivp`` accepts too. Any OdeSolver subclass may be
passed as ``method``.

Conventions (all of :mod:`flapping.periodic`)
---------------------------------------------
* Time along the last axis, as ``solve_ivp``'s ``y``: :attr:`FlowResult.x` and
  :attr:`VariationalFlow.x` are ``(n, m)``, :attr:`VariationalFlow.stm` is ``(n, n, m)``,
  :attr:`VariationalFlow.sensitivity` ``(n, n_p, m)``; ``x_end``, ``stm_end``,
  ``sensitivity_end`` give the last time.
* Counters as scipy names them: ``nfev`` (evaluations of ``fun``, finite differences included),
  ``njev`` (evaluations of ``jac`` and ``param_jac``).
* ``rtol``, ``atol``, ``method``, ``rk4_steps``, ``max_steps`` wherever something is integrated.
* Arguments are checked once, here; numbers become float64, bools and strings are refused.

Safety
------
Every value of ``fun`` and ``jac`` is checked: a wrong shape or a non-finite value at a finite
state is a ``ValueError`` naming the callable, the time and the state (``solve_ivp`` fed NaN
shrinks its step forever). Every integration has a step budget, ``max_steps`` (default
100 000 steps per call): beyond it, or as soon as the step size has stayed, for 100 steps, too
small to reach the end within it (an explicit method on a stiff problem), the integration stops
with ``success=False`` and a message that suggests an implicit method (``method="Radau"``).
A solution that overflows to a non-finite state also ends with ``success=False``.

Time grid
---------
With ``period`` ``T`` and ``breakpoints`` ``(b_1, ..., b_m)`` (fractions of the period in (0, 1),
increasing), segment ``k`` of period ``j`` is ``[(j + b_k) T, (j + b_{k+1}) T]`` with ``b_0 = 0``
and ``b_{m+1} = 1``; a sequence ``fun`` has ``m + 1`` callables, the ``k``-th used on segment ``k``
of every period, including at its two end points.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from scipy.integrate import OdeSolver

import flapping._validation as check
from flapping.periodic import _segments as seg
from flapping.periodic import settings as opt
from flapping.periodic._checks import first_call
from flapping.periodic._segments import FlowResult, VariationalFlow

__all__ = ["FlowResult", "VariationalFlow", "flow", "variational_flow", "SCIPY_METHODS"]

#: Methods handed to scipy's solvers by name; ``"RK4"`` is ours (:mod:`flapping.periodic.rk4`).
SCIPY_METHODS: tuple[str, ...] = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")

Method = str | type[OdeSolver]


def _check_common(t_span: Any, x0: Any, method: Any, rtol: Any, atol: Any, rk4_steps: Any,
                  max_steps: Any, period: Any, breakpoints: Any
                  ) -> tuple[float, float, np.ndarray, seg.Settings, float | None,
                             tuple[float, ...], float | None]:
    """The checks shared by :func:`flow` and :func:`variational_flow`.

    Returns ``(t0, t1, x0, settings, period, breakpoints, h)`` with ``h`` the RK4 step or None.
    """
    t0, t1 = seg.check_span(t_span)
    x = check.vector("x0", x0)
    settings = seg.check_settings(method, rtol, atol, rk4_steps, max_steps)
    opt.check_scaled("atol", settings.atol, x, opt.TOL_CEILING)
    T = None if period is None else check.positive("period", period)
    b = seg.check_breakpoints(breakpoints)
    h = seg.fixed_step(settings, t0, t1, T, b)
    return t0, t1, x, settings, T, b, h


def _first_times(t0: float, t1: float, period: float | None,
                 breakpoints: tuple[float, ...], max_steps: int) -> list[tuple[int, float]]:
    """``(segment, time)``: each segment the integration visits, with the start of its first
    piece (a time on its closed segment), in the order visited. Empty if nothing is
    integrated, or the restarts alone exceed the budget (:func:`~flapping.periodic._segments.
    propagate` then fails by itself)."""
    if not breakpoints:
        return [(0, t0)]
    if t1 == t0 or seg._too_many_pieces(t0, t1, period, breakpoints, 0, max_steps):
        return []
    nodes, segments = seg.restart_nodes(t0, t1, period, breakpoints)
    first: dict[int, float] = {}
    for a, k in zip(nodes[:-1], segments, strict=True):
        first.setdefault(int(k), float(a))
        if len(first) == len(breakpoints) + 1:
            break
    return list(first.items())


def _probe(funs: Sequence[Callable[..., Any]], jacs: Sequence[Callable[..., Any] | None],
           t0: float, t1: float, x0: np.ndarray, extra: tuple[Any, ...], period: float | None,
           breakpoints: tuple[float, ...], settings: seg.Settings, given: str) -> None:
    """The callables of the integration, each called once at ``x0`` and the start of its first
    piece, and checked (:func:`~flapping.periodic._checks.first_call`): an error names
    ``fun``, ``jac``, ``x0`` or ``args`` before anything is integrated. Not counted in
    ``nfev``: a check, not a step."""
    n, tail = x0.size, ", params" if given.endswith("`params`") else ""
    for i, (k, t) in enumerate(_first_times(t0, t1, period, breakpoints, settings.max_steps)):
        first_call(funs[k], "fun", t, x0, extra, (n,), call=f"fun(t, x, *args{tail})",
                   given=given, first=i == 0)
        jac = jacs[k]
        if jac is not None:
            first_call(jac, "jac", t, x0, extra, (n, n), call=f"jac(t, x, *args{tail})",
                       given=given)


def _check_t_out(t_out: Any, t0: float, t1: float, max_steps: int) -> tuple[float, ...]:
    """``t_out`` as floats within the span, in the order given; each is a restart of the
    integration, so more than ``max_steps`` of them is refused at once (1e7 took a minute to
    convert before the step budget refused them)."""
    times = check.array("t_out", t_out)
    if times.ndim != 1:
        raise ValueError(f"`t_out` must be a 1-D sequence of times; got shape {times.shape}")
    if times.size > max_steps:
        raise ValueError(f"`t_out` has {times.size} times, more than max_steps = {max_steps} "
                         f"(each is a restart of the integration, which takes a step)")
    outside = (times < min(t0, t1)) | (times > max(t0, t1))
    if outside.any():
        raise ValueError(f"`t_out` times must lie within t_span ({t0!r}, {t1!r}), got "
                         f"{float(times[outside][0])!r}")
    return tuple(times.tolist())


def flow(
    fun: Callable[..., Any] | Sequence[Callable[..., Any]],
    t_span: tuple[float, float],
    x0: Any,
    *,
    breakpoints: Sequence[float] = (),
    period: float | None = None,
    method: Method = "DOP853",
    rtol: float = opt.ORBIT_RTOL,
    atol: float = opt.ORBIT_ATOL,
    rk4_steps: int = 1024,
    max_steps: int | None = None,
    t_eval: Any = None,
    dense_output: bool = False,
    args: tuple[Any, ...] = (),
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
    method : str or OdeSolver subclass, optional
        ``"DOP853"`` (default), any other :func:`~scipy.integrate.solve_ivp` method, or ``"RK4"``
        (classical fixed step ``period / rk4_steps``, or ``(t1 - t0) / rk4_steps`` without period;
        breakpoints must then fall on step boundaries).
    rtol, atol : float, optional
        Tolerances of the adaptive methods (ignored by RK4).
    rk4_steps : int, optional
        RK4 steps per period; 1024 (``2**-10`` of a period) is the paper's choice (Sec. III.A).
    max_steps : int, optional
        Step budget of the call (default 100 000); see the module notes.
    t_eval : array_like, optional
        Times at which to report the solution (interpolated by the dense output).
    dense_output : bool, optional
        Return a callable ``sol``.
    args : tuple, optional
        Extra arguments of ``fun``.

    Returns
    -------
    FlowResult
        Times, states (shape (n, m)), number of right-hand-side evaluations, success flag
        (``False`` with a message when the integrator gave up or the step budget ran out).

    Raises
    ------
    ValueError
        For a bad argument (message names it and the accepted range: ``t_eval`` must be finite,
        within ``t_span``, sorted in the direction of integration and of at most
        ``CAPS["t_eval"]`` = 10**6 points; ``rtol`` in (0, 1e-3]; ``atol`` at most
        ``1e-2 max(1, |x0|)``), a wrong-shaped ``fun`` output (naming ``x0`` when its length
        is the likelier culprit), ``fun`` raising a ValueError or IndexError at its first call
        (naming ``x0`` and ``args``), or RK4 breakpoints off the step grid.
    NonFiniteError
        A ValueError: ``fun`` returned NaN or infinity at a finite state; carries ``t``,
        ``state``, ``source`` and ``value``.
    TypeError
        ``args`` does not fit ``fun``'s signature, or ``fun`` returned None, a string, or
        complex or boolean values (checked at the first call).

    Notes
    -----
    A solution that overflows, or an integration that runs out of its step budget, is not an
    error here: the result has ``success=False``, and ``failure`` says where (``t``, ``state``,
    ``source``).
    """
    t0, t1, x0, settings, period, breakpoints, h = _check_common(
        t_span, x0, method, rtol, atol, rk4_steps, max_steps, period, breakpoints)
    args = check.call_args(args)
    dense_output = check.boolean("dense_output", dense_output)
    if t_eval is not None:
        t_eval = opt.check_times("t_eval", t_eval, t0, t1)
    user_funs = seg.segment_callables(fun, len(breakpoints) + 1, "fun")
    _probe(user_funs, (None,) * len(user_funs), t0, t1, x0, args, period, breakpoints,
           settings, f"`args` = {check._show(args)}")
    counter = seg.Counter()
    funs = tuple(seg.Checked(f, args, None, x0.shape, counter) for f in user_funs)
    if t1 == t0:
        return FlowResult(np.array([t0]), x0[:, None], 0, True, "empty interval", None)
    out = seg.propagate(funs, t0, t1, x0, period=period, breakpoints=breakpoints,
                        settings=settings, h=h, t_eval=t_eval, dense=dense_output,
                        record_steps=True)
    x = out.y.T if out.y.size else np.empty((x0.size, 0))
    return FlowResult(out.t, x, counter.n, out.success, out.message,
                      out.sol if dense_output else None, out.failure)


def variational_flow(
    fun: Callable[..., Any] | Sequence[Callable[..., Any]],
    jac: Callable[..., Any] | Sequence[Callable[..., Any]] | None,
    t_span: tuple[float, float],
    x0: Any,
    *,
    breakpoints: Sequence[float] = (),
    period: float | None = None,
    method: Method = "DOP853",
    rtol: float = opt.ORBIT_RTOL,
    atol: float = opt.ORBIT_ATOL,
    stm_atol: float | None = None,
    rk4_steps: int = 1024,
    max_steps: int | None = None,
    t_out: Sequence[float] | np.ndarray | None = None,
    params: Any = None,
    param_jac: Callable[..., Any] | Sequence[Callable[..., Any]] | None = None,
    trace: bool = False,
    args: tuple[Any, ...] = (),
) -> VariationalFlow:
    """Integrate the state with its variational equations (paper eqs. 42-49).

    Integrates ``x' = f``, ``Phi' = J Phi`` (``Phi(t0) = I``), and with parameters
    ``S' = J S + df/dparams`` (``S(t0) = 0``), plus ``int trace J dt`` as an extra quadrature state.
    The extended system is integrated as one ODE with the same segments and error control
    (``method="RK4"`` then gives the exact derivative of the discrete RK4 map, because RK methods
    commute with linearisation).

    Parameters
    ----------
    fun : callable or sequence of callables
        ``fun(t, x, *args)`` or, with ``params``, ``fun(t, x, *args, params)``; a sequence gives one
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
    breakpoints, period, method, rtol, atol, rk4_steps, max_steps, args
        As in :func:`flow`.
    stm_atol : float, optional
        Absolute tolerance for the matrix (and sensitivity) components; default ``atol``. A large
        value takes them out of the step-size control (the step is then set by the state alone):
        cheaper, and enough where the matrix only steers a Newton iteration.
    t_out : sequence of float, optional
        Times (within ``t_span``) at which to report; default ``(t1,)``. The integrator restarts
        at each (so RK4 needs them on its grid); at most ``max_steps`` of them.
    params : array_like, optional
        Parameters ``params``, passed as the last argument of ``fun``, ``jac``, ``param_jac``; their
        sensitivities are integrated.
    param_jac : callable or sequence of callables, optional
        ``df/dparams``, shape (n, n_p); default central finite differences of ``fun`` in ``params``.
    trace : bool, optional
        Also integrate ``int trace J dt`` (Liouville's formula).

    Returns
    -------
    VariationalFlow
        States ``(n, m)``, state-transition matrices ``(n, n, m)``, sensitivities
        ``(n, n_p, m)``, trace integrals ``(m,)`` at ``t_out``, and evaluation counts; NaN
        arrays and ``success=False`` when the integration failed.

    Raises
    ------
    ValueError
        For a bad argument (as in :func:`flow`), ``fun``/``jac``/``param_jac`` returning the
        wrong shape, or ``fun``/``jac`` raising a ValueError or IndexError at the first call
        (naming ``x0`` and ``args``).
    NonFiniteError
        A ValueError: a callable returned NaN or infinity at a finite state (with ``t``,
        ``state``, ``source``, ``value``).
    TypeError
        ``args`` (and ``params``) do not fit the signature of ``fun`` or ``jac``, or either
        returned None, a string, or complex or boolean values (checked at the first call).
    """
    t0, t1, x0, settings, period, breakpoints, h = _check_common(
        t_span, x0, method, rtol, atol, rk4_steps, max_steps, period, breakpoints)
    args = check.call_args(args)
    n_seg = len(breakpoints) + 1
    funs = seg.segment_callables(fun, n_seg, "fun")
    jacs = (None,) * n_seg if jac is None else seg.segment_callables(jac, n_seg, "jac")
    params = None if params is None else check.vector("params", np.atleast_1d(params))
    if param_jac is not None and params is None:
        raise ValueError("`param_jac` needs `params`")
    pjacs = ((None,) * n_seg if param_jac is None
             else seg.segment_callables(param_jac, n_seg, "param_jac"))
    given = f"`args` = {check._show(args)}" + ("" if params is None else " and `params`")
    _probe(funs, jacs, t0, t1, x0, args if params is None else args + (params,), period,
           breakpoints, settings, given)
    times = (t1,) if t_out is None else _check_t_out(t_out, t0, t1, settings.max_steps)
    if stm_atol is not None:
        stm_atol = check.positive("stm_atol", stm_atol)
    return seg.variational(funs, jacs, pjacs, t0, t1, x0, args=args, params=params,
                           trace=check.boolean("trace", trace), settings=settings, h=h,
                           period=period,
                           breakpoints=breakpoints, t_out=times, stm_atol=stm_atol)


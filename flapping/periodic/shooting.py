"""The optimized shooting method (Dednam & Botha 2015; paper Sec. III.A, eqs. 30-38).

A periodic orbit of ``x' = f(t, x)`` (eq. 30) satisfies ``x(t + T) = x(t)`` (eq. 31). In normalised
time ``tau = t / T`` the orbit has period one (eq. 36), and the optimized shooting method finds the
initial state (and, for an autonomous system, the period) that minimise the residual (eq. 38, with
the paper's p residual blocks called m = ``n_points`` here)

    R = (x(1) - x(0), x(1 + delta) - x(delta), ..., x(1 + (m-1) delta) - x((m-1) delta))

with the Levenberg-Marquardt algorithm (eqs. 32-35), here MINPACK's ``lmder`` through
:func:`scipy.optimize.least_squares` (``method="lm"``).

What we change with respect to the paper (which differences the residual over a fixed-step RK4
integration, step ``2**-10`` of a period):

* ``jacobian="variational"`` (default): the Jacobian of R comes from the variational equations
  integrated with the state, one integration per Levenberg-Marquardt Jacobian, exact up to the
  integration tolerance, instead of one extra shooting integration per unknown;
* adaptive high-order integration (DOP853, ``rtol=1e-11``) instead of RK4 at ``2**-10``, which
  limits the period to about eight digits (see the validation chapter);
* segment-aware integration (:mod:`flapping.periodic.integrate`): right-hand sides that jump at a
  breakpoint (stroke reversal) are integrated one smooth segment at a time.

The paper's method is available as ``jacobian="finite-difference", method="RK4"``.

Structure: :func:`find_periodic_orbit` checks its arguments once and builds a
:class:`~flapping.periodic._problem.ShootingProblem` (unknowns <-> ``(x0, T, params)``, residual,
Jacobian, counters); Levenberg-Marquardt solves it; the answer and its diagnostics come back as a
:class:`PeriodicOrbit`.

Phase condition. An autonomous system's orbit can be started anywhere on it, so one more
condition than the periodicity residuals is needed. ``fixed`` (a component held: a Poincare
section), ``n_points >= 2`` or an ``extra_residual`` provide it; with none of them, the plain call
``find_periodic_orbit(fun, x0, period)`` holds the component of ``x0`` along which the vector
field at the guess is largest (the coordinate plane through the guess most transversal to the
flow). :attr:`PeriodicOrbit.phase_condition` says which was used.

No false successes. Every autonomous residual also vanishes at an equilibrium (any T) and as
``T -> 0``. An answer whose vector field satisfies ``|f(x0)| T <= sqrt(eps) max(1, |x0|,
|x0_guess|)`` (the state would move by less than the shooting's accuracy over a period) is refused
as an equilibrium, and a period below ``min_period`` as the collapse ``T -> 0``: both raise
:class:`~flapping.errors.ConvergenceError`, never ``success=True``.

Conventions as in :mod:`flapping.periodic.integrate`: counters ``nfev`` (evaluations of ``fun``),
``njev`` (of ``jac``/``param_jac``), ``nit`` (Levenberg-Marquardt iterations); ``rtol``,
``atol``, ``method``, ``rk4_steps``, ``max_steps`` for the integrations; arguments checked once.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from scipy.integrate import OdeSolver
from scipy.optimize import least_squares

import flapping._validation as check
from flapping.errors import AliasedPeriodWarning, ConvergenceError
from flapping.periodic import _segments as seg
from flapping.periodic import settings as opt
from flapping.periodic._checks import first_call, numeric
from flapping.periodic._problem import (
    IntegrationFailed,
    MultipleShootingProblem,
    ShootingProblem,
    ShootingSetup,
)
from flapping.periodic._readonly import freeze
from flapping.results import Status

__all__ = [
    "DEFAULTS",
    "PeriodicOrbit",
    "find_periodic_orbit",
    "JACOBIANS",
]

#: Accepted values of ``jacobian``.
JACOBIANS: tuple[str, ...] = ("variational", "finite-difference")

_EPS = float(np.finfo(float).eps)

#: Relative motion over a period below which an autonomous "orbit" is an equilibrium.
_EQUILIBRIUM = math.sqrt(_EPS)

#: An autonomous orbit that returns to ``x0`` at ``T / k`` (k = 2 .. ALIAS_ORDERS) within this
#: distance, relative to ``max(1, |x0|)``, is the orbit of period ``T / k`` traversed k times.
ALIAS_TOL = 1e-6
ALIAS_ORDERS = 8

#: Residual points closer than this in phase (fraction of the period) sample the same phase.
_ALIAS_PHASE = 1e-9


@dataclass(frozen=True)
class PeriodicOrbit:
    """A periodic orbit found by :func:`find_periodic_orbit`, with its diagnostics.

    Attributes
    ----------
    x0 : ndarray, shape (n,)
        Initial state on the orbit (fixed components at their given values).
    period : float
        Period ``T`` (the given one for a forced system).
    params : ndarray or None
        Converged free parameters.
    success : bool
        Converged to ``residual_norm <= tol`` (and, autonomous, neither an equilibrium nor a
        collapsed period).
    message : str
        Why the iteration stopped (MINPACK's reason, or why the answer was refused).
    residual : ndarray
        Final residual vector (eq. 38, then the extra residuals).
    residual_norm : float
        Its Euclidean norm.
    residual_history : ndarray
        Residual norm at every residual evaluation requested by Levenberg-Marquardt (trial points
        included; finite-difference probes excluded).
    iteration_history : ndarray
        Residual norm at every point where the Jacobian was evaluated (the accepted iterates),
        followed by the final one.
    nit : int
        Levenberg-Marquardt iterations (Jacobian evaluations).
    n_residual_evals : int
        Residual evaluations requested by Levenberg-Marquardt.
    nfev : int
        Evaluations of ``fun`` in total (residuals, Jacobians, finite differences; the one
        diagnostic evaluation of the equilibrium check is not counted).
    njev : int
        Evaluations of the analytic ``jac``/``param_jac`` (0 without them).
    jacobian : str
        ``"variational"`` or ``"finite-difference"``.
    method : str
        Integration method.
    autonomous : bool
        Whether the period was an unknown.
    unknowns : ndarray
        The final vector of unknowns (free components of x0, then T, then params).
    phase_condition : str
        What fixed the phase of an autonomous orbit (see the module notes), or why none was
        needed.
    segment_states : ndarray, shape (n, M) or None
        Multiple shooting: the state at the start of each of the M segments (time along the last
        axis; the first column is ``x0``). Single shooting: ``x0`` as one column.
    status : Status
        The outcome from the package's one status table (:class:`flapping.results.Status`):
        ``SUCCESS``, ``INTEGRATION_FAILED``, ``MAX_EVALUATIONS`` (Levenberg-Marquardt's budget),
        ``RESIDUAL_ABOVE_TOL``, or ``FAILED`` (converged to an equilibrium or a collapsed period).
    """

    x0: np.ndarray
    period: float
    params: np.ndarray | None
    success: bool
    message: str
    residual: np.ndarray
    residual_norm: float
    residual_history: np.ndarray
    iteration_history: np.ndarray
    nit: int
    n_residual_evals: int
    nfev: int
    njev: int
    jacobian: str
    method: str
    autonomous: bool
    unknowns: np.ndarray
    phase_condition: str
    segment_states: np.ndarray | None = None
    status: Status = Status.SUCCESS

    def __post_init__(self) -> None:
        freeze(self)

    @property
    def segments(self) -> int:
        """Number M of shooting segments (1: single shooting)."""
        return 1 if self.segment_states is None else int(self.segment_states.shape[1])


@dataclass(frozen=True)
class _Stopping:
    """Checked options of the Levenberg-Marquardt iteration and of the acceptance test."""

    tol: float
    xtol: float
    ftol: float
    max_nfev: int | None
    min_period: float


@dataclass(frozen=True)
class _Outcome:
    """How the Levenberg-Marquardt solve ended."""

    z: np.ndarray
    residual: np.ndarray
    message: str
    status_ok: bool
    failed: bool
    njev: int


def _check_fixed(fixed: Any, n: int) -> tuple[int, ...]:
    message = f"`fixed` must be a sequence of distinct integer indices in [0, {n}), got {fixed!r}"
    try:
        items = list(fixed)
    except TypeError:
        raise ValueError(message) from None
    for raw in items:
        if isinstance(raw, (bool, np.bool_)) or not isinstance(raw, (int, np.integer)):
            raise ValueError(message)
        if not 0 <= raw < n:
            raise ValueError(message)
    if len(set(items)) != len(items):
        raise ValueError(message)
    return tuple(int(i) for i in items)


def _check_stopping(tol: Any, xtol: Any, ftol: Any, max_nfev: Any, min_period: Any,
                    T: float, x: np.ndarray) -> _Stopping:
    opt.check_scaled("tol", tol, x)  # an absolute residual norm: its ceiling scales with x0
    return _Stopping(
        tol=tol,
        xtol=check.real("xtol", xtol, low=_EPS, high=opt.TOL_CEILING),
        ftol=check.real("ftol", ftol, low=_EPS, high=opt.TOL_CEILING),
        max_nfev=max_nfev,
        min_period=1e-2 * T if min_period is None else check.positive("min_period", min_period),
    )


def _check_shape_options(settings: seg.Settings, n_points: Any, delta: Any
                         ) -> tuple[int, float]:
    n_points = opt.capped("n_points", n_points)
    delta = check.real("delta", delta, low=0.0, high=1.0, low_open=True, high_open=True)
    _warn_aliased_sampling(n_points, delta)
    steps = settings.rk4_steps
    if settings.fixed_step and n_points > 1 and abs(delta * steps - round(delta * steps)) > 1e-9:
        raise ValueError(
            f"with method='RK4', `delta` must be a multiple of 1/rk4_steps = 1/{steps} so that "
            f"the residual points fall on the step grid, got delta={delta!r}")
    return n_points, delta


def _warn_aliased_sampling(n_points: int, delta: float) -> None:
    """Warn when two residual points ``k delta`` fall on the same phase of the period."""
    if n_points < 2:
        return
    phase = np.sort(np.mod(np.arange(n_points) * delta, 1.0))
    gaps = np.diff(np.append(phase, phase[0] + 1.0))
    if gaps.min() <= _ALIAS_PHASE:
        warnings.warn(
            f"aliased sampling: with n_points = {n_points} and delta = {delta!r} two residual "
            f"points k delta fall on the same phase of the period (gap {gaps.min():.2e}), so "
            f"their residual blocks repeat each other; keep (n_points - 1) * delta < 1",
            AliasedPeriodWarning, stacklevel=4)


def _check_segments(settings: seg.Settings, segments: Any, n_points: int) -> int:
    segments = opt.capped("segments", segments)
    if segments > 1 and n_points > 1:
        raise ValueError(f"`segments` > 1 (multiple shooting) needs n_points = 1, got "
                         f"n_points={n_points}: the continuity conditions replace eq. (38)'s "
                         f"extra residual blocks")
    if settings.fixed_step and settings.rk4_steps % segments:
        raise ValueError(f"with method='RK4', `rk4_steps` ({settings.rk4_steps}) must be a "
                         f"multiple of `segments` ({segments})")
    return segments


def _check_callables(fun: Any, jac: Any, param_jac: Any, n_seg: int, has_params: bool
                     ) -> tuple[tuple[Any, ...], tuple[Any, ...], tuple[Any, ...]]:
    funs = seg.segment_callables(fun, n_seg, "fun")
    jacs = (None,) * n_seg if jac is None else seg.segment_callables(jac, n_seg, "jac")
    if param_jac is not None and not has_params:
        raise ValueError("`param_jac` needs `free_params`")
    pjacs = ((None,) * n_seg if param_jac is None
             else seg.segment_callables(param_jac, n_seg, "param_jac"))
    return funs, jacs, pjacs


def _probe(setup: ShootingSetup, problem_counter: seg.Counter) -> tuple[np.ndarray, int]:
    """Evaluate each segment's ``fun`` and ``extra_residual`` at the initial guess.

    A wrong shape or a non-finite value is then a ValueError here, not an obscure failure
    inside MINPACK. Returns ``f`` of the first segment at ``(0, x0)`` and the extra length.
    """
    n, x = setup.x_init.size, setup.x_init
    extra = setup.args if setup.p_init is None else setup.args + (setup.p_init,)
    tail, given = (("", f"`args` = {check._show(setup.args)}") if setup.p_init is None else
                   (", params", f"`args` = {check._show(setup.args)} and `free_params`"))
    values = []
    n_p = 0 if setup.p_init is None else setup.p_init.size
    for k, (f, J, P) in enumerate(zip(setup.funs, setup.jacs, setup.pjacs, strict=True)):
        t = setup.T_init * (setup.breakpoints[k - 1] if k else 0.0)
        problem_counter.n += 1
        values.append(first_call(f, "fun", t, x, extra, (n,), call=f"fun(t, x, *args{tail})",
                                 given=given, first=k == 0))
        # jac and param_jac once each too (not counted in njev: a check, like _refusal's call)
        if J is not None:
            first_call(J, "jac", t, x, extra, (n, n), call=f"jac(t, x, *args{tail})",
                       given=given)
        if P is not None:
            first_call(P, "param_jac", t, x, extra, (n, n_p), reshape=True,
                       call=f"param_jac(t, x, *args{tail})", given=given)
    n_extra = 0
    if setup.extra_residual is not None:
        try:
            raw = setup.extra_residual(setup.x_init.copy(), setup.T_init, setup.p_init)
        except Exception as exc:  # the user's callable: its error, with where it was raised
            exc.add_note("(raised by `extra_residual` at its first call, "
                         "extra_residual(x0, period, params) at the guess)")
            raise
        extra0 = np.atleast_1d(numeric(raw, "extra_residual", "at the guess",
                                       "a 1-D array of real numbers"))
        if extra0.ndim != 1:
            raise ValueError(f"`extra_residual` must return a 1-D array, got shape {extra0.shape}")
        n_extra = extra0.size
    return values[0], n_extra


def _phase_condition(setup: ShootingSetup, f0: np.ndarray, fixed_given: bool
                     ) -> tuple[ShootingSetup, str]:
    """The setup with a phase condition added if an autonomous problem lacks one, and its name."""
    if not setup.autonomous:
        return setup, "none: the period is known (forced system)"
    if fixed_given:
        return setup, f"fixed: x[{', '.join(map(str, setup.fixed))}] held at the guess"
    if setup.n_residuals >= setup.n_unknowns:
        how = (f"{setup.n_points} residual blocks" if setup.n_points > 1 else "")
        how += (" and " if how and setup.n_extra else "") + ("extra_residual" if setup.n_extra
                                                              else "")
        return setup, f"none imposed: {how} leave the phase to Levenberg-Marquardt"
    k = int(np.argmax(np.abs(f0)))
    chosen = replace(setup, fixed=(k,))
    return chosen, (f"fixed: x[{k}] held at {setup.x_init[k]:.17g} (chosen: the component of "
                    f"largest |f| at the guess, {abs(f0[k]):.3g})")


def _check_size(setup: ShootingSetup) -> None:
    n, n_p = setup.x_init.size, 0 if setup.p_init is None else setup.p_init.size
    n_unknowns, n_residuals = setup.n_unknowns, setup.n_residuals
    if n_unknowns == 0:
        raise ValueError("nothing to solve for: every component is `fixed` and the period is known")
    if n_residuals < n_unknowns:
        raise ValueError(
            f"too few residuals for the unknowns: n_points={setup.n_points} gives "
            f"{n * setup.n_points} periodicity residuals (+{setup.n_extra} extra) for "
            f"{n_unknowns} unknowns ({n - len(setup.fixed)} free components of x0"
            f"{', T' if setup.autonomous else ''}{f', {n_p} parameters' if n_p else ''}); raise "
            f"`n_points`, hold a component with `fixed` (a phase condition), or add an "
            f"`extra_residual`")


def _solve(problem: ShootingProblem, stopping: _Stopping) -> _Outcome:
    """Levenberg-Marquardt (MINPACK ``lmder``) on the problem; failures become an outcome."""
    max_nfev = stopping.max_nfev or min(100 * (problem.setup.n_unknowns + 1),
                                        opt.CAPS["max_nfev"])
    failure = None
    try:
        result = least_squares(problem.residual, problem.z0, jac=problem.jacobian, method="lm",
                               x_scale="jac", xtol=stopping.xtol, ftol=stopping.ftol,
                               gtol=_EPS * 10, max_nfev=max_nfev)
        # The residual of the final iterate, from the discretisation the iteration used (the
        # variational integration takes other steps than the plain one; on an expanding orbit
        # the two differ by their global errors, ~1e-10 on Lorenz).
        r = problem.residual(result.x)
        return _Outcome(result.x, r, result.message, result.status > 0, False, int(result.njev))
    except IntegrationFailed as exc:
        failure = f"the iteration failed: {exc}"
    except (np.linalg.LinAlgError, FloatingPointError, OverflowError) as exc:
        failure = f"numerical failure during the iteration: {exc}"
    r = (problem.last_residual if problem.last_residual is not None
         else np.full(problem.setup.n_residuals, np.nan))
    return _Outcome(problem.last_good, r, failure, False, True, 0)


def _refusal(problem: ShootingProblem, x: np.ndarray, T: float, params: np.ndarray | None,
             min_period: float) -> str | None:
    """Why a converged autonomous answer is not a periodic orbit (None if it is one)."""
    if not min_period <= T:
        return (f"the period collapsed to T = {T:.3e} < min_period = {min_period:.3e}: the "
                f"trivial solution T -> 0 of the autonomous residual (no periodic orbit near the "
                f"guess, or an equilibrium)")
    s = problem.setup
    # One evaluation outside the counters: a diagnostic, not part of the iteration.
    extra = s.args if params is None else s.args + (params,)
    fx = np.asarray(s.funs[0](0.0, x, *extra), dtype=float)
    scale = max(1.0, float(np.linalg.norm(x)), float(np.linalg.norm(s.x_init)))
    moved = float(np.linalg.norm(fx)) * T
    if moved <= _EQUILIBRIUM * scale:
        return (f"converged to an equilibrium, not a periodic orbit: |f(x0)| T = {moved:.3e} "
                f"<= sqrt(eps) * {scale:.3g} (the state does not move over the period; x0 = "
                f"{x!r}); start from a guess on the orbit, or hold with `fixed` a component "
                f"whose value the equilibrium does not have")
    return None


def _result(problem: ShootingProblem, outcome: _Outcome, stopping: _Stopping,
            phase: str) -> PeriodicOrbit:
    """The :class:`PeriodicOrbit` of an outcome, with the acceptance verdict."""
    s = problem.setup
    norm = float(np.linalg.norm(outcome.residual))
    x, T, params = problem.unpack(outcome.z)
    problem.close_history(outcome.z, norm)
    success = not outcome.failed and outcome.status_ok and norm <= stopping.tol
    message = outcome.message
    status = (Status.SUCCESS if success else Status.INTEGRATION_FAILED if outcome.failed
              else Status.RESIDUAL_ABOVE_TOL if outcome.status_ok else Status.MAX_EVALUATIONS)
    if success and s.autonomous:
        refusal = _refusal(problem, x, T, params, stopping.min_period)
        if refusal is not None:
            success, message, status = False, refusal, Status.FAILED
    elif not outcome.failed and not success:
        message = (f"Levenberg-Marquardt stopped ({message}) with residual norm {norm:.3e} > "
                   f"tol = {stopping.tol:.1e}" if outcome.status_ok
                   else f"Levenberg-Marquardt did not converge: {message}")
    return PeriodicOrbit(
        x0=x, period=T, params=params, success=success, message=message,
        residual=np.asarray(outcome.residual), residual_norm=norm,
        residual_history=np.array(problem.residual_history),
        iteration_history=np.array(problem.iteration_history),
        nit=outcome.njev or len(problem.iteration_history) - 1,
        n_residual_evals=len(problem.residual_history), nfev=problem.nfev, njev=problem.njev,
        jacobian=s.jacobian, method=s.settings.method, autonomous=s.autonomous,
        unknowns=np.array(outcome.z, dtype=float), phase_condition=phase,
        segment_states=problem.segment_states(np.asarray(outcome.z, dtype=float)),
        status=status,
    )


def find_periodic_orbit(
    fun: Callable[..., Any] | Sequence[Callable[..., Any]],
    x0: Any,
    period: float,
    *,
    autonomous: bool = True,
    jac: Callable[..., Any] | Sequence[Callable[..., Any]] | None = None,
    free_params: Any = None,
    param_jac: Callable[..., Any] | Sequence[Callable[..., Any]] | None = None,
    extra_residual: Callable[..., Any] | None = None,
    fixed: Sequence[int] = (),
    breakpoints: Sequence[float] = (),
    jacobian: str = "variational",
    method: str | type[OdeSolver] | None = None,
    n_points: int = 1,
    delta: float = 2.0**-10,
    segments: int = 1,
    rtol: float | None = None,
    atol: float | None = None,
    rk4_steps: int | None = None,
    max_steps: int | None = None,
    tol: float | None = None,
    max_nfev: int | None = None,
    xtol: float = 1e-12,
    ftol: float = 1e-12,
    min_period: float | None = None,
    args: tuple[Any, ...] = (),
    settings: opt.SolverSettings | None = None,
) -> PeriodicOrbit:
    """Find a periodic orbit by the optimized shooting method (eqs. 30-38).

    Minimises the residual of eq. (38) in normalised time ``tau = t / T``,
    ``r_k = x(1 + k delta) - x(k delta)``, ``k = 0 .. n_points - 1``, stacked, followed by
    ``extra_residual(x0, period, params)``, with Levenberg-Marquardt (eq. 35; MINPACK ``lmder``).
    The unknowns are the components of ``x0`` not in ``fixed``, then ``T`` if ``autonomous``, then
    the free parameters.

    Parameters
    ----------
    fun : callable or sequence of callables
        Right-hand side ``fun(t, x, *args)``, or ``fun(t, x, *args, params)`` with
        ``free_params``; a sequence gives one callable per segment of the period
        (``len(breakpoints) + 1``), each smooth on its closed segment (see
        :mod:`flapping.periodic.integrate`).
    x0 : array_like, shape (n,)
        Initial guess of a state on the orbit; components in ``fixed`` are kept.
    period : float
        Period: the initial guess if ``autonomous``, the known forcing period otherwise.
    autonomous : bool, optional
        ``True``: ``fun`` does not depend on t and ``T`` is an unknown; a phase condition is
        then needed (``fixed``, ``n_points >= 2`` or ``extra_residual``; with none, the
        component of largest ``|f|`` at the guess is held, see the module notes).
        ``False``: forced system, ``T`` known and fixed.
    jac : callable or sequence of callables, optional
        Analytic ``df/dx`` (same signature and segments as ``fun``). Default: central finite
        differences of ``fun`` inside the variational equations.
    free_params : array_like, optional
        Initial guess of extra unknown parameters ``params`` (e.g. a flapping amplitude), passed
        as the last argument of ``fun``, ``jac``, ``param_jac`` and to ``extra_residual``.
    param_jac : callable or sequence of callables, optional
        ``df/dparams(t, x, *args, params)``, shape (n, n_p). Default: central differences of
        ``fun`` in params.
    extra_residual : callable, optional
        ``extra_residual(x0, period, params) -> array`` of further conditions appended to R
        (differenced centrally in the unknowns: it must be cheap and smooth).
    fixed : sequence of int, optional
        Indices of ``x0`` held at their given values: a Poincare-section phase condition
        (Dednam & Botha hold x3), or a state the vector field does not depend on (an altitude).
    breakpoints : sequence of float, optional
        Fractions of the period in (0, 1) where the integrator restarts (forced systems only).
    jacobian : {"variational", "finite-difference"}, optional
        ``"variational"``: one integration of state + variational equations per Jacobian (exact
        up to the tolerance; columns for x0, for T as ``tau f(x(tau))``, for params from the
        sensitivity equations). ``"finite-difference"``: forward differences of the residual,
        step ``sqrt(eps) |z_j|`` (MINPACK ``lmdif``'s rule, the paper's method); one extra
        shooting integration per unknown.
    method : str or OdeSolver subclass, optional
        Integrator: ``"DOP853"`` (default), another solve_ivp method, or ``"RK4"`` (fixed step
        ``T / rk4_steps``, the paper's).
    n_points : int, optional
        Number of residual blocks in eq. (38) (the paper's p), in [1, 1024]. Two blocks at the
        same phase (``k delta`` equal modulo 1) warn: the sampling aliases.
    delta : float, optional
        Spacing of the residual blocks in normalised time (paper: ``2**-10``), in (0, 1).
    segments : int, optional
        Number M of shooting segments (>= 1). ``1`` (default) is single shooting. With M > 1 the
        period is cut into M equal segments, each integrated from its own unknown state (started
        on the guess's trajectory); the residual is the M continuity conditions and its Jacobian
        is assembled from the per-segment variational integrations (block-bidiagonal). Long or
        strongly unstable orbits, out of reach of single shooting, converge (multiflap's Roessler
        example). Needs ``n_points == 1``; with RK4, ``rk4_steps`` a multiple of M.
    rtol, atol : float, optional
        Integration tolerances (adaptive methods; default 1e-11 and 1e-12). An ``rtol`` below
        ``100 eps`` is raised to it with a :class:`~flapping.errors.ToleranceWarning`.
    rk4_steps : int, optional
        RK4 steps per period (default 1024, at most 2**22).
    max_steps : int, optional
        Step budget of each integration (default 100 000, at most 10**7, see
        :mod:`flapping.periodic.integrate`); running out ends the iteration with advice.
    tol : float, optional
        Required final residual norm (absolute, in the units of the state; default 1e-10), at
        most ``1e-6 max(1, |x0|)`` (:data:`~flapping.periodic.settings.RESIDUAL_CEILING`: a
        looser residual is a point on no orbit, by :func:`~flapping.periodic.floquet.monodromy`'s
        closure test).
    max_nfev : int, optional
        Maximum residual evaluations of Levenberg-Marquardt (default ``100 * (n_unknowns + 1)``,
        at most 10**5).
    xtol, ftol : float, optional
        MINPACK's termination tolerances (relative step and relative reduction), in
        [2.2e-16, 1e-2].
    min_period : float, optional
        Autonomous only: a converged period below this is rejected as the trivial solution
        ``T -> 0`` every autonomous shooting residual has (default ``1e-2 * period``).
    args : tuple, optional
        Extra arguments of ``fun`` and ``jac`` (before ``params``).
    settings : SolverSettings, optional
        ``method``, ``rtol``, ``atol``, ``rk4_steps``, ``max_steps``, ``tol`` and ``max_nfev``
        as one object (:mod:`flapping.periodic.settings`); a keyword given explicitly
        overrides the same field.

    Returns
    -------
    PeriodicOrbit
        The orbit and the convergence diagnostics (``phase_condition`` says what fixed the
        phase).

    Raises
    ------
    ValueError
        Bad arguments: non-positive or non-finite period, x0 not a finite 1-D array, wrong output
        shape of ``fun``/``jac``/``param_jac``/``extra_residual``, ``fun`` raising a ValueError or
        IndexError at its first call (the message names ``x0`` and ``args``), ``fixed`` out of
        range, ``n_points < 1``, ``segments < 1`` or ``segments > 1`` with ``n_points > 1``,
        fewer residuals than unknowns, breakpoints with an autonomous system, RK4 grid mismatch,
        a size beyond its cap (``n_points``, ``segments``, ``rk4_steps``, ``max_steps``,
        ``max_nfev``: :data:`flapping.periodic.settings.CAPS`), a tolerance beyond its ceiling
        (``rtol`` > 1e-3, ``atol`` > ``1e-2 max(1, |x0|)``, ``tol`` > ``1e-6 max(1, |x0|)``,
        ``xtol`` or ``ftol`` > 1e-2).
    NonFiniteError
        A ValueError: a callable returned NaN or infinity at a finite state (with ``t``,
        ``state``, ``source``, ``value``).
    TypeError
        ``args`` (and ``free_params``) do not fit the signature of ``fun``, ``jac`` or
        ``param_jac``, or a callable (``extra_residual`` too) returned None, a string, or complex
        or boolean values (checked at the first call).
    ConvergenceError
        Levenberg-Marquardt stopped without reaching ``residual_norm <= tol``, the integration
        failed (or ran out of its step budget), the period collapsed, or the answer is an
        equilibrium; carries the last iterate (unknowns), the residual norm, the iteration
        count, and the :class:`PeriodicOrbit` as ``result``; when an integration failed, where
        it stopped: ``t``, ``state`` and ``source``.

    Warns
    -----
    AliasedPeriodWarning
        An autonomous orbit that closes already at ``T / k`` (``k = 2 .. 8``, within
        ``ALIAS_TOL = 1e-6`` of ``max(1, |x0|)``): the period found is k times the minimal one
        (usually a period guess near a multiple of it); checked by one integration over half a
        period after convergence. A forced orbit is not checked: its period is the forcing's,
        and a response with a shorter period (a symmetric stroke) is legitimate. Also two
        residual points at the same phase (see ``n_points``).
    ToleranceWarning
        ``rtol`` raised to ``100 eps``.
    """
    o = opt.resolve(settings, DEFAULTS, method=method, rtol=rtol, atol=atol,
                    rk4_steps=rk4_steps, max_steps=max_steps, tol=tol, max_nfev=max_nfev)
    x_init = check.vector("x0", x0)
    T_init = check.positive("period", period)
    integration = seg.check_settings(o["method"], o["rtol"], o["atol"], o["rk4_steps"],
                                     o["max_steps"])
    b = seg.check_breakpoints(breakpoints)
    if not isinstance(autonomous, (bool, np.bool_)):
        raise ValueError(f"`autonomous` must be True or False; got {autonomous!r}")
    if autonomous and b:
        raise ValueError(
            "`breakpoints` move with the unknown period, so they make the system non-autonomous: "
            "use autonomous=False (known period) with breakpoints")
    seg.fixed_step(integration, 0.0, T_init, T_init, b)
    jacobian = check.choice("jacobian", jacobian, JACOBIANS)
    n_points, delta = _check_shape_options(integration, n_points, delta)
    segments = _check_segments(integration, segments, n_points)
    opt.check_scaled("atol", integration.atol, x_init, opt.TOL_CEILING)
    stopping = _check_stopping(o["tol"], xtol, ftol, o["max_nfev"], min_period, T_init, x_init)
    fixed_given = _check_fixed(fixed, x_init.size)
    p_init = None if free_params is None else check.vector("free_params",
                                                                 np.atleast_1d(free_params))
    funs, jacs, pjacs = _check_callables(fun, jac, param_jac, len(b) + 1, p_init is not None)
    setup = ShootingSetup(funs, jacs, pjacs, check.call_args(args), x_init, T_init, p_init,
                          fixed_given, bool(autonomous), b, integration, n_points, delta,
                          extra_residual, 0, jacobian, segments)
    counter = seg.Counter()
    f0, n_extra = _probe(setup, counter)
    setup, phase = _phase_condition(replace(setup, n_extra=n_extra),
                                    f0, bool(fixed_given))
    _check_size(setup)
    problem = ShootingProblem(setup) if segments == 1 else MultipleShootingProblem(setup)
    problem.counter.n = counter.n  # the probe's evaluations count
    orbit = _result(problem, _solve(problem, stopping), stopping, phase)
    if not orbit.success:
        where = problem.failure if orbit.message.startswith("the iteration failed") else None
        raise ConvergenceError(f"no periodic orbit found: {orbit.message}", x=orbit.unknowns,
                               residual=orbit.residual_norm, iterations=orbit.nit, result=orbit,
                               t=None if where is None else where.t,
                               state=None if where is None else where.state,
                               source=None if where is None else where.source,
                               status=orbit.status)
    if setup.autonomous:
        _warn_if_multiple(problem, orbit)
    return orbit


#: What a call uses for each :class:`~flapping.periodic.settings.SolverSettings` field it
#: reads when neither the keyword nor ``settings`` gives it (the signature shows None).
DEFAULTS: dict[str, Any] = {"method": "DOP853", "rtol": opt.ORBIT_RTOL, "atol": opt.ORBIT_ATOL,
                             "rk4_steps": 1024, "max_steps": None, "tol": opt.ORBIT_TOL,
                             "max_nfev": None}


def _warn_if_multiple(problem: ShootingProblem, orbit: PeriodicOrbit) -> None:
    """Warn if the autonomous orbit closes at ``T / k``: its period is k times the minimal."""
    s, T = problem.setup, orbit.period
    ks = range(ALIAS_ORDERS, 1, -1)
    t_out = tuple(T / k for k in ks)  # increasing
    g = tuple(seg.Checked(f, s.args, orbit.params, (orbit.x0.size,), seg.Counter())
              for f in s.funs)
    # RK4's grid does not hold T / k: the check then runs DOP853 (its accuracy, ~1e-10, is far
    # below ALIAS_TOL, and so is RK4's error on the orbit)
    how = (seg.check_settings("DOP853", 1e-10, 1e-10, 1024, s.settings.max_steps)
           if s.settings.fixed_step else s.settings)
    out = seg.propagate(g, 0.0, t_out[-1], orbit.x0, period=T, breakpoints=s.breakpoints,
                        settings=how, h=None, t_out=t_out)
    if not out.success:
        return  # a diagnostic: a failure here is not the solve's
    scale = max(1.0, float(np.linalg.norm(orbit.x0)))
    for k, x in zip(ks, out.y_out, strict=True):
        gap = float(np.linalg.norm(x - orbit.x0))
        if gap <= ALIAS_TOL * scale:
            warnings.warn(
                f"aliased period: the orbit returns to x0 at T / {k} (|x(T/{k}) - x0| = "
                f"{gap:.2e}): T = {T:.10g} is {k} times its minimal period "
                f"{T / k:.10g} (a period guess near a multiple of it?); its multipliers are "
                f"the {k}-th powers of the orbit's", AliasedPeriodWarning, stacklevel=3)
            return

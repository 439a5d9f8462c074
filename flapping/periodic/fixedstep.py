"""Periodic orbits of forced systems by Newton's method on a fixed-step 8th-order period map.

:func:`find_periodic_orbit_fixed_step` solves the same problem as
:func:`~flapping.periodic.shooting.find_periodic_orbit` for a forced (non-autonomous) system --
``x(T) = x(0)`` with free parameters and held components -- differently:

- one period is integrated with the 8th-order Dormand-Prince formula at a *fixed* number of steps
  per segment, restarted at the breakpoints (where the right-hand side may jump), so the residual
  is a smooth function of the unknowns. An adaptive integrator's step sequence changes with the
  unknowns, which puts noise of the size of its tolerance in the residual and its differences; a
  Levenberg-Marquardt solve on it can stall at that noise floor (measured on the blade-element
  hover orbit: ~3e-8). Here Newton's method converges to rounding level;
- the Jacobian of the residual is the exact derivative of the discrete map: the variational
  equations integrated with the same stages when ``jac`` (and ``param_jac``) are given, else
  central differences of the discrete map (all perturbed trajectories integrated together).
  Newton reuses a Jacobian while it contracts well (a chord iteration) and recomputes it
  otherwise;
- the error of the answer is estimated by Richardson extrapolation: at the converged unknowns the
  map is evaluated again at half the steps, and the Newton correction that difference implies,
  divided by 2^8 - 1 and times a safety factor 2, estimates the error of each unknown; the
  multipliers' estimate is the change of the monodromy's eigenvalues when the monodromy is moved by
  its own Richardson correction. If an estimate exceeds its tolerance, the step count grows by
  the predicted factor and the solve is repeated (warm-started, with the last Jacobian);
- the monodromy (and the sensitivity to the parameters) is the derivative of the last pass.

This is the approach of the compiled hover kernel (:mod:`flapping.fast.kernel`), for any
``f(t, x[, params])`` and in plain NumPy. Autonomous systems (unknown period) are refused: use
:func:`~flapping.periodic.shooting.find_periodic_orbit`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

import flapping._validation as check
from flapping.errors import ConvergenceError, DomainError
from flapping.periodic import _segments as seg
from flapping.periodic import settings as opt
from flapping.periodic._checks import probe_fields
from flapping.periodic._fixedmap import NonFinite, OutOfWork, PeriodMap
from flapping.periodic._readonly import freeze
from flapping.results import MESSAGES, Floquet, Status

__all__ = [
    "DEFAULT_STEPS",
    "MAX_STEPS",
    "ERROR_TOL_FLOOR",
    "STATUS",
    "FixedStepOrbit",
    "fixed_step_flow",
    "find_periodic_orbit_fixed_step",
    "fixed_step_monodromy",
]

#: Steps per segment to start with (the error estimate adds more if needed).
DEFAULT_STEPS = 16

#: Largest number of steps per segment (the step count never grows beyond it).
MAX_STEPS = 4096

#: Smallest accepted ``error_tol``: Newton stops at a step of ``1e-13 max(1, |z_i|)``, so the
#: unknowns are not known better than that, and an error estimate below it is rounding noise.
ERROR_TOL_FLOOR = 1e-13

#: Default cap on the evaluations of ``fun`` in one solve, and the largest cap accepted.
MAX_NFEV, MAX_NFEV_CAP = 10**6, 10**8

#: The solve's outcome, by :attr:`FixedStepOrbit.status`: the package's one status table
#: (:class:`flapping.results.Status`), restricted to the outcomes this solver reports.
STATUS: dict[Status, str] = {status: MESSAGES[status] for status in (
    Status.SUCCESS, Status.MAX_ITERATIONS, Status.SINGULAR, Status.NON_FINITE,
    Status.TOLERANCE_NOT_MET, Status.MAX_EVALUATIONS, Status.RESIDUAL_ABOVE_TOL)}

#: Newton's stopping rule (every step below XTOL max(1, |z_i|)) and its iteration cap per step
#: count; a fresh Jacobian is computed when a step shrinks by less than _CONTRACTION.
_XTOL, _MAX_ITER, _CONTRACTION = 1e-13, 40, 0.1

#: A step that stops shrinking below this (scaled) size is rounding noise: Newton stops there.
_STALL = 1e-11

#: Halvings of a Newton step whose end the model refuses (:class:`~flapping.errors.DomainError`),
#: before the refusal ends the solve: 2^-10 of a step that left the domain is well inside it.
_MAX_HALVINGS = 10

#: Order of the formula, the step ratio of the Richardson estimate, its safety factor (at the
#: coarse level the error is not yet fully asymptotic), and the step-count increases per solve.
_ORDER, _COARSE, _SAFETY, _MAX_REFINEMENTS = 8, 2, 2.0, 8
_FACTOR = _SAFETY / (_COARSE**_ORDER - 1.0)


@dataclass(frozen=True)
class FixedStepOrbit:
    """A periodic orbit found by :func:`find_periodic_orbit_fixed_step`, with its diagnostics.

    Attributes
    ----------
    x0 : ndarray, shape (n,)
        Initial state on the orbit (held components at their given values).
    period : float
        The (known) period T.
    params : ndarray or None
        Converged free parameters.
    success : bool
        True if :attr:`status` is ``Status.SUCCESS``.
    status : Status
        Machine-readable outcome (:data:`STATUS`).
    message : str
        The outcome in words.
    residual : ndarray, shape (n,)
        x(T) - x(0) of the last pass (at :attr:`n_steps`).
    residual_norm : float
        Its Euclidean norm.
    nit : int
        Newton iterations in total (all step counts).
    nfev, njev : int
        Evaluations of ``fun`` and of ``jac``/``param_jac`` in total.
    n_steps : int
        Steps per segment of the answer.
    jacobian : str
        ``"variational"`` or ``"finite-difference"`` (central differences of the discrete map).
    unknowns : ndarray
        The free components of x0, then the parameters.
    unknowns_error : ndarray
        Richardson estimate of the error of each unknown (absolute).
    monodromy : ndarray, shape (n, n)
        d x(T) / d x(0) of the last pass.
    sensitivity : ndarray, shape (n, n_p) or None
        d x(T) / d params of the last pass.
    multipliers : ndarray, complex
        Eigenvalues of the monodromy, by descending modulus.
    multiplier_error : float
        Richardson estimate of the largest error of a multiplier (absolute).
    newton_step : float
        Largest scaled Newton step ``|dz_i| / max(1, |z_i|)`` of the last iteration.
    fixed : tuple of int
        The held components of x0.
    """

    x0: np.ndarray
    period: float
    params: np.ndarray | None
    success: bool
    status: Status
    message: str
    residual: np.ndarray
    residual_norm: float
    nit: int
    nfev: int
    njev: int
    n_steps: int
    jacobian: str
    unknowns: np.ndarray
    unknowns_error: np.ndarray
    monodromy: np.ndarray
    sensitivity: np.ndarray | None
    multipliers: np.ndarray
    multiplier_error: float
    newton_step: float
    fixed: tuple[int, ...] = ()

    def __post_init__(self) -> None:
        freeze(self)

    @property
    def floquet(self) -> Floquet:
        """The monodromy (of the state and the parameters' sensitivity rows as solved) and its
        multipliers as the package's one type (:class:`flapping.results.Floquet`), with
        :attr:`multiplier_error`."""
        return Floquet.of_matrix(self.monodromy, self.period, multipliers=self.multipliers,
                                 multiplier_error=self.multiplier_error)

    @property
    def x0_error(self) -> np.ndarray:
        """Estimated error of each component of :attr:`x0` (0 for the held ones)."""
        out = np.zeros(self.x0.size)
        free = [i for i in range(self.x0.size) if i not in self.fixed]
        out[free] = self.unknowns_error[: len(free)]
        return out

    @property
    def params_error(self) -> np.ndarray | None:
        """Estimated error of each parameter (None without parameters)."""
        if self.params is None:
            return None
        return np.array(self.unknowns_error[self.unknowns.size - self.params.size:])


# =========================================================================== the problem
class _Problem:
    """Unknowns z (free components of x0, then params) <-> (x0, params); residual, Jacobian."""

    def __init__(self, pmap: PeriodMap, x_init: np.ndarray, p_init: np.ndarray | None,
                 fixed: tuple[int, ...]) -> None:
        self.map, self.x_init, self.fixed = pmap, x_init, fixed
        d = x_init.size
        self.n_params = 0 if p_init is None else p_init.size
        self.free = [i for i in range(d) if i not in fixed]
        self.columns = self.free + [d + i for i in range(self.n_params)]
        self.E = np.zeros((d, len(self.columns)))
        self.E[self.free, range(len(self.free))] = 1.0
        self.z0 = np.concatenate([x_init[self.free], np.zeros(0) if p_init is None else p_init])

    def unpack(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
        x = self.x_init.copy()
        x[self.free] = z[: len(self.free)]
        return x, (z[len(self.free):].copy() if self.n_params else None)

    def residual(self, z: np.ndarray, n: int) -> np.ndarray:
        """x(T) - x(0) at n steps per segment."""
        x, params = self.unpack(z)
        end = self.map.flow(x[None, :], None if params is None else params[None, :], n)[0]
        return end - x

    def linearised(self, z: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
        """The residual and its Jacobian in z."""
        x, params = self.unpack(z)
        end, D = self.map.derivative(x, params, n, self.columns)
        return end - x, D - self.E

    def full(self, z: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The residual, its Jacobian in z and d x(T)/d(x0, params) (every column)."""
        x, params = self.unpack(z)
        end, D = self.map.derivative(x, params, n, range(x.size + self.n_params))
        return end - x, D[:, self.columns] - self.E, D


def _newton_step(J: np.ndarray, r: np.ndarray) -> np.ndarray:
    """-J^+ r (the solve for a square J, least squares otherwise); LinAlgError if singular."""
    if J.shape[0] == J.shape[1]:
        dz = np.linalg.solve(J, -r)
    else:
        dz, *_ = np.linalg.lstsq(J, -r, rcond=None)
    if not np.all(np.isfinite(dz)):
        raise np.linalg.LinAlgError("the Newton step is not finite")
    return dz


@dataclass
class _Newton:
    """The end of a Newton iteration at one step count."""

    z: np.ndarray
    J: np.ndarray | None
    nit: int
    step: float
    status: Status


def _newton(problem: _Problem, z: np.ndarray, n: int, J: np.ndarray | None) -> _Newton:
    """Newton (a chord iteration while it contracts well) at n steps per segment, from z.

    A step whose end the model refuses (:class:`~flapping.errors.DomainError`: e.g. a stroke
    amplitude past 90 deg) is halved, back towards the last iterate, at most
    :data:`_MAX_HALVINGS` times in a row, and Newton goes on from there with a fresh Jacobian:
    the plain Newton iteration wherever the model accepts every step. A refused evaluation
    counts as an iteration (towards ``nit`` and the cap).
    """
    prev = step = math.inf
    back: tuple[np.ndarray, np.ndarray] | None = None  # the last iterate and the step taken
    halvings = 0
    for it in range(1, _MAX_ITER + 1):
        fresh = J is None
        try:
            if J is None:
                r, J = problem.linearised(z, n)
            else:
                r = problem.residual(z, n)
        except DomainError:
            if back is None or halvings >= _MAX_HALVINGS:
                raise
            halvings += 1
            last, dz = back[0], 0.5 * back[1]
            back, z = (last, dz), last + dz
            J = None  # the linearisation that overshot is no guide from the shorter step
            continue
        halvings = 0
        dz = _newton_step(J, r)
        step = float(np.max(np.abs(dz) / np.maximum(1.0, np.abs(z))))
        back, z = (z, dz), z + dz
        if step <= _XTOL or (fresh and step <= _STALL and step > 0.5 * prev):
            return _Newton(z, J, it, step, Status.SUCCESS)
        if step > _CONTRACTION * prev:
            J = None  # slow contraction: a fresh Jacobian for the next step
        prev = step
    return _Newton(z, J, _MAX_ITER, step, Status.MAX_ITERATIONS)


@dataclass
class _Estimate:
    """The last pass at n steps and its Richardson error estimates."""

    residual: np.ndarray
    J: np.ndarray
    D: np.ndarray
    unknowns_error: np.ndarray
    multipliers: np.ndarray
    multiplier_error: float


def _estimate(problem: _Problem, z: np.ndarray, n: int) -> _Estimate:
    """The map and its derivative at n and n / 2 steps: residual, monodromy, error estimates."""
    r, J, D = problem.full(z, n)
    r_c, _, D_c = problem.full(z, n // _COARSE)
    dz = _newton_step(J, r - r_c) * _FACTOR
    d = problem.x_init.size
    M, M_c = D[:, :d], D_c[:, :d]
    mu = np.linalg.eigvals(M)
    moved = np.linalg.eigvals(M + (M - M_c) * _FACTOR)
    shift = float(np.max(np.min(np.abs(moved[None, :] - mu[:, None]), axis=1)))
    mu = mu[np.argsort(-np.abs(mu), kind="stable")]
    return _Estimate(r, J, D, np.abs(dz), mu, shift)


def _next_steps(n: int, ratio: float) -> int:
    """The step count predicted to bring an error ``ratio`` times its tolerance under it."""
    m = int(math.ceil(n * max(1.25, 1.1 * ratio ** (1.0 / _ORDER))))
    return min(MAX_STEPS, m + m % 2)


# =========================================================================== the solve
@dataclass(frozen=True)
class _Tolerances:
    error: float
    multiplier: float | None
    residual: float


class _Solve:
    """Newton at a growing step count until the error estimates meet their tolerances."""

    def __init__(self, problem: _Problem, n: int, tols: _Tolerances) -> None:
        self.problem, self.n, self.tols = problem, n, tols
        self.z = problem.z0.copy()
        self.J: np.ndarray | None = None
        self.nit, self.step, self.status = 0, math.inf, Status.SUCCESS
        self.estimate: _Estimate | None = None

    def run(self) -> None:
        """Refine until the tolerances are met; failures end in :attr:`status`."""
        try:
            for _ in range(_MAX_REFINEMENTS + 1):
                if not self._level():
                    return
        except np.linalg.LinAlgError:
            self.status = Status.SINGULAR
        except NonFinite:
            self.status = Status.NON_FINITE
        except OutOfWork:
            self.status = Status.MAX_EVALUATIONS

    def _level(self) -> bool:
        """One step count: Newton, the last pass, the estimate; True if more steps are needed."""
        newton = _newton(self.problem, self.z, self.n, self.J)
        self.z, self.nit, self.step = newton.z, self.nit + newton.nit, newton.step
        if not newton.status.success:
            self.status = newton.status
            return False
        self.estimate = est = _estimate(self.problem, self.z, self.n)
        ratio = self.ratio(est)
        if ratio <= 1.0 or self.n >= MAX_STEPS:
            self.status = Status.SUCCESS if ratio <= 1.0 else Status.TOLERANCE_NOT_MET
            if self.status.success and float(np.linalg.norm(est.residual)) > self.tols.residual:
                self.status = Status.RESIDUAL_ABOVE_TOL
            return False
        self.n, self.J = _next_steps(self.n, ratio), est.J
        return True

    def ratio(self, est: _Estimate) -> float:
        """The largest error estimate relative to its tolerance."""
        scale = self.tols.error * np.maximum(1.0, np.abs(self.z))
        ratio = float(np.max(est.unknowns_error / scale))
        if self.tols.multiplier is not None:
            ratio = max(ratio, est.multiplier_error / self.tols.multiplier)
        return ratio

    def result(self, period: float) -> FixedStepOrbit:
        """The :class:`FixedStepOrbit` of the solve (NaN diagnostics where none were reached)."""
        problem = self.problem
        x, params = problem.unpack(self.z)
        d, est = x.size, self.estimate
        nan = np.full((d, d + problem.n_params), math.nan)
        D = nan if est is None else est.D
        residual = np.full(d, math.nan) if est is None else est.residual
        message = STATUS[self.status] + f" ({self.n} steps per segment)"
        return FixedStepOrbit(
            x0=x, period=period, params=params, success=self.status.success, status=self.status,
            message=message, residual=residual, residual_norm=float(np.linalg.norm(residual)),
            nit=self.nit, nfev=problem.map.nfev, njev=problem.map.njev, n_steps=self.n,
            jacobian="variational" if problem.map.variational else "finite-difference",
            unknowns=self.z.copy(),
            unknowns_error=(np.full(self.z.size, math.nan) if est is None
                            else est.unknowns_error),
            monodromy=D[:, :d], sensitivity=D[:, d:] if problem.n_params else None,
            multipliers=(np.full(d, math.nan, dtype=complex) if est is None
                         else est.multipliers.astype(complex)),
            multiplier_error=math.nan if est is None else est.multiplier_error,
            newton_step=self.step, fixed=problem.fixed)


# =========================================================================== public
def find_periodic_orbit_fixed_step(
    fun: Callable[..., Any] | Sequence[Callable[..., Any]],
    x0: Any,
    period: float,
    *,
    autonomous: bool = False,
    jac: Callable[..., Any] | Sequence[Callable[..., Any]] | None = None,
    free_params: Any = None,
    param_jac: Callable[..., Any] | Sequence[Callable[..., Any]] | None = None,
    fixed: Sequence[int] = (),
    breakpoints: Sequence[float] = (),
    switches: Sequence[Any] = (),
    args: tuple[Any, ...] = (),
    n_steps: int | None = None,
    error_tol: float = opt.FIXED_STEP_ERROR_TOL,
    multiplier_tol: float | None = None,
    tol: float = opt.ORBIT_TOL,
    max_nfev: int | None = None,
) -> FixedStepOrbit:
    """Periodic orbit of a forced system by Newton's method on a fixed-step DOP853 period map.

    Solves ``x(T) - x(0) = 0`` (eq. 31 with the paper's eq. 38 at one point) for the components
    of ``x0`` not in ``fixed`` and the free parameters, as
    :func:`~flapping.periodic.shooting.find_periodic_orbit` (same conventions for ``fun``,
    ``jac``, ``param_jac``, ``free_params``, ``fixed``, ``breakpoints`` and ``args``), with the
    period integrated at a fixed number of 8th-order steps per segment and the step count raised
    until the Richardson error estimates meet ``error_tol`` (and ``multiplier_tol``); see the
    module notes.

    Parameters
    ----------
    fun : callable or sequence of callables
        ``fun(t, x, *args)``, or ``fun(t, x, *args, params)`` with ``free_params``; one callable per
        segment (``len(breakpoints) + 1``), each smooth on its closed segment.
    x0 : array_like, shape (n,)
        Initial guess; components in ``fixed`` are held.
    period : float
        The known forcing period T > 0.
    autonomous : bool
        Must be False: an autonomous system (unknown period) is refused (ValueError).
    jac, param_jac : callable or sequence of callables, optional
        ``df/dx`` (n, n) and ``df/dparams`` (n, n_p). With ``jac`` (and ``param_jac`` when there are
        parameters) the Jacobian of the residual comes from the variational equations integrated
        with the same stages; otherwise from central differences of the discrete map.
    free_params : array_like, optional
        Initial guess of the free parameters params.
    fixed : sequence of int
        Indices of ``x0`` held at their given values.
    breakpoints : sequence of float
        Fractions of the period in (0, 1) where the integration restarts (the segments).
    switches : sequence of callables, or one such sequence per segment
        Switching functions ``g(t, x, *args[, params]) -> float`` whose sign changes mark where
        ``fun`` is continuous but not smooth (a kink at a state-dependent time, e.g. an absolute
        value): a step across a sign change is split at the root (located to rounding along the
        step, Illinois method), so the formula keeps its order and the map stays smooth. A kink
        left unmarked drops the convergence to first or second order. ``fun`` must be
        continuous across every switch (a jump needs a breakpoint). With switches the Jacobian
        is always differenced (``jac`` is one-sided on the switching surface).
    args : tuple
        Extra arguments of the callables (before ``params``).
    n_steps : int, optional
        Steps per segment to start with (even, in [2, :data:`MAX_STEPS`]; default
        :data:`DEFAULT_STEPS`).
    error_tol : float
        Required accuracy of every unknown relative to ``max(1, |z_i|)`` (Richardson estimate),
        in [:data:`ERROR_TOL_FLOOR`, 1e-2].
    multiplier_tol : float, optional
        Required accuracy of every Floquet multiplier (absolute, in [1e-13, 1e-2]); default:
        estimated and reported, not enforced.
    tol : float
        Largest accepted residual norm at the answer (as ``find_periodic_orbit``'s ``tol``, at
        most ``1e-6 max(1, |x0|)``).
    max_nfev : int, optional
        Cap on the evaluations of ``fun`` (default 10**6, at most 10**8).

    Returns
    -------
    FixedStepOrbit

    Raises
    ------
    ValueError
        For bad arguments (each named with its accepted range), an autonomous system, a callable
        returning the wrong shape or a non-finite value at the guess, or raising a ValueError or
        IndexError there (naming ``x0`` and ``args``), or fewer residuals than unknowns.
    TypeError
        ``args`` does not fit a callable's signature, or a callable returned None, a string,
        or complex or boolean values at the guess.
    ConvergenceError
        If the solve fails (any :data:`STATUS` but ``SUCCESS``), with the last iterate, its
        residual norm, the iteration count, the status and the :class:`FixedStepOrbit` as
        ``result``.
    """
    if check.boolean("autonomous", autonomous):
        raise ValueError("find_periodic_orbit_fixed_step solves forced systems (known period) "
                         "only: autonomous=True is not supported; use find_periodic_orbit")
    x_init = check.vector("x0", x0)
    T = check.positive("period", period)
    b = seg.check_breakpoints(breakpoints)
    p_init = (None if free_params is None
              else check.vector("free_params", np.atleast_1d(free_params)))
    held = _check_fixed(fixed, x_init.size)
    if x_init.size - len(held) + (0 if p_init is None else p_init.size) > x_init.size:
        raise ValueError(f"too few residuals ({x_init.size}) for the unknowns: hold as many "
                         f"components with `fixed` as there are free parameters")
    funs, jacs, pjacs = _callables(fun, jac, param_jac, len(b) + 1, p_init is not None)
    args = probe_fields(funs, jacs, pjacs, args, x_init, p_init, T, b)
    n = DEFAULT_STEPS if n_steps is None else check.integer("n_steps", n_steps, low=2,
                                                             high=MAX_STEPS)
    tols = _Tolerances(
        check.real("error_tol", error_tol, low=ERROR_TOL_FLOOR, high=opt.TOL_CEILING),
        None if multiplier_tol is None else check.real("multiplier_tol", multiplier_tol,
                                                       low=1e-13, high=opt.TOL_CEILING),
        check.positive("tol", tol))
    opt.check_scaled("tol", tols.residual, x_init)
    cap = MAX_NFEV if max_nfev is None else check.integer("max_nfev", max_nfev, low=1,
                                                          high=MAX_NFEV_CAP)
    pmap = PeriodMap(funs, jacs, pjacs, tuple(args), T, b, p_init is not None, cap,
                     _switches(switches, len(b) + 1))
    _probe(pmap, x_init, p_init)
    solve = _Solve(_Problem(pmap, x_init, p_init, held), n + n % 2, tols)
    solve.run()
    result = solve.result(T)
    if not result.success:
        raise ConvergenceError(f"no periodic orbit found: {result.message}", x=result.unknowns,
                               residual=result.residual_norm, iterations=result.nit,
                               result=result, status=result.status)
    return result


def _check_fixed(fixed: Any, n: int) -> tuple[int, ...]:
    """``fixed`` as distinct indices in [0, n), or a ValueError."""
    message = f"`fixed` must be a sequence of distinct integer indices in [0, {n}), got {fixed!r}"
    try:
        items = [check.integer("fixed", i, low=0, high=n - 1) for i in fixed]
    except (TypeError, ValueError):
        raise ValueError(message) from None
    if len(set(items)) != len(items):
        raise ValueError(message)
    return tuple(items)


def _callables(fun: Any, jac: Any, param_jac: Any, n_seg: int, has_params: bool
               ) -> tuple[tuple[Any, ...], tuple[Any, ...], tuple[Any, ...]]:
    funs = seg.segment_callables(fun, n_seg, "fun")
    jacs = (None,) * n_seg if jac is None else seg.segment_callables(jac, n_seg, "jac")
    if param_jac is not None and not has_params:
        raise ValueError("`param_jac` needs `free_params`")
    pjacs = ((None,) * n_seg if param_jac is None
             else seg.segment_callables(param_jac, n_seg, "param_jac"))
    return funs, jacs, pjacs


def _switches(switches: Any, n_seg: int) -> tuple[tuple[Callable[..., Any], ...], ...]:
    """``switches`` as one tuple of callables per segment."""
    message = ("`switches` must be a sequence of callables, or one such sequence per segment "
               f"(len(breakpoints) + 1 = {n_seg})")
    try:
        items = list(switches)
    except TypeError:
        raise ValueError(message) from None
    if all(callable(g) for g in items):
        return (tuple(items),) * n_seg
    try:
        per_segment = tuple(tuple(gs) for gs in items)
    except TypeError:
        raise ValueError(message) from None
    if len(per_segment) != n_seg or not all(callable(g) for gs in per_segment for g in gs):
        raise ValueError(message)
    return per_segment


def _probe(pmap: PeriodMap, x: np.ndarray, params: np.ndarray | None) -> None:
    """Each callable once at the start of its segment: a wrong shape or a non-finite value is a
    ValueError naming it, here, rather than a failure deep in the iteration."""
    d, extra = x.size, pmap.args if params is None else (*pmap.args, params)
    shapes = {"fun": (d,), "jac": (d, d), "param_jac": (d, 0 if params is None else params.size)}
    for k, t in enumerate(pmap.nodes[:-1]):
        for name, fns in (("fun", pmap.funs), ("jac", pmap.jacs), ("param_jac", pmap.pjacs)):
            fn = fns[k]
            if fn is None:
                continue
            out = np.asarray(fn(t, x.copy(), *extra), dtype=float)
            if name == "param_jac" and out.size == math.prod(shapes[name]):
                out = out.reshape(shapes[name])
            if out.shape != shapes[name]:
                raise ValueError(f"`{name}` must return an array of shape {shapes[name]}, got "
                                 f"shape {out.shape}")
            check.finite_output(name, out, t, x)


def _checked_map(fun: Any, jac: Any, param_jac: Any, x0: Any, period: float, n_steps: int,
                 free_params: Any, breakpoints: Sequence[float], switches: Sequence[Any],
                 args: tuple[Any, ...], max_nfev: int | None, difference_scale: Any = 1.0
                 ) -> tuple[PeriodMap, np.ndarray, np.ndarray | None, int]:
    """The checked arguments of :func:`fixed_step_monodromy` and :func:`fixed_step_flow`: their
    period map (each callable probed at x0), x0, the parameters and the step count."""
    x = check.vector("x0", x0)
    T = check.positive("period", period)
    b = seg.check_breakpoints(breakpoints)
    params = (None if free_params is None
              else check.vector("free_params", np.atleast_1d(free_params)))
    funs, jacs, pjacs = _callables(fun, jac, param_jac, len(b) + 1, params is not None)
    args = probe_fields(funs, jacs, pjacs, args, x, params, T, b)
    n = check.integer("n_steps", n_steps, low=2, high=MAX_STEPS)
    cap = MAX_NFEV if max_nfev is None else check.integer("max_nfev", max_nfev, low=1,
                                                          high=MAX_NFEV_CAP)
    scale = check.real("difference_scale", difference_scale, low=0.1, high=10.0)
    pmap = PeriodMap(funs, jacs, pjacs, tuple(args), T, b, params is not None, cap,
                     _switches(switches, len(b) + 1), difference_scale=scale)
    _probe(pmap, x, params)
    return pmap, x, params, n


def fixed_step_monodromy(
    fun: Callable[..., Any] | Sequence[Callable[..., Any]],
    x0: Any,
    period: float,
    *,
    n_steps: int,
    free_params: Any = None,
    jac: Callable[..., Any] | Sequence[Callable[..., Any]] | None = None,
    param_jac: Callable[..., Any] | Sequence[Callable[..., Any]] | None = None,
    breakpoints: Sequence[float] = (),
    switches: Sequence[Any] = (),
    args: tuple[Any, ...] = (),
    max_nfev: int | None = None,
    difference_scale: float = 1.0,
) -> np.ndarray:
    """d x(T) / d x(0) of the fixed-step DOP853 period map at ``n_steps`` steps per segment.

    The derivative :func:`find_periodic_orbit_fixed_step` takes of its last pass
    (:attr:`FixedStepOrbit.monodromy`), at any step count: from the variational equations with
    ``jac`` (and ``param_jac`` with parameters) and no switches, else central differences of the
    discrete map. Evaluated at two step counts it gives an error estimate of the monodromy and
    its multipliers (their change), with no solve.

    Parameters
    ----------
    fun, jac, param_jac, free_params, breakpoints, switches, args, max_nfev
        As for :func:`find_periodic_orbit_fixed_step` (``free_params``: the parameters' values).
    x0 : array_like, shape (n,)
        The initial state (a point of the orbit, for a monodromy matrix).
    period : float
        The period T > 0.
    n_steps : int
        Steps per segment, in [2, :data:`MAX_STEPS`].
    difference_scale : float
        The central-difference step in units of the optimal one, in [0.1, 10] (central
        differences only): the monodromy at two scales tells the difference quotient's own
        error (truncation and rounding) apart from the mesh's.

    Returns
    -------
    ndarray, shape (n, n)
        Read-only.

    Raises
    ------
    ValueError
        For bad arguments, or a callable returning the wrong shape or a non-finite value at x0.
    TypeError
        ``args`` does not fit a callable's signature, or a callable returned None, a string,
        or complex or boolean values at x0.
    ConvergenceError
        If the integration produces a non-finite value or exceeds ``max_nfev``.
    """
    pmap, x, params, n = _checked_map(fun, jac, param_jac, x0, period, n_steps, free_params,
                                      breakpoints, switches, args, max_nfev, difference_scale)
    try:
        _, D = pmap.derivative(x, params, n, range(x.size))
    except (NonFinite, OutOfWork) as exc:
        raise ConvergenceError(f"the fixed-step monodromy at {n} steps per segment failed: "
                               f"{exc}", x=x) from None
    matrix = np.array(D, dtype=float)
    matrix.flags.writeable = False
    return matrix


def fixed_step_flow(
    fun: Callable[..., Any] | Sequence[Callable[..., Any]],
    x0: Any,
    period: float,
    *,
    n_steps: int,
    free_params: Any = None,
    breakpoints: Sequence[float] = (),
    switches: Sequence[Any] = (),
    args: tuple[Any, ...] = (),
    max_nfev: int | None = None,
) -> np.ndarray:
    """x(T) of the fixed-step DOP853 period map at ``n_steps`` steps per segment.

    The map :func:`find_periodic_orbit_fixed_step` solves, without its derivative: e.g. a
    quantity integrated along a solved orbit (a distance flown over the period) on the solve's
    own mesh.

    Parameters
    ----------
    fun, free_params, breakpoints, switches, args, max_nfev, n_steps
        As for :func:`fixed_step_monodromy`.
    x0 : array_like, shape (n,)
        The initial state.
    period : float
        The period T > 0.

    Returns
    -------
    ndarray, shape (n,)
        Read-only.

    Raises
    ------
    ValueError
        For bad arguments, or ``fun`` returning the wrong shape or a non-finite value at x0.
    TypeError
        ``args`` does not fit a callable's signature, or a callable returned None, a string,
        or complex or boolean values at x0.
    ConvergenceError
        If the integration produces a non-finite value or exceeds ``max_nfev``.
    """
    pmap, x, params, n = _checked_map(fun, None, None, x0, period, n_steps, free_params,
                                      breakpoints, switches, args, max_nfev)
    try:
        end = pmap.flow(x[None, :], None if params is None else params[None, :], n)[0]
    except (NonFinite, OutOfWork) as exc:
        raise ConvergenceError(f"the fixed-step integration at {n} steps per segment failed: "
                               f"{exc}", x=x) from None
    end = np.array(end, dtype=float)
    end.flags.writeable = False
    return end

"""Stability of the hovering orbit: Floquet multipliers, averaging, growth, sensitivity (Sec. IV).

Given a periodic orbit from :mod:`flapping.hover`, this module integrates the variational equations
over one period for the monodromy matrix and its Floquet multipliers (eqs. 42-49, 66-67) with the
Liouville check, compares them with the first-order averaged system (the cycle-averaged Jacobian
along the orbit, and its speed-pitch cubic), follows small perturbations with the full nonlinear
dynamics, and repeats the analysis for the modelling choices the paper leaves open.

Every function that integrates takes ``rtol`` and ``atol``; the defaults are
:data:`~flapping.hover.ANALYSIS_RTOL` and :data:`~flapping.hover.ANALYSIS_ATOL` (one decade tighter
than the orbit's own), and :data:`PERTURBATION_ATOL` for the simulations of a perturbed orbit.
Sampled trajectories have time along the last axis, as ``solve_ivp``'s ``y``.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field, fields
from typing import Any, overload

import numpy as np

from flapping import _validation
from flapping.backends import Adaptive, Backend, Compiled, FixedStep, warn_unused
from flapping.errors import HoverDriftWarning, require_success
from flapping.fast import kernel as _kernel
from flapping.hover._schema import StabilityViews
from flapping.hover.orbit import (
    ANALYSIS_ATOL,
    ANALYSIS_RTOL,
    HoverOrbit,
    Options,
    find_hover_orbit,
)
from flapping.hover.problem import DEFAULT_BACKEND, HoverProblem
from flapping.hover.sixdof import SixDofHoverOrbit, SixDofStability, sixdof_stability
from flapping.model.morphology import Insect
from flapping.periodic._readonly import freeze, readonly
from flapping.periodic.integrate import flow, variational_flow
from flapping.periodic.settings import SolverSettings
from flapping.results import Floquet

__all__ = [
    "HoverStability",
    "hover_stability",
    "mode_response",
    "PerturbationGrowth",
    "perturbation_growth",
    "DEFAULT_PERTURBATION",
    "simulate_perturbation",
    "SpeedPitchCubic",
    "speed_pitch_cubic",
    "describe_changes",
    "OPEN_CHOICES",
    "SensitivityRow",
    "hover_sensitivity",
    "PERTURBATION_ATOL",
]

#: Absolute tolerance of the simulations of a perturbed orbit (SI units of the states): two
#: decades below :data:`~flapping.hover.ANALYSIS_ATOL`, so that perturbations down to 1e-8 are
#: followed accurately from the first step.
PERTURBATION_ATOL = 1e-14

#: Largest perturbation of :func:`simulate_perturbation` (Euclidean, SI: 1 m/s, 1 rad/s or 1 rad
#: is already far outside the linear range the simulations compare with the multipliers).
MAX_EPSILON = 1.0

#: Most periods a perturbation is followed (each an adaptive integration at atol 1e-14), and most
#: output samples per period: caps on the work of one call.
MAX_PERIODS, MAX_SAMPLES_PER_PERIOD = 10_000, 1 << 14


@dataclass(frozen=True)
class HoverStability(StabilityViews):
    """Floquet stability of a periodic orbit (eqs. 42-49, 66-67) and the averaged approximation.

    Attributes
    ----------
    orbit : HoverOrbit
    monodromy : ndarray, shape (4, 4)
        Phi(T) of the variational equations along the orbit.
    multipliers : ndarray
        Floquet multipliers, sorted by modulus (descending).
    exponents : ndarray
        Floquet exponents log(mu)/T [1/s] (principal branch); -inf for a multiplier that is 0
        in floating point (a mode damped below ~1e-308 in one period).
    eigenvectors : ndarray, shape (4, 4)
        Column k is the eigenvector of the monodromy for ``multipliers[k]``.
    det, liouville_det : float
        det M and exp(int_0^T trace J dt); equal by Liouville's formula (either may under- or
        overflow to 0 or inf for a strongly damped or unstable orbit).
    averaged_jacobian : ndarray, shape (4, 4)
        (1/T) int_0^T J(t, x(t)) dt along the orbit: the first-order averaged system.
    averaged_eigenvalues : ndarray
        Its eigenvalues [1/s], sorted by real part (descending).
    trace_integral : float
        int_0^T trace J dt along the orbit, the logarithm of ``liouville_det`` (finite when
        that is not).
    multiplier_error : float
        Estimated largest absolute error of a multiplier, as the compiled kernel and
        :class:`~flapping.periodic.fixedstep.FixedStepOrbit` name it. On the compiled path the
        kernel's Richardson estimate. On the fixed-step path (``backend="fixed-step"``) twice
        the largest change of a multiplier between the monodromy at n and at 2n steps per
        half-stroke (the multipliers are the 2n ones; 2 is the safety factor of the fixed-step
        solve's own estimates). That change holds the truncation error and the rounding floor
        of the monodromy's central differences of the period map (~3e-10 on the hawkmoth,
        growing slowly with n), which dominates beyond ~32 steps on the linear loads: measured
        on the hawkmoth against an adaptive analysis at rtol 1e-13, 2.4e-10 off for an estimate
        of 1.1e-9 (linear loads), 4.7e-10 for 3.0e-9 (small-angle). NaN on the adaptive path,
        which has no estimate (``rtol`` bounds each step's local error, not the multipliers').
    """

    orbit: HoverOrbit
    monodromy: np.ndarray
    multipliers: np.ndarray
    exponents: np.ndarray
    eigenvectors: np.ndarray
    det: float
    liouville_det: float
    averaged_jacobian: np.ndarray
    averaged_eigenvalues: np.ndarray
    trace_integral: float = math.nan
    multiplier_error: float = math.nan
    # Computes the averaged Jacobian on first use of a field given as _LAZY (the multipliers do
    # not need it, and on the Python paths it is most of the analysis's time).
    _averaged: Callable[[], np.ndarray] | None = field(default=None, repr=False, compare=False)

    def __post_init__(self) -> None:
        freeze(self)  # an analysis of a result must be an analysis of what was solved
        lazy = [name for name in _LAZY_FIELDS if self.__dict__.get(name) is _LAZY]
        if lazy and self._averaged is None:
            raise ValueError(f"{', '.join(lazy)} given as lazy without a way to compute them")
        for name in lazy:  # absent from __dict__: __getattr__ computes them on first use
            del self.__dict__[name]

    def __getattr__(self, name: str) -> Any:
        # called only for attributes not in __dict__: the lazy fields not computed yet
        compute = self.__dict__.get("_averaged")
        if name not in _LAZY_FIELDS or compute is None:
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        averaged = np.array(compute(), dtype=float)
        eig = np.linalg.eigvals(averaged).astype(complex)  # always complex: one dtype for all
        trace = float(np.trace(averaged)) * self.orbit.period
        values = {"averaged_jacobian": readonly(averaged),
                  "averaged_eigenvalues": readonly(eig[np.argsort(-eig.real, kind="stable")]),
                  "trace_integral": trace,
                  "liouville_det": math.exp(trace) if trace < 700 else math.inf}
        for key in _LAZY_FIELDS:
            if key not in self.__dict__:
                object.__setattr__(self, key, values[key])
        return self.__dict__[name]

    @property
    def liouville_error(self) -> float:
        """Relative disagreement of det M and exp(int_0^T trace J dt) (Liouville's formula).

        ``|det M - L| / |L|`` with L = exp(int trace J) when both are finite and L is not 0.
        When they are not representable (under- or overflow), the same relative error from the
        logarithms, ``|exp(sum log|mu_k| - int trace J) - 1|``; ``nan`` if even that cannot be
        formed (a multiplier that is 0 or infinite in floating point): the check is impossible,
        not passed.
        """
        det, ref = self.det, self.liouville_det
        if math.isfinite(det) and math.isfinite(ref) and ref != 0.0:
            return abs(det - ref) / abs(ref)
        modulus = np.abs(self.multipliers)
        if not (np.all(np.isfinite(modulus)) and np.all(modulus > 0.0)
                and math.isfinite(self.trace_integral)):
            return math.nan
        log_ratio = float(np.sum(np.log(modulus))) - self.trace_integral
        return math.inf if log_ratio > 700.0 else abs(math.expm1(log_ratio))

    @property
    def floquet(self) -> Floquet:
        """The monodromy and its multipliers as the package's one type
        (:class:`~flapping.results.Floquet`), with :attr:`multiplier_error`."""
        return Floquet.of_matrix(self.monodromy, self.orbit.period, multipliers=self.multipliers,
                                 multiplier_error=self.multiplier_error,
                                 trace_integral=self.trace_integral)


# The dataclass leaves a field's default as a class attribute, which would shadow a lazy
# trace_integral (__getattr__ runs only when lookup fails); __init__ keeps its own copy.
del HoverStability.trace_integral


@dataclass(frozen=True)
class PerturbationGrowth:
    """Growth of a small perturbation of the orbit under the full nonlinear dynamics.

    Attributes
    ----------
    cycles : ndarray
        0, 1, ..., n.
    deviation : ndarray
        ``|x(kT) - x_orbit(0)|`` after k periods (Euclidean norm, SI units).
    growth_per_cycle : float
        Fitted deviation ratio per period over cycles ``fit_start`` ... n, where the growth is
        exponential (the decaying modes have died out).
    predicted : float
        Modulus of the largest Floquet multiplier.
    fit_start : int
        First cycle of the fit (two thirds of the way through the simulation).
    """

    cycles: np.ndarray
    deviation: np.ndarray
    growth_per_cycle: float
    predicted: float
    fit_start: int


@overload
def hover_stability(
    orbit: HoverOrbit,
    *,
    backend: Backend | str = DEFAULT_BACKEND,
    n_average: int = 64,
    method: str | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    rk4_steps: int | None = None,
    settings: SolverSettings | None = None,
) -> HoverStability: ...


@overload
def hover_stability(
    orbit: SixDofHoverOrbit,
    *,
    backend: Backend | str = DEFAULT_BACKEND,
    n_average: int = 64,
    method: str | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    rk4_steps: int | None = None,
    settings: SolverSettings | None = None,
) -> SixDofStability: ...


def hover_stability(
    orbit: HoverOrbit | SixDofHoverOrbit,
    *,
    backend: Backend | str = DEFAULT_BACKEND,
    n_average: int = 64,
    method: str | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    rk4_steps: int | None = None,
    settings: SolverSettings | None = None,
) -> HoverStability | SixDofStability:
    """Monodromy matrix, Floquet multipliers and the averaged system of a periodic orbit.

    The monodromy is Phi(T) of the variational equations (eqs. 42-49), its eigenvalues the
    Floquet multipliers, their logarithms over T the exponents (eq. 67); det M is checked against
    Liouville's formula exp(int_0^T trace J dt).

    Parameters
    ----------
    orbit : HoverOrbit or SixDofHoverOrbit
        A six-degree-of-freedom orbit (``find_hover_orbit(insect, dof=6)``) gets its eight
        multipliers from :func:`~flapping.hover.sixdof.sixdof_stability` (on the orbit's path,
        compiled or adaptive; ``rtol`` and ``atol`` apply to the adaptive one only), a
        :class:`~flapping.hover.sixdof.SixDofStability` with
        ``.longitudinal`` and ``.lateral`` views.
    backend : "auto", "compiled", "fixed-step", "adaptive", or a backend object
        The integration path of the monodromy (:mod:`flapping.backends`). ``"auto"`` (the
        default) analyses the orbit on the path that solved it
        (:func:`~flapping.hover.problem.choose_backend`): the compiled kernel gives every
        multiplier to 1e-8 (reusing the monodromy of the orbit's last Newton integration); the
        fixed-step path integrates the period map on the graded mesh at n and 2n steps per
        half-stroke (n the step count the orbit was solved with, else
        :class:`~flapping.backends.FixedStep`'s ``n_steps``) and reports the 2n multipliers
        with their change as :attr:`HoverStability.multiplier_error` (an absolute error: a tiny
        multiplier is known only to it, so Liouville's check, a product of the multipliers,
        reads poorly where one is tiny: 0.2 for the small-angle monarch, whose smallest is
        1.1e-9 against an estimate of 1.5e-8, where the adaptive path, a keyword away, gives
        2e-12); the adaptive path
        integrates the variational equations at :class:`~flapping.backends.Adaptive`'s
        ``analysis_rtol`` and ``analysis_atol``.
    n_average : int
        Gauss-Legendre nodes per half-stroke for the cycle-averaged Jacobian (the integrand is
        smooth within a half-stroke, so the rule converges spectrally).
    method, rtol, atol, rk4_steps, settings
        Shorthands for the adaptive path's options: ``rtol`` and ``atol`` are its
        ``analysis_rtol`` and ``analysis_atol`` (the monodromy's integration, and the orbit's
        for the averaged Jacobian off the compiled path); ``method`` ``"RK4"`` is the paper's
        fixed step, ``rk4_steps`` per period (another ``method`` selects the adaptive path under
        ``"auto"``); ``settings`` as for :func:`~flapping.hover.find_hover_orbit`.

    Returns
    -------
    HoverStability

    Raises
    ------
    ValueError
        For bad arguments.
    ConvergenceError
        If an integration fails.

    Warns
    -----
    OptionWarning
        If an option was given for a path that does not run.
    """
    # One validator for every path: the options become backend objects, checked when built.
    n_average = _validation.integer("n_average", n_average, low=1, high=1 << 16)
    options = Options.of(backend, method=method, rtol=rtol, atol=atol, rk4_steps=rk4_steps,
                         settings=settings, analysis=True)
    if isinstance(orbit, SixDofHoverOrbit):
        return _sixdof_stability(orbit, options)
    orbit = _validation.instance("orbit", orbit, HoverOrbit)
    problem = orbit.problem if orbit.problem is not None else HoverProblem.of_model(orbit.model)
    # The averaged Jacobian off the compiled path integrates the orbit at the analysis
    # tolerances: they apply to the fixed-step path too.
    path = options.choose(problem, solved=orbit.solver,
                          shared={FixedStep.name: ("analysis_rtol", "analysis_atol")})
    adaptive = options.adaptive
    rtol, atol = adaptive.analysis_rtol, adaptive.analysis_atol
    return path.analyse(orbit, problem, n_average, rtol, atol)


#: The adaptive options the six-degree-of-freedom analysis uses (its integrations' tolerances).
_SIXDOF_OPTIONS = ("analysis_rtol", "analysis_atol")


def _sixdof_stability(orbit: SixDofHoverOrbit, options: Options) -> SixDofStability:
    """hover_stability of a six-degree-of-freedom orbit: on the compiled path (the linear
    loads) or the adaptive one (DOP853, ``rtol`` and ``atol``); every other option given is
    warned about (:class:`~flapping.backends.OptionWarning`)."""
    spec = options.requested
    if not isinstance(spec, str) and not spec.sixdof_analyses:
        raise ValueError(f"a six-degree-of-freedom orbit is analysed on the adaptive path, or on "
                         f"the compiled one for the linear loads; got backend={spec.name!r}")
    if options.adaptive.method != "DOP853":
        raise ValueError("a six-degree-of-freedom orbit is analysed with DOP853: leave `method` "
                         f"at its default; got {options.adaptive.method!r}")
    if isinstance(spec, str):
        name = "auto"
        compiled = orbit.backend == Compiled.name
    else:
        compiled = spec.sixdof_compiled
        name = Compiled.name if compiled else "adaptive"
    given = options.given[Adaptive.name]
    used = () if compiled else _SIXDOF_OPTIONS
    warn_unused({k: v for k, v in given.items() if k not in used and k != "method"},
                f"six-degree-of-freedom {'compiled' if compiled else 'adaptive'}",
                stacklevel=3)
    return sixdof_stability(orbit, rtol=given.get("analysis_rtol"),
                            atol=given.get("analysis_atol"), backend=name)


class _Lazy:
    """The marker of a HoverStability field computed on first use."""

    def __repr__(self) -> str:
        return "<lazy>"


_LAZY: Any = _Lazy()

#: The HoverStability fields that may be given as _LAZY: the averaged Jacobian's, and (on the
#: fixed-step path, where they are its Gauss rule's) int trace J dt and its exponential.
_LAZY_FIELDS = ("averaged_jacobian", "averaged_eigenvalues", "trace_integral", "liouville_det")


def _stability(orbit: HoverOrbit, matrix: np.ndarray, values: np.ndarray, det: float,
               liouville: float, averaged: np.ndarray | Callable[[], np.ndarray],
               trace: float, error: float) -> HoverStability:
    """The HoverStability of a monodromy, its multipliers and the averaged Jacobian.

    ``averaged`` may be a function computing it on first use; ``liouville`` and ``trace`` may
    then be ``_LAZY`` (the Gauss rule's, from it).
    """
    # The eigenvectors from eig(M), matched to the multipliers by nearest eigenvalue.
    eig_values, eig_vectors = np.linalg.eig(matrix)
    match = [int(np.argmin(np.abs(eig_values - mu))) for mu in values]
    vectors = eig_vectors[:, match].astype(complex)
    common = (orbit, np.array(matrix, dtype=float), values, _exponents(values, orbit.period),
              vectors, float(det))
    if callable(averaged):
        return HoverStability(*common, _LAZY if liouville is _LAZY else float(liouville), _LAZY,
                              _LAZY, _LAZY if trace is _LAZY else float(trace), float(error),
                              averaged)
    avg_eig = np.linalg.eigvals(averaged).astype(complex)  # always complex: one dtype for all
    avg_eig = avg_eig[np.argsort(-avg_eig.real, kind="stable")]
    return HoverStability(*common, float(liouville), np.array(averaged, dtype=float), avg_eig,
                          float(trace), float(error))


def _kernel_problem(orbit: HoverOrbit) -> _kernel.KernelProblem:
    """The orbit's insect packed for the kernel (the problem's own packing when it has one)."""
    if orbit.problem is not None:
        return orbit.problem.kernel_problem
    return _kernel.KernelProblem.of(orbit.model.insect, orbit.model.alpha_m)


def _exponents(multipliers: np.ndarray, period: float) -> np.ndarray:
    """log(mu) / T, with -inf (not -inf + nan i) for a multiplier that is exactly 0."""
    with np.errstate(divide="ignore", invalid="ignore"):
        exponents = np.log(multipliers) / period
    exponents[multipliers == 0] = complex(-math.inf, 0.0)
    return exponents


def _averaged_jacobian(orbit: HoverOrbit, n_nodes: int, rtol: float, atol: float,
                       compiled: bool = False) -> np.ndarray:
    """(1/T) int_0^T J(t, x(t)) dt by Gauss-Legendre, ``n_nodes`` nodes per half-stroke."""
    if compiled:
        quad = _kernel.orbit_quadrature(_kernel_problem(orbit), orbit.x0, orbit.amplitude,
                                        n_nodes)
        return np.array(quad.averaged_jacobian)
    model = orbit.model
    rhs, jac = model.segment_functions()
    nodes, weights = np.polynomial.legendre.leggauss(n_nodes)  # ascending nodes
    bounds = np.array((0.0,) + tuple(model.breakpoints) + (1.0,)) * orbit.period
    half = 0.5 * np.diff(bounds)
    # Gauss-Legendre nodes of every segment, in time order: one integration of the orbit.
    t_all = np.concatenate([h * nodes + a + h for a, h in zip(bounds[:-1], half, strict=True)])
    x_all = require_success(
        flow(rhs, (0.0, orbit.period), orbit.x0, breakpoints=model.breakpoints,
             period=orbit.period, t_eval=t_all, rtol=rtol, atol=atol),
        "the averaged Jacobian").x
    total = np.zeros((4, 4))
    for i, (t, x) in enumerate(zip(t_all, x_all.T, strict=True)):
        k = i // n_nodes
        total += half[k] * weights[i % n_nodes] * jac[k](t, x)
    return total / orbit.period


def mode_response(
    stability: HoverStability,
    *,
    mode: int = 0,
    n_periods: int = 1,
    samples_per_period: int = 48,
    rtol: float | None = None,
    atol: float | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Time history of a Floquet mode along the orbit: delta x(t) = Phi(t, 0) v_k.

    Parameters
    ----------
    stability : HoverStability
    mode : int
        Index into ``stability.multipliers`` (0: the largest).
    n_periods : int
        Number of periods to follow (>= 1).
    samples_per_period : int
        Output samples per period (>= 2).
    rtol, atol : float, optional
        Tolerances of the variational equations' integration (default
        :data:`~flapping.hover.ANALYSIS_RTOL` and :data:`~flapping.hover.ANALYSIS_ATOL`).

    Returns
    -------
    t : ndarray, shape (m,)
    delta : ndarray, shape (4, m)
        The linearised response to a disturbance equal to the eigenvector (scaled to max 1);
        after k periods it equals mu_k^k v_k.

    Raises
    ------
    ValueError
        For bad arguments.
    ConvergenceError
        If the integration fails.
    """
    stability = _validation.instance("stability", stability, HoverStability)
    n_periods = _validation.integer("n_periods", n_periods, low=1, high=MAX_PERIODS)
    samples_per_period = _validation.integer("samples_per_period", samples_per_period, low=2,
                                             high=MAX_SAMPLES_PER_PERIOD)
    mode = _validation.integer("mode", mode, low=0, high=stability.multipliers.size - 1)
    rtol, atol = _validation.tolerances(ANALYSIS_RTOL if rtol is None else rtol,
                                        ANALYSIS_ATOL if atol is None else atol)
    orbit = stability.orbit
    model = orbit.model
    v = stability.eigenvectors[:, mode]
    v = v / v[np.argmax(np.abs(v))]
    if stability.multipliers[mode].imag == 0.0:
        v = np.real(v)
    t = np.linspace(0.0, n_periods * orbit.period, samples_per_period * n_periods + 1)
    rhs, jac = model.segment_functions()
    var = require_success(
        variational_flow(rhs, jac, (0.0, t[-1]), orbit.x0, breakpoints=model.breakpoints,
                         period=orbit.period, t_out=t[1:], rtol=rtol, atol=atol),
        "the mode's response")
    delta = np.column_stack([v, np.einsum("ijk,j->ik", var.stm, v)])
    return t, delta


#: A generic perturbation direction in (u, w, q, theta) (not an eigenvector), before normalising.
DEFAULT_PERTURBATION = (1.0, -0.7, 3.0, 0.2)


def _unit_direction(direction) -> np.ndarray:
    direction = _validation.vector(
        "direction", DEFAULT_PERTURBATION if direction is None else direction, size=4)
    if not np.any(direction):
        raise ValueError(f"`direction` must not be all zero; got {direction!r}")
    return direction / np.linalg.norm(direction)


def perturbation_growth(
    stability: HoverStability,
    *,
    epsilon: float = 1e-6,
    n_periods: int = 30,
    direction: np.ndarray | None = None,
    rtol: float | None = None,
    atol: float | None = None,
) -> PerturbationGrowth:
    """Simulate the full nonlinear dynamics from the orbit plus a small perturbation.

    The perturbation (default: a generic direction, not an eigenvector) grows, after a transient, by
    the largest multiplier per period; the growth is fitted over the last third of the cycles.

    Parameters
    ----------
    stability : HoverStability
    epsilon : float
        Size of the initial perturbation (Euclidean, SI units), in (0, 1e-3 max|x|] so that it
        stays linear over the fit.
    n_periods : int
        Periods simulated (>= 3).
    direction : array_like of 4 floats, optional
        Direction of the perturbation in (u, w, q, theta); default :data:`DEFAULT_PERTURBATION`.
    rtol, atol : float, optional
        Tolerances of the simulation (default :data:`~flapping.hover.ANALYSIS_RTOL` and
        :data:`PERTURBATION_ATOL`).

    Returns
    -------
    PerturbationGrowth

    Raises
    ------
    ValueError
        For bad arguments.
    ConvergenceError
        If the integration fails.
    """
    stability = _validation.instance("stability", stability, HoverStability)
    orbit = stability.orbit
    model = orbit.model
    scale = float(np.abs(orbit.x).max())
    epsilon = _validation.real("epsilon", epsilon, low=0.0, low_open=True, high=1e-3 * scale)
    n_periods = _validation.integer("n_periods", n_periods, low=3, high=MAX_PERIODS)
    rtol, atol = _validation.tolerances(ANALYSIS_RTOL if rtol is None else rtol,
                                        PERTURBATION_ATOL if atol is None else atol)
    direction = _unit_direction(direction)
    rhs, _ = model.segment_functions()
    times = orbit.period * np.arange(n_periods + 1)
    res = require_success(
        flow(rhs, (0.0, times[-1]), orbit.x0 + epsilon * direction,
             breakpoints=model.breakpoints, period=orbit.period, t_eval=times, rtol=rtol,
             atol=atol),
        "the perturbed simulation")
    deviation = np.linalg.norm(res.x - orbit.x0[:, None], axis=0)
    start = (2 * n_periods) // 3  # after the transient of the decaying modes
    slope = np.polyfit(np.arange(start, n_periods + 1), np.log(deviation[start:]), 1)[0]
    return PerturbationGrowth(np.arange(n_periods + 1), deviation, float(np.exp(slope)),
                              float(np.abs(stability.multipliers[0])), start)


def simulate_perturbation(
    orbit: HoverOrbit,
    epsilon: float,
    *,
    n_periods: int = 30,
    direction=None,
    samples_per_period: int = 64,
    rtol: float | None = None,
    atol: float | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The full nonlinear dynamics from x0 + epsilon * direction, beside the unperturbed orbit.

    Parameters
    ----------
    orbit : HoverOrbit
    epsilon : float
        Size of the perturbation (Euclidean, SI units), > 0.
    n_periods : int
        Periods simulated (>= 1).
    direction : array_like of 4 floats, optional
        As for :func:`perturbation_growth`.
    samples_per_period : int
        Output samples per period (>= 1).
    rtol, atol : float, optional
        Tolerances of both simulations (default :data:`~flapping.hover.ANALYSIS_RTOL` and
        :data:`PERTURBATION_ATOL`).

    Returns
    -------
    t : ndarray, shape (m,)
        Times over ``n_periods`` periods [s].
    x_perturbed, x_orbit : ndarray, shape (4, m)
        The perturbed trajectory and the orbit integrated from x0 (which itself departs from the
        orbit eventually, the orbit being unstable, from its round-off-level closure error).

    Raises
    ------
    ValueError
        For bad arguments.
    ConvergenceError
        If an integration fails.
    """
    orbit = _validation.instance("orbit", orbit, HoverOrbit)
    epsilon = _validation.real("epsilon", epsilon, low=0.0, low_open=True, high=MAX_EPSILON)
    n_periods = _validation.integer("n_periods", n_periods, low=1, high=MAX_PERIODS)
    samples_per_period = _validation.integer("samples_per_period", samples_per_period, low=1,
                                             high=MAX_SAMPLES_PER_PERIOD)
    rtol, atol = _validation.tolerances(ANALYSIS_RTOL if rtol is None else rtol,
                                        PERTURBATION_ATOL if atol is None else atol)
    start = orbit.x0 + epsilon * _unit_direction(direction)
    model = orbit.model
    rhs, _ = model.segment_functions()
    t = np.linspace(0.0, n_periods * orbit.period, samples_per_period * n_periods + 1)

    def simulate(x0: np.ndarray, what: str) -> np.ndarray:
        return require_success(flow(rhs, (0.0, t[-1]), x0, breakpoints=model.breakpoints,
                                    period=orbit.period, t_eval=t, rtol=rtol, atol=atol), what).x

    return (t, simulate(start, "the perturbed simulation"),
            simulate(orbit.x0, "the orbit's simulation"))


@dataclass(frozen=True)
class SpeedPitchCubic:
    """The averaged speed-pitch subsystem (u, q, theta) and its characteristic polynomial.

    With the vertical speed decoupled (its averaged couplings vanish by symmetry at x_h = 0):
    u' = Xu u + Xq q - g theta, q' = Mu u + Mq q, theta' = q, whose characteristic polynomial is

        c(lambda) = lambda (lambda - Xu)(lambda - Mq) - Xq Mu lambda + g Mu.

    Attributes
    ----------
    Xu, Xq, Mu, Mq, g : float
        The entries of the averaged Jacobian used (g is the -J[0, 3] entry, g cos(theta) on the
        orbit's mean).
    coefficients : ndarray
        Of c, highest power first.
    roots : ndarray
        Roots of c, sorted by real part (descending).
    quasi_static_root : float
        Positive root of lambda^2 - Xu lambda - g Mu / Mq = 0, the approximation in which the
        pitch rate follows the speed at once (large ``|Mq|``): a negative pitch stiffness.
    routh_hurwitz : tuple of float
        (a2 a1, a0) of c = lambda^3 + a2 lambda^2 + a1 lambda + a0; all roots in the left
        half-plane iff a2, a1, a0 > 0 and a2 a1 > a0.
    """

    Xu: float
    Xq: float
    Mu: float
    Mq: float
    g: float
    coefficients: np.ndarray
    roots: np.ndarray
    quasi_static_root: float
    routh_hurwitz: tuple[float, float]


def speed_pitch_cubic(averaged_jacobian: np.ndarray, *, flip_mu: bool = False) -> SpeedPitchCubic:
    """Characteristic cubic of the averaged speed-pitch subsystem (see :class:`SpeedPitchCubic`).

    Parameters
    ----------
    averaged_jacobian : ndarray, shape (4, 4)
        E.g. :attr:`HoverStability.averaged_jacobian` or
        :meth:`~flapping.model.derivatives.StabilityDerivatives.averaged_jacobian`.
    flip_mu : bool
        Reverse the sign of Mu (a what-if: the speed-pitch coupling of wings above the CG).

    Returns
    -------
    SpeedPitchCubic

    Raises
    ------
    ValueError
        If ``averaged_jacobian`` is not a finite 4x4 array.
    """
    J = np.asarray(averaged_jacobian, dtype=float)
    if J.shape != (4, 4) or not np.all(np.isfinite(J)):
        raise ValueError("averaged_jacobian must be a finite 4x4 array")
    Xu, Xq, g = J[0, 0], J[0, 2], -J[0, 3]
    Mu, Mq = (-1.0 if flip_mu else 1.0) * J[2, 0], J[2, 2]
    coeffs = np.array([1.0, -(Xu + Mq), Xu * Mq - Xq * Mu, g * Mu])
    roots = np.roots(coeffs).astype(complex)
    roots = roots[np.argsort(-roots.real, kind="stable")]
    stiffness = g * Mu / Mq
    disc = Xu**2 + 4.0 * stiffness
    qs = 0.5 * (Xu + math.sqrt(disc)) if disc >= 0 else float("nan")
    return SpeedPitchCubic(float(Xu), float(Xq), float(Mu), float(Mq), float(g), coeffs, roots,
                           qs, (float(coeffs[1] * coeffs[2]), float(coeffs[3])))


def describe_changes(changes: dict) -> str:
    """A short label for a set of :class:`~flapping.model.morphology.Insect` field changes.

    Built from the values themselves, so that a table of variants never repeats a number by hand:
    ``{"hinge_offset": 1e-3}`` -> ``"x_h = +1 mm"``; ``{}`` -> the defaults of :class:`Insect`.

    Parameters
    ----------
    changes : dict
        :class:`Insect` field name -> new value.

    Returns
    -------
    str
    """
    defaults: dict[str, Any] = {f.name: f.default for f in fields(Insect) if f.init}
    if not changes:
        return (f"defaults (AR = 2R^2/S, x_hat = {defaults['center_of_pressure']:g}, "
                f"x0_hat = {defaults['pitch_axis']:g}, x_h = {defaults['hinge_offset'] * 1e3:g} mm)"
                if defaults["aspect_ratio_convention"] == "pair" else "defaults")
    parts = []
    for key, value in changes.items():
        if key == "aspect_ratio_convention":
            parts.append("AR = R^2/S in eq. (4)" if value == "single" else "AR = 2R^2/S in eq. (4)")
        elif key == "center_of_pressure":
            parts.append(f"x_hat = {value:g}")
        elif key == "pitch_axis":
            parts.append(f"x0_hat = {value:g}")
        elif key == "hinge_offset":
            parts.append(f"x_h = {value * 1e3:+g} mm")
        elif key in ("mu1", "mu2") and set(changes) >= {"mu1", "mu2"} and not changes["mu1"] \
                and not changes["mu2"]:
            if key == "mu1":
                parts.append("no rotational damping (mu1 = mu2 = 0)")
        else:
            parts.append(f"{key} = {value:g}" if isinstance(value, (int, float))
                         else f"{key} = {value}")
    return ", ".join(parts)


_OPEN_CHOICE_CHANGES: tuple[dict, ...] = (
    {},
    {"aspect_ratio_convention": "single"},
    {"center_of_pressure": 0.15},
    {"center_of_pressure": 0.35},
    {"pitch_axis": 0.25},
    {"hinge_offset": 1e-3},
    {"hinge_offset": -1e-3},
    {"mu1": 0.0, "mu2": 0.0},
)


#: Modelling choices the paper leaves open, as Insect field changes from the defaults, keyed by
#: their :func:`describe_changes` label.
OPEN_CHOICES: dict[str, dict] = {describe_changes(c): c for c in _OPEN_CHOICE_CHANGES}


@dataclass(frozen=True)
class SensitivityRow:
    """Hover orbit and stability of one variant of the insect."""

    label: str
    changes: dict
    alpha_m_deg: float
    amplitude_deg: float
    multipliers: np.ndarray
    averaged_eigenvalues: np.ndarray
    mean_forward_velocity: float
    stability: HoverStability = field(repr=False)

    @property
    def orbit(self) -> HoverOrbit:
        """The variant's hover orbit."""
        return self.stability.orbit

    @property
    def largest_multiplier(self) -> float:
        """Modulus of the largest Floquet multiplier."""
        return float(np.abs(self.multipliers[0]))

    @property
    def is_hover(self) -> bool:
        """Whether the variant's orbit is hover (:attr:`flapping.hover.HoverOrbit.is_hover`)."""
        return self.orbit.is_hover


def hover_sensitivity(
    insect: Insect,
    variations: dict[str, dict] | None = None,
    *,
    aerodynamics: str = "linear",
) -> list[SensitivityRow]:
    """Hover amplitude and multipliers for variants of ``insect`` (default :data:`OPEN_CHOICES`).

    Each variant is re-trimmed (eq. 40) and its hover orbit found from the default guess. With
    x_h != 0 the half-period symmetry is lost, and the hover orbit (which fixes only the vertical
    drift) may drift horizontally: its mean forward velocity and ``is_hover`` are reported in its
    row, and the :class:`~flapping.errors.HoverDriftWarning` of :func:`find_hover_orbit` is not
    repeated.

    Parameters
    ----------
    insect : Insect
        The base insect.
    variations : dict, optional
        Label -> dict of :class:`Insect` field changes.
    aerodynamics : {"linear", "small-angle", "exact"}
        Loads model.

    Returns
    -------
    list of SensitivityRow
        One row per variation, in order, each carrying its orbit and stability.

    Raises
    ------
    ValueError, ConvergenceError
        As :func:`find_hover_orbit` for any variant.
    """
    insect = _validation.instance("insect", insect, Insect)
    variations = OPEN_CHOICES if variations is None else variations
    rows = []
    for label, changes in variations.items():
        variant = insect.with_(**changes)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", HoverDriftWarning)  # reported in the row instead
            orbit = find_hover_orbit(variant, aerodynamics=aerodynamics)
        stab = hover_stability(orbit)
        rows.append(SensitivityRow(label, dict(changes), math.degrees(orbit.model.alpha_m),
                                   orbit.amplitude_deg, stab.multipliers,
                                   stab.averaged_eigenvalues,
                                   orbit.mean_inertial_velocity["forward"], stab))
    return rows

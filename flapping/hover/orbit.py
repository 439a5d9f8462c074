"""The hovering periodic orbit of a flapping insect and its Floquet stability (paper Sec. IV).

Hover is a periodic orbit of the time-periodic longitudinal dynamics whose body does not climb or
sink on average. We solve for the initial state (u, w, q, theta) *and* the stroke amplitude Phi with
the optimized shooting method, on the state augmented with the inertial vertical displacement z
(positive down):

    z' = -u sin(theta) + w cos(theta),        z(0) = 0 held fixed,

so that periodicity of the augmented state, z(T) = z(0), is the hover condition: zero net change
of altitude over a period (zero mean inertial vertical speed). Five equations, five unknowns.

The paper's own condition (its "virtual state" h = w sin(theta) - u cos(theta), required to be
periodic) is examined by :func:`paper_hover_problem`: h is a function of the state, so h(T) = h(0)
follows from periodicity of u, w, theta and adds no equation; Phi is then left undetermined and the
solver returns one member of a family of climbing or sinking periodic orbits.

The hover condition fixes the mean *vertical* speed only. With the half-period symmetry of the
stroke broken (a wing hinge offset from the centre of gravity) the orbit it finds may fly forwards
or backwards on average: :attr:`HoverOrbit.is_hover` says whether it does, and
:func:`find_hover_orbit` warns (:class:`~flapping.errors.HoverDriftWarning`) when it does.

The stability of the orbit (Floquet multipliers, averaging, perturbation growth, sensitivity to
the modelling choices) is in :mod:`flapping.hover.stability`.

Conventions: SI units inside (angles in rad); sampled trajectories have time along the last axis
(``x[i, k]`` is state i at ``t[k]``), as ``solve_ivp``'s ``y``.
"""

from __future__ import annotations

import logging
import math
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from dataclasses import fields as dataclass_fields
from functools import cached_property
from typing import TYPE_CHECKING, Any, ClassVar, Literal, TypeVar, cast, overload

import numpy as np
from numpy.typing import ArrayLike

from flapping import _validation
from flapping.backends import (
    AUTO,
    Adaptive,
    Backend,
    Compiled,
    FixedStep,
    as_backend,
    warn_unused,
)
from flapping.errors import ConvergenceError, HoverDriftWarning, NonFiniteError, require_success
from flapping.fast import kernel as _kernel
from flapping.hover._schema import HOVER_SPEED_ATOL, HOVER_SPEED_RTOL, OrbitViews
from flapping.hover.problem import (
    DEFAULT_BACKEND,
    TRIMS,
    HoverProblem,
    check_trims,
    choose_backend,
    even_samples,
    state_guess,
)
from flapping.model.dynamics import STATE_NAMES, LongitudinalDynamics
from flapping.model.kinematics import segment_stroke_sign
from flapping.model.morphology import Insect, explain_blowup
from flapping.periodic._readonly import freeze, readonly
from flapping.periodic.fixedstep import (
    FixedStepOrbit,
)
from flapping.periodic.integrate import flow, variational_flow
from flapping.periodic.settings import SolverSettings
from flapping.periodic.shooting import PeriodicOrbit, find_periodic_orbit
from flapping.results import Floquet, HoverStatus, Stats, Status

if TYPE_CHECKING:  # annotations only: the six-degree-of-freedom module lies above this one
    from flapping.hover.sixdof import SixDofHoverOrbit

#: The six-degree-of-freedom solve behind ``find_hover_orbit(..., dof=6)``: registered by
#: :mod:`flapping.hover.sixdof` (which builds on this module) when the hover layer is imported.
_SIXDOF_SOLVE: list[Callable[..., Any]] = []


def register_sixdof(solve: Callable[..., Any]) -> None:
    """Register the six-degree-of-freedom solve (:func:`~flapping.hover.sixdof.
    find_sixdof_hover_orbit`): this module does not import the module above it."""
    _SIXDOF_SOLVE[:] = [solve]


__all__ = [
    "ANALYSIS_ATOL",
    "ANALYSIS_RTOL",
    "HALF_PERIOD_SYMMETRY",
    "HOVER_SPEED_ATOL",
    "HOVER_SPEED_RTOL",
    "HoverOrbit",
    "HOVER_METHODS",
    "HoverStatus",
    "find_hover_orbit",
    "forced_orbit",
    "paper_hover_problem",
    "force_budget",
    "use_kernel",
]

_LOG = logging.getLogger("flapping")

#: x(t + T/2) = S x(t) for the symmetric stroke (x_h = 0): u, q, theta change sign, w does not.
HALF_PERIOD_SYMMETRY = np.diag([-1.0, 1.0, -1.0, -1.0])

#: Default tolerances (relative; absolute in the states' SI units) of the integrations that
#: analyse a found orbit (its force budget here; its averaged Jacobian, Floquet modes and
#: perturbations in :mod:`flapping.hover.stability`): :class:`~flapping.backends.Adaptive`'s
#: ``analysis_rtol`` and ``analysis_atol``, a decade tighter than the orbit's own.
ANALYSIS_RTOL: float = Adaptive.analysis_rtol
#: Default absolute tolerance of those analysis integrations (see :data:`ANALYSIS_RTOL`).
ANALYSIS_ATOL: float = Adaptive.analysis_atol


# =========================================================================== results
@dataclass(frozen=True)
class _Sampled:
    """Samples computed with the orbit (the adaptive path integrates them anyway)."""

    t: np.ndarray
    x: np.ndarray

    def __call__(self) -> tuple[np.ndarray, np.ndarray]:
        return self.t, self.x


@dataclass(frozen=True)
class _KernelSamples:
    """Samples the compiled kernel integrates on first use (they cost more than the solve)."""

    problem: Any
    x0: np.ndarray
    amplitude: float
    n_samples: int

    def __call__(self) -> tuple[np.ndarray, np.ndarray]:
        t, x, _ = _kernel.sample_orbit(self.problem, self.x0, self.amplitude, self.n_samples)
        return t, x


@dataclass(frozen=True)
class _AdaptiveSamples:
    """Samples integrated by the adaptive path on first use (the adaptive and fixed-step paths'
    orbits)."""

    model: LongitudinalDynamics
    x0: np.ndarray
    n_samples: int
    method: str
    rtol: float
    atol: float

    def __call__(self) -> tuple[np.ndarray, np.ndarray]:
        t, x, _ = _sample(self.model, self.x0, self.n_samples, self.method, rtol=self.rtol,
                          atol=self.atol)
        return t, x


@dataclass(frozen=True, eq=False)
class HoverOrbit(OrbitViews):
    """A periodic orbit of the insect (the hovering one, or one at a prescribed amplitude).

    Whatever backend produced it, the orbit has the same attributes; arrays are read-only.

    Attributes
    ----------
    problem : HoverProblem or None
        The hover problem solved (None for :func:`forced_orbit`, which solves no trim).
    x0 : ndarray, shape (4,)
        (u, w, q, theta) at t = 0 (stroke reversal at the forward extreme) [m/s, m/s, rad/s, rad].
    amplitude : float
        Stroke amplitude Phi [rad].
    stroke_mean : float
        Mean stroke angle phi_bar [rad] (a trim when ``"stroke_mean"`` is in :attr:`trims`).
    z_drift : float
        Net descent z(T) - z(0) over one period [m]: for :func:`find_hover_orbit` the altitude
        component of the residual (0 to the solver's tolerance), for :func:`forced_orbit` the
        descent integrated along the orbit.
    backend : {"compiled", "adaptive", "fixed-step"}
        The path that solved it.
    nit, nfev : int
        Newton (or Levenberg-Marquardt) iterations and right-hand-side evaluations.
    residual_norm : float
        Norm of the periodicity residual at the solution.
    shooting : PeriodicOrbit or None
        The adaptive path's shooting result, with its diagnostics (None on the compiled path).
    kernel : HoverSolution or None
        The compiled kernel's result (monodromy, error estimates) when it found the orbit.
    fixed_step : FixedStepOrbit or None
        The fixed-step path's result when it found the orbit: the Richardson error estimate of
        every unknown (:attr:`~flapping.periodic.fixedstep.FixedStepOrbit.unknowns_error`, the
        states then the trims), the monodromy of the augmented state, its multipliers and their
        error estimate, the step count per half-stroke. The unknowns' estimate bounds their
        error (checked against solves at more steps); the multipliers' is the integration
        error's Richardson estimate and can understate it where the convergence in the step
        count is not yet regular (measured on the hawkmoth, small-angle, 64 steps: 1.9e-10 from
        the adaptive analysis against an estimate of 5.8e-11).
        ``hover_stability(orbit, backend="fixed-step")`` gives the multipliers at twice the
        steps with the change as their error estimate
        (:attr:`~flapping.hover.stability.HoverStability.multiplier_error`).
    mean_velocity : ndarray or None
        (forward, climb) cycle means of the inertial velocities [m/s] from the solve's own
        integration, where its path has them (the kernel's Newton integration; the fixed-step
        path's mesh); None: :attr:`mean_inertial_velocity` takes them from the samples.
    solver : Compiled, FixedStep or Adaptive, or None
        The backend object that solved it, with its options (:mod:`flapping.backends`).
    stats : Stats or None
        The solve's work: iterations, evaluations, wall-clock time
        (:class:`~flapping.results.Stats`).
    amplitude_error, x0_error, multiplier_error : float
        The solve's error estimates, whatever path produced it: of Phi [rad], of x0 (largest
        over the components, SI) and of the Floquet multipliers (largest absolute), on the
        compiled and fixed-step paths from their Richardson estimates (see :attr:`kernel` and
        :attr:`fixed_step` for what they were measured to be). NaN on the adaptive path, which
        has none (``rtol`` bounds each step's local error, not the unknowns').
    solve_status : Status
        The solve's outcome (:class:`~flapping.results.Status`): ``SUCCESS`` for a returned
        orbit (a failed solve raises :class:`~flapping.errors.ConvergenceError`). :attr:`status`
        says what the orbit is (hover, drifting or climbing).
    """

    problem: HoverProblem | None
    x0: np.ndarray
    amplitude: float
    stroke_mean: float
    z_drift: float
    backend: str
    nit: int
    nfev: int
    residual_norm: float
    shooting: PeriodicOrbit | None = field(default=None, repr=False)
    kernel: _kernel.HoverSolution | None = field(default=None, repr=False)
    samples: _Sampled | _KernelSamples | _AdaptiveSamples | None = field(default=None,
                                                                         repr=False)
    model_given: LongitudinalDynamics | None = field(default=None, repr=False)
    fixed_step: FixedStepOrbit | None = field(default=None, repr=False)
    mean_velocity: np.ndarray | None = field(default=None, repr=False)
    solver: Backend | None = field(default=None, repr=False)
    stats: Stats | None = field(default=None, repr=False)
    amplitude_error: float = field(default=math.nan, repr=False)
    x0_error: float = field(default=math.nan, repr=False)
    multiplier_error: float = field(default=math.nan, repr=False)
    solve_status: Status = field(default=Status.SUCCESS, repr=False)

    state_names: ClassVar[tuple[str, ...]] = STATE_NAMES
    half_period_symmetry: ClassVar[np.ndarray] = HALF_PERIOD_SYMMETRY

    def __post_init__(self) -> None:
        freeze(self)  # an analysis of the orbit must be an analysis of what was solved

    @cached_property
    def model(self) -> LongitudinalDynamics:
        """The dynamics at the orbit's amplitude and mean stroke angle."""
        if self.model_given is not None:
            return self.model_given
        assert self.problem is not None
        model = self.problem.model
        if self.stroke_mean != model.insect.stroke_mean:
            model = model.with_stroke_mean(self.stroke_mean)
        return model if self.amplitude == model.amplitude else model.with_amplitude(self.amplitude)

    @property
    def alpha_m(self) -> float:
        """Mean geometric angle of attack [rad], held while the trims were solved for."""
        if self.problem is None or self.problem.alpha_m is None:
            return self.model.alpha_m
        return self.problem.alpha_m

    @property
    def period(self) -> float:
        """Flapping period T [s]."""
        return self.model.period if self.problem is None else self.problem.period

    @property
    def trims(self) -> tuple[str, ...]:
        """The trim unknowns solved for (:data:`TRIMS`); empty for :func:`forced_orbit`."""
        return () if self.problem is None else self.problem.trims

    @cached_property
    def _sampled(self) -> tuple[np.ndarray, np.ndarray]:
        if self.samples is None:
            raise ValueError("this orbit was built without its samples (samples=None)")
        t, x = self.samples()
        return readonly(np.asarray(t, dtype=float)), readonly(np.asarray(x, dtype=float))

    @property
    def t(self) -> np.ndarray:
        """One period's sample times [s] (uniform; integrated on first use on the compiled path)."""
        return self._sampled[0]

    @property
    def x(self) -> np.ndarray:
        """The states at :attr:`t`, shape (4, len(t)) [m/s, m/s, rad/s, rad]."""
        return self._sampled[1]

    @cached_property
    def floquet(self) -> Floquet | None:
        """The monodromy of (u, w, q, theta) and its multipliers from the solve's own last
        integration, where its path has them (compiled, fixed-step; with the solve's
        :attr:`multiplier_error`); None on the adaptive path
        (:func:`~flapping.hover.stability.hover_stability` computes them for any orbit)."""
        if self.kernel is not None:
            return Floquet.of_matrix(self.kernel.monodromy, self.period,
                                     multipliers=self.kernel.multipliers,
                                     multiplier_error=self.multiplier_error,
                                     trace_integral=self.kernel.trace_integral)
        if self.fixed_step is not None:  # the augmented state's: z and x_e do not feed back
            return Floquet.of_matrix(np.asarray(self.fixed_step.monodromy)[:4, :4], self.period,
                                     multiplier_error=self.multiplier_error)
        return None

    @cached_property
    def mean_inertial_velocity(self) -> dict[str, float]:
        """Cycle means of the inertial velocities [m/s]: ``forward`` and ``climb`` (up positive).

        On the compiled and fixed-step paths from their own integration (x_e(T) / T and
        -z(T) / T, integrated with the orbit); from the samples otherwise.
        """
        if self.mean_velocity is not None:
            forward, climb = self.mean_velocity
            return {"forward": float(forward), "climb": float(climb)}
        u, w, _, th = self.x[:, :-1]
        return {"forward": float(np.mean(u * np.cos(th) + w * np.sin(th))),
                "climb": float(np.mean(u * np.sin(th) - w * np.cos(th)))}

    @property
    def insect(self) -> Insect:
        """The insect (its mean stroke angle the orbit's where that is a trim)."""
        return self.model.insect

    @property
    def aerodynamics(self) -> str:
        """The loads model (:data:`~flapping.model.dynamics.AERODYNAMIC_MODELS`)."""
        return self.model.aerodynamics

    @property
    def dof(self) -> int:
        """4: the planar (longitudinal) orbit (6 for a
        :class:`~flapping.hover.sixdof.SixDofHoverOrbit`)."""
        return 4

    @property
    def success(self) -> bool:
        """True: a returned orbit solved its equations (a failed solve raises)."""
        return self.solve_status.success


def _sample(model: LongitudinalDynamics, x0: np.ndarray, n_samples: int, method: str, **tol):
    """One period from x0 with the descent z alongside: (t, x (4 rows), z(T) - z(0))."""
    rhs = HoverProblem.of_model(model).fields()[0]
    t = np.linspace(0.0, model.period, n_samples + 1)
    res = require_success(
        flow(rhs, (0.0, model.period), np.append(x0, 0.0), breakpoints=model.breakpoints,
             period=model.period, method=method, t_eval=t if method != "RK4" else None,
             args=([model.amplitude],), **tol),
        "sampling the orbit")
    return (res.t if method == "RK4" else t), res.x[:4], float(res.x[4, -1])


# =========================================================================== hover
@overload
def find_hover_orbit(
    insect: Insect | HoverProblem,
    *,
    aerodynamics: str | None = None,
    alpha_m: float | None = None,
    amplitude_guess: float | None = None,
    x0_guess: ArrayLike | None = None,
    backend: Backend | str = DEFAULT_BACKEND,
    trims: Sequence[str] = ("amplitude",),
    n_samples: int = 512,
    method: str | None = None,
    jacobian: str | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    tol: float | None = None,
    kernel_options: Mapping[str, Any] | None = None,
    fixed_step_options: Mapping[str, Any] | None = None,
    settings: SolverSettings | None = None,
    dof: Literal[4] = 4,
) -> HoverOrbit: ...


@overload
def find_hover_orbit(
    insect: Insect | HoverProblem,
    *,
    aerodynamics: str | None = None,
    alpha_m: float | None = None,
    amplitude_guess: float | None = None,
    x0_guess: ArrayLike | None = None,
    backend: Backend | str = DEFAULT_BACKEND,
    trims: Sequence[str] = ("amplitude",),
    n_samples: int = 512,
    method: str | None = None,
    jacobian: str | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    tol: float | None = None,
    kernel_options: Mapping[str, Any] | None = None,
    fixed_step_options: Mapping[str, Any] | None = None,
    settings: SolverSettings | None = None,
    dof: Literal[6],
) -> SixDofHoverOrbit: ...


def find_hover_orbit(
    insect: Insect | HoverProblem,
    *,
    aerodynamics: str | None = None,
    alpha_m: float | None = None,
    amplitude_guess: float | None = None,
    x0_guess: ArrayLike | None = None,
    backend: Backend | str = DEFAULT_BACKEND,
    trims: Sequence[str] = ("amplitude",),
    n_samples: int = 512,
    method: str | None = None,
    jacobian: str | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    tol: float | None = None,
    kernel_options: Mapping[str, Any] | None = None,
    fixed_step_options: Mapping[str, Any] | None = None,
    settings: SolverSettings | None = None,
    dof: int = 4,
) -> HoverOrbit | SixDofHoverOrbit:
    """Find the hovering periodic orbit: initial state and stroke amplitude (and phi_bar).

    Unknowns (u0, w0, q0, theta0, Phi); equations: periodicity of (u, w, q, theta) and zero net
    altitude change over one period (module docstring). The mean angle of attack alpha_m stays at
    the trim of eq. (40) for the insect's nominal amplitude, as in the paper.

    Parameters
    ----------
    insect : Insect or HoverProblem
        The insect, or a hover problem already built (then ``aerodynamics``, ``alpha_m`` and
        ``trims`` are the problem's and must be left at their defaults).
    aerodynamics : {"linear", "small-angle", "exact"}, optional
        Loads model (:class:`~flapping.model.dynamics.LongitudinalDynamics`); ``"linear"`` is
        eq. (29), the default with ``dof=4``. With ``dof=6`` the default is ``"small-angle"``;
        ``"linear"`` is eq. (29) in six degrees of freedom
        (:mod:`flapping.model.sixdof_linear_derivation`).
    alpha_m : float, optional
        Mean geometric angle of attack [rad]; default the trim of eq. (40).
    amplitude_guess : float, optional
        Initial guess of Phi [rad]; default ``insect.stroke_amplitude``.
    x0_guess : sequence of 4 floats, optional
        Initial guess of (u, w, q, theta); default zeros.
    backend : "auto", "compiled", "fixed-step", "adaptive", or a backend object
        How the solve runs (:mod:`flapping.backends`: :class:`~flapping.backends.Compiled`,
        :class:`~flapping.backends.FixedStep`, :class:`~flapping.backends.Adaptive`, each with
        its options and their defaults). ``"auto"`` (:func:`~flapping.hover.problem.
        choose_backend`): the compiled kernel where it applies, the fixed-step path for the
        blade-element loads, the adaptive path otherwise; under ``"auto"`` a compiled or
        fixed-step solve that fails hands over to the adaptive path.
    trims : ("amplitude",) or ("amplitude", "stroke_mean")
        The trim unknowns (:data:`TRIMS`). With ``"stroke_mean"`` the mean stroke angle phi_bar
        of phi = phi_bar + Phi cos(2 pi f t) is solved for too (guess: ``insect.stroke_mean``),
        and the forward distance flown over a period joins the equations: zero mean vertical and
        horizontal speed, a true hover orbit for any hinge offset.
    n_samples : int
        Samples of the orbit over one period in the result (even, >= 2; integrated when first
        used).
    method, jacobian, rtol, atol, tol, kernel_options, fixed_step_options, settings
        Shorthands for the options of the backend objects: ``method``, ``jacobian``, ``rtol``,
        ``atol`` and ``settings`` (a :class:`~flapping.periodic.SolverSettings`) are
        :class:`~flapping.backends.Adaptive`'s (another ``method`` or ``jacobian`` selects the
        adaptive path under ``"auto"``); ``kernel_options`` (a mapping) are
        :class:`~flapping.backends.Compiled`'s; ``fixed_step_options`` are
        :class:`~flapping.backends.FixedStep`'s; ``tol`` (the residual's) is both the adaptive
        and the fixed-step path's. An option for a path that does not run warns
        (:class:`~flapping.backends.OptionWarning`); every option is checked whether or not its
        path runs.
    dof : {4, 6}
        Degrees of freedom: 4, the paper's planar (u, w, q, theta); 6, the insect in six degrees
        of freedom (:func:`~flapping.hover.sixdof.find_sixdof_hover_orbit`: the insect needs its
        roll and yaw inertia; the result is a
        :class:`~flapping.hover.sixdof.SixDofHoverOrbit`).

    Returns
    -------
    HoverOrbit or SixDofHoverOrbit
        Check :attr:`HoverOrbit.status` (or :attr:`HoverOrbit.is_hover`): with a hinge offset
        and the amplitude as the only trim the orbit may drift horizontally.

    Raises
    ------
    ValueError
        For bad arguments, or if the insect cannot trim (too heavy for its wings, eq. 40).
    ConvergenceError
        If the shooting does not converge, or converges to a stroke amplitude outside
        (0, 90 deg]: then no hover orbit exists for this insect with wings that do not cross.

    Warns
    -----
    HoverDriftWarning
        If the orbit's mean horizontal speed exceeds the hover tolerance (:attr:`HoverOrbit.
        is_hover`): the orbit holds its altitude but is not hover.
    OptionWarning
        If an option was given for a path that does not run.
    """
    _warn_deprecated_routes(method=method, jacobian=jacobian, rtol=rtol, atol=atol, tol=tol,
                            kernel_options=kernel_options,
                            fixed_step_options=fixed_step_options)
    return _find_hover_orbit(
        insect, aerodynamics=aerodynamics, alpha_m=alpha_m, amplitude_guess=amplitude_guess,
        x0_guess=x0_guess, backend=backend, trims=trims, n_samples=n_samples, method=method,
        jacobian=jacobian, rtol=rtol, atol=atol, tol=tol, kernel_options=kernel_options,
        fixed_step_options=fixed_step_options, settings=settings, dof=dof)


#: The keyword routes to the backends' options that forward to ``backend=`` and warn.
_DEPRECATED_ROUTES = {"method": "Adaptive", "jacobian": "Adaptive", "rtol": "Adaptive",
                      "atol": "Adaptive", "tol": "Adaptive or FixedStep",
                      "kernel_options": "Compiled", "fixed_step_options": "FixedStep"}


def _warn_deprecated_routes(**given: Any) -> None:
    """A DeprecationWarning for the flat and mapping routes to the backends' options: one route
    remains, ``backend=`` with an object (:mod:`flapping.backends`)."""
    used = [name for name, value in given.items() if value is not None]
    if used:
        objects = sorted({_DEPRECATED_ROUTES[name] for name in used})
        warnings.warn(
            f"find_hover_orbit's {', '.join(used)} keyword(s) are deprecated and forward to the "
            f"backend object: pass backend={' or '.join(objects)}(...) "
            "(flapping.backends) instead", DeprecationWarning, stacklevel=3)


def _find_hover_orbit(insect: Any, *, aerodynamics: str | None = None,
                      alpha_m: float | None = None, amplitude_guess: float | None = None,
                      x0_guess: ArrayLike | None = None,
                      backend: Backend | str = DEFAULT_BACKEND,
                      trims: Sequence[str] = ("amplitude",), n_samples: int = 512,
                      method: str | None = None, jacobian: str | None = None,
                      rtol: float | None = None, atol: float | None = None,
                      tol: float | None = None, kernel_options: Mapping[str, Any] | None = None,
                      fixed_step_options: Mapping[str, Any] | None = None,
                      settings: SolverSettings | None = None, dof: int = 4) -> Any:
    """:func:`find_hover_orbit` without the deprecation of its keyword routes (the package's
    own callers that forward a caller's options)."""
    dof = _validation.choice("dof", dof, (4, 6))
    if dof == 6:
        if not isinstance(insect, Insect):
            raise ValueError("dof=6 takes an Insect (a HoverProblem is planar)")
        planar = dict(alpha_m=alpha_m, amplitude_guess=amplitude_guess, x0_guess=x0_guess,
                      n_samples=n_samples, trims=trims, method=method, jacobian=jacobian,
                      rtol=rtol, atol=atol, kernel_options=kernel_options,
                      fixed_step_options=fixed_step_options, settings=settings)
        return _SIXDOF_SOLVE[0](
            insect, aerodynamics="small-angle" if aerodynamics is None else aerodynamics,
            backend=backend, tol=tol, **{k: v for k, v in planar.items() if v is not None})
    problem = _problem(insect, "linear" if aerodynamics is None else aerodynamics, alpha_m,
                       trims)
    guess = problem.guess(amplitude_guess)
    x0 = state_guess(x0_guess)
    n_samples = even_samples(n_samples)
    options = Options.of(backend, method=method, jacobian=jacobian, rtol=rtol, atol=atol,
                         tol=tol, kernel_options=kernel_options,
                         fixed_step_options=fixed_step_options, settings=settings)
    path = options.choose(problem)
    try:
        orbit = _solve(problem, path, options, guess, x0, n_samples)
    except (ConvergenceError, NonFiniteError) as exc:
        _attribute(exc, problem.insect)
        raise
    _warn_if_drifting(orbit)
    return orbit


def _solve(problem: HoverProblem, path: Backend, options: Options, guess: np.ndarray,
           x0: np.ndarray, n_samples: int) -> HoverOrbit:
    """The orbit on ``path`` (its strategy's :meth:`~flapping.backends.Compiled.solve`); under
    "auto" a failure of a path that hands over (compiled, fixed-step) hands over to the
    adaptive path."""
    try:
        return cast(HoverOrbit, path.solve(problem, guess, x0, n_samples))
    except ConvergenceError as exc:
        if not (options.auto and path.hands_over):
            raise
        # "auto" promises an answer where either path has one: the adaptive path's step
        # control survives insects the fixed-step paths do not.
        _LOG.info("the %s path failed (%s); trying the adaptive path", path.name, exc)
    return cast(HoverOrbit, options.adaptive.solve(problem, guess, x0, n_samples))


def _attribute(error: BaseException, insect: Insect) -> None:
    """Append to a failed solve's message the insect's fields likely to blame (a blow-up of an
    absurd combination of plausible numbers names them, instead of only the integrator)."""
    why = explain_blowup(insect)
    if why and error.args and why not in str(error.args[0]):
        error.args = (f"{error.args[0]}; {why}", *error.args[1:])


@dataclass(frozen=True)
class Options:
    """A hover entry point's backend argument and its keyword shorthands, as backend objects.

    ``backend`` is the object or name the caller passed; the keywords build candidate objects
    of every path (each checked, whether or not its path runs), and :meth:`choose` asks
    :func:`~flapping.hover.problem.choose_backend` which path runs, warning about the options
    that belong to another.
    """

    requested: Backend | str
    adaptive: Adaptive
    compiled: Compiled
    fixed_step: FixedStep
    given: Mapping[str, Mapping[str, Any]]

    @property
    def candidates(self) -> dict[str, Backend]:
        """The candidate object of every path, by name."""
        return {Adaptive.name: self.adaptive, Compiled.name: self.compiled,
                FixedStep.name: self.fixed_step}

    @property
    def auto(self) -> bool:
        """True if the caller let :func:`~flapping.hover.problem.choose_backend` decide."""
        return self.requested == AUTO

    @classmethod
    def of(cls, backend: Any, *, method: Any = None, jacobian: Any = None, rtol: Any = None,
           atol: Any = None, tol: Any = None, rk4_steps: Any = None,
           kernel_options: Any = None, fixed_step_options: Any = None, settings: Any = None,
           analysis: bool = False) -> Options:
        """The options of a call (``analysis``: ``rtol``/``atol`` are the analysis's)."""
        requested = as_backend(backend)
        adaptive = _adaptive_keywords(settings, method=method, jacobian=jacobian, rtol=rtol,
                                      atol=atol, tol=tol, rk4_steps=rk4_steps,
                                      analysis=analysis)
        compiled = _mapping("kernel_options", kernel_options, Compiled)
        fixed = _mapping("fixed_step_options", fixed_step_options, FixedStep)
        if tol is not None:
            fixed = {**fixed, "tol": tol}
        given = {Adaptive.name: adaptive, Compiled.name: compiled, FixedStep.name: fixed}
        def built(kind: type[_B]) -> _B:
            base = _default(kind)
            if not isinstance(requested, str) and requested.name == kind.name:
                base = cast(_B, requested)  # the caller's object of this path
            return base.with_options(**given[kind.name]) if given[kind.name] else base

        return cls(requested, built(Adaptive), built(Compiled), built(FixedStep), given)

    def choose(self, problem: HoverProblem, solved: Backend | None = None,
               shared: Mapping[str, Sequence[str]] | None = None) -> Backend:
        """The path that runs, with the caller's options; warns about options of other paths
        (except ``shared[name]``, options the caller uses too when path ``name`` runs)."""
        requested: Backend | str = self.requested
        if self.auto and self.adaptive.chosen_by_options:
            requested = self.adaptive
        path = choose_backend(problem, requested, solved=solved)
        chosen: Backend = self.candidates[path.name]
        if path is not solved:
            path = chosen
        elif self.given[path.name]:
            path = replace(path, **self.given[path.name])  # keys checked by the objects
        unused = {k: v for name, opts in self.given.items() if name != path.name
                  for k, v in opts.items()
                  if k not in (shared or {}).get(path.name, ())
                  and not (k == "tol" and "tol" in self.given[path.name])}
        warn_unused(unused, path.name, stacklevel=4)
        return path


_B = TypeVar("_B", Adaptive, Compiled, FixedStep)


#: The backend objects with their defaults, each built (and checked) once: every call of an
#: entry point, every sweep point, starts from them (frozen, so shared safely).
_DEFAULTS: dict[type, Any] = {}


def _default(kind: type[_B]) -> _B:
    """The backend object of ``kind`` with its defaults (:data:`_DEFAULTS`)."""
    found = _DEFAULTS.get(kind)
    if found is None:
        found = _DEFAULTS[kind] = kind()
    return cast(_B, found)


def _mapping(name: str, value: Any, kind: type[Compiled] | type[FixedStep]) -> dict[str, Any]:
    """The options of ``kind`` given as the mapping keyword ``name`` (keys checked)."""
    if value is None:
        return {}
    if not isinstance(value, Mapping):
        raise ValueError(f"`{name}` must be a mapping of option names to values; got "
                         f"{_validation._show(value)}")
    known = sorted(f.name for f in dataclass_fields(kind))
    unknown = sorted(map(str, set(value) - set(known)))
    if unknown:
        raise ValueError(f"`{name}` accepts {', '.join(known)} (the {kind.name} path's "
                         f"options); got {unknown}")
    return dict(value)


def _adaptive_keywords(settings: Any, *, analysis: bool, **keywords: Any) -> dict[str, Any]:
    """The adaptive path's options from its keywords and a SolverSettings (keywords win)."""
    if settings is not None and not isinstance(settings, SolverSettings):
        raise ValueError(f"`settings` must be a SolverSettings; got {settings!r} "
                         f"({type(settings).__name__})")
    out: dict[str, Any] = {}
    if settings is not None:
        out = {f: getattr(settings, f) for f in ("method", "rtol", "atol", "tol", "rk4_steps",
                                                  "max_steps", "max_nfev")
               if getattr(settings, f) is not None}
    out.update({k: v for k, v in keywords.items() if v is not None})
    if analysis:  # hover_stability's rtol and atol are its own integrations'
        for name in ("rtol", "atol"):
            if name in out:
                out[f"analysis_{name}"] = out.pop(name)
    return out


def _problem(insect: Insect | HoverProblem, aerodynamics: str, alpha_m: float | None,
             trims: Sequence[str]) -> HoverProblem:
    """The hover problem of the arguments (or the one given, with the defaults left alone)."""
    if not isinstance(insect, HoverProblem):
        return HoverProblem(insect, aerodynamics, alpha_m, check_trims(trims))
    if (aerodynamics, alpha_m, check_trims(trims)) != ("linear", None, TRIMS[0]):
        raise ValueError("with a HoverProblem, `aerodynamics`, `alpha_m` and `trims` are the "
                         "problem's own: leave them at their defaults")
    return insect


#: The integrators the adaptive hover path accepts: the explicit ones. The hover dynamics are
#: not stiff (DOP853 takes ~10^3 steps a period at rtol 1e-11); an implicit method (Radau, BDF,
#: LSODA) there spends minutes per period on Jacobian factorisations for no gain.
HOVER_METHODS: tuple[str, ...] = ("DOP853", "RK45", "RK23", "RK4")


def explicit_method(path: Adaptive) -> Adaptive:
    """``path``, if its method is one of :data:`HOVER_METHODS` (else a ValueError)."""
    if path.method not in HOVER_METHODS:
        raise ValueError(f"`method` must be one of {HOVER_METHODS} for the hover problem (it is "
                         f"not stiff: an implicit method only costs time); got {path.method!r}")
    return path


def _model_at(problem: HoverProblem, trims: list[float]) -> LongitudinalDynamics:
    """The dynamics at the solved trims."""
    model = problem.model
    if len(trims) == 2 and trims[1] != model.insect.stroke_mean:
        model = model.with_stroke_mean(trims[1])
    return model if trims[0] == model.amplitude else model.with_amplitude(trims[0])


def _orbit_of(problem: HoverProblem, result: PeriodicOrbit | FixedStepOrbit,
              trims: list[float], model: LongitudinalDynamics, path: Backend, started: float,
              *, njev: int = 0, **fields: Any) -> HoverOrbit:
    """The HoverOrbit of a converged adaptive or fixed-step solve."""
    phi_bar = trims[1] if len(trims) == 2 else problem.insect.stroke_mean
    stats = Stats(int(result.nit), int(result.nfev), njev, time.perf_counter() - started)
    return HoverOrbit(problem, np.array(result.x0[:4], dtype=float), trims[0], phi_bar,
                      float(result.residual[4]), path.name, int(result.nit), int(result.nfev),
                      float(result.residual_norm), model_given=model,
                      solver=path, stats=stats, **fields)


def _checked_trims(problem: HoverProblem, result: PeriodicOrbit | FixedStepOrbit
                   ) -> list[float]:
    """The trims of a converged solve; a ConvergenceError if they left their ranges (then no
    hover orbit was found)."""
    assert result.params is not None  # the trims are free parameters
    trims = [float(v) for v in result.params]
    phi = trims[0]
    phi_bar = trims[1] if len(trims) == 2 else 0.0
    if 0.0 < phi <= math.pi / 2 and -math.pi / 2 < phi_bar < math.pi / 2:
        return trims
    found = f"Phi = {math.degrees(phi):.4g} deg"
    if len(trims) == 2:
        found += f", phi_bar = {math.degrees(phi_bar):.4g} deg"
    ranges = "a stroke amplitude in (0, 90] deg" + (
        " and a mean stroke angle in (-90, 90) deg" if len(trims) == 2 else "")
    raise ConvergenceError(
        f"no hover orbit for {problem.insect.name} with {ranges}: the shooting converged to "
        f"{found}", x=np.append(result.x0, trims), residual=result.residual_norm,
        iterations=result.nit, result=result)


def _warn_if_drifting(orbit: HoverOrbit) -> None:
    if orbit.status == HoverStatus.DRIFTING:
        insect = orbit.model.insect
        warnings.warn(
            f"the orbit found for {insect.name} holds its altitude but is not hover: it flies "
            f"{'forwards' if orbit.mean_inertial_velocity['forward'] > 0 else 'backwards'} at a "
            f"mean {orbit.mean_horizontal_speed:.3g} m/s (tolerance "
            f"{orbit.hover_speed_tol:.3g} m/s), as the "
            f"hinge offset x_h = {insect.hinge_offset:g} m (or a mean stroke angle phi_bar = "
            f"{insect.stroke_mean:g} rad) breaks the half-period symmetry; "
            "trims=('amplitude', 'stroke_mean') finds a true hover orbit",
            HoverDriftWarning, stacklevel=3)


# =========================================================================== compiled backend
def use_kernel(backend: Backend | str, model: LongitudinalDynamics,
               default_settings: bool = True) -> bool:
    """Whether ``backend`` means the compiled kernel for this model
    (:func:`~flapping.hover.problem.choose_backend` decides).

    Parameters
    ----------
    backend : "auto", "compiled", "adaptive", "fixed-step" or a backend object
    model : LongitudinalDynamics
    default_settings : bool
        False if the caller asked for adaptive-path settings: then ``"auto"`` means adaptive.

    Raises
    ------
    ValueError, ImportError
        As :func:`~flapping.hover.problem.choose_backend`.
    """
    problem = HoverProblem.of_model(model)
    return problem.backend(backend, adaptive_options=not default_settings) == "compiled"


def forced_orbit(
    insect: Insect,
    amplitude: float | None = None,
    *,
    aerodynamics: str = "linear",
    alpha_m: float | None = None,
    x0_guess: Sequence[float] | None = None,
    method: str | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    tol: float | None = None,
    n_samples: int = 512,
    backend: Adaptive | str = Adaptive.name,
) -> HoverOrbit:
    """The periodic orbit at a *prescribed* stroke amplitude (periodicity of the states only).

    Such an orbit exists for a range of amplitudes; it climbs or sinks unless Phi is the hover
    amplitude.

    Parameters
    ----------
    insect : Insect
    amplitude : float, optional
        Stroke amplitude Phi [rad] in (0, pi/2]; default ``insect.stroke_amplitude``.
    aerodynamics, alpha_m, x0_guess, method, rtol, atol, tol, n_samples
        As for :func:`find_hover_orbit`.
    backend : "adaptive" or Adaptive
        The adaptive path is the only one that solves a forced orbit (no trim); ``method``,
        ``rtol``, ``atol`` and ``tol`` are shorthands for its options.

    Returns
    -------
    HoverOrbit
        With ``z_drift`` the net descent per period [m] (positive: sinking).

    Raises
    ------
    ValueError
        For bad arguments.
    ConvergenceError
        If the shooting does not converge.
    """
    path = explicit_method(adaptive_only("forced_orbit", backend, method=method, rtol=rtol,
                                         atol=atol, tol=tol))
    model = LongitudinalDynamics(insect, amplitude=amplitude, alpha_m=alpha_m,
                                 aerodynamics=aerodynamics)
    x0 = state_guess(x0_guess)
    n_samples = even_samples(n_samples)
    started = time.perf_counter()
    rhs, jac = model.segment_functions()
    result = find_periodic_orbit(rhs, x0, model.period, autonomous=False, jac=jac,
                                 breakpoints=model.breakpoints, method=path.method,
                                 rtol=path.rtol, atol=path.atol, tol=path.tol,
                                 rk4_steps=path.rk4_steps, max_steps=path.max_steps,
                                 max_nfev=path.max_nfev)
    x0 = np.array(result.x0, dtype=float)
    t, x, z_drift = _sample(model, x0, n_samples, path.method, rtol=path.rtol, atol=path.atol)
    stats = Stats(int(result.nit), int(result.nfev), int(result.njev),
                  time.perf_counter() - started)
    return HoverOrbit(None, x0, float(model.amplitude), insect.stroke_mean, z_drift, "adaptive",
                      int(result.nit), int(result.nfev), float(result.residual_norm),
                      shooting=result, samples=_Sampled(t, x), model_given=model, solver=path,
                      stats=stats)


def adaptive_only(function: str, backend: Any, **keywords: Any) -> Adaptive:
    """The Adaptive backend of a function that runs on the adaptive path only, with its keyword
    shorthands laid over it (a ValueError for another path)."""
    spec = Adaptive.required_by(function, backend)
    return spec.with_options(**{k: v for k, v in keywords.items() if v is not None})


def paper_hover_problem(
    insect: Insect,
    *,
    x0_guess: Sequence[float] = (0.1, 0.1, 0.1 * math.pi / 180, 0.1 * math.pi / 180),
    h0_guess: float = 2.0,
    amplitude_guess: float | None = None,
    aerodynamics: str = "linear",
    method: str | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    tol: float | None = None,
    backend: Adaptive | str = Adaptive.name,
) -> tuple[PeriodicOrbit, np.ndarray]:
    """The paper's hover problem (Sec. IV): the virtual state h = w sin(theta) - u cos(theta).

    h is integrated as a fifth state (h' = d/dt of its definition) with its own unknown initial
    value, and required to be periodic with the other states; Phi is a free parameter. Defaults
    are the paper's Table 1 guess.

    Parameters
    ----------
    insect : Insect
    x0_guess : sequence of 4 floats
        Guess of (u, w, q, theta) [m/s, m/s, rad/s, rad].
    h0_guess : float
        Guess of h(0) [m/s].
    amplitude_guess : float, optional
        Guess of Phi [rad]; default ``insect.stroke_amplitude``.
    aerodynamics, method, rtol, atol, tol
        As for :func:`find_hover_orbit`.
    backend : "adaptive" or Adaptive
        The path that solves it (the adaptive one only); ``method``, ``rtol``, ``atol`` and
        ``tol`` are shorthands for its options.

    Returns
    -------
    result : PeriodicOrbit
        The shooting result (``x0`` holds (u, w, q, theta, h), ``params`` holds Phi).
    singular_values : ndarray, shape (5,)
        Singular values of the Jacobian of the one-period residual y(T) - y(0) with respect to
        the six unknowns (u0, w0, q0, theta0, h0, Phi), from the variational equations. The
        smallest vanishes (to integration accuracy): the rank is 4, so the null space is two-
        dimensional -- h0 never feeds back, and h(T) - h(0) repeats the other residuals. Phi is
        therefore not determined by this problem.
    """
    path = adaptive_only("paper_hover_problem", backend, method=method, rtol=rtol, atol=atol,
                         tol=tol)
    method, rtol, atol, tol = path.method, path.rtol, path.atol, path.tol
    model = LongitudinalDynamics(insect, aerodynamics=aerodynamics)
    amplitude = insect.stroke_amplitude if amplitude_guess is None else amplitude_guess
    base = model.segment_functions()[0]

    def field(k):
        s = segment_stroke_sign(k)

        def f(t, y, params):
            dx = model.unchecked.rhs(t, y[:4], s, params[0])
            u, w, q, th = y[:4]
            dh = (dx[1] * math.sin(th) + w * math.cos(th) * q
                  - dx[0] * math.cos(th) + u * math.sin(th) * q)
            return np.append(dx, dh)
        return f

    rhs = [field(k) for k in range(len(base))]
    y0 = np.append(state_guess(x0_guess), _validation.real("h0_guess", h0_guess, unit="m/s"))
    result = find_periodic_orbit(rhs, y0, model.period, autonomous=False,
                                 free_params=[amplitude], breakpoints=model.breakpoints,
                                 n_points=3,  # three points per state, as in eq. (41)
                                 jacobian="finite-difference", method=method, rtol=rtol,
                                 atol=atol, tol=tol)

    # Jacobian of the one-period residual y(T) - y(0) in (y0, Phi) from the variational equations.
    var = require_success(
        variational_flow(rhs, None, (0.0, model.period), result.x0,
                         breakpoints=model.breakpoints, period=model.period, method=method,
                         rtol=rtol, atol=atol, params=result.params),
        "the paper problem's Jacobian")
    J = np.hstack([var.stm_end - np.eye(5), var.sensitivity_end])
    return result, np.linalg.svd(J, compute_uv=False)


# =========================================================================== stability
#: Most samples of :func:`force_budget` (each evaluates the derivatives in Python).
_MAX_BUDGET_SAMPLES = 1 << 17


def force_budget(
    orbit: HoverOrbit,
    n_samples: int = 4096,
    *,
    rtol: float | None = None,
    atol: float | None = None,
) -> dict[str, dict[str, float]]:
    """Cycle means of every term of the linear model's equations (2)/(29) along the orbit.

    On a periodic orbit each equation's terms average to zero (the mean of x' vanishes); the
    budget shows which terms carry the weight, e.g. why the hover amplitude differs from the trim
    of eq. (40), which balances the weight by Z0 alone.

    Parameters
    ----------
    orbit : HoverOrbit
        An orbit of the linear model.
    n_samples : int
        Uniform samples over one period, in [2, 2**17], for the cycle means (trapezoid rule;
        the terms are smooth within a half-stroke, so a few thousand resolve them).
    rtol, atol : float, optional
        Tolerances of the integration of the orbit (default :class:`~flapping.backends.
        Adaptive`'s ``analysis_rtol`` and ``analysis_atol``).

    Returns
    -------
    dict
        ``{"u": {...}, "w": {...}, "q": {...}}``, each a dict of term name -> cycle mean
        [m/s^2 for u and w, rad/s^2 for q], with the names of eq. (29) (``"X0/m"``, ``"Xu u"``,
        ``"-q w"``, ``"-g sin(theta)"``, ...).

    Raises
    ------
    ValueError
        If the orbit's model is not the linear one (the budget is of eq. 29's terms).
    """
    orbit = _validation.instance("orbit", orbit, HoverOrbit)
    n_samples = _validation.integer("n_samples", n_samples, low=2, high=_MAX_BUDGET_SAMPLES)
    path = Adaptive().with_options(**{k: v for k, v in (("analysis_rtol", rtol),
                                                           ("analysis_atol", atol))
                                      if v is not None})
    rtol, atol = path.analysis_rtol, path.analysis_atol
    model = orbit.model
    if model.aerodynamics != "linear":
        raise ValueError("force_budget needs an orbit of the linear model (aerodynamics='linear')")
    rhs, _ = model.segment_functions()
    t = np.linspace(0.0, orbit.period, n_samples, endpoint=False)
    x = require_success(
        flow(rhs, (0.0, orbit.period), orbit.x0, breakpoints=model.breakpoints,
             period=orbit.period, t_eval=t, rtol=rtol, atol=atol),
        "the budget").x
    u, w, q, th = x
    d = np.array([model.unchecked.derivatives(ti) for ti in t]).T
    g, m, Iy = model.insect.gravity, model.insect.mass, model.insect.pitch_inertia
    terms = {
        "u": {"-q w": -q * w, "-g sin(theta)": -g * np.sin(th), "X0/m": d[0] / m,
              "Xu u": d[3] * u, "Xw w": d[4] * w, "Xq q": d[5] * q},
        "w": {"q u": q * u, "g cos(theta)": g * np.cos(th), "Z0/m": d[1] / m,
              "Zu u": d[6] * u, "Zw w": d[7] * w, "Zq q": d[8] * q},
        "q": {"M0/Iy": d[2] / Iy, "Mu u": d[9] * u, "Mw w": d[10] * w, "Mq q": d[11] * q},
    }
    return {eq: {k: float(np.mean(v)) for k, v in parts.items()} for eq, parts in terms.items()}

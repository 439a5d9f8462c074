"""How a solve runs: one object per integration path, holding its own options and defaults.

After scipy's solver classes (``solve_ivp(method=RK45)``) and diffrax's solver and step-size
controller objects: every hover entry point (:func:`~flapping.hover.find_hover_orbit`,
:func:`~flapping.hover.stability.hover_stability`, :func:`~flapping.hover.branch.continue_hover`,
:func:`~flapping.studies.sweep.sweep_hover`, the :mod:`~flapping.studies.control` functions)
takes ``backend=`` as one of

- :class:`Compiled`: the numba hover kernel of :mod:`flapping.fast` (eq. 29's linear loads,
  one trim), Newton on a fixed-step 8th-order period map with Richardson error estimates;
- :class:`FixedStep`: Newton on a fixed-step 8th-order period map on a time mesh graded towards
  the stroke reversals (any loads model), with Richardson error estimates;
- :class:`Adaptive`: Levenberg-Marquardt shooting on scipy's adaptive integrators, as in the
  paper: the reference and the cross-check;
- ``"auto"`` (the default): the fastest of them that applies, decided by one function,
  :func:`flapping.hover.problem.choose_backend`.

The string forms ``"compiled"``, ``"fixed-step"`` and ``"adaptive"`` mean the objects with their
default options. Each object's defaults are its dataclass field defaults, and nowhere else::

    from flapping import find_hover_orbit, hawkmoth
    from flapping.backends import Adaptive, FixedStep

    find_hover_orbit(hawkmoth(), backend=Adaptive(rtol=1e-10))
    find_hover_orbit(hawkmoth(), aerodynamics="exact", backend=FixedStep(n_steps=32))

Every field is checked when the object is built (a ValueError names the field and its range),
so an absurd tolerance is refused on every path, whether or not that path runs. An option given
for a path that does not run (say ``rtol`` while the compiled kernel runs) is not dropped in
silence: the entry points warn with :class:`OptionWarning`.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, fields, replace
from typing import Any, ClassVar, Self, Union

import flapping._validation as check
from flapping.periodic import settings
from flapping.periodic.settings import (
    FIXED_STEP_ERROR_TOL,
    MONODROMY_ATOL,
    MONODROMY_RTOL,
    ORBIT_ATOL,
    ORBIT_RTOL,
    ORBIT_TOL,
)

__all__ = ["AUTO", "BACKEND_NAMES", "Adaptive", "Backend", "Compiled", "FixedStep",
           "OptionWarning", "as_backend", "backend_name"]

#: The shorthand that lets :func:`~flapping.hover.problem.choose_backend` pick the path.
AUTO = "auto"

#: The tolerance ranges are the periodic-orbit layer's (:mod:`flapping.periodic.settings`, one
#: place, each with its reason): ``rtol`` in [100 eps, 1e-3] (raised to the floor with a
#: warning), a residual ``tol`` at most 1e-6 (the closure of a point on an orbit), ``atol`` and
#: every error target at most 1e-2. A coarse, quick solve is possible; ``rtol=1`` or ``1e300`` is
#: a typo, refused whichever path runs.

#: Largest step count per half-stroke a fixed-step solve may start with (the fixed-step path
#: refines at most to 4096).
MAX_START_STEPS = 4096

#: The compiled kernel's range of starting steps per half-stroke (:mod:`flapping.fast.kernel`
#: refines at most to 1024: its Newton state is sized for it); a test holds them equal.
COMPILED_STEPS_RANGE = (4, 1024)
#: Smallest targets of the compiled kernel's error estimates: the float64 limit of its
#: fixed-step solve (:data:`flapping.fast.kernel.AMPLITUDE_TOL_FLOOR_DEG`,
#: :data:`~flapping.fast.kernel.MULTIPLIER_TOL_FLOOR`; a test holds them equal).
COMPILED_AMPLITUDE_TOL_FLOOR_DEG = 1e-11
COMPILED_MULTIPLIER_TOL_FLOOR = 1e-12


class OptionWarning(UserWarning):
    """An option was given for an integration path that does not run, and is ignored."""


def _tol(name: str, value: Any, *, residual: bool = False, floor: float | None = None) -> float:
    """A tolerance in (0, ceiling] (or [floor, ceiling]), or a ValueError naming ``name`` and the
    range (the ceiling: the periodic layer's residual one for a residual tolerance, its accuracy
    one otherwise)."""
    high = settings.RESIDUAL_CEILING if residual else settings.TOL_CEILING
    if floor is not None:
        return check.real(name, value, low=floor, high=high)
    return check.real(name, value, low=0.0, high=high, low_open=True)


def _rtol(name: str, value: Any) -> float:
    """A relative tolerance in (0, 1e-3], raised to 100 eps with a warning below it (as scipy's
    solve_ivp does)."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        rtol = settings.check_rtol(name, value)
    for w in caught:  # re-issued here, so that it points at the caller's line
        warnings.warn(w.message, w.category, stacklevel=5)
    return rtol


def _steps(name: str, value: Any, low: int) -> int:
    return check.integer(name, value, low=low, high=MAX_START_STEPS)


#: Each path's code, by name: the hover layer registers its modules
#: (:mod:`flapping.hover.compiled_path`, :mod:`~flapping.hover.fixed_step_path`,
#: :mod:`~flapping.hover.adaptive_path`) when it is imported, which a hover problem or orbit
#: implies. This layer imports none of them (it lies below).
_PATHS: dict[str, Any] = {}


def register(name: str, path: Any) -> None:
    """Register the code of the path ``name``: an object with ``check(backend, problem)``,
    ``solve(backend, problem, guess, x0, n_samples)`` and ``analyse(backend, orbit, problem,
    n_average, rtol, atol)``."""
    _PATHS[name] = path


@dataclass(frozen=True)
class _Backend:
    """What every backend object has: its name, the options a caller gave explicitly, and its
    path's code (a strategy: :meth:`solve`, :meth:`analyse`)."""

    name: ClassVar[str]
    #: Whether a failed solve under ``"auto"`` hands over to the adaptive path (whose step
    #: control survives insects the fixed-step paths do not).
    hands_over: ClassVar[bool] = True
    #: Whether the six-degree-of-freedom solve and analysis run compiled on this path.
    sixdof_compiled: ClassVar[bool] = False
    #: Whether the path solves the one-trim problem only (the compiled kernel).
    one_trim_only: ClassVar[bool] = False
    #: Whether a six-degree-of-freedom orbit is analysed on this path (the compiled and the
    #: adaptive ones; the six-degree-of-freedom solve has no fixed-step path).
    sixdof_analyses: ClassVar[bool] = True

    def _path(self) -> Any:
        return _PATHS[self.name]

    def check(self, problem: Any) -> None:
        """Refuse this path for ``problem`` where it does not apply (a ValueError or an
        ImportError saying why)."""
        self._path().check(self, problem)

    def solve(self, problem: Any, guess: Any, x0: Any, n_samples: int) -> Any:
        """The hover orbit of ``problem`` on this path from the trims' ``guess`` and the state
        guess ``x0``, with ``n_samples`` samples per period
        (:class:`~flapping.hover.orbit.HoverOrbit`)."""
        return self._path().solve(self, problem, guess, x0, n_samples)

    def analyse(self, orbit: Any, problem: Any, n_average: int, rtol: float,
                atol: float) -> Any:
        """The Floquet stability of ``orbit`` on this path
        (:class:`~flapping.hover.stability.HoverStability`); ``rtol`` and ``atol`` are the
        analysis's integrations' where the path integrates adaptively."""
        return self._path().analyse(self, orbit, problem, n_average, rtol, atol)

    def given(self) -> dict[str, Any]:
        """The options that differ from the defaults (what a caller chose)."""
        default = type(self)()
        return {f.name: getattr(self, f.name) for f in fields(self)
                if getattr(self, f.name) != getattr(default, f.name)}

    def with_options(self, **options: Any) -> Self:
        """A copy with ``options`` replaced (each checked), a ValueError naming an unknown one."""
        known = {f.name for f in fields(self)}
        unknown = sorted(set(options) - known)
        if unknown:
            raise ValueError(f"the {self.name} path has no option {', '.join(unknown)}; its "
                             f"options are {', '.join(sorted(known))}")
        return replace(self, **options)


@dataclass(frozen=True)
class Compiled(_Backend):
    """The compiled hover kernel (numba; eq. 29's linear loads, one trim).

    Attributes
    ----------
    n_steps : int, optional
        Steps per half-stroke to start with (refined until the tolerances hold); None: the
        kernel's own start (12), in [4, 1024] (:data:`COMPILED_STEPS_RANGE`).
    amplitude_tol_deg : float
        Target of the stroke amplitude's Richardson error estimate [deg], in [1e-11, 1e-2].
    multiplier_tol : float
        Target of every Floquet multiplier's error estimate (absolute), in [1e-12, 1e-2].
    """

    name: ClassVar[str] = "compiled"
    sixdof_compiled: ClassVar[bool] = True
    one_trim_only: ClassVar[bool] = True
    n_steps: int | None = None
    amplitude_tol_deg: float = 1e-9
    multiplier_tol: float = 1e-8

    def __post_init__(self) -> None:
        # The ranges the kernel's solve refuses outside: checked once, here.
        if self.n_steps is not None:
            low, high = COMPILED_STEPS_RANGE
            object.__setattr__(self, "n_steps",
                               check.integer("n_steps", self.n_steps, low=low, high=high))
        object.__setattr__(self, "amplitude_tol_deg",
                           _tol("amplitude_tol_deg", self.amplitude_tol_deg,
                                floor=COMPILED_AMPLITUDE_TOL_FLOOR_DEG))
        object.__setattr__(self, "multiplier_tol",
                           _tol("multiplier_tol", self.multiplier_tol,
                                floor=COMPILED_MULTIPLIER_TOL_FLOOR))


@dataclass(frozen=True)
class FixedStep(_Backend):
    """Newton on a fixed-step 8th-order period map on the graded time mesh (any loads model).

    Attributes
    ----------
    n_steps : int
        Steps per half-stroke to start with, in [2, 4096] (doubled until the error estimates
        meet ``error_tol``).
    error_tol : float
        Target of every unknown's Richardson error estimate, relative to max(1, abs(value)), in
        (0, 1e-2].
    multiplier_tol : float, optional
        Target of the multipliers' error estimate (None: estimated, not enforced).
    tol : float
        Largest accepted norm of the periodicity residual, in (0, 1e-6].
    max_nfev : int, optional
        Cap on the evaluations of the right-hand side of one solve (None: the solver's own).
    """

    name: ClassVar[str] = "fixed-step"
    sixdof_analyses: ClassVar[bool] = False
    n_steps: int = 64
    error_tol: float = FIXED_STEP_ERROR_TOL
    multiplier_tol: float | None = None
    tol: float = ORBIT_TOL
    max_nfev: int | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "n_steps", _steps("n_steps", self.n_steps, 2))
        object.__setattr__(self, "error_tol", _tol("error_tol", self.error_tol))
        if self.multiplier_tol is not None:
            object.__setattr__(self, "multiplier_tol",
                               _tol("multiplier_tol", self.multiplier_tol))
        object.__setattr__(self, "tol", _tol("tol", self.tol, residual=True))
        if self.max_nfev is not None:
            object.__setattr__(self, "max_nfev",
                               check.integer("max_nfev", self.max_nfev, low=1, high=10**8))

    def fixed_step_options(self) -> dict[str, Any]:
        """The keywords of :func:`~flapping.periodic.fixedstep.find_periodic_orbit_fixed_step`."""
        out = {"n_steps": self.n_steps, "error_tol": self.error_tol,
               "multiplier_tol": self.multiplier_tol, "tol": self.tol}
        if self.max_nfev is not None:
            out["max_nfev"] = self.max_nfev
        return out


#: The Jacobians of the adaptive path's shooting residual.
JACOBIANS = ("variational", "finite-difference")


@dataclass(frozen=True)
class Adaptive(_Backend):
    """Levenberg-Marquardt shooting on scipy's adaptive integrators (the reference path).

    Attributes
    ----------
    method : str
        ``"DOP853"``, another :func:`scipy.integrate.solve_ivp` method, or ``"RK4"`` (the
        paper's fixed step, ``rk4_steps`` per period).
    rtol, atol : float
        Tolerances of the orbit's integrations, rtol in [100 eps, 1e-3], atol in (0, 1e-2].
    analysis_rtol, analysis_atol : float
        Tolerances of the integrations that analyse a found orbit (its monodromy, averaged
        Jacobian, samples' force budget, perturbations): a decade tighter than the orbit's, so
        that the analysis adds no error of its own.
    tol : float
        Largest accepted norm of the shooting residual, in (0, 1e-6].
    jacobian : {"variational", "finite-difference"}, optional
        Jacobian of the shooting residual. None: variational for the linear loads (analytic),
        finite differences for the blade-element loads.
    rk4_steps : int
        RK4 steps per period (``method="RK4"`` only), in [1, 2**22].
    max_steps : int, optional
        Step budget of one integration (None: the integrator's own, 100 000).
    max_nfev : int, optional
        Residual evaluations of Levenberg-Marquardt (None: 100 (unknowns + 1)).
    """

    name: ClassVar[str] = "adaptive"
    hands_over: ClassVar[bool] = False
    method: str = "DOP853"
    rtol: float = ORBIT_RTOL
    atol: float = ORBIT_ATOL
    analysis_rtol: float = MONODROMY_RTOL
    analysis_atol: float = MONODROMY_ATOL
    tol: float = ORBIT_TOL
    jacobian: str | None = None
    rk4_steps: int = 1024
    max_steps: int | None = None
    max_nfev: int | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "method", settings.check_method(self.method))
        for name in ("rtol", "analysis_rtol"):
            object.__setattr__(self, name, _rtol(name, getattr(self, name)))
        for name in ("atol", "analysis_atol"):
            object.__setattr__(self, name, _tol(name, getattr(self, name)))
        object.__setattr__(self, "tol", _tol("tol", self.tol, residual=True))
        if self.jacobian is not None:
            check.choice("jacobian", self.jacobian, JACOBIANS)
        object.__setattr__(self, "rk4_steps",
                           check.integer("rk4_steps", self.rk4_steps, low=1, high=2**22))
        if self.max_steps is not None:
            object.__setattr__(self, "max_steps",
                               check.integer("max_steps", self.max_steps, low=1, high=10**7))
        if self.max_nfev is not None:
            object.__setattr__(self, "max_nfev",
                               check.integer("max_nfev", self.max_nfev, low=1, high=10**5))

    @classmethod
    def required_by(cls, function: str, backend: Any, default: Adaptive | None = None
                    ) -> Adaptive:
        """The Adaptive object of a function that runs on the adaptive path only (``default``,
        or the defaults, for ``"auto"`` or ``"adaptive"``); a ValueError for another path."""
        spec = as_backend(backend)
        if isinstance(spec, Adaptive):
            return default if default is not None and backend in (AUTO, cls.name) else spec
        if spec == AUTO:
            return cls() if default is None else default
        raise ValueError(f"{function} runs on the adaptive path only; got backend="
                         f"{check._show(backend)}")

    @property
    def chosen_by_options(self) -> bool:
        """True if the options ask for this path by name: another ``method`` or ``jacobian``
        than the default (``"auto"`` then means the adaptive path, as scipy's ``method``)."""
        return self.method != "DOP853" or self.jacobian not in (None, "variational")


#: Any backend object.
Backend = Union[Compiled, FixedStep, Adaptive]  # noqa: UP007 (a runtime alias, used in isinstance)

#: The backend classes by name (the string forms).
_BY_NAME: dict[str, type[Compiled] | type[FixedStep] | type[Adaptive]] = {
    Compiled.name: Compiled, FixedStep.name: FixedStep, Adaptive.name: Adaptive}

#: Every accepted string form.
BACKEND_NAMES: tuple[str, ...] = (AUTO, *_BY_NAME)


def as_backend(backend: Any) -> Backend | str:
    """``backend`` as a backend object, or ``"auto"``.

    Parameters
    ----------
    backend : "auto", "compiled", "fixed-step", "adaptive", or a backend object
        A string means that path with its default options.

    Returns
    -------
    Compiled, FixedStep, Adaptive or "auto"

    Raises
    ------
    ValueError
        For anything else, naming the accepted forms.
    """
    if isinstance(backend, (Compiled, FixedStep, Adaptive)):
        return backend
    if isinstance(backend, str) and backend in BACKEND_NAMES:
        return AUTO if backend == AUTO else _BY_NAME[backend]()
    if isinstance(backend, type) and backend in _BY_NAME.values():
        return backend()
    raise ValueError(f"`backend` must be one of {BACKEND_NAMES} or a Compiled, FixedStep or "
                     f"Adaptive object; got {check._show(backend)}")


def backend_name(backend: Backend | str) -> str:
    """The string form of a backend object (``"auto"`` stays ``"auto"``)."""
    return backend if isinstance(backend, str) else backend.name


def warn_unused(options: dict[str, Any], running: str, stacklevel: int = 3) -> None:
    """Warn (:class:`OptionWarning`) that ``options`` do not apply to the path that runs."""
    if options:
        names = ", ".join(f"{k}={v!r}" for k, v in sorted(options.items()))
        warnings.warn(f"{names} {'does' if len(options) == 1 else 'do'} not apply to the "
                      f"{running} path, which runs here: ignored (pass backend=... to choose "
                      "the path that uses it)", OptionWarning, stacklevel=stacklevel + 1)


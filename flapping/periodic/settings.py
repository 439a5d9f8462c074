"""One settings object for the solvers of :mod:`flapping.periodic`, and the checks of its fields.

:class:`SolverSettings` groups the options that recur in :func:`~flapping.periodic.shooting.
find_periodic_orbit`, :func:`~flapping.periodic.floquet.monodromy` and
:func:`~flapping.periodic.continuation.continue_orbit` (as diffrax passes its solver and step-size
controller as objects, and BifurcationKit keeps ``ContinuationPar`` apart from the problem). Each
of those functions accepts it as ``settings=``; its keyword arguments keep working, and a keyword
given explicitly overrides the same field of ``settings``::

    fast = SolverSettings(rtol=1e-9, atol=1e-9, max_steps=20_000)
    orbit = find_periodic_orbit(f, x0, T, settings=fast)             # rtol 1e-9
    orbit = find_periodic_orbit(f, x0, T, settings=fast, rtol=1e-11) # rtol 1e-11 (keyword wins)

A field left at ``None`` means "the function's own default" (the defaults differ where the
question does: a monodromy matrix wants a tighter ``rtol`` than a Newton step), so
``SolverSettings()`` changes nothing:

============  ====================  ================  ====================
field         find_periodic_orbit   monodromy         continue_orbit
============  ====================  ================  ====================
method        "DOP853"              "DOP853"          "DOP853"
rtol          1e-11                 1e-12             1e-10
atol          1e-12                 1e-12             1e-10
rk4_steps     1024                  1024              (adaptive only)
max_steps     100 000               100 000           100 000
tol           1e-10 (absolute)      (not used)        1e-8 (relative)
max_nfev      100 (n_unknowns + 1)  (not used)        (not used)
max_newton    (not used)            (not used)        6
============  ====================  ================  ====================

Validation, in this module only (:func:`check_field`): every field is checked when a
:class:`SolverSettings` is built and again when a keyword overrides it, with a ValueError naming
the field and the accepted range. Tolerances follow :func:`scipy.integrate.solve_ivp`: an
``rtol`` below ``100 * eps`` (2.2e-14) cannot be delivered in float64, so it is raised to that
floor with a :class:`~flapping.errors.ToleranceWarning` (solve_ivp does the same, with a plain
warning, at every call of the solver); ``atol`` must be positive (solve_ivp also accepts 0; a
zero ``atol`` stalls the step control at a zero component). Tolerances have ceilings too, each
with its reason beside it: ``rtol <= 1e-3`` (:data:`RTOL_CEILING`, scipy's default), a residual
tolerance at most 1e-6 relative to the state (:data:`RESIDUAL_CEILING`, the closure
:func:`~flapping.periodic.floquet.monodromy` accepts as an orbit), ``atol`` and the other accuracy
goals at most 1 % (:data:`TOL_CEILING`); where a tolerance is absolute, its ceiling scales with
``max(1, |x0|)`` (:func:`check_scaled`). The work an argument can ask for is capped
(:data:`CAPS`): a ``max_steps`` of 10**12 is a typo that would run for days, not a budget.

The defaults of the table are defined once each, here (:data:`ORBIT_RTOL`, :data:`ORBIT_ATOL`,
:data:`ORBIT_TOL`, :data:`MONODROMY_RTOL`, :data:`MONODROMY_ATOL`), with their reasons; every
function of the layer and the package's backend objects (:mod:`flapping.backends`) take them
from here, and a test finds any other literal of them.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, fields
from typing import Any

import numpy as np
from scipy.integrate import BDF, DOP853, LSODA, RK23, RK45, OdeSolver, Radau

import flapping._validation as check
from flapping.errors import ToleranceWarning
from flapping.periodic.rk4 import RK4

__all__ = ["SolverSettings", "METHODS", "MAX_STEPS", "RTOL_FLOOR", "RTOL_CEILING",
           "RESIDUAL_CEILING", "TOL_CEILING", "CAPS", "check_field", "check_rtol", "check_atol",
           "check_method", "check_scaled", "check_times", "capped", "resolve", "ORBIT_RTOL",
           "ORBIT_ATOL", "ORBIT_TOL", "MONODROMY_RTOL", "MONODROMY_ATOL", "CONTINUATION_RTOL",
           "CONTINUATION_ATOL", "FIXED_STEP_ERROR_TOL", "CURVE_TOL", "CURVE_RTOL", "CURVE_ATOL"]

#: Integration methods by name: scipy's and the fixed-step ``"RK4"``.
METHODS: dict[str, type[OdeSolver]] = {
    "RK45": RK45, "RK23": RK23, "DOP853": DOP853, "Radau": Radau, "BDF": BDF, "LSODA": LSODA,
    "RK4": RK4,
}

#: Default step budget of one integration call (all its pieces together).
MAX_STEPS = 100_000

#: Default relative tolerance of the integrations that find a periodic orbit (DOP853): near the
#: float64 floor of an 8th-order method over ~10^3 steps, so that the shooting residual can
#: reach :data:`ORBIT_TOL` (the paper's RK4 at 2**-10 gets ~1e-8).
ORBIT_RTOL = 1e-11
#: Default absolute tolerance of those integrations (SI units of the states): a decade under
#: :data:`ORBIT_RTOL`, for states that pass through zero.
ORBIT_ATOL = 1e-12
#: Default largest norm of the shooting residual (absolute, units of the state): ten times the
#: integration's error over a period at :data:`ORBIT_RTOL`, so that a converged solve is not
#: chasing integration noise.
ORBIT_TOL = 1e-10
#: Default tolerances of the integration of a monodromy (the variational equations along a found
#: orbit): a decade tighter than the orbit's, so that the analysis adds no error of its own.
MONODROMY_RTOL = 1e-12
#: Default absolute tolerance of a monodromy's integration: as :data:`MONODROMY_RTOL`.
MONODROMY_ATOL = 1e-12
#: Default target of a fixed-step solve's Richardson error estimate of every unknown (relative to
#: ``max(1, |value|)``): :data:`ORBIT_TOL`'s number, so that the fixed-step and the adaptive paths'
#: orbits are equally accurate by default.
FIXED_STEP_ERROR_TOL = ORBIT_TOL
#: Defaults of a bifurcation curve's continuation (:func:`~flapping.periodic.bifurcation_curves.
#: continue_bifurcation`): the defining system's residual relative to ``1 + |x|`` at the orbit's
#: number (its corrector converges to ~1e-10, which places the special points to ~1e-5), and the
#: integrations at the orbit's relative tolerance with an absolute one of the same size.
CURVE_TOL = ORBIT_TOL
#: Default relative tolerance of a bifurcation curve's integrations: :data:`ORBIT_RTOL`.
CURVE_RTOL = ORBIT_RTOL
#: Default absolute tolerance of a bifurcation curve's integrations: :data:`CURVE_RTOL`'s number.
CURVE_ATOL = ORBIT_RTOL
#: Default tolerances of a continuation's integrations: a decade looser than the orbit's, as
#: each point is a predictor-corrector step whose residual is relative (1e-8) and the branch's
#: bifurcations are located again at :data:`MONODROMY_RTOL`.
CONTINUATION_RTOL = 1e-10
#: Default absolute tolerance of a continuation's integrations: as :data:`CONTINUATION_RTOL`.
CONTINUATION_ATOL = 1e-10

#: The smallest relative tolerance float64 can deliver: scipy's ``100 * eps``.
RTOL_FLOOR = 100 * float(np.finfo(float).eps)

#: The largest relative integration tolerance accepted. scipy's ``solve_ivp`` takes any ``rtol``,
#: but its error control rests on the local error being small beside the state: at its own
#: default, 1e-3, an 8th- or 5th-order step already carries about three correct digits and
#: little more; above it the error estimate is no longer asymptotic and a "successful"
#: integration of a periodic orbit has no correct digit (Lorenz at rtol = 1 ends on the wrong
#: side of its attractor). So (RTOL_FLOOR, 1e-3]: scipy's default is the loosest we accept.
RTOL_CEILING = 1e-3

#: The largest residual tolerance of a periodic-orbit solve, relative to the size of the state
#: (``tol <= RESIDUAL_CEILING * max(1, |x0|)`` for the absolute ``tol`` of shooting and of the
#: fixed-step solver; the continuation's ``tol`` is relative already). It is
#: :data:`flapping.periodic.floquet.CLOSURE_TOL`: a point whose orbit closes worse than that is,
#: for :func:`~flapping.periodic.floquet.monodromy`, on no periodic orbit (ClosureWarning), so a
#: solver must not accept it as one (``tol = 1e6`` once "reached p_end" through non-solutions).
RESIDUAL_CEILING = 1e-6

#: The largest relative accuracy goal of the other tolerances of the layer (the fixed-step
#: solver's ``error_tol`` and ``multiplier_tol``; Levenberg-Marquardt's ``xtol`` and ``ftol``):
#: 1 %. Richardson's estimate assumes the error is in its asymptotic regime (small beside the
#: unknowns), and a multiplier known to +-0.01 still tells stability apart near abs(mu) = 1 only
#: just; MINPACK's relative step and reduction tests at 1 % stop after the first iteration.
TOL_CEILING = 1e-2

#: Largest value accepted for each size-like argument of the layer. The work of a call grows
#: with each (an integration's steps, the shooting residual's rows, Levenberg-Marquardt's and
#: the continuation's iterations); beyond these a call would run for hours or exhaust memory.
CAPS: dict[str, int] = {
    "max_steps": 10**7,     # steps of one integration (~1e8 evaluations of fun)
    "rk4_steps": 2**22,     # RK4 steps per period (4 evaluations each)
    "n_points": 1024,       # residual blocks of eq. (38): rows and restarts grow with it
    "segments": 1024,       # shooting segments: one integration each, a (nM)^2 Jacobian
    "max_nfev": 10**5,      # residual evaluations of Levenberg-Marquardt (one integration each)
    "max_newton": 100,      # Newton iterations per continuation point
    "max_points": 10**5,    # points of a continuation branch
    "n_sub": 4096,          # sub-intervals of a monodromy matrix (2**-12 of the period)
    "t_eval": 10**6,        # output times of a flow: each is one dense-output evaluation in
                            # Python (~10 us) and n floats: 1e7 took minutes; sample in chunks
}


def capped(name: str, value: Any, low: int = 1) -> int:
    """``value`` as an int in ``[low, CAPS[name]]``, or a ValueError naming the argument and cap."""
    return check.integer(name, value, low=low, high=CAPS[name])


def check_rtol(name: str, value: Any) -> float:
    """A relative tolerance in (0, :data:`RTOL_CEILING`], raised to :data:`RTOL_FLOOR` with a
    warning if below it."""
    rtol = check.real(name, value, low=0.0, high=RTOL_CEILING, low_open=True)
    if rtol < RTOL_FLOOR:
        warnings.warn(f"`{name}` = {rtol:.3g} is below what float64 can deliver (100 * eps = "
                      f"{RTOL_FLOOR:.3g}, as in scipy's solve_ivp): raised to {RTOL_FLOOR:.3g}",
                      ToleranceWarning, stacklevel=4)
        rtol = RTOL_FLOOR
    return rtol


def check_atol(name: str, value: Any) -> float | np.ndarray:
    """An absolute tolerance: a positive float, or a vector of positive floats."""
    if np.ndim(value) == 0:
        return check.positive(name, value)
    atol = check.vector(name, value)
    if not np.all(atol > 0):
        raise ValueError(f"`{name}` must be positive; got {value!r}")
    atol.flags.writeable = False
    return atol


def check_scaled(name: str, value: float | np.ndarray, x0: np.ndarray,
                 ceiling: float = RESIDUAL_CEILING) -> None:
    """An absolute tolerance (checked positive already) at most ``ceiling * max(1, |x0|)``.

    For the tolerances whose unit is the state's (shooting's ``tol``, an integration's ``atol``):
    their sane range depends on the size of the state, known only with ``x0``. ``atol`` uses
    :data:`TOL_CEILING` (an error control of 1 % of the state is already coarse; ``atol = 1e300``
    switches it off), the residual tolerances :data:`RESIDUAL_CEILING`.

    Raises
    ------
    ValueError
        Naming the argument, the bound and the state size it came from.
    """
    scale = max(1.0, float(np.linalg.norm(x0)))
    top = float(np.max(value))
    if top > ceiling * scale:
        raise ValueError(f"`{name}` must be at most {ceiling:g} * max(1, |x0|) = "
                         f"{ceiling * scale:.3g} (|x0| = {float(np.linalg.norm(x0)):.3g}); "
                         f"got {top!r}: a looser tolerance accepts non-solutions")


def check_times(name: str, value: Any, t0: float, t1: float) -> np.ndarray:
    """Output times: a finite 1-D array within ``[t0, t1]``, sorted in the direction of
    integration, of at most ``CAPS[name]`` points.

    Raises
    ------
    ValueError
        Naming the argument and what is wrong (a non-finite time, the order, the span, the size).
    """
    times = check.array(name, value)
    if times.ndim != 1:
        raise ValueError(f"`{name}` must be a 1-D array of times; got shape {times.shape}")
    if times.size > CAPS[name]:
        raise ValueError(f"`{name}` must have at most {CAPS[name]} points; got {times.size} "
                         f"(sample the solution in chunks, or use dense_output=True)")
    lo, hi = min(t0, t1), max(t0, t1)
    if times.size and (times.min() < lo or times.max() > hi):
        raise ValueError(f"`{name}` must lie within t_span [{lo!r}, {hi!r}]; got times in "
                         f"[{float(times.min())!r}, {float(times.max())!r}]")
    steps = np.diff(times) * (1.0 if t1 >= t0 else -1.0)
    if np.any(steps < 0):
        order = "increasing" if t1 >= t0 else "decreasing (t1 < t0)"
        k = int(np.argmax(steps < 0))
        raise ValueError(f"`{name}` must be sorted {order}, as the integration runs; got "
                         f"{float(times[k])!r} before {float(times[k + 1])!r} (index {k})")
    return times


def check_method(value: Any) -> str | type[OdeSolver]:
    """A method name of :data:`METHODS`, or an :class:`~scipy.integrate.OdeSolver` subclass."""
    if isinstance(value, type) and issubclass(value, OdeSolver):
        return value
    return check.choice("method", value, tuple(METHODS))


_CHECKS = {
    "method": check_method,
    "rtol": lambda v: check_rtol("rtol", v),
    "atol": lambda v: check_atol("atol", v),
    "rk4_steps": lambda v: capped("rk4_steps", v),
    "max_steps": lambda v: capped("max_steps", v),
    "tol": lambda v: check.positive("tol", v),  # its ceiling needs the state: check_scaled
    "max_nfev": lambda v: capped("max_nfev", v),
    "max_newton": lambda v: capped("max_newton", v),
}


def check_field(name: str, value: Any) -> Any:
    """One field of :class:`SolverSettings`, checked (None passes: "the function's default").

    Raises
    ------
    ValueError
        Naming the field and its accepted values.

    Warns
    -----
    ToleranceWarning
        When ``rtol`` is raised to :data:`RTOL_FLOOR`.
    """
    return None if value is None else _CHECKS[name](value)


@dataclass(frozen=True)
class SolverSettings:
    """The options shared by shooting, Floquet analysis and continuation (module notes).

    Every field defaults to ``None``: the function's own default (table in the module notes).

    Attributes
    ----------
    method : str or OdeSolver subclass, optional
        Integrator: ``"DOP853"``, another :func:`~scipy.integrate.solve_ivp` method, or ``"RK4"``.
    rtol : float, optional
        Relative integration tolerance, in (0, 1e-3] (:data:`RTOL_CEILING`); raised to
        100 eps with a warning below it.
    atol : float or array_like, optional
        Absolute integration tolerance, > 0.
    rk4_steps : int, optional
        RK4 steps per period, in [1, 2**22].
    max_steps : int, optional
        Step budget of one integration, in [1, 10**7].
    tol : float, optional
        Residual tolerance of the nonlinear solve (absolute for shooting, relative to the
        states' size for continuation), > 0; each solver bounds it by 1e-6 relative to the
        state (:data:`RESIDUAL_CEILING`) when it knows the state.
    max_nfev : int, optional
        Residual evaluations of Levenberg-Marquardt (shooting), in [1, 10**5].
    max_newton : int, optional
        Newton iterations per continuation point, in [1, 100].

    Raises
    ------
    ValueError
        For a field outside its range (named in the message).
    """

    method: str | type[OdeSolver] | None = None
    rtol: float | None = None
    atol: float | np.ndarray | None = None
    rk4_steps: int | None = None
    max_steps: int | None = None
    tol: float | None = None
    max_nfev: int | None = None
    max_newton: int | None = None

    def __post_init__(self) -> None:
        for f in fields(self):
            object.__setattr__(self, f.name, check_field(f.name, getattr(self, f.name)))

    def merged(self, **explicit: Any) -> dict[str, Any]:
        """The fields with the keywords that are not None laid over them (keywords win).

        Parameters
        ----------
        **explicit
            Keyword arguments as a function received them (None: not given).

        Returns
        -------
        dict
            Field name to value, checked; None where neither gives a value.
        """
        out = {name: getattr(self, name) for name in _FIELD_NAMES}
        for name, value in explicit.items():
            if value is not None:
                out[name] = check_field(name, value)
        return out


def resolve(settings: Any, defaults: dict[str, Any], **explicit: Any) -> dict[str, Any]:
    """Options of one call: explicit keyword, else ``settings``' field, else ``defaults``.

    Parameters
    ----------
    settings : SolverSettings or None
        The caller's settings object.
    defaults : dict
        The function's defaults for the fields it uses.
    **explicit
        The function's keyword arguments (None: not given).

    Returns
    -------
    dict
        The fields named in ``defaults``, checked.

    Raises
    ------
    ValueError
        If ``settings`` is not a SolverSettings, or a value is out of range.
    """
    if settings is None:
        if all(v is None for v in explicit.values()):
            return dict(defaults)  # the common call: nothing given, nothing to check
        settings = _EMPTY
    elif not isinstance(settings, SolverSettings):
        raise ValueError(f"`settings` must be a SolverSettings; got {settings!r} "
                         f"({type(settings).__name__})")
    given = settings.merged(**explicit)
    return {k: (v if given[k] is None else given[k]) for k, v in defaults.items()}


_EMPTY = SolverSettings()
_FIELD_NAMES = tuple(f.name for f in fields(SolverSettings))

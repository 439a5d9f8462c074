"""The hover problem of one insect, built once and asked by every solver.

A :class:`HoverProblem` knows the insect, the aerodynamic model, the mean angle of attack and the
trim unknowns. It hands out what the solvers need: the right-hand sides of the state augmented
with the hover conditions, their Jacobians and their sensitivities to the trims (for
:func:`flapping.periodic.shooting.find_periodic_orbit` and continuation), the compiled kernel's
packing, and the decision of which backend runs (:meth:`HoverProblem.backend`, the one place that
decides it). After BifurcationKit's ``BifurcationProblem``: the problem is built once, the solvers
never rebuild it.

The augmented state: (u, w, q, theta) and the descent z (z' = -u sin theta + w cos theta, z(0) = 0
held fixed, so that periodicity of z is zero mean vertical speed); with the mean stroke angle as a
second trim, the forward distance x_e too (zero mean horizontal speed). The trims are the free
parameters: params = [Phi] or params = [Phi, phi_bar].
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from flapping import _validation
from flapping.backends import (
    AUTO,
    BACKEND_NAMES,
    Adaptive,
    Backend,
    Compiled,
    FixedStep,
    as_backend,
)
from flapping.errors import DomainError
from flapping.fast import blade as _blade
from flapping.fast import kernel as _kernel
from flapping.model.aerodynamics import trim_angle_of_attack
from flapping.model.dynamics import (
    AERODYNAMIC_MODELS,
    LongitudinalDynamics,
    inertial_velocity,
    inertial_velocity_jac,
)
from flapping.model.kinematics import check_alpha_m, check_amplitude, segment_stroke_sign
from flapping.model.morphology import Insect

__all__ = ["BACKENDS", "DEFAULT_BACKEND", "GRADING_POWER", "TRIMS", "HoverProblem",
           "choose_backend", "grading", "grading_derivative"]

#: The string forms of ``backend`` (:mod:`flapping.backends`): ``"compiled"``, the numba kernel
#: of :mod:`flapping.fast` (eq. 29's linear loads only, ~1 ms); ``"fixed-step"``, Newton on a
#: fixed-step 8th-order period map on a time mesh graded towards the stroke reversals (any loads
#: model, made for the blade-element ones: 0.1-0.2 s of CPU per hawkmoth or monarch solve
#: with the compiled loads and period map of :mod:`flapping.fast.blade`); ``"adaptive"``, the
#: scipy path (adaptive DOP853, the reference and the cross-check); ``"auto"``, chosen by
#: :func:`choose_backend`.
BACKENDS: tuple[str, ...] = BACKEND_NAMES

#: The time mesh of the fixed-step path: on each half-stroke t = t_k + (T/2) g(s), s uniform in
#: [0, 1], with g' = sin^4(pi s) / (3/8): steps shrink as s^4 towards the stroke reversals. There
#: the sign-change station r* = -u_c / phi_dot of the section airspeed U sweeps in from the tip
#: on a time scale ~1e-4 T (the loads are analytic but vary that fast); a uniform step resolves
#: it only with thousands of steps per half-stroke (observed order 1-4), the graded one with
#: ~64 (observed order ~8 on the hawkmoth, small-angle and exact loads; see
#: ``benchmarks/bench_fixedstep_order.py``). The exponent is fixed (:func:`grading` is written for
#: it), not a setting.
GRADING_POWER = 4

#: The default backend of every hover path (:func:`~flapping.hover.find_hover_orbit`,
#: :func:`~flapping.hover.hover_stability`, sweeps): the fast one where it applies
#: (:func:`choose_backend`).
DEFAULT_BACKEND = AUTO

#: The trim sets: the stroke amplitude alone (zero mean vertical speed, the paper's hover), or the
#: amplitude and the mean stroke angle phi_bar together (zero mean vertical *and* horizontal
#: speed: a true hover orbit for any hinge offset).
TRIMS: tuple[tuple[str, ...], ...] = (("amplitude",), ("amplitude", "stroke_mean"))

#: Models kept at other mean stroke angles while phi_bar is iterated (a few are revisited).
_MODELS_KEPT = 8


@dataclass(frozen=True, eq=False)
class HoverProblem:
    """The hover problem of one insect (build once; every solver asks it).

    Parameters
    ----------
    insect : Insect
    aerodynamics : {"linear", "small-angle", "exact"}
        Loads model (:class:`~flapping.model.dynamics.LongitudinalDynamics`); ``"linear"`` is
        eq. (29).
    alpha_m : float, optional
        Mean geometric angle of attack [rad], held fixed while the trims are solved for; default
        the trim of eq. (40) at the insect's nominal amplitude, as in the paper.
    trims : ("amplitude",) or ("amplitude", "stroke_mean")
        The trim unknowns (:data:`TRIMS`).
    trim_check : bool, keyword-only
        Refuse at once an insect that cannot hover even at rest (eq. 40 needs Phi > 90 deg;
        the default). False skips that check only: the problem of a model at a prescribed
        amplitude (:meth:`of_model`, for :func:`~flapping.hover.forced_orbit`, which solves no
        trim) exists whether or not the insect can hover.

    Raises
    ------
    ValueError
        For a bad argument, or (with ``trim_check``) an insect too heavy to trim (eq. 40 needs
        Phi > 90 deg).
    """

    insect: Insect
    aerodynamics: str = "linear"
    alpha_m: float | None = None
    trims: tuple[str, ...] = ("amplitude",)
    trim_check: bool = field(default=True, kw_only=True, repr=False)

    def __post_init__(self) -> None:
        insect = _validation.instance("insect", self.insect, Insect)
        aerodynamics = _validation.choice("aerodynamics", self.aerodynamics, AERODYNAMIC_MODELS)
        alpha_m = (trim_angle_of_attack(insect, insect.stroke_amplitude) if self.alpha_m is None
                   else self.alpha_m)
        alpha_m = check_alpha_m(alpha_m)
        trims = check_trims(self.trims)
        if _validation.boolean("trim_check", self.trim_check):
            check_trim(insect, alpha_m)
        object.__setattr__(self, "aerodynamics", aerodynamics)
        object.__setattr__(self, "alpha_m", alpha_m)
        object.__setattr__(self, "trims", trims)

    @classmethod
    def of_model(cls, model: LongitudinalDynamics) -> HoverProblem:
        """The hover problem a model belongs to: its insect, loads and alpha_m, one trim.

        Built without the trim check (``trim_check=False``): the model may be at any amplitude
        (:func:`~flapping.hover.forced_orbit`'s), and its problem only hands out right-hand sides
        and decides the backend. The problem's :attr:`model` is ``model`` itself (its right-hand
        side takes the amplitude as an argument, so a model at any amplitude serves).

        Parameters
        ----------
        model : LongitudinalDynamics

        Returns
        -------
        HoverProblem
        """
        model = _validation.instance("model", model, LongitudinalDynamics)
        problem = cls(model.insect, model.aerodynamics, model.alpha_m, TRIMS[0],
                      trim_check=False)
        problem.__dict__["model"] = model  # the cached_property's slot: no second model built
        return problem

    # ---------------------------------------------------------------- what the solvers ask
    @property
    def period(self) -> float:
        """Flapping period T [s]."""
        return self.insect.period

    @property
    def n_conditions(self) -> int:
        """Hover conditions appended to the state: 1 (z) or 2 (z and x_e)."""
        return len(self.trims)

    @cached_property
    def model(self) -> LongitudinalDynamics:
        """The dynamics at the insect's nominal amplitude and mean stroke angle."""
        return LongitudinalDynamics(self.insect, alpha_m=self.alpha_m,
                                    aerodynamics=self.aerodynamics)

    @cached_property
    def kernel_problem(self) -> _kernel.KernelProblem:
        """The insect packed for the compiled kernel (linear loads, one trim)."""
        return _kernel.KernelProblem.of(self.insect, self.alpha_m)

    def fields(self) -> tuple[list[Any], list[Any], list[Any]]:
        """Per half-stroke ``f(t, y, params)``, ``J(t, y, params)`` and
        ``P(t, y, params) = df/dparams``.

        y is the augmented state (u, w, q, theta, z[, x_e]) and params the trims [Phi[, phi_bar]].
        """
        return _Fields(self).lists()

    def graded_fields(self, compiled: bool = True) -> tuple[list[Any], list[Any]]:
        """The fields of :meth:`fields` on the graded time mesh, and their switching functions.

        Per half-stroke k the time is t = T (k + g(s - k)) / 2 with s in [k, k + 1] and g the
        grading of :data:`GRADING_POWER` (g(0) = 0, g(1) = 1, g'(0) = g'(1) = 0); the field in s
        is ``dt/ds f(t(s), y, params)``. The period in s is 2, the breakpoint at s = 1 (fraction
        0.5).

        Parameters
        ----------
        compiled : bool
            For the blade-element models, evaluate the field with the compiled loads of
            :mod:`flapping.fast.blade` where they apply (numba installed, an insect they model):
            the same field to rounding, with its whole period map compiled too
            (:class:`~flapping.fast.blade.GradedMap`, attached to the callables, which the
            fixed-step solver finds): ~50 times faster per solve. False: the Python loads.

        Returns
        -------
        funs : list of callables
            ``F(s, y, params)`` per half-stroke.
        switches : list of tuples of callables
            Per half-stroke, ``g(s, y, params)`` whose sign changes mark the loads' kinks (a jump of
            a derivative of the right-hand side at a state-dependent time): the section airspeed
            U = 0 at the wing root (u - q h_w = 0) and at the tip
            ((u - q h_w) cos(phi) + phi_dot R = 0), and q = 0 (the rotational damping's
            ``|omega| omega``, omega = q cos(phi): a kink of the Jacobian; unmarked, the
            monodromy's multipliers at 64 steps were 3.5e-8 off on the hawkmoth, marked 1.2e-9).
            Empty for the linear loads (smooth within a half-stroke).
        """
        fast = _blade.BladeField.of(self.model, self.n_conditions) if compiled else None
        if fast is None:
            half = 0.5 * self.period
            out = [_graded(f, k, half) for k, f in enumerate(self.fields()[0])]
        else:
            out = [_compiled_graded(fast, k, self.n_conditions) for k in range(len(fast.signs))]
        if self.aerodynamics == "linear":
            return out, [() for _ in out]
        switches = [_switches(self, k) for k in range(len(out))]
        if fast is not None:  # the whole period map compiled too, for the fixed-step solver
            fast.attach_map(out, switches)
        return out, switches

    def guess(self, amplitude: float | None = None) -> np.ndarray:
        """The trims' starting values: [Phi] or [Phi, phi_bar] (default the insect's own)."""
        amp = check_amplitude(self.insect.stroke_amplitude if amplitude is None else amplitude,
                              "amplitude_guess")
        return np.array([amp, self.insect.stroke_mean][: self.n_conditions], dtype=float)

    def backend(self, backend: Backend | str = DEFAULT_BACKEND, *,
                adaptive_options: bool = False) -> str:
        """The name of the path that runs (:func:`choose_backend` decides).

        Parameters
        ----------
        backend : "auto", "compiled", "fixed-step", "adaptive" or a backend object
        adaptive_options : bool
            True if the caller set options of the adaptive path only (another ``method`` or
            ``jacobian``): ``"auto"`` then means the adaptive path.

        Returns
        -------
        {"compiled", "fixed-step", "adaptive"}
        """
        spec = Adaptive() if adaptive_options and as_backend(backend) == AUTO else backend
        return choose_backend(self, spec).name

    def _kernel_refusal(self) -> str:
        """Why the compiled kernel cannot solve this problem ('' if it can)."""
        if self.aerodynamics != "linear":
            return (f"the kernel has eq. (29)'s linear loads only, not "
                    f"aerodynamics={self.aerodynamics!r}")
        if self.n_conditions != 1:
            return "the kernel has no mean stroke angle, so it cannot trim it"
        if self.insect.stroke_mean != 0.0:
            return (f"the kernel has no mean stroke angle: stroke_mean = "
                    f"{self.insect.stroke_mean!r} rad must be 0")
        return _kernel.unsupported_field(self.insect)


def choose_backend(problem: HoverProblem, backend: Backend | str = DEFAULT_BACKEND, *,
                   solved: Backend | None = None) -> Backend:
    """The path that runs for ``problem``: the one function that decides it.

    ``"auto"`` is, for an orbit already solved (``solved``), the path that solved it (its
    analysis then reuses that path's last integration and reports its error estimates);
    otherwise the compiled kernel where it applies (linear loads, one trim, no mean stroke
    angle, numba installed), the fixed-step path for the blade-element loads (the adaptive
    path's residual stalls at its integration noise, ~3e-8, at some hinge heights), the
    adaptive path otherwise. A backend object, or a name, is that path (checked to apply).

    Parameters
    ----------
    problem : HoverProblem
    backend : "auto", "compiled", "fixed-step", "adaptive", or a backend object
        :mod:`flapping.backends`; a name means that path's default options.
    solved : Compiled, FixedStep or Adaptive, optional
        The path that solved the orbit being analysed.

    Returns
    -------
    Compiled, FixedStep or Adaptive

    Raises
    ------
    ValueError
        For an unknown backend, or the compiled path where the kernel does not apply (a
        blade-element model, two trims, a non-zero mean stroke angle).
    ImportError
        For the compiled path without numba.

    Warns
    -----
    RuntimeWarning
        ``"auto"`` where the kernel applies but numba is missing: the adaptive path runs.
    """
    spec = as_backend(backend)
    if not isinstance(spec, str):  # an object, not "auto"
        spec.check(problem)  # the path's own test of where it applies
        return spec
    if solved is not None:
        return solved
    why_not = problem._kernel_refusal()
    if problem.aerodynamics != "linear":
        return FixedStep()
    if why_not:
        return Adaptive()
    if not _kernel.numba_available():
        warnings.warn("numba is not installed: the hover orbit is computed by the adaptive "
                      "scipy path (~300 times slower; pip install flapping[fast])",
                      RuntimeWarning, stacklevel=3)
        return Adaptive()
    return Compiled()


# =========================================================================== right-hand sides
class _Fields:
    """The augmented right-hand side, its Jacobian and its trim sensitivity, per half-stroke.

    With two trims the model is rebuilt at each iterate's phi_bar (a few are kept).
    """

    def __init__(self, problem: HoverProblem) -> None:
        self.problem = problem
        self.size = 4 + problem.n_conditions
        self.models: dict[float, LongitudinalDynamics] = {}

    def lists(self) -> tuple[list[Any], list[Any], list[Any]]:
        signs = [segment_stroke_sign(k) for k in range(len(self.problem.model.breakpoints) + 1)]
        return ([lambda t, y, params, _s=s: self.rhs(t, y, params, _s) for s in signs],
                [lambda t, y, params, _s=s: self.jac(t, y, params, _s) for s in signs],
                [lambda t, y, params, _s=s: self.param_jac(t, y, params, _s) for s in signs])

    def at(self, params: np.ndarray) -> LongitudinalDynamics:
        """The model at the iterate's mean stroke angle (the problem's own with one trim)."""
        if self.size == 5:
            return self.problem.model
        stroke_mean = float(params[1])
        found = self.models.get(stroke_mean)
        if found is None:
            check_iterate_stroke_mean(stroke_mean)
            if len(self.models) >= _MODELS_KEPT:
                del self.models[next(iter(self.models))]
            found = self.problem.model.with_stroke_mean(stroke_mean)
            self.models[stroke_mean] = found
        return found

    def rhs(self, t: float, y: np.ndarray, params: np.ndarray, s: float) -> np.ndarray:
        check_iterate_amplitude(params[0])
        out = np.empty(self.size)
        out[:4] = self.at(params).unchecked.rhs(t, y, s, params[0])
        forward, down = inertial_velocity(y[0], y[1], y[3])
        out[4] = down
        if self.size == 6:
            out[5] = forward
        return out

    def jac(self, t: float, y: np.ndarray, params: np.ndarray, s: float) -> np.ndarray:
        out = np.zeros((self.size, self.size))
        out[:4, :4] = self.at(params).unchecked.jac(t, y, s, params[0])
        forward, down = inertial_velocity_jac(y[0], y[1], y[3])
        out[4, :4] = down
        if self.size == 6:
            out[5, :4] = forward
        return out

    def param_jac(self, t: float, y: np.ndarray, params: np.ndarray, s: float) -> np.ndarray:
        out = np.zeros((self.size, self.size - 4))
        model = self.at(params).unchecked  # the solvers' own arguments: checked at the boundary
        out[:4, :1] = model.amplitude_jac(t, y, s, params[0])
        if self.size == 6:
            out[:4, 1:] = model.stroke_mean_jac(t, y, s, params[0])
        return out


# =========================================================================== graded mesh
# (8/3) sin^4 integrated: g(s) = s - (2/3) sin(2 pi s) / pi + sin(4 pi s) / (12 pi), so that
# g' = (8/3) sin^4(pi s) (GRADING_POWER = 4; grading is its closed form, not a setting).
def grading(s: float) -> float:
    """g(s) of the graded mesh: a smooth increasing map of [0, 1] onto itself, g' ~ s^4 at 0."""
    x = 2.0 * math.pi * s
    return s - (4.0 / 3.0) * math.sin(x) / (2.0 * math.pi) + math.sin(2.0 * x) / (12.0 * math.pi)


def grading_derivative(s: float) -> float:
    """g'(s) = (8/3) sin^4(pi s)."""
    return (8.0 / 3.0) * math.sin(math.pi * s) ** 4


def _graded(f: Any, k: int, half: float) -> Any:
    """F(s, y, params) = dt/ds f(t(s), y, params) on half-stroke k."""
    def field(s: float, y: np.ndarray, params: np.ndarray) -> np.ndarray:
        local = s - k
        return (half * grading_derivative(local)) * f(half * (k + grading(local)), y, params)
    return field


def _compiled_graded(fast: _blade.BladeField, k: int, n_conditions: int) -> Any:
    """F(s, y, params) of :func:`_graded` on half-stroke k, by the compiled loads (the trims checked
    as :class:`_Fields` checks them)."""
    function, arguments = fast.function, fast.arguments(k)
    half_pi = 0.5 * math.pi
    if n_conditions == 1:
        def field(s: float, y: np.ndarray, params: np.ndarray) -> np.ndarray:
            if not 0.0 < params[0] <= half_pi:
                check_iterate_amplitude(params[0])
            return function(s, y, params, *arguments)
    else:
        def field(s: float, y: np.ndarray, params: np.ndarray) -> np.ndarray:
            if not (0.0 < params[0] <= half_pi and -half_pi < params[1] < half_pi):
                check_iterate_amplitude(params[0])
                check_iterate_stroke_mean(float(params[1]))
            return function(s, y, params, *arguments)
    return field


def _switches(problem: HoverProblem, k: int) -> tuple[Any, ...]:
    """The blade-element loads' switching functions on half-stroke k, in the graded time."""
    insect = problem.insect
    span, h_w = insect.semi_span, insect.hinge_height
    omega, half = 2.0 * math.pi * insect.frequency, 0.5 * problem.period
    two_trims = problem.n_conditions == 2

    def root(s: float, y: np.ndarray, params: np.ndarray) -> float:
        return float(y[0] - y[2] * h_w)

    def tip(s: float, y: np.ndarray, params: np.ndarray) -> float:
        t = half * (k + grading(s - k))
        phi_bar = float(params[1]) if two_trims else insect.stroke_mean
        phi = phi_bar + params[0] * math.cos(omega * t)
        return float((y[0] - y[2] * h_w) * math.cos(phi)
                     - omega * params[0] * math.sin(omega * t) * span)

    def pitch_rate(s: float, y: np.ndarray, params: np.ndarray) -> float:
        return float(y[2])

    return (root, tip, pitch_rate)


# =========================================================================== checks
def check_iterate_amplitude(amplitude: float) -> None:
    """Stop the shooting when an iterate's stroke amplitude leaves (0, pi/2]."""
    if not 0.0 < amplitude <= math.pi / 2:
        raise DomainError(
            f"the shooting iteration stepped the stroke amplitude to {math.degrees(amplitude):.4g} "
            "deg, outside (0, 90] deg: no hover orbit with wings that do not cross was found "
            "from this guess")


def check_iterate_stroke_mean(stroke_mean: float) -> None:
    """Stop the shooting when an iterate's mean stroke angle leaves (-pi/2, pi/2)."""
    if not -math.pi / 2 < stroke_mean < math.pi / 2:
        raise DomainError(
            f"the shooting iteration stepped the mean stroke angle to "
            f"{math.degrees(stroke_mean):.4g} deg, outside (-90, 90) deg")


def check_trims(trims: object) -> tuple[str, ...]:
    """``trims`` as a tuple of :data:`TRIMS`, or a ValueError naming the accepted sets."""
    value: tuple[Any, ...] = ()
    if isinstance(trims, str):
        value = (trims,)
    elif isinstance(trims, (tuple, list)):
        value = tuple(trims)
    if value not in TRIMS:
        raise ValueError(f"`trims` must be one of {TRIMS}; got {trims!r}")
    return value


def check_trim(insect: Insect, alpha_m: float) -> None:
    """Refuse at once an insect that cannot hover even at rest (eq. 40 needs Phi > 90 deg)."""
    # Eq. (40) solved for the amplitude at this alpha_m: the stroke a body at rest needs. If even
    # that exceeds 90 deg, no hover orbit exists with wings that do not cross.
    k21 = 0.5 * insect.air_density * insect.lift_slope * insect.span_integral(2, 1)
    needed = math.sqrt(insect.weight / (2.0 * math.pi**2 * insect.frequency**2 * k21
                                        * math.sin(2.0 * alpha_m)))
    if needed > math.pi / 2:
        raise ValueError(
            f"{insect.name} cannot hover with alpha_m = {math.degrees(alpha_m):.4g} deg: "
            f"eq. (40) needs a stroke amplitude of {math.degrees(needed):.4g} deg > 90 deg "
            f"(mass {insect.mass!r} kg); raise alpha_m towards 45 deg or lower the mass")


#: Largest magnitudes of an initial-state guess (u, w [m/s], q [rad/s], theta [rad]): far beyond
#: any hover orbit (the hawkmoth's swings by ~0.1 m/s, ~5 rad/s, ~0.1 rad), yet a guess beyond
#: them is a typo that would blow the integration up, not a start.
STATE_GUESS_LIMITS = (100.0, 100.0, 1e4, 2.0 * math.pi)


def state_guess(x0_guess: ArrayLike | None) -> np.ndarray:
    """The initial-state guess (u, w, q, theta): zeros by default; a ValueError naming the
    component beyond :data:`STATE_GUESS_LIMITS`."""
    if x0_guess is None:
        return np.zeros(4)
    x0 = _validation.vector("x0_guess", x0_guess, size=4)
    for i, (value, limit) in enumerate(zip(x0, STATE_GUESS_LIMITS, strict=True)):
        if abs(value) > limit:
            name, unit = (("u", "m/s"), ("w", "m/s"), ("q", "rad/s"), ("theta", "rad"))[i]
            raise ValueError(f"`x0_guess[{i}]` ({name}) must be in [-{limit:g}, {limit:g}] "
                             f"{unit} (no hover orbit is near it); got {value!r}")
    return x0


def even_samples(n_samples: Any) -> int:
    """The number of samples per period of an orbit: an even integer >= 2 (for the symmetry)."""
    n = _validation.integer("n_samples", n_samples, low=2, high=1 << 20)
    if n % 2:
        raise ValueError(f"`n_samples` must be an even integer >= 2; got {n_samples!r}")
    return n

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
the modelling choices) is in :mod:`flapping.stability`.

Conventions: SI units inside (angles in rad); sampled trajectories have time along the last axis
(``x[i, k]`` is state i at ``t[k]``), as ``solve_ivp``'s ``y``.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from flapping import _validation
from flapping.errors import ConvergenceError, HoverDriftWarning, require_success
from flapping.fast import kernel as _kernel
from flapping.model.dynamics import (
    STATE_NAMES,
    LongitudinalDynamics,
    inertial_velocity,
    inertial_velocity_jac,
)
from flapping.model.kinematics import segment_stroke_sign
from flapping.model.morphology import Insect
from flapping.periodic.integrate import flow, variational_flow
from flapping.periodic.shooting import PeriodicOrbit, find_periodic_orbit

__all__ = [
    "TRIMS",
    "ANALYSIS_ATOL",
    "ANALYSIS_RTOL",
    "BACKENDS",
    "DEFAULT_BACKEND",
    "HALF_PERIOD_SYMMETRY",
    "HOVER_SPEED_RTOL",
    "HoverOrbit",
    "find_hover_orbit",
    "forced_orbit",
    "paper_hover_problem",
    "force_budget",
]

#: x(t + T/2) = S x(t) for the symmetric stroke (x_h = 0): u, q, theta change sign, w does not.
HALF_PERIOD_SYMMETRY = np.diag([-1.0, 1.0, -1.0, -1.0])

#: Largest cycle-mean inertial speed (horizontal and vertical) of an orbit still called hover,
#: relative to the mean wingtip speed 4 Phi f R (~5.8 m/s for the hawkmoth, so ~6 um/s). A hover
#: orbit with the half-period symmetry (x_h = 0) drifts only at round-off (~1e-12 m/s); a hinge
#: 1 mm off the centre of gravity makes it fly at ~0.4 m/s.
HOVER_SPEED_RTOL = 1e-6

#: Default tolerances (relative; absolute in the states' SI units) of the integrations that
#: analyse a found orbit (its force budget here; its averaged Jacobian, Floquet modes and
#: perturbations in :mod:`flapping.stability`): a decade tighter than the orbit's own (rtol
#: 1e-11), so that the analysis adds no error of its own.
ANALYSIS_RTOL = 1e-12
#: Default absolute tolerance of those analysis integrations (see :data:`ANALYSIS_RTOL`).
ANALYSIS_ATOL = 1e-12

#: How the orbit and the monodromy are integrated: ``"compiled"``, the numba kernel of
#: :mod:`flapping.fast` (eq. 29's linear loads only: fixed-step 8th-order Runge-Kutta per
#: half-stroke, Newton, Phi to 1e-9 deg and the multipliers to 1e-8, ~1 ms); ``"adaptive"``, the
#: scipy path (adaptive DOP853, the reference, ~0.3 s); ``"auto"``, the kernel where it applies
#: (linear loads, the default ``method`` and ``jacobian``, numba installed), else adaptive.
BACKENDS: tuple[str, ...] = ("auto", "compiled", "adaptive")

#: The trim sets of :func:`find_hover_orbit`: the stroke amplitude alone (zero mean vertical
#: speed, the paper's hover), or the amplitude and the mean stroke angle phi_bar together (zero
#: mean vertical *and* horizontal speed: a true hover orbit for any hinge offset).
TRIMS: tuple[tuple[str, ...], ...] = (("amplitude",), ("amplitude", "stroke_mean"))

#: The default backend of :func:`find_hover_orbit` and :func:`flapping.stability.hover_stability`.
#: ``"adaptive"`` for now, although the kernel agrees to 1e-10 deg in Phi and 1e-10 in the
#: multipliers (the same printed digits): the book shows the adaptive path's own diagnostics
#: (Levenberg-Marquardt's iteration history, a Liouville error of 5e-14 where the kernel's is
#: 2e-11, a half-period symmetry error of 1e-10 where its own is 2e-9). Use ``backend="auto"`` (or
#: :mod:`flapping.sweep`) for speed.
DEFAULT_BACKEND = "adaptive"


# =========================================================================== results
@dataclass(frozen=True)
class HoverOrbit:
    """A periodic orbit of the insect (the hovering one, or one at a prescribed amplitude).

    Attributes
    ----------
    model : LongitudinalDynamics
        The dynamics at the orbit's amplitude (and mean stroke angle, in ``model.insect``).
    x0 : ndarray, shape (4,)
        (u, w, q, theta) at t = 0 (stroke reversal at the forward extreme) [m/s, m/s, rad/s, rad].
    amplitude : float
        Stroke amplitude Phi [rad].
    period : float
        Flapping period T [s].
    t, x : ndarray
        One period sampled uniformly (``x`` has shape (4, len(t))), for plots and statistics.
    z_drift : float
        Net descent z(T) - z(0) over one period [m]: for :func:`find_hover_orbit` the altitude
        component of the shooting residual (0 to the solver's tolerance), for
        :func:`forced_orbit` the descent integrated along the orbit.
    shooting : PeriodicOrbit
        The shooting solver's result, with its diagnostics.
    kernel : HoverSolution or None
        The compiled kernel's result (monodromy, error estimates) when it found the orbit.
    trims : tuple of str
        The trim unknowns solved for: ``("amplitude",)`` or ``("amplitude", "stroke_mean")``
        (see :data:`TRIMS`).
    """

    model: LongitudinalDynamics
    x0: np.ndarray
    amplitude: float
    period: float
    t: np.ndarray
    x: np.ndarray
    z_drift: float
    shooting: PeriodicOrbit = field(repr=False)
    kernel: Any = field(default=None, repr=False, compare=False)
    trims: tuple[str, ...] = ("amplitude",)

    @property
    def stroke_mean(self) -> float:
        """Mean stroke angle phi_bar [rad] of the orbit (a trim when ``"stroke_mean"`` in trims)."""
        return self.model.insect.stroke_mean

    @property
    def amplitude_deg(self) -> float:
        """Stroke amplitude in degrees."""
        return math.degrees(self.amplitude)

    @property
    def residual_norm(self) -> float:
        """Norm of the shooting residual at the solution."""
        return float(self.shooting.residual_norm)

    @property
    def mean_state(self) -> dict[str, float]:
        """Cycle mean of each state."""
        return {k: float(np.mean(self.x[i, :-1])) for i, k in enumerate(STATE_NAMES)}

    @property
    def state_range(self) -> dict[str, tuple[float, float]]:
        """(min, max) of each state over the period."""
        return {k: (float(self.x[i].min()), float(self.x[i].max()))
                for i, k in enumerate(STATE_NAMES)}

    @property
    def mean_inertial_velocity(self) -> dict[str, float]:
        """Cycle means of the inertial velocities [m/s]: ``forward`` and ``climb`` (up positive)."""
        u, w, _, th = self.x[:, :-1]
        return {"forward": float(np.mean(u * np.cos(th) + w * np.sin(th))),
                "climb": float(np.mean(u * np.sin(th) - w * np.cos(th)))}

    @property
    def mean_horizontal_speed(self) -> float:
        """Magnitude of the cycle-mean inertial horizontal velocity [m/s]: 0 on a hover orbit."""
        return abs(self.mean_inertial_velocity["forward"])

    @property
    def wingtip_speed(self) -> float:
        """Mean wingtip speed 4 Phi f R [m/s], the scale of :attr:`is_hover`'s tolerance."""
        insect = self.model.insect
        return 4.0 * self.amplitude * insect.frequency * insect.semi_span

    @property
    def is_hover(self) -> bool:
        """True if the orbit stays in place on average.

        That is, if both cycle-mean inertial speeds (:attr:`mean_inertial_velocity`) are at most
        :data:`HOVER_SPEED_RTOL` times the :attr:`wingtip_speed`. False for an orbit that drifts
        horizontally (a hinge offset, see :class:`~flapping.errors.HoverDriftWarning`) or climbs
        or sinks (an orbit of :func:`forced_orbit` away from the hover amplitude).
        """
        v = self.mean_inertial_velocity
        return max(abs(v["forward"]), abs(v["climb"])) <= HOVER_SPEED_RTOL * self.wingtip_speed

    @property
    def half_period_symmetry_error(self) -> float:
        """``max |x(t + T/2) - S x(t)| / max |x|`` over the period: 0 with the symmetry."""
        n = self.x.shape[1] - 1
        if n % 2:
            raise ValueError("needs an even number of samples per period")
        first, second = self.x[:, : n // 2], self.x[:, n // 2 : n]
        scale = np.abs(self.x).max(axis=1, keepdims=True)
        return float(np.max(np.abs(second - HALF_PERIOD_SYMMETRY @ first) / scale))


# =========================================================================== vector fields
def _hover_fields(model: LongitudinalDynamics):
    """Per-half-stroke (rhs, jac, param_jac) of the state with the descent z appended; p = [Phi]."""
    rhs, jac, pjac = [], [], []
    for k in range(len(model.breakpoints) + 1):
        s = segment_stroke_sign(k)

        def f(t, y, p, _s=s):
            _check_iterate_amplitude(p[0])
            out = np.empty(5)
            out[:4] = model.rhs(t, y, _s, p[0])
            out[4] = inertial_velocity(y[0], y[1], y[3])[1]
            return out

        def J(t, y, p, _s=s):
            out = np.zeros((5, 5))
            out[:4, :4] = model.jac(t, y, _s, p[0])
            out[4, :4] = inertial_velocity_jac(y[0], y[1], y[3])[1]
            return out

        def P(t, y, p, _s=s):
            out = np.zeros((5, 1))
            out[:4] = model.amplitude_jac(t, y, _s, p[0])
            return out

        rhs.append(f)
        jac.append(J)
        pjac.append(P)
    return rhs, jac, pjac


class _TwoTrimFields:
    """Per-half-stroke (rhs, jac, param_jac) with the descent z and the forward distance x_e
    appended; p = [Phi, phi_bar]. Models at other mean stroke angles are kept (a few)."""

    def __init__(self, model: LongitudinalDynamics) -> None:
        self.model = model
        self.models: dict[float, LongitudinalDynamics] = {}

    def at(self, stroke_mean: float) -> LongitudinalDynamics:
        """The model at mean stroke angle ``stroke_mean`` (an iterate's; validated)."""
        stroke_mean = float(stroke_mean)
        found = self.models.get(stroke_mean)
        if found is None:
            if not -math.pi / 2 < stroke_mean < math.pi / 2:
                raise ConvergenceError(
                    f"the shooting iteration stepped the mean stroke angle to "
                    f"{math.degrees(stroke_mean):.4g} deg, outside (-90, 90) deg")
            if len(self.models) >= 8:
                del self.models[next(iter(self.models))]
            found = self.models[stroke_mean] = self.model.with_stroke_mean(stroke_mean)
        return found

    def fields(self) -> tuple[list[Any], list[Any], list[Any]]:
        """Lists of f(t, y, p), J(t, y, p), P(t, y, p), one per half-stroke."""
        rhs, jac, pjac = [], [], []
        for k in range(len(self.model.breakpoints) + 1):
            s = segment_stroke_sign(k)
            rhs.append(lambda t, y, p, _s=s: self.rhs(t, y, p, _s))
            jac.append(lambda t, y, p, _s=s: self.jac(t, y, p, _s))
            pjac.append(lambda t, y, p, _s=s: self.param_jac(t, y, p, _s))
        return rhs, jac, pjac

    def rhs(self, t: float, y: np.ndarray, p: np.ndarray, s: float) -> np.ndarray:
        _check_iterate_amplitude(p[0])
        out = np.empty(6)
        out[:4] = self.at(p[1]).rhs(t, y, s, p[0])
        out[5], out[4] = inertial_velocity(y[0], y[1], y[3])  # forward, down
        return out

    def jac(self, t: float, y: np.ndarray, p: np.ndarray, s: float) -> np.ndarray:
        out = np.zeros((6, 6))
        out[:4, :4] = self.at(p[1]).jac(t, y, s, p[0])
        out[5, :4], out[4, :4] = inertial_velocity_jac(y[0], y[1], y[3])  # forward, down
        return out

    def param_jac(self, t: float, y: np.ndarray, p: np.ndarray, s: float) -> np.ndarray:
        out = np.zeros((6, 2))
        model = self.at(p[1])
        out[:4, :1] = model.amplitude_jac(t, y, s, p[0])
        out[:4, 1:] = model.stroke_mean_jac(t, y, s, p[0])
        return out


def _check_iterate_amplitude(amplitude: float) -> None:
    """Stop the shooting when an iterate's stroke amplitude leaves (0, pi/2]."""
    if not 0.0 < amplitude <= math.pi / 2:
        raise ConvergenceError(
            f"the shooting iteration stepped the stroke amplitude to {math.degrees(amplitude):.4g} "
            "deg, outside (0, 90] deg: no hover orbit with wings that do not cross was found "
            "from this guess")


def _sample(model: LongitudinalDynamics, x0: np.ndarray, n_samples: int, method: str, **tol):
    """One period from x0 with the descent z alongside: (t, x (4 rows), z(T) - z(0))."""
    rhs = _hover_fields(model)[0]
    t = np.linspace(0.0, model.period, n_samples + 1)
    res = require_success(
        flow(rhs, (0.0, model.period), np.append(x0, 0.0), breakpoints=model.breakpoints,
             period=model.period, method=method, t_eval=t if method != "RK4" else None,
             args=([model.amplitude],), **tol),
        "sampling the orbit")
    return (res.t if method == "RK4" else t), res.x[:4], float(res.x[4, -1])


# =========================================================================== hover
def find_hover_orbit(
    insect: Insect,
    *,
    aerodynamics: str = "linear",
    alpha_m: float | None = None,
    amplitude_guess: float | None = None,
    x0_guess: Sequence[float] | None = None,
    method: str = "DOP853",
    jacobian: str | None = None,
    rtol: float = 1e-11,
    atol: float = 1e-12,
    tol: float = 1e-10,
    n_samples: int = 512,
    backend: str = DEFAULT_BACKEND,
    trims: Sequence[str] = ("amplitude",),
) -> HoverOrbit:
    """Find the hovering periodic orbit: initial state and stroke amplitude.

    Unknowns (u0, w0, q0, theta0, Phi); equations: periodicity of (u, w, q, theta) and zero net
    altitude change over one period (module docstring). The mean angle of attack alpha_m stays at
    the trim of eq. (40) for the insect's nominal amplitude, as in the paper.

    Parameters
    ----------
    insect : Insect
    aerodynamics : {"linear", "small-angle", "exact"}
        Loads model (:class:`~flapping.model.dynamics.LongitudinalDynamics`); ``"linear"`` is
        eq. (29).
    alpha_m : float, optional
        Mean geometric angle of attack [rad]; default the trim of eq. (40).
    amplitude_guess : float, optional
        Initial guess of Phi [rad]; default ``insect.stroke_amplitude``.
    x0_guess : sequence of 4 floats, optional
        Initial guess of (u, w, q, theta); default zeros.
    jacobian : {"variational", "finite-difference"}, optional
        Jacobian of the shooting residual. Default: ``"variational"`` for the linear model (its
        Jacobian is analytic), ``"finite-difference"`` for the blade-element models (their
        Jacobian would itself be differenced at every step, which costs more, and the variational
        system's step sequence then varies enough between iterates to hold the residual at the
        integration-noise floor ~1e-10).
    method, rtol, atol, tol
        Passed to :func:`flapping.periodic.shooting.find_periodic_orbit` (``tol``: largest accepted
        residual norm).
    n_samples : int
        Samples of the orbit over one period in the result (even, >= 2).
    backend : {"auto", "compiled", "adaptive"}
        The integration path (see :data:`BACKENDS`); ``method``, ``jacobian``, ``rtol``,
        ``atol`` and ``tol`` belong to the adaptive one.
    trims : ("amplitude",) or ("amplitude", "stroke_mean")
        The trim unknowns (:data:`TRIMS`). With ``"stroke_mean"`` the mean stroke angle phi_bar
        of phi = phi_bar + Phi cos(2 pi f t) is solved for too (guess: ``insect.stroke_mean``),
        and the forward distance flown over a period joins the equations: zero mean vertical and
        horizontal speed, a true hover orbit for any hinge offset. Adaptive path only (the
        compiled kernel has no phi_bar; ``backend="auto"`` falls back).

    Returns
    -------
    HoverOrbit
        Check :attr:`HoverOrbit.is_hover`: with a hinge offset and the amplitude as the only trim
        the orbit may drift horizontally. :attr:`HoverOrbit.trims` says which trims were used.

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
        If the orbit's mean horizontal speed exceeds :data:`HOVER_SPEED_RTOL` times the mean
        wingtip speed (the orbit holds its altitude but is not hover; see
        :attr:`HoverOrbit.is_hover`).
    """
    model = LongitudinalDynamics(insect, alpha_m=alpha_m, aerodynamics=aerodynamics)
    amplitude = insect.stroke_amplitude if amplitude_guess is None else amplitude_guess
    model.with_amplitude(amplitude)  # validates the guess
    _check_trim(insect, model.alpha_m)
    x0 = _state_guess(x0_guess)
    n_samples = _even_samples(n_samples)
    trims = _check_trims(trims)
    if len(trims) == 2:
        if _validation.choice("backend", backend, BACKENDS) == "compiled":
            raise ValueError("trims=('amplitude', 'stroke_mean') needs the adaptive path: the "
                             "compiled kernel has no mean stroke angle (use backend='auto')")
        if jacobian is None:
            jacobian = "variational" if aerodynamics == "linear" else "finite-difference"
        orbit = _two_trim_orbit(model.with_amplitude(amplitude), x0, n_samples, method=method,
                                jacobian=jacobian, rtol=rtol, atol=atol, tol=tol)
        _warn_if_drifting(orbit)
        return orbit
    if use_kernel(backend, model, method == "DOP853" and jacobian in (None, "variational")):
        orbit = _kernel_orbit(model, amplitude, x0, n_samples)
        _warn_if_drifting(orbit)
        return orbit
    if jacobian is None:
        jacobian = "variational" if aerodynamics == "linear" else "finite-difference"
    rhs, jac, pjac = _hover_fields(model)
    result = find_periodic_orbit(
        rhs, np.append(x0, 0.0), model.period, autonomous=False, jac=jac, param_jac=pjac,
        free_params=[amplitude], fixed=(4,), breakpoints=model.breakpoints,
        jacobian=jacobian, method=method, rtol=rtol, atol=atol, tol=tol,
    )
    assert result.params is not None  # the amplitude is a free parameter
    phi = float(result.params[0])
    if not 0.0 < phi <= math.pi / 2:
        raise ConvergenceError(
            f"no hover orbit for {insect.name} with a stroke amplitude in (0, 90] deg: the "
            f"shooting converged to Phi = {math.degrees(phi):.4g} deg",
            x=np.append(result.x0, phi), residual=result.residual_norm,
            iterations=result.nit, result=result)
    hover_model = model.with_amplitude(phi)
    x0 = np.asarray(result.x0[:4], dtype=float)
    t, x, _ = _sample(hover_model, x0, n_samples, method, rtol=rtol, atol=atol)
    orbit = HoverOrbit(hover_model, x0, phi, model.period, t, x, float(result.residual[4]), result)
    _warn_if_drifting(orbit)
    return orbit


def _check_trims(trims: object) -> tuple[str, ...]:
    """``trims`` as a tuple of :data:`TRIMS`, or a ValueError naming the accepted sets."""
    value: tuple[Any, ...] = ()
    if isinstance(trims, str):
        value = (trims,)
    elif isinstance(trims, (tuple, list)):
        value = tuple(trims)
    if value not in TRIMS:
        raise ValueError(f"`trims` must be one of {TRIMS}; got {trims!r}")
    return value


def _two_trim_orbit(model: LongitudinalDynamics, x0: np.ndarray, n_samples: int,
                    **options: Any) -> HoverOrbit:
    """find_hover_orbit with (Phi, phi_bar) free: six equations, six unknowns."""
    fields = _TwoTrimFields(model)
    rhs, jac, pjac = fields.fields()
    guess = [model.amplitude, model.insect.stroke_mean]
    result = find_periodic_orbit(
        rhs, np.concatenate([x0, [0.0, 0.0]]), model.period, autonomous=False, jac=jac,
        param_jac=pjac, free_params=guess, fixed=(4, 5), breakpoints=model.breakpoints,
        **options)
    assert result.params is not None  # (Phi, phi_bar) are free parameters
    phi, phi_bar = (float(v) for v in result.params)
    if not (0.0 < phi <= math.pi / 2 and -math.pi / 2 < phi_bar < math.pi / 2):
        raise ConvergenceError(
            f"no hover orbit for {model.insect.name} with a stroke amplitude in (0, 90] deg and "
            f"a mean stroke angle in (-90, 90) deg: the shooting converged to Phi = "
            f"{math.degrees(phi):.4g} deg, phi_bar = {math.degrees(phi_bar):.4g} deg",
            x=np.append(result.x0, result.params), residual=result.residual_norm,
            iterations=result.nit, result=result)
    hover_model = model.with_amplitude(phi).with_stroke_mean(phi_bar)
    x_start = np.asarray(result.x0[:4], dtype=float)
    tol = {"rtol": options["rtol"], "atol": options["atol"]}
    t, x, _ = _sample(hover_model, x_start, n_samples, options["method"], **tol)
    return HoverOrbit(hover_model, x_start, phi, model.period, t, x, float(result.residual[4]),
                      result, trims=TRIMS[1])


def _warn_if_drifting(orbit: HoverOrbit) -> None:
    if not orbit.is_hover:
        insect = orbit.model.insect
        warnings.warn(
            f"the orbit found for {insect.name} holds its altitude but is not hover: it flies "
            f"{'forwards' if orbit.mean_inertial_velocity['forward'] > 0 else 'backwards'} at a "
            f"mean {orbit.mean_horizontal_speed:.3g} m/s (tolerance "
            f"{HOVER_SPEED_RTOL:g} x the wingtip speed {orbit.wingtip_speed:.3g} m/s), as the "
            f"hinge offset x_h = {insect.hinge_offset:g} m (or a mean stroke angle phi_bar = "
            f"{insect.stroke_mean:g} rad) breaks the half-period symmetry; "
            "trims=('amplitude', 'stroke_mean') finds a true hover orbit",
            HoverDriftWarning, stacklevel=3)


# =========================================================================== compiled backend
def use_kernel(backend: str, model: LongitudinalDynamics, default_settings: bool = True) -> bool:
    """Whether ``backend`` means the compiled kernel for this model (see :data:`BACKENDS`).

    Parameters
    ----------
    backend : {"auto", "compiled", "adaptive"}
    model : LongitudinalDynamics
        The kernel applies to ``aerodynamics="linear"`` (eq. 29) only.
    default_settings : bool
        False if the caller asked for adaptive-path settings (another ``method``): then
        ``"auto"`` means the adaptive path.

    Raises
    ------
    ValueError
        For an unknown backend, or ``"compiled"`` with a blade-element model or a non-zero
        ``insect.stroke_mean`` (``"auto"`` then means the adaptive path).
    ImportError
        For ``"compiled"`` without numba.

    Warns
    -----
    RuntimeWarning
        ``"auto"`` where the kernel applies but numba is missing: the adaptive path runs.
    """
    backend = _validation.choice("backend", backend, BACKENDS)
    if backend == "adaptive":
        return False
    if backend == "compiled":
        if model.aerodynamics != "linear":
            raise ValueError("backend='compiled' needs aerodynamics='linear' (eq. 29); the "
                             "blade-element models run on backend='adaptive'")
        if not _kernel.numba_available():
            raise ImportError("backend='compiled' needs numba: pip install flapping[fast]")
        if model.insect.stroke_mean != 0.0:
            raise ValueError(
                f"backend='compiled' has no mean stroke angle: stroke_mean = "
                f"{model.insect.stroke_mean!r} rad must be 0 (use backend='adaptive' or 'auto')")
        return True
    if model.aerodynamics != "linear" or not default_settings or model.insect.stroke_mean != 0.0:
        return False
    if not _kernel.numba_available():
        warnings.warn("numba is not installed: the hover orbit is computed by the adaptive "
                      "scipy path (~300 times slower; pip install flapping[fast])",
                      RuntimeWarning, stacklevel=3)
        return False
    return True


def _kernel_orbit(model: LongitudinalDynamics, amplitude: float, x0: np.ndarray,
                  n_samples: int) -> HoverOrbit:
    """find_hover_orbit on the compiled kernel, its answer in the adaptive path's result types."""
    problem = _kernel.KernelProblem.of(model.insect, model.alpha_m)
    sol = _kernel.solve_hover(problem, amplitude_guess=amplitude, x0_guess=x0)
    t, x, _ = _kernel.sample_orbit(problem, sol.x0, sol.amplitude, n_samples)
    norm = sol.residual_norm
    shooting = PeriodicOrbit(
        x0=np.append(sol.x0, 0.0), period=sol.period, params=np.array([sol.amplitude]),
        success=True, message=(f"compiled kernel: Newton converged with {sol.n_steps} fixed "
                               f"8th-order steps per half-stroke (estimated errors: Phi "
                               f"{math.degrees(sol.amplitude_error):.1e} deg, multipliers "
                               f"{sol.multiplier_error:.1e})"),
        residual=sol.residual, residual_norm=norm, residual_history=np.array([norm]),
        iteration_history=np.array([norm]), nit=sol.nit, n_residual_evals=sol.nit,
        nfev=sol.nfev, njev=sol.nfev, jacobian="variational",
        method=f"DOP853 tableau, fixed step ({sol.n_steps} per half-stroke)", autonomous=False,
        unknowns=np.append(sol.x0, sol.amplitude),
        phase_condition="none: the period is known (forced system)")
    return HoverOrbit(model.with_amplitude(sol.amplitude), sol.x0, sol.amplitude, sol.period, t,
                      x, sol.z_drift, shooting, sol)


def _check_trim(insect: Insect, alpha_m: float) -> None:
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


def forced_orbit(
    insect: Insect,
    amplitude: float | None = None,
    *,
    aerodynamics: str = "linear",
    alpha_m: float | None = None,
    x0_guess: Sequence[float] | None = None,
    method: str = "DOP853",
    rtol: float = 1e-11,
    atol: float = 1e-12,
    tol: float = 1e-10,
    n_samples: int = 512,
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
    model = LongitudinalDynamics(insect, amplitude=amplitude, alpha_m=alpha_m,
                                 aerodynamics=aerodynamics)
    x0 = _state_guess(x0_guess)
    n_samples = _even_samples(n_samples)
    rhs, jac = model.segment_functions()
    result = find_periodic_orbit(rhs, x0, model.period, autonomous=False, jac=jac,
                                 breakpoints=model.breakpoints, method=method, rtol=rtol,
                                 atol=atol, tol=tol)
    x0 = np.asarray(result.x0, dtype=float)
    t, x, z_drift = _sample(model, x0, n_samples, method, rtol=rtol, atol=atol)
    return HoverOrbit(model, x0, float(model.amplitude), model.period, t, x, z_drift, result)


def paper_hover_problem(
    insect: Insect,
    *,
    x0_guess: Sequence[float] = (0.1, 0.1, 0.1 * math.pi / 180, 0.1 * math.pi / 180),
    h0_guess: float = 2.0,
    amplitude_guess: float | None = None,
    aerodynamics: str = "linear",
    method: str = "DOP853",
    rtol: float = 1e-11,
    atol: float = 1e-12,
    tol: float = 1e-10,
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
    model = LongitudinalDynamics(insect, aerodynamics=aerodynamics)
    amplitude = insect.stroke_amplitude if amplitude_guess is None else amplitude_guess
    base = model.segment_functions()[0]

    def field(k):
        s = segment_stroke_sign(k)

        def f(t, y, p):
            dx = model.rhs(t, y[:4], s, p[0])
            u, w, q, th = y[:4]
            dh = (dx[1] * math.sin(th) + w * math.cos(th) * q
                  - dx[0] * math.cos(th) + u * math.sin(th) * q)
            return np.append(dx, dh)
        return f

    rhs = [field(k) for k in range(len(base))]
    y0 = np.append(_state_guess(x0_guess), _validation.real("h0_guess", h0_guess, unit="m/s"))
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
def force_budget(
    orbit: HoverOrbit,
    n_samples: int = 4096,
    *,
    rtol: float = ANALYSIS_RTOL,
    atol: float = ANALYSIS_ATOL,
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
        Uniform samples over one period (>= 2) for the cycle means (trapezoid rule).
    rtol, atol : float
        Tolerances of the integration of the orbit (default :data:`ANALYSIS_RTOL`,
        :data:`ANALYSIS_ATOL`).

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
    n_samples = _validation.integer("n_samples", n_samples, low=2)
    rtol, atol = _validation.tolerances(rtol, atol)
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
    d = np.array([model.derivatives(ti) for ti in t]).T
    g, m, Iy = model.insect.gravity, model.insect.mass, model.insect.pitch_inertia
    terms = {
        "u": {"-q w": -q * w, "-g sin(theta)": -g * np.sin(th), "X0/m": d[0] / m,
              "Xu u": d[3] * u, "Xw w": d[4] * w, "Xq q": d[5] * q},
        "w": {"q u": q * u, "g cos(theta)": g * np.cos(th), "Z0/m": d[1] / m,
              "Zu u": d[6] * u, "Zw w": d[7] * w, "Zq q": d[8] * q},
        "q": {"M0/Iy": d[2] / Iy, "Mu u": d[9] * u, "Mw w": d[10] * w, "Mq q": d[11] * q},
    }
    return {eq: {k: float(np.mean(v)) for k, v in parts.items()} for eq, parts in terms.items()}


def _state_guess(x0_guess) -> np.ndarray:
    if x0_guess is None:
        return np.zeros(4)
    return _validation.vector("x0_guess", x0_guess, size=4)


def _even_samples(n_samples) -> int:
    """The number of samples per period of an orbit: an even integer >= 2 (for the symmetry)."""
    n = _validation.integer("n_samples", n_samples, low=2)
    if n % 2:
        raise ValueError(f"`n_samples` must be an even integer >= 2; got {n_samples!r}")
    return n


"""The stability atlas: hover orbits of many insects, found robustly and compared (book/atlas.md).

Application layer: joins the presets (:mod:`flapping.model.presets`), the hover solve
(:func:`~flapping.hover.find_hover_orbit`) and its Floquet analysis
(:func:`~flapping.hover.stability.hover_stability`).

- :func:`hover_by_homotopy` finds the hover orbit of an insect by continuation from one whose
  orbit is known: the morphology moves step by step from one insect to the other, and each step is
  solved from the previous answer; a step that fails is halved. :func:`robust_hover_orbit` tries
  the default guess first and falls back on it.
- :func:`species_stability` reduces an orbit to the atlas's numbers (:class:`SpeciesStability`):
  multipliers, exponents, doubling time, the averaged system and its error, the unstable mode,
  and the exponents with the body attitude held on its periodic schedule
  (:func:`attitude_fixed_exponents`, the constraint of FWUAV's Floquet analysis).
- :func:`frequency_sweep` follows one insect in flapping frequency at a constant mean wingtip
  speed Phi f (hence a constant alpha_m), warm-starting each orbit from the previous one.
- :func:`morphology_sensitivity` recomputes the largest multiplier at the ends of the plausible
  range of every unverified or estimated number of a preset.

Conventions: SI units (angles in rad) unless a name ends in ``_deg``; rates in 1/s.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from flapping import _validation
from flapping.errors import ConvergenceError, PlausibilityWarning
from flapping.hover import ANALYSIS_ATOL, ANALYSIS_RTOL, HoverOrbit, find_hover_orbit
from flapping.hover.stability import HoverStability, hover_stability
from flapping.model.morphology import Insect, hawkmoth
from flapping.model.presets import PRESETS, ellington_r1
from flapping.periodic.floquet import monodromy
from flapping.studies._path import Guess, WarmStart, follow, follow_halving

__all__ = [
    "FWUAV_HOVER",
    "SUN_XIONG_2005",
    "ZHANG_SUN_2010_DOUBLING_WINGBEATS",
    "SCALE_FIELDS",
    "Homotopy",
    "hover_by_homotopy",
    "interpolate_insects",
    "robust_hover_orbit",
    "SpeciesStability",
    "species_stability",
    "GEOMETRY_CASES",
    "TWO_TRIMS",
    "GeometryCase",
    "geometry_comparison",
    "speed_pitch_neutral_height",
    "attitude_fixed_exponents",
    "frequency_sweep",
    "SensitivityBar",
    "morphology_sensitivity",
]

#: FWUAV's quasi-steady hovers with the body attitude prescribed (fdcl-gwu/FWUAV, commit 1a25d41,
#: ``matlab/sim_data/other_insects``): preset name -> (flapping frequency WK.f [Hz], stroke
#: amplitude WK.phi_m [rad], Floquet exponents of its two longitudinal velocity modes [1/s]),
#: from ``sim_QS_x_hover_<insect>.mat`` and ``sim_QS_x_hover_conv_rate.mat`` (entries 4 and 5;
#: ``fig_convergence_rate.m`` labels them "Longitudinal mode 1, 2"; entries 1-3 are the zero
#: exponents of position, entry 6 the lateral mode).
FWUAV_HOVER: dict[str, tuple[float, float, tuple[float, float]]] = {
    "hawkmoth": (30.234258, 0.8267611, (-1.7755204, -4.6284423)),
    "bumblebee": (126.728507, 1.2540563, (-1.5289432, -2.8919659)),
    "fruit_fly": (285.239805, 1.1612576, (-3.9368558, -7.0358839)),
    "monarch": (11.721978, 0.6072701, (-8.4354604, -12.8449206)),
}

#: Sun & Xiong (2005a, J. Exp. Biol. 208:447), bumblebee, CFD derivatives and the averaged model,
#: attitude free, as stated in their abstract: wingbeat period, the unstable oscillatory mode's
#: doubling time and period, and the halving times of the fast and slow subsidence modes [s].
SUN_XIONG_2005 = {"wingbeat": 6.4e-3, "doubling": 0.1, "oscillation_period": 0.32,
                  "fast_halving": 0.024, "slow_halving": 0.37}

#: UNVERIFIED, attribution doubtful: ~14 wingbeats for the doubling of a model drone fly's
#: longitudinal mode, from an earlier reading note that cites Zhang & Sun (2010, Acta Mech. Sin.
#: 26:175), a paper on the *lateral* motion; the book does not quote it.
ZHANG_SUN_2010_DOUBLING_WINGBEATS = 14.0

#: Fields interpolated geometrically by :func:`interpolate_insects` (positive scales spanning
#: decades between species: a fruit fly is 2000 times lighter than a hawkmoth); the others
#: (r1, r2, chord fractions, hinge offset, damping coefficients) linearly.
SCALE_FIELDS = ("semi_span", "wing_area", "frequency", "stroke_amplitude", "mass",
                "pitch_inertia", "air_density", "a0", "roll_inertia", "yaw_inertia")

_NUMERIC = tuple(f.name for f in dataclasses.fields(Insect)
                 if f.init and f.name not in ("name", "aspect_ratio_convention"))


# =========================================================================== homotopy
def interpolate_insects(start: Insect, target: Insect, s: float) -> Insect:
    """The insect a fraction ``s`` of the way from ``start`` to ``target``.

    Fields in :data:`SCALE_FIELDS` are interpolated geometrically (``a**(1-s) * b**s``), the others
    linearly. The set r1 < r2 < sqrt(r1) is convex, so every intermediate planform exists.
    ``s = 1`` returns ``target`` itself; gravity is the start's until ``s = 1`` only if both agree.

    Parameters
    ----------
    start, target : Insect
        The ends of the path (same ``aspect_ratio_convention``).
    s : float
        Fraction of the way, in [0, 1].

    Returns
    -------
    Insect
        Named ``"<start> -> <target> (s=...)"``.

    Raises
    ------
    ValueError
        If ``s`` is outside [0, 1] or the aspect-ratio conventions differ.
    """
    s = _validation.real("s", s, low=0.0, high=1.0)
    if start.aspect_ratio_convention != target.aspect_ratio_convention:
        raise ValueError("`start` and `target` must share the aspect_ratio_convention")
    if s == 1.0:
        return target
    values: dict[str, Any] = {}
    lateral = ("roll_inertia", "yaw_inertia", "roll_yaw_product")
    given = all(getattr(x, n) is not None for x in (start, target) for n in lateral)
    for name in _NUMERIC:
        a, b = getattr(start, name), getattr(target, name)
        if name in lateral and not given:  # six-dof only: the target's, whole (or None)
            values[name] = b
            continue
        if name in ("wing_mass_r1", "wing_mass_r2"):
            if a is None and b is None:  # both the area's radii: so is every intermediate
                continue
            i = name == "wing_mass_r2"
            a, b = start.wing_mass_radii[i], target.wing_mass_radii[i]
        if name in SCALE_FIELDS:
            values[name] = a ** (1.0 - s) * b**s
        else:
            values[name] = (1.0 - s) * a + s * b
    return dataclasses.replace(start, name=f"{start.name} -> {target.name} (s={s:.4g})",
                               **values)


@dataclass(frozen=True)
class Homotopy:
    """The result of :func:`hover_by_homotopy`.

    Attributes
    ----------
    orbit : HoverOrbit
        The hover orbit of the target insect.
    start : str
        Name of the insect the path started from.
    path : tuple of float
        The fractions s of the steps solved (the last is 1).
    nit : tuple of int
        Shooting iterations at each step.
    failures : int
        Steps that failed and were halved.
    """

    orbit: HoverOrbit
    start: str
    path: tuple[float, ...]
    nit: tuple[int, ...]
    failures: int


#: Most steps of a homotopy (each a hover solve): a path between two insects needs a handful; the
#: halvings on failure (``max_failures``, at most 60: 2^-60 of a step is below float64's
#: resolution of s) refine where it must.
MAX_HOMOTOPY_STEPS = 10_000


def hover_by_homotopy(
    target: Insect,
    start: Insect | None = None,
    *,
    n_steps: int = 4,
    max_failures: int = 12,
    start_orbit: HoverOrbit | None = None,
    **hover_options: Any,
) -> Homotopy:
    """The hover orbit of ``target`` by continuation in the morphology from ``start``.

    The insect moves from ``start`` to ``target`` (:func:`interpolate_insects`) in ``n_steps``
    equal steps of s; each step solves :func:`~flapping.hover.find_hover_orbit` from the previous
    steps' answers: the initial state and the ratio of the hover amplitude to the nominal one
    (which sets alpha_m), extrapolated along the secant through the last two solved steps. A step
    that fails (no convergence, or an amplitude leaving (0, 90] deg) is halved and retried, at most
    ``max_failures`` times in all; the steps do not grow again.

    Parameters
    ----------
    target : Insect
    start : Insect, optional
        An insect whose hover orbit the default guess finds; default the paper's hawkmoth.
    n_steps : int
        Initial number of steps, >= 1.
    max_failures : int
        Largest number of halvings, >= 0.
    start_orbit : HoverOrbit, optional
        The start's hover orbit, if already known (skips its solve).
    **hover_options
        Passed to :func:`~flapping.hover.find_hover_orbit` at every step (e.g. ``aerodynamics``);
        not ``amplitude_guess`` or ``x0_guess``, which the continuation sets.

    Returns
    -------
    Homotopy

    Raises
    ------
    ValueError
        For bad arguments.
    ConvergenceError
        If the start's orbit cannot be found, or a step fails ``max_failures`` times in all; the
        message gives the fraction s reached.
    """
    target = _validation.instance("target", target, Insect)
    start = hawkmoth() if start is None else _validation.instance("start", start, Insect)
    n_steps = _validation.integer("n_steps", n_steps, low=1, high=MAX_HOMOTOPY_STEPS)
    max_failures = _validation.integer("max_failures", max_failures, low=0, high=60)
    if {"amplitude_guess", "x0_guess"} & set(hover_options):
        raise ValueError("the continuation sets `amplitude_guess` and `x0_guess` itself")
    orbit = find_hover_orbit(start, **hover_options) if start_orbit is None else start_orbit
    warm = WarmStart(_continued_solve(hover_options), _unknowns, secant=True)
    warm.add(0.0, start, orbit)

    def stalled(s: float, halvings: int, exc: BaseException) -> ConvergenceError:
        return ConvergenceError(
            f"the continuation from {start.name} to {target.name} stalled at s = {s:.4g} "
            f"after {halvings} halvings of the step (last: {exc})")

    steps, failures = follow_halving(
        lambda s: interpolate_insects(start, target, s), warm, n_steps=n_steps,
        max_failures=max_failures, retry=(ConvergenceError, ValueError), stalled=stalled)
    orbits = [step.result for step in steps if step.result is not None]
    return Homotopy(orbits[-1], start.name, tuple(step.s for step in steps),
                    tuple(int(o.nit) for o in orbits), failures)


def _unknowns(insect: Insect, orbit: HoverOrbit) -> np.ndarray:
    """The continued unknowns: the initial state, and Phi over the insect's nominal amplitude
    (which sets alpha_m)."""
    return np.append(np.asarray(orbit.x0, dtype=float), orbit.amplitude / insect.stroke_amplitude)


def _continued_solve(hover_options: dict[str, Any]
                     ) -> Callable[[Insect, Guess[HoverOrbit] | None], HoverOrbit]:
    """``solve(insect, guess)`` of a continuation: the hover orbit from the predicted unknowns
    (:func:`_unknowns`), or from the default guess without one."""
    def solve(insect: Insect, guess: Guess[HoverOrbit] | None) -> HoverOrbit:
        if guess is None or guess.unknowns is None:
            return find_hover_orbit(insect, **hover_options)
        x0, ratio = guess.unknowns[:4], guess.unknowns[4]
        return find_hover_orbit(
            insect, amplitude_guess=min(ratio * insect.stroke_amplitude, math.pi / 2),
            x0_guess=x0.tolist(), **hover_options)
    return solve


def robust_hover_orbit(insect: Insect, *, start: Insect | None = None,
                       **hover_options: Any) -> tuple[HoverOrbit, Homotopy | None]:
    """The hover orbit from the default guess, or by :func:`hover_by_homotopy` if that fails.

    Parameters
    ----------
    insect : Insect
    start : Insect, optional
        Start of the continuation (default the paper's hawkmoth).
    **hover_options
        Passed to :func:`~flapping.hover.find_hover_orbit`.

    Returns
    -------
    orbit : HoverOrbit
    homotopy : Homotopy or None
        The continuation, if it was needed.

    Raises
    ------
    ConvergenceError
        If both fail.
    """
    try:
        return find_hover_orbit(insect, **hover_options), None
    except ConvergenceError:
        result = hover_by_homotopy(insect, start, **hover_options)
        return result.orbit, result


# =========================================================================== per species
def attitude_fixed_exponents(
    orbit: HoverOrbit, stab: HoverStability | None = None, *,
    rtol: float = ANALYSIS_RTOL, atol: float = ANALYSIS_ATOL,
) -> tuple[np.ndarray, np.ndarray]:
    """Floquet exponents of the (u, w) subsystem with the body attitude held on its schedule.

    Perturbations of pitch rate and angle are held at zero (q and theta follow the orbit's
    periodic schedule, as FWUAV prescribes the body attitude): the variational equations keep
    only the (u, w) block of the Jacobian along the orbit, J_c(t) = J(t)[:2, :2]. Their monodromy
    gives two multipliers; the averaged counterpart is the (u, w) block of the averaged Jacobian.

    Parameters
    ----------
    orbit : HoverOrbit
    stab : HoverStability, optional
        The orbit's stability (for the averaged Jacobian); computed if not given.
    rtol, atol : float
        Tolerances of the monodromy integration.

    Returns
    -------
    floquet : ndarray, shape (2,)
        Floquet exponents log(mu)/T of the (u, w) subsystem [1/s], by real part (descending).
    averaged : ndarray, shape (2,)
        Eigenvalues of the averaged (u, w) block [1/s], by real part (descending).
    """
    orbit = _validation.instance("orbit", orbit, HoverOrbit)
    stab = hover_stability(orbit) if stab is None else stab
    model = orbit.model
    rhs, jac = model.segment_functions()

    def constrained(j: Callable[..., np.ndarray]) -> Callable[..., np.ndarray]:
        def jc(t: float, x: np.ndarray) -> np.ndarray:
            out = np.zeros((4, 4))
            out[:2, :2] = j(t, x)[:2, :2]
            return out
        return jc

    mon = monodromy(rhs, orbit.x0, orbit.period, jac=[constrained(j) for j in jac],
                    breakpoints=model.breakpoints, rtol=rtol, atol=atol)
    mu = np.linalg.eigvals(np.asarray(mon.matrix)[:2, :2]).astype(complex)
    floquet = np.log(mu) / orbit.period
    averaged = np.linalg.eigvals(stab.averaged_jacobian[:2, :2]).astype(complex)
    return floquet[np.argsort(-floquet.real)], averaged[np.argsort(-averaged.real)]


@dataclass(frozen=True)
class SpeciesStability:
    """The atlas's numbers for one insect (one row of the book's table).

    Attributes
    ----------
    name : str
    frequency : float
        Flapping frequency f [Hz].
    amplitude_deg, alpha_m_deg : float
        Hover stroke amplitude Phi and mean angle of attack [deg].
    multipliers, exponents : ndarray, shape (4,)
        Floquet multipliers (by modulus) and exponents [1/s].
    averaged_eigenvalues : ndarray, shape (4,)
        Eigenvalues of the averaged system [1/s] (by real part).
    rate : float
        Floquet growth rate of the unstable mode, Re of the leading exponent [1/s].
    averaged_rate : float
        Largest real part of the averaged eigenvalues [1/s].
    mode : ndarray, shape (4,)
        The unstable mode (u, w, q, theta), its largest component 1 (SI units).
    fixed_attitude, fixed_attitude_averaged : ndarray, shape (2,)
        Exponents of the (u, w) subsystem with attitude held (:func:`attitude_fixed_exponents`).
    liouville_error : float
        Relative error of Liouville's formula for the monodromy.
    climb_speed : float
        Cycle-mean inertial climb speed of the orbit [m/s] (0 on hover).
    nit : int
        Shooting iterations.
    averaged_jacobian : ndarray, shape (4, 4)
        The Jacobian averaged over the orbit (the averaged system's matrix) [SI].
    """

    name: str
    frequency: float
    amplitude_deg: float
    alpha_m_deg: float
    multipliers: np.ndarray
    exponents: np.ndarray
    averaged_eigenvalues: np.ndarray
    rate: float
    averaged_rate: float
    mode: np.ndarray
    fixed_attitude: np.ndarray
    fixed_attitude_averaged: np.ndarray
    liouville_error: float
    climb_speed: float
    nit: int
    averaged_jacobian: np.ndarray

    @property
    def doubling_time(self) -> float:
        """Time for the unstable mode to double, ln 2 / rate [s] (inf if it does not grow)."""
        return math.log(2.0) / self.rate if self.rate > 0.0 else math.inf

    @property
    def doubling_wingbeats(self) -> float:
        """:attr:`doubling_time` in wingbeats."""
        return self.doubling_time * self.frequency

    @property
    def mode_per_pitch(self) -> np.ndarray:
        """The unstable mode per radian of pitch: (u [m/s], w [m/s], q [1/s], 1) / theta."""
        return self.mode / self.mode[3]

    @property
    def rate_per_frequency(self) -> float:
        """rate / f, the growth per wingbeat in e-folds (= ln ``|mu_1|``): the time-scale ratio."""
        return self.rate / self.frequency

    @property
    def averaging_error(self) -> float:
        """Relative error of the averaged unstable rate, (averaged - Floquet) / Floquet."""
        return (self.averaged_rate - self.rate) / self.rate


def species_stability(insect: Insect | None = None, orbit: HoverOrbit | None = None,
                      **hover_options: Any) -> SpeciesStability:
    """The atlas's numbers for an insect (its orbit found with :func:`robust_hover_orbit`).

    Parameters
    ----------
    insect : Insect, optional
        The insect; not needed when ``orbit`` is given.
    orbit : HoverOrbit, optional
        Its hover orbit, if already known.
    **hover_options
        Passed to :func:`robust_hover_orbit`.

    Returns
    -------
    SpeciesStability

    Raises
    ------
    ValueError
        If neither ``insect`` nor ``orbit`` is given.
    ConvergenceError
        If the orbit or an integration fails.
    """
    if orbit is None:
        if insect is None:
            raise ValueError("give `insect` or `orbit`")
        orbit, _ = robust_hover_orbit(insect, **hover_options)
    stab = hover_stability(orbit)
    fixed, fixed_avg = attitude_fixed_exponents(orbit, stab)
    mode = stab.unstable_mode
    return SpeciesStability(
        name=orbit.model.insect.name, frequency=orbit.model.insect.frequency,
        amplitude_deg=orbit.amplitude_deg, alpha_m_deg=math.degrees(orbit.model.alpha_m),
        multipliers=stab.multipliers, exponents=stab.exponents,
        averaged_eigenvalues=stab.averaged_eigenvalues,
        rate=float(np.max(np.real(stab.exponents))),
        averaged_rate=float(np.max(np.real(stab.averaged_eigenvalues))),
        mode=np.real(mode) if np.iscomplexobj(mode) else mode,
        fixed_attitude=fixed, fixed_attitude_averaged=fixed_avg,
        liouville_error=stab.liouville_error,
        climb_speed=orbit.mean_inertial_velocity["climb"], nit=int(orbit.nit),
        averaged_jacobian=stab.averaged_jacobian)


# =========================================================================== geometry
#: The three geometries of :func:`geometry_comparison`, in order: the paper's (hinge at the CG,
#: massless wings), the sources' hinge position with massless wings, and with the wings' mass.
#: "Source hinge", not "measured": five of the six hinge positions are estimates and the
#: hoverfly's is a second-hand model parameter (``geometry="source"``;
#: :attr:`~flapping.model.presets.Preset.measured` keeps its attribute name).
GEOMETRY_CASES: tuple[str, ...] = ("paper", "source hinge", "source hinge and wing mass")

#: The trims of a hover with the hinge off the centre of gravity: the mean stroke angle puts the
#: mean lift over the centre of gravity (else the orbit drifts).
TWO_TRIMS = ("amplitude", "stroke_mean")

#: A leading multiplier whose imaginary part is below this fraction of its modulus is real.
_REAL_TOL = 1e-8


@dataclass(frozen=True)
class GeometryCase:
    """One insect in one geometry of :func:`geometry_comparison`.

    Attributes
    ----------
    case : str
        One of :data:`GEOMETRY_CASES`.
    insect : Insect
        The insect solved (its hinge position and wing mass).
    stroke_mean_deg : float
        The hover's mean stroke angle phi_bar [deg] (0 in the paper's geometry).
    stability : SpeciesStability
        The atlas's numbers of its hover orbit.
    """

    case: str
    insect: Insect
    stroke_mean_deg: float
    stability: SpeciesStability

    @property
    def leading_multiplier(self) -> complex:
        """The multiplier of largest modulus."""
        return complex(self.stability.multipliers[0])

    @property
    def mode_type(self) -> str:
        """``"oscillatory"`` (a complex pair), ``"real"`` (a positive real multiplier) or
        ``"flip"`` (a negative one): the type of the leading mode."""
        mu = self.leading_multiplier
        if abs(mu.imag) > _REAL_TOL * abs(mu):
            return "oscillatory"
        return "real" if mu.real > 0.0 else "flip"

    @property
    def speed_pitch_moment(self) -> float:
        """M_u of the averaged system: the pitch acceleration per forward speed, averaged
        d(q_dot)/du [rad/s^2 per m/s]. Negative: forward speed pitches the body nose down, a
        divergence (a real multiplier above 1); see :func:`speed_pitch_neutral_height`."""
        return float(self.stability.averaged_jacobian[2, 0])

    @property
    def oscillation_period(self) -> float:
        """Period of the leading mode's oscillation [s]: 2 pi T / abs(arg mu) (inf if real)."""
        if self.mode_type != "oscillatory":
            return math.inf
        return 2.0 * math.pi * self.insect.period / abs(math.atan2(self.leading_multiplier.imag,
                                                                   self.leading_multiplier.real))


def geometry_comparison(name: str, **hover_options: Any) -> tuple[GeometryCase, ...]:
    """A preset in the paper's geometry, at its sources' hinge, and with its wings' mass.

    Each case is solved from the previous one's orbit (initial state, amplitude and mean stroke
    angle), by continuation in the geometry (:func:`hover_by_homotopy`) if the warm start fails;
    the source-hinge cases trim the mean stroke angle as well (:data:`TWO_TRIMS`).

    Parameters
    ----------
    name : str
        A preset name (:data:`~flapping.model.presets.PRESETS`).
    **hover_options
        Passed to :func:`~flapping.hover.find_hover_orbit` (not ``trims``, ``x0_guess`` or
        ``amplitude_guess``, which this sets).

    Returns
    -------
    tuple of 3 GeometryCase
        In the order of :data:`GEOMETRY_CASES`.

    Raises
    ------
    ValueError
        For an unknown preset or a reserved option.
    ConvergenceError
        If a case's orbit cannot be found.
    """
    name = _validation.choice("name", name, tuple(PRESETS))
    if {"trims", "x0_guess", "amplitude_guess"} & set(hover_options):
        raise ValueError("geometry_comparison sets `trims`, `x0_guess` and `amplitude_guess`")
    paper = PRESETS[name].insect()
    measured = PRESETS[name].insect("source")
    insects = (paper, measured.with_(wing_mass=0.0), measured)
    orbit, _ = robust_hover_orbit(paper, **hover_options)
    cases = [GeometryCase(GEOMETRY_CASES[0], paper, 0.0, species_stability(orbit=orbit))]
    for case, insect in zip(GEOMETRY_CASES[1:], insects[1:], strict=True):
        orbit = _warm_two_trim_orbit(insect, cases[-1].insect, orbit, hover_options)
        cases.append(GeometryCase(case, insect, math.degrees(orbit.stroke_mean),
                                  species_stability(orbit=orbit)))
    return tuple(cases)


def speed_pitch_neutral_height(insect: Insect, high: float | None = None, *,
                               xtol: float = 1e-6, **hover_options: Any) -> float:
    """The hinge height [m] at which the averaged M_u of the hover orbit vanishes.

    Raising the hinge adds -(m h_w / I_y) X_u > 0 to M_u (the wings' drag acts higher; book
    chapter control). In the averaged speed-pitch cubic
    (:func:`~flapping.hover.stability.speed_pitch_cubic`) the constant term is g M_u: where M_u
    changes sign, the real root that makes hover diverge passes through zero (its multiplier
    through +1), and above it the instability, if any, is an oscillation. Found by Brent's method
    on M_u(h_w), each value from the hover orbit at that height (the hinge straight above the
    centre of gravity: one trim).

    Parameters
    ----------
    insect : Insect
        With ``hinge_offset = 0`` (the heights are searched straight above the CG).
    high : float, optional
        Upper end of the search [m], > 0; default the wing length R.
    xtol : float
        Absolute tolerance on the height [m], > 0.
    **hover_options
        Passed to :func:`~flapping.hover.find_hover_orbit`.

    Returns
    -------
    float

    Raises
    ------
    ValueError
        For bad arguments, or if M_u does not change sign on [0, high].
    ConvergenceError
        If an orbit fails.
    """
    from scipy.optimize import brentq

    insect = _validation.instance("insect", insect, Insect)
    if insect.hinge_offset != 0.0:
        raise ValueError("`insect.hinge_offset` must be 0: the heights are searched straight "
                         f"above the centre of gravity; got {insect.hinge_offset!r} m")
    high = insect.semi_span if high is None else _validation.positive("high", high, unit="m")
    xtol = _validation.positive("xtol", xtol, unit="m")

    def moment(height: float) -> float:
        orbit = find_hover_orbit(insect.with_(hinge_height=height), **hover_options)
        return float(hover_stability(orbit).averaged_jacobian[2, 0])

    low_value, high_value = moment(0.0), moment(high)
    if low_value * high_value > 0.0:
        raise ValueError(f"the averaged M_u keeps its sign ({low_value:.4g}, {high_value:.4g} "
                         f"rad/s^2 per m/s) on hinge heights [0, {high:.4g}] m")
    return float(brentq(moment, 0.0, high, xtol=xtol))


def _warm_two_trim_orbit(insect: Insect, previous: Insect, orbit: HoverOrbit,
                         hover_options: dict[str, Any]) -> HoverOrbit:
    """The two-trim hover orbit of ``insect`` from ``previous``'s orbit (by homotopy if need be)."""
    start = previous.with_(stroke_mean=orbit.stroke_mean)
    target = insect.with_(stroke_mean=orbit.stroke_mean)  # phi_bar's first guess
    options = {**hover_options, "trims": TWO_TRIMS}
    try:
        return find_hover_orbit(target, x0_guess=np.asarray(orbit.x0).tolist(),
                                amplitude_guess=orbit.amplitude, **options)
    except (ConvergenceError, ValueError):
        start_orbit = find_hover_orbit(start, x0_guess=np.asarray(orbit.x0).tolist(),
                                       amplitude_guess=orbit.amplitude, **options)
        return hover_by_homotopy(target, start, start_orbit=start_orbit, **options).orbit


# =========================================================================== sweeps
def frequency_sweep(insect: Insect, frequencies: Iterable[float],
                    **hover_options: Any) -> list[SpeciesStability]:
    """The atlas's numbers along a sweep in flapping frequency at constant wingtip speed.

    At each frequency f the nominal amplitude is ``insect.stroke_amplitude * f0 / f`` (f0 the
    insect's frequency), so that Phi f, the mean aerodynamic loads and the trimmed alpha_m stay as
    they are: only the ratio of the body's time scales to the wingbeat changes. Each orbit starts
    from the secant extrapolation (in log f) of the previous two (as :func:`hover_by_homotopy`);
    start the sweep at f0 and go outwards in small steps.

    Parameters
    ----------
    insect : Insect
    frequencies : iterable of float
        Frequencies [Hz], > 0, in the order to solve them; each must keep the nominal amplitude
        at most pi/2.
    **hover_options
        Passed to :func:`~flapping.hover.find_hover_orbit`.

    Returns
    -------
    list of SpeciesStability
        One per frequency, in order.

    Raises
    ------
    ValueError
        For a bad frequency.
    ConvergenceError
        If an orbit fails.
    """
    f0, phi0 = insect.frequency, insect.stroke_amplitude

    def path() -> Iterator[tuple[float, Insect]]:  # (log f, member), checked lazily, in order
        for f in frequencies:
            f = _validation.positive("frequencies", f, unit="Hz")
            with warnings.catch_warnings():
                # The family leaves the range of real insects on purpose (a test of averaging
                # at any frequency ratio): its small amplitudes are not a unit mistake.
                warnings.simplefilter("ignore", PlausibilityWarning)
                member = insect.with_(frequency=f, stroke_amplitude=phi0 * f0 / f,
                                      name=f"{insect.name} at {f:.4g} Hz")
            yield math.log(f), member

    solve = _continued_solve(hover_options)

    def solve_and_analyse(member: Insect, guess: Guess[Any] | None
                          ) -> tuple[HoverOrbit, SpeciesStability]:
        orbit = solve(member, None if guess is None else Guess(guess.previous[0], guess.unknowns))
        return orbit, species_stability(orbit=orbit)

    warm = WarmStart(solve_and_analyse, lambda member, result: _unknowns(member, result[0]),
                     secant=True)
    return [step.result[1] for step in follow(path(), warm) if step.result is not None]


@dataclass(frozen=True)
class SensitivityBar:
    """One bar of a tornado chart: the largest multiplier at the ends of one number's range.

    Attributes
    ----------
    preset, field : str
        The preset and the :class:`Insect` field varied.
    status : str
        The field's status (``"unverified"``, ``"estimate"``, ...).
    low, nominal, high : float
        The field's values [SI].
    mu_low, mu_nominal, mu_high : float
        ``|mu_1|`` at each; NaN where no hover orbit exists (see ``note``).
    note : str
        Why an end has no orbit (e.g. the insect cannot trim, eq. 40), else empty.
    """

    preset: str
    field: str
    status: str
    low: float
    nominal: float
    high: float
    mu_low: float
    mu_nominal: float
    mu_high: float
    note: str = ""

    @property
    def spread(self) -> float:
        """Largest distance of an end from the nominal ``|mu_1|`` (NaN ends ignored; 0 if both
        are)."""
        ends = [abs(m - self.mu_nominal) for m in (self.mu_low, self.mu_high) if math.isfinite(m)]
        return max(ends, default=0.0)


def _leading_multiplier(insect: Insect, near: HoverOrbit) -> tuple[float, str]:
    """``|mu_1|`` of the insect's hover orbit (from a nearby one), or NaN and the reason."""
    try:
        orbit = find_hover_orbit(insect, amplitude_guess=near.amplitude,
                                 x0_guess=near.x0.tolist())
    except (ValueError, ConvergenceError) as exc:
        return math.nan, str(exc)
    return float(np.abs(hover_stability(orbit).multipliers[0])), ""


def morphology_sensitivity(name: str, fields: Sequence[str] | None = None,
                           orbit: HoverOrbit | None = None) -> list[SensitivityBar]:
    """``|mu_1|`` of a preset at both ends of the plausible range of each uncertain number.

    For each field with a range (:meth:`~flapping.model.presets.Preset.ranged`) the preset is
    re-solved with that field at its low and at its high end, the others nominal. When r2 moves,
    an estimated r1 moves with it along Ellington's fit (as it was estimated from r2). An end with
    no hover orbit (the insect cannot trim, or the amplitude would exceed 90 deg) gets NaN and a
    note, not an error.

    Parameters
    ----------
    name : str
        A preset name.
    fields : sequence of str, optional
        The fields to vary; default every field with a range.
    orbit : HoverOrbit, optional
        The preset's nominal hover orbit (warm start), if known.

    Returns
    -------
    list of SensitivityBar
        Sorted by spread, largest first.

    Raises
    ------
    ValueError
        For an unknown preset or a field without a range.
    ConvergenceError
        If an orbit fails.
    """
    preset = PRESETS[_validation.choice("name", name, tuple(PRESETS))]
    ranged = preset.ranged()
    fields = preset.ranged_fields(fields)
    base = preset.insect()
    orbit = find_hover_orbit(base) if orbit is None else orbit
    mu0 = float(np.abs(hover_stability(orbit).multipliers[0]))
    r1_follows = preset.values["r1"].status == "estimate"
    bars = []
    for f in fields:
        src = ranged[f]
        assert src.low is not None and src.high is not None
        ends = []
        for value in (src.low, src.high):
            changes = {f: value}
            if f == "r2" and r1_follows:
                changes["r1"] = ellington_r1(value)
            ends.append(_leading_multiplier(base.with_(**changes), orbit))
        note = "; ".join(f"{which}: {why}" for which, (_, why) in zip(("low", "high"), ends,
                                                                    strict=True) if why)
        bars.append(SensitivityBar(name, f, src.status, src.low, src.value, src.high,
                                   ends[0][0], mu0, ends[1][0], note))
    return sorted(bars, key=lambda b: -b.spread)

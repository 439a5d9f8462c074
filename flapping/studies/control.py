"""What would make hover stable: the hinge above the centre of gravity, and feedback per wingbeat.

Two routes to a stable hover orbit:

*Passive.* The wing hinge a height h_w above the centre of gravity (``Insect.hinge_height``) puts
the horizontal wing forces on a pendulum arm: a forward speed u makes a backward drag above the
CG, a nose-up moment (M_u grows by -h_w m X_u / I_y), the "pendulum stability" of Ristroph et al.
(2013) and Ducci et al. (2021). :func:`passive_sweep` follows the hover orbit and its Floquet
multipliers as h_w grows (warm-started, each orbit checked to be the symmetric hover orbit), and
:func:`locate_passive_crossing` finds where the largest multiplier modulus crosses 1 (brentq on
``max |mu| - 1``) and how: a real multiplier through +1 or -1, or a complex pair. A second,
independent location solves the defining condition of that crossing (det(I - M) = 0 for +1,
det(I + M) = 0 for -1, ``|mu|^2 - 1`` of the pair otherwise). The orbits are solved with both
trims (Phi and phi_bar): see :func:`hover_multipliers` for why.

*Feedback once per wingbeat.* The controller reads the state at the start of wingbeat k and sets
the mean stroke angle phi_bar (the hawkmoth's pitch control, Cheng et al. 2011) for wingbeat
k + d. Linearised about the hover orbit, the stroboscopic map is x_{k+1} = M x_k + B u_k, with M
the monodromy matrix and B = dx(T)/dphi_bar from the variational equations
(:func:`linear_wingbeat_map`); with u_k = K x_{k-d} the closed loop acts on the stacked state
(x_k, ..., x_{k-d}) of dimension 4(d + 1) (:func:`closed_loop_matrix`), stable iff its spectral
radius is below 1. :func:`gain_region` maps the spectral radius over the plane of the pitch-rate
and pitch-angle gains, :func:`delay_limit` the largest delay some gain still stabilises, and
:func:`simulate_feedback` runs the full nonlinear model with phi_bar updated every wingbeat.

Modelling limits: quasi-steady loads, massless wings, longitudinal motion only (as the rest of
the package).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy import optimize
from scipy.integrate import solve_ivp

from flapping import _validation
from flapping.backends import AUTO, Backend, as_backend
from flapping.errors import ConvergenceError, HoverDriftWarning
from flapping.hover import (
    ANALYSIS_ATOL,
    ANALYSIS_RTOL,
    DEFAULT_BACKEND,
    HoverOrbit,
    HoverProblem,
    find_hover_orbit,
)
from flapping.hover.problem import choose_backend
from flapping.hover.stability import hover_stability
from flapping.model.dynamics import LongitudinalDynamics
from flapping.model.kinematics import segment_stroke_sign
from flapping.model.morphology import Insect
from flapping.model.presets import BODY_SIZES
from flapping.periodic.integrate import variational_flow
from flapping.studies._path import Guess, WarmStart, follow

__all__ = [
    "BODY_LENGTHS",
    "BODY_DIAMETERS",
    "SPEED_PITCH",
    "PITCH_RATE_ANGLE",
    "PassiveSweep",
    "PassiveCrossing",
    "hover_multipliers",
    "passive_sweep",
    "locate_passive_crossing",
    "closest_approach",
    "stable_window",
    "PassiveMap",
    "passive_map",
    "WingbeatMap",
    "linear_wingbeat_map",
    "closed_loop_matrix",
    "spectral_radius",
    "GainRegion",
    "gain_region",
    "optimal_gains",
    "smallest_stabilising_gains",
    "delay_limit",
    "FeedbackSimulation",
    "simulate_feedback",
]

#: Body lengths [m] behind the presets' pitch-inertia estimates (:data:`flapping.model.presets.
#: BODY_SIZES`): the hinge heights studied run from 0 to half (and up to one) body length.
BODY_LENGTHS: dict[str, float] = {name: size[0] for name, size in BODY_SIZES.items()}

#: Body diameters [m] behind the same estimates: anatomy's scale for a hinge height, since the
#: wing base lies within the thorax, less than one diameter above the CG.
BODY_DIAMETERS: dict[str, float] = {name: size[1] for name, size in BODY_SIZES.items()}

#: Gains act on (u, w, q, theta). The default pair feeds back the forward speed u and the pitch
#: angle theta: the pair that stabilises the hawkmoth with the longest delay (the pitch-only pair
#: (q, theta) = (2, 3) stabilises it barely, without delay only).
SPEED_PITCH = (0, 3)
#: The pitch-rate and pitch-angle pair.
PITCH_RATE_ANGLE = (2, 3)

#: Caps on the work an argument can ask for (each is far above the book's use): the delay in
#: wingbeats (the closed loop is 4(d+1) square: eigenvalues cost (4(d+1))^3), the points of a
#: gain grid (one eigenvalue problem each), the hover solves of a passive sweep or map, the
#: wingbeats of a simulation (one nonlinear integration each) and the directions of a ray search.
MAX_DELAY = 100
MAX_GAIN_POINTS = 1_000_000
MAX_HOVER_SOLVES = 10_000
MAX_WINGBEATS = 100_000
MAX_ANGLES = 100_000

_STATE_NAMES = ("u", "w", "q", "theta")


def _states(states: Any) -> tuple[int, int]:
    """``states`` as two different indices into (u, w, q, theta), or a ValueError naming it."""
    expected = "two different indices into (u, w, q, theta), integers in [0, 3]"
    try:
        pair = tuple(states)
    except TypeError:
        raise ValueError(f"`states` must be {expected}; got {states!r}") from None
    ok = len(pair) == 2 and all(
        isinstance(i, (int, np.integer)) and not isinstance(i, (bool, np.bool_))
        and 0 <= i <= 3 for i in pair) and pair[0] != pair[1]
    if not ok:
        raise ValueError(f"`states` must be {expected}; got {states!r}")
    return int(pair[0]), int(pair[1])


def _delay(delay: Any, name: str = "delay") -> int:
    """A delay in wingbeats, an integer in [0, MAX_DELAY]."""
    return _validation.integer(name, delay, low=0, high=MAX_DELAY)


def _margin(margin: Any) -> float:
    """A stability margin in [0, 1): the radius sought is 1 - margin > 0."""
    return _validation.real("margin", margin, low=0.0, high=1.0, high_open=True)


def _pair(name: str, value: Any) -> np.ndarray:
    """Two gains as a float64 array of shape (2,)."""
    return _validation.vector(name, value, size=2)


# =========================================================================== passive stability
def hover_multipliers(insect: Insect, *, guess: HoverOrbit | None = None,
                      backend: Backend | str = DEFAULT_BACKEND
                      ) -> tuple[HoverOrbit, np.ndarray]:
    """The hover orbit of ``insect`` and its Floquet multipliers (sorted by modulus, descending).

    The orbit is solved with both trims, Phi and phi_bar (:func:`~flapping.hover.find_hover_orbit`
    with ``trims=("amplitude", "stroke_mean")``). Where a real multiplier of the symmetric orbit
    passes +1 the one-trim hover problem is singular (the symmetry-breaking mode, which flies
    forwards or backwards, costs no altitude), and past it that solve may land on a drifting
    orbit; the horizontal equation of the two-trim problem removes both.

    Where the compiled kernel applies to the one-trim problem (no hinge offset, so phi_bar = 0 by
    symmetry; ``backend`` ``"auto"`` or ``"compiled"``), its solve is tried first (~1 ms); it is
    kept if it converges to a hover orbit, else the two-trim solve runs (on the path
    :func:`~flapping.hover.problem.choose_backend` gives it: the adaptive one).

    Parameters
    ----------
    insect : Insect
    guess : HoverOrbit, optional
        A nearby orbit: its amplitude, mean stroke angle and initial state start the solve.
    backend : "auto", "compiled", "adaptive", or a backend object
        :mod:`flapping.backends`; ``"adaptive"``: the two-trim adaptive solve only.

    Returns
    -------
    orbit : HoverOrbit
    multipliers : ndarray, shape (4,), complex

    Raises
    ------
    ValueError
        If ``insect`` is not an Insect, ``guess`` not a HoverOrbit, or ``backend`` unknown.
    ConvergenceError
        If the solve fails, or lands on an orbit that is not hover (past a symmetry-breaking
        bifurcation the solver can find drifting orbits beside the symmetric one).
    """
    _validation.instance("insect", insect, Insect)
    kwargs: dict[str, Any] = {}
    if guess is not None:
        _validation.instance("guess", guess, HoverOrbit)
        kwargs = {"amplitude_guess": guess.amplitude, "x0_guess": guess.x0}
    spec = as_backend(backend)
    # A path that solves one trim only (the kernel) solves the centred insect's one-trim
    # problem, whose orbit is the two-trim one (phi_bar = 0 by symmetry).
    if insect.hinge_offset == 0.0:
        one_trim = HoverProblem(insect.with_(stroke_mean=0.0))
        path = choose_backend(one_trim, spec)
        if path.one_trim_only:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", HoverDriftWarning)
                try:
                    fast = find_hover_orbit(one_trim, backend=path, **kwargs)
                except ConvergenceError:  # near a +1 multiplier the one-trim problem is singular
                    fast = None
            if fast is not None and fast.is_hover and fast.kernel is not None:
                mu = np.asarray(fast.kernel.multipliers)
                return fast, mu[np.argsort(-np.abs(mu), kind="stable")]
    if guess is not None:
        insect = insect.with_(stroke_mean=guess.stroke_mean)
    two_trims = HoverProblem(insect, trims=("amplitude", "stroke_mean"))
    one_trim_only = not isinstance(spec, str) and spec.one_trim_only
    orbit = find_hover_orbit(two_trims, backend=AUTO if one_trim_only else spec, **kwargs)
    if not orbit.is_hover:
        raise ConvergenceError(
            f"the orbit found for {insect.name} at h_w = {insect.hinge_height:g} m flies at "
            f"{orbit.mean_horizontal_speed:.3g} m/s: not the hover orbit", x=orbit.x0)
    mu = hover_stability(orbit).multipliers
    return orbit, np.asarray(mu)[np.argsort(-np.abs(mu), kind="stable")]


@dataclass(frozen=True)
class PassiveSweep:
    """The hover orbit's multipliers over hinge heights (result of :func:`passive_sweep`).

    Attributes
    ----------
    insect : Insect
        The insect at h_w = 0 (each point is ``insect.with_(hinge_height=h)``).
    hinge_heights : ndarray, shape (n,)
        h_w [m].
    amplitudes : ndarray, shape (n,)
        Hover stroke amplitude Phi [rad].
    multipliers : ndarray, shape (n, 4), complex
        Floquet multipliers per point, by modulus (descending).
    orbits : tuple of HoverOrbit
    backend : "auto" or a backend object
        The backend of the sweep, used again by the functions that refine it.
    """

    insect: Insect
    hinge_heights: np.ndarray
    amplitudes: np.ndarray
    multipliers: np.ndarray
    orbits: tuple[HoverOrbit, ...]
    backend: Backend | str = DEFAULT_BACKEND

    @property
    def max_modulus(self) -> np.ndarray:
        """Largest multiplier modulus at each hinge height (< 1: stable)."""
        return np.abs(self.multipliers).max(axis=1)

    def brackets(self) -> list[tuple[int, int]]:
        """Index pairs (i, i + 1) between which ``max |mu| - 1`` changes sign."""
        s = np.sign(self.max_modulus - 1.0)
        return [(i, i + 1) for i in range(len(s) - 1) if s[i] * s[i + 1] < 0]


def passive_sweep(insect: Insect, hinge_heights: Any, *,
                  backend: Backend | str = DEFAULT_BACKEND) -> PassiveSweep:
    """Hover orbit and multipliers at each hinge height, each solve warm-started from the last.

    Parameters
    ----------
    insect : Insect
    hinge_heights : array_like
        Increasing hinge heights h_w [m] (e.g. 0 to half a body length).
    backend : "auto", "compiled", "adaptive", or a backend object
        As for :func:`hover_multipliers`.

    Returns
    -------
    PassiveSweep

    Raises
    ------
    ValueError
        If hinge_heights is not finite, increasing and at most MAX_HOVER_SOLVES long, or
        ``insect`` or ``backend`` is bad.
    ConvergenceError
        If a point has no hover orbit (see :func:`hover_multipliers`).
    """
    _validation.instance("insect", insect, Insect)
    h = _hinge_heights(hinge_heights)
    backend = as_backend(backend)

    def solve(member: Insect, guess: Guess[tuple[HoverOrbit, np.ndarray]] | None
              ) -> tuple[HoverOrbit, np.ndarray]:
        return hover_multipliers(member, guess=None if guess is None else guess.previous[0],
                                 backend=backend)

    path = ((float(value), insect.with_(hinge_height=float(value))) for value in h)
    results = [step.result for step in follow(path, WarmStart(solve))
               if step.result is not None]
    orbits = [orbit for orbit, _ in results]
    return PassiveSweep(insect, h, np.array([o.amplitude for o in orbits]),
                        np.array([mu for _, mu in results]), tuple(orbits), backend)


def _hinge_heights(hinge_heights: Any, solves: int = 1) -> np.ndarray:
    """Increasing hinge heights [m], 1-D, with at most MAX_HOVER_SOLVES solves in all."""
    h = _validation.array("hinge_heights", hinge_heights)
    if h.ndim != 1 or h.size < 1 or np.any(np.diff(h) <= 0):
        raise ValueError("`hinge_heights` must be a non-empty increasing 1-d array [m]; got "
                         f"shape {h.shape}")
    if h.size * solves > MAX_HOVER_SOLVES:
        raise ValueError(f"`hinge_heights` asks for {h.size * solves} hover solves; at most "
                         f"{MAX_HOVER_SOLVES} are allowed")
    return h


def closest_approach(sweep: PassiveSweep) -> tuple[float, np.ndarray]:
    """The hinge height where ``max |mu|`` is smallest, refined between the sweep's neighbours.

    Where no crossing exists this is how near the unit circle the hinge height brings the
    multipliers (often where two real multipliers collide and leave the real axis as a pair).

    Parameters
    ----------
    sweep : PassiveSweep

    Returns
    -------
    hinge_height : float
        h_w [m] (bounded Brent search, xatol 1e-7 m).
    multipliers : ndarray, complex
        The multipliers there, by modulus.

    Raises
    ------
    ValueError
        If ``sweep`` is not a PassiveSweep.
    """
    _validation.instance("sweep", sweep, PassiveSweep)
    h, m = sweep.hinge_heights, sweep.max_modulus
    i = int(np.argmin(m))
    lo, hi = float(h[max(i - 1, 0)]), float(h[min(i + 1, len(h) - 1)])
    if lo == hi:
        return lo, sweep.multipliers[i]
    guess = sweep.orbits[max(i - 1, 0)]

    def at(value: float) -> np.ndarray:
        return hover_multipliers(sweep.insect.with_(hinge_height=value), guess=guess,
                                 backend=sweep.backend)[1]

    best = optimize.minimize_scalar(lambda v: float(np.abs(at(v)).max()), bounds=(lo, hi),
                                    method="bounded", options={"xatol": 1e-7})
    return float(best.x), at(float(best.x))


@dataclass(frozen=True)
class PassiveCrossing:
    """Where the largest multiplier crosses the unit circle (:func:`locate_passive_crossing`).

    Attributes
    ----------
    hinge_height : float
        h_w [m] where ``max |mu| = 1`` (brentq, xtol 1e-10 m).
    kind : str
        ``"+1"``, ``"-1"`` (a real multiplier through +1 or -1) or ``"complex pair"``
        (``"none"``: an end of the sweep's range inside a stable window, no crossing).
    multipliers : ndarray, complex
        The multipliers there, by modulus.
    stabilising : bool
        True if hover is stable above ``hinge_height`` (``max |mu|`` falls through 1).
    check_height : float
        The same crossing from its defining condition (second route, on two-trim orbits of the
        adaptive integrator whatever the sweep's backend): det(I - M) = 0 for +1,
        det(I + M) = 0 for -1, ``|mu|^2 - 1`` of the pair for a complex pair.
    """

    hinge_height: float
    kind: str
    multipliers: np.ndarray
    stabilising: bool
    check_height: float


def locate_passive_crossing(sweep: PassiveSweep, bracket: tuple[int, int], *,
                            check: bool = True) -> PassiveCrossing:
    """Locate the crossing of ``max |mu| = 1`` between two points of a :class:`PassiveSweep`.

    Parameters
    ----------
    sweep : PassiveSweep
    bracket : (int, int)
        Indices from :meth:`PassiveSweep.brackets`.
    check : bool
        Also locate the crossing by the second route (``check_height``; NaN if False).

    Returns
    -------
    PassiveCrossing

    Raises
    ------
    ValueError
        If ``sweep`` is not a PassiveSweep, ``bracket`` not two increasing indices into it, or
        it does not bracket a crossing.
    """
    _validation.instance("sweep", sweep, PassiveSweep)
    i, j = _bracket(bracket, len(sweep.hinge_heights))
    check = _validation.boolean("check", check)
    if (sweep.max_modulus[i] - 1.0) * (sweep.max_modulus[j] - 1.0) >= 0:
        raise ValueError(f"`bracket` {bracket} does not bracket max |mu| = 1")
    return _locate(sweep, float(sweep.hinge_heights[i]), float(sweep.hinge_heights[j]),
                   sweep.orbits[i], bool(sweep.max_modulus[j] < 1.0), check)


def _bracket(bracket: Any, n: int) -> tuple[int, int]:
    """Two indices i < j into a sweep of ``n`` points."""
    expected = f"two indices (i, j) with 0 <= i < j <= {n - 1}"
    try:
        i, j = bracket
        i = _validation.integer("bracket[0]", i, low=0, high=n - 1)
        j = _validation.integer("bracket[1]", j, low=0, high=n - 1)
    except (TypeError, ValueError):
        raise ValueError(f"`bracket` must be {expected}; got {bracket!r}") from None
    if i >= j:
        raise ValueError(f"`bracket` must be {expected}; got {bracket!r}")
    return i, j


def _locate(sweep: PassiveSweep, lo: float, hi: float, guess: HoverOrbit,
            stabilising: bool, check: bool) -> PassiveCrossing:
    """brentq on max ``|mu|`` - 1 in [lo, hi] (the sweep's backend), classified, and checked on
    its defining condition (two-trim adaptive solves)."""

    def at(h: float, backend: Backend | str = sweep.backend) -> np.ndarray:
        return hover_multipliers(sweep.insect.with_(hinge_height=h), guess=guess,
                                 backend=backend)[1]

    root = optimize.brentq(lambda h: float(np.abs(at(h)).max()) - 1.0, lo, hi, xtol=1e-10)
    mu = at(root)
    on_circle = mu[np.abs(np.abs(mu) - 1.0) < 1e-6]
    kind = ("complex pair" if np.any(np.abs(on_circle.imag) > 1e-8)
            else "+1" if mu[0].real > 0 else "-1")

    def condition(h: float) -> float:
        m = at(h, "adaptive")
        if kind == "complex pair":
            return float(abs(m[0]) ** 2 - 1.0)
        target = 1.0 if kind == "+1" else -1.0
        return float(np.real(np.prod(target - m)))  # det(target I - M)

    second = optimize.brentq(condition, lo, hi, xtol=1e-10) if check else math.nan
    return PassiveCrossing(root, kind, mu, stabilising, second)


def stable_window(sweep: PassiveSweep, *,
                  check: bool = True) -> tuple[PassiveCrossing, PassiveCrossing] | None:
    """The interval of hinge heights with stable hover around the sweep's closest approach.

    A window narrower than the sweep's spacing (two crossings between neighbouring points) is
    found too: :func:`closest_approach` refines the minimum of ``max |mu|``, and if it is below 1
    the crossings on either side are located (:func:`locate_passive_crossing`'s two routes).

    Parameters
    ----------
    sweep : PassiveSweep
    check : bool
        Also locate each crossing by the second route (see :class:`PassiveCrossing`).

    Returns
    -------
    (entry, exit) : (PassiveCrossing, PassiveCrossing) or None
        None if ``max |mu|`` stays above 1; ``exit`` is the last point of the sweep's range
        (with ``kind`` ``"none"``) if hover is still stable there.

    Raises
    ------
    ValueError
        If ``sweep`` is not a PassiveSweep or ``check`` not a bool.
    """
    _validation.instance("sweep", sweep, PassiveSweep)
    check = _validation.boolean("check", check)
    h_min, mu_min = closest_approach(sweep)
    if np.abs(mu_min).max() >= 1.0:
        return None
    m, h = sweep.max_modulus, sweep.hinge_heights
    below = np.flatnonzero(h <= h_min)
    above = np.flatnonzero(h > h_min)
    lo = int(below[-1]) if below.size else 0
    while lo > 0 and m[lo] < 1.0:
        lo -= 1
    guess = sweep.orbits[lo]
    entry = (_locate(sweep, float(h[lo]), h_min, guess, True, check) if m[lo] > 1.0
             else PassiveCrossing(float(h[0]), "none", sweep.multipliers[0], True, float(h[0])))
    hi = int(above[0]) if above.size else len(h) - 1
    while hi < len(h) - 1 and m[hi] < 1.0:
        hi += 1
    if m[hi] < 1.0:
        last = PassiveCrossing(float(h[hi]), "none", sweep.multipliers[hi], False, float(h[hi]))
        return entry, last
    return entry, _locate(sweep, h_min, float(h[hi]), guess, False, check)


@dataclass(frozen=True)
class PassiveMap:
    """Largest multiplier modulus over hinge height x centre of pressure (:func:`passive_map`).

    Attributes
    ----------
    insect : Insect
    hinge_heights : ndarray, shape (n,)
        h_w [m].
    centers_of_pressure : ndarray, shape (m,)
        x_hat (fraction of the chord behind the pitch axis).
    max_modulus : ndarray, shape (m, n)
        ``max |mu|`` of the hover orbit, one row per centre of pressure (< 1: stable).
    drift : ndarray, shape (m, n)
        Mean horizontal speed of each orbit [m/s] (every orbit is checked to be hover).
    """

    insect: Insect
    hinge_heights: np.ndarray
    centers_of_pressure: np.ndarray
    max_modulus: np.ndarray
    drift: np.ndarray

    def boundary(self) -> np.ndarray:
        """Entry and exit of the first stable window in each row, shape (m, 2) [m].

        Linear interpolation of ``max |mu| - 1`` between the grid's neighbours (accurate to
        the grid spacing); NaN where a row has no such crossing.
        """
        out = np.full((len(self.centers_of_pressure), 2), np.nan)
        h = self.hinge_heights
        for row, m in enumerate(self.max_modulus - 1.0):
            flips = np.flatnonzero(m[:-1] * m[1:] < 0)
            entries = flips[m[flips] > 0]
            for col, i in enumerate(entries[:1].tolist()
                                    + flips[flips > entries[0]][:1].tolist()
                                    if entries.size else []):
                out[row, col] = h[i] + (h[i + 1] - h[i]) * m[i] / (m[i] - m[i + 1])
        return out


def passive_map(insect: Insect, hinge_heights: Any, centers_of_pressure: Any, *,
                backend: Backend | str = DEFAULT_BACKEND) -> PassiveMap:
    """``max |mu|`` of the hover orbit on a grid of hinge heights and centres of pressure.

    Each row is a :func:`passive_sweep` in h_w (warm-started; the kernel's one-trim orbits are
    kept only if they are hover, else the two-trim adaptive solve runs), so every point is a
    true hover orbit: a plain one-trim grid sweep can land on an orbit that drifts at metres per
    second inside the window, where the one-trim problem is singular.

    Parameters
    ----------
    insect : Insect
    hinge_heights : array_like
        Increasing h_w [m].
    centers_of_pressure : array_like
        x_hat values in [0, 1].
    backend : "auto", "compiled", "adaptive", or a backend object
        As for :func:`hover_multipliers`.

    Returns
    -------
    PassiveMap

    Raises
    ------
    ValueError
        For a bad grid (or one of more than MAX_HOVER_SOLVES points), insect or backend.
    ConvergenceError
        If a point has no hover orbit.
    """
    _validation.instance("insect", insect, Insect)
    x = _validation.array("centers_of_pressure", centers_of_pressure)
    if x.ndim != 1 or x.size < 1 or np.any((x < 0) | (x > 1)):
        raise ValueError("`centers_of_pressure` must be a non-empty 1-d array in [0, 1]; got "
                         f"{x!r}")
    _hinge_heights(hinge_heights, solves=x.size)
    backend = as_backend(backend)
    rows = [passive_sweep(insect.with_(center_of_pressure=float(v)), hinge_heights,
                          backend=backend) for v in x]
    return PassiveMap(insect, rows[0].hinge_heights, x,
                      np.array([r.max_modulus for r in rows]),
                      np.array([[o.mean_horizontal_speed for o in r.orbits] for r in rows]))


# =========================================================================== feedback
@dataclass(frozen=True)
class WingbeatMap:
    """The linearised one-wingbeat map x_{k+1} = M x_k + B u_k about a hover orbit.

    Attributes
    ----------
    orbit : HoverOrbit
    M : ndarray, shape (4, 4)
        Monodromy matrix.
    B : ndarray, shape (4, 1)
        dx(T)/dphi_bar [SI per rad]: the end-of-wingbeat state's sensitivity to a mean stroke
        angle offset held over the wingbeat.
    """

    orbit: HoverOrbit
    M: np.ndarray
    B: np.ndarray

    def __post_init__(self) -> None:
        _validation.instance("orbit", self.orbit, HoverOrbit)
        M, B = _system(self.M, self.B)
        object.__setattr__(self, "M", M)
        object.__setattr__(self, "B", B)


def linear_wingbeat_map(orbit: HoverOrbit, *, rtol: float = ANALYSIS_RTOL,
                        atol: float = ANALYSIS_ATOL) -> WingbeatMap:
    """M and B = dx(T)/dphi_bar of a hover orbit, from the variational equations.

    Parameters
    ----------
    orbit : HoverOrbit
    rtol, atol : float
        Integration tolerances.

    Returns
    -------
    WingbeatMap

    Raises
    ------
    ValueError
        If ``orbit`` is not a HoverOrbit or a tolerance is not positive.
    ConvergenceError
        If the variational integration fails.
    """
    _validation.instance("orbit", orbit, HoverOrbit)
    rtol, atol = _validation.tolerances(rtol, atol)
    model = orbit.model
    segments = range(len(model.breakpoints) + 1)
    signs = [segment_stroke_sign(k) for k in segments]
    phi_bar = model.insect.stroke_mean

    def at(p: np.ndarray) -> LongitudinalDynamics:
        return model if p[0] == phi_bar else model.with_stroke_mean(float(p[0]))

    var = variational_flow(
        [lambda t, x, p, _s=s: at(p).unchecked.rhs(t, x, _s) for s in signs],
        [lambda t, x, p, _s=s: at(p).unchecked.jac(t, x, _s) for s in signs],
        (0.0, orbit.period), orbit.x0, breakpoints=model.breakpoints, period=orbit.period,
        rtol=rtol, atol=atol, params=np.array([phi_bar]),
        param_jac=[lambda t, x, p, _s=s: at(p).unchecked.stroke_mean_jac(t, x, _s)
                   for s in signs])
    if not var.success or var.sensitivity is None:
        raise ConvergenceError(f"the variational integration failed: {var.message}")
    return WingbeatMap(orbit, var.stm[:, :, -1].copy(), var.sensitivity[:, :, -1].copy())


def closed_loop_matrix(M: Any, B: Any, K: Any, delay: int) -> np.ndarray:
    """The closed-loop map of (x_k, ..., x_{k-d}) with u_k = K x_{k-d}: shape 4(d+1) square.

    x_{k+1} = M x_k + B K x_{k-d}; the other blocks shift the history.

    Parameters
    ----------
    M : array_like, shape (n, n)
    B : array_like, shape (n, m)
    K : array_like, shape (m, n) or (n,) for one input
    delay : int
        d >= 0 wingbeats.

    Returns
    -------
    numpy.ndarray, shape (n (d+1), n (d+1))

    Raises
    ------
    ValueError
        If M is not square, B not (n, m) or (n,), K not (m, n) (or (n,) for one input), an
        entry is not finite, or the delay is not an integer in [0, MAX_DELAY].
    """
    M, B = _system(M, B)
    return _closed_loop(M, B, _gain_matrix(K, B.shape[1], M.shape[0]), _delay(delay))


def _system(M: Any, B: Any) -> tuple[np.ndarray, np.ndarray]:
    """M as a finite (n, n) float64 array and B as a finite (n, m) one ((n,) becomes (n, 1))."""
    M = _validation.array("M", M)
    if M.ndim != 2 or M.shape[0] != M.shape[1] or M.size == 0:
        raise ValueError(f"`M` must be a square 2-d array of shape (n, n); got shape {M.shape}")
    n = M.shape[0]
    B = _validation.array("B", B)
    B = B.reshape(n, 1) if B.shape == (n,) else B
    if B.ndim != 2 or B.shape[0] != n or B.shape[1] == 0:
        raise ValueError(f"`B` must have shape ({n}, m) or ({n},), as M is {M.shape}; got shape "
                         f"{B.shape}")
    return M, B


def _gain_matrix(K: Any, m: int, n: int) -> np.ndarray:
    """K as a finite (m, n) float64 array; (n,) is accepted for one input (m = 1)."""
    K = _validation.array("K", K)
    if K.shape == (n,) and m == 1:
        K = K.reshape(1, n)
    if K.shape != (m, n):
        one = f" or ({n},)" if m == 1 else ""
        raise ValueError(f"`K` must have shape ({m}, {n}){one} for B of {m} input(s) and M of "
                         f"{n} states; got shape {K.shape}")
    return K


def _closed_loop(M: np.ndarray, B: np.ndarray, K: np.ndarray, d: int) -> np.ndarray:
    """:func:`closed_loop_matrix` of checked arguments (K of shape (m, n) or (n,))."""
    K = K.reshape(B.shape[1], M.shape[0])
    n = M.shape[0]
    A = np.zeros((n * (d + 1), n * (d + 1)))
    A[:n, :n] = M
    A[:n, n * d:] += B @ K
    for k in range(d):
        A[n * (k + 1):n * (k + 2), n * k:n * (k + 1)] = np.eye(n)
    return A


def spectral_radius(M: Any, B: Any, K: Any, delay: int) -> float:
    """Largest eigenvalue modulus of :func:`closed_loop_matrix` (< 1: the loop is stable).

    Raises
    ------
    ValueError
        For the arguments :func:`closed_loop_matrix` refuses.
    """
    return _radius(closed_loop_matrix(M, B, K, delay))


def _radius(A: np.ndarray) -> float:
    return float(np.abs(np.linalg.eigvals(A)).max())


def _rho(wmap: WingbeatMap, gains: Any, states: tuple[int, ...], d: int) -> float:
    """Spectral radius with two gains on ``states`` (checked arguments)."""
    return _radius(_closed_loop(wmap.M, wmap.B, _gain_row(gains, states), d))


def _gain_row(gains: Any, states: tuple[int, ...], n: int = 4) -> np.ndarray:
    """Full gain row on (u, w, q, theta) from the gains on ``states``."""
    K = np.zeros(n)
    K[list(states)] = gains
    return K


@dataclass(frozen=True)
class GainRegion:
    """Spectral radius over a plane of two gains (result of :func:`gain_region`).

    Attributes
    ----------
    k1 : ndarray, shape (a,)
        Gains on ``states[0]`` [rad of phi_bar per SI unit of that state].
    k2 : ndarray, shape (b,)
        Gains on ``states[1]``.
    radius : ndarray, shape (b, a)
        Spectral radius of the closed loop, ``radius[i, j]`` at (k1[j], k2[i]).
    delay : int
    states : (int, int)
        Indices into (u, w, q, theta) of the two gains.
    """

    k1: np.ndarray
    k2: np.ndarray
    radius: np.ndarray
    delay: int
    states: tuple[int, ...]

    @property
    def stable_fraction(self) -> float:
        """Fraction of the grid where the loop is stable."""
        return float(np.mean(self.radius < 1.0))


def gain_region(wmap: WingbeatMap, k1: Any, k2: Any, delay: int,
                states: tuple[int, ...] = SPEED_PITCH) -> GainRegion:
    """The closed loop's spectral radius on a grid of two gains.

    Parameters
    ----------
    wmap : WingbeatMap
    k1, k2 : array_like
        Gain grids on ``states[0]`` and ``states[1]``.
    delay : int
        d >= 0 wingbeats.
    states : (int, int)
        Which states of (u, w, q, theta) are fed back (default u and theta).

    Returns
    -------
    GainRegion

    Raises
    ------
    ValueError
        If ``wmap`` is not a WingbeatMap, a grid is empty, not finite or beyond
        MAX_GAIN_POINTS points in all, the delay not an integer in [0, MAX_DELAY], or ``states``
        not two different indices in [0, 3].
    """
    _validation.instance("wmap", wmap, WingbeatMap)
    a1, a2 = _validation.vector("k1", k1), _validation.vector("k2", k2)
    if a1.size * a2.size > MAX_GAIN_POINTS:
        raise ValueError(f"`k1` and `k2` make a grid of {a1.size * a2.size} points; at most "
                         f"{MAX_GAIN_POINTS} are allowed")
    d, pair = _delay(delay), _states(states)
    radius = np.array([[_rho(wmap, (a, b), pair, d) for a in a1] for b in a2])
    return GainRegion(a1, a2, radius, d, pair)


def optimal_gains(wmap: WingbeatMap, delay: int, *, start: Any = (0.0, 0.0),
                  objective: str = "radius", margin: float = 0.02,
                  states: tuple[int, ...] = SPEED_PITCH) -> tuple[np.ndarray, float]:
    """Two gains minimising the spectral radius, or the smallest-norm stabilising ones.

    Parameters
    ----------
    wmap : WingbeatMap
    delay : int
    start : (float, float)
        Starting gains.
    objective : {"radius", "norm"}
        ``"radius"``: minimise the spectral radius (Nelder-Mead). ``"norm"``: minimise the gain
        norm (in the states' SI units: mixed, rad per m/s and rad per rad) subject to
        radius <= 1 - margin (SLSQP from ``start``, which must be stabilising; if SLSQP ends
        infeasible, ``start`` is returned).
    margin : float
        Stability margin of the ``"norm"`` objective.
    states : (int, int)
        Which states of (u, w, q, theta) are fed back.

    Returns
    -------
    gains : ndarray, shape (2,)
    radius : float
        The spectral radius at ``gains``.

    Raises
    ------
    ValueError
        If ``wmap`` is not a WingbeatMap, the delay not an integer in [0, MAX_DELAY], ``start``
        not two finite gains, ``objective`` unknown, ``margin`` not in [0, 1), or ``states``
        not two different indices in [0, 3].
    """
    _validation.instance("wmap", wmap, WingbeatMap)
    d, pair = _delay(delay), _states(states)
    x0 = _pair("start", start)
    objective = _validation.choice("objective", objective, ("radius", "norm"))
    margin = _margin(margin)
    return _optimal_gains(wmap, d, x0, objective, margin, pair)


def _optimal_gains(wmap: WingbeatMap, delay: int, x0: np.ndarray, objective: str,
                   margin: float, states: tuple[int, ...]) -> tuple[np.ndarray, float]:
    """:func:`optimal_gains` of checked arguments."""

    def rho(g: np.ndarray) -> float:
        return _rho(wmap, g, states, delay)

    if objective == "radius":
        res = optimize.minimize(rho, x0, method="Nelder-Mead",
                                options={"xatol": 1e-8, "fatol": 1e-10, "maxiter": 4000})
    else:
        res = optimize.minimize(lambda g: float(g @ g), x0, method="SLSQP",
                                constraints=[{"type": "ineq",
                                              "fun": lambda g: 1.0 - margin - rho(g)}])
        if not rho(np.asarray(res.x)) <= 1.0 - margin + 1e-9:
            return x0, rho(x0)
    return np.asarray(res.x), rho(np.asarray(res.x))


def smallest_stabilising_gains(wmap: WingbeatMap, delay: int, r_max: float, *,
                               margin: float = 0.02, n_angles: int = 120,
                               states: tuple[int, ...] = SPEED_PITCH) -> tuple[np.ndarray, float]:
    """The smallest-norm gains with spectral radius 1 - margin, by a search along rays.

    Along each of ``n_angles`` directions of the gain plane the radius ``r`` (up to ``r_max``,
    200 samples) where the loop first reaches ``radius <= 1 - margin`` is bracketed and found by
    brentq; the best direction is refined on a grid 20 times finer about it. The norm is taken
    in the states' SI units (mixed: rad per m/s and rad per rad).

    Parameters
    ----------
    wmap : WingbeatMap
    delay : int
    r_max : float
        Largest gain norm searched.
    margin : float
        The required margin below 1.
    n_angles : int
        Directions of the coarse search.
    states : (int, int)
        Which states of (u, w, q, theta) are fed back.

    Returns
    -------
    gains : ndarray, shape (2,)
    radius : float
        The spectral radius at ``gains`` (1 - margin to brentq's tolerance).

    Raises
    ------
    ValueError
        If no gains of norm <= r_max reach the margin; or for a bad argument: ``wmap`` not a
        WingbeatMap, the delay not an integer in [0, MAX_DELAY], ``r_max`` not positive,
        ``margin`` not in [0, 1), ``n_angles`` not an integer in [1, MAX_ANGLES], ``states``
        not two different indices in [0, 3].
    """
    _validation.instance("wmap", wmap, WingbeatMap)
    d, pair = _delay(delay), _states(states)
    r_max = _validation.positive("r_max", r_max)
    target = 1.0 - _margin(margin)
    n_angles = _validation.integer("n_angles", n_angles, low=1, high=MAX_ANGLES)
    radii = np.linspace(0.0, r_max, 201)[1:]

    def rho(g: np.ndarray) -> float:
        return _rho(wmap, g, pair, d)

    def first(angle: float) -> float:
        e = np.array([math.cos(angle), math.sin(angle)])
        values = np.array([rho(r * e) for r in radii]) - target
        hits = np.flatnonzero(values <= 0.0)
        if not hits.size:
            return math.inf
        i = int(hits[0])
        if i == 0:
            return float(radii[0])
        return float(optimize.brentq(lambda r: rho(r * e) - target, radii[i - 1], radii[i],
                                     xtol=1e-12))

    step = 2.0 * math.pi / n_angles
    coarse = [first(k * step) for k in range(n_angles)]
    k = int(np.argmin(coarse))
    if not math.isfinite(coarse[k]):
        raise ValueError(f"no gains of norm <= {r_max!r} give a spectral radius <= {target:g}")
    fine = np.linspace((k - 1) * step, (k + 1) * step, 41)
    r_fine = [first(a) for a in fine]
    j = int(np.argmin(r_fine))
    gains = r_fine[j] * np.array([math.cos(fine[j]), math.sin(fine[j])])
    return gains, rho(gains)


def delay_limit(wmap: WingbeatMap, max_delay: int = 8, start: Any = (0.0, 0.0),
                states: tuple[int, ...] = SPEED_PITCH) -> tuple[int, list[float]]:
    """The largest delay d (wingbeats) at which some pair of gains still stabilises hover.

    Parameters
    ----------
    wmap : WingbeatMap
    max_delay : int
        Delays 0 .. max_delay are tried.
    start : (float, float)
        Starting gains of the first minimisation (each next delay starts from the last optimum).
    states : (int, int)
        Which states of (u, w, q, theta) are fed back.

    Returns
    -------
    d_max : int
        The largest stabilisable delay (-1 if none).
    best : list of float
        The smallest spectral radius found at each delay.

    Raises
    ------
    ValueError
        If ``wmap`` is not a WingbeatMap, ``max_delay`` not an integer in [0, MAX_DELAY],
        ``start`` not two finite gains, or ``states`` not two different indices in [0, 3].
    """
    _validation.instance("wmap", wmap, WingbeatMap)
    max_delay, pair = _delay(max_delay, "max_delay"), _states(states)
    first = _pair("start", start)
    best, gains = [], first
    for d in range(max_delay + 1):
        candidates = [_optimal_gains(wmap, d, s, "radius", 0.02, pair)
                      for s in (gains, gains / 2, first)]
        gains, radius = min(candidates, key=lambda c: c[1])
        best.append(radius)
    stable = [d for d, r in enumerate(best) if r < 1.0]
    return (max(stable) if stable else -1), best


@dataclass(frozen=True)
class FeedbackSimulation:
    """A nonlinear closed-loop run (result of :func:`simulate_feedback`).

    Attributes
    ----------
    x : ndarray, shape (4, n + 1)
        State at the start of each wingbeat (wingbeat index along the last axis).
    deviation : ndarray, shape (n + 1,)
        Norm of the deviation from the orbit's x0, scaled per state by the orbit's range.
    u : ndarray, shape (n,)
        Mean stroke angle offset applied in each wingbeat [rad].
    decay_per_wingbeat : float
        exp of the least-squares slope of log(deviation) over the second half of the run.
    linear_deviation : ndarray, shape (n + 1,)
        The same deviation predicted by the linear closed loop (:func:`closed_loop_matrix`).
    linear_decay_per_wingbeat : float
        Its decay, fitted in the same way.
    """

    x: np.ndarray
    deviation: np.ndarray
    u: np.ndarray
    decay_per_wingbeat: float
    linear_deviation: np.ndarray
    linear_decay_per_wingbeat: float


def _one_wingbeat(model: LongitudinalDynamics, x: np.ndarray, period: float) -> np.ndarray:
    """The full model over one period from x (DOP853 per half-stroke, rtol 1e-11)."""
    edges = [0.0, *[b * period for b in model.breakpoints], period]
    for k in range(len(edges) - 1):
        s = segment_stroke_sign(k)
        sol = solve_ivp(lambda t, y, _s=s: model.unchecked.rhs(t, y, _s),
                        (edges[k], edges[k + 1]), x, method="DOP853", rtol=1e-11, atol=1e-13)
        x = sol.y[:, -1]
    return x


#: Smallest scaled norm of :func:`simulate_feedback`'s disturbance: the hover orbit closes to
#: ~1e-10 of its range (shooting's tolerance), so a smaller start would measure that error, and
#: a zero one has no decay at all (it returned a NaN rate). The book starts at 1e-3.
MIN_DISTURBANCE = 1e-9


def simulate_feedback(wmap: WingbeatMap, gains: Any, delay: int, disturbance: Any,
                      n_wingbeats: int = 20,
                      states: tuple[int, ...] = SPEED_PITCH) -> FeedbackSimulation:
    """Run the nonlinear model with phi_bar = phi_bar* + K (x_{k-d} - x*) set every wingbeat.

    Parameters
    ----------
    wmap : WingbeatMap
        The hover orbit (x* = ``orbit.x0``, phi_bar* its mean stroke angle) and its linear map.
    gains : array_like, shape (4,) or (2,)
        Full gain row on (u, w, q, theta), or the gains on ``states``; zeros: no control.
    delay : int
        d >= 0 wingbeats (the controller sees no deviation before wingbeat 0).
    disturbance : array_like, shape (4,)
        Added to x* at the start; its scaled norm (each state over its largest magnitude on the
        orbit) at least :data:`MIN_DISTURBANCE`.
    n_wingbeats : int
    states : (int, int)
        The states two gains act on.

    Returns
    -------
    FeedbackSimulation

    Raises
    ------
    ValueError
        If ``wmap`` is not a WingbeatMap, ``gains`` not 2 or 4 finite numbers, the delay not an
        integer in [0, MAX_DELAY], ``disturbance`` not 4 finite numbers (or below
        :data:`MIN_DISTURBANCE` in the scaled norm), ``n_wingbeats`` not an
        integer in [2, MAX_WINGBEATS], or ``states`` not two different indices in [0, 3].
    """
    _validation.instance("wmap", wmap, WingbeatMap)
    K = _validation.vector("gains", gains)
    if K.size not in (2, 4):
        raise ValueError(f"`gains` must have shape (2,) (on `states`) or (4,) (on u, w, q, "
                         f"theta); got shape {K.shape}")
    pair = _states(states)
    K = _gain_row(K, pair) if K.size == 2 else K
    d = _delay(delay)
    push = _validation.vector("disturbance", disturbance, size=4)
    n = _validation.integer("n_wingbeats", n_wingbeats, low=2, high=MAX_WINGBEATS)
    orbit = wmap.orbit
    model, x_star = orbit.model, orbit.x0
    phi_bar = model.insect.stroke_mean
    scale = np.abs(orbit.x).max(axis=1)
    size = float(np.linalg.norm(push / scale))
    if not size >= MIN_DISTURBANCE:  # a zero start has no decay to fit (log 0: a NaN rate)
        raise ValueError(f"`disturbance` must have a scaled norm in [{MIN_DISTURBANCE:g}, inf) "
                         f"(each state over its largest magnitude on the orbit); got {size:.3g}: "
                         "below it the run measures the orbit's own integration error")
    xs = [x_star + push]
    us = []
    for k in range(n):
        seen = xs[k - d] - x_star if k - d >= 0 else np.zeros(4)
        u = float(K @ seen)
        us.append(u)
        xs.append(_one_wingbeat(model.with_stroke_mean(phi_bar + u), xs[k], orbit.period))
    x = np.array(xs).T
    dev = np.linalg.norm((x - x_star[:, None]) / scale[:, None], axis=0)
    A = _closed_loop(wmap.M, wmap.B, K, d)
    stacked = np.zeros(A.shape[0])
    stacked[:4] = xs[0] - x_star
    lin = [stacked[:4]]
    for _ in range(n):
        stacked = A @ stacked
        lin.append(stacked[:4])
    lin_dev = np.linalg.norm(np.array(lin).T / scale[:, None], axis=0)
    return FeedbackSimulation(x, dev, np.array(us), _decay(dev), lin_dev, _decay(lin_dev))


def _decay(deviation: np.ndarray) -> float:
    """exp of the least-squares slope of log(deviation) over the second half of the run; 0 if
    the deviation reaches exactly zero there (a deadbeat loop: gone, not a NaN rate)."""
    n = len(deviation) - 1
    half = np.arange(n // 2, n + 1)
    if np.any(deviation[half] <= 0.0):
        return 0.0
    return float(math.exp(np.polyfit(half, np.log(deviation[half]), 1)[0]))

"""The verdict's uncertainty, globally: Sobol indices of the largest Floquet multiplier.

Replaces the one-at-a-time study of the atlas (:func:`~flapping.studies.atlas.
morphology_sensitivity`, each number at either end of its range, the others nominal) by a global
one: every uncertain input of a species varies at once over its range, uniformly and
independently; Saltelli's scheme (SALib: a scrambled Sobol' sequence; the first-order and
total estimators of Saltelli et al. 2010, Comput. Phys. Commun. 181:259) apportions the
variance of ln abs(mu_1) among them, and the same sample gives the probability that hover is
unstable and that its critical mode is oscillatory.

- :func:`sobol_indices` is the generic part: bounds, a vectorised function that may fail at some
  points, and the indices with bootstrap confidence intervals. The tests run it on Ishigami's
  function, whose indices are known in closed form.
- :func:`input_ranges` is the table of inputs and ranges per species (below, and
  :data:`RANGE_RULES`).
- :func:`global_sensitivity` runs the hover orbits of one species through the compiled sweep
  (:func:`~flapping.studies.sweep.sweep_hover`, ``backend="compiled"``) and returns a
  :class:`GlobalSensitivity`.
- :func:`reduction_check` solves a few of the same points in the full model the kernel lacks
  (two trims, wings of mass; the fixed-step path) and compares; :func:`nominal_reduction`
  splits the difference at the preset's hinge into its two terms.

**What the compiled kernel models, and so what this study is.** The kernel (eq. 29's loads, one
trim) has no mean stroke angle and no wing mass (:data:`flapping.fast.kernel.SUPPORTED_FIELDS`).
A hinge ahead of or behind the centre of gravity needs the mean stroke angle as a second trim to
hover (without it the orbit drifts: book appendix "robustness"), and that trim puts the mean
lift back over the centre of gravity. The study therefore solves the *reduced* model: the hinge's
height above the centre of gravity in stroke-plane axes, h', is kept, its fore-aft component x'
is taken as absorbed by the mean-stroke-angle trim, and the wings are massless.
:func:`reduction_check` measures what that drops, point by point, against the full model (both
trims, the hinge at (x', h'), the wings' mass); the book reports it beside the indices.

**Body angle.** Our stroke plane is the body x-y plane, horizontal at hover. A body angle
different from the sources' (the body pitched nose-up by delta with the stroke plane kept
horizontal) rotates the body-fixed hinge-to-CG vector (x_h, h_w) into stroke-plane axes:
x' = x_h cos(delta) - h_w sin(delta), h' = x_h sin(delta) + h_w cos(delta). That is all a body
angle does in this model (no body drag, the pitch inertia is about the centre of gravity).

**The inputs and their ranges** (uniform; SI inside, the table in :func:`input_ranges`):

==================  ==========================================================================
input               range, and why
==================  ==========================================================================
hinge_offset x_h    the preset's source hinge (:attr:`~flapping.model.presets.Preset.measured`)
                    +- w d, d its distance from the centre of gravity, w by status
                    (:data:`HINGE_HALF_WIDTH`: 0.3 for an estimate, the presets' own
                    HINGE_DISTANCE_RANGE; 0.15 for the hoverfly's second-hand number)
hinge_height h_w    the same, about the preset's h_w
body_angle delta    +- 15 deg about the sources' attitude for every species (the presets'
                    HINGE_ELEVATION_HALF_RANGE_DEG; no source gives a hover body angle with
                    its scatter for our six presets)
center_of_pressure  x_hat in [0.15, 0.35] about the paper's 0.25 (c/4) for every species: the
                    spread of the open choices of :data:`flapping.hover.stability.OPEN_CHOICES`;
                    the centre of pressure moves with the angle of attack and no source gives it
                    for these wings
pitch_inertia I_y   the preset's range where it has one (estimates: 0.6-1.6 times the
                    ellipsoid, :data:`~flapping.model.presets.INERTIA_RANGE`), else the status
                    rule (:data:`RELATIVE_HALF_WIDTH`)
r2                  the preset's range where it has one (+-0.03), else
                    :data:`R2_HALF_WIDTH` by status; an estimated r1 follows Ellington's fit
frequency f         the preset's range where it has one (hoverfly 150-180 Hz); the bumblebee's
                    two sources, 116 Hz (Berman & Wang) to 156.25 Hz (Sun & Xiong); else the
                    status rule
wing_mass m_w       full model only (:func:`reduction_check`): the preset's range where it has
                    one, else +-20 %: the masses were checked only against FWUAV's data file
                    (issue 28), not a measurement read here
==================  ==========================================================================

The status rule (:data:`RELATIVE_HALF_WIDTH`): verified +-5 %, the paper's +-10 %, second-hand
+-15 %, unverified +-20 %, estimated +-30 %: estimated numbers get wider ranges. The half-widths
are our judgement of how far each kind of number may be off, not taken from a source. The
nominal stroke amplitude (which fixes alpha_m by eq. 40) is held at the preset's.

Layers: a study. It imports the sweep (:mod:`flapping.studies.sweep`), the one study that is a
tool (the batch API of the compiled kernel), besides :mod:`flapping.hover` and the model.
SALib and pandas are imported when a study runs, not with this module.
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from flapping import _validation
from flapping.errors import ConvergenceError, PlausibilityWarning
from flapping.model.morphology import Insect, beta_shape_parameters
from flapping.model.presets import PRESETS, Sourced, ellington_r1

if TYPE_CHECKING:  # pragma: no cover
    import pandas

__all__ = [
    "INPUTS",
    "FULL_MODEL_INPUTS",
    "RELATIVE_HALF_WIDTH",
    "HINGE_HALF_WIDTH",
    "R2_HALF_WIDTH",
    "BODY_ANGLE_HALF_RANGE_DEG",
    "CENTER_OF_PRESSURE_RANGE",
    "WING_MASS_HALF_WIDTH",
    "InputRange",
    "input_ranges",
    "stroke_plane_hinge",
    "SobolIndices",
    "sobol_indices",
    "MIN_TRUSTED_BASE",
    "MAX_RESAMPLES",
    "SmallSampleWarning",
    "GlobalSensitivity",
    "global_sensitivity",
    "ReductionCheck",
    "reduction_check",
    "nominal_reduction",
]

#: The inputs of the compiled (reduced) study, in order.
INPUTS: tuple[str, ...] = ("hinge_offset", "hinge_height", "body_angle", "center_of_pressure",
                           "pitch_inertia", "r2", "frequency")

#: The inputs of the full model (:func:`reduction_check`): the study's and the wing mass.
FULL_MODEL_INPUTS: tuple[str, ...] = (*INPUTS, "wing_mass")

#: Relative half-width of a range by the number's status, where the preset gives none.
RELATIVE_HALF_WIDTH: Mapping[str, float] = {
    "verified": 0.05, "paper": 0.10, "second-hand": 0.15, "unverified": 0.20, "estimate": 0.30}

#: Half-width of each hinge coordinate, as a fraction of the hinge-to-CG distance, by status.
HINGE_HALF_WIDTH: Mapping[str, float] = {
    "verified": 0.05, "paper": 0.10, "second-hand": 0.15, "unverified": 0.20, "estimate": 0.30}

#: Absolute half-width of r2 by status, where the preset gives no range.
R2_HALF_WIDTH: Mapping[str, float] = {
    "verified": 0.01, "paper": 0.02, "second-hand": 0.02, "unverified": 0.03, "estimate": 0.04}

#: Half-range of the body angle about the sources' attitude [deg].
BODY_ANGLE_HALF_RANGE_DEG = 15.0

#: Range of the centre of pressure x_hat (over the chord, behind the pitch line).
CENTER_OF_PRESSURE_RANGE: tuple[float, float] = (0.15, 0.35)

#: Relative half-width of a wing mass without a range in its preset.
WING_MASS_HALF_WIDTH = 0.20

#: The bumblebee's frequency range [Hz]: its two sources (Berman & Wang 2007; Sun & Xiong 2005).
_BUMBLEBEE_FREQUENCIES = (116.0, 1.0 / 6.4e-3)

#: A leading multiplier whose imaginary part is below this fraction of its modulus is real (as
#: :class:`~flapping.studies.atlas.GeometryCase`).
_REAL_TOL = 1e-8

#: Smallest beta shape parameter of a planform the rotational damping admits (its c^4 integral
#: I_04 converges for p, q > 3/4).
_BETA_MIN = 0.75

#: Most base samples of a study: 2^20 (a species at 2^20 base samples is 9.4 million orbits).
MAX_BASE = 2**20

#: Fewest base samples (evaluated in full) whose indices :func:`sobol_indices` and
#: :func:`global_sensitivity` return without a :class:`SmallSampleWarning`. Measured on the
#: Ishigami function (exact indices known; ten seeds each): the largest error of S1 is (median)
#: 0.89 at N = 2, 0.36 at 8, 0.26 at 32, 0.09 at 64 and 0.04 at 256, and below N = 16 some
#: index exceeds 1 (up to 6.7 at N = 2; two samples gave the issue's S1 = 1.52 +- 0.19).
MIN_TRUSTED_BASE = 64

#: Most bootstrap resamples, and most resamples times base samples: SALib's bootstrap holds
#: arrays of resamples x base samples (8 bytes each); 2^28 entries is 2 GB an array, so the
#: default 200 resamples fit every N up to :data:`MAX_BASE` and 10^9 resamples (a MemoryError
#: deep in SALib) are refused before any work.
MAX_RESAMPLES = 10_000
_MAX_BOOTSTRAP_ENTRIES = 2**28


class SmallSampleWarning(UserWarning):
    """Sobol indices from fewer than :data:`MIN_TRUSTED_BASE` base samples: Saltelli's
    estimators are then off by tenths and may leave [0, 1], and their bootstrap intervals do
    not say so."""


# =========================================================================== inputs
@dataclass(frozen=True)
class InputRange:
    """One uncertain input of a species and its range (uniform).

    Attributes
    ----------
    name : str
        The input: an :class:`Insect` field, or ``"body_angle"``.
    symbol : str
        Its symbol in the book.
    low, nominal, high : float
        The range and the preset's value [SI: m, rad, kg m^2, Hz, kg].
    unit : str
    status : str
        The status of the preset's number (:data:`~flapping.model.presets.STATUSES`), or
        ``"choice"`` for a modelling choice (the centre of pressure, the body angle).
    why : str
        Where the range comes from.
    """

    name: str
    symbol: str
    low: float
    nominal: float
    high: float
    unit: str
    status: str
    why: str

    def __post_init__(self) -> None:
        if not (math.isfinite(self.low) and math.isfinite(self.high) and self.low < self.high):
            raise ValueError(f"the range of `{self.name}` must be finite with low < high; got "
                             f"[{self.low!r}, {self.high!r}]")


def _status_range(name: str, symbol: str, src: Sourced, unit: str, what: str) -> InputRange:
    """The preset's range of ``src`` if it has one, else the status rule."""
    if src.low is not None and src.high is not None:
        return InputRange(name, symbol, src.low, src.value, src.high, unit, src.status,
                          f"the preset's range ({what})")
    w = RELATIVE_HALF_WIDTH[src.status]
    return InputRange(name, symbol, src.value * (1 - w), src.value, src.value * (1 + w), unit,
                      src.status, f"+-{w:.0%}: the status rule for a {src.status} number")


def input_ranges(species: str, *, full_model: bool = False) -> tuple[InputRange, ...]:
    """The uncertain inputs of a species and their ranges (module docstring).

    Parameters
    ----------
    species : str
        A preset name (:data:`~flapping.model.presets.PRESETS`).
    full_model : bool
        Add the wing mass (:data:`FULL_MODEL_INPUTS`), which only the full model carries.

    Returns
    -------
    tuple of InputRange
        In the order of :data:`INPUTS` (then ``wing_mass``).

    Raises
    ------
    ValueError
        For an unknown species.
    """
    species = _validation.choice("species", species, tuple(PRESETS))
    p = PRESETS[species]
    x_src, h_src = p.measured["hinge_offset"], p.measured["hinge_height"]
    distance = math.hypot(x_src.value, h_src.value)
    w = HINGE_HALF_WIDTH[x_src.status] * distance
    hinge_why = (f"the source hinge +-{HINGE_HALF_WIDTH[x_src.status]:.2f} of its distance "
                 f"from the CG ({distance * 1e3:.2f} mm; {x_src.status})")
    ranges = [
        InputRange("hinge_offset", "x_h", x_src.value - w, x_src.value, x_src.value + w, "m",
                   x_src.status, hinge_why),
        InputRange("hinge_height", "h_w", h_src.value - w, h_src.value, h_src.value + w, "m",
                   h_src.status, hinge_why),
        InputRange("body_angle", "delta", -math.radians(BODY_ANGLE_HALF_RANGE_DEG), 0.0,
                   math.radians(BODY_ANGLE_HALF_RANGE_DEG), "rad", "choice",
                   f"+-{BODY_ANGLE_HALF_RANGE_DEG:.0f} deg about the sources' attitude (the "
                   "presets' hinge-elevation range)"),
        InputRange("center_of_pressure", "x_hat", *_cop(p.insect().center_of_pressure), "-",
                   "choice", "[0.15, 0.35]: the open-choice variants about the paper's c/4"),
        _status_range("pitch_inertia", "I_y", p.values["pitch_inertia"], "kg m^2",
                      "an estimate: 0.6-1.6 times the ellipsoid"),
    ]
    ranges.append(_r2_range(species))
    f = p.values["frequency"]
    if species == "bumblebee":
        ranges.append(InputRange("frequency", "f", *_BUMBLEBEE_FREQUENCIES[:1], f.value,
                                 _BUMBLEBEE_FREQUENCIES[1], "Hz", f.status,
                                 "the two sources: Berman & Wang's 116 Hz to Sun & Xiong's "
                                 "6.4 ms wingbeat"))
    else:
        ranges.append(_status_range("frequency", "f", f, "Hz", "Wu & Sun's drone fly"))
    if full_model:
        m = p.measured["wing_mass"]
        if m.low is not None and m.high is not None:
            ranges.append(InputRange("wing_mass", "m_w", m.low, m.value, m.high, "kg", m.status,
                                     "the preset's range"))
        else:
            ranges.append(InputRange(
                "wing_mass", "m_w", m.value * (1 - WING_MASS_HALF_WIDTH), m.value,
                m.value * (1 + WING_MASS_HALF_WIDTH), "kg", m.status,
                f"+-{WING_MASS_HALF_WIDTH:.0%}: checked only against FWUAV's data file"))
    return tuple(ranges)


def _planform_ok(species: str, r2: float) -> bool:
    """True if the preset's planform with this r2 (and r1, on Ellington's fit if estimated)
    exists and has the integrable c^4 of the rotational damping (beta shapes p, q > 3/4)."""
    p = PRESETS[species]
    r1 = ellington_r1(r2) if p.values["r1"].status == "estimate" else p.values["r1"].value
    try:
        shapes = beta_shape_parameters(r1, r2)
    except ValueError:
        return False
    return min(shapes) > _BETA_MIN


def _r2_range(species: str) -> InputRange:
    """r2's range: the preset's or the status rule's, each end pulled in to the planforms the
    model admits (bisection to 1e-6, then a margin of 1e-4)."""
    r2 = PRESETS[species].values["r2"]
    if r2.low is not None and r2.high is not None:
        low, high, why = r2.low, r2.high, "the preset's range (+-0.03)"
    else:
        half = R2_HALF_WIDTH[r2.status]
        low, high, why = r2.value - half, r2.value + half, f"+-{half:.2f}: the status rule"
    ends = []
    for end in (low, high):
        if not _planform_ok(species, end):
            inside, outside = r2.value, end
            while abs(outside - inside) > 1e-6:
                mid = 0.5 * (inside + outside)
                inside, outside = (mid, outside) if _planform_ok(species, mid) else (inside, mid)
            end = inside - math.copysign(1e-4, end - r2.value)
            why += (f"; {'high' if end > r2.value else 'low'} end cut to {end:.4f}: beyond "
                    "it the rotational damping's c^4 is not integrable (beta shape <= 3/4)")
        ends.append(end)
    return InputRange("r2", "r2", ends[0], r2.value, ends[1], "-", r2.status, why)


def _cop(nominal: float) -> tuple[float, float, float]:
    low, high = CENTER_OF_PRESSURE_RANGE
    return low, nominal, high


def stroke_plane_hinge(hinge_offset: float, hinge_height: float, body_angle: float
                       ) -> tuple[float, float]:
    """The body-fixed hinge-to-CG vector in stroke-plane axes after a body-angle change.

    The body pitches nose-up by ``body_angle`` while the stroke plane stays horizontal: a hinge
    ahead of the centre of gravity rises, one above it moves back.

    Parameters
    ----------
    hinge_offset, hinge_height : float
        x_h (ahead) and h_w (above) of the hinge from the centre of gravity at the sources'
        attitude [m].
    body_angle : float
        delta, the nose-up change of the body angle [rad].

    Returns
    -------
    tuple of 2 floats
        (x', h') [m]: x_h cos(delta) - h_w sin(delta), x_h sin(delta) + h_w cos(delta).
    """
    hinge_offset = _validation.real("hinge_offset", hinge_offset, unit="m")
    hinge_height = _validation.real("hinge_height", hinge_height, unit="m")
    body_angle = _validation.real("body_angle", body_angle, unit="rad")
    c, s = math.cos(body_angle), math.sin(body_angle)
    return hinge_offset * c - hinge_height * s, hinge_offset * s + hinge_height * c


def _insect(species: str, point: Mapping[str, float], full_model: bool) -> Insect:
    """The insect of one sample point: the reduced model (x' dropped, massless wings; the
    compiled kernel's) or the full one (the hinge at (x', h'), the wings' mass)."""
    p = PRESETS[species]
    x, h = stroke_plane_hinge(point["hinge_offset"], point["hinge_height"], point["body_angle"])
    changes: dict[str, Any] = {
        "hinge_height": h, "center_of_pressure": point["center_of_pressure"],
        "pitch_inertia": point["pitch_inertia"], "r2": point["r2"],
        "frequency": point["frequency"]}
    if p.values["r1"].status == "estimate":  # r1 was estimated from r2: it follows
        changes["r1"] = ellington_r1(point["r2"])
    if full_model:
        changes.update(hinge_offset=x, wing_mass=point["wing_mass"])
    base = p.insect("measured" if full_model else "paper")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)
        return base.with_(**changes)


# =========================================================================== Sobol indices
@dataclass(frozen=True)
class SobolIndices:
    """First-order and total Sobol indices of one output, with their confidence intervals.

    Attributes
    ----------
    names : tuple of str
        The inputs, in order.
    first, first_conf, total, total_conf : ndarray
        S_i, its half-width of the confidence interval (bootstrap over the base samples), S_Ti
        and its half-width, one per input.
    n_base : int
        Base samples N (the sample has N (D + 2) points).
    n_used : int
        Base samples whose N (D + 2) block evaluated everywhere (the estimate uses only these).
    n_failed : int
        Points where the function failed (NaN): their blocks are left out of the indices.
    conf_level : float
    """

    names: tuple[str, ...]
    first: np.ndarray
    first_conf: np.ndarray
    total: np.ndarray
    total_conf: np.ndarray
    n_base: int
    n_used: int
    n_failed: int
    conf_level: float

    def table(self) -> pandas.DataFrame:
        """The indices as a table, one row per input, by total index (largest first)."""
        import pandas

        df = pandas.DataFrame({"input": self.names, "S1": self.first, "S1_conf": self.first_conf,
                               "ST": self.total, "ST_conf": self.total_conf})
        return df.sort_values("ST", ascending=False, ignore_index=True)


def _problem(bounds: Mapping[str, tuple[float, float]]) -> dict[str, Any]:
    """SALib's problem dict of ``bounds`` (checked)."""
    if not isinstance(bounds, Mapping) or not bounds:
        raise ValueError(f"`bounds` must be a non-empty mapping of input names to (low, high); "
                         f"got {bounds!r}")
    names, pairs = [], []
    for name, pair in bounds.items():
        arr = _validation.array(f"bounds[{name!r}]", pair)
        if arr.shape != (2,) or not arr[0] < arr[1]:
            raise ValueError(f"`bounds[{name!r}]` must be (low, high) with finite low < high; "
                             f"got {pair!r}")
        names.append(str(name))
        pairs.append([float(arr[0]), float(arr[1])])
    return {"num_vars": len(names), "names": names, "bounds": pairs}


def _sample(problem: dict[str, Any], n_base: int, seed: int) -> np.ndarray:
    """Saltelli's sample of N (D + 2) points: per base sample, A, the D mixes AB_i, then B."""
    from SALib.sample import sobol as sobol_sample  # type: ignore[import-untyped]

    return np.asarray(sobol_sample.sample(problem, n_base, calc_second_order=False,
                                          scramble=True, seed=seed))


def _analyse(problem: dict[str, Any], y: np.ndarray, n_base: int, seed: int,
             num_resamples: int, conf_level: float) -> tuple[SobolIndices, np.ndarray]:
    """The indices of outputs ``y`` (NaN where the function failed); and the mask of the base
    samples used."""
    from SALib.analyze import sobol as sobol_analyze  # type: ignore[import-untyped]

    d = problem["num_vars"]
    blocks = y.reshape(n_base, d + 2)
    used = np.all(np.isfinite(blocks), axis=1)
    n_used = int(used.sum())
    if n_used < 2:
        raise ConvergenceError(f"only {n_used} of {n_base} base samples evaluated at all "
                               f"{d + 2} of their points: no Sobol index can be estimated")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a constant output: 0/0 -> NaN, kept
        # SALib seeds its bootstrap only for a truthy seed (0 would draw fresh intervals)
        si = sobol_analyze.analyze(problem, blocks[used].ravel(), calc_second_order=False,
                                   num_resamples=num_resamples, conf_level=conf_level,
                                   seed=seed + 1)
    first, first_conf, total, total_conf = (np.asarray(si[k], dtype=float).copy()
                                            for k in ("S1", "S1_conf", "ST", "ST_conf"))
    if n_used < MIN_TRUSTED_BASE:
        warnings.warn(f"Sobol indices from {n_used} base samples (of {n_base}) evaluated in full: "
                      f"below {MIN_TRUSTED_BASE} they can be off by tenths and leave [0, 1] "
                      "(MIN_TRUSTED_BASE); take `n_base` >= 64", SmallSampleWarning,
                      stacklevel=3)
    indices = SobolIndices(tuple(problem["names"]), first, first_conf, total, total_conf,
                           n_base=n_base, n_used=n_used, n_failed=int(np.sum(~np.isfinite(y))),
                           conf_level=conf_level)
    for a in (indices.first, indices.first_conf, indices.total, indices.total_conf):
        a.flags.writeable = False
    return indices, used


def _check_resamples(num_resamples: int, n_base: int) -> int:
    """``num_resamples`` in [10, MAX_RESAMPLES] and within the bootstrap's memory at ``n_base``."""
    high = min(MAX_RESAMPLES, _MAX_BOOTSTRAP_ENTRIES // n_base)
    return _validation.integer("num_resamples", num_resamples, low=10, high=high)


def _check_base(n_base: int) -> int:
    n_base = _validation.integer("n_base", n_base, low=2, high=MAX_BASE)
    if n_base & (n_base - 1):
        raise ValueError(f"`n_base` must be a power of 2 (Sobol' sequences balance only at "
                         f"powers of 2), in [2, {MAX_BASE}]; got {n_base}")
    return n_base


def sobol_indices(bounds: Mapping[str, tuple[float, float]],
                  function: Callable[[np.ndarray], np.ndarray], n_base: int, *, seed: int = 0,
                  num_resamples: int = 200, conf_level: float = 0.95) -> SobolIndices:
    """First-order and total Sobol indices of ``function`` over uniform inputs (Saltelli).

    The sample is Saltelli's extension of a scrambled Sobol' sequence (SALib), N (D + 2)
    points for D inputs; the indices are SALib's estimators (Saltelli et al. 2010: first order;
    Jansen: total) with bootstrap confidence intervals. Points where ``function`` returns NaN
    (failed) are counted; their base sample's whole block is left out of the estimate.

    Parameters
    ----------
    bounds : mapping of str to (low, high)
        The inputs and their ranges (low < high, finite).
    function : callable
        ``function(X) -> y`` for X of shape (n, D) (columns in the order of ``bounds``), y of
        shape (n,); NaN where it fails.
    n_base : int
        Base samples N, a power of 2 in [2, 2^20]; below :data:`MIN_TRUSTED_BASE` evaluated in
        full, a :class:`SmallSampleWarning`.
    seed : int
        Seed of the scrambling and of the bootstrap.
    num_resamples : int
        Bootstrap resamples, in [10, min(MAX_RESAMPLES, 2^28 / n_base)].
    conf_level : float
        Confidence level of the intervals, in (0, 1).

    Returns
    -------
    SobolIndices

    Raises
    ------
    ValueError
        For bad bounds, a bad ``n_base`` or ``function`` output of the wrong shape.
    ConvergenceError
        If fewer than two base samples evaluate everywhere.
    """
    problem = _problem(bounds)
    if not callable(function):  # checked before the sample is drawn (was a TypeError after)
        raise ValueError(f"`function` must be a callable function(X) -> y; got "
                         f"{type(function).__name__}")
    n_base = _check_base(n_base)
    seed = _validation.integer("seed", seed, low=0)
    num_resamples = _check_resamples(num_resamples, n_base)
    conf_level = _validation.real("conf_level", conf_level, low=0.0, high=1.0, low_open=True,
                                  high_open=True)
    x = _sample(problem, n_base, seed)
    y = np.asarray(function(x), dtype=float)
    if y.shape != (x.shape[0],):
        raise ValueError(f"`function` must return shape ({x.shape[0]},) for {x.shape[0]} "
                         f"points; got {y.shape}")
    return _analyse(problem, y, n_base, seed, num_resamples, conf_level)[0]


# =========================================================================== the hover study
@dataclass(frozen=True)
class GlobalSensitivity:
    """The global study of one species (:func:`global_sensitivity`).

    Attributes
    ----------
    species : str
    ranges : tuple of InputRange
    indices : SobolIndices
        Of ln abs(mu_1), the largest Floquet multiplier's modulus.
    samples : pandas.DataFrame
        One row per orbit: the inputs, the stroke-plane hinge height ``h_stroke``, then
        ``mu1_real``, ``mu1_imag``, ``abs_mu1``, ``converged``, ``mode`` (``"oscillatory"``,
        ``"real"``, ``"flip"``; ``""`` for a failed point), ``message`` (why a point failed),
        ``backend`` (the path that solved it) and ``retried`` (solved again alone and cold, with
        the adaptive path as fallback, after the warm-started compiled sweep failed there).
    p_unstable, p_oscillatory, p_real : float
        Fractions of the converged orbits whose largest multiplier is outside the unit circle;
        of those a complex pair (an oscillatory critical mode); a real one (positive or negative).
    p_unstable_ci, p_oscillatory_ci : tuple of 2 floats
        95 % bootstrap intervals (over the base samples).
    n_orbits, n_failed : int
        Orbits attempted, and those with no hover orbit after the retry (counted, each with its
        message in ``samples``; their base samples are left out of the indices).
    n_retried : int
        Points solved again after the compiled sweep failed there (see ``samples["retried"]``).
    wall_time_s : float
        Wall time of the sweep and the retries [s].
    """

    species: str
    ranges: tuple[InputRange, ...]
    indices: SobolIndices
    samples: pandas.DataFrame
    p_unstable: float
    p_oscillatory: float
    p_real: float
    p_unstable_ci: tuple[float, float]
    p_oscillatory_ci: tuple[float, float]
    n_orbits: int
    n_failed: int
    n_retried: int
    wall_time_s: float

    def table(self) -> pandas.DataFrame:
        """The indices with each input's range (by total index, largest first)."""
        import pandas

        ranges = pandas.DataFrame([{"input": r.name, "symbol": r.symbol, "low": r.low,
                                    "nominal": r.nominal, "high": r.high, "unit": r.unit,
                                    "status": r.status} for r in self.ranges])
        return self.indices.table().merge(ranges, on="input")

    def summary(self) -> dict[str, Any]:
        """The species' numbers in one dict (a row of the book's table)."""
        top = self.indices.table()
        return {"species": self.species, "n_orbits": self.n_orbits, "n_failed": self.n_failed,
                "n_retried": self.n_retried,
                "p_unstable": self.p_unstable, "p_oscillatory": self.p_oscillatory,
                "p_real": self.p_real, "top_input": top["input"][0], "top_ST": top["ST"][0],
                "second_input": top["input"][1], "second_ST": top["ST"][1],
                "wall_time_s": self.wall_time_s}


def _mode(mu: complex) -> str:
    """``"oscillatory"`` (a complex pair), ``"real"`` or ``"flip"`` (a negative real)."""
    if abs(mu.imag) > _REAL_TOL * abs(mu):
        return "oscillatory"
    return "real" if mu.real > 0.0 else "flip"


def global_sensitivity(species: str, n_base: int = 1024, *, seed: int = 0,
                       executor: Executor | None = None, num_resamples: int = 200,
                       progress: bool = False) -> GlobalSensitivity:
    """Sobol indices of ln abs(mu_1) and the verdict's probabilities for one species.

    Every input of :func:`input_ranges` varies uniformly over its range; Saltelli's sample of
    ``n_base * (len(INPUTS) + 2)`` points is solved by the compiled sweep
    (:func:`~flapping.studies.sweep.sweep_hover` over the list of insects,
    ``backend="compiled"``; consecutive points differ mostly in one input, so each starts
    from its neighbour's orbit); a point where it finds no hover orbit is solved again alone,
    cold, with the adaptive path as fallback (``backend="auto"``), unless the insect cannot trim
    there (eq. 40). The reduced model of the module docstring: the hinge at its
    stroke-plane height h' above the centre of gravity, massless wings.

    Parameters
    ----------
    species : str
        A preset name.
    n_base : int
        Base samples N, a power of 2 in [2, 2^20]; N (D + 2) = 9 N orbits. Below
        :data:`MIN_TRUSTED_BASE` evaluated in full, a :class:`SmallSampleWarning`.
    seed : int
        Seed of the sample's scrambling and of the bootstraps, >= 0.
    executor : concurrent.futures.Executor, optional
        Passed to the sweep (e.g. a ``ProcessPoolExecutor``).
    num_resamples : int
        Bootstrap resamples of the indices and of the probabilities, in
        [10, min(MAX_RESAMPLES, 2^28 / n_base)].
    progress : bool
        The sweep's progress bar.

    Returns
    -------
    GlobalSensitivity

    Raises
    ------
    ValueError
        For an unknown species or a bad argument.
    ConvergenceError
        If fewer than two base samples converge at all their points.
    """
    import pandas

    from flapping.studies.sweep import sweep_hover

    ranges = input_ranges(species)
    n_base = _check_base(n_base)
    seed = _validation.integer("seed", seed, low=0)
    num_resamples = _check_resamples(num_resamples, n_base)
    problem = _problem({r.name: (r.low, r.high) for r in ranges})
    x = _sample(problem, n_base, seed)
    points = [dict(zip(INPUTS, row, strict=True)) for row in x.tolist()]
    insects = [_insect(species, point, full_model=False) for point in points]
    started = time.perf_counter()
    rows = sweep_hover(insects, backend="compiled", executor=executor, progress=progress)
    retried = _retry_cold(rows, insects)
    wall = time.perf_counter() - started
    converged = rows["converged"].to_numpy(dtype=bool)
    mu = rows["mu1_real"].to_numpy(float) + 1j * rows["mu1_imag"].to_numpy(float)
    modulus = np.where(converged, np.abs(mu), np.nan)
    samples = pandas.DataFrame(x, columns=list(INPUTS))
    samples["h_stroke"] = [i.hinge_height for i in insects]
    samples["mu1_real"], samples["mu1_imag"] = mu.real, mu.imag
    samples["abs_mu1"] = modulus
    samples["converged"] = converged
    samples["mode"] = [_mode(complex(m)) if ok else "" for m, ok in zip(mu, converged,
                                                                         strict=True)]
    samples["message"] = rows["message"].to_numpy()
    samples["backend"] = rows["backend"].to_numpy()
    samples["retried"] = retried
    indices, used = _analyse(problem, np.log(modulus), n_base, seed, num_resamples, 0.95)
    unstable = converged & (modulus > 1.0)
    oscillatory = unstable & (samples["mode"].to_numpy() == "oscillatory")
    n_ok = int(converged.sum())
    p_u = float(unstable.sum() / n_ok)
    p_o = float(oscillatory.sum() / n_ok)
    ci_u, ci_o = _bootstrap(converged, (unstable, oscillatory), n_base, len(INPUTS) + 2,
                            num_resamples, seed)
    return GlobalSensitivity(species, ranges, indices, samples, p_u, p_o, p_u - p_o, ci_u,
                             ci_o, len(points), len(points) - n_ok, int(retried.sum()), wall)


def _retry_cold(rows: pandas.DataFrame, insects: Sequence[Insect]) -> np.ndarray:
    """Solve again, alone and cold, every point of the sweep that found no hover orbit, except
    those that cannot trim (a ValueError: eq. 40 has no alpha_m, the insect is too heavy for
    its nominal stroke). ``rows`` is updated in place; returns the mask of the points retried.

    Two failures of the warm-started compiled sweep are the method's, not the insect's: a
    leading multiplier near +1 leaves Newton's matrix nearly singular, and the kernel stops at
    its iteration cap with a residual at rounding level; and a warm start from a neighbour may
    land on a periodic orbit that drifts (not hover) where a cold start finds the hover.
    ``backend="auto"`` runs the compiled kernel from the default guess and hands a failure to
    the adaptive path, which solves both (~1 s a point); a cold compiled start that converges to
    a drifting orbit (no fallback runs then) is given to the adaptive path as well.
    """
    from flapping.studies.sweep import sweep_hover

    failed = ~rows["converged"].to_numpy(dtype=bool)
    cannot_trim = rows["message"].str.startswith("ValueError").to_numpy(dtype=bool)
    retry = failed & ~cannot_trim
    for i in np.flatnonzero(retry).tolist():
        again = sweep_hover([insects[i]], backend="auto", progress=False)
        if not again.at[0, "converged"]:  # a cold compiled start that drifts: no fallback ran
            again = sweep_hover([insects[i]], backend="adaptive", progress=False)
        for column in again.columns.intersection(rows.columns):
            rows.at[i, column] = again.at[0, column]
    return retry


def _bootstrap(ok: np.ndarray, events: Sequence[np.ndarray], n_base: int, block: int,
               num_resamples: int, seed: int) -> list[tuple[float, float]]:
    """95 % bootstrap intervals of the fractions of ``events`` among ``ok`` points, resampling
    whole base-sample blocks (the points of a block are not independent)."""
    rng = np.random.default_rng(seed)
    ok_b = ok.reshape(n_base, block).sum(axis=1)
    counts = [e.reshape(n_base, block).sum(axis=1) for e in events]
    picks = rng.integers(0, n_base, size=(num_resamples, n_base))
    denominators = ok_b[picks].sum(axis=1)
    out = []
    for c in counts:
        fractions = c[picks].sum(axis=1) / np.maximum(denominators, 1)
        lo, hi = np.quantile(fractions, [0.025, 0.975])
        out.append((float(lo), float(hi)))
    return out


# =========================================================================== the reduction
@dataclass(frozen=True)
class ReductionCheck:
    """The reduced model against the full one at random points (:func:`reduction_check`).

    Attributes
    ----------
    species : str
    table : pandas.DataFrame
        One row per point: the inputs of :data:`FULL_MODEL_INPUTS`, the stroke-plane hinge
        (``x_stroke``, ``h_stroke``), ``mu_reduced`` and ``mu_full`` (the leading multipliers,
        complex; NaN where a solve failed), ``stroke_mean_deg`` (the full model's trim) and
        ``message``.
    """

    species: str
    table: pandas.DataFrame

    @property
    def solved(self) -> pandas.DataFrame:
        """The rows where both models found a hover orbit."""
        t = self.table
        return t[np.isfinite(t["mu_full"].to_numpy(complex))
                 & np.isfinite(t["mu_reduced"].to_numpy(complex))]

    @property
    def max_log_error(self) -> float:
        """Largest difference of ln abs(mu_1) between the models over the solved rows."""
        t = self.solved
        d = np.log(np.abs(t["mu_full"].to_numpy(complex)))
        d -= np.log(np.abs(t["mu_reduced"].to_numpy(complex)))
        return float(np.max(np.abs(d))) if len(d) else math.nan

    @property
    def verdicts_agree(self) -> int:
        """Solved rows where both models agree on stable or unstable and on the mode type."""
        t = self.solved
        full = t["mu_full"].to_numpy(complex)
        red = t["mu_reduced"].to_numpy(complex)
        return int(sum((abs(a) > 1) == (abs(b) > 1) and _mode(a) == _mode(b)
                       for a, b in zip(full, red, strict=True)))


def reduction_check(species: str, n_points: int = 4, *, seed: int = 0) -> ReductionCheck:
    """The leading multiplier of the reduced and of the full model at random points.

    The full model hovers with both trims (Phi and the mean stroke angle, so the hinge may sit
    at (x', h') off the centre of gravity) and wings of mass; it runs on the fixed-step path
    (the compiled kernel lacks both), 1-3 s per point. The reduced model is the one
    :func:`global_sensitivity` solves (compiled). Points are uniform over
    :func:`input_ranges` with ``full_model=True`` (a seeded generator).

    Parameters
    ----------
    species : str
        A preset name.
    n_points : int
        Points, in [1, 10000].
    seed : int
        Seed of the points, >= 0.

    Returns
    -------
    ReductionCheck

    Raises
    ------
    ValueError
        For an unknown species or a bad argument.
    """
    import pandas

    from flapping.hover import find_hover_orbit
    from flapping.hover.stability import hover_stability

    ranges = input_ranges(species, full_model=True)
    n_points = _validation.integer("n_points", n_points, low=1, high=10_000)
    seed = _validation.integer("seed", seed, low=0)
    rng = np.random.default_rng(seed)
    lows = np.array([r.low for r in ranges])
    highs = np.array([r.high for r in ranges])
    rows = []
    for u in rng.random((n_points, len(ranges))):
        point = dict(zip(FULL_MODEL_INPUTS, (lows + u * (highs - lows)).tolist(), strict=True))
        x, h = stroke_plane_hinge(point["hinge_offset"], point["hinge_height"],
                                  point["body_angle"])
        row: dict[str, Any] = {**point, "x_stroke": x, "h_stroke": h, "mu_reduced": complex(
            math.nan), "mu_full": complex(math.nan), "stroke_mean_deg": math.nan,
            "message": ""}
        try:
            reduced = find_hover_orbit(_insect(species, point, False), backend="compiled")
            assert reduced.floquet is not None  # the compiled path's own analysis
            row["mu_reduced"] = complex(reduced.floquet.multipliers[0])
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", PlausibilityWarning)
                full = find_hover_orbit(_insect(species, point, True),
                                        trims=("amplitude", "stroke_mean"),
                                        backend="fixed-step", amplitude_guess=reduced.amplitude,
                                        x0_guess=reduced.x0)
            row["mu_full"] = complex(hover_stability(full).multipliers[0])
            row["stroke_mean_deg"] = math.degrees(full.stroke_mean)
        except (ValueError, ConvergenceError, ArithmeticError) as exc:
            row["message"] = f"{type(exc).__name__}: {exc}"
        rows.append(row)
    return ReductionCheck(species, pandas.DataFrame(rows))


def nominal_reduction(species: str) -> dict[str, complex]:
    """The leading multiplier at the preset's source hinge in the three models, one term apart.

    ``"reduced"``: the compiled kernel's (the hinge at its height above the centre of gravity,
    massless wings); ``"two trims"``: the hinge at (x_h, h_w) with the mean stroke angle
    trimmed, massless wings; ``"full"``: and the wings' mass. The first step is what dropping
    x' costs, the second what dropping the wing mass costs (fixed-step path, 1-3 s each).

    Parameters
    ----------
    species : str
        A preset name.

    Returns
    -------
    dict of str to complex

    Raises
    ------
    ValueError
        For an unknown species.
    ConvergenceError
        If an orbit cannot be found.
    """
    from flapping.hover import find_hover_orbit
    from flapping.hover.stability import hover_stability

    species = _validation.choice("species", species, tuple(PRESETS))
    measured = PRESETS[species].insect("measured")
    reduced = find_hover_orbit(PRESETS[species].insect(hinge_height=measured.hinge_height),
                               backend="compiled")
    assert reduced.floquet is not None  # the compiled path's own analysis
    out = {"reduced": complex(reduced.floquet.multipliers[0])}
    amplitude, x0 = reduced.amplitude, reduced.x0
    for label, insect in (("two trims", measured.with_(wing_mass=0.0)), ("full", measured)):
        orbit = find_hover_orbit(insect, trims=("amplitude", "stroke_mean"),
                                 backend="fixed-step", amplitude_guess=amplitude, x0_guess=x0)
        out[label] = complex(hover_stability(orbit).multipliers[0])
        amplitude, x0 = orbit.amplitude, orbit.x0
    return out

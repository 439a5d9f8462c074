"""The stability explorer's grid: hover, its multipliers, its leading mode and its orbit.

:func:`explore_hover` solves the hover orbit of the blade-element model
(:class:`~flapping.model.dynamics.LongitudinalDynamics` with ``aerodynamics="exact"``) at every
point of an :class:`ExplorerGrid` -- species x flapping frequency x hinge height x wing mass --
and returns two tidy tables (:class:`Exploration`): one row per point (the multipliers, the
leading mode's type and eigenvector, the solve's error estimates, or why there is no orbit), and
one row per point, sample time and state (the orbit over one period).

Why the blade-element loads: the wings' mass enters the equations of motion through their
inertial loads (:mod:`flapping.model.inertia`, the :class:`~flapping.model.morphology.Insect`
fields ``wing_mass``, ``wing_mass_r1``, ``wing_mass_r2``), which the compiled hover kernel of
eq. (29)'s linear loads does not model; the fixed-step path of the blade-element loads runs them
compiled (:mod:`flapping.fast.blade`), wings of mass included, at a few tenths of a second a
point. One model for every point, so that the sliders compare like with like.

The axes are relative, so that one slider means the same for every species: the frequency as a
fraction of the species' own, the hinge height h_w (above the centre of gravity) in units of the
wing length R, the wings' mass as a percentage of the insect's mass (the pair, ``2 wing_mass /
mass``; the body keeps the rest). Every other field is the preset's, in the paper's geometry
(hinge over the centre of gravity, ``hinge_offset = 0``).

Every point starts cold (from the default first guess); a point that fails is a row that says
why. The points are independent, so an :class:`concurrent.futures.Executor` may run them (a line
of hinge heights per task); the tables do not depend on it.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

import flapping._validation as _validation
from flapping.backends import FixedStep, OptionWarning
from flapping.errors import ConvergenceError, HoverDriftWarning, require_success
from flapping.hover import HoverOrbit, HoverProblem, HoverStatus, find_hover_orbit
from flapping.model.morphology import Insect
from flapping.model.presets import preset, preset_names
from flapping.periodic.integrate import flow
from flapping.results import status_of

if TYPE_CHECKING:  # pragma: no cover
    import pandas

__all__ = ["ExplorerGrid", "Exploration", "DEFAULT_GRID", "MAX_POINTS", "POINT_COLUMNS",
           "ORBIT_COLUMNS", "MODE_TYPES", "SAMPLE_RTOL", "SAMPLE_ATOL", "explorer_insect",
           "explore_hover", "leading_mode", "orbit_samples"]

#: The state components, in the order of the state vector (u, w, q, theta).
_STATES = ("u", "w", "q", "theta")

#: The grid's axes, in the order of the table's first columns (the last varies fastest).
AXES = ("species", "frequency_ratio", "wing_mass_percent", "hinge_height_ratio")

#: A leading multiplier whose imaginary part is below this fraction of its modulus is real (the
#: eigenvalues of a real 4 x 4 matrix: a real one comes out with a zero imaginary part, a complex
#: pair with one far above rounding).
_REAL_TOL = 1e-8

#: The leading mode's types: a complex pair, a positive real multiplier, a negative one.
MODE_TYPES = ("oscillatory", "real", "flip")

#: Columns of :attr:`Exploration.points` after the axes.
POINT_COLUMNS: tuple[str, ...] = (
    "frequency_hz", "hinge_height_mm", "wing_mass_mg", "converged", "message", "amplitude_deg",
    "alpha_m_deg", "mu1_real", "mu1_imag", "mu2_real", "mu2_imag", "mu3_real", "mu3_imag",
    "mu4_real", "mu4_imag", "max_abs_mu", "stable", "mode_type", "doubling_wingbeats",
    "mode_u_abs", "mode_w_abs", "mode_q_abs", "mode_theta_abs", "mode_u_phase_deg",
    "mode_w_phase_deg", "mode_q_phase_deg", "mode_theta_phase_deg", "amplitude_error_deg",
    "multiplier_error", "n_steps", "nit", "backend",
)

#: Most points an :class:`ExplorerGrid` may hold: at a few tenths of a second a point (the
#: fixed-step blade-element solve), 10,000 points are about an hour of one core and ~40 MB of
#: orbit samples at 48 a period; the book's grid has 450. A 10^8-point grid (a year of CPU)
#: is refused when the grid is built, before any work.
MAX_POINTS = 10_000

#: Columns of :attr:`Exploration.orbits`.
ORBIT_COLUMNS: tuple[str, ...] = ("point", "phase", "state", "value")


@dataclass(frozen=True)
class ExplorerGrid:
    """The explorer's axes (every combination is a point).

    Attributes
    ----------
    species : tuple of str
        Preset names (:func:`flapping.model.presets.preset_names`).
    frequency_ratio : tuple of float
        f over the species' own frequency, each in [0.5, 2].
    hinge_height_ratio : tuple of float
        h_w / R, the hinge's height above the centre of gravity over the wing length, in [0, 0.5].
    wing_mass_percent : tuple of float
        The wing pair's mass, 2 m_w / m in percent, in [0, 25] (:data:`~flapping.model.
        morphology.PLAUSIBLE_RANGES`' ``wing_mass_ratio``).

    Raises
    ------
    ValueError
        For an axis out of its range, or more than :data:`MAX_POINTS` points in all.
    """

    species: tuple[str, ...]
    frequency_ratio: tuple[float, ...]
    hinge_height_ratio: tuple[float, ...]
    wing_mass_percent: tuple[float, ...]

    def __post_init__(self) -> None:
        if isinstance(self.species, str) or not self.species:
            raise ValueError(f"`species` must be a non-empty sequence of preset names; got "
                             f"{self.species!r}")
        object.__setattr__(self, "species", tuple(
            _validation.choice("species", s, preset_names()) for s in self.species))
        for name, low, high in (("frequency_ratio", 0.5, 2.0), ("hinge_height_ratio", 0.0, 0.5),
                                ("wing_mass_percent", 0.0, 25.0)):
            values = _validation.array(name, getattr(self, name))
            if values.ndim != 1 or values.size == 0:
                raise ValueError(f"`{name}` must be a non-empty 1-D sequence of numbers")
            if values.min() < low or values.max() > high:
                raise ValueError(f"`{name}` must lie in [{low}, {high}]; got {values.tolist()}")
            if np.any(np.diff(values) <= 0.0):
                raise ValueError(f"`{name}` must be strictly increasing; got {values.tolist()}")
            object.__setattr__(self, name, tuple(values.tolist()))
        _validation.grid_size("grid", self.size, high=MAX_POINTS,
                              why=f" (MAX_POINTS; its axes give {' x '.join(map(str, self.shape))}"
                                  " points)")

    @property
    def shape(self) -> tuple[int, int, int, int]:
        """Points per axis, in the order of :data:`AXES`."""
        return (len(self.species), len(self.frequency_ratio), len(self.wing_mass_percent),
                len(self.hinge_height_ratio))

    @property
    def size(self) -> int:
        """Number of points."""
        return math.prod(self.shape)

    def lines(self) -> list[tuple[str, float, float]]:
        """(species, frequency ratio, wing mass %) of each line of hinge heights, in order."""
        return [(s, f, m) for s in self.species for f in self.frequency_ratio
                for m in self.wing_mass_percent]


#: The book's grid: the presets but the monarch, the frequency +-10 % around each species' own,
#: hinge heights up to a quarter of the wing length (the sources' estimates lie at 0.03-0.19 R),
#: wings of 0-6 % of the insect's mass (the hawkmoth's measured pair is ~5.7 %). The monarch is
#: left out: from the default first guess its solves fail at scattered points of such a grid
#: (13 of its 90 in a trial: Newton's cap, a non-finite integration, Phi stepped past 90 deg),
#: and abs(mu_1) goes from 1.30 (real) at 0.10 R to 0.85 (oscillatory) at 0.20 R across a point
#: without an orbit; a map of it needs continuation
#: (as :func:`~flapping.studies.atlas.hover_by_homotopy` does).
DEFAULT_GRID = ExplorerGrid(
    species=tuple(name for name in preset_names() if name != "monarch"),
    frequency_ratio=(0.9, 0.95, 1.0, 1.05, 1.1),
    hinge_height_ratio=(0.0, 0.05, 0.1, 0.15, 0.2, 0.25),
    wing_mass_percent=(0.0, 3.0, 6.0),
)


def explorer_insect(species: str, frequency_ratio: float, hinge_height_ratio: float,
                    wing_mass_percent: float) -> Insect:
    """The preset ``species`` (paper geometry) at a point of the explorer's axes.

    Parameters
    ----------
    species : str
        A preset name.
    frequency_ratio : float
        f over the preset's frequency.
    hinge_height_ratio : float
        h_w / R.
    wing_mass_percent : float
        2 m_w / m [%]; the body (without the wings) keeps ``mass - 2 wing_mass``.

    Returns
    -------
    Insect

    Raises
    ------
    ValueError
        For an unknown species or a value the :class:`Insect` refuses.
    """
    base = preset(species)
    return base.with_(frequency=frequency_ratio * base.frequency,
                      hinge_height=hinge_height_ratio * base.semi_span,
                      wing_mass=wing_mass_percent / 100.0 * base.mass / 2.0)


def leading_mode(monodromy: np.ndarray) -> tuple[complex, str, np.ndarray]:
    """The leading Floquet multiplier, its type and its eigenvector.

    Parameters
    ----------
    monodromy : ndarray, shape (4, 4)
        The monodromy matrix of (u, w, q, theta) (eqs. 42-49).

    Returns
    -------
    mu : complex
        The multiplier of largest modulus.
    mode_type : str
        One of :data:`MODE_TYPES`: ``"oscillatory"`` (a complex pair), ``"real"`` (mu > 0) or
        ``"flip"`` (mu < 0).
    vector : ndarray, complex, shape (4,)
        Its eigenvector in SI components (m/s, m/s, rad/s, rad), scaled so that its component of
        largest modulus is 1 (real for a real multiplier).

    Raises
    ------
    ValueError
        If ``monodromy`` is not a finite real 4 x 4 matrix.
    """
    matrix = _validation.array("monodromy", monodromy)  # finite: eig raised LinAlgError on NaN
    if matrix.shape != (4, 4):
        raise ValueError(f"`monodromy` must be a real 4 x 4 matrix (of u, w, q, theta); got "
                         f"shape {matrix.shape}")
    values, vectors = np.linalg.eig(matrix)
    i = int(np.argmax(np.abs(values)))
    mu = complex(values[i])
    v = vectors[:, i]
    v = v / v[np.argmax(np.abs(v))]
    if abs(mu.imag) > _REAL_TOL * abs(mu):
        return mu, "oscillatory", v
    v = v.real.astype(complex)
    return complex(mu.real, 0.0), ("real" if mu.real > 0.0 else "flip"), v


@dataclass(frozen=True)
class Exploration:
    """The explorer's grid solved.

    Attributes
    ----------
    grid : ExplorerGrid
    points : pandas.DataFrame
        One row per point in grid order (:data:`AXES`, the last fastest), then
        :data:`POINT_COLUMNS`: the point in SI-derived units (``frequency_hz``,
        ``hinge_height_mm``, ``wing_mass_mg`` of one wing); ``converged`` (a hover orbit was
        found) and ``message`` (why not, else empty); ``amplitude_deg`` (Phi), ``alpha_m_deg``;
        the multipliers ``mu1..mu4`` (real and imaginary parts, by descending modulus);
        ``max_abs_mu``, ``stable``; ``mode_type`` (:data:`MODE_TYPES`, empty without an orbit)
        and ``doubling_wingbeats`` (ln 2 / ln max_abs_mu; inf if stable); the leading
        eigenvector's components ``mode_<s>_abs`` (largest 1) and ``mode_<s>_phase_deg`` for
        s in u, w, q, theta; the error estimates ``amplitude_error_deg`` and
        ``multiplier_error``; ``n_steps`` (per half-stroke), ``nit``, ``backend``.
    orbits : pandas.DataFrame
        :data:`ORBIT_COLUMNS`: ``point`` (the row of :attr:`points`), ``phase`` (t / T in [0, 1]),
        ``state`` (u, w, q, theta) and ``value`` (SI); the orbits of converged points only.
    n_samples : int
        Samples per period of each orbit (``n_samples + 1`` times, both ends included).
    """

    grid: ExplorerGrid
    points: pandas.DataFrame = field(repr=False)
    orbits: pandas.DataFrame = field(repr=False)
    n_samples: int


#: Tolerances of the orbit's samples (adaptive DOP853). A plot needs ~1e-4; the orbit's own
#: samples (:attr:`~flapping.hover.HoverOrbit.x`, at the adaptive path's 1e-11) cost ~0.05 s of
#: CPU a point against ~0.03 s here, on a ~0.16 s point.
SAMPLE_RTOL, SAMPLE_ATOL = 1e-8, 1e-10


def orbit_samples(orbit: HoverOrbit, n_samples: int) -> np.ndarray:
    """The orbit's states at ``n_samples + 1`` equal times over one period, both ends included.

    Integrated from the orbit's x0 with the loads it was solved with (restarted at stroke
    reversal), to :data:`SAMPLE_RTOL` and :data:`SAMPLE_ATOL`.

    Parameters
    ----------
    orbit : HoverOrbit
    n_samples : int
        Steps per period, >= 1.

    Returns
    -------
    ndarray, shape (4, n_samples + 1)
        (u, w, q, theta) [SI], time along the last axis.

    Raises
    ------
    ConvergenceError
        If the integration fails.
    """
    _validation.instance("orbit", orbit, HoverOrbit)
    n = _validation.integer("n_samples", n_samples, low=1, high=1 << 20)
    model = orbit.model
    t = np.linspace(0.0, model.period, n + 1)
    rhs = HoverProblem.of_model(model).fields()[0]
    res = require_success(
        flow(rhs, (0.0, model.period), np.append(orbit.x0, 0.0), breakpoints=model.breakpoints,
             period=model.period, t_eval=t, args=([model.amplitude],), rtol=SAMPLE_RTOL,
             atol=SAMPLE_ATOL), "sampling the orbit")
    return np.ascontiguousarray(res.x[:4])


#: The failures of one point that become its row; others propagate.
_POINT_FAILURES = (ValueError, ConvergenceError, ArithmeticError, np.linalg.LinAlgError)


def _solve(insect: Insect, backend: FixedStep, n_samples: int) -> HoverOrbit:
    """Hover at one point, from the default first guess (a neighbour's orbit is no better a
    start here: measured on the hawkmoth's and the fruit fly's lines of hinge heights, Newton
    took 5-14 iterations from the neighbour against 6-7 cold)."""
    return find_hover_orbit(insect, aerodynamics="exact", backend=backend, n_samples=n_samples)


def _failed_row(insect: Insect | None, error: BaseException) -> dict[str, Any]:
    row: dict[str, Any] = dict.fromkeys(POINT_COLUMNS, math.nan)
    row.update(converged=False, stable=False, mode_type="", n_steps=0, nit=0, backend="",
               message=f"{type(error).__name__}: {error}", solve_status=str(status_of(error)))
    if insect is not None:
        row.update(frequency_hz=insect.frequency, hinge_height_mm=insect.hinge_height * 1e3,
                   wing_mass_mg=insect.wing_mass * 1e6)
    return row


def _row(insect: Insect, orbit: HoverOrbit) -> dict[str, Any]:
    """The columns of a solved point."""
    floquet = orbit.floquet
    assert floquet is not None  # the fixed-step path keeps its monodromy
    mus = np.asarray(floquet.multipliers)
    mu, kind, v = leading_mode(floquet.matrix)
    modulus = float(np.max(np.abs(mus)))
    hover = orbit.status == HoverStatus.HOVER
    row: dict[str, Any] = {
        "frequency_hz": insect.frequency, "hinge_height_mm": insect.hinge_height * 1e3,
        "wing_mass_mg": insect.wing_mass * 1e6, "converged": hover,
        "message": "" if hover else orbit.message, "amplitude_deg": orbit.amplitude_deg,
        "alpha_m_deg": math.degrees(orbit.alpha_m), "max_abs_mu": modulus,
        "stable": modulus < 1.0, "mode_type": kind,
        "doubling_wingbeats": math.log(2.0) / math.log(modulus) if modulus > 1.0 else math.inf,
        "amplitude_error_deg": math.degrees(orbit.amplitude_error),
        "multiplier_error": orbit.multiplier_error,
        "n_steps": orbit.fixed_step.n_steps if orbit.fixed_step is not None else 0,
        "nit": orbit.nit, "backend": orbit.backend, "solve_status": str(orbit.solve_status)}
    for i, m in enumerate(mus.tolist(), start=1):
        row[f"mu{i}_real"], row[f"mu{i}_imag"] = m.real, m.imag
    for s, c in zip(_STATES, v.tolist(), strict=True):
        row[f"mode_{s}_abs"] = abs(c)
        row[f"mode_{s}_phase_deg"] = math.degrees(math.atan2(c.imag, c.real)) if c else 0.0
    return row


def _solve_line(line: tuple[str, float, float], hinge_heights: Sequence[float],
                backend: FixedStep, n_samples: int
                ) -> list[tuple[dict[str, Any], np.ndarray | None]]:
    """One line of hinge heights: (row, orbit samples (4, n_samples + 1) or None) per point.

    Module-level (picklable) so that executors can run it.
    """
    species, f_ratio, mass_pct = line
    out: list[tuple[dict[str, Any], np.ndarray | None]] = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", HoverDriftWarning)  # the row records the drift
        warnings.simplefilter("ignore", OptionWarning)
        for h_ratio in hinge_heights:
            insect = None
            try:
                insect = explorer_insect(species, f_ratio, h_ratio, mass_pct)
                orbit = _solve(insect, backend, n_samples)
                row = _row(insect, orbit)
                samples = orbit_samples(orbit, n_samples) if row["converged"] else None
            except _POINT_FAILURES as error:
                out.append((_failed_row(insect, error), None))
                continue
            out.append((row, samples))
    return out


def explore_hover(grid: ExplorerGrid | None = None, *, backend: FixedStep | None = None,
                  n_samples: int = 48, executor: Executor | None = None) -> Exploration:
    """Hover, its Floquet multipliers (eqs. 42-49), its leading mode and its orbit over a grid.

    Parameters
    ----------
    grid : ExplorerGrid, optional
        The axes (default :data:`DEFAULT_GRID`).
    backend : FixedStep, optional
        The fixed-step path's options (default ``FixedStep()``: Richardson error estimates of
        every unknown below 1e-10 relative).
    n_samples : int
        Samples per period of each orbit, even, in [8, 1024].
    executor : concurrent.futures.Executor, optional
        Runs the lines of hinge heights (default: this process). The tables do not depend on it.

    Returns
    -------
    Exploration

    Raises
    ------
    ValueError
        For a bad argument (a point without an orbit is a row that says why).
    """
    import pandas

    grid = DEFAULT_GRID if grid is None else _validation.instance("grid", grid, ExplorerGrid)
    backend = FixedStep() if backend is None else _validation.instance("backend", backend,
                                                                       FixedStep)
    n = _validation.integer("n_samples", n_samples, low=8, high=1024)
    if n % 2:
        raise ValueError(f"`n_samples` must be an even integer in [8, 1024]; got {n_samples!r}")
    if executor is not None and not isinstance(executor, Executor):
        raise ValueError(f"`executor` must be a concurrent.futures.Executor; got {executor!r}")
    lines = grid.lines()
    heights = grid.hinge_height_ratio
    if executor is None:
        results = [_solve_line(line, heights, backend, n) for line in lines]
    else:
        futures = [executor.submit(_solve_line, line, heights, backend, n) for line in lines]
        try:
            results = [future.result() for future in futures]
        except BaseException:  # Ctrl-C or a failure: the lines not started are not run
            for future in futures:
                future.cancel()
            raise
    axes = [dict(zip(AXES, (s, f, m, h), strict=True))
            for (s, f, m) in lines for h in heights]
    rows = [row for result in results for row, _ in result]
    points = pandas.concat([pandas.DataFrame(axes),
                            pandas.DataFrame(rows, columns=[*POINT_COLUMNS, "solve_status"])],
                           axis=1)
    phase = np.linspace(0.0, 1.0, n + 1)
    blocks = []
    samples = [x for result in results for _, x in result]
    for i, x in enumerate(samples):
        if x is None:
            continue
        blocks.append(pandas.DataFrame({
            "point": np.repeat(i, x.size), "phase": np.tile(phase, 4),
            "state": np.repeat(_STATES, phase.size), "value": x.ravel()}))
    orbits = (pandas.concat(blocks, ignore_index=True) if blocks
              else pandas.DataFrame(columns=list(ORBIT_COLUMNS)))
    return Exploration(grid, points, orbits, n)

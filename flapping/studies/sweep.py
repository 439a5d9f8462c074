"""Sweeps: the hover orbit and its Floquet multipliers over a grid of insect parameters.

:func:`sweep_hover` evaluates hover (Phi, x0) and the multipliers at every point of a grid of
:class:`~flapping.model.morphology.Insect` fields (one, two or more at a time, as a full grid), or
over an explicit list of insects, and returns a tidy :class:`pandas.DataFrame`: one row per point,
failures included as rows that say why (a sweep never aborts on one bad point).

How it runs:

- with the compiled kernel (:mod:`flapping.fast`, eq. 29's linear loads) when numba is installed,
  else with the adaptive scipy path (:func:`~flapping.hover.find_hover_orbit` and
  :func:`~flapping.hover.stability.hover_stability`; a warning says so: it is ~1000 times slower);
  the blade-element loads (``aerodynamics``) on the fixed-step path, as
  :func:`~flapping.hover.find_hover_orbit` runs them (or on any path named by ``backend``);
- the points are visited in a boustrophedon ("snake") order through the grid, split into chunks
  of consecutive points; within a chunk each solve starts from its neighbour's step count and
  from (x0, Phi) predicted by the cubic through the last four answers on its grid line (the
  last answer at a corner of the snake), so most take two Newton iterations instead of five;
- the chunks run in this process by default, or on any :class:`concurrent.futures.Executor`:
  a ``ProcessPoolExecutor`` for local cores, or ``dask.distributed.Client.get_executor()`` for a
  cluster. The chunks are the same whichever runs them, so the table is identical.

pandas and tqdm (the ``sweep`` extra) are imported when a sweep runs, not with this module.
"""

from __future__ import annotations

import itertools
import math
import warnings
from collections.abc import Iterator, Mapping, Sequence
from concurrent.futures import Executor, as_completed
from dataclasses import dataclass, fields
from functools import cached_property, partial
from typing import TYPE_CHECKING, Any

import numpy as np

import flapping._validation as _validation
from flapping.errors import ConvergenceError, HoverDriftWarning
from flapping.fast import kernel
from flapping.hover import BACKENDS, HoverOrbit, HoverProblem, HoverStatus, find_hover_orbit
from flapping.hover.stability import hover_stability
from flapping.model.dynamics import AERODYNAMIC_MODELS
from flapping.model.morphology import Insect
from flapping.model.presets import preset_names
from flapping.periodic.settings import SolverSettings
from flapping.studies._path import Guess, Step, WarmStart, follow

if TYPE_CHECKING:  # pragma: no cover
    import pandas

__all__ = ["SWEEPABLE", "COLUMNS", "MAX_GRID_POINTS", "sweep_hover", "grid_points"]

#: Insect fields a grid may vary (the numeric ones).
SWEEPABLE: tuple[str, ...] = tuple(
    f.name for f in fields(Insect)
    if f.init and f.name not in ("name", "aspect_ratio_convention"))

#: Result columns after the parameter columns, in order.
COLUMNS: tuple[str, ...] = (
    "amplitude_deg", "alpha_m_deg", "u0", "w0", "q0", "theta0",
    "mu1_real", "mu1_imag", "mu2_real", "mu2_imag", "mu3_real", "mu3_imag", "mu4_real",
    "mu4_imag", "max_abs_mu", "stable", "converged", "status", "forward_speed", "climb_speed",
    "amplitude_error_deg", "multiplier_error", "nit", "n_steps", "backend", "message",
)

#: Points per chunk: the unit of work sent to an executor (warm starts run within a chunk).
DEFAULT_CHUNK = 50

#: Largest number of points of a grid (the product of its axes' lengths): ~30 min of solves on
#: one core with the compiled kernel, and the table's rows fill a few GB. A larger grid is refused
#: at once rather than enumerated.
MAX_GRID_POINTS = 10**7

#: The failures of one point that become its row (the sweep goes on); others propagate.
_POINT_FAILURES = (ValueError, ConvergenceError, ArithmeticError, np.linalg.LinAlgError)


@dataclass(frozen=True)
class _Settings:
    """What every chunk needs besides its points (picklable)."""

    backend: str
    amplitude_tol_deg: float
    multiplier_tol: float
    solver: SolverSettings | None = None
    aerodynamics: str = "linear"


def grid_points(grid: Mapping[str, Sequence[float]]) -> list[dict[str, float]]:
    """The points of a full grid in C order (the last parameter varies fastest).

    Parameters
    ----------
    grid : mapping of str to sequence of float
        Insect field name -> values (1-D, finite).

    Returns
    -------
    list of dict

    Raises
    ------
    ValueError
        If a name is not a numeric :class:`Insect` field, its values are not a non-empty
        finite 1-D sequence, or the grid has more than :data:`MAX_GRID_POINTS` points.
    """
    axes = _axes(grid)
    return [dict(zip(axes, combo, strict=True)) for combo in itertools.product(*axes.values())]


def _axes(grid: Mapping[str, Sequence[float]]) -> dict[str, list[float]]:
    """The grid's values per field, checked."""
    if not isinstance(grid, Mapping) or not grid:
        raise ValueError(f"`grid` must be a non-empty mapping of Insect fields to values; "
                         f"got {grid!r}")
    axes: dict[str, list[float]] = {}
    size = 1
    for name, values in grid.items():
        _validation.choice("grid key", name, SWEEPABLE)
        arr = _validation.array(f"grid[{name!r}]", values)
        if arr.ndim != 1 or arr.size == 0:
            raise ValueError(f"`grid[{name!r}]` must be a non-empty 1-D sequence of numbers")
        size *= arr.size
        if size > MAX_GRID_POINTS:
            lengths = " x ".join(str(n) for n in [*map(len, axes.values()), arr.size])
            raise ValueError(f"`grid` asks for at least {lengths} = {size} points; at most "
                             f"MAX_GRID_POINTS = {MAX_GRID_POINTS} are allowed (split the sweep)")
        axes[name] = arr.tolist()
    return axes


def _snake(shape: tuple[int, ...]) -> list[int]:
    """Flat C-order indices of a grid visited so that consecutive points are neighbours."""
    if len(shape) == 1:
        return list(range(shape[0]))
    inner = _snake(shape[1:])
    size = len(inner)
    order = []
    for i in range(shape[0]):
        order += [i * size + j for j in (inner if i % 2 == 0 else inner[::-1])]
    return order


# =========================================================================== one point
def _row(orbit: HoverOrbit | None, mu: np.ndarray | None, message: str,
         backend: str, mu_error: float = math.nan) -> dict[str, Any]:
    """The result columns of one point (NaN where there is no answer).

    ``converged`` is true only for a hover orbit: a periodic orbit that drifts (a hinge off the
    centre of gravity with the amplitude as the only trim) is a row with its drift speeds,
    ``status`` and a message, never a converged hover.
    """
    row: dict[str, Any] = dict.fromkeys(COLUMNS, math.nan)
    row.update(converged=False, stable=False, status=-1, nit=0, n_steps=0, backend=backend,
               message=message)
    if orbit is None or mu is None:
        return row
    v = orbit.mean_inertial_velocity
    status = orbit.status  # once: each call compares the speeds again
    hover = status == HoverStatus.HOVER
    # Python complex: abs is the same hypot as np.abs, and a row costs less. The multipliers are
    # finite (both eigenvalue paths refuse a non-finite monodromy), so max needs no NaN care.
    mus = mu.tolist()
    modulus = [abs(m) for m in mus]
    row.update(amplitude_deg=orbit.amplitude_deg, alpha_m_deg=math.degrees(orbit.alpha_m),
               max_abs_mu=max(modulus), stable=all(m < 1.0 for m in modulus),
               converged=hover, status=int(status), forward_speed=v["forward"],
               climb_speed=v["climb"], nit=orbit.nit, backend=orbit.backend,
               message="" if hover else orbit.message)
    if orbit.kernel is not None:
        row.update(amplitude_error_deg=math.degrees(orbit.kernel.amplitude_error),
                   multiplier_error=orbit.kernel.multiplier_error, n_steps=orbit.kernel.n_steps)
    elif orbit.fixed_step is not None:
        fs = orbit.fixed_step
        row.update(amplitude_error_deg=math.degrees(float(fs.unknowns_error[4])),
                   multiplier_error=mu_error, n_steps=fs.n_steps)
    row.update(zip(("u0", "w0", "q0", "theta0"), orbit.x0.tolist(), strict=True))
    for i, m in enumerate(mus[:4], start=1):
        row[f"mu{i}_real"], row[f"mu{i}_imag"] = m.real, m.imag
    return row


def _multipliers(orbit: HoverOrbit, solver: SolverSettings | None = None
                 ) -> tuple[np.ndarray, float]:
    """The orbit's Floquet multipliers and their error estimate: the kernel's (its last Newton
    integration), or those of :func:`~flapping.hover.stability.hover_stability`, on the
    fixed-step path for an orbit found there (its estimate: the change from n to 2n steps)."""
    if orbit.kernel is not None:
        return np.asarray(orbit.kernel.multipliers), orbit.kernel.multiplier_error
    backend = "fixed-step" if orbit.backend == "fixed-step" else "auto"
    stability = hover_stability(orbit, backend=backend, settings=solver)
    return stability.multipliers, stability.multiplier_error


class _Point:
    """A point of a grid: its insect, built (and checked) when first solved."""

    def __init__(self, base: Insect | None, point: Mapping[str, Any] | Insect) -> None:
        self.base = base
        self.point = point

    @cached_property
    def insect(self) -> Insect:
        """The base insect with the point's values (ValueError for a bad one)."""
        if isinstance(self.point, Insect):
            return self.point
        assert self.base is not None
        return self.base.with_(**self.point)


def _solve_point(point: _Point, guess: Guess[tuple[HoverOrbit, np.ndarray, float]] | None,
                 settings: _Settings) -> tuple[HoverOrbit, np.ndarray, float]:
    """One point: from the previous orbit's x0, Phi and step count, or cold without a guess."""
    problem = HoverProblem(point.insect, settings.aerodynamics)
    kernel_options = {"amplitude_tol_deg": settings.amplitude_tol_deg,
                      "multiplier_tol": settings.multiplier_tol}
    if guess is None:
        orbit = find_hover_orbit(problem, backend=settings.backend,
                                 kernel_options=kernel_options, settings=settings.solver)
    else:
        start = guess.previous[0]
        fixed_step_options = None
        if start.kernel is not None:
            kernel_options["n_steps"] = start.kernel.n_steps
        elif start.fixed_step is not None:  # this point runs the fixed-step path too
            fixed_step_options = {"n_steps": start.fixed_step.n_steps}
        x0, amplitude = start.x0, start.amplitude
        if guess.unknowns is not None and 0.0 < guess.unknowns[4] <= 0.5 * math.pi:
            x0, amplitude = guess.unknowns[:4], float(guess.unknowns[4])  # on a grid line
        orbit = find_hover_orbit(problem, amplitude_guess=amplitude, x0_guess=x0,
                                 backend=settings.backend, kernel_options=kernel_options,
                                 fixed_step_options=fixed_step_options,
                                 settings=settings.solver)
    return (orbit, *_multipliers(orbit, settings.solver))


def _unknowns(point: _Point, result: tuple[HoverOrbit, np.ndarray, float]) -> np.ndarray:
    """The continued unknowns of a solved point: (u0, w0, q0, theta0, Phi)."""
    return np.append(result[0].x0, result[0].amplitude)


#: Degree of the prediction of a point's (x0, Phi) from the solved points before it on the same
#: grid line (:class:`~flapping.studies._path.WarmStart`): the cubic through four. Newton
#: iterations a point on the hawkmoth (200 frequencies 20-32 Hz / 200 hinge heights 0-5 mm /
#: 1000 frequencies), by degree: 1: 3.06 / 2.08 / 2.32; 2: 2.34 / 2.08 / 2.09; 3: 2.19 / 1.82 /
#: 2.09; 4: 2.15 / 1.89 / 2.03; the previous answer alone: 3.18 / 3.04 / -.
_PREDICTION_ORDER = 3


def _solve_chunk(base: Insect | None, points: Sequence[Mapping[str, Any] | Insect],
                 settings: _Settings) -> list[dict[str, Any]]:
    """Solve consecutive points, each warm-started from the previous answers; one row each.

    A warm start that fails (a neighbour across a fold) is retried cold. Module-level
    (picklable) so that executors can run it. A point's failure (bad parameters, no
    convergence) is its row's message, and the next point starts cold.
    """
    if base is None:  # a list of insects: no line to predict along
        warm = WarmStart(partial(_solve_point, settings=settings), restart=(ConvergenceError,))
        path: Iterator[tuple[Any, _Point]] = (
            (float(i), _Point(base, point)) for i, point in enumerate(points))
    else:  # grid points: (x0, Phi) predicted along the grid line through the last solved ones
        warm = WarmStart(partial(_solve_point, settings=settings), _unknowns, secant=True,
                         order=_PREDICTION_ORDER, restart=(ConvergenceError,))
        path = ((tuple(map(float, point.values())), _Point(base, point))  # type: ignore[union-attr]
                for point in points)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", HoverDriftWarning)  # the row records the drift
        steps = follow(path, warm, record=_POINT_FAILURES)
    return [_row_of(step, settings.backend) for step in steps]


def _row_of(step: Step[Any, tuple[HoverOrbit, np.ndarray, float]], backend: str
            ) -> dict[str, Any]:
    """The row of a solved or failed point."""
    if step.result is None:
        return _row(None, None, f"{type(step.error).__name__}: {step.error}", backend)
    orbit, mu, mu_error = step.result
    return _row(orbit, mu, "", backend, mu_error)


# =========================================================================== the sweep
def _backend(backend: str, aerodynamics: str) -> str:
    backend = _validation.choice("backend", backend, BACKENDS)
    if backend in ("adaptive", "fixed-step"):
        return backend
    if aerodynamics != "linear":
        if backend == "compiled":
            raise ValueError(f"backend='compiled' does not apply: the kernel has eq. (29)'s "
                             f"linear loads only, not aerodynamics={aerodynamics!r}; use "
                             "backend='fixed-step' or 'auto'")
        return backend  # "auto": the fixed-step path, as find_hover_orbit runs it
    if kernel.numba_available():
        return backend  # each point's HoverProblem decides where "auto" runs
    if backend == "compiled":
        raise ImportError("backend='compiled' needs numba: pip install flapping[fast]")
    warnings.warn("numba is not installed: the sweep uses the adaptive scipy path, ~1000 times "
                  "slower per point (pip install flapping[fast] for the compiled kernel)",
                  RuntimeWarning, stacklevel=3)
    return "adaptive"


def _chunks(order: list[int], size: int) -> Iterator[list[int]]:
    for i in range(0, len(order), size):
        yield order[i:i + size]


def _run(tasks: list[tuple[list[int], list[Any]]], base: Insect | None, settings: _Settings,
         executor: Executor | None, progress: bool) -> dict[int, dict[str, Any]]:
    """Solve every chunk (in process or on the executor); rows by flat point index."""
    from tqdm import tqdm  # the text bar (tqdm.auto's notebook bar needs ipywidgets)

    rows: dict[int, dict[str, Any]] = {}
    total = sum(len(idx) for idx, _ in tasks)
    with tqdm(total=total, disable=not progress, unit="orbit", desc="hover sweep") as bar:
        if executor is None:
            for idx, points in tasks:
                rows.update(zip(idx, _solve_chunk(base, points, settings), strict=True))
                bar.update(len(idx))
        else:
            futures = {executor.submit(_solve_chunk, base, points, settings): idx
                       for idx, points in tasks}
            for future in as_completed(futures):
                idx = futures[future]
                rows.update(zip(idx, future.result(), strict=True))
                bar.update(len(idx))
    return rows


def sweep_hover(
    insect: Insect | Sequence[Insect],
    grid: Mapping[str, Sequence[float]] | None = None,
    *,
    executor: Executor | None = None,
    progress: bool = True,
    chunk_size: int = DEFAULT_CHUNK,
    backend: str = "auto",
    amplitude_tol_deg: float = kernel.AMPLITUDE_TOL_DEG,
    multiplier_tol: float = kernel.MULTIPLIER_TOL,
    settings: SolverSettings | None = None,
    aerodynamics: str = "linear",
) -> pandas.DataFrame:
    """Hover orbit and Floquet multipliers (eqs. 29, 42-49) at every point of a parameter grid.

    Parameters
    ----------
    insect : Insect or sequence of Insect
        The base insect whose fields ``grid`` varies; or, without ``grid``, the list of insects
        to evaluate (one row each).
    grid : mapping of str to sequence of float, optional
        Insect field -> values (SI units, e.g. ``{"frequency": np.linspace(20, 32, 100)}``); the
        sweep covers the full grid of all combinations (C order: last field fastest).
    executor : concurrent.futures.Executor, optional
        Where to run the chunks (default: this process). E.g.
        ``ProcessPoolExecutor(2)`` or ``dask.distributed.Client(...).get_executor()``.
    progress : bool
        Show a tqdm progress bar.
    chunk_size : int
        Consecutive points per task (warm starts run within a chunk), >= 1.
    backend : {"auto", "compiled", "adaptive", "fixed-step"}
        ``"auto"``: for the linear loads the compiled kernel if numba is installed, else the
        adaptive path (with a warning); for the blade-element loads the fixed-step path (as
        :func:`~flapping.hover.find_hover_orbit` decides, with its fallback to the adaptive
        path). ``"adaptive"``: the scipy reference path; ``"fixed-step"``: Newton on the
        fixed-step period map (:data:`flapping.hover.BACKENDS`), any loads model, each point
        warm-started with its neighbour's step count. The row's ``backend`` says which path
        solved it.
    amplitude_tol_deg, multiplier_tol : float
        The kernel's accuracy targets for Phi [deg] and every multiplier (absolute).
    settings : SolverSettings, optional
        Solver options of the points solved off the kernel, passed to
        :func:`~flapping.hover.find_hover_orbit` and
        :func:`~flapping.hover.stability.hover_stability` (each reads the fields it uses, with
        its own default for a field left at None). A ``method`` other than ``"DOP853"`` sends
        every point to the adaptive path.
    aerodynamics : {"linear", "small-angle", "exact"}
        Loads model of every point (:class:`~flapping.model.dynamics.LongitudinalDynamics`;
        ``"linear"`` is eq. 29).

    Returns
    -------
    pandas.DataFrame
        One row per point in grid order: the swept fields (or ``insect`` and ``name`` for a list),
        then :data:`COLUMNS`: ``amplitude_deg``; ``u0, w0, q0, theta0`` (SI); the multipliers
        ``mu1..mu4`` (real and imaginary parts, by descending modulus); ``max_abs_mu``;
        ``stable``; ``converged`` (a hover orbit was found: false for one that drifts);
        ``status`` (:class:`~flapping.hover.HoverStatus`, -1 for a failed point);
        ``forward_speed`` and ``climb_speed`` (cycle means of the inertial velocities [m/s]);
        the error estimates ``amplitude_error_deg`` and ``multiplier_error`` (largest absolute
        error of a multiplier: the kernel's estimate, or on the fixed-step path
        :attr:`~flapping.hover.stability.HoverStability.multiplier_error`, the multipliers being
        that analysis's; NaN on the adaptive path); ``nit``; ``n_steps`` (per half-stroke);
        ``backend``; ``message`` (why a point failed; empty otherwise).

    Raises
    ------
    ValueError
        For a bad grid or argument (a bad *point*, e.g. an insect that cannot trim, is a row):
        a string for ``insect`` (build it with :func:`flapping.model.presets.preset`), or a
        grid of more than :data:`MAX_GRID_POINTS` points.
    ImportError
        If pandas or tqdm is missing (``pip install flapping[sweep]``).
    """
    import pandas

    chunk_size = _validation.integer("chunk_size", chunk_size, low=1)
    if settings is not None and not isinstance(settings, SolverSettings):
        raise ValueError(f"`settings` must be a SolverSettings; got {settings!r} "
                         f"({type(settings).__name__})")
    aerodynamics = _validation.choice("aerodynamics", aerodynamics, AERODYNAMIC_MODELS)
    settings_ = _Settings(_backend(backend, aerodynamics),
                          _validation.positive("amplitude_tol_deg", amplitude_tol_deg),
                          _validation.positive("multiplier_tol", multiplier_tol), settings,
                          aerodynamics)
    if executor is not None and not isinstance(executor, Executor):
        raise ValueError(f"`executor` must be a concurrent.futures.Executor; got {executor!r}")
    base, points, params, shape = _points(insect, grid)
    order = _snake(shape)
    tasks = [(idx, [points[i] for i in idx]) for idx in _chunks(order, chunk_size)]
    rows = _run(tasks, base, settings_, executor, progress)
    table = pandas.DataFrame([rows[i] for i in range(len(points))], columns=list(COLUMNS))
    return pandas.concat([pandas.DataFrame(params), table], axis=1)


def _points(insect: Insect | Sequence[Insect], grid: Mapping[str, Sequence[float]] | None
            ) -> tuple[Insect | None, list[Any], dict[str, list[Any]], tuple[int, ...]]:
    """(base insect, points, parameter columns, grid shape) of the sweep's arguments."""
    _refuse_name("insect", insect)
    if grid is None:
        if isinstance(insect, Insect) or not isinstance(insect, Sequence) or not insect:
            raise ValueError("without `grid`, `insect` must be a non-empty sequence of Insect")
        for i, x in enumerate(insect):
            _refuse_name(f"insect[{i}]", x)
        insects = [_validation.instance(f"insect[{i}]", x, Insect) for i, x in enumerate(insect)]
        params: dict[str, list[Any]] = {"insect": list(range(len(insects))),
                                         "name": [x.name for x in insects]}
        return None, list(insects), params, (len(insects),)
    if not isinstance(insect, Insect):
        raise ValueError(f"with `grid`, `insect` must be an Insect; got {type(insect).__name__}")
    base = insect
    axes = _axes(grid)
    points: list[Any] = grid_points(axes)
    columns: dict[str, list[Any]] = {name: [point[name] for point in points] for name in axes}
    return base, points, columns, tuple(len(v) for v in axes.values())



def _refuse_name(name: str, value: object) -> None:
    """A ValueError for a string where an :class:`Insect` belongs (a preset's name, say)."""
    if not isinstance(value, str):
        return
    if value in preset_names():
        hint = f"flapping.model.presets.preset({value!r}) builds that preset"
    else:
        hint = f"flapping.model.presets.preset(name) builds one of {preset_names()}"
    raise ValueError(f"`{name}` must be an Insect, not the string {_validation._show(value)}: "
                     f"{hint}")

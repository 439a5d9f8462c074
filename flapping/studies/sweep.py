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
- the points are visited along the grid's lines (the last field varies fastest), each line cut
  into segments of at most :data:`SEGMENT` points; a segment's first point starts cold, and
  each later one from its neighbour's step count and from (x0, Phi) predicted by the cubic
  through the last four answers of the segment, so most take two Newton iterations instead of
  five. The segments depend on the grid alone, so the table is the same, bit for bit, however
  the segments are grouped into chunks (``chunk_size``) and whichever executor runs them;
- the chunks run in this process by default, or on any :class:`concurrent.futures.Executor`:
  a ``ProcessPoolExecutor`` for local cores, or ``dask.distributed.Client.get_executor()`` for a
  cluster.

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
from flapping.backends import Backend, OptionWarning, backend_name
from flapping.errors import ConvergenceError, HoverDriftWarning, caused_by_interrupt
from flapping.hover import DEFAULT_BACKEND, HoverOrbit, HoverProblem, HoverStatus
from flapping.hover.orbit import Options

# the hover entry without the deprecation of the option routes the sweep forwards
from flapping.hover.orbit import _find_hover_orbit as find_hover_orbit
from flapping.hover.sixdof import find_sixdof_hover_orbit
from flapping.hover.stability import hover_stability
from flapping.model.dynamics import AERODYNAMIC_MODELS
from flapping.model.morphology import Insect
from flapping.model.presets import preset_names
from flapping.periodic.settings import SolverSettings
from flapping.results import Status, status_of
from flapping.studies._path import Guess, Step, WarmStart, follow

if TYPE_CHECKING:  # pragma: no cover
    import pandas

__all__ = ["SWEEPABLE", "COLUMNS", "LATERAL_COLUMNS", "MAX_GRID_POINTS", "SEGMENT",
           "SweepInterrupted", "sweep_hover", "grid_points", "stop_process_pool"]

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

#: The columns ``dof=6`` adds after :data:`COLUMNS`: the lateral multipliers of (v, p, r, roll)
#: by descending modulus, the largest modulus, whether all are inside the unit circle, the
#: monodromy's coupling of the two sets, the six-dof analysis's multiplier error estimate and its
#: path (:class:`~flapping.hover.sixdof.SixDofStability`).
LATERAL_COLUMNS: tuple[str, ...] = (
    "lat_mu1_real", "lat_mu1_imag", "lat_mu2_real", "lat_mu2_imag", "lat_mu3_real",
    "lat_mu3_imag", "lat_mu4_real", "lat_mu4_imag", "lat_max_abs_mu", "lat_stable", "coupling",
    "sixdof_multiplier_error", "sixdof_backend",
)

#: Points per chunk at least: the unit of work sent to an executor (whole segments).
DEFAULT_CHUNK = 50

#: Most points of a segment: the run of consecutive points on one grid line (or of a list of
#: insects) within which each solve is warm-started from the ones before. A constant, so that
#: every point's start, and so the table, depends on the grid alone.
SEGMENT = 50

#: Largest number of points of a grid (the product of its axes' lengths): ~30 min of solves on
#: one core with the compiled kernel, and the table's rows fill a few GB. A larger grid is refused
#: at once rather than enumerated.
MAX_GRID_POINTS = 10**7

#: The failures of one point that become its row (the sweep goes on); others propagate.
_POINT_FAILURES = (ValueError, ConvergenceError, ArithmeticError, np.linalg.LinAlgError)


@dataclass(frozen=True)
class _Settings:
    """What every chunk needs besides its points (picklable)."""

    backend: Backend | str
    kernel_options: dict[str, float]
    solver: SolverSettings | None = None
    aerodynamics: str = "linear"
    dof: int = 4


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


def _segments(shape: tuple[int, ...]) -> list[list[int]]:
    """Flat C-order indices of the grid's points, cut into segments: runs of at most
    :data:`SEGMENT` consecutive points on one line of the last axis."""
    size = math.prod(shape)
    line = shape[-1]
    return [list(range(start + i, start + min(i + SEGMENT, line)))
            for start in range(0, size, line) for i in range(0, line, SEGMENT)]


# =========================================================================== one point
def _status_columns(status: HoverStatus | Status) -> dict[str, Any]:
    """``status`` as its word and ``converged``, derived from it (a hover orbit was found)."""
    return {"status": str(status), "converged": status == HoverStatus.HOVER}


def _row(orbit: HoverOrbit | None, mu: np.ndarray | None, message: str,
         backend: str, mu_error: float = math.nan,
         failure: Status = Status.SUCCESS) -> dict[str, Any]:
    """The result columns of one point (NaN where there is no answer).

    ``status`` is one word: the orbit's :class:`~flapping.results.HoverStatus` where the point
    solved, the solve's :class:`~flapping.results.Status` (``failure``) where it did not.
    ``converged`` is derived from it, true only for a hover orbit: a periodic orbit that drifts
    (a hinge off the centre of gravity with the amplitude as the only trim) is a row with its
    drift speeds, ``status`` ``"drifting"`` and a message, never a converged hover.
    """
    row: dict[str, Any] = dict.fromkeys(COLUMNS, math.nan)
    row.update(stable=False, nit=0, n_steps=0, backend=backend, message=message,
               **_status_columns(failure))
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
               **_status_columns(status), forward_speed=v["forward"],
               climb_speed=v["climb"], nit=orbit.nit, backend=orbit.backend,
               message="" if hover else orbit.message,
               amplitude_error_deg=math.degrees(orbit.amplitude_error), multiplier_error=mu_error)
    if orbit.kernel is not None:
        row.update(n_steps=orbit.kernel.n_steps)
    elif orbit.fixed_step is not None:
        row.update(n_steps=orbit.fixed_step.n_steps)
    row.update(zip(("u0", "w0", "q0", "theta0"), orbit.x0.tolist(), strict=True))
    for i, m in enumerate(mus[:4], start=1):
        row[f"mu{i}_real"], row[f"mu{i}_imag"] = m.real, m.imag
    return row


def _lateral_row(six: Any) -> dict[str, Any]:
    """The :data:`LATERAL_COLUMNS` of a point (NaN where there is no six-dof analysis)."""
    row: dict[str, Any] = dict.fromkeys(LATERAL_COLUMNS, math.nan)
    row.update(lat_stable=False, sixdof_backend="")
    if six is None:
        return row
    mus = np.asarray(six.lateral.multipliers).tolist()
    for i, m in enumerate(mus, start=1):
        row[f"lat_mu{i}_real"], row[f"lat_mu{i}_imag"] = m.real, m.imag
    modulus = [abs(m) for m in mus]
    row.update(lat_max_abs_mu=max(modulus), lat_stable=all(m < 1.0 for m in modulus),
               coupling=six.coupling, sixdof_multiplier_error=six.multiplier_error,
               sixdof_backend=six.orbit.backend)
    return row


def _multipliers(orbit: HoverOrbit, solver: SolverSettings | None = None
                 ) -> tuple[np.ndarray, float]:
    """The orbit's Floquet multipliers and their error estimate: the kernel's (its last Newton
    integration), or those of :func:`~flapping.hover.stability.hover_stability`, on the
    fixed-step path for an orbit found there (its estimate: the change from n to 2n steps)."""
    floquet = orbit.floquet if orbit.kernel is not None else None
    if floquet is None:  # the fixed-step analysis doubles the steps for its error estimate
        floquet = hover_stability(orbit, settings=solver).floquet
    return floquet.multipliers, floquet.multiplier_error


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


def _solve_point(point: _Point, guess: Guess[tuple[Any, ...]] | None,
                 settings: _Settings) -> tuple[Any, ...]:
    """One point: from the previous orbit's x0, Phi and step count, or cold without a guess;
    with ``dof=6`` also the six-degree-of-freedom orbit from the planar one, and its eight
    multipliers (:func:`~flapping.hover.sixdof.find_sixdof_hover_orbit`, its default path)."""
    problem = HoverProblem(point.insect, settings.aerodynamics)
    kernel_options = dict(settings.kernel_options)
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
    planar = (orbit, *_multipliers(orbit, settings.solver))
    if settings.dof == 4:
        return planar
    six = find_sixdof_hover_orbit(point.insect, aerodynamics=settings.aerodynamics,
                                  planar_orbit=orbit)
    return (*planar, hover_stability(six))


def _unknowns(point: _Point, result: tuple[Any, ...]) -> np.ndarray:
    """The continued unknowns of a solved point: (u0, w0, q0, theta0, Phi)."""
    return np.append(result[0].x0, result[0].amplitude)


#: Degree of the prediction of a point's (x0, Phi) from the solved points before it on the same
#: grid line (:class:`~flapping.studies._path.WarmStart`): the cubic through four. Newton
#: iterations a point on the hawkmoth (200 frequencies 20-32 Hz / 200 hinge heights 0-5 mm /
#: 1000 frequencies), by degree: 1: 3.06 / 2.08 / 2.32; 2: 2.34 / 2.08 / 2.09; 3: 2.19 / 1.82 /
#: 2.09; 4: 2.15 / 1.89 / 2.03; the previous answer alone: 3.18 / 3.04 / -.
_PREDICTION_ORDER = 3


def _solve_chunk(base: Insect | None, segments: Sequence[Sequence[Mapping[str, Any] | Insect]],
                 settings: _Settings) -> list[dict[str, Any]]:
    """Solve the segments of a chunk, one after the other; one row per point, in order.

    Module-level (picklable) so that executors can run it.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", HoverDriftWarning)  # the row records the drift
        # checked once for the sweep (sweep_hover warns there): a warm start's step count is
        # an option of the path that solved the neighbour, which this point may not run
        warnings.simplefilter("ignore", OptionWarning)
        return [row for segment in segments for row in _solve_segment(base, segment, settings)]


def _solve_segment(base: Insect | None, points: Sequence[Mapping[str, Any] | Insect],
                   settings: _Settings) -> list[dict[str, Any]]:
    """Solve consecutive points, each warm-started from the previous answers; one row each.

    The first point starts cold. A warm start that fails (a neighbour across a fold) is retried
    cold. A point's failure (bad parameters, no convergence) is its row's message, and the next
    point starts cold.
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
    steps = follow(path, warm, record=_POINT_FAILURES)
    return [_row_of(step, backend_name(settings.backend), settings.dof) for step in steps]


def _row_of(step: Step[Any, tuple[Any, ...]], backend: str, dof: int = 4) -> dict[str, Any]:
    """The row of a solved or failed point (with ``dof=6`` its :data:`LATERAL_COLUMNS` too)."""
    if step.result is None:
        assert step.error is not None
        row = _row(None, None, f"{type(step.error).__name__}: {step.error}", backend,
                   failure=status_of(step.error))
        return row if dof == 4 else {**row, **_lateral_row(None)}
    orbit, mu, mu_error = step.result[:3]
    row = _row(orbit, mu, "", backend, mu_error)
    return row if dof == 4 else {**row, **_lateral_row(step.result[3])}


# =========================================================================== the sweep
def _checked_backend(backend: Any, aerodynamics: str, base: Insect,
                     kernel_options: dict[str, float], solver: SolverSettings | None
                     ) -> Backend | str:
    """The sweep's backend argument, checked once: the path the first point would run is
    chosen as every point's is (:func:`~flapping.hover.problem.choose_backend`), which refuses a
    path that does not apply and warns about options of another path."""
    options = Options.of(backend, kernel_options=kernel_options, settings=solver)
    try:
        problem = HoverProblem(base, aerodynamics)
    except ValueError:
        return options.requested  # an insect that cannot hover is a point (its row says why)
    options.choose(problem)
    return options.requested


def _tasks(segments: list[list[int]], points: list[Any], size: int
           ) -> list[tuple[list[int], list[list[Any]]]]:
    """Whole segments grouped into chunks of at least ``size`` points (the last may be less)."""
    tasks: list[tuple[list[int], list[list[Any]]]] = []
    idx: list[int] = []
    group: list[list[Any]] = []
    for segment in segments:
        idx += segment
        group.append([points[i] for i in segment])
        if len(idx) >= size:
            tasks.append((idx, group))
            idx, group = [], []
    if idx:
        tasks.append((idx, group))
    return tasks


def _run(tasks: list[tuple[list[int], list[list[Any]]]], base: Insect | None,
         settings: _Settings, executor: Executor | None, progress: bool,
         rows: dict[int, dict[str, Any]]) -> None:
    """Solve every chunk (in process or on the executor) into ``rows``, by flat point index
    (filled chunk by chunk, so that an interruption keeps the chunks finished)."""
    from tqdm import tqdm  # the text bar (tqdm.auto's notebook bar needs ipywidgets)

    total = sum(len(idx) for idx, _ in tasks)
    with tqdm(total=total, disable=not progress, unit="orbit", desc="hover sweep") as bar:
        if executor is None:
            for idx, points in tasks:
                rows.update(zip(idx, _solve_chunk(base, points, settings), strict=True))
                bar.update(len(idx))
        else:
            futures = {executor.submit(_solve_chunk, base, points, settings): idx
                       for idx, points in tasks}
            try:
                for future in as_completed(futures):
                    idx = futures[future]
                    rows.update(zip(idx, future.result(), strict=True))
                    bar.update(len(idx))
            except BaseException:
                # Ctrl-C or a failure: the chunks not started are not run for nothing (the
                # executor is the caller's: its workers are its owner's to stop)
                for future in futures:
                    future.cancel()
                raise


def stop_process_pool(pool: Executor, timeout: float = 5.0) -> None:
    """Stop a ``ProcessPoolExecutor`` now: cancel its pending work, end its workers, and wait.

    ``shutdown(cancel_futures=True)`` cancels the chunks not started but leaves the running
    ones running, and the interpreter's exit then joins them: after Ctrl-C (the workers ignore
    SIGINT, the parent's to handle) the command waited for chunks of minutes, and a second
    Ctrl-C landed in that join (a traceback from ``concurrent.futures``, the process never
    exiting, its children left behind). Here the workers are terminated (SIGTERM, then SIGKILL
    after ``timeout`` seconds) and reaped, and the pool's manager thread is given ``timeout``
    seconds to end. Another executor is shut down without waiting.

    Parameters
    ----------
    pool : concurrent.futures.Executor
        The pool to stop (its results are abandoned).
    timeout : float
        Seconds to wait for each worker after SIGTERM, in (0, 60].
    """
    timeout = _validation.real("timeout", timeout, low=0.0, high=60.0, low_open=True, unit="s")
    # ProcessPoolExecutor keeps its workers in `_processes` (pid -> Process); Python 3.14 adds
    # terminate_workers(), 3.11-3.13 have no public way to end a running task.
    processes = list((getattr(pool, "_processes", None) or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        if process.is_alive():
            process.terminate()
    for process in processes:
        process.join(timeout)
        if process.is_alive():
            process.kill()
            process.join(timeout)
    # The pool's manager thread sees its workers gone and ends; bounded, as it can hang on a
    # worker killed while writing a result (a half message in the pipe)
    manager = getattr(pool, "_executor_manager_thread", None)
    if manager is not None:
        manager.join(timeout)


class SweepInterrupted(KeyboardInterrupt):
    """Ctrl-C during :func:`sweep_hover`: a KeyboardInterrupt that keeps the rows finished.

    Attributes
    ----------
    table : pandas.DataFrame
        The sweep's table with the points solved before the interruption (the others absent).
    """

    def __init__(self, table: pandas.DataFrame, total: int) -> None:
        super().__init__(f"hover sweep interrupted: {len(table)} of {total} points solved "
                         "(their rows are in this exception's `table`)")
        self.table = table



def sweep_hover(
    insect: Insect | Sequence[Insect],
    grid: Mapping[str, Sequence[float]] | None = None,
    *,
    executor: Executor | None = None,
    progress: bool = True,
    chunk_size: int = DEFAULT_CHUNK,
    backend: Backend | str = DEFAULT_BACKEND,
    amplitude_tol_deg: float | None = None,
    multiplier_tol: float | None = None,
    settings: SolverSettings | None = None,
    aerodynamics: str = "linear",
    dof: int = 4,
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
        Points per task at least (whole segments of :data:`SEGMENT` points), >= 1. The table
        does not depend on it.
    backend : "auto", "compiled", "fixed-step", "adaptive", or a backend object
        How every point is solved (:mod:`flapping.backends`), as
        :func:`~flapping.hover.find_hover_orbit` runs it: ``"auto"`` is the compiled kernel for
        the linear loads if numba is installed, else the adaptive path (with a warning), and
        the fixed-step path for the blade-element loads, each with its fallback to the adaptive
        path. A point is warm-started with its neighbour's step count. The row's ``backend``
        says which path solved it.
    amplitude_tol_deg, multiplier_tol : float, optional
        Shorthands for :class:`~flapping.backends.Compiled`'s accuracy targets for Phi [deg]
        and every multiplier (absolute).
    settings : SolverSettings, optional
        Shorthand for the adaptive path's options (:class:`~flapping.backends.Adaptive`), as
        :func:`~flapping.hover.find_hover_orbit` and
        :func:`~flapping.hover.stability.hover_stability` read it. A ``method`` other than
        ``"DOP853"`` sends every point to the adaptive path.
    aerodynamics : {"linear", "small-angle", "exact"}
        Loads model of every point (:class:`~flapping.model.dynamics.LongitudinalDynamics`;
        ``"linear"`` is eq. 29).
    dof : {4, 6}
        With 6, every point is also solved and analysed in six degrees of freedom from its
        planar orbit (:func:`~flapping.hover.sixdof.find_sixdof_hover_orbit` and
        :func:`~flapping.hover.stability.hover_stability`: the compiled six-dof path for the
        linear loads, the adaptive Python path for the blade-element ones, ~40 s a point), and
        the table adds :data:`LATERAL_COLUMNS`; the insect needs its roll and yaw inertia (a
        point without them is a failed row). The planar columns keep their meaning.

    Returns
    -------
    pandas.DataFrame
        One row per point in grid order: the swept fields (or ``insect`` and ``name`` for a list),
        then :data:`COLUMNS`: ``amplitude_deg``; ``u0, w0, q0, theta0`` (SI); the multipliers
        ``mu1..mu4`` (real and imaginary parts, by descending modulus); ``max_abs_mu``;
        ``stable``; ``converged`` (a hover orbit was found: ``status == "hover"``, false for
        one that drifts); ``status``, one word (:data:`~flapping.results.STATUS_WORDS`): the
        orbit's :class:`~flapping.results.HoverStatus` (``"hover"``, ``"drifting"``,
        ``"climbing"``) for a solved point, the solve's :class:`~flapping.results.Status`
        (``"invalid_input"``, ``"max_iterations"``, ...) for a failed one;
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
    SweepInterrupted
        On Ctrl-C (a KeyboardInterrupt, also where numba surfaces it as a SystemError), with the
        rows of the chunks finished in its ``table``.
    """
    import pandas

    chunk_size = _validation.integer("chunk_size", chunk_size, low=1)
    aerodynamics = _validation.choice("aerodynamics", aerodynamics, AERODYNAMIC_MODELS)
    dof = _validation.choice("dof", dof, (4, 6))
    columns = list(COLUMNS) + (list(LATERAL_COLUMNS) if dof == 6 else [])
    kernel_options = {k: v for k, v in (("amplitude_tol_deg", amplitude_tol_deg),
                                        ("multiplier_tol", multiplier_tol)) if v is not None}
    if executor is not None and not isinstance(executor, Executor):
        raise ValueError(f"`executor` must be a concurrent.futures.Executor; got {executor!r}")
    base, points, params, shape = _points(insect, grid)
    requested = _checked_backend(backend, aerodynamics, points[0] if base is None else base,
                                 kernel_options, settings)
    settings_ = _Settings(requested, kernel_options, settings, aerodynamics, dof)
    tasks = _tasks(_segments(shape), points, chunk_size)
    rows: dict[int, dict[str, Any]] = {}
    try:
        _run(tasks, base, settings_, executor, progress, rows)
    except (KeyboardInterrupt, SystemError) as exc:
        if not caused_by_interrupt(exc):
            raise
        done = sorted(rows)
        partial = pandas.concat([pandas.DataFrame(params).iloc[done].reset_index(drop=True),
                                 pandas.DataFrame([rows[i] for i in done],
                                                  columns=columns)], axis=1)
        raise SweepInterrupted(partial, len(points)) from None
    table = pandas.DataFrame([rows[i] for i in range(len(points))], columns=columns)
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

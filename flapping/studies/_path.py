"""Warm-started solves along a path of problems: the one loop behind the studies' sweeps.

A path is a sequence of points (insects, or whatever a ``solve`` takes), each at a coordinate s
(a grid index, the homotopy fraction, log f, a hinge height, or a tuple of a grid's values). Each
point is solved from what the path has learnt so far (:class:`Guess`): the previous point's result
and, when the caller names the continued unknowns, their prediction at s -- the previous point's,
or the polynomial through the last two (the secant) or more solved points that lie on one line
with s. :class:`WarmStart` holds that memory and makes one attempt (with a cold restart if a
warm start fails); :func:`follow` walks a given list of points, recording or raising failures;
:func:`follow_halving` walks s from 0 to 1 in steps that are halved when a point fails.

:func:`~flapping.studies.sweep.sweep_hover`, :func:`~flapping.studies.atlas.hover_by_homotopy`,
:func:`~flapping.studies.atlas.frequency_sweep` and
:func:`~flapping.studies.control.passive_sweep` all walk their paths with it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Generic, TypeVar

import numpy as np

__all__ = ["Coordinate", "Guess", "Step", "WarmStart", "follow", "follow_halving"]

P = TypeVar("P")
R = TypeVar("R")

#: Exception types, as ``except`` takes them.
Errors = tuple[type[BaseException], ...]

#: A point's coordinate on its path: a number, or a point of a grid (one number per axis).
Coordinate = float | tuple[float, ...]

#: The coordinate type of one path (a path's steps all have the same kind).
S = TypeVar("S", float, tuple[float, ...])

#: Relative distance from the line through the last two solved points below which a coordinate
#: counts as on it (grid values are exact, or rounded once by ``linspace``).
_ON_LINE_RTOL = 1e-9


@dataclass(frozen=True)
class Guess(Generic[R]):
    """What a warm-started solve starts from.

    Attributes
    ----------
    previous : object
        The result of the last point solved on the path.
    unknowns : ndarray or None
        The continued unknowns predicted at this point (the last point's, or the secant through
        the last two); None if the path continues none.
    """

    previous: R
    unknowns: np.ndarray | None


@dataclass(frozen=True)
class Step(Generic[S, R]):
    """One point of a path: its coordinate, and its result or why it failed.

    Attributes
    ----------
    s : float or tuple of float
        The point's coordinate on the path.
    result : object or None
        What ``solve`` returned (None if the point failed).
    error : BaseException or None
        The recorded failure (None if the point was solved).
    """

    s: S
    result: R | None
    error: BaseException | None = None


class WarmStart(Generic[P, R]):
    """The memory of a path (its last two solved points) and one attempt at the next point.

    Parameters
    ----------
    solve : callable
        ``solve(point, guess)`` with ``guess`` a :class:`Guess`, or None for a cold start;
        returns the point's result or raises.
    unknowns : callable, optional
        ``unknowns(point, result)``: the continued unknowns of a solved point (a 1-D array);
        without it a guess carries the previous result only.
    secant : bool
        Predict the unknowns along the secant through the last two solved points (by their
        coordinates), else take the last point's.
    restart : tuple of exception types
        Failures of a warm-started solve that are retried once from a cold start.
    order : int
        Degree of the prediction with ``secant``: the polynomial through the last ``order + 1``
        solved points (1: the secant; its error is O(step^2), that of degree d O(step^(d+1)), so
        on a smooth path a higher degree can save the Newton iteration the secant's error costs).
        Only the trailing points on one line with the new coordinate take part (a 2-D grid's
        snake turns a corner: there the guess is the last answer).
    """

    def __init__(self, solve: Callable[[P, Guess[R] | None], R],
                 unknowns: Callable[[P, R], np.ndarray] | None = None, *, secant: bool = False,
                 restart: Errors = (), order: int = 1) -> None:
        self.solve = solve
        self.unknowns = unknowns
        self.secant = secant
        self.restart = restart
        self.order = max(1, order) if secant else 0
        self.solved: list[tuple[Coordinate, R, np.ndarray | None]] = []

    def add(self, s: Coordinate, point: P, result: R) -> None:
        """Remember a solved point (only the last ``order + 1`` are kept)."""
        u = None if self.unknowns is None else self.unknowns(point, result)
        self.solved = [*self.solved[max(0, len(self.solved) - self.order):], (s, result, u)]

    def forget(self) -> None:
        """Start the next point cold (after a failure, its neighbour is no guide)."""
        self.solved = []

    def guess(self, s: Coordinate) -> Guess[R] | None:
        """The guess at coordinate s (None before any point is solved)."""
        if not self.solved:
            return None
        _, previous, u1 = self.solved[-1]
        if u1 is None or not self.secant or len(self.solved) == 1:
            return Guess(previous, u1)
        positions = _line_positions([c for c, _, _ in self.solved], s)
        if positions is None:
            return Guess(previous, u1)
        *known, target = positions
        if len(known) == 2:  # the secant, u1 + k (u1 - u0)
            u0 = self.solved[-2][2]
            assert u0 is not None
            return Guess(previous, u1 + target * (u1 - u0))
        used = [u for _, _, u in self.solved[len(self.solved) - len(known):] if u is not None]
        weights = np.array(_lagrange_weights(known, target))
        return Guess(previous, weights @ np.array(used))

    def attempt(self, s: Coordinate, point: P) -> R:
        """Solve ``point`` at s from the guess (then cold, on a ``restart`` failure); remember it.

        Raises
        ------
        Exception
            Whatever the last ``solve`` raised.
        """
        guess = self.guess(s)
        try:
            result = self.solve(point, guess)
        except self.restart:
            if guess is None:
                raise
            result = self.solve(point, None)
        self.add(s, point, result)
        return result


def _as_tuple(s: Coordinate) -> tuple[float, ...]:
    return (float(s),) if isinstance(s, (int, float)) else tuple(s)


def _line_positions(solved: Sequence[Coordinate], s: Coordinate) -> list[float] | None:
    """Positions along the line through the last two solved coordinates: of the trailing solved
    ones on it (at least those two), then of s; None if s is off that line or they coincide.

    The unit is the last step: the last solved point is at 0, the one before at -1.
    """
    if all(type(c) is tuple and len(c) == 1 for c in (*solved, s)):
        return _number_line_positions([c[0] for c in (*solved, s)])  # type: ignore[index]
    points = [_as_tuple(c) for c in (*solved, s)]
    last, before = points[-2], points[-3]
    moved = [i for i, (a, b) in enumerate(zip(last, before, strict=True)) if a != b]
    if not moved:
        return None
    if len(moved) == 1:  # along one axis (a number line, a grid line): exact comparisons
        k = moved[0]
        fixed = last[:k] + last[k + 1:]
        step = last[k] - before[k]

        def position(c: tuple[float, ...]) -> float | None:
            return (c[k] - last[k]) / step if c[:k] + c[k + 1:] == fixed else None
    else:
        vector = [a - b for a, b in zip(last, before, strict=True)]
        step2 = math.fsum(d * d for d in vector)

        def position(c: tuple[float, ...]) -> float | None:
            v = [a - b for a, b in zip(c, last, strict=True)]
            t = math.fsum(a * d for a, d in zip(v, vector, strict=True)) / step2
            off = math.fsum((a - t * d) ** 2 for a, d in zip(v, vector, strict=True))
            return t if off <= _ON_LINE_RTOL**2 * max(step2, math.fsum(a * a for a in v)) else None

    target = position(points[-1])
    if target is None:
        return None
    known = [-1.0, 0.0]  # oldest first, as ``solved``
    for c in reversed(points[:-3]):
        t = position(c)
        if t is None:
            break
        known.insert(0, t)
    return [*known, target]


def _number_line_positions(values: list[float]) -> list[float] | None:
    """:func:`_line_positions` for coordinates on one number line (a 1-D grid): the same
    arithmetic, without the general case's tuples (it runs at every point of a sweep)."""
    last, before = values[-2], values[-3]
    if last == before:
        return None
    step = last - before
    return [*((c - last) / step for c in values[:-3]), -1.0, 0.0, (values[-1] - last) / step]


def _lagrange_weights(nodes: Sequence[float], x: float) -> list[float]:
    """Weights of the values at ``nodes`` in the interpolating polynomial's value at x."""
    weights = []
    for i, a in enumerate(nodes):
        w = 1.0
        for j, b in enumerate(nodes):
            if j != i:
                w *= (x - b) / (a - b)
        weights.append(w)
    return weights


def follow(path: Iterable[tuple[S, P]], warm: WarmStart[P, R], *,
           record: Errors = ()) -> list[Step[S, R]]:
    """Solve the points of a path in order, each warm-started from the ones before.

    Parameters
    ----------
    path : iterable of (coordinate, point)
        Coordinates and points, in the order to solve them (consumed lazily).
    warm : WarmStart
        How to solve a point; it may hold solved points already (e.g. the path's start).
    record : tuple of exception types
        Failures recorded as the point's :class:`Step` (the next point then starts cold); any
        other failure propagates.

    Returns
    -------
    list of Step
        One per point, in order.
    """
    steps: list[Step[S, R]] = []
    for s, point in path:
        try:
            result = warm.attempt(s, point)
        except record as exc:
            steps.append(Step(s, None, exc))
            warm.forget()
            continue
        steps.append(Step(s, result))
    return steps


def follow_halving(member: Callable[[float], P], warm: WarmStart[P, R], *, n_steps: int,
                   max_failures: int, retry: Errors,
                   stalled: Callable[[float, int, BaseException], BaseException]
                   ) -> tuple[list[Step[float, R]], int]:
    """Walk s from 0 to 1 in ``n_steps`` equal steps, halving the step where a point fails.

    The steps do not grow again. ``warm`` must already hold the point at s = 0.

    Parameters
    ----------
    member : callable
        ``member(s)``: the point at s in (0, 1] (``member(1)`` the target).
    warm : WarmStart
        How to solve a point, holding the start.
    n_steps : int
        Initial number of steps, >= 1.
    max_failures : int
        Largest number of halvings, >= 0.
    retry : tuple of exception types
        The failures that halve the step.
    stalled : callable
        ``stalled(s, halvings, exc)``: the exception to raise when a failure exceeds
        ``max_failures`` (``s`` the last coordinate solved, ``exc`` the last failure).

    Returns
    -------
    steps : list of Step
        The points solved, in order (the last at s = 1).
    failures : int
        The halvings made.
    """
    s, step, failures = 0.0, 1.0 / n_steps, 0
    steps: list[Step[float, R]] = []
    while s < 1.0:
        s_next = 1.0 if s + step > 1.0 - 1e-9 else s + step
        point = member(s_next)
        try:
            result = warm.attempt(s_next, point)
        except retry as exc:
            failures += 1
            if failures > max_failures:
                raise stalled(s, failures - 1, exc) from exc
            step /= 2.0
            continue
        s = s_next
        steps.append(Step(s, result))
    return steps, failures

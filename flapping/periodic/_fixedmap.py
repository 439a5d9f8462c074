"""Package-internal: the one-period map of a fixed-step DOP853 integration, and its derivative.

:class:`PeriodMap` integrates a piecewise-smooth ``f(t, x[, params])`` over one period with the
8th-order Dormand-Prince formula (:mod:`flapping.periodic._tableau`) at ``n`` equal steps per
segment, restarted at the breakpoints. The step count is fixed, so the end state is a smooth
function of the initial state and the parameters (no step-size decisions jump as they move): a
Newton iteration on it converges to rounding level, and its derivative is

* with ``jac`` (and ``param_jac``, if there are parameters): the variational equations
  integrated with the *same* stages, which is the exact derivative of the discrete map
  (Runge-Kutta methods commute with linearisation), up to the accuracy of ``jac`` itself;
* without: central differences of the discrete map, all perturbed trajectories integrated
  together (one batch per step, so the per-step bookkeeping is paid once).

Per stage, one call of the user callable per trajectory; the rest is a few NumPy operations on
the whole batch. Inputs are trusted (:mod:`flapping.periodic.fixedstep` checks them).

A compiled map. Per stage a Python call costs microseconds, as much as a compiled field: the
callables may offer the whole integration compiled instead, as the attribute
:data:`COMPILED_MAP` of the first segment's callable, an object of the :class:`CompiledMap`
protocol (the blade-element hover field does: :mod:`flapping.fast.blade`). :class:`PeriodMap`
integrates by it only when it was built for exactly these callables and switching functions
(the same objects), without ``args`` and with parameters; its derivative is then the central
differences of the compiled map. The numbers are those of this module's integration to rounding.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any, Protocol

import numpy as np

from flapping._numdiff import central_step
from flapping.periodic._tableau import N_STAGES, A, B, C

__all__ = ["COMPILED_MAP", "CompiledMap", "NonFinite", "OutOfWork", "PeriodMap"]

#: The attribute of a segment callable that holds its compiled map (:class:`CompiledMap`).
COMPILED_MAP = "compiled_period_map"

_EPS = float(np.finfo(float).eps)
_ROOT_ITERATIONS = 60  # Illinois converges superlinearly: ~8 iterations to rounding
_ROWS = [np.ascontiguousarray(A[s, :s]) for s in range(N_STAGES)]
_NODES = [float(c) for c in C]


class NonFinite(ArithmeticError):
    """A state or a callable's value became non-finite during an integration."""


class OutOfWork(RuntimeError):
    """The evaluations of ``fun`` reached the cap of the solve."""


class CompiledMap(Protocol):
    """The period map of some segment callables and switching functions, integrated compiled.

    Attributes
    ----------
    funs : tuple of callables
        The segment callables ``f(t, x, params)`` it integrates.
    switches : tuple of tuples of callables
        Per segment, the switching functions it locates (as :class:`PeriodMap`'s).
    """

    funs: tuple[Callable[..., Any], ...]
    switches: tuple[tuple[Callable[..., Any], ...], ...]

    def flow(self, X: np.ndarray, P: np.ndarray, n: int, nodes: Sequence[float]
             ) -> tuple[np.ndarray, int]:
        """(end states, evaluations of the field) of :meth:`PeriodMap.flow`'s integration of the
        rows of ``X`` with the parameters the rows of ``P``, segment k over [nodes[k],
        nodes[k + 1]] at ``n`` steps; raises :class:`NonFinite` as it does, and whatever the
        callables raise for parameters they refuse."""
        ...


def compiled_map(funs: tuple[Callable[..., Any], ...],
                 switches: tuple[tuple[Callable[..., Any], ...], ...], args: tuple[Any, ...],
                 has_params: bool) -> CompiledMap | None:
    """The compiled map the callables offer for exactly these callables and switching
    functions, without ``args`` and with parameters (its calling convention); else None."""
    offer = getattr(funs[0], COMPILED_MAP, None)
    if offer is None or args or not has_params:
        return None
    if tuple(offer.funs) != funs or tuple(tuple(g) for g in offer.switches) != switches:
        return None
    return offer


class PeriodMap:
    """x(T) of x(0) (and its derivative) at ``n`` fixed DOP853 steps per segment.

    Parameters
    ----------
    funs, jacs, pjacs : sequence of callables (or None)
        Per segment: ``f(t, x, *args[, params])``, its ``df/dx`` and ``df/dparams``.
    args : tuple
        Extra arguments, before ``params``.
    period : float
    breakpoints : tuple of float
        Fractions of the period where the segments meet.
    has_params : bool
        Whether ``params`` is passed to the callables.
    switches : sequence of sequences of callables, optional
        Per segment, the functions ``g(t, x, *args[, params])`` whose sign changes mark where ``f``
        is continuous but not smooth (a kink): a step across a sign change is split at the
        root (see :meth:`_split`), so the formula keeps its order.
    max_nfev : int
        Cap on the evaluations of ``fun`` (:class:`OutOfWork` beyond it).
    """

    def __init__(self, funs: Sequence[Callable[..., Any]],
                 jacs: Sequence[Callable[..., Any] | None],
                 pjacs: Sequence[Callable[..., Any] | None], args: tuple[Any, ...],
                 period: float, breakpoints: tuple[float, ...], has_params: bool,
                 max_nfev: int, switches: Sequence[Sequence[Callable[..., Any]]] = (),
                 difference_scale: float = 1.0) -> None:
        self.funs, self.jacs, self.pjacs = tuple(funs), tuple(jacs), tuple(pjacs)
        # the central-difference step in units of the optimal one (_numdiff.central_step): a
        # second scale tells the quotient's own error (truncation, rounding) from the mesh's
        self.difference_scale = difference_scale
        self.switches = tuple(tuple(g) for g in switches) or ((),) * len(self.funs)
        self.args, self.has_params = args, has_params
        self.nodes = [period * b for b in (0.0, *breakpoints)] + [period]
        self.nfev = self.njev = 0
        self.max_nfev = max_nfev
        self.compiled = compiled_map(self.funs, self.switches, args, has_params)

    def _count(self, fev: int, jev: int = 0) -> None:
        self.nfev += fev
        self.njev += jev
        if self.nfev > self.max_nfev:
            raise OutOfWork(f"the solve reached its cap of {self.max_nfev} evaluations of `fun`")

    @property
    def variational(self) -> bool:
        """Whether the derivative comes from the variational equations: ``jac`` given (and
        ``param_jac``, with parameters) and no switching functions; else central differences of
        the discrete map. (At a split point a stage lies on the switching surface, where ``jac``
        is one-sided and a user's ``jac`` picks either side: measured, an O(h) error in the
        monodromy. ``fun`` is continuous there, so differences of the map are not affected.)"""
        return (not any(self.switches) and all(j is not None for j in self.jacs)
                and (not self.has_params or all(j is not None for j in self.pjacs)))

    def evaluations(self, n: int, trajectories: int) -> int:
        """Evaluations of ``fun`` one integration of ``trajectories`` trajectories costs."""
        return trajectories * n * N_STAGES * len(self.funs)

    # ------------------------------------------------------------------------------ plain
    def flow(self, X: np.ndarray, P: np.ndarray | None, n: int) -> np.ndarray:
        """End states of a batch: ``X`` (m, d) initial states, ``P`` (m, n_p) parameters."""
        X = np.array(X, dtype=float)
        if self.compiled is not None and P is not None:
            ends, nfev = self.compiled.flow(X, P, n, self.nodes)
            self._count(nfev)
            return ends
        with np.errstate(over="ignore", invalid="ignore"):  # a non-finite state raises NonFinite
            for k in range(len(self.funs)):
                t0, t1 = self.nodes[k], self.nodes[k + 1]
                h = (t1 - t0) / n
                for step in range(n):
                    X = self._step(k, t0 + step * h, h, X, P)
        return X

    def _step(self, k: int, t: float, h: float, X: np.ndarray,
              P: np.ndarray | None) -> np.ndarray:
        f, m, d = self.funs[k], X.shape[0], X.shape[1]
        K = np.empty((N_STAGES, m, d))
        extra = [self.args if P is None else (*self.args, P[j]) for j in range(m)]
        for s in range(N_STAGES):
            Y = X if s == 0 else X + h * (_ROWS[s] @ K[:s].reshape(s, m * d)).reshape(m, d)
            ts = t + _NODES[s] * h
            for j in range(m):
                K[s, j] = f(ts, Y[j], *extra[j])
        self._count(m * N_STAGES)
        X_new = X + h * (B @ K.reshape(N_STAGES, m * d)).reshape(m, d)
        if not math.isfinite(float(np.sum(np.abs(X_new)))):
            raise NonFinite(f"the state became non-finite at t = {t + h!r}")
        if self.switches[k]:
            for j in range(m):
                X_new[j] = self._split(k, t, h, X[j], X_new[j], extra[j])
        return X_new

    # ------------------------------------------------------------------------------ switches
    def _one_step(self, k: int, t: float, h: float, x: np.ndarray,
                  extra: tuple[Any, ...]) -> np.ndarray:
        """One DOP853 step of one trajectory."""
        f, K = self.funs[k], np.empty((N_STAGES, x.size))
        for s in range(N_STAGES):
            K[s] = f(t + _NODES[s] * h, x if s == 0 else x + h * (_ROWS[s] @ K[:s]), *extra)
        self._count(N_STAGES)
        return x + h * (B @ K)

    def _split(self, k: int, t: float, h: float, x: np.ndarray, x_new: np.ndarray,
               extra: tuple[Any, ...]) -> np.ndarray:
        """The step from (t, x) over h, split at every root of a switching function in it."""
        done: set[int] = set()
        while True:
            event = self._first_root(k, t, h, x, x_new, extra, done)
            if event is None:
                return x_new
            tau, i = event
            done.add(i)  # crossed: its root at the split point is not crossed again
            x = self._one_step(k, t, tau, x, extra)
            t, h = t + tau, h - tau
            x_new = self._one_step(k, t, h, x, extra)

    def _first_root(self, k: int, t: float, h: float, x: np.ndarray, x_new: np.ndarray,
                    extra: tuple[Any, ...], done: set[int]) -> tuple[float, int] | None:
        """(tau, i): the earliest root t + tau of a switching function i in the step, if any."""
        first: tuple[float, int] | None = None
        for i, g in enumerate(self.switches[k]):
            if i in done:
                continue
            g0, g1 = float(g(t, x, *extra)), float(g(t + h, x_new, *extra))
            if g0 * g1 < 0.0:
                tau = self._root(k, g, t, h, x, extra, g0, g1)
                if first is None or tau < first[0]:
                    first = (tau, i)
        return first

    def _root(self, k: int, g: Callable[..., Any], t: float, h: float, x: np.ndarray,
              extra: tuple[Any, ...], g0: float, g1: float) -> float:
        """tau in (0, h) with g(t + tau, x(t + tau)) = 0 along the step (Illinois method)."""
        a, fa, b, fb = 0.0, g0, h, g1
        c, side = b, 0
        for _ in range(_ROOT_ITERATIONS):
            c = (a * fb - b * fa) / (fb - fa)
            fc = float(g(t + c, self._one_step(k, t, c, x, extra), *extra))
            if fc == 0.0:
                break
            if fc * fb > 0.0:  # c replaces b; a kept twice in a row: halve f(a) (Illinois)
                b, fb = c, fc
                fa, side = (0.5 * fa if side == -1 else fa), -1
            else:
                a, fa = c, fc
                fb, side = (0.5 * fb if side == 1 else fb), 1
            if b - a <= 4.0 * _EPS * (abs(t) + h):
                break
        return c

    # ------------------------------------------------------------------------------ derivative
    def derivative(self, x: np.ndarray, params: np.ndarray | None, n: int,
                   columns: Sequence[int]) -> tuple[np.ndarray, np.ndarray]:
        """x(T) and the columns ``columns`` of d x(T) / d(x0, params), shape (d, len(columns)).

        Column j < d is d x(T)/d x0_j, column d + i is d x(T)/d p_i.
        """
        if self.variational:
            end, W = self._variational(x, params, n)
            return end, W[:, list(columns)]
        return self._differenced(x, params, n, columns)

    def _differenced(self, x: np.ndarray, params: np.ndarray | None, n: int,
                     columns: Sequence[int]) -> tuple[np.ndarray, np.ndarray]:
        """Central differences of the discrete map (all trajectories in one batch)."""
        d = x.size
        v = x if params is None else np.concatenate([x, params])
        h = central_step(v) * self.difference_scale
        V = np.repeat(v[None, :], 1 + 2 * len(columns), axis=0)
        for i, j in enumerate(columns):
            V[1 + 2 * i, j] += h[j]
            V[2 + 2 * i, j] -= h[j]
        ends = self.flow(V[:, :d], None if params is None else V[:, d:], n)
        spans = np.array([V[1 + 2 * i, j] - V[2 + 2 * i, j] for i, j in enumerate(columns)])
        D = (ends[1::2] - ends[2::2]).T / spans
        return ends[0], D

    def _variational(self, x: np.ndarray, params: np.ndarray | None, n: int
                     ) -> tuple[np.ndarray, np.ndarray]:
        """x(T) and d x(T)/d(x0, params), shape (d, d + n_p), from the variational equations."""
        d, n_p = x.size, 0 if params is None else params.size
        W = np.hstack([np.eye(d), np.zeros((d, n_p))])
        extra = self.args if params is None else (*self.args, params)
        with np.errstate(over="ignore", invalid="ignore"):  # a non-finite state raises NonFinite
            for k in range(len(self.funs)):
                t0, t1 = self.nodes[k], self.nodes[k + 1]
                h = (t1 - t0) / n
                for step in range(n):
                    x, W = self._variational_step(k, t0 + step * h, h, x, W, extra, n_p)
        return x, W

    def _variational_step(self, k: int, t: float, h: float, x: np.ndarray, W: np.ndarray,
                          extra: tuple[Any, ...], n_p: int) -> tuple[np.ndarray, np.ndarray]:
        """One step of the state and its derivative, split at the roots of the switching
        functions (``f`` is continuous there, so the derivative needs no jump term)."""
        x_new, W_new = self._variational_rk(k, t, h, x, W, extra, n_p)
        done: set[int] = set()
        while self.switches[k]:
            event = self._first_root(k, t, h, x, x_new, extra, done)
            if event is None:
                break
            tau, i = event
            done.add(i)
            x, W = self._variational_rk(k, t, tau, x, W, extra, n_p)
            t, h = t + tau, h - tau
            x_new, W_new = self._variational_rk(k, t, h, x, W, extra, n_p)
        return x_new, W_new

    def _variational_rk(self, k: int, t: float, h: float, x: np.ndarray, W: np.ndarray,
                        extra: tuple[Any, ...], n_p: int) -> tuple[np.ndarray, np.ndarray]:
        f, J, Pj = self.funs[k], self.jacs[k], self.pjacs[k]
        assert J is not None and (Pj is not None or not n_p)
        d, cols = x.size, W.shape[1]
        K, KW = np.empty((N_STAGES, d)), np.empty((N_STAGES, d, cols))
        for s in range(N_STAGES):
            a = _ROWS[s]
            Y = x if s == 0 else x + h * (a @ K[:s])
            V = W if s == 0 else W + h * (a @ KW[:s].reshape(s, d * cols)).reshape(d, cols)
            ts = t + _NODES[s] * h
            K[s] = f(ts, Y, *extra)
            KW[s] = np.asarray(J(ts, Y, *extra), dtype=float) @ V
            if Pj is not None and n_p:
                KW[s, :, d:] += np.reshape(Pj(ts, Y, *extra), (d, n_p))
        self._count(N_STAGES, N_STAGES * (2 if n_p else 1))
        x = x + h * (B @ K)
        W = W + h * (B @ KW.reshape(N_STAGES, d * cols)).reshape(d, cols)
        if not math.isfinite(float(np.sum(np.abs(x))) + float(np.sum(np.abs(W)))):
            raise NonFinite(f"the state or its derivative became non-finite at t = {t + h!r}")
        return x, W

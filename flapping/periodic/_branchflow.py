"""Package-internal: the extended shooting map that :mod:`~flapping.periodic.continuation` follows.

An :class:`OrbitSystem` turns the user's ``fun(t, x, p[, q])`` into a map ``F(u)`` of the
unknowns

    u = (s_0[free], s_1, ..., s_{M-1}, T if autonomous, q, p)

(the M segment states, the period of an autonomous orbit, the free parameters ``q`` and the
continuation parameter ``p``, always last), with

    F(u) = (x_0(t_1) - s_1, ..., x_{M-1}(t_M) - s_0,  <s_0 - s_ref, f_ref> if autonomous)

where ``x_k`` is the solution from ``s_k`` at ``t_k = k T / M`` and the last row is the
Poincare-type phase condition: the orbit starts on the hyperplane through a reference point
``s_ref`` (the previous point of the branch) normal to the vector field there. The hyperplane
moves with the branch, so it stays transversal to the orbit where a fixed coordinate plane would
stop being crossed.

``evaluate(u, jacobian=True)`` integrates each segment with its variational equations (state,
state-transition matrix ``Phi_k``, sensitivities to ``(p, q)``) and returns the residual, the
Jacobian ``dF/du`` (block-bidiagonal ``[Phi_k, -I]`` plus the period and parameter columns) and the
monodromy matrix ``Phi_{M-1} ... Phi_0``. The right-hand side of the variational system is lean on
purpose: a continuation integrates it once or twice per point, hundreds of times.

Inputs are trusted: :mod:`flapping.periodic.continuation` checks them.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any, NoReturn

import numpy as np

import flapping._validation as check
from flapping._numdiff import central_jacobian
from flapping.periodic import _segments as seg

__all__ = ["OrbitSystem", "Evaluation", "IntegrationFailed"]

_EPS = float(np.finfo(float).eps)


class IntegrationFailed(Exception):
    """A segment could not be integrated (step budget, non-finite state)."""


@dataclass(frozen=True)
class Evaluation:
    """``F(u)`` and, with ``jacobian=True``, ``dF/du`` and the monodromy matrix."""

    residual: np.ndarray
    jacobian: np.ndarray | None
    monodromy: np.ndarray | None
    states: np.ndarray  # (M, n): s_0 .. s_{M-1}
    ends: np.ndarray  # (M, n): x_k(t_{k+1})
    stms: tuple[np.ndarray, ...]


class _Params:
    """Binds ``fun(t, x, p)`` or ``fun(t, x, p, q)`` to the parameter vector ``P = (p, q)``."""

    __slots__ = ("n_q",)

    def __init__(self, n_q: int) -> None:
        self.n_q = n_q

    def extra(self, P: np.ndarray) -> tuple[Any, ...]:
        """The trailing arguments ``(p,)`` or ``(p, q)`` of ``fun(t, x, *extra)`` at P."""
        p = float(P[0])
        return (p, P[1:].copy()) if self.n_q else (p,)

    def bind(self, fun: Callable[..., Any], P: np.ndarray) -> Callable[[float, np.ndarray], Any]:
        """``g(t, x) = fun(t, x, P[0][, P[1:]])``."""
        extra = self.extra(P)
        return lambda t, x: fun(t, x, *extra)


class _Field:
    """``g(t, x)`` at fixed parameters: counted and checked for shape and finiteness."""

    def __init__(self, fun: Callable[..., Any], P: np.ndarray, params: _Params, n: int,
                 counter: seg.Counter) -> None:
        self.fun, self.P, self.params, self.n, self.counter = fun, P, params, n, counter
        self.extra = params.extra(P)
        self.shape = (n,)

    def g(self, t: float, x: np.ndarray) -> Any:
        """The user's ``fun`` at the bound parameters, unchecked and uncounted."""
        return self.fun(t, x, *self.extra)

    def __call__(self, t: float, x: np.ndarray) -> np.ndarray:
        # direct call, no bound lambda: this runs at every stage of every plain integration
        self.counter.n += 1
        out = np.asarray(self.fun(t, x, *self.extra), dtype=float)
        if out.shape == self.shape and math.isfinite(out.dot(out)):
            return out
        if out.shape != self.shape:
            raise ValueError(f"`fun` must return an array of shape ({self.n},), got {out.shape}")
        if not np.isfinite(x).all():
            raise seg.Diverged(f"the state became non-finite at t = {t!r}", float(t), x)
        check.finite_output("fun", out, float(t), x)
        return out


class _VariationalField:
    """``(x, Phi, S)' = (f, J Phi, J S + df/dP)``: the lean variational right-hand side.

    ``df/dP`` by forward differences in each parameter (relative error ~1e-8: it only enters
    the Newton matrix's parameter columns and the tangent, never the residual or M).
    """

    def __init__(self, field: _Field, jac: Callable[..., Any] | None, n_par: int) -> None:
        self.field, self.n_par = field, n_par
        self.fun, self.extra, self.user_jac = field.fun, field.extra, jac
        self.jac = None if jac is None else field.params.bind(jac, field.P)
        self.width = field.n + n_par   # y = (x, [Phi | S]), the block row-major
        self.shape, self.jshape = (field.n,), (field.n, field.n)
        self.n, self.size = field.n, field.n * (1 + self.width)
        self.counter, self.calls = field.counter, 1 + n_par
        self.shifted = []
        for j in range(n_par):
            h = _EPS ** 0.5 * max(1.0, abs(float(field.P[j])))
            P = field.P.copy()
            P[j] += h
            self.shifted.append((field.params.extra(P), h))

    def _jac(self, t: float, x: np.ndarray) -> np.ndarray:
        if self.jac is None:
            return central_jacobian(lambda z: self.field(t, z), x)
        J = np.asarray(self.jac(t, x), dtype=float)
        n = self.field.n
        flat = J.reshape(-1)
        if J.shape != (n, n) or not math.isfinite(flat.dot(flat)):
            if J.shape != (n, n):
                raise ValueError(f"`jac` must return an array of shape ({n}, {n}), got {J.shape}")
            check.finite_output("jac", J, float(t), x)
        return J

    def __call__(self, t: float, y: np.ndarray) -> np.ndarray:
        # The hot loop of continuation: the user's functions are called directly (no bound
        # lambdas). Only shapes are checked before the product; finiteness once, on the output:
        # a non-finite entry of f or J makes a component of the output non-finite (J's row
        # multiplies the nonsingular [Phi | S]), and _reject then names the culprit.
        n, fun, extra = self.n, self.fun, self.extra
        x = y[:n]
        f = np.asarray(fun(t, x, *extra), dtype=float)
        uj = self.user_jac
        J = self._jac(t, x) if uj is None else np.asarray(uj(t, x, *extra), dtype=float)
        if f.shape != self.shape or J.shape != self.jshape:
            self._reject(t, x)
        # Phi and S side by side: one product J [Phi | S], written in place into the output.
        out = np.empty(self.size)
        out[:n] = f
        block = out[n:].reshape(n, self.width)
        np.matmul(J, y[n:].reshape(n, self.width), out=block)
        for j, (shifted, h) in enumerate(self.shifted):
            block[:, n + j] += (np.asarray(fun(t, x, *shifted), dtype=float) - f) / h
        self.counter.n += self.calls
        if not math.isfinite(out.dot(out)):
            self._reject(t, x)
        return out

    def _reject(self, t: float, x: np.ndarray) -> NoReturn:
        """Raise the checked paths' error for a bad output (or Diverged if they pass)."""
        self.field(t, x)
        self._jac(t, x)
        raise seg.Diverged(f"the variational equations became non-finite at t = {t!r}",
                           float(t), x)


class OrbitSystem:
    """The extended shooting map of a continuation (module notes).

    Parameters
    ----------
    funs, jacs : tuple
        One callable per breakpoint segment of the period (``jacs`` entries may be None).
    n : int
        State dimension.
    autonomous : bool
        Whether the period is an unknown.
    period : callable or None
        ``period(p)`` of a forced system (None when autonomous).
    segments : int
        Number M of shooting segments.
    fixed : tuple of int
        Components of ``s_0`` held at their values in ``base``.
    n_q : int
        Number of free parameters ``q``.
    breakpoints : tuple of float
        Restart fractions of the period (forced systems).
    settings : Settings
        Integration settings.
    floquet_states : tuple of int
        States whose block of the monodromy matrix gives the multipliers.
    """

    def __init__(self, funs: tuple[Callable[..., Any], ...],
                 jacs: tuple[Callable[..., Any] | None, ...], n: int, autonomous: bool,
                 period: Callable[[float], float] | None, segments: int, fixed: tuple[int, ...],
                 n_q: int, breakpoints: tuple[float, ...], settings: seg.Settings,
                 floquet_states: tuple[int, ...]) -> None:
        self.funs, self.jacs, self.n, self.autonomous = funs, jacs, n, autonomous
        self.period_fn, self.M, self.fixed, self.n_q = period, segments, fixed, n_q
        self.breakpoints, self.settings = breakpoints, settings
        self.floquet_states = np.asarray(floquet_states, dtype=int)
        self.free = np.array([i for i in range(n) if i not in fixed], dtype=int)
        self.params = _Params(n_q)
        self.counter = seg.Counter()
        self.base = np.zeros(n)  # s_0 with the fixed components' values
        self.ref: tuple[np.ndarray, np.ndarray] | None = None  # phase condition (s_ref, f_ref)

    # ---- layout ----------------------------------------------------------------------------
    @property
    def size(self) -> int:
        """Number of unknowns N (the map has N - 1 components)."""
        return self.free.size + (self.M - 1) * self.n + int(self.autonomous) + self.n_q + 1

    def pack(self, states: np.ndarray, T: float, q: np.ndarray, p: float) -> np.ndarray:
        """Unknowns from the segment states (M, n), the period, q and p."""
        return np.concatenate([states[0][self.free], states[1:].ravel(),
                               [T] if self.autonomous else [], q, [p]])

    def unpack(self, u: np.ndarray) -> tuple[np.ndarray, float, np.ndarray, float]:
        """``(states (M, n), T, q, p)`` of the unknowns."""
        nf, n, M = self.free.size, self.n, self.M
        s0 = self.base.copy()
        s0[self.free] = u[:nf]
        i = nf + (M - 1) * n
        states = np.vstack([s0[None, :], u[nf:i].reshape(M - 1, n)])
        p = float(u[-1])
        T = float(u[i]) if self.autonomous else self.period(p)
        q = u[i + int(self.autonomous):-1]
        return states, T, q, p

    def period(self, p: float) -> float:
        """The period at p of a forced system."""
        assert self.period_fn is not None
        value = self.period_fn(p)
        try:
            T = float(value)
        except (TypeError, ValueError):
            raise TypeError(f"`period(p)` must return a number (the period at p); got "
                            f"{value!r} at p = {p!r}") from None
        if not (math.isfinite(T) and T > 0):
            raise ValueError(f"`period(p)` must return a positive finite period; got {T!r} "
                             f"at p = {p!r}")
        return T

    def field(self, k: int, P: np.ndarray) -> _Field:
        """The checked right-hand side of breakpoint segment k at the parameters P."""
        return _Field(self.funs[k], P, self.params, self.n, self.counter)

    def segment_at(self, t: float, T: float, left: bool) -> int:
        """Breakpoint segment containing t (its left limit if ``left``)."""
        if not self.breakpoints:
            return 0
        phase = (t / T) % 1.0
        if left and phase < 1e-12:
            phase = 1.0
        return int(np.searchsorted(self.breakpoints, phase, side="left" if left else "right"))

    def vector_field(self, x: np.ndarray, P: np.ndarray) -> np.ndarray:
        """``f(x)`` of an autonomous system at the parameters P."""
        return self.field(0, P)(0.0, x)

    def unpack_delta(self, du: np.ndarray) -> tuple[np.ndarray, float, np.ndarray, float]:
        """A direction in the unknowns as ``(states (M, n), dT, dq, dp)``, fixed parts zero."""
        base = self.base
        self.base = np.zeros(self.n)
        try:
            states, _, q, p = self.unpack(du)
        finally:
            self.base = base
        i = self.free.size + (self.M - 1) * self.n
        return states, float(du[i]) if self.autonomous else 0.0, q, p

    def doubled(self) -> OrbitSystem:
        """The same system around twice the period (2M segments), for a period doubling."""
        period, b = self.period_fn, self.breakpoints
        funs, jacs = self.funs, self.jacs
        if not self.autonomous:  # the forcing's breakpoints, as fractions of the doubled period
            b = tuple(v / 2 for v in b) + (0.5,) + tuple((1 + v) / 2 for v in b)
            funs, jacs = funs + funs, jacs + jacs
        other = OrbitSystem(funs, jacs, self.n, self.autonomous,
                            None if period is None else (lambda p: 2.0 * period(p)),
                            2 * self.M, self.fixed, self.n_q, b, self.settings,
                            tuple(self.floquet_states))
        other.base = self.base.copy()
        return other

    def set_reference(self, u: np.ndarray) -> None:
        """Phase condition through the point u, normal to the vector field there."""
        if self.autonomous:
            states, _, q, p = self.unpack(u)
            f = self.vector_field(states[0], np.concatenate([[p], q]))
            self.ref = (states[0].copy(), f / max(float(np.linalg.norm(f)), 1e-300))

    def rephase(self, u: np.ndarray, J: np.ndarray) -> np.ndarray:
        """Move the phase condition to the point u; the Jacobian J with its phase row updated."""
        if not self.autonomous:
            return J
        self.set_reference(u)
        assert self.ref is not None
        J = J.copy()
        J[-1, :] = 0.0
        J[-1, :self.free.size] = self.ref[1][self.free]
        return J

    def onto_phase(self, u: np.ndarray) -> np.ndarray:
        """u moved along ``f_ref`` onto the phase hyperplane (a predictor's phase residual 0)."""
        if not self.autonomous or self.ref is None:
            return u
        s_ref, f_ref = self.ref
        nf = self.free.size
        s0 = self.base.copy()
        s0[self.free] = u[:nf]
        u = u.copy()
        u[:nf] -= ((s0 - s_ref) @ f_ref) * f_ref[self.free]
        return u

    def scale(self, u: np.ndarray) -> float:
        """``1 + max_k |s_k|``: the size of the states, for relative tolerances."""
        return 1.0 + float(np.max(np.linalg.norm(self.unpack(u)[0], axis=1)))

    # ---- evaluation ------------------------------------------------------------------------
    def _segment(self, k: int, states: np.ndarray, T: float, P: np.ndarray,
                 variational: bool) -> np.ndarray:
        """State (and its variations) at t_{k+1} from s_k at t_k."""
        t0, t1 = k * T / self.M, (k + 1) * T / self.M
        n, n_par = self.n, P.size
        if variational:
            rhss: Sequence[Callable[..., Any]] = [
                _VariationalField(self.field(j, P), self.jacs[j], n_par)
                for j in range(len(self.funs))]
            y0 = np.concatenate([states[k], np.hstack([np.eye(n), np.zeros((n, n_par))]).ravel()])
            # The sensitivities are left out of the error control: their forward-difference
            # right-hand side is noisy at ~1e-8, which would make the steps collapse at tight
            # tolerances; they only enter the Newton matrix and the tangent.
            row = np.concatenate([np.broadcast_to(self.settings.atol, (n,)), np.full(n_par, 1e300)])
            atol: Any = np.concatenate([np.broadcast_to(self.settings.atol, (n,)), np.tile(row, n)])
        else:
            rhss, y0, atol = [self.field(j, P) for j in range(len(self.funs))], states[k], None
        try:
            out = seg.propagate(rhss, t0, t1, y0, period=T, breakpoints=self.breakpoints,
                                settings=self.settings, h=None, atol=atol)
        except seg.Diverged as exc:
            raise IntegrationFailed(str(exc)) from None
        if not out.success:
            raise IntegrationFailed(f"segment {k}: {out.message}")
        return out.y_end

    def evaluate(self, u: np.ndarray, jacobian: bool = True) -> Evaluation:
        """Residual (and Jacobian, monodromy matrix) at u.

        Raises
        ------
        IntegrationFailed
            If a segment cannot be integrated or the period is not positive.
        """
        states, T, q, p = self.unpack(u)
        if not (math.isfinite(T) and T > 0):
            raise IntegrationFailed(f"the period left (0, inf): T = {T!r}")
        P = np.concatenate([[p], q])
        n, M = self.n, self.M
        ys = [self._segment(k, states, T, P, jacobian) for k in range(M)]
        ends = np.array([y[:n] for y in ys])
        r = (ends - np.roll(states, -1, axis=0)).ravel()
        if self.autonomous:
            assert self.ref is not None
            r = np.append(r, (states[0] - self.ref[0]) @ self.ref[1])
        if not jacobian:
            return Evaluation(r, None, None, states, ends, ())
        blocks = [y[n:].reshape(n, n + P.size) for y in ys]
        stms = tuple(np.ascontiguousarray(b[:, :n]) for b in blocks)
        sens = [b[:, n:] for b in blocks]
        J = self._jacobian(u, states, ends, stms, sens, T, P)
        mono = np.eye(n)
        for F in stms:
            mono = F @ mono
        return Evaluation(r, J, mono, states, ends, stms)

    def _jacobian(self, u: np.ndarray, states: np.ndarray, ends: np.ndarray,
                  stms: tuple[np.ndarray, ...], sens: list[np.ndarray], T: float,
                  P: np.ndarray) -> np.ndarray:
        """Block-bidiagonal ``[Phi_k, -I]``, then the T, q and p columns, then the phase row."""
        n, M, nf = self.n, self.M, self.free.size
        J = np.zeros((n * M + int(self.autonomous), u.size))
        cols = [np.arange(nf)] + [nf + (k - 1) * n + np.arange(n) for k in range(1, M)]
        for k in range(M):
            rows = slice(k * n, (k + 1) * n)
            J[rows, cols[k]] = stms[k][:, self.free] if k == 0 else stms[k]
            nxt = (k + 1) % M
            J[rows, cols[nxt]] -= np.eye(n)[:, self.free] if nxt == 0 else np.eye(n)
        i = nf + (M - 1) * n
        S = np.vstack(sens)  # (nM, 1 + n_q): d ends / d(p, q)
        if self.autonomous:
            J[:n * M, i] = np.concatenate([self.vector_field(e, P) for e in ends]) / M
            J[-1, :nf] = self.ref[1][self.free] if self.ref is not None else 0.0
        J[:n * M, i + int(self.autonomous):-1] = S[:, 1:]
        J[:n * M, -1] = S[:, 0]
        if not self.autonomous:
            J[:n * M, -1] += self._period_column(states, ends, stms, T, P)
        return J

    def _period_column(self, states: np.ndarray, ends: np.ndarray,
                       stms: tuple[np.ndarray, ...], T: float, P: np.ndarray) -> np.ndarray:
        """``dT/dp`` times the motion of the segment ends with the period (forced systems)."""
        p = float(P[0])
        h = _EPS ** (1 / 3) * max(1.0, abs(p))
        dT = (self.period(p + h) - self.period(p - h)) / (2 * h)
        if dT == 0.0:
            return np.zeros(self.n * self.M)
        col = []
        for k in range(self.M):
            t0, t1 = k * T / self.M, (k + 1) * T / self.M
            f1 = self.field(self.segment_at(t1, T, True), P)(t1, ends[k])
            f0 = self.field(self.segment_at(t0, T, False), P)(t0, states[k])
            col.append(dT * ((k + 1) / self.M * f1 - k / self.M * (stms[k] @ f0)))
        return np.concatenate(col)

    def multipliers(self, mono: np.ndarray) -> np.ndarray:
        """Floquet multipliers of the ``floquet_states`` block, sorted by modulus (descending)."""
        idx = self.floquet_states
        mu = np.linalg.eigvals(mono[np.ix_(idx, idx)]).astype(complex)
        return mu[np.lexsort((-np.angle(mu), -np.abs(mu)))]

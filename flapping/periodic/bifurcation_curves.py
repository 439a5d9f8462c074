"""Curves of codimension-one bifurcations of periodic orbits in two parameters.

:func:`continue_bifurcation` follows a fold (a Floquet multiplier +1), a period doubling (-1) or
a Neimark-Sacker bifurcation (a complex pair ``exp(+-i theta)`` on the unit circle) of a forced
or autonomous periodic orbit of ``x' = fun(t, x, p, q)`` in the plane of the two parameters
``(p, q)``: it first locates the bifurcation in p at ``q0`` (from a point at or near it), then
continues the curve in q towards ``q_end`` by pseudo-arclength, and returns a
:class:`BifurcationCurve`.

How a curve is computed
-----------------------
The orbit is a fixed point of the stroboscopic map ``P(x; p, q)`` (the flow over one period
``T``, or ``T(p, q)``: time is then rescaled to ``tau = t / T(p, q)`` so that the period is 1
and its dependence on the parameters enters the right-hand side smoothly). The defining system
(:mod:`flapping.periodic._defining`) is the periodicity ``x - P(x) = 0`` plus a scalar ``g``
(two real ones for Neimark-Sacker, with ``theta`` an unknown) of a bordered system that vanishes
where ``M - I``, ``M + I`` or ``M - exp(i theta) I`` is singular (``M = dP/dx``, the monodromy
matrix, exact from the variational equations): a minimally augmented system (Govaerts 2000;
Kuznetsov 2004, sec. 10.2). From a point with unit tangent ``t`` (the null vector of the
Jacobian), the predictor ``U + ds t`` is corrected by Newton's method on ``G(U) = 0``,
``<U - U_k, t> = ds`` (chord iterations with the last point's Jacobian, refreshed every
four); the step grows by 1.5 after at most three iterations, shrinks by 0.6 after six or more
and halves on a failure. The last point is corrected at ``q = q_end`` exactly.

An autonomous orbit's period is an unknown, with the moving Poincare-type phase condition of
:func:`~flapping.periodic.continuation.continue_orbit` (through the last accepted point, normal
to the vector field there); its trivial multiplier makes ``M - I`` singular everywhere, so its
fold is the singularity of ``M - I`` bordered by ``f(x)`` and the phase condition's normal, and
the special points' tests leave the trivial multiplier out.

A fixed orbit (the same state for every ``(p, q)``, e.g. ``x = 0`` of the Mathieu equation)
makes the system above singular at a +1 multiplier; it is detected (``fun`` independent of p and
q at a periodic ``x0``) and the curve is then ``g(p, q) = 0`` with the state held.

Special points (codimension two), detected by sign changes between accepted points and located
by Brent's method on points corrected onto the curve:

* on every curve: ``"turning point"``, where the curve turns back in q (the continuation stops
  there: its message says so); on a fold curve, a turning point where the p-tangent vanishes
  too is a ``"cusp"`` (the fold curve's projection on (p, q) has a cusp);
* fold curves: ``"fold-flip"`` (another multiplier through -1), ``"1:1 resonance"`` (another
  real multiplier through +1), ``"fold-neimark-sacker"`` (a complex pair through the circle);
* period-doubling curves: ``"fold-flip"`` (a multiplier through +1), ``"1:2 resonance"``
  (another real multiplier through -1), ``"flip-neimark-sacker"``;
* Neimark-Sacker curves: ``"1:1 resonance"`` (theta through 0) and ``"1:2 resonance"`` (theta
  through pi), where the curve ends (beyond, it retraces itself with theta mirrored),
  ``"1:3 resonance"`` (theta = 2 pi / 3), ``"1:4 resonance"`` (theta = pi / 2),
  ``"fold-neimark-sacker"``, ``"flip-neimark-sacker"``.

A test function within 1e-4 of zero at either end of a step is not trusted (a double
multiplier at +-1, as all along the Mathieu equation's curves, splits by the square root of
the corrector's residual, ~1e-5): a crossing with a curve point that close to it is missed.

The start is Newton's method (full steps) from ``(x0, p0)`` at ``q = q0``: a guess between two
curves may converge to the farther one (the Mathieu equation's a = 1 at q = 0.2, between b_1
and a_1, goes to a = 25); ``curve.p[0]`` is where it landed.

Not computed: normal-form coefficients, hence generalised period doubling and Chenciner points
(and the non-degeneracy of the cusp beyond the tangent test), and the switch to the curves that
emanate from a codimension-two point. A bifurcation found on a
:class:`~flapping.periodic.continuation.Branch` is followed by passing its ``x0`` and ``p``
(and ``period``) here.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from scipy.integrate import DOP853
from scipy.optimize import brentq

import flapping._validation as check
from flapping.errors import ConvergenceError
from flapping.periodic import _segments as seg
from flapping.periodic import settings as opt
from flapping.periodic._branchflow import IntegrationFailed, OrbitSystem
from flapping.periodic._checks import first_call
from flapping.periodic._defining import Defining, Point
from flapping.periodic._dop853 import LeanDOP853
from flapping.periodic._readonly import freeze

__all__ = ["BifurcationCurve", "SpecialPoint", "CurveOptions", "continue_bifurcation", "KINDS"]

#: Kinds of codimension-one bifurcation that can be continued.
KINDS: tuple[str, ...] = ("fold", "period-doubling", "neimark-sacker")

#: A test function whose value at either end of a step is below this is noise, not a sign
#: change: a double multiplier (a Jordan block) at +-1 splits by the square root of the
#: perturbation, ~1e-5 for the corrector's residual 1e-10, either along the real axis or off it.
#: The Mathieu equation's second multiplier is such a double 1 (det M = 1) all along its fold
#: curves and would otherwise signal a 1:1 resonance at every other step. (A genuine crossing
#: is missed only if a curve point falls within 1e-4 of it.)
_TEST_NOISE = 1e-4

#: Distance from +-1 within which a complex pair is a split double multiplier, not a pair.
_SPLIT = 1e-3

#: Chord iterations of the corrector between refreshes of its Jacobian.
_REFRESH = 4

#: Resonance angles of a Neimark-Sacker curve and the special point each marks.
_RESONANCES: tuple[tuple[float, str], ...] = (
    (0.0, "1:1 resonance"), (math.pi / 2, "1:4 resonance"),
    (2 * math.pi / 3, "1:3 resonance"), (math.pi, "1:2 resonance"))


@dataclass(frozen=True)
class CurveOptions:
    """Checked options of :func:`continue_bifurcation` (see its docstring for each)."""

    ds: float = 0.05
    ds_min: float = 1e-6
    ds_max: float = 0.2
    max_points: int = 500
    tol: float = opt.CURVE_TOL
    max_newton: int = 12
    rtol: float = opt.CURVE_RTOL
    atol: float = opt.CURVE_ATOL
    method: str = "DOP853"
    max_steps: int | None = None
    fixed_orbit: bool | None = None
    special_points: bool = True


@dataclass(frozen=True)
class SpecialPoint:
    """A codimension-two point (or a turning point) located on a bifurcation curve.

    Attributes
    ----------
    kind : str
        ``"cusp"``, ``"turning point"``, ``"fold-flip"``, ``"1:1 resonance"``,
        ``"1:2 resonance"``, ``"1:3 resonance"``, ``"1:4 resonance"``,
        ``"fold-neimark-sacker"``, ``"flip-neimark-sacker"``.
    p, q : float
        The parameters there, from the located condition.
    x0 : ndarray, shape (n,)
        The orbit's state at t = 0.
    multipliers : ndarray, complex
        Floquet multipliers there, sorted by modulus (descending).
    theta : float
        The critical pair's angle on a Neimark-Sacker curve (NaN on the others).
    index : int
        The curve point just before it.
    """

    kind: str
    p: float
    q: float
    x0: np.ndarray
    multipliers: np.ndarray
    theta: float
    index: int

    def __post_init__(self) -> None:
        freeze(self)


@dataclass(frozen=True)
class BifurcationCurve:
    """A curve of one kind of bifurcation in ``(p, q)``, one row per point.

    Attributes
    ----------
    kind : str
        ``"fold"``, ``"period-doubling"`` or ``"neimark-sacker"``.
    p, q : ndarray, shape (m,)
        The parameters along the curve (``q[0] = q0``; ``q[-1] = q_end`` on success).
    period : ndarray, shape (m,)
        The orbit's period at each point.
    x0 : ndarray, shape (m, n)
        The orbit's state at t = 0 at each point.
    multipliers : ndarray, shape (m, n), complex
        Floquet multipliers at each point, sorted by modulus (descending).
    theta : ndarray, shape (m,)
        Angle of the critical pair (Neimark-Sacker; NaN for the other kinds).
    residual : ndarray, shape (m,)
        Norm of the defining system at each point.
    special_points : tuple of SpecialPoint
        In the order met.
    message : str
        Why the continuation stopped.
    success : bool
        True if the last point lies at ``q = q_end``.
    autonomous : bool
        Whether the period is an unknown.
    fixed_orbit : bool
        Whether the orbit's state was held (module notes).
    nfev : int
        Evaluations of ``fun`` (finite differences included).
    """

    kind: str
    p: np.ndarray
    q: np.ndarray
    period: np.ndarray
    x0: np.ndarray
    multipliers: np.ndarray
    theta: np.ndarray
    residual: np.ndarray
    special_points: tuple[SpecialPoint, ...]
    message: str
    success: bool
    autonomous: bool
    fixed_orbit: bool
    nfev: int

    def __post_init__(self) -> None:
        freeze(self)

    def __len__(self) -> int:
        return int(self.p.size)


# ---- the user's callables on the orbit system's signature ---------------------------------
class _Bound:
    """``fun(t, x, p, q)`` as ``fun(t, x, p, q_vector)``, in rescaled time when ``T(p, q)``.

    The orbit system passes its free parameters as a vector; the user's ``q`` is a number.
    With ``period(p, q)`` the time is ``tau = t / T``: ``dx/dtau = T f(T tau, x, p, q)``, of
    period 1, so the period's dependence on both parameters is in the right-hand side (and in
    the sensitivities the orbit system differentiates).
    """

    def __init__(self, fun: Callable[..., Any], period: Callable[..., Any] | None) -> None:
        self.fun, self.period = fun, period
        self.key: tuple[float, float] = (math.nan, math.nan)
        self.T = 1.0

    def _T(self, p: float, q: float) -> float:
        if (p, q) != self.key:
            assert self.period is not None
            self.T, self.key = _period_value(self.period, p, q), (p, q)
        return self.T

    def __call__(self, t: float, x: np.ndarray, p: float, qv: np.ndarray) -> Any:
        q = float(qv[0])
        if self.period is None:
            return self.fun(t, x, p, q)
        T = self._T(p, q)
        return T * np.asarray(self.fun(T * t, x, p, q), dtype=float)


def _period_value(period: Callable[..., Any], p: float, q: float) -> float:
    value = period(p, q)
    try:
        T = float(value)
    except (TypeError, ValueError):
        raise TypeError(f"`period(p, q)` must return a number; got {value!r} at p = {p!r}, "
                        f"q = {q!r}") from None
    if not (math.isfinite(T) and T > 0):
        raise ValueError(f"`period(p, q)` must return a positive finite period; got {T!r} at "
                         f"p = {p!r}, q = {q!r}")
    return T


# ---- options ---------------------------------------------------------------------------------
def _check_options(options: dict[str, Any]) -> CurveOptions:
    """The options, checked; unknown names are a ValueError naming the accepted ones."""
    names = CurveOptions.__dataclass_fields__
    unknown = sorted(set(options) - set(names))
    if unknown:
        raise ValueError(f"unknown option(s) {unknown}; accepted: {sorted(names)}")
    o = {k: getattr(CurveOptions(), k) for k in names}
    o.update(options)
    for k in ("ds", "ds_min", "ds_max", "tol", "atol"):
        o[k] = check.positive(k, o[k])
    o["tol"] = check.real("tol", o["tol"], low=0.0, high=opt.RESIDUAL_CEILING, low_open=True)
    if not o["ds_min"] <= o["ds"] <= o["ds_max"]:
        raise ValueError(f"`ds` must lie in [`ds_min`, `ds_max`] = [{o['ds_min']!r}, "
                         f"{o['ds_max']!r}] (and ds_min <= ds_max); got ds = {o['ds']!r}")
    o["max_points"] = opt.capped("max_points", o["max_points"], low=2)
    o["max_newton"] = opt.capped("max_newton", o["max_newton"])
    o["rtol"] = opt.check_rtol("rtol", o["rtol"])
    if o["fixed_orbit"] is not None:
        o["fixed_orbit"] = check.boolean("fixed_orbit", o["fixed_orbit"])
    o["special_points"] = check.boolean("special_points", o["special_points"])
    seg.check_settings(o["method"], o["rtol"], o["atol"], 1024, o["max_steps"])
    return CurveOptions(**o)


def _integration(opts: CurveOptions) -> seg.Settings:
    """Integration settings; DOP853 steps by the lean step (as continuation does)."""
    settings = seg.check_settings(opts.method, opts.rtol, opts.atol, 1024, opts.max_steps)
    if settings.solver is DOP853:
        settings = replace(settings, solver=LeanDOP853)
    return settings


# ---- the corrector -------------------------------------------------------------------------
class _Corrector:
    """Newton's method on ``G(U) = 0`` plus ``<U - U_c, d> = s``; None on failure."""

    def __init__(self, problem: Defining, tol: float, max_iter: int) -> None:
        self.problem, self.tol, self.max_iter = problem, tol, max_iter
        self.message, self.residual, self.iterations = "", math.nan, 0

    def __call__(self, U: np.ndarray, U_c: np.ndarray, d: np.ndarray, s: float,
                 DG: np.ndarray | None = None) -> tuple[Point, int] | None:
        """The corrected point (with its Jacobian) and the iterations, or None.

        With ``DG`` (the last point's Jacobian) the iterations are chord steps: one
        variational integration each instead of ``n + 3`` (the finite-difference rows of
        ``g``); the Jacobian is refreshed every ``_REFRESH`` iterations and once at the
        converged point, for its tangent. Without it (the start, from a rough guess), full
        Newton steps.
        """
        problem = self.problem
        U = U.copy()
        try:
            pt = problem.evaluate(U) if DG is None else problem.residual(U)
            J = pt.DG if DG is None else DG
            first = float(np.linalg.norm(pt.G))
            for it in range(1, self.max_iter + 1):
                A = np.vstack([J, d])
                r = np.append(pt.G, d @ (U - U_c) - s)
                U = U + np.linalg.solve(A, -r)
                refresh = DG is None or it % _REFRESH == 0
                pt = problem.evaluate(U) if refresh else problem.residual(U)
                if refresh:
                    J = pt.DG
                norm = float(np.linalg.norm(pt.G))
                self.residual, self.iterations = norm, it
                if norm <= self.tol * problem.scale(U):
                    return (pt if refresh else problem.evaluate(U)), it
                if not np.isfinite(norm) or norm > 1e3 * max(first, self.tol):
                    self.message = f"Newton diverged (residual {norm:.3e})"
                    return None
            self.message = (f"Newton did not reach the residual tol = {self.tol:.1e} in "
                            f"{self.max_iter} iterations (last {norm:.3e})")
        except IntegrationFailed as exc:
            self.message = f"integration failed: {exc}"
        except np.linalg.LinAlgError as exc:
            self.message = f"singular Newton matrix: {exc}"
        return None


def _tangent(DG: np.ndarray, previous: np.ndarray | None) -> np.ndarray:
    t = np.linalg.svd(DG)[2][-1]
    if previous is not None and t @ previous < 0:
        t = -t
    return np.asarray(t)


# ---- test functions of the special points -----------------------------------------------------
def _multipliers(mono: np.ndarray) -> np.ndarray:
    mu = np.linalg.eigvals(mono).astype(complex)
    return mu[np.lexsort((-np.angle(mu), -np.abs(mu)))]


def _others(kind: str, mu: np.ndarray, theta: float) -> np.ndarray:
    """The multipliers without the critical one (or the critical pair)."""
    if kind == "neimark-sacker":
        lam = np.exp(1j * theta)
        i = int(np.argmin(np.abs(mu - lam)))
        j = int(np.argmin(np.where(np.arange(mu.size) == i, np.inf, np.abs(mu - np.conj(lam)))))
        keep = np.ones(mu.size, dtype=bool)
        keep[[i, j]] = False
        return mu[keep]
    lam = 1.0 if kind == "fold" else -1.0
    return np.delete(mu, int(np.argmin(np.abs(mu - lam))))


def _is_complex(mu: np.ndarray) -> np.ndarray:
    return np.abs(mu.imag) > 1e-7 * np.maximum(np.abs(mu), 1e-300)


def _tests(kind: str, mu: np.ndarray, theta: float) -> dict[str, float]:
    """Test functions of the special points (a sign change marks each); NaN: not applicable.

    ``mu``: the multipliers without an autonomous orbit's trivial one.
    """
    others = _others(kind, mu, theta)
    # a double multiplier at +-1 (a Jordan block) splits by ~sqrt(eps) into a complex pair:
    # counted as real, not as a pair on the circle
    cplx = _is_complex(others) & (np.abs(others - 1.0) > _SPLIT) & (np.abs(others + 1.0) > _SPLIT)
    real = others[~cplx].real
    pairs = others[cplx & (others.imag > 0)]  # one of each conjugate pair
    out: dict[str, float] = {}
    # one of the other real multipliers through +1 or -1 (products over the real ones: a
    # complex pair contributes a positive factor)
    plus = float(np.prod(real - 1.0)) if real.size else math.nan
    minus = float(np.prod(real + 1.0)) if real.size else math.nan
    torus = (float(np.prod(np.abs(pairs) - 1.0)) if pairs.size else math.nan)
    if kind == "fold":
        out.update({"fold-flip": minus, "1:1 resonance": plus, "fold-neimark-sacker": torus})
    elif kind == "period-doubling":
        out.update({"fold-flip": plus, "1:2 resonance": minus, "flip-neimark-sacker": torus})
    else:
        out.update({"fold-neimark-sacker": plus, "flip-neimark-sacker": minus})
        for angle, name in _RESONANCES[1:3]:
            out[name] = theta - angle
    return out


def _value(kind: str, name: str, pt: Point, problem: Defining, t: np.ndarray,
           ref: np.ndarray) -> float:
    """The test function ``name`` at a corrected point with tangent t."""
    if name in ("turning point", "cusp"):
        return float(t[problem.iq] * np.sign(ref[problem.iq]))
    theta = problem.theta(pt.U)
    if name == "1:1 resonance" and kind == "neimark-sacker":
        return theta
    if name == "1:2 resonance" and kind == "neimark-sacker":
        return theta - math.pi
    return _tests(kind, problem.effective(_multipliers(pt.monodromy)), theta)[name]


# ---- the continuation loop ---------------------------------------------------------------------
@dataclass
class _Accepted:
    pt: Point
    t: np.ndarray
    tests: dict[str, float] = field(default_factory=dict)


class _Tracer:
    """Predictor, corrector, step control, special points, stopping."""

    def __init__(self, problem: Defining, opts: CurveOptions, q_end: float) -> None:
        self.problem, self.opts, self.q_end = problem, opts, q_end
        self.corrector = _Corrector(problem, opts.tol, opts.max_newton)
        self.points: list[_Accepted] = []
        self.special: list[SpecialPoint] = []

    def _accepted(self, pt: Point, previous: np.ndarray | None) -> _Accepted:
        t = _tangent(pt.DG, previous)
        theta = self.problem.theta(pt.U)
        mu = self.problem.effective(_multipliers(pt.monodromy))
        return _Accepted(pt, t, _tests(self.problem.kind, mu, theta))

    def run(self, start: Point, direction: float) -> tuple[str, bool]:
        """Follow the curve from ``start`` with q moving in the sign of ``direction``."""
        problem, opts = self.problem, self.opts
        first = _tangent(start.DG, None)
        if first[problem.iq] * direction < 0:
            first = -first
        if abs(first[problem.iq]) < 1e-8:
            raise ConvergenceError(
                f"the {problem.kind} curve is tangent to q = {problem.pq(start.U)[1]!r} at "
                f"p = {problem.pq(start.U)[0]!r}: it cannot be continued in q from there",
                x=start.U)
        self.points.append(_Accepted(start, first, self._accepted(start, first).tests))
        self.direction = direction
        ds = opts.ds
        while True:
            if len(self.points) >= opts.max_points:
                return f"step budget spent (max_points = {opts.max_points})", False
            last = self.points[-1]
            out = self.corrector(last.pt.U + ds * last.t, last.pt.U, last.t, ds, last.pt.DG)
            if out is None:
                ds *= 0.5
                if ds < opts.ds_min:
                    p, q = problem.pq(last.pt.U)
                    return (f"step size below minimum (ds_min = {opts.ds_min:g}) at p = "
                            f"{p:.10g}, q = {q:.10g}: {self.corrector.message}"), False
                continue
            pt, nit = out
            problem.update_borders(pt)
            problem.set_reference(pt)
            q = problem.pq(pt.U)[1]
            if (q - self.q_end) * direction >= 0:
                return self._finish(last)
            new = self._accepted(pt, last.t)
            stop = self._special(last, new)
            if stop:
                return stop, False
            self.points.append(new)
            ds = min(ds * 1.5, opts.ds_max) if nit <= 3 else (ds * 0.6 if nit >= 6 else ds)

    def _finish(self, last: _Accepted) -> tuple[str, bool]:
        """The last point, corrected at ``q = q_end`` exactly."""
        problem = self.problem
        e_q = np.zeros(problem.size)
        e_q[problem.iq] = 1.0
        dq = self.q_end - problem.pq(last.pt.U)[1]
        t_q = float(last.t[problem.iq])
        guess = last.pt.U + dq / t_q * last.t if abs(t_q) > 1e-3 else last.pt.U
        out = self.corrector(guess, last.pt.U, e_q, dq, last.pt.DG)
        if out is None:
            return f"could not correct the last point at q_end: {self.corrector.message}", False
        # the constraint holds to rounding (q_c + dq): q_end itself, as promised
        out[0].U[problem.iq] = self.q_end
        problem.set_reference(out[0])
        self.points.append(self._accepted(out[0], last.t))
        return "reached q_end", True

    def _special(self, a: _Accepted, b: _Accepted) -> str:
        """Locate the special points between a and b; a message if the curve ends there."""
        problem, kind = self.problem, self.problem.kind
        iq, ip = problem.iq, problem.iq + 1
        if self.opts.special_points:
            for name in a.tests:
                va, vb = a.tests[name], b.tests[name]
                if not (va * vb < 0 and min(abs(va), abs(vb)) > _TEST_NOISE):
                    continue
                self._locate(name, a, b)
        if kind == "neimark-sacker":
            for angle, name in (_RESONANCES[0], _RESONANCES[3]):
                ta, tb = problem.theta(a.pt.U) - angle, problem.theta(b.pt.U) - angle
                if ta * tb <= 0:
                    found = self._locate(name, a, b)
                    where = self._where(found, b)
                    return (f"the curve ends at a {name} (theta = {angle:.6g}) at {where}: "
                            f"beyond it, it retraces itself with theta mirrored")
        if b.t[iq] * self.direction < 0:   # q turns back
            cusp = kind == "fold" and problem.x_fixed is None and a.t[ip] * b.t[ip] < 0
            found = self._locate("cusp" if cusp else "turning point", a, b)
            return (f"the curve turns back in q at {self._where(found, b)}"
                    + (" (a cusp)" if cusp else "") + ": q_end not reached")
        return ""

    def _where(self, found: SpecialPoint | None, b: _Accepted) -> str:
        if found is not None:
            return f"p = {found.p:.10g}, q = {found.q:.10g}"
        p, q = self.problem.pq(b.pt.U)
        return f"p ~ {p:.10g}, q ~ {q:.10g} (not located)"

    def _locate(self, name: str, a: _Accepted, b: _Accepted) -> SpecialPoint | None:
        """The special point ``name`` between a and b by Brent's method on corrected points."""
        problem, kind = self.problem, self.problem.kind
        saved = (problem.b.copy(), problem.c.copy())
        cache: dict[float, tuple[Point, float]] = {}
        U_a, t_a = a.pt.U, a.t

        def f(s: float) -> float:
            near = min(cache, key=lambda v: abs(v - s)) if cache else None
            start = U_a + s * t_a if near is None else cache[near][0].U + (s - near) * t_a
            out = self.corrector(start, U_a, t_a, s, a.pt.DG)
            if out is None:
                raise IntegrationFailed(self.corrector.message)
            pt = out[0]
            value = _value(kind, name, pt, problem, _tangent(pt.DG, t_a), a.t)
            cache[s] = (pt, value)
            return value

        try:
            s_end = float(t_a @ (b.pt.U - U_a))
            s = brentq(f, 0.0, s_end, xtol=1e-12 * (1.0 + float(np.linalg.norm(U_a))),
                       maxiter=60)
            if s not in cache:
                f(s)
        except (IntegrationFailed, ValueError, RuntimeError):
            return None
        finally:
            problem.b, problem.c = saved
        pt = cache[s][0]
        p, q = problem.pq(pt.U)
        found = SpecialPoint(name, p, q, problem.x(pt.U), _multipliers(pt.monodromy),
                             problem.theta(pt.U), len(self.points) - 1)
        self.special.append(found)
        return found

    def curve(self, message: str, success: bool, period: Callable[[float, float], float]
              ) -> BifurcationCurve:
        problem = self.problem
        pts = [a.pt for a in self.points]
        pq = np.array([problem.pq(pt.U) for pt in pts])
        return BifurcationCurve(
            kind=problem.kind, p=pq[:, 0].copy(), q=pq[:, 1].copy(),
            period=np.array([problem.period(pt.U) if problem.auto else period(p, q)
                             for pt, (p, q) in zip(pts, pq, strict=True)]),
            x0=np.array([problem.x(pt.U) for pt in pts]),
            multipliers=np.array([_multipliers(pt.monodromy) for pt in pts]),
            theta=np.array([problem.theta(pt.U) for pt in pts]),
            residual=np.array([float(np.linalg.norm(pt.G)) for pt in pts]),
            special_points=tuple(self.special), message=message, success=success,
            autonomous=problem.auto, fixed_orbit=problem.x_fixed is not None,
            nfev=problem.system.counter.n)


# ---- the start -------------------------------------------------------------------------------
def _system(fun: Callable[..., Any], jac: Callable[..., Any] | None, n: int,
            period: Any, autonomous: bool, opts: CurveOptions) -> OrbitSystem:
    rescale = period if (callable(period) and not autonomous) else None
    funs: tuple[Any, ...] = (_Bound(fun, rescale),)
    jacs: tuple[Any, ...] = ((_Bound(jac, rescale),) if jac is not None else (None,))
    T = 1.0 if rescale is not None else period
    return OrbitSystem(funs, jacs, n, autonomous, None if autonomous else (lambda p: T), 1, (),
                       1, (), _integration(opts), tuple(range(n)))


def _probe(fun: Any, jac: Any, x0: np.ndarray, p0: float, q0: float, period: Any) -> None:
    """``fun``, ``jac`` and ``period`` called once at the start and checked."""
    n = x0.size
    if callable(period):
        _period_value(period, p0, q0)
    first_call(fun, "fun", 0.0, x0, (p0, q0), (n,), call="fun(t, x, p, q)",
               given="the parameters p0 and q0")
    if jac is not None:
        first_call(jac, "jac", 0.0, x0, (p0, q0), (n, n), call="jac(t, x, p, q)",
                   given="the parameters p0 and q0")


def _fixed_orbit(system: OrbitSystem, u0: np.ndarray, opts: CurveOptions) -> bool:
    """Whether x0 is an orbit for every (p, q): periodic, with zero parameter sensitivities."""
    if system.autonomous:
        return False
    if opts.fixed_orbit is not None:
        return opts.fixed_orbit
    ev = system.evaluate(u0, jacobian=True)
    assert ev.jacobian is not None
    scale = 1.0 + float(np.linalg.norm(u0[:system.n]))
    return bool(np.linalg.norm(ev.residual) <= opts.tol * scale
                and np.linalg.norm(ev.jacobian[:, -2:]) <= 1e-12 * scale)


def _initial_theta(problem: Defining, u0: np.ndarray, p0: float, q0: float) -> float:
    # x0 is a guess, not yet on the orbit: its trivial multiplier is only near 1
    mu = problem.effective(_multipliers(problem.flow(u0)[1]), near_orbit=False)
    pairs = mu[_is_complex(mu) & (mu.imag > 0)]
    if not pairs.size:
        raise ValueError(f"no complex pair of multipliers at (p0, q0) = ({p0!r}, {q0!r}) "
                         f"(multipliers {np.round(mu, 6).tolist()}): no Neimark-Sacker "
                         f"bifurcation near `x0`")
    return float(np.angle(pairs[np.argmin(np.abs(np.abs(pairs) - 1.0))]))


def _locate_start(problem: Defining, corrector: _Corrector, U0: np.ndarray, p0: float,
                  q0: float) -> Point:
    """The bifurcation in p at q = q0: Newton on G = 0 with q held."""
    problem.system.set_reference(problem.orbit_u(U0))
    mono = problem.flow(problem.orbit_u(U0))[1]
    problem.init_borders(mono, U0)
    e_q = np.zeros(problem.size)
    e_q[problem.iq] = 1.0
    out = corrector(U0, U0, e_q, 0.0)
    if out is None:
        raise ConvergenceError(
            f"continue_bifurcation: no {problem.kind} bifurcation found in p near p0 = {p0!r} "
            f"at q0 = {q0!r}: {corrector.message}", x=U0, residual=corrector.residual,
            iterations=corrector.iterations)
    problem.update_borders(out[0])
    problem.set_reference(out[0])
    return out[0]


def continue_bifurcation(
    fun: Callable[..., Any],
    x0: Any,
    period: float | Callable[[float, float], float],
    kind: str,
    p0: float,
    q0: float,
    q_end: float,
    *,
    autonomous: bool = False,
    jac: Callable[..., Any] | None = None,
    **options: Any,
) -> BifurcationCurve:
    """Follow a fold, period doubling or Neimark-Sacker bifurcation of a forced periodic orbit
    in two parameters ``(p, q)``, from ``q0`` to ``q_end``.

    Parameters
    ----------
    fun : callable
        ``fun(t, x, p, q) -> (n,)``, the right-hand side, p and q numbers.
    x0 : array_like, shape (n,)
        A state at t = 0 on (or near) the periodic orbit at ``(p0, q0)``, which is at or near
        the bifurcation of ``kind`` in p.
    period : float or callable
        Forced: the forcing period, or ``period(p, q)`` when it depends on the parameters.
        Autonomous: a guess of the period at the start (a number).
    kind : str
        ``"fold"`` (a multiplier +1), ``"period-doubling"`` (-1) or ``"neimark-sacker"``
        (a complex pair on the unit circle).
    p0, q0 : float
        Where to start: p a guess of the bifurcation's parameter at ``q = q0``.
    q_end : float
        Where to stop (``q_end != q0``).
    autonomous : bool, optional
        True: the period is an unknown, with a phase condition (module notes).
    jac : callable, optional
        ``jac(t, x, p, q)``: ``df/dx``; default central differences of ``fun``.
    **options
        :class:`CurveOptions`: ``ds`` (first step in the unknowns' arclength, 0.05),
        ``ds_min`` (1e-6), ``ds_max`` (0.2), ``max_points`` (500, at most 10**5), ``tol``
        (residual of the defining system relative to ``1 + |x|``, 1e-10, at most 1e-6),
        ``max_newton`` (12), ``rtol``/``atol`` (1e-11), ``method`` ("DOP853"), ``max_steps``
        (per integration), ``fixed_orbit`` (None: detected; True: hold the state ``x0``, an
        orbit for every (p, q)), ``special_points`` (True: detect and locate them).

    Returns
    -------
    BifurcationCurve
        ``p``, ``q``, orbits, multipliers (and ``theta``) along the curve, its
        ``special_points``, and the reason it stopped: ``q_end`` reached (the last point at
        ``q = q_end`` exactly), the curve turning back in q (at a turning point or a cusp),
        a Neimark-Sacker curve ending at a 1:1 or 1:2 resonance, or a step budget.

    Raises
    ------
    ValueError
        For bad arguments (``kind`` not one of :data:`KINDS`, ``q_end == q0``, unknown or out
        of range options, non-finite numbers, ``fun``/``jac`` returning a wrong shape at the
        first call; no complex pair of multipliers at the start of a Neimark-Sacker curve; a
        callable ``period`` or ``fixed_orbit=True`` with ``autonomous=True``).
    TypeError
        ``fun``/``jac`` cannot be called as ``fun(t, x, p, q)``, or ``period(p, q)`` returns no
        number.
    ConvergenceError
        If the bifurcation is not found in p at ``q0`` (with the residual and iterations), or
        the curve is tangent to ``q = q0`` there.
    """
    check.choice("kind", kind, KINDS)
    x = check.vector("x0", x0)
    p0, q0, q_end = check.real("p0", p0), check.real("q0", q0), check.real("q_end", q_end)
    if q_end == q0:
        raise ValueError(f"`q_end` equals `q0` ({q0!r}): nothing to continue")
    autonomous = check.boolean("autonomous", autonomous)
    if autonomous and callable(period):
        raise ValueError("`period` must be a number (a guess) for an autonomous system")
    T_given = None if callable(period) else check.positive("period", period)
    opts = _check_options(options)
    if autonomous and opts.fixed_orbit:
        raise ValueError("`fixed_orbit` needs a forced system (autonomous=False): an "
                         "autonomous orbit that does not move is an equilibrium")
    opt.check_scaled("atol", opts.atol, x, opt.TOL_CEILING)
    _probe(fun, jac, x, p0, q0, period)
    system = _system(fun, jac, x.size, period if T_given is None else T_given, autonomous,
                     opts)
    T0 = T_given if (autonomous and T_given is not None) else 1.0
    u0 = system.pack(x[None, :], T0, np.array([q0]), p0)
    system.set_reference(u0)
    fixed = _fixed_orbit(system, u0, opts)
    problem = Defining(system, kind, x.copy() if fixed else None)
    theta0 = _initial_theta(problem, u0, p0, q0) if kind == "neimark-sacker" else math.nan
    tracer = _Tracer(problem, opts, q_end)
    start = _locate_start(problem, tracer.corrector, problem.pack(x, T0, p0, q0, theta0),
                          p0, q0)
    message, success = tracer.run(start, math.copysign(1.0, q_end - q0))
    return tracer.curve(message, success, (lambda p, q: T_given) if T_given is not None
                        else period)  # type: ignore[arg-type]

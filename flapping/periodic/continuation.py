"""Following periodic orbits as a parameter changes: pseudo-arclength continuation of shooting.

:func:`continue_orbit` follows a periodic orbit of ``x' = fun(t, x, p)`` from ``p0`` towards
``p_end`` and returns a :class:`Branch`: the orbit, its period and Floquet multipliers at every
point, its stability, and the bifurcations met on the way, each located by solving its defining
condition (Kuznetsov 2004, ch. 10; Seydel 2010).

The method
----------
Unknowns ``u = (s_0, ..., s_{M-1}, T if autonomous, p)`` (M shooting segments; for a forced
system the period is known, ``T = period(p)``), and the shooting map ``F(u)`` of the continuity
conditions plus, for an autonomous orbit, a Poincare-type phase condition
``<s_0 - s_ref, f(s_ref)> = 0`` whose hyperplane moves with the branch (``s_ref`` is the previous
point): a fixed coordinate plane stops being crossed when the orbit moves or shrinks (Roessler
below c = 0.51), this one does not. ``F = 0`` defines a curve; from a point ``u_k`` with unit
tangent ``t_k`` (the null vector of ``dF/du``), a step of length ``ds`` is predicted,
``u_k + ds t_k``, and corrected by Newton's method on ``F(u) = 0``,
``<u - u_k, t_k> = ds`` (pseudo-arclength): the branch is followed round folds, where p turns
back. The first Newton step uses the previous point's Jacobian (a chord step, no variational
integration); every later one integrates the variational equations, which also give the
monodromy matrix ``Phi_{M-1} ... Phi_0`` and the multipliers of the accepted point. The step
grows by 1.5 when one iteration suffices, shrinks by 0.6 when three or more are needed, and
halves on a failure, between ``ds_min`` and ``ds_max``.

Stopping: when p reaches ``p_end`` (the last point is corrected at ``p = p_end`` exactly), after
``max_points`` points, when the step falls below ``ds_min``, when an autonomous orbit shrinks
onto an equilibrium or its period grows without bound. :attr:`Branch.message` says which; the
continuation never hangs (every integration has its step budget).

Bifurcations (test functions in :mod:`flapping.periodic._bifurcation`): ``"fold"`` (the tangent's
p-component changes sign; located by ``det(dF/dv) = 0``, v all unknowns but p: ``det(M - I)`` for
a forced orbit, the bordered determinant for an autonomous one), ``"period-doubling"``
(``det(M + I)`` changes sign) and ``"neimark-sacker"`` (a complex pair crosses the unit circle;
a pair that forms inside the circle is not one). :meth:`Branch.switch` starts the doubled orbit's
branch at a period doubling.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from scipy.integrate import DOP853

import flapping._validation as check
from flapping.errors import ConvergenceError
from flapping.periodic import _bifurcation as bif
from flapping.periodic import _segments as seg
from flapping.periodic import settings as opt
from flapping.periodic._branchflow import OrbitSystem
from flapping.periodic._checks import first_call
from flapping.periodic._dop853 import LeanDOP853
from flapping.periodic._readonly import freeze
from flapping.periodic.shooting import find_periodic_orbit

__all__ = ["Branch", "Bifurcation", "ContinuationOptions", "continue_orbit", "KINDS"]

#: Kinds of bifurcation detected.
KINDS: tuple[str, ...] = ("fold", "period-doubling", "neimark-sacker")


@dataclass(frozen=True)
class ContinuationOptions:
    """Checked options of :func:`continue_orbit` (see its docstring for each)."""

    ds: float = 0.05
    ds_min: float = 1e-6
    ds_max: float = 0.5
    max_points: int = 500
    tol: float = 1e-8
    max_newton: int = 6
    rtol: float = opt.CONTINUATION_RTOL
    atol: float = opt.CONTINUATION_ATOL
    method: str = "DOP853"
    max_steps: int | None = None
    locate_rtol: float = opt.MONODROMY_RTOL
    locate_atol: float = opt.MONODROMY_ATOL
    locate_tol: float = opt.ORBIT_TOL
    detect: tuple[str, ...] = KINDS
    segments: int = 1
    breakpoints: tuple[float, ...] = ()
    fixed: tuple[int, ...] = ()
    free_params: tuple[float, ...] = ()
    floquet_states: tuple[int, ...] | None = None
    switch_amplitude: float = 1e-2


@dataclass(frozen=True)
class Bifurcation:
    """A bifurcation located on a branch.

    Attributes
    ----------
    kind : str
        ``"fold"``, ``"period-doubling"`` or ``"neimark-sacker"``.
    p : float
        Parameter value, from the defining condition (not read off the grid).
    period : float
        Period of the orbit there.
    x0 : ndarray, shape (n,)
        State on the orbit at t = 0 (the phase of the branch's orbits).
    params : ndarray
        Free parameters there (empty without ``free_params``).
    multipliers : ndarray, complex
        Floquet multipliers there, sorted by modulus (descending).
    test_value : float
        The defining condition's value at the located point (0 to the location tolerance).
    index : int
        The branch point just before the bifurcation.
    """

    kind: str
    p: float
    period: float
    x0: np.ndarray
    params: np.ndarray
    multipliers: np.ndarray
    test_value: float
    index: int
    located: bif.Located = field(repr=False, compare=False)

    def __post_init__(self) -> None:
        freeze(self)


@dataclass(frozen=True)
class Branch:
    """A branch of periodic orbits, one row per point (see :func:`continue_orbit`).

    Attributes
    ----------
    p : ndarray, shape (m,)
        Parameter values.
    period : ndarray, shape (m,)
        Periods.
    x0 : ndarray, shape (m, n)
        State at t = 0 on each orbit.
    params : ndarray, shape (m, n_q)
        Free parameters at each point (``n_q = 0`` without ``free_params``).
    multipliers : ndarray, shape (m, k), complex
        Floquet multipliers of each orbit, sorted by modulus (descending) as in
        :mod:`flapping.periodic.floquet`.
    stable : ndarray of bool, shape (m,)
        Every multiplier (but the trivial one of an autonomous orbit) inside the unit circle.
    residual : ndarray, shape (m,)
        Residual norm of the shooting map at each point.
    bifurcations : tuple of Bifurcation
        In the order met.
    message : str
        Why the continuation stopped.
    success : bool
        True if it stopped because p reached ``p_end``.
    autonomous : bool
        Whether the period is an unknown.
    segments : int
        Shooting segments used (doubled at each branch switching).
    nfev : int
        Evaluations of ``fun`` (finite differences included).
    """

    p: np.ndarray
    period: np.ndarray
    x0: np.ndarray
    params: np.ndarray
    multipliers: np.ndarray
    stable: np.ndarray
    residual: np.ndarray
    bifurcations: tuple[Bifurcation, ...]
    message: str
    success: bool
    autonomous: bool
    segments: int
    nfev: int
    context: Any = field(repr=False, compare=False, default=None)

    def __post_init__(self) -> None:
        freeze(self)

    def __len__(self) -> int:
        return int(self.p.size)

    @property
    def det(self) -> np.ndarray:
        """``det M`` at each point (product of the multipliers), for Liouville's formula."""
        return np.prod(self.multipliers, axis=1).real

    def to_table(self) -> list[dict[str, Any]]:
        """Rows ``{"p", "period", "abs_mu" (list, descending), "stable"}``, one per point.

        Returns
        -------
        list of dict
            Plain Python values (``pandas.DataFrame(branch.to_table())`` makes a frame).
        """
        return [{"p": float(p), "period": float(T), "abs_mu": [float(v) for v in np.abs(m)],
                 "stable": bool(s)}
                for p, T, m, s in zip(self.p, self.period, self.multipliers, self.stable,
                                      strict=True)]

    def plot(self, measure: Callable[[np.ndarray], float] | None = None, axes: Any = None,
             label: str | None = None) -> Any:
        """Plot the branch and the multipliers' moduli against the parameter (matplotlib).

        Parameters
        ----------
        measure : callable, optional
            ``measure(x0) -> float`` plotted in the upper panel (default: the period).
        axes : pair of matplotlib Axes, optional
            Where to draw; default a new figure with two panels sharing the p axis.
        label : str, optional
            Legend label of the branch.

        Returns
        -------
        pair of matplotlib Axes
            Upper: the branch (stable solid, unstable dashed), bifurcations marked. Lower:
            ``abs(mu)`` of every multiplier, with the unit circle's modulus 1.
        """
        from flapping.periodic._branchplot import plot_branch
        return plot_branch(self, measure, axes, label)

    def switch(self, bifurcation: Bifurcation, p_end: float, **options: Any) -> Branch:
        """Follow the doubled orbit born at a period doubling of this branch.

        Parameters
        ----------
        bifurcation : Bifurcation
            A ``"period-doubling"`` of this branch.
        p_end : float
            Where to stop the new branch.
        **options
            Overrides of this branch's options (:class:`ContinuationOptions`).

        Returns
        -------
        Branch
            The branch of the doubled orbit (period about twice, 2M segments).

        Raises
        ------
        ValueError
            If ``bifurcation`` is not a period doubling of this branch.
        ConvergenceError
            If no genuinely doubled orbit is found near the bifurcation (the corrector slides
            back onto the period-1 orbit traversed twice, or fails).
        """
        if bifurcation.kind != "period-doubling" or bifurcation not in self.bifurcations:
            raise ValueError("`bifurcation` must be a period doubling of this branch; got "
                             f"{bifurcation.kind!r} at p = {bifurcation.p!r}")
        system, opts = self.context
        opts = _check_options({**_as_dict(opts), **options})
        p_end = check.real("p_end", p_end)
        system = _with_settings(system, opts)
        double, u, d, message = bif.double_at(
            system, bifurcation.located, lambda s: bif.Corrector(s, opts.tol, opts.max_newton),
            opts.switch_amplitude)
        if message:
            raise ConvergenceError(f"branch switching at the period doubling p = "
                                   f"{bifurcation.p:.10g} failed: {message}")
        return _Tracer(double, opts, p_end).run(u, d)


def _as_dict(opts: ContinuationOptions) -> dict[str, Any]:
    return {k: getattr(opts, k) for k in ContinuationOptions.__dataclass_fields__}


#: The :class:`~flapping.periodic.settings.SolverSettings` fields that continuation uses.
_SETTINGS_FIELDS = ("method", "rtol", "atol", "max_steps", "tol", "max_newton")


def _check_options(options: dict[str, Any], settings: Any = None) -> ContinuationOptions:
    """The options, checked; unknown names are a ValueError naming the accepted ones.

    Precedence: ``options`` (keywords), then the fields of ``settings``, then the defaults.
    """
    names = ContinuationOptions.__dataclass_fields__
    unknown = sorted(set(options) - set(names))
    if unknown:
        raise ValueError(f"unknown option(s) {unknown}; accepted: {sorted(names)}")
    defaults = _as_dict(ContinuationOptions())
    given = opt.resolve(settings, {k: defaults[k] for k in _SETTINGS_FIELDS},
                        **{k: options.get(k) for k in _SETTINGS_FIELDS})
    o = {**defaults, **options, **given}
    for k in ("ds", "ds_min", "ds_max", "tol", "rtol", "atol", "locate_rtol", "locate_atol",
              "locate_tol", "switch_amplitude"):
        o[k] = check.positive(k, o[k])
    # The corrector's tol (and locate_tol) is relative to 1 + max |s_k| already: at most
    # RESIDUAL_CEILING (1e-6), the closure floquet.monodromy still accepts as an orbit; Newton
    # converges quadratically, so a tighter tol costs one iteration, a looser one lets the
    # branch "reach p_end" through points that are on no orbit (tol = 1e6 once did).
    for k in ("tol", "locate_tol"):
        o[k] = check.real(k, o[k], low=0.0, high=opt.RESIDUAL_CEILING, low_open=True)
    # switch_amplitude is relative to the orbit's size: beyond 1 the first step onto the
    # doubled orbit is larger than the orbit itself.
    o["switch_amplitude"] = check.real("switch_amplitude", o["switch_amplitude"], low=0.0,
                                       high=1.0, low_open=True)
    if not o["ds_min"] <= o["ds"] <= o["ds_max"]:
        raise ValueError(f"`ds` must lie in [`ds_min`, `ds_max`] = [{o['ds_min']!r}, "
                         f"{o['ds_max']!r}] (and ds_min <= ds_max); got ds = {o['ds']!r}")
    o["max_points"] = opt.capped("max_points", o["max_points"], low=2)
    o["segments"] = opt.capped("segments", o["segments"])
    for k in ("locate_rtol", "rtol"):
        o[k] = opt.check_rtol(k, o[k])
    detect = (o["detect"],) if isinstance(o["detect"], str) else tuple(o["detect"])
    for kind in detect:
        check.choice("detect", kind, KINDS)
    o["detect"] = detect
    o["breakpoints"] = seg.check_breakpoints(o["breakpoints"])
    o["fixed"] = tuple(check.integer("fixed", i, low=0) for i in o["fixed"])
    o["free_params"] = tuple(float(v) for v in check.vector(
        "free_params", np.atleast_1d(np.asarray(o["free_params"], dtype=float)))) \
        if len(np.atleast_1d(o["free_params"])) else ()
    if o["floquet_states"] is not None:
        o["floquet_states"] = tuple(check.integer("floquet_states", i, low=0)
                                    for i in o["floquet_states"])
    seg.check_settings(o["method"], o["rtol"], o["atol"], 1024, o["max_steps"])
    return ContinuationOptions(**o)


def _with_settings(system: OrbitSystem, opts: ContinuationOptions) -> OrbitSystem:
    system.settings = _integration(opts, opts.rtol, opts.atol)
    return system


def _integration(opts: ContinuationOptions, rtol: float, atol: float) -> seg.Settings:
    """The integration settings of the branch; DOP853 steps by :class:`LeanDOP853`.

    A branch integrates tens of thousands of DOP853 steps of a small system, where scipy's
    per-stage bookkeeping costs more than the user's right-hand side; the lean step is the same
    method (tableau, error estimate, step control) with rounding-level differences.
    """
    settings = seg.check_settings(opts.method, rtol, atol, 1024, opts.max_steps)
    if settings.solver is DOP853:
        settings = replace(settings, solver=LeanDOP853)
    return settings


@dataclass
class _Point:
    """One accepted point of the branch."""

    u: np.ndarray
    t: np.ndarray
    J: np.ndarray
    mu: np.ndarray
    residual: float
    tests: bif.TestValues


class _Tracer:
    """The continuation loop: predictor, corrector, step control, detection, stopping."""

    def __init__(self, system: OrbitSystem, opts: ContinuationOptions, p_end: float) -> None:
        self.system, self.opts, self.p_end = system, opts, p_end
        self.corrector = bif.Corrector(system, opts.tol, opts.max_newton)
        # location corrects to locate_tol (never looser than the branch's tol); where that
        # tolerance is out of reach (integration noise), the branch's corrector tries again
        self.locate_corrector = bif.Corrector(system, min(opts.tol, opts.locate_tol),
                                              opts.max_newton)
        self.locate_settings = _integration(opts, opts.locate_rtol, opts.locate_atol)
        self.points: list[_Point] = []
        self.found: list[Bifurcation] = []
        self.stop = ""

    def _point(self, u: np.ndarray, ev: Any, previous: np.ndarray | None) -> _Point:
        # The phase hyperplane moves to this point now: the Jacobian's phase row and the
        # tangent follow it, so that the next predictor stays on the next hyperplane.
        J = self.system.rephase(u, ev.jacobian)
        t = bif.tangent(J, previous)
        mu = self.system.multipliers(ev.monodromy)
        return _Point(u, t, J, mu, float(np.linalg.norm(ev.residual)),
                      bif.test_values(self.system, mu, t))

    def run(self, u0: np.ndarray, direction: np.ndarray) -> Branch:
        """Follow the branch from the corrected point ``u0``, leaving along ``direction``."""
        system, opts = self.system, self.opts
        system.set_reference(u0)
        ev = system.evaluate(u0)
        self.points.append(self._point(u0, ev, direction))
        self.start_sign = math.copysign(1.0, float(u0[-1]) - self.p_end)
        self.T0 = system.unpack(u0)[1]
        self.L0 = self._length(u0)
        ds, message, reached = opts.ds, "", False
        while not message:
            if len(self.points) >= opts.max_points:
                message = f"step budget spent (max_points = {opts.max_points})"
                break
            last = self.points[-1]
            try:
                out = self.corrector(self._predict(ds), last.u, last.t, ds, J0=last.J)
            except ValueError as exc:  # the user's model refuses a parameter value: its edge
                if ds > 4 * opts.ds_min:
                    ds *= 0.25
                    continue
                message = (f"the model refused a parameter value near p = {last.u[-1]:.10g}: "
                           f"{exc}")
                break
            if out is None:
                ds *= 0.5
                if ds < opts.ds_min:
                    message = (f"step size below minimum (ds_min = {opts.ds_min:g}) at "
                               f"p = {last.u[-1]:.10g}: {self.corrector.message}")
                continue
            u, ev, nit = out
            if (float(u[-1]) - self.p_end) * self.start_sign <= 0:
                reached = self._finish(last)
                message = "reached p_end" if reached else (
                    f"could not correct the last point at p_end: {self.corrector.message}")
                break
            self._accept(self._point(u, ev, last.t))
            message = self.stop or self._degenerate()
            ds = min(ds * 1.5, opts.ds_max) if nit <= 1 else (ds * 0.6 if nit >= 3 else ds)
            ds = max(ds, opts.ds_min)
        return self._branch(message, reached)

    def _predict(self, ds: float) -> np.ndarray:
        """Second-order predictor: the tangent plus the curvature of the last two tangents."""
        last = self.points[-1]
        u = last.u + ds * last.t
        if len(self.points) >= 2:
            before = self.points[-2]
            h = float(np.linalg.norm(last.u - before.u))
            if h > 0:
                u += 0.5 * ds * ds * (last.t - before.t) / h
        return self.system.onto_phase(u)

    def _finish(self, last: _Point) -> bool:
        """Correct the last point at p = p_end exactly (natural parameter)."""
        e_p = np.zeros_like(last.u)
        e_p[-1] = 1.0
        guess = last.u + (self.p_end - last.u[-1]) / last.t[-1] * last.t \
            if abs(last.t[-1]) > 1e-3 else last.u
        out = self.corrector(guess, last.u, e_p, self.p_end - float(last.u[-1]))
        if out is None:
            return False
        self._accept(self._point(out[0], out[1], last.t))
        return True

    def _accept(self, point: _Point) -> None:
        previous = self.points[-1]
        self.points.append(point)
        for kind in self._changes(previous.tests, point.tests):
            xtol = 1e-13 * (1.0 + abs(float(point.u[-1])))
            located = bif.locate(kind, self.locate_corrector, self.locate_settings, previous.u,
                                 previous.t, point.u, xtol)
            if located is None and self.locate_corrector.tol < self.corrector.tol:
                located = bif.locate(kind, self.corrector, self.locate_settings, previous.u,
                                     previous.t, point.u, xtol)
            if located is None:
                continue
            if kind == "fold" and self._length(located.u) < 1e-3 * self.L0:
                # the branch ran through zero amplitude (it continues as the same orbits
                # shifted by half a period): a Hopf point, not a fold
                self.points.pop()
                p = float(located.u[-1])
                self.stop = (f"the orbit shrank onto an equilibrium at p = {p:.10g} (a Hopf "
                             f"point ends the branch)")
                return
            self.found.append(self._bifurcation(located, len(self.points) - 2))
        self.system.set_reference(point.u)

    def _changes(self, a: bif.TestValues, b: bif.TestValues) -> list[str]:
        kinds = []
        if a.fold_tp * b.fold_tp < 0:
            kinds.append("fold")
        if a.pd * b.pd < 0:
            kinds.append("period-doubling")
        if a.n_complex_out != b.n_complex_out and a.has_complex and b.has_complex:
            kinds.append("neimark-sacker")
        return [k for k in kinds if k in self.opts.detect]

    def _bifurcation(self, located: bif.Located, index: int) -> Bifurcation:
        states, T, q, p = self.system.unpack(located.u)
        assert located.evaluation.monodromy is not None
        return Bifurcation(located.kind, p, T, states[0].copy(), q.copy(),
                           self.system.multipliers(located.evaluation.monodromy),
                           located.value, index, located)

    def _length(self, u: np.ndarray) -> float:
        """``abs(f(x0)) T``, the size of an autonomous orbit (its length, for a circle)."""
        if not self.system.autonomous:
            return 1.0
        states, T, q, p = self.system.unpack(u)
        f = self.system.vector_field(states[0], np.concatenate([[p], q]))
        return float(np.linalg.norm(f)) * T

    def _degenerate(self) -> str:
        """Why an autonomous branch cannot go on (orbit shrunk or period unbounded), or ''."""
        if not self.system.autonomous:
            return ""
        states, T, q, p = self.system.unpack(self.points[-1].u)
        size = self._length(self.points[-1].u)
        if size <= 1e-4 * self.L0:
            return (f"the orbit shrank onto an equilibrium at p = {p:.10g} (abs(f(x0)) T = "
                    f"{size:.2e}): a Hopf point ends the branch")
        if T > 50.0 * self.T0:
            return (f"the period grows without bound (T = {T:.6g} at p = {p:.10g}, "
                    f"{T / self.T0:.0f} times the first): a homoclinic orbit ends the branch")
        return ""

    def _branch(self, message: str, reached: bool) -> Branch:
        system = self.system
        rows = [system.unpack(pt.u) for pt in self.points]
        mus = np.array([pt.mu for pt in self.points])
        return Branch(
            p=np.array([r[3] for r in rows]), period=np.array([r[1] for r in rows]),
            x0=np.array([r[0][0] for r in rows]),
            params=np.array([r[2] for r in rows]).reshape(len(rows), system.n_q),
            multipliers=mus, stable=np.array([_stable(system, m) for m in mus]),
            residual=np.array([pt.residual for pt in self.points]),
            bifurcations=tuple(self.found), message=message, success=reached,
            autonomous=system.autonomous, segments=system.M, nfev=system.counter.n,
            context=(system, self.opts))


def _stable(system: OrbitSystem, mu: np.ndarray) -> bool:
    return bool(np.all(np.abs(bif.nontrivial(system, mu)) < 1.0))


def _start(fun: Any, jac: Any, x0: np.ndarray, period: Any, p0: float, autonomous: bool,
           opts: ContinuationOptions) -> tuple[OrbitSystem, np.ndarray]:
    """The system and the first point, from :func:`find_periodic_orbit` at p0."""
    n = x0.size
    n_seg = len(opts.breakpoints) + 1
    funs = seg.segment_callables(fun, n_seg, "fun")
    jacs = (None,) * n_seg if jac is None else seg.segment_callables(jac, n_seg, "jac")
    q0 = np.array(opts.free_params, dtype=float)
    period_fn = None
    if not autonomous:
        T_fixed = None if callable(period) else check.positive("period", period)
        period_fn = period if T_fixed is None else (lambda p: T_fixed)
    _probe(funs[0], jacs[0], x0, p0, q0)
    floquet = tuple(range(n)) if opts.floquet_states is None else opts.floquet_states
    if any(i >= n for i in opts.fixed + floquet):
        raise ValueError(f"`fixed` and `floquet_states` must be indices in [0, {n})")
    system = OrbitSystem(funs, jacs, n, autonomous, period_fn, opts.segments, opts.fixed,
                         q0.size, opts.breakpoints, _integration(opts, opts.rtol, opts.atol),
                         floquet)
    if system.size - 1 != n * opts.segments + int(autonomous):
        raise ValueError(
            f"the continuation needs as many `fixed` components as `free_params`: got "
            f"{len(opts.fixed)} fixed and {q0.size} free parameters")
    if autonomous:
        T0 = check.positive("period", period)
    else:
        try:
            T0 = system.period(p0)
        except Exception as exc:  # the user's callable: its error, with where it was raised
            exc.add_note(f"(raised by `period` at its first call, period(p0) with p0 = {p0!r})")
            raise
    orbit = _first_orbit(funs, jacs, x0, T0, p0, q0, autonomous, opts)
    states = orbit.segment_states.T if orbit.segment_states is not None else orbit.x0[None, :]
    system.base = orbit.x0.copy()
    q = orbit.params if orbit.params is not None else q0
    return system, system.pack(states, orbit.period, q, p0)


def _probe(fun: Any, jac: Any, x0: np.ndarray, p0: float, q0: np.ndarray) -> None:
    """``fun`` and ``jac`` of the first segment once each at ``(0, x0, p0[, free_params])``,
    checked: a signature, type or shape mistake is named here, not deep in the solve."""
    n, extra = x0.size, ((p0, q0.copy()) if q0.size else (p0,))
    tail, given = ((", p, params", "the parameter p0 and `free_params`") if q0.size
                   else (", p", "the parameter p0"))
    first_call(fun, "fun", 0.0, x0, extra, (n,), call=f"fun(t, x{tail})", given=given)
    if jac is not None:
        first_call(jac, "jac", 0.0, x0, extra, (n, n), call=f"jac(t, x{tail})", given=given)


def _first_orbit(funs: tuple[Any, ...], jacs: tuple[Any, ...], x0: np.ndarray, T0: float,
                 p0: float, q0: np.ndarray, autonomous: bool, opts: ContinuationOptions) -> Any:
    """The orbit at p0 by Levenberg-Marquardt shooting, or a ConvergenceError saying so."""
    def bind(f: Any) -> Any:
        if f is None:
            return None
        return (lambda t, x, q, _f=f: _f(t, x, p0, q)) if q0.size else \
            (lambda t, x, _f=f: _f(t, x, p0))
    try:
        return find_periodic_orbit(
            [bind(f) for f in funs], x0, T0, autonomous=autonomous,
            jac=None if jacs[0] is None else [bind(j) for j in jacs],
            free_params=q0 if q0.size else None, fixed=opts.fixed,
            breakpoints=opts.breakpoints, segments=opts.segments, method=opts.method,
            rtol=opts.rtol, atol=opts.atol, tol=opts.tol, max_steps=opts.max_steps)
    except ConvergenceError as exc:
        raise ConvergenceError(f"continue_orbit: no periodic orbit near the guess at p0 = "
                               f"{p0!r}: {exc}", x=exc.x, residual=exc.residual,
                               iterations=exc.iterations, result=exc.result, t=exc.t,
                               state=exc.state, source=exc.source) from None


def continue_orbit(
    fun: Callable[..., Any] | Sequence[Callable[..., Any]],
    x0: Any,
    period: float | Callable[[float], float],
    p0: float,
    p_end: float,
    *,
    autonomous: bool = True,
    jac: Callable[..., Any] | Sequence[Callable[..., Any]] | None = None,
    settings: opt.SolverSettings | None = None,
    **options: Any,
) -> Branch:
    """Follow a periodic orbit from ``p0`` to ``p_end`` by pseudo-arclength continuation.

    Parameters
    ----------
    fun : callable or sequence of callables
        ``fun(t, x, p)`` with the scalar parameter p last (``fun(t, x, p, params)`` with
        ``free_params``: the free parameters solved with each orbit); one callable per segment
        of the period with ``breakpoints``.
    x0 : array_like, shape (n,)
        A state on (or near) the orbit at ``p0``.
    period : float or callable
        Autonomous: a guess of the period at ``p0``. Forced: the period, or ``period(p)`` when
        the forcing frequency depends on the parameter.
    p0, p_end : float
        Start and end of the parameter range (``p_end != p0``).
    autonomous : bool, optional
        True: the period is an unknown, with a moving Poincare-type phase condition.
    jac : callable or sequence of callables, optional
        ``jac(t, x, p)``: ``df/dx``; default central differences of ``fun``.
    **options
        :class:`ContinuationOptions`: ``ds`` (first step, 0.05), ``ds_min`` (1e-6), ``ds_max``
        (0.5), ``max_points`` (500), ``tol`` (corrector residual, 1e-8), ``max_newton`` (6),
        ``rtol``/``atol`` (1e-10), ``method`` ("DOP853"), ``max_steps`` (per integration),
        ``locate_rtol``/``locate_atol`` (1e-12) and ``locate_tol`` (1e-10): the tighter
        settings of bifurcation location, ``detect`` (kinds to detect, default all),
        ``segments`` (M, 1), ``breakpoints`` (forced), ``fixed`` (components of x0 held) with
        as many ``free_params`` (initial values of the free parameters ``params``, extra
        unknowns; e.g. an amplitude fixed by an extra periodic state), ``floquet_states`` (the
        states whose block of the monodromy matrix gives the multipliers, default all),
        ``switch_amplitude`` (1e-2, relative size of the first step onto a doubled orbit).
        ``max_points`` is at most 10**5, ``max_newton`` at most 100, ``segments`` at most 1024;
        an ``rtol`` or ``locate_rtol`` below ``100 eps`` is raised to it with a
        :class:`~flapping.errors.ToleranceWarning`.
    settings : SolverSettings, optional
        ``method``, ``rtol``, ``atol``, ``max_steps``, ``tol`` and ``max_newton`` as one object
        (:mod:`flapping.periodic.settings`; ``rk4_steps`` and ``max_nfev`` are not used); an
        option given as a keyword overrides the same field.

    Returns
    -------
    Branch
        Points, multipliers, stability, bifurcations and the reason it stopped.

    Raises
    ------
    ValueError
        For bad arguments (``p_end == p0``, unknown options, non-finite numbers, ``tol`` or
        ``locate_tol`` outside (0, 1e-6] (relative: the closure :func:`monodromy` accepts),
        ``rtol`` or ``locate_rtol`` above 1e-3, ``atol`` or ``locate_atol`` above
        ``1e-2 max(1, |x0|)``, ``switch_amplitude`` outside (0, 1], ...); ``fun`` or ``jac``
        returning a wrong shape or raising a ValueError or IndexError at the first call (naming
        ``x0``); a non-finite value (:class:`~flapping.errors.NonFiniteError`).
    TypeError
        ``fun`` or ``jac`` cannot be called as ``fun(t, x, p)`` (``fun(t, x, p, params)`` with
        ``free_params``), or returned None, a string, or complex or boolean values.
    ConvergenceError
        If no periodic orbit is found near ``x0`` at ``p0`` (with ``t``, ``state``, ``source``
        when an integration failed).
    """
    x = check.vector("x0", x0)
    p0, p_end = check.real("p0", p0), check.real("p_end", p_end)
    if p_end == p0:
        raise ValueError(f"`p_end` equals `p0` ({p0!r}): nothing to continue (use "
                         f"find_periodic_orbit for one parameter value)")
    if not isinstance(autonomous, (bool, np.bool_)):
        raise ValueError(f"`autonomous` must be True or False; got {autonomous!r}")
    if autonomous and callable(period):
        raise ValueError("`period` must be a number (a guess) for an autonomous system")
    opts = _check_options(options, settings)
    for name in ("atol", "locate_atol"):
        opt.check_scaled(name, getattr(opts, name), x, opt.TOL_CEILING)
    if autonomous and opts.breakpoints:
        raise ValueError("`breakpoints` need a forced system (autonomous=False)")
    system, u0 = _start(fun, jac, x, period, p0, bool(autonomous), opts)
    e_p = np.zeros(u0.size)
    e_p[-1] = math.copysign(1.0, p_end - p0)
    return _Tracer(system, opts, p_end).run(u0, e_p)

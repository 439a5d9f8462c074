"""Package-internal: the corrector, test functions, bifurcation location and branch switching.

Test functions along a branch (Kuznetsov 2004, ch. 10; Seydel 2010):

* fold: detected where the p-component of the arclength tangent changes sign (the branch turns
  back); located by solving ``det(dF/dv) = 0``, the Jacobian of the shooting map in every unknown
  but p. For a forced orbit that is ``det(M - I) = 0``; for an autonomous one the bordered
  ``det([[M - I, f], [f_ref^T, 0]])`` (the trivial multiplier is double at the fold, so
  ``det(M - I)`` vanishes identically and cannot serve);
* period doubling: ``det(M + I)`` changes sign (a real multiplier crosses -1);
* Neimark-Sacker: the number of complex multipliers outside the unit circle changes while a
  complex pair exists at both ends; located by ``|mu| - 1 = 0`` for the complex pair nearest the
  circle. A pair that forms inside (or outside) the circle from two real multipliers is not one.

Location: the test function is a scalar function of the arclength ``s`` from the last point
before the change, each value from a point corrected onto the branch (on the hyperplane
``<u - u_i, t_i> = s``) with the multipliers recomputed there (AUTO-07p issue 35), at the tighter
location tolerances; Brent's method finds its root.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from flapping.periodic import _segments as seg
from flapping.periodic._branchflow import Evaluation, IntegrationFailed, OrbitSystem
from flapping.periodic._readonly import freeze
from flapping.periodic.floquet import nontrivial_multipliers

__all__ = ["Corrector", "Located", "TestValues", "test_values", "locate", "tangent",
           "double_at"]

#: Imaginary part (relative to the modulus) below which a multiplier counts as real.
REAL_TOL = 1e-7


@dataclass(frozen=True)
class TestValues:
    """The test functions at one branch point."""

    pd: float  # det(M + I)
    fold_tp: float  # p-component of the tangent
    n_complex_out: int  # complex multipliers with modulus > 1
    has_complex: bool


@dataclass(frozen=True)
class Located:
    """A located bifurcation: the corrected point, its evaluation and test-function value."""

    kind: str
    u: np.ndarray
    evaluation: Evaluation
    tangent: np.ndarray
    value: float

    def __post_init__(self) -> None:
        freeze(self)
        freeze(self.evaluation)  # the located point owns its evaluation


def tangent(J: np.ndarray, previous: np.ndarray | None) -> np.ndarray:
    """Unit null vector of the (N-1) x N Jacobian, oriented along ``previous``."""
    t = np.linalg.svd(J)[2][-1]
    if previous is not None and t @ previous < 0:
        t = -t
    return t


class Corrector:
    """Newton's method on ``F(u) = 0`` plus one linear constraint ``<u - u_c, d> = s``.

    Parameters
    ----------
    system : OrbitSystem
        The shooting map.
    tol : float
        Required residual norm, relative to ``1 + max abs(s_k)`` (the size of the states).
    max_iter : int
        Newton iterations before giving up.
    """

    def __init__(self, system: OrbitSystem, tol: float, max_iter: int) -> None:
        self.system, self.tol, self.max_iter = system, tol, max_iter
        self.message = ""

    def __call__(self, u: np.ndarray, u_c: np.ndarray, d: np.ndarray, s: float,
                 J0: np.ndarray | None = None) -> tuple[np.ndarray, Evaluation, int] | None:
        """The corrected point, its evaluation and the iterations; None on failure.

        ``J0``: a Jacobian to take the first (chord) step with, saving one variational
        integration; without it the first step uses the Jacobian at ``u``.
        """
        u = u.copy()
        try:
            ev = self.system.evaluate(u, jacobian=J0 is None)
            J = J0 if J0 is not None else ev.jacobian
            first = float(np.linalg.norm(ev.residual))
            for it in range(1, self.max_iter + 1):
                assert J is not None
                A = np.vstack([J, d])
                b = np.append(ev.residual, d @ (u - u_c) - s)
                u = u + np.linalg.solve(A, -b)
                ev = self.system.evaluate(u, jacobian=True)
                J = ev.jacobian
                norm = float(np.linalg.norm(ev.residual))
                if norm <= self.tol * self.system.scale(u):
                    return u, ev, it
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


def nontrivial(system: OrbitSystem, mu: np.ndarray) -> np.ndarray:
    """The multipliers without the trivial one of an autonomous orbit (all of a forced one's)."""
    return nontrivial_multipliers(mu) if system.autonomous and mu.size else mu


def _is_complex(mu: np.ndarray) -> np.ndarray:
    return np.abs(mu.imag) > REAL_TOL * np.maximum(np.abs(mu), 1e-300)


def test_values(system: OrbitSystem, mu: np.ndarray, t: np.ndarray) -> TestValues:
    """The test functions at a point with multipliers ``mu`` and tangent ``t``."""
    others = nontrivial(system, mu)
    cplx = _is_complex(others)
    return TestValues(pd=float(np.prod(mu + 1.0).real), fold_tp=float(t[-1]),
                      n_complex_out=int(np.sum(cplx & (np.abs(others) > 1.0))),
                      has_complex=bool(np.any(cplx)))


def _pd_value(system: OrbitSystem, ev: Evaluation, _t: np.ndarray) -> float:
    assert ev.monodromy is not None
    return float(np.prod(system.multipliers(ev.monodromy) + 1.0).real)


def _fold_value(system: OrbitSystem, ev: Evaluation, _t: np.ndarray) -> float:
    assert ev.jacobian is not None
    return float(np.linalg.det(ev.jacobian[:, :-1]))


def _ns_value(system: OrbitSystem, ev: Evaluation, _t: np.ndarray) -> float:
    assert ev.monodromy is not None
    others = nontrivial(system, system.multipliers(ev.monodromy))
    pairs = others[_is_complex(others)]
    if not pairs.size:
        return float("nan")
    return float(np.abs(pairs[np.argmin(np.abs(np.abs(pairs) - 1.0))]) - 1.0)


TESTS: dict[str, Callable[[OrbitSystem, Evaluation, np.ndarray], float]] = {
    "fold": _fold_value, "period-doubling": _pd_value, "neimark-sacker": _ns_value}


def locate(kind: str, corrector: Corrector, settings: seg.Settings, u_i: np.ndarray,
           t_i: np.ndarray, u_j: np.ndarray, xtol: float) -> Located | None:
    """Solve the defining condition of ``kind`` between the branch points ``u_i``, ``u_j``.

    Returns None when the test function has no sign change on the re-corrected points (a
    grid artefact) or a point cannot be corrected.
    """
    system = corrector.system
    saved_settings, saved_ref = system.settings, system.ref
    system.settings = settings
    system.set_reference(u_i)
    cache: dict[float, tuple[np.ndarray, Evaluation, float]] = {}

    def g(s: float) -> float:
        near = min(cache, key=lambda v: abs(v - s)) if cache else None
        start = u_i + s * t_i if near is None else cache[near][0] + (s - near) * t_i
        out = corrector(start, u_i, t_i, s)
        if out is None:
            raise IntegrationFailed(corrector.message)
        value = TESTS[kind](system, out[1], t_i)
        cache[s] = (out[0], out[1], value)
        return value

    try:
        s_end = float(t_i @ (u_j - u_i))
        a, b = g(0.0), g(s_end)
        if not (np.isfinite(a) and np.isfinite(b)) or a * b > 0:
            return None
        s = brentq(g, 0.0, s_end, xtol=xtol, rtol=4 * np.finfo(float).eps, maxiter=100)
        if s not in cache:
            g(s)
        u, ev, value = cache[s]
        assert ev.jacobian is not None
        return Located(kind, u, ev, tangent(ev.jacobian, t_i), value)
    except (IntegrationFailed, ValueError, RuntimeError):
        return None
    finally:
        system.settings, system.ref = saved_settings, saved_ref


def double_at(system: OrbitSystem, located: Located, corrector_for: Callable[
        [OrbitSystem], Corrector], amplitude: float) -> tuple[OrbitSystem, np.ndarray,
                                                              np.ndarray, str]:
    """Branch switching at a period doubling: a first point of the doubled orbit.

    The doubled system (2M segments, period 2T) has a pitchfork at the period-doubling point:
    the period-1 orbit traversed twice and the new orbit cross. The new branch leaves along the
    critical eigenvector ``v`` (``M v = -v``) carried round the orbit, ``(v_0 .. v_{M-1}, -v_0 ..
    -v_{M-1})``, made orthogonal to the period-1 tangent so that the corrector cannot slide back
    onto the period-1 orbit. The result is checked to be genuinely doubled: ``x(T/2) != x(0)``.

    Returns the doubled system, the first point, the direction away from the bifurcation, and a
    message (empty on success).
    """
    ev = located.evaluation
    assert ev.monodromy is not None
    lam, vec = np.linalg.eig(ev.monodromy)
    v = vec[:, int(np.argmin(np.abs(lam + 1.0)))].real
    vs = [v / np.linalg.norm(v)]
    for F in ev.stms[:-1]:
        vs.append(F @ vs[-1])
    double = system.doubled()
    states, T, q, p = system.unpack(located.u)
    u_star = double.pack(np.vstack([states, states]), 2 * T, q, p)
    dstates, dT, dq, dp = system.unpack_delta(located.tangent)
    t1 = double.pack(np.vstack([dstates, dstates]), 2 * dT, dq, dp)
    d = double.pack(np.vstack([np.array(vs), -np.array(vs)]), 0.0, np.zeros_like(q), 0.0)
    t1 /= np.linalg.norm(t1)
    d -= (d @ t1) * t1
    d /= np.linalg.norm(d)
    double.set_reference(u_star)
    corrector = corrector_for(double)
    scale = 1.0 + float(np.linalg.norm(states[0]))
    message = "the corrector failed"
    for eps in amplitude * scale * np.array([1.0, 3.0, 0.3]):
        out = corrector(u_star + eps * d, u_star, d, eps)
        if out is None:
            message = corrector.message
            continue
        s = double.unpack(out[0])[0]
        split = float(np.linalg.norm(s[double.M // 2] - s[0]))
        if split > 1e-6 * scale:
            return double, out[0], d, ""
        message = (f"converged to the period-1 orbit traversed twice (|x(T/2) - x(0)| = "
                   f"{split:.2e})")
    return double, u_star, d, message

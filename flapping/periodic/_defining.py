"""Package-internal: the defining systems of codimension-one bifurcations of periodic orbits.

Used by :mod:`flapping.periodic.bifurcation_curves`. A forced orbit is a fixed point of the
stroboscopic map ``P(x; p, q)`` (the flow over one period); its monodromy matrix is
``M = dP/dx``, integrated exactly from the variational equations by
:class:`~flapping.periodic._branchflow.OrbitSystem` (one shooting segment, ``q`` its one free
parameter, ``p`` its continuation parameter). The unknowns are

    U = (x, [T,] q, p)            fold, period doubling
    U = (x, [T,] q, p, theta)     Neimark-Sacker

(T for an autonomous orbit) and the defining system ``G(U) = (x(T) - x, [phase,] g)`` is
minimally augmented (Govaerts 2000, ch. 4; Kuznetsov 2004, sec. 10.2): with
``A = M - lam I`` (``lam = 1``, ``-1``, ``exp(i theta)``) and border vectors ``b``, ``c``,
the scalar ``g`` solves the bordered system

    [[A, b], [c^H, 0]] [v; g] = [0; 1],

and vanishes exactly where ``A`` is singular (its null vector is then ``v``). The fold of an
autonomous orbit uses ``A = [[M - I, f(x)], [f_ref^T, 0]]`` instead (the trivial multiplier
makes ``M - I`` singular everywhere; Kuznetsov 2004, sec. 10.3.1). For
Neimark-Sacker ``A`` is complex and ``g`` gives two real equations (``Re g``, ``Im g``) for the
one extra unknown ``theta``, the angle of the critical pair: a bordered complex system keeps the
matrix of size n + 1 and gives ``theta`` directly (the strong resonances are where it crosses
0, pi/2, 2 pi/3, pi), where the bialternate product would square the size and lose the angle.
The borders are refreshed at every accepted point (``c`` the null vector ``v``, ``b`` the
adjoint one ``w``), which keeps the bordered matrix well conditioned.

Derivatives of ``g``: ``g_z = -w^H (dA/dz) v`` (``w^H A = 0`` and ``w^H b = 1``), with
``dA/dz v = (A(z + h e_z) - A(z)) v / h`` a forward difference of the monodromy matrix (one
variational integration per unknown, relative error ~1e-8). The exact derivative needs the
second-order variational equations, which the layer does not integrate; the difference only
enters the Newton matrix and the tangent, never the residual, so the curve is exact to the
corrector's tolerance (whose chord iterations use an older Jacobian anyway). ``g_theta`` is exact:
``dA/dtheta = -i exp(i theta) I``.

A *fixed orbit* (the same state ``x*`` for every ``(p, q)``: ``x = 0`` of a linear or an odd
system such as the Mathieu equation) has ``dP/dp = dP/dq = 0`` and, at a +1 multiplier, a line
of periodic solutions: the system above is singular there. The curve is then ``g(p, q) = 0``
with ``x = x*`` held (``U = (q, p[, theta])``), which is what is computed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from flapping.periodic import _segments as seg
from flapping.periodic._branchflow import (
    IntegrationFailed,
    OrbitSystem,
    _VariationalField,
)
from flapping.periodic.floquet import nontrivial_multipliers

__all__ = ["Defining", "Point"]

_SQRT_EPS = math.sqrt(float(np.finfo(float).eps))


@dataclass
class Point:
    """One point of the defining system: unknowns, residual, Jacobian, monodromy."""

    U: np.ndarray
    G: np.ndarray
    DG: np.ndarray
    monodromy: np.ndarray
    v: np.ndarray  # right null vector of A (approximately)
    w: np.ndarray  # left null vector of A (approximately)


class Defining:
    """``G(U)`` and ``dG/dU`` of one kind of bifurcation (module notes).

    Parameters
    ----------
    system : OrbitSystem
        One segment, one free parameter (q), forced or autonomous.
    kind : str
        ``"fold"``, ``"period-doubling"`` or ``"neimark-sacker"``.
    x_fixed : ndarray or None
        The fixed orbit's state, or None when the orbit's state is an unknown.
    """

    def __init__(self, system: OrbitSystem, kind: str, x_fixed: np.ndarray | None) -> None:
        self.system, self.kind, self.x_fixed = system, kind, x_fixed
        self.n, self.auto = system.n, system.autonomous
        self.nT = int(self.auto)
        self.ns = kind == "neimark-sacker"
        # an autonomous orbit's trivial multiplier makes M - I singular everywhere: its fold is
        # the singularity of M - I bordered by the vector field and the phase condition
        self.m = self.n + int(self.auto and kind == "fold")
        dtype = complex if self.ns else float
        self.b = np.zeros(self.m, dtype=dtype)
        self.c = np.zeros(self.m, dtype=dtype)

    # ---- layout ------------------------------------------------------------------------
    @property
    def size(self) -> int:
        """Number of unknowns."""
        return self.iq + 2 + int(self.ns)

    @property
    def iq(self) -> int:
        """Index of q in U."""
        return 0 if self.x_fixed is not None else self.n + self.nT

    def orbit_u(self, U: np.ndarray) -> np.ndarray:
        """The unknowns ``(x, [T,] q, p)`` of the orbit system."""
        if self.x_fixed is not None:
            return np.concatenate([self.x_fixed, U[:2]])
        return U[:self.iq + 2].copy()

    def x(self, U: np.ndarray) -> np.ndarray:
        """The orbit's state at t = 0."""
        return self.x_fixed.copy() if self.x_fixed is not None else U[:self.n].copy()

    def period(self, U: np.ndarray) -> float:
        """The period unknown of an autonomous orbit, or the (rescaled) forced one."""
        return self.system.unpack(self.orbit_u(U))[1]

    def pq(self, U: np.ndarray) -> tuple[float, float]:
        """``(p, q)``."""
        return float(U[self.iq + 1]), float(U[self.iq])

    def theta(self, U: np.ndarray) -> float:
        """The critical pair's angle (NaN but for Neimark-Sacker)."""
        return float(U[-1]) if self.ns else math.nan

    def pack(self, x: np.ndarray, T: float, p: float, q: float, theta: float) -> np.ndarray:
        """Unknowns from their parts (T only for an autonomous orbit)."""
        head = [] if self.x_fixed is not None else list(x) + ([T] if self.auto else [])
        return np.array(head + [q, p] + ([theta] if self.ns else []), dtype=float)

    def scale(self, U: np.ndarray) -> float:
        """``1 + |x|``: the size of the state, for relative tolerances."""
        return 1.0 + float(np.linalg.norm(self.x(U)))

    def effective(self, mu: np.ndarray) -> np.ndarray:
        """The multipliers without the trivial one of an autonomous orbit."""
        return nontrivial_multipliers(mu) if self.auto else mu

    # ---- the phase condition (autonomous) ----------------------------------------------
    def set_reference(self, point: Point) -> None:
        """Move the phase condition to the point; its Jacobian's phase row follows."""
        if not self.auto:
            return
        self.system.set_reference(self.orbit_u(point.U))
        assert self.system.ref is not None
        if point.DG.size:
            point.DG[self.n, :] = 0.0
            point.DG[self.n, :self.n] = self.system.ref[1]

    # ---- the bordered scalar -----------------------------------------------------------
    def lam(self, U: np.ndarray) -> complex:
        """The critical multiplier: 1, -1 or ``exp(i theta)``."""
        if self.kind == "fold":
            return 1.0
        if self.kind == "period-doubling":
            return -1.0
        return complex(np.exp(1j * float(U[-1])))

    def matrix(self, mono: np.ndarray, U: np.ndarray) -> np.ndarray:
        """``A = M - lam I`` (for an autonomous fold bordered by ``f(x)`` and ``f_ref``)."""
        A = mono - self.lam(U) * np.eye(self.n)
        if self.m == self.n:
            return A
        states, _, q, p = self.system.unpack(self.orbit_u(U))
        f = self.system.vector_field(states[0], np.concatenate([[p], q]))
        assert self.system.ref is not None
        return np.block([[A, f[:, None]], [self.system.ref[1][None, :], np.zeros((1, 1))]])

    def init_borders(self, mono: np.ndarray, U: np.ndarray) -> None:
        """Borders from the singular vectors of A's smallest singular value."""
        uu, _, vh = np.linalg.svd(self.matrix(mono, U))
        self.b, self.c = uu[:, -1].copy(), vh[-1].conj().copy()

    def bordered(self, mono: np.ndarray, U: np.ndarray) -> tuple[complex, np.ndarray,
                                                                   np.ndarray]:
        """``(g, v, w)``: the bordered scalar and the (approximate) right and left null vectors.

        Raises
        ------
        numpy.linalg.LinAlgError
            If the bordered matrix is singular (borders orthogonal to the null vectors).
        """
        n = self.m
        B = np.zeros((n + 1, n + 1), dtype=self.b.dtype)
        B[:n, :n] = self.matrix(mono, U)
        B[:n, n] = self.b
        B[n, :n] = self.c.conj()
        rhs = np.zeros(n + 1, dtype=B.dtype)
        rhs[n] = 1.0
        sol = np.linalg.solve(B, rhs)
        adj = np.linalg.solve(B.conj().T, rhs)
        return complex(sol[n]), sol[:n], adj[:n]

    def update_borders(self, point: Point) -> None:
        """Borders at an accepted point: its null vectors, normalised."""
        self.c = point.v / np.linalg.norm(point.v)
        self.b = point.w / np.linalg.norm(point.w)

    # ---- G and dG/dU ------------------------------------------------------------------
    def _g_rows(self, g: complex) -> list[float]:
        return [g.real, g.imag] if self.ns else [g.real]

    def flow(self, u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(x(T), M)`` at the orbit unknowns u: state and monodromy only.

        The orbit system's own evaluation also integrates the sensitivities to (p, q) (one
        more call of ``fun`` per parameter at every stage); the residual and the difference
        quotients of ``g`` need only the state and the monodromy, at about half the cost.

        Raises
        ------
        IntegrationFailed
        """
        system, n = self.system, self.n
        states, T, q, p = system.unpack(u)
        P = np.concatenate([[p], q])
        rhs = _VariationalField(system.field(0, P), system.jacs[0], 0)
        y0 = np.concatenate([states[0], np.eye(n).ravel()])
        try:
            out = seg.propagate([rhs], 0.0, T, y0, period=T, breakpoints=(),
                                settings=system.settings, h=None)
        except seg.Diverged as exc:
            raise IntegrationFailed(str(exc)) from None
        if not out.success:
            raise IntegrationFailed(out.message)
        return out.y_end[:n], out.y_end[n:].reshape(n, n)

    def residual(self, U: np.ndarray) -> Point:
        """``G(U)`` without its Jacobian (``DG`` left empty): one lean variational integration.

        Raises
        ------
        IntegrationFailed, numpy.linalg.LinAlgError
        """
        u = self.orbit_u(U)
        x_end, mono = self.flow(u)
        g, v, w = self.bordered(mono, U)
        head: list[float] = []
        if self.x_fixed is None:
            head = list(x_end - u[:self.n])
            if self.auto:
                assert self.system.ref is not None
                s_ref, f_ref = self.system.ref
                head.append(float((u[:self.n] - s_ref) @ f_ref))
        return Point(U.copy(), np.array(head + self._g_rows(g)), np.empty((0, self.size)),
                     mono, v, w)

    def evaluate(self, U: np.ndarray) -> Point:
        """``G(U)`` with its Jacobian (forward differences for the ``g`` rows: module notes).

        Raises
        ------
        IntegrationFailed, numpy.linalg.LinAlgError
        """
        pt = self.residual(U)
        A, v, w = self.matrix(pt.monodromy, U), pt.v, pt.w
        n, n_per = self.n, (0 if self.x_fixed is not None else self.n + self.nT)
        DG = np.zeros((pt.G.size, self.size))
        u = self.orbit_u(U)
        x_end = pt.G[:n] + u[:n] if n_per else None
        if n_per:  # the periodicity (and phase) rows' exact parts: M - I, f(x(T)), f_ref
            DG[:n, :n] = pt.monodromy - np.eye(n)
            if self.auto:
                assert self.system.ref is not None and x_end is not None
                states, _, q, p = self.system.unpack(u)
                DG[:n, n] = self.system.vector_field(x_end, np.concatenate([[p], q]))
                DG[n, :n] = self.system.ref[1]
        # forward differences of the lean flow: the g rows, g_z = -w^H (dA/dz) v, and the
        # periodicity rows' parameter columns dx(T)/dq, dx(T)/dp (relative error ~1e-8, as
        # the orbit system's own sensitivities, at no extra integration)
        for k in range(self.iq + 2):
            h = _SQRT_EPS * max(1.0, abs(float(U[k])))
            shifted = U.copy()
            shifted[k] += h
            end_k, mono_k = self.flow(self.orbit_u(shifted))
            A_k = self.matrix(mono_k, shifted)
            DG[n_per:, k] = self._g_rows(complex(-(w.conj() @ ((A_k - A) @ v)) / h))
            if n_per and k >= self.iq:
                assert x_end is not None
                DG[:n, k] = (end_k - x_end) / h
        if self.ns:
            dg = 1j * np.exp(1j * float(U[-1])) * (w.conj() @ v[:self.n])
            DG[n_per:, -1] = self._g_rows(complex(dg))
        pt.DG = DG
        return pt


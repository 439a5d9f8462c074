"""The shooting problem: unknowns, residual (eq. 38) and its Jacobian, with evaluation counters.

:class:`ShootingProblem` is what :func:`flapping.periodic.shooting.find_periodic_orbit` hands to
Levenberg-Marquardt. It owns

* the layout of the unknowns ``z = (x0[free], T if autonomous, params)``
  (:meth:`~ShootingProblem.unpack`),
* the residual ``r_k = x(1 + k delta) - x(k delta)``, ``k = 0 .. n_points - 1`` (normalised time
  ``tau = t / T``), followed by the user's extra residual,
* its Jacobian, from the variational equations (one integration gives r and J) or from forward
  differences of the residual (the paper's method),
* the counters and histories reported in :class:`~flapping.periodic.shooting.PeriodicOrbit`.

Multiple shooting (:class:`MultipleShootingProblem`, ``segments = M > 1``). The period is cut
into M equal segments, each integrated from its own unknown state ``s_k`` (``s_0 = x0``); the
residual is the continuity blocks ``x_k(end) - s_{k+1}`` (``s_M = s_0``: periodicity), and the
Jacobian is assembled block by block from the per-segment variational integrations: a
block-bidiagonal matrix ``[Phi_k, -I]`` with the period and parameter columns beside it. A long
or strongly unstable orbit whose single-shooting residual is too nonlinear for Newton or
Levenberg-Marquardt (the state-transition matrix over the whole period is huge) is then a
well-conditioned problem: each segment's matrix is moderate. The monodromy matrix is the product
``Phi_{M-1} ... Phi_0``, independent of M. The caching, counting and histories that
Levenberg-Marquardt relies on stay as they are.

Inputs are trusted: :mod:`flapping.periodic.shooting` checks them at the public boundary.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from flapping._numdiff import central_jacobian, forward_jacobian
from flapping.periodic import _segments as seg

__all__ = ["ShootingSetup", "ShootingProblem", "MultipleShootingProblem", "IntegrationFailed"]



class IntegrationFailed(Exception):
    """Raised inside the residual to leave MINPACK when the integrator gives up.

    ``failure``: where the integration stopped (None when no integration did: a period that
    left (0, inf)).
    """

    def __init__(self, message: str, failure: seg.Failure | None = None) -> None:
        super().__init__(message)
        self.failure = failure


@dataclass(frozen=True)
class ShootingSetup:
    """The checked inputs of a shooting problem (see ``find_periodic_orbit`` for each).

    Attributes
    ----------
    funs, jacs, pjacs : tuple
        The user's callables, one per segment of the period (None: finite differences).
    args : tuple
        Extra arguments of the callables (before ``params``).
    x_init : ndarray, shape (n,)
        Initial guess of the state; its ``fixed`` components are kept.
    T_init : float
        Period guess (autonomous) or the known period.
    p_init : ndarray or None
        Initial guess of the free parameters.
    fixed : tuple of int
        Components of x0 held at their guess (the user's, or the chosen phase condition).
    autonomous : bool
        Whether T is an unknown.
    breakpoints : tuple of float
        Restart fractions of the period.
    settings : Settings
        Integration settings.
    n_points, delta : int, float
        Residual blocks and their spacing in normalised time (eq. 38).
    extra_residual : callable or None
        Further conditions ``extra_residual(x0, T, params)``, of length ``n_extra``.
    n_extra : int
        Length of the extra residual.
    jacobian : str
        ``"variational"`` or ``"finite-difference"``.
    segments : int
        Number M of shooting segments (1: single shooting).
    """

    funs: tuple[Callable[..., Any], ...]
    jacs: tuple[Callable[..., Any] | None, ...]
    pjacs: tuple[Callable[..., Any] | None, ...]
    args: tuple[Any, ...]
    x_init: np.ndarray
    T_init: float
    p_init: np.ndarray | None
    fixed: tuple[int, ...]
    autonomous: bool
    breakpoints: tuple[float, ...]
    settings: seg.Settings
    n_points: int
    delta: float
    extra_residual: Callable[..., Any] | None
    n_extra: int
    jacobian: str
    segments: int = 1

    @property
    def n_unknowns(self) -> int:
        """Free components of x0, the other segments' states, T if autonomous, the parameters."""
        n_p = 0 if self.p_init is None else self.p_init.size
        n = self.x_init.size
        return n - len(self.fixed) + (self.segments - 1) * n + int(self.autonomous) + n_p

    @property
    def n_residuals(self) -> int:
        """Periodicity (continuity) residuals (``n * n_points * segments``) plus the extra ones."""
        return self.x_init.size * self.n_points * self.segments + self.n_extra


class ShootingProblem:
    """Residual and Jacobian of the shooting method for Levenberg-Marquardt (eqs. 30-38).

    ``residual(z)`` and ``jacobian(z)`` are the ``fun`` and ``jac`` of
    :func:`scipy.optimize.least_squares`. A point seen before is not integrated again (scipy
    re-requests points); with the variational Jacobian the residual integration also yields the
    Jacobian, so an accepted trial point costs no further integration.

    Parameters
    ----------
    setup : ShootingSetup
        The checked inputs.
    """

    def __init__(self, setup: ShootingSetup) -> None:
        self.setup = setup
        n = setup.x_init.size
        self.free = np.array([i for i in range(n) if i not in setup.fixed], dtype=int)
        self.n_p = 0 if setup.p_init is None else setup.p_init.size
        # Residual points in normalised time: tau = k delta and 1 + k delta (eq. 38).
        self.taus_a = np.arange(setup.n_points) * setup.delta
        self.taus_b = 1.0 + self.taus_a
        self.tau_out = np.concatenate([self.taus_a[1:], self.taus_b])
        self.counter, self.jcounter = seg.Counter(), seg.Counter()
        self.residual_history: list[float] = []
        self.iteration_history: list[float] = []
        self.last_good = self.z0.copy()
        self.last_residual: np.ndarray | None = None
        self.failure: seg.Failure | None = None  # where the last failed integration stopped
        self._r_cache: tuple[np.ndarray, np.ndarray] | None = None  # (z, r)
        self._J_cache: tuple[np.ndarray, np.ndarray] | None = None  # (z, J)
        self._last_jacobian_z: np.ndarray | None = None

    # ---- unknowns <-> (x0, T, params) ----------------------------------------------------------

    @property
    def z0(self) -> np.ndarray:
        """The initial unknowns."""
        s = self.setup
        return np.concatenate([s.x_init[self.free], [s.T_init] if s.autonomous else [],
                               s.p_init if self.n_p else []])

    def unpack(self, z: np.ndarray) -> tuple[np.ndarray, float, np.ndarray | None]:
        """``(x0, T, params)`` of the unknowns ``z``."""
        s = self.setup
        x = s.x_init.copy()
        x[self.free] = z[: self.free.size]
        T = float(z[self.free.size]) if s.autonomous else s.T_init
        params = z[self.free.size + int(s.autonomous):].copy() if self.n_p else None
        return x, T, params

    def segment_states(self, z: np.ndarray) -> np.ndarray:
        """States at the segment starts, time along the last axis: shape (n, segments)."""
        return self.unpack(z)[0][:, None]

    # ---- counters --------------------------------------------------------------------------------

    @property
    def nfev(self) -> int:
        """Evaluations of ``fun`` so far (finite differences included)."""
        return self.counter.n

    @property
    def njev(self) -> int:
        """Evaluations of ``jac`` and ``param_jac`` so far."""
        return self.jcounter.n

    def bind(self, params: np.ndarray | None) -> tuple[seg.Checked, ...]:
        """The per-segment callables ``g(t, x)`` at ``params``, counted and checked."""
        n = self.setup.x_init.size
        return tuple(seg.Checked(f, self.setup.args, params, (n,), self.counter)
                     for f in self.setup.funs)

    # ---- Levenberg-Marquardt's fun and jac ------------------------------------------------------

    def residual(self, z: np.ndarray) -> np.ndarray:
        """The residual at ``z`` (eq. 38 and the extra residual); cached.

        Raises
        ------
        IntegrationFailed
            When the period leaves (0, inf) or the integration fails.
        """
        if self._r_cache is not None and np.array_equal(z, self._r_cache[0]):
            return self._r_cache[1]  # scipy re-requests points it has seen; do not integrate twice
        s = self.setup
        i_T = self.free.size + (s.segments - 1) * s.x_init.size
        if s.autonomous and not z[i_T] > 0.0:
            raise IntegrationFailed(
                f"the period left (0, inf) (T = {z[i_T]:.3e}): the iteration is "
                f"heading for the trivial solution T -> 0 of the autonomous residual (no "
                f"periodic orbit near the guess, or an equilibrium)")
        if s.jacobian == "variational":
            # Integrate the variational equations with every residual: a trial point that LM
            # accepts (the usual case near the orbit) then has its Jacobian for free, one
            # integration per iteration instead of two.
            r, J = self._variational_residual(z)
            self._J_cache = (z.copy(), J)
        else:
            r = self._plain_residual(z)
        self._r_cache = (z.copy(), r)
        self.last_good, self.last_residual = z.copy(), r
        self.residual_history.append(float(np.linalg.norm(r)))
        return r

    def jacobian(self, z: np.ndarray) -> np.ndarray:
        """The Jacobian of the residual at ``z``; records the iteration history."""
        r = self.residual(z)
        if self._last_jacobian_z is None or not np.array_equal(z, self._last_jacobian_z):
            self.iteration_history.append(float(np.linalg.norm(r)))
            self._last_jacobian_z = z.copy()
        if self._J_cache is not None and np.array_equal(z, self._J_cache[0]):
            return self._J_cache[1]
        if self.setup.jacobian == "variational":
            J = self._variational_residual(z)[1]
        else:
            J = self._forward_difference_jacobian(z, r)
        self._J_cache = (z.copy(), J)
        return J

    def close_history(self, z: np.ndarray, norm: float) -> None:
        """End the iteration history with the final point's residual norm."""
        if self._last_jacobian_z is None or not np.array_equal(z, self._last_jacobian_z):
            self.iteration_history.append(norm)
        else:
            self.iteration_history[-1] = norm  # the same point, at full accuracy

    # ---- integration ---------------------------------------------------------------------------

    def _span(self, T: float) -> tuple[float, tuple[float, ...], float | None]:
        """End time, output times and RK4 step of the shooting integration at period T."""
        h = T / self.setup.settings.rk4_steps if self.setup.settings.fixed_step else None
        return float(self.taus_b[-1] * T), tuple(self.tau_out * T), h

    def _integrate(self, x: np.ndarray, T: float, params: np.ndarray | None) -> np.ndarray:
        """States at ``tau_out * T`` (time-first), by one integration of the state."""
        s = self.setup
        t1, t_out, h = self._span(T)
        out = seg.propagate(self.bind(params), 0.0, t1, x, period=T, breakpoints=s.breakpoints,
                            settings=s.settings, h=h, t_out=t_out)
        if not out.success:
            raise self._failed(out.message, out.failure)
        return np.array(out.y_out)

    def _integrate_variational(self, x: np.ndarray, T: float,
                               params: np.ndarray | None) -> seg.VariationalFlow:
        """States, matrices and sensitivities at ``tau_out * T`` by one integration."""
        s = self.setup
        t1, t_out, h = self._span(T)
        var = seg.variational(s.funs, s.jacs, s.pjacs, 0.0, t1, x, args=s.args, params=params,
                              trace=False, settings=s.settings, h=h, period=T,
                              breakpoints=s.breakpoints, t_out=t_out)
        self.counter.n += var.nfev
        self.jcounter.n += var.njev
        if not var.success:
            raise self._failed(var.message, var.failure)
        return var

    def _failed(self, message: str, failure: seg.Failure | None) -> IntegrationFailed:
        """The exception for a failed integration; ``self.failure`` keeps where it stopped."""
        self.failure = failure
        return IntegrationFailed(message, failure)

    # ---- assembly ------------------------------------------------------------------------------

    def _assemble(self, z: np.ndarray, xa: np.ndarray, xb: np.ndarray) -> np.ndarray:
        """Residual from the states at ``taus_a`` and ``taus_b`` (time-first), extra appended."""
        r = (xb - xa).ravel()
        if self.setup.n_extra:
            r = np.concatenate([r, self._extra(z)])
        if not np.all(np.isfinite(r)):
            raise IntegrationFailed("non-finite residual")
        return r

    def _plain_residual(self, z: np.ndarray) -> np.ndarray:
        """Eq. (38) by one integration of the state (states at tau = k delta, 1 + k delta)."""
        x, T, params = self.unpack(z)
        ys = self._integrate(x, T, params)
        k = self.setup.n_points - 1
        return self._assemble(z, np.vstack([x[None, :], ys[:k]]), ys[k:])

    def _variational_residual(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Eq. (38) and its Jacobian from one integration of the variational equations."""
        x, T, params = self.unpack(z)
        var = self._integrate_variational(x, T, params)
        k = self.setup.n_points - 1
        xs = var.x.T  # time-first: one row per output time
        xa, xb = np.vstack([x[None, :], xs[:k]]), xs[k:]
        r = self._assemble(z, xa, xb)
        return r, self._assemble_jacobian(z, var, xa, xb, params)

    def _assemble_jacobian(self, z: np.ndarray, var: seg.VariationalFlow, xa: np.ndarray,
                           xb: np.ndarray, params: np.ndarray | None) -> np.ndarray:
        """Columns for the free x0 (matrices), T (``tau f(x(tau))``), params (sensitivities)."""
        n, k = self.setup.x_init.size, self.setup.n_points - 1
        stm = np.moveaxis(var.stm, -1, 0)  # time-first
        stm_a = np.concatenate([np.eye(n)[None], stm[:k]])
        blocks = [(stm[k:] - stm_a)[:, :, self.free]]
        if self.setup.autonomous:
            # d x(tau) / dT = tau f(x(tau)) for an autonomous field: the solution of the
            # variational equation forced by f (normalised time, eq. 36) in closed form.
            g = self.bind(params)[0]
            col = np.array([tb * g(0.0, b) - ta * g(0.0, a)
                            for ta, tb, a, b in zip(self.taus_a, self.taus_b, xa, xb,
                                                    strict=True)])
            blocks.append(col[:, :, None])
        if self.n_p:
            assert var.sensitivity is not None
            sens = np.moveaxis(var.sensitivity, -1, 0)
            sens_a = np.concatenate([np.zeros((1, n, self.n_p)), sens[:k]])
            blocks.append(sens[k:] - sens_a)
        J = np.concatenate(blocks, axis=2).reshape(n * self.setup.n_points, z.size)
        if self.setup.n_extra:
            # central differences of the (cheap, integration-free) extra residual
            J = np.vstack([J, central_jacobian(self._extra, z)])
        return J

    def _forward_difference_jacobian(self, z: np.ndarray, r0: np.ndarray) -> np.ndarray:
        """Forward differences of the residual, MINPACK lmdif's step (the paper's method)."""
        return forward_jacobian(self._plain_residual, z, r0)

    def _extra(self, z: np.ndarray) -> np.ndarray:
        """The user's extra residual at ``z``, checked."""
        extra = self.setup.extra_residual
        assert extra is not None
        x, T, params = self.unpack(z)
        e = np.atleast_1d(np.asarray(extra(x, T, params), dtype=float))
        if e.shape != (self.setup.n_extra,):
            raise ValueError(f"`extra_residual` must return shape {(self.setup.n_extra,)}, got "
                             f"{e.shape}")
        if not np.all(np.isfinite(e)):
            raise ValueError(f"`extra_residual` returned a non-finite value at x0 = {x!r}, "
                             f"T = {T!r}, params = {params!r}: {e!r}")
        return e


class MultipleShootingProblem(ShootingProblem):
    """Multiple shooting: M segments of the period, each from its own unknown state.

    Unknowns ``z = (x0[free], s_1, ..., s_{M-1}, T if autonomous, params)``; residual blocks
    ``x_k(t_{k+1}) - s_{k+1}``, ``t_k = k T / M``, ``s_M = s_0 = x0``. The initial segment states
    are the guess's own trajectory at ``t_k`` (as multiflap starts), or ``x0`` repeated when that
    integration fails.

    Parameters
    ----------
    setup : ShootingSetup
        The checked inputs, with ``segments >= 2`` and ``n_points == 1``.
    """

    def __init__(self, setup: ShootingSetup) -> None:
        self.M = setup.segments
        self._guess = np.repeat(setup.x_init[None, :], setup.segments - 1, axis=0)
        super().__init__(setup)
        T = setup.T_init
        out = seg.propagate(self.bind(setup.p_init), 0.0, T, setup.x_init, period=T,
                            breakpoints=setup.breakpoints, settings=setup.settings,
                            h=self._step(T), t_out=tuple(self._times(T)[1:-1]))
        if out.success:
            self._guess = np.array(out.y_out)
        self.last_good = self.z0.copy()

    def _times(self, T: float) -> np.ndarray:
        """Segment boundaries ``t_k = k T / M``, k = 0 .. M."""
        return np.arange(self.M + 1) * (T / self.M)

    def _step(self, T: float) -> float | None:
        return T / self.setup.settings.rk4_steps if self.setup.settings.fixed_step else None

    @property
    def z0(self) -> np.ndarray:
        """The initial unknowns (the guess's trajectory as the segment states)."""
        s = self.setup
        return np.concatenate([s.x_init[self.free], self._guess.ravel(),
                               [s.T_init] if s.autonomous else [],
                               s.p_init if self.n_p else []])

    def unpack(self, z: np.ndarray) -> tuple[np.ndarray, float, np.ndarray | None]:
        """``(x0, T, params)`` of the unknowns ``z``."""
        s, nf, n = self.setup, self.free.size, self.setup.x_init.size
        x = s.x_init.copy()
        x[self.free] = z[:nf]
        i = nf + (self.M - 1) * n
        T = float(z[i]) if s.autonomous else s.T_init
        params = z[i + int(s.autonomous):].copy() if self.n_p else None
        return x, T, params

    def segment_states(self, z: np.ndarray) -> np.ndarray:
        """States at the segment starts, time along the last axis: shape (n, M)."""
        x = self.unpack(z)[0]
        n, nf = x.size, self.free.size
        return np.vstack([x[None, :], z[nf:nf + (self.M - 1) * n].reshape(-1, n)]).T

    def _plain_residual(self, z: np.ndarray) -> np.ndarray:
        """Continuity blocks, one integration of the state per segment."""
        x, T, params = self.unpack(z)
        states, t, g = self.segment_states(z).T, self._times(T), self.bind(params)
        ends = []
        for k in range(self.M):
            out = seg.propagate(g, float(t[k]), float(t[k + 1]), states[k], period=T,
                                breakpoints=self.setup.breakpoints, settings=self.setup.settings,
                                h=self._step(T))
            if not out.success:
                raise self._failed(f"segment {k}: {out.message}", out.failure)
            ends.append(out.y_end)
        return self._assemble(z, np.roll(states, -1, axis=0), np.array(ends))

    def _variational_residual(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Continuity blocks and their block-bidiagonal Jacobian (per-segment variations)."""
        s = self.setup
        x, T, params = self.unpack(z)
        states, t = self.segment_states(z).T, self._times(T)
        flows = []
        for k in range(self.M):
            var = seg.variational(s.funs, s.jacs, s.pjacs, float(t[k]), float(t[k + 1]),
                                  states[k], args=s.args, params=params, trace=False,
                                  settings=s.settings, h=self._step(T), period=T,
                                  breakpoints=s.breakpoints, t_out=(float(t[k + 1]),))
            self.counter.n += var.nfev
            self.jcounter.n += var.njev
            if not var.success:
                raise self._failed(f"segment {k}: {var.message}", var.failure)
            flows.append(var)
        ends = np.array([v.x_end for v in flows])
        r = self._assemble(z, np.roll(states, -1, axis=0), ends)
        return r, self._block_jacobian(z, flows, states, ends, T, params)

    def _block_jacobian(self, z: np.ndarray, flows: list[seg.VariationalFlow],
                        states: np.ndarray, ends: np.ndarray, T: float,
                        params: np.ndarray | None) -> np.ndarray:
        """``d r_k / d s_k = Phi_k``, ``d r_k / d s_{k+1} = -I``, then the T and params columns."""
        s, n, M, nf = self.setup, self.setup.x_init.size, self.M, self.free.size
        J = np.zeros((n * M, z.size))
        cols = [np.arange(nf)] + [nf + (k - 1) * n + np.arange(n) for k in range(1, M)]
        for k, var in enumerate(flows):
            rows = slice(k * n, (k + 1) * n)
            J[rows, cols[k]] = var.stm_end[:, self.free] if k == 0 else var.stm_end
            nxt = (k + 1) % M
            J[rows, cols[nxt]] -= np.eye(n)[:, self.free] if nxt == 0 else np.eye(n)
        i = nf + (M - 1) * n
        if s.autonomous:
            # x_k(end) = phi_{T/M}(s_k): d/dT = f(x_k(end)) / M
            g = self.bind(params)[0]
            J[:, i] = np.concatenate([g(0.0, e) for e in ends]) / M
        if self.n_p:
            sens = [v.sensitivity_end for v in flows]
            assert all(v is not None for v in sens)
            J[:, i + int(s.autonomous):] = np.vstack(sens)  # type: ignore[arg-type]
        if s.n_extra:
            J = np.vstack([J, central_jacobian(self._extra, z)])
        return J

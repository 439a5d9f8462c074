"""The optimized shooting method (Dednam & Botha 2015; paper Sec. III.A, eqs. 30-38).

A periodic orbit of ``x' = f(t, x)`` (eq. 30) satisfies ``x(t + T) = x(t)`` (eq. 31). In normalised
time ``tau = t / T`` the orbit has period one (eq. 36), and the optimized shooting method finds the
initial state (and, for an autonomous system, the period) that minimise the residual (eq. 38)

    R = (x(1) - x(0), x(1 + delta) - x(delta), ..., x(1 + (p-1) delta) - x((p-1) delta))

with the Levenberg-Marquardt algorithm (eqs. 32-35), here MINPACK's ``lmder`` through
:func:`scipy.optimize.least_squares` (``method="lm"``).

What we change with respect to the paper (which differences the residual over a fixed-step RK4
integration, step ``2**-10`` of a period):

* ``jacobian="variational"`` (default): the Jacobian of R comes from the variational equations
  integrated with the state, one integration per Levenberg-Marquardt Jacobian, exact up to the
  integration tolerance, instead of one extra shooting integration per unknown;
* adaptive high-order integration (DOP853, ``rtol=1e-11``) instead of RK4 at ``2**-10``, which
  limits the period to about eight digits (see the validation chapter);
* segment-aware integration (:mod:`flapping.periodic.integrate`): right-hand sides that jump at a
  breakpoint (stroke reversal) are integrated one smooth segment at a time.

The paper's method is available as ``jacobian="finite-difference", method="RK4"``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from flapping.errors import ConvergenceError
from flapping.periodic.integrate import (
    _check_breakpoints,
    _check_method,
    _check_period,
    _check_rk4_steps,
    _check_state,
    _check_tolerances,
    _Counted,
    _Counter,
    _FunP,
    _propagate,
    _segment_callables,
    variational_flow,
)

__all__ = [
    "PeriodicOrbit",
    "find_periodic_orbit",
    "JACOBIANS",
]

#: Accepted values of ``jacobian``.
JACOBIANS: tuple[str, ...] = ("variational", "finite-difference")

_EPS = np.finfo(float).eps


@dataclass(frozen=True)
class PeriodicOrbit:
    """A periodic orbit found by :func:`find_periodic_orbit`, with its diagnostics.

    Attributes
    ----------
    x0 : ndarray, shape (n,)
        Initial state on the orbit (fixed components at their given values).
    period : float
        Period ``T`` (the given one for a forced system).
    params : ndarray or None
        Converged free parameters.
    success : bool
        Converged to ``residual_norm <= tol``.
    message : str
        Why the iteration stopped (MINPACK's reason).
    residual : ndarray
        Final residual vector (eq. 38, then the extra residuals).
    residual_norm : float
        Its Euclidean norm.
    residual_history : ndarray
        Residual norm at every residual evaluation requested by Levenberg-Marquardt (trial points
        included; finite-difference probes excluded).
    iteration_history : ndarray
        Residual norm at every point where the Jacobian was evaluated (the accepted iterates),
        followed by the final one.
    iterations : int
        Number of Jacobian evaluations (Levenberg-Marquardt iterations).
    n_residual_evals : int
        Residual evaluations requested by Levenberg-Marquardt.
    n_rhs_evals : int
        Right-hand-side evaluations in total (residuals, Jacobians, finite differences).
    n_jac_evals : int
        Evaluations of the analytic ``jac``/``param_jac`` (0 without them).
    jacobian : str
        ``"variational"`` or ``"finite-difference"``.
    method : str
        Integration method.
    autonomous : bool
        Whether the period was an unknown.
    unknowns : ndarray
        The final vector of unknowns (free components of x0, then T, then params).
    """

    x0: np.ndarray
    period: float
    params: np.ndarray | None
    success: bool
    message: str
    residual: np.ndarray
    residual_norm: float
    residual_history: np.ndarray
    iteration_history: np.ndarray
    iterations: int
    n_residual_evals: int
    n_rhs_evals: int
    n_jac_evals: int
    jacobian: str
    method: str
    autonomous: bool
    unknowns: np.ndarray


class _IntegrationFailed(Exception):
    """Raised inside the residual to leave MINPACK when the integrator gives up."""


def _check_fixed(fixed, n) -> tuple[int, ...]:
    message = f"`fixed` must be a sequence of distinct integer indices in [0, {n}), got {fixed!r}"
    try:
        items = list(fixed)
    except TypeError:
        raise ValueError(message) from None
    for raw in items:
        if isinstance(raw, (bool, np.bool_)) or not isinstance(raw, (int, np.integer)):
            raise ValueError(message)
        if not 0 <= raw < n:
            raise ValueError(message)
    if len(set(items)) != len(items):
        raise ValueError(message)
    return tuple(int(i) for i in items)


def find_periodic_orbit(
    fun: Callable | Sequence[Callable],
    x0,
    period: float,
    *,
    autonomous: bool = True,
    jac: Callable | Sequence[Callable] | None = None,
    free_params=None,
    param_jac: Callable | Sequence[Callable] | None = None,
    extra_residual: Callable | None = None,
    fixed: Sequence[int] = (),
    breakpoints: Sequence[float] = (),
    jacobian: str = "variational",
    method: str = "DOP853",
    n_points: int = 1,
    delta: float = 2.0**-10,
    rtol: float = 1e-11,
    atol: float = 1e-12,
    rk4_steps: int = 1024,
    tol: float = 1e-10,
    max_nfev: int | None = None,
    xtol: float = 1e-12,
    ftol: float = 1e-12,
    min_period: float | None = None,
    args: tuple = (),
) -> PeriodicOrbit:
    """Find a periodic orbit by the optimized shooting method (eqs. 30-38).

    Minimises the residual of eq. (38) in normalised time ``tau = t / T``,
    ``r_k = x(1 + k delta) - x(k delta)``, ``k = 0 .. n_points - 1``, stacked, followed by
    ``extra_residual(x0, period, params)``, with Levenberg-Marquardt (eq. 35; MINPACK ``lmder``).
    The unknowns are the components of ``x0`` not in ``fixed``, then ``T`` if ``autonomous``, then
    the free parameters.

    Parameters
    ----------
    fun : callable or sequence of callables
        Right-hand side ``fun(t, x, *args)``, or ``fun(t, x, *args, p)`` with ``free_params``; a
        sequence gives one callable per segment of the period (``len(breakpoints) + 1``), each
        smooth on its closed segment (see :mod:`flapping.periodic.integrate`).
    x0 : array_like, shape (n,)
        Initial guess of a state on the orbit; components in ``fixed`` are kept.
    period : float
        Period: the initial guess if ``autonomous``, the known forcing period otherwise.
    autonomous : bool, optional
        ``True``: ``fun`` does not depend on t and ``T`` is an unknown (a phase condition, e.g. a
        component in ``fixed`` or ``n_points >= 2``, is then needed to make the problem square).
        ``False``: forced system, ``T`` known and fixed.
    jac : callable or sequence of callables, optional
        Analytic ``df/dx`` (same signature and segments as ``fun``). Default: central finite
        differences of ``fun`` inside the variational equations.
    free_params : array_like, optional
        Initial guess of extra unknown parameters ``p`` (e.g. a flapping amplitude), passed as the
        last argument of ``fun``, ``jac``, ``param_jac`` and to ``extra_residual``.
    param_jac : callable or sequence of callables, optional
        ``df/dp(t, x, *args, p)``, shape (n, n_p). Default: central differences of ``fun`` in p.
    extra_residual : callable, optional
        ``extra_residual(x0, period, params) -> array`` of further conditions appended to R
        (differenced centrally in the unknowns: it must be cheap and smooth).
    fixed : sequence of int, optional
        Indices of ``x0`` held at their given values: a Poincare-section phase condition
        (Dednam & Botha hold x3), or a state the vector field does not depend on (an altitude).
    breakpoints : sequence of float, optional
        Fractions of the period in (0, 1) where the integrator restarts (forced systems only).
    jacobian : {"variational", "finite-difference"}, optional
        ``"variational"``: one integration of state + variational equations per Jacobian (exact
        up to the tolerance; columns for x0, for T as ``tau f(x(tau))``, for p from the
        sensitivity equations). ``"finite-difference"``: forward differences of the residual,
        step ``sqrt(eps) |z_j|`` (MINPACK ``lmdif``'s rule, the paper's method); one extra
        shooting integration per unknown.
    method : str, optional
        Integrator: ``"DOP853"`` (default), another solve_ivp method, or ``"RK4"`` (fixed step
        ``T / rk4_steps``, the paper's).
    n_points : int, optional
        Number ``p`` of residual blocks in eq. (38) (>= 1).
    delta : float, optional
        Spacing of the residual blocks in normalised time (paper: ``2**-10``), in (0, 1).
    rtol, atol : float, optional
        Integration tolerances (adaptive methods).
    rk4_steps : int, optional
        RK4 steps per period.
    tol : float, optional
        Required final residual norm (absolute, in the units of the state).
    max_nfev : int, optional
        Maximum residual evaluations of Levenberg-Marquardt (default ``100 * (n_unknowns + 1)``).
    xtol, ftol : float, optional
        MINPACK's termination tolerances (relative step and relative reduction), >= 2.2e-16.
    min_period : float, optional
        Autonomous only: a converged period below this is rejected as the trivial solution
        ``T -> 0`` every autonomous shooting residual has (default ``1e-2 * period``).
    args : tuple, optional
        Extra arguments of ``fun`` and ``jac`` (before ``p``).

    Returns
    -------
    PeriodicOrbit
        The orbit and the convergence diagnostics.

    Raises
    ------
    ValueError
        Bad arguments: non-positive or non-finite period, x0 not a finite 1-D array, wrong output
        shape of ``fun``/``extra_residual``, ``fixed`` out of range, ``n_points < 1``, fewer
        residuals than unknowns, breakpoints with an autonomous system, RK4 grid mismatch.
    ConvergenceError
        Levenberg-Marquardt stopped without reaching ``residual_norm <= tol``, the integration
        failed, or the period collapsed; carries the last iterate (unknowns), the residual norm,
        the iteration count, and the :class:`PeriodicOrbit` as ``result``.
    """
    # ---- validation at the public boundary --------------------------------------------------
    x_init = _check_state(x0)
    n = x_init.size
    T_init = _check_period(period)
    method = _check_method(method)
    _check_tolerances(rtol, atol)
    rk4_steps = _check_rk4_steps(rk4_steps)
    breakpoints = _check_breakpoints(breakpoints)
    if autonomous and breakpoints:
        raise ValueError(
            "`breakpoints` move with the unknown period, so they make the system non-autonomous: "
            "use autonomous=False (known period) with breakpoints"
        )
    if jacobian not in JACOBIANS:
        raise ValueError(f"`jacobian` must be one of {JACOBIANS}, got {jacobian!r}")
    if isinstance(n_points, bool) or int(n_points) != n_points or n_points < 1:
        raise ValueError(f"`n_points` must be an integer >= 1, got {n_points!r}")
    n_points = int(n_points)
    if not (math.isfinite(delta) and 0.0 < delta < 1.0):
        raise ValueError(f"`delta` must lie in (0, 1) (a fraction of the period), got {delta!r}")
    if method == "RK4" and n_points > 1 and abs(delta * rk4_steps - round(delta * rk4_steps)) > 1e-9:
        raise ValueError(
            f"with method='RK4', `delta` must be a multiple of 1/rk4_steps = 1/{rk4_steps} so that "
            f"the residual points fall on the step grid, got delta={delta!r}"
        )
    if not (math.isfinite(tol) and tol > 0):
        raise ValueError(f"`tol` must be a positive finite number, got {tol!r}")
    for name, value in (("xtol", xtol), ("ftol", ftol)):
        if not (math.isfinite(value) and value >= _EPS):
            raise ValueError(f"`{name}` must be finite and >= machine epsilon ({_EPS:.2e}), got {value!r}")
    if max_nfev is not None and (int(max_nfev) != max_nfev or max_nfev < 1):
        raise ValueError(f"`max_nfev` must be a positive integer, got {max_nfev!r}")
    fixed = _check_fixed(fixed, n)
    free = np.array([i for i in range(n) if i not in fixed], dtype=int)
    if free_params is not None:
        p_init = np.atleast_1d(np.array(free_params, dtype=float))
        if p_init.ndim != 1 or p_init.size == 0 or not np.all(np.isfinite(p_init)):
            raise ValueError(f"`free_params` must be a non-empty finite 1-D array, got {free_params!r}")
    else:
        p_init = None
    n_p = 0 if p_init is None else p_init.size
    args = tuple(args)
    n_seg = len(breakpoints) + 1
    funs_raw = _segment_callables(fun, n_seg, "fun")
    if jac is not None:
        _segment_callables(jac, n_seg, "jac")
    if param_jac is not None:
        if p_init is None:
            raise ValueError("`param_jac` needs `free_params`")
        _segment_callables(param_jac, n_seg, "param_jac")
    if min_period is None:
        min_period = 1e-2 * T_init

    counter = _Counter()

    def bind(p):
        """Per-segment counted callables g(t, x) for the parameters p."""
        if p is None:
            return tuple(_Counted(f, args, (n,), counter, "fun") for f in funs_raw)
        return tuple(_FunP(f, args, p, (n,), counter) for f in funs_raw)

    # One evaluation per segment at the initial guess: a wrong shape or a non-finite value is a
    # ValueError here, not an obscure failure inside MINPACK.
    for k, g in enumerate(bind(p_init)):
        value = g(T_init * (breakpoints[k - 1] if k else 0.0), x_init)
        if not np.all(np.isfinite(value)):
            raise ValueError(f"`fun` returned non-finite values at the initial guess: {value}")

    n_unknowns = free.size + (1 if autonomous else 0) + n_p
    n_extra = 0
    if extra_residual is not None:
        extra0 = np.atleast_1d(np.asarray(extra_residual(x_init.copy(), T_init, p_init), dtype=float))
        if extra0.ndim != 1:
            raise ValueError(f"`extra_residual` must return a 1-D array, got shape {extra0.shape}")
        n_extra = extra0.size
    n_residuals = n * n_points + n_extra
    if n_unknowns == 0:
        raise ValueError("nothing to solve for: every component is `fixed` and the period is known")
    if n_residuals < n_unknowns:
        raise ValueError(
            f"too few residuals for the unknowns: n_points={n_points} gives {n * n_points} "
            f"periodicity residuals (+{n_extra} extra) for {n_unknowns} unknowns "
            f"({free.size} free components of x0{', T' if autonomous else ''}"
            f"{f', {n_p} parameters' if n_p else ''}); raise `n_points`, hold a component with "
            f"`fixed` (a phase condition), or add an `extra_residual`"
        )

    # ---- unknowns <-> (x0, T, p) -------------------------------------------------------------
    z_init = np.concatenate([x_init[free], [T_init] if autonomous else [], p_init if n_p else []])

    def unpack(z):
        x = x_init.copy()
        x[free] = z[: free.size]
        T = float(z[free.size]) if autonomous else T_init
        p = z[free.size + (1 if autonomous else 0):].copy() if n_p else None
        return x, T, p

    # Residual points in normalised time: tau = k delta and 1 + k delta (eq. 38).
    taus_a = np.arange(n_points) * delta
    taus_b = 1.0 + taus_a
    tau_out = np.concatenate([taus_a[1:], taus_b])

    state = {"z": None, "r": None, "last_good": z_init.copy()}
    residual_history: list[float] = []
    iteration_history: list[float] = []
    jcounter = _Counter()
    jac_cache = {"z": None, "J": None}

    def extra(z):
        x, T, p = unpack(z)
        e = np.atleast_1d(np.asarray(extra_residual(x, T, p), dtype=float))
        if e.shape != (n_extra,):
            raise ValueError(f"`extra_residual` must return shape {(n_extra,)}, got {e.shape}")
        return e

    def extra_jacobian(z):
        """Central differences of the (cheap, integration-free) extra residual."""
        E = np.empty((n_extra, z.size))
        hs = _EPS ** (1.0 / 3.0) * np.maximum(1.0, np.abs(z))
        for j in range(z.size):
            zp, zm = z.copy(), z.copy()
            zp[j] += hs[j]
            zm[j] -= hs[j]
            E[:, j] = (extra(zp) - extra(zm)) / (zp[j] - zm[j])
        return E

    def finish(r, z):
        if n_extra:
            r = np.concatenate([r, extra(z)])
        if not np.all(np.isfinite(r)):
            raise _IntegrationFailed("non-finite residual")
        return r

    def plain_residual(z):
        """Eq. (38) by one integration of the state (states at tau = k delta, 1 + k delta)."""
        x, T, p = unpack(z)
        out = _propagate(bind(p), 0.0, float(taus_b[-1] * T), x, period=T,
                         breakpoints=breakpoints, method=method, rtol=rtol, atol=atol,
                         rk4_h=T / rk4_steps, t_out=tuple(tau_out * T))
        if not out["success"]:
            raise _IntegrationFailed(out["message"])
        ys = np.array(out["y_out"])
        xa = np.vstack([x[None, :], ys[: n_points - 1]])
        return finish((ys[n_points - 1:] - xa).ravel(), z)

    def variational_residual(z):
        """Eq. (38) and its Jacobian from one integration of the variational equations."""
        x, T, p = unpack(z)
        var = variational_flow(
            fun, jac, (0.0, float(taus_b[-1] * T)), x, breakpoints=breakpoints, period=T,
            method=method, rtol=rtol, atol=atol, rk4_steps=rk4_steps, t_out=tuple(tau_out * T),
            params=p, param_jac=param_jac, args=args,
        )
        counter.n += var.nfev
        jcounter.n += var.njev
        if not var.success:
            raise _IntegrationFailed(var.message)
        xa = np.vstack([x[None, :], var.x[: n_points - 1]])
        xb = var.x[n_points - 1:]
        r = finish((xb - xa).ravel(), z)
        stm_a = np.concatenate([np.eye(n)[None], var.stm[: n_points - 1]])
        blocks = [(var.stm[n_points - 1:] - stm_a)[:, :, free]]
        if autonomous:
            # d x(tau) / dT = tau f(x(tau)) for an autonomous field: the solution of the
            # variational equation forced by f (normalised time, eq. 36) in closed form.
            g = bind(p)[0]
            col = np.array([tb * g(0.0, b) - ta_ * g(0.0, a)
                            for ta_, tb, a, b in zip(taus_a, taus_b, xa, xb)])
            blocks.append(col[:, :, None])
        if n_p:
            sens_a = np.concatenate([np.zeros((1, n, n_p)), var.sensitivity[: n_points - 1]])
            blocks.append(var.sensitivity[n_points - 1:] - sens_a)
        J = np.concatenate(blocks, axis=2).reshape(n * n_points, z.size)
        if n_extra:
            J = np.vstack([J, extra_jacobian(z)])
        return r, J

    def residual(z):
        if state["z"] is not None and np.array_equal(z, state["z"]):
            return state["r"]  # scipy re-requests points it has seen; do not integrate twice
        if autonomous and not z[free.size] > 0.0:
            raise _IntegrationFailed(
                f"the period left (0, inf) (T = {z[free.size]:.3e}): the iteration is heading for "
                f"the trivial solution T -> 0 of the autonomous residual (no periodic orbit near "
                f"the guess, or an equilibrium)"
            )
        if jacobian == "variational":
            # Integrate the variational equations with every residual: a trial point that LM
            # accepts (the usual case near the orbit) then has its Jacobian for free, one
            # integration per iteration instead of two.
            r, J = variational_residual(z)
            jac_cache["z"], jac_cache["J"] = z.copy(), J
        else:
            r = plain_residual(z)
        norm = float(np.linalg.norm(r))
        state["z"], state["r"], state["last_good"] = z.copy(), r, z.copy()
        residual_history.append(norm)
        return r

    def jacobian_fd(z):
        r0 = residual(z)
        J = np.empty((r0.size, z.size))
        for j in range(z.size):
            h = math.sqrt(_EPS) * abs(z[j]) or math.sqrt(_EPS)  # MINPACK lmdif's step
            zp = z.copy()
            zp[j] += h
            J[:, j] = (plain_residual(zp) - r0) / (zp[j] - z[j])
        return J

    last_jac = {"z": None}

    def jacobian_fn(z):
        r = residual(z)
        if last_jac["z"] is None or not np.array_equal(z, last_jac["z"]):
            iteration_history.append(float(np.linalg.norm(r)))
            last_jac["z"] = z.copy()
        if jac_cache["z"] is not None and np.array_equal(z, jac_cache["z"]):
            return jac_cache["J"]
        J = variational_residual(z)[1] if jacobian == "variational" else jacobian_fd(z)
        jac_cache["z"], jac_cache["J"] = z.copy(), J
        return J

    # ---- Levenberg-Marquardt (MINPACK) ---------------------------------------------------------
    if max_nfev is None:
        max_nfev = 100 * (n_unknowns + 1)
    result, failure = None, None
    try:
        result = least_squares(residual, z_init, jac=jacobian_fn, method="lm", x_scale="jac",
                               xtol=xtol, ftol=ftol, gtol=_EPS * 10, max_nfev=max_nfev)
    except _IntegrationFailed as exc:
        failure = f"the iteration failed: {exc}"
    except (np.linalg.LinAlgError, FloatingPointError, OverflowError) as exc:
        failure = f"numerical failure during the iteration: {exc}"

    if result is not None:
        z_final = result.x
        # The residual of the final iterate, from the discretisation the iteration used (the
        # variational integration takes other steps than the plain one; on an expanding orbit
        # the two differ by their global errors, ~1e-10 on Lorenz).
        r_final = residual(z_final)
        message = result.message
        status_ok = result.status > 0
    else:
        z_final = state["last_good"]
        r_final = state["r"] if state["r"] is not None else np.full(n_residuals, np.nan)
        message, status_ok = failure, False
    norm = float(np.linalg.norm(r_final))
    x_fin, T_fin, p_fin = unpack(z_final)
    if last_jac["z"] is None or not np.array_equal(z_final, last_jac["z"]):
        iteration_history.append(norm)
    else:
        iteration_history[-1] = norm  # the same point, at full accuracy
    success = failure is None and status_ok and norm <= tol
    if success and autonomous and not (T_fin >= min_period):
        success = False
        message = (f"the period collapsed to T = {T_fin:.3e} < min_period = {min_period:.3e}: "
                   f"the trivial solution T -> 0 of the autonomous residual (no periodic orbit "
                   f"near the guess, or an equilibrium)")
    elif failure is None and not success:
        message = (f"Levenberg-Marquardt stopped ({message}) with residual norm {norm:.3e} > "
                   f"tol = {tol:.1e}" if status_ok else f"Levenberg-Marquardt did not converge: {message}")
    orbit = PeriodicOrbit(
        x0=x_fin, period=T_fin, params=p_fin, success=success, message=message,
        residual=np.asarray(r_final), residual_norm=norm,
        residual_history=np.array(residual_history), iteration_history=np.array(iteration_history),
        iterations=int(result.njev) if result is not None and result.njev else len(iteration_history) - 1, n_residual_evals=len(residual_history),
        n_rhs_evals=counter.n, n_jac_evals=jcounter.n, jacobian=jacobian, method=method,
        autonomous=bool(autonomous), unknowns=np.array(z_final, dtype=float),
    )
    if not success:
        raise ConvergenceError(
            f"no periodic orbit found: {message}", x=z_final, residual=norm,
            iterations=orbit.iterations, result=orbit,
        )
    return orbit

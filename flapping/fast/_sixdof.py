"""The compiled six-degree-of-freedom hover path for the paper's linear loads (eq. 29).

What the planar kernel (:mod:`flapping.fast._compiled`) does for (u, w, q, theta), done here for
the eight states (u, v, w, p, q, r, roll, theta) and the descent z, with every formula generated
by SymPy (one source of truth): the linear loads, the mass matrix and the Jacobians of the
mechanics from :mod:`flapping.model._sixdof_linear_generated` (written into arrays), the forcing
and Euler-angle rates from :mod:`flapping.model._sixdof_generated`. Wing mass is included (the
mass matrix A(phi) is solved at every stage by Gaussian elimination with partial pivoting).

- Integration: the DOP853 tableau at a fixed step, ``n`` steps per half-stroke, restarted at
  stroke reversal (the linear loads are not smooth there: they hold ``|phi_dot|``).
- Variational equations with the analytic Jacobian: the linear loads' derivatives and the
  generated Jacobian of the forcing, through A(phi)^-1 (A depends on phi only).
- Newton (in Python: 9 unknowns) on (x0, Phi) for periodicity of the eight states and zero net
  descent, the state columns from the variational matrix, the Phi column by central differences
  of two plain integrations.

State layout (float64): the plain state (9): the eight states and z; the variational state
(82): the plain one, the 9 x 8 matrix dx(t)/dx0 row-major in ``y[9:81]``, and the integral of
trace J in ``y[81]`` (Liouville's formula).

Imported only when the six-degree-of-freedom compiled path first runs; numba compiles the
functions on their first call (and caches them on disk where it can).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from flapping.fast import _dop853
from flapping.fast import _jit as _jit_policy
from flapping.model import _sixdof_generated, _sixdof_linear_generated
from flapping.periodic import _tableau

# The one policy of flapping's numba code (flapping.fast._jit): cached entry points keyed also
# on the sources they inline, and helpers linked into them.
_jit = _jit_policy.entry_point(_sixdof_generated, _sixdof_linear_generated, _tableau)
_helper = _jit_policy.helper

N_PLAIN = 9
N_VAR = 82


# The generated formulas, linked into the cached entry points (the kernel's helper wrapper).
_linear_loads = _helper(_sixdof_linear_generated.linear_loads)
_forcing_jacobian = _helper(_sixdof_linear_generated.forcing_jacobian)
_euler_jacobian = _helper(_sixdof_linear_generated.euler_rates_jacobian)
_mass_matrix = _helper(_sixdof_linear_generated.mass_matrix)  # floats only
_forcing = _helper(_sixdof_generated.forcing)
_euler_rates = _helper(_sixdof_generated.euler_rates)
_earth_velocity = _helper(_sixdof_generated.earth_velocity)
_earth_jacobian = _helper(_sixdof_linear_generated.earth_velocity_jacobian)

RK_A = np.ascontiguousarray(_dop853.A)
RK_B = np.ascontiguousarray(_dop853.B)
RK_C = np.ascontiguousarray(_dop853.C)
N_STAGES = _dop853.N_STAGES


@_helper
def _solve(a, b, n, m):  # pragma: no cover - compiled
    """Solve a X = b in place (b is n x m, overwritten by X): Gauss with partial pivoting."""
    for col in range(n):
        pivot = col
        for i in range(col + 1, n):
            if abs(a[i, col]) > abs(a[pivot, col]):
                pivot = i
        if pivot != col:
            for j in range(n):
                a[col, j], a[pivot, j] = a[pivot, j], a[col, j]
            for j in range(m):
                b[col, j], b[pivot, j] = b[pivot, j], b[col, j]
        for i in range(col + 1, n):
            f = a[i, col] / a[col, col]
            if f != 0.0:
                for j in range(col, n):
                    a[i, j] -= f * a[col, j]
                for j in range(m):
                    b[i, j] -= f * b[col, j]
    for col in range(n - 1, -1, -1):
        for j in range(m):
            acc = b[col, j]
            for k in range(col + 1, n):
                acc -= a[col, k] * b[k, j]
            b[col, j] = acc / a[col, col]


@_helper
def _field(t, y, dy, variational, amplitude, p, klin, kmech, w):  # pragma: no cover
    """dy/dt of the plain (variational False) or the variational state.

    ``p`` = (omega [rad/s], phi_bar [rad], alpha_m [rad]); ``klin`` the linear loads' constants,
    ``kmech`` the mechanics' (tuple, :data:`~flapping.model.sixdof_derivation.CONSTANT_NAMES`);
    ``w`` the scratch arrays of :func:`_work`.
    """
    lin, b, a, jf, je, jac = w
    omega, phi_bar, alpha_m = p[0], p[1], p[2]
    c, s = math.cos(omega * t), math.sin(omega * t)
    phi = phi_bar + amplitude * c
    phi_dot = -omega * amplitude * s
    phi_ddot = -omega * omega * amplitude * c
    u, v, w_, pr, q, r, roll, theta = y[0], y[1], y[2], y[3], y[4], y[5], y[6], y[7]
    _linear_loads(phi, phi_dot, abs(phi_dot), alpha_m, klin, lin)
    f0, f1, f2, f3, f4, f5 = _forcing(phi, phi_dot, phi_ddot, u, v, w_, pr, q, r, roll, theta,
                                      kmech)
    b[0, 0], b[1, 0], b[2, 0], b[3, 0], b[4, 0], b[5, 0] = f0, f1, f2, f3, f4, f5
    for i in range(6):
        acc = b[i, 0] + lin[i]
        for j in range(6):
            acc += lin[6 + 6 * i + j] * y[j]
        b[i, 0] = acc
    ncol = 1
    if variational:
        ncol = 9
        _forcing_jacobian(phi, phi_dot, phi_ddot, u, v, w_, pr, q, r, roll, theta, kmech, jf)
        for i in range(6):
            for j in range(8):
                b[i, 1 + j] = jf[8 * i + j]
            for j in range(6):
                b[i, 1 + j] += lin[6 + 6 * i + j]
    _mass_matrix(phi, kmech, jf[48:])
    for i in range(6):
        for j in range(6):
            a[i, j] = jf[48 + 6 * i + j]
    _solve(a, b, 6, ncol)
    for i in range(6):
        dy[i] = b[i, 0]
    roll_dot, theta_dot = _euler_rates(u, v, w_, pr, q, r, roll, theta)
    dy[6] = roll_dot
    dy[7] = theta_dot
    dy[8] = _earth_velocity(u, v, w_, pr, q, r, roll, theta)[2]  # the descent
    if not variational:
        return
    _euler_jacobian(u, v, w_, pr, q, r, roll, theta, je)
    # J (9 x 8): the accelerations', the Euler angles' and the descent's rows.
    for i in range(6):
        for k in range(8):
            jac[i, k] = b[i, 1 + k]
    _earth_jacobian(u, v, w_, pr, q, r, roll, theta, jf)  # A's values are used up: reuse
    for k in range(8):
        jac[6, k] = je[k]
        jac[7, k] = je[8 + k]
        jac[8, k] = jf[16 + k]  # the descent's row
    for i in range(9):
        for j in range(8):
            dy[9 + 8 * i + j] = 0.0
        for k in range(8):
            jik = jac[i, k]
            if jik != 0.0:
                for j in range(8):
                    dy[9 + 8 * i + j] += jik * y[9 + 8 * k + j]
    trace = 0.0
    for i in range(8):
        trace += jac[i, i]
    dy[81] = trace


@_helper
def _work():  # pragma: no cover - compiled
    """The scratch arrays of :func:`_field`: loads (42), B (6 x 9), A (6 x 6), dF/dx and A's
    values (48 + 36), the Euler rates' Jacobian (16), J (9 x 8)."""
    return (np.empty(42), np.empty((6, 9)), np.empty((6, 6)), np.empty(84), np.empty(16),
            np.empty((9, 8)))


@_jit
def segment(y0, t0, h, n_steps, variational, amplitude, p, klin, kmech):  # pragma: no cover
    """The state after ``n_steps`` DOP853 steps of size h from time t0 (a smooth stretch)."""
    n = y0.size
    y = y0.copy()
    stages = np.empty((N_STAGES, n))
    tmp = np.empty(n)
    work = _work()
    for step in range(n_steps):
        t = t0 + h * step
        for st in range(N_STAGES):
            for i in range(n):
                tmp[i] = y[i]
            for j in range(st):
                aij = h * RK_A[st, j]
                if aij != 0.0:
                    for i in range(n):
                        tmp[i] += aij * stages[j, i]
            _field(t + RK_C[st] * h, tmp, stages[st], variational, amplitude, p, klin, kmech,
                   work)
        for st in range(N_STAGES):
            bs = h * RK_B[st]
            if bs != 0.0:
                for i in range(n):
                    y[i] += bs * stages[st, i]
    return y


@_jit
def integrate(y0, n_steps, variational, amplitude, period, p, klin, kmech):  # pragma: no cover
    """The state after one period: ``n_steps`` DOP853 steps per half-stroke (restarted at
    stroke reversal)."""
    h = 0.5 * period / n_steps
    y = segment(y0, 0.0, h, n_steps, variational, amplitude, p, klin, kmech)
    return segment(y, 0.5 * period, h, n_steps, variational, amplitude, p, klin, kmech)


# --------------------------------------------------------------------------- the Python driver
def constants(model: Any) -> tuple[np.ndarray, np.ndarray, tuple[float, ...]]:
    """(p, klin, kmech) of a :class:`~flapping.model.sixdof.SixDofDynamics` with linear loads."""
    from flapping.model.sixdof import linear_constants

    p = np.array([2.0 * math.pi * model.insect.frequency, model.insect.stroke_mean,
                  model.alpha_m])
    return p, linear_constants(model.insect), tuple(float(v) for v in model._k)


def flow(model: Any, x0: np.ndarray, amplitude: float, n_steps: int,
         variational: bool) -> np.ndarray:
    """The plain (9) or variational (82) state after one period from x0 (8 states), z = 0."""
    p, klin, kmech = constants(model)
    y0 = np.zeros(N_VAR if variational else N_PLAIN)
    y0[:8] = x0
    if variational:
        y0[9:81] = np.vstack([np.eye(8), np.zeros((1, 8))]).ravel()
    return integrate(y0, int(n_steps), variational, float(amplitude), model.period, p, klin,
                     kmech)


#: Factors of the monodromy per half-stroke (the variational matrix restarts at the identity
#: at each): the product of well-conditioned factors keeps det M's digits (Liouville's check),
#: which M itself loses to its tiny multipliers.
FACTORS_PER_HALF_STROKE = 4


def monodromy_factors(model: Any, x0: np.ndarray, amplitude: float,
                      n_steps: int) -> tuple[np.ndarray, np.ndarray, float]:
    """The monodromy's factors (8 x 8 x K, M is their product, the last factor leftmost), the
    state after one period (9) and the integral of trace J over it. ``n_steps`` per half-stroke
    (a multiple of :data:`FACTORS_PER_HALF_STROKE`)."""
    p, klin, kmech = constants(model)
    y = np.zeros(N_VAR)
    y[:8] = x0
    k = FACTORS_PER_HALF_STROKE
    per = int(n_steps) // k
    h = 0.5 * model.period / (per * k)
    factors = np.empty((8, 8, 2 * k))
    trace = 0.0
    for i in range(2 * k):
        y[9:81] = np.vstack([np.eye(8), np.zeros((1, 8))]).ravel()
        y[81] = 0.0
        y = segment(y, i * per * h, h, per, True, float(amplitude), p, klin, kmech)
        factors[:, :, i] = y[9:81].reshape(9, 8)[:8]
        trace += y[81]
    return factors, y[:9].copy(), trace


def newton(model: Any, x0: np.ndarray, amplitude: float, n_steps: int, tol: float,
           max_iter: int = 12) -> tuple[np.ndarray, float, np.ndarray, float, int, int]:
    """Newton on (x0, Phi): periodicity of the eight states and zero net descent.

    Each iteration integrates the variational state (its matrix gives the state columns of
    Newton's Jacobian) and one plain flow at Phi (1 + 1e-7) (the Phi column by a forward
    difference: a Jacobian column to ~1e-7 keeps Newton's convergence quadratic to rounding from
    the planar orbit's start, whose residual is ~1e-9). After a step, a plain flow (9 states,
    not 82) checks the new point; the variational state is integrated again only if it does
    not pass.

    Returns
    -------
    tuple
        x0, amplitude, the variational end state (82) of the last point where Newton's Jacobian
        was formed (its matrix is the monodromy at ``n_steps`` there: at the solution, or one
        converging step from it, ~1e-9 away), the residual norm, the iterations and the
        evaluations of the right-hand side.
    """
    x = np.array(x0, dtype=float)
    amp = float(amplitude)
    per_flow = 2 * int(n_steps) * N_STAGES
    end = flow(model, x, amp, n_steps, True)
    evaluations = per_flow
    residual = np.append(end[:8] - x, end[8])
    for it in range(max_iter + 1):
        norm = float(np.linalg.norm(residual))
        if norm <= tol or it == max_iter or not np.isfinite(norm):
            return x, amp, end, norm, it, evaluations
        jac = np.empty((9, 9))
        jac[:, :8] = end[9:81].reshape(9, 8)
        jac[:8, :8] -= np.eye(8)
        h = 1e-7 * amp
        plus = flow(model, x, amp + h, n_steps, False)
        evaluations += per_flow
        jac[:, 8] = (plus - end[:9]) / h
        delta = np.linalg.solve(jac, -residual)
        x += delta[:8]
        amp += float(delta[8])
        check = flow(model, x, amp, n_steps, False)  # the new point, plain
        evaluations += per_flow
        residual = np.append(check[:8] - x, check[8])
        if float(np.linalg.norm(residual)) > tol:  # another step: its Jacobian
            end = flow(model, x, amp, n_steps, True)
            evaluations += per_flow
            residual = np.append(end[:8] - x, end[8])
    raise AssertionError("unreachable")  # pragma: no cover

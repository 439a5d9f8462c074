"""The numba-compiled parts of the hover kernel (imported only when the kernel is first used).

Everything here runs inside numba and trusts its inputs; the checks, the choice of step count and
the error estimate are in :mod:`flapping.fast.kernel`.

What is compiled, and how often. numba compiles a function the first time it is called, and the
code of every compiled function it calls is linked into the caller's and optimised and translated
to machine code again there, once per level of calls; numba's ``inline='always'`` costs more still
(it copies and retypes the callee at every call site). So the levels are few: the entry points
(:func:`newton_and_estimate`, with Newton's method in it; :func:`variational_period`,
:func:`sample_period`, :func:`states_at`, :func:`orbit_quadrature`) call small helpers and the
right-hand sides, and each entry point is compiled (or loaded from numba's cache,
``cache=True``) on its first call, so the orbit and its multipliers compile only what they use.
The right-hand sides have no flag choosing between the plain and the variational state (numba
typed both branches of such a flag, so both sets of generated derivatives were compiled
everywhere), and there is no NumPy slice assignment, ``np.linalg`` call or array expression: a
slice assignment compiled numba's shape-mismatch message (string formatting, ~1.5 s), and
``np.linalg.solve`` and ``det`` their checks and copies; LAPACK's ``dgesv`` and ``dgetrf``, which
they call, are called directly with the same arguments, so every number is the same to the last
bit. With an empty cache the default path (orbit, multipliers, averaged Jacobian) compiles in
~6-8 s of CPU instead of ~19 s (measured on a loaded 2-core machine).

State layouts (float64 arrays):

- the plain state ``x`` (5): u, w, q, theta and the descent z of :mod:`flapping.hover`;
- the variational state ``y`` (31): ``x``; the 5 x 4 matrix ``Y = dx(t)/d(u0, w0, q0, theta0)``
  row-major in ``y[5:25]``; the sensitivity ``s = dx(t)/dPhi`` in ``y[25:30]``; and the integral
  of trace J (the 4 x 4 Jacobian of eq. 2 with eq. 29's loads) in ``y[30]`` for Liouville's formula;
  and the forward distance x_e (x_e' = u cos theta + w sin theta) in ``y[31]``, so that the
  Newton integration gives both mean inertial velocities (x_e(T) / T and -z(T) / T).

``k`` is the constants array of :mod:`flapping.fast._generated` (``CONSTANTS``); ``p`` holds
(g [m/s^2], omega = 2 pi f [rad/s], 1/m [1/kg], 1/I_y [1/(kg m^2)]).

Integration: the 12-stage, 8th-order Runge-Kutta formula of Dormand and Prince (the tableau of
:mod:`flapping.fast._dop853`, equal to scipy's DOP853) at a fixed step, ``n`` steps per
half-stroke, restarted at stroke reversal where the right-hand side jumps (eq. 11): each
half-stroke is smooth, so the global error is O(h^8).
"""

from __future__ import annotations

import math

import numba
import numpy as np

# numba's own bindings of LAPACK's dgeev, those behind its np.linalg.eigvals (numba 0.60-0.68),
# which refuses a real matrix with complex eigenvalues (an oscillatory mode's pair): called here
# directly for the real and imaginary parts. Internal names: if a numba release moves them, the
# import fails loudly here rather than the multipliers changing.
from numba.np.linalg import _LAPACK, F_INT_nptype, _dummy_liveness_func

from flapping.fast import _dop853, _generated
from flapping.fast import _jit as _jit_policy
from flapping.model import _inertia_generated
from flapping.periodic import _tableau

# How every numba function of flapping is compiled and cached (one policy): an entry point is
# cached under the digest of the sources it inlines, a helper is linked into the entry points.
_jit = _jit_policy.entry_point(_dop853, _tableau, _generated, _inertia_generated)
_helper = _jit_policy.helper


# The generated formulas (plain Python, from the SymPy derivation), compiled here.
derivatives = _helper(_generated.derivatives)
derivatives_and_amplitude = _helper(_generated.derivatives_and_amplitude)
# The planar equations of motion (the six-dof derivation's planar case, never written by hand).
rigid_rates = _helper(_inertia_generated.rigid_rates)
rigid_state_jac = _helper(_inertia_generated.rigid_state_jac)

N_STAGES = _dop853.N_STAGES
RK_A = np.ascontiguousarray(_dop853.A)
RK_B = np.ascontiguousarray(_dop853.B)
RK_C = np.ascontiguousarray(_dop853.C)

N_PLAIN = 5
N_VAR = 32

# Newton's outcomes (status codes returned to the Python wrapper).
CONVERGED = 0
MAX_ITERATIONS = 1
AMPLITUDE_OUT_OF_RANGE = 2
NOT_FINITE = 3
SINGULAR = 4

# The eigenvalue problems' outcomes (np.linalg.eigvals raises LinAlgError for both failures).
EIGEN_OK = 0
EIGEN_NOT_FINITE = 1
EIGEN_NOT_CONVERGED = 2

_DGEEV = _LAPACK().numba_ez_rgeev(numba.float64)
_DGEEV_KIND = ord("d")
_DGEEV_NO_VECTORS = ord("N")
# And those behind numba's np.linalg.solve (dgesv) and np.linalg.det (dgetrf), called directly
# with the arguments numba passes (see :func:`_solve`, :func:`_det_is_zero`).
_DGESV = _LAPACK().numba_xgesv(numba.float64)
_DGETRF = _LAPACK().numba_xxgetrf(numba.float64)


@_helper
def _phase(t, amp, sign, p):  # pragma: no cover - compiled
    """phi, phi_dot, |phi_dot| and the sines and cosines of phi and 2 phi at time t (eq. 39)."""
    wt = p[1] * t
    phi = amp * math.cos(wt)
    phidot = -p[1] * amp * math.sin(wt)
    sphi, cphi = math.sin(phi), math.cos(phi)
    return phi, phidot, sign * phidot, sphi, cphi, 2.0 * sphi * cphi, cphi * cphi - sphi * sphi


@_helper
def plain_rhs(t, x, amp, sign, k, p, d, out):  # pragma: no cover - compiled
    """dx/dt of eq. (2) with eq. (29)'s loads, and z' = -u sin(theta) + w cos(theta)."""
    phi, phidot, absphidot, sphi, cphi, s2phi, c2phi = _phase(t, amp, sign, p)
    derivatives(phi, phidot, absphidot, sphi, cphi, s2phi, c2phi, k, d)
    u, w, q, th = x[0], x[1], x[2], x[3]
    r = rigid_rates(u, w, q, th, p[0])  # the generated eq. (2) at zero load
    out[0] = r[0] + d[0] * p[2] + d[3] * u + d[4] * w + d[5] * q
    out[1] = r[1] + d[1] * p[2] + d[6] * u + d[7] * w + d[8] * q
    out[2] = r[2] + d[2] * p[3] + d[9] * u + d[10] * w + d[11] * q
    out[3] = r[3]
    out[4] = r[4]


@_helper
def variational_rhs(t, y, amp, sign, k, p, d, out):  # pragma: no cover - compiled
    """d/dt of the variational state: x, Y' = J Y, s' = J s + df/dPhi, and trace J."""
    phi, phidot, absphidot, sphi, cphi, s2phi, c2phi = _phase(t, amp, sign, p)
    derivatives_and_amplitude(phi, phidot, absphidot, sphi, cphi, s2phi, c2phi, k, d)
    g, im, ii = p[0], p[2], p[3]
    u, w, q, th = y[0], y[1], y[2], y[3]
    rates = rigid_rates(u, w, q, th, g)  # the generated eq. (2) at zero load
    out[0] = rates[0] + d[0] * im + d[3] * u + d[4] * w + d[5] * q
    out[1] = rates[1] + d[1] * im + d[6] * u + d[7] * w + d[8] * q
    out[2] = rates[2] + d[2] * ii + d[9] * u + d[10] * w + d[11] * q
    out[3] = rates[3]
    out[4] = rates[4]
    # The Jacobian of the augmented field (its z column is zero: z feeds back into nothing):
    # the generated rigid-body part plus eq. (29)'s derivatives.
    r = rigid_state_jac(u, w, q, th, g)
    j00, j01, j02, j03 = r[0] + d[3], r[1] + d[4], r[2] + d[5], r[3]
    j10, j11, j12, j13 = r[4] + d[6], r[5] + d[7], r[6] + d[8], r[7]
    j20, j21, j22, j23 = r[8] + d[9], r[9] + d[10], r[10] + d[11], r[11]
    j30, j31, j32, j33 = r[12], r[13], r[14], r[15]
    j40, j41, j42, j43 = r[16], r[17], r[18], r[19]
    for c in range(5):  # the 4 columns of Y, then s
        b = 5 + c if c < 4 else 25
        step = 4 if c < 4 else 1
        y0, y1, y2, y3 = y[b], y[b + step], y[b + 2 * step], y[b + 3 * step]
        out[b] = j00 * y0 + j01 * y1 + j02 * y2 + j03 * y3
        out[b + step] = j10 * y0 + j11 * y1 + j12 * y2 + j13 * y3
        out[b + 2 * step] = j20 * y0 + j21 * y1 + j22 * y2 + j23 * y3
        out[b + 3 * step] = j30 * y0 + j31 * y1 + j32 * y2 + j33 * y3
        out[b + 4 * step] = j40 * y0 + j41 * y1 + j42 * y2 + j43 * y3
    inv = 1.0 / amp  # the generated amplitude derivatives are Phi d/dPhi
    out[25] += inv * (d[12] * im + d[15] * u + d[16] * w + d[17] * q)
    out[26] += inv * (d[13] * im + d[18] * u + d[19] * w + d[20] * q)
    out[27] += inv * (d[14] * ii + d[21] * u + d[22] * w + d[23] * q)
    out[30] = j00 + j11 + j22 + j33  # trace J, for Liouville's formula
    out[31] = rates[5]  # forward speed: no variations needed (nothing depends on x_e)


@_helper
def _stage_state(s, h, y, stages, tmp):  # pragma: no cover - compiled
    """tmp = y + h sum_j a_sj k_j: the state at which stage s of a step is evaluated.

    The sums run over contiguous rows of ``stages`` (the inner loop over the state vectorises)
    and skip the zero couplings of the tableau (16 of the 66 a_ij); each sum adds its terms in
    the order of the plain double loop, so the result is the same to the last bit.
    """
    n = y.size
    for i in range(n):
        tmp[i] = y[i]
    for j in range(s):
        a = h * RK_A[s, j]
        if a != 0.0:
            for i in range(n):
                tmp[i] += a * stages[j, i]


@_helper
def _step_end(h, y, stages, tmp):  # pragma: no cover - compiled
    """y += h sum_s b_s k_s in place, skipping the zero weights (4 of the 12 b_s)."""
    n = y.size
    for i in range(n):
        tmp[i] = 0.0
    for s in range(N_STAGES):
        b = RK_B[s]
        if b != 0.0:
            for i in range(n):
                tmp[i] += b * stages[s, i]
    for i in range(n):
        y[i] += h * tmp[i]


@_helper
def _plain_step(t, h, y, amp, sign, k, p, d, stages, tmp):  # pragma: no cover - compiled
    """One fixed step of the 8th-order Dormand-Prince formula on the plain state, in place.

    :func:`variational_period` takes the same step with :func:`variational_rhs` in its loop: one
    function per state rather than a flag choosing the right-hand side (numba typed and compiled
    both branches of such a flag) and one level of compiled calls less on the default path.
    """
    for s in range(N_STAGES):
        _stage_state(s, h, y, stages, tmp)
        plain_rhs(t + RK_C[s] * h, tmp, amp, sign, k, p, d, stages[s])
    _step_end(h, y, stages, tmp)


@_jit
def variational_period(z, n_steps, k, p):  # pragma: no cover - compiled
    """The variational state after one period from x0 = z[:4] (z = 0) at Phi = z[4].

    ``n_steps`` per half-stroke: segment 0 is the backward stroke (|phi_dot| = -phi_dot),
    segment 1 the forward stroke.
    """
    y = np.zeros(N_VAR)
    for i in range(4):
        y[i] = z[i]
    for j in range(4):
        y[5 + 5 * j] = 1.0  # Y = [I; 0] (row-major 5 x 4: element (j, j) at 5 + 4 j + j)
    amp = z[4]
    period = 2.0 * math.pi / p[1]
    h = 0.5 * period / n_steps
    d = np.empty(24)
    stages = np.empty((N_STAGES, N_VAR))
    tmp = np.empty(N_VAR)
    for segment in range(2):
        sign = -1.0 if segment == 0 else 1.0
        t0 = 0.5 * period * segment
        for step in range(n_steps):  # one Dormand-Prince step (as _plain_step's)
            t = t0 + step * h
            for s in range(N_STAGES):
                _stage_state(s, h, y, stages, tmp)
                variational_rhs(t + RK_C[s] * h, tmp, amp, sign, k, p, d, stages[s])
            _step_end(h, y, stages, tmp)
    return y


@_helper
def residual_and_jacobian(y, z):  # pragma: no cover - compiled
    """The hover residual x(T) - x(0) (z(0) = 0) and its Jacobian in (u0, w0, q0, theta0, Phi)."""
    r = np.empty(5)
    J = np.empty((5, 5))
    for i in range(5):
        r[i] = y[i] - (z[i] if i < 4 else 0.0)
        for j in range(4):
            J[i, j] = y[5 + 4 * i + j] - (1.0 if i == j else 0.0)
        J[i, 4] = y[25 + i]
    return r, J


@_helper
def _all_finite(r, J):  # pragma: no cover - compiled
    """Whether every entry of the vector r and of the matrix J is finite."""
    for i in range(r.size):
        if not math.isfinite(r[i]):
            return False
    for i in range(J.shape[0]):
        for j in range(J.shape[1]):
            if not math.isfinite(J[i, j]):
                return False
    return True


@_helper
def _fortran_copy(m):  # pragma: no cover - compiled
    """The square matrix m copied to Fortran order (its transpose in C order), as LAPACK reads
    it and as numba's np.linalg functions copy it."""
    n = m.shape[0]
    a = np.empty((n, n))
    for i in range(n):
        for j in range(n):
            a[j, i] = m[i, j]
    return a


@_helper
def _det_is_zero(m):  # pragma: no cover - compiled
    """``np.linalg.det(m) == 0`` for a finite square m, computed as numba computes det: LAPACK's
    LU factorisation (dgetrf) of a Fortran-ordered copy, det = +-exp(sum log |u_ii|), zero if a
    pivot is exactly zero (dgetrf's info > 0) or if the exponential underflows."""
    n = m.shape[0]
    a = _fortran_copy(m)
    ipiv = np.empty(n, dtype=F_INT_nptype)
    info = _DGETRF(_DGEEV_KIND, n, n, a.ctypes, n, ipiv.ctypes)
    _dummy_liveness_func([a.size, ipiv.size])  # alive through the call
    if info > 0:
        return True
    log_det = 0.0
    for i in range(n):
        log_det = log_det + math.log(abs(a[i, i]))
    return math.exp(log_det) == 0.0


@_helper
def _solve_negated(m, b):  # pragma: no cover - compiled
    """``np.linalg.solve(m, -b)``, as numba computes it: its checks, then LAPACK's dgesv on a
    Fortran-ordered copy of m and a copy of -b, with the same arguments."""
    n = m.shape[0]
    if not _all_finite(b, m):
        raise np.linalg.LinAlgError("Array must not contain infs or NaNs.")
    a = _fortran_copy(m)
    x = np.empty(n)
    for i in range(n):
        x[i] = -b[i]
    ipiv = np.empty(n, dtype=F_INT_nptype)
    info = _DGESV(_DGEEV_KIND, n, 1, a.ctypes, n, ipiv.ctypes, x.ctypes, n)
    _dummy_liveness_func([a.size, x.size, ipiv.size])  # alive through the call
    if info > 0:
        raise np.linalg.LinAlgError("Matrix is singular to machine precision.")
    return x


@_helper
def eigenvalues(m, out):  # pragma: no cover - compiled
    """Eigenvalues of the real square matrix ``m`` into the complex ``out``: LAPACK's dgeev, as
    ``np.linalg.eigvals``. Returns :data:`EIGEN_OK`, or the failure (non-finite entries, or
    dgeev did not converge)."""
    n = m.shape[0]
    a = np.empty((n, n))  # m transposed in C order: m in the Fortran order dgeev reads
    for i in range(n):
        for j in range(n):
            if not math.isfinite(m[i, j]):
                return EIGEN_NOT_FINITE
            a[j, i] = m[i, j]
    wr = np.empty(n)
    wi = np.empty(n)
    vl = np.empty(1)  # not referenced (no eigenvectors), but some LAPACKs check the pointers
    vr = np.empty(1)
    info = _DGEEV(_DGEEV_KIND, _DGEEV_NO_VECTORS, _DGEEV_NO_VECTORS, n, a.ctypes, n, wr.ctypes,
                  wi.ctypes, vl.ctypes, 1, vr.ctypes, 1)
    _dummy_liveness_func([a.size, wr.size, wi.size, vl.size, vr.size])  # alive through the call
    if info != 0:
        return EIGEN_NOT_CONVERGED
    for i in range(n):
        out[i] = complex(wr[i], wi[i])
    return EIGEN_OK


@_helper
def sort_multipliers(w):  # pragma: no cover - compiled
    """In place: by descending modulus (a stable sort), in a complex-conjugate pair the positive
    imaginary part first (the order of :func:`flapping.fast.kernel._sorted`)."""
    n = w.size
    for i in range(1, n):
        v = w[i]
        modulus = abs(v)
        j = i - 1
        while j >= 0 and abs(w[j]) < modulus:
            w[j + 1] = w[j]
            j -= 1
        w[j + 1] = v
    for i in range(n - 1):
        a, b = w[i], w[i + 1]
        if a.imag < 0.0 and abs(a - b.conjugate()) <= 1e-12 * max(1.0, abs(a)):
            w[i], w[i + 1] = b, a


@_jit
def newton_and_estimate(z, n_steps, k, p, max_iter, xtol, factor):  # pragma: no cover
    """Newton's method on the hover residual at ``n_steps``, then the Richardson estimates.

    Newton runs from z = (u0, w0, q0, theta0, Phi), in place, and stops when its next step would
    be below ``xtol`` (relative to max(1, |z_i|)) in every unknown, leaving z at the last
    integrated point, to which the variational state y belongs. One compiled function with the
    estimates: a Newton of its own would be one more level of compiled calls, in which numba
    optimises and translates the whole integration again (~1 s with an empty cache).

    Returns (status, iterations, residual norm, y, r, z_err, multipliers, multiplier_err,
    eigen_status): ``y`` the variational state of the last Newton integration and ``r`` its
    residual at z; ``z_err`` (5) the absolute Richardson estimate of z's error, ``factor`` times
    the Newton correction that the ``n_steps / 2`` integration at z asks for; ``multipliers``
    the eigenvalues of the monodromy M (sorted by :func:`sort_multipliers`) and
    ``multiplier_err`` the largest distance from one of them to the nearest eigenvalue of
    M + dM, dM = ``factor`` (M - M_coarse). On a failed Newton solve only the status, iterations
    and norm are meaningful; ``eigen_status`` is :data:`EIGEN_OK` unless an eigenvalue problem
    failed.
    """
    status, nit, norm = MAX_ITERATIONS, max_iter, math.inf
    y = np.zeros(N_VAR)
    r = np.zeros(5)
    for it in range(1, max_iter + 1):
        if not (0.0 < z[4] <= 0.5 * math.pi):
            status, nit = AMPLITUDE_OUT_OF_RANGE, it - 1
            break
        nit = it
        y = variational_period(z, n_steps, k, p)
        r, J = residual_and_jacobian(y, z)
        norm = 0.0
        for i in range(5):  # np.sum(r * r): its sum, term by term from 0
            norm += r[i] * r[i]
        norm = math.sqrt(norm)
        if not _all_finite(r, J):
            status = NOT_FINITE
            break
        if _det_is_zero(J):
            status = SINGULAR
            break
        dz = _solve_negated(J, r)
        # Keep the amplitude step within a third of the way to either end of (0, pi/2].
        limit = min(z[4], 0.5 * math.pi - z[4] + 1e-3) / 3.0
        scale = min(1.0, limit / abs(dz[4])) if dz[4] != 0.0 else 1.0
        small = True
        for i in range(5):
            if abs(dz[i]) > xtol * max(1.0, abs(z[i])):
                small = False
        if small:  # z is the root to rounding level; y and the residual belong to it
            status = CONVERGED
            break
        for i in range(5):
            z[i] += scale * dz[i]
    multipliers = np.zeros(4, dtype=np.complex128)
    if status != CONVERGED:
        return status, nit, norm, y, np.zeros(5), np.zeros(5), multipliers, 0.0, EIGEN_OK
    coarse = variational_period(z, n_steps // 2, k, p)
    r_c, J_c = residual_and_jacobian(coarse, z)
    change = np.empty(5)
    for i in range(5):
        change[i] = r_c[i] - r[i]
    z_err = _solve_negated(J_c, change)
    for i in range(5):
        z_err[i] = abs(z_err[i] * factor)
    M = np.empty((4, 4))
    moved = np.empty((4, 4))
    for i in range(4):
        for j in range(4):
            m = y[5 + 4 * i + j]
            M[i, j] = m
            moved[i, j] = m + (m - coarse[5 + 4 * i + j]) * factor
    moved_values = np.empty(4, dtype=np.complex128)
    eigen = eigenvalues(M, multipliers)
    if eigen == EIGEN_OK:
        eigen = eigenvalues(moved, moved_values)
    shift = 0.0
    for i in range(4):
        nearest = math.inf
        for j in range(4):
            nearest = min(nearest, abs(moved_values[j] - multipliers[i]))
        shift = max(shift, nearest)
    sort_multipliers(multipliers)
    return status, nit, norm, y, r, z_err, multipliers, shift, eigen


@_jit
def sample_period(x0, amp, n_steps, k, p):  # pragma: no cover - compiled
    """The plain state (u, w, q, theta, z) over one period: row 0 the start, row i after step i
    (``n_steps`` per half-stroke, at t = i h)."""
    samples = np.empty((2 * n_steps + 1, N_PLAIN))
    y = np.zeros(N_PLAIN)
    for i in range(4):
        y[i] = x0[i]
    for i in range(N_PLAIN):
        samples[0, i] = y[i]
    period = 2.0 * math.pi / p[1]
    h = 0.5 * period / n_steps
    d = np.empty(24)
    stages = np.empty((N_STAGES, N_PLAIN))
    tmp = np.empty(N_PLAIN)
    row = 1
    for segment in range(2):
        sign = -1.0 if segment == 0 else 1.0
        t0 = 0.5 * period * segment
        for i in range(n_steps):
            _plain_step(t0 + i * h, h, y, amp, sign, k, p, d, stages, tmp)
            for j in range(N_PLAIN):
                samples[row, j] = y[j]
            row += 1
    return samples


@_jit
def states_at(x0, amp, n_steps, k, p, times):  # pragma: no cover - compiled
    """The plain state at sorted ``times`` in (0, T): the step grid, then one shorter step."""
    samples = sample_period(x0, amp, n_steps, k, p)
    half = np.pi / p[1]
    h = half / n_steps
    out = np.empty((times.size, N_PLAIN))
    d = np.empty(24)
    stages = np.empty((N_STAGES, N_PLAIN))
    tmp = np.empty(N_PLAIN)
    y = np.empty(N_PLAIN)
    for i in range(times.size):
        segment = 0 if times[i] < half else 1
        j = min(int((times[i] - segment * half) / h), n_steps - 1)
        t_grid = segment * half + j * h
        for m in range(N_PLAIN):
            y[m] = samples[segment * n_steps + j, m]
        sign = -1.0 if segment == 0 else 1.0
        _plain_step(t_grid, times[i] - t_grid, y, amp, sign, k, p, d, stages, tmp)
        for m in range(N_PLAIN):
            out[i, m] = y[m]
    return out


@_helper
def _add_jacobian(d, x, g, weight, total):  # pragma: no cover - compiled
    """total += weight J, with J the Jacobian of eq. (2) + eq. (29)'s loads at x (eqs. 44-47):
    the generated rigid-body part plus the derivatives."""
    r = rigid_state_jac(x[0], x[1], x[2], x[3], g)
    for i in range(4):
        for j in range(4):
            entry = r[4 * i + j]
            if i < 3 and j < 3:
                entry = entry + d[3 + 3 * i + j]
            total[i, j] += weight * entry


@_jit
def orbit_quadrature(x0, amp, k, p, nodes, weights, min_steps):  # pragma: no cover - compiled
    """Cycle means of the Jacobian and of the inertial velocities along the orbit from x0.

    Gauss-Legendre (``nodes``, ``weights`` on [-1, 1]) on each half-stroke, where the integrands
    are smooth. The state is carried from node to node by the fixed-step formula, each gap split
    into equal steps of at most T / (2 min_steps). Returns (J_mean (4, 4), v_mean (2,)) with
    v = (forward, climb) = (u cos(theta) + w sin(theta), u sin(theta) - w cos(theta)).
    """
    period = 2.0 * math.pi / p[1]
    half = 0.5 * period
    h = 0.5 * half  # half-width of a half-stroke, as in the (0, T/2, T) split of the adaptive path
    h_max = half / min_steps
    total = np.zeros((4, 4))
    velocity = np.zeros(2)
    y = np.zeros(N_PLAIN)
    for i in range(4):
        y[i] = x0[i]
    d = np.empty(24)
    stages = np.empty((N_STAGES, N_PLAIN))
    tmp = np.empty(N_PLAIN)
    for segment in range(2):
        sign = -1.0 if segment == 0 else 1.0
        a = half * segment
        t = a
        # To each node; after the backward stroke's, on to the stroke reversal, where the
        # forward stroke starts.
        for i in range(nodes.size + 1 - segment):
            t_next = h * nodes[i] + a + h if i < nodes.size else half
            n = max(1, int(math.ceil((t_next - t) / h_max)))  # equal steps of at most h_max
            step = (t_next - t) / n
            for j in range(n):
                _plain_step(t + j * step, step, y, amp, sign, k, p, d, stages, tmp)
            t = t_next
            if i == nodes.size:
                break
            phi, phidot, absphidot, sphi, cphi, s2phi, c2phi = _phase(t, amp, sign, p)
            derivatives(phi, phidot, absphidot, sphi, cphi, s2phi, c2phi, k, d)
            weight = h * weights[i]
            _add_jacobian(d, y, p[0], weight, total)
            rates = rigid_rates(y[0], y[1], y[2], y[3], 0.0)
            velocity[0] += weight * rates[5]
            velocity[1] += weight * -rates[4]  # climb = -down
    for i in range(4):
        for j in range(4):
            total[i, j] /= period
    for i in range(2):
        velocity[i] /= period
    return total, velocity

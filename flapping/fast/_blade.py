"""The numba-compiled blade-element loads and graded hover field (imported on first use only).

Everything here runs inside ``numba.njit(cache=True)`` and trusts its inputs; the packing, the
checks and the choice of when to run it are in :mod:`flapping.fast.blade`.

The arithmetic is :meth:`flapping.model.aerodynamics.BladeElementModel._loads` (with
``_sign_split``, ``_lev_coefficients`` and ``_add_sign_correction``), eq. (2) of
:meth:`flapping.model.dynamics.LongitudinalDynamics.rhs` (for wings of mass, the generated
inertial loads of :mod:`flapping.model._inertia_generated`, compiled as they are), the inertial
velocity of :func:`flapping.model.dynamics.inertial_velocity` and the time grading of
:func:`flapping.hover.problem.grading`, written out as scalar loops over the span stations in
the same order of operations. Those Python functions stay the single source of truth:
``tests/fast/test_blade.py`` checks this copy against them at random states, phases and insects.
The quadrature rules and constants are not recomputed here: they are the Python model's own
arrays, packed by :func:`flapping.fast.blade.pack` into one float64 array ``data`` laid out as
the ``I_*`` indices and ``OFFSET`` below.

The one function not in the Python path is the regularized incomplete beta function (scipy's
``betainc``/``betaincc`` there): a continued fraction (modified Lentz), accurate to a few ulps
of 1, which is all the sign correction needs (it multiplies span moments that are a fraction of
the loads; checked against scipy in the tests).
"""

from __future__ import annotations

import math

import numpy as np

from flapping.fast import _jit as _jit_policy
from flapping.model import _inertia_generated
from flapping.periodic import _tableau
from flapping.periodic._tableau import N_STAGES, A, B, C

# The one policy of flapping's numba code (flapping.fast._jit): cached entry points, keyed also
# on the sources they inline (the generated inertial loads, the tableau).
_jit = _jit_policy.entry_point(_inertia_generated, _tableau)

# The layout of ``data``: the 13 constants of BladeElementModel._consts, in its order, then ...
(I_OMEGA, I_SIN_2AM, I_COS_2AM, I_SIN_AM2, I_COS_AM2, I_RHO_A, I_RHO_K, I_X_H, I_ZH, I_XC,
 I_DAMPING, I_MU1F, I_MU2) = range(13)
# ... the semi-span R [m], the hinge height h_w [m], the insect's mean stroke angle [rad],
# g [m/s^2], m [kg], I_y [kg m^2], the half period T/2 [s], the variant (0 small-angle, 1 exact),
# the number of span stations, the number of hover conditions (1: z; 2: z and x_e) ...
(I_R, I_H_W, I_PHI_BAR, I_G, I_MASS, I_IY, I_HALF, I_VARIANT, I_N_R, I_N_COND) = range(13, 23)
# ... whether the wings have mass (1.0) or not (0.0), the 8 constants of the wings' inertia
# (flapping.model.inertia_derivation.CONSTANT_NAMES, WingInertia.constants) ...
I_INERTIA, I_K = 23, 24
# ... and from OFFSET: the stations r (n_r), the weight matrix W (n_r x 6, row-major), its column
# sums S0 (6) and r-moments S1 (6), the incomplete-moment parameters a, b and totals (7 each),
# and log B(a, b) of each (7; :func:`log_beta`, so that the sign correction's seven incomplete
# beta functions do not recompute three lgamma each at every evaluation).
OFFSET = 32
N_PARTIAL = 7

RK_A, RK_B, RK_C = np.ascontiguousarray(A), np.ascontiguousarray(B), np.ascontiguousarray(C)

_FPMIN = 1e-300
_CF_EPS = 1e-16
_CF_MAXIT = 500


@_jit
def _betacf(a, b, x):  # pragma: no cover - compiled
    """The continued fraction of the incomplete beta function (modified Lentz)."""
    qab, qap, qam = a + b, a + 1.0, a - 1.0
    c = 1.0
    d = 1.0 - qab * x / qap
    if abs(d) < _FPMIN:
        d = _FPMIN
    d = 1.0 / d
    h = d
    for m in range(1, _CF_MAXIT + 1):
        m2 = 2.0 * m
        aa = m * (b - m) * x / ((qam + m2) * (a + m2))
        d = 1.0 + aa * d
        if abs(d) < _FPMIN:
            d = _FPMIN
        c = 1.0 + aa / c
        if abs(c) < _FPMIN:
            c = _FPMIN
        d = 1.0 / d
        h *= d * c
        aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2))
        d = 1.0 + aa * d
        if abs(d) < _FPMIN:
            d = _FPMIN
        c = 1.0 + aa / c
        if abs(c) < _FPMIN:
            c = _FPMIN
        d = 1.0 / d
        delta = d * c
        h *= delta
        if abs(delta - 1.0) < _CF_EPS:
            break
    return h


@_jit
def log_beta(a, b):  # pragma: no cover - compiled
    """-log B(a, b) = lgamma(a + b) - lgamma(a) - lgamma(b), as betainc_pair sums it."""
    return math.lgamma(a + b) - math.lgamma(a) - math.lgamma(b)


@_jit
def betainc_pair(a, b, x):  # pragma: no cover - compiled
    """(I_x(a, b), 1 - I_x(a, b)): the regularized incomplete beta function and its complement,
    one from the continued fraction that converges at x, the other as 1 minus it (so both are
    accurate to ~1e-13 of the larger of the two, not always relative to the smaller)."""
    if x <= 0.0:
        return 0.0, 1.0
    if x >= 1.0:
        return 1.0, 0.0
    return betainc_pair_from(a, b, x, log_beta(a, b), math.log(x), math.log1p(-x))


@_jit
def betainc_pair_from(a, b, x, lb, log_x, log1m_x):  # pragma: no cover - compiled
    """betainc_pair for x in (0, 1) from lb = log_beta(a, b), log(x) and log1p(-x) (the same
    operations in the same order: a caller with several (a, b) at one x computes them once)."""
    front = math.exp(lb + a * log_x + b * log1m_x)
    if x < (a + 1.0) / (a + b + 2.0):
        lower = front * _betacf(a, b, x) / a
        return lower, 1.0 - lower
    upper = front * _betacf(b, a, 1.0 - x) / b
    return 1.0 - upper, upper


@_jit
def sign_split(phi_dot, u_c, s, R):  # pragma: no cover - compiled
    """aerodynamics._sign_split: (sigma, x, root, split); the piece is [0, x] (root) or [x, R]
    where sign(U) = -sigma, and ``split`` says whether U changes sign inside the span."""
    if phi_dot == 0.0:
        return (s if u_c == 0.0 else math.copysign(1.0, u_c)), 0.0, False, False
    x = -u_c / phi_dot
    if not 0.0 < x < R:
        mid = phi_dot * 0.5 * R + u_c
        return (s if mid == 0.0 else math.copysign(1.0, mid)), x, False, False
    root_sign = math.copysign(1.0, u_c)
    if x <= 0.5 * R:
        return -root_sign, x, True, True
    return root_sign, x, False, True


@_jit
def lev_integrals(phi_dot, u_c, w_0, q_s, sin_2ag, sigma, data):  # pragma: no cover - compiled
    """aerodynamics._lev_coefficients at every station, integrated against the columns of W
    that are used: (A1[0], A1[1], B1[0], B1[1], B1[3]) (chord powers c, c^2, c^2, c^2, c r)."""
    sin_am2, cos_am2, cos_2am = data[I_SIN_AM2], data[I_COS_AM2], data[I_COS_2AM]
    small_angle = data[I_VARIANT] == 0.0
    n_r = int(data[I_N_R])
    i_w = OFFSET + n_r
    half_sin = 0.5 * sin_2ag
    a10 = a11 = b10 = b11 = b13 = 0.0
    for i in range(n_r):
        r = data[OFFSET + i]
        U = phi_dot * r + u_c
        w_eff = w_0 - q_s * r
        if small_angle:
            abs_u = sigma * U
            uu = U * abs_u
            aw = abs_u * w_eff
            a = -(uu * sin_am2 + half_sin * aw)
            b = -(half_sin * uu + cos_am2 * aw)
        else:
            uw = U * w_eff
            uu = U * U
            ww = w_eff * w_eff
            diff = uu - ww
            v2 = uu + ww
            lift = sin_2ag * diff + (2.0 * cos_2am) * uw
            drag = v2 - cos_2am * diff + (2.0 * sin_2ag) * uw
            # 0.5 / |V| as the Python's 0.5 * (...) ** -0.5 to an ulp: a libm pow per station
            # was half the exact variant's time
            half_inv_v = 0.5 / math.sqrt(v2 + 1e-300)
            a = (lift * w_eff - drag * U) * half_inv_v
            b = -(lift * U + drag * w_eff) * half_inv_v
        row = i_w + 6 * i
        a10 += a * data[row]
        a11 += a * data[row + 1]
        b10 += b * data[row]
        b11 += b * data[row + 1]
        b13 += b * data[row + 3]
    return a10, a11, b10, b11, b13


@_jit
def _partial_moment(m, xr, log_x, log1m_x, root, i_pa, data):  # pragma: no cover - compiled
    """Incomplete span moment m on [0, x] (root) or [x, R]: its total times I_xr(a, b) or its
    complement (xr = x / R), by betainc_pair from the packed log B(a, b), log xr and
    log(1 - xr)."""
    i_pb = i_pa + N_PARTIAL
    i_pf, i_lb = i_pb + N_PARTIAL, i_pb + 2 * N_PARTIAL
    a, b = data[i_pa + m], data[i_pb + m]
    if 0.0 < xr < 1.0:
        lower, upper = betainc_pair_from(a, b, xr, data[i_lb + m], log_x, log1m_x)
    else:  # x / R rounded onto an end of the span
        lower, upper = betainc_pair(a, b, xr)
    return data[i_pf + m] * (lower if root else upper)


@_jit
def sign_correction(x, root, sigma, phi_dot, u_c, w_0, q_s, sin_2ag,
                    data):  # pragma: no cover - compiled
    """aerodynamics._add_sign_correction: the increments of (A1[0], A1[1], B1[0], B1[1],
    B1[3]) on the piece where ``|U|`` = -sigma U (incomplete span moments, closed form)."""
    sin_am2, cos_am2 = data[I_SIN_AM2], data[I_COS_AM2]
    n_r = int(data[I_N_R])
    i_pa = OFFSET + 7 * n_r + 12
    xr = x / data[I_R]
    log_x, log1m_x = math.log(xr), math.log1p(-xr)  # once for the seven functions
    j01 = _partial_moment(0, xr, log_x, log1m_x, root, i_pa, data)
    j11 = _partial_moment(1, xr, log_x, log1m_x, root, i_pa, data)
    j21 = _partial_moment(2, xr, log_x, log1m_x, root, i_pa, data)
    j31 = _partial_moment(3, xr, log_x, log1m_x, root, i_pa, data)
    j02 = _partial_moment(4, xr, log_x, log1m_x, root, i_pa, data)
    j12 = _partial_moment(5, xr, log_x, log1m_x, root, i_pa, data)
    j22 = _partial_moment(6, xr, log_x, log1m_x, root, i_pa, data)
    c2, c1, c0 = phi_dot * phi_dot, 2.0 * phi_dot * u_c, u_c * u_c
    d2, d1, d0 = -phi_dot * q_s, phi_dot * w_0 - u_c * q_s, u_c * w_0
    two_sigma, half_sin = 2.0 * sigma, 0.5 * sin_2ag
    e2 = two_sigma * (sin_am2 * c2 + half_sin * d2)
    e1 = two_sigma * (sin_am2 * c1 + half_sin * d1)
    e0 = two_sigma * (sin_am2 * c0 + half_sin * d0)
    f2 = two_sigma * (half_sin * c2 + cos_am2 * d2)
    f1 = two_sigma * (half_sin * c1 + cos_am2 * d1)
    f0 = two_sigma * (half_sin * c0 + cos_am2 * d0)
    return (e0 * j01 + e1 * j11 + e2 * j21, e0 * j02 + e1 * j12 + e2 * j22,
            f0 * j01 + f1 * j11 + f2 * j21, f0 * j02 + f1 * j12 + f2 * j22,
            f0 * j11 + f1 * j21 + f2 * j31)


@_jit
def loads(t, u, w, q, s, amplitude, phi_bar, data):  # pragma: no cover - compiled
    """(X, Z, M) of both wings [N, N, N m]: BladeElementModel._loads at amplitude Phi and mean
    stroke angle phi_bar (body axes; eqs. 9-23 integrated over the span)."""
    omega_f = data[I_OMEGA]
    rho_a, rho_k, x_h, zh, xc = data[I_RHO_A], data[I_RHO_K], data[I_X_H], data[I_ZH], data[I_XC]
    damping, mu1f, mu2 = data[I_DAMPING], data[I_MU1F], data[I_MU2]
    h_w = data[I_H_W]
    n_r = int(data[I_N_R])
    i_s0 = OFFSET + 7 * n_r
    i_s1 = i_s0 + 6
    phase = omega_f * t
    phi = amplitude * math.cos(phase)
    if phi_bar != 0.0:
        phi += phi_bar
    phi_dot = -omega_f * amplitude * math.sin(phase)
    cphi, sphi = math.cos(phi), math.sin(phi)
    sin_2ag = s * data[I_SIN_2AM]
    u_c = (u - q * h_w) * cphi if h_w != 0.0 else u * cphi
    w_0 = w - q * x_h
    q_s = q * sphi
    sigma, x, root, split = 1.0, 0.0, False, False
    if data[I_VARIANT] == 0.0:  # small-angle: |U| integrated as sigma U, corrected on a piece
        sigma, x, root, split = sign_split(phi_dot, u_c, s, data[I_R])
    a10, a11, b10, b11, b13 = lev_integrals(phi_dot, u_c, w_0, q_s, sin_2ag, sigma, data)
    if split:
        da10, da11, db10, db11, db13 = sign_correction(x, root, sigma, phi_dot, u_c, w_0, q_s,
                                                       sin_2ag, data)
        a10 += da10
        a11 += da11
        b10 += db10
        b11 += db11
        b13 += db13
    # Rotational lift: A2 = k (w_0 S0 - q_s S1), B2 = -k (phi_dot S1 + u_c S0).
    omega = q * cphi
    k = rho_k * omega
    a21 = k * (w_0 * data[i_s0 + 1] - q_s * data[i_s1 + 1])
    a22 = k * (w_0 * data[i_s0 + 2] - q_s * data[i_s1 + 2])
    b21 = -k * (phi_dot * data[i_s1 + 1] + u_c * data[i_s0 + 1])
    b22 = -k * (phi_dot * data[i_s1 + 2] + u_c * data[i_s0 + 2])
    b24 = -k * (phi_dot * data[i_s1 + 4] + u_c * data[i_s0 + 4])
    a1_c, a1_c2 = rho_a * a10, rho_a * a11
    b1_c, b1_c2, b1_cr = rho_a * b10, rho_a * b11, rho_a * b13
    x_force = cphi * (a1_c + a21)
    z_force = b1_c + b21
    xcp = xc * s * cphi
    zcp = zh * cphi
    moment = (
        -(x_h * b1_c + sphi * b1_cr)
        + zcp * a1_c2 - (x_h * b21 + sphi * b24) + xcp * b1_c2
        + zcp * a22 + xcp * b22
        + damping * (mu1f + mu2 * abs(omega)) * omega * cphi
    )
    if h_w != 0.0:
        moment -= h_w * x_force
    return x_force, z_force, moment


# The wings' inertial loads: the generated code of flapping.model.inertia (the SymPy derivation),
# compiled here as the hover kernel compiles its generated derivatives.
mass_matrix = _jit(_inertia_generated.mass_matrix)
forcing = _jit(_inertia_generated.forcing)
rigid_rates = _jit(_inertia_generated.rigid_rates)


@_jit
def solve3(m):  # pragma: no cover - compiled
    """x of a x = b from the augmented 3 x 4 matrix m = [a | b] (overwritten): Gaussian
    elimination with partial pivoting (the LU factorisation np.linalg.solve asks LAPACK for)."""
    for col in range(3):
        pivot = col
        for i in range(col + 1, 3):
            if abs(m[i, col]) > abs(m[pivot, col]):
                pivot = i
        if pivot != col:
            for j in range(4):
                m[col, j], m[pivot, j] = m[pivot, j], m[col, j]
        for i in range(col + 1, 3):
            factor = m[i, col] / m[col, col]
            for j in range(col + 1, 4):
                m[i, j] -= factor * m[col, j]
    x = np.empty(3)
    for i in range(2, -1, -1):
        acc = m[i, 3]
        for j in range(i + 1, 3):
            acc -= m[i, j] * x[j]
        x[i] = acc / m[i, i]
    return x


@_jit
def wing_accelerations(t, amplitude, phi_bar, u, w, q, theta, X, Z, M,
                       data):  # pragma: no cover - compiled
    """(u', w', q') with wings of mass: WingInertia.accelerations, A^-1 (loads + F), at the
    stroke of flapping.model.inertia.stroke_phase."""
    omega = data[I_OMEGA]
    c, s = math.cos(omega * t), math.sin(omega * t)
    phi = phi_bar + amplitude * c
    phi_dot = -omega * amplitude * s
    phi_ddot = -omega * omega * amplitude * c
    i = I_K
    k = (data[i], data[i + 1], data[i + 2], data[i + 3], data[i + 4], data[i + 5], data[i + 6],
         data[i + 7])
    f0, f1, f2 = forcing(phi, phi_dot, phi_ddot, u, w, q, theta, k)
    # The generated matrix is a tuple of mixed ints and floats: unpacked statically.
    a0, a1, a2, a3, a4, a5, a6, a7, a8 = mass_matrix(phi, k)
    m = np.array([[a0, a1, a2, X + f0], [a3, a4, a5, Z + f1], [a6, a7, a8, M + f2]],
                 dtype=np.float64)
    return solve3(m)


@_jit
def grading(s):  # pragma: no cover - compiled
    """g(s) of the graded mesh (flapping.hover.problem.grading)."""
    x = 2.0 * math.pi * s
    return s - (4.0 / 3.0) * math.sin(x) / (2.0 * math.pi) + math.sin(2.0 * x) / (12.0 * math.pi)


@_jit
def grading_derivative(s):  # pragma: no cover - compiled
    """g'(s) = (8/3) sin^4(pi s) (flapping.hover.problem.grading_derivative)."""
    return (8.0 / 3.0) * math.pow(math.sin(math.pi * s), 4.0)


@_jit
def rhs_into(t, y, p, sign, data, out):  # pragma: no cover - compiled
    """The augmented hover field f(t, y, p) on a half-stroke of stroke sign ``sign`` into
    ``out``: eq. (2) with the blade-element loads, then z' (and x_e' with two trims);
    p = [Phi(, phi_bar)]."""
    n_cond = int(data[I_N_COND])
    amplitude = p[0]
    phi_bar = p[1] if n_cond == 2 else data[I_PHI_BAR]
    u, w, q, theta = y[0], y[1], y[2], y[3]
    X, Z, M = loads(t, u, w, q, sign, amplitude, phi_bar, data)
    m = data[I_MASS]
    # The generated planar equations (massless wings), and the wings' mass matrix if they have
    # mass; theta' and the earth-frame velocity are the same either way.
    rates = rigid_rates(u, w, q, theta, data[I_G])  # eq. (2) at zero load
    if data[I_INERTIA] != 0.0:
        acc = wing_accelerations(t, amplitude, phi_bar, u, w, q, theta, X, Z, M, data)
        out[0], out[1], out[2] = acc[0], acc[1], acc[2]
    else:
        out[0] = rates[0] + X / m
        out[1] = rates[1] + Z / m
        out[2] = rates[2] + M / data[I_IY]
    out[3] = rates[3]
    out[4] = rates[4]
    if n_cond == 2:
        out[5] = rates[5]


@_jit
def graded_into(s, y, p, k, sign, data, out):  # pragma: no cover - compiled
    """F(s, y, p) = dt/ds f(t(s), y, p) on half-stroke k (flapping.hover.problem._graded) into
    ``out``."""
    half = data[I_HALF]
    local = s - k
    rhs_into(half * (k + grading(local)), y, p, sign, data, out)
    factor = half * grading_derivative(local)
    for i in range(4 + int(data[I_N_COND])):
        out[i] = factor * out[i]


@_jit
def graded_rhs(s, y, p, k, sign, data):  # pragma: no cover - compiled
    """F(s, y, p) = dt/ds f(t(s), y, p) on half-stroke k (flapping.hover.problem._graded)."""
    out = np.empty(4 + int(data[I_N_COND]))
    graded_into(s, y, p, k, sign, data, out)
    return out


# =========================================================================== the period map
# The fixed-step period map of flapping.periodic._fixedmap.PeriodMap (its flow, _step, _split,
# _first_root, _root and _one_step) for the graded field above and the switching functions of
# flapping.hover.problem._switches, written out per trajectory: one call integrates a batch of
# trajectories over the whole period, so Python runs only Newton. Same steps, same stage
# arithmetic in the same order (sums over the stages as plain loops, where NumPy's matrix
# products may round differently), the same Illinois root search: the same map to rounding
# (tests/fast/test_blade.py compares the two).

#: The switching functions, in the order of flapping.hover.problem._switches: U = 0 at the root
#: (u - q h_w), U = 0 at the tip, and the pitch rate q.
N_SWITCHES = 3
_EPS = float(np.finfo(np.float64).eps)
_ROOT_ITERATIONS = 60  # as _fixedmap's


@_jit
def switch(i, s, y, p, k, data):  # pragma: no cover - compiled
    """Switching function i of half-stroke k at (s, y, p) (flapping.hover.problem._switches)."""
    h_w = data[I_H_W]
    if i == 0:
        return y[0] - y[2] * h_w
    if i == 2:
        return y[2]
    omega = data[I_OMEGA]
    t = data[I_HALF] * (k + grading(s - k))
    phi_bar = p[1] if int(data[I_N_COND]) == 2 else data[I_PHI_BAR]
    phi = phi_bar + p[0] * math.cos(omega * t)
    return (y[0] - y[2] * h_w) * math.cos(phi) - omega * p[0] * math.sin(omega * t) * data[I_R]


# :func:`_jit` with LLVM's ``contract`` flag: ``a * b + c`` may become one fused multiply-add.
# The stage sums then round as the Python map's NumPy matrix products do (BLAS kernels fuse
# them): measured on the hawkmoth's orbit, the two maps' central-difference multipliers differed
# by 1.6e-9 unfused, 1.0e-10 fused.
_jit_fused = _jit_policy.entry_point(_inertia_generated, _tableau, fastmath={"contract"})


@_jit_fused
def dop853_step(t, h, x, p, k, sign, data, K, y, out):  # pragma: no cover - compiled
    """One DOP853 step of the graded field of half-stroke k from (t, x) over h into ``out``
    (``K``: the stages, ``y``: a stage state; work arrays)."""
    d = x.size
    for st in range(N_STAGES):
        if st == 0:
            for c in range(d):
                y[c] = x[c]
        else:
            for c in range(d):
                acc = 0.0
                for i in range(st):
                    acc += RK_A[st, i] * K[i, c]
                y[c] = x[c] + h * acc
        graded_into(t + RK_C[st] * h, y, p, k, sign, data, K[st])
    for c in range(d):
        acc = 0.0
        for i in range(N_STAGES):
            acc += RK_B[i] * K[i, c]
        out[c] = x[c] + h * acc


@_jit
def switch_root(i, t, h, x, p, k, sign, data, g0, g1, K, y, tmp):  # pragma: no cover
    """(tau, evaluations): tau in (0, h) with switch i zero along the step (Illinois method)."""
    a, fa, b, fb = 0.0, g0, h, g1
    c, side, nfev = b, 0, 0
    for _ in range(_ROOT_ITERATIONS):
        c = (a * fb - b * fa) / (fb - fa)
        dop853_step(t, c, x, p, k, sign, data, K, y, tmp)
        nfev += N_STAGES
        fc = switch(i, t + c, tmp, p, k, data)
        if fc == 0.0:
            break
        if fc * fb > 0.0:  # c replaces b; a kept twice in a row: halve f(a) (Illinois)
            b, fb = c, fc
            if side == -1:
                fa = 0.5 * fa
            side = -1
        else:
            a, fa = c, fc
            if side == 1:
                fb = 0.5 * fb
            side = 1
        if b - a <= 4.0 * _EPS * (abs(t) + h):
            break
    return c, nfev


@_jit
def split_step(t, h, x, x_new, p, k, sign, data, K, y, tmp, done):  # pragma: no cover
    """The step from (t, x) over h, split at every root of a switching function in it: x_new
    (the unsplit step's end on entry) becomes the split step's end; x is overwritten. Returns
    the evaluations of the field."""
    for i in range(N_SWITCHES):
        done[i] = False
    nfev = 0
    while True:
        first, tau = -1, 0.0
        for i in range(N_SWITCHES):
            if done[i]:
                continue
            g0, g1 = switch(i, t, x, p, k, data), switch(i, t + h, x_new, p, k, data)
            if g0 * g1 < 0.0:
                root, used = switch_root(i, t, h, x, p, k, sign, data, g0, g1, K, y, tmp)
                nfev += used
                if first < 0 or root < tau:
                    first, tau = i, root
        if first < 0:
            return nfev
        done[first] = True  # crossed: its root at the split point is not crossed again
        dop853_step(t, tau, x, p, k, sign, data, K, y, tmp)
        for c in range(x.size):
            x[c] = tmp[c]
        t, h = t + tau, h - tau
        dop853_step(t, h, x, p, k, sign, data, K, y, x_new)
        nfev += 2 * N_STAGES


@_jit
def graded_flow(X, P, n, nodes, signs, data):  # pragma: no cover - compiled
    """(ends, evaluations, t): the end states of a batch of trajectories (rows of X, parameters
    the rows of P) over the segments between ``nodes`` (segment k: the field of half-stroke k
    with stroke sign signs[k]) at n steps each, split at the switching functions' roots; t is
    the end of the earliest step whose state became non-finite (inf if none), that
    trajectory's integration stopping there."""
    m, d = X.shape
    ends = np.empty((m, d))
    K = np.empty((N_STAGES, d))
    y, tmp, x, x_new = np.empty(d), np.empty(d), np.empty(d), np.empty(d)
    done = np.zeros(N_SWITCHES, dtype=np.bool_)
    nfev, failed_at = 0, math.inf
    for j in range(m):
        p = P[j]
        for c in range(d):
            x[c] = X[j, c]
        finite = True
        for k in range(nodes.size - 1):
            t0, sign = nodes[k], signs[k]
            h = (nodes[k + 1] - t0) / n
            for step in range(n):
                t = t0 + step * h
                dop853_step(t, h, x, p, k, sign, data, K, y, x_new)
                nfev += N_STAGES
                total = 0.0
                for c in range(d):
                    total += abs(x_new[c])
                if not math.isfinite(total):
                    failed_at = min(failed_at, t + h)
                    finite = False
                    break
                nfev += split_step(t, h, x, x_new, p, k, sign, data, K, y, tmp, done)
                for c in range(d):
                    x[c] = x_new[c]
            if not finite:
                break
        for c in range(d):
            ends[j, c] = x[c]
    return ends, nfev, failed_at

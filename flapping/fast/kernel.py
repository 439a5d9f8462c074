"""The compiled hover kernel: orbit, monodromy and multipliers of eq. (29)'s model in ~1 ms.

The same problem as :func:`flapping.hover.find_hover_orbit` with ``aerodynamics="linear"``:
unknowns (u0, w0, q0, theta0, Phi), equations x(T) = x(0) for (u, w, q, theta) and zero net
descent z(T) = z(0) = 0 over a period (the hover condition), alpha_m at the trim of eq. (40) for
the insect's nominal amplitude. It is solved differently:

- the right-hand side, the variational equations (the 5 x 4 state-transition matrix of the state
  augmented with z) and the sensitivity to the stroke amplitude are compiled with numba, the
  stability derivatives coming from code generated from the SymPy derivation
  (:func:`flapping.model.derivation.generate_numba_source`);
- each half-stroke is integrated with the 8th-order Dormand-Prince formula at a *fixed* step
  (restarted at stroke reversal, where the loads jump), so the residual is a smooth function of
  the unknowns and Newton's method converges quadratically to rounding level;
- the monodromy matrix (eqs. 42-49) is the state-transition matrix of the last Newton integration.

Error estimate and step count. With n steps per half-stroke the global error is O(n^-8). The
solve is repeated (one Newton correction and one variational integration) at n/2 steps: the
Richardson estimate of the error of the n-step answer is then the n/2-step correction divided by
2^8 - 1, times a safety factor 2 (at n/2 steps the error is not yet fully asymptotic), for Phi and
x0; for the multipliers it is the change of the eigenvalues when the monodromy is moved by its own
(safe) Richardson correction, which keeps the square-root sensitivity of a nearly coalescing pair.
If an estimate exceeds its tolerance (by default Phi to 1e-9 deg, every multiplier to 1e-8) the
step count grows by the predicted factor and the solve is repeated.

numba is imported the first time a kernel function runs (not when :mod:`flapping` is imported);
its compiled code is cached on disk (``cache=True``), so later processes load it in ~0.1 s.
"""

from __future__ import annotations

import importlib.util
import math
import time
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType

import numpy as np
from numpy.typing import ArrayLike

import flapping._validation as _validation
from flapping.errors import ConvergenceError
from flapping.fast import _generated
from flapping.model.aerodynamics import AeroConstants, aero_constants, trim_angle_of_attack
from flapping.model.kinematics import check_alpha_m, check_amplitude
from flapping.model.morphology import Insect

__all__ = [
    "AMPLITUDE_TOL_DEG",
    "MULTIPLIER_TOL",
    "DEFAULT_STEPS",
    "HoverSolution",
    "KernelProblem",
    "numba_available",
    "load",
    "solve_hover",
    "monodromy_at",
    "sample_orbit",
    "states_at",
]

#: Default accuracy of the stroke amplitude [deg] and of every Floquet multiplier (absolute).
AMPLITUDE_TOL_DEG = 1e-9
MULTIPLIER_TOL = 1e-8

#: Steps per half-stroke to start with (enough for the hawkmoth; the estimate adds more if needed).
DEFAULT_STEPS = 12

#: Bounds on the steps per half-stroke, and the number of step-count increases per solve.
_MIN_STEPS, _MAX_STEPS, _MAX_REFINEMENTS = 4, 1024, 6

#: Order of the Dormand-Prince formula, and the step ratio of the error estimate.
_ORDER, _COARSE = 8, 2

#: Safety factor on the Richardson estimate: at 4-6 steps per half-stroke (the coarse level of
#: a 8-12 step solve) the error is not yet fully asymptotic and the plain estimate can be low by
#: up to ~2 (measured at f = 20 Hz: 6.2e-10 deg estimated, 1.2e-9 deg actual).
_SAFETY = 2.0

#: Newton's stopping rule: every step below 1e-13 max(1, |z_i|) (the unknowns are then right to
#: rounding level: the convergence is quadratic), and its iteration cap.
_XTOL, _MAX_ITER = 1e-13, 40

_STATUS = {
    1: "Newton's method reached its iteration cap",
    2: "an iterate's stroke amplitude left (0, 90] deg",
    3: "the integration produced a non-finite value",
    4: "the Jacobian of the hover residual is singular",
}


def numba_available() -> bool:
    """True if numba can be imported (the ``fast`` extra), without importing it."""
    return importlib.util.find_spec("numba") is not None


_MODULE: list[ModuleType] = []


def load() -> ModuleType:
    """Import (and on first use in this environment, compile) the kernel's numba code.

    Returns
    -------
    module
        :mod:`flapping.fast._compiled`.

    Raises
    ------
    ImportError
        If numba is not installed (``pip install flapping[fast]``).
    """
    if not _MODULE:
        _drop_stale_cache()
        from flapping.fast import _compiled

        _MODULE.append(_compiled)
    return _MODULE[0]


def _drop_stale_cache(here: Path | None = None) -> None:
    """Remove numba's on-disk cache of :mod:`flapping.fast._compiled` if ``_generated`` changed.

    numba keys a cached function on the time stamp of its own file only, so the functions of
    ``_compiled`` that inline the generated derivatives would keep the old arithmetic (and the
    old layout of the constants) after a regeneration. A stamp of the generated source beside
    the cache (in ``__pycache__``, numba's default place) detects that. ``here`` is the package
    directory (default this module's; a test passes another).
    """
    import hashlib

    here = Path(__file__).parent if here is None else here
    cache = here / "__pycache__"
    digest = hashlib.sha256((here / "_generated.py").read_bytes()).hexdigest()
    stamp = cache / "_compiled.generated-sha256"
    try:
        if stamp.is_file() and stamp.read_text() == digest:
            return
        for old in list(cache.glob("_compiled.*.nbi")) + list(cache.glob("_compiled.*.nbc")):
            old.unlink()
        cache.mkdir(exist_ok=True)
        stamp.write_text(digest)
    except OSError:  # a read-only install: numba then caches elsewhere or not at all
        pass


def warm_up() -> float:
    """Run every compiled function once on the hawkmoth; returns the seconds it took.

    The first call in an environment compiles (seconds); later processes load the on-disk cache.
    """
    from flapping.model.morphology import hawkmoth

    start = time.perf_counter()
    problem = KernelProblem.of(hawkmoth())
    solve_hover(problem)
    sample_orbit(problem, np.zeros(4), problem.insect.stroke_amplitude, 8)
    return time.perf_counter() - start


# =========================================================================== the problem
@dataclass(frozen=True)
class KernelProblem:
    """An insect's constants packed for the kernel (build with :meth:`of`).

    Attributes
    ----------
    insect : Insect
    alpha_m : float
        Mean geometric angle of attack [rad] (fixed while Phi is solved for, as in the paper).
    k : ndarray
        The constants of the generated derivatives, laid out as
        :data:`flapping.fast._generated.CONSTANTS`.
    p : ndarray
        (g [m/s^2], 2 pi f [rad/s], 1/m [1/kg], 1/I_y [1/(kg m^2)]).
    """

    insect: Insect
    alpha_m: float
    k: np.ndarray
    p: np.ndarray

    @classmethod
    def of(cls, insect: Insect, alpha_m: float | None = None) -> KernelProblem:
        """Pack ``insect`` (and alpha_m, default the trim of eq. 40 at its nominal amplitude).

        Raises
        ------
        ValueError
            For a bad insect or alpha_m, an insect too heavy to trim (eq. 40), or a non-zero
            ``stroke_mean`` (the kernel's stroke is phi = Phi cos(2 pi f t): use the adaptive
            path).
        """
        _validation.instance("insect", insect, Insect)
        if insect.stroke_mean != 0.0:
            raise ValueError(
                f"the compiled kernel has no mean stroke angle: stroke_mean = "
                f"{insect.stroke_mean!r} rad must be 0 (use backend='adaptive')")
        if alpha_m is None:
            alpha_m = trim_angle_of_attack(insect, insect.stroke_amplitude)
        alpha_m = check_alpha_m(alpha_m)
        k = _pack(aero_constants(insect), alpha_m)
        p = np.array([insect.gravity, 2.0 * math.pi * insect.frequency, 1.0 / insect.mass,
                      1.0 / insect.pitch_inertia])
        return cls(insect, alpha_m, k, p)

    @property
    def period(self) -> float:
        """Flapping period T [s]."""
        return self.insect.period


def _pack(c: AeroConstants, alpha_m: float) -> np.ndarray:
    """The constants array of the generated derivatives (layout :data:`_generated.CONSTANTS`)."""
    values = {"FREQUENCY": c.f, "MASS": c.m, "PITCH_INERTIA": c.Iy, "K_NU": c.Knu,
              "MU1": c.mu1, "X_H": c.x_h, "H_W": c.h_w, "X_HAT": c.x_hat,
              "SIN_ALPHA_M": math.sin(alpha_m),
              "COS_ALPHA_M": math.cos(alpha_m), "SIN_2ALPHA_M": math.sin(2.0 * alpha_m)}
    for name in _generated.CONSTANTS:
        if name.startswith(("K_", "KROT_")) and name != "K_NU":
            table = c.Krot if name.startswith("KROT_") else c.K
            values[name] = table[(int(name[-2]), int(name[-1]))]
    return np.array([values[name] for name in _generated.CONSTANTS], dtype=float)


# =========================================================================== results
@dataclass(frozen=True)
class HoverSolution:
    """The hover orbit and its Floquet multipliers from the compiled kernel.

    Attributes
    ----------
    x0 : ndarray, shape (4,)
        (u, w, q, theta) at t = 0 [m/s, m/s, rad/s, rad].
    amplitude : float
        Stroke amplitude Phi [rad].
    alpha_m : float
        Mean geometric angle of attack [rad].
    period : float
        T [s].
    monodromy : ndarray, shape (4, 4)
        State-transition matrix over one period (eqs. 42-49).
    multipliers : ndarray, complex, shape (4,)
        Its eigenvalues, sorted by modulus (descending).
    trace_integral : float
        int_0^T trace J dt (Liouville: det M = exp of it).
    residual : ndarray, shape (5,)
        x(T) - x(0) for (u, w, q, theta, z) at the last Newton integration.
    nit : int
        Newton iterations in total (all step counts).
    nfev : int
        Evaluations of the right-hand side (variational, 31 states) in total.
    n_steps : int
        Steps per half-stroke of the answer.
    amplitude_error, x0_error, multiplier_error : float
        Estimated errors of Phi [rad], of x0 (max over components, SI) and of the multipliers
        (max absolute), from the comparison with n_steps / 2 (see the module notes).
    """

    x0: np.ndarray
    amplitude: float
    alpha_m: float
    period: float
    monodromy: np.ndarray
    multipliers: np.ndarray
    trace_integral: float
    residual: np.ndarray
    nit: int
    nfev: int
    n_steps: int
    amplitude_error: float
    x0_error: float
    multiplier_error: float

    @property
    def amplitude_deg(self) -> float:
        """Stroke amplitude [deg]."""
        return math.degrees(self.amplitude)

    @property
    def residual_norm(self) -> float:
        """Euclidean norm of :attr:`residual`."""
        return float(np.linalg.norm(self.residual))

    @property
    def z_drift(self) -> float:
        """Net descent over one period [m] (the hover residual: 0 to rounding)."""
        return float(self.residual[4])

    @property
    def det(self) -> float:
        """det of the monodromy."""
        return float(np.linalg.det(self.monodromy))

    @property
    def liouville_det(self) -> float:
        """exp(int_0^T trace J dt): equal to :attr:`det` by Liouville's formula."""
        return math.exp(self.trace_integral)

    @property
    def max_modulus(self) -> float:
        """Largest ``|multiplier|``."""
        return float(np.max(np.abs(self.multipliers)))

    @property
    def is_stable(self) -> bool:
        """True if every multiplier lies inside the unit circle."""
        return self.max_modulus < 1.0


def _sorted(values: np.ndarray) -> np.ndarray:
    """By descending modulus; in a complex-conjugate pair, positive imaginary part first."""
    values = np.asarray(values, dtype=complex)
    values = values[np.argsort(-np.abs(values), kind="stable")]
    for i in range(values.size - 1):
        a, b = values[i], values[i + 1]
        if a.imag < 0.0 and abs(a - np.conj(b)) <= 1e-12 * max(1.0, abs(a)):
            values[i], values[i + 1] = b, a
    return values


def _eigenvalue_shift(M: np.ndarray, dM: np.ndarray) -> float:
    """max over the eigenvalues of M of the distance to the nearest eigenvalue of M + dM."""
    a, b = np.linalg.eigvals(M), np.linalg.eigvals(M + dM)
    return float(max(np.min(np.abs(b - mu)) for mu in a))


# =========================================================================== solving
def _newton(kc: ModuleType, problem: KernelProblem, z: np.ndarray, n: int
            ) -> tuple[np.ndarray, int, np.ndarray]:
    """Newton at n steps per half-stroke; (variational state, iterations, residual)."""
    status, nit, norm, y = kc.newton(z, n, problem.k, problem.p, _MAX_ITER, _XTOL)
    if status != kc.CONVERGED:
        raise ConvergenceError(
            f"no hover orbit for {problem.insect.name} with the compiled kernel "
            f"({n} steps per half-stroke): {_STATUS[status]} (Phi = "
            f"{math.degrees(z[4]):.6g} deg)", x=z, residual=float(norm), iterations=int(nit))
    r, _ = kc.residual_and_jacobian(y, z)
    return y, int(nit), r


def _estimate(kc: ModuleType, problem: KernelProblem, z: np.ndarray, y: np.ndarray,
              n: int) -> tuple[np.ndarray, float]:
    """Richardson estimates: the error of z (5,) and the largest multiplier error at n steps."""
    z_at = z.copy()  # the point of the last integration: the variational state y belongs to it
    coarse = kc.variational_period(z_at, n // _COARSE, problem.k, problem.p)
    r_c, J_c = kc.residual_and_jacobian(coarse, z_at)
    r_f, _ = kc.residual_and_jacobian(y, z_at)
    factor = _SAFETY / (_COARSE**_ORDER - 1.0)
    dz = np.linalg.solve(J_c, -(r_c - r_f)) * factor
    M = _monodromy(y)
    dM = (M - _monodromy(coarse)) * factor
    return np.abs(dz), _eigenvalue_shift(M, dM)


def _monodromy(y: np.ndarray) -> np.ndarray:
    """The 4 x 4 state-transition matrix of (u, w, q, theta) in a variational state."""
    return np.array(y[5:21]).reshape(4, 4)


def _next_steps(n: int, ratio: float) -> int:
    """The step count predicted to bring an error ``ratio`` times its tolerance under it."""
    grow = max(1.25, 1.1 * ratio ** (1.0 / _ORDER))
    m = int(math.ceil(n * grow))
    return min(_MAX_STEPS, m + m % 2)


def solve_hover(
    problem: KernelProblem | Insect,
    *,
    amplitude_guess: float | None = None,
    x0_guess: ArrayLike | None = None,
    n_steps: int | None = None,
    amplitude_tol_deg: float = AMPLITUDE_TOL_DEG,
    multiplier_tol: float = MULTIPLIER_TOL,
) -> HoverSolution:
    """Hover orbit and Floquet multipliers of eq. (29)'s model with the compiled kernel.

    Parameters
    ----------
    problem : KernelProblem or Insect
        The insect (alpha_m at its trim, eq. 40), or a packed :class:`KernelProblem`.
    amplitude_guess : float, optional
        Initial Phi [rad]; default ``insect.stroke_amplitude``.
    x0_guess : sequence of 4 floats, optional
        Initial (u, w, q, theta); default zeros.
    n_steps : int, optional
        Steps per half-stroke to start with (even, >= 4; default :data:`DEFAULT_STEPS`). More
        are taken if the error estimate asks for them.
    amplitude_tol_deg, multiplier_tol : float
        Required accuracy of Phi [deg] and of every multiplier (absolute).

    Returns
    -------
    HoverSolution

    Raises
    ------
    ValueError
        For bad arguments.
    ConvergenceError
        If Newton's method fails (iteration cap, amplitude outside (0, 90] deg, non-finite
        values), or if the tolerances are not met with the largest step count.
    ImportError
        If numba is not installed.
    """
    if isinstance(problem, Insect):
        problem = KernelProblem.of(problem)
    problem = _validation.instance("problem", problem, KernelProblem)
    insect = problem.insect
    amp = check_amplitude(insect.stroke_amplitude if amplitude_guess is None else amplitude_guess,
                          "amplitude_guess")
    x0 = np.zeros(4) if x0_guess is None else _validation.vector("x0_guess", x0_guess, size=4)
    n = DEFAULT_STEPS if n_steps is None else _validation.integer(
        "n_steps", n_steps, low=_MIN_STEPS, high=_MAX_STEPS)
    n += n % 2
    tol_amp = math.radians(_validation.positive("amplitude_tol_deg", amplitude_tol_deg))
    tol_mu = _validation.positive("multiplier_tol", multiplier_tol)
    kc = load()
    z = np.append(x0, amp)
    total_nit = nfev = 0
    for _ in range(_MAX_REFINEMENTS + 1):
        y, nit, r = _newton(kc, problem, z, n)
        total_nit += nit
        nfev += nit * 2 * n * kc.N_STAGES + n * kc.N_STAGES
        z_at = z.copy()
        z_err, mu_err = _estimate(kc, problem, z_at, y, n)
        ratio = max(z_err[4] / tol_amp, mu_err / tol_mu)
        if ratio <= 1.0 or n >= _MAX_STEPS:
            break
        n = _next_steps(n, ratio)
    if ratio > 1.0:
        raise ConvergenceError(
            f"the compiled kernel could not meet the tolerances with {n} steps per half-stroke "
            f"(estimated errors: Phi {math.degrees(z_err[4]):.2e} deg, multipliers "
            f"{mu_err:.2e})", x=z, residual=float(np.linalg.norm(r)), iterations=total_nit)
    M = _monodromy(y)
    return HoverSolution(
        x0=z[:4].copy(), amplitude=float(z[4]), alpha_m=problem.alpha_m, period=problem.period,
        monodromy=M, multipliers=_sorted(np.linalg.eigvals(M)), trace_integral=float(y[30]),
        residual=r, nit=total_nit, nfev=nfev, n_steps=n, amplitude_error=float(z_err[4]),
        x0_error=float(z_err[:4].max()), multiplier_error=mu_err)


# =========================================================================== given orbits
def monodromy_at(
    problem: KernelProblem,
    x0: ArrayLike,
    amplitude: float,
    *,
    n_steps: int | None = None,
    multiplier_tol: float = MULTIPLIER_TOL,
) -> tuple[np.ndarray, float, float, int]:
    """Monodromy of the orbit from ``x0`` at ``amplitude`` (no solve), to ``multiplier_tol``.

    Parameters
    ----------
    problem : KernelProblem
    x0 : sequence of 4 floats
        (u, w, q, theta) at t = 0.
    amplitude : float
        Phi [rad].
    n_steps : int, optional
        Steps per half-stroke to start with (default :data:`DEFAULT_STEPS`).
    multiplier_tol : float
        Required accuracy of every multiplier.

    Returns
    -------
    monodromy : ndarray, shape (4, 4)
    trace_integral : float
        int_0^T trace J dt.
    multiplier_error : float
        Estimated error of the multipliers.
    n_steps : int
        Steps per half-stroke used.
    """
    problem = _validation.instance("problem", problem, KernelProblem)
    z = np.append(_validation.vector("x0", x0, size=4), check_amplitude(amplitude))
    tol = _validation.positive("multiplier_tol", multiplier_tol)
    n = DEFAULT_STEPS if n_steps is None else _validation.integer(
        "n_steps", n_steps, low=_MIN_STEPS, high=_MAX_STEPS)
    n += n % 2
    kc = load()
    while True:
        y = kc.variational_period(z, n, problem.k, problem.p)
        coarse = kc.variational_period(z, n // _COARSE, problem.k, problem.p)
        M = _monodromy(y)
        err = _eigenvalue_shift(M, (M - _monodromy(coarse)) * _SAFETY / (_COARSE**_ORDER - 1.0))
        if err <= tol or n >= _MAX_STEPS:
            return M, float(y[30]), err, n
        n = _next_steps(n, err / tol)


def sample_orbit(problem: KernelProblem, x0: ArrayLike, amplitude: float,
                 n_samples: int) -> tuple[np.ndarray, np.ndarray, float]:
    """One period from x0 sampled at ``n_samples + 1`` uniform times (one RK step apart).

    Parameters
    ----------
    problem : KernelProblem
    x0 : sequence of 4 floats
        (u, w, q, theta) at t = 0.
    amplitude : float
        Phi [rad].
    n_samples : int
        Even number >= 2 of steps per period (n_samples / 2 per half-stroke).

    Returns
    -------
    t : ndarray, shape (n_samples + 1,)
    x : ndarray, shape (4, n_samples + 1)
        Time along the last axis.
    z_drift : float
        Net descent over the period [m].
    """
    problem = _validation.instance("problem", problem, KernelProblem)
    n = _validation.integer("n_samples", n_samples, low=2)
    if n % 2:
        raise ValueError(f"`n_samples` must be an even integer >= 2; got {n_samples!r}")
    x = _validation.vector("x0", x0, size=4)
    samples = load().sample_period(x, check_amplitude(amplitude), n // 2, problem.k, problem.p)
    t = np.linspace(0.0, problem.period, n + 1)
    return t, np.ascontiguousarray(samples[:, :4].T), float(samples[-1, 4])


def states_at(problem: KernelProblem, x0: ArrayLike, amplitude: float, times: ArrayLike,
              n_steps: int = 64) -> np.ndarray:
    """The orbit from x0 at given times of the first period (for quadratures along the orbit).

    Each time is reached from the step grid (``n_steps`` per half-stroke) by one shorter step of
    the same formula, so every value has the grid's accuracy (~1e-15 at the default 64 steps
    for the hawkmoth).

    Parameters
    ----------
    problem : KernelProblem
    x0 : array_like, shape (4,)
        (u, w, q, theta) at t = 0.
    amplitude : float
        Phi [rad].
    times : array_like
        Times in [0, T], none at stroke reversal T/2 (the half-stroke of such a time is ambiguous).
    n_steps : int
        Steps per half-stroke.

    Returns
    -------
    ndarray, shape (4, len(times))
        Time along the last axis.
    """
    problem = _validation.instance("problem", problem, KernelProblem)
    t = _validation.array("times", times).ravel()
    if t.size and (t.min() < 0.0 or t.max() > problem.period):
        raise ValueError(f"`times` must lie in [0, T] = [0, {problem.period:g}] s")
    n = _validation.integer("n_steps", n_steps, low=1, high=_MAX_STEPS)
    x = _validation.vector("x0", x0, size=4)
    out = load().states_at(x, check_amplitude(amplitude), n, problem.k, problem.p, t)
    return np.ascontiguousarray(out[:, :4].T)

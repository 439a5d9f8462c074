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

Smallest tolerances. The unknowns come out of Newton's method right to rounding level, not
better: :data:`AMPLITUDE_TOL_FLOOR_DEG` and :data:`MULTIPLIER_TOL_FLOOR` are the smallest
tolerances accepted (see their notes); a smaller one is a ValueError, since an error estimate
below the rounding noise is itself noise and the claim "tolerance met" would be false.

Compilation and its cache. numba is imported the first time a kernel function runs (never when
:mod:`flapping` is imported), and every numba module of :mod:`flapping.fast` is compiled by one
policy (:mod:`flapping.fast._jit`): ``numba.njit(cache=True)``, the machine code cached on disk
where numba puts it: the directory named by ``NUMBA_CACHE_DIR`` if set, else ``__pycache__``
beside this package if it is writable, else numba's user-wide cache directory
(``$XDG_CACHE_HOME/numba`` or ``~/.cache/numba`` on Linux), which is where an installed wheel in
a read-only ``site-packages`` caches. If no place is writable the kernel still runs, compiled
again in every process. Each entry point is compiled (or loaded, ~0.1 s) on its first call:
with an empty cache the orbit and its multipliers compile in the process in 5-10 s of CPU, said
once by a :class:`KernelCompileWarning` before and logged on the ``"flapping"`` logger after.
:func:`flapping.fast.warm_up` (``python -m flapping compile``) compiles everything ahead, for
installs, clusters and CI.

The environment variable ``FLAPPING_FIRST_CALL`` chooses: ``compiled`` (the default, as above) or
``uncompiled``: an entry point whose machine code is not in numba's cache runs the same functions
as plain Python (:mod:`flapping.fast._uncompiled`: the same arithmetic and the same LAPACK
routines, equal to the compiled results bit for bit; the default orbit and multipliers in
~0.2 s), said once by a :class:`KernelCompileWarning`, and nothing is compiled or started; the
result says which path answered (:attr:`HoverSolution.compiled`). With ``NUMBA_DISABLE_JIT=1``
every call runs uncompiled.
"""

from __future__ import annotations

import dataclasses
import functools
import importlib.util
import logging
import math
import time
import warnings
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType, ModuleType
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

import flapping._validation as _validation
from flapping.backends import Compiled
from flapping.errors import ConvergenceError
from flapping.fast import _generated, _jit
from flapping.fast._jit import KernelCompileWarning
from flapping.model.aerodynamics import AeroConstants, aero_constants, trim_angle_of_attack
from flapping.model.kinematics import check_alpha_m, check_amplitude
from flapping.model.morphology import Insect
from flapping.results import Status

__all__ = [
    "AMPLITUDE_TOL_DEG",
    "MULTIPLIER_TOL",
    "AMPLITUDE_TOL_FLOOR_DEG",
    "MULTIPLIER_TOL_FLOOR",
    "DEFAULT_STEPS",
    "SUPPORTED_FIELDS",
    "unsupported_field",
    "HoverSolution",
    "KernelCompileWarning",
    "KernelProblem",
    "OrbitQuadrature",
    "cache_dir",
    "first_call_mode",
    "numba_available",
    "run_reporting",
    "load",
    "run",
    "solve_hover",
    "monodromy_at",
    "orbit_quadrature",
    "sample_orbit",
    "states_at",
]

#: Default accuracy of the stroke amplitude [deg] and of every Floquet multiplier (absolute).
AMPLITUDE_TOL_DEG: float = Compiled.amplitude_tol_deg
MULTIPLIER_TOL: float = Compiled.multiplier_tol

#: Smallest accepted ``amplitude_tol_deg`` [deg]. Newton stops when its next step is below
#: _XTOL = 1e-13 max(1, abs(Phi)) rad (the step is then rounding noise: the residual's rounding,
#: ~1e-16 of the states, times the inverse Jacobian), so the solve can promise that bound at
#: Phi <= pi/2, 1.6e-13 rad = 9e-12 deg, rounded up. Measured (hawkmoth, 20-32 Hz, h_w 0-5 mm):
#: Phi solved at 32 to 256 steps per half-stroke, where discretisation errors are < 1e-15 deg,
#: scatters by up to 7e-13 deg, and the Richardson estimate there is that noise (~1e-12 deg).
AMPLITUDE_TOL_FLOOR_DEG = 1e-11

#: Smallest accepted ``multiplier_tol``. The monodromy sums ~10^3 RK stage terms with entries
#: of order 1, so its rounding error is ~1e-13, and the Richardson estimate (a difference of two
#: such matrices) is noise at that level. Measured as above: the multipliers scatter by up to
#: 8e-14 and the estimate at 32 steps reads ~1.7e-13; the floor keeps a factor ~6 above it.
MULTIPLIER_TOL_FLOOR = 1e-12

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

#: Newton's stopping rule: every step below 1e-13 max(1, abs(z_i)) (the unknowns are then right to
#: rounding level: the convergence is quadratic), and its iteration cap.
_XTOL, _MAX_ITER = 1e-13, 40

#: Quadrature along the orbit: Gauss nodes per half-stroke at most (a cap on the work), and the
#: fewest steps per half-stroke that carry the state between nodes. At 32 steps the formula's
#: error is (12/32)^8 ~ 4e-4 of the 12-step solve's (~1e-11 relative): rounding level.
_MAX_NODES, _QUADRATURE_STEPS = 1 << 16, 32

#: Samples per period of :func:`sample_orbit` at most (a cap on the work and the memory).
_MAX_SAMPLES = 2**20

# The compiled code's outcome codes are the values of the package's one status table
# (flapping.results.Status; a test holds them equal): the wrapper reads them as Status(code).

#: The :class:`~flapping.model.morphology.Insect` fields the kernel follows, and how each enters.
#: :meth:`KernelProblem.of` refuses an insect whose other fields differ from their defaults, so
#: a field added to ``Insect`` (say a wing mass) is refused until the kernel models it and is
#: listed here.
SUPPORTED_FIELDS: Mapping[str, str] = MappingProxyType({
    "name": "label only",
    "semi_span": "R of the span integrals I_mn (K, Krot, K_nu)",
    "wing_area": "S of the span integrals and of the aspect ratio in eq. (4)",
    "r1": "the beta chord distribution of the span integrals",
    "r2": "the beta chord distribution of the span integrals",
    "frequency": "omega = 2 pi f of eq. (39), the period and the rotational damping",
    "stroke_amplitude": "the first guess of Phi and the trim of alpha_m (eq. 40)",
    "mass": "1/m of eq. (2) and the trim",
    "pitch_inertia": "1/I_y of eq. (2)",
    "air_density": "rho of K, Krot and K_nu",
    "gravity": "g of eq. (2) and the trim",
    "a0": "the 2-D lift slope in A of eq. (4)",
    "aspect_ratio_convention": "the aspect ratio in A of eq. (4)",
    "pitch_axis": "3/4 - x0_hat of the rotational circulation (eq. 5, Krot)",
    "center_of_pressure": "x_hat of the moments (eqs. 21-23)",
    "hinge_offset": "x_h of the moments",
    "mu1": "the rotational damping of M_q (mu1 f K_nu)",
    "mu2": "none: eq. (29)'s loads have no mu2 term (as on the adaptive linear path)",
    "hinge_height": "h_w terms of the generated derivatives",
    "roll_inertia": "none: the planar model has no roll (six degrees of freedom only)",
    "yaw_inertia": "none: the planar model has no yaw (six degrees of freedom only)",
    "roll_yaw_product": "none: the planar model has no roll or yaw",
})

_LOG = logging.getLogger("flapping")


@functools.lru_cache(maxsize=1)
def numba_available() -> bool:
    """True if numba can be imported (the ``fast`` extra), without importing it (looked up once
    per process: every solve asks)."""
    return importlib.util.find_spec("numba") is not None


_MODULE: list[ModuleType] = []

#: The entry points of :mod:`flapping.fast._compiled` called compiled in this process (their
#: later calls skip the first call's checks).
_READY: set[str] = set()
_NOTED: list[bool] = []


def load() -> ModuleType:
    """Import the kernel's numba code, once per process; nothing is compiled here.

    Each entry point of :mod:`flapping.fast._compiled` is compiled (or loaded from numba's
    cache) on its first call (see :func:`run`), so a call compiles only what it uses: the orbit
    and its multipliers (:func:`solve_hover`, the default path) compile ``newton_and_estimate``
    and what it calls (5-7 s of CPU with an empty cache, measured on a busy 2-core machine;
    ~0.1 s to load from numba's cache); the sampled orbit, the quadrature along it and
    :func:`monodromy_at` compile their own on first use.

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
        from flapping.fast import _compiled

        _MODULE.append(_compiled)
    return _MODULE[0]


#: How :attr:`HoverSolution.path` names the uncompiled first call.
UNCOMPILED_PATH = "compiled kernel's Python code, uncompiled (FLAPPING_FIRST_CALL=uncompiled)"

#: The values of ``FLAPPING_FIRST_CALL`` (see :mod:`flapping.fast._jit`).
FIRST_CALL_MODES = _jit.FIRST_CALL_MODES


def first_call_mode() -> str:
    """How a first call runs: ``FLAPPING_FIRST_CALL`` (:func:`flapping.fast._jit.first_call_mode`:
    ``compiled``, the default, or ``uncompiled``).

    Raises
    ------
    ValueError
        If the variable holds another value than :data:`FIRST_CALL_MODES`.
    """
    return _jit.first_call_mode()


def run(kc: ModuleType, name: str, *args: Any) -> Any:
    """Call the entry point ``name`` of ``kc`` (:func:`load`) with ``args``.

    Compiled (or loaded from numba's cache), unless ``FLAPPING_FIRST_CALL=uncompiled`` and the
    cache holds no machine code of it (see the module notes and :func:`run_reporting`, which
    also says which path answered).
    """
    return run_reporting(kc, name, *args)[0]


def run_reporting(kc: ModuleType, name: str, *args: Any) -> tuple[Any, bool]:
    """:func:`run`, and whether the compiled code answered (False: the uncompiled Python).

    ``FLAPPING_FIRST_CALL`` is checked on every call. With ``uncompiled``, an entry point whose
    machine code numba's cache does not hold runs its Python code (the same numbers, bit for
    bit; nothing is compiled or started), said once per process by a
    :class:`KernelCompileWarning`. Otherwise numba loads it from the cache, or compiles it in
    this process (:mod:`flapping.fast._jit` says so).
    """
    mode = first_call_mode()  # checked on every call: a bad value is refused by each alike
    fn = getattr(kc, name)
    if name in _READY:
        return fn(*args), True
    from flapping.fast import _uncompiled  # the first calls only

    if _jit_disabled():  # njit returned the Python functions, which Python cannot run as they are
        return _uncompiled.entry(kc, name)(*args), False
    if mode == "uncompiled" and not _jit.ready(fn):
        return _run_uncompiled(kc, name, args), False
    out = fn(*args)
    _READY.add(name)
    return out, True


def _jit_disabled() -> bool:
    """Whether numba's JIT is off (``NUMBA_DISABLE_JIT``; numba is imported by :func:`load`)."""
    from numba.core import config

    return bool(getattr(config, "DISABLE_JIT", False))


def _run_uncompiled(kc: ModuleType, name: str, args: tuple[Any, ...]) -> Any:
    """The entry point's Python code on ``args``, said once per process."""
    from flapping.fast import _uncompiled

    start = time.perf_counter()
    out = _uncompiled.entry(kc, name)(*args)
    seconds = time.perf_counter() - start
    _LOG.info("hover kernel (%s) ran uncompiled in %.2f s (FLAPPING_FIRST_CALL=uncompiled)",
              name, seconds)
    if not _NOTED:
        _NOTED.append(True)
        warnings.warn(f"flapping's hover kernel is not in numba's cache here: with "
                      f"FLAPPING_FIRST_CALL=uncompiled it runs its Python code uncompiled (the "
                      f"same arithmetic, {seconds:.2f} s for this call); `python -m flapping "
                      f"compile` compiles it into the cache once", KernelCompileWarning,
                      stacklevel=5)
    return out


def cache_dir(compiled: ModuleType | None = None) -> Path | None:
    """The directory of numba's on-disk cache of the kernel, or None if it is not cached.

    Parameters
    ----------
    compiled : module, optional
        :mod:`flapping.fast._compiled` (default: :func:`load` it).

    Returns
    -------
    pathlib.Path or None
        Where numba chose to cache (see the module notes); None if no place was writable.
    """
    compiled = load() if compiled is None else compiled
    return _jit.cache_dir(compiled.newton_and_estimate)


def warm_up() -> float:
    """Run every compiled entry point once on the hawkmoth, compiled; returns the seconds it took.

    The first call in an environment compiles (seconds); later processes load the on-disk cache.
    :func:`flapping.fast.warm_up` runs it with the other fast modules'.
    """
    from flapping.model.morphology import hawkmoth

    start = time.perf_counter()
    with _jit.forced("compiled"):
        problem = KernelProblem.of(hawkmoth())
        sol = solve_hover(problem)
        orbit_quadrature(problem, sol.x0, sol.amplitude)
        monodromy_at(problem, sol.x0, sol.amplitude)
        states_at(problem, sol.x0, sol.amplitude, [0.25 * problem.period])  # and the samples
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
        :data:`flapping.fast._generated.CONSTANTS` (read-only).
    p : ndarray
        (g [m/s^2], 2 pi f [rad/s], 1/m [1/kg], 1/I_y [1/(kg m^2)]) (read-only).
    """

    insect: Insect
    alpha_m: float
    k: np.ndarray
    p: np.ndarray

    @classmethod
    def of(cls, insect: Insect, alpha_m: float | None = None) -> KernelProblem:
        """Pack ``insect`` (and alpha_m, default the trim of eq. 40 at its nominal amplitude).

        Packing is cached per (insect, alpha_m) (``Insect`` is a frozen, hashable dataclass):
        asking again for the same insect returns the same problem at no cost.

        Raises
        ------
        ValueError
            For a bad insect or alpha_m, an insect too heavy to trim (eq. 40), or an insect
            whose fields outside :data:`SUPPORTED_FIELDS` differ from their defaults (today
            ``stroke_mean``: the kernel's stroke is phi = Phi cos(2 pi f t); use the adaptive
            path).
        """
        _validation.instance("insect", insect, Insect)
        return _packed(insect, None if alpha_m is None else check_alpha_m(alpha_m))

    @property
    def period(self) -> float:
        """Flapping period T [s]."""
        return self.insect.period


@functools.lru_cache(maxsize=256)
def _packed(insect: Insect, alpha_m: float | None) -> KernelProblem:
    """:meth:`KernelProblem.of` on validated arguments (cached)."""
    _check_supported(insect)
    if alpha_m is None:
        alpha_m = check_alpha_m(trim_angle_of_attack(insect, insect.stroke_amplitude))
    k = _pack(aero_constants(insect), alpha_m)
    p = np.array([insect.gravity, 2.0 * math.pi * insect.frequency, 1.0 / insect.mass,
                  1.0 / insect.pitch_inertia])
    return KernelProblem(insect, alpha_m, _read_only(k), _read_only(p))


def unsupported_field(insect: Insect) -> str:
    """Why the kernel cannot model this insect: its first field outside :data:`SUPPORTED_FIELDS`
    that is not at its default, in words ('' if there is none)."""
    cls: Any = type(insect)  # a dataclass type is hashable (mypy reads Insect.__hash__)
    for name, default in _unsupported_fields(cls, tuple(SUPPORTED_FIELDS)):
        value = getattr(insect, name)
        if default is dataclasses.MISSING or value != default:
            shown = "" if default is dataclasses.MISSING else f" (its default {default!r})"
            return (f"the compiled kernel does not model the insect field `{name}` = "
                    f"{value!r}: it supports the default only{shown}")
    return ""


@functools.lru_cache(maxsize=16)
def _unsupported_fields(cls: type, supported: tuple[str, ...]) -> tuple[tuple[str, object], ...]:
    """The init fields of an ``Insect`` class outside ``supported`` and their defaults, in field
    order (listed once per class: a sweep asks at every point)."""
    return tuple((f.name, f.default) for f in dataclasses.fields(cls)
                 if f.init and f.name not in supported)


def _check_supported(insect: Insect) -> None:
    """Refuse an insect whose fields outside :data:`SUPPORTED_FIELDS` are not at their defaults."""
    why_not = unsupported_field(insect)
    if why_not:
        raise ValueError(f"{why_not}; use backend='adaptive'")


def _read_only(a: np.ndarray) -> np.ndarray:
    a.flags.writeable = False
    return a


def _pack(c: AeroConstants, alpha_m: float) -> np.ndarray:
    """The constants array of the generated derivatives (layout :data:`_generated.CONSTANTS`)."""
    trig = {"SIN_ALPHA_M": math.sin(alpha_m), "COS_ALPHA_M": math.cos(alpha_m),
            "SIN_2ALPHA_M": math.sin(2.0 * alpha_m)}
    return np.array([trig[name] if attr is None else
                     getattr(c, attr) if key is None else getattr(c, attr)[key]
                     for name, attr, key in _LAYOUT], dtype=float)


def _source(name: str) -> tuple[str, str | None, tuple[int, int] | None]:
    """Where constant ``name`` of the layout comes from: (name, AeroConstants attribute or None
    for a function of alpha_m, key of the K or Krot table or None)."""
    plain = {"FREQUENCY": "f", "MASS": "m", "PITCH_INERTIA": "Iy", "K_NU": "Knu", "MU1": "mu1",
             "X_H": "x_h", "H_W": "h_w", "X_HAT": "x_hat"}
    if name in plain:
        return name, plain[name], None
    if name.startswith(("K_", "KROT_")):
        return name, "Krot" if name.startswith("KROT_") else "K", (int(name[-2]), int(name[-1]))
    return name, None, None


#: The layout of :data:`_generated.CONSTANTS`, resolved once (a sweep packs every point).
_LAYOUT = tuple(_source(name) for name in _generated.CONSTANTS)


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
        Evaluations of the right-hand side (variational, 32 states) in total.
    n_steps : int
        Steps per half-stroke of the answer.
    amplitude_error, x0_error, multiplier_error : float
        Estimated errors of Phi [rad], of x0 (max over components, SI) and of the multipliers
        (max absolute), from the comparison with n_steps / 2 (see the module notes). Estimates,
        not bounds: the coarse level (6 steps per half-stroke for a 12-step answer) is not yet
        asymptotic. Measured against solves at 256 steps (hawkmoth 20-32 Hz, hinge heights
        0-5 mm, the six presets; 30 points): Phi's error exceeded its estimate at 5 points, by
        up to 5.1x, yet stayed under the default tolerance everywhere (worst 7.2e-10 deg against
        1e-9 deg); the multipliers' estimate exceeded their error at every point (worst
        2.4e-10). For a guaranteed bound, compare with a solve at more steps (``n_steps``).
    mean_velocity : ndarray, shape (2,)
        Cycle means (forward, climb) [m/s] of the inertial velocity along the orbit, from the
        last Newton integration: x_e(T) / T and -z(T) / T. Read-only.
    compiled : bool
        True if numba's compiled code answered every call of the solve; False if a call ran
        the kernel's Python code uncompiled (``FLAPPING_FIRST_CALL=uncompiled`` and numba's
        cache without it, see the module notes), whose numbers are the same to the last bit.
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
    mean_velocity: np.ndarray
    compiled: bool = True

    @property
    def path(self) -> str:
        """Which code answered, in words: ``"compiled"``, or ``UNCOMPILED_PATH`` (the kernel's
        Python code, uncompiled: ``FLAPPING_FIRST_CALL=uncompiled`` with a cold cache)."""
        return "compiled" if self.compiled else UNCOMPILED_PATH

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
    # On Python complex numbers: for four values a third of the cost of NumPy's argsort and
    # indexing, with the same order (a stable sort by modulus, as a stable argsort of -abs).
    vals = [complex(v) for v in np.asarray(values).ravel().tolist()]
    vals.sort(key=abs, reverse=True)
    if any(v.imag < 0.0 for v in vals):  # else no pair to reorder
        for i in range(len(vals) - 1):
            a, b = vals[i], vals[i + 1]
            if a.imag < 0.0 and abs(a - b.conjugate()) <= 1e-12 * max(1.0, abs(a)):
                vals[i], vals[i + 1] = b, a
    return np.array(vals, dtype=complex)


def _shift(eigenvalues: np.ndarray, moved: np.ndarray) -> float:
    """max over ``eigenvalues`` of the distance to the nearest of ``moved``.

    On Python complex numbers: NumPy's broadcast costs more than the arithmetic on 4 x 4 values
    (the distances are then libm's hypot, NumPy's within an ulp).
    """
    moved_list = moved.tolist()
    return float(max(min(abs(m - e) for m in moved_list) for e in eigenvalues.tolist()))


def _eigenvalue_shift(eigenvalues: np.ndarray, M: np.ndarray, dM: np.ndarray) -> float:
    """max over the eigenvalues of M of the distance to the nearest eigenvalue of M + dM."""
    return _shift(np.asarray(eigenvalues, dtype=complex),
                  np.asarray(np.linalg.eigvals(M + dM), dtype=complex))


def _read_only_array(a: np.ndarray) -> np.ndarray:
    """A read-only copy of ``a`` (results are read-only: an analysis is of what was solved)."""
    return _read_only(np.array(a))


# =========================================================================== argument checks
def _problem(problem: KernelProblem | Insect) -> KernelProblem:
    if isinstance(problem, Insect):
        return KernelProblem.of(problem)
    return _validation.instance("problem", problem, KernelProblem)


def _steps(n_steps: int | None) -> int:
    """The starting steps per half-stroke: even, in [_MIN_STEPS, _MAX_STEPS]."""
    if n_steps is None:
        return DEFAULT_STEPS
    n = _validation.integer("n_steps", n_steps, low=_MIN_STEPS, high=_MAX_STEPS)
    return n + n % 2


def _tolerance(name: str, value: float, floor: float, unit: str = "") -> float:
    """A tolerance >= its floor (the float64 limit of the fixed-step solve), as a float."""
    return _validation.real(name, value, low=floor, unit=unit)


def _amplitude_tol(value: float) -> float:
    """``amplitude_tol_deg`` checked against its floor, in radians."""
    if value is AMPLITUDE_TOL_DEG:  # the default: checked once, at import
        return _AMPLITUDE_TOL_RAD
    return math.radians(_tolerance("amplitude_tol_deg", value, AMPLITUDE_TOL_FLOOR_DEG, "deg"))


def _multiplier_tol(value: float) -> float:
    """``multiplier_tol`` checked against its floor."""
    return value if value is MULTIPLIER_TOL else _tolerance("multiplier_tol", value,
                                                               MULTIPLIER_TOL_FLOOR)


_AMPLITUDE_TOL_RAD = math.radians(AMPLITUDE_TOL_DEG)


# =========================================================================== solving
#: Richardson's factor: the n/2-step correction over 2^8 - 1, with the safety factor.
_FACTOR = _SAFETY / (_COARSE**_ORDER - 1.0)


def _newton_and_estimate(kc: ModuleType, problem: KernelProblem, z: np.ndarray, n: int
                         ) -> tuple[np.ndarray, int, np.ndarray, np.ndarray, float, np.ndarray,
                                    bool]:
    """Newton at n steps per half-stroke from z (in place), and the Richardson estimates.

    One compiled call: Newton's integrations, the n/2-step integration at the answer, and the
    eigenvalues of the monodromy and of its Richardson-moved copy. Returns the variational
    state, the iterations, the residual, the estimated error of z (5,), the largest multiplier
    error, the multipliers (sorted as :func:`_sorted`) and whether the compiled code ran.
    """
    (status, nit, norm, y, r, z_err, multipliers, shift, eigen), compiled = run_reporting(
        kc, "newton_and_estimate", z, n, problem.k, problem.p, _MAX_ITER, _XTOL, _FACTOR)
    if status != kc.CONVERGED:
        raise ConvergenceError(
            f"no hover orbit for {problem.insect.name} with the compiled kernel "
            f"({n} steps per half-stroke): {Status(status).message} (Phi = "
            f"{math.degrees(z[4]):.6g} deg)", x=z, residual=float(norm), iterations=int(nit),
            status=Status(status))
    if eigen != kc.EIGEN_OK:  # the messages of np.linalg.eigvals
        raise np.linalg.LinAlgError("Array must not contain infs or NaNs"
                                    if eigen == kc.EIGEN_NOT_FINITE else
                                    "Eigenvalues did not converge")
    return y, int(nit), r, z_err, float(shift), multipliers, compiled


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
    amplitude_tol_deg : float
        Required accuracy of Phi [deg], >= :data:`AMPLITUDE_TOL_FLOOR_DEG`.
    multiplier_tol : float
        Required accuracy of every multiplier (absolute), >= :data:`MULTIPLIER_TOL_FLOOR`.

    Returns
    -------
    HoverSolution

    Raises
    ------
    ValueError
        For bad arguments, tolerances below their floors included (the message names the
        argument and the accepted range).
    ConvergenceError
        If Newton's method fails (iteration cap, amplitude outside (0, 90] deg, non-finite
        values), or if the tolerances are not met with the largest step count.
    ImportError
        If numba is not installed.
    """
    problem = _problem(problem)
    amp = (problem.insect.stroke_amplitude if amplitude_guess is None
           else check_amplitude(amplitude_guess, "amplitude_guess"))
    x0 = np.zeros(4) if x0_guess is None else _validation.vector("x0_guess", x0_guess, size=4)
    return solve_checked(problem, np.append(x0, amp),
                         *checked_options(n_steps, amplitude_tol_deg, multiplier_tol))


def checked_options(n_steps: int | None = None, amplitude_tol_deg: float = AMPLITUDE_TOL_DEG,
                    multiplier_tol: float = MULTIPLIER_TOL) -> tuple[int, float, float]:
    """:func:`solve_hover`'s options checked: (steps per half-stroke, Phi tolerance [rad],
    multiplier tolerance).

    Raises
    ------
    ValueError
        As :func:`solve_hover`.
    """
    return _steps(n_steps), _amplitude_tol(amplitude_tol_deg), _multiplier_tol(multiplier_tol)


def solve_checked(problem: KernelProblem, z: np.ndarray, n: int, tol_amp: float,
                  tol_mu: float) -> HoverSolution:
    """:func:`solve_hover` from a checked start ``z = (x0, Phi)`` (a float array it may modify)
    and :func:`checked_options`: for callers that have validated them already (the hover layer
    checks its guesses once)."""
    return _solve(load(), problem, z, n, tol_amp, tol_mu)


def _solve(kc: ModuleType, problem: KernelProblem, z: np.ndarray, n: int, tol_amp: float,
           tol_mu: float) -> HoverSolution:
    """:func:`solve_hover` on checked arguments, from z = (x0, Phi) (modified in place)."""
    total_nit = nfev = 0
    compiled = True
    for _ in range(_MAX_REFINEMENTS + 1):
        y, nit, r, z_err, mu_err, eigenvalues, ran_compiled = _newton_and_estimate(kc, problem,
                                                                                   z, n)
        compiled = compiled and ran_compiled
        total_nit += nit
        nfev += nit * 2 * n * kc.N_STAGES + n * kc.N_STAGES
        ratio = max(z_err[4] / tol_amp, mu_err / tol_mu)
        if ratio <= 1.0 or n >= _MAX_STEPS:
            break
        n = _next_steps(n, ratio)
    if ratio > 1.0:
        raise ConvergenceError(
            f"the compiled kernel could not meet the tolerances with {n} steps per half-stroke "
            f"(estimated errors: Phi {math.degrees(z_err[4]):.2e} deg, multipliers "
            f"{mu_err:.2e})", x=z, residual=float(np.linalg.norm(r)), iterations=total_nit,
            status=Status.TOLERANCE_NOT_MET)
    period = problem.period
    return HoverSolution(
        x0=_read_only(z[:4].copy()), amplitude=float(z[4]), alpha_m=problem.alpha_m,
        period=period, monodromy=_read_only(_monodromy(y)),
        multipliers=_read_only(eigenvalues), trace_integral=float(y[30]),
        residual=_read_only(r), nit=total_nit, nfev=nfev, n_steps=n,
        amplitude_error=float(z_err[4]), x0_error=float(z_err[:4].max()), multiplier_error=mu_err,
        mean_velocity=_read_only(np.array([y[31], -y[4]]) / period), compiled=compiled)


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
        Required accuracy of every multiplier, >= :data:`MULTIPLIER_TOL_FLOOR`.

    Returns
    -------
    monodromy : ndarray, shape (4, 4)
        Read-only.
    trace_integral : float
        int_0^T trace J dt.
    multiplier_error : float
        Estimated error of the multipliers.
    n_steps : int
        Steps per half-stroke used.

    Raises
    ------
    ValueError
        For bad arguments.
    ConvergenceError
        If the estimate exceeds ``multiplier_tol`` at the largest step count.
    """
    problem = _validation.instance("problem", problem, KernelProblem)
    z = np.append(_validation.vector("x0", x0, size=4), check_amplitude(amplitude))
    tol = _multiplier_tol(multiplier_tol)
    n = _steps(n_steps)
    kc = load()
    while True:
        y = run(kc, "variational_period", z, n, problem.k, problem.p)
        coarse = run(kc, "variational_period", z, n // _COARSE, problem.k, problem.p)
        M = _monodromy(y)
        err = _eigenvalue_shift(np.linalg.eigvals(M), M, (M - _monodromy(coarse)) * _FACTOR)
        if err <= tol:
            return _read_only(M), float(y[30]), err, n
        if n >= _MAX_STEPS:
            raise ConvergenceError(
                f"the compiled kernel could not integrate the monodromy to multiplier_tol = "
                f"{tol:g} with {n} steps per half-stroke (estimated error {err:.2e})", x=z,
                status=Status.TOLERANCE_NOT_MET)
        n = _next_steps(n, err / tol)


@dataclass(frozen=True)
class OrbitQuadrature:
    """Cycle means along an orbit of the kernel (Gauss-Legendre on each half-stroke).

    Attributes
    ----------
    averaged_jacobian : ndarray, shape (4, 4)
        (1/T) int_0^T J(t, x(t)) dt, J the Jacobian of eq. (2) with eq. (29)'s loads in
        (u, w, q, theta) (eqs. 44-47): the averaged system of the stability chapter. Read-only.
    mean_velocity : ndarray, shape (2,)
        Cycle means (forward, climb) [m/s] of the centre of gravity's inertial velocity,
        forward = u cos(theta) + w sin(theta), climb = u sin(theta) - w cos(theta); both ~0 on
        a hover orbit. Read-only.
    n_nodes : int
        Gauss-Legendre nodes per half-stroke.
    compiled : bool
        False if the kernel's Python code answered uncompiled (as :attr:`HoverSolution.compiled`).
    """

    averaged_jacobian: np.ndarray
    mean_velocity: np.ndarray
    n_nodes: int
    compiled: bool = True

    @property
    def forward_velocity(self) -> float:
        """Mean forward velocity [m/s]."""
        return float(self.mean_velocity[0])

    @property
    def climb_velocity(self) -> float:
        """Mean climb velocity [m/s] (minus the mean descent rate)."""
        return float(self.mean_velocity[1])


@functools.lru_cache(maxsize=32)
def _gauss(n_nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes (ascending) and weights on [-1, 1], read-only, per node count."""
    nodes, weights = np.polynomial.legendre.leggauss(n_nodes)
    return _read_only(nodes), _read_only(weights)


def orbit_quadrature(problem: KernelProblem | Insect, x0: ArrayLike, amplitude: float,
                     n_nodes: int = 64) -> OrbitQuadrature:
    """The cycle-averaged Jacobian and mean velocities along the orbit from x0, in one call.

    Gauss-Legendre with ``n_nodes`` nodes on each half-stroke (the integrands are smooth there
    and jump at stroke reversal, eq. 11), the same rule as the adaptive path's averaged
    Jacobian; the state is carried between nodes by the kernel's fixed-step formula with at
    least 32 steps per half-stroke (its error is then at rounding level).

    Parameters
    ----------
    problem : KernelProblem or Insect
    x0 : sequence of 4 floats
        (u, w, q, theta) at t = 0 [m/s, m/s, rad/s, rad], e.g. ``HoverSolution.x0``.
    amplitude : float
        Phi [rad].
    n_nodes : int
        Nodes per half-stroke, in [1, 65536].

    Returns
    -------
    OrbitQuadrature

    Raises
    ------
    ValueError
        For bad arguments.
    """
    problem = _problem(problem)
    x = _validation.vector("x0", x0, size=4)
    amp = check_amplitude(amplitude)
    nodes, weights = _gauss(_validation.integer("n_nodes", n_nodes, low=1, high=_MAX_NODES))
    (J, v), compiled = run_reporting(load(), "orbit_quadrature", x, amp, problem.k, problem.p,
                                     nodes, weights, _QUADRATURE_STEPS)
    return OrbitQuadrature(_read_only(J), _read_only(v), nodes.size, compiled)


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
        Even number in [2, 2^20] of steps per period (n_samples / 2 per half-stroke).

    Returns
    -------
    t : ndarray, shape (n_samples + 1,)
    x : ndarray, shape (4, n_samples + 1)
        Time along the last axis.
    z_drift : float
        Net descent over the period [m].
    """
    problem = _validation.instance("problem", problem, KernelProblem)
    n = _validation.integer("n_samples", n_samples, low=2, high=_MAX_SAMPLES)
    if n % 2:
        raise ValueError(f"`n_samples` must be an even integer in [2, {_MAX_SAMPLES}]; got "
                         f"{n_samples!r}")
    x = _validation.vector("x0", x0, size=4)
    samples = run(load(), "sample_period", x, check_amplitude(amplitude), n // 2, problem.k,
                  problem.p)
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
    out = run(load(), "states_at", x, check_amplitude(amplitude), n, problem.k, problem.p, t)
    return np.ascontiguousarray(out[:, :4].T)

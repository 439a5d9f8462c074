"""The hovering periodic orbit of a flapping insect and its Floquet stability (paper Sec. IV).

Hover is a periodic orbit of the time-periodic longitudinal dynamics whose body does not climb or
sink on average. We solve for the initial state (u, w, q, theta) *and* the stroke amplitude Phi with
the optimized shooting method, on the state augmented with the inertial vertical displacement z
(positive down):

    z' = -u sin(theta) + w cos(theta),        z(0) = 0 held fixed,

so that periodicity of the augmented state, z(T) = z(0), is the hover condition: zero net change
of altitude over a period (zero mean inertial vertical speed). Five equations, five unknowns.

The paper's own condition (its "virtual state" h = w sin(theta) - u cos(theta), required to be
periodic) is examined by :func:`paper_hover_problem`: h is a function of the state, so h(T) = h(0)
follows from periodicity of u, w, theta and adds no equation; Phi is then left undetermined and the
solver returns one member of a family of climbing or sinking periodic orbits.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import Sequence

import numpy as np

from flapping.dynamics import STATE_NAMES, LongitudinalDynamics
from flapping.errors import ConvergenceError
from flapping.floquet import monodromy
from flapping.integrate import flow, variational_flow
from flapping.kinematics import segment_stroke_sign
from flapping.morphology import Insect
from flapping.shooting import PeriodicOrbit, find_periodic_orbit

__all__ = [
    "HALF_PERIOD_SYMMETRY",
    "HoverOrbit",
    "HoverStability",
    "PerturbationGrowth",
    "find_hover_orbit",
    "forced_orbit",
    "paper_hover_problem",
    "hover_stability",
    "perturbation_growth",
    "mode_response",
    "force_budget",
    "DEFAULT_PERTURBATION",
    "simulate_perturbation",
    "SpeedPitchCubic",
    "speed_pitch_cubic",
    "SensitivityRow",
    "OPEN_CHOICES",
    "describe_changes",
    "hover_sensitivity",
]

#: x(t + T/2) = S x(t) for the symmetric stroke (x_h = 0): u, q, theta change sign, w does not.
HALF_PERIOD_SYMMETRY = np.diag([-1.0, 1.0, -1.0, -1.0])


# =========================================================================== results
@dataclass(frozen=True)
class HoverOrbit:
    """A periodic orbit of the insect (the hovering one, or one at a prescribed amplitude).

    Attributes
    ----------
    model : LongitudinalDynamics
        The dynamics at the orbit's amplitude.
    x0 : ndarray, shape (4,)
        (u, w, q, theta) at t = 0 (stroke reversal at the forward extreme) [m/s, m/s, rad/s, rad].
    amplitude : float
        Stroke amplitude Phi [rad].
    period : float
        Flapping period T [s].
    t, x : ndarray
        One period sampled uniformly (``x`` has shape (4, len(t))), for plots and statistics.
    z_drift : float
        Net descent z(T) - z(0) over one period [m] (0 on a hover orbit).
    shooting : PeriodicOrbit
        The shooting solver's result, with its diagnostics.
    """

    model: LongitudinalDynamics
    x0: np.ndarray
    amplitude: float
    period: float
    t: np.ndarray
    x: np.ndarray
    z_drift: float
    shooting: PeriodicOrbit = field(repr=False)

    @property
    def amplitude_deg(self) -> float:
        """Stroke amplitude in degrees."""
        return math.degrees(self.amplitude)

    @property
    def residual_norm(self) -> float:
        """Norm of the shooting residual at the solution."""
        return float(self.shooting.residual_norm)

    @property
    def mean_state(self) -> dict[str, float]:
        """Cycle mean of each state."""
        return {k: float(np.mean(self.x[i, :-1])) for i, k in enumerate(STATE_NAMES)}

    @property
    def state_range(self) -> dict[str, tuple[float, float]]:
        """(min, max) of each state over the period."""
        return {k: (float(self.x[i].min()), float(self.x[i].max())) for i, k in enumerate(STATE_NAMES)}

    @property
    def mean_inertial_velocity(self) -> dict[str, float]:
        """Cycle means of the inertial velocities [m/s]: ``forward`` and ``climb`` (up positive)."""
        u, w, _, th = self.x[:, :-1]
        return {"forward": float(np.mean(u * np.cos(th) + w * np.sin(th))),
                "climb": float(np.mean(u * np.sin(th) - w * np.cos(th)))}

    @property
    def half_period_symmetry_error(self) -> float:
        """max |x(t + T/2) - S x(t)| / max|x| over the period: 0 if the orbit has the symmetry."""
        n = self.x.shape[1] - 1
        if n % 2:
            raise ValueError("needs an even number of samples per period")
        first, second = self.x[:, : n // 2], self.x[:, n // 2 : n]
        scale = np.abs(self.x).max(axis=1, keepdims=True)
        return float(np.max(np.abs(second - HALF_PERIOD_SYMMETRY @ first) / scale))


@dataclass(frozen=True)
class HoverStability:
    """Floquet stability of a periodic orbit (eqs. 42-49, 66-67) and the averaged approximation.

    Attributes
    ----------
    orbit : HoverOrbit
    monodromy : ndarray, shape (4, 4)
        Phi(T) of the variational equations along the orbit.
    multipliers : ndarray
        Floquet multipliers, sorted by modulus (descending).
    exponents : ndarray
        Floquet exponents log(mu)/T [1/s] (principal branch).
    eigenvectors : ndarray, shape (4, 4)
        Column k is the eigenvector of the monodromy for ``multipliers[k]``.
    det, liouville_det : float
        det M and exp(int_0^T trace J dt); equal by Liouville's formula.
    averaged_jacobian : ndarray, shape (4, 4)
        (1/T) int_0^T J(t, x(t)) dt along the orbit: the first-order averaged system.
    averaged_eigenvalues : ndarray
        Its eigenvalues [1/s], sorted by real part (descending).
    """

    orbit: HoverOrbit
    monodromy: np.ndarray
    multipliers: np.ndarray
    exponents: np.ndarray
    eigenvectors: np.ndarray
    det: float
    liouville_det: float
    averaged_jacobian: np.ndarray
    averaged_eigenvalues: np.ndarray

    @property
    def liouville_error(self) -> float:
        """|det M - exp(int trace J)| / |exp(int trace J)|."""
        return abs(self.det - self.liouville_det) / abs(self.liouville_det)

    @property
    def is_stable(self) -> bool:
        """True if every multiplier lies inside the unit circle."""
        return bool(np.all(np.abs(self.multipliers) < 1.0))

    @property
    def unstable_mode(self) -> np.ndarray:
        """Eigenvector of the largest multiplier scaled so its largest component is 1.

        Real (float) when that multiplier is real; complex when it belongs to a complex pair.
        """
        v = self.eigenvectors[:, 0]
        v = v / v[np.argmax(np.abs(v))]
        return np.real(v) if abs(self.multipliers[0].imag) == 0.0 else v


@dataclass(frozen=True)
class PerturbationGrowth:
    """Growth of a small perturbation of the orbit under the full nonlinear dynamics.

    Attributes
    ----------
    cycles : ndarray
        0, 1, ..., n.
    deviation : ndarray
        |x(kT) - x_orbit(0)| after k periods (Euclidean norm, SI units).
    growth_per_cycle : float
        Fitted deviation ratio per period over cycles ``fit_start`` ... n, where the growth is
        exponential (the decaying modes have died out).
    predicted : float
        Modulus of the largest Floquet multiplier.
    fit_start : int
        First cycle of the fit (two thirds of the way through the simulation).
    """

    cycles: np.ndarray
    deviation: np.ndarray
    growth_per_cycle: float
    predicted: float
    fit_start: int


# =========================================================================== vector fields
def _hover_fields(model: LongitudinalDynamics):
    """Per-half-stroke (rhs, jac, param_jac) of the state augmented with the descent z, p = [Phi]."""
    rhs, jac, pjac = [], [], []
    for k in range(len(model.breakpoints) + 1):
        s = segment_stroke_sign(k)

        def f(t, y, p, _s=s):
            _check_iterate_amplitude(p[0])
            out = np.empty(5)
            out[:4] = model.rhs(t, y, _s, p[0])
            u, w, th = y[0], y[1], y[3]
            out[4] = -u * math.sin(th) + w * math.cos(th)
            return out

        def J(t, y, p, _s=s):
            out = np.zeros((5, 5))
            out[:4, :4] = model.jac(t, y, _s, p[0])
            u, w, th = y[0], y[1], y[3]
            out[4, 0] = -math.sin(th)
            out[4, 1] = math.cos(th)
            out[4, 3] = -u * math.cos(th) - w * math.sin(th)
            return out

        def P(t, y, p, _s=s):
            out = np.zeros((5, 1))
            out[:4] = model.amplitude_jac(t, y, _s, p[0])
            return out

        rhs.append(f)
        jac.append(J)
        pjac.append(P)
    return rhs, jac, pjac


def _check_iterate_amplitude(amplitude: float) -> None:
    """Stop the shooting when an iterate's stroke amplitude leaves (0, pi/2]."""
    if not 0.0 < amplitude <= math.pi / 2:
        raise ConvergenceError(
            f"the shooting iteration stepped the stroke amplitude to {math.degrees(amplitude):.4g} "
            "deg, outside (0, 90] deg: no hover orbit with wings that do not cross was found "
            "from this guess")


def _checked(result, what: str):
    """Raise ConvergenceError if an integration did not reach its end."""
    if not result.success:
        raise ConvergenceError(f"{what}: the integration failed ({result.message})")
    return result


def _sample(model: LongitudinalDynamics, x0: np.ndarray, n_samples: int, method: str, **tol):
    rhs, _ = model.segment_functions()
    t = np.linspace(0.0, model.period, n_samples + 1)
    res = _checked(flow(rhs, (0.0, model.period), x0, breakpoints=model.breakpoints,
                        period=model.period, method=method,
                        t_eval=t if method != "RK4" else None, **tol), "sampling the orbit")
    if method == "RK4":
        return res.t, res.x
    return t, res.x


# =========================================================================== hover
def find_hover_orbit(
    insect: Insect,
    *,
    aerodynamics: str = "linear",
    alpha_m: float | None = None,
    amplitude_guess: float | None = None,
    x0_guess: Sequence[float] | None = None,
    method: str = "DOP853",
    jacobian: str | None = None,
    rtol: float = 1e-11,
    atol: float = 1e-12,
    tol: float = 1e-10,
    n_samples: int = 512,
) -> HoverOrbit:
    """Find the hovering periodic orbit: initial state and stroke amplitude.

    Unknowns (u0, w0, q0, theta0, Phi); equations: periodicity of (u, w, q, theta) and zero net
    altitude change over one period (module docstring). The mean angle of attack alpha_m stays at
    the trim of eq. (40) for the insect's nominal amplitude, as in the paper.

    Parameters
    ----------
    insect : Insect
    aerodynamics : {"linear", "small-angle", "exact"}
        Loads model (:class:`~flapping.dynamics.LongitudinalDynamics`); ``"linear"`` is eq. (29).
    alpha_m : float, optional
        Mean geometric angle of attack [rad]; default the trim of eq. (40).
    amplitude_guess : float, optional
        Initial guess of Phi [rad]; default ``insect.stroke_amplitude``.
    x0_guess : sequence of 4 floats, optional
        Initial guess of (u, w, q, theta); default zeros.
    jacobian : {"variational", "finite-difference"}, optional
        Jacobian of the shooting residual. Default: ``"variational"`` for the linear model (its
        Jacobian is analytic), ``"finite-difference"`` for the blade-element models (their
        Jacobian would itself be differenced at every step, which costs more, and the variational
        system's step sequence then varies enough between iterates to hold the residual at the
        integration-noise floor ~1e-10).
    method, rtol, atol, tol
        Passed to :func:`flapping.shooting.find_periodic_orbit` (``tol``: largest accepted
        residual norm).
    n_samples : int
        Samples of the orbit over one period in the result (even).

    Returns
    -------
    HoverOrbit

    Raises
    ------
    ValueError
        For bad arguments, or if the insect cannot trim (too heavy for its wings, eq. 40).
    ConvergenceError
        If the shooting does not converge, or converges to a stroke amplitude outside
        (0, 90 deg]: then no hover orbit exists for this insect with wings that do not cross.
    """
    model = LongitudinalDynamics(insect, alpha_m=alpha_m, aerodynamics=aerodynamics)
    amplitude = insect.stroke_amplitude if amplitude_guess is None else amplitude_guess
    model.with_amplitude(amplitude)  # validates the guess
    # Eq. (40) solved for the amplitude at this alpha_m: the stroke a body at rest needs. If even
    # that exceeds 90 deg, no hover orbit exists with wings that do not cross.
    k21 = 0.5 * insect.air_density * insect.lift_slope * insect.span_integral(2, 1)
    needed = math.sqrt(insect.weight / (2.0 * math.pi**2 * insect.frequency**2 * k21
                                        * math.sin(2.0 * model.alpha_m)))
    if needed > math.pi / 2:
        raise ValueError(
            f"{insect.name} cannot hover with alpha_m = {math.degrees(model.alpha_m):.4g} deg: "
            f"eq. (40) needs a stroke amplitude of {math.degrees(needed):.4g} deg > 90 deg "
            f"(mass {insect.mass!r} kg); raise alpha_m towards 45 deg or lower the mass")
    x0 = _state_guess(x0_guess)
    if n_samples < 2 or n_samples % 2:
        raise ValueError(f"n_samples must be an even integer >= 2; got {n_samples!r}")
    if jacobian is None:
        jacobian = "variational" if aerodynamics == "linear" else "finite-difference"
    rhs, jac, pjac = _hover_fields(model)
    result = find_periodic_orbit(
        rhs, np.append(x0, 0.0), model.period, autonomous=False, jac=jac, param_jac=pjac,
        free_params=[amplitude], fixed=(4,), breakpoints=model.breakpoints,
        jacobian=jacobian, method=method, rtol=rtol, atol=atol, tol=tol,
    )
    phi = float(result.params[0])
    if not 0.0 < phi <= math.pi / 2:
        raise ConvergenceError(
            f"no hover orbit for {insect.name} with a stroke amplitude in (0, 90] deg: the "
            f"shooting converged to Phi = {math.degrees(phi):.4g} deg",
            x=np.append(result.x0, phi), residual=result.residual_norm,
            iterations=result.iterations, result=result)
    hover_model = model.with_amplitude(phi)
    x0 = np.asarray(result.x0[:4], dtype=float)
    t, x = _sample(hover_model, x0, n_samples, method, rtol=rtol, atol=atol)
    return HoverOrbit(hover_model, x0, phi, model.period, t, x, float(result.residual[4]), result)


def forced_orbit(
    insect: Insect,
    amplitude: float | None = None,
    *,
    aerodynamics: str = "linear",
    alpha_m: float | None = None,
    x0_guess: Sequence[float] | None = None,
    method: str = "DOP853",
    rtol: float = 1e-11,
    atol: float = 1e-12,
    tol: float = 1e-10,
    n_samples: int = 512,
) -> HoverOrbit:
    """The periodic orbit at a *prescribed* stroke amplitude (periodicity of the states only).

    Such an orbit exists for a range of amplitudes; it climbs or sinks unless Phi is the hover
    amplitude.

    Parameters
    ----------
    insect : Insect
    amplitude : float, optional
        Stroke amplitude Phi [rad] in (0, pi/2]; default ``insect.stroke_amplitude``.
    aerodynamics, alpha_m, x0_guess, method, rtol, atol, tol, n_samples
        As for :func:`find_hover_orbit`.

    Returns
    -------
    HoverOrbit
        With ``z_drift`` the net descent per period [m] (positive: sinking).

    Raises
    ------
    ValueError
        For bad arguments.
    ConvergenceError
        If the shooting does not converge.
    """
    model = LongitudinalDynamics(insect, amplitude=amplitude, alpha_m=alpha_m,
                                 aerodynamics=aerodynamics)
    x0 = _state_guess(x0_guess)
    rhs, jac = model.segment_functions()
    result = find_periodic_orbit(rhs, x0, model.period, autonomous=False, jac=jac,
                                 breakpoints=model.breakpoints, method=method, rtol=rtol,
                                 atol=atol, tol=tol)
    x0 = np.asarray(result.x0, dtype=float)
    t, x = _sample(model, x0, n_samples, method, rtol=rtol, atol=atol)
    hrhs = _hover_fields(model)[0]
    aug = _checked(flow(hrhs, (0.0, model.period), np.append(x0, 0.0),
                        breakpoints=model.breakpoints, period=model.period, method=method,
                        rtol=rtol, atol=atol, args=([model.amplitude],)), "the altitude drift")
    return HoverOrbit(model, x0, float(model.amplitude), model.period, t, x,
                      float(aug.x[4, -1]), result)


def paper_hover_problem(
    insect: Insect,
    *,
    x0_guess: Sequence[float] = (0.1, 0.1, 0.1 * math.pi / 180, 0.1 * math.pi / 180),
    h0_guess: float = 2.0,
    amplitude_guess: float | None = None,
    aerodynamics: str = "linear",
    method: str = "DOP853",
    rtol: float = 1e-11,
    atol: float = 1e-12,
    tol: float = 1e-10,
) -> tuple[PeriodicOrbit, np.ndarray]:
    """The paper's hover problem (Sec. IV): the virtual state h = w sin(theta) - u cos(theta).

    h is integrated as a fifth state (h' = d/dt of its definition) with its own unknown initial
    value, and required to be periodic with the other states; Phi is a free parameter. Defaults
    are the paper's Table 1 guess.

    Returns
    -------
    result : PeriodicOrbit
        The shooting result (``x0`` holds (u, w, q, theta, h), ``params`` holds Phi).
    singular_values : ndarray, shape (5,)
        Singular values of the Jacobian of the one-period residual y(T) - y(0) with respect to
        the six unknowns (u0, w0, q0, theta0, h0, Phi), from the variational equations. The
        smallest vanishes (to integration accuracy): the rank is 4, so the null space is two-
        dimensional -- h0 never feeds back, and h(T) - h(0) repeats the other residuals. Phi is
        therefore not determined by this problem.
    """
    model = LongitudinalDynamics(insect, aerodynamics=aerodynamics)
    amplitude = insect.stroke_amplitude if amplitude_guess is None else amplitude_guess
    base = model.segment_functions()[0]

    def field(k):
        s = segment_stroke_sign(k)

        def f(t, y, p):
            dx = model.rhs(t, y[:4], s, p[0])
            u, w, q, th = y[:4]
            dh = (dx[1] * math.sin(th) + w * math.cos(th) * q
                  - dx[0] * math.cos(th) + u * math.sin(th) * q)
            return np.append(dx, dh)
        return f

    rhs = [field(k) for k in range(len(base))]
    y0 = np.append(_state_guess(x0_guess), h0_guess)
    result = find_periodic_orbit(rhs, y0, model.period, autonomous=False,
                                 free_params=[amplitude], breakpoints=model.breakpoints,
                                 n_points=3,  # three points per state, as in eq. (41)
                                 jacobian="finite-difference", method=method, rtol=rtol,
                                 atol=atol, tol=tol)

    # Jacobian of the one-period residual y(T) - y(0) in (y0, Phi) from the variational equations.
    var = _checked(variational_flow(rhs, None, (0.0, model.period), result.x0,
                                    breakpoints=model.breakpoints, period=model.period,
                                    method=method, rtol=rtol, atol=atol, params=result.params),
                   "the paper problem's Jacobian")
    J = np.hstack([var.stm_end - np.eye(5), var.sensitivity[-1]])
    return result, np.linalg.svd(J, compute_uv=False)


# =========================================================================== stability
def hover_stability(
    orbit: HoverOrbit,
    *,
    method: str = "DOP853",
    rtol: float = 1e-12,
    atol: float = 1e-12,
    rk4_steps: int = 1024,
    n_average: int = 64,
) -> HoverStability:
    """Monodromy matrix, Floquet multipliers and the averaged system of a periodic orbit.

    Parameters
    ----------
    orbit : HoverOrbit
    method : str
        ``"DOP853"`` (default) or ``"RK4"`` (the paper's fixed step, ``rk4_steps`` per period).
    rtol, atol : float
        Tolerances of the adaptive integrator.
    n_average : int
        Gauss-Legendre nodes per half-stroke for the cycle-averaged Jacobian (the integrand is
        smooth within a half-stroke, so the rule converges spectrally).
    """
    model = orbit.model
    rhs, jac = model.segment_functions()
    mon = monodromy(rhs, orbit.x0, orbit.period, jac=jac, breakpoints=model.breakpoints,
                    method=method, rtol=rtol, atol=atol, rk4_steps=rk4_steps)
    # Multipliers from the monodromy's product-QR iteration (accurate even when small); the
    # eigenvectors from eig(M), matched to them by nearest eigenvalue.
    values = np.asarray(mon.multipliers, dtype=complex)
    eig_values, eig_vectors = np.linalg.eig(mon.matrix)
    match = [int(np.argmin(np.abs(eig_values - mu))) for mu in values]
    vectors = eig_vectors[:, match].astype(complex)
    averaged = _averaged_jacobian(orbit, n_average)
    avg_eig = np.linalg.eigvals(averaged).astype(complex)  # always complex: one dtype for all
    avg_eig = avg_eig[np.argsort(-avg_eig.real, kind="stable")]
    return HoverStability(orbit, mon.matrix, values, np.log(values) / orbit.period, vectors,
                          float(mon.det), float(mon.liouville_det), averaged, avg_eig)


def mode_response(
    stability: HoverStability,
    *,
    mode: int = 0,
    n_periods: int = 1,
    samples_per_period: int = 48,
) -> tuple[np.ndarray, np.ndarray]:
    """Time history of a Floquet mode along the orbit: delta x(t) = Phi(t, 0) v_k.

    Parameters
    ----------
    stability : HoverStability
    mode : int
        Index into ``stability.multipliers`` (0: the largest).
    n_periods : int
        Number of periods to follow (>= 1).
    samples_per_period : int
        Output samples per period (>= 2).

    Returns
    -------
    t : ndarray, shape (m,)
    delta : ndarray, shape (4, m)
        The linearised response to a disturbance equal to the eigenvector (scaled to max 1);
        after k periods it equals mu_k^k v_k.
    """
    if not (isinstance(n_periods, int) and n_periods >= 1):
        raise ValueError(f"n_periods must be an integer >= 1; got {n_periods!r}")
    if not (isinstance(samples_per_period, int) and samples_per_period >= 2):
        raise ValueError(f"samples_per_period must be an integer >= 2; got {samples_per_period!r}")
    if not (isinstance(mode, int) and 0 <= mode < stability.multipliers.size):
        raise ValueError(f"mode must lie in [0, {stability.multipliers.size - 1}]; got {mode!r}")
    orbit = stability.orbit
    model = orbit.model
    v = stability.eigenvectors[:, mode]
    v = v / v[np.argmax(np.abs(v))]
    if stability.multipliers[mode].imag == 0.0:
        v = np.real(v)
    t = np.linspace(0.0, n_periods * orbit.period, samples_per_period * n_periods + 1)
    rhs, jac = model.segment_functions()
    var = _checked(variational_flow(rhs, jac, (0.0, t[-1]), orbit.x0,
                                    breakpoints=model.breakpoints, period=orbit.period,
                                    t_out=t[1:], rtol=1e-12, atol=1e-12), "the mode's response")
    delta = np.column_stack([v, np.einsum("kij,j->ik", var.stm, v)])
    return t, delta


def force_budget(orbit: HoverOrbit, n_samples: int = 4096) -> dict[str, dict[str, float]]:
    """Cycle means of every term of the linear model's equations (2)/(29) along the orbit.

    On a periodic orbit each equation's terms average to zero (the mean of x' vanishes); the
    budget shows which terms carry the weight, e.g. why the hover amplitude differs from the trim
    of eq. (40), which balances the weight by Z0 alone.

    Returns
    -------
    dict
        ``{"u": {...}, "w": {...}, "q": {...}}``, each a dict of term name -> cycle mean
        [m/s^2 for u and w, rad/s^2 for q], with the names of eq. (29) (``"X0/m"``, ``"Xu u"``,
        ``"-q w"``, ``"-g sin(theta)"``, ...).

    Raises
    ------
    ValueError
        If the orbit's model is not the linear one (the budget is of eq. 29's terms).
    """
    model = orbit.model
    if model.aerodynamics != "linear":
        raise ValueError("force_budget needs an orbit of the linear model (aerodynamics='linear')")
    if not (isinstance(n_samples, int) and n_samples >= 2):
        raise ValueError(f"n_samples must be an integer >= 2; got {n_samples!r}")
    rhs, _ = model.segment_functions()
    t = np.linspace(0.0, orbit.period, n_samples, endpoint=False)
    x = _checked(flow(rhs, (0.0, orbit.period), orbit.x0, breakpoints=model.breakpoints,
                      period=orbit.period, t_eval=t, rtol=1e-12, atol=1e-12), "the budget").x
    u, w, q, th = x
    d = np.array([model.derivatives(ti) for ti in t]).T
    g, m, Iy = model.insect.gravity, model.insect.mass, model.insect.pitch_inertia
    terms = {
        "u": {"-q w": -q * w, "-g sin(theta)": -g * np.sin(th), "X0/m": d[0] / m,
              "Xu u": d[3] * u, "Xw w": d[4] * w, "Xq q": d[5] * q},
        "w": {"q u": q * u, "g cos(theta)": g * np.cos(th), "Z0/m": d[1] / m,
              "Zu u": d[6] * u, "Zw w": d[7] * w, "Zq q": d[8] * q},
        "q": {"M0/Iy": d[2] / Iy, "Mu u": d[9] * u, "Mw w": d[10] * w, "Mq q": d[11] * q},
    }
    return {eq: {k: float(np.mean(v)) for k, v in parts.items()} for eq, parts in terms.items()}


def _averaged_jacobian(orbit: HoverOrbit, n_nodes: int) -> np.ndarray:
    model = orbit.model
    rhs, jac = model.segment_functions()
    nodes, weights = np.polynomial.legendre.leggauss(n_nodes)
    bounds = (0.0,) + tuple(model.breakpoints) + (1.0,)
    total = np.zeros((4, 4))
    for k in range(len(bounds) - 1):
        a, b = bounds[k] * orbit.period, bounds[k + 1] * orbit.period
        t_k = 0.5 * (b - a) * nodes + 0.5 * (a + b)
        res = _checked(flow(rhs, (0.0, orbit.period), orbit.x0, breakpoints=model.breakpoints,
                            period=orbit.period, t_eval=np.sort(t_k), rtol=1e-12, atol=1e-12),
                       "the averaged Jacobian")
        for t, x, wgt in zip(res.t, res.x.T, weights[np.argsort(t_k)]):
            total += 0.5 * (b - a) * wgt * jac[k](t, x)
    return total / orbit.period


def perturbation_growth(
    stability: HoverStability,
    *,
    epsilon: float = 1e-6,
    n_cycles: int = 30,
    direction: np.ndarray | None = None,
) -> PerturbationGrowth:
    """Simulate the full nonlinear dynamics from the orbit plus a small perturbation.

    The perturbation (default: a generic direction, not an eigenvector) grows, after a transient, by
    the largest multiplier per period; the growth is fitted over the last third of the cycles.
    """
    orbit = stability.orbit
    model = orbit.model
    scale = float(np.abs(orbit.x).max())
    if not (isinstance(epsilon, (int, float)) and 0.0 < epsilon <= 1e-3 * scale):
        raise ValueError(
            f"epsilon must lie in (0, 1e-3 max|x|] = (0, {1e-3 * scale:.3g}] so that the "
            f"perturbation stays linear over the fit; got {epsilon!r}")
    if not (isinstance(n_cycles, int) and n_cycles >= 3):
        raise ValueError(f"n_cycles must be an integer >= 3; got {n_cycles!r}")
    direction = _unit_direction(direction)
    rhs, _ = model.segment_functions()
    times = orbit.period * np.arange(n_cycles + 1)
    res = _checked(flow(rhs, (0.0, times[-1]), orbit.x0 + epsilon * direction,
                        breakpoints=model.breakpoints, period=orbit.period, t_eval=times,
                        rtol=1e-12, atol=1e-14), "the perturbed simulation")
    deviation = np.linalg.norm(res.x - orbit.x0[:, None], axis=0)
    start = (2 * n_cycles) // 3  # after the transient of the decaying modes
    slope = np.polyfit(np.arange(start, n_cycles + 1), np.log(deviation[start:]), 1)[0]
    return PerturbationGrowth(np.arange(n_cycles + 1), deviation, float(np.exp(slope)),
                              float(np.abs(stability.multipliers[0])), start)


# =========================================================================== sensitivity
def describe_changes(changes: dict) -> str:
    """A short label for a set of :class:`~flapping.morphology.Insect` field changes.

    Built from the values themselves, so that a table of variants never repeats a number by hand:
    ``{"hinge_offset": 1e-3}`` -> ``"x_h = +1 mm"``; ``{}`` -> the defaults of :class:`Insect`.
    """
    defaults = {f.name: f.default for f in fields(Insect) if f.init}
    if not changes:
        return (f"defaults (AR = 2R^2/S, x_hat = {defaults['center_of_pressure']:g}, "
                f"x0_hat = {defaults['pitch_axis']:g}, x_h = {defaults['hinge_offset'] * 1e3:g} mm)"
                if defaults["aspect_ratio_convention"] == "pair" else "defaults")
    parts = []
    for key, value in changes.items():
        if key == "aspect_ratio_convention":
            parts.append("AR = R^2/S in eq. (4)" if value == "single" else "AR = 2R^2/S in eq. (4)")
        elif key == "center_of_pressure":
            parts.append(f"x_hat = {value:g}")
        elif key == "pitch_axis":
            parts.append(f"x0_hat = {value:g}")
        elif key == "hinge_offset":
            parts.append(f"x_h = {value * 1e3:+g} mm")
        elif key in ("mu1", "mu2") and set(changes) >= {"mu1", "mu2"} and not changes["mu1"] \
                and not changes["mu2"]:
            if key == "mu1":
                parts.append("no rotational damping (mu1 = mu2 = 0)")
        else:
            parts.append(f"{key} = {value:g}" if isinstance(value, (int, float)) else f"{key} = {value}")
    return ", ".join(parts)


_OPEN_CHOICE_CHANGES: tuple[dict, ...] = (
    {},
    {"aspect_ratio_convention": "single"},
    {"center_of_pressure": 0.15},
    {"center_of_pressure": 0.35},
    {"pitch_axis": 0.25},
    {"hinge_offset": 1e-3},
    {"hinge_offset": -1e-3},
    {"mu1": 0.0, "mu2": 0.0},
)

#: Modelling choices the paper leaves open, as Insect field changes from the defaults, keyed by
#: their :func:`describe_changes` label.
OPEN_CHOICES: dict[str, dict] = {describe_changes(c): c for c in _OPEN_CHOICE_CHANGES}


@dataclass(frozen=True)
class SensitivityRow:
    """Hover orbit and stability of one variant of the insect."""

    label: str
    changes: dict
    alpha_m_deg: float
    amplitude_deg: float
    multipliers: np.ndarray
    averaged_eigenvalues: np.ndarray
    mean_forward_velocity: float
    stability: HoverStability = field(repr=False)

    @property
    def orbit(self) -> HoverOrbit:
        """The variant's hover orbit."""
        return self.stability.orbit

    @property
    def largest_multiplier(self) -> float:
        """Modulus of the largest Floquet multiplier."""
        return float(np.abs(self.multipliers[0]))


def hover_sensitivity(
    insect: Insect,
    variations: dict[str, dict] | None = None,
    *,
    aerodynamics: str = "linear",
) -> list[SensitivityRow]:
    """Hover amplitude and multipliers for variants of ``insect`` (default :data:`OPEN_CHOICES`).

    Each variant is re-trimmed (eq. 40) and its hover orbit found from the default guess. With
    x_h != 0 the half-period symmetry is lost, and the hover orbit (which fixes only the vertical
    drift) may drift horizontally: its mean forward velocity is reported.

    Parameters
    ----------
    insect : Insect
        The base insect.
    variations : dict, optional
        Label -> dict of :class:`Insect` field changes.
    aerodynamics : {"linear", "small-angle", "exact"}
        Loads model.

    Returns
    -------
    list of SensitivityRow
        One row per variation, in order, each carrying its orbit and stability.

    Raises
    ------
    ValueError, ConvergenceError
        As :func:`find_hover_orbit` for any variant.
    """
    variations = OPEN_CHOICES if variations is None else variations
    rows = []
    for label, changes in variations.items():
        variant = insect.with_(**changes)
        orbit = find_hover_orbit(variant, aerodynamics=aerodynamics)
        stab = hover_stability(orbit)
        rows.append(SensitivityRow(label, dict(changes), math.degrees(orbit.model.alpha_m),
                                   orbit.amplitude_deg, stab.multipliers,
                                   stab.averaged_eigenvalues,
                                   orbit.mean_inertial_velocity["forward"], stab))
    return rows


#: A generic perturbation direction in (u, w, q, theta) (not an eigenvector), before normalising.
DEFAULT_PERTURBATION = (1.0, -0.7, 3.0, 0.2)


def _unit_direction(direction) -> np.ndarray:
    direction = np.asarray(DEFAULT_PERTURBATION if direction is None else direction, dtype=float)
    if direction.shape != (4,) or not np.all(np.isfinite(direction)) or not np.any(direction):
        raise ValueError(f"direction must be 4 finite numbers, not all zero; got {direction!r}")
    return direction / np.linalg.norm(direction)


def simulate_perturbation(
    orbit: HoverOrbit,
    epsilon: float,
    *,
    n_cycles: int = 30,
    direction=None,
    samples_per_cycle: int = 64,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The full nonlinear dynamics from x0 + epsilon * direction, beside the unperturbed orbit.

    Returns
    -------
    t : ndarray, shape (m,)
        Times over ``n_cycles`` periods [s].
    x_perturbed, x_orbit : ndarray, shape (4, m)
        The perturbed trajectory and the orbit integrated from x0 (which itself departs from the
        orbit eventually, the orbit being unstable, from its round-off-level closure error).
    """
    if not (math.isfinite(epsilon) and epsilon > 0):
        raise ValueError(f"epsilon must be a positive number; got {epsilon!r}")
    if not (isinstance(n_cycles, int) and n_cycles >= 1):
        raise ValueError(f"n_cycles must be an integer >= 1; got {n_cycles!r}")
    model = orbit.model
    rhs, _ = model.segment_functions()
    t = np.linspace(0.0, n_cycles * orbit.period, samples_per_cycle * n_cycles + 1)
    kw = dict(breakpoints=model.breakpoints, period=orbit.period, t_eval=t, rtol=1e-12,
              atol=1e-14)
    x_pert = _checked(flow(rhs, (0.0, t[-1]), orbit.x0 + epsilon * _unit_direction(direction),
                           **kw), "the perturbed simulation").x
    x_orb = _checked(flow(rhs, (0.0, t[-1]), orbit.x0, **kw), "the orbit's simulation").x
    return t, x_pert, x_orb


@dataclass(frozen=True)
class SpeedPitchCubic:
    """The averaged speed-pitch subsystem (u, q, theta) and its characteristic polynomial.

    With the vertical speed decoupled (its averaged couplings vanish by symmetry at x_h = 0):
    u' = Xu u + Xq q - g theta, q' = Mu u + Mq q, theta' = q, whose characteristic polynomial is

        p(lambda) = lambda (lambda - Xu)(lambda - Mq) - Xq Mu lambda + g Mu.

    Attributes
    ----------
    Xu, Xq, Mu, Mq, g : float
        The entries of the averaged Jacobian used (g is the -J[0, 3] entry, g cos(theta) on the
        orbit's mean).
    coefficients : ndarray
        Of p, highest power first.
    roots : ndarray
        Roots of p, sorted by real part (descending).
    quasi_static_root : float
        Positive root of lambda^2 - Xu lambda - g Mu / Mq = 0, the approximation in which the
        pitch rate follows the speed at once (|Mq| large): a negative pitch stiffness.
    routh_hurwitz : tuple of float
        (a2 a1, a0) of p = lambda^3 + a2 lambda^2 + a1 lambda + a0; all roots in the left
        half-plane iff a2, a1, a0 > 0 and a2 a1 > a0.
    """

    Xu: float
    Xq: float
    Mu: float
    Mq: float
    g: float
    coefficients: np.ndarray
    roots: np.ndarray
    quasi_static_root: float
    routh_hurwitz: tuple[float, float]


def speed_pitch_cubic(averaged_jacobian: np.ndarray, *, flip_mu: bool = False) -> SpeedPitchCubic:
    """Characteristic cubic of the averaged speed-pitch subsystem (see :class:`SpeedPitchCubic`).

    Parameters
    ----------
    averaged_jacobian : ndarray, shape (4, 4)
        E.g. :attr:`HoverStability.averaged_jacobian` or
        :meth:`~flapping.stability_derivatives.StabilityDerivatives.averaged_jacobian`.
    flip_mu : bool
        Reverse the sign of Mu (a what-if: the speed-pitch coupling of wings above the CG).
    """
    J = np.asarray(averaged_jacobian, dtype=float)
    if J.shape != (4, 4) or not np.all(np.isfinite(J)):
        raise ValueError("averaged_jacobian must be a finite 4x4 array")
    Xu, Xq, g = J[0, 0], J[0, 2], -J[0, 3]
    Mu, Mq = (-1.0 if flip_mu else 1.0) * J[2, 0], J[2, 2]
    coeffs = np.array([1.0, -(Xu + Mq), Xu * Mq - Xq * Mu, g * Mu])
    roots = np.roots(coeffs).astype(complex)
    roots = roots[np.argsort(-roots.real, kind="stable")]
    stiffness = g * Mu / Mq
    disc = Xu**2 + 4.0 * stiffness
    qs = 0.5 * (Xu + math.sqrt(disc)) if disc >= 0 else float("nan")
    return SpeedPitchCubic(float(Xu), float(Xq), float(Mu), float(Mq), float(g), coeffs, roots,
                           qs, (float(coeffs[1] * coeffs[2]), float(coeffs[3])))


def _state_guess(x0_guess) -> np.ndarray:
    if x0_guess is None:
        return np.zeros(4)
    x0 = np.asarray(x0_guess, dtype=float)
    if x0.shape != (4,) or not np.all(np.isfinite(x0)):
        raise ValueError(f"x0_guess must be 4 finite numbers (u, w, q, theta); got {x0_guess!r}")
    return x0

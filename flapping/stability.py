"""Stability of the hovering orbit: Floquet multipliers, averaging, growth, sensitivity (Sec. IV).

Given a periodic orbit from :mod:`flapping.hover`, this module integrates the variational equations
over one period for the monodromy matrix and its Floquet multipliers (eqs. 42-49, 66-67) with the
Liouville check, compares them with the first-order averaged system (the cycle-averaged Jacobian
along the orbit, and its speed-pitch cubic), follows small perturbations with the full nonlinear
dynamics, and repeats the analysis for the modelling choices the paper leaves open.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

import numpy as np

from flapping.periodic.floquet import monodromy
from flapping.hover import HoverOrbit, _checked, find_hover_orbit
from flapping.periodic.integrate import flow, variational_flow
from flapping.model.morphology import Insect

__all__ = [
    "HoverStability",
    "hover_stability",
    "mode_response",
    "PerturbationGrowth",
    "perturbation_growth",
    "DEFAULT_PERTURBATION",
    "simulate_perturbation",
    "SpeedPitchCubic",
    "speed_pitch_cubic",
    "describe_changes",
    "OPEN_CHOICES",
    "SensitivityRow",
    "hover_sensitivity",
]


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


def _averaged_jacobian(orbit: HoverOrbit, n_nodes: int) -> np.ndarray:
    model = orbit.model
    rhs, jac = model.segment_functions()
    nodes, weights = np.polynomial.legendre.leggauss(n_nodes)  # ascending nodes
    bounds = np.array((0.0,) + tuple(model.breakpoints) + (1.0,)) * orbit.period
    half = 0.5 * np.diff(bounds)
    # Gauss-Legendre nodes of every segment, in time order: one integration of the orbit.
    t_all = np.concatenate([h * nodes + a + h for a, h in zip(bounds[:-1], half)])
    res = _checked(flow(rhs, (0.0, orbit.period), orbit.x0, breakpoints=model.breakpoints,
                        period=orbit.period, t_eval=t_all, rtol=1e-12, atol=1e-12),
                   "the averaged Jacobian")
    total = np.zeros((4, 4))
    for i, (t, x) in enumerate(zip(res.t, res.x.T)):
        k = i // n_nodes
        total += half[k] * weights[i % n_nodes] * jac[k](t, x)
    return total / orbit.period


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


#: A generic perturbation direction in (u, w, q, theta) (not an eigenvector), before normalising.
DEFAULT_PERTURBATION = (1.0, -0.7, 3.0, 0.2)


def _unit_direction(direction) -> np.ndarray:
    direction = np.asarray(DEFAULT_PERTURBATION if direction is None else direction, dtype=float)
    if direction.shape != (4,) or not np.all(np.isfinite(direction)) or not np.any(direction):
        raise ValueError(f"direction must be 4 finite numbers, not all zero; got {direction!r}")
    return direction / np.linalg.norm(direction)


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
        :meth:`~flapping.model.derivatives.StabilityDerivatives.averaged_jacobian`.
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


def describe_changes(changes: dict) -> str:
    """A short label for a set of :class:`~flapping.model.morphology.Insect` field changes.

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

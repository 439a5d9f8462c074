"""Quasi-steady blade-element aerodynamics of a hovering flapping wing, nonlinear in the states.

Paper Sec. II (eqs. 3-23). A section of one wing at radius r, chord c, moves in the (xi, z) plane of
the section (xi: chordwise horizontal, with body-x component cos(phi); z down) with velocity

    U     = r phi_dot + u cos(phi)                   (eq. 9, signed)
    w_eff = w - q (r sin(phi) + x_h)                 (eq. 12)

and pitches about its span axis at Omega = q cos(phi) (alpha_dot = 0 within a half-stroke). The
geometric pitch is alpha_g = alpha_m on the forward stroke (s = sign(phi_dot) = +1) and
pi - alpha_m on the backward stroke (eq. 11). Loads per unit span:

* leading-edge-vortex lift, C_L = A sin(2 alpha) (eq. 3), drag C_D = 2 A sin(alpha)**2 (eq. 6);
* rotational lift rho ``|V|`` Gamma with Gamma = pi c**2 (3/4 - x0_hat) Omega (eq. 5);
* a pitching moment about the centre of gravity from these forces acting at the centre of pressure,
  x_hat c behind the pitch line along the chord, plus Berman & Wang's rotational damping torque
  tau = -(pi/16) rho c**4 (mu1 f + mu2 ``|Omega|``) Omega (eqs. 20-23).

Two variants:

``"small-angle"``
    The paper's eqs. (13)-(19): first order in the induced angle alpha_i = w_eff/``|U|``, ``|V|`` ~
    ``|U|``.
``"exact"``
    The exact inflow angle psi = atan2(-w_eff, U) and speed ``|V|`` = sqrt(U**2 + w_eff**2).

Both agree to first order in w_eff/``|U|``, and differ at second order (tested), on either stroke
and
also where U opposes the stroke (s != sign(U), near reversal with u != 0). Neither is linearised
in (u, w, q): the linearised model of eq. (29) lives elsewhere and is checked against finite
differences of these loads.

Span integration
----------------
Every section load is a polynomial in the chord, ``load = sum_n c(r)**n g_n(r)`` (n = 1..4; the
coefficients g_n do not depend on c), and Ellington's beta chord
c(r) = c_bar/B(p, q) r_hat**(p-1) (1 - r_hat)**(q-1) is singular at the root when p < 1. Each
power is therefore integrated by Gauss-Jacobi quadrature whose weight is exactly
r_hat**(n(p-1)) (1 - r_hat)**(n(q-1)): polynomial g_n are integrated exactly, and the singularity
costs nothing (:func:`span_quadrature`). The small-angle g_n are polynomials in r except for the
kink of ``|U|`` where U changes sign, which is handled in closed form, so that variant is integrated
exactly at every state; the exact variant converges geometrically with the number of nodes
(:class:`BladeElementModel`).

Linearised loads
----------------
The constants of the linearised loads of eq. (29), K_mn = rho A I_mn / 2 and their kin
(:func:`aero_constants`), live here too: they are the same aerodynamics, integrated over the span
in closed form, and both :mod:`flapping.model.derivation` and :mod:`flapping.model.derivatives`
use them.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike
from scipy import special

import flapping._validation as _validation
from flapping.model.kinematics import check_alpha_m, check_amplitude, stroke_sign_scalar
from flapping.model.kinematics import stroke_sign as _kinematic_stroke_sign
from flapping.model.morphology import Insect, _span_integral

__all__ = [
    "VARIANTS",
    "MAX_NODES",
    "check_nodes",
    "SpanQuadrature",
    "span_quadrature",
    "trim_angle_of_attack",
    "AeroConstants",
    "aero_constants",
    "section_loads",
    "BladeElementModel",
    "wing_loads",
]

Variant = Literal["small-angle", "exact"]

#: The aerodynamic model variants: the paper's small induced angle, or exact inflow.
VARIANTS: tuple[Variant, ...] = ("small-angle", "exact")

#: Scalar types of the fast path of :meth:`BladeElementModel.loads` (NumPy float64 is a float).
_REAL = (float, int)

#: Highest power of the chord in a section load (the damping torque, c**4).
_MAX_CHORD_POWER = 4


# =========================================================================== span quadrature
#: Most span quadrature nodes a blade-element model may ask for: a cap on the work (building a
#: model evaluates its loads at every node about 25 times; scipy's Gauss-Jacobi rule for 1e9
#: nodes would allocate gigabytes). The default 32 nodes meet the loads to ~1e-6 relative, 128
#: to rounding for the smooth sections; 4096 is far beyond any accuracy float64 can show.
MAX_NODES = 1 << 12


def check_nodes(n_nodes: object) -> int:
    """``n_nodes`` as an int in [2, :data:`MAX_NODES`], or a ValueError naming it."""
    return _validation.integer("n_nodes", n_nodes, low=2, high=MAX_NODES)


@dataclass(frozen=True, eq=False)
class SpanQuadrature:
    """Gauss-Jacobi rules for ``2 int_0^R c(r)**n g(r) dr`` (both wings), n = 0..4.

    ``weights[n] @ g(nodes[n])`` approximates the integral and is exact when g is a polynomial of
    degree < 2 * n_nodes: the chord power
    c**n = (c_bar/B(p,q))**n r_hat**a_n (1 - r_hat)**b_n, a_n = n(p-1), b_n = n(q-1), is the
    Gauss-Jacobi weight, and the chord factor and the factor 2 for the wing pair are inside the
    weights. Rules are ``None`` when the integral diverges for the planform (a_n <= -1: a root
    singularity too strong).

    Attributes
    ----------
    n_nodes : int
        Nodes per rule.
    nodes, weights : tuple of (numpy.ndarray or None)
        One rule per chord power n = 0..4 ([m] and [m^(n+1)]).
    """

    n_nodes: int
    nodes: tuple[np.ndarray | None, ...]
    weights: tuple[np.ndarray | None, ...]

    def integrate(self, n: int, values: np.ndarray | Sequence[float]) -> float:
        """``2 int_0^R c**n g dr`` from ``values = g(nodes[n])``.

        Raises
        ------
        ValueError
            If the integral diverges for this chord distribution (no rule for power n).
        """
        weights = self.weights[n]
        if weights is None:
            raise ValueError(f"2 int_0^R c(r)**{n} g(r) dr diverges for this chord distribution")
        return float(weights @ np.asarray(values, dtype=float))


def span_quadrature(insect: Insect, n_nodes: int = 32) -> SpanQuadrature:
    """Gauss-Jacobi span quadrature adapted to the insect's beta chord distribution.

    With r = R r_hat, r_hat = (1 + x)/2 and a_n = n(p - 1), b_n = n(q - 1)::

        2 int_0^R c**n g dr = 2 R (c_bar/B(p,q))**n 2**-(a_n+b_n+1)
                              int_-1^1 (1 - x)**b_n (1 + x)**a_n g dx,

    a Gauss-Jacobi integral with (scipy's convention) alpha = b_n (tip), beta = a_n (root).
    Rules are cached per (R, c_bar, p, q, n_nodes); nothing is computed at import.

    Parameters
    ----------
    insect : Insect
        Supplies R, c_bar and the beta shape (p, q).
    n_nodes : int
        Nodes per rule, in [2, :data:`MAX_NODES`].

    Returns
    -------
    SpanQuadrature

    Raises
    ------
    ValueError
        If n_nodes is not an integer >= 2.
    """
    _validation.instance("insect", insect, Insect)
    n_nodes = check_nodes(n_nodes)
    return _span_quadrature_cached(
        float(insect.semi_span), float(insect.mean_chord),
        float(insect.beta_p), float(insect.beta_q), n_nodes,
    )


@functools.lru_cache(maxsize=64)
def _span_quadrature_cached(R: float, c_bar: float, p: float, q: float,
                            n_nodes: int) -> SpanQuadrature:
    log_scale = math.log(c_bar) - special.betaln(p, q)
    nodes: list[np.ndarray | None] = []
    weights: list[np.ndarray | None] = []
    for n in range(_MAX_CHORD_POWER + 1):
        a, b = n * (p - 1.0), n * (q - 1.0)
        if a <= -1.0 or b <= -1.0:
            nodes.append(None)
            weights.append(None)
            continue
        # scipy: int_-1^1 (1 - x)**alpha (1 + x)**beta f(x) dx; here alpha = b (tip), beta = a.
        x, wx = special.roots_jacobi(n_nodes, b, a)
        nodes.append(_frozen(0.5 * R * (1.0 + x)))
        weights.append(_frozen(2.0 * math.exp(n * log_scale) * R * 2.0 ** -(a + b + 1.0) * wx))
    return SpanQuadrature(n_nodes, tuple(nodes), tuple(weights))


def _frozen(array: np.ndarray) -> np.ndarray:
    array.setflags(write=False)
    return array


def _check_convergent(insect: Insect, quad: SpanQuadrature) -> None:
    """Raise if a span integral the loads need diverges (root singularity of c(r)**n)."""
    needed = [1, 2]
    if insect.center_of_pressure != 0.0:
        needed.append(3)
    if insect.mu1 != 0.0 or insect.mu2 != 0.0:
        needed.append(4)
    for n in needed:
        if quad.weights[n] is None:
            raise ValueError(
                f"the span integral of c(r)**{n} diverges for {insect.name} (beta shape "
                f"p={insect.beta_p:.4g}: root exponent {n}(p-1) <= -1); the loads are infinite"
            )


def _stations(quad: SpanQuadrature) -> tuple[np.ndarray, np.ndarray]:
    """Span stations of the c, c^2, c^3 rules side by side, and their weight matrix.

    Column j of the weight matrix holds the rule of chord power j + 1 (j < 3) on its own
    stations, zero elsewhere; columns 3..5 the same times r (for the r sin(phi) moment arms).
    """
    rules = [(n, quad.nodes[n], quad.weights[n]) for n in (1, 2, 3)]
    present = [(n, x, w) for n, x, w in rules if x is not None and w is not None]
    r = np.concatenate([x for _, x, _ in present])
    weights = np.zeros((r.size, 6))
    for k, (n, x, w) in enumerate(present):
        rows = slice(k * quad.n_nodes, (k + 1) * quad.n_nodes)
        weights[rows, n - 1] = w
        weights[rows, n + 2] = w * x
    return r, weights


def _partial_span_moments(insect: Insect) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Beta parameters (a, b) and totals I_mn of the incomplete span moments of the sign correction.

    2 int_0^x r^m c^n dr = I_mn betainc(m + n(p-1) + 1, n(q-1) + 1, x/R), for the (m, n) of
    :func:`_add_sign_correction`.
    """
    moments = ((0, 1), (1, 1), (2, 1), (3, 1), (0, 2), (1, 2), (2, 2))
    p, q = insect.beta_p, insect.beta_q
    return (
        _frozen(np.array([m + n * (p - 1.0) + 1.0 for m, n in moments])),
        _frozen(np.array([n * (q - 1.0) + 1.0 for m, n in moments])),
        _frozen(np.array([insect.span_integral(m, n) for m, n in moments])),
    )


def _load_constants(insect: Insect, alpha_m: float, i04: float) -> tuple[float, ...]:
    """The constants of :meth:`BladeElementModel._loads`, in the order it unpacks them."""
    am = alpha_m
    return (
        2.0 * math.pi * insect.frequency,
        math.sin(2.0 * am), math.cos(2.0 * am), math.sin(am) ** 2, math.cos(am) ** 2,
        insect.air_density * insect.lift_slope,                 # rho A
        insect.air_density * math.pi * (0.75 - insect.pitch_axis),  # rho Gamma/(c^2 Omega)
        insect.hinge_offset,
        insect.center_of_pressure * math.sin(am),       # z_cp / c
        insect.center_of_pressure * math.cos(am),       # |chordwise x_cp offset| / c
        -(math.pi / 16.0) * insect.air_density * i04,   # damping torque / (...) both wings
        insect.mu1 * insect.frequency, insect.mu2,
    )


# =========================================================================== trim
def trim_angle_of_attack(insect: Insect, amplitude: float | None = None) -> float:
    """Mid-stroke angle of attack alpha_m that balances the weight with mean LEV lift, eq. (40).

    At zero body state the vertical force of both wings is
    Z0(t) = -K21 phi_dot(t)**2 sin(2 alpha_m) with K21 = rho A I21 / 2 (eq. 26 integrated), on
    both half-strokes. With phi = Phi cos(2 pi f t) the cycle mean of phi_dot**2 is
    2 pi**2 f**2 Phi**2, so mean(Z0) = -m g requires

        sin(2 alpha_m) = m g / (2 pi**2 f**2 Phi**2 K21) = m g T**2 / (pi**2 rho A Phi**2 I21).

    The root in (0, pi/4] is returned (the other, pi/2 - alpha_m, has the same LEV lift and more
    drag).

    Parameters
    ----------
    insect : Insect
        Mass, gravity, density, frequency, lift slope A (eq. 4) and planform (I21).
    amplitude : float, optional
        Stroke amplitude Phi [rad] in (0, pi/2]; default ``insect.stroke_amplitude``.

    Returns
    -------
    float
        alpha_m [rad] in (0, pi/4].

    Raises
    ------
    ValueError
        If amplitude is outside (0, pi/2], or if the weight exceeds the largest mean lift the
        wings can make at this amplitude (sin(2 alpha_m) would exceed 1).
    """
    _validation.instance("insect", insect, Insect)
    amplitude = _amplitude(insect, amplitude)
    k21 = 0.5 * insect.air_density * insect.lift_slope * insect.span_integral(2, 1)
    max_mean_lift = 2.0 * math.pi**2 * insect.frequency**2 * amplitude**2 * k21
    ratio = insect.weight / max_mean_lift
    if ratio > 1.0:
        raise ValueError(
            f"{insect.name}: weight m g = {insect.weight:.6g} N exceeds the largest mean lift "
            f"{max_mean_lift:.6g} N (alpha_m = 45 deg) at amplitude {amplitude!r} rad "
            f"({math.degrees(amplitude):.4g} deg): eq. (40) needs sin(2 alpha_m) = {ratio:.6g} > 1"
        )
    return 0.5 * math.asin(ratio)


# =========================================================================== linearised loads
@dataclass(frozen=True)
class AeroConstants:
    """The constants of the linearised loads (after eq. 29), SI units.

    Attributes
    ----------
    K : dict
        K[(m, n)] = rho A I_mn / 2.
    Krot : dict
        Krot[(m, n)] = rho pi (3/4 - x0_hat) I_mn.
    Knu : float
        (pi/16) rho I_04.
    x_hat, x_h, mu1, f, m, Iy : float
        Centre of pressure (fraction of chord), hinge offset [m], damping coefficient, flapping
        frequency [Hz], mass [kg], pitch inertia [kg m^2].
    h_w : float
        Hinge height above the centre of gravity [m].
    """

    K: dict[tuple[int, int], float]
    Krot: dict[tuple[int, int], float]
    Knu: float
    x_hat: float
    x_h: float
    mu1: float
    f: float
    m: float
    Iy: float
    h_w: float = 0.0


def aero_constants(insect: Insect) -> AeroConstants:
    """The constants K_mn, Krot_mn and K_nu of the linearised loads (after eq. 29).

    Parameters
    ----------
    insect : Insect
        Morphology; the span integrals I_mn come from its closed form (beta functions).

    Returns
    -------
    AeroConstants
        K[(m, n)] = rho A I_mn / 2 and Krot[(m, n)] = rho pi (3/4 - x0_hat) I_mn for m = 0..3,
        n = 1..4 where I_mn converges; K_nu = (pi/16) rho I_04; and the insect's x_hat, x_h,
        mu1, f, m, I_y.

    Raises
    ------
    ValueError
        If the rotational damping is on (mu1 or mu2 > 0) but I_04 diverges for this planform.
    """
    _validation.instance("insect", insect, Insect)
    K, Krot, knu = _load_tables(insect.air_density, insect.lift_slope, 0.75 - insect.pitch_axis,
                                insect.semi_span, insect.mean_chord, insect.beta_p, insect.beta_q)
    if knu is None:
        if insect.mu1 != 0.0 or insect.mu2 != 0.0:
            raise ValueError(
                f"the rotational damping needs I_04 = 2 int c^4 dr, which diverges for this "
                f"planform (r1={insect.r1!r}, r2={insect.r2!r}: beta shape "
                f"p={insect.beta_p:.4g} <= 3/4); choose r1, r2 with p > 3/4 or set mu1 = mu2 = 0")
        knu = 0.0  # no rotational damping: its diverging span integral is never needed
    return AeroConstants(
        K=dict(K),
        Krot=dict(Krot),
        Knu=knu,
        x_hat=insect.center_of_pressure,
        x_h=insect.hinge_offset,
        mu1=insect.mu1,
        f=insect.frequency,
        m=insect.mass,
        Iy=insect.pitch_inertia,
        h_w=insect.hinge_height,
    )


@functools.lru_cache(maxsize=256)
def _load_tables(rho: float, A: float, kappa: float, semi_span: float, mean_chord: float,
                 p: float, q: float) -> tuple[tuple[tuple[tuple[int, int], float], ...],
                                              tuple[tuple[tuple[int, int], float], ...],
                                              float | None]:
    """(K, Krot) as items, and K_nu (None where I_04 diverges), per air and planform (cached: a
    sweep over the frequency or the mass asks the same tables at every point)."""
    I = _span_table(semi_span, mean_chord, p, q)
    K = tuple((k, 0.5 * rho * A * v) for k, v in I)
    Krot = tuple((k, rho * math.pi * kappa * v) for k, v in I)
    knu = dict(I).get((0, 4))
    return K, Krot, None if knu is None else math.pi / 16.0 * rho * knu


@functools.lru_cache(maxsize=256)
def _span_table(semi_span: float, mean_chord: float, p: float,
                q: float) -> tuple[tuple[tuple[int, int], float], ...]:
    """((m, n), I_mn) for m = 0..3, n = 1..4 where I_mn converges, per planform (cached: a
    sweep over any other field asks the same table at every point)."""
    return tuple(((m, n), _span_integral(semi_span, mean_chord, p, q, float(m), float(n)))
                 for m in range(4) for n in range(1, 5) if (m + 1 + n * (p - 1.0)) > 0)


# =========================================================================== section loads
def _lev_coefficients(U, w_eff, sin_2ag, cos_2am, sin_am2, cos_am2, variant, sign_u=None):
    """Leading-edge-vortex force coefficients of a section, per unit span, chord and rho A.

    Returns (a, b) with F_xi = rho A c a and F_z = rho A c b for the LEV lift and drag of one
    section (the rotational lift, c**2 terms, is added by the callers: rho Gamma (w_eff, -U)).
    Inputs broadcast; nothing is validated. In the small-angle variant, ``sign_u`` (+1 or -1)
    replaces ``|U|`` by sign_u * U, which makes the coefficients polynomial in r (the span
    integration then adds the correction where sign(U) differs).
    """
    if variant == "small-angle":
        # eqs. (17)-(19), first order in w_eff/|U|, signs restored for both strokes:
        # F_xi = -rho A c (U|U| sin^2 alpha_m + |U| w_eff sin(2 alpha_g)/2)
        # F_z  = -rho A c (U|U| sin(2 alpha_g)/2 + |U| w_eff cos^2 alpha_m)
        abs_u = np.abs(U) if sign_u is None else sign_u * U
        uu = U * abs_u
        aw = abs_u * w_eff
        a = -(uu * sin_am2 + (0.5 * sin_2ag) * aw)
        b = -((0.5 * sin_2ag) * uu + cos_am2 * aw)
        return a, b
    # Exact inflow: with psi = atan2(-w_eff, U) and alpha = alpha_g - psi, the products
    # |V|^2 sin(2 alpha) and |V|^2 cos(2 alpha) are quadratic forms in (U, w_eff); the lift
    # direction is n = (w_eff, -U)/|V| and the drag direction -V_hat = -(U, w_eff)/|V|. With
    # l = rho A c |V|^2 sin(2 alpha)/2 and d = rho A c |V|^2 sin^2(alpha) = rho A c |V|^2
    # (1 - cos(2 alpha))/2 no trigonometric function is needed.
    uw = U * w_eff
    uu = U * U
    ww = w_eff * w_eff
    diff = uu - ww
    v2 = uu + ww
    lift = sin_2ag * diff + (2.0 * cos_2am) * uw                 # 2 l / (rho A c)
    drag = v2 - cos_2am * diff + (2.0 * sin_2ag) * uw            # 2 d / (rho A c)
    # Where |V| = 0, lift = drag = 0 and the tiny offset keeps 0 * finite = 0.
    half_inv_v = 0.5 * (v2 + 1e-300) ** -0.5
    a = (lift * w_eff - drag * U) * half_inv_v
    b = -(lift * U + drag * w_eff) * half_inv_v
    return a, b


def section_loads(
    r: ArrayLike, chord: ArrayLike, phi: ArrayLike, phi_dot: ArrayLike, s: ArrayLike,
    u: ArrayLike, w: ArrayLike, q: ArrayLike, alpha_m: float, insect: Insect,
    variant: str = "small-angle",
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Aerodynamic loads per unit span on one wing section, eqs. (9)-(23), nonlinear in (u, w, q).

    Parameters
    ----------
    r : array_like
        Radius of the section from the wing hinge [m].
    chord : array_like
        Chord of the section [m] (broadcasts with r; e.g. ``insect.chord(r)``).
    phi, phi_dot : float or array_like
        Flapping angle [rad] and rate [rad/s].
    s : float or array_like
        Stroke sign, +1 forward (geometric pitch alpha_m), -1 backward (pi - alpha_m), eq. (11).
    u, w, q : float or array_like
        Body velocities [m/s] (x forward, z down) and pitch rate [rad/s] (nose-up positive).
    alpha_m : float
        Mid-stroke angle of attack [rad], in (0, pi/2).
    insect : Insect
        Air density, lift slope A, x0_hat, x_hat, x_h, mu1, mu2, frequency.
    variant : {"small-angle", "exact"}
        Induced-angle treatment (see the module docstring).

    Returns
    -------
    F_x, F_z, M : numpy.ndarray
        Body-axis force per unit span [N/m] (x forward, z down) and pitching moment per unit span
        about the centre of gravity [N m/m] (nose-up positive), for one wing.

    Raises
    ------
    ValueError
        If variant is unknown, an input is not finite, s is not +1 or -1, or alpha_m is outside
        (0, pi/2).

    Notes
    -----
    F_x = F_xi cos(phi). The centre of pressure is at x_cp = x_h + r sin(phi)
    - x_hat c cos(alpha_g) cos(phi), z_cp = x_hat c sin(alpha_g), and
    M = z_cp F_x - x_cp F_z + tau cos(phi), tau = -(pi/16) rho c**4 (mu1 f + mu2 ``|Omega|``) Omega
    with Omega = q cos(phi) (eqs. 20-23). With the hinge a height h_w above the centre of gravity
    (``insect.hinge_height``; z down) the section moves forward at r phi_dot + (u - q h_w) cos(phi)
    and z_cp = x_hat c sin(alpha_g) - h_w. ``phi`` is the whole flapping angle (with any mean
    stroke angle already added).
    """
    variant = _validation.choice("variant", variant, VARIANTS)
    names = ("r", "chord", "phi", "phi_dot", "s", "u", "w", "q")
    values = (r, chord, phi, phi_dot, s, u, w, q)
    ra, ca, phia, phi_dota, sa, ua, wa, qa = (
        _validation.array(n, v) for n, v in zip(names, values, strict=True))
    _stroke_signs(sa)
    _validation.instance("insect", insect, Insect)
    return _section_loads(ra, ca, phia, phi_dota, sa, ua, wa, qa, check_alpha_m(alpha_m),
                          insect, variant)


def _section_loads(r: np.ndarray, c: np.ndarray, phi: np.ndarray, phi_dot: np.ndarray,
                   s: np.ndarray, u: np.ndarray, w: np.ndarray, q: np.ndarray, alpha_m: float,
                   insect: Insect, variant: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`section_loads` for validated inputs."""
    rho = insect.air_density
    cphi, sphi = np.cos(phi), np.sin(phi)
    h_w = insect.hinge_height  # the hinge at z = -h_w moves forward at u - q h_w
    U = r * phi_dot + (u - q * h_w) * cphi
    w_eff = w - q * (r * sphi + insect.hinge_offset)
    omega = q * cphi
    k = math.pi * (0.75 - insect.pitch_axis) * omega
    a1, b1 = _lev_coefficients(
        U, w_eff, s * math.sin(2.0 * alpha_m), math.cos(2.0 * alpha_m),
        math.sin(alpha_m) ** 2, math.cos(alpha_m) ** 2, variant)
    rho_a = rho * insect.lift_slope
    a1, b1 = rho_a * a1, rho_a * b1
    # Rotational lift rho |V| Gamma along n = (w_eff, -U)/|V|, Gamma = c^2 k: the same in both
    # variants.
    a2 = rho * k * w_eff
    b2 = -rho * k * U
    f_x = cphi * (c * a1 + c * c * a2)
    f_z = c * b1 + c * c * b2
    x_hat = insect.center_of_pressure
    x_cp = insect.hinge_offset + r * sphi - x_hat * c * (s * math.cos(alpha_m)) * cphi
    z_cp = x_hat * c * math.sin(alpha_m) - h_w
    tau = -(math.pi / 16.0) * rho * c**4 * (
        insect.mu1 * insect.frequency + insect.mu2 * np.abs(omega)) * omega
    moment = z_cp * f_x - x_cp * f_z + tau * cphi
    f_x, f_z, moment = np.broadcast_arrays(f_x, f_z, moment)
    return f_x, f_z, moment


# =========================================================================== wing loads
@dataclass(frozen=True, init=False)
class BladeElementModel:
    """Blade-element loads of both wings for one insect, trim and variant, for ODE right-hand sides.

    Everything that depends only on the insect, alpha_m, the amplitude and the quadrature is
    computed once at construction; :meth:`loads` then costs a few vectorised operations on
    ``3 n_nodes`` span stations (about 15-30 microseconds).

    Span integration is exact (to rounding) for the small-angle variant at any state: its section
    loads are polynomials in r times powers of the chord, except for ``|U|``, which has a kink at
    the
    station r* = -u cos(phi)/phi_dot where U changes sign. The loads are integrated with ``|U|``
    replaced by sigma U (sigma the sign of U on most of the span; polynomial, so Gauss-Jacobi is
    exact), and the difference, non-zero only between the root or tip and r*, is added in closed
    form with incomplete beta functions. The exact variant's integrand sqrt(U**2 + w_eff**2) is
    smooth but varies on the scale ``|w_eff/phi_dot|`` about r*; its quadrature converges
    geometrically in n_nodes, slowly when w_eff is small near r* (tested).

    Parameters
    ----------
    insect : Insect
    alpha_m : float
        Mid-stroke angle of attack [rad], in (0, pi/2) (e.g. :func:`trim_angle_of_attack`).
    amplitude : float, optional
        Stroke amplitude Phi [rad] in (0, pi/2]; default ``insect.stroke_amplitude``.
    variant : {"small-angle", "exact"}
    n_nodes : int
        Gauss-Jacobi nodes per chord power, in [2, :data:`MAX_NODES`] (default 32).

    Attributes
    ----------
    insect, alpha_m, amplitude, variant, n_nodes
        The arguments, validated (alpha_m and amplitude as floats).

    Raises
    ------
    ValueError
        For an unknown variant, n_nodes < 2, alpha_m or amplitude out of range, or a planform
        whose root singularity makes a needed span integral diverge.
    """

    insect: Insect
    alpha_m: float
    amplitude: float
    variant: str
    n_nodes: int
    _partial_moments: tuple[np.ndarray, np.ndarray, np.ndarray] = field(
        init=False, repr=False, compare=False)
    _r: np.ndarray = field(init=False, repr=False, compare=False)
    _weights: np.ndarray = field(init=False, repr=False, compare=False)
    _weight_sums: np.ndarray = field(init=False, repr=False, compare=False)
    _weight_moments: np.ndarray = field(init=False, repr=False, compare=False)
    _consts: tuple[float, ...] = field(init=False, repr=False, compare=False)

    def __init__(self, insect: Insect, alpha_m: float, amplitude: float | None = None,
                 variant: str = "small-angle", n_nodes: int = 32) -> None:
        _validation.instance("insect", insect, Insect)
        n_nodes = check_nodes(n_nodes)
        alpha_m = check_alpha_m(alpha_m)
        values = dict(
            insect=insect, alpha_m=alpha_m, amplitude=_amplitude(insect, amplitude),
            variant=_validation.choice("variant", variant, VARIANTS), n_nodes=n_nodes)
        quad = span_quadrature(insect, n_nodes)
        _check_convergent(insect, quad)
        r, weights = _stations(quad)
        i04 = float(quad.weights[4].sum()) if quad.weights[4] is not None else 0.0
        values.update(
            _partial_moments=_partial_span_moments(insect),
            _r=_frozen(r),
            _weights=_frozen(weights),
            _weight_sums=_frozen(weights.sum(axis=0)),
            _weight_moments=_frozen(r @ weights),
            _consts=_load_constants(insect, alpha_m, i04),
        )
        for name, value in values.items():
            object.__setattr__(self, name, value)

    @property
    def period(self) -> float:
        """Flapping period T [s]."""
        return self.insect.period

    def loads(self, t: ArrayLike, u: ArrayLike, w: ArrayLike, q: ArrayLike,
              s: ArrayLike | None = None) -> np.ndarray:
        """Total aerodynamic force and moment of both wings, (X, Z, M), eqs. (17)-(23) integrated.

        Parameters
        ----------
        t : float or array_like
            Time [s]; phi = phi_bar + Phi cos(2 pi f t) (eq. 39 with the insect's
            ``stroke_mean`` phi_bar).
        u, w, q : float or array_like
            Body state (broadcasts with t): [m/s], [m/s], [rad/s].
        s : float or array_like, optional
            Stroke sign +1/-1 overriding ``sign(phi_dot(t))`` (e.g. exactly at stroke reversal,
            or per half-stroke segment). Default :func:`flapping.model.kinematics.stroke_sign`.

        Returns
        -------
        numpy.ndarray
            ``(X, Z, M)`` [N, N, N m] in body axes (x forward, z down, nose-up moment about the
            CG); shape ``(3,) + broadcast shape`` of the inputs.

        Raises
        ------
        ValueError
            If an input is not finite or s is not +1 or -1.
        """
        if (isinstance(t, _REAL) and isinstance(u, _REAL) and isinstance(w, _REAL)
                and isinstance(q, _REAL) and (s is None or isinstance(s, _REAL))):
            # The fast path of ODE right-hand sides: the same checks as below, inline (a call
            # into the validation module per evaluation would cost more than the loads).
            if not (math.isfinite(t) and math.isfinite(u) and math.isfinite(w)
                    and math.isfinite(q)):
                for name, value in (("t", t), ("u", u), ("w", w), ("q", q)):
                    _validation.real(name, value)
            if s is None:
                s = stroke_sign_scalar(t, self.insect.frequency)
            elif s != 1 and s != -1:
                _stroke_signs(s)
            return np.array(self._loads(float(t), float(u), float(w), float(q), float(s)))
        # Arrays (or NumPy scalars): validate, broadcast, and evaluate point by point.
        ta, ua, wa, qa = (_validation.array(n, v) for n, v in zip("tuwq", (t, u, w, q),
                                                                   strict=True))
        if s is None:
            sa = _kinematic_stroke_sign(ta, self.insect.frequency)
        else:
            sa = _stroke_signs(_validation.array("s", s))
        ta, ua, wa, qa, sa = np.broadcast_arrays(ta, ua, wa, qa, sa)
        out = np.empty((3,) + ta.shape)
        for index in np.ndindex(ta.shape):
            out[(slice(None),) + index] = self._loads(
                float(ta[index]), float(ua[index]), float(wa[index]), float(qa[index]),
                float(sa[index]))
        return out

    def wing_resultants(self, U0: float, U1: float, W0: float, W1: float, omega: float,
                        s: float) -> tuple[float, ...]:
        """Span integrals of ONE wing's section loads for strip speeds linear along the span.

        The six-degree-of-freedom model (:mod:`flapping.model.sixdof`) gives each wing's strip
        speeds U = U0 + U1 r, w_eff = W0 + W1 r and its span-axis pitch rate ``omega``
        (:mod:`flapping.model.sixdof_derivation`, step 3); the section law is this model's own,
        integrated as :meth:`loads` integrates it (exactly for the small-angle variant).

        Parameters
        ----------
        U0, U1, W0, W1, omega : float
            Strip speeds [m/s, 1/s, m/s, 1/s] and pitch rate [rad/s] of the wing (trusted).
        s : float
            Stroke sign, +1 or -1.

        Returns
        -------
        tuple of float
            (T0, T1, Tc, N0, N1, Nc, Q): the integrals over the wing of F_t, r F_t, c F_t, F_n,
            r F_n, c F_n (tangential and normal force per unit span, along t_k and n) and of the
            damping torque about the span axis (:data:`~flapping.model.sixdof_derivation.
            RESULTANT_NAMES`).
        """
        (_, sin_2am, cos_2am, sin_am2, cos_am2, rho_a, rho_k, _, _, _, damping, mu1f,
         mu2) = self._consts
        sin_2ag = s * sin_2am
        r, W = self._r, self._weights
        if self.variant == "small-angle":
            sigma, piece = _sign_split(U1, U0, s, self.insect.semi_span)
        else:
            sigma, piece = None, None
        a1, b1 = _lev_coefficients(U1 * r + U0, W0 + W1 * r, sin_2ag, cos_2am, sin_am2,
                                   cos_am2, self.variant, sign_u=sigma)
        A1 = (a1 @ W).tolist()
        B1 = (b1 @ W).tolist()
        if piece is not None and sigma is not None:
            _add_sign_correction(A1, B1, self._partial_moments, self.insect.semi_span, piece,
                                 sigma, U1, U0, W0, -W1, sin_2ag, sin_am2, cos_am2)
        # Rotational lift rho Gamma (w_eff, -U), Gamma = c^2 rho_k omega / rho: linear in r.
        k = rho_k * omega
        S0, S1 = self._weight_sums, self._weight_moments
        A2 = (k * (W0 * S0 + W1 * S1)).tolist()
        B2 = (-k * (U1 * S1 + U0 * S0)).tolist()
        # The weights integrate both wings: halve. Columns: c, c^2, c^3, then times r.
        return (0.5 * (rho_a * A1[0] + A2[1]), 0.5 * (rho_a * A1[3] + A2[4]),
                0.5 * (rho_a * A1[1] + A2[2]), 0.5 * (rho_a * B1[0] + B2[1]),
                0.5 * (rho_a * B1[3] + B2[4]), 0.5 * (rho_a * B1[1] + B2[2]),
                0.5 * damping * (mu1f + mu2 * abs(omega)) * omega)

    def _loads(self, t: float, u: float, w: float, q: float,
               s: float) -> tuple[float, float, float]:
        """(X, Z, M) for trusted scalar inputs."""
        (omega_f, sin_2am, cos_2am, sin_am2, cos_am2, rho_a, rho_k, x_h, zh, xc, damping,
         mu1f, mu2) = self._consts
        amplitude = self.amplitude
        phase = omega_f * t
        phi = amplitude * math.cos(phase)
        if self.insect.stroke_mean != 0.0:  # phi = phi_bar + Phi cos(2 pi f t)
            phi += self.insect.stroke_mean
        phi_dot = -omega_f * amplitude * math.sin(phase)
        cphi, sphi = math.cos(phi), math.sin(phi)
        sin_2ag = s * sin_2am
        # U = phi_dot r + u_c and w_eff = w_0 - q_s r (eqs. 9, 12) are linear in r; the hinge,
        # h_w above the centre of gravity, moves forward at u - q h_w.
        h_w = self.insect.hinge_height
        u_c = (u - q * h_w) * cphi if h_w != 0.0 else u * cphi
        w_0 = w - q * x_h
        q_s = q * sphi
        r = self._r
        W = self._weights
        if self.variant == "small-angle":
            # |U| is integrated exactly as sigma U (polynomial in r) plus a correction on the
            # part of the span where sign(U) = -sigma; sigma is the sign of U on most of the span.
            sigma, piece = _sign_split(phi_dot, u_c, s, self.insect.semi_span)
        else:
            sigma, piece = None, None
        a1, b1 = _lev_coefficients(phi_dot * r + u_c, w_0 - q_s * r, sin_2ag, cos_2am, sin_am2,
                                   cos_am2, self.variant, sign_u=sigma)
        # Span integrals: columns are the c, c^2, c^3 rules, then the same times r.
        A1 = (a1 @ W).tolist()
        B1 = (b1 @ W).tolist()
        if piece is not None and sigma is not None:
            _add_sign_correction(A1, B1, self._partial_moments, self.insect.semi_span, piece,
                                 sigma, phi_dot, u_c, w_0, q_s, sin_2ag, sin_am2, cos_am2)
        # Rotational lift rho Gamma (w_eff, -U) with Gamma = c^2 k: linear in r, so integrated with
        # the precomputed sums of the weights (S0) and of r times the weights (S1).
        omega = q * cphi
        k = rho_k * omega
        S0, S1 = self._weight_sums, self._weight_moments
        A2 = (k * (w_0 * S0 - q_s * S1)).tolist()
        B2 = (-k * (phi_dot * S1 + u_c * S0)).tolist()
        a1_c, a1_c2 = rho_a * A1[0], rho_a * A1[1]
        b1_c, b1_c2, b1_cr = rho_a * B1[0], rho_a * B1[1], rho_a * B1[3]
        x_force = cphi * (a1_c + A2[1])
        z_force = b1_c + B2[1]
        # M' = z_cp F_x - x_cp F_z + tau cos(phi) with z_cp = zh c,
        # x_cp = x_h + r sin(phi) - xcp c, F_x = cos(phi)(c a1 + c^2 a2), F_z = c b1 + c^2 b2.
        xcp = xc * s * cphi
        zcp = zh * cphi
        moment = (
            -(x_h * b1_c + sphi * b1_cr)                                      # c
            + zcp * a1_c2 - (x_h * B2[1] + sphi * B2[4]) + xcp * b1_c2       # c^2
            + zcp * A2[2] + xcp * B2[2]                                       # c^3
            + damping * (mu1f + mu2 * abs(omega)) * omega * cphi              # c^4
        )
        if h_w != 0.0:  # every force acts h_w above the centre of gravity: z_cp -= h_w
            moment -= h_w * x_force
        return x_force, z_force, moment


def _sign_split(phi_dot: float, u_c: float, s: float,
                R: float) -> tuple[float, tuple[float, bool] | None]:
    """Where U = phi_dot r + u_c changes sign on [0, R]: (sigma, piece).

    sigma is the sign of U on the larger part of the span; piece = (x, root) describes the
    smaller part, [0, x] (root True) or [x, R], where sign(U) = -sigma; piece is None when U does
    not change sign inside the span (sigma is then its sign, or s if U = 0 throughout).
    """
    if phi_dot == 0.0:
        return (s if u_c == 0.0 else math.copysign(1.0, u_c)), None
    x = -u_c / phi_dot
    if not 0.0 < x < R:
        # No sign change inside: the sign at mid-span is everybody's sign.
        mid = phi_dot * 0.5 * R + u_c
        return (s if mid == 0.0 else math.copysign(1.0, mid)), None
    root_sign = math.copysign(1.0, u_c)        # sign of U on [0, x)
    if x <= 0.5 * R:
        return -root_sign, (x, True)
    return root_sign, (x, False)


def _add_sign_correction(A1: list[float], B1: list[float],
                         partial_moments: tuple[np.ndarray, np.ndarray, np.ndarray], R: float,
                         piece: tuple[float, bool], sigma: float, phi_dot: float, u_c: float,
                         w_0: float, q_s: float, sin_2ag: float, sin_am2: float,
                         cos_am2: float) -> None:
    """Add to the span integrals A1, B1 (lists, in place; per rho A) of the small-angle LEV
    coefficients computed with ``|U|`` := sigma U the correction on ``piece``, where ``|U|`` =
    -sigma U.

    There ``|U|`` - sigma U = -2 sigma U, so the coefficients of :func:`_lev_coefficients` change by
    Delta a = 2 sigma (sin^2(alpha_m) U^2 + sin(2 alpha_g) U w_eff / 2) and
    Delta b = 2 sigma (sin(2 alpha_g) U^2 / 2 + cos^2(alpha_m) U w_eff), quadratics in r whose
    integrals against c and c^2 over the piece are incomplete span moments (incomplete beta
    functions): exact. Only the c, c^2 and c r columns involve these coefficients.
    """
    x, root = piece
    a, b, full = partial_moments
    fraction = special.betainc(a, b, x / R) if root else special.betaincc(a, b, x / R)
    j01, j11, j21, j31, j02, j12, j22 = (full * fraction).tolist()
    # U^2 = c2 r^2 + c1 r + c0 and U w_eff = d2 r^2 + d1 r + d0.
    c2, c1, c0 = phi_dot * phi_dot, 2.0 * phi_dot * u_c, u_c * u_c
    d2, d1, d0 = -phi_dot * q_s, phi_dot * w_0 - u_c * q_s, u_c * w_0
    two_sigma, half_sin = 2.0 * sigma, 0.5 * sin_2ag
    pairs = ((c2, d2), (c1, d1), (c0, d0))
    e2, e1, e0 = (two_sigma * (sin_am2 * c + half_sin * d) for c, d in pairs)    # Delta a
    f2, f1, f0 = (two_sigma * (half_sin * c + cos_am2 * d) for c, d in pairs)    # Delta b
    A1[0] += e0 * j01 + e1 * j11 + e2 * j21
    A1[1] += e0 * j02 + e1 * j12 + e2 * j22
    A1[3] += e0 * j11 + e1 * j21 + e2 * j31   # int c r a: the yaw moment of six dof
    B1[0] += f0 * j01 + f1 * j11 + f2 * j21
    B1[1] += f0 * j02 + f1 * j12 + f2 * j22
    B1[3] += f0 * j11 + f1 * j21 + f2 * j31


@functools.lru_cache(maxsize=32)
def _cached_model(insect: Insect, alpha_m: float, amplitude: float, variant: str,
                  n_nodes: int) -> BladeElementModel:
    return BladeElementModel(insect, alpha_m, amplitude, variant, n_nodes)


def wing_loads(t: ArrayLike, state: Sequence[Any], insect: Insect, alpha_m: float, *,
               amplitude: float | None = None, variant: str = "small-angle",
               stroke_sign: ArrayLike | None = None, n_nodes: int = 32) -> np.ndarray:
    """Aerodynamic force and pitching moment of both wings, (X, Z, M), nonlinear in the state.

    A thin wrapper around :meth:`BladeElementModel.loads` (models are memoised per argument set;
    build a :class:`BladeElementModel` once for the fastest calls). Paper eqs. (9)-(23), integrated
    over the span of both wings as after eq. (29).

    Parameters
    ----------
    t : float or array_like
        Time [s].
    state : sequence of float or arrays
        (u, w, q) or (u, w, q, theta) [m/s, m/s, rad/s, rad]; theta does not enter the loads.
    insect : Insect
    alpha_m : float
        Mid-stroke angle of attack [rad] in (0, pi/2) (e.g. :func:`trim_angle_of_attack`).
    amplitude : float, optional
        Stroke amplitude Phi [rad] in (0, pi/2]; default ``insect.stroke_amplitude``.
    variant : {"small-angle", "exact"}
    stroke_sign : float, optional
        +1/-1, overrides the stroke sign from t (for evaluation at reversal / per segment).
    n_nodes : int
        Gauss-Jacobi nodes per chord power, in [2, :data:`MAX_NODES`].

    Returns
    -------
    numpy.ndarray
        (X, Z, M) [N, N, N m], body axes, shape ``(3,)`` for scalar inputs.

    Raises
    ------
    ValueError
        Unknown variant, n_nodes < 2, alpha_m or amplitude out of range, non-finite time or
        state, a state of wrong length, or a stroke sign other than +1/-1.
    """
    if len(state) not in (3, 4):
        raise ValueError(
            f"`state` must be (u, w, q) or (u, w, q, theta); got length {len(state)}")
    if len(state) == 4:
        _validation.array("theta", state[3])
    # NumPy scalars other than float64 (a float subclass) take the fast scalar path as floats.
    u, w, q = (float(v) if isinstance(v, (np.floating, np.integer)) else v for v in state[:3])
    if isinstance(t, (np.floating, np.integer)):
        t = float(t)
    # Validated before the cache, so that the cache is keyed on floats (True == 1.0 as a key).
    _validation.instance("insect", insect, Insect)
    model = _cached_model(insect, check_alpha_m(alpha_m), _amplitude(insect, amplitude),
                          _validation.choice("variant", variant, VARIANTS),
                          check_nodes(n_nodes))
    return model.loads(t, u, w, q, stroke_sign)


# =========================================================================== validation helpers
def _stroke_signs(s: Any) -> Any:
    """``s`` if every entry is +1 or -1 (the stroke sign of eq. 11), else a ValueError."""
    if not np.all((np.asarray(s) == 1.0) | (np.asarray(s) == -1.0)):
        raise ValueError(f"the stroke sign `s` must be +1 or -1; got {s!r}")
    return s


def _amplitude(insect: Insect, amplitude: object) -> float:
    """The stroke amplitude, ``insect.stroke_amplitude`` when None, validated."""
    return check_amplitude(insect.stroke_amplitude if amplitude is None else amplitude)

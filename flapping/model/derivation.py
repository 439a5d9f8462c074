"""SymPy derivation of the linearised aerodynamic loads: the stability derivatives X0 ... Mq.

This module *is* the derivation of the paper's Sec. II.C-D (eqs. 9-29), done by the computer algebra
system rather than by hand, step by step so that the book can show each step:

1. section kinematics: chordwise velocity U (eq. 9), effective vertical velocity w_eff (eq. 12),
   pitch rate about the span axis Omega, rotational circulation Gamma (eq. 5);
2. section forces to first order in the induced angle (eqs. 13-19) and the pitching moment per unit
   span (eqs. 20-23), for one wing;
3. first-order linearisation in the body states (u, w, q) about zero (eqs. 24-27);
4. integration over the span of both wings: every monomial r^m c^n becomes I_mn, and the constants
   are collected into K_mn = rho A I_mn / 2, Krot_mn = rho pi (3/4 - x0_hat) I_mn and
   K_nu = (pi/16) rho I_04 (after eq. 29);
5. the stability derivatives, normalised as in eq. (29): X0, Z0 [N], M0 [N m]; X_u ... Z_q per unit
   mass; M_u ... M_q per unit pitch inertia.

Stroke direction enters through s = sign(phi_dot) = +-1, constant on a half-stroke: ``|U|`` = s U
near
the zero state, sin(2 alpha_g) = s sin(2 alpha_m), cos(alpha_g) = s cos(alpha_m) with the
geometric pitch alpha_g of eq. (11). The results are reported with ``|phi_dot|`` = s phi_dot.

The numeric model does not import SymPy: :func:`generate_source` prints the derivatives as plain
NumPy code into ``flapping/model/_derivatives_generated.py``, which is committed, and a test checks
that regenerating it gives the same text. Importing :mod:`flapping` never runs this derivation.

Layering: this module imports the model's lower layers only (morphology, kinematics, and
:mod:`flapping.model.aerodynamics`, which holds the K constants that :func:`evaluate` substitutes);
the numeric :mod:`flapping.model.derivatives` sits above it and uses the generated code.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import sympy as sp
from numpy.typing import ArrayLike

import flapping._validation as _validation
from flapping.model.aerodynamics import aero_constants, trim_angle_of_attack
from flapping.model.kinematics import check_alpha_m, check_amplitude, flapping_angle, flapping_rate
from flapping.model.morphology import Insect

__all__ = [
    "DERIVATIVE_NAMES",
    "Symbols",
    "symbols",
    "section_loads",
    "linearise",
    "span_integrate",
    "collect_constants",
    "stability_derivatives",
    "paper_derivatives",
    "compare_with_paper",
    "vanishing_symmetry",
    "evaluate",
    "generate_source",
    "generate_numba_source",
]

#: Order of the derivatives in tables and in the generated code.
DERIVATIVE_NAMES = ("X0", "Z0", "M0", "Xu", "Xw", "Xq", "Zu", "Zw", "Zq", "Mu", "Mw", "Mq")


@dataclass(frozen=True)
class Symbols:
    """The SymPy symbols of the derivation (names as in the paper)."""

    r: sp.Symbol
    c: sp.Symbol
    phi: sp.Symbol
    phidot: sp.Symbol
    absphidot: sp.Symbol
    s: sp.Symbol
    s_omega: sp.Symbol
    alpha_m: sp.Symbol
    u: sp.Symbol
    w: sp.Symbol
    q: sp.Symbol
    rho: sp.Symbol
    A: sp.Symbol
    x0_hat: sp.Symbol
    kappa: sp.Symbol
    x_hat: sp.Symbol
    x_h: sp.Symbol
    h_w: sp.Symbol
    mu1: sp.Symbol
    mu2: sp.Symbol
    f: sp.Symbol
    m: sp.Symbol
    Iy: sp.Symbol

    def I(self, m: int, n: int) -> sp.Symbol:  # noqa: E743 - the paper's name
        """Span integral I_mn = 2 int_0^R r^m c^n dr (both wings)."""
        return sp.Symbol(f"I_{{{m}{n}}}", positive=True)

    def K(self, m: int, n: int) -> sp.Symbol:
        """K_mn = rho A I_mn / 2."""
        return sp.Symbol(f"K_{{{m}{n}}}", positive=True)

    def Krot(self, m: int, n: int) -> sp.Symbol:
        """Krot_mn = rho pi (3/4 - x0_hat) I_mn."""
        return sp.Symbol(f"K^{{rot}}_{{{m}{n}}}", real=True)

    @property
    def Knu(self) -> sp.Symbol:
        """K_nu = (pi/16) rho I_04."""
        return sp.Symbol(r"K_{\nu}", positive=True)


@lru_cache(maxsize=1)
def symbols() -> Symbols:
    """The symbols, created once."""
    pos = dict(positive=True)
    return Symbols(
        r=sp.Symbol("r", **pos),
        c=sp.Symbol("c", **pos),
        phi=sp.Symbol(r"\phi", real=True),
        phidot=sp.Symbol(r"\dot{\phi}", real=True),
        absphidot=sp.Symbol(r"|\dot{\phi}|", nonnegative=True),
        s=sp.Symbol("s", real=True),
        s_omega=sp.Symbol(r"s_{\Omega}", real=True),
        alpha_m=sp.Symbol(r"\alpha_m", positive=True),
        u=sp.Symbol("u", real=True),
        w=sp.Symbol("w", real=True),
        q=sp.Symbol("q", real=True),
        rho=sp.Symbol(r"\rho", **pos),
        A=sp.Symbol("A", **pos),
        x0_hat=sp.Symbol(r"\hat{x}_0", real=True),
        kappa=sp.Symbol(r"\kappa", real=True),
        x_hat=sp.Symbol(r"\hat{x}", real=True),
        x_h=sp.Symbol("x_h", real=True),
        h_w=sp.Symbol("h_w", real=True),
        mu1=sp.Symbol(r"\mu_1", nonnegative=True),
        mu2=sp.Symbol(r"\mu_2", nonnegative=True),
        f=sp.Symbol("f", **pos),
        m=sp.Symbol("m", **pos),
        Iy=sp.Symbol("I_y", **pos),
    )


def section_loads(hinge_height: bool = False) -> dict[str, sp.Expr]:
    """Steps 1-2: per-unit-span loads of one wing at radius r, small induced angle (eqs. 9-23).

    Parameters
    ----------
    hinge_height : bool
        Keep the hinge height h_w above the centre of gravity (the generated code does). Default
        False: the paper's model, h_w = 0, as the book shows it.

    Returns
    -------
    dict
        Named intermediate expressions, ending with ``"Fx"``, ``"Fz"`` (body-axis forces per unit
        span [N/m]) and ``"M"`` (pitching moment per unit span about the CG [N]). Valid near the
        zero state, where sign(U) = s.
    """
    S = symbols()
    r, c, phi, phidot, s, am = S.r, S.c, S.phi, S.phidot, S.s, S.alpha_m
    rho, A = S.rho, S.A
    # eq. (9), signed, small w; the hinge h_w above the CG (z = -h_w) moves at u - q h_w.
    U = r * phidot + (S.u - S.q * S.h_w) * sp.cos(phi)
    w_eff = S.w - S.q * (r * sp.sin(phi) + S.x_h)  # eq. (12)
    Omega = S.q * sp.cos(phi)  # alpha_dot = 0: only the body's pitch rate turns the section
    # eq. (5); kappa = 3/4 - x0_hat is kept as one symbol so that it can be collected into Krot.
    Gamma = sp.pi * c**2 * S.kappa * Omega
    absU = s * U  # near the zero state sign(U) = sign(phi_dot) = s
    sin2ag = s * sp.sin(2 * am)  # geometric pitch alpha_g of eq. (11)
    cosag = s * sp.cos(am)
    sinag = sp.sin(am)
    # eqs. (16)-(19) with signs restored: F_xi = -H' along the stroke direction, F_z = -V'.
    F_xi = (-rho * A * c * U * absU * sp.sin(am) ** 2
            - sp.Rational(1, 2) * rho * A * c * absU * w_eff * sin2ag
            + rho * Gamma * w_eff)
    Fz = -(sp.Rational(1, 2) * rho * A * c
           * (U * absU * sin2ag + 2 * absU * w_eff * sp.cos(am) ** 2)
           + rho * U * Gamma)
    Fx = F_xi * sp.cos(phi)
    # eqs. (20)-(23): lift acts at the centre of pressure, x_hat c behind the hinge line and
    # h_w above the CG (body z is down, so z_cp = -h_w + ...: a forward force pitches nose down).
    x_cp = S.x_h + r * sp.sin(phi) - S.x_hat * c * cosag * sp.cos(phi)
    z_cp = -S.h_w + S.x_hat * c * sinag
    # Berman and Wang's rotational damping torque
    tau = -sp.pi / 16 * rho * c**4 * (S.mu1 * S.f + S.mu2 * S.s_omega * Omega) * Omega
    M = z_cp * Fx - x_cp * Fz + tau * sp.cos(phi)
    steps = {"U": U, "w_eff": w_eff, "Omega": Omega, "Gamma": Gamma, "F_xi": F_xi,
             "Fx": Fx, "Fz": Fz, "x_cp": x_cp, "z_cp": z_cp, "tau": tau, "M": M}
    if not hinge_height:
        steps = {name: expr.subs(S.h_w, 0) for name, expr in steps.items()}
    return steps


def linearise(expr: sp.Expr) -> dict[str, sp.Expr]:
    """Step 3: the constant term and the first derivatives in u, w, q at the zero state (eq. 24-27).

    Parameters
    ----------
    expr : sympy.Expr
        A section load of :func:`section_loads`.

    Returns
    -------
    dict
        ``"0"``, ``"u"``, ``"w"``, ``"q"``: the value and the three partial derivatives at
        u = w = q = 0, with s**2 = 1.
    """
    S = symbols()
    zero = {S.u: 0, S.w: 0, S.q: 0}
    out = {"0": expr.subs(zero)}
    for name, var in (("u", S.u), ("w", S.w), ("q", S.q)):
        out[name] = sp.diff(expr, var).subs(zero)
    return {k: sp.expand(v.subs(S.s**2, 1)).subs(S.s**2, 1) for k, v in out.items()}


def span_integrate(expr: sp.Expr) -> sp.Expr:
    """Step 4a: 2 int_0^R (...) dr of a polynomial in r and c: r^m c^n -> I_mn (after eq. 29).

    Parameters
    ----------
    expr : sympy.Expr
        A polynomial in the symbols r and c (coefficients free of them).

    Returns
    -------
    sympy.Expr
        The expression with every monomial r^m c^n replaced by the span integral I_mn.
    """
    S = symbols()
    poly = sp.Poly(sp.expand(expr), S.r, S.c)
    return sp.Add(*[coeff * S.I(m, n) for (m, n), coeff in poly.terms()])


def collect_constants(expr: sp.Expr) -> sp.Expr:
    """Step 4b: rewrite rho A I_mn, rho pi (3/4 - x0_hat) I_mn, (pi/16) rho I_04 as K constants."""
    S = symbols()
    out = []
    for term in sp.Add.make_args(sp.expand(expr)):
        I_syms = [a for a in term.free_symbols if a.name.startswith("I_{")]
        if len(I_syms) != 1:
            raise AssertionError(f"term {term} has span integrals {I_syms}")
        I_mn = I_syms[0]
        m, n = int(I_mn.name[3]), int(I_mn.name[4])
        if term.has(S.A):
            new = term.subs(I_mn, 2 * S.K(m, n) / (S.rho * S.A))
        elif term.has(S.mu1) or term.has(S.mu2):
            new = term.subs(I_mn, 16 * S.Knu / (sp.pi * S.rho))
        elif term.has(S.kappa):  # rotational circulation: rho pi (3/4 - x0_hat) I_mn
            new = term.subs(I_mn, S.Krot(m, n) / (S.rho * sp.pi * S.kappa))
        else:
            raise AssertionError(f"term {term} belongs to no constant group")
        out.append(sp.expand(new))
    return sp.Add(*out)


_CONSTANT_NAMES = ("K_", "K^", "x_h", "h_w", r"\hat{x}", r"\mu", "f", "m", "I_y")


def _split(term: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """Split a product into (constants: K's, x_h, h_w, x_hat, mu1, f, m, I_y) and the rest."""
    const, rest = sp.Integer(1), sp.Integer(1)
    for factor in sp.Mul.make_args(term):
        base = factor.as_base_exp()[0]
        if isinstance(base, sp.Symbol) and base.name.startswith(_CONSTANT_NAMES):
            const *= factor
        else:
            rest *= factor
    return const, rest


def _groups(expr: sp.Expr) -> dict[sp.Expr, sp.Expr]:
    """Group the terms of an expanded expression by their constant factor."""
    out: dict[sp.Expr, sp.Expr] = {}
    for term in sp.Add.make_args(sp.expand(expr)):
        const, rest = _split(term)
        out[const] = out.get(const, 0) + rest
    return out


def tidy(expr: sp.Expr) -> sp.Expr:
    """Readable form: terms grouped by constant, each coefficient trig-simplified and factored."""
    return sp.Add(*[k * _tidy_coefficient(v) for k, v in _groups(expr).items()])


def _tidy_coefficient(expr: sp.Expr) -> sp.Expr:
    """Products of sines and cosines of alpha_m and phi, with sin x cos x written sin(2x)/2."""
    S = symbols()
    out = sp.factor(sp.expand_trig(expr))
    for x in (S.alpha_m, S.phi):
        out = out.subs(sp.sin(x) ** 2 + sp.cos(x) ** 2, 1)
        out = out.subs(sp.sin(x) * sp.cos(x), sp.sin(2 * x) / 2)
    return out


def _to_abs(expr: sp.Expr) -> sp.Expr:
    """Express the stroke sign through ``|phi_dot|``: s phi_dot -> ``|phi_dot|``.

    Uses s^2 = 1 and ``|phi_dot|``^2 = phi_dot^2.
    """
    S = symbols()
    a, pd = S.absphidot, S.phidot
    expr = sp.expand(sp.expand(expr).subs(S.s**2, 1).subs(S.s, a / pd))
    expr = expr.replace(lambda e: e.is_Pow and e.base == a and e.exp.is_Integer and e.exp >= 2,
                        lambda e: pd ** (int(e.exp) - int(e.exp) % 2) * a ** (int(e.exp) % 2))
    return sp.expand(expr)


@lru_cache(maxsize=2)
def stability_derivatives(hinge_height: bool = False) -> dict[str, sp.Expr]:
    """Step 5: the twelve stability derivatives of eq. (29) in the K constants.

    Parameters
    ----------
    hinge_height : bool
        Keep the terms in the hinge height h_w above the centre of gravity (the generated code
        does). Default False: the paper's model, h_w = 0, as the book shows it.

    Returns
    -------
    dict
        Keys :data:`DERIVATIVE_NAMES`. X0, Z0 in N and M0 in N m; Xu, Xw, Zu, Zw in 1/s; Xq, Zq in
        m/s per rad/s; Mu, Mw in 1/(m s); Mq in 1/s (the forces divided by m, the moment by I_y,
        as in eq. 29).
    """
    S = symbols()
    loads = section_loads(hinge_height=True)  # h_w removed below, after the span integration
    out: dict[str, sp.Expr] = {}
    for axis, key, norm in (("X", "Fx", S.m), ("Z", "Fz", S.m), ("M", "M", S.Iy)):
        lin = linearise(loads[key])
        for var in ("0", "u", "w", "q"):
            total = collect_constants(span_integrate(lin[var]))
            if var != "0":
                total = total / norm
            if not hinge_height:
                total = total.subs(S.h_w, 0)
            out[f"{axis}{var}"] = tidy(_to_abs(total))
    return {name: out[name] for name in DERIVATIVE_NAMES}


def paper_derivatives() -> dict[str, sp.Expr]:
    """The derivatives as printed after eq. (29), transcribed as we read them.

    The text extraction lost every sign, so each term is entered with a + sign and
    :func:`compare_with_paper` compares magnitudes term by term. alpha is the geometric pitch
    alpha_g of eq. (11): we write sin(2 alpha_g) = s sin(2 alpha_m), cos(alpha_g) = s cos(alpha_m).
    Where the argument of a sine or cosine was lost, the reading in the comment was taken.
    """
    S = symbols()
    ph, pd, ad, s, am = S.phi, S.phidot, S.absphidot, S.s, S.alpha_m
    sin_a, cos_a, sin2a = sp.sin(am), s * sp.cos(am), s * sp.sin(2 * am)
    K, Kr, m, Iy, xh, xt = S.K, S.Krot, S.m, S.Iy, S.x_h, S.x_hat
    Xw = K(1, 1) / m * ad * sp.cos(ph) * sin2a
    Zw = 2 * K(1, 1) / m * ad * cos_a**2
    Xq = K(2, 1) / m * ad * sp.sin(ph) * sp.cos(ph) * sin2a + xh * Xw
    Zu = 2 * Xw
    Zq = 2 * K(2, 1) / m * ad * sp.sin(ph) * cos_a**2 + Kr(1, 2) / m * pd * sp.cos(ph) + xh * Zw
    paper = {
        "X0": 2 * K(2, 1) * ad * pd * sin_a**2,  # no cos(phi): see eq. (24) vs (25)
        "Z0": K(2, 1) * ad * pd * sin2a,
        "M0": 2 * ad * pd * sin_a * (K(2, 2) * xt * sp.cos(ph) + K(2, 1) * xh * cos_a
                                     + K(3, 1) * sp.sin(ph) * cos_a),
        "Xu": 4 * K(1, 1) / m * ad * sp.cos(ph) ** 2 * sin_a**2,
        "Xw": Xw,
        "Xq": Xq,
        "Zu": Zu,
        "Zw": Zw,
        "Zq": Zq,
        "Mu": 4 * K(1, 2) * xt / Iy * pd * sp.cos(ph) ** 2 * sin_a + m / Iy * (2 * Xq + xh * Zu),
        "Mw": (2 * K(1, 2) * xt / Iy * pd * sp.cos(ph) * cos_a
               + 2 * K(2, 1) / Iy * ad * sp.sin(ph) * cos_a**2 + m * xh / Iy * Zw),
        "Mq": (2 * xt / Iy * ad * sp.cos(ph) * cos_a * (K(1, 2) * xh + K(2, 2) * sp.sin(ph))
               + 1 / Iy * pd * sp.cos(ph)
               * (Kr(1, 3) * xt * cos_a * sp.cos(ph) + Kr(2, 2) * sp.sin(ph))
               + 2 / Iy * ad * cos_a**2 * sp.sin(ph) * (K(2, 1) * xh + K(3, 1) * sp.sin(ph))
               + S.Knu * S.mu1 * S.f / Iy * sp.cos(ph) ** 2 + m * xh / Iy * Zq),
    }
    return {name: _to_abs(paper[name]) for name in DERIVATIVE_NAMES}


@dataclass(frozen=True)
class TermComparison:
    """One group of terms of one derivative (same constant factor), ours against the paper's.

    ``status`` is ``"same"`` (identical), ``"sign"`` (equal up to an overall sign, which the text
    extraction may have lost), ``"differs"`` (another function of phase), ``"only ours"`` (the
    paper has no such term) or ``"only paper"`` (our derivation gives no such term).
    """

    name: str
    constant: sp.Expr
    ours: sp.Expr
    paper: sp.Expr
    status: str


def _same(a: sp.Expr, b: sp.Expr) -> bool:
    """a == b on both half-strokes (``|phi_dot|`` = s phi_dot with s = +1 and s = -1)."""
    S = symbols()
    for sign in (1, -1):
        diff = (a - b).subs(S.absphidot, sign * S.phidot)
        if sp.simplify(sp.expand_trig(diff)) != 0:
            return False
    return True


def compare_with_paper() -> list[TermComparison]:
    """Compare each derived derivative with the paper's printed one, group by group of terms."""
    ours, paper = stability_derivatives(), paper_derivatives()
    rows = []
    for name in DERIVATIVE_NAMES:
        a, b = _groups(ours[name]), _groups(paper[name])
        for const in list(a) + [k for k in b if k not in a]:
            ea, eb = a.get(const, sp.Integer(0)), b.get(const, sp.Integer(0))
            if const not in b:
                status = "only ours"
            elif const not in a:
                status = "only paper"
            elif _same(ea, eb):
                status = "same"
            elif _same(ea, -eb):
                status = "sign"
            else:
                status = "differs"
            rows.append(TermComparison(name, const, _tidy_coefficient(ea),
                                       _tidy_coefficient(eb), status))
    return rows


def vanishing_symmetry(expr: sp.Expr) -> str:
    """Which symmetry of the stroke makes ``expr`` average to zero over a wingbeat.

    phi(t) = Phi cos(2 pi f t) is even about t = 0 and odd under the half-period shift, so an
    expression odd under time reversal (phi_dot -> -phi_dot, phi fixed) or under the half-period
    shift (phi -> -phi, phi_dot -> -phi_dot) has zero cycle mean. ``|phi_dot|`` is even under both.

    Returns
    -------
    str
        The symmetries under which the whole expression is odd (``"time reversal"``,
        ``"half-period shift"``, or both joined by ``" and "``); failing that,
        ``"term by term"`` if each term is odd under one of them; ``""`` if some term survives
        averaging.
    """
    S = symbols()
    maps = {
        "time reversal": {S.phidot: -S.phidot},
        "half-period shift": {S.phidot: -S.phidot, S.phi: -S.phi},
    }

    def odd(e, name):
        return sp.simplify(e.subs(maps[name], simultaneous=True) + e) == 0

    whole = [name for name in maps if odd(expr, name)]
    if whole:
        return " and ".join(sorted(whole))
    if all(any(odd(term, name) for name in maps) for term in sp.Add.make_args(sp.expand(expr))):
        return "term by term"
    return ""


def evaluate(expr: sp.Expr, insect: Insect, t: ArrayLike, *, alpha_m: float | None = None,
             amplitude: float | None = None) -> np.ndarray:
    """Evaluate an expression of the derivation's symbols for ``insect`` at times ``t``.

    Any expression built from :func:`symbols` (a derivative of :func:`stability_derivatives`, a
    printed one of :func:`paper_derivatives`, a term group of :func:`compare_with_paper`) is
    turned into numbers: phi, phi_dot, ``|phi_dot|`` from the stroke (eq. 39), alpha_m from the trim
    (eq. 40) unless given, K_mn, Krot_mn, K_nu, x_hat, x_h, mu1, f, m, I_y from the insect.

    Parameters
    ----------
    expr : sympy.Expr
        An expression in the symbols of :func:`symbols`.
    insect : Insect
        Supplies the constants.
    t : array_like
        Times [s].
    alpha_m : float, optional
        Mid-stroke angle of attack [rad] in (0, pi/2); default the trim of eq. (40).
    amplitude : float, optional
        Stroke amplitude Phi [rad] in (0, pi/2]; default ``insect.stroke_amplitude``.

    Returns
    -------
    numpy.ndarray
        The values, broadcast to the shape of ``t``.

    Raises
    ------
    ValueError
        If an argument is outside its range (the message names it).
    """
    _validation.instance("insect", insect, Insect)
    S = symbols()
    amplitude = check_amplitude(insect.stroke_amplitude if amplitude is None else amplitude)
    alpha_m = check_alpha_m(trim_angle_of_attack(insect) if alpha_m is None else alpha_m)
    t = _validation.array("t", t)
    phidot = flapping_rate(t, amplitude, insect.frequency)
    c = aero_constants(insect)
    values = {S.alpha_m: alpha_m, S.x_hat: c.x_hat, S.x_h: c.x_h, S.h_w: c.h_w, S.mu1: c.mu1,
              S.f: c.f, S.m: c.m, S.Iy: c.Iy, S.Knu: c.Knu, S.rho: insect.air_density,
              S.A: insect.lift_slope, S.x0_hat: insect.pitch_axis,
              S.kappa: 0.75 - insect.pitch_axis}
    values.update({S.K(m, n): v for (m, n), v in c.K.items()})
    values.update({S.Krot(m, n): v for (m, n), v in c.Krot.items()})
    expr = sp.sympify(expr).subs(values)
    args = (S.phi, S.phidot, S.absphidot)
    fn = sp.lambdify(args, expr, modules="numpy")
    phi = flapping_angle(t, amplitude, insect.frequency)
    if insect.stroke_mean != 0.0:  # phi = phi_bar + Phi cos(2 pi f t)
        phi = phi + insect.stroke_mean
    out = fn(phi, phidot, np.abs(phidot))
    return np.broadcast_to(np.asarray(out, dtype=float), t.shape).copy()


# --------------------------------------------------------------------------- code generation
_ARGUMENTS = ("phi", "phidot", "absphidot", "alpha_m", "c")


def _numeric_names() -> dict[sp.Symbol, str]:
    S = symbols()
    names = {S.phi: "phi", S.phidot: "phidot", S.absphidot: "absphidot", S.alpha_m: "alpha_m",
             S.x_hat: "c.x_hat", S.x_h: "c.x_h", S.mu1: "c.mu1", S.f: "c.f", S.m: "c.m",
             S.Iy: "c.Iy", S.Knu: "c.Knu"}
    for mm in range(5):
        for nn in range(5):
            names[S.K(mm, nn)] = f"c.K[{mm}, {nn}]"
            names[S.Krot(mm, nn)] = f"c.Krot[{mm}, {nn}]"
    names[S.h_w] = "c.h_w"  # last: the placeholders of the others keep their numbers
    return names


def _split_hinge(exprs: list[sp.Expr]) -> tuple[list[sp.Expr], list[sp.Expr]]:
    """Each expression as (its value at h_w = 0, the terms in the hinge height h_w).

    The generated code evaluates the second part only when h_w != 0, so that the paper's model
    (h_w = 0) runs exactly the arithmetic it ran before the hinge height was added.
    """
    S = symbols()
    base = [e.subs(S.h_w, 0) for e in exprs]
    return base, [sp.expand(e - b) for e, b in zip(exprs, base, strict=True)]


def _numpy_body(printer: object, exprs: list[sp.Expr], labels: list[str]) -> list[str]:
    """Lines of a generated function returning ``exprs`` (hinge terms only if h_w != 0)."""
    names = _numeric_names()
    placeholders = {sym: sp.Symbol(f"__{i}__") for i, sym in enumerate(names)}
    printed_of = {placeholders[sym]: names[sym] for sym in names}

    def show(e: sp.Expr) -> str:
        text = printer.doprint(e)  # type: ignore[attr-defined]
        for ph in sorted(printed_of, key=lambda p: -len(p.name)):
            text = text.replace(ph.name, printed_of[ph])
        return text

    def cse(exprs: list[sp.Expr], prefix: str) -> tuple[list[str], list[sp.Expr]]:
        replacements, reduced = sp.cse([e.xreplace(placeholders) for e in exprs],
                                       symbols=sp.numbered_symbols(prefix), optimizations="basic")
        return [f"    {sym} = {show(e)}" for sym, e in replacements], reduced

    base, hinge = _split_hinge(exprs)
    lines, reduced = cse(base, "t")
    lines.append("    out = (")
    lines += [f"        {show(e)},  # {name}" for name, e in zip(labels, reduced, strict=True)]
    lines += ["    )", "    if c.h_w == 0.0:", "        return out"]
    extra, reduced = cse(hinge, "h")
    lines += extra + ["    return ("]
    lines += [f"        out[{i}]" + ("" if e == 0 else f" + {show(e)}") + f",  # {name}"
              for i, (name, e) in enumerate(zip(labels, reduced, strict=True))]
    return lines + ["    )"]


def generate_source() -> str:
    """Python source of ``flapping/model/_derivatives_generated.py`` (NumPy, common subexpressions).

    The generated function ``stability_derivatives(phi, phidot, absphidot, alpha_m, c)`` takes the
    flapping angle and rate (arrays), ``|phi_dot|``, the trim pitch alpha_m and a constants object
    ``c`` with attributes K, Krot (5x5 arrays indexed [m, n]), Knu, x_hat, x_h, h_w, mu1, f, m, Iy.
    ``stability_derivatives_scalar_with_amplitude`` adds Phi d/dPhi of each at phi_bar = 0, and
    ``stability_derivatives_scalar_phi_derivative`` gives d/dphi of each (the sensitivity to the
    mean stroke angle phi_bar; Phi d/dPhi = Euler - phi_bar d/dphi when phi_bar != 0).
    """
    derivs = stability_derivatives(hinge_height=True)
    exprs = [derivs[k] for k in DERIVATIVE_NAMES]
    # Phi d/dPhi of each derivative: with phi_bar = 0, phi, phi_dot and |phi_dot| are all
    # proportional to the amplitude Phi, so Phi d/dPhi is the Euler operator phi d/dphi +
    # phi_dot d/dphi_dot + ...; with a mean stroke angle phi_bar subtract phi_bar d/dphi (the
    # third generated function).
    S = symbols()
    euler = [sp.expand(S.phi * sp.diff(e, S.phi) + S.phidot * sp.diff(e, S.phidot)
                       + S.absphidot * sp.diff(e, S.absphidot)) for e in exprs]
    amp_labels = [f"Phi d{name}/dPhi" for name in DERIVATIVE_NAMES]

    from sympy.printing.numpy import NumPyPrinter
    from sympy.printing.pycode import PythonCodePrinter

    numpy_printer = NumPyPrinter({"fully_qualified_modules": True})
    math_printer = PythonCodePrinter({"fully_qualified_modules": True})
    lines = [
        '"""Stability derivatives X0 ... Mq of eq. (29), GENERATED by flapping.model.derivation.',
        "",
        "Do not edit: regenerate with",
        "`python -m flapping.model.derivation > flapping/model/_derivatives_generated.py`",
        "(a test checks that the committed file equals a fresh generation).",
        '"""',
        "",
        "import math",
        "",
        "import numpy",
        "",
        f"NAMES = {DERIVATIVE_NAMES!r}",
        "",
        "",
        "def stability_derivatives(phi, phidot, absphidot, alpha_m, c):",
        '    """(X0, Z0, M0, Xu, Xw, Xq, Zu, Zw, Zq, Mu, Mw, Mq) for arrays of phases (NumPy)."""',
        *_numpy_body(numpy_printer, exprs, list(DERIVATIVE_NAMES)),
        "",
        "",
        "def stability_derivatives_scalar_with_amplitude(phi, phidot, absphidot, alpha_m, c):",
        '    """The twelve derivatives and then Phi * d/dPhi of each (24 floats), '
        'for one phase."""',
        *_numpy_body(math_printer, exprs + euler, list(DERIVATIVE_NAMES) + amp_labels),
        "",
        "",
        "def stability_derivatives_scalar_phi_derivative(phi, phidot, absphidot, alpha_m, c):",
        '    """d/dphi of the twelve derivatives (12 floats), for one phase (for d/dphi_bar)."""',
        *_numpy_body(math_printer, [sp.diff(e, S.phi) for e in exprs],
                     [f"d{name}/dphi" for name in DERIVATIVE_NAMES]),
    ]
    return "\n".join(lines) + "\n"


# --------------------------------------------------------------------------- numba kernel
def _numba_substitutions() -> tuple[dict[sp.Expr, sp.Symbol], dict[sp.Symbol, str]]:
    """Symbols for the trigonometric values the kernel supplies, and the printed name of each.

    The compiled kernel evaluates sin and cos of phi once per time (and those of alpha_m once per
    insect) and passes them in, so the generated code is plain arithmetic.
    """
    S = symbols()
    trig = {
        sp.sin(S.phi): "sphi", sp.cos(S.phi): "cphi",
        sp.sin(2 * S.phi): "s2phi", sp.cos(2 * S.phi): "c2phi",
        sp.sin(S.alpha_m): "k[SIN_ALPHA_M]", sp.cos(S.alpha_m): "k[COS_ALPHA_M]",
        sp.sin(2 * S.alpha_m): "k[SIN_2ALPHA_M]",
    }
    replace = {expr: sp.Symbol(f"__trig{i}__") for i, expr in enumerate(trig)}
    printed = {replace[expr]: name for expr, name in trig.items()}
    names = {S.phi: "phi", S.phidot: "phidot", S.absphidot: "absphidot"}
    plain = {"m": "MASS", "Iy": "PITCH_INERTIA", "f": "FREQUENCY", "Knu": "K_NU"}
    for symbol, text in _numeric_names().items():
        if text.startswith("c."):  # c.K[2, 1] -> K_21, c.Krot[1, 2] -> KROT_12, c.x_h -> X_H
            attr = text[2:]
            name = plain.get(attr) or re.sub(r"\[(\d), (\d)\]", r"_\1\2", attr).upper()
            names[symbol] = f"k[{name}]"
    printed.update({sp.Symbol(f"__sym{i}__"): names[sym] for i, sym in enumerate(names)})
    replace.update({sym: sp.Symbol(f"__sym{i}__") for i, sym in enumerate(names)})
    return replace, printed


def _numba_function(name: str, doc: str, exprs: list[sp.Expr], labels: list[str]) -> list[str]:
    """One function writing ``exprs`` into ``out`` (common subexpressions shared)."""
    from sympy.printing.pycode import PythonCodePrinter

    replace, printed = _numba_substitutions()
    printer = PythonCodePrinter({"fully_qualified_modules": True})
    base, hinge = _split_hinge(exprs)
    cse, reduced = sp.cse([e.xreplace(replace) for e in base],
                          symbols=sp.numbered_symbols("t"), optimizations="basic")
    hinge_cse, hinge_reduced = sp.cse([e.xreplace(replace) for e in hinge],
                                      symbols=sp.numbered_symbols("h"), optimizations="basic")

    def show(e: sp.Expr) -> str:
        text = printer.doprint(e)
        for placeholder in sorted(printed, key=lambda p: -len(p.name)):
            text = text.replace(placeholder.name, printed[placeholder])
        if "math." in text or "__" in text:
            raise AssertionError(f"the numba kernel's code must be arithmetic only: {text}")
        return text

    return [
        f"def {name}(phi, phidot, absphidot, sphi, cphi, s2phi, c2phi, k, out):",
        f'    """{doc}"""',
        *[f"    {sym} = {show(e)}" for sym, e in cse],
        *[f"    out[{i}] = {show(e)}  # {label}"
          for i, (label, e) in enumerate(zip(labels, reduced, strict=True))],
        "    if k[H_W] != 0.0:  # the hinge height's terms (none at h_w = 0: the paper's model)",
        *[f"        {sym} = {show(e)}" for sym, e in hinge_cse],
        *[f"        out[{i}] += {show(e)}  # {label}"
          for i, (label, e) in enumerate(zip(labels, hinge_reduced, strict=True)) if e != 0],
    ]


def generate_numba_source() -> str:
    """Python source of ``flapping/fast/_generated.py``: the derivatives for the numba kernel.

    The same expressions as :func:`generate_source` (one source of truth), printed for the
    compiled hover kernel of :mod:`flapping.fast`: ``derivatives(...)`` writes X0 ... Mq into
    ``out[:12]``; ``derivatives_and_amplitude(...)`` writes them and then Phi d/dPhi of each into
    ``out[:24]``. Both take phi, phi_dot, ``abs(phi_dot)``, sin(phi), cos(phi), sin(2 phi),
    cos(2 phi), a float64 array ``k`` of constants laid out as the module's ``CONSTANTS`` (the K's
    in SI, x_hat, x_h, mu1, f, m, I_y and the sines and cosines of alpha_m) and the output array.
    """
    S = symbols()
    derivs = stability_derivatives(hinge_height=True)
    exprs = [derivs[k] for k in DERIVATIVE_NAMES]
    euler = [sp.expand(S.phi * sp.diff(e, S.phi) + S.phidot * sp.diff(e, S.phidot)
                       + S.absphidot * sp.diff(e, S.absphidot)) for e in exprs]
    amp_labels = [f"Phi d{name}/dPhi" for name in DERIVATIVE_NAMES]
    replace, printed = _numba_substitutions()
    used = set().union(*[e.xreplace(replace).free_symbols for e in exprs + euler])
    constants = sorted({printed[p][2:-1] for p in used if printed[p].startswith("k[")}
                       | {"SIN_ALPHA_M", "COS_ALPHA_M", "SIN_2ALPHA_M"})
    lines = [
        '"""Stability derivatives X0 ... Mq of eq. (29) for the numba kernel, GENERATED by',
        "flapping.model.derivation (the expressions of flapping/model/_derivatives_generated.py).",
        "",
        "Do not edit: regenerate with",
        "`python -m flapping.model.derivation --numba > flapping/fast/_generated.py`",
        "(a test checks that the committed file equals a fresh generation). Plain Python:",
        ":mod:`flapping.fast._compiled` compiles these functions with numba on first use.",
        '"""',
        "",
        f"NAMES = {DERIVATIVE_NAMES!r}",
        "",
        "#: Layout of the constants array ``k``: the index of each is the constant of its name.",
        f"CONSTANTS = {tuple(constants)!r}",
        *[f"{name} = {i}" for i, name in enumerate(constants)],
        "",
        "",
        *_numba_function("derivatives", "(X0, ..., Mq) into out[:12], for one phase.",
                         exprs, list(DERIVATIVE_NAMES)),
        "",
        "",
        *_numba_function("derivatives_and_amplitude",
                         "(X0, ..., Mq) into out[:12], Phi d/dPhi of each into out[12:24].",
                         exprs + euler, list(DERIVATIVE_NAMES) + amp_labels),
    ]
    return "\n".join(lines) + "\n"


if __name__ == "__main__":  # pragma: no cover - regeneration entry point
    import sys

    print(generate_numba_source() if "--numba" in sys.argv[1:] else generate_source(), end="")

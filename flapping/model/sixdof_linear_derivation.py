"""SymPy derivation of the paper's linear loads (eq. 29) in six degrees of freedom.

The planar linear model is the exact linearisation at the zero state of the small-angle section
loads (:mod:`flapping.model.derivation`). This module repeats that derivation for the insect in
six degrees of freedom, reusing both derivations rather than restating them:

1. **Section law.** :func:`flapping.model.derivation.section_loads` evaluated with phi = 0,
   phi_dot = 0 and the hinge at the centre of gravity is the section law itself: its
   chordwise speed is u, its effective normal speed w and its span-axis pitch rate q. Replacing
   them by the strip speeds U_k, w_eff_k and the pitch rate Omega_k of wing k
   (:func:`flapping.model.sixdof_derivation.strip_kinematics`) gives that wing's tangential force
   F_t (along t_k), normal force F_n (along n) and damping torque tau per unit span, with
   ``|U|`` = s U near the zero state (s the stroke sign).
2. **Linearisation** of F_t, F_n and tau in (u, v, w, p, q, r) at zero (s^2 = 1).
3. **Span integration** of each wing's F_t, r F_t, c F_t, F_n, r F_n, c F_n and tau (the
   resultants of :data:`~flapping.model.sixdof_derivation.RESULTANT_NAMES`): r^m c^n becomes
   I_mn / 2 (I_mn integrates both wings), then the constants are collected into K_mn,
   Krot_mn and K_nu (:func:`flapping.model.derivation.collect_constants`).
4. **Assembly** about the centre of gravity by :func:`flapping.model.sixdof_derivation.wing_loads`
   (forces at the chordwise centre of pressure, the torque about the span axis). The assembly is
   linear in the resultants with coefficients free of the states, so the constant loads and
   each column of the derivative matrix are the assembly of the resultants' constant part and
   of their derivative in that state.
5. The stroke sign is written through ``|phi_dot|`` (s phi_dot -> ``|phi_dot|``, as the planar
   derivation does).

Result: the constant loads (X0, Y0, Z0, L0, M0, N0) [N, N m] and the 6 x 6 matrix of their
derivatives in (u, v, w, p, q, r) (dimensional: N per m/s, N per rad/s, N m per m/s, N m per
rad/s; not divided by the mass or an inertia, since the inertia tensor is not diagonal), in phi,
phi_dot, ``|phi_dot|``, alpha_m and the insect's constants. The wing roots sit on the plane of
symmetry (y_w = 0), as in the package's six-degree-of-freedom model.

:func:`generate_source` prints them (math only, common subexpressions shared) into
``flapping/model/_sixdof_linear_generated.py``, committed; a test regenerates it and compares the
text. Importing :mod:`flapping` never runs this derivation.

Layering: the planar derivation (:mod:`flapping.model.derivation`) and the six-degree-of-freedom
one (:mod:`flapping.model.sixdof_derivation`).
"""

from __future__ import annotations

import re
from functools import lru_cache

import sympy as sp

from flapping.model import derivation, sixdof_derivation

__all__ = ["LOAD_NAMES", "DERIVATIVE_NAMES", "OUTPUT_NAMES", "section_law", "wing_section_loads",
           "linear_loads", "mechanics_jacobians", "generate_source"]

#: The loads, in order.
LOAD_NAMES: tuple[str, ...] = ("X", "Y", "Z", "L", "M", "N")
#: The states the loads are linearised in, in order.
VELOCITY_NAMES: tuple[str, ...] = ("u", "v", "w", "p", "q", "r")
#: The 36 derivatives, row-major: d(load)/d(state), e.g. ``"Xu"``, ``"Lp"``.
DERIVATIVE_NAMES: tuple[str, ...] = tuple(f"{a}{b}" for a in LOAD_NAMES for b in VELOCITY_NAMES)
#: What the generated ``linear_loads`` returns: the six constant loads, then the derivatives.
OUTPUT_NAMES: tuple[str, ...] = tuple(f"{a}0" for a in LOAD_NAMES) + DERIVATIVE_NAMES


def _six() -> sixdof_derivation.SixDofSymbols:
    return sixdof_derivation.sixdof_symbols()


def _velocities() -> tuple[sp.Symbol, ...]:
    return _six().states[:6]


@lru_cache(maxsize=1)
def section_law() -> dict[str, sp.Expr]:
    """Step 1: the planar section loads as a law of (U, w_eff, Omega), per unit span.

    Returns
    -------
    dict
        ``"F_t"``, ``"F_n"``, ``"tau"`` in the symbols ``U``, ``W``, ``Omega`` (placeholders for
        the chordwise speed, the effective normal speed and the span-axis pitch rate), the chord
        c, the stroke sign s and the planar derivation's constants.
    """
    S = derivation.symbols()
    steps = derivation.section_loads(hinge_height=True)
    U, W, Om = sp.symbols("U W Omega", real=True)
    # With phi = phi_dot = 0 and the hinge at the CG, the planar section sees U = u, w_eff = w
    # and Omega = q: the loads are then the section law in (u, w, q).
    at_root = {S.phi: 0, S.phidot: 0, S.x_h: 0, S.h_w: 0}
    check = {name: sp.simplify(steps[name].subs(at_root) - value)
             for name, value in (("U", S.u), ("w_eff", S.w), ("Omega", S.q))}
    if any(v != 0 for v in check.values()):  # pragma: no cover - the planar derivation changed
        raise AssertionError(f"the planar section kinematics are not (u, w, q) there: {check}")
    law = {"F_t": steps["F_xi"], "F_n": steps["Fz"], "tau": steps["tau"]}
    return {name: sp.expand(e.subs(at_root).xreplace({S.u: U, S.w: W, S.q: Om}))
            for name, e in law.items()}


def _kinematics_in_planar_symbols() -> dict[str, tuple[sp.Expr, sp.Expr, sp.Expr]]:
    """Per wing (U, w_eff, Omega_k) along the span, in the planar derivation's r, phi, phi_dot."""
    S, six = derivation.symbols(), _six()
    phi, phi_dot = six.kinematics[:2]
    x_h, y_w, h_w = six.constants[8:11]
    rename = {phi: S.phi, phi_dot: S.phidot, six.rho: S.r, x_h: S.x_h, h_w: S.h_w, y_w: 0}
    out = {}
    for name, (U0, U1, W0, W1, omega) in sixdof_derivation.strip_kinematics().items():
        out[name] = tuple(e.subs(rename) for e in (U0 + U1 * six.rho, W0 + W1 * six.rho, omega))
    return out


@lru_cache(maxsize=1)
def wing_section_loads() -> dict[str, dict[str, sp.Expr]]:
    """Step 1 applied to each wing: ``{"R": {"F_t", "F_n", "tau"}, "L": {...}}`` per unit span."""
    law = section_law()
    U, W, Om = sp.symbols("U W Omega", real=True)
    out = {}
    for name, (u_k, w_k, om_k) in _kinematics_in_planar_symbols().items():
        out[name] = {key: sp.expand(e.xreplace({U: u_k, W: w_k, Om: om_k}))
                     for key, e in law.items()}
    return out


def _linearised(expr: sp.Expr) -> list[sp.Expr]:
    """Step 2: [value, d/du, ..., d/dr] at the zero state, with s^2 = 1."""
    S = derivation.symbols()
    zero = dict.fromkeys(_velocities(), 0)
    parts = [expr.subs(zero)] + [sp.diff(expr, x).subs(zero) for x in _velocities()]
    return [sp.expand(sp.expand(p).subs(S.s**2, 1)) for p in parts]


def _resultants(loads: dict[str, sp.Expr]) -> list[list[sp.Expr]]:
    """Step 3: the seven resultants of one wing (T0, T1, Tc, N0, N1, Nc, Q), each as [value,
    d/du, ..., d/dr] in the K constants."""
    S = derivation.symbols()
    integrands = [loads["F_t"], S.r * loads["F_t"], S.c * loads["F_t"],
                  loads["F_n"], S.r * loads["F_n"], S.c * loads["F_n"], loads["tau"]]
    out = []
    for integrand in integrands:
        # span_integrate gives I_mn = 2 int r^m c^n dr over both wings: one wing is half.
        out.append([derivation.collect_constants(derivation.span_integrate(part) / 2)
                    if part != 0 else sp.Integer(0) for part in _linearised(integrand)])
    return out


@lru_cache(maxsize=1)
def linear_loads() -> tuple[sp.Matrix, sp.Matrix]:
    """Steps 1-5: the constant loads and their derivatives in the six body velocities.

    Returns
    -------
    loads0 : sympy.Matrix, 6 x 1
        (X0, Y0, Z0, L0, M0, N0) [N, N m] about the centre of gravity, body axes.
    derivatives : sympy.Matrix, 6 x 6
        d(X, Y, Z, L, M, N)/d(u, v, w, p, q, r) at the zero state (dimensional).

    Both in the symbols of :func:`flapping.model.derivation.symbols`: phi, phi_dot,
    ``|phi_dot|``, alpha_m, x_hat, x_h, h_w, f, mu1 and the K constants.
    """
    S, six = derivation.symbols(), _six()
    assembly = sixdof_derivation.wing_loads()
    sign, alpha_m, x_hat = sp.symbols("s alpha_m x_hat", real=True)
    x_h, y_w, h_w = six.constants[8:11]
    rename = {six.kinematics[0]: S.phi, sign: S.s, alpha_m: S.alpha_m, x_hat: S.x_hat,
              x_h: S.x_h, h_w: S.h_w, y_w: 0}
    assembly = assembly.subs(rename)
    wings = wing_section_loads()
    symbols = {name: [sp.Symbol(f"{r}_{name}", real=True)
                      for r in sixdof_derivation.RESULTANT_NAMES] for name in wings}
    parts = {name: _resultants(wings[name]) for name in wings}
    columns = []
    for j in range(7):  # the value, then d/du ... d/dr
        values = {sym: parts[name][i][j] for name in wings
                  for i, sym in enumerate(symbols[name])}
        column = assembly.xreplace(values).applyfunc(
            lambda e: derivation._to_abs(sp.expand(e)))
        columns.append(column)
    loads0 = columns[0]
    derivatives = sp.Matrix.hstack(*columns[1:])
    leftover = (loads0.free_symbols | derivatives.free_symbols) & {S.s, S.rho, S.A, S.kappa}
    if leftover:  # pragma: no cover - a derivation step failed
        raise AssertionError(f"symbols left in the linear loads: {leftover}")
    return loads0, derivatives


@lru_cache(maxsize=1)
def mechanics_jacobians() -> tuple[sp.Matrix, sp.Matrix]:
    """The Jacobians in the eight states of the forcing F of A x_dot = loads + F and of the Euler
    angles' rates (:func:`flapping.model.sixdof_derivation.equations_of_motion`,
    :func:`~flapping.model.sixdof_derivation.euler_rates`), for the variational equations of the
    compiled path (the mass matrix A depends on phi only, and the linear loads' Jacobian is
    :func:`linear_loads`'s derivatives).

    Returns
    -------
    forcing_jacobian : sympy.Matrix, 6 x 8
    euler_jacobian : sympy.Matrix, 2 x 8
    """
    six = _six()
    _, forcing = sixdof_derivation.equations_of_motion()
    states = list(six.states)
    euler = sp.Matrix(list(sixdof_derivation.euler_rates()))
    return forcing.jacobian(states), euler.jacobian(states)


# --------------------------------------------------------------------------- code generation
def _constant_names() -> dict[sp.Symbol, str]:
    """The printed name of each constant of the derivation (the generated ``CONSTANTS``)."""
    S = derivation.symbols()
    names = {S.Knu: "K_NU", S.x_hat: "X_HAT", S.x_h: "X_H", S.h_w: "H_W", S.mu1: "MU1",
             S.f: "FREQUENCY"}
    for m in range(6):
        for n in range(6):
            names[S.K(m, n)] = f"K_{m}{n}"
            names[S.Krot(m, n)] = f"KROT_{m}{n}"
    return names


def _printed_into(name: str, args: str, doc: str, exprs: list[sp.Expr],
                  unpack: list[str]) -> list[str]:
    """Lines of one generated function writing ``exprs`` into ``out`` (a float64 array: numba
    indexes it at run time without the switch a tuple's run-time index compiles to)."""
    replacements, reduced = sp.cse(exprs, symbols=sp.numbered_symbols("c"))
    lines = [f"def {name}({args}, out):", f'    """{doc}"""', *unpack]
    for symbol, expr in replacements:
        lines.append(f"    {symbol} = {sp.pycode(expr, fully_qualified_modules=True)}")
    for i, e in enumerate(reduced):
        value = sp.pycode(sp.Float(e) if e.is_Number else e, fully_qualified_modules=True)
        lines.append(f"    out[{i}] = {value}")
    return lines


def generate_source() -> str:
    """The text of ``flapping/model/_sixdof_linear_generated.py`` (scalar functions, math only).

    Returns
    -------
    str
        Python source with ``CONSTANTS`` (the names of the constants array ``k``, in order),
        ``OUTPUT_NAMES`` and ``linear_loads(phi, phi_dot, abs_phi_dot, alpha_m, k, out)``:
        the 42 values of :data:`OUTPUT_NAMES` (six constant loads, then the 6 x 6 derivatives
        row-major) written into ``out``; likewise ``forcing_jacobian`` (48 values, 6 x 8
        row-major, constants ``k`` of :data:`~flapping.model.sixdof_derivation.CONSTANT_NAMES`)
        and ``euler_rates_jacobian`` (16 values, 2 x 8) of :func:`mechanics_jacobians`,
        ``earth_velocity_jacobian`` (24 values, 3 x 8, of
        :func:`~flapping.model.sixdof_derivation.earth_velocity`), and
        ``mass_matrix`` (36 values, that of
        :func:`~flapping.model.sixdof_derivation.equations_of_motion`). Plain Python that numba
        can compile; the outputs are float64 arrays.
    """
    S = derivation.symbols()
    loads0, derivatives = linear_loads()
    exprs = list(loads0) + [derivatives[i, j] for i in range(6) for j in range(6)]
    names = _constant_names()
    used = set().union(*[e.free_symbols for e in exprs])
    constants = sorted(names[x] for x in used if x in names)
    printed = {x: sp.Symbol(names[x], real=True) for x in used if x in names}
    printed.update({S.phi: sp.Symbol("phi", real=True),
                    S.phidot: sp.Symbol("phi_dot", real=True),
                    S.absphidot: sp.Symbol("abs_phi_dot", real=True),
                    S.alpha_m: sp.Symbol("alpha_m", real=True)})
    unknown = used - set(printed)
    if unknown:  # pragma: no cover - a derivation step failed
        raise AssertionError(f"no printed name for {unknown}")
    exprs = [e.xreplace(printed) for e in exprs]
    lines = [
        '"""Generated by flapping.model.sixdof_linear_derivation.generate_source(): do not edit.',
        "",
        "The paper's linear loads (eq. 29) in six degrees of freedom: the constant loads and their",
        "derivatives in (u, v, w, p, q, r) at the zero state. Regenerate with",
        "`python -m flapping.model.sixdof_linear_derivation > "
        "flapping/model/_sixdof_linear_generated.py`",
        "(a test checks that the committed file equals a fresh generation).",
        '"""',
        "",
        "# ruff: noqa",
        "import math",
        "",
        f"OUTPUT_NAMES = {OUTPUT_NAMES!r}",
        "",
        "#: Layout of the constants array ``k`` of linear_loads (SI).",
        f"CONSTANTS = {tuple(constants)!r}",
        "",
        "",
        *_printed_into(
            "linear_loads", "phi, phi_dot, abs_phi_dot, alpha_m, k",
            "(X0, Y0, Z0, L0, M0, N0) and d(X ... N)/d(u ... r) row-major into out[:42].",
            exprs, [f"    {name} = k[{i}]" for i, name in enumerate(constants)]),
    ]
    six = _six()
    states = ", ".join(str(x) for x in six.states)
    jf, je = mechanics_jacobians()
    unpack = ["    " + ", ".join(sixdof_derivation.CONSTANT_NAMES) + " = k"]
    lines += ["", "", *_printed_into(
        "forcing_jacobian", f"phi, phi_dot, phi_ddot, {states}, k",
        "dF/d(u, v, w, p, q, r, roll, theta) of A x_dot = loads + F, row-major into out[:48].",
        [jf[i, j] for i in range(6) for j in range(8)], unpack)]
    mass, _ = sixdof_derivation.equations_of_motion()
    lines += ["", "", *_printed_into(
        "mass_matrix", "phi, k",
        "A of A x_dot = loads + F (sixdof_derivation's), row-major into out[:36].",
        [mass[i, j] for i in range(6) for j in range(6)], unpack)]
    lines += ["", "", *_printed_into(
        "euler_rates_jacobian", states,
        "d(roll_dot, theta_dot)/d(u, v, w, p, q, r, roll, theta), row-major into out[:16].",
        [je[i, j] for i in range(2) for j in range(8)], [])]
    earth = sp.Matrix(list(sixdof_derivation.earth_velocity())).jacobian(list(six.states))
    lines += ["", "", *_printed_into(
        "earth_velocity_jacobian", states,
        "d(forward, right, down)/d(u, v, w, p, q, r, roll, theta), row-major into out[:24].",
        [earth[i, j] for i in range(3) for j in range(8)], [])]
    # SymPy prints a float 1 as 1.00000000000000: shorten such literals.
    return re.sub(r"\b(\d+)\.0{14}\b", r"\1.0", "\n".join(lines) + "\n")


if __name__ == "__main__":  # pragma: no cover - the regeneration command
    print(generate_source(), end="")

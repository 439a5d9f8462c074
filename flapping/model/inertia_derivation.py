"""SymPy derivation of the wings' inertial loads on the body (the paper neglects them).

The paper's eq. (2) treats the insect as one rigid body: massless wings. Real wings are not
(a hawkmoth's pair weighs ~6 % of its body), and flapping them shakes the body every stroke. This
module gives the longitudinal equations of motion of a rigid body carrying two wings whose motion
relative to the body is prescribed (the stroke angle phi(t)), as the special case of the
six-degree-of-freedom derivation (:mod:`flapping.model.sixdof_derivation`) in the plane:

1. the body frame: x forward, z down, y to the right wing; the reference point O is the body's own
   centre of gravity (the states u, w, q, theta describe the body, as in eq. 2);
2. a wing element at distance rho from the hinge sits at
   r = (x_h + rho sin(phi), +-rho cos(phi), -h_w) (right, left wing): the hinge x_h ahead of and
   h_w above O, the stroke plane the body's x-y plane, phi positive forward (eq. 39); the wing's
   mass lies on its span line (its chordwise mass moments and the feathering rotation are
   neglected: they are second order in the chord);
3. the absolute acceleration of every element, a = a_O + q_dot x r + q x (q x r) + 2 q x r_dot +
   r_ddot (q the body's angular velocity, dots relative to the body), integrated over each wing
   through its mass moments: int dm = m_w, int rho dm = A1 / 2, int rho^2 dm = A2 / 2 (A1, A2 of
   the pair);
4. Newton's and Euler's laws for the whole system about O: sum m a = F_aero + m_total g and
   sum r x m a = M_aero + sum r x m g (the body adds m_b a_O and I_b q_dot);
5. the result is linear in the body's accelerations: A(phi) (u_dot, w_dot, q_dot) =
   (X, Z, M) + F(phi, phi_dot, phi_ddot, u, w, q, theta), with a symmetric mass matrix A.

:func:`generate_source` prints A, F and their derivatives (in the states and in phi, phi_dot,
phi_ddot) as plain Python into ``flapping/model/_inertia_generated.py``, committed; a test checks
that regenerating it gives the same text. Importing :mod:`flapping` never runs this derivation.

The derivation itself is :mod:`flapping.model.sixdof_derivation`'s (the insect in six degrees of
freedom): this module restricts it to the plane of symmetry (v = p = r = roll = 0, both wings
alike) and prints the planar equations of motion that every planar path runs: with wing mass
(A and F, and their derivatives), and without (:func:`rigid_body`, the paper's eq. 2, with the
pitch angle's rate and the earth-frame velocity). Nothing of the equations of motion is written
by hand anywhere else in the package.

Layering: imports :mod:`flapping.model.sixdof_derivation` only (SymPy).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import sympy as sp
import sympy.core.random as sympy_random

from flapping.model import sixdof_derivation

__all__ = ["InertiaSymbols", "inertia_symbols", "equations_of_motion", "rigid_body",
           "generate_source", "CONSTANT_NAMES"]

#: Order of the constants tuple ``k`` of the generated functions.
CONSTANT_NAMES: tuple[str, ...] = ("m", "I_b", "m_w", "A1", "A2", "x_h", "h_w", "g")


@dataclass(frozen=True)
class InertiaSymbols:
    """The symbols of the derivation.

    Attributes
    ----------
    states : tuple of Symbol
        u, w, q, theta.
    rates : tuple of Symbol
        u_dot, w_dot, q_dot (the unknowns).
    kinematics : tuple of Symbol
        phi, phi_dot, phi_ddot (prescribed).
    loads : tuple of Symbol
        X, Z, M: the aerodynamic loads about O.
    constants : tuple of Symbol
        In the order of :data:`CONSTANT_NAMES`: total mass m (body and both wings), the body's
        pitch inertia I_b about its own centre of gravity, one wing's mass m_w, the pair's first
        and second spanwise mass moments about the hinge A1, A2, the hinge position x_h, h_w,
        gravity g.
    """

    states: tuple[sp.Symbol, ...]
    rates: tuple[sp.Symbol, ...]
    kinematics: tuple[sp.Symbol, ...]
    loads: tuple[sp.Symbol, ...]
    constants: tuple[sp.Symbol, ...]


@lru_cache(maxsize=1)
def inertia_symbols() -> InertiaSymbols:
    """The symbols of :func:`equations_of_motion` (real; masses and moments positive)."""
    return InertiaSymbols(
        states=sp.symbols("u w q theta", real=True),
        rates=sp.symbols("u_dot w_dot q_dot", real=True),
        kinematics=sp.symbols("phi phi_dot phi_ddot", real=True),
        loads=sp.symbols("X Z M", real=True),
        constants=sp.symbols("m I_b m_w A1 A2 x_h h_w g", real=True),
    )


def _planar() -> dict[sp.Symbol, sp.Expr]:
    """The substitution that restricts the six-dof derivation to the plane of symmetry."""
    six = sixdof_derivation.sixdof_symbols()
    s = inertia_symbols()
    u, v, w, p, q, r, roll, theta = six.states
    const = dict(zip(sixdof_derivation.CONSTANT_NAMES, six.constants, strict=True))
    lateral = {v: 0, p: 0, r: 0, roll: 0, const["y_w"]: 0}
    lateral.update({x: 0 for x in (six.rates[1], six.rates[3], six.rates[5])})
    lateral.update({six.loads[1]: 0, six.loads[3]: 0, six.loads[5]: 0})
    # Same names and assumptions are the same SymPy symbols, except the body's pitch inertia.
    lateral[const["I_y"]] = s.constants[1]
    return lateral


@lru_cache(maxsize=1)
def equations_of_motion() -> tuple[sp.Matrix, sp.Matrix]:
    """The mass matrix A (3 x 3) and the forcing F (3 x 1) of A x_dot = (X, Z, M) + F.

    The rows (u, w, q) of :func:`flapping.model.sixdof_derivation.equations_of_motion` in the
    plane of symmetry (v = p = r = roll = 0, both wings alike, roots on the plane of symmetry).
    There the longitudinal rows do not involve the lateral accelerations (checked here: the
    restriction raises otherwise).

    Returns
    -------
    A, F : sympy.Matrix
        In the symbols of :func:`inertia_symbols`; x_dot = (u_dot, w_dot, q_dot).
    """
    A6, F6 = sixdof_derivation.equations_of_motion()
    planar = _planar()
    rows, lateral = (0, 2, 4), (1, 3, 5)
    coupling = [sp.simplify(A6[i, j].subs(planar)) for i in rows for j in lateral]
    if any(c != 0 for c in coupling):
        raise AssertionError(f"longitudinal rows couple to lateral rates: {coupling}")
    A = sp.Matrix(3, 3, lambda i, j: sp.expand(A6[rows[i], rows[j]].subs(planar)))
    forcing = sp.Matrix([sp.expand(F6[i].subs(planar)) for i in rows])
    # simplify's factorisation (Wang's algorithm) draws random evaluation points from SymPy's
    # unseeded generator: the result is unique, but an unlucky draw once ran for over 20
    # minutes (a CI run) where the derivation takes ~3 s. A fixed seed makes the path, and the
    # time, reproducible; the generator's state is restored afterwards.
    state = sympy_random.rng.getstate()
    sympy_random.seed(20261202)
    try:
        return A.applyfunc(sp.simplify), forcing.applyfunc(sp.simplify)
    finally:
        sympy_random.rng.setstate(state)


@lru_cache(maxsize=1)
def rigid_body() -> tuple[sp.Matrix, sp.Matrix]:
    """The planar rigid-body equations (massless wings, the paper's eq. 2) without the loads.

    With m_w = A1 = A2 = 0 the mass matrix is diag(m, m, I_b), so the rates are
    (X / m, Z / m, M / I_b, 0, 0, 0) plus what this returns: the rates at zero aerodynamic
    load, with the pitch angle's rate and the earth-frame velocity (forward, down) of the
    six-dof derivation in the plane. The loads are added by the caller in the form its
    aerodynamic model gives them (eq. 29's derivatives come per unit mass and inertia).

    Returns
    -------
    rates : sympy.Matrix
        (u_dot, w_dot, q_dot, theta_dot, down, forward) at zero load, 6 x 1, in u, w, q, theta
        and g.
    jacobian : sympy.Matrix
        d rates / d(u, w, q, theta), 6 x 4.
    """
    s = inertia_symbols()
    m, i_b, m_w, a1, a2 = s.constants[:5]
    A, F = equations_of_motion()
    massless = {m_w: 0, a1: 0, a2: 0}
    if A.subs(massless) != sp.diag(m, m, i_b):
        raise AssertionError("massless wings must leave diag(m, m, I_b)")  # cannot happen
    accel = A.subs(massless).LUsolve(F.subs(massless)).applyfunc(sp.simplify)
    planar = _planar()
    theta_dot = sixdof_derivation.euler_rates()[1].subs(planar)
    forward, _, down = (x.subs(planar) for x in sixdof_derivation.earth_velocity())
    rates = sp.Matrix([*accel, theta_dot, down, forward])
    return rates, rates.jacobian(sp.Matrix(s.states))


def _printed(name: str, args: str, doc: str, exprs: list[sp.Expr],
             floats: bool = False) -> list[str]:
    """Lines of one generated function returning ``exprs`` (common subexpressions shared)."""
    s = inertia_symbols()
    replacements, reduced = sp.cse(exprs, symbols=sp.numbered_symbols("c"))
    lines = [f"def {name}({args}):", f'    """{doc}"""']
    if args.endswith(", k"):
        lines.append("    " + ", ".join(str(c) for c in s.constants) + " = k")
    for symbol, expr in replacements:
        lines.append(f"    {symbol} = {sp.pycode(expr, fully_qualified_modules=True)}")
    # Whole-number entries as floats in the massless functions, so that numba types their
    # tuples as homogeneous (indexable in a loop); A's entries keep SymPy's printing.
    body = ", ".join(f"{float(e)!r}" if floats and e.is_Integer
                     else sp.pycode(e, fully_qualified_modules=True) for e in reduced)
    lines.append(f"    return ({body},)")
    return lines


def generate_source() -> str:
    """The text of ``flapping/model/_inertia_generated.py`` (scalar functions, math only).

    Returns
    -------
    str
        Python source: ``mass_matrix``, ``forcing``, ``forcing_state_jac``,
        ``mass_matrix_phi_jac``, ``forcing_kinematic_jac``, ``rigid_rates`` and
        ``rigid_state_jac`` (row-major tuples).
    """
    s = inertia_symbols()
    A, F = equations_of_motion()
    rates, jac = rigid_body()
    phi, phi_dot, phi_ddot = s.kinematics
    states, kin = list(s.states), list(s.kinematics)
    a_entries = [A[i, j] for i in range(3) for j in range(3)]
    functions: list[tuple[str, str, str, list[sp.Expr], bool]] = [
        ("mass_matrix", "phi, k", "A of A x_dot = loads + F, row-major (9 values).",
         a_entries, False),
        ("forcing", "phi, phi_dot, phi_ddot, u, w, q, theta, k",
         "F of A x_dot = loads + F (3 values).", list(F), False),
        ("forcing_state_jac", "phi, phi_dot, phi_ddot, u, w, q, theta, k",
         "dF/d(u, w, q, theta), row-major (12 values).",
         [sp.diff(F[i], x) for i in range(3) for x in states], False),
        ("mass_matrix_phi_jac", "phi, k", "dA/dphi, row-major (9 values).",
         [sp.diff(e, phi) for e in a_entries], False),
        ("forcing_kinematic_jac", "phi, phi_dot, phi_ddot, u, w, q, theta, k",
         "dF/d(phi, phi_dot, phi_ddot), row-major (9 values).",
         [sp.diff(F[i], x) for i in range(3) for x in kin], False),
        ("rigid_rates", "u, w, q, theta, g",
         "(u_dot, w_dot, q_dot, theta_dot, down, forward) of eq. 2 at zero load (6 values).",
         list(rates), True),
        ("rigid_state_jac", "u, w, q, theta, g",
         "d rigid_rates / d(u, w, q, theta), row-major (24 values).",
         [jac[i, j] for i in range(6) for j in range(4)], True),
    ]
    del phi_dot, phi_ddot
    out = ['"""Generated by flapping.model.inertia_derivation.generate_source(): do not edit.',
           "", "The planar equations of motion: with the wings' mass (mass matrix A and forcing F;",
           "constants k in the order of :data:`flapping.model.inertia_derivation.CONSTANT_NAMES`)",
           "and without (rigid_rates).", '"""', "",
           "import math", ""]
    for name, args, doc, exprs, floats in functions:
        out += ["", *_printed(name, args, doc, exprs, floats), ""]
    return "\n".join(out).rstrip() + "\n"

"""SymPy derivation of the wings' inertial loads on the body (the paper neglects them).

The paper's eq. (2) treats the insect as one rigid body: massless wings. Real wings are not
(a hawkmoth's pair weighs ~6 % of its body), and flapping them shakes the body every stroke. This
module derives, by computer algebra, the longitudinal equations of motion of a rigid body carrying
two wings whose motion relative to the body is prescribed (the stroke angle phi(t)):

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

Layering: imports nothing of the model (SymPy only).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import sympy as sp
import sympy.core.random as sympy_random

__all__ = ["InertiaSymbols", "inertia_symbols", "equations_of_motion", "generate_source",
           "CONSTANT_NAMES"]

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


def _cross(a: sp.Matrix, b: sp.Matrix) -> sp.Matrix:
    return a.cross(b)


def _wing_integral(expr: sp.Expr, rho: sp.Symbol, m_w: sp.Expr, a1: sp.Expr,
                   a2: sp.Expr) -> sp.Expr:
    """int over one wing of expr dm, expr a polynomial of degree <= 2 in the span position rho."""
    poly = sp.Poly(sp.expand(expr), rho)
    moments = {0: m_w, 1: a1 / 2, 2: a2 / 2}
    total = sp.Integer(0)
    for (power,), coefficient in poly.terms():
        if power not in moments:
            raise AssertionError(f"wing integrand of degree {power} in rho")  # cannot happen
        total += coefficient * moments[power]
    return total


@lru_cache(maxsize=1)
def equations_of_motion() -> tuple[sp.Matrix, sp.Matrix]:
    """The mass matrix A (3 x 3) and the forcing F (3 x 1) of A x_dot = (X, Z, M) + F.

    Returns
    -------
    A, F : sympy.Matrix
        In the symbols of :func:`inertia_symbols`; x_dot = (u_dot, w_dot, q_dot).
    """
    s = inertia_symbols()
    u, w, q, theta = s.states
    u_dot, w_dot, q_dot = s.rates
    m, i_b, m_w, a1, a2, x_h, h_w, g = s.constants
    t, rho = sp.symbols("t rho", real=True)
    phi_t = sp.Function("phi", real=True)(t)

    omega = sp.Matrix([0, q, 0])
    omega_dot = sp.Matrix([0, q_dot, 0])
    velocity = sp.Matrix([u, 0, w])
    a_origin = sp.Matrix([u_dot, 0, w_dot]) + _cross(omega, velocity)
    gravity = g * sp.Matrix([-sp.sin(theta), 0, sp.cos(theta)])

    force = (m - 2 * m_w) * (a_origin - gravity)      # the body, its CG at O
    moment_y = i_b * q_dot                              # the body's pitch about its own CG
    for side in (1, -1):
        r = sp.Matrix([x_h + rho * sp.sin(phi_t), side * rho * sp.cos(phi_t), -h_w])
        r_dot, r_ddot = r.diff(t), r.diff(t, 2)
        accel = (a_origin + _cross(omega_dot, r) + _cross(omega, _cross(omega, r))
                 + 2 * _cross(omega, r_dot) + r_ddot)
        net = accel - gravity                           # per unit mass: m a - m g
        phase = {phi_t.diff(t, 2): s.kinematics[2], phi_t.diff(t): s.kinematics[1],
                 phi_t: s.kinematics[0]}
        net = net.subs(phase)
        torque_y = _cross(r.subs(phase), net)[1]
        force += sp.Matrix([_wing_integral(net[i], rho, m_w, a1, a2) for i in range(3)])
        moment_y += _wing_integral(torque_y, rho, m_w, a1, a2)

    X, Z, M = s.loads
    residual = [sp.expand(force[0] - X), sp.expand(force[2] - Z), sp.expand(moment_y - M)]
    A, b = sp.linear_eq_to_matrix(residual, list(s.rates))
    forcing = (b - sp.Matrix(list(s.loads))).applyfunc(sp.expand)
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


def _printed(name: str, args: str, doc: str, exprs: list[sp.Expr]) -> list[str]:
    """Lines of one generated function returning ``exprs`` (common subexpressions shared)."""
    s = inertia_symbols()
    replacements, reduced = sp.cse(exprs, symbols=sp.numbered_symbols("c"))
    lines = [f"def {name}({args}):", f'    """{doc}"""']
    lines.append("    " + ", ".join(str(c) for c in s.constants) + " = k")
    for symbol, expr in replacements:
        lines.append(f"    {symbol} = {sp.pycode(expr, fully_qualified_modules=True)}")
    body = ", ".join(sp.pycode(e, fully_qualified_modules=True) for e in reduced)
    lines.append(f"    return ({body},)")
    return lines


def generate_source() -> str:
    """The text of ``flapping/model/_inertia_generated.py`` (scalar functions, math only).

    Returns
    -------
    str
        Python source: ``mass_matrix``, ``forcing``, ``forcing_state_jac``,
        ``mass_matrix_phi_jac`` and ``forcing_kinematic_jac`` (row-major tuples).
    """
    s = inertia_symbols()
    A, F = equations_of_motion()
    phi, phi_dot, phi_ddot = s.kinematics
    states, kin = list(s.states), list(s.kinematics)
    a_entries = [A[i, j] for i in range(3) for j in range(3)]
    functions = [
        ("mass_matrix", "phi, k", "A of A x_dot = loads + F, row-major (9 values).", a_entries),
        ("forcing", "phi, phi_dot, phi_ddot, u, w, q, theta, k",
         "F of A x_dot = loads + F (3 values).", list(F)),
        ("forcing_state_jac", "phi, phi_dot, phi_ddot, u, w, q, theta, k",
         "dF/d(u, w, q, theta), row-major (12 values).",
         [sp.diff(F[i], x) for i in range(3) for x in states]),
        ("mass_matrix_phi_jac", "phi, k", "dA/dphi, row-major (9 values).",
         [sp.diff(e, phi) for e in a_entries]),
        ("forcing_kinematic_jac", "phi, phi_dot, phi_ddot, u, w, q, theta, k",
         "dF/d(phi, phi_dot, phi_ddot), row-major (9 values).",
         [sp.diff(F[i], x) for i in range(3) for x in kin]),
    ]
    del phi_dot, phi_ddot
    out = ['"""Generated by flapping.model.inertia_derivation.generate_source(): do not edit.',
           "", "The wings' inertial loads (mass matrix A and forcing F); constants k in the order",
           "of :data:`flapping.model.inertia_derivation.CONSTANT_NAMES`.", '"""', "",
           "import math", ""]
    for name, args, doc, exprs in functions:
        out += ["", *_printed(name, args, doc, exprs), ""]
    return "\n".join(out).rstrip() + "\n"

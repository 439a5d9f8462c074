"""SymPy derivation of the insect in six degrees of freedom: one body, two flapping wings.

The paper's insect is planar (u, w, q, theta). This module derives, once and by computer algebra,
everything the six-degree-of-freedom model needs that is geometry and mechanics, leaving to
:mod:`flapping.model.aerodynamics` only the section law (the loads of a strip given its speed):

1. **Frames.** Body axes x forward, y right, z down at the centre of gravity O; states
   (u, v, w) [m/s], (p, q, r) [rad/s] and the 3-2-1 Euler angles roll and pitch theta (heading and
   position do not feed back into the loads or the body's motion). Inertia tensor of the body
   alone about O: [[I_x, 0, -I_xz], [0, I_y, 0], [-I_xz, 0, I_z]].
2. **Wings.** Both roots at (x_h, +-y_w, -h_w) (y_w, half the root spacing, is 0 in the package
   today); the stroke plane is the body's x-y plane; the stroke angle phi(t), positive forward, is
   the same for both wings. Span directions e_R = (sin phi, cos phi, 0), e_L = (sin phi, -cos phi,
   0); stroke-tangential directions t_k = de_k/dphi, t_R = (cos phi, -sin phi, 0),
   t_L = (cos phi, sin phi, 0); normal n = (0, 0, 1).
3. **Strip kinematics.** A strip at distance rho along wing k sits at r_s = hinge_k + rho e_k and
   moves through still air at v_s = V + Omega x r_s + rho phi_dot t_k. Its chordwise speed is
   U_k = v_s . t_k, its effective normal speed w_eff_k = v_s . n (the spanwise component is
   ignored), both linear in rho, and the wing's pitch rate about its span from the body's rotation
   is Omega_k = Omega . e_R (right), -Omega . e_L (left): mirror images, so that the section law
   of the planar model applies to each wing unchanged. In the planar case both reduce to today's
   U = rho phi_dot + (u - q h_w) cos(phi), w_eff = w - q (x_h + rho sin(phi)), Omega = q cos(phi).
4. **Loads.** Each strip's tangential and normal forces F_t, F_n act along t_k and n at the
   chordwise centre of pressure d = x_hat c (-cos(alpha_g) t_k + sin(alpha_m) n) from the span line;
   the rotational damping torque tau acts about the span axis (tau e_R, -tau e_L). The moment about
   O is the sum of r x F and these torques; it needs per wing only the span integrals
   T0 = int F_t, T1 = int rho F_t, Tc = int c F_t, N0, N1, Nc likewise of F_n, and Q = int tau
   (:func:`wing_loads`).
5. **Equations of motion.** Newton's and Euler's laws for the body and the two wings, whose mass
   lies on their span lines (its chordwise mass moments and the feathering rotation are
   neglected: they are second order in the chord): the absolute
   acceleration of a wing element, a = a_O + Omega_dot x r + Omega x (Omega x r)
   + 2 Omega x r_dot + r_ddot, is integrated over each wing through its mass moments. The
   result is linear in the accelerations:
   A(phi) (u_dot, v_dot, w_dot, p_dot, q_dot, r_dot) = (X, Y, Z, L, M, N) + F.
   Massless wings give A = diag(m, m, m, inertia tensor) and the rigid-body equations.
6. **Kinematics of the attitude and the path.** The 3-2-1 Euler angle rates (roll, theta) from
   (p, q, r), and the velocity in the earth frame (x north, z down; heading zero, since it does
   not feed back), whose vertical component the hover condition holds at zero mean.

:func:`generate_source` prints these as plain Python (math only, common subexpressions shared) into
``flapping/model/_sixdof_generated.py``, committed; a test regenerates it and compares the text.
Importing :mod:`flapping` never runs this derivation.

The planar model is this derivation's special case: :mod:`flapping.model.inertia_derivation`
restricts it to the plane of symmetry (v = p = r = roll = 0) and prints the planar equations of
motion, with and without wing mass, that every planar path of the package runs.

Layering: imports nothing of the model (SymPy only).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from functools import lru_cache

import sympy as sp

__all__ = ["STATE_NAMES", "CONSTANT_NAMES", "RESULTANT_NAMES", "SixDofSymbols", "sixdof_symbols",
           "strip_kinematics", "wing_loads", "equations_of_motion", "euler_rates",
           "earth_velocity", "wing_integral", "generate_source", "section_coefficients",
           "load_jacobians", "generate_jacobian_source"]

#: The eight states that feed back, in order (heading and position do not).
STATE_NAMES: tuple[str, ...] = ("u", "v", "w", "p", "q", "r", "roll", "theta")
#: Order of the constants tuple ``k`` of the generated mechanics functions.
CONSTANT_NAMES: tuple[str, ...] = ("m", "I_x", "I_y", "I_z", "I_xz", "m_w", "A1", "A2",
                                   "x_h", "y_w", "h_w", "g")
#: Per-wing span integrals the load assembly takes (see the module docstring, step 4).
RESULTANT_NAMES: tuple[str, ...] = ("T0", "T1", "Tc", "N0", "N1", "Nc", "Q")


@dataclass(frozen=True)
class SixDofSymbols:
    """The symbols of the derivation (all real).

    Attributes
    ----------
    states : tuple of Symbol
        u, v, w, p, q, r, roll, theta.
    rates : tuple of Symbol
        u_dot, v_dot, w_dot, p_dot, q_dot, r_dot (the unknowns of step 5).
    kinematics : tuple of Symbol
        phi, phi_dot, phi_ddot (prescribed).
    loads : tuple of Symbol
        X, Y, Z, L, M, N: the aerodynamic loads about O in body axes.
    constants : tuple of Symbol
        In the order of :data:`CONSTANT_NAMES`: total mass, the body's inertia tensor entries,
        one wing's mass, the pair's first and second spanwise mass moments about the hinge, the
        hinge position (x_h ahead, y_w to the side, h_w above O), gravity.
    rho : Symbol
        Distance along the span from the wing root.
    """

    states: tuple[sp.Symbol, ...]
    rates: tuple[sp.Symbol, ...]
    kinematics: tuple[sp.Symbol, ...]
    loads: tuple[sp.Symbol, ...]
    constants: tuple[sp.Symbol, ...]
    rho: sp.Symbol


@lru_cache(maxsize=1)
def sixdof_symbols() -> SixDofSymbols:
    """The symbols of this derivation, created once."""
    return SixDofSymbols(
        states=sp.symbols("u v w p q r roll theta", real=True),
        rates=sp.symbols("u_dot v_dot w_dot p_dot q_dot r_dot", real=True),
        kinematics=sp.symbols("phi phi_dot phi_ddot", real=True),
        loads=sp.symbols("X Y Z L M N", real=True),
        constants=sp.symbols(" ".join(CONSTANT_NAMES), real=True),
        rho=sp.Symbol("rho", real=True),
    )


#: The two wings: name and side (+1 right, -1 left).
SIDES: tuple[tuple[str, int], ...] = (("R", 1), ("L", -1))


def wing_integral(expr: sp.Expr, rho: sp.Symbol, m_w: sp.Expr, a1: sp.Expr,
                  a2: sp.Expr) -> sp.Expr:
    """int over one wing of expr dm, expr a polynomial of degree <= 2 in the span position rho.

    The wing's mass lies on its span line: int dm = m_w, int rho dm = A1 / 2 and
    int rho^2 dm = A2 / 2 (A1, A2 of the pair).
    """
    poly = sp.Poly(sp.expand(expr), rho)
    moments = {0: m_w, 1: a1 / 2, 2: a2 / 2}
    total = sp.Integer(0)
    for (power,), coefficient in poly.terms():
        if power not in moments:
            raise AssertionError(f"wing integrand of degree {power} in rho")  # cannot happen
        total += coefficient * moments[power]
    return total


def _frame(phi: sp.Expr, side: int) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """(e_k, t_k, n) of wing ``side`` at stroke angle phi (step 2)."""
    e = sp.Matrix([sp.sin(phi), side * sp.cos(phi), 0])
    return e, e.diff(phi), sp.Matrix([0, 0, 1])


def _hinge(side: int) -> sp.Matrix:
    s = sixdof_symbols()
    x_h, y_w, h_w = s.constants[8:11]
    return sp.Matrix([x_h, side * y_w, -h_w])


def _body_rates() -> tuple[sp.Matrix, sp.Matrix]:
    """(V, Omega): the body's velocity and angular velocity in body axes."""
    u, v, w, p, q, r = sixdof_symbols().states[:6]
    return sp.Matrix([u, v, w]), sp.Matrix([p, q, r])


@lru_cache(maxsize=1)
def strip_kinematics() -> dict[str, tuple[sp.Expr, ...]]:
    """Step 3: per wing, U = U0 + U1 rho, w_eff = W0 + W1 rho and the span-axis pitch rate Omega_k.

    Returns
    -------
    dict
        ``{"R": (U0, U1, W0, W1, Omega_R), "L": (...)}`` in the states, phi and phi_dot.
    """
    s = sixdof_symbols()
    phi, phi_dot = s.kinematics[:2]
    V, Omega = _body_rates()
    out = {}
    for name, side in SIDES:
        e, t, n = _frame(phi, side)
        r_s = _hinge(side) + s.rho * e
        v_s = V + Omega.cross(r_s) + s.rho * phi_dot * t
        U = sp.Poly(sp.expand(v_s.dot(t)), s.rho)
        W = sp.Poly(sp.expand(v_s.dot(n)), s.rho)
        if U.degree() > 1 or W.degree() > 1:
            raise AssertionError("strip speeds must be linear along the span")  # cannot happen
        omega_k = side * Omega.dot(e)
        out[name] = tuple(sp.trigsimp(sp.expand(x)) for x in (
            U.coeff_monomial(1), U.coeff_monomial(s.rho), W.coeff_monomial(1),
            W.coeff_monomial(s.rho), omega_k))
    return out


def _resultant_symbols(name: str) -> tuple[sp.Symbol, ...]:
    return tuple(sp.Symbol(f"{r}_{name}", real=True) for r in RESULTANT_NAMES)


@lru_cache(maxsize=1)
def wing_loads() -> sp.Matrix:
    """Step 4: the aerodynamic loads (X, Y, Z, L, M, N) about O from both wings' span integrals.

    Per unit span a strip carries F_t along t_k and F_n along n at r_s + d, and the torque tau
    about its span axis; the moment integrand (r_s + d) x (F_t t_k + F_n n) + side tau e_k is
    linear in F_t, F_n, with coefficients 1, rho and the chord c: its span integral is a linear
    form in the integrals T0, T1, Tc, N0, N1, Nc and Q of :data:`RESULTANT_NAMES`.

    Returns
    -------
    sympy.Matrix
        6 x 1, in phi, the stroke sign s (cos(alpha_g) = s cos(alpha_m)), alpha_m, x_hat, the
        hinge constants and the symbols ``T0_R`` ... ``Q_L``.
    """
    s = sixdof_symbols()
    phi = s.kinematics[0]
    sign, alpha_m, x_hat, c = sp.symbols("s alpha_m x_hat c", real=True)
    f_t, f_n, tau = sp.symbols("F_t F_n tau", real=True)
    total = sp.zeros(6, 1)
    for name, side in SIDES:
        e, t, n = _frame(phi, side)
        d = x_hat * c * (-sign * sp.cos(alpha_m) * t + sp.sin(alpha_m) * n)
        force = f_t * t + f_n * n
        moment = (_hinge(side) + s.rho * e + d).cross(force) + side * tau * e
        T0, T1, Tc, N0, N1, Nc, Q = _resultant_symbols(name)
        integral = {(f_t, 0, 0): T0, (f_t, 1, 0): T1, (f_t, 0, 1): Tc,
                    (f_n, 0, 0): N0, (f_n, 1, 0): N1, (f_n, 0, 1): Nc}
        for row, expr in enumerate(list(force) + list(moment)):
            poly = sp.Poly(sp.expand(expr), f_t, f_n, tau, s.rho, c)
            for (a, _b, k, i, j), coefficient in poly.terms():
                if k == 1:
                    total[row] += coefficient * Q
                else:
                    total[row] += coefficient * integral[(f_t if a else f_n, i, j)]
    return total.applyfunc(lambda x: sp.trigsimp(sp.expand(x)))


def gravity_body() -> sp.Matrix:
    """g in body axes for 3-2-1 Euler angles: g (-sin theta, sin roll cos theta, cos roll cos
    theta)."""
    s = sixdof_symbols()
    roll, theta = s.states[6:]
    g = s.constants[-1]
    return g * sp.Matrix([-sp.sin(theta), sp.sin(roll) * sp.cos(theta),
                          sp.cos(roll) * sp.cos(theta)])


@lru_cache(maxsize=1)
def equations_of_motion() -> tuple[sp.Matrix, sp.Matrix]:
    """Step 5: the mass matrix A (6 x 6) and forcing F (6 x 1) of A x_dot = loads + F.

    Returns
    -------
    A, F : sympy.Matrix
        In the symbols of :func:`sixdof_symbols`; x_dot = (u_dot, v_dot, w_dot, p_dot, q_dot,
        r_dot), loads = (X, Y, Z, L, M, N) about O.
    """
    s = sixdof_symbols()
    m, i_x, i_y, i_z, i_xz, m_w, a1, a2 = s.constants[:8]
    t = sp.Symbol("t", real=True)
    phi_t = sp.Function("phi", real=True)(t)
    V, Omega = _body_rates()
    V_dot, Omega_dot = sp.Matrix(s.rates[:3]), sp.Matrix(s.rates[3:])
    a_origin = V_dot + Omega.cross(V)
    gravity = gravity_body()
    inertia = sp.Matrix([[i_x, 0, -i_xz], [0, i_y, 0], [-i_xz, 0, i_z]])
    force = (m - 2 * m_w) * (a_origin - gravity)            # the body, its CG at O
    moment = inertia * Omega_dot + Omega.cross(inertia * Omega)
    phase = {phi_t.diff(t, 2): s.kinematics[2], phi_t.diff(t): s.kinematics[1],
             phi_t: s.kinematics[0]}
    for _, side in SIDES:
        r = _hinge(side) + s.rho * _frame(phi_t, side)[0]
        r_dot, r_ddot = r.diff(t), r.diff(t, 2)
        accel = (a_origin + Omega_dot.cross(r) + Omega.cross(Omega.cross(r))
                 + 2 * Omega.cross(r_dot) + r_ddot)
        net = (accel - gravity).subs(phase)                 # per unit mass: a - g
        torque = r.subs(phase).cross(net)
        force += sp.Matrix([wing_integral(net[i], s.rho, m_w, a1, a2) for i in range(3)])
        moment += sp.Matrix([wing_integral(torque[i], s.rho, m_w, a1, a2) for i in range(3)])
    residual = [sp.expand(x - load) for x, load in zip(list(force) + list(moment), s.loads,
                                                         strict=True)]
    A, b = sp.linear_eq_to_matrix(residual, list(s.rates))
    forcing = (b - sp.Matrix(list(s.loads))).applyfunc(sp.expand)
    return A.applyfunc(lambda x: sp.trigsimp(sp.expand(x))), forcing.applyfunc(sp.trigsimp)


@lru_cache(maxsize=1)
def euler_rates() -> tuple[sp.Expr, sp.Expr]:
    """(roll_dot, theta_dot) of the 3-2-1 Euler angles from the body rates (p, q, r)."""
    s = sixdof_symbols()
    p, q, r, roll, theta = s.states[3:]
    return (p + (q * sp.sin(roll) + r * sp.cos(roll)) * sp.tan(theta),
            q * sp.cos(roll) - r * sp.sin(roll))


@lru_cache(maxsize=1)
def earth_velocity() -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """The body's velocity in the earth frame (x forward at zero heading, y right, z down).

    The body-to-earth rotation of 3-2-1 Euler angles with the heading set to zero (it does not
    feed back into anything), applied to (u, v, w).
    """
    s = sixdof_symbols()
    roll, theta = s.states[6:]
    V, _ = _body_rates()
    c_roll, s_roll = sp.cos(roll), sp.sin(roll)
    c_th, s_th = sp.cos(theta), sp.sin(theta)
    pitch = sp.Matrix([[c_th, 0, s_th], [0, 1, 0], [-s_th, 0, c_th]])
    bank = sp.Matrix([[1, 0, 0], [0, c_roll, -s_roll], [0, s_roll, c_roll]])
    forward, right, down = (sp.expand(x) for x in pitch * bank * V)
    return forward, right, down


def _printed(name: str, args: str, doc: str, exprs: list[sp.Expr], unpack: str = "") -> list[str]:
    """Lines of one generated function returning ``exprs`` (common subexpressions shared)."""
    replacements, reduced = sp.cse(exprs, symbols=sp.numbered_symbols("c"))
    lines = [f"def {name}({args}):", f'    """{doc}"""']
    if unpack:
        lines.append(f"    {unpack}")
    for symbol, expr in replacements:
        lines.append(f"    {symbol} = {sp.pycode(expr, fully_qualified_modules=True)}")
    body = ", ".join(sp.pycode(e, fully_qualified_modules=True) for e in reduced)
    lines.append(f"    return ({body},)")
    return lines


def generate_source() -> str:
    """The text of ``flapping/model/_sixdof_generated.py`` (scalar functions, math only).

    Returns
    -------
    str
        Python source: ``strip_kinematics`` (per wing U0, U1, W0, W1, Omega_k; right then left),
        ``wing_loads`` (X, Y, Z, L, M, N from the 14 span integrals), ``mass_matrix`` (36 values,
        row-major), ``forcing`` (6), ``euler_rates`` (2) and ``earth_velocity`` (3).
    """
    s = sixdof_symbols()
    states = ", ".join(str(x) for x in s.states)
    constants = ", ".join(CONSTANT_NAMES) + " = k"
    kin = strip_kinematics()
    A, F = equations_of_motion()
    resultants = ", ".join(str(x) for name, _ in SIDES for x in _resultant_symbols(name))
    functions = [
        ("strip_kinematics", f"phi, phi_dot, {states}, k",
         "Per wing (U0, U1, W0, W1, Omega_k), right then left (10 values).",
         [*kin["R"], *kin["L"]], constants),
        ("wing_loads", f"phi, s, alpha_m, x_hat, {resultants}, k",
         "(X, Y, Z, L, M, N) about the centre of gravity from the wings' span integrals.",
         list(wing_loads()), constants),
        ("mass_matrix", "phi, k", "A of A x_dot = loads + F, row-major (36 values).",
         [A[i, j] for i in range(6) for j in range(6)], constants),
        ("forcing", f"phi, phi_dot, phi_ddot, {states}, k", "F of A x_dot = loads + F (6 values).",
         list(F), constants),
        ("euler_rates", f"{states}", "(roll_dot, theta_dot) of the 3-2-1 Euler angles.",
         list(euler_rates()), ""),
        ("earth_velocity", f"{states}",
         "(forward, right, down) velocity in the earth frame at zero heading.",
         list(earth_velocity()), ""),
    ]
    out = ['"""Generated by flapping.model.sixdof_derivation.generate_source(): do not edit.',
           "", "The insect in six degrees of freedom: strip kinematics, load assembly, equations",
           "of motion. Constants k in the order of",
           ":data:`flapping.model.sixdof_derivation.CONSTANT_NAMES`.", '"""', "",
           "# ruff: noqa", "import math", ""]
    for name, args, doc, exprs, unpack in functions:
        out += ["", *_printed(name, args, doc, exprs, unpack), ""]
    return "\n".join(out).rstrip() + "\n"


# --------------------------------------------------------------------------- Jacobians
#: The section-law symbols of :func:`section_coefficients`: the strip's chordwise and effective
#: normal speeds, the sign taken for ``|U|`` (small-angle), the load constants of
#: :func:`flapping.model.aerodynamics._lev_coefficients`, and a tiny offset of ``|V|^2``.
SECTION_SYMBOLS: tuple[str, ...] = ("U", "W", "sigma", "sin_2ag", "cos_2am", "sin_am2",
                                    "cos_am2", "tiny")


def section_coefficients(variant: str) -> tuple[sp.Expr, ...]:
    """The leading-edge-vortex coefficients (a, b) of a section and their gradients in (U, W).

    The section law of :func:`flapping.model.aerodynamics._lev_coefficients` (F_t = rho A c a,
    F_n = rho A c b per unit span), restated in SymPy for its derivatives: in the small-angle
    variant ``|U|`` is sigma U (the compiled span integration corrects the piece where the sign
    differs, as the Python one does); the exact variant's ``|V|`` is sqrt(U^2 + W^2 + tiny).

    Parameters
    ----------
    variant : {"small-angle", "exact"}

    Returns
    -------
    tuple of sympy.Expr
        (a, b, da/dU, da/dW, db/dU, db/dW) in the symbols :data:`SECTION_SYMBOLS`.
    """
    U, W, sigma, sin_2ag, cos_2am, sin_am2, cos_am2, tiny = sp.symbols(
        " ".join(SECTION_SYMBOLS), real=True)
    if variant == "small-angle":
        abs_u = sigma * U
        a = -(U * abs_u * sin_am2 + sin_2ag / 2 * abs_u * W)
        b = -(sin_2ag / 2 * U * abs_u + cos_am2 * abs_u * W)
    else:
        diff, v2 = U**2 - W**2, U**2 + W**2
        lift = sin_2ag * diff + 2 * cos_2am * U * W
        drag = v2 - cos_2am * diff + 2 * sin_2ag * U * W
        half_inv_v = 1 / (2 * sp.sqrt(v2 + tiny))
        a = (lift * W - drag * U) * half_inv_v
        b = -(lift * U + drag * W) * half_inv_v
    return (a, b, sp.diff(a, U), sp.diff(a, W), sp.diff(b, U), sp.diff(b, W))


@lru_cache(maxsize=1)
def load_jacobians() -> tuple[sp.Matrix, sp.Matrix]:
    """The geometry's Jacobians for the variational equations of the blade-element loads.

    Returns
    -------
    kinematics : sympy.Matrix, 10 x 8
        d(strip speeds of :func:`strip_kinematics`, right then left)/d(the eight states).
    assembly : sympy.Matrix, 6 x 14
        d(X, Y, Z, L, M, N)/d(T0_R ... Q_L): the coefficients of :func:`wing_loads`, which is
        linear in the wings' span integrals.
    """
    s = sixdof_symbols()
    kin = strip_kinematics()
    speeds = sp.Matrix([*kin["R"], *kin["L"]])
    resultants = [x for name, _ in SIDES for x in _resultant_symbols(name)]
    return speeds.jacobian(list(s.states)), wing_loads().jacobian(resultants)


def _printed_into(name: str, args: str, doc: str, exprs: list[sp.Expr],
                  unpack: str = "") -> list[str]:
    """Lines of one generated function writing ``exprs`` into the float64 array ``out``."""
    replacements, reduced = sp.cse(exprs, symbols=sp.numbered_symbols("c"))
    lines = [f"def {name}({args}, out):", f'    """{doc}"""']
    if unpack:
        lines.append(f"    {unpack}")
    for symbol, expr in replacements:
        lines.append(f"    {symbol} = {sp.pycode(expr, fully_qualified_modules=True)}")
    for i, e in enumerate(reduced):
        value = sp.pycode(sp.Float(e) if e.is_Number else e, fully_qualified_modules=True)
        lines.append(f"    out[{i}] = {value}")
    return lines


def generate_jacobian_source() -> str:
    """The text of ``flapping/model/_sixdof_jacobian_generated.py`` (scalar functions, math only).

    Returns
    -------
    str
        Python source that numba compiles (outputs written into float64 arrays):
        ``kinematics_jacobian`` (80 values, 10 x 8 row-major), ``assembly_jacobian`` (84 values,
        6 x 14) of :func:`load_jacobians`, and ``section_small_angle`` and ``section_exact`` (6
        values: a, b and their derivatives in U and W) of :func:`section_coefficients`.
    """
    s = sixdof_symbols()
    states = ", ".join(str(x) for x in s.states)
    constants = ", ".join(CONSTANT_NAMES) + " = k"
    kinematics, assembly = load_jacobians()
    section = ", ".join(SECTION_SYMBOLS)
    functions = [
        ("kinematics_jacobian", f"phi, phi_dot, {states}, k",
         "d(U0, U1, W0, W1, Omega_k; right then left)/d(states), row-major into out[:80].",
         [kinematics[i, j] for i in range(10) for j in range(8)], constants),
        ("assembly_jacobian", "phi, s, alpha_m, x_hat, k",
         "d(X, Y, Z, L, M, N)/d(T0_R ... Q_L), row-major into out[:84].",
         [assembly[i, j] for i in range(6) for j in range(14)], constants),
        ("section_small_angle", section,
         "(a, b, a_U, a_W, b_U, b_W) of the small-angle section law into out[:6].",
         list(section_coefficients("small-angle")), ""),
        ("section_exact", section,
         "(a, b, a_U, a_W, b_U, b_W) of the exact section law into out[:6].",
         list(section_coefficients("exact")), ""),
    ]
    out = ['"""Generated by flapping.model.sixdof_derivation.generate_jacobian_source(): do not '
           "edit.", "",
           "The Jacobians of the six-degree-of-freedom blade-element loads: strip kinematics,",
           "load assembly and the section law. Regenerate with",
           "`python -m flapping.model.sixdof_derivation jacobians > "
           "flapping/model/_sixdof_jacobian_generated.py`",
           "(a test checks that the committed file equals a fresh generation).", '"""', "",
           "# ruff: noqa", "import math", ""]
    for name, args, doc, exprs, unpack in functions:
        out += ["", *_printed_into(name, args, doc, exprs, unpack), ""]
    # SymPy prints a float 1 as 1.00000000000000: shorten such literals.
    return re.sub(r"\b(\d+)\.0{14}\b", r"\1.0", "\n".join(out).rstrip() + "\n")


if __name__ == "__main__":  # pragma: no cover - the regeneration command
    import sys

    if sys.argv[1:] == ["jacobians"]:
        print(generate_jacobian_source(), end="")
    else:
        print(generate_source(), end="")

"""One derivation of the mechanics: the planar equations every planar path runs are the six-dof
derivation's special case, and no module writes them by hand (issue 27, item 1)."""

import ast
import math
from pathlib import Path

import numpy as np
import pytest

import flapping
from flapping.model import _inertia_generated as planar
from flapping.model import _sixdof_generated as six

RNG = np.random.default_rng(27)
ROOT = Path(flapping.__file__).parent
#: The modules that used to write eq. (2) by hand, and now call the generated code.
RUNNERS = ("model/dynamics.py", "fast/_compiled.py", "fast/_blade.py", "fast/_sixdof.py",
           "hover/sixdof.py", "model/sixdof.py")


def constants():
    """Planar constants (m, I_b, m_w, A1, A2, x_h, h_w, g) and six-dof ones with y_w = 0."""
    m, i_b, m_w, a1, a2, x_h, h_w, g = 1.6e-3, 2.1e-8, 4e-5, 1.3e-6, 4.0e-8, 1.2e-3, 2.5e-3, 9.81
    return ((m, i_b, m_w, a1, a2, x_h, h_w, g),
            (m, 1.1e-8, i_b, 2.9e-8, 3e-9, m_w, a1, a2, x_h, 0.0, h_w, g))


@pytest.mark.parametrize("trial", range(5))
def test_the_planar_equations_are_the_sixdof_ones_in_the_plane(trial):
    k4, k6 = constants()
    phi, phi_dot, phi_ddot = RNG.uniform(-1.2, 1.2), RNG.normal(0, 300), RNG.normal(0, 5e4)
    u, w, q, theta = RNG.normal(0, 0.5, 2).tolist() + RNG.normal(0, 3, 1).tolist() + [
        RNG.uniform(-1, 1)]
    A6 = np.reshape(six.mass_matrix(phi, k6), (6, 6))
    F6 = np.array(six.forcing(phi, phi_dot, phi_ddot, u, 0.0, w, 0.0, q, 0.0, 0.0, theta, k6))
    lon, lat = [0, 2, 4], [1, 3, 5]
    A4 = np.reshape(planar.mass_matrix(phi, k4), (3, 3))
    F4 = np.array(planar.forcing(phi, phi_dot, phi_ddot, u, w, q, theta, k4))
    assert np.allclose(A6[np.ix_(lon, lon)], A4, rtol=1e-13, atol=0)
    assert np.allclose(F6[lon], F4, rtol=1e-13, atol=1e-13 * np.abs(F4).max())
    assert np.abs(A6[np.ix_(lon, lat)]).max() == 0.0  # the plane decouples exactly
    assert np.abs(F6[lat]).max() <= 1e-13 * np.abs(F6).max()


def test_the_massless_planar_equations_are_the_papers_eq_2():
    # Written here, independently of the derivation: eq. (2) with the earth-frame velocity.
    g = 9.81
    for _ in range(5):
        u, w, q, theta = RNG.normal(0, 1, 4)
        r = planar.rigid_rates(u, w, q, theta, g)
        expected = (-q * w - g * math.sin(theta), q * u + g * math.cos(theta), 0.0, q,
                    -u * math.sin(theta) + w * math.cos(theta),
                    u * math.cos(theta) + w * math.sin(theta))
        assert np.allclose(r, expected, rtol=1e-15, atol=1e-15)
        J = np.reshape(planar.rigid_state_jac(u, w, q, theta, g), (6, 4))
        x, h = np.array([u, w, q, theta]), 1e-6
        for j in range(4):
            e = np.eye(4)[j] * h
            fd = (np.array(planar.rigid_rates(*(x + e), g))
                  - np.array(planar.rigid_rates(*(x - e), g))) / (2 * h)
            assert np.allclose(J[:, j], fd, atol=1e-8)


def test_massless_wings_leave_the_rigid_body_mass_matrix():
    k4, _ = constants()
    k4 = (*k4[:2], 0.0, 0.0, 0.0, *k4[5:])
    assert np.array_equal(np.reshape(planar.mass_matrix(0.7, k4), (3, 3)),
                          np.diag([k4[0], k4[0], k4[1]]))


def _products(path: Path) -> set[str]:
    """Every product of two plain names in a module, e.g. ``q * w`` (as 'q*w')."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if (isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mult)
                and isinstance(node.left, ast.Name) and isinstance(node.right, ast.Name)):
            found.add(f"{node.left.id}*{node.right.id}")
    return found


@pytest.mark.parametrize("module", RUNNERS)
def test_no_module_writes_the_equations_of_motion_by_hand(module):
    # eq. (2)'s inertial terms q w, q u and the earth-frame velocity's u cos(theta) ... used to
    # be written in each of these modules (and kept in line by tests): now none is.
    hand = {"q*w", "q*u", "w*q", "u*q", "u*cth", "w*sth", "u*sth", "w*cth", "g*sth", "g*cth",
            "u*st", "w*ct", "g*st", "g*ct", "v*sr", "w_*cr", "u*ct", "p*q", "q*r",
            "p*r", "r*q"}
    assert not _products(ROOT / module) & hand


def test_the_force_budgets_named_terms_add_up_to_the_generated_equations():
    # The hover chapter's budget names eq. (2)'s terms one by one (for its table): over a period
    # of the orbit each equation's terms must average to zero (the states are periodic), which
    # holds only if the named terms are the equations the solver ran (the generated ones).
    from flapping.hover.orbit import force_budget

    budget = force_budget(flapping.find_hover_orbit(flapping.hawkmoth()), n_samples=4000)
    scale = max(abs(v) for terms in budget.values() for v in terms.values())  # ~ g
    for equation, terms in budget.items():
        assert abs(sum(terms.values())) <= 1e-6 * scale, (equation, terms)

"""The SymPy derivation: reproducible generated code, and agreement with the blade-element model."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import flapping
from flapping.model.aerodynamics import BladeElementModel, trim_angle_of_attack
from flapping.model.derivatives import stability_derivatives
from flapping.model.dynamics import LongitudinalDynamics

sympy = pytest.importorskip("sympy")
sp_sin = sympy.sin
from flapping.model import derivation  # noqa: E402  (needs sympy)

GENERATED = Path(flapping.__file__).parent / "model" / "_derivatives_generated.py"


def test_generated_code_is_what_the_derivation_produces():
    # The committed numeric code must be exactly the output of the derivation, so the model
    # cannot drift from the algebra the book shows.
    assert GENERATED.read_text() == derivation.generate_source()


def test_importing_flapping_does_not_run_the_derivation():
    code = "import sys, flapping, flapping.model.dynamics; print('sympy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


@pytest.fixture(scope="module", params=[{}, {"hinge_height": 8e-3, "stroke_mean": 0.25}],
                ids=["paper", "hinge-height-and-mean-stroke"])
def hawkmoth_models(request):
    # x_h != 0 exercises every term; the second set adds the hinge height h_w above the CG and
    # the mean stroke angle phi_bar, both non-zero.
    insect = flapping.hawkmoth(hinge_offset=1.5e-3, **request.param)
    alpha_m = trim_angle_of_attack(insect)
    linear = LongitudinalDynamics(insect, alpha_m=alpha_m)
    blade = BladeElementModel(insect, alpha_m, variant="small-angle", n_nodes=40)
    return insect, linear, blade


# Phases avoiding stroke reversal (t = 0, T/2), where |U| has a kink at the zero state.
PHASES = [0.03, 0.11, 0.2, 0.27, 0.38, 0.46, 0.55, 0.61, 0.74, 0.83, 0.9, 0.97]


@pytest.mark.parametrize("phase", PHASES)
def test_symbolic_derivatives_match_finite_differences_of_blade_element_loads(hawkmoth_models, phase):
    insect, linear, blade = hawkmoth_models
    t = phase * insect.period
    d = np.array(linear.derivatives(t))
    loads0 = blade.loads(t, 0.0, 0.0, 0.0)
    scale = np.array([insect.mass, insect.mass, insect.pitch_inertia])
    # Zero-state loads: exact quadrature of polynomials in r times c^n, so near round-off.
    np.testing.assert_allclose(d[:3], loads0, rtol=1e-10, atol=1e-12 * np.abs(loads0).max())
    # Central differences, step 1e-4 in natural units: truncation O(h^2) ~ 1e-8 relative.
    h = 1e-4
    fd = np.empty((3, 3))
    for j in range(3):
        e = np.zeros(3)
        e[j] = h
        fd[:, j] = (blade.loads(t, *e) - blade.loads(t, *(-e))) / (2 * h) / scale
    sym = d[3:].reshape(3, 3)
    np.testing.assert_allclose(sym, fd, rtol=1e-6, atol=1e-6 * np.abs(fd).max())


def test_linearisation_error_shrinks_as_square_of_state(hawkmoth_models):
    insect, linear, blade = hawkmoth_models
    t = 0.3 * insect.period
    direction = np.array([0.3, -0.4, 2.0])  # m/s, m/s, rad/s
    errors = []
    for eps in (1e-2, 5e-3, 2.5e-3):
        x = eps * direction
        errors.append(np.abs(linear.loads(t, x) - blade.loads(t, *x)).max())
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    # Second-order remainder: halving the state quarters the error (within 10 %).
    np.testing.assert_allclose(ratios, 4.0, rtol=0.1)


def test_paper_comparison_finds_the_dropped_cos_phi_in_x0():
    rows = {(r.name, str(r.constant)): r for r in derivation.compare_with_paper()}
    x0 = rows[("X0", "K_{21}")]
    assert x0.status == "differs"
    S = derivation.symbols()
    # Ours carries cos(phi) (eq. 24 has it); the printed X0 (eq. 25 onwards) does not.
    assert sympy.simplify(x0.ours / x0.paper + sympy.cos(S.phi)) == 0


def test_paper_comparison_finds_the_extra_hinge_term_in_mu():
    rows = {(r.name, str(r.constant)): r for r in derivation.compare_with_paper()}
    mu = rows[("Mu", "K_{11}*x_h/I_y")]
    # The printed (m/I_y)(2 Xq + x_h Zu) doubles the x_h term we derive.
    assert mu.status == "differs"
    assert sympy.simplify(mu.paper / mu.ours) == 2


def test_derived_forces_have_the_symmetries_of_the_stroke():
    d = derivation.stability_derivatives()
    S = derivation.symbols()
    # Z0 is the same on both half-strokes: even in phi_dot.
    assert sympy.simplify(d["Z0"].subs(S.phidot, -S.phidot) - d["Z0"]) == 0
    # X0 reverses with the stroke (odd in phi_dot for fixed |phi_dot|).
    assert sympy.simplify(d["X0"].subs(S.phidot, -S.phidot) + d["X0"]) == 0


def test_vanishing_symmetry_classifies_the_cycle_means():
    d = derivation.stability_derivatives()
    insect = flapping.hawkmoth()
    t = np.linspace(0.0, insect.period, 2048, endpoint=False)
    means = stability_derivatives(insect, t).cycle_mean()
    for name, expr in d.items():
        S = derivation.symbols()
        reason = derivation.vanishing_symmetry(expr.subs({S.x_h: 0, S.h_w: 0}))
        scale = np.abs(derivation.evaluate(expr, insect, t)).max()
        if reason:
            assert abs(means[name]) < 1e-12 * max(scale, 1e-30), name
        else:
            assert abs(means[name]) > 1e-6 * scale, name


def test_the_paper_expressions_are_the_full_ones_at_zero_hinge_height():
    S = derivation.symbols()
    full = derivation.stability_derivatives(hinge_height=True)
    paper = derivation.stability_derivatives()
    assert any(e.has(S.h_w) for e in full.values())
    for name in derivation.DERIVATIVE_NAMES:
        assert sympy.simplify(full[name].subs(S.h_w, 0) - paper[name]) == 0, name


def test_generated_code_at_zero_hinge_height_is_the_paper_arithmetic():
    # h_w = 0 skips the hinge terms: the numbers are those of the paper's model bit for bit.
    insect = flapping.hawkmoth(hinge_offset=1e-3)
    t = np.linspace(0.01, 0.9, 7) * insect.period
    a = stability_derivatives(insect, t).as_dict()
    b = stability_derivatives(insect.with_(hinge_height=1e-30), t).as_dict()
    assert all(np.array_equal(a[k], b[k]) for k in ("X0", "Z0", "Xu", "Xw", "Zu", "Zw"))
    assert not np.array_equal(a["Mu"], stability_derivatives(
        insect.with_(hinge_height=1e-3), t).Mu)


@pytest.mark.parametrize("extra", [{}, {"hinge_height": 6e-3, "stroke_mean": -0.3}])
def test_evaluate_reproduces_the_generated_code(extra):
    insect = flapping.hawkmoth(hinge_offset=1e-3, **extra)
    t = np.linspace(0.01, 0.9, 7) * insect.period
    numeric = stability_derivatives(insect, t).as_dict()
    for name, expr in derivation.stability_derivatives(hinge_height=True).items():
        np.testing.assert_allclose(derivation.evaluate(expr, insect, t), numeric[name],
                                   rtol=1e-12, atol=1e-14 * np.abs(numeric[name]).max())


def test_vanishing_symmetry_names_the_symmetry_of_the_whole_expression():
    S = derivation.symbols()
    d = {k: v.subs({S.x_h: 0, S.h_w: 0})
         for k, v in derivation.stability_derivatives().items()}
    assert derivation.vanishing_symmetry(d["Xq"]) == "time reversal"
    assert derivation.vanishing_symmetry(d["Zq"]) == "half-period shift"
    assert derivation.vanishing_symmetry(d["X0"]) == "half-period shift and time reversal"
    assert derivation.vanishing_symmetry(d["Zw"]) == ""
    # A sum of a term odd only under time reversal and one odd only under the shift vanishes on
    # average, but under neither symmetry as a whole.
    mixed = S.phidot * sp_sin(S.phi) + sp_sin(S.phi) * S.absphidot
    assert derivation.vanishing_symmetry(mixed) == "term by term"

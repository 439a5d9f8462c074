"""Curves of codimension-one bifurcations in two parameters (flapping.periodic.bifurcation_curves),
checked on problems whose curves are known.

References and tolerances:
- Mathieu ``x'' + (a - 2 q cos 2t) x = 0`` (period pi): a multiplier +1 on ``a = a_0(q)``,
  ``b_2(q)``; -1 on ``a_1(q)``, ``b_1(q)`` (scipy.special.mathieu_a / mathieu_b, ~1e-12 here).
  The curve is corrected to a residual 1e-10 of the bordered scalar with monodromies integrated at
  rtol 1e-11 (error ~1e-11 on M, so ~1e-11 on a, measured 1e-11 .. 2e-10 over q up to 5): the
  tolerance 1e-9 leaves a margin of 5 over the worst measured.
- A rotating linear system with ``mu = p - q^2``, ``omega = 1 + q``: the Neimark-Sacker curve is
  ``p = q^2`` with angle ``theta = 1 + q`` (closed form), its resonances at ``q = pi/2 - 1``,
  ``2 pi / 3 - 1``, ``pi - 1`` (1:4, 1:3, 1:2) and ``-1`` (1:1).
- Forced Duffing (``x'' + 0.2 x' + x + x^3 = F cos(w t)``): folds at F = 0.3 in w,
  1.38385653200 and 1.30304596946 (tests/periodic/test_continuation.py, two routes, 11 digits);
  elsewhere the second route is continue_orbit locating the fold at fixed F (~1e-11): 1e-8.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq
from scipy.special import mathieu_a, mathieu_b

from flapping.errors import ConvergenceError
from flapping.periodic import continue_bifurcation
from flapping.periodic.bifurcation_curves import BifurcationCurve
from flapping.periodic.continuation import continue_orbit

FOLD_UP, FOLD_DOWN = 1.38385653200, 1.30304596946


def mathieu(t, x, a, q):
    return np.array([x[1], -(a - 2.0 * q * math.cos(2.0 * t)) * x[0]])


def mathieu_jac(t, x, a, q):
    return np.array([[0.0, 1.0], [-(a - 2.0 * q * math.cos(2.0 * t)), 0.0]])


def duffing(t, x, w, F):
    return np.array([x[1], -0.2 * x[1] - x[0] - x[0] ** 3 + F * math.cos(w * t)])


def duffing_jac(t, x, w, F):
    return np.array([[0.0, 1.0], [-1.0 - 3.0 * x[0] ** 2, -0.2]])


def duffing_period(w, F):
    return 2.0 * math.pi / w


def rotor(t, x, p, q, forcing=1.0):
    mu, om = p - q * q, 1.0 + q
    return np.array([mu * x[0] - om * x[1] + forcing * math.cos(2 * math.pi * t),
                     om * x[0] + mu * x[1]])


def rotor_jac(t, x, p, q):
    mu, om = p - q * q, 1.0 + q
    return np.array([[mu, -om], [om, mu]])


@pytest.mark.parametrize(("kind", "ref", "m"), [
    ("fold", mathieu_a, 0), ("fold", mathieu_b, 2),
    ("period-doubling", mathieu_a, 1), ("period-doubling", mathieu_b, 1)])
def test_mathieu_transition_curves(kind, ref, m):
    q0, q_end = 0.5, 1.5
    curve = continue_bifurcation(mathieu, [0.0, 0.0], math.pi, kind, ref(m, q0) + 0.02, q0,
                                 q_end, jac=mathieu_jac)
    assert isinstance(curve, BifurcationCurve)
    assert curve.success and curve.message == "reached q_end"
    assert curve.fixed_orbit  # x = 0 for every (a, q): the monodromy's singularity alone
    assert curve.q[0] == q0 and curve.q[-1] == q_end  # exactly
    assert len(curve) >= 5
    np.testing.assert_allclose(curve.p, ref(m, curve.q), rtol=0, atol=1e-9)
    lam = 1.0 if kind == "fold" else -1.0
    closest = np.min(np.abs(curve.multipliers - lam), axis=1)
    assert np.all(closest < 1e-4)  # a double multiplier: sqrt of the error in a
    assert curve.special_points == ()  # Hamiltonian: the other multiplier is 1 (noise)
    assert not curve.p.flags.writeable


def test_rotor_neimark_sacker_curve_and_resonances():
    curve = continue_bifurcation(rotor, [0.1, 0.0], 1.0, "neimark-sacker", 0.01, 0.0, 2.5,
                                 jac=rotor_jac, ds_max=0.5)
    assert not curve.fixed_orbit  # forced: the orbit's state is an unknown
    np.testing.assert_allclose(curve.p, curve.q ** 2, rtol=0, atol=1e-9)
    np.testing.assert_allclose(curve.theta, 1.0 + curve.q, rtol=0, atol=1e-9)
    kinds = [s.kind for s in curve.special_points]
    assert kinds == ["1:4 resonance", "1:3 resonance", "1:2 resonance"]
    for s, angle in zip(curve.special_points, (math.pi / 2, 2 * math.pi / 3, math.pi),
                        strict=True):
        assert abs(s.q - (angle - 1.0)) < 1e-9 and abs(s.p - s.q ** 2) < 1e-9
        assert abs(s.theta - angle) < 1e-9
        np.testing.assert_allclose(np.abs(s.multipliers), 1.0, atol=1e-9)
    # the curve ends at the 1:2 resonance (theta = pi), before q_end
    assert not curve.success and "1:2 resonance" in curve.message
    assert curve.q[-1] < math.pi - 1.0 + 1e-9


def test_rotor_neimark_sacker_ends_at_one_to_one():
    curve = continue_bifurcation(lambda t, x, p, q: rotor(t, x, p, q, 0.0), [0.0, 0.0], 1.0,
                                 "neimark-sacker", 0.01, 0.0, -1.5, jac=rotor_jac)
    assert curve.fixed_orbit
    (s,) = curve.special_points
    assert s.kind == "1:1 resonance" and abs(s.q + 1.0) < 1e-9 and abs(s.p - 1.0) < 1e-9
    np.testing.assert_allclose(s.multipliers, [1.0, 1.0], atol=1e-8)
    assert "1:1 resonance" in curve.message and not curve.success


@pytest.mark.parametrize(("fold", "side"), [(FOLD_UP, -1.0), (FOLD_DOWN, 1.0)])
def test_duffing_fold_curve_agrees_with_one_parameter_route(fold, side):
    """``side``: where in w the orbit exists next to the fold (the upper fold's below it)."""
    branch = continue_orbit(lambda t, x, w: duffing(t, x, w, 0.3), [0.0, 0.0],
                            lambda w: 2 * math.pi / w, 0.6, 2.0, autonomous=False,
                            jac=lambda t, x, w: duffing_jac(t, x, w, 0.3), ds=0.05, ds_max=0.1)
    (start,) = [b for b in branch.bifurcations if b.kind == "fold" and abs(b.p - fold) < 1e-3]
    q_end = 0.35
    curve = continue_bifurcation(duffing, start.x0, duffing_period, "fold", start.p + 1e-3,
                                 0.3, q_end, jac=duffing_jac)
    assert abs(curve.p[0] - fold) < 1e-9  # the start, located in p at q0 = 0.3
    assert curve.success and curve.q[-1] == q_end
    np.testing.assert_allclose(curve.period, 2 * math.pi / curve.p, rtol=1e-15)
    np.testing.assert_allclose(np.min(np.abs(curve.multipliers - 1.0), axis=1), 0.0,
                               atol=1e-8)
    # second route: the fold of the orbit branch at F = q_end, from the curve's last orbit
    p_last, x_last = float(curve.p[-1]), curve.x0[-1]
    other = continue_orbit(lambda t, x, w: duffing(t, x, w, q_end), x_last,
                           lambda w: 2 * math.pi / w, p_last + 0.02 * side, p_last - 0.02 * side,
                           autonomous=False, jac=lambda t, x, w: duffing_jac(t, x, w, q_end),
                           ds=0.005, max_points=40)
    folds = [b.p for b in other.bifurcations if b.kind == "fold"]
    assert folds and min(abs(f - p_last) for f in folds) < 1e-8


@pytest.mark.slow
def test_duffing_fold_curves_meet_at_their_cusp():
    """Both fold curves turn back in F at one point, where the p-tangent vanishes too."""
    cusps = []
    for fold in (FOLD_UP, FOLD_DOWN):
        branch = continue_orbit(lambda t, x, w: duffing(t, x, w, 0.3), [0.0, 0.0],
                                lambda w: 2 * math.pi / w, 0.6, 2.0, autonomous=False,
                                jac=lambda t, x, w: duffing_jac(t, x, w, 0.3), ds=0.05,
                                ds_max=0.1)
        (start,) = [b for b in branch.bifurcations if b.kind == "fold" and abs(b.p - fold) < 1e-3]
        curve = continue_bifurcation(duffing, start.x0, duffing_period, "fold", start.p, 0.3,
                                     0.0, jac=duffing_jac)
        assert not curve.success and "cusp" in curve.message
        (cusp,) = [s for s in curve.special_points if s.kind == "cusp"]
        cusps.append((cusp.p, cusp.q))
    (p1, q1), (p2, q2) = cusps
    assert abs(p1 - p2) < 1e-8 and abs(q1 - q2) < 1e-8
    assert 0.0 < q1 < 0.3


def two_oscillators(t, x, a, q):
    """A Mathieu oscillator beside a damped one whose stiffness is a + 0.7: the first gives the
    fold curve a = a_0(q), the second a period doubling that crosses it (a fold-flip point)."""
    k = 2.0 * q * math.cos(2.0 * t)
    return np.array([x[1], -(a - k) * x[0], x[3], -0.1 * x[3] - (a + 0.7 - k) * x[2]])


def test_fold_flip_on_a_fold_curve_lies_on_the_flip_curve():
    curve = continue_bifurcation(two_oscillators, np.zeros(4), math.pi, "fold",
                                 mathieu_a(0, 0.1), 0.1, 0.6)
    (ff,) = [s for s in curve.special_points if s.kind == "fold-flip"]
    assert abs(ff.p - mathieu_a(0, ff.q)) < 1e-9  # on the fold curve
    assert np.min(np.abs(ff.multipliers + 1.0)) < 1e-8
    # second route: the period doubling located in p at q = ff.q is the same point
    flip = continue_bifurcation(two_oscillators, np.zeros(4), math.pi, "period-doubling",
                                ff.p + 0.01, ff.q, ff.q + 0.01, max_points=2)
    assert abs(flip.p[0] - ff.p) < 1e-8


def oscillator_and_rotor(t, x, a, q):
    """A Mathieu oscillator beside a rotating linear system of growth rate a + 0.3: its complex
    pair crosses the unit circle where a = -0.3 (a fold-Neimark-Sacker point on a = a_0(q))."""
    mu, om = a + 0.3, 1.3
    return np.array([x[1], -(a - 2.0 * q * math.cos(2.0 * t)) * x[0],
                     mu * x[2] - om * x[3], om * x[2] + mu * x[3]])


def test_fold_neimark_sacker_where_the_pair_crosses_the_circle():
    curve = continue_bifurcation(oscillator_and_rotor, np.zeros(4), math.pi, "fold",
                                 mathieu_a(0, 0.5), 0.5, 1.0)
    (fns,) = [s for s in curve.special_points if s.kind == "fold-neimark-sacker"]
    q_star = brentq(lambda q: mathieu_a(0, q) + 0.3, 0.5, 1.0, xtol=1e-14)
    # located to the bisection's xtol on corrected points (1e-12) and the curve's 1e-10
    assert abs(fns.p + 0.3) < 1e-9 and abs(fns.q - q_star) < 1e-8
    pair = fns.multipliers[np.abs(fns.multipliers.imag) > 1e-3]
    np.testing.assert_allclose(np.abs(pair), 1.0, atol=1e-9)


def test_fold_flip_is_the_same_point_seen_from_the_flip_curve():
    fold = continue_bifurcation(two_oscillators, np.zeros(4), math.pi, "fold",
                                mathieu_a(0, 0.1), 0.1, 0.6)
    # the lower edge of the damped oscillator's first tongue, a + 0.7 ~ 1 - q
    flip = continue_bifurcation(two_oscillators, np.zeros(4), math.pi, "period-doubling",
                                0.05, 0.25, 0.6)
    (a,) = [s for s in fold.special_points if s.kind == "fold-flip"]
    (b,) = [s for s in flip.special_points if s.kind == "fold-flip"]
    assert abs(a.p - b.p) < 1e-8 and abs(a.q - b.q) < 1e-8


def jordan(t, x, p, q):
    """``x' = [[p, 1], [-q, p]] x`` over period 1: multipliers exp(p +- sqrt(-q)). A +1
    multiplier on the parabola q = -p^2 (q <= 0), a pair exp(p +- i sqrt(q)) on the circle on
    p = 0 (q > 0, theta = sqrt(q)); the two curves meet at the 1:1 resonance (0, 0), a Jordan
    block (the miniature of the +1 and Neimark-Sacker curves meeting in the bumblebee's map)."""
    return np.array([p * x[0] + x[1], -q * x[0] + p * x[1]])


def test_fold_and_neimark_sacker_curves_meet_at_the_one_to_one_resonance():
    fold = continue_bifurcation(jordan, [0.0, 0.0], 1.0, "fold", -0.9, -1.0, 0.5)
    np.testing.assert_allclose(fold.q, -fold.p ** 2, rtol=0, atol=1e-9)
    assert "turns back" in fold.message and not fold.success
    kinds = {s.kind: s for s in fold.special_points}
    assert set(kinds) == {"1:1 resonance", "turning point"}
    for s in kinds.values():
        assert abs(s.p) < 1e-9 and abs(s.q) < 1e-9
    ns = continue_bifurcation(jordan, [0.0, 0.0], 1.0, "neimark-sacker", 0.05, 1.0, -0.5)
    np.testing.assert_allclose(ns.p, 0.0, atol=1e-9)
    np.testing.assert_allclose(ns.theta, np.sqrt(ns.q), atol=1e-8)
    (one,) = ns.special_points
    # the pair degenerates into a Jordan block there: p to the square root of the residual
    assert one.kind == "1:1 resonance" and abs(one.q) < 1e-9 and abs(one.p) < 1e-5
    assert "1:1 resonance" in ns.message


def test_last_point_exactly_at_q_end_backwards():
    curve = continue_bifurcation(mathieu, [0.0, 0.0], math.pi, "period-doubling",
                                 mathieu_a(1, 0.2) + 0.01, 0.2, 0.0, jac=mathieu_jac)
    assert curve.success and curve.q[-1] == 0.0 and np.all(np.diff(curve.q) < 0)
    assert abs(curve.p[-1] - 1.0) < 1e-9  # a_1(0) = b_1(0) = 1


@pytest.mark.parametrize(("args", "kwargs", "match"), [
    (("saddle-node", 0.0, 0.5, 1.0), {}, "kind"),
    (("fold", 0.0, 0.5, 0.5), {}, "q_end"),
    (("fold", 0.0, 0.5, 1.0), {"bogus": 1}, "bogus"),
    (("fold", 0.0, 0.5, 1.0), {"tol": 1e-3}, "tol"),
    (("fold", 0.0, 0.5, 1.0), {"ds": 1.0, "ds_max": 0.5}, "ds"),
    (("fold", 0.0, 0.5, 1.0), {"fixed_orbit": 1}, "fixed_orbit"),
    (("fold", math.nan, 0.5, 1.0), {}, "p0"),
])
def test_bad_arguments_are_named(args, kwargs, match):
    with pytest.raises(ValueError, match=match):
        continue_bifurcation(mathieu, [0.0, 0.0], math.pi, *args, **kwargs)


def bautin(t, x, b1, b2):
    """Bautin normal form r' = r (b1 + b2 r^2 - r^4), phase' = 1: cycles of period 2 pi whose
    fold is on b1 = -b2^2 / 4, at r^2 = b2 / 2 (closed form)."""
    rho = x[0] ** 2 + x[1] ** 2
    g = b1 + b2 * rho - rho * rho
    return np.array([x[0] * g - x[1], x[1] * g + x[0]])


def test_autonomous_fold_of_cycles_on_the_bautin_curve():
    r = math.sqrt(0.5)
    curve = continue_bifurcation(bautin, [1.05 * r, 0.0], 2 * math.pi * 1.01, "fold",
                                 -0.24, 1.0, 1.3, autonomous=True)
    assert curve.success and curve.autonomous and curve.q[-1] == 1.3
    # the corrector's residual 1e-10 and rtol 1e-11: ~1e-11 on each; measured ~1e-12
    np.testing.assert_allclose(curve.p, -curve.q ** 2 / 4, rtol=0, atol=1e-9)
    np.testing.assert_allclose(curve.period, 2 * math.pi, rtol=0, atol=1e-9)
    np.testing.assert_allclose(np.hypot(*curve.x0.T) ** 2, curve.q / 2, rtol=0, atol=1e-8)
    np.testing.assert_allclose(curve.multipliers, 1.0, atol=1e-5)  # double: sqrt of 1e-10


def test_autonomous_period_doubling_starts_at_the_roessler_reference():
    from flapping.periodic.shooting import find_periodic_orbit
    from flapping.periodic.testproblems import rossler

    def fun(t, x, c, a):
        return rossler(t, x, a=a, b=0.2, c=c)

    orbit = find_periodic_orbit(lambda t, x: fun(t, x, 2.83, 0.2), [4.58081622, 0.0, 1.52645301],
                                5.77, autonomous=True)
    # at the reference's rtol 1e-12: with the defaults (rtol 1e-11, a residual 5e-10 of the
    # bordered scalar, whose derivative in c is ~0.2) c is off by 2.6e-9, here by 5e-11
    curve = continue_bifurcation(fun, orbit.x0, orbit.period, "period-doubling", 2.83, 0.2,
                                 0.205, autonomous=True, rtol=1e-12, atol=1e-12)
    # c = 2.83244502786, T = 5.76982001651 at a = b = 0.2 (test_continuation.py, two routes)
    assert abs(curve.p[0] - 2.83244502786) < 1e-9
    assert abs(curve.period[0] - 5.76982001651) < 1e-9
    assert curve.success and curve.q[-1] == 0.205
    assert np.all(np.min(np.abs(curve.multipliers + 1.0), axis=1) < 1e-8)


def hopf_and_rotor(t, x, p, q):
    """The circle r = sqrt(p) of period 2 pi beside a rotating linear system of growth rate
    q - p and frequency 0.3: a Neimark-Sacker curve p = q with theta = 0.6 pi."""
    g = p - x[0] ** 2 - x[1] ** 2
    mu = q - p
    return np.array([x[0] * g - x[1], x[1] * g + x[0], mu * x[2] - 0.3 * x[3],
                     0.3 * x[2] + mu * x[3]])


def test_autonomous_neimark_sacker_curve():
    curve = continue_bifurcation(hopf_and_rotor, [0.72, 0.0, 0.0, 0.0], 6.4, "neimark-sacker",
                                 0.51, 0.5, 0.8, autonomous=True)
    assert curve.success and curve.q[-1] == 0.8
    np.testing.assert_allclose(curve.p, curve.q, rtol=0, atol=1e-9)
    np.testing.assert_allclose(curve.theta, 0.6 * math.pi, rtol=0, atol=1e-9)
    np.testing.assert_allclose(curve.period, 2 * math.pi, rtol=0, atol=1e-9)


@given(ds=st.one_of(st.floats(max_value=0.0), st.just(math.inf), st.just(math.nan)))
@settings(max_examples=25, deadline=None)
def test_nonpositive_or_nonfinite_ds_is_refused_by_name(ds):
    with pytest.raises(ValueError, match="ds"):
        continue_bifurcation(mathieu, [0.0, 0.0], math.pi, "fold", 0.0, 0.5, 1.0, ds=ds)


def test_autonomous_needs_a_number_as_period():
    with pytest.raises(ValueError, match="period"):
        continue_bifurcation(bautin, [0.7, 0.0], lambda p, q: 6.0, "fold", -0.25, 1.0, 1.2,
                             autonomous=True)


def test_no_complex_pair_for_neimark_sacker():
    # inside the first instability tongue both multipliers are real
    with pytest.raises(ValueError, match="complex pair"):
        continue_bifurcation(mathieu, [0.0, 0.0], math.pi, "neimark-sacker", 1.0, 1.0, 2.0)


def test_failed_location_is_a_convergence_error_with_diagnostics():
    with pytest.raises(ConvergenceError) as info:
        continue_bifurcation(duffing, [0.5, 0.0], duffing_period, "fold", 0.8, 0.3, 0.4,
                             jac=duffing_jac, max_newton=1)
    assert info.value.residual is not None and info.value.iterations == 1
    assert "fold" in str(info.value)


def test_wrong_signature_is_named():
    with pytest.raises(TypeError, match="fun"):
        continue_bifurcation(lambda t, x, p: x, [0.0, 0.0], math.pi, "fold", 0.0, 0.5, 1.0)

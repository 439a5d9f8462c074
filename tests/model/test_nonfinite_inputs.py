"""Every public model function that takes a time, a state or an angle refuses a non-finite one.

Issue 26 (item 6): a NaN stroke angle, time or state returned a NaN matrix or NaN loads without
a word. Each public call now raises a ValueError naming the argument; the solvers call the
unchecked implementations (``segment_functions``, the ``_`` methods), which keep returning what
the arithmetic gives, so that an overflowing integration is still reported by the integrator.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from flapping.model import dynamics, inertia, kinematics
from flapping.model.dynamics import LongitudinalDynamics, inertial_velocity, inertial_velocity_jac
from flapping.model.morphology import hawkmoth

NAN, INF = math.nan, math.inf


@pytest.fixture(scope="module")
def models():
    moth = hawkmoth()
    return {"linear": LongitudinalDynamics(moth),
            "exact": LongitudinalDynamics(moth, aerodynamics="exact", n_nodes=8),
            "winged": LongitudinalDynamics(moth.with_(wing_mass=2e-5))}


STATE = [0.1, -0.05, 0.3, 0.02]
METHODS = ["rhs", "jac", "amplitude_jac", "stroke_mean_jac", "loads"]


@pytest.mark.parametrize("kind", ["linear", "exact", "winged"])
@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("bad, name", [
    (dict(t=NAN), "`t`"), (dict(t=INF), "`t`"), (dict(x=[NAN, 0, 0, 0]), "`x`"),
    (dict(x=[0, 0, 0, -INF]), "`x`"), (dict(x=[0.0, 0.0]), "`x`"), (dict(x="abcd"), "`x`"),
    (dict(stroke=NAN), "`stroke`"), (dict(stroke=0.5), "`stroke`"),
    (dict(amplitude=NAN), "`amplitude`"), (dict(t="0.1"), "`t`")])
def test_public_dynamics_calls_refuse_a_bad_argument_by_name(models, kind, method, bad, name):
    model = models[kind]
    args = dict(t=0.003, x=STATE, stroke=None, amplitude=None) | bad
    if method == "loads" and "x" in bad and bad["x"] == [0, 0, 0, -INF]:
        args["x"] = [0, 0, -INF]  # theta does not enter the loads: spoil q instead
    with pytest.raises(ValueError, match=name):
        getattr(model, method)(args["t"], args["x"], args["stroke"], args["amplitude"])


@pytest.mark.parametrize("method", ["derivatives", "amplitude_derivatives",
                                    "stroke_mean_derivatives"])
def test_derivatives_refuse_a_non_finite_time_or_amplitude(models, method):
    with pytest.raises(ValueError, match="`t`"):
        getattr(models["linear"], method)(NAN)
    with pytest.raises(ValueError, match="`amplitude`"):
        getattr(models["linear"], method)(0.01, INF)


@pytest.mark.parametrize("kind", ["linear", "exact", "winged"])
def test_checked_and_solver_entries_agree_on_good_input(models, kind):
    model = models[kind]
    rhs, jac = model.segment_functions()
    for t, s, k in ((0.003, -1.0, 0), (0.03, 1.0, 1)):
        assert np.array_equal(model.rhs(t, STATE, s), rhs[k](t, np.array(STATE)))
        assert np.array_equal(model.jac(t, STATE, s), jac[k](t, np.array(STATE)))
    # a state longer than 4 (the hover layer's augmented state) is read in its first entries
    assert np.array_equal(model.rhs(0.003, STATE + [5.0, 6.0]), model.rhs(0.003, STATE))


def test_the_solver_entry_still_returns_what_the_arithmetic_gives(models):
    # The integrators feed an overflowed state back only to report it (Diverged): the
    # unchecked entry must return, not raise.
    rhs, _ = models["linear"].segment_functions()
    assert not np.all(np.isfinite(rhs[0](0.003, np.array([NAN, 0.0, 0.0, 0.0]))))


@pytest.mark.parametrize("call, name", [
    (lambda: kinematics.flapping_angle(NAN, 1.0, 26.0), "`t`"),
    (lambda: kinematics.flapping_angle([0.0, INF], 1.0, 26.0), "`t`"),
    (lambda: kinematics.flapping_angle(0.0, NAN, 26.0), "`amplitude`"),
    (lambda: kinematics.flapping_angle(0.0, 1.0, -26.0), "`frequency`"),
    (lambda: kinematics.flapping_rate(NAN, 1.0, 26.0), "`t`"),
    (lambda: kinematics.flapping_rate(0.0, 1.0, NAN), "`frequency`"),
    (lambda: kinematics.stroke_sign(NAN, 26.0), "`t`"),
    (lambda: kinematics.stroke_sign(0.1, 0.0), "`frequency`"),
    (lambda: kinematics.stroke_sign_scalar(NAN, 26.0), "`t`"),
    (lambda: kinematics.stroke_sign_scalar(0.1, INF), "`frequency`"),
    (lambda: kinematics.geometric_pitch(NAN, 1.0), "`alpha_m`"),
    (lambda: kinematics.geometric_pitch(0.5, NAN), "`sign`"),
    (lambda: kinematics.geometric_pitch(0.5, [1.0, 0.0]), "`sign`"),
    (lambda: kinematics.segment_stroke_sign(NAN), "`segment`"),
    (lambda: inertial_velocity(NAN, 0.0, 0.0), "`u`"),
    (lambda: inertial_velocity(0.0, 0.0, INF), "`theta`"),
    (lambda: inertial_velocity_jac(0.0, NAN, 0.0), "`w`"),
    (lambda: inertia.stroke_phase(hawkmoth(), NAN, 1.0), "`t`"),
    (lambda: inertia.stroke_phase(hawkmoth(), 0.0, NAN), "`amplitude`"),
])
def test_public_helpers_refuse_non_finite_input_by_name(call, name):
    # Reproducers: each returned NaN (stroke_sign_scalar raised "cannot convert float NaN to
    # integer"; stroke_sign called NaN the forward stroke; segment_stroke_sign(NaN) was +1).
    with pytest.raises(ValueError, match=name):
        call()


def test_wing_inertia_refuses_a_nan_stroke_angle(models):
    # Reproducer (issue 26): a NaN stroke angle gave a NaN matrix.
    wings = models["winged"]._inertia
    phase = inertia.stroke_phase(models["winged"].insect, 0.003, 1.0)
    with pytest.raises(ValueError, match="`phase`"):
        wings.accelerations((NAN, 0.0, 0.0), STATE, (0.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="`x`"):
        wings.state_jac(phase, [0.0, NAN, 0.0, 0.0], np.zeros((3, 4)))
    with pytest.raises(ValueError, match="`dphase`"):
        wings.stroke_jac(phase, STATE, (0.0, 0.0, 0.0), (NAN, 0.0, 0.0), (0.0, 0.0, 0.0))
    assert np.all(np.isfinite(wings.accelerations(phase, STATE, (0.0, 0.0, 0.0))))


def test_the_check_costs_little_beside_the_right_hand_side(models):
    # Measured on bench_hover (adaptive orbit + multipliers): no difference within noise. Here
    # a coarse guard that the public check stays a small fraction of one evaluation.
    import timeit

    model, x = models["linear"], np.array(STATE)
    check = min(timeit.repeat(lambda: dynamics._check_call(0.003, x, 4, 1.0, None),
                              number=2000, repeat=5))
    rhs = min(timeit.repeat(lambda: model._rhs(0.003, x, 1.0), number=2000, repeat=5))
    assert check < 0.5 * rhs


def test_stability_derivatives_refuse_an_empty_time_sample():
    # An empty sample returned empty arrays whose cycle means are NaN (with a numpy warning).
    from flapping.model.derivatives import stability_derivatives

    with pytest.raises(ValueError, match="`t` must hold at least one time"):
        stability_derivatives(hawkmoth(), [])


@pytest.mark.parametrize("kind", ["linear", "exact", "winged"])
def test_the_unchecked_calls_are_the_public_ones_without_the_check(models, kind):
    # For the hover layer's solvers (they call rhs, jac and the sensitivities with arguments
    # they made): same answers on good input, the arithmetic's answer on a non-finite state.
    import pickle

    model = models[kind]
    fast = model.unchecked
    for name in ("rhs", "jac", "amplitude_jac", "stroke_mean_jac", "loads"):
        assert np.array_equal(getattr(fast, name)(0.003, STATE, 1.0, 1.0),
                              getattr(model, name)(0.003, STATE, 1.0, 1.0)), name
    assert fast.derivatives(0.003) == model.derivatives(0.003)
    if kind != "exact":  # the blade-element loads check their own arguments, as they always did
        assert np.isnan(fast.rhs(0.003, [NAN, 0.0, 0.0, 0.0], 1.0)).any()
    copy = pickle.loads(pickle.dumps(model))  # (process pools pickle models)
    assert copy.unchecked.rhs.__self__ is copy


@pytest.mark.parametrize("call, name, bound", [
    (lambda: __import__("flapping.model.aerodynamics", fromlist=["x"]).span_quadrature(
        hawkmoth(), n_nodes=10**9), "n_nodes", "4096"),
    (lambda: __import__("flapping.model.aerodynamics", fromlist=["x"]).wing_loads(
        0.0, STATE, hawkmoth(), 0.5, n_nodes=10**8), "n_nodes", "4096"),
    (lambda: LongitudinalDynamics(hawkmoth(), aerodynamics="exact", n_nodes=10**9), "n_nodes",
     "4096"),
    (lambda: kinematics.reversed_flow_fraction(0.01, 0.1, 1.0, 26.0, n_samples=10**12),
     "n_samples", "4194304"),
])
def test_a_huge_work_size_is_refused_by_name_not_allocated(call, name, bound):
    # Reproducers: MemoryError ("Unable to allocate 7.45 GiB" / "7.28 TiB"), or gigabytes taken
    # from a shared machine before that.
    with pytest.raises(ValueError, match=rf"`{name}` must be an integer in \[\d, {bound}\]"):
        call()


def test_the_chord_refuses_a_non_finite_radius():
    # Reproducer: hawkmoth().chord(nan) returned 0 (NaN is "outside the wing").
    with pytest.raises(ValueError, match="`r`"):
        hawkmoth().chord(NAN)
    assert hawkmoth().chord(-1.0) == 0.0  # outside the wing: zero, as documented

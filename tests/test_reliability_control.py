"""Every public function of flapping.studies.control refuses bad arguments with a message naming them.

Before, about fifteen of these ended in a raw reshape ValueError, a LinAlgError or an IndexError
(wrong-shaped M, B, K or gains, a negative or fractional delay, an empty grid, max_delay < 0,
r_max <= 0, a disturbance of the wrong size, ...), or ran for ever (a delay of 10**6). Each case
below names the argument the message must name; a test checks that every public function of
the module has cases, so a new function cannot skip validation unnoticed.
"""

from __future__ import annotations

import inspect
import math
from types import SimpleNamespace

import numpy as np
import pytest

from flapping.studies import control

NAN = math.nan


@pytest.fixture(scope="module")
def ctx(insect, orbit):
    """A wingbeat map and a three-point passive sweep built by hand (no solve needed)."""
    wmap = control.WingbeatMap(orbit, 0.5 * np.eye(4), np.ones((4, 1)))
    mus = np.tile(np.array([1.2, 0.5, 0.3, 0.1], dtype=complex), (3, 1))
    sweep = control.PassiveSweep(insect, np.array([0.0, 1e-3, 2e-3]), np.full(3, 1.0), mus,
                                 (orbit,) * 3)
    return SimpleNamespace(insect=insect, orbit=orbit, wmap=wmap, sweep=sweep, M=np.eye(4),
                           B=np.ones((4, 1)), K=np.ones(4))


# (function name, argument the message must name, call of ctx c)
CASES = [
    ("hover_multipliers", "insect", lambda c: control.hover_multipliers("hawkmoth")),
    ("hover_multipliers", "guess", lambda c: control.hover_multipliers(c.insect, guess=1.0)),
    ("hover_multipliers", "backend",
     lambda c: control.hover_multipliers(c.insect, backend="gpu")),
    ("passive_sweep", "insect", lambda c: control.passive_sweep(None, [0.0])),
    ("passive_sweep", "hinge_heights", lambda c: control.passive_sweep(c.insect, [])),
    ("passive_sweep", "hinge_heights", lambda c: control.passive_sweep(c.insect, [[0, 1e-3]])),
    ("passive_sweep", "hinge_heights", lambda c: control.passive_sweep(c.insect, [1e-3, 0])),
    ("passive_sweep", "hinge_heights", lambda c: control.passive_sweep(c.insect, [NAN])),
    ("passive_sweep", "hinge_heights",
     lambda c: control.passive_sweep(c.insect, np.linspace(0, 0.05, 20_000))),
    ("passive_sweep", "backend", lambda c: control.passive_sweep(c.insect, [0.0], backend=1)),
    ("closest_approach", "sweep", lambda c: control.closest_approach("sweep")),
    ("locate_passive_crossing", "sweep", lambda c: control.locate_passive_crossing(None, (0, 1))),
    ("locate_passive_crossing", "bracket",
     lambda c: control.locate_passive_crossing(c.sweep, (0,))),
    ("locate_passive_crossing", "bracket",
     lambda c: control.locate_passive_crossing(c.sweep, (0, 5))),
    ("locate_passive_crossing", "bracket",
     lambda c: control.locate_passive_crossing(c.sweep, (1, 0))),
    ("locate_passive_crossing", "bracket",
     lambda c: control.locate_passive_crossing(c.sweep, (0.5, 1))),
    ("locate_passive_crossing", "bracket", lambda c: control.locate_passive_crossing(c.sweep, 3)),
    ("locate_passive_crossing", "check",
     lambda c: control.locate_passive_crossing(c.sweep, (0, 1), check="no")),
    ("stable_window", "sweep", lambda c: control.stable_window([1, 2])),
    ("stable_window", "check", lambda c: control.stable_window(c.sweep, check=0)),
    ("passive_map", "insect", lambda c: control.passive_map("moth", [0.0], [0.25])),
    ("passive_map", "centers_of_pressure", lambda c: control.passive_map(c.insect, [0.0], [1.5])),
    ("passive_map", "centers_of_pressure", lambda c: control.passive_map(c.insect, [0.0], [])),
    ("passive_map", "hinge_heights", lambda c: control.passive_map(c.insect, [], [0.25])),
    ("passive_map", "hinge_heights",
     lambda c: control.passive_map(c.insect, np.linspace(0, 0.05, 200), np.linspace(0, 1, 100))),
    ("passive_map", "backend",
     lambda c: control.passive_map(c.insect, [0.0], [0.25], backend="fast")),
    ("linear_wingbeat_map", "orbit", lambda c: control.linear_wingbeat_map(c.insect)),
    ("linear_wingbeat_map", "rtol", lambda c: control.linear_wingbeat_map(c.orbit, rtol=0.0)),
    ("linear_wingbeat_map", "atol", lambda c: control.linear_wingbeat_map(c.orbit, atol=-1.0)),
    ("WingbeatMap", "orbit", lambda c: control.WingbeatMap(None, c.M, c.B)),
    ("WingbeatMap", "M", lambda c: control.WingbeatMap(c.orbit, np.ones((3, 4)), c.B)),
    ("WingbeatMap", "B", lambda c: control.WingbeatMap(c.orbit, c.M, np.ones((3, 1)))),
    ("closed_loop_matrix", "M", lambda c: control.closed_loop_matrix(np.ones((3, 4)), c.B, c.K, 0)),
    ("closed_loop_matrix", "M", lambda c: control.closed_loop_matrix([], c.B, c.K, 0)),
    ("closed_loop_matrix", "M",
     lambda c: control.closed_loop_matrix(np.full((4, 4), NAN), c.B, c.K, 0)),
    ("closed_loop_matrix", "M", lambda c: control.closed_loop_matrix(np.ones(4), c.B, c.K, 0)),
    ("closed_loop_matrix", "B", lambda c: control.closed_loop_matrix(c.M, np.ones((3, 1)), c.K, 0)),
    ("closed_loop_matrix", "B", lambda c: control.closed_loop_matrix(c.M, np.ones(5), c.K, 0)),
    ("closed_loop_matrix", "B", lambda c: control.closed_loop_matrix(c.M, [[True]] * 4, c.K, 0)),
    ("closed_loop_matrix", "K", lambda c: control.closed_loop_matrix(c.M, c.B, np.ones(3), 0)),
    ("closed_loop_matrix", "K",
     lambda c: control.closed_loop_matrix(c.M, c.B, np.ones((2, 4)), 0)),
    ("closed_loop_matrix", "K",
     lambda c: control.closed_loop_matrix(c.M, np.ones((4, 2)), np.ones(4), 0)),
    ("closed_loop_matrix", "delay", lambda c: control.closed_loop_matrix(c.M, c.B, c.K, -1)),
    ("closed_loop_matrix", "delay", lambda c: control.closed_loop_matrix(c.M, c.B, c.K, 1.5)),
    ("closed_loop_matrix", "delay", lambda c: control.closed_loop_matrix(c.M, c.B, c.K, "2")),
    ("closed_loop_matrix", "delay", lambda c: control.closed_loop_matrix(c.M, c.B, c.K, 10**6)),
    ("spectral_radius", "M", lambda c: control.spectral_radius(np.ones((2, 3)), c.B, c.K, 0)),
    ("spectral_radius", "B", lambda c: control.spectral_radius(c.M, np.ones((5, 1)), c.K, 0)),
    ("spectral_radius", "K", lambda c: control.spectral_radius(c.M, c.B, [1.0, NAN, 0, 0], 0)),
    ("spectral_radius", "delay", lambda c: control.spectral_radius(c.M, c.B, c.K, -2)),
    ("gain_region", "wmap", lambda c: control.gain_region(None, [0.0], [0.0], 0)),
    ("gain_region", "k1", lambda c: control.gain_region(c.wmap, [], [0.0], 0)),
    ("gain_region", "k1", lambda c: control.gain_region(c.wmap, [NAN], [0.0], 0)),
    ("gain_region", "k2", lambda c: control.gain_region(c.wmap, [0.0], [[0.0, 1.0]], 0)),
    ("gain_region", "k1",
     lambda c: control.gain_region(c.wmap, np.zeros(2000), np.zeros(1000), 0)),
    ("gain_region", "delay", lambda c: control.gain_region(c.wmap, [0.0], [0.0], -1)),
    ("gain_region", "states", lambda c: control.gain_region(c.wmap, [0.0], [0.0], 0, (0, 0))),
    ("gain_region", "states", lambda c: control.gain_region(c.wmap, [0.0], [0.0], 0, (0, 4))),
    ("gain_region", "states", lambda c: control.gain_region(c.wmap, [0.0], [0.0], 0, (1,))),
    ("gain_region", "states", lambda c: control.gain_region(c.wmap, [0.0], [0.0], 0, 5)),
    ("optimal_gains", "wmap", lambda c: control.optimal_gains(c.orbit, 0)),
    ("optimal_gains", "delay", lambda c: control.optimal_gains(c.wmap, -1)),
    ("optimal_gains", "start", lambda c: control.optimal_gains(c.wmap, 0, start=(1, 2, 3))),
    ("optimal_gains", "start", lambda c: control.optimal_gains(c.wmap, 0, start=(NAN, 0))),
    ("optimal_gains", "objective", lambda c: control.optimal_gains(c.wmap, 0, objective="x")),
    ("optimal_gains", "margin", lambda c: control.optimal_gains(c.wmap, 0, margin=1.0)),
    ("optimal_gains", "margin", lambda c: control.optimal_gains(c.wmap, 0, margin=-0.1)),
    ("optimal_gains", "states", lambda c: control.optimal_gains(c.wmap, 0, states=(2, 2))),
    ("smallest_stabilising_gains", "wmap",
     lambda c: control.smallest_stabilising_gains(None, 0, 0.3)),
    ("smallest_stabilising_gains", "delay",
     lambda c: control.smallest_stabilising_gains(c.wmap, -1, 0.3)),
    ("smallest_stabilising_gains", "r_max",
     lambda c: control.smallest_stabilising_gains(c.wmap, 0, 0.0)),
    ("smallest_stabilising_gains", "r_max",
     lambda c: control.smallest_stabilising_gains(c.wmap, 0, -1.0)),
    ("smallest_stabilising_gains", "r_max",
     lambda c: control.smallest_stabilising_gains(c.wmap, 0, NAN)),
    ("smallest_stabilising_gains", "margin",
     lambda c: control.smallest_stabilising_gains(c.wmap, 0, 0.3, margin=1.5)),
    ("smallest_stabilising_gains", "n_angles",
     lambda c: control.smallest_stabilising_gains(c.wmap, 0, 0.3, n_angles=0)),
    ("smallest_stabilising_gains", "n_angles",
     lambda c: control.smallest_stabilising_gains(c.wmap, 0, 0.3, n_angles=2.5)),
    ("smallest_stabilising_gains", "states",
     lambda c: control.smallest_stabilising_gains(c.wmap, 0, 0.3, states=(0, 1, 2))),
    ("delay_limit", "wmap", lambda c: control.delay_limit("map")),
    ("delay_limit", "max_delay", lambda c: control.delay_limit(c.wmap, -1)),
    ("delay_limit", "max_delay", lambda c: control.delay_limit(c.wmap, 2.5)),
    ("delay_limit", "max_delay", lambda c: control.delay_limit(c.wmap, 10**6)),
    ("delay_limit", "start", lambda c: control.delay_limit(c.wmap, 2, start=(1.0,))),
    ("delay_limit", "states", lambda c: control.delay_limit(c.wmap, 2, states=(3, 3))),
    ("simulate_feedback", "wmap", lambda c: control.simulate_feedback(None, (0, 0), 0, c.K)),
    ("simulate_feedback", "gains",
     lambda c: control.simulate_feedback(c.wmap, (1.0, 2.0, 3.0), 0, c.K)),
    ("simulate_feedback", "gains",
     lambda c: control.simulate_feedback(c.wmap, (NAN, 0.0), 0, c.K)),
    ("simulate_feedback", "delay", lambda c: control.simulate_feedback(c.wmap, (0, 0), -1, c.K)),
    ("simulate_feedback", "delay", lambda c: control.simulate_feedback(c.wmap, (0, 0), 0.5, c.K)),
    ("simulate_feedback", "disturbance",
     lambda c: control.simulate_feedback(c.wmap, (0, 0), 0, (0.0, 0.0, 0.0))),
    ("simulate_feedback", "disturbance",
     lambda c: control.simulate_feedback(c.wmap, (0, 0), 0, np.zeros((4, 1)))),
    # issue 35: a zero disturbance returned a NaN decay rate (log 0)
    ("simulate_feedback", "disturbance",
     lambda c: control.simulate_feedback(c.wmap, (0, 0), 0, np.zeros(4))),
    ("simulate_feedback", "n_wingbeats",
     lambda c: control.simulate_feedback(c.wmap, (0, 0), 0, c.K, 1)),
    ("simulate_feedback", "n_wingbeats",
     lambda c: control.simulate_feedback(c.wmap, (0, 0), 0, c.K, 10**9)),
    ("simulate_feedback", "states",
     lambda c: control.simulate_feedback(c.wmap, c.K, 0, c.K, states=(0, 9))),
]


@pytest.mark.parametrize("function, argument, call", CASES,
                         ids=[f"{f}-{a}-{i}" for i, (f, a, _) in enumerate(CASES)])
def test_a_bad_argument_is_refused_naming_it(ctx, function, argument, call):
    with pytest.raises((ValueError, TypeError), match=f"`{argument}") as error:
        call(ctx)
    assert type(error.value) in (ValueError, TypeError)  # not a LinAlgError or a subclass


def _public_callables():
    return [name for name in control.__all__
            if callable(getattr(control, name))
            and (inspect.isfunction(getattr(control, name)) or name == "WingbeatMap")]


def test_every_public_function_has_bad_input_cases():
    assert {f for f, _, _ in CASES} == set(_public_callables())


def test_validation_keeps_the_good_paths(ctx):
    # The shapes the package itself passes: K as (4,) or (1, 4), B as (4, 1) or (4,).
    a = control.closed_loop_matrix(ctx.M, ctx.B, ctx.K, 2)
    b = control.closed_loop_matrix(ctx.M, np.ones(4), ctx.K.reshape(1, 4), np.int64(2))
    assert a.shape == (12, 12) and np.array_equal(a, b)
    assert control.spectral_radius(ctx.M, ctx.B, np.zeros(4), 0) == 1.0  # M = I: radius 1

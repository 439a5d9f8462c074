"""The warm-start helper behind the studies' sweeps (flapping.studies._path)."""

import numpy as np
import pytest

from flapping.errors import ConvergenceError
from flapping.studies._path import WarmStart, follow, follow_halving


class Recorder:
    """A solve of x = point that records its guesses and fails where told."""

    def __init__(self, fail_warm=(), fail=(), fail_once=()):
        self.calls = []
        self.fail_warm, self.fail, self.fail_once = set(fail_warm), set(fail), set(fail_once)

    def __call__(self, point, guess):
        self.calls.append((point, None if guess is None else guess.unknowns))
        if point in self.fail_once:
            self.fail_once.discard(point)
            raise ConvergenceError(f"no answer at {point} yet")
        if point in self.fail or (guess is not None and point in self.fail_warm):
            raise ConvergenceError(f"no answer at {point}")
        return point


def unknowns(point, result):
    return np.array([result, result**2])


def test_secant_predicts_a_linear_path_exactly():
    solve = Recorder()
    warm = WarmStart(solve, unknowns, secant=True)
    follow([(s, 2.0 * s) for s in (1.0, 2.0, 4.0)], warm)
    # Third point: the secant through (1, [2, 4]) and (2, [4, 16]) at s = 4.
    assert solve.calls[0][1] is None
    np.testing.assert_array_equal(solve.calls[1][1], [2.0, 4.0])
    np.testing.assert_array_equal(solve.calls[2][1], [8.0, 40.0])


def test_without_secant_the_guess_is_the_last_answer():
    solve = Recorder()
    follow([(s, s) for s in (1.0, 2.0, 3.0)], WarmStart(solve, unknowns))
    np.testing.assert_array_equal(solve.calls[2][1], [2.0, 4.0])


def test_failed_warm_start_is_retried_cold_and_failures_are_recorded():
    solve = Recorder(fail_warm={2.0}, fail={3.0})
    warm = WarmStart(solve, unknowns, restart=(ConvergenceError,))
    steps = follow([(s, s) for s in (1.0, 2.0, 3.0, 4.0)], warm, record=(ConvergenceError,))
    assert [step.result for step in steps] == [1.0, 2.0, None, 4.0]
    assert "no answer at 3.0" in str(steps[2].error)
    guessed = [(p, g is not None) for p, g in solve.calls]
    # 2.0: warm, then cold; 3.0: warm, cold, recorded; 4.0 starts cold after the failure.
    assert guessed == [(1.0, False), (2.0, True), (2.0, False), (3.0, True), (3.0, False),
                       (4.0, False)]


def test_unrecorded_failures_propagate():
    warm = WarmStart(Recorder(fail={2.0}))
    with pytest.raises(ConvergenceError, match="2.0"):
        follow([(1.0, 1.0), (2.0, 2.0)], warm)


def test_halving_refines_where_a_point_fails_and_keeps_the_short_step():
    solve = Recorder(fail_once={0.5})
    warm = WarmStart(solve, unknowns, secant=True)
    warm.add(0.0, 0.0, 0.0)
    steps, failures = follow_halving(lambda s: s, warm, n_steps=2, max_failures=3,
                                     retry=(ConvergenceError,), stalled=RuntimeError)
    assert failures == 1
    assert [step.s for step in steps] == [0.25, 0.5, 0.75, 1.0]  # the steps do not grow again
    assert [step.result for step in steps] == [0.25, 0.5, 0.75, 1.0]


def test_halving_stops_after_max_failures_with_the_callers_error():
    warm = WarmStart(Recorder(fail={1.0, 0.5}))
    warm.add(0.0, 0.0, 0.0)

    def stalled(s, halvings, exc):
        return ValueError(f"stalled at {s} after {halvings}")

    with pytest.raises(ValueError, match="stalled at 0.0 after 1") as info:
        follow_halving(lambda s: s, warm, n_steps=1, max_failures=1,
                       retry=(ConvergenceError,), stalled=stalled)
    assert isinstance(info.value.__cause__, ConvergenceError)


def test_order_two_predicts_a_quadratic_path_exactly():
    solve = Recorder()
    warm = WarmStart(solve, lambda point, result: np.array([result**2]), secant=True, order=2)
    follow([(s, s) for s in (1.0, 2.0, 4.0, 5.0)], warm)
    # Fourth point: the parabola through (1, 1), (2, 4), (4, 16) at s = 5 is 25.
    np.testing.assert_allclose(solve.calls[3][1], [25.0], rtol=1e-14)


def test_a_grid_corner_takes_the_last_answer_then_the_new_line():
    # A 2-D snake: along the first axis, round the corner, then along the second.
    solve = Recorder()
    warm = WarmStart(solve, lambda point, result: np.array([sum(result)]), secant=True, order=2)
    path = [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (2.0, 1.0), (2.0, 2.0)]
    follow([(c, c) for c in path], warm)
    np.testing.assert_allclose(solve.calls[2][1], [2.0])  # secant on the first line: 0, 1 -> 2
    np.testing.assert_allclose(solve.calls[3][1], [2.0])  # off that line: the last answer
    np.testing.assert_allclose(solve.calls[4][1], [4.0])  # secant on the new line: 2, 3 -> 4


def test_order_three_keeps_four_points_and_predicts_a_cubic_exactly():
    # The memory must hold order + 1 points from the third one on (it once kept one point too
    # few while filling, and the cubic fell back to the secant).
    solve = Recorder()
    warm = WarmStart(solve, lambda point, result: np.array([result**3]), secant=True, order=3)
    follow([(s, s) for s in (1.0, 2.0, 3.0, 4.0, 5.0)], warm)
    np.testing.assert_allclose(solve.calls[4][1], [125.0], rtol=1e-13)


def test_a_number_line_is_positioned_as_the_general_case_positions_a_grid_line():
    # 1-tuples take a fast path; a second axis held fixed sends the same values through the
    # general one: the positions must be the same numbers
    from flapping.studies._path import _line_positions

    rng = np.random.default_rng(3)
    for _ in range(2000):
        n = int(rng.integers(3, 7))
        values = list(rng.uniform(-5, 5) + rng.choice([0.1, 1e-3, 0.012, 3.0]) * np.arange(n))
        if rng.random() < 0.2:
            values[int(rng.integers(n))] += float(rng.uniform(-1, 1))
        line = [(float(v),) for v in values]
        grid = [(float(v), 0.7) for v in values]
        assert _line_positions(line[:-1], line[-1]) == _line_positions(grid[:-1], grid[-1])

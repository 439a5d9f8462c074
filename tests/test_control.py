"""What would make hover stable: the hinge height (passive) and feedback once per wingbeat."""

import warnings

import numpy as np
import pytest

import flapping
from flapping.hover.branch import continue_hover
from flapping.model.presets import preset
from flapping.studies import control


@pytest.fixture(scope="module")
def wmap():
    return control.linear_wingbeat_map(flapping.find_hover_orbit(flapping.hawkmoth()))


# --------------------------------------------------------------- the linear wingbeat map
def test_monodromy_is_that_of_hover_stability(wmap):
    reference = flapping.hover_stability(wmap.orbit).monodromy
    np.testing.assert_allclose(wmap.M, reference, rtol=1e-8, atol=1e-8 * np.abs(reference).max())


def test_input_matrix_matches_differences_of_the_nonlinear_wingbeat(wmap):
    # B from the variational equations against central differences of the full one-wingbeat
    # map in phi_bar (step 1e-6 rad: truncation ~1e-12, integration noise ~1e-11/1e-6 = 1e-5
    # relative at worst).
    orbit, h = wmap.orbit, 1e-6
    plus = control._one_wingbeat(orbit.model.with_stroke_mean(h), orbit.x0, orbit.period)
    minus = control._one_wingbeat(orbit.model.with_stroke_mean(-h), orbit.x0, orbit.period)
    np.testing.assert_allclose(wmap.B[:, 0], (plus - minus) / (2 * h), rtol=1e-5,
                               atol=1e-6 * np.abs(wmap.B).max())


@pytest.mark.parametrize("delay", [0, 1, 2])
def test_closed_loop_without_gain_has_the_open_loop_multipliers(wmap, delay):
    A = control.closed_loop_matrix(wmap.M, wmap.B, np.zeros(4), delay)
    assert A.shape == (4 * (delay + 1),) * 2
    mu = np.sort(np.abs(np.linalg.eigvals(A)))[::-1]
    np.testing.assert_allclose(mu[:4], np.sort(np.abs(np.linalg.eigvals(wmap.M)))[::-1],
                               rtol=1e-12)
    np.testing.assert_allclose(mu[4:], 0.0, atol=1e-12)  # the shift register's zeros


def test_closed_loop_without_delay_is_m_plus_bk(wmap):
    K = np.array([0.1, 0.0, -0.01, -0.2])
    np.testing.assert_array_equal(control.closed_loop_matrix(wmap.M, wmap.B, K, 0),
                                  wmap.M + wmap.B @ K[None, :])


def test_bad_delay_is_named(wmap):
    with pytest.raises(ValueError, match="delay"):
        control.closed_loop_matrix(wmap.M, wmap.B, np.zeros(4), -1)


# --------------------------------------------------------------- feedback maps
@pytest.mark.parametrize("delay", [0, 1, 2])
def test_speed_and_pitch_feedback_stabilises_with_up_to_two_wingbeats_of_delay(wmap, delay):
    gains, radius = control.optimal_gains(wmap, delay, start=(0.1, -0.2))
    assert radius < 0.9
    span = np.linspace(-0.05, 0.05, 21)
    region = control.gain_region(wmap, gains[0] + span, gains[1] + span, delay)
    assert 0.0 < region.stable_fraction < 1.0  # a bounded region of the plane
    small, small_radius = control.smallest_stabilising_gains(wmap, delay, 0.3)
    assert small_radius == pytest.approx(0.98, abs=1e-9)  # on the margin's boundary
    assert np.linalg.norm(small) < np.linalg.norm(gains)
    # No stabilising grid point (with the margin) is nearer the origin.
    g1, g2 = np.meshgrid(region.k1, region.k2)
    norms = np.hypot(g1, g2)[region.radius <= 0.98]
    assert norms.size == 0 or norms.min() >= np.linalg.norm(small) - 1e-12


def test_pitch_rate_and_angle_alone_stabilise_without_delay_only(wmap):
    pair = control.PITCH_RATE_ANGLE
    _, radius0 = control.optimal_gains(wmap, 0, start=(-0.01, -1.4), states=pair)
    _, radius1 = control.optimal_gains(wmap, 1, start=(-0.003, -0.33), states=pair)
    assert radius0 < 1.0 < radius1


def test_delay_limit_of_speed_and_pitch_feedback(wmap):
    d_max, best = control.delay_limit(wmap, 6, start=(0.1, -0.2))
    assert d_max == 4
    assert best[4] < 1.0 < best[5]
    assert np.all(np.diff(best) > 0)  # each wingbeat of delay costs stability margin


def test_feedback_turns_a_growing_disturbance_into_a_decaying_one(wmap):
    mu, vectors = np.linalg.eig(wmap.M)
    scale = np.abs(wmap.orbit.x).max(axis=1)
    v = np.real(vectors[:, np.argmax(np.abs(mu))])
    v = 1e-3 * v / np.linalg.norm(v / scale)
    free = control.simulate_feedback(wmap, (0.0, 0.0), 1, v, 8)
    assert free.decay_per_wingbeat == pytest.approx(np.abs(mu).max(), rel=1e-3)
    gains, radius = control.optimal_gains(wmap, 1, start=(0.1, -0.2))
    run = control.simulate_feedback(wmap, gains, 1, v, 40)
    # Non-normal transient: the deviation first grows (~2.6 x), then decays.
    assert run.deviation[-1] < 0.3 * run.deviation[0]
    # A 1e-3 disturbance: the nonlinear run follows the linear prediction to ~1e-3 relative.
    np.testing.assert_allclose(run.deviation, run.linear_deviation, rtol=2e-3)
    assert run.decay_per_wingbeat == pytest.approx(run.linear_decay_per_wingbeat, rel=1e-3)
    assert run.decay_per_wingbeat < 1.0


# --------------------------------------------------------------- passive stability
@pytest.fixture(scope="module")
def hawkmoth_sweep():
    return control.passive_sweep(flapping.hawkmoth(), np.array([0.0, 10e-3, 20e-3, 22e-3,
                                                                23e-3, 25e-3]))


def test_hinge_height_shrinks_the_unstable_multiplier(hawkmoth_sweep):
    m = hawkmoth_sweep.max_modulus
    assert m[0] == pytest.approx(1.2929, abs=1e-4)  # the paper-model hover, h_w = 0
    assert np.all(np.diff(m[:4]) < 0)
    for orbit in hawkmoth_sweep.orbits:
        assert orbit.is_hover and abs(orbit.stroke_mean) < 1e-9  # the symmetric orbit


def test_hawkmoth_hover_becomes_stable_through_plus_one(hawkmoth_sweep):
    assert hawkmoth_sweep.brackets() == [(3, 4)]
    crossing = control.locate_passive_crossing(hawkmoth_sweep, (3, 4))
    assert crossing.kind == "+1" and crossing.stabilising
    assert 22.5e-3 < crossing.hinge_height < 22.8e-3
    # Two routes: max |mu| = 1 on the kernel (one trim; the adaptive two-trim solve where the
    # kernel fails next to the crossing) and det(I - M) = 0 on two-trim adaptive orbits, each by
    # brentq to 1e-10 m; the multipliers agree to ~1e-8, so the routes to ~1e-9 m.
    assert abs(crossing.hinge_height - crossing.check_height) < 1e-8
    # A third: the continuation in hinge_height (one-trim problem, pseudo-arclength) brackets it.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        branch = continue_hover(flapping.hawkmoth(hinge_height=21e-3), "hinge_height", 24e-3)
    modulus = np.abs(branch.multipliers).max(axis=1)
    before = branch.p < crossing.hinge_height
    assert np.all(modulus[before] > 1.0) and np.all(modulus[~before] < 1.0)


def test_locate_refuses_a_non_bracket(hawkmoth_sweep):
    with pytest.raises(ValueError, match="bracket"):
        control.locate_passive_crossing(hawkmoth_sweep, (0, 1))


def test_sweep_needs_increasing_heights():
    with pytest.raises(ValueError, match="hinge_heights"):
        control.passive_sweep(flapping.hawkmoth(), [0.0, 0.0])


def test_bumblebee_is_stable_in_a_narrow_window_only():
    # The two leading real multipliers collide just inside the unit circle: a real multiplier
    # enters through +1, the pair they form leaves through the circle 0.16 mm higher (a
    # Neimark-Sacker crossing). A 3 mm sweep steps over the window; the refinement finds it.
    heights = np.linspace(0.0, control.BODY_LENGTHS["bumblebee"], 7)
    sweep = control.passive_sweep(preset("bumblebee"), heights)
    assert sweep.brackets() == [] and np.all(sweep.max_modulus > 1.0)
    h, mu = control.closest_approach(sweep)
    assert 4.9e-3 < h < 5.2e-3 and np.abs(mu).max() < 1.0
    window = control.stable_window(sweep)
    assert window is not None
    entry, leave = window
    assert entry.kind == "+1" and entry.stabilising
    assert leave.kind == "complex pair" and not leave.stabilising
    assert entry.hinge_height < h < leave.hinge_height
    assert 0.1e-3 < leave.hinge_height - entry.hinge_height < 0.3e-3
    for crossing in window:
        assert abs(crossing.hinge_height - crossing.check_height) < 1e-8


def test_passive_map_boundary_matches_the_located_window_and_moves_with_the_pressure_centre():
    # A 2 mm x 0.1-chord map; its x_hat = 0.25 row against the two-route window edges.
    heights = np.linspace(0.0, 40e-3, 21)
    moth = flapping.hawkmoth()
    pmap = control.passive_map(moth, heights, [0.15, 0.25, 0.35])
    assert pmap.max_modulus.shape == (3, 21)
    assert np.abs(pmap.drift).max() < 1e-6  # every point a true hover orbit
    window = control.stable_window(control.passive_sweep(moth, heights))
    assert window is not None
    edges = pmap.boundary()
    row = pmap.max_modulus[1]
    for col, crossing in enumerate(window):
        assert abs(crossing.hinge_height - crossing.check_height) < 1e-8
        i = int(np.searchsorted(heights, crossing.hinge_height))  # heights[i-1] < h < heights[i]
        assert (row[i - 1] - 1.0) * (row[i] - 1.0) < 0  # the map brackets the located edge
        assert abs(edges[1, col] - crossing.hinge_height) < heights[1] - heights[0]
    # A pressure centre further aft needs a higher hinge: entry and exit rise with x_hat,
    # each by about 5-7 mm per 0.1 chord.
    shift = np.diff(edges, axis=0)
    assert np.all((shift > 4e-3) & (shift < 8e-3))


def test_passive_map_refuses_a_pressure_centre_off_the_chord():
    with pytest.raises(ValueError, match="centers_of_pressure"):
        control.passive_map(flapping.hawkmoth(), [0.0, 1e-3], [0.25, 1.5])

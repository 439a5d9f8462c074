"""Animations of the insect: what each frame draws, the size of the HTML, the arguments."""

import math
import re
import subprocess
import sys

import numpy as np
import pytest
from scipy.integrate import cumulative_trapezoid

from flapping.hover.stability import hover_stability
from flapping_book import animation

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")

#: The bound on one animation's HTML in the book (bytes), and the frame counts of the defaults.
HTML_BOUND = 1.5e6
DEFAULT_FRAMES = {"hover": 2 * 16, "unstable": 10 * 6 + 1}
FRAME = re.compile(r'frames\[\d+\] = "data:image/png;base64,')


@pytest.fixture(scope="module")
def stability(orbit):
    return hover_stability(orbit)


def _pose(view):
    """(forward, up, pitch) of the drawn body, read back from its patches' transform."""
    matrix = (view.body[0].get_transform() - view.side_axes.transData).get_matrix()
    return matrix[0, 2], matrix[1, 2], math.atan2(matrix[1, 0], matrix[0, 0])


def _orbit_position(orbit):
    """The inertial position along the orbit's own samples (trapezoid rule), forward and down."""
    u, w, _, theta = orbit.x
    forward = cumulative_trapezoid(u * np.cos(theta) + w * np.sin(theta), orbit.t, initial=0.0)
    down = cumulative_trapezoid(-u * np.sin(theta) + w * np.cos(theta), orbit.t, initial=0.0)
    return forward, down


def test_importing_the_animations_does_not_import_matplotlib():
    code = "import sys, flapping_book.animation; print('matplotlib' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_the_hover_scene_loops_over_its_wingbeats_without_repeating_a_frame(orbit):
    view = animation.hover_scene(orbit, wingbeats=2, frames_per_wingbeat=5)
    assert view.n_frames == 10  # the closing frame at t = 2T equals the first: dropped
    assert view.flight.n_frames == 11
    assert view.flight.t[view.flight.sample(5)] == pytest.approx(orbit.period, rel=1e-14)


def test_each_frame_draws_the_pitch_and_the_magnified_position_of_the_orbit(orbit):
    # Frames fall on the orbit's own samples (512 per period); the orbit was integrated at
    # rtol 1e-11, the flight at 1e-12: they agree to ~1e-10. The trapezoid rule on 512 samples
    # gives the position to ~1e-10 m (h^2/12 times an acceleration of ~5 m/s^2 over T).
    magnification, n = 40.0, 8
    view = animation.hover_scene(orbit, wingbeats=1, frames_per_wingbeat=n,
                                 magnification=magnification)
    forward, down = _orbit_position(orbit)
    R = orbit.model.insect.semi_span
    step = (orbit.t.size - 1) // n
    for k in range(n):
        view.draw(k)
        x, y, pitch = _pose(view)
        j = k * step
        assert pitch == pytest.approx(orbit.x[3, j], abs=1e-8)
        assert x == pytest.approx(magnification * forward[j] / R, abs=1e-8 * magnification / R)
        assert y == pytest.approx(-magnification * down[j] / R, abs=1e-8 * magnification / R)


def test_the_wing_is_drawn_at_the_stroke_angle(orbit):
    view = animation.hover_scene(orbit, wingbeats=1, frames_per_wingbeat=4)
    view.draw(0)  # t = 0: the front reversal, phi = Phi; the leading edge's tip at R sin(Phi)
    tip = view.leading_edge.get_xdata()[-1]
    assert tip == pytest.approx(math.sin(orbit.amplitude), rel=1e-12)
    view.draw(2)  # t = T/2: the rear reversal, phi = -Phi
    assert view.leading_edge.get_xdata()[-1] == pytest.approx(-math.sin(orbit.amplitude), rel=1e-12)


def test_the_magnification_scales_the_displacement_and_is_written_on_the_figure(orbit):
    poses = {}
    for factor in (1.0, 25.0):
        view = animation.hover_scene(orbit, wingbeats=1, frames_per_wingbeat=4,
                                     magnification=factor)
        view.draw(1)
        poses[factor] = _pose(view)
        texts = " ".join(t.get_text() for t in view.side_axes.texts)
        assert ("true scale" if factor == 1.0 else "\u00d725") in texts
    assert poses[25.0][0] == pytest.approx(25.0 * poses[1.0][0], rel=1e-12)
    assert poses[25.0][1] == pytest.approx(25.0 * poses[1.0][1], rel=1e-12)
    assert poses[25.0][2] == poses[1.0][2]  # the pitch is drawn true


def test_the_disturbance_along_the_unstable_mode_grows_by_the_largest_multiplier(stability):
    # From x0 + eps v1 the pitch departs from the orbit by mu_1 per wingbeat, up to the
    # nonlinear terms, of relative size ~eps * mu_1^k ~ 1e-4 here.
    eps, n = 1e-4, 4
    view = animation.unstable_mode_scene(stability, epsilon=eps, wingbeats=n,
                                         frames_per_wingbeat=1)
    orbit = stability.orbit
    assert np.allclose(view.flight.x[:, 0], orbit.x0 + eps * stability.unstable_mode, rtol=0,
                       atol=1e-15)
    assert view.n_frames == n + 1  # played once, the end included
    index = [view.flight.sample(k) for k in range(n + 1)]
    departure = view.flight.x[3, index] - view.reference.x[3, index]
    ratios = departure[1:] / departure[:-1]
    assert ratios[-1] == pytest.approx(stability.multipliers[0].real, rel=1e-3)


@pytest.mark.parametrize("scene, kwargs", [
    ("hover", dict(wingbeats=1, frames_per_wingbeat=6)),
    ("unstable", dict(wingbeats=2, frames_per_wingbeat=3)),
])
def test_the_html_player_embeds_every_frame_offline_and_fits_the_bound(orbit, stability, scene,
                                                                       kwargs):
    if scene == "hover":
        anim = animation.animate_hover(orbit, **kwargs)
    else:
        anim = animation.animate_unstable_mode(stability, **kwargs)
    html = animation.animation_html(anim)
    n = len(FRAME.findall(html))
    expected = kwargs["wingbeats"] * kwargs["frames_per_wingbeat"] + (scene == "unstable")
    assert n == expected
    # The book's default animation has DEFAULT_FRAMES of these (the player counted per frame,
    # so the estimate errs high).
    assert len(html.encode()) / n * DEFAULT_FRAMES[scene] < HTML_BOUND
    assert "://" not in html  # nothing from the network: no CDN stylesheet
    assert '<i class="fa' not in html  # the icons are characters


@pytest.mark.parametrize("call, name", [
    (lambda o, s: animation.hover_scene(o, magnification=0.0), "magnification"),
    (lambda o, s: animation.hover_scene(o, wingbeats=0), "wingbeats"),
    (lambda o, s: animation.hover_scene(o, frames_per_wingbeat=1000), "frames_per_wingbeat"),
    (lambda o, s: animation.hover_scene(s), "orbit"),
    (lambda o, s: animation.unstable_mode_scene(s, epsilon=0.0), "epsilon"),
    (lambda o, s: animation.unstable_mode_scene(s, epsilon=2.0), "epsilon"),
    (lambda o, s: animation.unstable_mode_scene(o), "stability"),
    (lambda o, s: animation.fly(o, [0.0, 0.0], wingbeats=1, frames_per_wingbeat=1), "start"),
    (lambda o, s: animation.animate_hover(o, wingbeat_seconds=-1.0), "wingbeat_seconds"),
    (lambda o, s: animation.animation_html("not an animation"), "animation"),
])
def test_bad_arguments_raise_a_value_error_naming_them(orbit, stability, call, name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        call(orbit, stability)

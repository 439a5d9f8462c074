"""Animations of the insect in flight, seen from the side: the hover orbit and its unstable mode.

Two scenes, each a :class:`SideView` (the insect on the left, its pitch and forward drift against
time on the right) that :meth:`SideView.animation` turns into a
:class:`matplotlib.animation.FuncAnimation`, and :func:`animation_html` into HTML for a page:

* :func:`animate_hover` (:func:`hover_scene`): the insect on its hover orbit over a wingbeat or
  two. The body's motion is a fraction of a millimetre, so its displacement is magnified (the
  factor is written on the figure); its pitch, a few degrees, is drawn true.
* :func:`animate_unstable_mode` (:func:`unstable_mode_scene`): the full nonlinear equations of
  motion started on the orbit plus a disturbance along the unstable Floquet mode, over ten or so
  wingbeats, beside the undisturbed orbit (in grey): the pitch and the drift grow by the largest
  multiplier per wingbeat.

The flights are integrated by :func:`fly`: the state equations (paper eq. 2) with the inertial
position alongside, so that the drawn position is the integral of the drawn states. The drawing
follows the book's axes (book/notation.md): x forward, z down, theta nose up; the
plot shows up as up. Lengths are drawn in units of the semi-span R; the body outline is the
schematic's (:mod:`flapping_book.schematic`), the wing is the insect's own planform seen from the
side, at the stroke angle phi(t) of paper eq. (39) and the geometric pitch of paper eq. (11).
Matplotlib is imported inside the functions: importing this module does not import it.
"""

from __future__ import annotations

import base64
import io
import math
import re
from dataclasses import dataclass
from typing import Any

import numpy as np

from flapping import _validation
from flapping.errors import require_success
from flapping.hover import ANALYSIS_RTOL, HoverOrbit
from flapping.hover.stability import PERTURBATION_ATOL, HoverStability
from flapping.model.dynamics import inertial_velocity
from flapping.model.kinematics import flapping_angle, stroke_sign
from flapping.periodic.integrate import flow
from flapping_book.plotting import shade_half_strokes
from flapping_book.schematic import draw_body
from flapping_book.style import LOAD_COLORS, SOURCE_COLORS, STATE_COLORS

__all__ = [
    "FIGSIZE_IN",
    "DPI",
    "Flight",
    "fly",
    "SideView",
    "hover_scene",
    "unstable_mode_scene",
    "animate_hover",
    "animate_unstable_mode",
    "animation_html",
]

#: Size of every animation's frame [in]; with :data:`DPI`, 680 x 270 px: narrower than the
#: book's ~750 px column, and small enough that sixty frames stay under ~1.5 MB of HTML.
FIGSIZE_IN: tuple[float, float] = (6.8, 2.7)
#: Resolution of the frames [pixels per inch].
DPI = 100
#: Samples per wingbeat of the integrated flight at least (the traces and the CG's path are drawn
#: from them; the frames are every ``samples_per_frame``-th).
MIN_SAMPLES_PER_WINGBEAT = 64
#: Most wingbeats and frames per wingbeat of an animation (bounds its size and render time).
MAX_WINGBEATS = 40
MAX_FRAMES_PER_WINGBEAT = 64

_INK = "0.15"
_GHOST = "0.78"
_WING = "0.45"
_FONT = 8
_CHORD_CLIP = 0.4  # the chord is clipped at 0.4 R near the root, as in the schematic
_SPAN_POINTS = 41  # stations along the span of the drawn wing


# =========================================================================== the flight
@dataclass(frozen=True)
class Flight:
    """A flight of the insect sampled for an animation.

    Attributes
    ----------
    t : ndarray, shape (m,)
        Times [s], uniform, from 0 to ``wingbeats`` periods.
    x : ndarray, shape (4, m)
        States (u, w, q, theta) at ``t`` [m/s, m/s, rad/s, rad].
    position : ndarray, shape (2, m)
        Inertial position of the centre of gravity from its start [m]: forward (along the body
        x axis at theta = 0) and down.
    period : float
        Wingbeat period T [s].
    samples_per_frame : int
        Samples of ``t`` between two frames: frame k is sample ``k * samples_per_frame``.
    """

    t: np.ndarray
    x: np.ndarray
    position: np.ndarray
    period: float
    samples_per_frame: int

    @property
    def n_frames(self) -> int:
        """Frames from t = 0 to the last sample, both included."""
        return (self.t.size - 1) // self.samples_per_frame + 1

    def sample(self, frame: int) -> int:
        """Index into :attr:`t` of frame ``frame``."""
        return frame * self.samples_per_frame


def _with_position(fun):
    """The right-hand side of (u, w, q, theta) extended by the inertial velocity (forward, down)."""
    def extended(t: float, y: np.ndarray) -> np.ndarray:
        return np.concatenate([fun(t, y[:4]), inertial_velocity(y[0], y[1], y[3])])

    return extended


def fly(
    orbit: HoverOrbit,
    start: Any,
    *,
    wingbeats: int,
    frames_per_wingbeat: int,
    rtol: float = ANALYSIS_RTOL,
    atol: float = PERTURBATION_ATOL,
) -> Flight:
    """Integrate the full nonlinear dynamics (paper eq. 2) from ``start``, with the position.

    The inertial position of the centre of gravity is integrated with the states,
    forward' = u cos(theta) + w sin(theta) and down' = -u sin(theta) + w cos(theta) (as the
    altitude of :mod:`flapping.hover`), so it carries the integration's accuracy.

    Parameters
    ----------
    orbit : HoverOrbit
        Supplies the dynamics (its ``model``) and the period.
    start : array_like, shape (4,)
        Initial state (u, w, q, theta) at t = 0 [SI]; ``orbit.x0`` follows the orbit.
    wingbeats : int
        Periods integrated, in [1, :data:`MAX_WINGBEATS`].
    frames_per_wingbeat : int
        Frames per period, in [1, :data:`MAX_FRAMES_PER_WINGBEAT`]; the flight is sampled at
        least :data:`MIN_SAMPLES_PER_WINGBEAT` times per period, at a multiple of it.
    rtol, atol : float
        Tolerances of the integration (the defaults of
        :func:`flapping.hover.stability.perturbation_growth`).

    Returns
    -------
    Flight

    Raises
    ------
    ValueError
        For bad arguments.
    ConvergenceError
        If the integration fails.
    """
    orbit = _validation.instance("orbit", orbit, HoverOrbit)
    start = _validation.vector("start", start, size=4)
    wingbeats = _validation.integer("wingbeats", wingbeats, low=1, high=MAX_WINGBEATS)
    frames_per_wingbeat = _validation.integer("frames_per_wingbeat", frames_per_wingbeat, low=1,
                                              high=MAX_FRAMES_PER_WINGBEAT)
    rtol, atol = _validation.tolerances(rtol, atol)
    per_frame = math.ceil(MIN_SAMPLES_PER_WINGBEAT / frames_per_wingbeat)
    model = orbit.model
    t = np.linspace(0.0, wingbeats * orbit.period,
                    wingbeats * frames_per_wingbeat * per_frame + 1)
    rhs, _ = model.segment_functions()
    result = require_success(
        flow([_with_position(f) for f in rhs], (0.0, t[-1]), np.append(start, (0.0, 0.0)),
             breakpoints=model.breakpoints, period=orbit.period, t_eval=t, rtol=rtol,
             atol=atol),
        "the animated flight")
    return Flight(t, result.x[:4], result.x[4:], orbit.period, per_frame)


# =========================================================================== the drawing
def _wing_outline(insect, alpha_m: float, phi: float, sign: float) -> np.ndarray:
    """The wing seen from the side in body axes (forward, up) [R], shape (n, 2).

    The leading edge lies on the span axis (as in the schematic): at radius r it is r sin(phi)
    ahead of the hinge; the chord c(r) hangs behind it at the geometric pitch of paper eq. (11)
    (alpha_m, trailing edge behind and below on the forward stroke, ``sign`` = +1; mirrored on
    the backward stroke), its fore-aft part foreshortened by cos(phi).
    """
    R = insect.semi_span
    hinge = np.array([insect.hinge_offset, insect.hinge_height]) / R
    r = np.linspace(0.0, 1.0, _SPAN_POINTS)
    chord = np.minimum(insect.chord(r * R) / R, _CHORD_CLIP)
    leading = hinge + np.outer(r * math.sin(phi), (1.0, 0.0))
    to_trailing = np.array([-sign * math.cos(alpha_m) * math.cos(phi), -math.sin(alpha_m)])
    trailing = leading + np.outer(chord, to_trailing)
    return np.vstack([leading, trailing[::-1]])


def _add_body(ax, pose, facecolor: str, zorder: float) -> tuple[Any, ...]:
    """The schematic's body outline (body axes, in R), placed by the affine transform ``pose``."""
    before = len(ax.patches)
    draw_body(ax, lambda p: p, facecolor=facecolor)
    patches = tuple(ax.patches[before:])
    for patch in patches:
        patch.set_transform(pose + ax.transData)
        patch.set_zorder(zorder)
    return patches


class SideView:
    """A flight drawn from the side, frame by frame, beside its pitch and forward drift.

    Parameters
    ----------
    flight : Flight
        What is drawn: the body pitched by theta and placed at its magnified position, the wing
        at phi(t), the path of the centre of gravity so far.
    orbit : HoverOrbit
        The insect, its stroke amplitude and wing pitch.
    magnification : float
        Factor on the displacement of the centre of gravity (not on the pitch, drawn true).
    reference : Flight, optional
        A second flight drawn in grey (the body only), e.g. the undisturbed orbit.
    title : str
        Title of the side view.
    loop : bool
        True for a flight that closes on itself (the last frame, equal to the first, is dropped
        and the animation loops).

    Attributes
    ----------
    figure : matplotlib.figure.Figure
        Not registered with pyplot (a notebook shows only the animation, not a still of it).
    side_axes : matplotlib.axes.Axes
        The side view (data units: semi-spans R).
    body : tuple of matplotlib.patches.Patch
        The body's outline; its transform minus ``side_axes.transData`` is the drawn pose.
    leading_edge : matplotlib.lines.Line2D
        The wing's leading edge, in body axes [R] (its tip is R sin(phi) ahead of the hinge).
    """

    def __init__(self, flight: Flight, orbit: HoverOrbit, *, magnification: float,
                 reference: Flight | None = None, title: str = "", loop: bool = False) -> None:
        from matplotlib.figure import Figure
        from matplotlib.transforms import Affine2D

        self.flight, self.reference, self.loop = flight, reference, loop
        self.magnification = magnification
        self._insect = orbit.model.insect
        self._alpha_m, self._amplitude = orbit.model.alpha_m, orbit.amplitude
        self.figure = Figure(figsize=FIGSIZE_IN, dpi=DPI, layout="constrained")
        grid = self.figure.add_gridspec(2, 2, width_ratios=(1.45, 1.0))
        self.side_axes = self.figure.add_subplot(grid[:, 0])
        self._theta_axes = self.figure.add_subplot(grid[0, 1])
        self._drift_axes = self.figure.add_subplot(grid[1, 1], sharex=self._theta_axes)
        self._pose, self._ghost_pose = Affine2D(), Affine2D()
        self._draw_scene(title)
        self._draw_traces()
        self.draw(0)
        # Lay the figure out once: constrained layout at every frame would triple the render time.
        self.figure.draw_without_rendering()
        self.figure.set_layout_engine(None)  # None, not "none": savefig then draws once

    # ------------------------------------------------------------------ static parts
    def _plot_xy(self, flight: Flight) -> np.ndarray:
        """Magnified position of the centre of gravity on the plot (forward, up) [R]."""
        return self.magnification * flight.position * np.array([[1.0], [-1.0]]) / \
            self._insect.semi_span

    def _set_limits(self) -> None:
        """Limits that hold every drawn pose: the magnified paths plus the insect's reach."""
        flights = [f for f in (self.flight, self.reference) if f is not None]
        paths = np.hstack([self._plot_xy(f) for f in flights])
        pitch = max(float(np.abs(f.x[3]).max()) for f in flights)
        insect = self._insect
        reach_x = 1.0 + abs(insect.hinge_offset) / insect.semi_span + 0.1  # wing tip, chord
        reach_z = 0.5 + abs(insect.hinge_height) / insect.semi_span + math.sin(pitch)
        ax = self.side_axes
        ax.set_xlim(paths[0].min() - reach_x, paths[0].max() + reach_x)
        ax.set_ylim(paths[1].min() - reach_z, paths[1].max() + reach_z)
        ax.set_aspect("equal", adjustable="box")

    def _draw_scene(self, title: str) -> None:
        ax = self.side_axes
        ax.axis("off")
        ax.set_title(title, loc="left", fontsize=_FONT + 1)
        self._set_limits()
        ax.axhline(0.0, color=SOURCE_COLORS["ours"], lw=0.6, ls=(0, (6, 4)), alpha=0.5, zorder=0)
        scale = ("true scale" if self.magnification == 1.0
                 else f"displacement \u00d7{self.magnification:g}")
        ax.text(0.0, 0.0, f"{scale}; pitch true", transform=ax.transAxes, fontsize=_FONT,
                color="0.35", va="bottom")
        if self.reference is not None:
            self._ghost = _add_body(ax, self._ghost_pose, _GHOST, zorder=1)
            for patch in self._ghost:
                patch.set_edgecolor(_GHOST)
        self.body = _add_body(ax, self._pose, "0.86", zorder=3)
        on_body = self._pose + ax.transData
        hinge = np.array([self._insect.hinge_offset, self._insect.hinge_height]) / \
            self._insect.semi_span
        ax.plot(hinge[0] + np.array([-1.0, 1.0]), [hinge[1]] * 2, color=LOAD_COLORS["X"],
                lw=1.5, alpha=0.45, transform=on_body, zorder=2)
        from matplotlib.patches import Polygon

        # The near wing, in front of the body: translucent, so that the body shows through.
        self._wing = Polygon(np.zeros((2, 2)), closed=True, facecolor=_WING, edgecolor="0.3",
                             lw=0.7, alpha=0.45, transform=on_body, zorder=4)
        ax.add_patch(self._wing)
        (self.leading_edge,) = ax.plot([], [], color=_INK, lw=1.6, transform=on_body, zorder=4,
                                solid_capstyle="round")
        (self._cg,) = ax.plot(0.0, 0.0, "o", color=_INK, ms=3, transform=on_body, zorder=5)
        (self._path,) = ax.plot([], [], color=_INK, lw=0.8, alpha=0.7, zorder=2)
        self._clock = ax.text(0.0, 1.0, "", transform=ax.transAxes, fontsize=_FONT, va="top")

    def _draw_traces(self) -> None:
        f = self.flight
        cycles = f.t[-1] / f.period
        for ax in (self._theta_axes, self._drift_axes):
            shade_half_strokes(ax, 0.0, cycles, label=None)
            ax.tick_params(labelsize=_FONT - 1)
            ax.set_xlim(0.0, cycles)
        self._theta_axes.set_ylabel(r"$\theta$ [deg]", fontsize=_FONT)
        self._drift_axes.set_ylabel("forward [mm]", fontsize=_FONT)
        self._drift_axes.set_xlabel(r"$t/T$", fontsize=_FONT)
        self._theta_axes.tick_params(labelbottom=False)
        series = [(self._theta_axes, 180.0 / math.pi, STATE_COLORS["theta"], lambda g: g.x[3]),
                  (self._drift_axes, 1e3, _INK, lambda g: g.position[0])]
        self._traces = []
        for ax, scale, color, of in series:
            if self.reference is not None:
                ax.plot(self.reference.t / f.period, scale * of(self.reference), color=_GHOST,
                        lw=1.0)
            values = scale * of(f)
            pad = 0.08 * (np.ptp(values) or 1.0)
            ax.set_ylim(values.min() - pad, values.max() + pad)
            (line,) = ax.plot([], [], color=color, lw=1.2)
            (dot,) = ax.plot([], [], "o", color=color, ms=3)
            self._traces.append((line, dot, scale, of))

    # ------------------------------------------------------------------ one frame
    def draw(self, frame: int) -> list[Any]:
        """Show frame ``frame`` (``frame / frames_per_wingbeat`` periods); the changed artists."""
        f = self.flight
        i = f.sample(frame)
        xy = self._plot_xy(f)
        theta = float(f.x[3, i])
        self._pose.clear().rotate(theta).translate(*xy[:, i])
        insect = self._insect
        phi = insect.stroke_mean + float(flapping_angle(f.t[i], self._amplitude,
                                                        insect.frequency))
        sign = float(stroke_sign(f.t[i], insect.frequency))
        outline = _wing_outline(insect, self._alpha_m, phi, sign)
        self._wing.set_xy(outline)
        self.leading_edge.set_data(outline[:_SPAN_POINTS, 0], outline[:_SPAN_POINTS, 1])
        self._path.set_data(xy[0, :i + 1], xy[1, :i + 1])
        self._clock.set_text(f"t/T = {f.t[i] / f.period:.2f}")  # plain text: no mathtext per frame
        if self.reference is not None:
            ref = self._plot_xy(self.reference)
            self._ghost_pose.clear().rotate(float(self.reference.x[3, i])).translate(*ref[:, i])
        for line, dot, scale, of in self._traces:
            values = scale * of(f)
            line.set_data(f.t[:i + 1] / f.period, values[:i + 1])
            dot.set_data([f.t[i] / f.period], [values[i]])
        return [*self.body, self._wing, self.leading_edge, self._path, self._clock]

    @property
    def n_frames(self) -> int:
        """Frames of the animation (the flight's, less the closing one when looping)."""
        return self.flight.n_frames - (1 if self.loop else 0)

    def animation(self, *, wingbeat_seconds: float = 1.0):
        """The frames as a :class:`matplotlib.animation.FuncAnimation`.

        Parameters
        ----------
        wingbeat_seconds : float
            Playing time of one wingbeat [s] (> 0): the animation is slowed down from the
            insect's period by ``wingbeat_seconds / T``.

        Returns
        -------
        matplotlib.animation.FuncAnimation
        """
        from matplotlib.animation import FuncAnimation

        wingbeat_seconds = _validation.positive("wingbeat_seconds", wingbeat_seconds, unit="s")
        frames_per_wingbeat = round(self.flight.period / (self.flight.t[1] - self.flight.t[0])
                                    / self.flight.samples_per_frame)
        return FuncAnimation(self.figure, self.draw, frames=self.n_frames,
                             interval=1e3 * wingbeat_seconds / frames_per_wingbeat,
                             repeat=self.loop, blit=False)


# =========================================================================== the two scenes
def hover_scene(orbit: HoverOrbit, *, wingbeats: int = 2, frames_per_wingbeat: int = 16,
                magnification: float = 50.0) -> SideView:
    """The insect on its hover orbit (the scene of :func:`animate_hover`).

    Parameters
    ----------
    orbit : HoverOrbit
    wingbeats : int
        Periods shown, in [1, :data:`MAX_WINGBEATS`].
    frames_per_wingbeat : int
        In [1, :data:`MAX_FRAMES_PER_WINGBEAT`].
    magnification : float
        Factor on the displacement (> 0): it is a fraction of a millimetre on the orbit.

    Returns
    -------
    SideView
        Looping (the orbit closes after each wingbeat).

    Raises
    ------
    ValueError
        For bad arguments.
    """
    orbit = _validation.instance("orbit", orbit, HoverOrbit)
    magnification = _validation.positive("magnification", magnification)
    flight = fly(orbit, orbit.x0, wingbeats=wingbeats, frames_per_wingbeat=frames_per_wingbeat)
    return SideView(flight, orbit, magnification=magnification, title="(a) on the hover orbit",
                    loop=True)


def unstable_mode_scene(stability: HoverStability, *, epsilon: float = 0.1, wingbeats: int = 10,
                        frames_per_wingbeat: int = 6, magnification: float = 1.0) -> SideView:
    """The orbit disturbed along its unstable mode (the scene of :func:`animate_unstable_mode`).

    The full nonlinear dynamics start at x0 + epsilon v1, with v1 the eigenvector of the largest
    Floquet multiplier scaled to unit max-norm (:attr:`HoverStability.unstable_mode`); the
    undisturbed orbit, integrated from x0, is drawn in grey.

    Parameters
    ----------
    stability : HoverStability
        The orbit and its Floquet analysis; its largest multiplier must be real.
    epsilon : float
        Size of the disturbance, nonzero in [-1, 1] (its sign picks one of the mode's two
        directions; in the unit of v1's largest component).
    wingbeats : int
        Periods shown, in [1, :data:`MAX_WINGBEATS`].
    frames_per_wingbeat : int
        In [1, :data:`MAX_FRAMES_PER_WINGBEAT`].
    magnification : float
        Factor on the displacement (> 0).

    Returns
    -------
    SideView
        Played once, from t = 0 to ``wingbeats`` periods.

    Raises
    ------
    ValueError
        For bad arguments, or a largest multiplier that is complex (its mode is not one
        direction).
    """
    stability = _validation.instance("stability", stability, HoverStability)
    epsilon = _validation.real("epsilon", epsilon, low=-1.0, high=1.0)
    if epsilon == 0.0:
        raise ValueError("`epsilon` must be nonzero (the size of the disturbance); got 0.0")
    magnification = _validation.positive("magnification", magnification)
    mode = stability.unstable_mode
    if np.iscomplexobj(mode):
        raise ValueError("`stability` has a complex largest multiplier "
                         f"({stability.multipliers[0]!r}): its mode is not a single direction")
    orbit = stability.orbit
    kw = dict(wingbeats=wingbeats, frames_per_wingbeat=frames_per_wingbeat)
    disturbed = fly(orbit, orbit.x0 + epsilon * mode, **kw)
    return SideView(disturbed, orbit, magnification=magnification, reference=fly(
        orbit, orbit.x0, **kw), title="(b) disturbed along the unstable mode")


def animate_hover(orbit: HoverOrbit, *, wingbeats: int = 2, frames_per_wingbeat: int = 16,
                  magnification: float = 50.0, wingbeat_seconds: float = 1.0):
    """Animation of the insect on its hover orbit, from the side (see :func:`hover_scene`).

    Parameters
    ----------
    orbit, wingbeats, frames_per_wingbeat, magnification
        As for :func:`hover_scene`.
    wingbeat_seconds : float
        Playing time of one wingbeat [s].

    Returns
    -------
    matplotlib.animation.FuncAnimation

    Raises
    ------
    ValueError
        For bad arguments.
    """
    scene = hover_scene(orbit, wingbeats=wingbeats, frames_per_wingbeat=frames_per_wingbeat,
                        magnification=magnification)
    return scene.animation(wingbeat_seconds=wingbeat_seconds)


def animate_unstable_mode(stability: HoverStability, *, epsilon: float = 0.1,
                          wingbeats: int = 10, frames_per_wingbeat: int = 6,
                          magnification: float = 1.0, wingbeat_seconds: float = 0.6):
    """Animation of the orbit disturbed along its unstable mode (see :func:`unstable_mode_scene`).

    Parameters
    ----------
    stability, epsilon, wingbeats, frames_per_wingbeat, magnification
        As for :func:`unstable_mode_scene`.
    wingbeat_seconds : float
        Playing time of one wingbeat [s].

    Returns
    -------
    matplotlib.animation.FuncAnimation

    Raises
    ------
    ValueError
        For bad arguments.
    """
    scene = unstable_mode_scene(stability, epsilon=epsilon, wingbeats=wingbeats,
                                frames_per_wingbeat=frames_per_wingbeat,
                                magnification=magnification)
    return scene.animation(wingbeat_seconds=wingbeat_seconds)


# =========================================================================== HTML
#: Matplotlib's player draws its buttons with Font Awesome icons from a CDN; the book is read
#: offline, so :func:`animation_html` drops the link and writes the icons as plain characters.
_ICONS = {
    "fa-minus": "\u2212", "fa-fast-backward": "\u21e4", "fa-step-backward": "\u2039",
    "fa-play fa-flip-horizontal": "\u25c0\ufe0e", "fa-pause": "\u275a\u275a",
    "fa-play": "\u25b6\ufe0e", "fa-step-forward": "\u203a", "fa-fast-forward": "\u21e5",
    "fa-plus": "+",
}
_ICON = re.compile(r'<i class="fa ([^"]+)"></i>')
_CDN_LINK = re.compile(r"<link[^>]*font-awesome[^>]*>", re.DOTALL)
_FRAME = re.compile(r'"data:image/png;base64,([^"]*)"')

#: Settings of the frames that the book's other figures might change (dpi, tight bbox).
_FRAME_RC: dict[Any, Any] = {
    "savefig.dpi": "figure", "savefig.bbox": "standard", "savefig.transparent": False,
    "savefig.facecolor": "white", "animation.frame_format": "png",
}


def _quantized(match: re.Match, colors: int) -> str:
    """A PNG frame of the player (its data URI, quoted) re-encoded with ``colors`` colours."""
    from PIL import Image  # a dependency of matplotlib

    data = base64.b64decode(match.group(1).replace("\\\n", ""))
    image = Image.open(io.BytesIO(data)).convert("RGB").quantize(colors)
    out = io.BytesIO()
    image.save(out, format="png")
    return f'"data:image/png;base64,{base64.b64encode(out.getvalue()).decode("ascii")}"'


def animation_html(animation, *, colors: int = 64) -> str:
    """A self-contained HTML player of ``animation`` (frames embedded as PNG), for a book page.

    :meth:`~matplotlib.animation.Animation.to_jshtml` at the figure's own size and dpi
    (:data:`FIGSIZE_IN`, :data:`DPI` for the scenes of this module), then two changes: each
    frame is re-encoded with a palette of ``colors`` colours (a third of the size of matplotlib's
    RGBA frames for these flat drawings, with no visible change), and the player's network link
    is removed (its icons become characters), so the page renders offline.

    Parameters
    ----------
    animation : matplotlib.animation.Animation
    colors : int
        Colours of each frame's palette, in [2, 256].

    Returns
    -------
    str
        Display it with ``IPython.display.HTML``.

    Raises
    ------
    ValueError
        If ``animation`` is not a matplotlib animation, or for a bad ``colors``.
    """
    import matplotlib
    from matplotlib.animation import Animation

    animation = _validation.instance("animation", animation, Animation)
    colors = _validation.integer("colors", colors, low=2, high=256)
    with matplotlib.rc_context(_FRAME_RC):
        html = animation.to_jshtml()
    html = _FRAME.sub(lambda m: _quantized(m, colors), html)
    html = _CDN_LINK.sub("", html)
    return _ICON.sub(lambda m: _ICONS.get(m.group(1), m.group(0)), html)

"""The schematic of the paper's model (its Figs. 1-4) in one figure: :func:`draw_insect_model`.

Drawn with matplotlib patches in the book's colours (:mod:`flapping_book.style`); matplotlib is
imported inside the functions. The private helpers draw one panel each: the stroke from above
(:func:`_draw_top_view`), the body axes and states from the side (:func:`_draw_side_view`), and a
wing section on the forward and backward strokes (:func:`_draw_section`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from flapping_book.style import LOAD_COLORS, STATE_COLORS

__all__ = ["draw_insect_model", "draw_body"]


def _pyplot():
    import matplotlib.pyplot as plt  # lazy: drawn figures only load matplotlib

    return plt


def draw_insect_model(insect=None, *, alpha_m: float | None = None, theta_deg: float = 15.0,
                      phi_deg: float = 30.0, induced_deg: float = 10.0):
    """Schematic of the paper's model (its Figs. 1-4) in one figure of three panels.

    (a) Top view of the stroke: body, hinge at x_h, right wing (Ellington's beta planform of
    ``insect``) at flapping angle phi between the extremes +-Phi, a section at radius r with its
    velocity U = r phi_dot + u cos(phi) and its arm r sin(phi) ahead of the hinge.
    (b) Side view in body axes (x forward, z down): the body pitched by theta, the stroke plane
    fixed in the body, the hinge at x_h ahead of the centre of gravity, the states u, w, q, theta.
    (c) The wing section on the forward stroke (geometric pitch alpha_m) and on the backward
    stroke (pi - alpha_m), the section velocity (U, w_eff), the induced angle alpha_i, lift l and
    drag d and their body-axis components X', Z'.

    Parameters
    ----------
    insect : Insect, optional
        Sets the planform, the stroke amplitude and (with ``alpha_m=None``) the trim pitch of
        eq. (40); default :func:`flapping.hawkmoth`.
    alpha_m : float, optional
        Geometric pitch on the forward stroke [rad], default the trim of eq. (40).
    theta_deg : float
        Body pitch drawn in (b) [deg] (illustrative).
    phi_deg : float
        Flapping angle drawn in (a) [deg] (illustrative).
    induced_deg : float
        Induced angle drawn in (c) [deg] (exaggerated for legibility).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from flapping.model.morphology import hawkmoth

    if insect is None:
        insect = hawkmoth()
    if alpha_m is None:
        from flapping.model.aerodynamics import trim_angle_of_attack

        alpha_m = trim_angle_of_attack(insect)
    plt = _pyplot()
    fig = plt.figure(figsize=(9.0, 7.2), layout="constrained")
    grid = fig.add_gridspec(2, 2, width_ratios=(1.0, 1.0))
    ax_top = fig.add_subplot(grid[0, 0])
    ax_side = fig.add_subplot(grid[1, 0])
    ax_sec = fig.add_subplot(grid[:, 1])
    _draw_top_view(ax_top, insect, math.radians(phi_deg))
    _draw_side_view(ax_side, math.radians(theta_deg))
    _draw_section(ax_sec, alpha_m, math.radians(induced_deg))
    for ax in (ax_top, ax_side, ax_sec):
        ax.set_aspect("equal")
        ax.axis("off")
    ax_top.set_title("(a) the stroke, from above", fontsize=13, loc="left")
    ax_side.set_title("(b) body axes and states, from the side", fontsize=13, loc="left")
    ax_sec.set_title("(c) a wing section, along the span", fontsize=13,
                     loc="left")
    return fig

_INK = "0.15"
_GREY = "0.5"
_LIFT = "#117733"   # lift and drag are drawn only in the model figure
_DRAG = "#AA3377"
_X_TEXT = "#A86F00"  # darker shades of the load colours, for text on white
_Z_TEXT = "#1F78B4"
_FONT = 12


def _arrow(ax, start, end, color=_INK, lw=1.6, style="-|>", ls="-", mutation=13, zorder=3,
           rad=0.0):
    """A straight (rad = 0) or curved (arc3 connection of curvature rad) arrow."""
    from matplotlib.patches import FancyArrowPatch

    patch = FancyArrowPatch(start, end, arrowstyle=style, mutation_scale=mutation, color=color,
                            lw=lw, linestyle=ls, zorder=zorder, shrinkA=0.0, shrinkB=0.0,
                            connectionstyle=f"arc3,rad={rad}")
    ax.add_patch(patch)
    return patch


def _arc(ax, center, radius, theta1, theta2, color=_INK, lw=1.0):
    """Arc from angle theta1 to theta2 [deg], counter-clockwise."""
    from matplotlib.patches import Arc

    ax.add_patch(Arc(center, 2 * radius, 2 * radius, theta1=theta1, theta2=theta2, color=color,
                     lw=lw, zorder=2))


def _polar(center, radius, angle):
    return (center[0] + radius * math.cos(angle), center[1] + radius * math.sin(angle))


def _rot(v, angle):
    c, s = math.cos(angle), math.sin(angle)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1])


def _add(a, b, k=1.0):
    return (a[0] + k * b[0], a[1] + k * b[1])


def _segment(a, b):
    """The x and y coordinates of the segment from point a to point b, for ``ax.plot``."""
    return (a[0], b[0]), (a[1], b[1])


def _text(ax, xy, s, **kw):
    kw.setdefault("fontsize", _FONT)
    kw.setdefault("zorder", 6)
    return ax.text(xy[0], xy[1], s, **kw)


def draw_body(ax: Any, transform: Callable[[tuple[float, float]], Any],
              facecolor: str = "0.86") -> None:
    """Draw the insect's outline: a thorax-abdomen ellipse and a head (illustrative, not to scale).

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Where to draw.
    transform : callable
        Maps a point ``(x, z)`` of body coordinates (in semi-spans, x forward, the pitch axis at
        the origin) to plot coordinates; the animations pitch and move the body with it.
    facecolor : str
        Fill colour of the outline.
    """
    from matplotlib.patches import Polygon

    s = np.linspace(0.0, 2.0 * math.pi, 90)
    trunk = [transform((0.62 * math.cos(a), 0.14 * math.sin(a))) for a in s]
    head = [transform((0.72 + 0.1 * math.cos(a), 0.1 * math.sin(a))) for a in s]
    for outline in (trunk, head):
        ax.add_patch(Polygon(outline, closed=True, facecolor=facecolor, edgecolor=_INK, lw=1.2,
                             zorder=2))


def _draw_top_view(ax, insect, phi):
    """Panel (a). Plot coordinates: x forward to the right, the right wing (y > 0) downward."""
    from matplotlib.patches import Polygon

    R, x_h = 1.0, 0.12                          # drawing units; x_h illustrative
    hinge = (x_h, 0.0)
    Phi = insect.stroke_amplitude
    down = (0.0, -1.0)                          # the body y axis (right wing) on the page
    draw_body(ax, lambda p: p)
    # Right wing at flapping angle phi (forward of the y axis), Ellington's beta planform with
    # the leading edge on the span axis (x0_hat = 0) and the chord behind it.
    span = _rot(down, phi)
    behind = _rot(span, -math.pi / 2)
    r = np.linspace(0.0, insect.semi_span, 120)
    chord = np.minimum(insect.chord(r) / insect.semi_span, 0.4)  # clip the root singularity
    le = [_add(hinge, span, ri / insect.semi_span) for ri in r]
    te = [_add(p, behind, ci) for p, ci in zip(le, chord, strict=True)]
    outline = le + te[::-1]
    ax.add_patch(Polygon(outline, closed=True, facecolor="#e3e3e3", edgecolor=_GREY, lw=0.9,
                         zorder=1))
    ax.plot(*_segment(hinge, _add(hinge, span, R)), color=_INK, lw=1.6, zorder=3)
    # Stroke extremes and the angle phi from the y axis.
    for sign, name, ha in ((1, r"$+\Phi$", "left"), (-1, r"$-\Phi$", "right")):
        d = _rot(down, sign * Phi)
        ax.plot(*_segment(hinge, _add(hinge, d, 1.12 * R)), color=_GREY, lw=0.9, ls=(0, (4, 3)),
                zorder=1)
        _text(ax, _add(hinge, d, 1.2 * R), name, color=_GREY, ha=ha, va="top")
    ax.plot(*_segment(hinge, _add(hinge, down, 1.12 * R)), color=_GREY, lw=0.8, ls=":", zorder=1)
    _text(ax, _add(hinge, down, 1.17 * R), r"$y$", color=_GREY, ha="center", va="top")
    _arrow(ax, _add(hinge, down, 0.45), _add(hinge, span, 0.45), rad=0.2, lw=1.2)
    _text(ax, _add(hinge, _rot(down, phi / 2), 0.55), r"$\phi$", fontsize=14, ha="left",
          va="center")
    # A section at radius r and its chordwise velocity (forward stroke shown).
    sec = _add(hinge, span, 0.66 * R)
    ax.plot(*sec, "o", color=_INK, ms=4.5, zorder=4)
    _text(ax, _add(_add(hinge, span, 0.3 * R), behind, 0.1), r"$r$", ha="center",
          va="center", fontsize=13)
    motion = (-behind[0], -behind[1])
    tip = _add(sec, motion, 0.5)
    _arrow(ax, sec, tip, color=STATE_COLORS["u"], lw=2.2)
    _text(ax, _add(tip, (0.05, 0.0)), r"$U = r\dot\phi + u\cos\phi$", color=STATE_COLORS["u"],
          ha="left", va="center")
    # Its arm r sin(phi) ahead of the hinge (eq. 12, eqs. 20-23).
    y = sec[1] - 0.22
    ax.plot([sec[0], sec[0]], [sec[1], y - 0.04], color=_GREY, lw=0.7, ls=":")
    _arrow(ax, (x_h, y), (sec[0], y), style="<|-|>", lw=0.9, mutation=9)
    _text(ax, (0.5 * (x_h + sec[0]), y - 0.05), r"$r\sin\phi$", ha="center", va="top")
    # CG, hinge and the body x axis.
    ax.plot(0.0, 0.0, "o", color=_INK, ms=5, zorder=5)
    ax.plot(*hinge, marker="o", mfc="white", mec=_INK, ms=7, zorder=5)
    _text(ax, (-0.05, 0.05), "CG", ha="right", va="bottom", fontsize=11)
    _text(ax, (x_h + 0.05, 0.05), "hinge", ha="left", va="bottom", fontsize=11)
    _arrow(ax, (0.9, 0.0), (1.3, 0.0), lw=1.4)
    _text(ax, (1.33, 0.0), r"$x$", va="center", fontsize=13)
    ax.set_xlim(-0.95, 2.15)
    ax.set_ylim(-1.45, 0.45)


def _draw_side_view(ax, theta):
    """Panel (b). The horizon is horizontal; body axes (x forward, z down) pitched up by theta."""
    def body(p):  # body coordinates (x, z) -> plot coordinates (right, up)
        return _rot((p[0], -p[1]), theta)

    x_h = 0.12
    ax.plot([-1.1, 1.75], [0.0, 0.0], color=_GREY, lw=0.9, ls=(0, (6, 4)), zorder=1)
    _text(ax, (-1.1, -0.04), "horizon", color=_GREY, fontsize=11, ha="left", va="top")
    # Stroke plane: fixed in the body, through the hinge, containing the x axis.
    ax.plot(*_segment(body((-0.95, 0.0)), body((1.05, 0.0))), color=LOAD_COLORS["X"], lw=3.0,
            alpha=0.6, zorder=3, solid_capstyle="round")
    draw_body(ax, body)
    _text(ax, body((0.8, 0.1)), "stroke plane", color=_X_TEXT, fontsize=11, ha="left",
          va="top", rotation=math.degrees(theta), rotation_mode="anchor")
    ax.plot(0.0, 0.0, "o", color=_INK, ms=5, zorder=5)
    ax.plot(*body((x_h, 0.0)), marker="o", mfc="white", mec=_INK, ms=7, zorder=6)
    _text(ax, body((-0.1, -0.03)), "CG", fontsize=11, ha="right", va="bottom")
    _text(ax, body((x_h + 0.07, 0.03)), "hinge", fontsize=11, ha="left", va="top")
    # Body axes.
    _arrow(ax, body((0.85, 0.0)), body((1.45, 0.0)), lw=1.5)
    _text(ax, body((1.5, 0.0)), r"$x$", fontsize=13, va="center")
    _arrow(ax, body((0.0, 0.16)), body((0.0, 0.85)), lw=1.5)
    _text(ax, body((0.0, 0.92)), r"$z$", fontsize=13, va="top", ha="center")
    # States: u along x, w along z, q nose-up about the CG, theta from the horizon.
    u0, u1 = body((-0.3, -0.36)), body((0.3, -0.36))
    _arrow(ax, u0, u1, color=STATE_COLORS["u"], lw=2.4)
    _text(ax, _add(u1, (0.04, 0.0)), r"$u$", color=STATE_COLORS["u"], fontsize=15,
          va="center")
    w0, w1 = body((0.45, 0.2)), body((0.45, 0.72))
    _arrow(ax, w0, w1, color=STATE_COLORS["w"], lw=2.4)
    _text(ax, _add(w1, (0.06, 0.02)), r"$w$", color=STATE_COLORS["w"], fontsize=15,
          ha="left", va="top")
    # Nose-up pitch turns the nose (+x) toward -z: counter-clockwise on the page.
    q0 = _polar((0.0, 0.0), 0.62, math.radians(192.0) + theta)
    q1 = _polar((0.0, 0.0), 0.62, math.radians(250.0) + theta)
    _arrow(ax, q0, q1, color=STATE_COLORS["q"], lw=2.0, rad=0.3)
    _text(ax, _polar((0.0, 0.0), 0.78, math.radians(228.0) + theta), r"$q$",
          color=STATE_COLORS["q"], fontsize=15, ha="center", va="center")
    _arc(ax, (0.0, 0.0), 1.6, 0.0, math.degrees(theta), color=STATE_COLORS["theta"], lw=2.0)
    _text(ax, _polar((0.0, 0.0), 1.66, theta / 2), r"$\theta$", color=STATE_COLORS["theta"],
          fontsize=15, va="center")
    # Gravity, vertical in inertial axes.
    _arrow(ax, (-0.95, 0.65), (-0.95, 0.1), lw=1.5)
    _text(ax, (-1.0, 0.45), r"$mg$", ha="right", va="center", fontsize=13)
    ax.set_xlim(-1.2, 1.9)
    ax.set_ylim(-0.95, 0.75)


def _draw_section(ax, alpha_m, alpha_i):
    """Panel (c). Plot coordinates: chordwise direction of motion of the forward stroke to the
    right, up (-z) up. The forward stroke on top with every vector, the backward one below."""
    alpha = alpha_m + alpha_i                # effective angle of attack (eq. 10)
    lift_len = 2.3
    drag_len = lift_len * math.tan(alpha)    # C_D / C_L = tan(alpha), eq. (6)
    # Lift normal to the relative wind (tilted forward by alpha_i), drag along it.
    lift = (math.sin(alpha_i) * lift_len, math.cos(alpha_i) * lift_len)
    drag = (-math.cos(alpha_i) * drag_len, math.sin(alpha_i) * drag_len)
    le, cp = _draw_forward_wing(ax, alpha_m)
    _draw_relative_wind(ax, le, alpha_i)
    _draw_forward_loads(ax, cp, lift, drag)
    _draw_section_velocity(ax, alpha_i)
    _draw_backward_stroke(ax, alpha_m, lift, drag)
    ax.set_xlim(-2.5, 3.9)
    ax.set_ylim(-7.3, 4.0)


def _draw_forward_wing(ax, alpha_m):
    """The section on the forward stroke, its pitch axis, centre of pressure and pitch angle.

    Returns the leading edge and the centre of pressure (plot coordinates).
    """
    c = 2.1
    le = (1.0, 0.0)
    to_te = (-math.cos(alpha_m), -math.sin(alpha_m))
    te = _add(le, to_te, c)
    cp = _add(le, to_te, 0.25 * c)
    ax.plot(*_segment(le, te), color=_INK, lw=5.5, solid_capstyle="round", zorder=3)
    ax.plot(*le, "o", mfc="white", mec=_INK, ms=7, zorder=4)
    ax.plot(*cp, "o", color=_INK, ms=4.5, zorder=5)
    _text(ax, (-2.4, 3.95), r"forward stroke: $\dot\phi > 0$, $s = +1$", fontsize=13,
          fontweight="bold", va="top")
    _text(ax, (-2.4, 3.55), r"geometric pitch $\alpha_m$ (eq. 11)", va="top")
    ax.annotate("leading edge = pitch axis\n($\\hat{x}_0 = 0$)", le,
                xytext=_add(le, (0.45, 0.75)), fontsize=11, ha="left", va="bottom",
                arrowprops=dict(arrowstyle="-", color=_GREY, lw=0.8))
    ax.annotate("centre of pressure,\n$\\hat{x}c$ behind the pitch axis", cp,
                xytext=_add(cp, (0.55, -0.95)), fontsize=11, ha="left", va="top",
                arrowprops=dict(arrowstyle="-", color=_GREY, lw=0.8))
    # Geometric pitch, measured at the trailing edge from the stroke plane.
    ax.plot([te[0], te[0] + 1.3], [te[1], te[1]], color=_GREY, lw=0.8, ls=":", zorder=1)
    _arc(ax, te, 1.0, 0.0, math.degrees(alpha_m))
    _text(ax, _polar(te, 1.08, alpha_m / 2), r"$\alpha_m$", ha="left", va="center")
    return le, cp


def _draw_relative_wind(ax, le, alpha_i):
    """The relative wind ahead of the leading edge ``le``, inclined by the induced angle."""
    # Relative wind from ahead and below (the section moves forward and down).
    wind = (-math.cos(alpha_i), math.sin(alpha_i))
    w_end = _add(le, wind, -0.2)
    w_start = _add(w_end, wind, -2.0)
    _arrow(ax, w_start, w_end, color=_GREY, lw=1.4, ls="--")
    ax.plot([w_start[0] - 1.1, w_start[0]], [w_start[1], w_start[1]], color=_GREY, lw=0.8,
            ls=":")
    _arc(ax, w_start, 1.0, 180.0 - math.degrees(alpha_i), 180.0, color=_GREY)
    _text(ax, _add(w_start, (0.0, -0.12)), "relative wind", color=_GREY, fontsize=11,
          ha="right", va="top")
    _text(ax, _add(w_start, (-1.05, 0.0)), r"$\alpha_i$", color=_GREY, ha="right",
          va="center", fontsize=13)


def _draw_forward_loads(ax, cp, lift, drag):
    """Lift and drag at the centre of pressure ``cp`` and their body-axis components X', Z'."""
    _arrow(ax, cp, _add(cp, lift), color=_LIFT, lw=2.4)
    _text(ax, _add(cp, lift, 1.03), r"$l$, lift", color=_LIFT, fontsize=14, ha="left",
          va="bottom")
    _arrow(ax, cp, _add(cp, drag), color=_DRAG, lw=2.4)
    _text(ax, _add(_add(cp, drag), (-0.05, -0.05)), r"$d$, drag", color=_DRAG, fontsize=14,
          ha="right", va="top")
    # Body-axis components of l + d, tip to tail: -Z' (up) then X' (here backward).
    total = _add(lift, drag)
    top = _add(cp, (0.0, total[1]))
    _arrow(ax, cp, top, color=LOAD_COLORS["Z"], lw=2.4)
    _text(ax, _add(cp, (-0.08, 0.62 * total[1])), r"$-Z'$", color=_Z_TEXT, fontsize=14,
          ha="right", va="center")
    _arrow(ax, top, _add(top, (total[0], 0.0)), color=LOAD_COLORS["X"], lw=2.4)
    _text(ax, _add(top, (0.5 * total[0], 0.08)), r"$X'$", color=_X_TEXT, fontsize=14,
          ha="center", va="bottom")
    _arrow(ax, cp, _add(cp, total), color=_GREY, lw=0.9, ls=(0, (3, 2)), mutation=9)


def _draw_section_velocity(ax, alpha_i):
    """The section velocity (U, w_eff) below the forward stroke, and the formulas linking them."""
    # Section velocity: U along the stroke, w_eff down (eqs. 9, 12).
    start = (-1.2, -2.05)
    u_len = 1.9
    _arrow(ax, start, _add(start, (u_len, 0.0)), color=STATE_COLORS["u"], lw=2.2)
    _text(ax, _add(start, (u_len + 0.08, 0.0)), r"$U$", color=STATE_COLORS["u"], fontsize=14,
          va="center")
    _arrow(ax, start, _add(start, (0.0, -u_len * math.tan(alpha_i))), color=STATE_COLORS["w"],
           lw=2.2)
    _text(ax, _add(start, (-0.08, -0.5 * u_len * math.tan(alpha_i))), r"$w_\mathrm{eff}$",
          color=STATE_COLORS["w"], fontsize=14, ha="right", va="center")
    _text(ax, _add(start, (0.0, 0.12)), "section velocity", color=_GREY, fontsize=11,
          va="bottom")
    _text(ax, (-2.4, -2.75), r"$w_\mathrm{eff} = w - q\,(r\sin\phi + x_h)$,  "
          r"$\alpha_i \approx w_\mathrm{eff}/|U|$,  $\alpha = \alpha_m + \alpha_i$",
          fontsize=11, va="top")


def _draw_backward_stroke(ax, alpha_m, lift, drag):
    """The mirror image: the backward stroke, its pitch pi - alpha_m and its loads."""
    y0 = -5.2
    c2 = 1.5
    le2 = (-0.9, y0)
    to_te2 = (math.cos(alpha_m), -math.sin(alpha_m))
    te2 = _add(le2, to_te2, c2)
    cp2 = _add(le2, to_te2, 0.25 * c2)
    _text(ax, (-2.4, y0 + 1.75), r"backward stroke: $\dot\phi < 0$, $s = -1$", fontsize=13,
          fontweight="bold", va="top")
    _text(ax, (-2.4, y0 + 1.35), r"geometric pitch $\pi - \alpha_m$: the leading edge leads",
          va="top")
    ax.plot(*_segment(le2, te2), color=_INK, lw=4.5, solid_capstyle="round", zorder=3)
    ax.plot(*le2, "o", mfc="white", mec=_INK, ms=6, zorder=4)
    ax.plot(*cp2, "o", color=_INK, ms=4, zorder=5)
    ax.plot([te2[0], te2[0] + 0.9], [te2[1], te2[1]], color=_GREY, lw=0.8, ls=":", zorder=1)
    _arc(ax, te2, 0.6, 0.0, 180.0 - math.degrees(alpha_m))
    _text(ax, _polar(te2, 0.68, math.radians(60.0)), r"$\pi - \alpha_m$", ha="left",
          va="bottom")
    scale = 0.45
    _arrow(ax, cp2, _add(cp2, (-lift[0] * scale, lift[1] * scale)), color=_LIFT, lw=2.2)
    _arrow(ax, cp2, _add(cp2, (-drag[0] * scale, drag[1] * scale)), color=_DRAG, lw=2.2)
    _text(ax, _add(cp2, (-lift[0] * scale - 0.05, lift[1] * scale)), r"$l$", color=_LIFT,
          fontsize=14, ha="right", va="top")
    _text(ax, _add(cp2, (-drag[0] * scale, drag[1] * scale + 0.05)), r"$d$", color=_DRAG,
          fontsize=14, ha="left", va="bottom")
    start2 = (1.2, y0 - 0.95)
    _arrow(ax, start2, _add(start2, (-1.3, 0.0)), color=STATE_COLORS["u"], lw=2.2)
    _text(ax, _add(start2, (0.08, 0.0)), r"$U < 0$", color=STATE_COLORS["u"], fontsize=13,
          va="center")
    _text(ax, (-2.4, y0 - 1.5), "lift still up, drag now forward:\n"
          r"$X'$ changes sign with the stroke, $Z'$ does not", fontsize=11, va="top")

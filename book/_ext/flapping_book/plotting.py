"""Figures shared by the book's chapters, in the book's colours (:mod:`flapping_book.style`).

Matplotlib is imported inside the functions, when a figure is drawn: ``import
flapping_book.plotting`` never imports it, so the tables and styles a chapter or the Sphinx build
imports stay light.

* **Time in cycles.** Functions that take times accept ``period`` and then plot t/T; the backward
  half-strokes (phase in [0, 1/2), :mod:`flapping.model.kinematics`) can be shaded with
  :func:`shade_half_strokes`.
* Colours, line styles, labels and display units come from :mod:`flapping_book.style`; the
  schematic of the model is in :mod:`flapping_book.schematic`, tables in
  :mod:`flapping_book.tables`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from flapping_book.style import (
    DERIVATIVE_LABELS,
    GUIDE_COLOR,
    LOAD_COLORS,
    LOAD_LABELS,
    MODEL_LABELS,
    MODEL_LINESTYLES,
    STATE_COLORS,
    STATE_LABELS,
    STATE_NAMES,
    STATE_SCALES,
    derivative_color,
)

__all__ = [
    "shade_half_strokes",
    "plot_states",
    "plot_loads",
    "plot_load_models",
    "plot_derivatives",
    "plot_relative_difference",
    "plot_agreement",
    "plot_multipliers",
    "HALF_STROKE_STYLES",
    "plot_orbit_projections",
    "plot_stroboscopic",
    "plot_stroboscopic_map",
    "label_levels",
]


# =========================================================================== small helpers
def _pyplot():
    import matplotlib.pyplot as plt  # lazy: drawn figures only load matplotlib

    return plt


def label_levels(x: Sequence[float], min_gap: float) -> list[int]:
    """Rows for labels placed above points at ``x`` so that no two in a row are closer than
    ``min_gap`` (same units as ``x``): 0 for the first row, 1 for the one above, ...

    Greedy from left to right: each label takes the lowest row whose last label is at least
    ``min_gap`` to its left.

    Parameters
    ----------
    x : sequence of float
        Label positions.
    min_gap : float
        Smallest distance between two labels in the same row (> 0).

    Returns
    -------
    list of int
        The row of each label, in the order of ``x``.
    """
    if not min_gap > 0:
        raise ValueError(f"min_gap must be > 0; got {min_gap!r}")
    order = sorted(range(len(x)), key=lambda k: x[k])
    last: list[float] = []          # the rightmost label of each row so far
    rows = [0] * len(x)
    for k in order:
        row = next((r for r, right in enumerate(last) if x[k] - right >= min_gap), len(last))
        if row == len(last):
            last.append(x[k])
        else:
            last[row] = x[k]
        rows[k] = row
    return rows


def _time_axis(t, period):
    t = np.asarray(t, dtype=float)
    if period is None:
        return t, "time $t$ [s]"
    return t / float(period), "time $t/T$ [wingbeats]"  # the insect's period: one wingbeat


def shade_half_strokes(ax, start: float = 0.0, stop: float = 1.0, *, color: str = "0.92",
                       label: str | None = "backward stroke"):
    """Shade the backward half-strokes (phase in [0, 1/2)) of an axis whose x is t/T in cycles.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    start, stop : float
        Range of cycles to shade.
    color : str
        Fill colour (light grey by default).
    label : str or None
        Legend entry of the first shaded band.

    Returns
    -------
    matplotlib.axes.Axes
        ``ax``.
    """
    for k in range(math.floor(start), math.ceil(stop)):
        a, b = max(k, start), min(k + 0.5, stop)
        if b > a:
            ax.axvspan(a, b, color=color, zorder=0, lw=0, label=label)
            label = None
    return ax


def _grid(plt, nrows, ncols, axes, figsize, sharex=True):
    if axes is not None:
        axes = np.asarray(axes, dtype=object).reshape(nrows, ncols)
        return axes[0, 0].figure, axes
    fig, axes = plt.subplots(nrows, ncols, figsize=figsize, sharex=sharex, squeeze=False,
                             layout="constrained")
    return fig, axes


# =========================================================================== time histories
def plot_states(t, x, *, period: float | None = None, axes=None, label: str | None = None,
                shade: bool = True, **line_kw):
    """The four states u, w, q, theta against time, one panel each, in the book's colours.

    Parameters
    ----------
    t : array_like, shape (n,)
        Times [s].
    x : array_like, shape (4, n)
        States (u, w, q, theta) in SI (as ``solve_ivp``'s ``sol.y``); shape (n, 4) is accepted
        when n != 4. theta is plotted in degrees.
    period : float, optional
        Flapping period T [s]: time is then shown in cycles t/T and the backward half-strokes
        are shaded (``shade``).
    axes : sequence of 4 Axes, optional
        Draw into these (e.g. the axes of an earlier call, to overlay a second trajectory).
    label : str, optional
        Legend entry of these curves (shown on the first panel).
    shade : bool
        Shade backward half-strokes when ``period`` is given and new axes are made.
    **line_kw
        Passed to ``Axes.plot`` (e.g. ``linestyle``); ``color`` overrides the state colours.

    Returns
    -------
    matplotlib.figure.Figure
    """
    x = np.asarray(x, dtype=float)
    t = np.asarray(t, dtype=float)
    if x.ndim != 2 or 4 not in x.shape:
        raise ValueError(f"x must have shape (4, n) or (n, 4); got {x.shape}")
    if x.shape[0] != 4:
        x = x.T
    if x.shape[1] != t.size:
        raise ValueError(f"x has {x.shape[1]} samples but t has {t.size}")
    plt = _pyplot()
    new = axes is None
    fig, grid = _grid(plt, 2, 2, axes, (8.0, 4.8))
    tt, xlabel = _time_axis(t, period)
    for ax, name, values in zip(grid.flat, STATE_NAMES, x, strict=True):
        kw = {"color": STATE_COLORS[name], **line_kw}
        ax.plot(tt, values * STATE_SCALES[name], label=label, **kw)
        ax.set_ylabel(STATE_LABELS[name])
        if new and shade and period is not None:
            shade_half_strokes(ax, tt.min(), tt.max(), label=None)
    for ax in grid[-1]:
        ax.set_xlabel(xlabel)
    if label is not None:
        grid[0, 0].legend(loc="best", fontsize="small")
    return fig


def plot_loads(t, loads, *, period: float | None = None, axes=None, model: str | None = None,
               label: str | None = None, shade: bool = True, **line_kw):
    """Aerodynamic loads X, Z, M against time, one panel each; the model sets the line style.

    Parameters
    ----------
    t : array_like, shape (n,)
        Times [s].
    loads : array_like, shape (3, n)
        (X, Z, M) [N, N, N m], e.g. from
        :meth:`flapping.model.aerodynamics.BladeElementModel.loads`.
    period : float, optional
        Flapping period T [s]: time in cycles, backward half-strokes shaded.
    axes : sequence of 3 Axes, optional
        Draw into these (to overlay models).
    model : {"linear", "small-angle", "exact"}, optional
        Selects the line style (:data:`MODEL_LINESTYLES`) and the default legend text.
    label : str, optional
        Legend entry (default: the model's label).
    shade : bool
        Shade backward half-strokes when ``period`` is given and new axes are made.

    Returns
    -------
    matplotlib.figure.Figure
    """
    loads = np.asarray(loads, dtype=float)
    if loads.ndim != 2 or loads.shape[0] != 3:
        raise ValueError(f"loads must have shape (3, n); got {loads.shape}")
    if model is not None and model not in MODEL_LINESTYLES:
        raise ValueError(f"model must be one of {tuple(MODEL_LINESTYLES)}; got {model!r}")
    plt = _pyplot()
    new = axes is None
    fig, grid = _grid(plt, 3, 1, axes, (7.0, 5.6))
    tt, xlabel = _time_axis(t, period)
    if label is None and model is not None:
        label = MODEL_LABELS[model]
    style = {"linestyle": MODEL_LINESTYLES[model]} if model is not None else {}
    for ax, name, values in zip(grid[:, 0], "XZM", loads, strict=True):
        kw = {"color": LOAD_COLORS[name], **style, **line_kw}
        ax.plot(tt, values, label=label, **kw)
        ax.set_ylabel(LOAD_LABELS[name])
        if new and shade and period is not None:
            shade_half_strokes(ax, tt.min(), tt.max(), label=None)
    grid[-1, 0].set_xlabel(xlabel)
    return fig


def plot_load_models(t, loads: Mapping[str, np.ndarray], *, reference: str | None = None,
                     period: float | None = None, shade: bool = True):
    """Loads of several aerodynamic models over time (top row) and their differences (bottom row).

    Parameters
    ----------
    t : array_like, shape (n,)
        Times [s].
    loads : mapping
        Model name (a key of :data:`MODEL_LINESTYLES`) -> (X, Z, M) array of shape (3, n).
    reference : str, optional
        The model the others are compared with in the bottom row (``other - reference``);
        default the last key of ``loads``.
    period : float, optional
        Flapping period T [s]: time in cycles, backward half-strokes shaded.

    Returns
    -------
    matplotlib.figure.Figure
    """
    if not loads:
        raise ValueError("loads must name at least one model")
    for model, value in loads.items():
        if model not in MODEL_LINESTYLES:
            raise ValueError(f"model must be one of {tuple(MODEL_LINESTYLES)}; got {model!r}")
        if np.shape(value)[0] != 3:
            raise ValueError(f"loads[{model!r}] must have shape (3, n); got {np.shape(value)}")
    reference = list(loads)[-1] if reference is None else reference
    if reference not in loads:
        raise ValueError(f"reference {reference!r} is not a key of loads")
    plt = _pyplot()
    fig, grid = plt.subplots(2, 3, figsize=(10.0, 4.6), sharex=True, layout="constrained")
    tt, xlabel = _time_axis(t, period)
    ref = np.asarray(loads[reference], dtype=float)
    for j, name in enumerate("XZM"):
        top, bottom = grid[0, j], grid[1, j]
        for model, value in loads.items():
            value = np.asarray(value, dtype=float)
            top.plot(tt, value[j], color=LOAD_COLORS[name], linestyle=MODEL_LINESTYLES[model],
                     label=MODEL_LABELS[model])
            if model != reference:
                bottom.plot(tt, value[j] - ref[j], color=LOAD_COLORS[name],
                            linestyle=MODEL_LINESTYLES[model])
        top.set_ylabel(LOAD_LABELS[name])
        unit = LOAD_LABELS[name].split("[")[1]
        bottom.set_ylabel(f"difference [{unit}")
        bottom.axhline(0.0, color="0.6", lw=0.8, zorder=1)
        bottom.set_xlabel(xlabel)
        if shade and period is not None:
            for ax in (top, bottom):
                shade_half_strokes(ax, tt.min(), tt.max(), label=None)
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], color="0.25", linestyle=MODEL_LINESTYLES[m]) for m in loads]
    fig.legend(handles, [MODEL_LABELS[m] for m in loads], loc="outside upper center",
               ncols=len(loads), fontsize="small", frameon=False)
    for ax in grid[1]:
        ax.set_title(f"model minus {MODEL_LABELS[reference]}", fontsize="small")
    return fig


def plot_derivatives(t, values: Mapping[str, np.ndarray], names: Sequence[str] | None = None, *,
                     period: float | None = None, axes=None, ncols: int = 3,
                     label: str | None = None, shade: bool = True, show_mean: bool = False,
                     **line_kw):
    """Stability derivatives against time, one panel each, coloured by :func:`derivative_color`.

    Parameters
    ----------
    t : array_like, shape (n,)
        Times [s].
    values : mapping
        Name -> array of shape (n,), e.g. ``StabilityDerivatives.as_dict()``.
    names : sequence of str, optional
        Which derivatives, in reading order (row by row); default: all keys of ``values``.
    period : float, optional
        Flapping period T [s]: time in cycles, backward half-strokes shaded.
    axes : array of Axes, optional
        Draw into these (one per name, row-major), e.g. to overlay a second source.
    ncols : int
        Panels per row.
    label : str, optional
        Legend entry (shown on the first panel).
    show_mean : bool
        Draw the mean of the samples as a thin dashed grey guide line (the cycle average when
        ``t`` is a uniform grid over whole periods).
    **line_kw
        Passed to ``Axes.plot``; ``color`` overrides the derivative colours.

    Returns
    -------
    matplotlib.figure.Figure
    """
    names = list(values) if names is None else list(names)
    for name in names:
        derivative_color(name)  # validates the name
        if name not in values:
            raise ValueError(f"values has no entry {name!r}")
    plt = _pyplot()
    nrows = math.ceil(len(names) / ncols)
    new = axes is None
    fig, grid = _grid(plt, nrows, ncols, axes, (3.0 * ncols, 2.1 * nrows))
    tt, xlabel = _time_axis(t, period)
    flat = list(grid.flat)
    for ax, name in zip(flat, names, strict=False):  # spare axes hidden below
        kw = {"color": derivative_color(name), **line_kw}
        series = np.broadcast_to(values[name], tt.shape)
        ax.plot(tt, series, label=label, **kw)
        if show_mean:
            ax.axhline(float(np.mean(series)), color=GUIDE_COLOR, lw=0.9, ls="--", zorder=1)
        ax.axhline(0.0, color="0.7", lw=0.6, zorder=0)
        ax.set_ylabel(DERIVATIVE_LABELS[name])
        if new and shade and period is not None:
            shade_half_strokes(ax, tt.min(), tt.max(), label=None)
    for ax in flat[len(names):]:
        ax.set_visible(False)
    for ax in flat[max(0, len(names) - ncols):len(names)]:
        ax.set_xlabel(xlabel)
    if label is not None:
        flat[0].legend(loc="best", fontsize="small")
    return fig


_AXIS_LINESTYLES = {"X": "-", "Z": "--", "M": ":"}


def plot_relative_difference(t, reference: Mapping[str, np.ndarray],
                             other: Mapping[str, np.ndarray], names: Sequence[str] | None = None,
                             *, period: float | None = None, ax=None, floor: float = 1e-17):
    """``|other - reference| / max|reference|`` per derivative, on a log axis.

    Each curve is normalised by the largest magnitude of its reference over the samples, so a
    derivative that passes through zero does not blow up the relative error. Colours follow
    :func:`derivative_color`; line style tells the load (X solid, Z dashed, M dotted).

    Parameters
    ----------
    t : array_like, shape (n,)
        Times [s].
    reference, other : mapping
        Name -> array of shape (n,).
    names : sequence of str, optional
        Default: the keys of ``reference``.
    period : float, optional
        Flapping period T [s] (time in cycles).
    ax : matplotlib.axes.Axes, optional
    floor : float
        Differences below this (e.g. exact zeros) are drawn at ``floor`` so the log axis shows them.

    Returns
    -------
    matplotlib.axes.Axes
    """
    names = list(reference) if names is None else list(names)
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(7.0, 3.6), layout="constrained")
    tt, xlabel = _time_axis(t, period)
    for name in names:
        ref = np.asarray(reference[name], dtype=float)
        scale = np.abs(ref).max()
        diff = np.abs(np.asarray(other[name], dtype=float) - ref)
        rel = diff / scale if scale > 0 else diff
        ax.semilogy(tt, np.maximum(rel, floor), color=derivative_color(name),
                    linestyle=_AXIS_LINESTYLES[name[0]], lw=1.2,
                    label=DERIVATIVE_LABELS[name].split(" [")[0])
    ax.set_xlabel(xlabel)
    ax.set_ylabel("|difference| / max|reference|")
    return ax


def plot_agreement(t, reference: Mapping[str, np.ndarray], other: Mapping[str, np.ndarray],
                   shown: Sequence[str], names: Sequence[str] | None = None, *,
                   period: float | None = None, labels: tuple[str, str] = ("formula", "check"),
                   markers: int = 40):
    """Two independent computations of the same quantities: a few overlaid, all compared.

    Left: the quantities ``shown``, each divided by the largest magnitude of its reference, as
    lines (``reference``) and markers (``other``, about ``markers`` of them). Right: for every
    one of ``names``, the largest ``|other - reference|`` over the samples relative to the largest
    ``|reference|``, as bars on a log axis.

    Parameters
    ----------
    t : array_like, shape (n,)
        Times [s].
    reference, other : mapping
        Name -> array of shape (n,) (stability-derivative names, for the colours and labels).
    shown : sequence of str
        The names overlaid in the left panel.
    names : sequence of str, optional
        The names compared in the right panel (default: all keys of ``reference``).
    period : float, optional
        Flapping period T [s] (time in cycles).
    labels : (str, str)
        Legend texts of ``reference`` and ``other``.
    markers : int
        Approximate number of markers per curve in the left panel.

    Returns
    -------
    matplotlib.figure.Figure
    """
    names = list(reference) if names is None else list(names)
    plt = _pyplot()
    fig, (left, right) = plt.subplots(1, 2, figsize=(10.0, 3.6), layout="constrained",
                                      width_ratios=(1.2, 1.0))
    tt, xlabel = _time_axis(t, period)
    every = max(1, len(tt) // markers)
    for name in shown:
        ref = np.asarray(reference[name], dtype=float)
        scale = np.abs(ref).max() or 1.0
        colour = derivative_color(name)
        symbol = DERIVATIVE_LABELS[name].split(" [")[0]
        left.plot(tt, ref / scale, color=colour, lw=1.4, label=f"{symbol}, {labels[0]}")
        left.plot(tt[::every], np.asarray(other[name], dtype=float)[::every] / scale, "o",
                  color=colour, ms=4, mfc="none", label=f"{symbol}, {labels[1]}")
    left.set_xlabel(xlabel)
    left.set_ylabel("value / max|value|")
    left.set_ylim(-1.15, 1.15)
    # below the panels, at the text size of the axis labels: inside the left panel it had to be
    # x-small (about 6 px high once the figure is scaled to the page)
    handles, texts = left.get_legend_handles_labels()
    fig.legend(handles, texts, loc="outside lower center", ncols=max(1, len(shown)),
               frameon=False)
    rel = []
    for name in names:
        ref = np.asarray(reference[name], dtype=float)
        diff = np.abs(np.asarray(other[name], dtype=float) - ref).max()
        rel.append(diff / (np.abs(ref).max() or 1.0))
    x = np.arange(len(names))
    right.bar(x, np.maximum(rel, 1e-18), color=[derivative_color(n) for n in names])
    right.set_yscale("log")
    right.set_xticks(x, [DERIVATIVE_LABELS[n].split(" [")[0] for n in names])
    right.set_ylabel("max|difference| / max|value|")
    right.set_ylim(1e-17, 1e-3)
    right.grid(axis="y", color="0.9", lw=0.6)
    right.set_axisbelow(True)
    return fig


# =========================================================================== Floquet multipliers
def plot_multipliers(mu, ax=None, *, label: str | None = None, color: str = "k",
                     marker: str = "o", circle: bool = True, **scatter_kw):
    """Floquet multipliers in the complex plane with the unit circle (stability boundary).

    Parameters
    ----------
    mu : array_like of complex
        Multipliers (eigenvalues of the monodromy matrix).
    ax : matplotlib.axes.Axes, optional
        Draw into this axis (e.g. to overlay the paper's multipliers on ours).
    label : str, optional
        Legend entry.
    color, marker : str
        Marker style; pass ``marker="x"`` etc. to tell sources apart.
    circle : bool
        Draw the unit circle (skip it when overlaying on an axis that has one).

    Returns
    -------
    matplotlib.axes.Axes
    """
    mu = np.atleast_1d(np.asarray(mu, dtype=complex))
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(4.2, 4.2), layout="constrained")
    if circle:
        angle = np.linspace(0.0, 2.0 * math.pi, 361)
        ax.plot(np.cos(angle), np.sin(angle), color="0.5", lw=1.0, label="unit circle")
        ax.axhline(0.0, color="0.85", lw=0.8, zorder=0)
        ax.axvline(0.0, color="0.85", lw=0.8, zorder=0)
    ax.scatter(mu.real, mu.imag, color=color, marker=marker, zorder=3, label=label,
               **scatter_kw)
    extent = max(1.15, 1.1 * float(np.abs(mu).max(initial=0.0)))
    lo, hi = ax.get_xlim()
    extent = max(extent, -lo, hi)
    ax.set_xlim(-extent, extent)
    ax.set_ylim(-extent, extent)
    ax.set_aspect("equal")
    ax.set_xlabel(r"Re $\mu$ [-]")
    ax.set_ylabel(r"Im $\mu$ [-]")
    return ax


# =========================================================================== orbits and maps
#: Line style of each half-stroke in phase portraits (neutral, so the state colours stay free):
#: the backward stroke (phase in [0, 1/2)) pale, the forward stroke dark.
HALF_STROKE_STYLES: dict[str, dict] = {
    "backward": {"color": "0.62", "lw": 2.2, "ls": "-"},
    "forward": {"color": "0.1", "lw": 1.3, "ls": "-"},
}


def plot_orbit_projections(x, *,
                           pairs: Sequence[tuple[str, str]] = (("theta", "u"), ("theta", "q")),
                           axes=None, mark_start: bool = True):
    """A periodic orbit in phase-plane projections, the two half-strokes told apart.

    The first half of the samples is the backward stroke, the second the forward stroke
    (:mod:`flapping.model.kinematics`: t = 0 at the forward reversal). With the half-period symmetry
    ``x(t + T/2) = P x(t)``, ``P = diag(-1, 1, -1, -1)``, each projection on two odd states
    (u, q, theta) is symmetric about the origin: the forward stroke is the backward one turned
    by 180 degrees.

    Parameters
    ----------
    x : array_like, shape (4, n + 1)
        States over one period on a uniform grid, both ends included (n even).
    pairs : sequence of (str, str)
        (horizontal, vertical) state names per panel.
    axes : sequence of Axes, optional
        One per pair.
    mark_start : bool
        Mark x(0) (filled circle) and x(T/2) (open square).

    Returns
    -------
    matplotlib.figure.Figure
    """
    x = np.asarray(x, dtype=float)
    if x.ndim != 2 or x.shape[0] != 4 or (x.shape[1] - 1) % 2:
        raise ValueError(f"x must have shape (4, n + 1) with n even; got {x.shape}")
    plt = _pyplot()
    if axes is None:
        fig, axes = plt.subplots(1, len(pairs), figsize=(3.4 * len(pairs), 3.2),
                                 layout="constrained", squeeze=False)
        axes = axes[0]
    fig = axes[0].figure
    index = {name: k for k, name in enumerate(STATE_NAMES)}
    half = (x.shape[1] - 1) // 2
    strokes = {"backward": slice(0, half + 1), "forward": slice(half, None)}
    for ax, (h, v) in zip(axes, pairs, strict=True):
        xs, ys = (x[index[h]] * STATE_SCALES[h], x[index[v]] * STATE_SCALES[v])
        for stroke, part in strokes.items():
            ax.plot(xs[part], ys[part], label=f"{stroke} stroke", **HALF_STROKE_STYLES[stroke])
        if mark_start:
            ax.plot(xs[0], ys[0], "o", color="k", ms=6, label="$x(0)$")
            ax.plot(xs[half], ys[half], "s", color="k", mfc="white", ms=6, label="$x(T/2)$")
        ax.axhline(0.0, color="0.85", lw=0.6, zorder=0)
        ax.axvline(0.0, color="0.85", lw=0.6, zorder=0)
        ax.set_xlabel(STATE_LABELS[h])
        ax.set_ylabel(STATE_LABELS[v])
    axes[0].legend(fontsize="x-small", loc="best")
    return fig


def plot_stroboscopic(t, x, *, period: float, names: Sequence[str] = ("u", "q", "theta"),
                      reference=None, axes=None, label: str | None = None):
    """States over many periods, pale, with the stroboscopic samples x(kT) on top.

    The fast oscillation within each period is drawn thin and light; the samples at whole
    periods, where the Floquet map acts, are drawn as joined markers in the state's colour, so
    that a slow drift shows under the wingbeat.

    Parameters
    ----------
    t : array_like, shape (m,)
        Times [s], including every whole period t = kT.
    x : array_like, shape (4, m)
        States (SI; theta plotted in degrees).
    period : float
        T [s].
    names : sequence of str
        Which states, one panel each (stacked).
    reference : array_like, shape (4, m), optional
        An unperturbed trajectory (e.g. the orbit), drawn in grey with its own samples.
    axes : sequence of Axes, optional
    label : str, optional
        Legend text of the samples.

    Returns
    -------
    matplotlib.figure.Figure
    """
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    if x.shape != (4, t.size):
        raise ValueError(f"x must have shape (4, {t.size}); got {x.shape}")
    phase = t / float(period)
    whole = np.isclose(phase, np.round(phase), rtol=0.0, atol=1e-9)
    if whole.sum() < 2:
        raise ValueError("t must include at least two whole periods t = kT")
    plt = _pyplot()
    if axes is None:
        fig, axes = plt.subplots(len(names), 1, figsize=(6.8, 1.7 * len(names) + 0.6),
                                 sharex=True, layout="constrained", squeeze=False)
        axes = axes[:, 0]
    fig = axes[0].figure
    index = {name: k for k, name in enumerate(STATE_NAMES)}
    for ax, name in zip(axes, names, strict=True):
        scale, colour = STATE_SCALES[name], STATE_COLORS[name]
        if reference is not None:
            ref = np.asarray(reference, dtype=float)[index[name]] * scale
            ax.plot(phase, ref, color="0.8", lw=0.6, zorder=1)
            ax.plot(phase[whole], ref[whole], "s", color="0.55", ms=3, zorder=2,
                    label="orbit, $x(kT)$")
        values = x[index[name]] * scale
        ax.plot(phase, values, color=colour, lw=0.5, alpha=0.45, zorder=2)
        ax.plot(phase[whole], values[whole], "o-", color=colour, ms=3.5, lw=1.0, zorder=3,
                label=label or "$x(kT)$")
        ax.set_ylabel(STATE_LABELS[name])
    axes[-1].set_xlabel("time $t/T$ [wingbeats]")
    axes[0].legend(fontsize="x-small", loc="best")
    return fig


def plot_stroboscopic_map(t, x, *, period: float, ax=None, color: str = "k",
                          label: str | None = None, ylabel: str = "$x$"):
    """One scalar over many periods (thin) with its samples x(kT) (markers): the map x_k -> x_k+1.

    Parameters
    ----------
    t, x : array_like, shape (m,)
        Times [s] (including the whole periods) and the scalar.
    period : float
        T [s].
    ax : matplotlib.axes.Axes, optional
    color : str
    label : str, optional
        Legend text of the continuous curve.
    ylabel : str

    Returns
    -------
    matplotlib.axes.Axes
    """
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    phase = t / float(period)
    whole = np.isclose(phase, np.round(phase), rtol=0.0, atol=1e-9)
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(6.4, 3.0), layout="constrained")
    ax.plot(phase, x, color=color, lw=0.9, alpha=0.6, label=label)
    ax.plot(phase[whole], x[whole], "o", color=color, ms=5, zorder=3,
            label=None if label is None else "samples $x(kT)$")
    ax.set_xlabel("time $t/T$ [periods]")
    ax.set_ylabel(ylabel)
    return ax

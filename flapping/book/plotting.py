"""Plotting (and table) helpers shared by the book's chapters: one colour per quantity.

Matplotlib is optional for the package (it is in ``environment.txt`` for the book, not in the
package's dependencies): it is imported inside the functions, so ``import flapping`` and
``import flapping.book.plotting`` never import it. The style constants below are plain data.

Conventions used across the book
--------------------------------
* **Colour = quantity.** Each state keeps its colour in every chapter (:data:`STATE_COLORS`), each
  load likewise (:data:`LOAD_COLORS`). A stability derivative takes the colour of the state it
  multiplies (X_w, Z_w, M_w are all "w"-coloured) and the constant terms X0, Z0, M0 the colour of
  their load (:func:`derivative_color`).
* **Line style = model.** The aerodynamic models of :mod:`flapping.model.dynamics` are told apart by line
  style (:data:`MODEL_LINESTYLES`), never by colour.
* **Time in cycles.** Functions that take times accept ``period`` and then plot t/T; the backward
  half-strokes (phase in [0, 1/2), :mod:`flapping.model.kinematics`) can be shaded with
  :func:`shade_half_strokes`.
* Display units: theta in degrees (:data:`STATE_SCALES`); everything else SI.

Besides figures, :func:`markdown_table` and :func:`latex_aligned` format tables and equations for
``myst_nb.glue`` (as ``IPython.display.Markdown`` / ``Math`` objects).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

__all__ = [
    "STATE_NAMES",
    "STATE_COLORS",
    "STATE_LABELS",
    "STATE_SCALES",
    "LOAD_COLORS",
    "LOAD_LABELS",
    "SOURCE_COLORS",
    "MODEL_LINESTYLES",
    "MODEL_LABELS",
    "DERIVATIVE_LABELS",
    "derivative_color",
    "draw_insect_model",
    "shade_half_strokes",
    "plot_states",
    "plot_loads",
    "plot_load_models",
    "plot_derivatives",
    "plot_relative_difference",
    "plot_agreement",
    "plot_multipliers",
    "markdown_table",
    "latex_aligned",
]

#: State components, in the order of the state vector x = (u, w, q, theta).
STATE_NAMES: tuple[str, ...] = ("u", "w", "q", "theta")

#: One colour per state, in every chapter (Okabe-Ito palette: distinguishable in colour blindness).
STATE_COLORS: dict[str, str] = {
    "u": "#0072B2",      # blue
    "w": "#D55E00",      # vermilion
    "q": "#009E73",      # bluish green
    "theta": "#CC79A7",  # reddish purple
}

#: Axis labels with display units (theta is shown in degrees, see :data:`STATE_SCALES`).
STATE_LABELS: dict[str, str] = {
    "u": r"$u$ [m/s]",
    "w": r"$w$ [m/s]",
    "q": r"$q$ [rad/s]",
    "theta": r"$\theta$ [deg]",
}

#: Factor from SI to the display unit of :data:`STATE_LABELS`.
STATE_SCALES: dict[str, float] = {"u": 1.0, "w": 1.0, "q": 1.0, "theta": 180.0 / math.pi}

#: One colour per aerodynamic load (body-axis force X, Z and pitching moment M).
LOAD_COLORS: dict[str, str] = {
    "X": "#44AA99",  # teal (orange is kept for the paper's numbers, see SOURCE_COLORS)
    "Z": "#56B4E9",  # sky blue
    "M": "#332288",  # indigo
}

#: Where a number comes from, when ours and others' share a figure: ours, the paper's printed
#: values, the first-order averaged system. Distinct from every state and load colour.
SOURCE_COLORS: dict[str, str] = {
    "ours": "0.15",        # dark grey
    "paper": "#E69F00",    # orange
    "averaged": "#882255",  # wine
}

#: Axis labels of the loads, SI.
LOAD_LABELS: dict[str, str] = {"X": r"$X$ [N]", "Z": r"$Z$ [N]", "M": r"$M$ [N m]"}

#: Line style of each aerodynamic model (see :data:`flapping.model.dynamics.AERODYNAMIC_MODELS`).
MODEL_LINESTYLES: dict[str, str] = {"linear": ":", "small-angle": "-", "exact": "--"}

#: Legend text of each aerodynamic model.
MODEL_LABELS: dict[str, str] = {
    "linear": "linear, eq. (29)",
    "small-angle": "blade element, small induced angle",
    "exact": "blade element, exact inflow",
}

#: Axis labels of the stability derivatives with their units (normalised as in eq. 29).
DERIVATIVE_LABELS: dict[str, str] = {
    "X0": r"$X_0$ [N]",
    "Z0": r"$Z_0$ [N]",
    "M0": r"$M_0$ [N m]",
    "Xu": r"$X_u$ [1/s]",
    "Xw": r"$X_w$ [1/s]",
    "Xq": r"$X_q$ [m/(s rad)]",
    "Zu": r"$Z_u$ [1/s]",
    "Zw": r"$Z_w$ [1/s]",
    "Zq": r"$Z_q$ [m/(s rad)]",
    "Mu": r"$M_u$ [1/(m s)]",
    "Mw": r"$M_w$ [1/(m s)]",
    "Mq": r"$M_q$ [1/s]",
}

_STATE_OF_SUFFIX = {"u": "u", "w": "w", "q": "q"}


def derivative_color(name: str) -> str:
    """Colour of a stability derivative: its state's colour (X_u -> u), or its load's (X0 -> X).

    Raises
    ------
    ValueError
        If ``name`` is not one of X0, Z0, M0, Xu, ..., Mq.
    """
    if name not in DERIVATIVE_LABELS:
        raise ValueError(f"name must be one of {tuple(DERIVATIVE_LABELS)}; got {name!r}")
    suffix = name[1:]
    return STATE_COLORS[suffix] if suffix in _STATE_OF_SUFFIX else LOAD_COLORS[name[0]]


# =========================================================================== small helpers
def _pyplot():
    import matplotlib.pyplot as plt  # lazy: matplotlib is not a dependency of the package

    return plt


def _time_axis(t, period):
    t = np.asarray(t, dtype=float)
    if period is None:
        return t, "time $t$ [s]"
    return t / float(period), "time $t/T$ [cycles]"


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
    for ax, name, values in zip(grid.flat, STATE_NAMES, x):
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
        (X, Z, M) [N, N, N m], e.g. from :meth:`flapping.model.aerodynamics.BladeElementModel.loads`.
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
    for ax, name, values in zip(grid[:, 0], "XZM", loads):
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
        Draw the mean of the samples as a thin dashed line (the cycle average when ``t`` is a
        uniform grid over whole periods).
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
    for ax, name in zip(flat, names):
        kw = {"color": derivative_color(name), **line_kw}
        series = np.broadcast_to(values[name], tt.shape)
        ax.plot(tt, series, label=label, **kw)
        if show_mean:
            ax.axhline(float(np.mean(series)), color=kw["color"], lw=0.9, ls="--", zorder=1)
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
    """|other - reference| / max|reference| per derivative, on a log axis.

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
    left.set_ylim(-1.15, 1.6)
    left.legend(fontsize="x-small", ncols=2, loc="upper center", frameon=False)
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


# =========================================================================== tables
def markdown_table(header: Sequence[str], rows: Sequence[Sequence], align: str | None = None) -> str:
    """A Markdown (GFM/MyST) pipe table, for ``glue`` of ``IPython.display.Markdown`` objects.

    Parameters
    ----------
    header : sequence of str
        Column titles.
    rows : sequence of sequences
        Cells, converted with ``str``; ``|`` inside a cell is escaped.
    align : str, optional
        One character per column: ``l``, ``c`` or ``r``; default all left.

    Returns
    -------
    str

    Raises
    ------
    ValueError
        If a row or ``align`` does not have one entry per column.
    """
    n = len(header)
    align = "l" * n if align is None else align
    if len(align) != n or set(align) - set("lcr"):
        raise ValueError(f"align must have one of 'l', 'c', 'r' per column ({n}); got {align!r}")
    rule = {"l": ":--", "c": ":-:", "r": "--:"}

    def line(cells):
        return "| " + " | ".join(str(c).replace("|", "\\|") for c in cells) + " |"

    out = [line(header), "|" + "|".join(rule[a] for a in align) + "|"]
    for row in rows:
        if len(row) != n:
            raise ValueError(f"every row needs {n} cells; got {len(row)} in {row!r}")
        out.append(line(row))
    return "\n".join(out)


def latex_aligned(rows: Mapping[str, object], terms_per_line: int = 3, key=None) -> str:
    r"""A LaTeX ``aligned`` block of equations ``lhs &= rhs``, long sums broken every few terms.

    Parameters
    ----------
    rows : mapping
        Left-hand side (LaTeX) -> right-hand side: a SymPy expression (printed term by term with
        ``sympy.latex``) or a LaTeX string (used as is).
    terms_per_line : int
        Terms of a sum per line, >= 1.
    key : callable, optional
        Sort key for the terms of a sum (SymPy expressions), e.g. to put the terms that vanish
        for the hawkmoth last; default SymPy's order.

    Returns
    -------
    str
        ``\begin{aligned} ... \end{aligned}``, without math delimiters.
    """
    if terms_per_line < 1:
        raise ValueError(f"terms_per_line must be >= 1; got {terms_per_line!r}")
    lines = []
    for lhs, rhs in rows.items():
        if isinstance(rhs, str):
            lines.append(f"{lhs} &= {rhs}")
            continue
        import sympy  # only needed for symbolic right-hand sides

        terms = list(sympy.Add.make_args(rhs))
        if key is not None:
            terms.sort(key=key)
        printed = []
        for k, term in enumerate(terms):
            text = sympy.latex(term)
            printed.append(text if k == 0 or text.startswith("-") else "+ " + text)
        chunks = [" ".join(printed[k:k + terms_per_line])
                  for k in range(0, len(printed), terms_per_line)]
        lines.append(f"{lhs} &= " + r" \\ &\qquad ".join(chunks))
    return "\\begin{aligned}\n" + " \\\\[6pt]\n".join(lines) + "\n\\end{aligned}"


# =========================================================================== the model figure
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


def _text(ax, xy, s, **kw):
    kw.setdefault("fontsize", _FONT)
    kw.setdefault("zorder", 6)
    return ax.text(xy[0], xy[1], s, **kw)


def _draw_body(ax, transform, facecolor="0.86"):
    """Thorax-abdomen ellipse and head, in body coordinates mapped to the plot by ``transform``."""
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
    _draw_body(ax, lambda p: p)
    # Right wing at flapping angle phi (forward of the y axis), Ellington's beta planform with
    # the leading edge on the span axis (x0_hat = 0) and the chord behind it.
    span = _rot(down, phi)
    behind = _rot(span, -math.pi / 2)
    r = np.linspace(0.0, insect.semi_span, 120)
    chord = np.minimum(insect.chord(r) / insect.semi_span, 0.4)  # clip the root singularity
    le = [_add(hinge, span, ri / insect.semi_span) for ri in r]
    te = [_add(p, behind, ci) for p, ci in zip(le, chord)]
    outline = le + te[::-1]
    ax.add_patch(Polygon(outline, closed=True, facecolor="#e3e3e3", edgecolor=_GREY, lw=0.9,
                         zorder=1))
    ax.plot(*zip(hinge, _add(hinge, span, R)), color=_INK, lw=1.6, zorder=3)
    # Stroke extremes and the angle phi from the y axis.
    for sign, name, ha in ((1, r"$+\Phi$", "left"), (-1, r"$-\Phi$", "right")):
        d = _rot(down, sign * Phi)
        ax.plot(*zip(hinge, _add(hinge, d, 1.12 * R)), color=_GREY, lw=0.9, ls=(0, (4, 3)),
                zorder=1)
        _text(ax, _add(hinge, d, 1.2 * R), name, color=_GREY, ha=ha, va="top")
    ax.plot(*zip(hinge, _add(hinge, down, 1.12 * R)), color=_GREY, lw=0.8, ls=":", zorder=1)
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
    ax.plot(*zip(body((-0.95, 0.0)), body((1.05, 0.0))), color=LOAD_COLORS["X"], lw=3.0,
            alpha=0.6, zorder=3, solid_capstyle="round")
    _draw_body(ax, body)
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
    # ---------------------------------------------------------- forward stroke
    c = 2.1
    le = (1.0, 0.0)
    to_te = (-math.cos(alpha_m), -math.sin(alpha_m))
    te = _add(le, to_te, c)
    cp = _add(le, to_te, 0.25 * c)
    ax.plot(*zip(le, te), color=_INK, lw=5.5, solid_capstyle="round", zorder=3)
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
    # Lift normal to the relative wind (tilted forward by alpha_i), drag along it.
    lift = (math.sin(alpha_i) * lift_len, math.cos(alpha_i) * lift_len)
    drag = (-math.cos(alpha_i) * drag_len, math.sin(alpha_i) * drag_len)
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
          r"$\alpha_i \approx w_\mathrm{eff}/|U|$,  $\alpha = \alpha_m + \alpha_i$", fontsize=11, va="top")
    # ---------------------------------------------------------- backward stroke (mirror image)
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
    ax.plot(*zip(le2, te2), color=_INK, lw=4.5, solid_capstyle="round", zorder=3)
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
    ax.set_xlim(-2.5, 3.9)
    ax.set_ylim(-7.3, 4.0)

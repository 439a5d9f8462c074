"""The stability explorer: an interactive plotly figure of a grid of hover orbits, offline.

:func:`explorer_data` turns the tables of :func:`flapping.studies.explorer.explore_hover` into
plain JSON-able data, one record per grid point (multipliers, leading mode, orbit, a one-line
readout); :func:`explorer_figure` draws the figure at one point, with one slider per numeric axis
and a species menu; :func:`explorer_html` writes the figure, its data and a small script into one
HTML fragment with plotly.js bundled (no network: the page works on a plane).

The figure: the four Floquet multipliers in the complex plane with the unit circle (top left),
the leading multiplier's eigenvector (its components' moduli, largest 1; bottom left), and the
orbit u, w, q, theta over one period (four panels). The sliders and the menu run plotly's
``"skip"`` method (plotly itself changes nothing); the script listens to their events and
restyles the traces from the point's record, and writes the readout above the figure. A point
without a hover orbit empties the traces and says why in the readout.

plotly is imported inside the functions: importing this module does not import it.
"""

from __future__ import annotations

import importlib
import json
import math
from typing import Any

import numpy as np

from flapping_book.style import GUIDE_COLOR, STATE_COLORS, STATE_NAMES, STATE_SCALES

__all__ = ["SLIDER_AXES", "STATE_TITLES", "explorer_data", "explorer_figure", "explorer_html",
           "point_index", "readout"]

#: The numeric axes with a slider, in the order of the sliders (the species has the menu), and
#: each one's label and value format.
SLIDER_AXES: tuple[tuple[str, str, str], ...] = (
    ("frequency_ratio", "frequency f / f₀", "×{:.2f}"),
    ("hinge_height_ratio", "hinge height h_w / R", "{:.2f}"),
    ("wing_mass_percent", "wing pair's mass, % of m", "{:g} %"),
)

#: Panel titles of the orbit's states, with display units (theta in degrees).
STATE_TITLES: dict[str, str] = {"u": "u [m/s]", "w": "w [m/s]", "q": "q [rad/s]",
                                "theta": "θ [deg]"}

#: The grid's axes in the order of the points' flat index (the last varies fastest), as in
#: :data:`flapping.studies.explorer.AXES`.
_INDEX_AXES = ("species", "frequency_ratio", "wing_mass_percent", "hinge_height_ratio")

#: Significant digits of the numbers written into the page (the plots need ~4; the readout
#: prints abs(mu_1) to 4 decimals).
_DIGITS = 6

#: Most characters of a failed point's reason in the readout.
_REASON_CHARS = 160

#: Height of the figure [px]: the six panels, and below them (in the bottom margin)
#: the three sliders. Its width follows the column.
HEIGHT_PX = 860

#: Orbit panels: (row, column) of u, w, q, theta in the 2 x 3 grid (column 1 holds the
#: multipliers and the mode).
_ORBIT_CELLS = {"u": (1, 2), "w": (1, 3), "q": (2, 2), "theta": (2, 3)}


def _round(values: Any) -> list[float | None]:
    """Numbers to ``_DIGITS`` significant digits (None for NaN), as plain floats for JSON."""
    out: list[float | None] = []
    for v in np.asarray(values, dtype=float).ravel().tolist():
        out.append(None if not math.isfinite(v) else float(f"{v:.{_DIGITS}g}"))
    return out


def point_index(shape: tuple[int, int, int, int], species: int, frequency: int, wing_mass: int,
                hinge_height: int) -> int:
    """Flat index of a grid point (C order over species, frequency, wing mass, hinge height).

    Raises
    ------
    ValueError
        If an index is outside its axis.
    """
    idx = (species, frequency, wing_mass, hinge_height)
    for name, i, n in zip(_INDEX_AXES, idx, shape, strict=True):
        if not 0 <= i < n:
            raise ValueError(f"index of `{name}` must be in [0, {n - 1}]; got {i}")
    return int(np.ravel_multi_index(idx, shape))


def readout(row: Any) -> str:
    """One line on a point: where it is and what the reader sees (or why there is no orbit).

    Parameters
    ----------
    row : mapping or pandas.Series
        A row of :attr:`~flapping.studies.explorer.Exploration.points`.
    """
    where = (f"{str(row['species']).replace('_', ' ')}, f = {row['frequency_hz']:.1f} Hz "
             f"(×{row['frequency_ratio']:.2f}), h_w = {row['hinge_height_mm']:.2f} mm "
             f"({row['hinge_height_ratio']:.2f} R), wings {row['wing_mass_percent']:g} % of m")
    if not row["converged"]:
        reason = str(row["message"]).split(": ", 1)[-1] or "no orbit"
        if len(reason) > _REASON_CHARS:
            reason = reason[:_REASON_CHARS - 3].rstrip() + "..."
        return f"{where}: no hover orbit ({reason})"
    mu = complex(row["mu1_real"], row["mu1_imag"])
    if row["stable"]:
        growth = "stable: every |μ| < 1"
    else:
        growth = f"doubles in {row['doubling_wingbeats']:.1f} wingbeats"
    mode = {"real": "real mode", "oscillatory": "oscillatory mode", "flip": "flip mode"}
    return (f"{where}: |μ₁| = {abs(mu):.4f}, {mode[str(row['mode_type'])]}, {growth}; "
            f"Φ = {row['amplitude_deg']:.1f}°")


def explorer_data(points: Any, orbits: Any, n_samples: int) -> dict[str, Any]:
    """The explorer's data as plain JSON-able values.

    Parameters
    ----------
    points, orbits : pandas.DataFrame
        :attr:`~flapping.studies.explorer.Exploration.points` and ``.orbits`` (the points in
        grid order).
    n_samples : int
        Samples per period of the orbits.

    Returns
    -------
    dict
        ``axes`` (each axis's values, species first), ``shape``, ``phase`` (t / T), and
        ``points``: one record per point in grid order with ``ok`` (a hover orbit), ``text``
        (:func:`readout`), and where ``ok``: ``mu_re``, ``mu_im`` (the four multipliers),
        ``mode`` (the leading eigenvector's moduli, u, w, q, theta), ``phase_deg`` (their
        phases) and ``orbit`` (four lists over ``phase``, theta in degrees).

    Raises
    ------
    ValueError
        If the points are not a full grid in order, or an orbit has the wrong length.
    """
    axes: dict[str, list[Any]] = {}
    for name in _INDEX_AXES:
        axes[name] = list(dict.fromkeys(points[name].tolist()))
    shape = tuple(len(axes[name]) for name in _INDEX_AXES)
    if math.prod(shape) != len(points):
        raise ValueError(f"`points` must be a full grid: {' x '.join(map(str, shape))} axes "
                         f"but {len(points)} rows")
    grid = np.array(np.unravel_index(np.arange(len(points)), shape)).T
    for name, k in zip(_INDEX_AXES, range(4), strict=True):
        if points[name].tolist() != [axes[name][i] for i in grid[:, k]]:
            raise ValueError(f"`points` must be in grid order (C order over {_INDEX_AXES}); "
                             f"column {name!r} is not")
    phase = np.linspace(0.0, 1.0, n_samples + 1)
    by_point = {int(i): g for i, g in orbits.groupby("point")}
    records: list[dict[str, Any]] = []
    for i, row in enumerate(points.to_dict("records")):
        rec: dict[str, Any] = {"ok": bool(row["converged"]), "text": readout(row)}
        if rec["ok"]:
            g = by_point.get(i)
            if g is None:
                raise ValueError(f"point {i} converged but has no orbit in `orbits`")
            curves = []
            for s in STATE_NAMES:
                v = g.loc[g["state"] == s, "value"].to_numpy()
                if v.size != phase.size:
                    raise ValueError(f"orbit of point {i}, state {s!r}: {v.size} samples, "
                                     f"expected n_samples + 1 = {phase.size}")
                curves.append(_round(v * STATE_SCALES[s]))
            rec.update(
                mu_re=_round([row[f"mu{k}_real"] for k in range(1, 5)]),
                mu_im=_round([row[f"mu{k}_imag"] for k in range(1, 5)]),
                mode=_round([row[f"mode_{s}_abs"] for s in STATE_NAMES]),
                phase_deg=_round([row[f"mode_{s}_phase_deg"] for s in STATE_NAMES]),
                orbit=curves)
        records.append(rec)
    return {"axes": axes, "shape": list(shape), "phase": _round(phase), "points": records}


def _start_index(data: dict[str, Any], start: dict[str, Any]) -> tuple[int, ...]:
    """Indexes of the figure's first point along each axis (``start``: axis -> value)."""
    out = []
    for name in _INDEX_AXES:
        values = data["axes"][name]
        if start.get(name, values[0]) not in values:
            raise ValueError(f"`start[{name!r}]` must be one of {values}; got {start[name]!r}")
        out.append(values.index(start.get(name, values[0])))
    return tuple(out)


def explorer_figure(data: dict[str, Any], start: dict[str, Any] | None = None) -> Any:
    """The explorer's figure at one point, with its sliders and species menu.

    Parameters
    ----------
    data : dict
        :func:`explorer_data`.
    start : dict, optional
        The point shown first: axis name -> one of its values (default: each axis's first).

    Returns
    -------
    plotly.graph_objects.Figure
        Traces 0-3 the orbit (u, w, q, theta), 4 the multipliers, 5 the mode, 6 the unit
        circle. ``layout.meta`` holds the axes' order and the grid's shape for the script.
    """
    go = importlib.import_module("plotly.graph_objects")
    subplots = importlib.import_module("plotly.subplots")
    first = _start_index(data, start or {})
    rec = data["points"][point_index(tuple(data["shape"]), *first)]
    fig = subplots.make_subplots(
        rows=2, cols=3, horizontal_spacing=0.09, vertical_spacing=0.16,
        subplot_titles=("multipliers μ", STATE_TITLES["u"], STATE_TITLES["w"],
                        "leading mode |v|", STATE_TITLES["q"], STATE_TITLES["theta"]))
    phase = data["phase"]
    for k, s in enumerate(STATE_NAMES):
        row, col = _ORBIT_CELLS[s]
        fig.add_trace(go.Scatter(x=phase, y=rec["orbit"][k] if rec["ok"] else [], mode="lines",
                                 name=s, line={"color": STATE_COLORS[s], "width": 2},
                                 showlegend=False), row=row, col=col)
        fig.update_xaxes(title_text="t / T", row=row, col=col, range=[0, 1])
    fig.add_trace(go.Scatter(x=rec.get("mu_re", []), y=rec.get("mu_im", []), mode="markers",
                             name="μ", marker={"color": "black", "size": 9},
                             showlegend=False), row=1, col=1)
    fig.add_trace(go.Bar(x=["u", "w", "q", "θ"], y=rec.get("mode", []), name="|v|",
                         text=_phases(rec), textposition="none",
                         hovertemplate="%{x}: |v| = %{y:.3f}, phase %{text}°<extra></extra>",
                         marker={"color": [STATE_COLORS[s] for s in STATE_NAMES]},
                         showlegend=False), row=2, col=1)
    angle = np.linspace(0.0, 2.0 * math.pi, 121)
    fig.add_trace(go.Scatter(x=_round(np.cos(angle)), y=_round(np.sin(angle)), mode="lines",
                             name="unit circle", hoverinfo="skip", showlegend=False,
                             line={"color": _css_grey(GUIDE_COLOR), "width": 1}), row=1, col=1)
    reach = max([1.0] + [math.hypot(a or 0.0, b or 0.0) for p in data["points"] if p["ok"]
                         for a, b in zip(p["mu_re"], p["mu_im"], strict=True)])
    lim = 1.1 * reach
    fig.update_xaxes(range=[-lim, lim], title_text="Re μ", row=1, col=1)
    fig.update_yaxes(range=[-lim, lim], title_text="Im μ", scaleanchor="x", row=1, col=1)
    fig.update_yaxes(range=[0, 1.05], row=2, col=1)
    n = data["shape"]
    sliders = []
    for k, (name, label, fmt) in enumerate(SLIDER_AXES):
        values = data["axes"][name]
        sliders.append({
            "name": name, "active": first[_INDEX_AXES.index(name)],
            "currentvalue": {"prefix": f"{label}: ", "font": {"size": 12}},
            "pad": {"t": 10, "b": 0}, "len": 1.0, "x": 0.0, "y": -0.14 - 0.16 * k,
            "yanchor": "top",
            "steps": [{"method": "skip", "label": fmt.format(v), "value": str(i), "args": []}
                      for i, v in enumerate(values)]})
    menu = {"type": "dropdown", "name": "species", "active": first[0], "x": 0.0, "y": 1.16,
            "xanchor": "left", "yanchor": "top", "showactive": True,
            "buttons": [{"method": "skip", "label": s.replace("_", " "), "args": []}
                        for s in data["axes"]["species"]]}
    fig.update_layout(
        height=HEIGHT_PX, autosize=True, margin={"l": 50, "r": 20, "t": 90, "b": 270},
        sliders=sliders, updatemenus=[menu], template="plotly_white", font={"size": 11},
        meta={"axes": list(_INDEX_AXES), "shape": n, "sliders": [a[0] for a in SLIDER_AXES]})
    return fig


def _phases(rec: dict[str, Any]) -> list[str]:
    """The eigenvector's phases as the bar chart's hover text (degrees, rounded)."""
    return [f"{p:.0f}" for p in rec.get("phase_deg", [])]


def _css_grey(color: str) -> str:
    """A matplotlib grey level ("0.6") as a CSS colour; other colours unchanged."""
    try:
        level = float(color)
    except ValueError:
        return color
    v = round(255 * level)
    return f"rgb({v},{v},{v})"


#: The script that connects the controls to the traces (``{plot_id}`` is the figure's div).
_SCRIPT = """
(function () {
  var gd = document.getElementById('{plot_id}');
  var data = JSON.parse(document.getElementById('{plot_id}-data').textContent);
  var out = document.getElementById('{plot_id}-readout');
  var meta = gd.layout.meta, shape = data.shape;
  var at = {};
  meta.axes.forEach(function (name, k) { at[name] = 0; });
  at.species = gd.layout.updatemenus[0].active;
  gd.layout.sliders.forEach(function (s) { at[s.name] = s.active; });
  function show() {
    var i = 0;
    meta.axes.forEach(function (name, k) { i = i * shape[k] + at[name]; });
    var p = data.points[i], e = [];
    var ok = p.ok;
    Plotly.restyle(gd, {
      x: [data.phase, data.phase, data.phase, data.phase, ok ? p.mu_re : e, ['u', 'w', 'q', 'θ']],
      y: [ok ? p.orbit[0] : e, ok ? p.orbit[1] : e, ok ? p.orbit[2] : e, ok ? p.orbit[3] : e,
          ok ? p.mu_im : e, ok ? p.mode : e]
    }, [0, 1, 2, 3, 4, 5]);
    Plotly.restyle(gd, {text: [ok ? p.phase_deg.map(function (v) { return v.toFixed(0); })
                               : e]}, [5]);
    out.textContent = p.text;
    gd.setAttribute('data-point', String(i));
  }
  gd.on('plotly_sliderchange', function (ev) { at[ev.slider.name] = ev.slider.active; show(); });
  gd.on('plotly_buttonclicked', function (ev) { at.species = ev.active; show(); });
  show();
})();
"""


def explorer_html(data: dict[str, Any], start: dict[str, Any] | None = None, *,
                  div_id: str = "stability-explorer") -> str:
    """The figure, its data and its script as one HTML fragment, plotly.js bundled (offline).

    Parameters
    ----------
    data : dict
        :func:`explorer_data`.
    start : dict, optional
        The point shown first (:func:`explorer_figure`).
    div_id : str
        The figure's element id (letters, digits, ``-`` and ``_``); the readout above it is
        ``<div_id>-readout`` and the data ``<div_id>-data``.

    Returns
    -------
    str
        Display it with ``IPython.display.HTML``.
    """
    if not div_id or not all(c.isalnum() or c in "-_" for c in div_id):
        raise ValueError(f"`div_id` must be letters, digits, '-' and '_'; got {div_id!r}")
    fig = explorer_figure(data, start)
    # "</" cannot close the script element early: every "<" in the JSON is escaped.
    payload = json.dumps(data, separators=(",", ":"), allow_nan=False).replace("<", "\\u003c")
    first = data["points"][point_index(tuple(data["shape"]),
                                       *_start_index(data, start or {}))]["text"]
    plot = fig.to_html(full_html=False, include_plotlyjs=True, div_id=div_id,
                       default_width="100%", default_height=f"{HEIGHT_PX}px",
                       config={"responsive": True, "displaylogo": False},
                       post_script=_SCRIPT.replace("{plot_id}", div_id))
    return (f'<div class="stability-explorer">\n'
            f'<p id="{div_id}-readout" class="explorer-readout" aria-live="polite">'
            f'{_escape(first)}</p>\n'
            f'<script type="application/json" id="{div_id}-data">{payload}</script>\n'
            f'{plot}\n</div>')


def _escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")

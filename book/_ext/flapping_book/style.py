"""The book's visual conventions: one colour per quantity, one line style per model.

Plain data (no matplotlib), shared by the figures (:mod:`flapping_book.plotting`) and the model
schematic (:mod:`flapping_book.schematic`), so that a chapter can colour a table or a caption the
way the figures are coloured.

* **Colour = quantity.** Each state keeps its colour in every chapter (:data:`STATE_COLORS`), each
  load likewise (:data:`LOAD_COLORS`). A stability derivative takes the colour of the state it
  multiplies (X_w, Z_w, M_w are all "w"-coloured) and the constant terms X0, Z0, M0 the colour of
  their load (:func:`derivative_color`).
* **Line style = model.** Where a figure compares the aerodynamic models of
  :mod:`flapping.model.dynamics`, they are told apart by line style (:data:`MODEL_LINESTYLES`),
  never by colour. A curve in a quantity's or a source's colour is otherwise solid, whatever
  its model. Guide lines (zero, the unit circle,
  cycle means, envelopes, reference slopes, nominal values) are thin and grey
  (:data:`GUIDE_COLOR`, :func:`is_grey`), in any line style; the caption names them.
* **Colour = source** where ours and others' numbers share a figure (:data:`SOURCE_COLORS`).
* Display units: theta in degrees (:data:`STATE_SCALES`); everything else SI.
"""

from __future__ import annotations

import math
from typing import Literal

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
    "GUIDE_COLOR",
    "derivative_color",
    "is_grey",
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
#: Dark tones chosen far from every state and source colour (the teal and sky blue used before
#: sat next to q's green and u's blue) and not grey (grey is for guide lines);
#: tests/book/test_style.py checks both.
LOAD_COLORS: dict[str, str] = {
    "X": "#556B2F",  # dark olive
    "Z": "#800000",  # maroon
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

#: Line style of each aerodynamic model where a figure compares them (see
#: :data:`flapping.model.dynamics.AERODYNAMIC_MODELS`); a figure of one model draws it solid.
MODEL_LINESTYLES: dict[str, Literal["-", "--", ":", "-."]] = {
    "linear": ":", "small-angle": "-", "exact": "--",
}

#: Colour of guide lines (cycle means, envelopes, reference slopes): a mid grey, drawn thin, in any
#: line style. Line style tells models apart only for curves in a quantity's or source's colour.
GUIDE_COLOR: str = "0.55"

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


_GREY_NAMES = frozenset({"k", "black", "w", "white", "grey", "gray", "lightgrey", "lightgray",
                         "darkgrey", "darkgray", "dimgrey", "dimgray", "silver"})


def is_grey(color: str) -> bool:
    """Whether a Matplotlib colour string is a grey (black and white included): a grey level
    ("0.55"), a grey name ("k", "grey", ...) or "#rrggbb" with three equal components.

    Guide lines must be grey (:data:`GUIDE_COLOR`); the book's test of its figures' line styles
    asks this of every line drawn dashed or dotted outside :data:`MODEL_LINESTYLES`.

    Raises
    ------
    ValueError
        If ``color`` is not a string.
    """
    if not isinstance(color, str):
        raise ValueError(f"color must be a Matplotlib colour string; got {color!r}")
    text = color.strip().lower()
    if text in _GREY_NAMES:
        return True
    try:
        level = float(text)
    except ValueError:
        pass
    else:
        return 0.0 <= level <= 1.0
    if len(text) in (7, 9) and text.startswith("#"):
        try:
            r, g, b = (int(text[k:k + 2], 16) for k in (1, 3, 5))
        except ValueError:
            return False
        return r == g == b
    return False

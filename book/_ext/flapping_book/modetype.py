"""Tables and the figure of the chapter "Real or oscillatory?" (book/mode_type.md).

The science is in :mod:`flapping.studies.cfd`; these functions only format its results: the
non-dimensional derivatives side by side, the modes of a set of eigenvalues in ms and in
wingbeats, the swaps and the physics cases, and M_u+ against the hinge height.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from flapping_book.style import GUIDE_COLOR, SOURCE_COLORS, STATE_COLORS

__all__ = ["DERIVATIVE_SYMBOLS", "derivative_rows", "mode_rows", "swap_rows", "physics_rows",
           "plot_mu_against_hinge_height", "plot_mu_sweep"]

#: Line style of each system in :func:`plot_mu_sweep`: ours solid, theirs dashed.
SYSTEM_LINESTYLES: dict[str, str] = {"ours": "-", "theirs": "--"}
SYSTEM_LABELS: dict[str, str] = {"ours": "our other terms", "theirs": "Sun & Xiong's other terms"}

#: The non-dimensional derivatives as the chapter writes them.
DERIVATIVE_SYMBOLS: dict[str, str] = {
    n: f"${n[0]}_{n[1]}^+$" for n in ("Xu", "Xw", "Xq", "Zu", "Zw", "Zq", "Mu", "Mw", "Mq")}

#: Below this, a derivative of ours is zero to rounding (the fore-aft symmetric terms are
#: ~1e-12): printed as 0 and given no ratio.
_ZERO = 1e-9


def _number(value: float, fmt: str) -> str:
    return "0" if abs(value) < _ZERO else format(value, fmt)


def derivative_rows(theirs: Mapping[str, float], ours: Mapping[str, float],
                    why: Mapping[str, str], fmt: str = ".3f") -> list[list[str]]:
    """Rows (symbol, theirs, ours, ours/theirs, why they differ) of the derivative table.

    Parameters
    ----------
    theirs, ours : mapping of str to float
        The derivatives by name (``"Xu"`` ... ``"Mq"``), in the same order.
    why : mapping of str to str
        The "why they differ" text per name (missing names get an empty cell).
    fmt : str
        Format of the values.

    Returns
    -------
    list of list of str
        A ratio is "-" where ours is zero to rounding.

    Raises
    ------
    ValueError
        If the two mappings do not name the same derivatives.
    """
    if list(theirs) != list(ours):
        raise ValueError(f"theirs and ours must name the same derivatives; got {list(theirs)} "
                         f"and {list(ours)}")
    rows = []
    for name, t in theirs.items():
        o = ours[name]
        ratio = "–" if abs(o) < _ZERO else f"{o / t:.2f}"
        rows.append([DERIVATIVE_SYMBOLS.get(name, name), _number(t, fmt), _number(o, fmt),
                     ratio, why.get(name, "")])
    return rows


def _kind(lam: complex, real_tol: float) -> str:
    growing = "unstable" if lam.real > 0 else "stable"
    if abs(lam.imag) > real_tol * abs(lam):
        return f"oscillation, {growing}"
    return "divergence" if lam.real > 0 else "subsidence"


def mode_rows(eigenvalues: Sequence[complex], period: float, *,
              real_tol: float = 1e-8) -> list[list[str]]:
    """One row per mode (a complex pair once): eigenvalue, kind, period and doubling or halving
    time, each in ms and in wingbeats.

    Parameters
    ----------
    eigenvalues : sequence of complex
        Eigenvalues [1/s] of a dimensional system, or Floquet exponents.
    period : float
        The wingbeat period T [s] (> 0), the unit of the "wingbeats" columns.
    real_tol : float
        An eigenvalue whose imaginary part is below this fraction of its modulus is real.

    Returns
    -------
    list of list of str
        ``[lambda [1/s], kind, period [ms], period [wingbeats], time [ms], time [wingbeats]]``,
        by real part, descending; the time doubles a growing mode and halves a decaying one
        (labelled "x2" or "x1/2").

    Raises
    ------
    ValueError
        If ``period`` is not positive and finite.
    """
    if not (math.isfinite(period) and period > 0.0):
        raise ValueError(f"period must be positive and finite [s]; got {period!r}")
    ev = np.asarray(eigenvalues, dtype=complex)
    rows = []
    for lam in ev[np.argsort(-ev.real, kind="stable")]:
        if lam.imag < -real_tol * abs(lam):
            continue                      # the conjugate of a pair already listed
        oscillatory = abs(lam.imag) > real_tol * abs(lam)
        value = (f"{lam.real:.2f} ± {abs(lam.imag):.2f}i" if oscillatory else f"{lam.real:.2f}")
        if oscillatory:
            p = 2.0 * math.pi / abs(lam.imag)
            p_ms, p_t = f"{p * 1e3:.0f}", f"{p / period:.1f}"
        else:
            p_ms = p_t = "–"
        t = math.log(2.0) / abs(lam.real)
        label = "×2" if lam.real > 0 else "×1/2"
        rows.append([value, _kind(complex(lam), real_tol), p_ms, p_t,
                     f"{t * 1e3:.1f} ({label})", f"{t / period:.1f}"])
    return rows


def swap_rows(swaps: Any, direction: str, labels: Sequence[str], period: float
              ) -> list[list[str]]:
    """Rows of :func:`flapping.studies.cfd.swap_table` for one direction and chosen swaps.

    Parameters
    ----------
    swaps : pandas.DataFrame
        The swap table.
    direction : str
        ``"ours <- theirs"`` or ``"theirs <- ours"``.
    labels : sequence of str
        The ``swapped`` labels to show, in order (e.g. ``"none"``, ``"Mu"``, ``"Xu+Mu"``).
    period : float
        The wingbeat period [s], for the doubling time in wingbeats.

    Returns
    -------
    list of list of str
        ``[swapped (in symbols), M_u+, type, period [ms], doubling time [ms], [wingbeats]]``.

    Raises
    ------
    ValueError
        If a label is not in the table for that direction.
    """
    part = swaps[swaps["direction"] == direction].set_index("swapped")
    missing = [label for label in labels if label not in part.index]
    if missing:
        raise ValueError(f"labels {missing} not in the swap table for {direction!r}; "
                         f"known: {list(part.index)}")
    rows = []
    for label in labels:
        r = part.loc[label]
        names = label.split("+")
        shown = label if label in ("none", "all") else ", ".join(
            DERIVATIVE_SYMBOLS.get(n, n) for n in names)
        per = "–" if not math.isfinite(r["period"]) else f"{r['period'] * 1e3:.0f}"
        rows.append([shown, f"{r['Mu']:.3f}", r["type"], per, f"{r['doubling_time'] * 1e3:.0f}",
                     f"{r['doubling_time'] / period:.1f}"])
    return rows


def case_label(case: str) -> str:
    """A case of :func:`flapping.studies.cfd.physics_table` in the book's symbols.

    The package names its cases in plain text (``"centre of pressure x_hat 0.1"``,
    ``"hinge height x2"``); the table shows ``$\\hat x$ = 0.1`` and ``×2``.
    """
    case = re.sub(r"\bx_hat (\S+)", r"$\\hat x$ = \1", case)
    return re.sub(r"\bx(\d)", r"×\1", case)


def physics_rows(physics: Any, period: float) -> list[list[str]]:
    """Rows of :func:`flapping.studies.cfd.physics_table`.

    Parameters
    ----------
    physics : pandas.DataFrame
        The physics table (a case without an orbit shows its message).
    period : float
        The wingbeat period [s].

    Returns
    -------
    list of list of str
        ``[case, M_u+, M_q+, averaged type, Floquet type, leading multiplier,
        doubling time [wingbeats] (Floquet), mean stroke angle [deg]]``.
    """
    rows = []
    for _, r in physics.iterrows():
        if r.get("message"):
            rows.append([case_label(r["case"]), "–", "–", "no orbit", "–", "–", "–",
                         r["message"]])
            continue
        mu = complex(r["leading_multiplier"])
        mult = (f"{mu.real:.4f}" if abs(mu.imag) < 1e-12
                else f"{mu.real:.4f} ± {abs(mu.imag):.4f}i")
        doubling = "–" if abs(mu) <= 1.0 else f"{math.log(2.0) / math.log(abs(mu)):.1f}"
        phibar = round(r["stroke_mean_deg"], 1) + 0.0     # no "-0.0" for a trim at rounding
        rows.append([case_label(r["case"]), f"{r['Mu']:.3f}", f"{r['Mq']:.3f}", r["averaged_type"],
                     r["floquet_type"], mult, doubling, f"{phibar:.1f}"])
    return rows


def plot_mu_against_hinge_height(heights: Sequence[float], mu: Sequence[float],
                                 oscillatory: Sequence[bool], *, intercept: float, slope: float,
                                 theirs: float, body_length: float, source_height: float,
                                 ax=None):
    """M_u+ of solved orbits against the hinge height, the straight law, and CFD's value.

    Parameters
    ----------
    heights : sequence of float
        Hinge heights above the CG [m] of the solved cases.
    mu : sequence of float
        Their M_u+.
    oscillatory : sequence of bool
        Whether each case's leading Floquet mode is oscillatory (filled marker) or real (open).
    intercept, slope : float
        The law M_u+ = intercept + slope h (slope in 1/m), drawn from h = 0 to beyond the
        height at which it reaches ``theirs``.
    theirs : float
        The CFD study's M_u+.
    body_length, source_height : float
        Body length and the comparison's hinge height [m], marked on the axis.
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ValueError
        If the sequences differ in length, or ``slope`` or ``body_length`` is not positive.
    """
    import matplotlib.pyplot as plt

    h, m, osc = (np.asarray(heights, float), np.asarray(mu, float),
                 np.asarray(oscillatory, bool))
    if not (h.shape == m.shape == osc.shape):
        raise ValueError("heights, mu and oscillatory must have the same length")
    if not slope > 0.0:
        raise ValueError(f"slope must be positive (M_u+ rising with h) [1/m]; got {slope!r}")
    if not body_length > 0.0:
        raise ValueError(f"body_length must be positive [m]; got {body_length!r}")
    if ax is None:
        fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
    else:
        fig = ax.figure
    h_match = (theirs - intercept) / slope
    h_zero = -intercept / slope
    grid = np.linspace(0.0, 1.08 * max(h_match, h.max()), 200)
    scale = 1.0 / body_length
    ax.axhline(0.0, color="0.7", lw=0.6, zorder=1)
    ax.plot(grid * scale, intercept + slope * grid, color=GUIDE_COLOR, ls="--", lw=1.0,
            label=r"law $M_u^+(0) - h X_u^+/c$")
    ax.plot(h[~osc] * scale, m[~osc], "o", mfc="white", color=STATE_COLORS["u"],
            label="our orbits, real mode")
    ax.plot(h[osc] * scale, m[osc], "o", color=STATE_COLORS["u"],
            label="our orbits, oscillatory mode")
    ax.axhline(theirs, color=SOURCE_COLORS["paper"], lw=1.4,
               label=r"CFD $M_u^+$ (Sun & Xiong)")
    ax.axvline(source_height * scale, color=GUIDE_COLOR, lw=0.8, ls=":")
    ax.text(source_height * scale, 0.5, " estimated hinge", transform=ax.get_xaxis_transform(),
            rotation=90, ha="left", va="center", fontsize="small", color="0.35")
    ax.plot([h_zero * scale], [0.0], "x", color="k", ms=7, label="neutral height")
    ax.plot([h_match * scale], [theirs], "s", color=SOURCE_COLORS["paper"], ms=6,
            label="CFD's value reached")
    ax.set_xlabel(r"hinge height above the centre of gravity, $h/L$ [body lengths]")
    ax.set_ylabel(r"$M_u^+$ [–]")
    ax.legend(loc="lower right", fontsize="small", frameon=False)
    return fig


def plot_mu_sweep(sweeps: Mapping[str, Any], thresholds: Mapping[str, float], *, ours: float,
                  theirs: float, period: float):
    """The leading mode's growth rate and frequency as M_u+ alone varies, per system.

    Parameters
    ----------
    sweeps : mapping of str to pandas.DataFrame
        :func:`flapping.studies.cfd.mu_sweep` per base (``"ours"``, ``"theirs"``).
    thresholds : mapping of str to float
        :func:`flapping.studies.cfd.mode_type_threshold` per base (marked).
    ours, theirs : float
        The two M_u+ (dotted verticals).
    period : float
        The wingbeat period [s] (> 0): rates are shown per wingbeat too, on a second axis.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    ValueError
        If a threshold names a system with no sweep, or ``period`` is not positive.
    """
    import matplotlib.pyplot as plt

    if set(thresholds) - set(sweeps):
        raise ValueError(f"thresholds name systems without a sweep: "
                         f"{sorted(set(thresholds) - set(sweeps))}")
    if not period > 0.0:
        raise ValueError(f"period must be positive [s]; got {period!r}")
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(6.4, 4.6), layout="constrained")
    for base, sweep in sweeps.items():
        style = SYSTEM_LINESTYLES.get(base, ":")
        top.plot(sweep["Mu"], sweep["rate"], color=STATE_COLORS["q"], ls=style,
                 label=SYSTEM_LABELS.get(base, base))
        bottom.plot(sweep["Mu"], sweep["frequency"], color=STATE_COLORS["theta"], ls=style,
                    label=SYSTEM_LABELS.get(base, base))
        if base in thresholds:
            bottom.plot([thresholds[base]], [0.0], "o", color="k", ms=4)
    for ax in (top, bottom):
        ax.axhline(0.0, color="0.7", lw=0.6, zorder=1)
        for x in (ours, theirs):
            ax.axvline(x, color=GUIDE_COLOR, lw=0.8, ls=":")
    for x, text, side in ((ours, " our $M_u^+$", "left"), (theirs, "CFD's $M_u^+$ ", "right")):
        bottom.text(x, 0.95, text, transform=bottom.get_xaxis_transform(), ha=side, va="top",
                    fontsize="small", color="0.35")
    top.set_ylabel("growth rate [1/s]")
    bottom.set_ylabel("angular frequency\n[rad/s]")
    bottom.set_xlabel(r"$M_u^+$ [–]")
    top.legend(loc="lower right", fontsize="small", frameon=False)
    per_wingbeat = top.secondary_yaxis("right", functions=(lambda r: r * period,
                                                          lambda g: g / period))
    per_wingbeat.set_ylabel("per wingbeat [–]")
    return fig

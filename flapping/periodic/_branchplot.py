"""Package-internal: the plot of :meth:`flapping.periodic.continuation.Branch.plot`.

matplotlib is imported here, when a plot is asked for, never at import time.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

__all__ = ["plot_branch"]

#: Marker of each bifurcation kind.
MARKERS = {"fold": "s", "period-doubling": "o", "neimark-sacker": "D"}


def _runs(stable: np.ndarray) -> list[tuple[int, int, bool]]:
    """Index ranges ``[i, j]`` of equal stability (adjacent ranges share their end point)."""
    runs, start = [], 0
    for k in range(1, stable.size + 1):
        if k == stable.size or stable[k] != stable[start]:
            runs.append((start, min(k, stable.size - 1), bool(stable[start])))
            start = k
    return runs


def plot_branch(branch: Any, measure: Callable[[np.ndarray], float] | None, axes: Any,
                label: str | None) -> Any:
    """Upper panel: the branch (stable solid, unstable dashed); lower: the moduli of mu."""
    import matplotlib.pyplot as plt

    if axes is None:
        _, axes = plt.subplots(2, 1, sharex=True, figsize=(6.4, 5.6))
    top, bottom = axes
    y = branch.period if measure is None else np.array([measure(x) for x in branch.x0])
    colour = None
    for i, j, stable in _runs(branch.stable):
        lines = top.plot(branch.p[i:j + 1], y[i:j + 1], "-" if stable else "--", color=colour,
                         label=label if colour is None else None)
        colour = lines[0].get_color()
    for b in branch.bifurcations:
        yb = b.period if measure is None else measure(b.x0)
        top.plot([b.p], [yb], MARKERS[b.kind], color="k", mfc="none")
    top.set_ylabel("period" if measure is None else "orbit measure")
    mods = np.abs(branch.multipliers)
    for k in range(mods.shape[1]):
        bottom.plot(branch.p, mods[:, k], ".", ms=2, color=colour)
    bottom.axhline(1.0, color="0.5", lw=0.8)
    bottom.set_yscale("log")
    bottom.set_xlabel("parameter p")
    bottom.set_ylabel("|multiplier|")
    return axes

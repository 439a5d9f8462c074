"""Smoke test of an installed flapping (run by .ci/run in a venv holding only the wheel).

``python smoke.py``: the core install works (import, a periodic orbit, its multipliers).
``python smoke.py --extra derive``: SymPy regenerates exactly the derivative code the wheel ships.
``python smoke.py --extra plot``: the book's plotting helpers draw with matplotlib.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import flapping


def core() -> None:
    from flapping.periodic.testproblems import lorenz, lorenz_jac

    assert "site-packages" in flapping.__file__, f"not the installed wheel: {flapping.__file__}"
    orbit = flapping.find_periodic_orbit(lorenz, [-13.76, -19.58, 27.0], 1.56, jac=lorenz_jac,
                                         fixed=[2])
    assert orbit.success and abs(orbit.period - 1.5586522) < 1e-6, orbit
    mon = flapping.monodromy(lorenz, orbit.x0, orbit.period, jac=lorenz_jac)
    assert np.isclose(abs(mon.multipliers).max(), 4.714, rtol=1e-3), mon.multipliers
    print(f"flapping {flapping.__version__}: Lorenz orbit T = {orbit.period:.7f}, "
          f"|mu| = {np.abs(mon.multipliers)}")


def derive() -> None:
    from flapping.model import derivation

    shipped = Path(flapping.__file__).parent / "model" / "_derivatives_generated.py"
    assert derivation.generate_source() == shipped.read_text(), "generated code differs"
    print("derive: SymPy regenerates the shipped derivative code exactly")


def plot() -> None:
    import matplotlib

    matplotlib.use("Agg")
    from flapping.book import plotting

    fig = plotting.plot_multipliers(np.array([1.29, 0.77, 0.65, 0.41]))
    print("plot: drew", type(fig).__name__)


if __name__ == "__main__":
    extra = sys.argv[2] if len(sys.argv) > 2 and sys.argv[1] == "--extra" else None
    {None: core, "derive": derive, "plot": plot}[extra]()

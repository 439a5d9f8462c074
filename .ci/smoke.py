"""Smoke test of an installed flapping (run by .ci/run in a venv holding only the wheel).

``python smoke.py``: the core install works (import, a periodic orbit, its multipliers).
``python smoke.py --extra derive``: SymPy regenerates exactly the derivative code the wheel ships.
``python smoke.py --extra plot``: a continuation branch draws itself with matplotlib.
``python smoke.py --extra fast``: the compiled kernel agrees with the adaptive path.
``python smoke.py --extra sweep``: a three-point sweep gives a pandas table.
``python smoke.py --extra distributed``: the same sweep on a dask LocalCluster gives the same table.
"""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path

import numpy as np

import flapping


def core() -> None:
    assert "site-packages" in flapping.__file__, f"not the installed wheel: {flapping.__file__}"
    assert "scipy.integrate" not in sys.modules, "import flapping loaded the solvers"
    assert importlib.util.find_spec("flapping_book") is None, "the book's helpers are installed"
    from flapping.periodic.testproblems import lorenz, lorenz_jac

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


def _hopf(t, x, p):
    """Hopf normal form: the circle r = sqrt(p), period 2 pi."""
    r2 = x[0] ** 2 + x[1] ** 2
    return np.array([p * x[0] - x[1] - x[0] * r2, x[0] + p * x[1] - x[1] * r2])


def plot() -> None:
    import matplotlib

    matplotlib.use("Agg")
    from flapping.periodic import continue_orbit

    branch = continue_orbit(_hopf, [math.sqrt(0.5), 0.0], 2 * math.pi, 0.5, 0.6)
    upper, lower = branch.plot()
    assert branch.success and len(upper.lines) > 0, branch.message
    print(f"plot: drew a branch of {len(branch.p)} orbits on", type(upper).__name__)


def fast() -> None:
    from flapping.fast import numba_available, solve_hover

    assert numba_available()
    kernel = solve_hover(flapping.hawkmoth())
    orbit = flapping.find_hover_orbit(flapping.hawkmoth(), backend="adaptive")
    assert abs(np.degrees(kernel.amplitude - orbit.amplitude)) < 1e-8, (kernel, orbit)
    print(f"fast: kernel Phi = {np.degrees(kernel.amplitude):.9f} deg, as the adaptive path")


def _table(executor=None):
    from flapping.studies.sweep import sweep_hover

    return sweep_hover(flapping.hawkmoth(), {"frequency": [25.0, 26.3, 27.0]},
                       executor=executor, progress=False)


def sweep() -> None:
    table = _table()
    assert len(table) == 3 and table["converged"].all(), table
    print("sweep:", len(table), "rows,", list(table.columns)[:6], "...")


def distributed() -> None:
    from dask.distributed import Client, LocalCluster

    with LocalCluster(n_workers=1, processes=False) as cluster, Client(cluster) as client:
        remote = _table(client.get_executor())
    local = _table()
    assert np.allclose(remote["amplitude_deg"], local["amplitude_deg"], rtol=0, atol=1e-12)
    print("distributed: the LocalCluster sweep equals the in-process one")


if __name__ == "__main__":
    extra = sys.argv[2] if len(sys.argv) > 2 and sys.argv[1] == "--extra" else None
    {None: core, "derive": derive, "plot": plot, "fast": fast, "sweep": sweep,
     "distributed": distributed}[extra]()

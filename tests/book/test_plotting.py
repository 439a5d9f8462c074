"""Plotting helpers: each runs headless and returns a figure or axes; matplotlib stays optional."""

import subprocess
import sys

import numpy as np
import pytest

from flapping_book import plotting, style

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.axes import Axes  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def test_importing_the_book_helpers_does_not_import_matplotlib():
    # matplotlib loads when a figure is drawn, not when the helpers are imported.
    code = ("import sys, flapping, flapping_book.plotting, flapping_book.schematic, "
            "flapping_book.style, flapping_book.tables; print('matplotlib' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_plot_states_overlays_on_given_axes():
    t = np.linspace(0.0, 0.076, 50)
    x = np.vstack([np.sin(t), np.cos(t), t, 0.1 * t])
    fig = plotting.plot_states(t, x, period=0.038, label="a")
    assert isinstance(fig, Figure) and len(fig.axes) == 4
    again = plotting.plot_states(t, x.T, axes=fig.axes, linestyle="--")
    assert again is fig
    # theta is drawn in degrees
    assert np.allclose(fig.axes[3].lines[0].get_ydata(), np.degrees(x[3]))
    with pytest.raises(ValueError, match="shape"):
        plotting.plot_states(t, x[:3])


def test_plot_loads_and_load_models():
    t = np.linspace(0.0, 0.038, 40)
    loads = np.vstack([np.sin(t), np.cos(t), t])
    assert isinstance(plotting.plot_loads(t, loads, period=0.038, model="exact"), Figure)
    fig = plotting.plot_load_models(t, {"small-angle": loads, "exact": 1.01 * loads},
                                    period=0.038)
    assert isinstance(fig, Figure)
    with pytest.raises(ValueError, match="model"):
        plotting.plot_load_models(t, {"viscous": loads})


def test_plot_derivatives_and_relative_difference():
    t = np.linspace(0.0, 0.038, 30)
    values = {name: np.sin(t + k) for k, name in enumerate(style.DERIVATIVE_LABELS)}
    fig = plotting.plot_derivatives(t, values, ["Xu", "Zw", "Mq", "M0"], period=0.038)
    assert isinstance(fig, Figure)
    assert sum(ax.get_visible() for ax in fig.axes) == 4
    other = {k: v + 1e-9 for k, v in values.items()}
    ax = plotting.plot_relative_difference(t, values, other, period=0.038)
    assert isinstance(ax, Axes) and len(ax.lines) == len(values)


def test_plot_multipliers_keeps_the_unit_circle_in_view():
    mu = np.array([0.59, 1.03, 0.987 + 0.01j, 0.987 - 0.01j])
    ax = plotting.plot_multipliers(mu, label="ours")
    assert isinstance(ax, Axes)
    lo, hi = ax.get_xlim()
    assert lo <= -1.0 and hi >= 1.03
    assert plotting.plot_multipliers(2.5, ax=ax, circle=False, marker="x") is ax
    assert ax.get_xlim()[1] >= 2.5


def test_orbit_projections_and_stroboscopic_figures():
    n = 64
    t = np.linspace(0.0, 3.0, 3 * n + 1)
    x = np.vstack([np.cos(2 * np.pi * t), 0.1 * np.ones_like(t), np.sin(2 * np.pi * t), 0.01 * t])
    fig = plotting.plot_orbit_projections(x[:, : n + 1])
    assert isinstance(fig, Figure) and len(fig.axes) == 2
    fig = plotting.plot_stroboscopic(t, x, period=1.0, reference=x)
    assert len(fig.axes) == 3
    # the samples x(kT): 4 whole periods in [0, 3]
    assert len(fig.axes[0].lines[-1].get_xdata()) == 4
    ax = plotting.plot_stroboscopic_map(t, x[0], period=1.0, label="x")
    assert isinstance(ax, Axes)
    with pytest.raises(ValueError):
        plotting.plot_orbit_projections(x[:, :n])


def test_plot_agreement_legend_below_the_panels_at_a_readable_size():
    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    from flapping_book.plotting import plot_agreement

    t = np.linspace(0.0, 1.0, 50)
    ref = {"Zw": np.sin(2 * np.pi * t), "Mq": np.cos(2 * np.pi * t)}
    fig = plot_agreement(t, ref, ref, shown=["Zw", "Mq"], names=["Zw", "Mq"], period=1.0)
    assert fig.axes[0].get_legend() is None            # not squeezed into the panel
    (legend,) = fig.legends
    assert len(legend.get_texts()) == 4
    size = legend.get_texts()[0].get_fontsize()
    assert size >= fig.axes[0].xaxis.label.get_fontsize()
    import matplotlib.pyplot as plt
    plt.close(fig)


def test_label_levels_separate_close_labels():
    import pytest

    from flapping_book.plotting import label_levels

    assert label_levels([0.0, 10.0, 20.0], 5.0) == [0, 0, 0]
    assert label_levels([0.0, 1.0, 2.0, 10.0], 5.0) == [0, 1, 2, 0]
    assert label_levels([2.0, 0.0, 1.0], 1.5) == [0, 0, 1]   # returned in the order given
    rows = label_levels([-25.0, -3.0, -1.0, 6.0], 8.0)
    assert rows[1] != rows[2] and rows[0] == 0
    with pytest.raises(ValueError):
        label_levels([0.0], 0.0)

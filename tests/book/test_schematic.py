"""The schematic of the model: one figure, three panels, drawn headless."""

import pytest

import flapping
from flapping_book import schematic

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402


@pytest.fixture(autouse=True)
def _close_figures():
    yield
    plt.close("all")


def test_draw_insect_model_returns_a_figure_with_three_panels():
    fig = schematic.draw_insect_model(flapping.hawkmoth())
    assert isinstance(fig, Figure)
    assert len(fig.axes) == 3
    titles = [ax.get_title(loc="left") for ax in fig.axes]
    assert [t[:3] for t in titles] == ["(a)", "(b)", "(c)"]


def test_draw_insect_model_accepts_an_explicit_pitch():
    fig = schematic.draw_insect_model(alpha_m=0.6, theta_deg=5.0, phi_deg=-20.0)
    assert isinstance(fig, Figure)

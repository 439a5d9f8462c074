"""Tables and the figure of the chapter "Real or oscillatory?" (flapping_book.modetype)."""

import math

import numpy as np
import pandas
import pytest

from flapping_book import modetype


def test_derivative_rows_print_a_zero_of_ours_without_a_ratio():
    theirs = {"Xu": -0.785, "Xw": 0.050}
    ours = {"Xu": -0.3003, "Xw": 1e-12}
    rows = modetype.derivative_rows(theirs, ours, {"Xw": "symmetry"})
    assert rows[0] == ["$X_u^+$", "-0.785", "-0.300", "0.38", ""]
    assert rows[1][2] == "0" and rows[1][3] == "–" and rows[1][4] == "symmetry"
    with pytest.raises(ValueError, match="same derivatives"):
        modetype.derivative_rows(theirs, {"Xu": 1.0}, {})


def test_mode_rows_list_a_pair_once_with_its_period_and_doubling_time():
    period = 6.4e-3
    lam = [complex(-29.0, 0.0), complex(6.93, 19.48), complex(6.93, -19.48), complex(-1.87, 0)]
    rows = modetype.mode_rows(lam, period)
    assert len(rows) == 3
    first = rows[0]
    assert first[0] == "6.93 ± 19.48i" and first[1] == "oscillation, unstable"
    assert float(first[2]) == pytest.approx(2e3 * math.pi / 19.48, abs=0.5)   # ms
    assert first[4].startswith(f"{math.log(2) / 6.93 * 1e3:.1f}") and "×2" in first[4]
    assert float(first[5]) == pytest.approx(math.log(2) / 6.93 / period, abs=0.05)
    assert rows[1][1] == "subsidence" and "×1/2" in rows[1][4] and rows[1][2] == "–"
    assert rows[2][0] == "-29.00"                      # fastest decay last
    with pytest.raises(ValueError, match="period"):
        modetype.mode_rows(lam, 0.0)


def _swaps():
    return pandas.DataFrame([
        {"direction": "ours <- theirs", "swapped": "none", "Mu": -0.18, "type": "real",
         "rate": 6.7, "period": math.inf, "doubling_time": 0.1035},
        {"direction": "ours <- theirs", "swapped": "Xu+Mu", "Mu": 2.389, "type": "oscillatory",
         "rate": 7.3, "period": 0.322, "doubling_time": 0.0948},
    ])


def test_swap_rows_name_the_terms_in_symbols_and_refuse_an_unknown_swap():
    rows = modetype.swap_rows(_swaps(), "ours <- theirs", ["none", "Xu+Mu"], 6.4e-3)
    assert rows[0][0] == "none" and rows[0][3] == "–"
    assert rows[1][0] == "$X_u^+$, $M_u^+$" and rows[1][3] == "322"
    assert rows[1][5] == f"{0.0948 / 6.4e-3:.1f}"
    with pytest.raises(ValueError, match="Mq"):
        modetype.swap_rows(_swaps(), "ours <- theirs", ["Mq"], 6.4e-3)


def test_case_labels_use_the_books_symbols():
    assert modetype.case_label("centre of pressure x_hat 0.1") == r"centre of pressure $\hat x$ = 0.1"
    assert modetype.case_label("hinge height x0.5") == "hinge height ×0.5"
    assert modetype.case_label("hinge 1 chord ahead") == "hinge 1 chord ahead"


def test_physics_rows_show_a_complex_multiplier_and_a_failed_case():
    table = pandas.DataFrame([
        {"case": "a", "Mu": 0.17, "Mq": -0.86, "averaged_type": "oscillatory",
         "floquet_type": "oscillatory", "leading_multiplier": complex(1.007, 0.0437),
         "stroke_mean_deg": -2.9e-12, "message": ""},
        {"case": "b", "message": "ConvergenceError: no orbit"},
    ])
    rows = modetype.physics_rows(table, 6.4e-3)
    assert rows[0][5] == "1.0070 ± 0.0437i" and rows[0][7] == "0.0"
    expected = math.log(2) / math.log(abs(complex(1.007, 0.0437)))
    assert rows[0][6] == f"{expected:.1f}"
    assert rows[1][3] == "no orbit" and "ConvergenceError" in rows[1][-1]


def test_the_hinge_height_figure_marks_the_neutral_and_matching_heights():
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    fig = modetype.plot_mu_against_hinge_height(
        [0.0, 2e-3, 8e-3], [-0.35, -0.2, 0.3], [False, False, True], intercept=-0.35,
        slope=75.0, theirs=2.389, body_length=18e-3, source_height=2.34e-3)
    ax = fig.axes[0]
    neutral = [ln for ln in ax.lines if ln.get_label() == "neutral height"][0]
    assert neutral.get_xdata()[0] == pytest.approx(0.35 / 75.0 / 18e-3)
    match = [ln for ln in ax.lines if ln.get_label() == "CFD's value reached"][0]
    assert match.get_xdata()[0] == pytest.approx((2.389 + 0.35) / 75.0 / 18e-3)
    assert "body lengths" in ax.get_xlabel()
    with pytest.raises(ValueError, match="slope"):
        modetype.plot_mu_against_hinge_height([0.0], [0.0], [False], intercept=0.0, slope=-1.0,
                                              theirs=1.0, body_length=1.0, source_height=0.0)
    matplotlib.pyplot.close(fig)
    assert np.isfinite(neutral.get_xdata()).all()


def test_the_sweep_figure_marks_each_threshold_on_the_zero_frequency_line():
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    mu = np.linspace(-0.2, 1.0, 13)
    sweep = pandas.DataFrame({"Mu": mu, "rate": 5 * np.abs(mu),
                              "frequency": np.where(mu > 0, 10 * mu, 0.0)})
    fig = modetype.plot_mu_sweep({"ours": sweep}, {"ours": 0.0}, ours=-0.18, theirs=2.4,
                                 period=6.4e-3)
    top, bottom = fig.axes[:2]
    marks = [ln for ln in bottom.lines if ln.get_marker() == "o"]
    assert len(marks) == 1 and marks[0].get_ydata()[0] == 0.0
    assert [ln.get_linestyle() for ln in top.lines if ln.get_marker() != "o"][0] == "-"
    with pytest.raises(ValueError, match="without a sweep"):
        modetype.plot_mu_sweep({"ours": sweep}, {"theirs": 0.0}, ours=0.0, theirs=1.0,
                               period=1.0)
    matplotlib.pyplot.close(fig)

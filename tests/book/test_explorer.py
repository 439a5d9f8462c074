"""The explorer's figure (flapping_book.explorer): its data are the tables', in grid order; the
figure shows the point it is started at; the HTML bundles plotly.js and needs no network."""

import json
import math
import re

import numpy as np
import pytest

pytest.importorskip("numba")
pandas = pytest.importorskip("pandas")
pytest.importorskip("plotly")
from flapping.studies.explorer import ExplorerGrid, explore_hover  # noqa: E402
from flapping_book import explorer  # noqa: E402
from flapping_book.style import STATE_COLORS, STATE_NAMES  # noqa: E402

#: Two species, a frequency that cannot trim and one that can, two heights, two wing masses.
GRID = ExplorerGrid(species=("hawkmoth", "fruit_fly"), frequency_ratio=(0.5, 1.0),
                    hinge_height_ratio=(0.0, 0.2), wing_mass_percent=(0.0, 6.0))
N_SAMPLES = 16


@pytest.fixture(scope="module")
def explored():
    return explore_hover(GRID, n_samples=N_SAMPLES)


@pytest.fixture(scope="module")
def data(explored):
    return explorer.explorer_data(explored.points, explored.orbits, explored.n_samples)


def test_one_record_per_point_with_the_tables_numbers(explored, data):
    points = explored.points
    assert data["shape"] == [2, 2, 2, 2] and len(data["points"]) == len(points)
    assert data["axes"]["species"] == ["hawkmoth", "fruit_fly"]
    np.testing.assert_allclose(data["phase"], np.linspace(0, 1, N_SAMPLES + 1))
    for i, (row, rec) in enumerate(zip(points.to_dict("records"), data["points"], strict=True)):
        assert rec["ok"] == row["converged"]
        assert rec["text"] == explorer.readout(row)
        if not rec["ok"]:
            assert set(rec) == {"ok", "text"}
            continue
        np.testing.assert_allclose(rec["mu_re"], [row[f"mu{k}_real"] for k in range(1, 5)],
                                   rtol=1e-5)
        np.testing.assert_allclose(rec["mode"], [row[f"mode_{s}_abs"] for s in STATE_NAMES],
                                   rtol=1e-5, atol=1e-12)
        orbits = explored.orbits
        theta = orbits[(orbits.point == i) & (orbits.state == "theta")].value.to_numpy()
        np.testing.assert_allclose(rec["orbit"][3], np.degrees(theta), rtol=1e-5, atol=1e-9)


def test_data_refuse_a_table_out_of_grid_order(explored):
    order = [1, 0, *range(2, len(explored.points))]  # two neighbours swapped
    shuffled = explored.points.iloc[order].reset_index(drop=True)
    with pytest.raises(ValueError, match="grid order"):
        explorer.explorer_data(shuffled, explored.orbits, N_SAMPLES)
    with pytest.raises(ValueError, match="full grid"):
        explorer.explorer_data(explored.points.iloc[1:], explored.orbits, N_SAMPLES)
    with pytest.raises(ValueError, match="samples"):
        explorer.explorer_data(explored.points, explored.orbits, 2 * N_SAMPLES)


def test_point_index_is_the_tables_row(explored, data):
    points, axes = explored.points, data["axes"]
    for i, row in enumerate(points.to_dict("records")):
        idx = [axes[name].index(row[name]) for name in
               ("species", "frequency_ratio", "wing_mass_percent", "hinge_height_ratio")]
        assert explorer.point_index(tuple(data["shape"]), *idx) == i
    with pytest.raises(ValueError, match="hinge_height"):
        explorer.point_index((2, 2, 2, 2), 0, 0, 0, 2)


def test_readout_says_what_the_reader_sees(explored):
    points = explored.points
    ok = points[points.converged].iloc[0]
    text = explorer.readout(ok)
    assert f"|μ₁| = {ok.max_abs_mu:.4f}" in text and f"{ok.mode_type} mode" in text
    assert f"doubles in {math.log(2) / math.log(ok.max_abs_mu):.1f} wingbeats" in text
    failed = points[~points.converged].iloc[0]
    bad = explorer.readout(failed)
    assert "no hover orbit (" in bad and "exceeds the largest mean lift" in bad
    assert "ValueError" not in bad and len(bad) < len(explorer.readout(ok)) + 160
    stable = dict(ok, stable=True, mu1_real=0.9, doubling_wingbeats=math.inf)
    assert "stable: every |μ| < 1" in explorer.readout(stable)


def test_figure_starts_at_the_point_asked_for(data):
    start = {"species": "fruit_fly", "frequency_ratio": 1.0, "hinge_height_ratio": 0.2,
             "wing_mass_percent": 6.0}
    fig = explorer.explorer_figure(data, start)
    rec = data["points"][explorer.point_index((2, 2, 2, 2), 1, 1, 1, 1)]
    assert rec["ok"]
    for k, s in enumerate(STATE_NAMES):
        trace = fig.data[k]
        assert trace.name == s and trace.line.color == STATE_COLORS[s]
        np.testing.assert_array_equal(trace.y, rec["orbit"][k])
    np.testing.assert_array_equal(fig.data[4].x, rec["mu_re"])
    np.testing.assert_array_equal(fig.data[5].y, rec["mode"])
    assert list(fig.data[5].text) == [f"{p:.0f}" for p in rec["phase_deg"]]
    assert {abs(p) for p in rec["phase_deg"]} <= {0.0, 180.0} or rec["mu_im"][0] != 0.0
    names = [s.name for s in fig.layout.sliders]
    assert names == [a[0] for a in explorer.SLIDER_AXES]
    for slider in fig.layout.sliders:
        values = data["axes"][slider.name]
        assert slider.active == values.index(start[slider.name])
        assert [st.method for st in slider.steps] == ["skip"] * len(values)
    menu = fig.layout.updatemenus[0]
    assert menu.active == 1 and [b.label for b in menu.buttons] == ["hawkmoth", "fruit fly"]
    assert list(fig.layout.meta["axes"]) == ["species", "frequency_ratio", "wing_mass_percent",
                                             "hinge_height_ratio"]
    with pytest.raises(ValueError, match="start"):
        explorer.explorer_figure(data, {"frequency_ratio": 0.7})


def test_failed_point_shows_empty_traces(data):
    fig = explorer.explorer_figure(data, {"frequency_ratio": 0.5})
    assert all(len(trace.y) == 0 for trace in fig.data[:6])


def test_html_bundles_plotly_and_needs_no_network(data):
    html = explorer.explorer_html(data, {"frequency_ratio": 1.0}, div_id="ex1")
    assert 'id="ex1"' in html and 'id="ex1-readout"' in html
    scripts = re.findall(r"<script[^>]*\bsrc=", html)
    assert scripts == []  # nothing fetched: plotly.js is inline
    assert "<link" not in html and "@import" not in html  # no style sheet fetched either
    # (plotly.js names a CDN only as its default topojsonURL, for geo maps: not fetched here;
    # tests/book/test_explorer_page.py checks in Chromium that no request leaves the page.)
    assert len(html) > 3e6  # plotly.js itself (~4.7 MB minified) is in the page
    payload = re.search(r'<script type="application/json" id="ex1-data">(.*?)</script>', html,
                        re.S).group(1)
    assert json.loads(payload) == json.loads(json.dumps(data))
    first = data["points"][explorer.point_index((2, 2, 2, 2), 0, 1, 0, 0)]["text"]
    assert f'id="ex1-readout" class="explorer-readout" aria-live="polite">{first}<' in html
    with pytest.raises(ValueError, match="div_id"):
        explorer.explorer_html(data, div_id="a b")


def test_html_data_cannot_close_its_script(data):
    evil = json.loads(json.dumps(data))
    evil["points"][0]["text"] = "</script><script>alert(1)</script>"
    html = explorer.explorer_html(evil, div_id="ex2")
    payload = re.search(r'id="ex2-data">(.*?)</script>', html, re.S).group(1)
    assert json.loads(payload)["points"][0]["text"] == evil["points"][0]["text"]

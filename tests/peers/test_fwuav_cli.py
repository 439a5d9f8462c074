"""``python -m flapping fwuav``: JSON report, no NaN, one-line errors with exit status 2."""

from __future__ import annotations

import json
import math

import pytest

from flapping.cli import main


def test_the_json_report_compares_with_fwuav(capsys):
    assert main(["fwuav", "--insect", "fruit_fly", "--json"]) == 0
    out = capsys.readouterr().out
    report = json.loads(out, parse_constant=lambda c: pytest.fail(f"{c} in the JSON"))
    assert report["name"] == "fruit_fly"
    assert math.isclose(report["frequency_hz"] * report["period_s"], 1.0)
    assert len(report["exponents"]) == 6
    assert report["fwuav_longitudinal"] == pytest.approx([-3.9368558007, -7.0358838946])
    ours = [e["re"] for e in report["longitudinal"]]
    diff = [abs(a - b) / abs(b) for a, b in zip(ours, report["fwuav_longitudinal"], strict=True)]
    assert report["relative_difference"]["longitudinal"] == pytest.approx(diff)
    assert max(diff) < 0.02
    assert report["residual_norm"] < 1e-10
    assert "1a25d41" in report["provenance"]


def test_the_text_report_has_a_row_per_exponent(capsys):
    assert main(["fwuav", "--insect", "fruit_fly"]) == 0
    out = capsys.readouterr().out
    assert "longitudinal 1" in out and "lateral" in out and "FWUAV" in out


def test_an_unknown_insect_exits_2_with_one_line(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["fwuav", "--insect", "locust"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "locust" in err

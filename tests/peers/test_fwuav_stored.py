"""The versioned pitch-free results the chapter "A second model" loads
(book/data/fwuav_pitch_free.json, written by ``python -m flapping.peers.fwuav.stored``): the
cases are the ones the module lists, the file reads back exactly, and recomputed entries agree
with it to the study's accuracy."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from flapping.peers.fwuav import stored

FILE = Path(__file__).resolve().parents[2] / "book" / "data" / "fwuav_pitch_free.json"


def test_the_file_holds_the_listed_cases_and_reads_back_exactly() -> None:
    results = stored.load(FILE)
    assert list(results) == list(stored.CASES)
    raw = json.loads(FILE.read_text())["cases"]
    for key, result in results.items():
        assert stored.to_json(result) == raw[key]["result"]  # every float exact
        assert result.trim_parameters == (("phi_m", "phi_0") if stored.CASES[key]["trim"]
                                          else ())
        # the chapter's checks on what it loads: a complex leading pair outside the unit circle
        assert abs(result.multipliers[0]) > 1 and abs(result.multipliers[0].imag) > 0.05


def test_a_file_with_other_cases_is_refused(tmp_path: Path) -> None:
    data = json.loads(FILE.read_text())
    data["cases"]["free fwuav"]["arguments"]["rtol"] = 1e-7
    stale = tmp_path / "stale.json"
    stale.write_text(json.dumps(data))
    with pytest.raises(ValueError, match="CASES"):
        stored.load(stale)


@pytest.mark.slow  # recomputes two pitch-free hovers: about a minute on two shared cores
@pytest.mark.parametrize("key", ["free fwuav", "trimmed fwuav"])
def test_recomputed_entries_agree_with_the_file(key: str) -> None:
    saved = stored.load(FILE)[key]
    fresh = stored.compute(key)
    # the shooting closes to min(1000 rtol, 1e-6) = 1e-6 at rtol 1e-8: the orbit's start, the
    # trim and the multipliers agree to that order (1e-6 relative); on this machine, exactly
    np.testing.assert_allclose(fresh.y0, saved.y0, rtol=0, atol=1e-6)
    np.testing.assert_allclose(fresh.trim_values, saved.trim_values, rtol=0, atol=1e-6)
    np.testing.assert_allclose(fresh.multipliers, saved.multipliers, rtol=1e-6)
    np.testing.assert_allclose(fresh.mean_velocity, saved.mean_velocity, rtol=0, atol=1e-6)

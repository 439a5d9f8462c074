"""The stored studies (flapping_book.stored, book/_data/): a file reads back as what was
saved, a loaded sensitivity study equals a computed one, and sampled points solved again today
agree with the versioned files (to the solves' own accuracy), so a change that moves the book's
stored numbers fails here until `python scripts/book_data.py` writes them again."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
from pandas.testing import assert_frame_equal

from flapping.errors import PlausibilityWarning
from flapping.model.presets import preset
from flapping.studies import control
from flapping.studies import sensitivity as gs
from flapping.studies.explorer import DEFAULT_GRID, ExplorerGrid, explore_hover
from flapping.studies.sweep import sweep_hover
from flapping_book import stored

DATA = Path(__file__).resolve().parents[2] / "book" / "_data"
EXPLORER = DATA / "explorer.npz"
SENSITIVITY = DATA / "global_sensitivity.npz"
REDUCTION = DATA / "reduction_check.npz"
WINDOWS = DATA / "passive_windows.npz"
#: The explorer's and the reduction check's points: Newton on the fixed-step map with Richardson
#: estimates below 1e-10 relative (FixedStep's default); the orbit samples at rtol 1e-8
#: (explorer.SAMPLE_RTOL).
POINT_RTOL, SAMPLE_RTOL = 1e-8, 1e-6
#: The sensitivity sweep warm-starts each point from its neighbour; solved alone and cold a
#: point lands on the same orbit within the compiled kernel's Newton tolerance.
MU_RTOL = 1e-7
#: A small sample for the round trips (9 x 32 compiled orbits, about a second).
N_SMALL = 32
FLOATS = ["amplitude_deg", "alpha_m_deg", "mu1_real", "mu1_imag", "mu2_real", "mu2_imag",
          "max_abs_mu", "mode_u_abs", "mode_w_abs", "mode_q_abs", "mode_theta_abs"]


def test_an_exploration_reads_back_bit_for_bit(tmp_path):
    grid = ExplorerGrid(species=("hawkmoth", "monarch"), frequency_ratio=(1.0,),
                        hinge_height_ratio=(0.0, 0.3), wing_mass_percent=(3.0,))
    exploration = explore_hover(grid, n_samples=8)
    path = stored.save_exploration(exploration, tmp_path / "e.npz", wall_time_s=1.5)
    again, meta = stored.load_exploration(path)
    assert_frame_equal(again.points, exploration.points, check_exact=True)
    assert_frame_equal(again.orbits, exploration.orbits, check_exact=True)
    assert (again.grid, again.n_samples, meta["wall_time_s"]) == (grid, 8, 1.5)


def test_a_loaded_sensitivity_study_equals_the_computed_one(tmp_path):
    study = gs.global_sensitivity("hawkmoth", N_SMALL, seed=3, num_resamples=20)
    path = stored.save_global_sensitivity({"hawkmoth": study}, tmp_path / "g.npz",
                                          n_base=N_SMALL, seed=3, num_resamples=20)
    again = stored.load_global_sensitivity(path)[0]["hawkmoth"]
    assert_frame_equal(again.samples, study.samples, check_exact=True)
    assert_frame_equal(again.table(), study.table(), check_exact=True)
    for name in ("first", "first_conf", "total", "total_conf"):
        assert np.array_equal(getattr(again.indices, name), getattr(study.indices, name),
                              equal_nan=True)
    for name in ("ranges", "p_unstable", "p_oscillatory", "p_real", "p_unstable_ci",
                 "p_oscillatory_ci", "n_orbits", "n_failed", "n_retried", "wall_time_s"):
        assert getattr(again, name) == getattr(study, name), name


def test_a_stored_study_of_another_sample_size_is_refused(tmp_path):
    study = gs.global_sensitivity("hawkmoth", N_SMALL, seed=0, num_resamples=20)
    path = stored.save_global_sensitivity({"hawkmoth": study}, tmp_path / "g.npz",
                                          n_base=2 * N_SMALL, seed=0, num_resamples=20)
    with pytest.raises(ValueError, match="288 stored points, the sample of n_base = 64 has 576"):
        stored.load_global_sensitivity(path)


def _sampled(n: int, size: int) -> list[int]:
    return sorted({int(i) for i in np.linspace(0, size - 1, n)})


def test_the_stored_explorer_grid_is_todays():
    exploration, meta = stored.load_exploration(EXPLORER)
    points = exploration.points
    assert exploration.grid == DEFAULT_GRID and len(points) == DEFAULT_GRID.size
    failed = points.index[~points.converged].tolist()
    for i in _sampled(4, len(points)) + failed[:1]:
        row = points.iloc[i]
        one = ExplorerGrid(species=(row.species,), frequency_ratio=(row.frequency_ratio,),
                           hinge_height_ratio=(row.hinge_height_ratio,),
                           wing_mass_percent=(row.wing_mass_percent,))
        today = explore_hover(one, n_samples=exploration.n_samples)
        new = today.points.iloc[0]
        assert new.converged == row.converged, (i, new.message, row.message)
        if not row.converged:
            assert new.message.split(":")[0] == row.message.split(":")[0]
            continue
        assert new.mode_type == row.mode_type and new.stable == row.stable
        np.testing.assert_allclose(new[FLOATS].to_numpy(float), row[FLOATS].to_numpy(float),
                                   rtol=POINT_RTOL, atol=POINT_RTOL, err_msg=f"point {i}")
        mine = exploration.orbits[exploration.orbits.point == i]["value"].to_numpy()
        np.testing.assert_allclose(today.orbits["value"].to_numpy(), mine, rtol=SAMPLE_RTOL,
                                   atol=SAMPLE_RTOL * np.abs(mine).max(), err_msg=f"point {i}")


def test_the_stored_sensitivity_sample_is_todays():
    studies, meta = stored.load_global_sensitivity(SENSITIVITY)
    assert meta["n_base"] == 256 and meta["seed"] == 0
    for species, study in studies.items():
        samples = study.samples
        picks = _sampled(3, len(samples))
        picks += samples.index[samples.retried].tolist()[:1]       # solved again alone
        picks += samples.index[~samples.converged].tolist()[:1]    # no orbit (eq. 40)
        for i in picks:
            point = dict(samples.loc[i, list(gs.INPUTS)])
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", PlausibilityWarning)
                insect = gs._insect(species, point, full_model=False)
            backend = "auto" if samples.at[i, "retried"] else "compiled"
            today = sweep_hover([insect], backend=backend, progress=False).iloc[0]
            if not today.converged and samples.at[i, "retried"]:
                today = sweep_hover([insect], backend="adaptive", progress=False).iloc[0]
            assert bool(today.converged) == bool(samples.at[i, "converged"]), (species, i)
            if not today.converged:
                assert today.message.split(":")[0] == samples.at[i, "message"].split(":")[0]
                continue
            mu = complex(today.mu1_real, today.mu1_imag)
            stored_mu = complex(samples.at[i, "mu1_real"], samples.at[i, "mu1_imag"])
            assert abs(mu - stored_mu) <= MU_RTOL * abs(stored_mu), (species, i, mu, stored_mu)


def test_a_reduction_check_reads_back_bit_for_bit(tmp_path):
    checks = {"fruit_fly": gs.reduction_check("fruit_fly", 1, seed=5)}
    terms = {"fruit_fly": {"reduced": 1.25 + 0.5j, "full": 1.5 + 0j}}
    path = stored.save_reduction_checks(checks, terms, tmp_path / "r.npz", n_points=1, seed=5)
    again, again_terms, meta = stored.load_reduction_checks(path)
    assert_frame_equal(again["fruit_fly"].table, checks["fruit_fly"].table, check_exact=True)
    assert again_terms == terms and (meta["n_points"], meta["seed"]) == (1, 5)


def test_the_stored_reduction_check_is_todays():
    checks, terms, meta = stored.load_reduction_checks(REDUCTION)
    assert (meta["n_points"], meta["seed"]) == (2, 0)
    for species in ("hawkmoth", "hoverfly"):
        # The first point of a seeded check is the same whatever the number of points.
        new = gs.reduction_check(species, 1, seed=0).table.iloc[0]
        old = checks[species].table.iloc[0]
        inputs = list(gs.FULL_MODEL_INPUTS)
        assert new[inputs].to_numpy(float).tolist() == old[inputs].to_numpy(float).tolist()
        assert new.message.split(":")[0] == old.message.split(":")[0]
        for key in ("mu_reduced", "mu_full"):
            np.testing.assert_allclose(new[key], old[key], rtol=POINT_RTOL, err_msg=species)
    today = gs.nominal_reduction("hawkmoth")
    assert list(today) == list(terms["hawkmoth"])
    np.testing.assert_allclose(list(today.values()), list(terms["hawkmoth"].values()),
                               rtol=POINT_RTOL)


def test_the_stored_stable_windows_are_todays():
    windows, meta = stored.load_windows(WINDOWS)
    assert list(windows) == ["hawkmoth", "bumblebee", "fruit_fly", "honeybee", "hoverfly"]
    species = min(meta["wall_time_s"], key=meta["wall_time_s"].get)  # the quickest to redo
    sweep = control.passive_sweep(preset(species),
                                  np.linspace(0.0, control.BODY_LENGTHS[species], 25))
    today = control.stable_window(sweep, check=True)
    assert today is not None
    for new, old in zip(today, windows[species], strict=True):
        assert (new.kind, new.stabilising) == (old.kind, old.stabilising)
        # brentq's xtol is 1e-10 m on both routes
        assert abs(new.hinge_height - old.hinge_height) <= 1e-9
        assert abs(new.check_height - old.check_height) <= 1e-9
        np.testing.assert_allclose(new.multipliers, old.multipliers, rtol=1e-6, atol=1e-9)


def test_stable_windows_read_back_bit_for_bit(tmp_path):
    mu = np.array([0.99 + 0.1j, 0.5 + 0j])
    pair = (control.PassiveCrossing(0.001, "+1", mu, True, 0.0010000001),
            control.PassiveCrossing(0.004, "none", mu * 0.5, False, 0.004))
    path = stored.save_windows({"hoverfly": pair}, tmp_path / "w.npz", wall_time_s={})
    again = stored.load_windows(path)[0]["hoverfly"]
    for new, old in zip(again, pair, strict=True):
        assert (new.hinge_height, new.kind, new.stabilising, new.check_height) == (
            old.hinge_height, old.kind, old.stabilising, old.check_height)
        assert np.array_equal(new.multipliers, old.multipliers)


def test_a_text_column_with_a_missing_value_is_refused(tmp_path):
    study = gs.global_sensitivity("hawkmoth", N_SMALL, seed=0, num_resamples=20)
    study.samples.loc[0, "message"] = None
    with pytest.raises(ValueError, match="column 'message': text with a missing value"):
        stored.save_global_sensitivity({"hawkmoth": study}, tmp_path / "g.npz", n_base=N_SMALL,
                                       seed=0, num_resamples=20)

"""Tests of flapping.studies.sensitivity: Sobol indices (Ishigami's function, known in closed
form), the input ranges, the body-angle rotation, and the global hover study at small N."""

from __future__ import annotations

import math

import numpy as np
import pytest

from flapping.model.morphology import beta_shape_parameters
from flapping.model.presets import PRESETS, ellington_r1
from flapping.studies import sensitivity as sens

pytest.importorskip("SALib")

A, B = 7.0, 0.1
PI_BOUNDS = {f"x{i}": (-math.pi, math.pi) for i in (1, 2, 3)}


def ishigami(x: np.ndarray) -> np.ndarray:
    """Ishigami & Homma (1990): sin x1 + a sin^2 x2 + b x3^4 sin x1, x_i uniform on [-pi, pi]."""
    return np.sin(x[:, 0]) + A * np.sin(x[:, 1]) ** 2 + B * x[:, 2] ** 4 * np.sin(x[:, 0])


def ishigami_exact() -> tuple[np.ndarray, np.ndarray]:
    """The closed-form first-order and total indices (Sobol & Levitan 1999)."""
    v1 = 0.5 * (1 + B * math.pi**4 / 5) ** 2
    v2 = A**2 / 8
    v13 = B**2 * math.pi**8 * (1 / 18 - 1 / 50)
    v = v1 + v2 + v13
    return np.array([v1, v2, 0.0]) / v, np.array([v1 + v13, v2, v13]) / v


# Monte Carlo error of Saltelli's estimators at N = 2048 base samples: a few 1/sqrt(N) ~ 0.022
# times the output's scale; 0.05 is ~2-3 standard errors, and the exact S_3 = 0 against
# S_T3 = 0.24 is far outside it.
TOL = 0.05


def test_ishigami_indices_match_the_closed_form() -> None:
    result = sens.sobol_indices(PI_BOUNDS, ishigami, 2048, seed=3)
    first, total = ishigami_exact()
    np.testing.assert_allclose(result.first, first, atol=TOL)
    np.testing.assert_allclose(result.total, total, atol=TOL)
    assert result.n_used == result.n_base == 2048 and result.n_failed == 0
    # the bootstrap interval is a real interval, narrower than the spread of the indices
    assert np.all(result.first_conf > 0) and np.all(result.total_conf < 0.1)
    table = result.table()
    assert list(table["input"]) == ["x1", "x2", "x3"]  # by total index: 0.56, 0.44, 0.24


def test_failed_points_are_counted_and_their_blocks_left_out() -> None:
    rng = np.random.default_rng(0)

    def flaky(x: np.ndarray) -> np.ndarray:
        y = ishigami(x)
        y[rng.random(y.size) < 0.01] = np.nan
        return y

    result = sens.sobol_indices(PI_BOUNDS, flaky, 1024, seed=1)
    assert result.n_failed > 0
    assert result.n_used < 1024
    # each failed point spoils at most its own block of D + 2 = 5
    assert result.n_used >= 1024 - result.n_failed
    first, total = ishigami_exact()
    np.testing.assert_allclose(result.total, total, atol=2 * TOL)


@pytest.mark.parametrize("seed", [0, 5])
def test_sobol_indices_reproducible_with_a_seed(seed: int) -> None:
    a = sens.sobol_indices(PI_BOUNDS, ishigami, 64, seed=seed)
    b = sens.sobol_indices(PI_BOUNDS, ishigami, 64, seed=seed)
    c = sens.sobol_indices(PI_BOUNDS, ishigami, 64, seed=seed + 1)
    np.testing.assert_array_equal(a.total, b.total)
    # the bootstrap intervals too (SALib leaves its bootstrap unseeded for seed 0)
    np.testing.assert_array_equal(a.first_conf, b.first_conf)
    np.testing.assert_array_equal(a.total_conf, b.total_conf)
    assert not np.array_equal(a.total, c.total)


@pytest.mark.parametrize("bounds", [
    {"x": (1.0, 1.0)}, {"x": (2.0, 1.0)}, {"x": (0.0, math.inf)}, {"x": (0.0,)}, {},
    {"x": (0.0, math.nan)},
])
def test_invalid_ranges_refused(bounds: dict) -> None:
    with pytest.raises(ValueError, match="bounds"):
        sens.sobol_indices(bounds, ishigami, 8)


@pytest.mark.parametrize("n_base", [0, 1, 3, 100, 2**21])
def test_n_base_must_be_a_power_of_two_in_range(n_base: int) -> None:
    with pytest.raises(ValueError, match="n_base"):
        sens.sobol_indices(PI_BOUNDS, ishigami, n_base)


def test_wrong_output_shape_refused() -> None:
    with pytest.raises(ValueError, match="function"):
        sens.sobol_indices(PI_BOUNDS, lambda x: np.zeros((x.shape[0], 2)), 8)


def test_input_range_refuses_an_empty_range() -> None:
    with pytest.raises(ValueError, match="hinge_height"):
        sens.InputRange("hinge_height", "h_w", 1e-3, 1e-3, 1e-3, "m", "estimate", "")


def test_unknown_species_refused() -> None:
    with pytest.raises(ValueError, match="species"):
        sens.input_ranges("dragonfly")
    with pytest.raises(ValueError, match="species"):
        sens.global_sensitivity("dragonfly", 8)


@pytest.mark.parametrize("species", list(PRESETS))
def test_ranges_contain_the_preset_and_estimates_are_wider(species: str) -> None:
    ranges = {r.name: r for r in sens.input_ranges(species, full_model=True)}
    assert tuple(ranges) == sens.FULL_MODEL_INPUTS
    for r in ranges.values():
        assert r.low <= r.nominal <= r.high, r.name
    hinge = ranges["hinge_height"]
    status = PRESETS[species].measured["hinge_height"].status
    distance = math.hypot(ranges["hinge_offset"].nominal, hinge.nominal)
    assert (hinge.high - hinge.low) / distance == pytest.approx(
        2 * sens.HINGE_HALF_WIDTH[status])
    # both ends of r2 give a planform the model admits (beta shapes > 3/4)
    r1_estimated = PRESETS[species].values["r1"].status == "estimate"
    for r2 in (ranges["r2"].low, ranges["r2"].high):
        r1 = ellington_r1(r2) if r1_estimated else PRESETS[species].values["r1"].value
        assert min(beta_shape_parameters(r1, r2)) > 0.75


def test_estimated_numbers_get_wider_ranges_than_verified_ones() -> None:
    widths = sens.RELATIVE_HALF_WIDTH
    order = ["verified", "paper", "second-hand", "unverified", "estimate"]
    assert [widths[s] for s in order] == sorted(widths[s] for s in order)
    moth = {r.name: r for r in sens.input_ranges("hawkmoth")}   # verified f, the paper's I_y
    bee = {r.name: r for r in sens.input_ranges("honeybee")}    # an estimated I_y
    assert (moth["pitch_inertia"].high / moth["pitch_inertia"].low
            < bee["pitch_inertia"].high / bee["pitch_inertia"].low)


def test_body_angle_rotates_the_hinge_vector() -> None:
    x, h = sens.stroke_plane_hinge(3e-3, 4e-3, 0.3)
    assert math.hypot(x, h) == pytest.approx(5e-3, rel=1e-14)  # a rotation keeps the distance
    up, _ = sens.stroke_plane_hinge(0.0, 2e-3, 0.2)
    assert up < 0.0                                  # nose up: a hinge above the CG moves back
    _, rises = sens.stroke_plane_hinge(2e-3, 0.0, 0.2)
    assert rises > 0.0                               # nose up: a hinge ahead of the CG rises
    assert sens.stroke_plane_hinge(3e-3, 4e-3, 0.0) == (3e-3, 4e-3)


@pytest.fixture(scope="module")
def hoverfly_small() -> sens.GlobalSensitivity:
    return sens.global_sensitivity("hoverfly", 8, seed=2, num_resamples=50)


def test_global_study_probabilities_and_counts(hoverfly_small: sens.GlobalSensitivity) -> None:
    g = hoverfly_small
    d = len(sens.INPUTS)
    assert g.n_orbits == 8 * (d + 2) == len(g.samples)
    assert g.n_failed == int((~g.samples["converged"]).sum())
    for p in (g.p_unstable, g.p_oscillatory, g.p_real):
        assert 0.0 <= p <= 1.0
    assert g.p_oscillatory + g.p_real == pytest.approx(g.p_unstable)
    assert g.p_unstable_ci[0] <= g.p_unstable <= g.p_unstable_ci[1]
    ok = g.samples[g.samples["converged"]]
    assert g.p_unstable == pytest.approx(float(np.mean(ok["abs_mu1"] > 1.0)))
    # a failed point has a message; a converged one a mode
    assert (g.samples.loc[~g.samples["converged"], "message"] != "").all()
    assert set(ok["mode"]) <= {"real", "oscillatory", "flip"}
    assert list(g.table()["input"]) == list(g.indices.table()["input"])


def test_global_study_reproducible_with_a_seed(hoverfly_small: sens.GlobalSensitivity) -> None:
    again = sens.global_sensitivity("hoverfly", 8, seed=2, num_resamples=50)
    np.testing.assert_array_equal(again.samples["abs_mu1"], hoverfly_small.samples["abs_mu1"])
    np.testing.assert_array_equal(again.indices.total, hoverfly_small.indices.total)


def test_reduced_model_is_the_kernels_hinge_height(hoverfly_small: sens.GlobalSensitivity
                                                    ) -> None:
    s = hoverfly_small.samples
    expected = [sens.stroke_plane_hinge(x, h, a)[1]
                for x, h, a in zip(s["hinge_offset"], s["hinge_height"], s["body_angle"],
                                   strict=True)]
    np.testing.assert_allclose(s["h_stroke"], expected, rtol=1e-15)


def test_reduction_check_solves_both_models() -> None:
    check = sens.reduction_check("hawkmoth", 1, seed=0)
    row = check.table.iloc[0]
    assert row["message"] == ""
    assert np.isfinite(row["mu_full"]) and np.isfinite(row["mu_reduced"])
    # the full model trims the mean stroke angle to move the lift over the CG: the hinge is
    # ahead of it (x' > 0), so the stroke's mean moves back (phi_bar < 0)
    assert row["x_stroke"] > 0 and row["stroke_mean_deg"] < 0
    assert len(check.solved) == 1

"""sweep_hover(..., dof=6): the lateral columns of every point (flapping.studies.sweep)."""

import numpy as np
import pytest

import flapping
from flapping.studies.sweep import COLUMNS, LATERAL_COLUMNS

pytest.importorskip("pandas")
pytest.importorskip("tqdm")


@pytest.fixture(scope="module")
def moth():
    return flapping.hawkmoth()


def test_a_six_dof_sweep_adds_the_lateral_columns(moth):
    table = flapping.sweep_hover(moth, {"frequency": [24.0, 26.0]}, dof=6, progress=False)
    assert list(table.columns) == ["frequency", *COLUMNS, *LATERAL_COLUMNS]
    assert table["converged"].all() and (table["sixdof_backend"] == "compiled").all()
    for _, row in table.iterrows():
        insect = moth.with_(frequency=row["frequency"])
        direct = flapping.hover_stability(
            flapping.find_hover_orbit(insect, dof=6, aerodynamics="linear"))
        lateral = row[[f"lat_mu{i}_{part}" for i in range(1, 5) for part in ("real", "imag")]]
        expected = np.column_stack([direct.lateral.multipliers.real,
                                    direct.lateral.multipliers.imag]).ravel()
        np.testing.assert_allclose(lateral.to_numpy(dtype=float), expected, rtol=0, atol=1e-8)
        assert row["lat_stable"] == bool(np.all(np.abs(direct.lateral.multipliers) < 1.0))
        assert row["coupling"] < 1e-8 and row["sixdof_multiplier_error"] < 1e-8
        # The planar columns keep their meaning: the longitudinal multipliers.
        mu1 = complex(row["mu1_real"], row["mu1_imag"])
        assert abs(mu1 - direct.longitudinal.multipliers[0]) < 1e-8


def test_a_planar_sweep_keeps_its_columns(moth):
    table = flapping.sweep_hover(moth, {"frequency": [26.0]}, progress=False)
    assert list(table.columns) == ["frequency", *COLUMNS]


def test_a_point_without_lateral_inertia_is_a_failed_row(moth):
    table = flapping.sweep_hover(moth.with_(roll_inertia=None), {"frequency": [26.0]}, dof=6,
                                 progress=False)
    assert not table["converged"].iloc[0]
    assert "roll_inertia" in table["message"].iloc[0]
    assert np.isnan(table["lat_max_abs_mu"].iloc[0])


def test_a_bad_dof_is_refused(moth):
    with pytest.raises(ValueError, match="dof"):
        flapping.sweep_hover(moth, {"frequency": [26.0]}, dof=5, progress=False)

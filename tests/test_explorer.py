"""The explorer's grid (flapping.studies.explorer): the points are the insects they claim, the
multipliers and the mode agree with an independent analysis, the orbits close, failures are rows,
and the tables do not depend on the executor."""

import math
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from flapping import find_hover_orbit
from flapping.backends import FixedStep
from flapping.hover.stability import hover_stability
from flapping.model.presets import preset

pytest.importorskip("numba")
pandas = pytest.importorskip("pandas")
from flapping.studies.explorer import (  # noqa: E402
    AXES,
    DEFAULT_GRID,
    MODE_TYPES,
    ORBIT_COLUMNS,
    POINT_COLUMNS,
    SAMPLE_RTOL,
    ExplorerGrid,
    explore_hover,
    explorer_insect,
    leading_mode,
    orbit_samples,
)

#: Two frequencies (half the hawkmoth's cannot trim), two hinge heights, two wing masses.
GRID = ExplorerGrid(species=("hawkmoth",), frequency_ratio=(0.5, 1.0),
                    hinge_height_ratio=(0.0, 0.2), wing_mass_percent=(0.0, 6.0))


@pytest.fixture(scope="module")
def explored():
    return explore_hover(GRID, n_samples=32)


def test_grid_validates_each_axis_by_name():
    with pytest.raises(ValueError, match="species"):
        ExplorerGrid(species=("dragonfly",), frequency_ratio=(1.0,), hinge_height_ratio=(0.0,),
                     wing_mass_percent=(0.0,))
    with pytest.raises(ValueError, match="species"):
        ExplorerGrid(species="hawkmoth", frequency_ratio=(1.0,), hinge_height_ratio=(0.0,),
                     wing_mass_percent=(0.0,))
    with pytest.raises(ValueError, match=r"frequency_ratio.*\[0.5, 2.0\]"):
        ExplorerGrid(species=("hawkmoth",), frequency_ratio=(0.1,), hinge_height_ratio=(0.0,),
                     wing_mass_percent=(0.0,))
    with pytest.raises(ValueError, match=r"wing_mass_percent.*\[0.0, 25.0\]"):
        ExplorerGrid(species=("hawkmoth",), frequency_ratio=(1.0,), hinge_height_ratio=(0.0,),
                     wing_mass_percent=(30.0,))
    with pytest.raises(ValueError, match="hinge_height_ratio.*increasing"):
        ExplorerGrid(species=("hawkmoth",), frequency_ratio=(1.0,),
                     hinge_height_ratio=(0.2, 0.1), wing_mass_percent=(0.0,))
    with pytest.raises(ValueError, match="wing_mass_percent.*non-empty"):
        ExplorerGrid(species=("hawkmoth",), frequency_ratio=(1.0,), hinge_height_ratio=(0.0,),
                     wing_mass_percent=())


def test_default_grid_size_and_lines():
    assert DEFAULT_GRID.size == math.prod(DEFAULT_GRID.shape) == len(DEFAULT_GRID.lines()) * len(
        DEFAULT_GRID.hinge_height_ratio)
    assert DEFAULT_GRID.lines()[1] == ("hawkmoth", 0.9, 3.0)  # the wing mass before the height


@pytest.mark.parametrize("species", ["hawkmoth", "fruit_fly", "monarch"])
def test_explorer_insect_is_the_preset_at_the_point(species):
    base = preset(species)
    insect = explorer_insect(species, 1.1, 0.2, 6.0)
    assert insect.frequency == pytest.approx(1.1 * base.frequency, rel=1e-15)
    assert insect.hinge_height == pytest.approx(0.2 * base.semi_span, rel=1e-15)
    assert 2 * insect.wing_mass / insect.mass == pytest.approx(0.06, rel=1e-15)
    assert insect.mass == base.mass  # the wings are part of the insect's mass
    assert insect.with_(frequency=base.frequency, hinge_height=0.0, wing_mass=0.0) == base


def _matrix(eigenvalues, seed=0):
    rng = np.random.default_rng(seed)
    V = rng.normal(size=(4, 4))
    return V @ np.diag(eigenvalues) @ np.linalg.inv(V), V


def test_leading_mode_real_flip_and_oscillatory():
    M, V = _matrix([0.2, 1.3, 0.5, -0.7])
    mu, kind, v = leading_mode(M)
    assert kind == "real" and mu == pytest.approx(1.3, rel=1e-12) and mu.imag == 0.0
    assert np.max(np.abs(v)) == pytest.approx(1.0) and np.all(v.imag == 0.0)
    np.testing.assert_allclose(M @ v, mu * v, atol=1e-10)
    assert abs(np.vdot(v, V[:, 1])) / (np.linalg.norm(v) * np.linalg.norm(V[:, 1])) == (
        pytest.approx(1.0, rel=1e-10))
    mu, kind, _ = leading_mode(_matrix([0.2, -1.3, 0.5, 0.7])[0])
    assert kind == "flip" and mu.real == pytest.approx(-1.3, rel=1e-12)
    # A complex pair of modulus 1.1 at +-40 degrees, in real form.
    c, s = 1.1 * math.cos(math.radians(40)), 1.1 * math.sin(math.radians(40))
    block = np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 0.5, 0], [0, 0, 0, 0.1]])
    rng = np.random.default_rng(1)
    T = rng.normal(size=(4, 4))
    M = T @ block @ np.linalg.inv(T)
    mu, kind, v = leading_mode(M)
    assert kind == "oscillatory" and abs(mu) == pytest.approx(1.1, rel=1e-12)
    assert math.degrees(abs(math.atan2(mu.imag, mu.real))) == pytest.approx(40.0, rel=1e-10)
    np.testing.assert_allclose(M @ v, mu * v, atol=1e-10)
    assert set(MODE_TYPES) == {"real", "flip", "oscillatory"}


def test_one_row_per_point_in_grid_order(explored):
    points = explored.points
    assert list(points.columns[:4]) == list(AXES)
    assert set(POINT_COLUMNS) <= set(points.columns)
    assert len(points) == GRID.size == 8
    assert points.species.eq("hawkmoth").all()
    assert points.frequency_ratio.tolist() == [0.5] * 4 + [1.0] * 4
    assert points.wing_mass_percent.tolist() == [0.0, 0.0, 6.0, 6.0] * 2
    assert points.hinge_height_ratio.tolist() == [0.0, 0.2] * 4


def test_points_that_cannot_trim_are_rows_that_say_why(explored):
    failed = explored.points[explored.points.frequency_ratio == 0.5]
    assert not failed.converged.any() and failed.max_abs_mu.isna().all()
    assert failed.message.str.contains("exceeds the largest mean lift").all()
    assert (failed.mode_type == "").all()
    assert (failed.frequency_hz == 0.5 * preset("hawkmoth").frequency).all()
    assert not explored.orbits.point.isin(failed.index).any()


def test_multipliers_and_mode_agree_with_the_adaptive_analysis(explored):
    # Two independent paths: the table's (compiled fixed-step, Richardson-checked to ~1e-10)
    # and scipy's adaptive DOP853 shooting with the variational equations (rtol 1e-10): they
    # agree to the adaptive path's accuracy, ~1e-7 on the multipliers.
    ok = explored.points[explored.points.converged]
    assert len(ok) == 4
    for row in ok.itertuples():
        insect = explorer_insect(row.species, row.frequency_ratio, row.hinge_height_ratio,
                                 row.wing_mass_percent)
        stab = hover_stability(find_hover_orbit(insect, aerodynamics="exact",
                                                backend="adaptive"))
        mu = np.array([complex(getattr(row, f"mu{i}_real"), getattr(row, f"mu{i}_imag"))
                       for i in range(1, 5)])
        np.testing.assert_allclose(mu, stab.multipliers, atol=1e-6)
        assert row.max_abs_mu == pytest.approx(abs(stab.multipliers[0]), abs=1e-6)
        v = np.array([getattr(row, f"mode_{s}_abs")
                      * np.exp(1j * math.radians(getattr(row, f"mode_{s}_phase_deg")))
                      for s in ("u", "w", "q", "theta")])
        np.testing.assert_allclose(stab.monodromy @ v, mu[0] * v, atol=1e-5)
        assert row.mode_type in MODE_TYPES and np.max(np.abs(v)) == pytest.approx(1.0)
        assert row.doubling_wingbeats == pytest.approx(math.log(2) / math.log(row.max_abs_mu))
        assert row.stable == (row.max_abs_mu < 1.0)


def test_orbits_close(explored):
    orbits = explored.orbits
    assert list(orbits.columns) == list(ORBIT_COLUMNS)
    n = explored.n_samples + 1
    ok = explored.points[explored.points.converged]
    assert len(orbits) == len(ok) * 4 * n
    for i in ok.index:
        x = np.array([orbits[(orbits.point == i) & (orbits.state == s)].value.to_numpy()
                      for s in ("u", "w", "q", "theta")])
        assert x.shape == (4, n)
        scale = np.abs(x).max(axis=1)
        # A periodic orbit: back at its start after one period, to the sampling's tolerance
        # (SAMPLE_RTOL of each step's size; measured up to 2e-7 of a state's swing).
        np.testing.assert_array_less(np.abs(x[:, -1] - x[:, 0]) / scale, 100 * SAMPLE_RTOL)
    phases = orbits[orbits.point == ok.index[0]].phase.to_numpy()[:n]
    np.testing.assert_allclose(phases, np.linspace(0, 1, n))


def test_wing_mass_changes_the_answer(explored):
    # The wings' inertia is in the equations: 6 % of the mass moves every multiplier.
    ok = explored.points[explored.points.converged].set_index(
        ["wing_mass_percent", "hinge_height_ratio"])
    for h in (0.0, 0.2):
        assert abs(ok.loc[(6.0, h), "mu4_real"] - ok.loc[(0.0, h), "mu4_real"]) > 1e-3


def test_the_executor_does_not_change_the_tables(explored):
    with ThreadPoolExecutor(2) as pool:
        again = explore_hover(GRID, n_samples=32, executor=pool)
    pandas.testing.assert_frame_equal(again.points, explored.points)
    pandas.testing.assert_frame_equal(again.orbits, explored.orbits)


def test_bad_arguments_are_named():
    with pytest.raises(ValueError, match="n_samples"):
        explore_hover(GRID, n_samples=33)
    with pytest.raises(ValueError, match="n_samples"):
        explore_hover(GRID, n_samples=4)
    with pytest.raises(ValueError, match="grid"):
        explore_hover({"species": ["hawkmoth"]})
    with pytest.raises(ValueError, match="backend"):
        explore_hover(GRID, backend="compiled")
    with pytest.raises(ValueError, match="executor"):
        explore_hover(GRID, executor=object())
    assert FixedStep().error_tol == 1e-10  # the documented default of explore_hover


def test_orbit_samples_agree_with_the_orbits_own():
    # The orbit's own samples are integrated at the adaptive path's tolerance (1e-11): ours at
    # SAMPLE_RTOL agree to a few times that (measured 3e-7 on five species), far below a plot's
    # resolution.
    orbit = find_hover_orbit(explorer_insect("fruit_fly", 1.0, 0.2, 6.0), aerodynamics="exact",
                             n_samples=24)
    x = orbit_samples(orbit, 24)
    assert x.shape == (4, 25)
    np.testing.assert_array_less(np.abs(x - orbit.x).max(axis=1) / np.abs(orbit.x).max(axis=1),
                                 100 * SAMPLE_RTOL)
    with pytest.raises(ValueError, match="n_samples"):
        orbit_samples(orbit, 0)

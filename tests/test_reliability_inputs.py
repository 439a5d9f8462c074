"""Bad inputs on the surfaces added since issue 26, answered at the root (issue 35, item 8).

Each test is a reproducer: before the fix the call hung, returned a silent result (a non-orbit's
multipliers, Sobol indices from two samples, a 13 km hinge, an impossible body), or failed deep
inside with a raw error (LinAlgError, KeyError, MemoryError, "`fun`"). Now each is refused or
warned before any work, with the parameter's name and the accepted range.
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import flapping
from flapping import _validation
from flapping.errors import ClosureWarning, PlausibilityWarning
from flapping.model.insect_file import load_insect
from flapping.model.presets import preset, preset_names
from flapping.model.sixdof import body_inertia
from flapping.periodic.floquet import TRIVIAL_TOL, nontrivial_multipliers
from flapping.studies import control

MOTH = flapping.hawkmoth()


# =========================================================================== hangs
def test_an_explorer_grid_above_the_cap_is_refused_before_any_work():
    pytest.importorskip("numba")
    from flapping.studies.explorer import DEFAULT_GRID, MAX_POINTS, ExplorerGrid

    assert DEFAULT_GRID.size <= MAX_POINTS  # the book's grid fits
    started = time.perf_counter()
    # 10^8 points (1e4 frequencies x 1e4 hinge heights) used to be accepted and run for ever
    with pytest.raises(ValueError, match=r"`grid` must have at most 10000 points.*100000000"):
        ExplorerGrid(species=("hawkmoth",), frequency_ratio=np.linspace(0.5, 2.0, 10_000),
                     hinge_height_ratio=np.linspace(0.0, 0.5, 10_000), wing_mass_percent=(0.0,))
    assert time.perf_counter() - started < 5.0
    ExplorerGrid(species=("hawkmoth",), frequency_ratio=np.linspace(0.5, 2.0, 100),
                 hinge_height_ratio=np.linspace(0.0, 0.5, 100), wing_mass_percent=(0.0,))


def test_fwuav_attitude_free_y0_far_from_any_orbit_is_refused_naming_it():
    from flapping.peers.fwuav.attitude import FwuavPitchFree
    from flapping.peers.fwuav.attitude3d import attitude_free_floquet

    model = FwuavPitchFree("hawkmoth")
    started = time.perf_counter()
    with pytest.raises(ValueError, match=r"`y0\[1\]` \(v_1\).*\[-10, 10\] m/s"):
        attitude_free_floquet(model, y0=[1.0, 1e6, 0.0, 0.0])
    with pytest.raises(ValueError, match=r"`y0\[0\]` \(theta\)"):
        attitude_free_floquet(model, y0=[1e6] * 4)  # did not return
    with pytest.raises(ValueError, match=r"`y0\[3\]` \(q\).*rad/s"):
        attitude_free_floquet(model, y0=[1.0, 0.0, 0.0, -1e3])
    assert time.perf_counter() - started < 5.0


# =========================================================================== impossible bodies
@pytest.mark.parametrize("changes", [
    {"roll_inertia": 10.0},                              # 10 kg m^2 on a 1.6 g moth
    {"roll_inertia": MOTH.roll_inertia * 1e7},           # g cm^2 typed as kg m^2
    {"yaw_inertia": MOTH.yaw_inertia * 1e7},
    {"roll_inertia": 1e-8, "yaw_inertia": 1e-3},         # I_z = 4600 (I_x + I_y)
])
def test_principal_moments_that_no_body_has_are_refused(changes):
    with pytest.raises(ValueError, match=r"`roll_inertia`.*triangle inequality"):
        MOTH.with_(**changes)


@pytest.mark.parametrize("name", preset_names())
def test_every_preset_is_a_body(name):
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        insect = preset(name)
    if insect.roll_inertia is not None:  # its estimates obey the inequality itself
        i_x, i_y, i_z, i_xz = body_inertia(insect)
        moments = [*np.linalg.eigvalsh([[i_x, -i_xz], [-i_xz, i_z]]), i_y]
        _validation.triangle_inequality("moments", moments)


@settings(max_examples=60, deadline=None)
@given(a=st.floats(1e-3, 1.0), b=st.floats(1e-3, 1.0), c=st.floats(1e-3, 1.0),
       angle=st.floats(-1.5, 1.5))
def test_any_body_is_accepted(a, b, c, angle):
    """The moments of a body: I_x = s_y + s_z, I_y = s_x + s_z, I_z = s_x + s_y for second
    moments s >= 0 (here in units of 1e-8 kg m^2), tilted in the x-z plane."""
    s_x, s_y, s_z = 1e-8 * a, 1e-8 * b, 1e-8 * c
    i_x, i_y, i_z = s_y + s_z, s_x + s_z, s_x + s_y
    cos, sin = math.cos(angle), math.sin(angle)
    # the tensor [[I_x, -I_xz], [-I_xz, I_z]] rotated by `angle` about y
    rx = cos * cos * i_x + sin * sin * i_z
    rz = sin * sin * i_x + cos * cos * i_z
    rxz = cos * sin * (i_z - i_x)
    with warnings.catch_warnings():  # a body: neither refused nor warned
        warnings.simplefilter("error", PlausibilityWarning)
        insect = MOTH.with_(pitch_inertia=i_y, roll_inertia=rx, yaw_inertia=rz,
                            roll_yaw_product=rxz)
    assert body_inertia(insect)[1] == i_y


def test_a_mild_break_of_the_triangle_inequality_warns():
    # the presets' lateral moments are estimates (I_z = I_y): the book scales one at a time
    # (x0.5, x2), up to 1.6 times the bound; refused only beyond TRIANGLE_SLACK
    with pytest.warns(PlausibilityWarning, match="triangle inequality"):
        MOTH.with_(yaw_inertia=2.0 * MOTH.yaw_inertia)
    with pytest.warns(PlausibilityWarning, match="triangle inequality"):
        MOTH.with_(roll_inertia=1e-8, yaw_inertia=1e-6)  # I_z = 4.6 (I_x + I_y)
    with warnings.catch_warnings():  # I_y alone: the planar studies vary it
        warnings.simplefilter("error", PlausibilityWarning)
        MOTH.with_(pitch_inertia=0.5 * MOTH.pitch_inertia)


# =========================================================================== non-orbits
# one 3-D variational integration over a period: ~5 s
def test_fwuav_multipliers_of_a_point_on_no_orbit_warn():
    from flapping.peers.fwuav.attitude import FwuavPitchFree
    from flapping.peers.fwuav.attitude3d import attitude_free_floquet

    # near the hawkmoth's orbit (1.089, -0.107, 0.169, 0.298) but not on it: closure ~1e-2
    with pytest.warns(ClosureWarning, match="does not close"):
        result = attitude_free_floquet(FwuavPitchFree("hawkmoth"), y0=[1.09, -0.11, 0.17, 0.3])
    assert result.closure > 1e-3


def _ishigami(x: np.ndarray) -> np.ndarray:
    return np.sin(x[:, 0]) + 7.0 * np.sin(x[:, 1]) ** 2 + 0.1 * x[:, 2] ** 4 * np.sin(x[:, 0])


_PI = {f"x{i}": (-math.pi, math.pi) for i in (1, 2, 3)}


def test_sobol_indices_from_a_small_sample_warn():
    pytest.importorskip("SALib")
    from flapping.studies import sensitivity as sens

    with pytest.warns(sens.SmallSampleWarning, match="2 base samples"):
        sens.sobol_indices(_PI, _ishigami, 2)  # S1 = 1.52 +- 0.19 came back silently
    with warnings.catch_warnings():
        warnings.simplefilter("error", sens.SmallSampleWarning)
        sens.sobol_indices(_PI, _ishigami, sens.MIN_TRUSTED_BASE)


@pytest.mark.parametrize("resamples", [10**9, 10**5])
def test_sobol_resamples_beyond_memory_are_refused_before_work(resamples):
    pytest.importorskip("SALib")
    from flapping.studies import sensitivity as sens

    def never(x: np.ndarray) -> np.ndarray:
        raise AssertionError("the function ran")

    with pytest.raises(ValueError, match=r"`num_resamples` must be an integer in \[10, "):
        sens.sobol_indices(_PI, never, 64, num_resamples=resamples)  # was a MemoryError
    with pytest.raises(ValueError, match="num_resamples"):
        sens.sobol_indices(_PI, never, 2**20, num_resamples=1000)  # 2^30 bootstrap entries


@pytest.fixture(scope="module")
def comparison():
    pytest.importorskip("pandas")
    from flapping.studies import cfd

    return cfd.compare("sun2005")


def test_cfd_m_u_targets_out_of_range_are_refused(comparison):
    from flapping.studies import cfd

    with pytest.raises(ValueError, match=r"`mu` must be a real number in \[-10, 10\]"):
        cfd.hinge_height_for(comparison, mu=1e6)  # a 13 km hinge
    h = cfd.hinge_height_for(comparison, 0.0)
    assert 0.0 < h < 0.05
    with pytest.raises(ValueError, match="`values`"):
        cfd.mu_sweep(comparison, [0.0, math.nan])  # a LinAlgError from eigvals
    with pytest.raises(ValueError, match=r"`values` must be a real number in \[-10, 10\]"):
        cfd.mu_sweep(comparison, [1e6])


def test_cfd_mu_law_of_a_wrong_table_is_a_value_error(comparison):
    import pandas

    from flapping.studies import cfd

    with pytest.raises(ValueError, match="`physics` must be a table of physics_table"):
        cfd.mu_law(pandas.DataFrame({"x": [1.0]}), comparison, "hinge_height")  # a KeyError


# =========================================================================== raw errors
def test_leading_mode_of_a_non_finite_matrix_is_a_value_error():
    pytest.importorskip("numba")
    from flapping.studies.explorer import leading_mode

    with pytest.raises(ValueError, match="`monodromy` must be finite"):
        leading_mode(np.full((4, 4), np.nan))  # a LinAlgError
    with pytest.raises(ValueError, match="`monodromy` must be a real 4 x 4"):
        leading_mode(np.eye(3))
    with pytest.raises(ValueError, match="`monodromy` must be an array of real numbers"):
        leading_mode(np.full((4, 4), 1j))


def test_orbit_samples_of_no_orbit_is_a_value_error():
    pytest.importorskip("numba")
    from flapping.studies.explorer import orbit_samples

    with pytest.raises(ValueError, match="`orbit` must be a HoverOrbit"):
        orbit_samples(None, 8)  # an AttributeError


def test_sobol_function_and_hinge_are_checked_before_work():
    pytest.importorskip("SALib")
    from flapping.studies import sensitivity as sens

    with pytest.raises(ValueError, match="`function` must be a callable"):
        sens.sobol_indices(_PI, None, 64)  # a TypeError after sampling
    with pytest.raises(ValueError, match="`body_angle`"):
        sens.stroke_plane_hinge(1e-3, 2e-3, math.nan)  # (nan, nan), silently


def test_cfd_reference_names_and_masses_are_checked():
    from flapping.studies import cfd

    s = cfd.study("sun2005")
    with pytest.raises(ValueError, match="`name` must be one of"):
        s.value("weight")  # a KeyError
    with pytest.raises(ValueError, match=r"`mass` must be a real number in \(0, inf\) kg"):
        s.mass_ratio(-1.0)  # a negative m+, silently


def test_averaged_lateral_of_a_planar_orbit_says_a_six_dof_orbit_is_needed():
    from flapping.hover.sixdof import averaged_lateral

    planar = flapping.find_hover_orbit(MOTH)
    with pytest.raises(ValueError, match="six-dof hover orbit.*got HoverOrbit"):
        averaged_lateral(planar)  # blamed `fun`


@pytest.mark.parametrize("cast", [np.float32, np.float64, np.array, float])
def test_fwuav_takes_any_real_type_of_rtol(cast):
    """A float32 1e-8 lies inside [1e-12, 1e-6] and was refused as not "a number"; each call
    now passes rtol and stops at the next (bad) argument, named."""
    from flapping.peers.fwuav.attitude import FwuavPitchFree, pitch_free_floquet
    from flapping.peers.fwuav.attitude3d import attitude_free_floquet
    from flapping.peers.fwuav.floquet import fwuav_procedure, hover_floquet

    rtol = cast(1e-8)
    with pytest.raises(ValueError, match="trim"):
        pitch_free_floquet("hawkmoth", rtol=rtol, trim="yes")
    with pytest.raises(ValueError, match="y0"):
        attitude_free_floquet(FwuavPitchFree("hawkmoth"), y0=[9.0] * 4, rtol=rtol)
    with pytest.raises(ValueError, match="start"):
        fwuav_procedure("hawkmoth", rtol=rtol, start=[math.nan] * 3)
    with pytest.raises(ValueError, match="n_strips"):
        hover_floquet("hawkmoth", rtol=rtol, n_strips=-1)
    with pytest.raises(ValueError, match=r"`rtol` must be a real number in \[1e-12, 1e-06\]"):
        pitch_free_floquet("hawkmoth", rtol=np.float32(1e-3))


# =========================================================================== still open
def test_a_multiplier_far_from_one_is_not_trivial():
    with pytest.raises(ValueError, match="no trivial multiplier"):
        nontrivial_multipliers([5.0])  # returned [] (5 dropped as "trivial")
    with pytest.raises(ValueError, match="no trivial multiplier"):
        nontrivial_multipliers([0.5, -0.9, 1.0 + 2 * TRIVIAL_TOL])
    with pytest.raises(ValueError, match="`tol`"):
        nontrivial_multipliers([1.0], tol=0.0)


@settings(max_examples=100, deadline=None)
@given(others=st.lists(st.complex_numbers(max_magnitude=1e6, allow_nan=False,
                                          allow_infinity=False), max_size=6),
       error=st.floats(-0.9 * TRIVIAL_TOL, 0.9 * TRIVIAL_TOL), where=st.integers(0, 6))
def test_the_trivial_multiplier_is_the_one_of_an_autonomous_orbit(others, error, where):
    """With a multiplier within TRIVIAL_TOL of 1 (the trivial one, to the monodromy's error),
    the others come back in order; the one dropped is the closest to 1."""
    k = min(where, len(others))
    mu = np.array([*others[:k], 1.0 + error, *others[k:]], dtype=complex)
    kept = nontrivial_multipliers(mu)
    assert kept.size == len(others)
    closest = int(np.argmin(np.abs(mu - 1.0)))
    np.testing.assert_array_equal(kept, np.delete(mu, closest))


def test_a_deviation_that_reaches_zero_decays_by_zero_not_nan():
    # a deadbeat loop: the deviation is gone; the rate is 0 per wingbeat, not a NaN from log 0
    assert control._decay(np.array([1.0, 0.5, 0.0, 0.0, 0.0])) == 0.0
    assert control._decay(np.array([1.0, 0.5, 0.25, 0.125, 0.0625])) == pytest.approx(0.5)


def test_grams_typed_as_kilograms_in_an_insect_file_warn_naming_the_field(tmp_path):
    path = tmp_path / "moth.toml"
    path.write_text('preset = "hawkmoth"\nmass = 1.648\n')  # the hawkmoth's 1.648 g, in "kg"
    with pytest.warns(PlausibilityWarning, match=r"`mass` = 1.648.*grams typed as kg"):
        insect = load_insect(path)
    assert insect.mass == 1.648  # valid for the model (a 1.6 kg vehicle), so not refused
    good = tmp_path / "fine.toml"
    good.write_text('preset = "hawkmoth"\nmass = 1.7e-3\n')
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        load_insect(good)


@pytest.mark.parametrize("name", preset_names())
def test_no_preset_read_from_a_file_warns(tmp_path, name):
    path = tmp_path / "p.toml"
    path.write_text(f'preset = "{name}"\n')
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        load_insect(path)

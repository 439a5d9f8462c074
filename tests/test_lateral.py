"""The lateral-stability study (flapping.studies.lateral)."""

import math

import numpy as np
import pytest

from flapping.model import presets
from flapping.studies import lateral as lat

# --- Mode classification on synthetic multipliers (no model) ---------------------------------

def test_a_real_multiplier_above_one_is_a_divergence_with_its_doubling_time():
    T = 0.01
    (mode,) = lat.classify_multipliers([2.0], T)
    assert (mode.type, mode.stable, mode.kind) == ("real", False, "divergence")
    # |mu| = 2: the amplitude doubles in exactly one wingbeat.
    assert mode.time_wingbeats == pytest.approx(1.0, rel=1e-14)
    assert mode.time_ms == pytest.approx(10.0, rel=1e-14)
    assert mode.growth_rate == pytest.approx(math.log(2.0) / T, rel=1e-14)
    assert math.isnan(mode.period_ms)


def test_a_complex_pair_is_one_oscillatory_mode_with_its_period():
    T = 0.02
    mu = 0.5 * np.exp(1j * 2.0 * np.pi / 8.0)  # halves every wingbeat, 8 wingbeats per turn
    modes = lat.classify_multipliers([mu, np.conj(mu), 0.25], T)
    assert len(modes) == 2
    osc, sub = modes
    assert (osc.type, osc.stable, osc.kind) == ("oscillatory", True, "damped oscillation")
    assert osc.multiplier.imag > 0
    assert osc.time_wingbeats == pytest.approx(1.0, rel=1e-12)  # halving time
    assert osc.period_ms == pytest.approx(8 * 20.0, rel=1e-12)
    assert (sub.type, sub.kind, sub.time_wingbeats) == ("real", "subsidence", pytest.approx(0.5))


def test_a_negative_multiplier_is_a_flip_and_modes_sort_by_modulus():
    modes = lat.classify_multipliers([0.1, -1.5, 1.2j * 0 + 0.9], 1.0)
    assert [m.type for m in modes] == ["flip", "real", "real"]
    assert [abs(m.multiplier) for m in modes] == [1.5, 0.9, 0.1]
    assert modes[0].kind == "unstable flip"


def test_an_underflowed_multiplier_is_a_subsidence_that_halves_at_once():
    (mode,) = lat.classify_multipliers([0.0], 0.01)
    assert (mode.kind, mode.time_wingbeats, mode.growth_rate) == ("subsidence", 0.0, -math.inf)


@pytest.mark.parametrize("bad", [[np.nan], [np.inf], [1 + 1j, 0.5], []])
def test_bad_multipliers_are_refused(bad):
    with pytest.raises(ValueError, match="multipliers"):
        lat.classify_multipliers(bad, 1.0)


def test_a_bad_period_is_refused_by_name():
    with pytest.raises(ValueError, match="period"):
        lat.classify_multipliers([0.5], -1.0)


# --- Which presets --------------------------------------------------------------------------

def test_the_lateral_presets_are_those_with_roll_and_yaw_inertia():
    have = {n for n in presets.preset_names() if presets.preset(n).roll_inertia is not None}
    assert set(lat.LATERAL_PRESETS) == have
    assert set(presets.preset_names()) - have == set(lat.NO_LATERAL_INERTIA)


def test_the_monarch_is_refused_with_the_reason():
    with pytest.raises(ValueError, match="monarch.*no roll or yaw inertia"):
        lat.analyse("monarch")


# --- The published records ------------------------------------------------------------------

def test_zhang_and_sun_record_three_modes_divergence_first():
    (zs,) = [r for r in lat.PUBLISHED_LATERAL if r.cite == "zhang2010"]
    assert [lat.MODE_KINDS[m] for m in zs.modes] == ["divergence", "damped oscillation",
                                                     "subsidence"]
    assert zs.verdict == "unstable" and zs.doubling_wingbeats == 9.0
    assert "slow divergence" in zs.quote


def test_every_published_record_names_a_preset_and_a_bib_key():
    import pathlib
    bib = (pathlib.Path(__file__).parents[1] / "book" / "references.bib").read_text()
    for r in lat.PUBLISHED_LATERAL:
        assert r.preset in lat.LATERAL_PRESETS
        assert f"{{{r.cite}," in bib, r.cite
        assert r.verdict == "unstable"  # every source read finds hover laterally unstable
    assert lat.PUBLISHED_LATERAL_DERIVATIVES == {}  # none could be read (module docstring)


def test_a_bad_published_record_is_refused():
    with pytest.raises(ValueError, match="type"):
        lat.PublishedLateral("x", "y", "hawkmoth", "m", (("spiral", False),), None, "q",
                             "verified")


# --- The model (one cached analysis of the bumblebee, the cheapest preset) ------------------

@pytest.fixture(scope="module")
def bee():
    return lat.analyse("bumblebee")


def test_the_modes_are_the_stability_lateral_multipliers(bee):
    ours = np.array([m.multiplier for m in bee.modes])
    lateral = bee.stability.lateral.multipliers
    # Real modes here, so one mode per multiplier, in the same (descending modulus) order.
    np.testing.assert_array_equal(np.abs(ours), np.abs(lateral))
    assert bee is lat.analyse("bumblebee")  # cached


def test_the_tables_have_their_columns(bee):
    table = lat.lateral_table(["bumblebee"])
    for column in ("multipliers", "mode_types", "leading_multiplier", "leading_type",
                   "doubling_wingbeats", "doubling_ms", "averaged_eigenvalues_per_s",
                   "floquet_exponents_per_s", "coupling", "multiplier_error"):
        assert column in table.columns
    row = table.loc["bumblebee"]
    assert row["leading_multiplier"] == bee.stability.lateral.multipliers[0]
    if not row["stable"]:
        lead = abs(row["leading_multiplier"])
        assert row["doubling_wingbeats"] == pytest.approx(math.log(2) / math.log(lead))
        assert row["doubling_ms"] == pytest.approx(
            1e3 * row["doubling_wingbeats"] * bee.orbit.period)
    modes = lat.mode_table(["bumblebee"])
    assert list(modes["mode"]) == list(range(1, len(bee.modes) + 1))
    derivatives = lat.derivative_table(["bumblebee"])
    assert list(derivatives.columns) == ["Yv", "Yp", "Yr", "Lv", "Lp", "Lr", "Nv", "Np", "Nr"]
    assert derivatives.loc["bumblebee", "Lp"] == bee.averaged.nondimensional["Lp"]


def test_the_floquet_exponents_are_the_log_of_the_multipliers_over_the_period(bee):
    row = lat.lateral_table(["bumblebee"]).loc["bumblebee"]
    for exponent, mode in zip(row["floquet_exponents_per_s"], bee.modes, strict=True):
        assert np.exp(exponent * bee.orbit.period) == pytest.approx(mode.multiplier, rel=1e-12)


def test_the_comparison_puts_the_mode_type_first_and_matches_by_rank(bee):
    xu = [r for r in lat.PUBLISHED_LATERAL if r.cite == "xu2013"]
    table = lat.compare_published(records=xu)
    assert list(table.columns[4:7]) == ["their_type", "our_type", "type_agrees"]
    assert list(table["type_agrees"]) == ["not stated"]  # Xu & Sun: type not recorded
    assert table["our_stable"].iloc[0] == bee.modes[0].stable
    assert table["stability_agrees"].iloc[0] == ("yes" if not bee.modes[0].stable else "no")


@pytest.mark.slow
def test_zhang_and_sun_are_compared_mode_by_mode():
    zs = [r for r in lat.PUBLISHED_LATERAL if r.cite == "zhang2010"]
    table = lat.compare_published(records=zs)
    ours = lat.analyse("hoverfly").modes
    assert list(table["mode"]) == [1, 2, 3]
    assert list(table["our_type"]) == [m.type for m in ours[:3]]
    assert list(table["type_agrees"]) == [
        "yes" if m.type == t else "no" for m, (t, _) in zip(ours, zs[0].modes, strict=False)]


@pytest.mark.slow
def test_the_hawkmoths_leading_lateral_multiplier_is_the_stability_one():
    from flapping import find_hover_orbit, hover_stability

    analysis = lat.analyse("hawkmoth")
    table = lat.lateral_table(["hawkmoth"])
    assert table.loc["hawkmoth", "leading_multiplier"] == analysis.stability.lateral.multipliers[0]
    # An independent solve through the public entry points gives the same multiplier to the
    # analysis's error estimate (~1e-8).
    fresh = hover_stability(find_hover_orbit(presets.preset("hawkmoth"), dof=6))
    assert abs(table.loc["hawkmoth", "leading_multiplier"] - fresh.lateral.multipliers[0]) < 1e-7
    assert table.loc["hawkmoth", "leading_type"] == "real"


@pytest.mark.slow
def test_the_inertia_sensitivity_reuses_the_orbit_and_matches_a_fresh_solve(bee):
    from flapping.hover.sixdof import find_sixdof_hover_orbit, sixdof_stability

    table = lat.inertia_sensitivity("bumblebee", factors=(2.0,))
    assert list(table["scaled"]) == ["none", "I_x", "I_z", "both"]
    assert table["leading_multiplier"].iloc[0] == bee.stability.lateral.multipliers[0]
    # The reused orbit is the orbit: a fresh solve with doubled I_x gives the same multiplier.
    insect = bee.orbit.insect.with_(roll_inertia=2.0 * bee.orbit.insect.roll_inertia)
    fresh = sixdof_stability(find_sixdof_hover_orbit(insect))
    assert abs(table["leading_multiplier"].iloc[1] - fresh.lateral.multipliers[0]) < 1e-7
    # Scaling the inertia moves the multiplier (the test can fail if it did not).
    assert abs(table["leading_multiplier"].iloc[1] - table["leading_multiplier"].iloc[0]) > 1e-6

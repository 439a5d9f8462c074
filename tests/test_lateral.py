"""The lateral-stability study (flapping.studies.lateral)."""

import math

import numpy as np
import pytest

from flapping.hover.sixdof import LATERAL_DERIVATIVE_NAMES
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


# --- Sun's group's lateral system and the published reference quantities --------------------

def _inverse_inertia_system(d, r):
    """The lateral system written the long way: the inertia matrix inverted numerically."""
    inertia = np.array([[r["Ix"], -r["Ixz"]], [-r["Ixz"], r["Iz"]]])
    moments = np.array([[d["Lv"], d["Lp"], d["Lr"]], [d["Nv"], d["Np"], d["Nr"]]])
    rates = np.linalg.solve(inertia, moments)
    a = np.zeros((4, 4))
    a[0, :3] = [d["Yv"] / r["m"], d["Yp"] / r["m"], d["Yr"] / r["m"]]
    a[1, :3], a[2, :3] = rates
    a[0, 3], a[3, 1] = r["g"], 1.0
    return a


def test_the_lateral_system_solves_the_inertia_coupled_euler_equations():
    rng = np.random.default_rng(3)
    d = dict(zip(LATERAL_DERIVATIVE_NAMES, rng.normal(size=9), strict=True))
    r = {"m": 80.0, "Ix": 4.0, "Iz": 15.0, "Ixz": -3.0, "g": 0.015}
    np.testing.assert_allclose(lat.lateral_system(d, r), _inverse_inertia_system(d, r),
                               rtol=1e-13, atol=1e-15)


def test_the_lateral_system_refuses_missing_terms_and_a_bad_inertia():
    d = {n: 0.1 for n in ("Yv", "Yp", "Yr", "Lv", "Lp", "Lr", "Nv", "Np")}
    r = {"m": 80.0, "Ix": 4.0, "Iz": 15.0, "Ixz": 0.0, "g": 0.015}
    with pytest.raises(ValueError, match="Nr"):
        lat.lateral_system(d, r)
    with pytest.raises(ValueError, match="I_xz"):
        lat.lateral_system({**d, "Nr": 0.1}, {**r, "Ixz": 8.0})
    with pytest.raises(ValueError, match="ratios\\['m'\\]"):
        lat.lateral_system({**d, "Nr": 0.1}, {**r, "m": -1.0})


def test_the_published_transcription_cannot_be_checked_and_says_which_terms_are_missing():
    for key in lat.LATERAL_STUDIES:
        with pytest.raises(ValueError, match="Yv.*Nr.*were not read"):
            lat.check_lateral_transcription(key)


def test_the_dronefly_reference_is_our_hoverfly_preset_and_read_in_xu_and_sun_2015():
    ref = lat.lateral_study("zhang2010").reference
    fly = presets.preset("hoverfly")
    assert ref["mass"].value == pytest.approx(fly.mass, rel=1e-12)
    assert ref["semi_span"].value == pytest.approx(fly.semi_span, rel=1e-12)
    assert ref["mean_chord"].value == pytest.approx(fly.mean_chord, rel=1e-12)
    assert ref["r2"].value == pytest.approx(fly.r2, rel=1e-12)
    assert {n.status for n in ref.values()} == {"read"}
    assert {n.source for n in ref.values()} == {"xu2015"}
    # 0.13 of a body length of 1.29 R above the CG.
    assert ref["hinge_to_cg"].value == pytest.approx(0.13 * 1.29 * 11.2e-3, rel=1e-12)


def test_our_nondimensional_derivatives_follow_suns_definitions(bee):
    """Y_v+ = Y_v / (0.5 rho U S_t), Y_p+ = Y_p / (0.5 rho U^2 S_t T), L_v+ = L_v /
    (0.5 rho U S_t c), L_p+ = L_p / (0.5 rho U^2 S_t c T): U = 2 Phi n r2, S_t both wings."""
    ins, orbit = bee.orbit.insect, bee.orbit
    phi_pp = 2.0 * orbit.amplitude
    u = 2.0 * phi_pp * ins.frequency * ins.r2 * ins.semi_span
    s_t = 2.0 * ins.wing_area
    half_rho = 0.5 * ins.air_density
    d, nd = bee.averaged.dimensional, bee.averaged.nondimensional
    t, c = 1.0 / ins.frequency, ins.mean_chord
    scale = {"Yv": half_rho * u * s_t, "Yp": half_rho * u * u * s_t * t,
             "Lv": half_rho * u * s_t * c, "Lp": half_rho * u * u * s_t * c * t,
             "Nr": half_rho * u * u * s_t * c * t, "Lr": half_rho * u * u * s_t * c * t}
    for name, sc in scale.items():
        assert nd[name] == pytest.approx(d[name] / sc, rel=1e-12, abs=1e-300), name


@pytest.fixture(scope="module")
def bee_comparison(bee):
    return lat.compare_lateral("xu2013")


def test_our_derivatives_in_suns_system_give_our_averaged_modes(bee_comparison):
    # Two routes to the same eigenvalues: the averaged Jacobian of the right-hand side, and
    # the averaged loads' derivatives, non-dimensional, in Sun's system. They differ by the
    # central differences' rounding (steps 1e-6): 1e-5 of the largest eigenvalue.
    assert bee_comparison.system_error < 1e-5
    assert list(bee_comparison.derivatives.status) == ["not read"] * 9
    assert bee_comparison.derivatives.theirs.isna().all()
    modes = bee_comparison.modes
    assert modes.floquet_kind.iloc[0] == "divergence" == modes.averaged_kind.iloc[0]


def test_the_sign_of_lv_decides_the_lateral_mode_type(bee_comparison):
    table = lat.term_table(bee_comparison)
    base = table.iloc[0]
    assert base.mode_types == "real, real, real, real"
    changed = table[table.types_change]
    # Only L_v's sign and L_p's size change the types; negated, L_v gives the oscillating
    # divergence Perl et al. report for the fruit fly (a restoring slip-roll coupling).
    assert set(changed.derivative) <= {"Lv", "Lp"}
    (lv,) = changed[changed.derivative == "Lv"].itertuples()
    assert lv.change == "negated" and lv.leading_kind == "oscillating divergence"
    # The threshold is L_v+ = 0 (the characteristic polynomial's constant term is -g+ L_v+
    # over the inertia, so L_v+ > 0 forces a positive real root), less a sliver where the
    # slow roots first meet.
    threshold = lat.lv_threshold(bee_comparison)
    assert -1e-2 < threshold <= 0.0


def test_an_inclined_body_keeps_its_principal_inertias():
    fly = presets.preset("hoverfly")
    ia, it = fly.roll_inertia, fly.yaw_inertia
    assert lat.inclined_body_inertia(fly, 0.0) == pytest.approx((ia, it, 0.0), abs=1e-25)
    ix, iz, ixz = lat.inclined_body_inertia(fly, math.pi / 2)
    assert (ix, iz) == pytest.approx((it, ia), rel=1e-12) and abs(ixz) < 1e-24
    ix, iz, ixz = lat.inclined_body_inertia(fly, math.radians(53.3))
    eig = np.linalg.eigvalsh(np.array([[ix, -ixz], [-ixz, iz]]))
    np.testing.assert_allclose(eig, sorted((ia, it)), rtol=1e-12)
    assert ixz < 0.0  # nose up: the mass ahead of the CG lies above it (z down)
    with pytest.raises(ValueError, match="body_angle"):
        lat.inclined_body_inertia(fly, 2.0)


def test_suns_inclined_body_gives_zhang_and_suns_mode_types():
    """With the dronefly's body hanging at 53.3 deg (Xu & Sun 2015) instead of along x, our
    Floquet and averaged lateral modes are Zhang & Sun's: a divergence, a damped oscillation
    and a subsidence."""
    chi = lat.lateral_study("zhang2010").reference["hanging_angle"].value
    (row,) = lat.geometry_table("hoverfly", (("body inclined", 0.0, chi),)).itertuples()
    expected = "divergence, damped oscillation, subsidence"
    assert row.floquet_kinds == expected == row.averaged_kinds
    assert row.multiplier_error < 1e-7

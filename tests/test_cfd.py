"""CFD derivatives as data and our model on their insect (flapping.studies.cfd, issue 28)."""

import math
from pathlib import Path

import numpy as np
import pytest

import flapping.studies.cfd
from flapping.studies import cfd

# ------------------------------------------------------------------ item 1: the data

#: Half a unit of the last printed digit of each published number, relative: the rounding the
#: reproduced value may differ by (0.32 s, 0.1 s, 0.024 s, 0.37 s in Sun & Xiong's abstract).
ROUNDING = {"oscillation_period": 0.005 / 0.32, "doubling_time": 0.05 / 0.1,
            "fast_halving": 0.0005 / 0.024, "slow_halving": 0.005 / 0.37}


def test_every_number_has_a_source_a_table_and_a_known_status():
    for s in cfd.STUDIES.values():
        assert set(s.derivatives) == set(cfd.DERIVATIVES)
        for n in [*s.derivatives.values(), *s.reference.values()]:
            assert n.status in cfd.STATUSES and n.source and n.table
            assert math.isfinite(n.value)
        assert all(n.status == "read" for n in s.derivatives.values())


def test_a_number_with_an_unknown_status_is_refused():
    with pytest.raises(ValueError, match="status"):
        cfd.Number(1.0, "somebody", "-", "guessed")


def test_an_unknown_study_names_the_known_ones():
    with pytest.raises(ValueError, match="sun2005"):
        cfd.study("nobody2099")


def test_sun_xiong_reference_quantities_follow_their_definitions():
    s = cfd.study("sun2005")
    u = 2.0 * math.radians(116.0) * (1.0 / 6.4e-3) * 0.55 * 13.2e-3
    assert s.speed == pytest.approx(u, rel=1e-14)
    assert s.period == pytest.approx(6.4e-3, rel=1e-14)
    assert s.gravity_ratio == pytest.approx(9.81 * 6.4e-3 / u, rel=1e-14)
    # m+ = m / (0.5 rho U S T) with S the two wings
    assert s.mass_ratio() == pytest.approx(175e-6 / (0.5 * 1.225 * u * 2 * 13.2e-3 * 4.01e-3
                                                      * 6.4e-3), rel=1e-14)


def test_the_published_matrix_maps_to_the_dimensional_one_and_back():
    """A = D A+ D^-1 / T and A+ = T D^-1 A D are inverse; the derivatives come back."""
    s = cfd.study("sun2005")
    a_plus = s.matrix(80.0, 12.0)
    d = s.scaling()
    a = d @ a_plus @ np.linalg.inv(d) / s.period
    assert a[0, 3] == pytest.approx(-9.81, rel=1e-12)  # -g theta in SI
    back = s.period * np.linalg.solve(d, a) @ d
    np.testing.assert_allclose(cfd._derivatives_of(back, 80.0, 12.0), s.derivative_vector(),
                               rtol=1e-12)


def test_sun_xiong_derivatives_reproduce_their_published_modes():
    """Four published numbers, two identified (m+, I+): each reproduced within its rounding.

    The doubling time is printed to one figure (0.1 s), so it bounds little; the period and the
    two halving times (two figures) are three conditions on two unknowns.
    """
    check = cfd.check_transcription("sun2005")
    errors = check.relative_errors()
    for name, tol in ROUNDING.items():
        assert abs(errors[name]) <= tol, (name, errors[name], tol)
    assert cfd.mode_summary(check.eigenvalues)["type"] == "oscillatory"
    assert check.eigenvalues[0].real > 0.0 > check.eigenvalues[2].real


def test_a_transcription_slip_breaks_the_reproduction():
    """The check can fail: M_u+ read as 2.839 (two digits swapped) misses the rounding bounds."""
    s = cfd.study("sun2005")
    slipped = dict(s.derivatives)
    slipped["Mu"] = cfd.Number(2.839, "test", "-", "estimated")
    bad = cfd.CFDStudy(s.key, s.insect, slipped, s.reference, s.modes)
    mp, ip = cfd.identify_mass_and_inertia(bad)
    ev = np.linalg.eigvals(bad.matrix(mp, ip)) / bad.period
    numbers = cfd._mode_numbers(ev)
    rel = (numbers - bad.modes.targets()) / np.abs(bad.modes.targets())
    assert np.max(np.abs(rel[[1, 2, 3]])) > min(ROUNDING.values())


def test_identified_mass_and_inertia_are_those_of_a_bumblebee():
    """m+ within 10 % of the morphology's (rho, S of the CFD not read: 6 % apart), and I_y
    between the ellipsoid estimates of a 15-20 mm, 5-8 mm body (1e-9 .. 6e-9 kg m^2)."""
    check = cfd.check_transcription("sun2005")
    assert check.mass_ratio == pytest.approx(check.mass_ratio_morphology, rel=0.10)
    assert 1e-9 < check.pitch_inertia < 6e-9


def test_the_unattributed_table_is_kept_out():
    assert cfd.UNATTRIBUTED and all("why" in t for t in cfd.UNATTRIBUTED)
    for s in cfd.STUDIES.values():
        assert s.derivatives["Xu"].value != -1.28


def test_searched_studies_are_cited_kept_out_and_say_why():
    bib = (Path(__file__).resolve().parents[1] / "book" / "references.bib").read_text()
    assert cfd.SEARCHED
    for key, entry in cfd.SEARCHED.items():
        assert f"{{{key}," in bib, key
        assert key not in cfd.STUDIES
        assert entry["insect"] and entry["found"] and entry["why"]


def test_mode_summary_reads_the_leading_mode():
    osc = cfd.mode_summary([1.0 + 2.0j, 1.0 - 2.0j, -3.0])
    assert osc["type"] == "oscillatory" and osc["period"] == pytest.approx(math.pi)
    assert osc["doubling_time"] == pytest.approx(math.log(2.0))
    real = cfd.mode_summary([0.5, -1.0 + 1.0j, -1.0 - 1.0j])
    assert real["type"] == "real" and real["period"] == math.inf
    assert cfd.mode_summary([-1.0, -2.0])["doubling_time"] == math.inf


def test_the_module_is_importable_by_its_dotted_name():
    assert flapping.studies.cfd.compare is cfd.compare


# ------------------------------------------------------------------ item 2: our model on theirs
@pytest.fixture(scope="module")
def comparison():
    return cfd.compare("sun2005")


def test_compare_returns_a_frozen_term_by_term_table(comparison):
    import dataclasses

    assert list(comparison.table.index) == list(cfd.DERIVATIVES)
    assert list(comparison.table.columns) == ["theirs", "ours", "ratio"]
    np.testing.assert_array_equal(comparison.table["theirs"].to_numpy(),
                                  cfd.study("sun2005").derivative_vector())
    with pytest.raises(dataclasses.FrozenInstanceError):
        comparison.insect = None


def test_our_insect_is_theirs(comparison):
    s, ins = comparison.study, comparison.insect
    assert ins.mass == s.value("mass") and ins.frequency == s.value("frequency")
    assert 2.0 * ins.stroke_amplitude == pytest.approx(s.value("stroke_amplitude"))
    assert ins.hinge_height == s.value("hinge_height") and ins.wing_mass == 0.0
    # the trim reports both amplitudes, peak to peak, and our trimmed one is near theirs
    assert comparison.trim["their_stroke_amplitude_deg"] == pytest.approx(116.0)
    assert comparison.trim["our_stroke_amplitude_deg"] == pytest.approx(
        2.0 * math.degrees(comparison.orbit.amplitude))


def test_our_derivatives_rebuild_our_averaged_jacobian(comparison):
    """Non-dimensional and back: D A+(ours) D^-1 / T is the averaged Jacobian, every entry
    (its gravity column and kinematic row included: nothing else hides in it)."""
    s, ins = comparison.study, comparison.insect
    d = s.scaling()
    a_plus = cfd._system(comparison.table["ours"].to_numpy(), s.mass_ratio(ins.mass),
                         ins.pitch_inertia / s.inertia_scale(), s.gravity_ratio)
    rebuilt = d @ a_plus @ np.linalg.inv(d) / s.period
    jac = comparison.stability.averaged_jacobian
    # the orbit's small pitch oscillation makes the gravity entry -g <cos theta>: 1e-5 relative
    np.testing.assert_allclose(rebuilt, jac, rtol=1e-4, atol=1e-4 * np.max(np.abs(jac)))


def test_with_the_hinge_at_the_cg_our_averages_are_the_cycle_means_of_eq_29():
    """Independent route: the cycle means of the analytic derivatives of eq. (29) at the
    orbit's amplitude equal the Jacobian averaged along the orbit (linear loads)."""
    from flapping.model.derivatives import stability_derivatives

    ins = cfd.study_insect(cfd.study("sun2005"), hinge_height=0.0)
    orbit, stab = cfd._solve(ins)
    t = np.arange(512) / 512 * ins.period
    means = stability_derivatives(ins, t, alpha_m=orbit.alpha_m,
                                  amplitude=orbit.amplitude).averaged_jacobian(ins.gravity)
    scale = np.max(np.abs(means))
    np.testing.assert_allclose(stab.averaged_jacobian, means, rtol=1e-4, atol=1e-6 * scale)


def test_both_sets_of_modes_are_reported(comparison):
    check = cfd.check_transcription("sun2005")
    np.testing.assert_allclose(comparison.their_eigenvalues, check.eigenvalues, rtol=1e-12)
    assert dict(comparison.their_mode) == cfd.mode_summary(check.eigenvalues)
    np.testing.assert_allclose(comparison.our_eigenvalues,
                               comparison.stability.averaged_eigenvalues)
    assert comparison.our_multipliers.shape == (4,)
    assert dict(comparison.our_floquet_mode) == cfd.mode_summary(
        comparison.stability.exponents)
    assert comparison.not_modelled and any("body drag" in n for n in comparison.not_modelled)


# ------------------------------------------------------------------ item 3: which term
@pytest.fixture(scope="module")
def swaps(comparison):
    return cfd.swap_table(comparison)


def _row(table, direction, swapped):
    rows = table[(table.direction == direction) & (table.swapped == swapped)]
    assert len(rows) == 1
    return rows.iloc[0]


def test_swapping_everything_gives_their_modes_and_nothing_gives_ours(swaps, comparison):
    all_theirs = _row(swaps, "ours <- theirs", "all")
    assert all_theirs["type"] == comparison.their_mode["type"]
    assert all_theirs["rate"] == pytest.approx(comparison.their_mode["rate"], rel=1e-12)
    none = _row(swaps, "ours <- theirs", "none")
    back = _row(swaps, "theirs <- ours", "all")
    assert none["rate"] == pytest.approx(back["rate"], rel=1e-12)
    assert none["type"] == back["type"]


def test_each_single_swap_changes_exactly_its_term(swaps, comparison):
    theirs = comparison.study.derivatives["Mu"].value
    ours = comparison.table.loc["Mu", "ours"]
    for name in cfd.DERIVATIVES:
        row = _row(swaps, "ours <- theirs", name)
        assert row["Mu"] == (theirs if name == "Mu" else ours)
    assert len(swaps) == 2 * (1 + len(cfd.DERIVATIVES) + len(cfd.SWAP_GROUPS))


@pytest.fixture(scope="module")
def physics(comparison):
    return cfd.physics_table(comparison)


def test_every_physics_case_found_its_orbit(physics):
    assert (physics["message"] == "").all(), physics[physics["message"] != ""]


def test_the_hinge_height_adds_minus_h_xu_over_c_to_mu(physics, comparison):
    """The hinge h above the CG turns the backward force X_u u on the wings into a nose-up
    moment: Delta M_u+ = -Delta h X_u+ / c (X_u+ does not depend on h). Tolerance 1 %: X_u+ moves
    with the trimmed amplitude, which moves by < 0.2 % between the cases."""
    s = comparison.study
    base = physics[physics.case == "as compared"].iloc[0]
    high = physics[physics.case == "hinge height x4"].iloc[0]
    dh = 3.0 * s.value("hinge_height")
    xu = comparison.table.loc["Xu", "ours"]
    assert high["Mu"] - base["Mu"] == pytest.approx(-dh * xu / s.value("mean_chord"), rel=0.01)


def test_the_as_compared_case_is_the_comparison(physics, comparison):
    row = physics[physics.case == "as compared"].iloc[0]
    assert row["Mu"] == comparison.table.loc["Mu", "ours"]
    assert row["averaged_type"] == comparison.our_mode["type"]


def test_an_offset_hinge_is_trimmed_by_the_mean_stroke_angle(physics):
    """Ahead of the CG the mean stroke angle moves back, behind it forward, by symmetry."""
    ahead = physics[physics.case == "hinge 1 chord ahead"].iloc[0]["stroke_mean_deg"]
    behind = physics[physics.case == "hinge 1 chord behind"].iloc[0]["stroke_mean_deg"]
    assert ahead < 0.0 < behind
    assert ahead == pytest.approx(-behind, rel=1e-6)


def test_the_speed_pitch_moment_alone_decides_the_mode_type(swaps, comparison):
    """The docstring's claim: of the single swaps, only M_u changes the leading mode's type, in
    both directions (ours with their M_u oscillates; theirs with ours does not)."""
    for direction, base in (("ours <- theirs", comparison.our_mode["type"]),
                            ("theirs <- ours", comparison.their_mode["type"])):
        changed = [n for n in cfd.DERIVATIVES
                   if _row(swaps, direction, n)["type"] != base]
        assert changed == ["Mu"], (direction, changed)


def test_the_reference_time_is_the_wingbeat_not_c_over_u():
    """With q+ = q c/U (time c/U) the pitch-rate terms are UT/c ~ 7 times smaller in the
    dimensional system, and no m+, I+ reproduce the modes: the rounding bounds are missed."""
    s = cfd.study("sun2005")
    k = s.value("mean_chord") / (s.speed * s.period)
    d = {n: (cfd.Number(v.value * k, "test", "-", "estimated") if n.endswith("q") else v)
         for n, v in s.derivatives.items()}
    alt = cfd.CFDStudy(s.key, s.insect, d, s.reference, s.modes)
    mp, ip = cfd.identify_mass_and_inertia(alt)
    numbers = cfd._mode_numbers(np.linalg.eigvals(alt.matrix(mp, ip)) / alt.period)
    rel = (numbers - alt.modes.targets()) / np.abs(alt.modes.targets())
    tight = [ROUNDING["oscillation_period"], ROUNDING["fast_halving"], ROUNDING["slow_halving"]]
    assert np.any(np.abs(rel[[1, 2, 3]]) > tight)


def test_the_neutral_hinge_height_turns_our_mode_oscillatory_just_above_it(comparison):
    """hinge_height_for(mu=0) from the linear law, checked on solved orbits 10 % either side."""
    h0 = cfd.hinge_height_for(comparison, 0.0)
    assert h0 > comparison.insect.hinge_height  # our M_u+ < 0 at the compared hinge
    kinds = {}
    for k in (0.9, 1.1):
        orbit, stab = cfd._solve(comparison.insect.with_(hinge_height=k * h0), comparison.orbit)
        mu = cfd.our_derivatives(comparison.study, stab)[cfd.DERIVATIVES.index("Mu")]
        kinds[k] = (np.sign(mu), cfd.mode_summary(stab.averaged_eigenvalues)["type"])
    assert kinds[0.9] == (-1.0, "real") and kinds[1.1] == (1.0, "oscillatory")
    # their M_u+ needs a hinge far above ours: more than a bumblebee body length (18 mm)
    assert cfd.hinge_height_for(comparison) > 18e-3


def test_the_hinge_height_is_its_stated_fraction_of_the_body_length():
    """The estimate the chapter quotes in body lengths: 0.13 L (Sun's group's hoverfly)."""
    s = cfd.study("sun2005")
    assert s.value("hinge_height") / s.value("body_length") == pytest.approx(0.13, rel=1e-14)
    assert s.reference["body_length"].status == "estimated"


def test_the_mode_type_changes_once_between_our_and_their_speed_pitch_moment(comparison):
    """Bisection finds one switch; either side has the other type (checked, not assumed)."""
    for base in cfd.BASES:
        mu0 = cfd.mode_type_threshold(comparison, base)
        below, above = cfd.mu_sweep(comparison, [mu0 - 1e-6, mu0 + 1e-6], base)["type"]
        assert (below, above) == ("real", "oscillatory"), base
        ends = cfd.mu_sweep(comparison, [comparison.table.loc["Mu", "ours"],
                                         comparison.table.loc["Mu", "theirs"]], base)
        assert list(ends["type"]) == ["real", "oscillatory"]


def test_with_our_other_terms_the_switch_sits_where_the_real_root_leaves_zero(comparison):
    """Ours has X_w+ = Z_u+ = Z_q+ = M_w+ = 0 (fore-aft symmetry), so det A+ is proportional to
    M_u+: a root passes through zero at M_u+ = 0, and the switch lies just above it."""
    sweep = cfd.mu_sweep(comparison, [-1e-3, 0.0], "ours")
    assert sweep["type"].tolist() == ["real", "real"]
    assert sweep["rate"][0] > 0.0 and abs(sweep["rate"][1]) < 1e-9
    assert 0.0 < cfd.mode_type_threshold(comparison, "ours") < 0.05


def test_mu_sweep_reproduces_the_swap_of_m_u_alone(comparison):
    swaps = cfd.swap_table(comparison)
    row = swaps[(swaps.direction == "ours <- theirs") & (swaps.swapped == "Mu")].iloc[0]
    sweep = cfd.mu_sweep(comparison, [comparison.table.loc["Mu", "theirs"]], "ours").iloc[0]
    assert sweep["type"] == row["type"] and sweep["rate"] == pytest.approx(row["rate"], 1e-12)
    assert sweep["frequency"] == pytest.approx(2 * math.pi / row["period"], rel=1e-12)


def test_threshold_refuses_a_bad_base_or_no_bracket(comparison):
    with pytest.raises(ValueError, match="base"):
        cfd.mode_type_threshold(comparison, "mine")
    import dataclasses

    table = comparison.table.copy()
    table.loc["Mu", "theirs"] = -0.5          # both real: no switch between them
    flat = dataclasses.replace(comparison, table=table)
    with pytest.raises(ValueError, match="no threshold"):
        cfd.mode_type_threshold(flat, "ours")


def test_the_hinge_height_law_fitted_over_the_orbits_is_the_minus_h_xu_over_c_law(physics,
                                                                                   comparison):
    """Six orbits (h = 0 ... 4 h_source) on one line of slope -X_u+/c; 1 % as above."""
    law = cfd.mu_law(physics, comparison, "hinge_height")
    assert len(law.values) == 6 and law.values[0] == 0.0
    xu, c = comparison.table.loc["Xu", "ours"], comparison.study.value("mean_chord")
    assert law.slope == pytest.approx(-xu / c, rel=0.01)
    assert law.max_residual < 0.01 * abs(law.slope) * law.values[-1]
    h0 = law.value_for(0.0)
    assert h0 == pytest.approx(cfd.hinge_height_for(comparison, 0.0), rel=0.01)


def test_the_centre_of_pressure_law_needs_three_cases_and_an_insect_field(physics, comparison):
    law = cfd.mu_law(physics, comparison, "center_of_pressure")
    assert list(law.values) == [0.1, 0.25, 0.4]
    assert law.slope < 0.0           # nearer the leading edge, more nose-up M_u
    with pytest.raises(ValueError, match="at least 3"):
        cfd.mu_law(physics, comparison, "wing_mass")
    with pytest.raises(ValueError, match="Insect field"):
        cfd.mu_law(physics, comparison, "wingspan")


# ------------------------------------------------------------------ the trim's angle of attack
@pytest.fixture(scope="module")
def angle_table():
    return cfd.angle_of_attack_table("sun2005")


@pytest.fixture(scope="module")
def type_change(angle_table):
    return cfd.type_change_angle("sun2005", table=angle_table)


def test_the_table_at_the_eq40_angle_is_the_comparison(comparison):
    """Holding alpha_m at eq. (40)'s own value is compare()'s default solve: the same orbit, so
    the same numbers to the hover solve's tolerance (the angle goes through degrees and back,
    a change of a few ulp)."""
    alpha_deg = math.degrees(comparison.orbit.alpha_m)
    row = cfd.angle_of_attack_table("sun2005", [alpha_deg]).iloc[0]
    assert row["alpha_m_deg"] == pytest.approx(alpha_deg, rel=1e-14)
    assert row["stroke_amplitude_deg"] == pytest.approx(
        comparison.trim["our_stroke_amplitude_deg"], rel=1e-8)
    for name in ("Xu", "Zw", "Mu", "Mq"):
        assert row[name] == pytest.approx(comparison.table.loc[name, "ours"], rel=1e-6), name
    assert row["leading_multiplier"] == pytest.approx(comparison.our_multipliers[0], rel=1e-8)
    assert row["averaged_eigenvalue"] == pytest.approx(comparison.our_eigenvalues[0], rel=1e-6)
    assert (row["averaged_type"], row["floquet_type"]) == ("real", "real")


def test_the_angles_are_held_and_the_amplitude_trims_instead(angle_table):
    np.testing.assert_allclose(angle_table["alpha_m_deg"], cfd.ANGLES_DEG, rtol=1e-12)
    # a larger angle of attack carries the weight with a smaller stroke, up to 40 deg
    upto40 = angle_table[angle_table.alpha_m_deg <= 40.0]
    assert np.all(np.diff(upto40["stroke_amplitude_deg"]) < 0.0)


def test_mu_and_the_wing_drag_grow_with_the_angle_of_attack(angle_table):
    """M_u+ rises monotonically with alpha_m, and so does the drag derivative -X_u+ that the
    hinge above the CG turns into it."""
    assert np.all(np.diff(angle_table["Mu"]) > 0.0)
    assert np.all(np.diff(angle_table["Xu"]) < 0.0)
    assert angle_table["Mu"].iloc[0] < 0.0 < angle_table["Mu"].iloc[-1]


def test_the_averaged_type_flips_where_mu_changes_sign(angle_table):
    """Row by row: our averaged leading mode oscillates exactly where M_u+ > 0 (the threshold of
    mode_type_threshold, ~1e-3, lies below every |M_u+| of the table)."""
    oscillatory = angle_table["averaged_type"] == "oscillatory"
    assert (oscillatory == (angle_table["Mu"] > 0.0)).all()
    assert oscillatory.any() and not oscillatory.all()


def test_at_the_mu_zero_angle_mu_vanishes_and_the_types_straddle_it(type_change):
    """Route 1's root is a root, and the averaged type changes within 0.1 deg of it (0.1 deg of
    alpha_m moves M_u+ by ~2e-3, above mode_type_threshold's ~1e-3)."""
    lo, hi = type_change.averaged_bracket
    assert lo < type_change.mu_zero < hi
    below, at, above = (cfd.compare("sun2005", alpha_m=type_change.mu_zero + d)
                        for d in (-math.radians(0.1), 0.0, math.radians(0.1)))
    assert abs(at.table.loc["Mu", "ours"]) < 1e-3
    assert below.our_mode["type"] == "real" and above.our_mode["type"] == "oscillatory"


def test_the_floquet_type_changes_inside_its_final_bracket(type_change):
    half = 0.5 * type_change.xtol
    below, above = (cfd.compare("sun2005", alpha_m=type_change.floquet + d) for d in (-half, half))
    assert below.our_floquet_mode["type"] == "real"
    assert above.our_floquet_mode["type"] == "oscillatory"


def test_the_two_routes_to_the_type_change_agree_within_a_degree(type_change, angle_table):
    """Averaging drops the periodic terms, first order in the wingbeat over the modes' time
    scale (T |lambda| ~ 0.035 for the fastest averaged mode here), so the Floquet flip need not
    sit at M_u+ = 0 exactly. Agreement is asked on the scale of the question, CFD's M_u+: a
    degree of alpha_m moves our M_u+ by ~0.02 (the table's slope near the root), under 1 % of
    CFD's 2.389. The bisection's own width (0.1 deg) is inside that."""
    assert abs(type_change.gap_deg) < 1.0
    ends = angle_table[np.isin(np.radians(angle_table.alpha_m_deg).round(12),
                               np.round(type_change.averaged_bracket, 12))]
    assert len(ends) == 2
    slope = np.diff(ends.Mu).item() / np.diff(ends.alpha_m_deg).item()   # M_u+ per degree
    assert abs(slope * type_change.gap_deg) < 0.01 * cfd.study("sun2005").derivatives["Mu"].value
    assert type_change.nfev > 0


@pytest.mark.parametrize("bad", [0.0, 90.0, -5.0, 120.0, float("nan"), "20", True])
def test_the_angle_table_refuses_an_angle_outside_0_90_deg(bad):
    with pytest.raises(ValueError, match=r"alphas_deg.*\(0, 90\) deg"):
        cfd.angle_of_attack_table("sun2005", [20.0, bad])


def test_the_angle_functions_refuse_bad_options(angle_table):
    with pytest.raises(ValueError, match="alphas_deg"):
        cfd.angle_of_attack_table("sun2005", [])
    with pytest.raises(ValueError, match="alpha_m"):
        cfd.angle_of_attack_table("sun2005", [20.0], alpha_m=0.3)
    with pytest.raises(ValueError, match="xtol_deg"):
        cfd.type_change_angle("sun2005", table=angle_table, xtol_deg=0.0)
    real_only = angle_table[angle_table.Mu < 0.0]
    with pytest.raises(ValueError, match="no bracket"):
        cfd.type_change_angle("sun2005", table=real_only)

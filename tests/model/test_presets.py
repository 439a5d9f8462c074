"""The species presets (flapping.model.presets): sources, estimates, and a hover orbit for each."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import flapping
from flapping.hover import find_hover_orbit
from flapping.hover.stability import hover_stability
from flapping.model import morphology, presets
from flapping.model.presets import (
    PRESETS,
    STATUSES,
    Sourced,
    ellington_r1,
    ellipsoid_pitch_inertia,
    preset,
    preset_names,
    species_table,
)

NAMES = preset_names()


def test_at_least_six_presets_with_the_required_species():
    assert len(NAMES) >= 6
    assert {"hawkmoth", "bumblebee", "fruit_fly", "honeybee", "hoverfly"} <= set(NAMES)


def test_hawkmoth_is_the_papers_preset_unchanged():
    assert preset("hawkmoth") == morphology.hawkmoth() == flapping.hawkmoth()
    assert presets.hawkmoth is morphology.hawkmoth


@pytest.mark.parametrize("name", NAMES)
def test_each_preset_builds_its_insect_with_its_name(name):
    insect = preset(name)
    assert insect.name == name
    assert getattr(presets, name)() == insect  # the documented function of the same name
    for field, src in PRESETS[name].values.items():
        assert getattr(insect, field) == src.value


@pytest.mark.parametrize("name", NAMES)
def test_every_number_has_a_source_and_a_status(name):
    for src in [*PRESETS[name].values.values(), *PRESETS[name].extras.values()]:
        assert src.source.strip()
        assert src.status in STATUSES
        if src.status in ("unverified", "estimate") and src in PRESETS[name].values.values():
            assert src.has_range, f"{name}: an uncertain number needs a plausible range"


@pytest.mark.parametrize("name", NAMES)
def test_an_estimated_r1_follows_ellingtons_fit_from_r2(name):
    values = PRESETS[name].values
    if values["r1"].status == "estimate":
        r1, r2 = values["r1"].value, values["r2"].value
        assert 0.929 * r1**0.732 == pytest.approx(r2, rel=1e-12)


def test_ellington_fit_direction_keeps_r1_below_r2():
    # The reversed fit r1 = 0.929 r2^0.732 would give r1 = 0.600 > r2 = 0.55 (no planform).
    for r2 in np.linspace(0.45, 0.65, 21):
        r1 = ellington_r1(r2)
        assert r1 < r2 < math.sqrt(r1)
    with pytest.raises(ValueError, match="r2"):
        ellington_r1(0.95)


def test_ellipsoid_inertia_of_a_sphere_is_two_fifths_m_r_squared():
    m, r = 2.0, 0.3
    assert ellipsoid_pitch_inertia(m, 2 * r, 2 * r) == pytest.approx(0.4 * m * r**2, rel=1e-15)


def test_ellipsoid_inertia_is_within_five_percent_of_the_papers_hawkmoth():
    # The method's check (module docstring): L = 48 mm, d = 10 mm against the paper's 2080 mg cm^2.
    estimate = ellipsoid_pitch_inertia(1.648e-3, 48e-3, 10e-3)
    assert abs(estimate / flapping.hawkmoth().pitch_inertia - 1.0) < 0.05


def test_monarch_inertia_is_fwuavs_two_bodies_about_their_joint_cg():
    # Independent route: moments about the thorax centre, then one parallel-axis shift to the CG.
    m_b, m_a = 1.485e-4, 1.092e-4
    x_a = -(7.315e-3 + 8.69e-3)
    j_a_cg = m_a * (1.738e-2**2 / 3 + 3.71e-3**2 / 16) - m_a * 8.69e-3**2
    about_thorax = 2.94814204e-9 + j_a_cg + m_a * x_a**2
    x_cg = m_a * x_a / (m_b + m_a)
    expected = about_thorax - (m_b + m_a) * x_cg**2
    assert preset("monarch").pitch_inertia == pytest.approx(expected, rel=1e-12)


def test_monarch_thorax_inertia_note_gives_its_units_and_the_tables_unit():
    # The I_y column is in mg cm^2: the note's SI value must carry its unit and its conversion.
    note = PRESETS["monarch"].values["pitch_inertia"].note
    j = presets._MONARCH_THORAX_IY
    assert f"{j / 1e-9:.2f} \u00d7 10\u207b\u2079 kg m\u00b2" in note
    assert f"({j * 1e10:.3g} mg cm\u00b2)" in note  # 29.5 mg cm^2


def test_bumblebee_frequency_choice_and_its_alternative():
    assert preset("bumblebee").frequency == pytest.approx(1 / 6.4e-3)
    alternative = PRESETS["bumblebee"].extras["frequency_berman_wang"].value
    assert presets.bumblebee(frequency=alternative).frequency == 116.0


def test_unknown_preset_is_refused_with_the_names():
    with pytest.raises(ValueError, match="bumblebee"):
        preset("dragonfly")


def test_an_override_is_validated_and_named():
    with pytest.raises(ValueError, match="mass"):
        preset("honeybee", mass=-1.0)


def test_species_table_lists_every_preset():
    rows = species_table()
    assert [r["name"] for r in rows] == list(NAMES)
    for row in rows:
        p = PRESETS[row["name"]]
        assert (row["mass_kg"], row["wing_length_m"], row["frequency_hz"]) == (
            p.mass, p.semi_span, p.frequency)
        assert row["source"]


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"low": 2.0, "high": 3.0}, "low"),       # low above the value
    ({"low": 0.0, "high": 0.5}, "high"),      # high below the value
    ({"low": 0.0}, "together"),
])
def test_sourced_refuses_an_inconsistent_range(kwargs, match):
    with pytest.raises(ValueError, match=match):
        Sourced(1.0, "x", "estimate", **kwargs)


def test_sourced_refuses_an_unknown_status():
    with pytest.raises(ValueError, match="status"):
        Sourced(1.0, "x", "probably")


# ------------------------------------------------------------------ every preset hovers
def _descent_by_scipy(orbit):
    """z(T) - z(0) [m] and x(T), integrated independently with scipy (z positive down)."""
    model = orbit.model
    rhs, _ = model.segment_functions()
    edges = [0.0, *(b * orbit.period for b in model.breakpoints), orbit.period]  # fractions of T
    y = np.append(orbit.x0, 0.0)
    for k, (a, b) in enumerate(zip(edges[:-1], edges[1:], strict=True)):
        def f(t, y, _f=rhs[k]):
            u, w, _, th = y[:4]
            return np.append(_f(t, y[:4]), -u * math.sin(th) + w * math.cos(th))
        sol = solve_ivp(f, (a, b), y, method="DOP853", rtol=1e-12, atol=1e-14)
        assert sol.success
        y = sol.y[:, -1]
    return y[4], y[:4]


@pytest.fixture(scope="module", params=NAMES)
def hover(request):
    # From the default guess, on the reference path (LM shooting, adaptive DOP853 at rtol 1e-11)
    orbit = find_hover_orbit(preset(request.param), backend="adaptive")
    return orbit, hover_stability(orbit)


def test_each_preset_on_the_default_path_agrees_with_the_reference(hover):
    # The default (the compiled kernel where it applies) promises Phi to 1e-9 deg and every
    # multiplier to 1e-8; the reference's own error is ~1e-10 in both.
    ref, ref_stab = hover
    orbit = find_hover_orbit(ref.model.insect)
    stab = hover_stability(orbit)
    assert orbit.is_hover
    assert abs(orbit.amplitude_deg - ref.amplitude_deg) < 2e-9
    np.testing.assert_allclose(stab.multipliers, ref_stab.multipliers, rtol=0, atol=2e-8)


def test_each_preset_converges_from_the_default_guess_to_a_hover_orbit(hover):
    orbit, _ = hover
    assert orbit.shooting.success
    assert 0.0 < orbit.amplitude <= math.pi / 2
    assert orbit.is_hover


def test_each_preset_orbit_holds_its_altitude_by_an_independent_integration(hover):
    orbit, _ = hover
    descent, x_end = _descent_by_scipy(orbit)
    # DOP853 at rtol 1e-12 (the package's own orbit was found at 1e-11): no net descent beyond
    # 1e-9 of the vertical excursion w_max T within the period, and the state returns to its
    # start to 1e-9 of each state's range.
    excursion = np.abs(orbit.x[1]).max() * orbit.period
    assert abs(descent) < 1e-9 * excursion
    scale = np.abs(orbit.x).max(axis=1)
    assert np.all(np.abs(x_end - orbit.x0) / scale < 1e-9)


def test_each_preset_mean_vertical_speed_vanishes(hover):
    orbit, _ = hover
    speed = orbit.mean_inertial_velocity["climb"]
    assert abs(speed) < 1e-9 * orbit.wingtip_speed


def test_each_preset_satisfies_liouvilles_formula(hover):
    _, stab = hover
    # det M from the multipliers against exp(int trace J): both at rtol 1e-12 integrations.
    assert stab.liouville_error < 1e-9
    assert np.prod(stab.multipliers).real == pytest.approx(stab.det, rel=1e-9)


# ------------------------------------------------------------------------------ the sources' geometry
@pytest.mark.parametrize("name", presets.preset_names())
def test_the_paper_geometry_is_the_default_and_unchanged(name):
    assert presets.preset(name, geometry="paper") == presets.preset(name)
    insect = presets.preset(name)
    assert (insect.hinge_offset, insect.hinge_height, insect.wing_mass) == (0.0, 0.0, 0.0)


@pytest.mark.parametrize("name", presets.preset_names())
def test_the_source_geometry_sets_the_hinge_and_the_wing_mass_with_sources(name):
    p = presets.PRESETS[name]
    assert {"hinge_offset", "hinge_height", "wing_mass"} <= set(p.measured)
    insect = presets.preset(name, geometry="source")
    for field, value in p.measured.items():
        assert getattr(insect, field) == value.value
        assert value.source and value.status in presets.STATUSES
        # Anything short of a verified number carries the range a sensitivity study needs.
        assert value.status == "verified" or value.has_range
    assert insect.hinge_height > 0.0 and 0.0 < 2 * insect.wing_mass < 0.2 * insect.mass


def test_the_hoverflys_hinge_is_sun_and_xus_distance_straight_above_the_cg():
    fly = presets.preset("hoverfly", geometry="source")
    assert fly.hinge_offset == 0.0  # exactly: one trim suffices (the CLI's choice)
    assert fly.hinge_height == pytest.approx(0.13 * 1.29 * 11.2e-3)  # 0.13 body lengths


def test_hinge_geometry_places_the_hinge_on_a_circle_about_the_cg():
    x, h = presets.hinge_geometry(2e-3, math.radians(30.0))
    assert math.hypot(x, h) == pytest.approx(2e-3)
    assert math.degrees(math.atan2(h, x)) == pytest.approx(30.0)
    assert presets.hinge_geometry(1e-3, math.pi / 2)[1] == 1e-3


@pytest.mark.parametrize(("args", "match"), [((-1e-3, 0.5), "distance"), ((1e-3, 2.0), "elevation")])
def test_hinge_geometry_refuses_bad_arguments_by_name(args, match):
    with pytest.raises(ValueError, match=match):
        presets.hinge_geometry(*args)


@pytest.mark.parametrize("name", presets.preset_names())
def test_the_former_name_measured_still_works_and_warns_naming_source(name):
    with pytest.warns(DeprecationWarning, match="geometry='source'") as record:
        old = presets.preset(name, geometry="measured")
    assert old == presets.preset(name, geometry="source")
    assert record[0].filename == __file__  # the warning points at the caller's line
    with pytest.warns(DeprecationWarning, match="geometry='source'") as record:
        via_preset = presets.PRESETS[name].insect("measured")
    assert via_preset == old and record[0].filename == __file__


def test_the_source_geometry_warns_nothing():
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        presets.preset("bumblebee", geometry="source")
        presets.PRESETS["bumblebee"].insect("source")
    assert presets.GEOMETRIES == ("paper", "source")
    assert dict(presets.DEPRECATED_GEOMETRIES) == {"measured": "source"}


def test_an_unknown_geometry_is_refused_naming_the_choices():
    with pytest.raises(ValueError, match="geometry.*source"):
        presets.preset("hawkmoth", geometry="anatomical")


# ------------------------------------------------------------------------------ issue 26
def test_ranged_fields_says_why_the_hawkmoth_has_nothing_to_vary():
    # Reproducer (issue 26): morphology_sensitivity("hawkmoth", fields=["foo"]) listed the
    # allowed fields as "one of ()": the hawkmoth's numbers are all verified or the paper's.
    with pytest.raises(ValueError, match=r"hawkmoth preset has no number with a plausible range"
                                         r".*presets with uncertain numbers: bumblebee"):
        PRESETS["hawkmoth"].ranged_fields(["foo"])
    assert PRESETS["hawkmoth"].ranged_fields() == ()


def test_ranged_fields_lists_the_allowed_fields_and_refuses_a_bare_string():
    bee = PRESETS["bumblebee"]
    assert bee.ranged_fields() == tuple(bee.ranged())
    assert bee.ranged_fields(["r2"]) == ("r2",)
    with pytest.raises(ValueError, match=r"one of \('r2', 'r1'.*got 'foo'"):
        bee.ranged_fields(["foo"])
    with pytest.raises(ValueError, match="sequence of field names; got 'r2'"):
        bee.ranged_fields("r2")

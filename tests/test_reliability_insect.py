"""Reliability of Insect's magnitudes (flapping.model.morphology): overflow, zero gravity and
implausible values, checked over every numeric field rather than the three reproducers alone.

Three properties: a value beyond float64 or MAGNITUDE_LIMIT is a ValueError naming the field and
its range; any accepted insect has finite derived quantities (no OverflowError later); a value
outside PLAUSIBLE_RANGES warns (PlausibilityWarning) naming the field, the value and the range,
and no preset does.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from fractions import Fraction

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from flapping.errors import PlausibilityWarning
from flapping.model.morphology import (
    MAGNITUDE_LIMIT,
    PHYSICAL_RANGES,
    PLAUSIBLE_RANGES,
    Insect,
    beta_shape_parameters,
    explain_blowup,
    hawkmoth,
    implausible_fields,
    r2_range,
    support_amplitude,
)
from flapping.model.presets import PRESETS
from flapping.model.presets import preset as preset_insect

#: Every numeric field of Insect (read from the dataclass: a new field is covered unasked).
NUMERIC_FIELDS = [f.name for f in dataclasses.fields(Insect)
                  if f.init and f.name not in ("name", "aspect_ratio_convention")]

#: The span integrals the aerodynamic models need (m < 4, n <= 2; I_04 only where it converges).
MOMENTS = [(m, n) for m in range(4) for n in range(1, 3)]


def test_every_numeric_field_is_listed():
    assert len(NUMERIC_FIELDS) == 24
    assert set(PLAUSIBLE_RANGES) - {"aspect_ratio_1", "wing_mass_ratio"} <= set(NUMERIC_FIELDS)


def derived_quantities(insect: Insect) -> list[float]:
    """Everything the model derives from the fields before any integration."""
    return [insect.mean_chord, insect.aspect_ratio, insect.lift_slope, insect.period,
            insect.weight, insect.beta_p, insect.beta_q,
            *(insect.span_integral(m, n) for m, n in MOMENTS),
            *(row[2] for row in insect.as_table())]


# ------------------------------------------------------------------------------ overflow
@pytest.mark.parametrize("name", NUMERIC_FIELDS)
@pytest.mark.parametrize("huge", [10**400, -(10**400), 10**5000, Fraction(10**400, 3)],
                         ids=["1e400", "-1e400", "1e5000", "fraction"])
def test_a_number_beyond_float64_is_a_value_error_naming_the_field(name, huge):
    # Reproducer: hawkmoth(mass=10**400) raised OverflowError from float().
    with pytest.raises(ValueError, match=f"`{name}` must be") as error:
        hawkmoth(**{name: huge})
    assert "[" in str(error.value) or "(" in str(error.value)  # the accepted range is stated
    assert len(str(error.value)) < 400  # 10**5000 is not printed in full


@pytest.mark.parametrize("name", NUMERIC_FIELDS)
def test_a_magnitude_beyond_the_limit_is_refused(name):
    with pytest.raises(ValueError, match=f"`{name}`"):
        hawkmoth(**{name: 1e3 * MAGNITUDE_LIMIT})


@settings(max_examples=300, deadline=None)
@given(changes=st.dictionaries(st.sampled_from(NUMERIC_FIELDS),
                               st.floats(allow_nan=True, allow_infinity=True), max_size=4))
def test_any_values_give_a_named_error_or_finite_derived_quantities(changes):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)
        try:
            insect = hawkmoth(**changes)
        except ValueError as exc:
            named = set(changes) | ({"r2"} if "r1" in changes else set())  # r2's range is r1's
            assert any(f"`{name}`" in str(exc) for name in named), exc
            return
    assert all(math.isfinite(v) for v in derived_quantities(insect))


# ------------------------------------------------------------------------------ gravity
@pytest.mark.parametrize("gravity", [0, 0.0, -9.81, 1e-40])
def test_no_gravity_is_refused_naming_gravity(gravity):
    # Reproducer: hawkmoth(gravity=0) was accepted and failed later as an alpha_m error.
    with pytest.raises(ValueError, match="`gravity`"):
        hawkmoth(gravity=gravity)


# ------------------------------------------------------------------------------ plausibility
def _outside(name: str) -> list[float]:
    """Values below and above the plausible range, where the model accepts them (tenfold or
    twofold beyond the ends: the physical ranges are about ten times wider)."""
    low, high, _ = PLAUSIBLE_RANGES[name]
    step = 0.1 * (high - low)
    if low > 0:
        candidates = [(low / 10, low / 2), (high * 10, high * 2)]
    else:
        candidates = [(low - step,), (high + step,)]
    found = []
    for side in candidates:
        found += [v for v in side if _accepted(name, v)][:1]
    return found


def _changes(name: str, value: float) -> dict[str, float]:
    """``{name: value}``, with the wing's other size scaled to keep the hawkmoth's R^2/S (a
    wing length alone off the plausible range makes a needle or a sail, which is refused)."""
    ratio = hawkmoth().semi_span ** 2 / hawkmoth().wing_area
    if name == "semi_span":
        return {name: value, "wing_area": value**2 / ratio}
    if name == "wing_area":
        return {name: value, "semi_span": math.sqrt(value * ratio)}
    return {name: value}


def _accepted(name: str, value: float) -> bool:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)
        try:
            hawkmoth(**_changes(name, value))
        except ValueError:
            return False
    return True


#: Ranges of derived quantities, not fields.
DERIVED = ("aspect_ratio_1", "wing_mass_ratio")
FIELD_CASES = [(name, value) for name in PLAUSIBLE_RANGES if name not in DERIVED
               for value in _outside(name)]


def test_wings_heavier_than_a_quarter_of_the_insect_warn():
    with pytest.warns(PlausibilityWarning, match="2 wing_mass / mass"):
        hawkmoth(wing_mass=0.3e-3)


@pytest.mark.parametrize("name, value", FIELD_CASES)
def test_an_implausible_value_warns_naming_field_value_and_range(name, value):
    low, high, _ = PLAUSIBLE_RANGES[name]
    with pytest.warns(PlausibilityWarning, match=f"`{name}`") as caught:
        hawkmoth(**_changes(name, value))
    message = next(str(w.message) for w in caught if f"`{name}`" in str(w.message))
    assert f"{value:.6g}" in message and f"[{low:.6g}, {high:.6g}]" in message


def test_every_plausibility_range_is_exercised():
    # Each listed field has a value the model accepts and the table calls implausible.
    assert {name for name, _ in FIELD_CASES} == set(PLAUSIBLE_RANGES) - set(DERIVED)


def test_a_terahertz_wing_beat_is_refused_naming_the_physical_range():
    # Reproducer (issue 26): hawkmoth(frequency=1e12) "hovered" at 4406 m/s with a warning only.
    with pytest.raises(ValueError, match=r"`frequency` must be a real number in "
                                         r"\[0.1, 10000\] Hz; got 1000000000000.0"):
        hawkmoth(frequency=1e12)


@pytest.mark.parametrize("area", [1e-4, 1e-2])
def test_a_needle_or_a_sail_warns_about_the_aspect_ratio(area):
    # R^2/S of the hawkmoth's 51.9 mm wing: 27 with 1 cm^2, 0.27 with 100 cm^2.
    with pytest.warns(PlausibilityWarning, match="semi_span\\*\\*2 / wing_area"):
        hawkmoth(wing_area=area)


@pytest.mark.parametrize("area", [1e-7, 1.0])
def test_a_wing_no_planform_has_is_refused_naming_both_sizes(area):
    # R^2/S = 2.7e4 (a 2 um chord on a 52 mm wing) or 2.7e-3 (a 19 m chord): no wing.
    with pytest.raises(ValueError, match=r"`semi_span`\*\*2 / `wing_area`.* must be in "
                                         r"\[0.05, 200\]"):
        hawkmoth(wing_area=area)


@settings(max_examples=100, deadline=None)
@given(data=st.data())
def test_plausible_values_are_accepted_without_a_warning(data):
    name = data.draw(st.sampled_from([n for n in PLAUSIBLE_RANGES if n not in DERIVED]))
    low, high, _ = PLAUSIBLE_RANGES[name]
    changes = {name: data.draw(st.floats(low, high))}
    ratio = hawkmoth().semi_span ** 2 / hawkmoth().wing_area  # keep the hawkmoth's R^2/S
    if name == "semi_span":
        changes["wing_area"] = _clip(changes[name] ** 2 / ratio, "wing_area")
    elif name == "wing_area":
        changes["semi_span"] = _clip(math.sqrt(changes[name] * ratio), "semi_span")
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        hawkmoth(**changes)


def _clip(value: float, name: str) -> float:
    low, high, _ = PLAUSIBLE_RANGES[name]
    return min(max(value, low), high)


def _preset_insects():
    for name, preset in PRESETS.items():
        yield name, {}
        for field, sourced in preset.ranged().items():
            yield name, {field: sourced.low}
            yield name, {field: sourced.high}


@pytest.mark.parametrize("name, changes", list(_preset_insects()))
def test_no_preset_or_preset_range_end_warns(name, changes):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        PRESETS[name].insect(**changes)


def test_the_default_hawkmoth_does_not_warn():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        hawkmoth()
        Insect(**{f.name: getattr(hawkmoth(), f.name) for f in dataclasses.fields(Insect)
                  if f.init})


# ------------------------------------------------------------------------------ physical ranges
def _beyond(name: str) -> list[float]:
    """A value just below and one just above the physical range of ``name``."""
    low, high, _ = PHYSICAL_RANGES[name]
    return [low / 2 if low > 0 else low - 1.0, 2 * high if high > 0 else high + 1.0]


@pytest.mark.parametrize("name, value", [(name, value) for name in PHYSICAL_RANGES
                                         for value in _beyond(name)])
def test_a_value_beyond_the_physical_range_is_refused_naming_field_and_range(name, value):
    low, high, _ = PHYSICAL_RANGES[name]
    with pytest.raises(ValueError, match=f"`{name}` must be a real number in") as error:
        hawkmoth(**{name: value})
    message = str(error.value)
    assert f"{low:g}" in message or name == "stroke_amplitude"  # (in rad: 0.0174533)
    assert f"{high:g}" in message or name == "stroke_amplitude"


@pytest.mark.parametrize("name, value", [("mass", 1e-12), ("semi_span", 10.0),
                                         ("frequency", 1e12), ("pitch_inertia", 1e3),
                                         ("air_density", 1e3), ("stroke_amplitude", 1e-3)])
def test_absurd_insects_of_the_user_test_are_refused_at_construction(name, value):
    # Reproducers (issue 26): mass=1e-12 and semi_span=10 ended in "`fun` returned a
    # non-finite value" deep in the hover solve; frequency=1e12 "hovered" at 4406 m/s.
    with pytest.raises(ValueError, match=f"`{name}` must be"):
        hawkmoth(**{name: value})


@pytest.mark.parametrize("r1", [0.3, 0.44, 0.5, 0.7])
def test_r2_is_refused_with_ellingtons_admissible_range_not_1e30(r1):
    # Reproducer: the message of a bad r2 quoted the range [-1e+30, 1e+30].
    low, high = r2_range(r1)
    for r2 in (r1 - 0.01, high + 0.01, math.nan):
        with pytest.raises(ValueError, match="`r2` must") as error:
            hawkmoth(r1=r1, r2=r2)
        assert "1e+30" not in str(error.value)
        if not math.isnan(r2):
            assert f"{high:.6g}" in str(error.value) and f"{low:.6g}" in str(error.value)
    hawkmoth(r1=r1, r2=0.5 * (low + high))  # the middle of the range is a planform


def test_r2_range_ends_where_the_squared_chord_stops_being_integrable():
    # At the upper end the smaller beta shape parameter is 1/2 (I_02 diverges there).
    for r1 in (0.2, 0.44, 0.6):
        low, high = r2_range(r1)
        p, q = beta_shape_parameters(r1, high * (1 - 1e-9))
        assert min(p, q) == pytest.approx(0.5, rel=1e-6) and low == r1


# ------------------------------------------------------------------------------ culprits
def test_a_plausible_insect_has_no_implausible_field():
    assert hawkmoth().implausible_fields() == {}
    assert explain_blowup(hawkmoth()) == ""
    for name in PRESETS:
        for geometry in ("paper", "source"):
            assert implausible_fields(preset_insect(name, geometry=geometry)) == {}, (name, geometry)


@pytest.mark.parametrize("changes, culprits", [
    ({"mass": 1e-8}, {"mass", "pitch_inertia"}),    # plausible alone: 1e-5 of the hawkmoth
    ({"pitch_inertia": 1e-15}, {"pitch_inertia", "mass"}),
    ({"frequency": 5e3}, {"frequency"}),
    ({"wing_area": 1e-4}, {"semi_span", "wing_area"}),
    ({"hinge_height": 0.3}, {"hinge_height"}),
    ({"mass": 5.0}, {"mass", "pitch_inertia"}),     # a 5 kg hawkmoth, too light to pitch
    ({"mass": 8e-3, "pitch_inertia": 8e-7}, {"mass"}),  # too heavy to lift at 90 deg
])
def test_implausible_fields_name_the_culprits_of_a_blowup(changes, culprits):
    # Reproducer (issue 26): such insects ended in "`fun` returned a non-finite value" (or a
    # diverging amplitude) without naming a field; the hover layer can now say which.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)
        insect = hawkmoth(**changes)
    found = insect.implausible_fields()
    assert set(found) == culprits
    text = explain_blowup(insect)
    assert text.startswith("likely cause: ") and all(f"`{name}`" in text for name in culprits)


def test_support_amplitude_is_eq_40_at_45_degrees():
    # The hawkmoth's nominal 60.5 deg at its trimmed alpha_m carries the weight; at 45 deg less.
    moth = hawkmoth()
    phi = support_amplitude(moth)
    k21 = 0.5 * moth.air_density * moth.lift_slope * moth.span_integral(2, 1)
    assert 2 * math.pi**2 * moth.frequency**2 * phi**2 * k21 == pytest.approx(moth.weight)
    assert phi < moth.stroke_amplitude
    with pytest.raises(ValueError, match="`insect`"):
        support_amplitude("hawkmoth")

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
from flapping.model.morphology import MAGNITUDE_LIMIT, PLAUSIBLE_RANGES, Insect, hawkmoth
from flapping.model.presets import PRESETS

#: Every numeric field of Insect (read from the dataclass: a new field is covered unasked).
NUMERIC_FIELDS = [f.name for f in dataclasses.fields(Insect)
                  if f.init and f.name not in ("name", "aspect_ratio_convention")]

#: The span integrals the aerodynamic models need (m < 4, n <= 2; I_04 only where it converges).
MOMENTS = [(m, n) for m in range(4) for n in range(1, 3)]


def test_every_numeric_field_is_listed():
    assert len(NUMERIC_FIELDS) == 21
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
    """A value below and one above the plausible range, where the model accepts them."""
    low, high, _ = PLAUSIBLE_RANGES[name]
    step = 0.1 * (high - low)
    below, above = (low / 10, high * 10) if low > 0 else (low - step, high + step)
    return [v for v in (below, above) if _accepted(name, v)]


def _accepted(name: str, value: float) -> bool:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)
        try:
            hawkmoth(**{name: value})
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
        hawkmoth(**{name: value})
    message = next(str(w.message) for w in caught if f"`{name}`" in str(w.message))
    assert f"{value:.6g}" in message and f"[{low:.6g}, {high:.6g}]" in message


def test_every_plausibility_range_is_exercised():
    # Each listed field has a value the model accepts and the table calls implausible.
    assert {name for name, _ in FIELD_CASES} == set(PLAUSIBLE_RANGES) - set(DERIVED)


def test_a_one_megahertz_wing_beat_warns():
    # Reproducer: hawkmoth(frequency=1e12) "hovered" at 4406 m/s without a word.
    with pytest.warns(PlausibilityWarning, match=r"`frequency` = 1e\+12 Hz"):
        hawkmoth(frequency=1e12)


@pytest.mark.parametrize("area", [1e-7, 1e-2])
def test_a_needle_or_a_sail_warns_about_the_aspect_ratio(area):
    # R^2/S of the hawkmoth's 51.9 mm wing: 27 with 0.1 mm^2, 0.27 with 100 cm^2.
    with pytest.warns(PlausibilityWarning, match="semi_span\\*\\*2 / wing_area"):
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

"""A user's insect from a TOML or JSON file (flapping.model.insect_file)."""

import dataclasses
import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from flapping.model.insect_file import (
    INSECT_FIELDS,
    REQUIRED_FIELDS,
    insect_from_mapping,
    load_insect,
    resolve_insect,
)
from flapping.model.presets import preset


def _fields(insect):
    # None (the wing-mass radii's "as the area's") has no TOML spelling: a file leaves it out.
    return {f.name: getattr(insect, f.name) for f in dataclasses.fields(insect)
            if f.init and getattr(insect, f.name) is not None}


def _toml(values):
    def fmt(v):
        return json.dumps(v) if isinstance(v, str) else repr(float(v))
    return "\n".join(f"{k} = {fmt(v)}" for k, v in values.items()) + "\n"


@pytest.mark.parametrize("suffix", [".toml", ".json"])
def test_a_full_file_gives_the_same_insect(tmp_path, suffix):
    bee = preset("bumblebee")
    path = tmp_path / f"bee{suffix}"
    values = _fields(bee)
    path.write_text(_toml(values) if suffix == ".toml" else json.dumps(values))
    assert load_insect(path) == bee


def test_a_file_may_start_from_a_preset(tmp_path):
    path = tmp_path / "heavy.toml"
    path.write_text('preset = "bumblebee"\nname = "heavy_bee"\nmass = 1.8e-4\n')
    insect = load_insect(path)
    assert insect == preset("bumblebee", name="heavy_bee", mass=1.8e-4)


@pytest.mark.parametrize(("value", "shown"), [('"heavy"', "'heavy'"), ("-1.0", "-1.0"),
                                               ("true", "True"), ("nan", "nan")])
def test_a_bad_value_is_refused_naming_the_field_and_the_file(tmp_path, value, shown):
    values = _fields(preset("honeybee"))
    text = _toml({k: v for k, v in values.items() if k != "mass"}) + f"mass = {value}\n"
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(ValueError) as err:
        load_insect(path)
    message = str(err.value)
    assert "`mass`" in message and str(path) in message and shown in message


def test_an_unknown_key_is_named_with_the_accepted_ones(tmp_path):
    path = tmp_path / "typo.toml"
    path.write_text('preset = "hawkmoth"\nwingarea = 1e-3\n')
    with pytest.raises(ValueError, match="unknown field 'wingarea'.*wing_area"):
        load_insect(path)


def test_missing_fields_are_named(tmp_path):
    path = tmp_path / "short.json"
    path.write_text(json.dumps({"name": "x", "semi_span": 0.01}))
    with pytest.raises(ValueError, match="missing field 'wing_area'"):
        load_insect(path)
    assert set(REQUIRED_FIELDS) < set(INSECT_FIELDS)


@pytest.mark.parametrize(("name", "text", "match"), [
    ("bad.toml", "mass = = 1", "not valid TOML"),
    ("bad.json", "{mass: 1}", "not valid JSON"),
    ("list.json", "[1, 2]", "table of insect fields"),
    ("bad.yaml", "mass: 1", "must end in .toml or .json"),
    ("preset.toml", 'preset = "dragonfly"', "`preset` must be one of"),
])
def test_unreadable_content_is_refused_with_the_file_named(tmp_path, name, text, match):
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(ValueError, match=match) as err:
        load_insect(path)
    assert str(path) in str(err.value)


def test_a_missing_file_is_a_value_error_naming_it(tmp_path):
    with pytest.raises(ValueError, match="cannot read"):
        load_insect(tmp_path / "absent.toml")


def test_resolve_takes_a_preset_name_or_a_file(tmp_path):
    assert resolve_insect("fruit_fly") == preset("fruit_fly")
    path = tmp_path / "fly.json"
    path.write_text(json.dumps({"preset": "fruit_fly", "mass": 8e-7}))
    assert resolve_insect(str(path)).mass == 8e-7
    with pytest.raises(ValueError, match="unknown insect 'dragonfly'.*hawkmoth"):
        resolve_insect("dragonfly")


def test_mapping_must_be_a_mapping():
    with pytest.raises(ValueError, match="table"):
        insect_from_mapping([("mass", 1.0)])


@settings(max_examples=40, deadline=None)
@given(mass=st.floats(1e-7, 1e-2), inertia=st.floats(1e-14, 1e-6))
def test_numbers_survive_the_file_exactly(tmp_path_factory, mass, inertia):
    # TOML and JSON both print a float's shortest round-trip representation.
    path = tmp_path_factory.mktemp("h") / "x.toml"
    path.write_text(f'preset = "hoverfly"\nmass = {mass!r}\npitch_inertia = {inertia!r}\n')
    insect = load_insect(path)
    assert (insect.mass, insect.pitch_inertia) == (mass, inertia)

"""The presets on the command line, run as a user would (subprocesses of `python -m flapping`)."""

import json
import subprocess
import sys

import pytest

from flapping.model.presets import preset, preset_names

HOVER_KEYS = {"version", "insect", "insect_parameters", "aerodynamics", "amplitude_deg",
              "alpha_m_deg", "initial_state", "period_s", "residual_norm",
              "mean_inertial_velocity", "mean_horizontal_velocity", "mean_vertical_velocity",
              "is_hover", "multipliers", "floquet_exponents", "det_monodromy", "liouville_det",
              "liouville_error", "averaged_eigenvalues", "stable", "solver", "units"}


def run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "flapping", *args], capture_output=True,
                          text=True, timeout=300, cwd=cwd)


def test_species_lists_every_preset_as_json():
    out = run("species", "--json")
    assert out.returncode == 0, out.stderr
    rows = json.loads(out.stdout)
    assert [r["name"] for r in rows] == list(preset_names())
    for row in rows:
        assert set(row) == {"name", "species", "mass_kg", "wing_length_m", "frequency_hz",
                            "source", "measured_geometry"}
        measured = preset(row["name"], geometry="source")
        geometry = row["measured_geometry"]
        assert set(geometry) == {"hinge_offset_m", "hinge_height_m", "wing_mass_kg"}
        assert geometry["hinge_height_m"]["value"] == measured.hinge_height
        assert geometry["wing_mass_kg"]["value"] == measured.wing_mass
        assert all(entry["source"] and entry["status"] for entry in geometry.values())
        insect = preset(row["name"])
        assert (row["mass_kg"], row["wing_length_m"], row["frequency_hz"]) == (
            insect.mass, insect.semi_span, insect.frequency)


def test_species_text_has_one_line_per_preset():
    out = run("species")
    assert out.returncode == 0, out.stderr
    lines = out.stdout.strip().splitlines()
    assert len(lines) == 1 + len(preset_names())
    assert all(line.split()[0] == name for line, name in zip(lines[1:], preset_names(),
                                                             strict=True))


@pytest.mark.parametrize("name", preset_names())
def test_hover_works_for_every_listed_name(name):
    out = run("hover", "--insect", name, "--json")
    assert out.returncode == 0, out.stderr
    report = json.loads(out.stdout)
    assert set(report) >= HOVER_KEYS
    assert report["insect"] == name and report["is_hover"]
    assert report["insect_parameters"]["mass"] == preset(name).mass


@pytest.mark.parametrize("suffix", [".toml", ".json"])
def test_hover_loads_a_users_insect_file(tmp_path, suffix):
    path = tmp_path / f"bee{suffix}"
    if suffix == ".toml":
        path.write_text('preset = "bumblebee"\nname = "heavy_bee"\nmass = 1.8e-4\n')
    else:
        path.write_text(json.dumps({"preset": "bumblebee", "name": "heavy_bee", "mass": 1.8e-4}))
    out = run("hover", "--insect", str(path), "--json")
    assert out.returncode == 0, out.stderr
    report = json.loads(out.stdout)
    assert report["insect"] == "heavy_bee" and report["insect_parameters"]["mass"] == 1.8e-4


@pytest.mark.parametrize(("spec", "text", "expected"), [
    ("dragonfly", None, "unknown insect 'dragonfly'"),
    ("absent.toml", None, "cannot read"),
    ("bad.toml", 'preset = "bumblebee"\nmass = "heavy"\n', "`mass`"),
    ("typo.json", '{"preset": "bumblebee", "mas": 1e-4}', "unknown field 'mas'"),
])
def test_a_bad_name_or_file_is_one_line_and_exit_2(tmp_path, spec, text, expected):
    if text is not None:
        (tmp_path / spec).write_text(text)
    out = run("hover", "--insect", spec, cwd=tmp_path)
    assert out.returncode == 2
    assert out.stdout == ""
    assert len(out.stderr.strip().splitlines()) == 1
    assert expected in out.stderr and "Traceback" not in out.stderr


@pytest.mark.parametrize("name", ["hoverfly", "bumblebee"])
def test_hover_at_the_source_geometry_trims_the_stroke_where_the_hinge_is_off_the_cg(name):
    out = run("hover", "--insect", name, "--geometry", "source", "--json")
    assert out.returncode == 0, out.stderr
    report = json.loads(out.stdout)
    assert set(report) >= HOVER_KEYS  # the keys of the paper geometry stay
    insect = preset(name, geometry="source")
    assert report["insect_parameters"]["wing_mass"] == insect.wing_mass
    assert report["trims"] == (["amplitude"] if insect.hinge_offset == 0.0
                               else ["amplitude", "stroke_mean"])
    assert report["is_hover"]
    if insect.hinge_offset > 0.0:  # the mean lift returns over a CG behind the hinge
        assert report["stroke_mean_deg"] < 0.0


def test_the_former_geometry_name_still_runs_and_warns_once_naming_source():
    new = run("hover", "--insect", "hoverfly", "--geometry", "source", "--json")
    old = run("hover", "--insect", "hoverfly", "--geometry", "measured", "--json")
    assert old.returncode == 0, old.stderr
    assert json.loads(old.stdout)["multipliers"] == json.loads(new.stdout)["multipliers"]
    warned = [line for line in old.stderr.splitlines() if "deprecated" in line]
    assert len(warned) == 1 and "geometry='source'" in warned[0]
    assert "deprecated" not in new.stderr


def test_the_geometry_help_says_estimated_and_names_both_spellings():
    out = run("hover", "--help")
    assert out.returncode == 0
    text = " ".join(out.stdout.split())
    assert "estimated" in text and "{paper,source,measured}" in text
    assert "deprecated name of 'source'" in text


def test_geometry_applies_to_presets_only(tmp_path):
    path = tmp_path / "bee.toml"
    path.write_text('preset = "bumblebee"\n')
    out = run("hover", "--insect", str(path), "--geometry", "source")
    assert out.returncode == 2
    assert "--geometry" in out.stderr and len(out.stderr.strip().splitlines()) <= 2

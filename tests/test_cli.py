"""The command line (flapping.cli): `flapping` and `python -m flapping`."""

import json
import math
import subprocess
import sys

import pytest

import flapping
from flapping import cli
from flapping.hover import find_hover_orbit
from flapping.hover.stability import hover_stability

# The keys of `hover --json` before the report grew (checked from outside: names and meanings
# must not change), and the ones added with it.
ORIGINAL_KEYS = {"insect", "aerodynamics", "amplitude_deg", "alpha_m_deg", "initial_state",
                 "period_s", "residual_norm", "mean_inertial_velocity", "multipliers",
                 "floquet_exponents", "det_monodromy", "liouville_det", "averaged_eigenvalues",
                 "stable"}
ADDED_KEYS = {"version", "insect_parameters", "solver", "liouville_error",
              "mean_horizontal_velocity", "mean_vertical_velocity", "is_hover", "units",
              "status", "backend",  # status and backend: one hover problem (issue 17)
              "trims", "stroke_mean_deg", "continued_from"}  # measured geometry (issue 18)


def strict_loads(text):
    """json.loads that refuses NaN and +-Infinity, as strict parsers (and RFC 8259) do."""
    def refuse(constant):
        raise ValueError(f"non-finite number {constant} in the JSON output")
    return json.loads(text, parse_constant=refuse)


@pytest.fixture(scope="module")
def report():
    return cli.hover_report("hawkmoth", "linear")


def test_version(capsys):
    with pytest.raises(SystemExit) as exit_:
        cli.main(["--version"])
    assert exit_.value.code == 0
    assert capsys.readouterr().out.strip() == f"flapping {flapping.__version__}"


@pytest.mark.parametrize("argv", [["--help"], ["hover", "--help"]])
def test_help_states_the_exit_codes_and_units(capsys, argv):
    with pytest.raises(SystemExit) as exit_:
        cli.main(argv)
    assert exit_.value.code == 0
    text = capsys.readouterr().out
    assert "exit status" in text
    for line in ("0  success", "1  the solver failed", "2  bad command-line arguments"):
        assert line in text
    assert "SI" in text or "[m/s]" in text
    assert cli.__doc__.splitlines()[0] not in text  # a written description, not the docstring


def test_hover_help_names_every_json_key(capsys):
    with pytest.raises(SystemExit):
        cli.main(["hover", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    for key in ORIGINAL_KEYS | ADDED_KEYS:
        assert key in text, key


def test_json_in_process_is_strict_and_complete(capsys, report):
    assert cli.main(["hover", "--json"]) == 0
    out = capsys.readouterr()
    parsed = strict_loads(out.out)
    assert set(parsed) == ORIGINAL_KEYS | ADDED_KEYS
    expected = strict_loads(json.dumps(report))
    for times in (parsed, expected):  # the wall-clock times differ from run to run
        assert times["solver"]["ran"].pop("solve_time_s") > 0.0
        assert times["solver"]["ran"].pop("stability_time_s") > 0.0
    assert parsed == expected  # what hover_report returns, exactly (times aside)


def test_json_report_agrees_with_the_library(report):
    orbit = find_hover_orbit(flapping.hawkmoth())
    assert report["amplitude_deg"] == orbit.amplitude_deg
    assert report["period_s"] == orbit.period
    assert report["mean_horizontal_velocity"] == orbit.mean_inertial_velocity["forward"]
    assert report["mean_vertical_velocity"] == orbit.mean_inertial_velocity["climb"]
    assert report["is_hover"] is True
    assert report["status"] == "hover" and report["backend"] in ("compiled", "adaptive")
    assert report["version"] == flapping.__version__
    assert report["insect"] == "hawkmoth"
    assert report["insect_parameters"]["mass"] == flapping.hawkmoth().mass
    assert report["insect_parameters"]["hinge_offset"] == 0.0
    mu = report["multipliers"][0]
    assert report["floquet_exponents"][0]["re"] == pytest.approx(
        math.log(math.hypot(mu["re"], mu["im"])) / report["period_s"], rel=1e-12)
    assert report["liouville_error"] < 1e-9


def test_json_states_the_solver_settings_it_ran_with(report):
    shooting, stability = report["solver"]["shooting"], report["solver"]["stability"]
    assert (shooting["method"], shooting["rtol"], shooting["atol"], shooting["tol"]) == (
        "DOP853", 1e-11, 1e-12, 1e-10)
    assert (stability["method"], stability["rtol"], stability["atol"]) == ("DOP853", 1e-12, 1e-12)
    assert shooting["success"] is True
    assert shooting["nit"] >= 1 and shooting["nfev"] > shooting["nit"]


def test_json_says_what_ran_with_its_options_estimates_and_times(report):
    # Reproducer (issue 35): the solver block printed Adaptive()'s DOP853 tolerances whatever
    # ran; the compiled path ran (the default for the linear loads).
    ran = report["solver"]["ran"]
    assert ran["backend"] == report["backend"] == "compiled"
    assert set(ran["options"]) == {"n_steps", "amplitude_tol_deg", "multiplier_tol"}
    assert ran["n_steps"] >= 4 and 0.0 < ran["amplitude_error_deg"] <= 1e-9
    assert 0.0 < ran["multiplier_error"] <= 1e-8 and ran["solve_time_s"] > 0.0
    adaptive = cli._ran(find_hover_orbit(flapping.hawkmoth(), backend="adaptive"),
                        hover_stability(find_hover_orbit(flapping.hawkmoth())), 0.1)
    assert adaptive["options"]["method"] == "DOP853" and adaptive["x0_error"] is None


def test_every_key_has_a_unit(report):
    # The units map mirrors the report: every key (nested ones too) has an entry, and no entry
    # names a key the report lacks.
    def check(values, units, path):
        assert set(units) == set(values), path
        for key, value in values.items():
            if isinstance(value, dict) and key in units and isinstance(units[key], dict):
                check(value, units[key], f"{path}.{key}")
            elif isinstance(value, dict):  # one unit for every member
                assert isinstance(units[key], str), f"{path}.{key}"

    check({k: v for k, v in report.items() if k != "units"}, report["units"], "report")
    assert report["units"]["period_s"] == "s"
    assert report["units"]["initial_state"] == {"u": "m/s", "w": "m/s", "q": "rad/s",
                                                "theta": "rad"}
    assert report["units"]["floquet_exponents"] == "1/s"
    assert report["units"]["insect_parameters"]["pitch_inertia"] == "kg m^2"


def test_text_output(capsys):
    assert cli.main(["hover"]) == 0
    text = capsys.readouterr().out
    assert "hawkmoth hover (linear aerodynamics)" in text
    assert "hover is UNSTABLE" in text


def test_non_finite_result_exits_1_and_prints_no_number(capsys, monkeypatch):
    # Reproducer (issue 7): hawkmoth(mu1=1e6, mu2=1e6) printed NaN and -Infinity (a Floquet
    # exponent of a multiplier that underflows to 0). Damping 7.5e4 underflows it just the same
    # at a tenth of the cost. The report (hover_report raises NonFiniteResultError) refuses it:
    # exit 1, one line on stderr naming the offending keys, nothing on stdout.
    stiff = flapping.hawkmoth(mu1=7.5e4, mu2=7.5e4)
    monkeypatch.setitem(cli.PRESETS, "stiff", lambda: stiff)
    assert cli.main(["hover", "--insect", "stiff", "--json"]) == 1
    out = capsys.readouterr()
    assert out.out == ""
    assert len(out.err.strip().splitlines()) == 1
    assert "not finite" in out.err and "floquet_exponents[3].re = -inf" in out.err
    assert "Traceback" not in out.err


def test_non_finite_report_is_a_value_error():
    # So that callers catching bad input or results (ValueError) catch it too.
    assert issubclass(cli.NonFiniteResultError, ValueError)


@pytest.mark.parametrize("argv", [["hover", "--insect", "dragonfly"], ["fly"], ["hover", "--bogus"],
                                  [], ["hover", "--aerodynamics", "quadratic"]])
def test_bad_arguments_exit_2_with_one_line(capsys, argv):
    with pytest.raises(SystemExit) as exit_:
        cli.main(argv)
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
    assert err.startswith("python -m flapping")  # the subcommand's parser adds " hover"
    assert ": error: " in err


def test_the_console_script_names_itself_flapping(capsys, monkeypatch):
    monkeypatch.setattr(sys, "argv", ["/usr/local/bin/flapping", "fly"])
    with pytest.raises(SystemExit):
        cli.main()
    assert capsys.readouterr().err.startswith("flapping: error:")


def test_hover_report_refuses_an_unknown_preset():
    with pytest.raises(ValueError, match="insect"):
        cli.hover_report("dragonfly")


def _run(*args):
    return subprocess.run([sys.executable, "-m", "flapping", *args], capture_output=True,
                          text=True, timeout=300)


def test_python_m_flapping_hover_json_in_a_subprocess():
    out = _run("hover", "--json")
    assert out.returncode == 0, out.stderr
    assert out.stderr == ""
    report = strict_loads(out.stdout)
    assert set(report) >= ORIGINAL_KEYS | ADDED_KEYS
    assert set(report["initial_state"]) == {"u", "w", "q", "theta"}
    assert len(report["multipliers"]) == 4
    assert all(set(m) == {"re", "im"} for m in report["multipliers"])
    assert report["version"] == flapping.__version__

"""The command line under bad input and Ctrl-C (flapping.cli).

Every bad argument exits 2 with one line ``PROG: error: ...`` on standard error, never a
traceback; Ctrl-C exits 130 with one line, and a sweep keeps the rows it finished; JSON never
holds NaN or Infinity. Reproducers: ``--param frequency=20:32:99999999999`` exited 1 with a
traceback (numpy.linspace allocating 800 GB), and Ctrl-C printed 28 to 87 lines of traceback.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from flapping import cli
from flapping.studies.sweep import sweep_hover


def strict_loads(text):
    """json.loads that refuses NaN and +-Infinity, as strict parsers (and RFC 8259) do."""
    def refuse(constant):
        raise ValueError(f"non-finite number {constant} in the JSON output")
    return json.loads(text, parse_constant=refuse)


def one_error_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    return lines[0]


SWEEP = ["sweep", "--quiet", "--param"]
BAD_ARGUMENTS = [
    SWEEP + ["frequency=20:32:99999999999"],                      # the reproducer: a grid cap
    SWEEP + ["frequency=20:32:1000", "--param", "mass=1e-3:2e-3:1001"],  # the product capped
    SWEEP + ["frequency=nan:32:10"],
    SWEEP + ["frequency=20:inf:10"],
    SWEEP + ["frequency=20:1e400:10"],
    SWEEP + ["frequency=20:32:0"],
    SWEEP + ["frequency=20:32:-5"],
    SWEEP + ["frequency=20:32:2.5"],
    SWEEP + ["frequency=20:32"],
    SWEEP + ["frequency=twenty:32:3"],
    SWEEP + ["frequency=20:32:" + "9" * 5000],                    # no int of that many digits
    SWEEP + ["wingspan=1:2:3"],
    SWEEP + ["frequency=20:32:3", "--param", "frequency=1:2:3"],  # repeated
    SWEEP + ["frequency=20:32:3", "--workers", "0"],
    SWEEP + ["frequency=20:32:3", "--workers", "-3"],
    SWEEP + ["frequency=20:32:3", "--workers", "100000"],
    SWEEP + ["frequency=20:32:3", "--workers", "two"],
    SWEEP + ["frequency=20:32:3", "--insect", "dragonfly"],
    SWEEP + ["frequency=20:32:3", "--csv", "--json"],
    ["sweep"],
    ["hover", "--insect", "dragonfly"],
    ["hover", "--insect", "no/such/file.toml"],
    ["hover", "--aerodynamics", "quadratic"],
    ["hover", "--json", "extra"],
    ["species", "--csv"],
    ["fly"],
    [],
]


@pytest.mark.parametrize("argv", BAD_ARGUMENTS, ids=[" ".join(a)[:60] for a in BAD_ARGUMENTS])
def test_a_bad_argument_exits_2_with_one_line(capsys, argv):
    with pytest.raises(SystemExit) as exit_:
        cli.main(argv)
    assert exit_.value.code == 2
    out = capsys.readouterr()
    line = one_error_line(out.err)
    assert line.startswith("python -m flapping") and ": error: " in line
    assert out.out == ""


BAD_FILES = {
    "deep.json": "[" * 100_000 + "]" * 100_000,        # RecursionError in json.loads
    "long_int.json": '{"preset": "hawkmoth", "mass": ' + "9" * 5000 + "}",  # int digit limit
    "huge.json": '{"preset": "hawkmoth", "mass": ' + "1" + "0" * 400 + "}",  # beyond float64
    "nan.json": '{"preset": "hawkmoth", "mass": NaN}',
    "inf.toml": 'preset = "hawkmoth"\nfrequency = inf\n',
    "zero_g.toml": 'preset = "hawkmoth"\ngravity = 0.0\n',
    "list.json": "[1, 2, 3]",
    "key.toml": 'preset = "hawkmoth"\nwingspan = 1.0\n',
    "binary.toml": b"\xff\xfe\x00 not text",
    "big.json": '{"preset": "hawkmoth", "name": "' + "x" * 2_000_000 + '"}',
}


@pytest.mark.parametrize("name", BAD_FILES)
def test_a_bad_insect_file_exits_2_with_one_line_naming_it(capsys, tmp_path, name):
    path = tmp_path / name
    content = BAD_FILES[name]
    path.write_bytes(content if isinstance(content, bytes) else content.encode())
    with pytest.raises(SystemExit) as exit_:
        cli.main(["hover", "--insect", str(path)])
    assert exit_.value.code == 2
    line = one_error_line(capsys.readouterr().err)
    assert "argument --insect" in line and name in line


def test_a_directory_named_like_an_insect_file_exits_2(capsys, tmp_path):
    (tmp_path / "moth.json").mkdir()
    with pytest.raises(SystemExit) as exit_:
        cli.main(["hover", "--insect", str(tmp_path / "moth.json")])
    assert exit_.value.code == 2
    one_error_line(capsys.readouterr().err)


def test_the_grid_cap_reproducer_in_a_subprocess():
    out = subprocess.run([sys.executable, "-m", "flapping", "sweep", "--param",
                          "frequency=20:32:99999999999"], capture_output=True, text=True,
                         timeout=300)
    assert out.returncode == 2
    line = one_error_line(out.stderr)
    assert "--param" in line and str(cli.MAX_SWEEP_POINTS) in line


# ------------------------------------------------------------------------------ Ctrl-C
def interrupted_after(calls: int):
    """sweep_hover that solves ``calls`` blocks, then raises KeyboardInterrupt (a Ctrl-C)."""
    count = {"n": 0}

    def fake(*args, **kwargs):
        count["n"] += 1
        if count["n"] > calls:
            raise KeyboardInterrupt
        return sweep_hover(*args, **kwargs)
    return fake


@pytest.mark.parametrize("form", ["--csv", "--json"])
def test_ctrl_c_in_a_sweep_exits_130_and_keeps_the_finished_rows(capsys, monkeypatch, form):
    argv = ["sweep", "--quiet", "--param", "frequency=20:32:450", form]
    assert cli.main(argv) == 0
    full = capsys.readouterr().out.splitlines()
    monkeypatch.setattr(cli, "sweep_hover", interrupted_after(1))
    assert cli.main(argv) == 130
    out = capsys.readouterr()
    line = one_error_line(out.err)
    assert "interrupted" in line and "200 of 450 points written" in line
    rows = out.out.splitlines()
    header = 1 if form == "--csv" else 0
    assert len(rows) == 200 + header
    assert rows == full[:len(rows)]  # the rows the uninterrupted sweep prints, exactly
    if form == "--json":
        assert all(isinstance(strict_loads(r), dict) for r in rows)


def test_ctrl_c_before_any_row_prints_only_the_header_and_one_line(capsys, monkeypatch):
    monkeypatch.setattr(cli, "sweep_hover", interrupted_after(0))
    assert cli.main(["sweep", "--quiet", "--param", "frequency=20:32:5"]) == 130
    out = capsys.readouterr()
    assert "0 of 5 points written" in one_error_line(out.err)
    assert out.out == ""


def test_ctrl_c_in_hover_exits_130_with_one_line(capsys, monkeypatch):
    def interrupt(*args, **kwargs):
        raise KeyboardInterrupt
    monkeypatch.setattr(cli, "hover_report", interrupt)
    assert cli.main(["hover", "--json"]) == 130
    out = capsys.readouterr()
    assert one_error_line(out.err).endswith("interrupted") and out.out == ""


# ------------------------------------------------------------------------------ output
def test_a_one_parameter_sweep_prints_what_one_sweep_hover_call_returns(capsys):
    # Blocks of 200 points, a multiple of the sweep's chunk: the same warm starts, the same rows.
    assert cli.main(["sweep", "--quiet", "--param", "frequency=20:32:450"]) == 0
    table = sweep_hover(cli.PRESETS["hawkmoth"](), {"frequency": np.linspace(20, 32, 450)},
                        progress=False)
    expected = table.to_csv(index=False, float_format="%.17g").rstrip("\n")
    assert capsys.readouterr().out.rstrip("\n") == expected


def test_sweep_json_has_null_for_every_non_finite_value(capsys, monkeypatch):
    def with_non_finite(*args, **kwargs):
        table = sweep_hover(*args, **kwargs)
        table.loc[0, "amplitude_deg"] = math.inf
        table.loc[1, "amplitude_deg"] = -math.inf
        table.loc[2, "max_abs_mu"] = math.nan
        return table
    monkeypatch.setattr(cli, "sweep_hover", with_non_finite)
    assert cli.main(["sweep", "--quiet", "--json", "--param", "frequency=20:32:3"]) == 0
    rows = [strict_loads(line) for line in capsys.readouterr().out.splitlines()]
    assert [r["amplitude_deg"] for r in rows[:2]] == [None, None]
    assert rows[2]["max_abs_mu"] is None and rows[2]["amplitude_deg"] > 0


def test_hover_json_keeps_every_key_and_is_strict(capsys):
    assert cli.main(["hover", "--json"]) == 0
    report = strict_loads(capsys.readouterr().out)
    assert set(report) >= set(cli.UNITS) | {"units"}
    assert set(report["solver"]["shooting"]) == set(cli.UNITS["solver"]["shooting"])


def test_a_warning_is_one_line_after_the_output(capsys, tmp_path):
    # An implausible value read from a file warned in Python's two-line format, unprefixed.
    path = tmp_path / "damped.toml"
    path.write_text('preset = "hawkmoth"\nmu1 = 12.0\n')
    assert cli.main(["hover", "--insect", str(path)]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("python -m flapping: warning: `mu1` = 12")


# ------------------------------------------------------------------------------ issue 26
def surfacing_as_system_error(calls: int):
    """sweep_hover that solves ``calls`` blocks, then fails as numba does when Ctrl-C lands in
    compiled code: a SystemError whose cause is the KeyboardInterrupt."""
    count = {"n": 0}

    def fake(*args, **kwargs):
        count["n"] += 1
        if count["n"] > calls:
            try:
                raise KeyboardInterrupt
            except KeyboardInterrupt as exc:
                raise SystemError("<numba dispatcher> returned a result with an exception "
                                  "set") from exc
        return sweep_hover(*args, **kwargs)
    return fake


def test_ctrl_c_surfacing_as_numba_system_error_exits_130_keeping_the_rows(capsys, monkeypatch):
    # Reproducer (issue 26): exit 1 with a 60-line SystemError traceback (rows kept).
    monkeypatch.setattr(cli, "sweep_hover", surfacing_as_system_error(1))
    assert cli.main(["sweep", "--quiet", "--param", "frequency=20:32:450"]) == 130
    out = capsys.readouterr()
    assert "200 of 450 points written" in one_error_line(out.err)
    assert len(out.out.splitlines()) == 201  # the header and the first block


def test_ctrl_c_surfacing_as_system_error_in_hover_exits_130(capsys, monkeypatch):
    def interrupt(*args, **kwargs):
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as exc:
            raise SystemError("returned a result with an exception set") from exc
    monkeypatch.setattr(cli, "hover_report", interrupt)
    assert cli.main(["hover"]) == 130
    out = capsys.readouterr()
    assert one_error_line(out.err).endswith("interrupted") and out.out == ""


def test_a_ctrl_c_that_a_solver_swallows_still_exits_130(capsys, monkeypatch):
    # A solver that catches the KeyboardInterrupt (or numba's SystemError) and carries on must
    # not turn Ctrl-C into a printed result.
    import contextlib
    import signal

    def swallowing(*args, **kwargs):
        with contextlib.suppress(KeyboardInterrupt):
            signal.raise_signal(signal.SIGINT)
        return {"never": "printed"}
    monkeypatch.setattr(cli, "hover_report", swallowing)
    assert cli.main(["hover", "--json"]) == 130
    out = capsys.readouterr()
    assert one_error_line(out.err).endswith("interrupted") and out.out == ""


def test_a_system_error_that_is_not_a_ctrl_c_is_not_called_one(monkeypatch):
    def broken(*args, **kwargs):
        raise SystemError("a real bug")
    monkeypatch.setattr(cli, "hover_report", broken)
    with pytest.raises(SystemError, match="a real bug"):
        cli.main(["hover"])


@pytest.mark.parametrize("param, form", [("mass=-1:-0.5:3", "--csv"),
                                         ("frequency=1e5:2e5:2", "--json")])
def test_a_sweep_whose_every_point_is_invalid_exits_1_with_one_line(capsys, param, form):
    # Reproducer (issue 26): every row failed and the sweep exited 0.
    assert cli.main(["sweep", "--quiet", "--param", param, form]) == 1
    out = capsys.readouterr()
    line = one_error_line(out.err)
    assert "no point of the sweep gave an orbit" in line and param.split("=")[0] in line
    rows = out.out.splitlines()
    assert len(rows) == int(param.rsplit(":", 1)[1]) + (form == "--csv")  # every row printed
    if form == "--json":
        assert all(strict_loads(r)["status"] == "invalid_input" for r in rows)


def test_a_sweep_with_some_invalid_points_exits_0(capsys):
    assert cli.main(["sweep", "--quiet", "--param", "frequency=-10:26:2"]) == 0
    rows = capsys.readouterr().out.splitlines()
    assert len(rows) == 3 and ",invalid_input," in rows[1] and ",hover," in rows[2]


def test_the_exit_status_table_names_the_failed_sweep(capsys):
    with pytest.raises(SystemExit):
        cli.main(["--help"])
    assert "a sweep in which no point gave an orbit" in capsys.readouterr().out


# ------------------------------------------------------------------------------ real SIGINT
class _Process:
    """A ``python -m flapping`` subprocess whose standard output is read by a thread (so that
    the test can wait for rows without mixing buffered reads and communicate())."""

    def __init__(self, *argv: str, code: str | None = None) -> None:
        import threading

        command = [sys.executable, "-c", code] if code else [sys.executable, "-m", "flapping"]
        self.process = subprocess.Popen([*command, *argv], stdout=subprocess.PIPE,
                                        stderr=subprocess.PIPE, text=True)
        self.lines: list[str] = []
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()

    def _read(self) -> None:
        assert self.process.stdout is not None
        for line in self.process.stdout:
            self.lines.append(line)

    def wait_for_lines(self, n: int, timeout: float = 240.0) -> None:
        import time

        deadline = time.monotonic() + timeout
        while len(self.lines) < n:
            assert self.process.poll() is None, "the process ended before printing its rows"
            assert time.monotonic() < deadline, "no rows within the timeout (loaded machine?)"
            time.sleep(0.05)

    def interrupt(self) -> tuple[int, str]:
        import signal

        self.process.send_signal(signal.SIGINT)
        _, err = self.process.communicate(timeout=240)
        self.reader.join(timeout=60)
        return self.process.returncode, err


@pytest.mark.parametrize("rows", [2, 201])
def test_real_ctrl_c_mid_sweep_exits_130_with_one_line_and_whole_rows(rows):
    # A real SIGINT, sent once the sweep has printed `rows` lines (inside the first block or
    # after it): whatever the solver was doing (numba code included), one line and status 130.
    run = _Process("sweep", "--quiet", "--param", "frequency=20:32:100000")
    run.wait_for_lines(rows)
    status, err = run.interrupt()
    assert status == 130
    line = one_error_line(err)
    assert "interrupted" in line and "of 100000 points written" in line
    written = int(line.split("interrupted: ")[1].split(" of")[0])
    assert len(run.lines) == written + 1  # the header and every counted row, whole
    assert all(len(r.split(",")) == len(run.lines[0].split(",")) for r in run.lines)


#: Runs the console script's entry point with a SIGINT delivered while flapping.cli is being
#: imported (an import hook raises it): the moment before main() has its handler.
_STARTUP = """
import importlib.abc, os, signal, sys
# Python's own Ctrl-C handler, as in a terminal (a runner started in the background of a
# non-interactive shell hands its children SIGINT ignored, and Python then installs none)
signal.signal(signal.SIGINT, signal.default_int_handler)
import flapping  # the package itself: its __init__ is not the command line's to guard
class Interrupt(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name == "flapping.cli":
            os.kill(os.getpid(), signal.SIGINT)
        return None
sys.meta_path.insert(0, Interrupt())
from flapping.__main__ import main
sys.exit(main(["species"]))
"""


def test_ctrl_c_while_the_command_line_loads_exits_130_with_one_line():
    # Reproducer (issue 26): Ctrl-C during start-up printed a traceback.
    run = _Process(code=_STARTUP)
    _, err = run.process.communicate(timeout=240)
    assert run.process.returncode == 130
    assert one_error_line(err).endswith("interrupted")


def test_a_failed_hover_names_the_likely_culprit_field(capsys, monkeypatch, tmp_path):
    # Issue 26: a blow-up ended in "`fun` returned a non-finite value" without naming the field
    # that caused it. The solver is replaced by one that fails, as the hover layer does for such
    # an insect (a hawkmoth of 10 ug: its wings lift 1e5 times its weight).
    def failing(*args, **kwargs):
        raise ValueError("`fun` returned a non-finite value at t = 0.001")
    monkeypatch.setattr(cli, "hover_report", failing)
    path = tmp_path / "light.toml"
    path.write_text('preset = "hawkmoth"\nmass = 1e-8\n')
    assert cli.main(["hover", "--insect", str(path)]) == 1
    line = [x for x in capsys.readouterr().err.splitlines() if ": error:" in x]
    assert len(line) == 1 and "likely cause: " in line[0] and "non-finite" in line[0]
    assert "`mass` (" in line[0]


@pytest.mark.parametrize("argv", [["--version", "extra"], ["hover", "--version"]])
def test_version_with_other_arguments_is_a_bad_argument(capsys, argv):
    # `flapping --version extra` printed the version and exited 0, ignoring "extra".
    with pytest.raises(SystemExit) as exit_:
        cli.main(argv)
    assert exit_.value.code == 2
    assert "--version" in one_error_line(capsys.readouterr().err)

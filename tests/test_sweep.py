"""Sweeps: one row per point, failures as rows, warm starts that do not change the answers, and
the same table in-process, on local processes and on a dask cluster."""

import math
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

import flapping

pytest.importorskip("numba")
pandas = pytest.importorskip("pandas")
pytest.importorskip("tqdm")
from flapping.fast.kernel import solve_hover  # noqa: E402
from flapping.results import STATUS_WORDS  # noqa: E402
from flapping.studies.sweep import COLUMNS, SEGMENT, grid_points, sweep_hover  # noqa: E402

GRID = {"frequency": np.linspace(22.0, 30.0, 5), "center_of_pressure": [0.1, 0.25, 0.4]}


@pytest.fixture(scope="module")
def table():
    return sweep_hover(flapping.hawkmoth(), GRID, progress=False, chunk_size=4)


def test_one_row_per_point_in_grid_order(table):
    assert list(table.columns) == list(GRID) + list(COLUMNS)
    assert len(table) == 15
    expected = grid_points(GRID)
    assert table[list(GRID)].to_dict("records") == expected
    assert table.converged.all() and (table.message == "").all()
    assert (table.max_abs_mu > 1).all() == (~table.stable).all()


def test_warm_started_points_equal_cold_solves(table):
    # Warm starts change the Newton path, not the root: to the kernel's accuracy (1e-9 deg,
    # 1e-8 on the multipliers), and in fact to rounding since Newton converges to it.
    for row in table.itertuples():
        cold = solve_hover(flapping.hawkmoth(frequency=row.frequency,
                                             center_of_pressure=row.center_of_pressure),
                           n_steps=int(row.n_steps))
        assert abs(row.amplitude_deg - cold.amplitude_deg) < 1e-11
        mu = [complex(getattr(row, f"mu{i}_real"), getattr(row, f"mu{i}_imag"))
              for i in range(1, 5)]
        np.testing.assert_allclose(mu, cold.multipliers, rtol=0, atol=1e-11)
        assert row.max_abs_mu == pytest.approx(abs(cold.multipliers[0]), abs=1e-11)


def test_a_bad_point_is_a_row_not_an_abort():
    # At 8 Hz the hawkmoth cannot trim (eq. 40): that row says so, the others are solved.
    df = sweep_hover(flapping.hawkmoth(), {"frequency": [8.0, 26.3, 27.0]}, progress=False)
    assert df.converged.tolist() == [False, True, True]
    assert "exceeds the largest mean lift" in df.message[0]
    assert math.isnan(df.amplitude_deg[0]) and df.nit[0] == 0


def test_a_list_of_insects():
    insects = [flapping.hawkmoth(), flapping.hawkmoth(name="heavy", mass=1.8e-3)]
    df = sweep_hover(insects, progress=False)
    assert df.name.tolist() == ["hawkmoth", "heavy"] and df.insect.tolist() == [0, 1]
    assert df.amplitude_deg[1] > df.amplitude_deg[0]  # a heavier body needs a larger stroke


def test_process_pool_gives_the_same_table(table):
    with ProcessPoolExecutor(2) as pool:
        df = sweep_hover(flapping.hawkmoth(), GRID, progress=False, chunk_size=4, executor=pool)
    pandas.testing.assert_frame_equal(df, table)


@pytest.mark.parametrize(("chunk_size", "workers"), [(1, None), (7, 2), (1000, None)])
def test_the_table_does_not_depend_on_how_the_grid_is_cut(chunk_size, workers):
    # Reproducer: Phi moved 7e-10 deg between chunks of 50 and 250 (a chunk's first point started
    # cold wherever the chunk began). Segments of SEGMENT points on a grid line start cold,
    # whatever the chunks: bit-identical tables. A line longer than a segment is cut too.
    grid = {"frequency": [24.0, 27.0], "hinge_height": np.linspace(0.0, 4e-3, SEGMENT + 7)}
    reference = sweep_hover(flapping.hawkmoth(), grid, progress=False)
    if workers is None:
        df = sweep_hover(flapping.hawkmoth(), grid, progress=False, chunk_size=chunk_size)
    else:
        with ProcessPoolExecutor(workers) as pool:
            df = sweep_hover(flapping.hawkmoth(), grid, progress=False, chunk_size=chunk_size,
                             executor=pool)
    pandas.testing.assert_frame_equal(df, reference, check_exact=True)


def test_a_point_s_status_is_one_word_and_converged_follows_from_it():
    # Reproducer (issue 35): a row carried converged, an integer status (0, 1, -1) and a
    # solve_status; now one status word, the failed solve's or the orbit's.
    df = sweep_hover(flapping.hawkmoth(), {"frequency": [8.0, 26.3]}, progress=False)
    assert df.status.tolist() == ["invalid_input", "hover"]
    assert df.converged.tolist() == [False, True] and "solve_status" not in df
    assert set(df.status) <= STATUS_WORDS


def test_dask_cluster_gives_the_same_table(table):
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, processes=False, threads_per_worker=1,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        df = sweep_hover(flapping.hawkmoth(), GRID, progress=False, chunk_size=4,
                         executor=client.get_executor())
    pandas.testing.assert_frame_equal(df, table)


def test_progress_bar_unless_quiet(capsys):
    sweep_hover(flapping.hawkmoth(), {"frequency": [26.0, 27.0]}, progress=True)
    assert "hover sweep" in capsys.readouterr().err
    sweep_hover(flapping.hawkmoth(), {"frequency": [26.0, 27.0]}, progress=False)
    assert capsys.readouterr().err == ""


@pytest.mark.parametrize("grid", [{"wingspan": [1.0]}, {"frequency": []}, {},
                                  {"frequency": [[1.0, 2.0]]}, {"frequency": [np.nan]}])
def test_bad_grids_are_value_errors(grid):
    with pytest.raises(ValueError):
        sweep_hover(flapping.hawkmoth(), grid, progress=False)


def test_bad_arguments_are_value_errors():
    with pytest.raises(ValueError):
        sweep_hover(flapping.hawkmoth(), progress=False)  # no grid and not a list
    with pytest.raises(ValueError):
        sweep_hover(flapping.hawkmoth(), GRID, executor="pool", progress=False)
    with pytest.raises(ValueError):
        sweep_hover(flapping.hawkmoth(), GRID, chunk_size=0, progress=False)


@pytest.mark.parametrize("args", [("hawkmoth",), (["hawkmoth"],),
                                  ("hawkmoth", {"frequency": [26.3]})])
def test_a_preset_name_is_refused_with_the_way_to_build_it(args):
    # Was "`insect[0]` must be a Insect; got 'h'": a string is a sequence of one-letter strings.
    with pytest.raises(ValueError, match=r"not the string 'hawkmoth'.*preset\('hawkmoth'\)"):
        sweep_hover(*args, progress=False)


def test_an_unknown_name_is_refused_with_the_preset_names():
    with pytest.raises(ValueError, match="one of .*'bumblebee'"):
        sweep_hover("moth", progress=False)


def test_a_huge_grid_is_refused_at_once():
    # Was a hang in itertools.product: the size is the product of the axes' lengths, checked
    # before any point is made.
    axis = np.linspace(20.0, 30.0, 10_000)
    with pytest.raises(ValueError, match=r"`grid` asks for at least 10000 x 10000 = "
                                         r"100000000 points.*MAX_GRID_POINTS = 10000000"):
        sweep_hover(flapping.hawkmoth(), {"frequency": axis, "mass": axis * 1e-4},
                    progress=False)
    with pytest.raises(ValueError, match="`grid`"):
        grid_points({"frequency": axis, "mass": axis, "a0": [1.0, 2.0]})


def test_the_grid_cap_counts_every_axis(monkeypatch):
    from flapping.studies import sweep

    monkeypatch.setattr(sweep, "MAX_GRID_POINTS", 6)
    assert len(grid_points({"frequency": [20.0, 21.0], "mass": [1e-3, 2e-3, 3e-3]})) == 6
    with pytest.raises(ValueError, match="2 x 3 x 2 = 12 points"):
        grid_points({"frequency": [20.0, 21.0], "mass": [1e-3, 2e-3, 3e-3], "a0": [5.0, 6.0]})


def _cli(*args):
    import subprocess
    import sys

    return subprocess.run([sys.executable, "-m", "flapping", "sweep", *args],
                          capture_output=True, text=True)


def test_cli_sweep_prints_one_csv_row_per_point():
    out = _cli("--insect", "hawkmoth", "--param", "frequency=20:32:1000", "--csv")
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert len(lines) == 1001 and lines[0].startswith("frequency,amplitude_deg,")
    header = lines[0].split(",")
    converged = header.index("converged")
    assert all(line.split(",")[converged] == "True" for line in lines[1:])


def test_cli_sweep_json_lines_on_two_workers_over_two_parameters():
    import json

    out = _cli("--insect", "hawkmoth", "--param", "frequency=8:32:3", "--param",
               "center_of_pressure=0.1:0.3:2", "--json", "--workers", "2")
    assert out.returncode == 0, out.stderr
    rows = [json.loads(line) for line in out.stdout.splitlines()]
    assert len(rows) == 6 and [r["converged"] for r in rows] == [False] * 2 + [True] * 4
    assert rows[0]["amplitude_deg"] is None and "lift" in rows[0]["message"]


def test_cli_sweep_refuses_an_unknown_field():
    out = _cli("--param", "wingspan=1:2:3")
    assert out.returncode == 2 and "unknown Insect field" in out.stderr


@pytest.mark.parametrize("how", ["keyboard", "numba"])
def test_ctrl_c_keeps_the_finished_rows(monkeypatch, how):
    # Reproducer: Ctrl-C inside a compiled call surfaced as numba's SystemError. Either way the
    # sweep raises a KeyboardInterrupt carrying the rows of the chunks finished.
    import flapping.studies.sweep as sweep_module

    solve, calls = sweep_module._solve_chunk, []

    def interrupted_second_chunk(*args):
        calls.append(1)
        if len(calls) == 2:
            if how == "keyboard":
                raise KeyboardInterrupt
            try:
                raise KeyboardInterrupt
            except KeyboardInterrupt as exc:
                raise SystemError("<CPUDispatcher> returned a result with an exception set") \
                    from exc
        return solve(*args)

    monkeypatch.setattr(sweep_module, "_solve_chunk", interrupted_second_chunk)
    grid = {"frequency": [24.0, 27.0], "hinge_height": [0.0, 1e-3]}
    with pytest.raises(sweep_module.SweepInterrupted) as info:
        sweep_hover(flapping.hawkmoth(), grid, progress=False, chunk_size=1)
    assert isinstance(info.value, KeyboardInterrupt)
    table = info.value.table
    assert len(table) == 2 and table.converged.all()
    assert table.frequency.tolist() == [24.0, 24.0]
    assert "2 of 4 points" in str(info.value)


def test_another_system_error_is_not_taken_for_ctrl_c(monkeypatch):
    import flapping.studies.sweep as sweep_module

    def broken(*args):
        raise SystemError("a real one")

    monkeypatch.setattr(sweep_module, "_solve_chunk", broken)
    with pytest.raises(SystemError, match="a real one"):
        sweep_hover(flapping.hawkmoth(), {"frequency": [24.0]}, progress=False)

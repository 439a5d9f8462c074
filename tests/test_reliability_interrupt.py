"""Ctrl-C on a sweep with workers (flapping.studies.sweep, flapping.cli), issue 35 item 8.

Reproducer: a double Ctrl-C on ``python -m flapping sweep --workers 2`` printed a traceback from
``concurrent.futures`` and never exited (5 of 8 tries), leaving the pool's children behind: the
first Ctrl-C left the workers (which ignore SIGINT) running their chunks, and the interpreter's
exit joined them; the second Ctrl-C landed in that join.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
from concurrent.futures import ProcessPoolExecutor

import pytest

pytest.importorskip("pandas")
pytest.importorskip("tqdm")

from flapping.studies.sweep import stop_process_pool  # noqa: E402


def _children(pid: int) -> list[int]:
    """The pids whose parent is ``pid`` (from /proc)."""
    found = []
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as f:
                fields = f.read().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            found.append(int(entry))
    return found


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as f:
            state = f.read().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


@pytest.mark.skipif(not os.path.isdir("/proc"), reason="reads the process table from /proc")
@pytest.mark.parametrize("gap", [0.0, 0.3])
def test_double_ctrl_c_on_a_sweep_with_workers_exits_130_and_leaves_no_child(gap):
    process = subprocess.Popen(
        [sys.executable, "-m", "flapping", "sweep", "--quiet", "--workers", "2", "--param",
         "frequency=20:32:100000"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    lines: list[str] = []
    reader = threading.Thread(target=lambda: lines.extend(process.stdout), daemon=True)
    reader.start()
    deadline = time.monotonic() + 240.0
    while len(lines) < 2:  # the header and a row: the pool runs its chunks
        assert process.poll() is None, "the sweep ended before printing its rows"
        assert time.monotonic() < deadline, "no rows within the timeout (loaded machine?)"
        time.sleep(0.05)
    workers = _children(process.pid)
    assert workers, "the pool has no child processes"
    process.send_signal(signal.SIGINT)
    time.sleep(gap)
    if process.poll() is None:
        process.send_signal(signal.SIGINT)
    try:
        _, err = process.communicate(timeout=60)
    except subprocess.TimeoutExpired:  # the bug: it never exits
        process.kill()
        process.communicate()
        pytest.fail("the sweep did not exit within 60 s of a double Ctrl-C")
    assert process.returncode == 130, err
    assert "Traceback" not in err, err
    errors = [x for x in err.splitlines() if "interrupted" in x]
    assert len(errors) == 1
    time.sleep(1.0)
    left = [pid for pid in workers if _alive(pid)]
    for pid in left:  # clean up after a failure
        os.kill(pid, signal.SIGKILL)
    assert not left, f"pool children left behind: {left}"


def _sleep(seconds: float) -> float:
    time.sleep(seconds)
    return seconds


def test_stop_process_pool_cancels_pending_work_and_ends_running_workers():
    pool = ProcessPoolExecutor(2)
    futures = [pool.submit(_sleep, 30.0) for _ in range(6)]
    time.sleep(1.0)  # two running, four pending
    processes = list(pool._processes.values())  # type: ignore[attr-defined]
    started = time.monotonic()
    stop_process_pool(pool)
    assert time.monotonic() - started < 15.0  # not the 30 s of a running task
    assert all(not p.is_alive() for p in processes)
    # the running futures are failed by the pool's manager thread once it sees its workers gone
    # (it may lag the return under load): done within seconds, never the 30 s of the task
    # (futures.wait would not do: it counts a future cancelled but not yet notified as pending)
    deadline = time.monotonic() + 10.0
    while not all(f.cancelled() or f.done() for f in futures) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert all(f.cancelled() or f.done() for f in futures)


def test_a_sweep_with_workers_that_ends_prints_every_row_and_exits_0():
    # the pool is stopped at the end as well (its idle workers ended): same rows as in-process
    argv = [sys.executable, "-m", "flapping", "sweep", "--quiet", "--param",
            "frequency=20:32:5"]
    one = subprocess.run(argv, capture_output=True, text=True, timeout=600)
    two = subprocess.run([*argv, "--workers", "2"], capture_output=True, text=True, timeout=600)
    assert one.returncode == two.returncode == 0, two.stderr
    assert two.stdout == one.stdout and len(two.stdout.splitlines()) == 6
    assert "Traceback" not in two.stderr

"""numba compiling the kernel in a background process, into the on-disk cache.

When the first call of the kernel in an environment is answered uncompiled
(:func:`flapping.fast.kernel.run`), :func:`start` launches one detached Python process that runs
:func:`flapping.fast.kernel.warm_up` (every entry point compiled and cached, the solve's first),
so that later calls, in this process or in the next, load machine code from the cache.

One compile per cache directory at a time, and a way to know that one runs: the lock file
``flapping-compile.lock`` in the cache directory, locked (``fcntl.flock``) by the launching
process before the start and handed to the child, which holds it until it exits (the operating
system releases it then, also on a crash or a kill). :func:`running` tests it; :func:`wait` waits
for it or for a condition, with a time limit. The child reports its outcome and its CPU time in
``flapping-compile.json`` beside the lock. Without ``fcntl`` (Windows) nothing is started (later
calls compile in the process, as numba does).

The child: the same interpreter, the same ``flapping`` (its directory first on ``sys.path``),
the same numba cache directory (checked: it does nothing if its own differs), standard streams
on ``os.devnull`` (a parent that reads this process's output does not wait for it), a session
of its own (the terminal's Ctrl-C is not for it), a low priority (``os.nice``). The launching
process reaps it if it is still alive (a daemon thread waits for it); otherwise the system does.
"""

from __future__ import annotations

import contextlib
import json
import logging
import os
import subprocess
import sys
import threading
import time
import traceback
from pathlib import Path

try:
    import fcntl
except ImportError:  # pragma: no cover - Windows
    fcntl = None  # type: ignore[assignment]

LOCK_NAME = "flapping-compile.lock"
REPORT_NAME = "flapping-compile.json"

#: The background process's niceness increment (it yields the CPU to foreground work).
NICE = 10

_LOG = logging.getLogger("flapping")


def supported() -> bool:
    """Whether a background compile can be started and watched here (``fcntl`` and an
    interpreter to start)."""
    return fcntl is not None and bool(sys.executable)


def _locked(fd: int) -> bool:
    """Try the lock on ``fd``: True if another holds it (it is not taken then)."""
    assert fcntl is not None
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        return True
    fcntl.flock(fd, fcntl.LOCK_UN)
    return False


def running(cache: Path) -> bool:
    """Whether a background compile into ``cache`` runs now (its lock is held)."""
    if fcntl is None:
        return False
    try:
        fd = os.open(cache / LOCK_NAME, os.O_RDONLY)
    except OSError:  # no lock file: none was ever started here
        return False
    try:
        return _locked(fd)
    finally:
        os.close(fd)


def wait(cache: Path, timeout: float, done=lambda: False, poll: float = 0.05) -> bool:
    """Wait until no background compile runs in ``cache`` or ``done()`` is true, at most
    ``timeout`` seconds; returns whether the wait ended before the time limit."""
    end = time.monotonic() + timeout
    while running(cache) and not done():
        if time.monotonic() > end:
            return False
        time.sleep(poll)
    return True


def start(cache: Path) -> int | None:
    """Start the background compile into ``cache`` unless one runs; its process id, or None
    (one runs already, or none can be started: the reason is logged at DEBUG)."""
    if not supported():
        return None
    try:
        cache.mkdir(parents=True, exist_ok=True)
        fd = os.open(cache / LOCK_NAME, os.O_RDWR | os.O_CREAT, 0o644)
    except OSError as error:
        _LOG.debug("no background compile: %s", error)
        return None
    try:
        assert fcntl is not None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            return None  # another process compiles into this cache now
        root = str(Path(__file__).resolve().parents[2])
        code = ("import sys; sys.path.insert(0, sys.argv[1]); "
                "from flapping.fast._background import main; sys.exit(main(sys.argv[2:]))")
        env = dict(os.environ, FLAPPING_FIRST_CALL="compiled")
        try:
            from numba.core import config

            directory = getattr(config, "CACHE_DIR", "")
            if directory:
                env["NUMBA_CACHE_DIR"] = directory
        except ImportError:  # pragma: no cover - the kernel imported numba
            pass
        process = subprocess.Popen(
            [sys.executable, "-c", code, root, str(cache)], env=env,
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            pass_fds=(fd,), start_new_session=True)
    except OSError as error:
        _LOG.debug("no background compile: %s", error)
        return None
    finally:
        os.close(fd)  # the child's copy holds the lock now (or none was started)
    threading.Thread(target=process.wait, name="flapping-compile-reaper", daemon=True).start()
    return process.pid


def report(cache: Path) -> dict | None:
    """The last background compile's report in ``cache`` (None if there is none)."""
    try:
        return json.loads((cache / REPORT_NAME).read_text())
    except (OSError, ValueError):
        return None


def main(argv: list[str], niceness: int = NICE) -> int:
    """The background process: compile and cache every entry point into the cache ``argv[0]``
    at a priority lowered by ``niceness`` and write the report (the lock's descriptor,
    inherited, is held until the process exits). Returns the exit status (1: not compiled)."""
    import resource

    cache = Path(argv[0])
    started = time.perf_counter()
    outcome: dict = {"pid": os.getpid(), "ok": False, "error": ""}
    if niceness:
        with contextlib.suppress(OSError):  # not allowed: compile at the usual priority
            os.nice(niceness)
    try:
        from flapping.fast import kernel

        own = kernel.cache_dir(kernel.load())
        if own is None or own.resolve() != cache.resolve():
            outcome["error"] = f"numba caches in {own} here, not in {cache}: nothing compiled"
        else:
            kernel.warm_up()
            outcome["ok"] = True
    except BaseException:  # noqa: BLE001 - reported in the file; the caller compiles itself
        outcome["error"] = traceback.format_exc(limit=5)
    usage = resource.getrusage(resource.RUSAGE_SELF)
    outcome.update(cpu_s=usage.ru_utime + usage.ru_stime,
                   wall_s=time.perf_counter() - started)
    with contextlib.suppress(OSError):
        (cache / REPORT_NAME).write_text(json.dumps(outcome))
    return 0 if outcome["ok"] else 1

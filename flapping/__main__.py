"""``python -m flapping`` and the console script ``flapping``: the command line of
:mod:`flapping.cli`.

The command line's modules are imported inside :func:`main`, so that a Ctrl-C while they load
exits with status 130 and one line, as a Ctrl-C anywhere later does, not with a traceback.
(Ctrl-C while ``import flapping`` itself runs, before this module is reached, is the package's
``__init__``'s to handle.)
"""

import contextlib
import ctypes
import os
import signal
import sys
from collections.abc import Sequence

#: Exit status after Ctrl-C (128 + SIGINT), as :mod:`flapping.cli` returns it.
_INTERRUPTED = 130


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line (:func:`flapping.cli.main`); 130 and one line if Ctrl-C lands while
    its modules load.

    Parameters
    ----------
    argv : sequence of str, optional
        The arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status (see ``flapping --help``).
    """
    try:
        from flapping.cli import main as cli_main
    except KeyboardInterrupt:
        # as flapping.cli names itself (that module may be the one that was interrupted)
        prog = "flapping" if sys.argv and os.path.basename(sys.argv[0]) == "flapping" else \
            "python -m flapping"
        print(f"{prog}: interrupted", file=sys.stderr)
        return _interrupted()
    status = cli_main(argv)
    if status == _INTERRUPTED:
        # Exiting after Ctrl-C: another one while the interpreter shuts down (the user pressing
        # again) would end the process by SIGINT (status -2) instead of 130.
        with contextlib.suppress(ValueError):  # not the main thread: not ours to handle
            signal.signal(signal.SIGINT, signal.SIG_IGN)
        _exit_if_a_thread_hangs(status)
        return _interrupted()
    return status


def _interrupted() -> int:
    """130, and CPython told that the Ctrl-C was handled.

    CPython 3.8-3.11 remember a KeyboardInterrupt that left any ``PyRun_*`` evaluation (one
    runs while the command line's modules load) in ``_Py_UnhandledKeyboardInterrupt``, even once
    it is caught, and at exit kill the process with SIGINT instead of exiting with the status
    returned: a parent saw -2 instead of 130 after about a third of early Ctrl-Cs. The handled
    interrupt is forgotten here (on another Python the flag is absent and nothing is done).
    """
    # not CPython 3.8-3.11 (no such flag): nothing to forget
    with contextlib.suppress(AttributeError, ValueError, OSError):
        ctypes.c_int.in_dll(ctypes.pythonapi, "_Py_UnhandledKeyboardInterrupt").value = 0
    return _INTERRUPTED


def _exit_if_a_thread_hangs(status: int, timeout: float = 5.0) -> None:
    """After Ctrl-C, end the process at once if a thread would hold its exit for ever.

    The interpreter joins every non-daemon thread before it exits; a process pool's manager
    thread can block for ever on a worker killed while it wrote a result. Each gets
    ``timeout`` seconds; then the output is flushed and the process exits with ``status``
    without waiting (``os._exit``).
    """
    import threading

    others = [t for t in threading.enumerate()
              if t is not threading.current_thread() and not t.daemon]
    for thread in others:
        thread.join(timeout)
    if any(thread.is_alive() for thread in others):
        for stream in (sys.stdout, sys.stderr):
            with contextlib.suppress(Exception):
                stream.flush()
        os._exit(status)


if __name__ == "__main__":
    sys.exit(main())

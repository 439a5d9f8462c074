"""Benchmark: the first hover orbit and Floquet multipliers in a fresh process, cold and warm.

Issue 26, item 5 ("fast from the first call"): a new process runs
``flapping.hover_stability(flapping.find_hover_orbit(flapping.hawkmoth()))`` -- the default path,
the compiled kernel -- first with an empty numba cache (``NUMBA_CACHE_DIR`` a new directory),
then with that cache warm (numba loads the machine code). With an empty cache the kernel answers
its first calls with its Python code, uncompiled (the same numbers), and starts a background
process that compiles it into the cache (:mod:`flapping.fast.kernel`, "The first call in a new
environment"); the script waits for that process before the warm runs, and checks that the cold
run answered uncompiled and the warm ones compiled (each run prints which path answered).

Each run is timed as the CPU seconds of the child process (its rusage: user + system, the
interpreter's start and imports included), which other processes on a shared machine disturb
less than wall time; the warm run is the best of N. The background compile is not in the cold
run's time (the user has the answer before it ends): its own CPU seconds, which it reports, are
printed apart. For comparison, the script also times the first call that compiles in the
process before answering (``FLAPPING_FIRST_CALL=compiled``, another empty cache), as every first
call did before. It prints the times, the ratio cold / warm and the issue's target (cold at most
3 times warm).

Run: ``python benchmarks/bench_first_call.py [--repeat N] [--quick] [--no-compiled]``
(``--quick``: the warm run only, against numba's usual cache; ``--no-compiled``: without the
in-process compile for comparison).
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
from pathlib import Path

#: Issue 26: the first call with an empty cache costs at most this many times a warm one.
TARGET_RATIO = 3.0

#: Longest wait for the background compile [s].
WAIT_S = 900.0

CALL = ("import warnings, flapping; warnings.simplefilter('ignore'); "
        "orbit = flapping.find_hover_orbit(flapping.hawkmoth()); "
        "stability = flapping.hover_stability(orbit); "
        "print(orbit.kernel.path, abs(stability.multipliers).max().hex())")


def child_cpu(env: dict[str, str]) -> tuple[float, str]:
    """CPU seconds [s] of a fresh interpreter running :data:`CALL`, and what it printed."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run([sys.executable, "-c", CALL], env=env, check=True, capture_output=True,
                         text=True).stdout.strip()
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), out


def background_compile(cache: str) -> dict:
    """Wait for the background compile into the numba cache under ``cache``; its report."""
    from flapping.fast import _background

    locks = sorted(Path(cache).rglob(_background.LOCK_NAME))
    if not locks:
        return {"ok": False, "error": "no background compile was started"}
    directory = locks[0].parent
    if not _background.wait(directory, WAIT_S):
        return {"ok": False, "error": f"still compiling after {WAIT_S:g} s"}
    return _background.report(directory) or {"ok": False, "error": "no report"}


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="warm runs, best of N (default 3)")
    parser.add_argument("--quick", action="store_true", help="the warm run only")
    parser.add_argument("--no-compiled", action="store_true",
                        help="without the in-process compile (FLAPPING_FIRST_CALL=compiled)")
    args = parser.parse_args(argv)
    base = {k: v for k, v in os.environ.items() if k != "FLAPPING_FIRST_CALL"}
    if args.quick:
        warm, out = min(child_cpu(dict(base)) for _ in range(args.repeat))
        print(f"first orbit + multipliers in a fresh process, numba's cache: {warm:.2f} s CPU "
              f"({out})")
        return {"warm_s": warm}
    with tempfile.TemporaryDirectory() as cache:
        env = dict(base, NUMBA_CACHE_DIR=cache)
        cold, cold_out = child_cpu(env)
        background = background_compile(cache)
        warm, warm_out = min(child_cpu(env) for _ in range(args.repeat))
    compiled_first = None
    if not args.no_compiled:
        with tempfile.TemporaryDirectory() as cache:
            compiled_first, _ = child_cpu(dict(base, NUMBA_CACHE_DIR=cache,
                                               FLAPPING_FIRST_CALL="compiled"))
    ratio = cold / warm
    same = cold_out.split()[-1] == warm_out.split()[-1]
    print("first orbit + multipliers in a fresh process (CPU s of the child, interpreter included)")
    print(f"   empty numba cache            : {cold:6.2f} s   ({cold_out})")
    print(f"   warm numba cache (best of {args.repeat}) : {warm:6.2f} s   ({warm_out})")
    print(f"   ratio cold / warm            : {ratio:6.1f}   (target <= {TARGET_RATIO:g}: "
          f"{'met' if ratio <= TARGET_RATIO else 'NOT met'})")
    print(f"   largest multiplier, cold and warm, equal to the last bit: {same}")
    if background.get("ok"):
        print(f"   background compile (not in the cold run): {background['cpu_s']:6.2f} s CPU, "
              f"{background['wall_s']:.1f} s wall")
    else:
        print(f"   background compile FAILED: {background.get('error')}")
    if compiled_first is not None:
        print(f"   empty cache, compiling before the answer (FLAPPING_FIRST_CALL=compiled): "
              f"{compiled_first:6.2f} s ({compiled_first / warm:.1f}x warm)")
    return {"cold_s": cold, "warm_s": warm, "ratio": ratio, "cold_path": cold_out,
            "warm_path": warm_out, "same_result": same,
            "background_cpu_s": background.get("cpu_s"), "compiled_first_s": compiled_first}


if __name__ == "__main__":
    main()

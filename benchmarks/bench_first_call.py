"""Benchmark: the first hover orbit and Floquet multipliers in a fresh process, cold and warm.

Issue 26, item 5 ("fast from the first call"): a new process runs
``flapping.hover_stability(flapping.find_hover_orbit(flapping.hawkmoth()))`` -- the default path,
the compiled kernel -- first with an empty numba cache (``NUMBA_CACHE_DIR`` a new directory: numba
compiles what the call uses and fills the cache), then with that cache warm (numba loads the
machine code). Each is timed as the CPU seconds of the child process (its rusage: user + system,
the interpreter's start and imports included), which other processes on a shared machine disturb
less than wall time; the warm run is the best of N. The script prints both, their ratio and the
issue's target (cold at most 3 times warm).

Run: ``python benchmarks/bench_first_call.py [--repeat N] [--quick]`` (``--quick``: the warm run
only, against numba's usual cache: no compilation).
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile

#: Issue 26: the first call with an empty cache costs at most this many times a warm one.
TARGET_RATIO = 3.0

CALL = ("import warnings, flapping; warnings.simplefilter('ignore'); "
        "orbit = flapping.find_hover_orbit(flapping.hawkmoth()); "
        "stability = flapping.hover_stability(orbit); "
        "print(orbit.backend, abs(stability.multipliers).max())")


def child_cpu(env: dict[str, str]) -> tuple[float, str]:
    """CPU seconds [s] of a fresh interpreter running :data:`CALL`, and what it printed."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run([sys.executable, "-c", CALL], env=env, check=True, capture_output=True,
                         text=True).stdout.strip()
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), out


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="warm runs, best of N (default 3)")
    parser.add_argument("--quick", action="store_true", help="the warm run only")
    args = parser.parse_args(argv)
    if args.quick:
        warm, out = min(child_cpu(dict(os.environ)) for _ in range(args.repeat))
        print(f"first orbit + multipliers in a fresh process, numba's cache: {warm:.2f} s CPU "
              f"({out})")
        return {"warm_s": warm}
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        cold, out = child_cpu(env)
        warm = min(child_cpu(env)[0] for _ in range(args.repeat))
    ratio = cold / warm
    print("first orbit + multipliers in a fresh process (CPU s of the child, interpreter included)")
    print(f"   empty numba cache (compiles) : {cold:6.2f} s   ({out})")
    print(f"   warm numba cache (best of {args.repeat}) : {warm:6.2f} s")
    print(f"   ratio cold / warm            : {ratio:6.1f}   (target <= {TARGET_RATIO:g}: "
          f"{'met' if ratio <= TARGET_RATIO else 'NOT met'})")
    return {"cold_s": cold, "warm_s": warm, "ratio": ratio}


if __name__ == "__main__":
    main()

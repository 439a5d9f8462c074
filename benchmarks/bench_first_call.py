"""Benchmark: the first hover orbit and Floquet multipliers in a fresh process, cold and warm.

Issue 35, item 5 ("compilation the numba way"): a new process runs
``flapping.hover_stability(flapping.find_hover_orbit(flapping.hawkmoth()))`` -- the default path,
the compiled kernel -- with an empty numba cache (``NUMBA_CACHE_DIR`` a new directory) and with a
warm one (numba loads the machine code), under each first-call policy of
:mod:`flapping.fast._jit`:

- ``FLAPPING_FIRST_CALL=compiled`` (the default): the cold run compiles in the process;
- ``FLAPPING_FIRST_CALL=uncompiled``: the cold run answers with the kernel's Python code (the same
  numbers), compiles nothing and starts nothing.

Each run is timed as CPU seconds of the child process and of everything it started (its rusage
and its children's: user + system, the interpreter's start and imports included; nothing may be
left running behind it, which the script checks by the cache staying empty after an uncompiled
run), which other processes on a shared machine disturb less than wall time; the warm run is
the best of N. The target (issue 35): a cold first call's total CPU at most 3 times a warm one,
or it runs uncompiled with no background work. The script also times ``python -m flapping
compile`` into an empty cache (the explicit warm-up for installs, clusters and CI).

Run: ``python benchmarks/bench_first_call.py [--repeat N] [--quick] [--no-compile-command]``
(``--quick``: the warm run only, against numba's usual cache).
"""

from __future__ import annotations

import argparse
import os
import resource
import subprocess
import sys
import tempfile
from pathlib import Path

#: Issue 35: the first call with an empty cache costs at most this many times a warm one.
TARGET_RATIO = 3.0

CALL = ("import warnings, flapping; warnings.simplefilter('ignore'); "
        "orbit = flapping.find_hover_orbit(flapping.hawkmoth()); "
        "stability = flapping.hover_stability(orbit); "
        "print(orbit.kernel.compiled, abs(stability.multipliers).max().hex())")


def child_cpu(env: dict[str, str], args: list[str] | None = None) -> tuple[float, str]:
    """CPU seconds [s] of a fresh interpreter (and all it started) running :data:`CALL` (or
    ``args``), and the last line it printed."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run([sys.executable, *(args or ["-c", CALL])], env=env, check=True,
                         capture_output=True, text=True).stdout.strip()
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    last = out.splitlines()[-1] if out else ""
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime), last


def _files(directory: str) -> int:
    return sum(1 for p in Path(directory).rglob("*") if p.is_file())


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="warm runs, best of N (default 3)")
    parser.add_argument("--quick", action="store_true", help="the warm run only")
    parser.add_argument("--no-compile-command", action="store_true",
                        help="without timing `python -m flapping compile`")
    args = parser.parse_args(argv)
    base = {k: v for k, v in os.environ.items() if k != "FLAPPING_FIRST_CALL"}
    if args.quick:
        warm, out = min(child_cpu(dict(base)) for _ in range(args.repeat))
        print(f"first orbit + multipliers in a fresh process, numba's cache: {warm:.2f} s CPU "
              f"({out})")
        return {"warm_s": warm}
    results: dict = {}
    with tempfile.TemporaryDirectory() as cache:
        env = dict(base, NUMBA_CACHE_DIR=cache)
        uncompiled, uncompiled_out = child_cpu(dict(env, FLAPPING_FIRST_CALL="uncompiled"))
        results["uncompiled_cache_files"] = _files(cache)  # nothing compiled, nothing started
        cold, cold_out = child_cpu(env)
        warm, warm_out = min(child_cpu(env) for _ in range(args.repeat))
    compile_s = None
    if not args.no_compile_command:
        with tempfile.TemporaryDirectory() as cache:
            compile_s, _ = child_cpu(dict(base, NUMBA_CACHE_DIR=cache),
                                     ["-m", "flapping", "compile"])
    same = len({o.split()[-1] for o in (cold_out, warm_out, uncompiled_out)}) == 1

    def verdict(ratio: float) -> str:
        return "met" if ratio <= TARGET_RATIO else "NOT met"

    print("first orbit + multipliers in a fresh process (CPU s of the child and all it started)")
    print(f"   warm numba cache (best of {args.repeat})          : {warm:6.2f} s   ({warm_out})")
    print(f"   empty cache, compiled in the process       : {cold:6.2f} s   ({cold_out}) "
          f"{cold / warm:5.1f}x warm (target <= {TARGET_RATIO:g}: {verdict(cold / warm)})")
    print(f"   empty cache, FLAPPING_FIRST_CALL=uncompiled: {uncompiled:6.2f} s   "
          f"({uncompiled_out}) {uncompiled / warm:5.1f}x warm (target <= {TARGET_RATIO:g}: "
          f"{verdict(uncompiled / warm)}); files in the cache after it: "
          f"{results['uncompiled_cache_files']} (no background work)")
    print(f"   largest multiplier equal to the last bit on the three runs: {same}")
    if compile_s is not None:
        print(f"   `python -m flapping compile` into an empty cache: {compile_s:6.2f} s CPU "
              f"(every numba function of the package, once per environment)")
    results.update(cold_s=cold, warm_s=warm, uncompiled_s=uncompiled, ratio=cold / warm,
                   uncompiled_ratio=uncompiled / warm, same_result=same, compile_s=compile_s)
    return results


if __name__ == "__main__":
    main()

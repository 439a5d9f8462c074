"""Benchmark: FWUAV's hawkmoth hover orbit and its Floquet exponents (the peer model).

Ours: :func:`flapping.peers.fwuav.hover_floquet` (shooting on the velocity, position over one
period, monodromy of the six states; every integration DOP853 at rtol 1e-11, analytic Jacobian),
its result cache cleared before each call. Baseline, in the same process: one plain
``solve_ivp`` (DOP853, the same tolerances) of the velocity equation over one period from FWUAV's
stored velocity, the unit of work of every integration inside. The script prints CPU seconds
(best of N: the process's own, which other processes on a shared machine disturb less than wall
time), the ratio ours / baseline (how many period integrations the whole analysis costs) and
whether ours meets issue 35's target of 1 s.

Run: ``python benchmarks/bench_fwuav.py [--repeat N]``.
"""

from __future__ import annotations

import argparse
import resource

import numpy as np
from scipy.integrate import solve_ivp

from flapping.peers.fwuav import FwuavHover, floquet, hover_floquet, species

#: Issue 35 (item 6): hover_floquet("hawkmoth") in at most this many seconds (issue 26: 2 s).
TARGET_S = 1.0
RTOL = 1e-11


def _cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def best_cpu(fn, repeat: int):
    """The least CPU time of ``repeat`` calls of ``fn()`` [s], and what the last returned."""
    best, out = float("inf"), None
    for _ in range(repeat):
        start = _cpu()
        out = fn()
        best = min(best, _cpu() - start)
    return best, out


def ours():
    floquet._cached.cache_clear()  # hover_floquet caches per argument set
    return hover_floquet("hawkmoth")


def baseline():
    model = FwuavHover("hawkmoth")
    v0 = np.array(species("hawkmoth").velocity_guess)
    return solve_ivp(model.velocity_rhs, (0.0, model.period), v0, method="DOP853", rtol=RTOL,
                     atol=RTOL * 1e-1)


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="best of N (default 3)")
    args = parser.parse_args(argv)
    ours()  # imports and first calls out of the timing
    t_ours, r = best_cpu(ours, args.repeat)
    t_base, sol = best_cpu(baseline, args.repeat)
    print(f"FWUAV hawkmoth, hover orbit + Floquet exponents (CPU s, best of {args.repeat})")
    print(f"   hover_floquet            : {t_ours:7.3f} s  ({r.nfev} right-hand sides)")
    print(f"   one period, plain DOP853 : {t_base:7.3f} s  ({sol.nfev} right-hand sides)")
    print(f"   ratio                    : {t_ours / t_base:7.1f} period integrations' worth")
    print(f"   target                   : {TARGET_S:.1f} s -> "
          f"{'met' if t_ours <= TARGET_S else 'NOT met'}")
    print(f"   exponents (1/s): longitudinal {r.longitudinal.real}, lateral {r.lateral.real:.6f}")
    return {"fwuav_s": t_ours, "baseline_s": t_base, "ratio": t_ours / t_base,
            "target_s": TARGET_S}


if __name__ == "__main__":
    main()

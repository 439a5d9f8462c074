"""Benchmark: a hover sweep's cost per orbit, as ratios against baselines run in this process.

The sweep: :func:`flapping.studies.sweep.sweep_hover` of the hawkmoth over 1000 frequencies
(20-32 Hz), in process, after a first call that loads the kernel. Each point is warm-started
from the parabola through the last three answers on the grid line. Baselines on the same points:

- *per-point loop*: ``find_hover_orbit`` + the multipliers for each insect independently, from
  the default guess (what a loop over the grid without the sweep would do);
- *adaptive path*: ``find_hover_orbit(..., backend="adaptive")`` + ``hover_stability``, the
  scipy cross-check, on a few of the points (it costs ~0.3 s an orbit);
- *compiled share*: the time the sweep itself spends inside the kernel's compiled calls (Newton
  and the error estimate's coarse integration), measured by wrapping that call during one
  sweep: the rest is Python (building each insect and problem, the result objects, the rows).

Printed: ms per orbit of each (best of N; they move with the machine's load, the ratios much
less), the speed-ups of the sweep over the per-point loop and the adaptive path, the Newton
iterations per point, and where the sweep's time goes.
Run: ``python benchmarks/bench_sweep.py [n_points]``.
"""

from __future__ import annotations

import math
import sys
import time
import warnings

import numpy as np
from _timing import best_of  # benchmarks/ is on sys.path when a script runs

import flapping
from flapping import find_hover_orbit, hover_stability
from flapping.errors import HoverDriftWarning
from flapping.fast import kernel
from flapping.studies.sweep import sweep_hover

#: Points of the adaptive baseline (each ~0.3 s).
ADAPTIVE_POINTS = 4


def sweep(insect, frequencies):
    return sweep_hover(insect, {"frequency": frequencies}, progress=False)


def per_point(insect, frequencies):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", HoverDriftWarning)
        return [find_hover_orbit(insect.with_(frequency=float(f))).kernel.multipliers
                for f in frequencies]


def adaptive(insect, frequencies):
    return [hover_stability(find_hover_orbit(insect.with_(frequency=float(f)),
                                             backend="adaptive")).multipliers
            for f in frequencies]


def compiled_seconds(insect, frequencies) -> float:
    """Seconds one sweep spends inside the kernel's compiled Newton-and-estimate calls."""
    kc = kernel.load()
    inner = kc.newton_and_estimate
    spent = [0.0]

    def timed(*args):
        t0 = time.perf_counter()
        out = inner(*args)
        spent[0] += time.perf_counter() - t0
        return out

    kc.newton_and_estimate = timed
    try:
        sweep(insect, frequencies)
    finally:
        kc.newton_and_estimate = inner
    return spent[0]


def main(n: int = 1000, repeat: int = 5) -> dict:
    insect = flapping.hawkmoth()
    frequencies = np.linspace(20.0, 32.0, n)
    sweep(insect, frequencies)  # loads the kernel
    # Interleaved rounds (best of each): a load that changes during the run hits both alike.
    t_sweep = t_loop = math.inf
    for _ in range(repeat):
        t, table = best_of(lambda: sweep(insect, frequencies), 1)
        t_sweep = min(t_sweep, t)
        t_loop = min(t_loop, best_of(lambda: per_point(insect, frequencies), 1)[0])
    some = frequencies[:: max(1, n // ADAPTIVE_POINTS)][:ADAPTIVE_POINTS]
    t_adaptive, _ = best_of(lambda: adaptive(insect, some), 1)
    t_compiled = min(compiled_seconds(insect, frequencies) for _ in range(repeat))
    per = {"sweep": t_sweep / n * 1e3, "loop": t_loop / n * 1e3,
           "adaptive": t_adaptive / len(some) * 1e3, "compiled": t_compiled / n * 1e3}
    print(f"hover sweep of the {insect.name} over {n} frequencies (best of {repeat}), per orbit:")
    print(f"  sweep_hover (predicted warm starts): {per['sweep']:.3f} ms")
    print(f"  per-point loop (cold solves)       : {per['loop']:.3f} ms")
    print(f"  adaptive path ({len(some)} points)           : {per['adaptive']:.1f} ms")
    print(f"  speed-up over the per-point loop   : {per['loop'] / per['sweep']:.2f}x")
    print(f"  speed-up over the adaptive path    : {per['adaptive'] / per['sweep']:.0f}x")
    print(f"  of the sweep: compiled {per['compiled']:.3f} ms "
          f"({per['compiled'] / per['sweep']:.0%}), Python {per['sweep'] - per['compiled']:.3f} ms")
    print(f"  converged rows: {int(table.converged.sum())} of {n}; Newton iterations per "
          f"point: {table.nit.mean():.2f}; steps per half-stroke: "
          f"{ {int(k): int(v) for k, v in table.n_steps.value_counts().sort_index().items()} }")
    return per


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:2]))

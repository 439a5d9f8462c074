"""Benchmark: a hover sweep's cost per orbit, as ratios against baselines run in this process.

The sweep: :func:`flapping.studies.sweep.sweep_hover` of the hawkmoth over 1000 frequencies
(20-32 Hz), warm-started, in process, after a first call that loads the kernel. Two baselines on
the same points:

- *cold solves*: ``find_hover_orbit`` + the multipliers for each insect independently, from the
  default guess (what a loop over the grid without the sweep would do);
- *compiled floor*: the numba calls alone that the sweep's kernel path makes per point (Newton at
  the answer's step count from the previous point, the coarse integration of the error estimate,
  the 64-node orbit quadrature of the mean velocities), with the insects packed beforehand: the
  cost of the sweep without any Python around it.

Printed: ms per orbit of each (best of N; they move with the machine's load), the speed-up over
cold solves, and the sweep's overhead over its compiled floor (1.0 = no Python cost at all).
Run: ``python benchmarks/bench_sweep.py``.
"""

from __future__ import annotations

import warnings

import numpy as np
from _timing import best_of  # benchmarks/ is on sys.path when a script runs

import flapping
from flapping.errors import HoverDriftWarning
from flapping.fast import kernel
from flapping.hover import find_hover_orbit
from flapping.studies.sweep import sweep_hover

FREQUENCIES = np.linspace(20.0, 32.0, 1000)


def sweep(insect):
    return sweep_hover(insect, {"frequency": FREQUENCIES}, progress=False)


def cold(insect):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", HoverDriftWarning)
        return [find_hover_orbit(insect.with_(frequency=float(f))).kernel.multipliers
                for f in FREQUENCIES]


def compiled_floor(packed, start, n_steps):
    """The sweep's numba calls alone, each point from the previous point's answer."""
    kc = kernel.load()
    nodes, weights = kernel._gauss(64)
    z = start.copy()
    for kp in packed:
        kc.newton(z, n_steps, kp.k, kp.p, kernel._MAX_ITER, kernel._XTOL)
        kc.variational_period(z, n_steps // 2, kp.k, kp.p)
        kc.orbit_quadrature(z[:4].copy(), z[4], kp.k, kp.p, nodes, weights,
                            kernel._QUADRATURE_STEPS)


def main(repeat: int = 5) -> dict:
    insect = flapping.hawkmoth()
    table = sweep(insect)  # loads the kernel
    packed = [kernel.KernelProblem.of(insect.with_(frequency=float(f))) for f in FREQUENCIES]
    first = table.iloc[0]
    start = np.array([first.u0, first.w0, first.q0, first.theta0,
                      np.radians(first.amplitude_deg)])
    n = len(FREQUENCIES)
    t_sweep, table = best_of(lambda: sweep(insect), repeat)
    t_floor, _ = best_of(lambda: compiled_floor(packed, start, int(table.n_steps.median())),
                         repeat)
    t_cold, _ = best_of(lambda: cold(insect), max(1, repeat // 2))
    per = {name: t / n * 1e3 for name, t in
           (("sweep", t_sweep), ("floor", t_floor), ("cold", t_cold))}
    print(f"hover sweep of the {insect.name} over {n} frequencies (best of {repeat}), per orbit:")
    print(f"  sweep_hover (warm-started)     : {per['sweep']:.3f} ms")
    print(f"  independent cold solves        : {per['cold']:.3f} ms")
    print(f"  compiled floor (numba only)    : {per['floor']:.3f} ms")
    print(f"  speed-up over cold solves      : {t_cold / t_sweep:.2f}x")
    print(f"  overhead over the compiled floor: {t_sweep / t_floor:.2f}x "
          f"(Python share {1 - t_floor / t_sweep:.0%})")
    print(f"  converged rows: {int(table.converged.sum())} of {n}; Newton iterations per "
          f"point: {table.nit.mean():.2f}")
    return per


if __name__ == "__main__":
    main()

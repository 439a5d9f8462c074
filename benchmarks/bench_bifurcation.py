"""Benchmark: a 200-point curve of period doublings (Mathieu) beside a 200-point branch (Roessler).

Target (issue 37, item 5): a 200-point bifurcation curve "in seconds on the compiled path".
There is no compiled path for `continue_bifurcation` yet (it integrates the user's Python
`fun`), so the script measures the Python path and states the target as not met until one
exists.

(a) ``continue_bifurcation``: the Mathieu equation's transition curve a_1(q) (a multiplier -1)
    from q = 0.5 with the step fixed at 0.01, 200 points, analytic Jacobian, the default
    tolerances; the held orbit x = 0 (the curve is the monodromy's singularity alone).
(b) ``continue_orbit``: the 200-point Roessler period-1 branch of ``bench_continuation.py``
    (detection on), the one-parameter reference in the same process.

Prints wall time (best of ``--repeat``, :func:`_timing.best_of`), evaluations of ``fun``, the
time per point of each, their ratio (a)/(b), and the largest error of the curve against
``scipy.special.mathieu_b`` (the check that it computed the right thing). The machine may be
shared: run it alone for the numbers that matter; the ratio moves less than the times.

Run: ``python benchmarks/bench_bifurcation.py [--repeat N]``.
"""

from __future__ import annotations

import argparse
import math

import numpy as np
from _timing import best_of  # benchmarks/ is on sys.path when a script runs
from bench_continuation import run_continuation
from scipy.special import mathieu_a

from flapping.periodic import continue_bifurcation

N_POINTS = 200
Q0, STEP = 0.5, 0.01


def mathieu(t, x, a, q):
    return np.array([x[1], -(a - 2.0 * q * math.cos(2.0 * t)) * x[0]])


def mathieu_jac(t, x, a, q):
    return np.array([[0.0, 1.0], [-(a - 2.0 * q * math.cos(2.0 * t)), 0.0]])


def run_curve():
    # a_1(q) bounds the first instability tongue (period 2 pi: a multiplier -1 of the pi-map)
    a0 = float(mathieu_a(1, Q0))
    return continue_bifurcation(mathieu, [0.0, 0.0], math.pi, "period-doubling", a0, Q0,
                                Q0 + STEP * (N_POINTS - 1), jac=mathieu_jac, ds=STEP,
                                ds_max=STEP, max_points=N_POINTS)


def main(repeat: int | None = None) -> dict[str, float]:
    if repeat is None:
        parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
        parser.add_argument("--repeat", type=int, default=3)
        repeat = parser.parse_args().repeat
    t_a, curve = best_of(run_curve, repeat)
    t_b, branch = best_of(lambda: run_continuation(True), repeat)
    error = float(np.max(np.abs(curve.p - mathieu_a(1, curve.q))))
    per_a, per_b = t_a / len(curve.p), t_b / len(branch)
    print(f"(a) continue_bifurcation, Mathieu a_1(q), {len(curve.p)} points, q = "
          f"{curve.q[0]:.2f} .. {curve.q[-1]:.2f}: {t_a:7.3f} s ({1e3 * per_a:.1f} ms a point), "
          f"max |a - mathieu_a(1, q)| = {error:.1e}")
    print(f"(b) continue_orbit, Roessler, {len(branch)} points: {t_b:7.3f} s "
          f"({1e3 * per_b:.1f} ms a point)")
    print(f"ratio (a)/(b) per point = {per_a / per_b:.2f} (best of {repeat})")
    print(f"target: a 200-point curve in seconds on the compiled path: {t_a:.1f} s on the "
          "Python path; no compiled path for continue_bifurcation yet")
    return {"curve_s": t_a, "branch_s": t_b, "ratio": per_a / per_b, "error": error}


if __name__ == "__main__":
    main()

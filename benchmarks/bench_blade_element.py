"""Benchmark: the blade-element hover orbit on the fixed-step path against the adaptive path.

Ours: :func:`flapping.hover.find_hover_orbit` with ``backend="fixed-step"`` (what ``"auto"``
runs for the blade-element models): Newton on a fixed-step DOP853 period map on a time mesh
graded towards the stroke reversals, the loads' kinks as switching functions, a Richardson error
estimate. Baseline: the same call with ``backend="adaptive"`` (Levenberg-Marquardt over adaptive
DOP853 flows, a finite-difference Jacobian), the path ``"auto"`` took before.

Both run in this process from the same default guess, at hinge heights where both converge (0)
and where the adaptive path's LM stalls at its integration noise (10 mm); the script prints wall
times, residual norms, iterations and the ratio baseline/ours. Run:
``python benchmarks/bench_blade_element.py [small-angle|exact]`` (a few minutes).
"""

from __future__ import annotations

import math
import sys

from _timing import best_of  # benchmarks/ is on sys.path when a script runs

import flapping
from flapping.errors import ConvergenceError
from flapping.hover import find_hover_orbit


def solve(insect, aerodynamics: str, backend: str) -> tuple[bool, float, int, float]:
    """(converged, residual norm, iterations, Phi [deg]) of one solve."""
    try:
        orbit = find_hover_orbit(insect, aerodynamics=aerodynamics, backend=backend)
    except ConvergenceError as exc:
        return False, float(exc.residual or math.nan), int(exc.iterations or 0), math.nan
    return True, orbit.residual_norm, orbit.nit, orbit.amplitude_deg


def main(aerodynamics: str = "small-angle", repeat: int = 1) -> dict:
    out = {}
    for h_mm in (0.0, 10.0):
        insect = flapping.hawkmoth(hinge_height=h_mm * 1e-3)
        t_ours, ours = best_of(lambda i=insect: solve(i, aerodynamics, "fixed-step"), repeat)
        t_base, base = best_of(lambda i=insect: solve(i, aerodynamics, "adaptive"), repeat)
        print(f"{aerodynamics} hover orbit of the hawkmoth, hinge height {h_mm:g} mm "
              f"(best of {repeat})")
        for name, t, (ok, res, nit, phi) in (("ours", t_ours, ours), ("baseline", t_base, base)):
            print(f"  {name:9s}: {t:7.2f} s  converged={ok!s:5s}  residual {res:.2e}  "
                  f"nit {nit:3d}  Phi = {phi:.10f} deg")
        print(f"  ratio baseline/ours: {t_base / t_ours:.2f}")
        out[h_mm] = {"ours_s": t_ours, "baseline_s": t_base, "ratio": t_base / t_ours,
                     "ours_converged": ours[0], "baseline_converged": base[0]}
    return out


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "small-angle")

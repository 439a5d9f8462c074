"""Benchmark: the blade-element hover orbit on the fixed-step path, against two baselines.

Ours: :func:`flapping.hover.find_hover_orbit` with ``backend="fixed-step"`` (what ``"auto"``
runs for the blade-element models): Newton on a fixed-step DOP853 period map on a time mesh
graded towards the stroke reversals, the loads' kinks as switching functions, a Richardson error
estimate, the field evaluated by the compiled blade-element loads (:mod:`flapping.fast.blade`).

Baselines, run in this process from the same default guess:

- ``loads``: the same solve with the Python loads (``HoverProblem.graded_fields(compiled=False)``,
  what the fixed-step path ran before the compiled loads): the script prints the ratio and the
  agreement of x0, Phi and the multipliers (the same field to rounding: x0 and Phi to ~1e-13,
  the multipliers to the noise of the path's finite-difference monodromy, ~1e-9);
- ``paths`` (the default): the adaptive path (Levenberg-Marquardt over adaptive DOP853 flows, a
  finite-difference Jacobian), the path ``"auto"`` took before the fixed-step one, at hinge
  heights where both converge (0) and where the adaptive path's LM stalls at its integration
  noise (10 mm).

Run: ``python benchmarks/bench_blade_element.py [paths|loads] [small-angle|exact]`` (a few
minutes each).
"""

from __future__ import annotations

import math
import sys
import time
import warnings
from unittest import mock

import numpy as np
from _timing import best_of  # benchmarks/ is on sys.path when a script runs

import flapping
from flapping.errors import ConvergenceError
from flapping.hover import HoverProblem, find_hover_orbit
from flapping.model.presets import preset


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


#: The solves of the loads comparison: (label, insect, aerodynamics).
LOADS_CASES = (
    ("hawkmoth", lambda: flapping.hawkmoth(), "small-angle"),
    ("hawkmoth", lambda: flapping.hawkmoth(), "exact"),
    ("monarch", lambda: preset("monarch"), "small-angle"),
    ("hawkmoth h_w = 10 mm", lambda: flapping.hawkmoth(hinge_height=10e-3), "small-angle"),
    ("monarch, measured geometry (wing mass)", lambda: preset("monarch", geometry="measured"),
     "small-angle"),
)


_GRADED = HoverProblem.graded_fields


def _python_loads(problem: HoverProblem, compiled: bool = True) -> tuple[list, list]:
    """graded_fields with the Python loads whatever is asked (patched in for the baseline)."""
    return _GRADED(problem, compiled=False)


def _timed(fn, repeat: int) -> tuple[float, float, object]:
    """Best wall and best CPU time of ``repeat`` calls [s] (the CPU time of this process is the
    steadier measure on a shared machine), and the last result."""
    wall = cpu = math.inf
    out = None
    for _ in range(repeat):
        t0, c0 = time.perf_counter(), time.process_time()
        out = fn()
        wall = min(wall, time.perf_counter() - t0)
        cpu = min(cpu, time.process_time() - c0)
    return wall, cpu, out


def loads(cases=LOADS_CASES, repeat: int = 1) -> dict:
    """The fixed-step solve with the compiled loads against the same with the Python loads."""
    out = {}
    # Compile (or load numba's cache) before timing: a cost paid once per environment.
    find_hover_orbit(flapping.hawkmoth(), aerodynamics="small-angle", backend="fixed-step")
    warnings.simplefilter("ignore", flapping.HoverDriftWarning)  # x_h != 0 with one trim
    for label, make, aerodynamics in cases:
        insect = make()

        def run(insect=insect, aerodynamics=aerodynamics):
            return find_hover_orbit(insect, aerodynamics=aerodynamics, backend="fixed-step")

        t_ours, c_ours, ours = _timed(run, repeat)
        with mock.patch.object(HoverProblem, "graded_fields", _python_loads):
            t_base, c_base, base = _timed(run, repeat)
        d_x0 = float(np.max(np.abs(ours.x0 - base.x0)))
        d_phi = abs(ours.amplitude_deg - base.amplitude_deg)
        m_ours = np.sort_complex(ours.fixed_step.multipliers)
        m_base = np.sort_complex(base.fixed_step.multipliers)
        d_mult = float(np.max(np.abs(m_ours - m_base)))
        print(f"{label}, {aerodynamics} (best of {repeat}): compiled loads {t_ours:6.2f} s wall, "
              f"{c_ours:6.2f} s CPU (nfev {ours.fixed_step.nfev}, n_steps "
              f"{ours.fixed_step.n_steps}); Python loads {t_base:6.2f} s wall, {c_base:6.2f} s CPU "
              f"(nfev {base.fixed_step.nfev}); ratio {t_base / t_ours:5.2f} wall, "
              f"{c_base / c_ours:5.2f} CPU")
        print(f"  Phi = {ours.amplitude_deg:.12f} deg; differences: x0 {d_x0:.1e}, Phi "
              f"{d_phi:.1e} deg, multipliers {d_mult:.1e}")
        out[(label, aerodynamics)] = {"compiled_s": t_ours, "python_s": t_base,
                                      "ratio": t_base / t_ours, "cpu_ratio": c_base / c_ours,
                                      "x0": d_x0, "phi_deg": d_phi, "multipliers": d_mult}
    return out


if __name__ == "__main__":
    args = sys.argv[1:]
    which = args.pop(0) if args and args[0] in ("paths", "loads") else "paths"
    if which == "loads":
        loads()
    else:
        main(args[0] if args else "small-angle")

"""Benchmark: hover and its eight multipliers in six degrees of freedom, against the planar default.

Ours: ``find_hover_orbit(insect, dof=6, aerodynamics="linear")`` and ``hover_stability`` of it
(the eight multipliers on the compiled six-degree-of-freedom path, :mod:`flapping.fast._sixdof`:
fixed-step DOP853 variational equations, Newton on the orbit, an analysis at half the steps for
the error estimate). Baseline, in this process: the planar default, ``find_hover_orbit(insect)``
and ``hover_stability`` of it (the compiled kernel, eq. 29's linear loads): the same loads, so
the ratio is that of the paths. Issue 27's target is a ratio of at most :data:`TARGET_RATIO`;
the script prints the ratio as measured, and beside it the six-degree-of-freedom default
(blade-element loads, adaptive Python path) and the planar blade-element solve on its default
(fixed-step) path.

Run: ``python benchmarks/bench_sixdof.py [repeat]`` (about a minute on an idle machine).
"""

from __future__ import annotations

import sys

from _timing import best_of  # benchmarks/ is on sys.path when a script runs

import flapping

#: Issue 27's target: six-dof hover + eight multipliers within this factor of the planar default.
TARGET_RATIO = 4.0


def main(repeat: int = 1) -> dict[str, float]:
    insect = flapping.hawkmoth()
    planar = lambda: flapping.hover_stability(flapping.find_hover_orbit(insect))  # noqa: E731
    blade = lambda: flapping.hover_stability(  # noqa: E731
        flapping.find_hover_orbit(insect, aerodynamics="small-angle"))
    six = lambda: flapping.hover_stability(flapping.find_hover_orbit(insect, dof=6))  # noqa: E731
    linear = lambda: flapping.hover_stability(  # noqa: E731
        flapping.find_hover_orbit(insect, dof=6, aerodynamics="linear"))
    planar()  # compile and load the kernels outside the timing
    linear()
    t_planar, _ = best_of(planar, max(repeat, 3))
    t_linear, lin = best_of(linear, max(repeat, 3))
    t_blade, _ = best_of(blade, repeat)
    t_six, stab = best_of(six, repeat)
    ratio = t_linear / t_planar
    print(f"planar default (compiled, linear loads):         {t_planar * 1e3:.2f} ms")
    print(f"six dof + eight multipliers (compiled, linear):  {t_linear * 1e3:.2f} ms "
          f"(multiplier error estimate {lin.multiplier_error:.1e})")
    print(f"planar blade-element (fixed-step):               {t_blade:.3f} s")
    print(f"six dof + eight multipliers (small-angle, adaptive): {t_six:.2f} s "
          f"(multiplier error estimate {stab.multiplier_error:.1e})")
    print(f"ratio six dof compiled / planar default: {ratio:.1f}x (target <= {TARGET_RATIO:g}x: "
          f"{'met' if ratio <= TARGET_RATIO else 'NOT met'}); six dof adaptive / planar default: "
          f"{t_six / t_planar:.0f}x")
    return {"planar_s": t_planar, "linear_s": t_linear, "blade_s": t_blade, "sixdof_s": t_six,
            "ratio": ratio}


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 1)

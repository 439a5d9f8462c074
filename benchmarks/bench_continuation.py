"""Benchmark: a 200-point continuation of the Roessler period-1 branch against independent solves.

Targets (issue 17, item 6): (a) under 2 s on a quiet core, and (b) / (a) >= 5.

The branch (a = b = 0.2) from c = 2.5, fixed arclength step 0.02, 200 points, analytic Jacobian,
integration rtol = atol = 1e-10; it passes the period doubling at c = 2.8324450279, which is
located on the way. Measured:

(a) ``continue_orbit`` as a user calls it (bifurcation detection and location included);
(a') the same with ``detect=()`` (the branch alone);
(b) the same 200 orbits by repeated independent solves: :func:`find_periodic_orbit`
    (Levenberg-Marquardt, started from the previous orbit) and :func:`monodromy` for the
    multipliers at each parameter value of branch (a), same tolerances.

Prints wall time (best of ``--repeat`` runs, same process, :func:`_timing.best_of`), evaluations
of ``fun``, the ratios b/a and b/a', and whether the targets are met. The machine may be shared:
run it alone for the numbers that matter (under load, both times grow, the ratio much less).

Run: ``python benchmarks/bench_continuation.py [--repeat N]``.
"""

from __future__ import annotations

import argparse

import numpy as np
from _timing import best_of  # benchmarks/ is on sys.path when a script runs

from flapping.periodic.continuation import continue_orbit
from flapping.periodic.floquet import monodromy
from flapping.periodic.shooting import find_periodic_orbit
from flapping.periodic.testproblems import rossler, rossler_jac

X0, T0, C0 = [4.58081622, 0.0, 1.52645301], 5.749, 2.5
OPTIONS = {"ds": 0.02, "ds_max": 0.02, "max_points": 200, "rtol": 1e-10, "atol": 1e-10}


def f(t, x, c):
    return rossler(t, x, c=c)


def jac(t, x, c):
    return rossler_jac(t, x, c=c)


def run_continuation(detect):
    extra = {} if detect else {"detect": ()}
    return continue_orbit(f, X0, T0, C0, 10.0, jac=jac, **OPTIONS, **extra)


def run_independent(cs):
    x, T, nfev = np.array(X0), T0, 0
    for c in cs:
        orbit = find_periodic_orbit(rossler, x, T, jac=rossler_jac, args=(0.2, 0.2, c),
                                    rtol=1e-10, atol=1e-10, tol=1e-8)
        mon = monodromy(rossler, orbit.x0, orbit.period, jac=rossler_jac, args=(0.2, 0.2, c),
                        rtol=1e-10, atol=1e-10)
        x, T, nfev = orbit.x0, orbit.period, nfev + orbit.nfev + mon.nfev
    return nfev


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    t_a, branch = best_of(lambda: run_continuation(True), args.repeat)
    t_a0, plain = best_of(lambda: run_continuation(False), args.repeat)
    t_b, nfev_b = best_of(lambda: run_independent(plain.p), args.repeat)
    pd = [b.p for b in branch.bifurcations if b.kind == "period-doubling"]
    print(f"Roessler period-1 branch, {len(branch)} points, c = {branch.p[0]:.3f} .. "
          f"{branch.p[-1]:.3f} (best of {args.repeat})")
    print(f"(a)  continue_orbit, detection on : {t_a:7.3f} s  nfev {branch.nfev:9d}  "
          + (f"PD at c = {pd[0]:.13f}" if pd else "no PD located"))
    print(f"(a') continue_orbit, detect=()    : {t_a0:7.3f} s  nfev {plain.nfev:9d}")
    print(f"(b)  independent solves           : {t_b:7.3f} s  nfev {nfev_b:9d}")
    print(f"ratio (b)/(a') = {t_b / t_a0:.2f}, (b)/(a) = {t_b / t_a:.2f}")
    print(f"targets: (b)/(a) >= 5: {'met' if t_b / t_a >= 5 else 'NOT met'}; (a) < 2 s: "
          f"{'met' if t_a < 2 else 'not met here (quiet core needed to judge)'}")


if __name__ == "__main__":
    main()

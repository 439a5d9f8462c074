"""Benchmark: our optimized shooting vs the paper's method on the Roessler period-1 orbit.

Finds the orbit (a = b = 0.2, c = 5.7; x = 0 held fixed as the Poincare section) and its Floquet
multipliers from one perturbed guess, with

(a) our default: Levenberg-Marquardt (MINPACK) with the Jacobian from the variational equations,
    DOP853 at rtol 1e-11; multipliers from the product-QR monodromy (DOP853, rtol 1e-12);
(a') the same without the analytic Jacobian (finite differences inside the variational equations);
(b) the paper's method: Levenberg-Marquardt with a forward-difference Jacobian of the residual,
    fixed-step RK4 at 2^-10 of the period; multipliers from the variational equations by the same
    RK4 (eqs. 42-49).

Prints wall time (best of ``--repeat`` runs), right-hand-side and Jacobian evaluations, digits of
T correct against ChaosBook's 5.881088455554846, and the ratios b/a. The right-hand side is the
same cheap pure-Python function for every method.

Run: ``python benchmarks/bench_shooting.py [--repeat N]``.
"""

from __future__ import annotations

import argparse
import math
import time

from flapping.periodic.floquet import monodromy
from flapping.periodic.shooting import find_periodic_orbit
from flapping.periodic.testproblems import rossler, rossler_jac

T_CHAOSBOOK = 5.881088455554846
GUESS = [0.0, -8.2, 0.03]
T_GUESS = 5.8


def run_ours(jac):
    orbit = find_periodic_orbit(rossler, GUESS, T_GUESS, fixed=[0], jac=jac)
    mon = monodromy(rossler, orbit.x0, orbit.period, jac=jac)
    return orbit, mon


def run_paper():
    orbit = find_periodic_orbit(rossler, GUESS, T_GUESS, fixed=[0], jacobian="finite-difference",
                                method="RK4")
    mon = monodromy(rossler, orbit.x0, orbit.period, jac=rossler_jac, method="RK4", n_sub=1,
                    max_cond=math.inf)
    return orbit, mon


def measure(fn, repeat):
    best = math.inf
    for _ in range(repeat):
        start = time.perf_counter()
        orbit, mon = fn()
        best = min(best, time.perf_counter() - start)
    digits = -math.log10(max(abs(orbit.period / T_CHAOSBOOK - 1.0), 1e-17))
    return {
        "time": best, "rhs": orbit.nfev + mon.nfev, "jac": orbit.njev + mon.njev,
        "iters": orbit.nit, "T": orbit.period, "digits": digits,
        "mu": mon.multipliers[0].real,
    }


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="runs per method; best time kept")
    repeat = parser.parse_args(argv).repeat
    rows = {
        "(a)  variational, DOP853, analytic J": measure(lambda: run_ours(rossler_jac), repeat),
        "(a') variational, DOP853, FD J": measure(lambda: run_ours(None), repeat),
        "(b)  paper: FD-LM over RK4 2^-10": measure(run_paper, repeat),
    }
    print(f"Roessler period-1 orbit from guess {GUESS}, T = {T_GUESS}; best of {repeat} runs")
    print(f"{'method':40s} {'wall [s]':>9s} {'RHS evals':>10s} {'J evals':>8s} {'LM it':>6s} "
          f"{'T':>18s} {'digits':>7s} {'mu_e':>12s}")
    for name, r in rows.items():
        print(f"{name:40s} {r['time']:9.3f} {r['rhs']:10d} {r['jac']:8d} {r['iters']:6d} "
              f"{r['T']:18.15f} {r['digits']:7.1f} {r['mu']:12.8f}")
    a, b = rows["(a)  variational, DOP853, analytic J"], rows["(b)  paper: FD-LM over RK4 2^-10"]
    print(f"ratio b/a: wall time {b['time'] / a['time']:.1f}, "
          f"RHS evaluations {b['rhs'] / a['rhs']:.1f}, "
          f"RHS+J evaluations {b['rhs'] / (a['rhs'] + a['jac']):.1f}")


if __name__ == "__main__":
    main()

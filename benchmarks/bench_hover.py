"""Benchmark: the hawkmoth's hover orbit plus its Floquet multipliers, ours against a baseline.

Ours: :func:`flapping.hover.find_hover_orbit` on the adaptive path (``backend="adaptive"``:
variational Jacobian, segment-aware DOP853) and :func:`flapping.hover.stability.hover_stability`
(variational monodromy). The default path (the compiled kernel) is timed against both in
``bench_kernel.py``.
Baseline: the straightforward approach at the same tolerance -- MINPACK Levenberg-Marquardt with a
finite-difference Jacobian over ``solve_ivp`` flows of the augmented state, and the monodromy by
central differences of the flow.

Both run in this process, from the same default guess, and are timed best-of-N; the script prints
wall times, right-hand-side evaluations and the ratio baseline/ours. Run:
``python benchmarks/bench_hover.py``.
"""

from __future__ import annotations

import math

import numpy as np
from _timing import best_of  # benchmarks/ is on sys.path when a script runs
from scipy.integrate import solve_ivp
from scipy.optimize import least_squares

import flapping
from flapping.hover import find_hover_orbit
from flapping.hover.stability import hover_stability
from flapping.model.dynamics import LongitudinalDynamics

RTOL, ATOL = 1e-11, 1e-12


def ours(insect):
    orbit = find_hover_orbit(insect, rtol=RTOL, atol=ATOL, backend="adaptive")
    stab = hover_stability(orbit, rtol=RTOL, atol=ATOL)
    return orbit.amplitude, stab.multipliers, orbit.nfev


def baseline(insect):
    model = LongitudinalDynamics(insect)
    T = model.period
    count = [0]

    def f(t, y, phi):
        count[0] += 1
        dx = model.rhs(t, y[:4], None, phi)
        u, w, _, th = y[:4]
        return np.append(dx, -u * math.sin(th) + w * math.cos(th))

    def flow(y0, phi):
        return solve_ivp(f, (0.0, T), y0, method="DOP853", rtol=RTOL, atol=ATOL,
                         args=(phi,)).y[:, -1]

    def residual(z):
        y0 = np.append(z[:4], 0.0)
        return flow(y0, z[4]) - y0

    sol = least_squares(residual, np.append(np.zeros(4), insect.stroke_amplitude), method="lm",
                        xtol=1e-12, ftol=1e-12)
    x0, phi = sol.x[:4], sol.x[4]
    M = np.empty((4, 4))
    for j in range(4):
        h = 1e-6
        e = np.zeros(5)
        e[j] = h
        y0 = np.append(x0, 0.0)
        M[:, j] = (flow(y0 + e, phi)[:4] - flow(y0 - e, phi)[:4]) / (2 * h)
    mu = np.linalg.eigvals(M)
    return phi, mu[np.argsort(-np.abs(mu))], count[0]


def main(repeat: int = 3) -> dict:
    insect = flapping.hawkmoth()
    t_ours, (phi_a, mu_a, n_a) = best_of(lambda: ours(insect), repeat)
    t_base, (phi_b, mu_b, n_b) = best_of(lambda: baseline(insect), repeat)
    print(f"hover orbit + Floquet multipliers of the {insect.name} (best of {repeat})")
    print(f"  ours     : {t_ours * 1e3:8.1f} ms   {n_a:7d} RHS evals (shooting)  "
          f"Phi = {math.degrees(phi_a):.9f} deg")
    print(f"  baseline : {t_base * 1e3:8.1f} ms   {n_b:7d} RHS evals (all)       "
          f"Phi = {math.degrees(phi_b):.9f} deg")
    print(f"  ratio baseline/ours: {t_base / t_ours:.1f}")
    print(f"  largest multiplier: ours {abs(mu_a[0]):.10f}, baseline {abs(mu_b[0]):.10f}")
    return {"ours_s": t_ours, "baseline_s": t_base, "ratio": t_base / t_ours}


if __name__ == "__main__":
    main()

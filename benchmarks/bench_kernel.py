"""Benchmark: the compiled hover kernel against the adaptive path and the straightforward baseline.

In one run, best of N, on this machine:

1. the hawkmoth's hover orbit + Floquet multipliers with the kernel path (``solve_hover`` +
   ``orbit_quadrature``: orbit, multipliers, averaged Jacobian and mean velocities), with the
   library's default path (``find_hover_orbit`` + ``hover_stability``), with the adaptive scipy
   path (the same with ``backend="adaptive"``: DOP853 shooting at rtol 1e-11) and with the
   baseline of ``bench_hover.py`` (MINPACK LM with a finite-difference Jacobian over
   ``solve_ivp`` flows, monodromy by central differences); the ratio adaptive / kernel path
   (issue 17 asks >= 300x), all timed in this process;
2. a 10,000-point sweep (frequency x centre of pressure): per-orbit cost in this process and on
   a 2-process ``ProcessPoolExecutor``;
3. the first-call cost: compiling from scratch (an empty ``NUMBA_CACHE_DIR``) and loading the
   cache, each in a fresh interpreter;
4. the kernel against the adaptive path over a 1000-point frequency sweep (20-32 Hz, through the
   birth of a complex pair): the largest differences in Phi [deg], the multipliers and x0. The
   adaptive reference solves run on 2 processes (~0.4 s each); ``--quick`` skips this part.

Run: ``python benchmarks/bench_kernel.py [--quick | --single] [--repeat N]`` (``--single``: part 1
only).
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

import flapping
from flapping.fast.kernel import KernelProblem, orbit_quadrature, solve_hover
from flapping.studies.sweep import sweep_hover

sys.path.insert(0, str(Path(__file__).parent))
from _timing import best_of  # noqa: E402
from bench_hover import baseline  # noqa: E402


def adaptive(insect):
    orbit = flapping.find_hover_orbit(insect, backend="adaptive")
    stab = flapping.hover_stability(orbit, backend="adaptive")
    return orbit.amplitude, stab.multipliers, orbit.x0


def kernel_path(problem):
    """Orbit, multipliers, averaged Jacobian and mean velocities on the kernel, from the insect."""
    sol = solve_hover(problem)
    quad = orbit_quadrature(problem, sol.x0, sol.amplitude)
    return sol.amplitude, sol.multipliers, quad


def default_path(insect):
    orbit = flapping.find_hover_orbit(insect)
    stab = flapping.hover_stability(orbit)
    return orbit.amplitude, stab.multipliers, orbit.x0


def single_solve(repeat: int) -> dict:
    insect = flapping.hawkmoth()
    problem = KernelProblem.of(insect)
    kernel_path(problem)  # compiled or loaded before timing
    many = max(repeat, 50)
    t_solve, fast = best_of(lambda: solve_hover(problem), many)
    t_quad, _ = best_of(lambda: orbit_quadrature(problem, fast.x0, fast.amplitude), many)
    t_path, (_, _, quad) = best_of(lambda: kernel_path(KernelProblem.of(insect)), many)
    t_default, (phi_d, mu_d, _) = best_of(lambda: default_path(insect), many)
    t_adaptive, (phi_a, mu_a, _) = best_of(lambda: adaptive(insect), repeat)
    t_base, (phi_b, mu_b, _) = best_of(lambda: baseline(insect), repeat)
    print(f"\n1. hover orbit + Floquet multipliers of the hawkmoth (best of {repeat}; kernel and "
          f"default path best of {many})")
    print(f"   {'path':<40}{'time':>12}{'Phi [deg]':>22}{'max|mu|':>16}")
    rows = (("kernel: solve_hover", t_solve, fast.amplitude, fast.multipliers),
            ("kernel: orbit_quadrature (64 nodes)", t_quad, fast.amplitude, fast.multipliers),
            ("kernel path (both, from the Insect)", t_path, fast.amplitude, fast.multipliers),
            ("default find_hover_orbit+hover_stability", t_default, phi_d, mu_d),
            ("adaptive (backend='adaptive')", t_adaptive, phi_a, mu_a),
            ("baseline (FD-LM, solve_ivp)", t_base, phi_b, mu_b))
    for name, t, phi, mu in rows:
        print(f"   {name:<40}{t * 1e3:9.3f} ms{math.degrees(phi):22.12f}"
              f"{np.max(np.abs(mu)):16.10f}")
    print(f"   ratio adaptive / kernel path: {t_adaptive / t_path:.0f}x (issue 17 asks >= 300x); "
          f"adaptive / default path: {t_adaptive / t_default:.0f}x; baseline / kernel path: "
          f"{t_base / t_path:.0f}x")
    print(f"   kernel: {fast.nit} Newton iterations, {fast.n_steps} steps per half-stroke, "
          f"estimated errors Phi {math.degrees(fast.amplitude_error):.1e} deg, multipliers "
          f"{fast.multiplier_error:.1e}; mean velocity (forward, climb) "
          f"{quad.mean_velocity[0]:.1e}, {quad.mean_velocity[1]:.1e} m/s")
    return {"kernel_path_s": t_path, "solve_s": t_solve, "quadrature_s": t_quad,
            "default_s": t_default, "adaptive_s": t_adaptive, "baseline_s": t_base,
            "ratio": t_adaptive / t_path}


def big_sweep(n_side: int = 100) -> dict:
    grid = {"frequency": np.linspace(20.0, 40.0, n_side),
            "center_of_pressure": np.linspace(0.0, 0.6, n_side)}
    n = n_side * n_side
    t0 = time.perf_counter()
    df = sweep_hover(flapping.hawkmoth(), grid, progress=False)
    t_in = time.perf_counter() - t0
    with ProcessPoolExecutor(2) as pool:
        sweep_hover(flapping.hawkmoth(), {"frequency": np.linspace(25.0, 27.0, 8)},
                    progress=False, executor=pool, chunk_size=1)  # start every worker first
        t0 = time.perf_counter()
        df2 = sweep_hover(flapping.hawkmoth(), grid, progress=False, executor=pool,
                          chunk_size=250)
        t_pool = time.perf_counter() - t0
    print(f"\n2. sweep of {n} points (frequency x centre of pressure), {df.converged.sum()} "
          f"converged, {int((~df.converged).sum())} rows of points that cannot trim")
    print(f"   in-process        : {t_in:6.2f} s  = {t_in / n * 1e3:.3f} ms per point")
    print(f"   2 processes       : {t_pool:6.2f} s  = {t_pool / n * 1e3:.3f} ms per point "
          f"(speed-up {t_in / t_pool:.2f}x; {df2.converged.sum()} converged)")
    print(f"   Newton iterations per point: mean {df.nit[df.converged].mean():.2f}; steps per "
          f"half-stroke: {sorted(set(df.n_steps[df.converged].astype(int)))}")
    return {"sweep_s": t_in, "sweep_pool_s": t_pool, "points": n}


def compile_times() -> dict:
    code = ("import time; t = time.perf_counter(); from flapping.fast import kernel; "
            "kernel.load(); kernel.warm_up(); print(time.perf_counter() - t)")
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        times = [float(subprocess.run([sys.executable, "-c", code], env=env, check=True,
                                      capture_output=True, text=True).stdout)
                 for _ in range(2)]
    print("\n3. first call in a fresh interpreter (import of the kernel + its first solve)")
    print(f"   cold (empty numba cache): {times[0]:6.2f} s")
    print(f"   cached                  : {times[1]:6.2f} s")
    return {"compile_cold_s": times[0], "compile_cached_s": times[1]}


def _reference(frequencies):
    out = []
    for f in frequencies:
        phi, mu, x0 = adaptive(flapping.hawkmoth(frequency=float(f)))
        out.append((phi, mu, x0))
    return out


def compare(n: int = 1000) -> dict:
    freqs = np.linspace(20.0, 32.0, n)
    t0 = time.perf_counter()
    df = sweep_hover(flapping.hawkmoth(), {"frequency": freqs}, progress=False)
    t_fast = time.perf_counter() - t0
    t0 = time.perf_counter()
    with ProcessPoolExecutor(2) as pool:
        ref = [r for part in pool.map(_reference, np.array_split(freqs, 20)) for r in part]
    t_ref = time.perf_counter() - t0
    d_phi, d_mu, d_x0, n_complex = 0.0, 0.0, 0.0, 0
    for row, (phi, mu, x0) in zip(df.itertuples(), ref, strict=True):
        ours = np.array([complex(getattr(row, f"mu{i}_real"), getattr(row, f"mu{i}_imag"))
                         for i in range(1, 5)])
        n_complex += bool(np.any(ours.imag != 0))
        d_phi = max(d_phi, abs(row.amplitude_deg - math.degrees(phi)))
        d_mu = max(d_mu, max(np.min(np.abs(ours - m)) for m in mu),
                   max(np.min(np.abs(mu - m)) for m in ours))
        d_x0 = max(d_x0, float(np.max(np.abs(np.array([row.u0, row.w0, row.q0, row.theta0])
                                             - x0))))
    print(f"\n4. kernel vs adaptive over {n} frequencies in [20, 32] Hz ({n_complex} points with "
          f"a complex pair)")
    print(f"   max |Phi difference|        : {d_phi:.2e} deg (promise 1e-9)")
    print(f"   max |multiplier difference| : {d_mu:.2e} (promise 1e-8)")
    print(f"   max |x0 difference|         : {d_x0:.2e} (SI)")
    print(f"   max estimated errors        : Phi {df.amplitude_error_deg.max():.2e} deg, "
          f"multipliers {df.multiplier_error.max():.2e}")
    print(f"   time: kernel {t_fast:.2f} s in-process, adaptive {t_ref:.0f} s on 2 processes")
    return {"d_phi_deg": d_phi, "d_mu": d_mu, "d_x0": d_x0}


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="skip the 1000-point comparison")
    parser.add_argument("--single", action="store_true", help="part 1 only (single solves)")
    parser.add_argument("--repeat", type=int, default=3, help="best of N (default 3)")
    args = parser.parse_args(argv)
    print(f"flapping {flapping.__version__}, {os.cpu_count()} cores")
    out = single_solve(args.repeat)
    if args.single:
        return out
    out.update(big_sweep())
    out.update(compile_times())
    if not args.quick:
        out.update(compare())
    return out


if __name__ == "__main__":
    main()

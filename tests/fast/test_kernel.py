"""The compiled hover kernel against the adaptive scipy path (the reference), and its own checks.

Tolerances: the kernel promises Phi to 1e-9 deg and every multiplier to 1e-8 (absolute); the
adaptive reference (DOP853, rtol 1e-11 for the orbit, 1e-12 for the monodromy) is ~100 times more
accurate than that on Phi and ~1e-10 on the multipliers away from a coalescing pair.
"""

import math
import os
import subprocess
import sys

import numpy as np
import pytest

import flapping
from flapping.errors import ConvergenceError

pytest.importorskip("numba")
from flapping.fast import kernel  # noqa: E402
from flapping.fast.kernel import KernelProblem, monodromy_at, sample_orbit, solve_hover  # noqa: E402

PHI_TOL_DEG, MU_TOL = 1e-9, 1e-8


def _adaptive(insect):
    orbit = flapping.find_hover_orbit(insect)
    return orbit, flapping.hover_stability(orbit)


def _match(a, b):
    """max over a of the distance to the nearest element of b (multipliers, any order)."""
    return max(np.min(np.abs(np.asarray(b) - x)) for x in a)


@pytest.fixture(scope="module")
def hawkmoth_pair():
    insect = flapping.hawkmoth()
    return insect, solve_hover(insect), *_adaptive(insect)


def test_importing_the_package_imports_no_numba_pandas_or_tqdm():
    code = ("import sys, flapping, flapping.fast, flapping.studies.sweep; "
            "print(sorted(m for m in ('numba', 'pandas', 'tqdm') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_hawkmoth_hover_agrees_with_the_adaptive_path(hawkmoth_pair):
    _, fast, orbit, stab = hawkmoth_pair
    assert abs(fast.amplitude_deg - orbit.amplitude_deg) < PHI_TOL_DEG
    assert _match(fast.multipliers, stab.multipliers) < MU_TOL
    np.testing.assert_allclose(fast.x0, orbit.x0, rtol=0, atol=1e-8)  # SI units, |x0| ~ 2
    np.testing.assert_allclose(fast.monodromy, stab.monodromy, rtol=0, atol=1e-8)
    assert fast.residual_norm < 1e-12  # Newton on a smooth (fixed-step) residual: to rounding


def test_error_estimates_bound_the_actual_errors(hawkmoth_pair):
    _, fast, orbit, stab = hawkmoth_pair
    # The estimate is of the kernel's own discretisation error; the reference adds ~1e-12 deg.
    assert abs(fast.amplitude_deg - orbit.amplitude_deg) < 3 * math.degrees(
        fast.amplitude_error) + 1e-11
    assert _match(fast.multipliers, stab.multipliers) < 3 * fast.multiplier_error + 1e-11
    assert math.degrees(fast.amplitude_error) < PHI_TOL_DEG
    assert fast.multiplier_error < MU_TOL


def test_liouville_formula_holds_for_the_kernels_monodromy(hawkmoth_pair):
    # det M = exp(int_0^T trace J dt): two independent outputs of one integration. The error is
    # the 8th-order discretisation error of the matrix (~1e-11 at 12 steps per half-stroke).
    _, fast, _, _ = hawkmoth_pair
    assert abs(fast.det - fast.liouville_det) < 1e-9 * abs(fast.liouville_det)


def test_error_estimate_converges_at_eighth_order():
    # Doubling the steps divides the error (and its estimate) by ~2^8 = 256 in the asymptotic
    # range; the estimate at n tracks the actual error (against n = 96) within a factor 4.
    problem = KernelProblem.of(flapping.hawkmoth())
    loose = dict(amplitude_tol_deg=1.0, multiplier_tol=1.0)
    fine = solve_hover(problem, n_steps=96, **loose)
    runs = {n: solve_hover(problem, n_steps=n, **loose) for n in (12, 24)}
    for n, run in runs.items():
        assert run.n_steps == n
        actual = abs(run.amplitude - fine.amplitude)
        assert actual / 4 < run.amplitude_error < 4 * actual, n
        actual_mu = _match(run.multipliers, fine.multipliers)
        assert actual_mu / 4 < run.multiplier_error < 4 * actual_mu, n
    ratio = runs[12].amplitude_error / runs[24].amplitude_error
    assert 100 < ratio < 600


def test_a_tight_tolerance_raises_the_step_count():
    problem = KernelProblem.of(flapping.hawkmoth())
    floors = dict(amplitude_tol_deg=kernel.AMPLITUDE_TOL_FLOOR_DEG,
                  multiplier_tol=kernel.MULTIPLIER_TOL_FLOOR)
    tight = solve_hover(problem, **floors)
    assert tight.n_steps > kernel.DEFAULT_STEPS
    assert math.degrees(tight.amplitude_error) <= kernel.AMPLITUDE_TOL_FLOOR_DEG
    assert tight.multiplier_error <= kernel.MULTIPLIER_TOL_FLOOR


def test_monodromy_at_the_solution_is_the_solutions(hawkmoth_pair):
    _, fast, _, _ = hawkmoth_pair
    problem = KernelProblem.of(flapping.hawkmoth())
    M, trace, err, n = monodromy_at(problem, fast.x0, fast.amplitude)
    np.testing.assert_allclose(M, fast.monodromy, rtol=0, atol=1e-13)
    assert trace == pytest.approx(fast.trace_integral, abs=1e-13) and err < MU_TOL and n >= 12


def test_sampled_orbit_is_periodic_and_matches_the_adaptive_samples(hawkmoth_pair):
    _, fast, orbit, _ = hawkmoth_pair
    problem = KernelProblem.of(flapping.hawkmoth())
    t, x, z_drift = sample_orbit(problem, fast.x0, fast.amplitude, orbit.t.size - 1)
    np.testing.assert_allclose(t, orbit.t, rtol=1e-15, atol=0)
    np.testing.assert_allclose(x[:, -1], x[:, 0], atol=1e-12)  # the orbit closes
    # hover: no net descent [m], up to the 12-step answer's own error (x0 to ~3e-9, z(T) moving
    # ~1e-4 m per unit of x0)
    assert abs(z_drift) < 1e-12
    np.testing.assert_allclose(x, orbit.x, rtol=0, atol=1e-8)


# 40 points: 20 frequencies across the birth of the complex pair, 20 on a (frequency,
# centre-of-pressure) grid with real and complex pairs.
_POINTS = ([{"frequency": f} for f in np.linspace(20.0, 32.0, 20)]
           + [{"frequency": f, "center_of_pressure": c}
              for f in (18.0, 24.0, 30.0, 36.0) for c in (0.0, 0.15, 0.3, 0.45, 0.6)])


@pytest.mark.parametrize("point", _POINTS, ids=lambda p: ",".join(f"{k}={v:.4g}"
                                                                    for k, v in p.items()))
def test_kernel_agrees_with_the_adaptive_path_over_a_sweep(point):
    insect = flapping.hawkmoth(**point)
    try:
        orbit, stab = _adaptive(insect)
    except ValueError:  # cannot trim (eq. 40): the kernel must refuse it alike
        with pytest.raises(ValueError):
            solve_hover(insect)
        return
    fast = solve_hover(insect)
    assert abs(fast.amplitude_deg - orbit.amplitude_deg) < PHI_TOL_DEG
    assert _match(fast.multipliers, stab.multipliers) < MU_TOL
    assert _match(stab.multipliers, fast.multipliers) < MU_TOL


def test_sweep_points_include_complex_pairs():
    # The agreement above is tested where it is hardest: near and inside complex pairs.
    complex_points = [p for p in _POINTS[:20]
                      if np.any(solve_hover(flapping.hawkmoth(**p)).multipliers.imag != 0)]
    assert 0 < len(complex_points) < 20


def test_no_hover_orbit_raises_a_convergence_error_with_diagnostics():
    # alpha_m given: the trim of eq. (40) is skipped, and this heavy insect needs Phi > 90 deg.
    problem = KernelProblem.of(flapping.hawkmoth(mass=2.4e-3), alpha_m=0.2)
    with pytest.raises(ConvergenceError) as info:
        solve_hover(problem)
    assert info.value.iterations is not None and info.value.iterations >= 1
    assert info.value.x is not None and info.value.x.shape == (5,)


@pytest.mark.parametrize("bad", [dict(n_steps=2), dict(n_steps=True), dict(n_steps=5000),
                                 dict(amplitude_guess=2.0), dict(x0_guess=[0.0, 1.0]),
                                 dict(x0_guess=[np.nan, 0, 0, 0]), dict(multiplier_tol=0.0)])
def test_bad_arguments_are_value_errors(bad):
    with pytest.raises(ValueError):
        solve_hover(flapping.hawkmoth(), **bad)


def test_compiled_eigenvalues_and_their_order_are_numpys():
    # The kernel's multipliers come from LAPACK's dgeev called in the compiled code: the values
    # of np.linalg.eigvals (same routine; 1e-13 allows another LAPACK build's rounding) in the
    # order of kernel._sorted, on real spectra, complex pairs and a repeated eigenvalue.
    kc = kernel.load()
    rng = np.random.default_rng(7)
    out = np.empty(4, dtype=complex)
    kinds = set()
    for i in range(300):
        m = rng.normal(size=(4, 4))
        if i % 3 == 0:
            m = m + m.T
        if i % 5 == 0:
            m = np.diag([0.5, 0.5, -0.2, 1.5]) + 0.0 * m
        assert kc.eigenvalues(m, out) == kc.EIGEN_OK
        kc.sort_multipliers(out)
        ref = kernel._sorted(np.linalg.eigvals(m))
        np.testing.assert_allclose(out, ref, rtol=1e-13, atol=1e-14)
        kinds.add(bool(np.any(ref.imag != 0)))
    assert kinds == {True, False}
    bad = np.eye(4)
    bad[2, 1] = np.inf
    assert kc.eigenvalues(bad, out) == kc.EIGEN_NOT_FINITE


@pytest.mark.parametrize("frequency", [20.0, 21.0, 22.0, 23.0, 26.0, 32.0])
def test_default_tolerances_hold_against_a_fine_solve(frequency):
    # The estimates are not bounds (HoverSolution's notes: Phi's read low by up to 5x at 21-23
    # Hz), but the answers meet the default tolerances: the reference at 256 steps per
    # half-stroke has discretisation errors below 1e-15.
    insect = flapping.hawkmoth().with_(frequency=frequency)
    sol, ref = solve_hover(insect), solve_hover(insect, n_steps=256)
    assert math.degrees(abs(sol.amplitude - ref.amplitude)) < kernel.AMPLITUDE_TOL_DEG
    gap = np.max(np.abs(np.sort_complex(sol.multipliers) - np.sort_complex(ref.multipliers)))
    assert gap < kernel.MULTIPLIER_TOL and gap <= sol.multiplier_error


def test_the_first_orbit_compiles_only_what_it_uses(tmp_path):
    # With an empty numba cache, a solve compiles newton_and_estimate (and what it calls), one
    # specialisation, and none of the other entry points (load() used to compile them all, ~2x
    # the CPU). A fresh process: this one has compiled everything already.
    code = ("import warnings; warnings.simplefilter('ignore'); import flapping; "
            "from flapping.fast import kernel; kernel.solve_hover(flapping.hawkmoth()); "
            "kc = kernel.load(); print({n: len(getattr(kc, n).signatures) for n in "
            "('newton_and_estimate', 'variational_period', 'sample_period', 'states_at', "
            "'orbit_quadrature')})")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env={**os.environ, "NUMBA_CACHE_DIR": str(tmp_path),
                              "FLAPPING_FIRST_CALL": "compiled"}, timeout=600)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().splitlines()[-1] == str(
        {"newton_and_estimate": 1, "variational_period": 1, "sample_period": 0, "states_at": 0,
         "orbit_quadrature": 0})
    assert any(tmp_path.rglob("_compiled.newton_and_estimate-*.nbi"))


def test_a_solve_reports_the_compile_once_and_each_entry_point_once(tmp_path):
    # One KernelCompileWarning per process, before numba compiles (the cache holds nothing),
    # and one INFO line per compile called from Python (flapping.fast._jit): variational_period
    # compiles inside newton_and_estimate's compile (in its time), and monodromy_at finds it.
    code = ("import logging, warnings; logging.basicConfig(level=logging.INFO); "
            "warnings.simplefilter('always'); import flapping; "
            "from flapping.fast import kernel; p = kernel.KernelProblem.of(flapping.hawkmoth()); "
            "s = kernel.solve_hover(p); kernel.solve_hover(p); "
            "kernel.monodromy_at(p, s.x0, s.amplitude)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env={**os.environ, "NUMBA_CACHE_DIR": str(tmp_path),
                              "FLAPPING_FIRST_CALL": "compiled"}, timeout=600)
    assert out.returncode == 0, out.stderr
    assert out.stderr.count("KernelCompileWarning") == 1
    assert out.stderr.count("numba compiled flapping.fast._compiled.newton_and_estimate") == 1
    assert out.stderr.count("numba compiled") == 1

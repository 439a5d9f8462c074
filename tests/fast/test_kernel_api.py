"""The kernel's packing cache, supported fields, tolerance floors, orbit quadrature, speed of the
Python wrapper, and the first-compile note and cache location."""

import dataclasses
import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import flapping
from flapping.errors import ConvergenceError
from flapping.model.dynamics import LongitudinalDynamics
from flapping.model.morphology import Insect

pytest.importorskip("numba")
from flapping.fast import kernel  # noqa: E402
from flapping.fast.kernel import KernelProblem, orbit_quadrature, solve_hover  # noqa: E402


@pytest.fixture(scope="module")
def hover():
    problem = KernelProblem.of(flapping.hawkmoth())
    return problem, solve_hover(problem, amplitude_tol_deg=kernel.AMPLITUDE_TOL_FLOOR_DEG,
                                multiplier_tol=kernel.MULTIPLIER_TOL_FLOOR)


# ------------------------------------------------------------------ packing
def test_packing_is_cached_per_insect_and_alpha_m():
    a = KernelProblem.of(flapping.hawkmoth())
    assert KernelProblem.of(flapping.hawkmoth()) is a  # equal insects: one packing
    assert KernelProblem.of(flapping.hawkmoth(frequency=25.0)) is not a
    b = KernelProblem.of(flapping.hawkmoth(), alpha_m=0.6)
    assert b is not a and b.alpha_m == 0.6 and KernelProblem.of(flapping.hawkmoth(), 0.6) is b
    assert not a.k.flags.writeable and not a.p.flags.writeable  # shared: must not be altered


@pytest.mark.parametrize("bad", [dict(alpha_m=0.0), dict(alpha_m=math.nan), dict(alpha_m="x")])
def test_bad_alpha_m_is_refused_before_the_cache(bad):
    with pytest.raises(ValueError, match="alpha_m"):
        KernelProblem.of(flapping.hawkmoth(), **bad)


def test_supported_fields_name_every_insect_field_but_the_ones_the_kernel_refuses():
    fields = {f.name for f in dataclasses.fields(Insect) if f.init}
    assert set(kernel.SUPPORTED_FIELDS) <= fields
    # update with the kernel
    assert fields - set(kernel.SUPPORTED_FIELDS) == {"stroke_mean", "wing_mass", "wing_mass_r1",
                                                      "wing_mass_r2"}


def test_an_unsupported_field_away_from_its_default_is_refused_by_name(monkeypatch):
    reduced = {k: v for k, v in kernel.SUPPORTED_FIELDS.items() if k != "hinge_height"}
    monkeypatch.setattr(kernel, "SUPPORTED_FIELDS", reduced)
    with pytest.raises(ValueError, match="hinge_height"):
        KernelProblem.of(flapping.hawkmoth(hinge_height=1.2345e-3))
    KernelProblem.of(flapping.hawkmoth(hinge_height=0.0, frequency=26.1234))  # the default passes


def test_a_new_insect_field_is_refused_until_the_kernel_supports_it():
    # A future Insect field (here a wing flexibility, on a subclass) is unknown to the kernel.
    @dataclasses.dataclass(frozen=True)
    class FlexibleInsect(Insect):
        wing_flexibility: float = 0.0

    base = {f.name: getattr(flapping.hawkmoth(), f.name)
            for f in dataclasses.fields(Insect) if f.init}
    with pytest.raises(ValueError, match="wing_flexibility"):
        KernelProblem.of(FlexibleInsect(**base, wing_flexibility=1e-5))
    assert KernelProblem.of(FlexibleInsect(**base)).insect.wing_flexibility == 0.0


def test_wings_of_mass_are_refused_by_the_kernel_and_solved_by_auto():
    moth = flapping.hawkmoth(wing_mass=4.7e-5)
    with pytest.raises(ValueError, match="wing_mass"):
        KernelProblem.of(moth)
    assert flapping.find_hover_orbit(moth).backend == "adaptive"


# ------------------------------------------------------------------ tolerances
@pytest.mark.parametrize("name, value", [("multiplier_tol", 1e-30), ("multiplier_tol", 1e-13),
                                         ("amplitude_tol_deg", 1e-13),
                                         ("amplitude_tol_deg", 1e-30)])
def test_tolerances_below_the_float64_floor_are_refused_by_name(name, value):
    # multiplier_tol=1e-30 used to report "met": the estimate was rounding noise.
    with pytest.raises(ValueError, match=rf"`{name}` must be a real number in \[1e-1[12]"):
        solve_hover(flapping.hawkmoth(), **{name: value})


def test_monodromy_at_refuses_a_tolerance_below_the_floor(hover):
    problem, sol = hover
    with pytest.raises(ValueError, match="multiplier_tol"):
        kernel.monodromy_at(problem, sol.x0, sol.amplitude, multiplier_tol=1e-30)


def test_the_floors_lie_above_the_rounding_scatter():
    # Phi and the multipliers solved at 32-128 steps (discretisation errors < 1e-15) differ by
    # rounding only; a tolerance is honest only well above that scatter (10x asked).
    problem = KernelProblem.of(flapping.hawkmoth(frequency=20.0))
    runs = [solve_hover(problem, n_steps=n, amplitude_tol_deg=1.0, multiplier_tol=1.0)
            for n in (32, 64, 128)]
    phi = [math.degrees(r.amplitude) for r in runs]
    assert max(phi) - min(phi) < kernel.AMPLITUDE_TOL_FLOOR_DEG / 10
    mu = np.array([r.multipliers for r in runs])
    assert np.abs(mu - mu[0]).max() < kernel.MULTIPLIER_TOL_FLOOR / 10


def test_an_unreachable_tolerance_at_the_step_cap_raises(monkeypatch, hover):
    problem, sol = hover
    monkeypatch.setattr(kernel, "_MAX_STEPS", 8)
    with pytest.raises(ConvergenceError, match="could not meet the tolerances with 8 steps"):
        solve_hover(problem, n_steps=6, multiplier_tol=kernel.MULTIPLIER_TOL_FLOOR)
    with pytest.raises(ConvergenceError, match="with 8 steps"):
        kernel.monodromy_at(problem, sol.x0, sol.amplitude, n_steps=6,
                            multiplier_tol=kernel.MULTIPLIER_TOL_FLOOR)


def test_results_are_read_only(hover):
    _, sol = hover
    for array in (sol.x0, sol.monodromy, sol.multipliers, sol.residual):
        with pytest.raises(ValueError, match="read-only"):
            array[0] = 1.0


# ------------------------------------------------------------------ quadrature along the orbit
def _adaptive_quadrature(insect, x0, amplitude, n_nodes=64):
    """The averaged Jacobian and mean velocities by the definition, independently: scipy's
    DOP853 at rtol 1e-13 to the Gauss nodes of each half-stroke, LongitudinalDynamics.jac there."""
    model = LongitudinalDynamics(insect, amplitude, aerodynamics="linear")
    rhs, jac = model.segment_functions()
    nodes, weights = np.polynomial.legendre.leggauss(n_nodes)
    T, x = model.period, np.asarray(x0, dtype=float)
    J, v = np.zeros((4, 4)), np.zeros(2)
    for k, a in enumerate((0.0, 0.5 * T)):
        h = 0.25 * T
        t_nodes = h * nodes + a + h
        sol = solve_ivp(rhs[k], (a, a + 0.5 * T), x, method="DOP853", rtol=1e-13, atol=1e-15,
                        t_eval=np.append(t_nodes, a + 0.5 * T))
        for t, state, wt in zip(t_nodes, sol.y.T[:-1], weights, strict=True):
            J += h * wt * jac[k](t, state)
            c, s = math.cos(state[3]), math.sin(state[3])
            v += h * wt * np.array([state[0] * c + state[1] * s, state[0] * s - state[1] * c])
        x = sol.y[:, -1]
    return J / T, v / T


@pytest.mark.parametrize("point", [{}, {"hinge_offset": 1e-3, "hinge_height": 4e-3}])
def test_orbit_quadrature_agrees_with_the_adaptive_definition(point):
    # Same rule, same nodes; the states differ by the reference's integration error (rtol 1e-13
    # over ~10^2 steps, ~1e-12 relative), which moves the Jacobian's state-dependent entries by
    # as much: agreement to 1e-10 of the largest entry leaves a factor ~100.
    insect = flapping.hawkmoth(**point)
    problem = KernelProblem.of(insect)
    sol = solve_hover(problem)
    q = orbit_quadrature(problem, sol.x0, sol.amplitude)
    J, v = _adaptive_quadrature(insect, sol.x0, sol.amplitude)
    np.testing.assert_allclose(q.averaged_jacobian, J, rtol=0, atol=1e-10 * np.abs(J).max())
    np.testing.assert_allclose(q.mean_velocity, v, rtol=0, atol=1e-12)  # |v| ~ 0.1-1 m/s here
    assert q.n_nodes == 64 and not q.averaged_jacobian.flags.writeable


def test_mean_velocity_vanishes_on_the_hover_orbit_and_not_off_it(hover):
    problem, sol = hover
    q = orbit_quadrature(problem, sol.x0, sol.amplitude)
    # Hover: no net climb (the solved condition, z(T) = 0) and, for the paper's hawkmoth (x_h =
    # 0), no net forward flight; both to rounding of velocities ~1 m/s.
    assert abs(q.climb_velocity) < 1e-12 and abs(q.forward_velocity) < 1e-12
    # Off the orbit, the Gauss mean of the climb rate equals -z(T)/T of the RK integration.
    x0 = np.asarray(sol.x0) + np.array([0.05, -0.02, 0.0, 0.01])
    off = orbit_quadrature(problem, x0, sol.amplitude)
    _, _, z_drift = kernel.sample_orbit(problem, x0, sol.amplitude, 256)
    assert abs(off.climb_velocity) > 1e-3
    assert off.climb_velocity == pytest.approx(-z_drift / problem.period, rel=1e-10)


def test_orbit_quadrature_converges_spectrally_in_the_nodes(hover):
    problem, sol = hover
    ref = orbit_quadrature(problem, sol.x0, sol.amplitude, 128).averaged_jacobian
    err = {n: np.abs(orbit_quadrature(problem, sol.x0, sol.amplitude, n).averaged_jacobian
                     - ref).max() / np.abs(ref).max() for n in (8, 16, 32)}
    assert err[8] > 1e-7 and err[16] < 1e-11 and err[32] < 1e-13


@pytest.mark.parametrize("bad", [dict(n_nodes=0), dict(n_nodes=10**6), dict(n_nodes=2.0),
                                 dict(x0=[0, 0]), dict(amplitude=2.0)])
def test_orbit_quadrature_refuses_bad_arguments(hover, bad):
    problem, sol = hover
    args = dict(x0=sol.x0, amplitude=sol.amplitude) | bad
    with pytest.raises(ValueError):
        orbit_quadrature(problem, **args)


def test_a_solve_does_each_python_step_once(hover, monkeypatch):
    # The Python around the compiled Newton, counted rather than timed (timings on a shared
    # machine are noise): per solve at one step count, no eigenvalue call and no residual
    # evaluation from Python (Newton, the coarse integration of the estimate and both
    # eigenvalue problems are one compiled call; there were three eigvals calls, then two, and
    # two residual evaluations) and no range check of the default tolerances.
    problem, _ = hover
    kc = kernel.load()
    calls = {"eigvals": 0, "residual": 0, "real": 0}

    def counting(name, fn):
        def wrapper(*args, **kwargs):
            calls[name] += 1
            return fn(*args, **kwargs)
        return wrapper

    monkeypatch.setattr(np.linalg, "eigvals", counting("eigvals", np.linalg.eigvals))
    monkeypatch.setattr(kc, "residual_and_jacobian",
                        counting("residual", kc.residual_and_jacobian))
    monkeypatch.setattr(kernel._validation, "real", counting("real", kernel._validation.real))
    sol = solve_hover(problem)
    assert sol.n_steps == kernel.DEFAULT_STEPS  # one step count: one estimate
    assert calls == {"eigvals": 0, "residual": 0, "real": 0}


# ------------------------------------------------------------------ compile note and cache
def test_the_cache_directory_holds_the_kernel_and_nothing_of_ours():
    # numba's files only: no lock, report or stamp of flapping's in numba's cache
    cache = kernel.cache_dir()
    if cache is None:
        pytest.skip("numba found no writable cache directory here")
    kernel.solve_hover(flapping.hawkmoth())
    assert any(cache.glob("_compiled.newton_and_estimate-*.nbi"))
    assert {p.suffix for p in cache.iterdir() if p.is_file()} <= {".nbi", ".nbc"}


def _in_subprocess(code, **env):
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env=dict(os.environ, **env), timeout=120)
    assert out.returncode == 0, out.stderr
    return out.stdout.strip().splitlines()[-1]


def test_a_read_only_package_caches_in_the_user_cache_directory(tmp_path):
    # A wheel in a read-only site-packages: numba's in-tree locator refuses (as it does when
    # __pycache__ is not writable; simulated, since chmod does not stop root), and numba falls
    # back to its user-wide directory, which persists. Import only: nothing is compiled.
    code = ("import numba.core.caching as c; "
            "c.InTreeCacheLocator.from_function = classmethod(lambda cls, f, p: None); "
            "from flapping.fast import kernel, _compiled; print(kernel.cache_dir(_compiled))")
    env = {"XDG_CACHE_HOME": str(tmp_path), "NUMBA_CACHE_DIR": ""}
    path = Path(_in_subprocess(code, **env))
    assert path.parent == tmp_path / "numba" and path.name.startswith("fast_")


def test_without_any_writable_cache_the_kernel_still_loads(tmp_path):
    code = ("import numba.core.caching as c; "
            "none = classmethod(lambda cls, f, p: None); "
            "c.InTreeCacheLocator.from_function = none; "
            "c.UserWideCacheLocator.from_function = none; "
            "from flapping.fast import kernel, _compiled; "
            "from flapping.fast import _jit; print(_jit.cached(), kernel.cache_dir(_compiled))")
    assert _in_subprocess(code, NUMBA_CACHE_DIR="") == "False None"


def test_importing_flapping_does_not_import_numba():
    code = ("import sys, flapping, flapping.fast, flapping.fast.kernel; "
            "print('numba' in sys.modules)")
    assert _in_subprocess(code) == "False"

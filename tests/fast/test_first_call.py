"""The first call in an environment whose numba cache is cold: answered uncompiled, said so,
equal to the compiled answer bit for bit; the background compile fills the cache; later calls
and sweeps run compiled (flapping.fast.kernel, "The first call in a new environment")."""

from __future__ import annotations

import ast
import inspect
import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import flapping
from flapping.fast import _background, _uncompiled, kernel

pytest.importorskip("numba")


@pytest.fixture(scope="module")
def kc():
    kernel.warm_up()  # compiled (or loaded from the cache) in this process
    return kernel.load()


INSECTS = [flapping.hawkmoth(), flapping.hawkmoth(frequency=20.0),
           flapping.hawkmoth(hinge_height=4e-3), flapping.hawkmoth(center_of_pressure=0.35)]


def _equal(a, b):
    """Outputs equal to the last bit (tuples of arrays and scalars compared item by item)."""
    if isinstance(a, tuple):
        return len(a) == len(b) and all(_equal(x, y) for x, y in zip(a, b, strict=True))
    return np.array_equal(np.asarray(a), np.asarray(b))


@pytest.mark.parametrize("insect", INSECTS, ids=lambda i: f"{i.frequency:g}Hz")
def test_every_entry_point_uncompiled_equals_compiled_bit_for_bit(kc, insect):
    p = kernel.KernelProblem.of(insect)
    sol = kernel.solve_hover(p)
    nodes, weights = kernel._gauss(64)
    times = np.linspace(1e-4, 0.97 * p.period, 17)
    calls = {
        "newton_and_estimate": lambda: (np.append(np.zeros(4), insect.stroke_amplitude), 12,
                                        p.k, p.p, kernel._MAX_ITER, kernel._XTOL,
                                        kernel._FACTOR),
        "variational_period": lambda: (np.append(sol.x0, sol.amplitude), 12, p.k, p.p),
        "sample_period": lambda: (sol.x0, sol.amplitude, 16, p.k, p.p),
        "states_at": lambda: (sol.x0, sol.amplitude, 16, p.k, p.p, times),
        "orbit_quadrature": lambda: (sol.x0, sol.amplitude, p.k, p.p, nodes, weights, 32),
    }
    for name, args in calls.items():
        compiled = getattr(kc, name)(*args())
        python = _uncompiled.entry(kc, name)(*args())
        assert _equal(compiled, python), name


def test_the_lapack_stand_ins_answer_as_the_compiled_helpers(kc):
    rng = np.random.default_rng(7)
    ns = _uncompiled.namespace(kc)
    for m in [rng.normal(size=(5, 5)), np.diag([1.0, 2.0, 0.0, 3.0, 4.0]),
              np.full((5, 5), 1e-80)]:  # random, singular, an underflowing determinant
        assert ns["_det_is_zero"](m) == kc._det_is_zero(m)
    m, b = rng.normal(size=(5, 5)), rng.normal(size=5)
    assert np.array_equal(ns["_solve_negated"](m, b), kc._solve_negated(m, b))
    for bad, message in [(np.diag([1.0, 0.0, 1.0, 1.0, 1.0]), "singular"),
                         (np.full((5, 5), np.nan), "infs or NaNs")]:
        for solve in (ns["_solve_negated"], kc._solve_negated):
            with pytest.raises(np.linalg.LinAlgError, match=message):
                solve(bad, b)
    rotation = np.array([[0.0, -1.0, 0, 0], [1.0, 0, 0, 0], [0, 0, 2.0, 0], [0, 0, 0, 0.5]])
    for m in [rng.normal(size=(4, 4)), rotation, np.full((4, 4), np.inf)]:
        outs = [np.zeros(4, dtype=complex), np.zeros(4, dtype=complex)]
        codes = [ns["eigenvalues"](m, outs[0]), kc.eigenvalues(m, outs[1])]
        assert codes[0] == codes[1] and np.array_equal(outs[0], outs[1])


def test_the_power_rewrite_is_numbas_product():
    # numba writes x**n (n an integer constant) as an unrolled product; Python's ** calls pow.
    source = "def f(x):\n    return x**2, x**3, x**5, -x**2*3.0, x**0.5, x**-1\n"
    tree = _uncompiled._Products().visit(ast.parse(source))
    ns: dict = {}
    exec(compile(ast.fix_missing_locations(tree), "<f>", "exec"), ns)
    x = 1.1000000000000003
    assert ns["f"](x) == (x * x, x * (x * x), x * ((x * x) * (x * x)), -(x * x) * 3.0,
                          x**0.5, x**-1)
    generated = ast.parse(inspect.getsource(_uncompiled._generated))
    assert any(isinstance(n, ast.Pow) for n in ast.walk(generated))  # there is work to do
    assert not any(isinstance(n, ast.BinOp) and isinstance(n.op, ast.Pow)
                   for n in ast.walk(_uncompiled._Products().visit(generated)))


@pytest.fixture
def fresh_process(monkeypatch, kc):
    """This process as if no entry point had been called (the cache stays warm)."""
    if kernel.cache_dir() is None:
        pytest.skip("numba found no writable cache directory here: no cache is ever warm")
    monkeypatch.setattr(kernel, "_READY", set())
    monkeypatch.setattr(kernel, "_FIRST_DONE", set())
    monkeypatch.setattr(kernel, "_NOTED", [])

    def no_start(cache):
        raise AssertionError("a background compile started with a warm cache")

    monkeypatch.setattr(_background, "start", no_start)
    return monkeypatch


def test_a_forced_uncompiled_first_call_says_so_and_the_next_runs_compiled(fresh_process):
    fresh_process.setenv("FLAPPING_FIRST_CALL", "uncompiled")
    insect = flapping.hawkmoth(frequency=23.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error", kernel.KernelCompileWarning)  # warm: nothing to say
        first = kernel.solve_hover(insect)
        second = kernel.solve_hover(insect)
        quad = [kernel.orbit_quadrature(insect, first.x0, first.amplitude) for _ in range(2)]
    assert (first.compiled, second.compiled) == (False, True)
    assert first.path == kernel.UNCOMPILED_PATH and second.path == "compiled"
    assert (quad[0].compiled, quad[1].compiled) == (False, True)
    for name in ("x0", "amplitude", "monodromy", "multipliers", "residual", "amplitude_error",
                 "x0_error", "multiplier_error", "mean_velocity", "nit", "n_steps"):
        assert np.array_equal(getattr(first, name), getattr(second, name)), name
    assert np.array_equal(quad[0].averaged_jacobian, quad[1].averaged_jacobian)


def test_the_hover_orbit_names_the_path_and_a_warm_cache_answers_compiled(fresh_process):
    # auto (the default) with a warm cache: compiled from the first call, no background process
    fresh_process.delenv("FLAPPING_FIRST_CALL", raising=False)
    orbit = flapping.find_hover_orbit(flapping.hawkmoth(frequency=24.0))
    assert orbit.backend == "compiled" and orbit.kernel.compiled
    fresh_process.setattr(kernel, "_FIRST_DONE", set())
    fresh_process.setattr(kernel, "_READY", set())
    fresh_process.setenv("FLAPPING_FIRST_CALL", "uncompiled")
    cold = flapping.find_hover_orbit(flapping.hawkmoth(frequency=24.0))
    assert not cold.kernel.compiled and cold.kernel.path == kernel.UNCOMPILED_PATH
    assert np.array_equal(cold.floquet.multipliers, orbit.floquet.multipliers)
    assert cold.amplitude == orbit.amplitude


def test_a_first_call_with_much_work_compiles(fresh_process):
    fresh_process.setenv("FLAPPING_FIRST_CALL", "uncompiled")
    sol = kernel.solve_hover(flapping.hawkmoth(), n_steps=64)  # above the limit of 32
    assert sol.compiled


def test_a_bad_first_call_mode_is_named(fresh_process):
    fresh_process.setenv("FLAPPING_FIRST_CALL", "sometimes")
    with pytest.raises(ValueError, match="FLAPPING_FIRST_CALL must be one of auto, compiled"):
        kernel.solve_hover(flapping.hawkmoth())


def test_one_background_compile_per_cache_and_a_failed_one_reports(tmp_path, kc):
    # While the lock is held (here by this test), none starts and running() says so.
    import fcntl

    fd = os.open(tmp_path / _background.LOCK_NAME, os.O_RDWR | os.O_CREAT)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        assert _background.running(tmp_path)
        assert _background.start(tmp_path) is None
        assert not _background.wait(tmp_path, 0.2)  # the time limit, not a hang
    finally:
        os.close(fd)
    assert not _background.running(tmp_path)
    # A child whose numba caches elsewhere compiles nothing and says why, with exit status 1.
    assert _background.main([str(tmp_path)], niceness=0) == 1
    report = _background.report(tmp_path)
    assert not report["ok"] and "nothing compiled" in report["error"]


def _python(code, env, timeout=600):
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                         timeout=timeout)
    assert out.returncode == 0, out.stderr
    return out


FIRST = ("import warnings, flapping; warnings.simplefilter('always'); "
         "from flapping.fast import kernel; "
         "o = flapping.find_hover_orbit(flapping.hawkmoth()); "
         "s = flapping.hover_stability(o); "
         "print(o.kernel.compiled, abs(s.multipliers).max().hex(), o.amplitude.hex())")

SWEEP = ("import warnings, flapping; warnings.simplefilter('ignore'); "
         "from flapping.fast import kernel; from flapping.studies.sweep import sweep_hover; "
         "import hashlib; "
         "t = sweep_hover(flapping.hawkmoth(), {'frequency': [24.0, 25.0, 26.0]}, "
         "progress=False); kc = kernel.load(); "
         "rows = repr([[repr(v) for v in r] for r in t.itertuples(index=False)]); "
         "print(len(kc.newton_and_estimate.signatures), 'newton_and_estimate' in kernel._READY, "
         "len(t), hashlib.sha256(rows.encode()).hexdigest())")


def _cold_env(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    env.pop("FLAPPING_FIRST_CALL", None)
    env.pop("NUMBA_DISABLE_JIT", None)
    return env


def test_a_cold_cache_answers_the_first_calls_uncompiled_in_a_new_process(tmp_path):
    # The cache directory's compile lock held here: the process finds a compile running and
    # starts none (so this test compiles nothing); it answers uncompiled and says so.
    import fcntl

    env = _cold_env(tmp_path)
    code = ("from flapping.fast import kernel; print(kernel.cache_dir(kernel.load()))")
    directory = _python(code, env).stdout.strip()
    fd = os.open(os.path.join(directory, _background.LOCK_NAME), os.O_RDWR | os.O_CREAT)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        out = _python(FIRST, env, 120)
    finally:
        os.close(fd)
    assert out.stdout.split()[0] == "False"
    assert out.stderr.count("KernelCompileWarning") == 1
    assert "ran its Python code uncompiled" in out.stderr and "runs already" in out.stderr
    assert not list(tmp_path.rglob("*.nbi")) and _background.report(Path(directory)) is None
    mu = float.fromhex(out.stdout.split()[1])
    assert mu == abs(kernel.solve_hover(flapping.hawkmoth()).multipliers).max()


@pytest.mark.slow
def test_cold_cache_first_call_uncompiled_background_fills_the_cache_sweeps_compile(tmp_path):
    """The whole story with one background compile (20-60 s on two busy cores)."""
    env = _cold_env(tmp_path)
    cold = _python(FIRST, env)
    compiled, mu, phi = cold.stdout.split()
    assert compiled == "False"
    assert cold.stderr.count("KernelCompileWarning") == 1
    assert "uncompiled" in cold.stderr and "background process" in cold.stderr
    locks = list(tmp_path.rglob(_background.LOCK_NAME))
    assert len(locks) == 1
    cache = locks[0].parent
    # A sweep in a new process while the compile runs: its first point may be answered
    # uncompiled, the others wait and run compiled, and its table is the warm table.
    sweep = _python(SWEEP, env).stdout.split()
    assert _background.wait(cache, 600)
    report = _background.report(cache)
    assert report["ok"], report
    assert {p.name.split("-")[0] for p in cache.glob("*.nbi")} == {
        f"_compiled.{n}" for n in ("newton_and_estimate", "variational_period",
                                   "sample_period", "states_at", "orbit_quadrature")}
    assert sweep[:3] == ["1", "True", "3"]  # the sweep's solves ran compiled
    assert _python(SWEEP, env).stdout.split() == sweep  # the warm table, bit for bit
    # The next process: compiled from the first call, nothing to say, no background process.
    warm = _python(FIRST, env)
    assert warm.stdout.split() == ["True", mu, phi]
    assert "KernelCompileWarning" not in warm.stderr
    assert _background.report(cache)["pid"] == report["pid"]  # no second compile


def test_with_numba_disabled_every_call_is_uncompiled_and_nothing_starts(tmp_path):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), "NUMBA_DISABLE_JIT": "1"}
    out = _python(FIRST.replace("print(", "o2 = flapping.find_hover_orbit(flapping.hawkmoth("
                                "frequency=25.0)); print(o2.kernel.compiled, "), env, 300)
    assert out.stdout.split()[:2] == ["False", "False"]
    assert not list(tmp_path.rglob(_background.LOCK_NAME))
    mu = float.fromhex(out.stdout.split()[2])
    assert mu == abs(kernel.solve_hover(flapping.hawkmoth()).multipliers).max()


def test_a_wrapper_in_place_of_an_entry_point_is_called(fresh_process, kc):
    # as benchmarks/bench_sweep.py times the solves: a plain function has no numba cache to ask
    fresh_process.delenv("FLAPPING_FIRST_CALL", raising=False)
    calls = []
    inner = kc.newton_and_estimate

    def timed(*args):
        calls.append(1)
        return inner(*args)

    fresh_process.setattr(kc, "newton_and_estimate", timed)
    assert kernel.solve_hover(flapping.hawkmoth(frequency=22.0)).compiled
    assert calls == [1]

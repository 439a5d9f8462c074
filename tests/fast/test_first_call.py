"""The first call (flapping.fast._jit, one policy for every numba module): compiled in the
process and said once, or, with FLAPPING_FIRST_CALL=uncompiled and a cold cache, the kernel's
Python code, equal to the compiled answer bit for bit; no process started; the variable checked
on every call; a corrupt cache file recompiled with a warning."""

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
from flapping.fast import _jit, _uncompiled, kernel

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
    """This process as if no entry point had been called (the cache stays as it is)."""
    monkeypatch.setattr(kernel, "_READY", set())
    monkeypatch.setattr(kernel, "_NOTED", [])
    monkeypatch.delenv("FLAPPING_FIRST_CALL", raising=False)
    return monkeypatch


@pytest.fixture
def cold(fresh_process):
    """As if numba's cache held none of the kernel (whatever it holds: no test depends on it)."""
    fresh_process.setattr(_jit, "ready", lambda dispatcher: False)
    return fresh_process


def test_uncompiled_with_a_cold_cache_answers_in_python_says_so_once_and_equals_compiled(cold):
    cold.setenv("FLAPPING_FIRST_CALL", "uncompiled")
    insect = flapping.hawkmoth(frequency=23.0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        first, second = kernel.solve_hover(insect), kernel.solve_hover(insect)
        quad = kernel.orbit_quadrature(insect, first.x0, first.amplitude)
    notes = [w for w in caught if issubclass(w.category, kernel.KernelCompileWarning)]
    assert len(notes) == 1 and "FLAPPING_FIRST_CALL=uncompiled" in str(notes[0].message)
    assert (first.compiled, second.compiled, quad.compiled) == (False, False, False)
    assert first.path == kernel.UNCOMPILED_PATH
    cold.setenv("FLAPPING_FIRST_CALL", "compiled")
    compiled = kernel.solve_hover(insect)
    assert compiled.compiled and compiled.path == "compiled"
    for name in ("x0", "amplitude", "monodromy", "multipliers", "residual", "amplitude_error",
                 "x0_error", "multiplier_error", "mean_velocity", "nit", "n_steps"):
        assert np.array_equal(getattr(first, name), getattr(compiled, name)), name
    assert np.array_equal(quad.averaged_jacobian, kernel.orbit_quadrature(
        insect, first.x0, first.amplitude).averaged_jacobian)


def test_uncompiled_with_the_kernel_in_the_cache_runs_compiled(fresh_process):
    fresh_process.setattr(_jit, "ready", lambda dispatcher: True)
    fresh_process.setenv("FLAPPING_FIRST_CALL", "uncompiled")
    with warnings.catch_warnings():
        warnings.simplefilter("error", kernel.KernelCompileWarning)  # nothing to say
        assert kernel.solve_hover(flapping.hawkmoth(frequency=24.0)).compiled


def test_the_hover_orbit_names_the_path(cold):
    orbit = flapping.find_hover_orbit(flapping.hawkmoth(frequency=24.0))
    assert orbit.backend == "compiled" and orbit.kernel.compiled
    cold.setattr(kernel, "_READY", set())
    cold.setenv("FLAPPING_FIRST_CALL", "uncompiled")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", kernel.KernelCompileWarning)
        python = flapping.find_hover_orbit(flapping.hawkmoth(frequency=24.0))
    assert not python.kernel.compiled and python.kernel.path == kernel.UNCOMPILED_PATH
    assert np.array_equal(python.floquet.multipliers, orbit.floquet.multipliers)
    assert python.amplitude == orbit.amplitude


@pytest.mark.parametrize("value", ["garbage", "auto", "sometimes", "1"])
def test_a_bad_first_call_mode_is_refused_on_every_call(fresh_process, value):
    # It was refused on the first call and accepted on the second (read on the first only).
    insect = flapping.hawkmoth()
    kernel.solve_hover(insect)  # a first call done: the entry point is ready
    fresh_process.setenv("FLAPPING_FIRST_CALL", value)
    for _ in range(2):
        with pytest.raises(ValueError, match="FLAPPING_FIRST_CALL must be one of compiled, "
                                             "uncompiled"):
            kernel.solve_hover(insect)
    with pytest.raises(ValueError, match="FLAPPING_FIRST_CALL"):
        _jit.first_call_mode()
    # also while warm_up forces a mode
    with pytest.raises(ValueError, match="FLAPPING_FIRST_CALL"), _jit.forced("compiled"):
        _jit.first_call_mode()


@pytest.mark.parametrize("value", ["", "compiled", " Uncompiled "])
def test_the_first_call_modes_read_alike(fresh_process, value):
    fresh_process.setenv("FLAPPING_FIRST_CALL", value)
    assert _jit.first_call_mode() == (value.strip().lower() or "compiled")


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


def _cold_env(tmp_path, **extra):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), **extra}
    if "FLAPPING_FIRST_CALL" not in extra:
        env.pop("FLAPPING_FIRST_CALL", None)
    env.pop("NUMBA_DISABLE_JIT", None)
    return env


def test_an_uncompiled_first_call_starts_nothing_and_writes_nothing(tmp_path, kc):
    out = _python(FIRST, _cold_env(tmp_path, FLAPPING_FIRST_CALL="uncompiled"), 300)
    assert out.stdout.split()[0] == "False"
    assert out.stderr.count("KernelCompileWarning") == 1
    assert not [p for p in tmp_path.rglob("*") if p.is_file()]  # no cache file, lock or stamp
    mu = float.fromhex(out.stdout.split()[1])
    assert mu == abs(kernel.solve_hover(flapping.hawkmoth()).multipliers).max()


@pytest.mark.slow
def test_a_cold_cache_compiles_in_the_process_says_so_and_the_next_process_loads(tmp_path):
    """The first call in a new environment (20-60 s on two busy cores): compiled in the
    process, one warning; the next process loads the cache, silently, to the same bits."""
    env = _cold_env(tmp_path)
    cold = _python(FIRST, env)
    assert cold.stdout.split()[0] == "True"
    assert cold.stderr.count("KernelCompileWarning") == 1
    assert "compiling flapping's numba code" in cold.stderr
    warm = _python(FIRST, env)
    assert warm.stdout.split() == cold.stdout.split()
    assert "KernelCompileWarning" not in warm.stderr


def test_with_numba_disabled_every_call_is_uncompiled(tmp_path, kc):
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), "NUMBA_DISABLE_JIT": "1"}
    out = _python(FIRST.replace("print(", "o2 = flapping.find_hover_orbit(flapping.hawkmoth("
                                "frequency=25.0)); print(o2.kernel.compiled, "), env, 300)
    assert out.stdout.split()[:2] == ["False", "False"]
    mu = float.fromhex(out.stdout.split()[2])
    assert mu == abs(kernel.solve_hover(flapping.hawkmoth()).multipliers).max()


def test_a_wrapper_in_place_of_an_entry_point_is_called(fresh_process, kc):
    # as benchmarks/bench_sweep.py times the solves: a plain function has no numba cache to ask
    fresh_process.setenv("FLAPPING_FIRST_CALL", "uncompiled")
    calls = []
    inner = kc.newton_and_estimate

    def timed(*args):
        calls.append(1)
        return inner(*args)

    fresh_process.setattr(kc, "newton_and_estimate", timed)
    assert kernel.solve_hover(flapping.hawkmoth(frequency=22.0)).compiled
    assert calls == [1]


# --------------------------------------------------------------------------- numba's cache
#: A tiny entry point (compiled in ~0.2 s): the cache's behaviour is the same for every one.
SMALL = ("import warnings; warnings.simplefilter('always'); "
         "from flapping.fast import _blade; print(_blade.grading(0.25).hex())")


@pytest.mark.parametrize("suffix", [".nbi", ".nbc"])
def test_a_corrupt_cache_file_is_named_recompiled_and_rewritten(tmp_path, suffix):
    # numba raised UnpicklingError on every run until the file was deleted.
    env = _cold_env(tmp_path)
    first = _python(SMALL, env, 300)
    files = list(tmp_path.rglob(f"_blade.grading-*{suffix}"))
    assert len(files) == 1
    files[0].write_bytes(b"\x80\x04garbage, not a pickle")
    second = _python(SMALL, env, 300)
    assert second.stdout == first.stdout
    assert second.stderr.count("KernelCompileWarning") >= 1
    assert str(files[0]) in second.stderr and "recompiles" in second.stderr
    assert "Traceback" not in second.stderr
    third = _python(SMALL, env, 300)  # numba wrote the entry again: read without a word
    assert third.stdout == first.stdout and "KernelCompileWarning" not in third.stderr


def test_the_cache_key_holds_the_sources_a_function_inlines(tmp_path):
    # numba keys an entry on the function's own file: after a regeneration of _generated.py
    # alone it loaded the old arithmetic. The digest of the inlined sources is in the key.
    from numba.core.registry import cpu_target

    from flapping.fast import _cache

    a, b = tmp_path / "a.py", tmp_path / "b.py"
    a.write_text("X = 1\n")
    b.write_text("X = 1\n")
    modules = [type(sys)("a"), type(sys)("b")]
    modules[0].__file__, modules[1].__file__ = str(a), str(b)
    assert _jit._digest((modules[0],)) == _jit._digest((modules[1],))
    b.write_text("X = 2\n")
    digests = [_jit._digest((m,)) for m in modules]
    assert digests[0] != digests[1]
    fn = kernel.load().newton_and_estimate.py_func
    codegen = cpu_target.target_context.codegen()
    keys = [_cache.Cache(fn, d, _jit.announce, _jit._unreadable)._index_key(("sig",), codegen)
            for d in digests]
    assert keys[0][:3] == keys[1][:3] and keys[0] != keys[1]


def test_no_numba_module_bypasses_the_policy():
    # One policy: every compiled function of flapping.fast is decorated by flapping.fast._jit
    # (numba.njit appears nowhere else).
    import flapping.fast as package

    def jits(path):
        """The uses of numba.njit / numba.jit / njit in the code (not in the docstrings)."""
        return [n for n in ast.walk(ast.parse(path.read_text()))
                if (isinstance(n, ast.Attribute) and n.attr in ("njit", "jit")
                    and isinstance(n.value, ast.Name) and n.value.id == "numba")
                or (isinstance(n, ast.Name) and n.id == "njit")]

    root = Path(package.__file__).parent
    offenders = [p.name for p in root.glob("*.py") if p.name != "_jit.py" and jits(p)]
    assert offenders == []
    assert jits(root / "_jit.py")  # the test finds what it looks for
    kernel.load()
    from flapping.fast import _blade, _sixdof  # noqa: F401 - their entry points register

    registered = _jit.entry_points()
    for module in ("flapping.fast._compiled", "flapping.fast._blade", "flapping.fast._sixdof"):
        assert registered.get(module), module


def test_uncompiled_with_a_cold_cache_runs_the_python_blade_loads(cold):
    # The blade-element loads' Python twin is the model's own loads: the field is not compiled.
    from flapping.fast import blade
    from flapping.model.dynamics import LongitudinalDynamics

    model = LongitudinalDynamics(flapping.hawkmoth(), aerodynamics="small-angle")
    cold.setattr(blade, "_MODULE", [])
    cold.setattr(blade, "_UNCOMPILED_NOTED", [])
    cold.setenv("FLAPPING_FIRST_CALL", "uncompiled")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert blade.BladeField.of(model, 1) is None
        assert blade.BladeField.of(model, 1) is None
    assert sum(issubclass(w.category, kernel.KernelCompileWarning) for w in caught) == 1
    assert blade._MODULE == []  # nothing compiled or loaded
    cold.setenv("FLAPPING_FIRST_CALL", "compiled")
    assert blade.BladeField.of(model, 1) is not None

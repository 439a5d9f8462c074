"""The kernel's numba functions run as plain Python, with the same arithmetic.

:mod:`flapping.fast._compiled` is written in the subset of Python that numba compiles, so its
functions also run uncompiled (numba keeps each one's Python function as ``py_func``). The
first call of an entry point in an environment whose numba cache is cold is answered this way
(in about 0.2 s instead of seconds of compiling, see :func:`flapping.fast.kernel.run`), and so is
every call when ``NUMBA_DISABLE_JIT`` is set.

:func:`namespace` copies the module's functions with their Python code and three kinds of
replacement, so that every number is the one the compiled code computes:

- the calls between them go to the Python copies (a call to numba's dispatcher would compile);
- the generated derivatives (:mod:`flapping.fast._generated`) and planar equations of motion
  (:mod:`flapping.model._inertia_generated`) are re-compiled by Python with
  each ``x**n`` written as numba writes it for an integer constant ``n``, a product of ``x``
  (Python's ``**`` calls C's ``pow``, which can differ from the product in the last bit);
- the three LAPACK calls (``dgetrf``, ``dgesv``, ``dgeev`` through numba's bindings, which
  Python cannot call) go to SciPy's wrappers of the same LAPACK routines
  (:mod:`scipy.linalg.lapack`), which numba's bindings also reach (``scipy.linalg.cython_lapack``).

A test holds the uncompiled entry points' results equal to the compiled ones, bit for bit.
"""

from __future__ import annotations

import ast
import functools
import math
import types
from pathlib import Path
from typing import Any

import numpy as np

from flapping.fast import _generated
from flapping.model import _inertia_generated


class _Products(ast.NodeTransformer):
    """``x ** n`` (n an integer constant, 0 < n <= 64) as numba's unrolled product of x:
    ``res = 1; while n: (res *= x if n odd); n >>= 1; x *= x`` (its ``static_power_impl``)."""

    def visit_BinOp(self, node: ast.BinOp) -> ast.AST:
        self.generic_visit(node)
        exponent = node.right
        if not (isinstance(node.op, ast.Pow) and isinstance(exponent, ast.Constant)
                and type(exponent.value) is int and 0 < exponent.value <= 64):
            return node
        n, power, result = exponent.value, node.left, None
        while n:
            if n & 1:
                result = power if result is None else ast.BinOp(result, ast.Mult(), power)
            n >>= 1
            if n:
                power = ast.BinOp(power, ast.Mult(), power)
        assert result is not None
        return ast.copy_location(result, node)


@functools.lru_cache(maxsize=4)
def generated(module: types.ModuleType = _generated) -> dict[str, Any]:
    """The namespace of a generated module (:mod:`flapping.fast._generated`, or the planar
    equations of motion of :mod:`flapping.model._inertia_generated`) compiled by Python with
    numba's powers (the module's own, with Python's powers, if its source cannot be read)."""
    path = Path(module.__file__ or "")
    try:
        tree = _Products().visit(ast.parse(path.read_text(), filename=str(path)))
    except (OSError, SyntaxError, ValueError):  # e.g. installed without sources
        return dict(vars(module))
    ns: dict[str, Any] = {"__name__": module.__name__}
    exec(compile(ast.fix_missing_locations(tree), str(path), "exec"), ns)  # noqa: S102
    return ns


def _lapack() -> Any:
    from scipy.linalg import lapack

    return lapack


def _det_is_zero(m: np.ndarray) -> bool:
    """The compiled ``_det_is_zero`` with SciPy's dgetrf: a zero pivot, or an underflowing
    exp(sum log abs(u_ii))."""
    lu, _, info = _lapack().dgetrf(m)
    if info > 0:
        return True
    log_det = 0.0
    for i in range(m.shape[0]):
        log_det = log_det + math.log(abs(lu[i, i]))
    return math.exp(log_det) == 0.0


def _solve_negated(m: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The compiled ``_solve_negated`` (numba's np.linalg.solve(m, -b)) with SciPy's dgesv."""
    if not (np.isfinite(b).all() and np.isfinite(m).all()):
        raise np.linalg.LinAlgError("Array must not contain infs or NaNs.")
    _, _, x, info = _lapack().dgesv(m, -b)
    if info > 0:
        raise np.linalg.LinAlgError("Matrix is singular to machine precision.")
    return x


def _eigenvalues(ns: dict[str, Any], m: np.ndarray, out: np.ndarray) -> int:
    """The compiled ``eigenvalues`` with SciPy's dgeev (no eigenvectors)."""
    if not np.isfinite(m).all():
        return int(ns["EIGEN_NOT_FINITE"])
    wr, wi, _, _, info = _lapack().dgeev(m, compute_vl=0, compute_vr=0)
    if info != 0:
        return int(ns["EIGEN_NOT_CONVERGED"])
    for i in range(m.shape[0]):
        out[i] = complex(wr[i], wi[i])
    return int(ns["EIGEN_OK"])


def _python_function(obj: Any) -> types.FunctionType | None:
    """The Python function behind a numba dispatcher (or the function itself when numba's JIT
    is disabled and njit returned it), None for anything else."""
    fn = getattr(obj, "py_func", obj)
    return fn if isinstance(fn, types.FunctionType) else None


@functools.lru_cache(maxsize=4)
def namespace(compiled: types.ModuleType) -> dict[str, Any]:
    """The globals of ``compiled`` (:mod:`flapping.fast._compiled`) with every function as
    plain Python calling the others' Python copies (see the module notes)."""
    ns = dict(vars(compiled))
    generated_modules = {m.__name__: m for m in (_generated, _inertia_generated)}
    for name, obj in vars(compiled).items():
        fn = _python_function(obj)
        if fn is None:
            continue
        if fn.__module__ == compiled.__name__:
            ns[name] = types.FunctionType(fn.__code__, ns, fn.__name__, fn.__defaults__,
                                          fn.__closure__)
        elif fn.__module__ in generated_modules:
            ns[name] = generated(generated_modules[fn.__module__])[fn.__name__]
    ns["_det_is_zero"] = _det_is_zero
    ns["_solve_negated"] = _solve_negated
    ns["eigenvalues"] = functools.partial(_eigenvalues, ns)
    return ns


def entry(compiled: types.ModuleType, name: str) -> Any:
    """The entry point ``name`` of ``compiled`` as plain Python (see :func:`namespace`)."""
    return namespace(compiled)[name]

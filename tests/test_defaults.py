"""Defaults once: each default tolerance of the solvers is defined in one place, with its reason
(flapping.periodic.settings), and every function and backend object takes it from there."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import flapping
from flapping.backends import Adaptive, FixedStep
from flapping.periodic import settings

PACKAGE = Path(flapping.__file__).parent
#: The values of the layer's default tolerances (DOP853's orbit, monodromy, continuation).
VALUES = {settings.ORBIT_RTOL, settings.ORBIT_ATOL, settings.ORBIT_TOL, settings.MONODROMY_RTOL,
          settings.MONODROMY_ATOL, settings.CONTINUATION_RTOL, settings.CONTINUATION_ATOL}
NAME = re.compile(r"^(\w+_)?(rtol|atol|tol)$", re.IGNORECASE)
#: Where a default tolerance is written as a number: the one place, and the six-degree-of-freedom
#: analysis's own (looser, 3e-11, with its reason: finite-difference Jacobians).
ALLOWED = {"periodic/settings.py", "hover/sixdof.py"}


def _defaults(tree: ast.AST):
    """(name, default expression) of every argument default and (annotated) assignment."""
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            a = node.args
            positional = a.posonlyargs + a.args
            yield from ((arg.arg, d) for arg, d in
                        zip(positional[len(positional) - len(a.defaults):], a.defaults,
                            strict=True))
            yield from ((arg.arg, d) for arg, d in zip(a.kwonlyargs, a.kw_defaults, strict=True)
                        if d is not None)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name) and node.value:
            yield node.target.id, node.value
        elif (isinstance(node, ast.Assign) and len(node.targets) == 1
              and isinstance(node.targets[0], ast.Name)):
            yield node.targets[0].id, node.value
        elif isinstance(node, ast.Dict):  # a table of defaults, {"rtol": ...}
            yield from ((key.value, value) for key, value in zip(node.keys, node.values,
                                                                 strict=True)
                        if isinstance(key, ast.Constant) and isinstance(key.value, str))


def test_no_default_tolerance_is_typed_twice():
    # Reproducer (issue 35): DOP853's 1e-11 / 1e-12 / 1e-10 were typed in backends.py,
    # shooting.py, floquet.py, integrate.py (twice) and continuation.py.
    found = []
    for path in PACKAGE.rglob("*.py"):
        where = str(path.relative_to(PACKAGE))
        if where in ALLOWED:
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for name, value in _defaults(tree):
            if (NAME.match(name) and isinstance(value, ast.Constant)
                    and value.value in VALUES):
                found.append(f"{where}: {name} = {value.value}")
    assert not found, found


def test_the_checker_finds_a_typed_default():
    tree = ast.parse("def f(x, *, rtol=1e-11, tol: float = 1e-10):\n    pass\n"
                     "DEFAULTS = {'atol': 1e-12}\n")
    assert {name for name, value in _defaults(tree)
            if isinstance(value, ast.Constant) and value.value in VALUES} == {"rtol", "tol",
                                                                               "atol"}


def test_the_backends_and_the_layer_share_their_defaults():
    from flapping.periodic.continuation import ContinuationOptions
    from flapping.periodic.floquet import DEFAULTS as MONODROMY
    from flapping.periodic.shooting import DEFAULTS as SHOOTING

    assert (Adaptive.rtol, Adaptive.atol, Adaptive.tol) == (
        SHOOTING["rtol"], SHOOTING["atol"], SHOOTING["tol"])
    assert (Adaptive.analysis_rtol, Adaptive.analysis_atol) == (MONODROMY["rtol"],
                                                                MONODROMY["atol"])
    assert FixedStep.error_tol == settings.FIXED_STEP_ERROR_TOL and FixedStep.tol == Adaptive.tol
    assert ContinuationOptions.rtol == settings.CONTINUATION_RTOL


def test_the_unused_default_markers_are_gone():
    assert not hasattr(settings, "default") and not hasattr(settings, "given")

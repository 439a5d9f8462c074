"""One meaning per name: in the periodic-orbit tools and the hover application, ``p`` is the
continuation parameter only; the free parameters solved with an orbit (the trims, for hover) are
``params`` wherever code names them."""

from __future__ import annotations

import ast
from pathlib import Path

import flapping

PACKAGE = Path(flapping.__file__).parent

#: The modules where ``p`` is the continuation parameter (so it may appear there).
CONTINUATION = {"periodic/continuation.py", "periodic/_branchflow.py", "periodic/_bifurcation.py",
                "periodic/_branchplot.py", "hover/branch.py",
                # the two parameters of a bifurcation curve are p and q (issue 37's interface)
                "periodic/bifurcation_curves.py", "periodic/_defining.py"}

CHECKED = ["hover", "periodic", "studies/sweep.py", "studies/_path.py", "cli.py"]


def _modules() -> list[Path]:
    out: list[Path] = []
    for entry in CHECKED:
        path = PACKAGE / entry
        out += sorted(path.glob("*.py")) if path.is_dir() else [path]
    return out


def _bindings_of_p(tree: ast.AST) -> list[int]:
    """Lines where the name ``p`` is bound: an argument, an assignment target, a loop or
    comprehension variable, or an attribute ``x.p``."""
    def binds(node: ast.AST) -> bool:
        if isinstance(node, ast.arg):
            return node.arg == "p"
        if isinstance(node, ast.Name):
            return node.id == "p" and isinstance(node.ctx, ast.Store)
        return isinstance(node, ast.Attribute) and node.attr == "p"

    return [node.lineno for node in ast.walk(tree) if binds(node)]


def test_the_modules_checked_exist():
    modules = _modules()
    assert len(modules) > 20 and all(m.exists() for m in modules)
    assert {m.relative_to(PACKAGE).as_posix() for m in modules} >= CONTINUATION


def test_p_is_the_continuation_parameter_only():
    found = {}
    for module in _modules():
        name = module.relative_to(PACKAGE).as_posix()
        if name in CONTINUATION:
            continue
        lines = _bindings_of_p(ast.parse(module.read_text(), str(module)))
        if lines:
            found[name] = lines
    assert not found, f"`p` bound outside the continuation modules (use `params`): {found}"


def test_the_check_sees_a_p():
    # The test above can fail: the same check finds the free parameters named p in old code.
    old = "def rhs(t, y, p, s):\n    return p[0]\nclass C:\n    def at(self, x):\n        self.p = x\n"
    assert _bindings_of_p(ast.parse(old)) == [1, 5]

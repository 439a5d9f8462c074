"""The package's shape: layers import only the layers below them; functions fit on a screen.

These are the redesign's promises to the next maintainer (issue 7), checked on the source text so
that a violation fails here rather than in review.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import flapping

PACKAGE = Path(flapping.__file__).parent
GENERATED = {"_derivatives_generated.py", "_generated.py"}  # written by SymPy, not by hand
MAX_CODE_LINES = 80  # per function, docstring, comments and blank lines aside


def _modules(subpackage: str = "") -> list[Path]:
    root = PACKAGE / subpackage if subpackage else PACKAGE
    return sorted(p for p in root.rglob("*.py") if p.name not in GENERATED)


def _imported_modules(path: Path) -> set[str]:
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            if node.module != "flapping":  # `from flapping import x` imports flapping.x only
                names.add(node.module)
            names.update(f"{node.module}.{alias.name}" for alias in node.names)
    return names


# The shared top-level modules every layer may import: errors, validation, numerical helpers,
# how a solve runs (backends) and what it returns (results).
SHARED = ("flapping.errors", "flapping._validation", "flapping._numdiff", "flapping.backends",
          "flapping.results")

# Which flapping modules each layer may import (besides its own subpackage).
ALLOWED = {
    "periodic": ("flapping.periodic", "flapping.errors", "flapping._validation", "flapping._numdiff"),
    "model": ("flapping.model", "flapping.errors", "flapping._validation", "flapping._numdiff"),
    "fast": ("flapping.fast", "flapping.model", "flapping.periodic", "flapping.errors",
             "flapping._validation", "flapping._numdiff"),
    "hover": ("flapping.hover", "flapping.fast", "flapping.model", "flapping.periodic",
              "flapping.errors", "flapping._validation", "flapping._numdiff"),
    "studies": ("flapping.studies", "flapping.hover", "flapping.fast", "flapping.model",
                "flapping.periodic", "flapping.errors", "flapping._validation",
                "flapping._numdiff"),
    "peers": ("flapping.peers", "flapping.periodic", "flapping.errors", "flapping._validation",
              "flapping._numdiff"),
}

#: The modules at the top of the package: the namespace, the command line and the shared
#: helpers every layer may use; everything else lives in a layer's subpackage.
TOP_LEVEL = {"__init__", "__main__", "cli", "errors", "_validation", "_numdiff", "backends",
             "results"}


@pytest.mark.parametrize("layer", sorted(ALLOWED))
def test_a_layer_imports_only_what_lies_below_it(layer):
    allowed = ALLOWED[layer] + SHARED
    offending = []
    for path in _modules(layer):
        for name in _imported_modules(path):
            if name.startswith("flapping") and not name.startswith(allowed):
                offending.append(f"{path.relative_to(PACKAGE)} imports {name}")
    assert not offending, "\n".join(offending)


def test_the_book_helpers_are_not_imported_by_the_package():
    offending = [
        f"{path.relative_to(PACKAGE)} imports {name}"
        for path in _modules()
        if "book" not in path.relative_to(PACKAGE).parts
        for name in _imported_modules(path)
        if name.startswith("flapping.book")
    ]
    assert not offending, "\n".join(offending)


def _code_lines(lines: list[str], node: ast.FunctionDef | ast.AsyncFunctionDef) -> int:
    skip: set[int] = set()
    first = node.body[0]
    if ast.get_docstring(node, clean=False) is not None and isinstance(first, ast.Expr):
        skip.update(range(first.lineno, (first.end_lineno or first.lineno) + 1))
    end = node.end_lineno or node.lineno
    return sum(
        1 for i in range(node.lineno, end + 1)
        if i not in skip and lines[i - 1].strip() and not lines[i - 1].strip().startswith("#")
    )


def test_no_function_is_longer_than_a_screen():
    long = []
    for path in _modules():
        source = path.read_text(encoding="utf-8")
        lines = source.splitlines()
        for node in ast.walk(ast.parse(source)):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                n = _code_lines(lines, node)
                if n > MAX_CODE_LINES:
                    long.append(f"{path.relative_to(PACKAGE)}:{node.lineno} {node.name}: {n} lines")
    assert not long, "\n".join(long)


def test_the_top_level_namespace_offers_the_main_entry_points():
    for name in ("Insect", "hawkmoth", "find_hover_orbit", "hover_stability",
                 "find_periodic_orbit", "monodromy", "ConvergenceError"):
        assert name in flapping.__all__ and hasattr(flapping, name)
    assert not hasattr(flapping, "plotting")  # book helpers stay out of the namespace


def test_the_top_of_the_package_holds_only_a_handful_of_modules():
    assert {p.stem for p in PACKAGE.glob("*.py")} == TOP_LEVEL


def test_a_study_imports_no_other_study():
    # Private modules (flapping/studies/_path.py, the warm-start helper) are the layer's shared
    # tools, not studies: every study may use them.
    studies = {p.stem for p in (PACKAGE / "studies").glob("*.py") if not p.stem.startswith("_")}
    for path in (PACKAGE / "studies").glob("*.py"):
        others = {f"flapping.studies.{s}" for s in studies - {path.stem}}
        assert not {n for n in _imported_modules(path) if n.startswith(tuple(others))}, path


@pytest.mark.parametrize("old", sorted(flapping.MOVED_MODULES))
def test_moved_modules_stay_importable_as_the_same_module(old):
    import importlib

    assert importlib.import_module(old) is importlib.import_module(flapping.MOVED_MODULES[old])


def test_the_names_users_import_today_stay_importable():
    from flapping.sweep import sweep_hover

    from flapping.model.presets import preset
    from flapping.periodic.continuation import continue_orbit
    from flapping.periodic.floquet import monodromy
    from flapping.periodic.shooting import find_periodic_orbit

    assert callable(preset) and callable(continue_orbit) and callable(monodromy)
    assert callable(find_periodic_orbit) and flapping.sweep_hover is sweep_hover
    for name in ("find_hover_orbit", "hover_stability", "hawkmoth", "HoverProblem"):
        assert hasattr(flapping, name)
